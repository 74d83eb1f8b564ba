"""Input constraints: linear conditions on the controls at every control value of the
transcription, ``lower <= A u <= upper`` (a contact wrench inside its cone: hovi.contact.FlatFoot)."""
from __future__ import annotations

import numpy as np
import numpy.typing as npt

from .._checks import real_array


class InputConstraint:
    """``lower (r,) <= A (r, m) u <= upper (r,)`` at every control value u (m,) of the transcription."""

    def __init__(self, A: npt.ArrayLike, lower: npt.ArrayLike, upper: npt.ArrayLike):
        A = real_array(A, "InputConstraint A", finite=False)
        if A.ndim not in (1, 2) or A.size == 0:
            raise ValueError(f"InputConstraint A must be a matrix (r, m), got shape {A.shape}")
        self.A = np.atleast_2d(A)
        r = len(self.A)
        bounds = []
        for name, value in (("lower", lower), ("upper", upper)):
            v = real_array(value, f"InputConstraint {name}", finite=False)
            if v.shape not in ((), (1,), (r,)):
                raise ValueError(f"InputConstraint {name} must be a number or {r} numbers (one per row of A), "
                                 f"got shape {v.shape}")
            bounds.append(np.broadcast_to(v, (r,)).copy())
        self.lower, self.upper = bounds
        if not np.all(np.isfinite(self.A)):
            raise ValueError("an input constraint's matrix A must be finite")
        if np.any(np.isnan(self.lower)) or np.any(np.isnan(self.upper)) or np.any(self.lower > self.upper):
            raise ValueError("an input constraint needs lower <= upper (no NaN)")

    def check(self, m: int) -> None:
        """Raise ValueError unless A has a column per control (m)."""
        if self.A.shape[1] != m:
            raise ValueError(f"an input constraint's A must have {m} columns (one per control), got {self.A.shape[1]}")
