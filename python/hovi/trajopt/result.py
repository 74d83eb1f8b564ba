"""The outcome of a trajectory optimisation."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable

import numpy as np
import numpy.typing as npt

if TYPE_CHECKING:
    from ..integrator import Trajectory


@dataclass
class Result:
    """The outcome of ``solve``: IPOPT's status, the cost, the largest constraint violation, the
    iterations and time, and the transcription's arrays (``trajectory``: t, q (P, n), p or v, u) of
    the solution x (n_variables,)."""
    status: str                 # IPOPT's status message
    success: bool
    cost: float
    constraint_violation: float  # largest violation of the constraints and bounds
    iterations: int
    wall_seconds: float
    trajectory: dict[str, Any]  # the transcription's arrays: t, q (configuration points), p or v, u, ...
    x: np.ndarray = field(repr=False)
    timing: dict[str, float] = field(default_factory=dict)  # where the time went (see solve())
    sizes: dict[str, int] = field(default_factory=dict)  # variables, constraints, Jacobian nonzeros
    transcription: Any = field(default=None, repr=False)
    contact: dict = field(default_factory=dict)
    solver: dict = field(default_factory=dict)  # a solver's own output (FDDP: xs, us, gains K, trace)

    def control_function(self) -> Callable[[npt.ArrayLike], np.ndarray]:
        """u(t) of the solution, vectorised: times t (K,) -> controls (K, m)."""
        return self.transcription.control_function(self.x)

    def as_guess(self) -> tuple[Callable[[npt.ArrayLike], np.ndarray], ...]:
        """(q(t), v(t), u(t)) of this solution, each vectorised: times t (K,) -> (K, n) or (K, m): a guess for solving the problem again with another
        transcription, order or N (``solve(..., guess=result.as_guess())``)."""
        return self.transcription.interpolants(self.x)

    def replay(self) -> Trajectory:
        """Re-simulate the optimised controls with hovi's Integrator (VI transcriptions: the same
        integrator, so the states are reproduced to the solver's tolerance)."""
        if not hasattr(self.transcription, "replay"):
            raise NotImplementedError(f"replay needs the VI transcription, this is {self.transcription.name}")
        return self.transcription.replay(self.x)
