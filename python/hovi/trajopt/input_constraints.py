"""Input constraints: linear conditions on the controls at every control value of the
transcription, ``lower <= A u <= upper`` (a contact wrench inside its cone: hovi.contact.FlatFoot)."""
from __future__ import annotations

import numpy as np
import numpy.typing as npt


class InputConstraint:
    """``lower (r,) <= A (r, m) u <= upper (r,)`` at every control value u (m,) of the transcription."""

    def __init__(self, A: npt.ArrayLike, lower: npt.ArrayLike, upper: npt.ArrayLike):
        self.A = np.atleast_2d(np.asarray(A, float))
        r = len(self.A)
        self.lower = np.broadcast_to(np.asarray(lower, float), (r,)).copy()
        self.upper = np.broadcast_to(np.asarray(upper, float), (r,)).copy()
        if not np.all(np.isfinite(self.A)):
            raise ValueError("an input constraint's matrix A must be finite")
        if np.any(np.isnan(self.lower)) or np.any(np.isnan(self.upper)) or np.any(self.lower > self.upper):
            raise ValueError("an input constraint needs lower <= upper (no NaN)")

    def check(self, m: int) -> None:
        """Raise ValueError unless A has a column per control (m)."""
        if self.A.shape[1] != m:
            raise ValueError(f"an input constraint's A must have {m} columns (one per control), got {self.A.shape[1]}")
