"""A feedback policy on the integrator's state x = (q, p): LQR at an equilibrium, time-varying LQR
along a trajectory, or the gains of an FDDP solve. Closed loops apply it in C++ (closed_loop.py)."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Optional

import numpy as np
import numpy.typing as npt

from .._checks import real_array
from .._typing import FloatArray


@dataclass(frozen=True)
class Policy:
    """u^{k,a} = clip(u_ref^{k,a} - K^k (x^k - x_ref^k), lower, upper) at step k, a = 0..s, with the
    state x = (q, p) (the integrator's momentum p, not q̇): the feedback is held over the step, the
    feed-forward is given at each control point. One reference and gain (``stages`` = 1: LQR at an
    equilibrium) holds at every step; S of them (time-varying LQR) hold at steps 0..S-1 and the last
    after that.

    x_ref (S, 2n), u_ref (S, s+1, m), gains (S, m, 2n), lower and upper (m,) (±inf: no limit),
    cost_to_go (S+1, 2n, 2n) or (1, 2n, 2n): x^T P x of the linear-quadratic problem, dt and s of the
    integrator it was made for.
    """
    x_ref: FloatArray
    u_ref: FloatArray
    gains: FloatArray
    lower: FloatArray
    upper: FloatArray
    cost_to_go: FloatArray
    dt: float
    s: int

    @property
    def stages(self) -> int:
        """The number of references and gains S."""
        return int(self.gains.shape[0])

    @property
    def n(self) -> int:
        """The degrees of freedom n of the model it was made for."""
        return int(self.x_ref.shape[1] // 2)

    @property
    def m(self) -> int:
        """The number of controls m."""
        return int(self.gains.shape[1])

    def control(self, k: int, q: npt.ArrayLike, p: npt.ArrayLike) -> FloatArray:
        """The controls (s+1, m) at step k from the state q, p (n,): what the C++ loop computes."""
        j = min(int(k), self.stages - 1)
        x = np.concatenate([real_array(q, "q", (self.n,)), real_array(p, "p", (self.n,))])
        du = -self.gains[j] @ (x - self.x_ref[j])
        out: FloatArray = np.clip(self.u_ref[j] + du[None, :], self.lower, self.upper)
        return out

    def with_limits(self, lower: Optional[npt.ArrayLike] = None, upper: Optional[npt.ArrayLike] = None) -> Policy:
        """The same policy saturated at lower, upper (numbers or (m,); None: unchanged)."""
        lo = self.lower if lower is None else np.broadcast_to(real_array(lower, "lower", finite=False), (self.m,)).copy()
        hi = self.upper if upper is None else np.broadcast_to(real_array(upper, "upper", finite=False), (self.m,)).copy()
        if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or np.any(lo > hi):
            raise ValueError(f"control limits must be numbers with lower <= upper, got {lo.tolist()} and {hi.tolist()}")
        return replace(self, lower=lo, upper=hi)
