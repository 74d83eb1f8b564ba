"""Rigid point contacts with Coulomb friction, as force inputs of the model.

Each contact point c (a point of a body, in its joint frame) gets 2 + d inputs appended to the
model's controls: the normal force lambda_c along the surface normal +z, the friction
coefficients beta_c,i >= 0 of the d friction directions D_i (a polyhedral cone: +-x, +-y in 3D
(d = 4), +-x in the x-z plane (d = 2)), and a slack gamma_c (no force: the magnitude of the
sliding velocity at the optimum, Stewart-Trinkle / Manchester-Kuindersma). The forces enter the
DEL equations as point forces at the control points (``Model.add_point_wrench`` with a control),
like the constraint forces, so their Jacobians come from the existing linearisation.

The complementarity conditions (``ContactRows`` in ``hovi.trajopt.complementarity`` builds them
for a transcription) pair the inputs at configuration point i with the motion that follows it:

    phi_c(q_{i+1}) >= 0,  lambda_i >= 0,  lambda_i phi_c(q_{i+1}) = 0        (no penetration, no pull)
    mu lambda_i - sum_k beta_i,k >= 0,  gamma_i >= 0,  their product = 0    (friction cone)
    gamma_i + D_k^T v_i >= 0,  beta_i,k >= 0,  their product = 0            (maximal dissipation)

with v_i the contact point's velocity over [t_i, t_{i+1}] (a difference of positions), and the
inputs at the last point equal to those of the point before. This is Stewart and Trinkle's time
stepping (Manchester and Kuindersma's variational form): the force that decides whether q_{i+1}
penetrates is one that acts on it. A force at a point cannot move that point itself: in the
Galerkin VI the force at a knot only enters the following stage, so pairing lambda_i with
phi(q_i) leaves the knots without a force that can stop a falling body (time stepping that
system finds no solution at some impacts and a rebound at others: bench/README.md, "Design
measurements").

With s = 1 (linear stages: ``hovi.trajopt.VI(s=1)``, the order to use for contact) every stage's
conditions form an LCP with a P-matrix (one unique solution) and impacts are inelastic: a dropped
mass lands and stays, lambda = m g from the step after the impact. With s = 2 the stage's LCP is
unique too, but a parabola through the points where it lands turns upwards at the stage's end: an
impact inside a stage rebounds (a fraction of the impact speed whatever dt; bench/README.md). The
other pairing for s = 2 (the knot force with the next knot) has two solutions per resting stage.

Each condition holds exactly at the solution of ``solve_contact`` (see there: a relaxation
homotopy, then an exact solve on the sides of the pairs it found).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, List, Sequence, Tuple, Union

import numpy as np

from .. import _core
from .._bodies import body_index
from .._checks import real_array, real_number
from .._core import Model
from .terrain import Terrain

# The friction coefficient of the ground when none is given (the paper's robot examples', the CLI's).
DEFAULT_FRICTION = 0.8
# The largest friction coefficient taken: real ones are below about 2 (rubber on rough ground);
# mu = 1e3 already means no slip, and beyond it the cone rows mu lambda - sum beta lose their scale.
MAX_FRICTION = 1e3


def friction_coefficient(mu: object, name: str = "mu", *, positive: bool = False) -> float:
    """``mu`` checked: a real number, finite, >= 0 (> 0 with ``positive``) and at most MAX_FRICTION."""
    value = real_number(mu, name, minimum=0.0, strict_minimum=positive)
    if value > MAX_FRICTION:
        raise ValueError(f"{name} must be at most {MAX_FRICTION:g} (a friction coefficient: real ones are below "
                         f"about 2; {MAX_FRICTION:g} already means no slip), got {value:g}")
    return value


def contact_body(model: Model, body: object, what: str) -> int:
    """The index of ``body`` (a name, or an integer index: not a bool or float) in ``model``."""
    if not isinstance(body, (str, int, np.integer)) or isinstance(body, (bool, np.bool_)):
        raise TypeError(f"{what} must be a body name or an integer index, got {type(body).__name__} {body!r:.60}")
    return body_index(model, body if isinstance(body, str) else int(body), what)


def robot_names(model: Model) -> Tuple[Tuple[str, ...], Tuple[str, ...]]:
    """The body and joint names of ``model``: what tells a robot apart from another one."""
    return tuple(model.body_names), tuple(model.joint_names)


def check_robot(robot: Tuple[Tuple[str, ...], Tuple[str, ...]], model: Model, what: str) -> None:
    """ValueError naming ``what`` unless ``robot`` (``robot_names``) is ``model``'s."""
    if robot != robot_names(model):
        raise ValueError(f"{what} was built on another model (bodies {list(robot[0])[:6]}...), not this one "
                         f"(bodies {list(model.body_names)[:6]}...)")


