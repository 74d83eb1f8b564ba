"""Controls that hold a robot still: the statics the paper's robot examples start and stand from."""
from __future__ import annotations

from typing import Sequence

import numpy as np


def static_controls(model, q: np.ndarray, controls: Sequence[int] | None = None) -> np.ndarray:
    """Controls u (m,) that hold configuration q (nq,) at rest: Q(q, 0, u) = G(q), with Q = Q0 + (dQ/du) u
    the non-conservative force (force_jacobians) and G(q) = inverse_dynamics(q, 0, 0) the gravity force;
    the least-squares (least-norm) u using only the ``controls`` (indices; default all), the others zero."""
    zero = np.zeros(model.n)
    Q0, _, _, Qu = model.force_jacobians(q, zero)
    cols = np.arange(model.n_controls) if controls is None else np.asarray(controls, dtype=int)
    u = np.zeros(model.n_controls)
    u[cols] = np.linalg.lstsq(Qu[:, cols], model.inverse_dynamics(q, zero, zero) - Q0, rcond=None)[0]
    return u
