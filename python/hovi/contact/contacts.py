"""Rigid point contacts with Coulomb friction, as force inputs of the model.

Each contact point c (a point of a body, in its joint frame) gets 2 + d inputs appended to the
model's controls: the normal force lambda_c along the surface normal +z, the friction
coefficients beta_c,i >= 0 of the d friction directions D_i (a polyhedral cone: +-x, +-y in 3D
(d = 4), +-x in the x-z plane (d = 2)), and a slack gamma_c (no force: the magnitude of the
sliding velocity at the optimum, Stewart-Trinkle / Manchester-Kuindersma). The forces enter the
DEL equations as point forces at the control points (``Model.add_point_wrench`` with a control),
like the constraint forces, so their Jacobians come from the existing linearisation.

The complementarity conditions at every configuration point j (``ContactRows`` in
``hovi.trajopt.complementarity`` builds them for a transcription):

    phi_c(q_j) >= 0,  lambda >= 0,  lambda phi <= eps                 (no penetration, no pull)
    mu lambda - sum_i beta_i >= 0,  gamma >= 0,  gamma (mu lambda - sum beta) <= eps   (cone)
    gamma + D_i^T v_c >= 0,  beta_i >= 0,  beta_i (gamma + D_i^T v_c) <= eps   (maximal dissipation)

with v_c the contact point's velocity over the interval ending at j (a difference of positions);
eps -> 0 over a few solves (a relaxation homotopy, ``hovi.trajopt.solve_contact``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import List, Sequence, Tuple, Union

import numpy as np

from .._core import Model
from .terrain import Terrain


@dataclass(frozen=True)
class ContactPoint:
    """A point ``point`` (3,) of ``body`` (index), in the body's joint frame."""
    body: int
    point: np.ndarray


def friction_directions(plane: str = "") -> np.ndarray:
    """(d, 3) friction directions: +-x, +-y in 3D; in a vertical plane ('xz' or 'yz') its horizontal axis."""
    if plane == "":
        return np.array([[1.0, 0, 0], [-1.0, 0, 0], [0, 1.0, 0], [0, -1.0, 0]])
    if plane in ("xz", "yz"):
        axis = np.eye(3)[0 if plane == "xz" else 1]
        return np.array([axis, -axis])
    raise ValueError(f"plane must be '' (3D), 'xz' or 'yz', got '{plane}'")


class Contacts:
    """Point contacts of a model with a terrain.

    model: the robot (not changed: ``self.model`` is a copy with the contact inputs appended).
    points: [(body name or index, point (3,) in the body's joint frame), ...].
    mu: friction coefficient; plane: '' for 3D friction, 'xz' / 'yz' for a planar robot.
    """

    def __init__(self, model: Model, points: Sequence[Tuple[Union[str, int], Sequence[float]]],
                 terrain: Terrain, mu: float, plane: str = "") -> None:
        if not points:
            raise ValueError("give at least one contact point")
        if not (np.isfinite(mu) and mu >= 0):
            raise ValueError(f"mu must be finite and non-negative, got {mu}")
        self.terrain, self.mu = terrain, float(mu)
        self.D = friction_directions(plane)
        self.d = len(self.D)
        self.points: List[ContactPoint] = []
        for body, point in points:
            b = model.body_index(body) if isinstance(body, str) else int(body)
            if not 0 <= b < model.n:
                raise ValueError(f"unknown contact body {body!r}")
            p = np.asarray(point, dtype=float)
            if p.shape != (3,) or not np.all(np.isfinite(p)):
                raise ValueError(f"contact point must be 3 finite numbers, got {point!r}")
            self.points.append(ContactPoint(b, p))
        self.m_user = model.n_controls
        self.model = model.copy()
        self.first_input = self.model.n_controls
        for c in self.points:
            lam = self.model.add_control()
            self.model.add_point_wrench(c.body, force=(0.0, 0.0, 1.0), point=c.point, control=lam)
            for direction in self.D:
                beta = self.model.add_control()
                self.model.add_point_wrench(c.body, force=direction, point=c.point, control=beta)
            self.model.add_control()  # gamma: a slack, no force

    @property
    def n_contacts(self) -> int:
        return len(self.points)

    @property
    def inputs_per_contact(self) -> int:
        return 2 + self.d

    def input_index(self, c: int, what: str, i: int = 0) -> int:
        """The control index of contact c's 'normal', 'friction' (direction i) or 'slack' input."""
        base = self.first_input + c * self.inputs_per_contact
        return {"normal": base, "friction": base + 1 + i, "slack": base + 1 + self.d}[what]

    def input_bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """Bounds of the contact inputs (all >= 0)."""
        k = self.n_contacts * self.inputs_per_contact
        return np.zeros(k), np.full(k, np.inf)

    def effort_weights(self, weight: Union[float, Sequence[float]] = 1.0) -> np.ndarray:
        """ControlEffort weights: ``weight`` on the model's own controls, zero on the contact inputs."""
        w = np.zeros(self.model.n_controls)
        w[:self.m_user] = weight
        return w

    def forces(self, u: np.ndarray) -> np.ndarray:
        """World contact forces (P, contacts, 3) from controls u (P, m) of the contact model."""
        u = np.atleast_2d(u)
        out = np.zeros((len(u), self.n_contacts, 3))
        for c in range(self.n_contacts):
            out[:, c, 2] = u[:, self.input_index(c, "normal")]
            beta = u[:, self.input_index(c, "friction"):self.input_index(c, "friction") + self.d]
            out[:, c] += beta @ self.D
        return out
