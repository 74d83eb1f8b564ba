"""A feedback policy on the integrator's state x = (q, p): LQR at an equilibrium, time-varying LQR
along a trajectory, or the gains of an FDDP solve. Closed loops apply it in C++ (closed_loop.py)."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Optional

import numpy as np
import numpy.typing as npt

from .._checks import real_array, real_number, step_count, whole_number
from .._typing import FloatArray

MAX_S = 16  # the integrator's largest s (cpp/src/quadrature/lobatto.cpp)


def _order(s: Any) -> int:
    """An integrator's s: a whole number in [1, MAX_S]."""
    s = whole_number(s, "s", minimum=1)
    if s > MAX_S:
        raise ValueError(f"s must be <= {MAX_S} (the integrator's largest), got {s}")
    return s


@dataclass(frozen=True)
class Policy:
    """u^{k,a} = clip(u_ref^{k,a} - K^k (x^k - x_ref^k), lower, upper) at step k, a = 0..s, with the
    state x = (q, p) (the integrator's momentum p, not q̇): the feedback is held over the step, the
    feed-forward is given at each control point. One reference and gain (``stages`` = 1: LQR at an
    equilibrium) holds at every step; S of them (time-varying LQR) hold at steps 0..S-1 and the last
    after that.

    On a model with a free base x^k - x_ref^k is in tangent coordinates, (q ⊖ q_ref, p - p_ref) =
    (``Model.difference(q_ref, q)``, p - p_ref) (x_ref's q has nq = n + 1 entries: the attitude's
    quaternion).

    x_ref (S, nq + n), u_ref (S, s+1, m), gains (S, m, 2n), lower and upper (m,) (±inf: no limit),
    cost_to_go (S+1, 2n, 2n) or (1, 2n, 2n): x^T P x of the linear-quadratic problem (the loop does
    not use it: any number of rows is taken), dt > 0 and s >= 1 of the integrator it was made for (a
    closed loop refuses a plant of another dt or s). Arrays may be nested lists; every field is
    checked on construction (ValueError naming it). ``open_loop``: feed-forward controls alone.
    """
    x_ref: FloatArray
    u_ref: FloatArray
    gains: FloatArray
    lower: FloatArray
    upper: FloatArray
    cost_to_go: FloatArray
    dt: float
    s: int

    def __post_init__(self) -> None:
        gains = real_array(self.gains, "gains")
        if gains.ndim != 3 or min(gains.shape) < 1 or gains.shape[2] % 2:
            raise ValueError(f"gains must have shape (S, m, 2n) (S stages, m controls, n degrees of freedom), "
                             f"got shape {gains.shape}")
        S, m, n2 = gains.shape
        s = _order(self.s)
        x_ref, u_ref = real_array(self.x_ref, "x_ref"), real_array(self.u_ref, "u_ref")
        if x_ref.shape[:1] != (S,) or u_ref.shape[:1] != (S,):
            raise ValueError(f"x_ref, u_ref and gains must each have one row per stage: got shapes {x_ref.shape}, "
                             f"{u_ref.shape} and {gains.shape}")
        if x_ref.ndim != 2 or x_ref.shape[1] not in (n2, n2 + 1):
            raise ValueError(f"x_ref must have shape (S, nq + n) = ({S}, {n2}) or, with a free base, ({S}, {n2 + 1}), "
                             f"got shape {x_ref.shape}")
        fields = dict(
            x_ref=real_array(x_ref, "x_ref", (S, x_ref.shape[1])), u_ref=real_array(u_ref, "u_ref", (S, s + 1, m)), gains=gains,
            lower=real_array(self.lower, "lower", (m,), finite=False),
            upper=real_array(self.upper, "upper", (m,), finite=False),
            cost_to_go=real_array(self.cost_to_go, "cost_to_go", (None, n2, n2)),
            dt=real_number(self.dt, "dt", minimum=0.0, strict_minimum=True), s=s)
        lo, hi = fields["lower"], fields["upper"]
        if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or np.any(lo > hi):
            raise ValueError(f"lower and upper must be numbers with lower <= upper, got {lo.tolist()} and "
                             f"{hi.tolist()}")
        for name, value in fields.items():  # frozen: the checked values replace what was given
            object.__setattr__(self, name, value)

    @classmethod
    def open_loop(cls, u: npt.ArrayLike, dt: float, s: int, n: int) -> Policy:
        """The feed-forward controls u alone (no feedback, no limits) for a plant of n degrees of
        freedom, step dt and s: u (K, s+1, m) per control point or (K, m) held over each step, applied
        at steps 0..K-1 as ``Integrator.rollout(q0, K, u=u)`` applies them (the last after that)."""
        s, n = _order(s), whole_number(n, "n", minimum=1)
        given = real_array(u, "u")
        U = np.repeat(given[:, None, :], s + 1, axis=1) if given.ndim == 2 else given
        if U.ndim != 3 or U.shape[1] != s + 1 or min(U.shape) < 1:
            raise ValueError(f"u must have shape (K, {s + 1}, m) (per control point) or (K, m) (held), K and m >= 1, "
                             f"got shape {given.shape}")
        K, m = U.shape[0], U.shape[2]
        return cls(x_ref=np.zeros((K, 2 * n)), u_ref=U, gains=np.zeros((K, m, 2 * n)), lower=np.full(m, -np.inf),
                   upper=np.full(m, np.inf), cost_to_go=np.zeros((1, 2 * n, 2 * n)), dt=dt, s=s)

    def without_feedback(self) -> Policy:
        """The same feed-forward controls and limits with zero gains (the open loop)."""
        return replace(self, gains=np.zeros_like(self.gains))

    @property
    def stages(self) -> int:
        """The number of references and gains S."""
        return int(self.gains.shape[0])

    @property
    def n(self) -> int:
        """The degrees of freedom n of the model it was made for."""
        return int(self.gains.shape[2] // 2)

    @property
    def nq(self) -> int:
        """The configuration's size nq of the model it was made for (n + 1 with a free base)."""
        return int(self.x_ref.shape[1] - self.n)

    @property
    def m(self) -> int:
        """The number of controls m."""
        return int(self.gains.shape[1])

    def control(self, k: int, q: npt.ArrayLike, p: npt.ArrayLike, model: Any = None) -> FloatArray:
        """The controls (s+1, m) at step k >= 0 from the state q (nq,), p (n,): what the C++ loop
        computes. A free base needs its ``model`` (for ``Model.difference``)."""
        j = min(step_count(k, "k"), self.stages - 1)
        q, p = real_array(q, "q", (self.nq,)), real_array(p, "p", (self.n,))
        q_ref = self.x_ref[j, :self.nq]
        if self.nq == self.n:
            dq = q - q_ref
        elif model is None or getattr(model, "nq", None) != self.nq:
            raise ValueError(f"a policy on a free base needs its model (nq = {self.nq}) for the state's difference")
        else:
            dq = model.difference(q_ref, q)
        du = -self.gains[j] @ np.concatenate([dq, p - self.x_ref[j, self.nq:]])
        out: FloatArray = np.clip(self.u_ref[j] + du[None, :], self.lower, self.upper)
        return out

    def with_limits(self, lower: Optional[npt.ArrayLike] = None, upper: Optional[npt.ArrayLike] = None) -> Policy:
        """The same policy saturated at lower, upper (numbers or (m,); None: unchanged)."""
        return replace(self, lower=self.lower if lower is None else _limit(lower, "lower", self.m),
                       upper=self.upper if upper is None else _limit(upper, "upper", self.m))


def _limit(value: Any, name: str, m: int) -> FloatArray:
    """A control limit: a number or m numbers (±inf: none), as (m,)."""
    a = real_array(value, name, finite=False)
    if a.shape not in ((), (1,), (m,)):
        raise ValueError(f"{name} must be a number or {m} numbers, got shape {a.shape}")
    return np.broadcast_to(a, (m,)).copy()
