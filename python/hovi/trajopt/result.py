"""The outcome of a trajectory optimisation."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class Result:
    status: str                 # IPOPT's status message
    success: bool
    cost: float
    constraint_violation: float  # largest violation of the constraints and bounds
    iterations: int
    wall_seconds: float
    trajectory: dict            # the transcription's arrays: t, q (configuration points), p or v, u, ...
    x: np.ndarray = field(repr=False)
    timing: dict = field(default_factory=dict)  # where the time went (see solve())
    sizes: dict = field(default_factory=dict)   # variables, constraints, Jacobian nonzeros
    transcription: object = field(default=None, repr=False)

    def control_function(self):
        """u(t) of the solution, vectorised."""
        return self.transcription.control_function(self.x)

    def as_guess(self):
        """(q(t), v(t), u(t)) of this solution: a guess for solving the problem again with another
        transcription, order or N (``solve(..., guess=result.as_guess())``)."""
        return self.transcription.interpolants(self.x)

    def replay(self):
        """Re-simulate the optimised controls with hovi's Integrator (VI transcriptions: the same
        integrator, so the states are reproduced to the solver's tolerance)."""
        if not hasattr(self.transcription, "replay"):
            raise NotImplementedError(f"replay needs the VI transcription, this is {self.transcription.name}")
        return self.transcription.replay(self.x)