@dataclass(frozen=True)
class ContactPoint:
    """A contact of a body (a name, or its index): ``point`` (3,) in the body's joint frame (the URDF
    link frame), or, with ``radius`` > 0, the centre of a sphere of that radius (a round foot), which
    touches the terrain when the centre is ``radius`` above it; ``name`` tells the contacts apart
    (e.g. 'fl_foot'). The one contact-point type of hovi (``Contacts.points`` hold the body's index)."""
    body: Union[str, int]
    point: Any
    radius: float = 0.0
    name: str = ""

    def __post_init__(self) -> None:
        # checked when made (point: a read-only float array): a bad one never reaches Contacts
        if not isinstance(self.body, (str, int, np.integer)) or isinstance(self.body, (bool, np.bool_)):
            raise TypeError(f"ContactPoint body must be a body name or an integer index, got "
                            f"{type(self.body).__name__} {self.body!r:.60}")
        try:
            point = real_array(self.point, "ContactPoint point", (3,))
        except (TypeError, ValueError) as e:
            raise ValueError(f"{e}: a contact point must be 3 finite numbers (in the body's joint frame), got "
                             f"{self.point!r:.60}") from None
        point.flags.writeable = False
        object.__setattr__(self, "body", self.body if isinstance(self.body, str) else int(self.body))
        object.__setattr__(self, "point", point)
        object.__setattr__(self, "radius", real_number(self.radius, "ContactPoint radius", minimum=0.0))
        if not isinstance(self.name, str):
            raise TypeError(f"ContactPoint name must be a string, got {type(self.name).__name__}")


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

    model: the robot (not changed: ``with_inputs`` is a copy of it with the contact inputs appended, what
    the trajectory optimiser's Problem is made with).
    points: ContactPoints, or (body name or index, point (3,) in the body's joint frame[, radius]) tuples.
    mu: friction coefficient (default DEFAULT_FRICTION, 0.8); plane: '' for 3D friction, 'xz' / 'yz'
    for a planar robot.
    """

    def __init__(self, model: Model, points: Sequence[Union[ContactPoint, Tuple[Any, ...]]],
                 terrain: Terrain, mu: float = DEFAULT_FRICTION, plane: str = "") -> None:
        if not isinstance(model, Model):
            raise TypeError(f"model must be a hovi.Model, got {type(model).__name__}")
        if not isinstance(terrain, Terrain):
            raise TypeError(f"terrain must be a hovi.contact.Terrain, got {type(terrain).__name__}")
        if isinstance(points, (str, bytes, dict, np.ndarray)) or not isinstance(points, Sequence):
            raise TypeError(f"points must be a list of (body name or index, point (3,)), got {type(points).__name__}")
        if not points:
            raise ValueError("give at least one contact point")
        mu = friction_coefficient(mu)
        if not isinstance(plane, str):
            raise ValueError(f"plane must be '' (3D), 'xz' or 'yz', got {plane!r}")
        self.terrain, self.mu = terrain, mu
        self.D = friction_directions(plane)
        self.d = len(self.D)
        points_: List[ContactPoint] = []
        for i, entry in enumerate(points):
            if isinstance(entry, ContactPoint):
                entry = (entry.body, entry.point, entry.radius, entry.name)
            if isinstance(entry, (str, bytes)) or not hasattr(entry, "__len__") or len(entry) not in (2, 3, 4):
                raise ValueError(f"contact point {i}: a contact point is a ContactPoint or (body name or index, point "
                                 f"(3,)[, radius]), got {entry!r}")
            body, point, radius, name = (*entry, 0.0, "")[:4] if len(entry) < 4 else entry
            b = contact_body(model, body, "contact body")
            try:
                p = real_array(point, f"contact point {i} ({body!r})", (3,))
            except (TypeError, ValueError) as e:
                raise ValueError(f"{e}: a contact point must be 3 finite numbers (in the body's joint frame), got "
                                 f"{point!r:.60}") from None
            r = real_number(radius, f"contact point {i} ({body!r}) radius", minimum=0.0)
            points_.append(ContactPoint(b, p, r, str(name)))
        self.points: Tuple[ContactPoint, ...] = tuple(points_)
        self.D.flags.writeable = False
        self.m_user = model.n_controls
        self.robot = (tuple(model.body_names), tuple(model.joint_names), model.n_controls)
        self.first_input = model.n_controls
        self._core = self._contact_model()
        self.with_inputs = self._core.with_inputs(model)
        self._frozen = True

    def _contact_model(self) -> _core.ContactModel:
        return _core.ContactModel([int(c.body) for c in self.points], np.array([c.point for c in self.points]),
                                  self.terrain.core(), self.mu, self.D, self.radii)

    def __setattr__(self, name: str, value: Any) -> None:
        # Fixed once made: an integrator or a problem made with these contacts, and every copy of
        # it, computes with what they were made with.
        if getattr(self, "_frozen", False):
            raise AttributeError(f"Contacts are fixed once made (an integrator made with them keeps them): make a "
                                 f"new hovi.contact.Contacts instead of changing {name!r}")
        super().__setattr__(name, value)

    def __getstate__(self) -> dict:
        return {k: v for k, v in self.__dict__.items() if k not in ("_core", "_frozen")}

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.D.flags.writeable = False
        self.__dict__["_core"] = self._contact_model()
        self.__dict__["_frozen"] = True

    def check_model(self, model: Model) -> None:
        """ValueError unless ``model`` is the robot these contacts were built on (its bodies, joints and
        controls; not ``with_inputs``, which adds the trajectory optimiser's contact inputs)."""
        got = (tuple(model.body_names), tuple(model.joint_names), model.n_controls)
        if got == self.robot:
            return
        if got[:2] == self.robot[:2] and model.n_controls == self.with_inputs.n_controls:
            raise ValueError("contacts: give the robot's own model, not Contacts.with_inputs (which adds the trajectory "
                             f"optimiser's {self.with_inputs.n_controls - self.m_user} contact inputs as controls)")
        raise ValueError(f"contacts were built for another model (bodies {list(self.robot[0])[:6]}..., "
                         f"{self.robot[2]} controls), not this one (bodies {list(got[0])[:6]}..., {got[2]} controls)")

    def core_model(self) -> _core.ContactModel:
        """These contacts as the C++ contact model (the integrator's contact stages, the complementarity
        rows): the points, the terrain, mu and the friction directions, fixed when made."""
        model: _core.ContactModel = self._core
        return model

    @property
    def radii(self) -> np.ndarray:
        """(C,) the contacts' radii (0 for points)."""
        return np.array([c.radius for c in self.points])

    def gaps(self, q: np.ndarray) -> np.ndarray:
        """The signed gaps (C,) of the contacts to the terrain at configuration q (nq,) (of a sphere's
        surface, for a contact with a radius)."""
        q = real_array(q, "q", (self.with_inputs.nq,))
        gaps: np.ndarray = self.core_model().gaps(self.positions(q[None])[0])
        return gaps

    def positions(self, Q: np.ndarray) -> np.ndarray:
        """(K, C, 3) world positions of the contact points (the spheres' centres) at configurations Q (K, nq)."""
        X, _ = _core.body_point_kinematics(self.with_inputs, Q, [int(c.body) for c in self.points],
                                           np.array([c.point for c in self.points]))
        positions: np.ndarray = X
        return positions

    @property
    def n_contacts(self) -> int:
        return len(self.points)

    @property
    def inputs_per_contact(self) -> int:
        return 2 + self.d

    def input_index(self, c: int, what: str, i: int = 0) -> int:
        """The control index of contact c's 'normal', 'friction' (direction i) or 'slack' input."""
        index: int = self.first_input + self.core_model().index(c, what, i)
        return index

    def input_bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """Bounds of the contact inputs (all >= 0)."""
        k = self.n_contacts * self.inputs_per_contact
        return np.zeros(k), np.full(k, np.inf)

    def effort_weights(self, weight: Union[float, Sequence[float]] = 1.0) -> np.ndarray:
        """ControlEffort weights: ``weight`` on the model's own controls, zero on the contact inputs."""
        w = np.zeros(self.with_inputs.n_controls)
        w[:self.m_user] = weight
        return w

    def forces(self, u: np.ndarray) -> np.ndarray:
        """World contact forces (P, contacts, 3) from controls u (P, m) of the contact model."""
        u = real_array(u, "u")
        m = self.with_inputs.n_controls
        if u.ndim not in (1, 2) or u.shape[-1] != m:
            raise ValueError(f"u must be the controls of the contact model, (P, {m}) or ({m},) (the robot's "
                             f"{self.m_user} and {m - self.m_user} contact inputs), got shape {u.shape}")
        forces: np.ndarray = self.core_model().world_impulses(np.atleast_2d(u)[:, self.first_input:])
        return forces
