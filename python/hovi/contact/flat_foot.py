"""A foot flat on the ground (a stance foot) as a contact wrench: six inputs of the model, the force
f and torque tau at the centre of a rectangular sole, with the sole held at its pose and the wrench
kept inside the contact wrench cone of the rectangle (Hereid et al.'s flat-foot contact; the cone
in closed form after Caron, Pham and Nakamura, RSS 2015).

The sole frame is the foot body's frame at the initial configuration, which must be flat (its z
axis vertical); the sole is the rectangle |x| <= X, |y| <= Y around ``centre`` in that frame. The
wrench w = (f, tau), in the sole frame at the centre, is the sum of forces at the four corners,
each in the friction pyramid |f_x|, |f_y| <= mu f_z. That set is the cone G w >= 0 with the rows

    f_z >= 0,  mu f_z -+ f_x >= 0,  mu f_z -+ f_y >= 0          (unilateral, friction)
    Y f_z -+ tau_x >= 0,  X f_z -+ tau_y >= 0                     (centre of pressure in the sole)
    tau_z - tau_min >= 0,  tau_max - tau_z >= 0                   (yaw friction; 4 rows each)

    tau_min = -mu (X + Y) f_z + |Y f_x - mu tau_x| + |X f_y - mu tau_y|
    tau_max =  mu (X + Y) f_z - |Y f_x + mu tau_x| - |X f_y + mu tau_y|

(tests/test_flat_foot.py checks it against a linear program over the corner forces).
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import Sequence, Tuple, Union

import numpy as np

from .._checks import real_array, real_number
from .._core import Model
from .contacts import Contacts, check_robot, contact_body, friction_coefficient, robot_names
from .terrain import Terrain


def wrench_cone(X: float, Y: float, mu: float) -> np.ndarray:
    """G (17, 6): w = (f, tau) at the centre of the sole |x| <= X, |y| <= Y (sole frame) is a sum of
    corner forces in the friction pyramid of mu iff G w >= 0."""
    rows = [[0, 0, 1, 0, 0, 0]]
    for sign in (1, -1):
        rows += [[-sign, 0, mu, 0, 0, 0], [0, -sign, mu, 0, 0, 0],
                 [0, 0, Y, -sign, 0, 0], [0, 0, X, 0, -sign, 0]]
    for s1, s2 in itertools.product((1, -1), repeat=2):
        # tau_z + mu (X + Y) f_z - s1 (Y f_x - mu tau_x) - s2 (X f_y - mu tau_y) >= 0
        rows.append([-s1 * Y, -s2 * X, mu * (X + Y), s1 * mu, s2 * mu, 1])
        # -tau_z + mu (X + Y) f_z - s1 (Y f_x + mu tau_x) - s2 (X f_y + mu tau_y) >= 0
        rows.append([-s1 * Y, -s2 * X, mu * (X + Y), -s1 * mu, -s2 * mu, -1])
    return np.array(rows, dtype=float)


@dataclass(frozen=True, eq=False)
class Stance:
    """A body held at its pose at configuration q0 (n,) at every configuration point: its point
    ``point`` (3,) and the sole's half-sizes ``size`` (X, Y) (``Problem.add_constraint`` turns it
    into a ``hovi.trajopt.PoseHeld``)."""
    body: int
    q0: np.ndarray
    point: np.ndarray
    size: Tuple[float, float]
    robot: Tuple[Tuple[str, ...], Tuple[str, ...]]  # the foot's model's body and joint names


@dataclass(frozen=True, eq=False)
class WrenchCone:
    """The linear rows ``lower <= A u <= upper`` on the controls u (m,) at every control value that
    keep a foot's wrench in its cone (``Problem.add_constraint`` turns them into a
    ``hovi.trajopt.InputConstraint``)."""
    A: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    robot: Tuple[Tuple[str, ...], Tuple[str, ...]]  # the foot's model's body and joint names


class FlatFoot:
    """A stance foot: ``body`` (name or index) with a rectangular sole of half-length X (along the
    body's x axis) and half-width Y (its y axis) centred at ``centre`` (3,) (in the body's joint
    frame), friction coefficient mu, flat on the ground (its z axis vertical within 1e-3 degrees) at
    the initial configuration q0 (n,).

    ``with_inputs`` is a copy of ``model`` with six inputs appended (``first_input`` ..
    ``first_input + 5``): the force and torque at the sole centre along the sole frame's axes, in
    units of ``scale`` N and N m (default: the robot's weight, so that the inputs are of order
    one; ``wrench(u)`` converts). Add ``stance()`` (the foot held at its pose) and ``cone()`` (the
    wrench in its cone) to the Problem (``Problem.add_constraint``).
    """

    def __init__(self, model: Model, body: Union[str, int], centre: Sequence[float], X: float, Y: float,
                 mu: float, q0: Sequence[float], scale: float | None = None) -> None:
        if not isinstance(model, Model):
            raise TypeError(f"model must be a hovi.Model, got {type(model).__name__}")
        self.body = contact_body(model, body, "foot body")
        try:
            self.centre = real_array(centre, "the sole centre", (3,))
        except (TypeError, ValueError) as e:
            raise ValueError(f"{e}: the sole centre must be 3 finite numbers, got {centre!r:.60}") from None
        for name, value in (("X", X), ("Y", Y)):
            real_number(value, f"the sole's half-size {name}", minimum=0.0, strict_minimum=True)
        mu = friction_coefficient(mu, positive=True)
        try:
            q0 = real_array(q0, "q0", (model.n,))
        except (TypeError, ValueError) as e:
            raise ValueError(f"{e}: q0 must be {model.n} finite numbers") from None
        pose = model.joint_placements(q0)[self.body]
        self.robot = robot_names(model)
        self.R0 = pose[:3, :3]
        tilt = np.degrees(np.arccos(np.clip(self.R0[2, 2], -1.0, 1.0)))
        if tilt > 1e-3:  # degrees
            raise ValueError(f"the foot is not flat at q0: its z axis is {tilt:.3g} degrees from vertical")
        self.X, self.Y, self.mu, self.q0 = float(X), float(Y), float(mu), q0
        self.with_inputs = model.copy()
        self.first_input = self.with_inputs.n_controls
        weight = model.total_mass * float(np.linalg.norm(model.gravity))
        self.scale = (weight if weight > 0 else 1.0) if scale is None else \
            real_number(scale, "scale", minimum=0.0, strict_minimum=True)
        for axis in self.R0.T:                                               # f along the sole axes
            self.with_inputs.add_point_wrench(self.body, force=self.scale * axis, point=self.centre,
                                        control=self.with_inputs.add_control())
        for axis in self.R0.T:                                               # tau about them
            self.with_inputs.add_point_wrench(self.body, torque=self.scale * axis, point=self.centre,
                                        control=self.with_inputs.add_control())

    def stance(self) -> Stance:
        """The foot held at its pose at q0 at every configuration point (a path constraint once added
        to a Problem)."""
        return Stance(self.body, self.q0, self.centre, (self.X, self.Y), self.robot)

    def cone(self, n_controls: int | None = None) -> WrenchCone:
        """The rows G w >= 0 (``wrench_cone``) on the foot's wrench inputs at every point (an input
        constraint once added to a Problem), for a model with ``n_controls`` controls (default:
        ``with_inputs``'s; more if inputs were appended after the foot's, e.g. by
        ``Contacts(foot.with_inputs, ...)``)."""
        A = np.zeros((17, self.with_inputs.n_controls if n_controls is None else int(n_controls)))
        A[:, self.first_input:self.first_input + 6] = wrench_cone(self.X, self.Y, self.mu)
        return WrenchCone(A, lower=np.zeros(17), upper=np.full(17, np.inf), robot=self.robot)

    def corners(self) -> list[Tuple[int, np.ndarray]]:
        """The sole's four corners [(body, point (3,) in its joint frame), ...]: the contact points the
        simulator takes for this foot (``Contacts.from_flat_feet``). The wrench cone is the set of sums
        of forces at them, each in its friction pyramid, so the two models of the foot agree."""
        return [(self.body, self.centre + np.array([sx * self.X, sy * self.Y, 0.0]))
                for sx in (1.0, -1.0) for sy in (1.0, -1.0)]

    def wrench(self, u: np.ndarray) -> np.ndarray:
        """The wrenches (P, 6) (f, tau in the sole frame at its centre; N, N m) in the controls u (P, m)."""
        u = real_array(u, "u")
        m = self.with_inputs.n_controls
        if u.ndim not in (1, 2) or u.shape[-1] < self.first_input + 6:
            raise ValueError(f"u must be controls (P, m) or (m,) of the foot's model (m >= {self.first_input + 6}: "
                             f"its {m} inputs, and any appended after them), got shape {u.shape}")
        return self.scale * np.atleast_2d(u)[:, self.first_input:self.first_input + 6]

    def centre_of_pressure(self, u: np.ndarray) -> np.ndarray:
        """The centre of pressure (P, 2) in the sole frame relative to its centre: (-tau_y, tau_x) / f_z."""
        w = self.wrench(u)
        return np.stack([-w[:, 4], w[:, 3]], axis=1) / w[:, 2:3]


def flat_feet_contacts(model: Model, feet: Sequence[FlatFoot], terrain: Terrain, plane: str = "") -> Contacts:
    """Point contacts at the sole corners of flat feet (``FlatFoot.corners``), with the feet's friction
    coefficient: the contact simulator's model of a flat foot (``hovi.Integrator(..., contacts=...)``),
    whose set of contact wrenches is the trajectory optimiser's wrench cone."""
    if isinstance(feet, (str, bytes)) or not isinstance(feet, Sequence) or not feet:
        raise ValueError("feet must be a non-empty list of hovi.contact.FlatFoot")
    for i, foot in enumerate(feet):
        if not isinstance(foot, FlatFoot):
            raise TypeError(f"feet[{i}] must be a hovi.contact.FlatFoot, got {type(foot).__name__}")
        check_robot(foot.robot, model, f"feet[{i}]")
    mus = {foot.mu for foot in feet}
    if len(mus) != 1:
        raise ValueError(f"the feet have different friction coefficients {sorted(mus)}: give feet of one mu")
    return Contacts(model, [corner for foot in feet for corner in foot.corners()], terrain, mu=mus.pop(), plane=plane)
