"""The paper's robots standing on their terrain in the contact simulator: joint PD control about
the nominal pose q0 (``Robot.q0``) plus the static feed-forward torques that hold q0 with the
feet loaded (``hovi.control.static_controls`` on the trajectory optimiser's contact model, least
norm over the controls and the contact forces).

The PD law is built into the model as a spring (stiffness kp, rest angle q0) and a damper (kd) on
each actuated joint (GAINS), so that it acts inside the C++ step (no Python per step) and implicitly in
the damper: u = u_ff - kp (q - q0) - kd q̇. The stiffness that a step resolves is bounded by the
integrator (s = 1 is Störmer-Verlet in the potential forces: stable while the fastest joint
oscillation has omega dt < 2), so each robot has its own gains and dt (measured: bench/README.md,
"Contact simulation"). Spring Flamingo's ankles are passive springs of 1 N m/rad: its legs are an
inverted pendulum on them that no hip or knee PD holds (it falls in about a second), so its
standing scene stiffens them (``ANKLE_STIFFNESS``), as a robot with actuated ankles would."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Dict, Tuple

import numpy as np

from ..contact import DEFAULT_FRICTION, Contacts, Terrain
from ..integrator import Integrator
from .._core import Model
from .._typing import FloatArray
from .robots import Robot, atlas, littledog, spring_flamingo
from ..control.statics import static_controls

ANKLE_STIFFNESS = 300.0  # N m/rad: Spring Flamingo's ankles when it stands (the example's are 1 N m/rad)
# (f Hz, kp_min N m/rad, legs, dt s) per robot: each actuated joint j gets kp_j = M_jj (2 pi f)^2, at
# least kp_min on the joints whose name contains ``legs``, and kd_j = max(2 zeta M_jj 2 pi f, kp_j / 10)
# (M_jj the joint's diagonal of the mass matrix at q0, zeta = 0.7): alone, each joint is a damped
# oscillator of f Hz. The floor is for the stance legs, which hold the whole body as an inverted
# pendulum that their own M_jj (a foot, a shin) does not see: Atlas tips over in seconds below
# about 1000 N m/rad on its legs; and the light LittleDog legs need 20. dt: s = 1 is Störmer-Verlet
# in the springs, unstable once omega dt > 2 on the stiffest, lightest joint (Atlas at dt = 0.01).
GAINS: Dict[str, Tuple[float, float, str, float]] = {
    "littledog": (5.0, 20.0, "", 0.005),
    "spring_flamingo": (5.0, 0.0, "", 0.005),
    "atlas": (5.0, 3000.0, "_leg_", 0.005),
}
ZETA = 0.7


@dataclass
class Standing:
    """A robot standing: ``integrator`` (with the PD springs and dampers and the contacts) from ``q0``
    with the constant feed-forward controls ``u`` (m,); ``plant`` is the robot without the PD, on the
    same contacts, for a controller of one's own (``hovi.control.lqr(scene.plant, scene.rest)``)."""
    robot: Robot
    model: Model
    contacts: Contacts
    integrator: Integrator
    q0: FloatArray
    u: FloatArray

    @property
    def plant(self) -> Integrator:
        """The robot's own model (no PD springs or dampers) with the scene's contacts, s and dt."""
        return Integrator(self.robot.model, s=self.integrator.s, dt=self.integrator.dt, contacts=self.contacts)

    @functools.cached_property
    def rest(self) -> FloatArray:
        """The pose the robot settles to under the PD from q0 (its feet on the ground, loaded): 2 s of the
        scene. ValueError if it is still moving then."""
        traj = self.integrator.rollout(self.q0, int(round(2.0 / self.integrator.dt)), u=self.u)
        speed = float(np.abs(traj.q[-1] - traj.q[-2]).max() / self.integrator.dt)
        if speed > 1e-6:
            raise ValueError(f"the {self.robot.name} scene does not come to rest in 2 s (joint speeds up to {speed:.3g})")
        rest: FloatArray = traj.q[-1].copy()
        return rest


def pd_model(robot: Robot, frequency: float, kp_min: float = 0.0, legs: str = "") -> Model:
    """A copy of the robot's model with a spring about q0 and a damper on every actuated joint, of the
    gains GAINS describes for ``frequency`` (Hz), ``kp_min`` and ``legs``."""
    model = robot.model.copy()
    M = robot.model.mass_matrix(robot.q0)
    w = 2 * np.pi * frequency
    for joint in robot.actuated:
        j = model.joint_index(joint)
        kp = max(M[j, j] * w * w, kp_min if legs in joint else 0.0)
        model.add_spring(joint, kp, float(robot.q0[j]))
        model.add_damper(joint, max(2 * ZETA * M[j, j] * w, kp / 10))
    return model


def standing(name: str, dt: float | None = None, frequency: float | None = None, *, mu: float = DEFAULT_FRICTION,
             ground: float = 0.0, s: int = 1) -> Standing:
    """The standing scene of robot ``name`` ('littledog', 'spring_flamingo' or 'atlas'), with its
    GAINS and dt unless given, on flat ground at height ``ground`` with friction ``mu``, simulated
    with the VI of order 2s (the one scene builder of ``hovi simulate <robot>`` too)."""
    builders = {"littledog": littledog, "spring_flamingo": lambda: spring_flamingo(ANKLE_STIFFNESS), "atlas": atlas}
    if name not in builders:
        raise ValueError(f"no standing scene for {name!r}; choose one of {', '.join(builders)}")
    robot = builders[name]()
    f, kp_min, legs, dt0 = GAINS[name]
    plane = "xz" if robot.base == "planar" else ""
    statics = Contacts(robot.model, robot.contact_points, Terrain(), mu=DEFAULT_FRICTION, plane=plane)  # at q0
    u = static_controls(statics.with_inputs, robot.q0)[:statics.m_user]
    model = pd_model(robot, f if frequency is None else frequency, kp_min, legs)
    contacts = Contacts(model, robot.contact_points, Terrain(ground=ground), mu=mu, plane=plane)
    integrator = Integrator(model, s=s, dt=dt0 if dt is None else dt, contacts=contacts)
    return Standing(robot, model, contacts, integrator, robot.q0.copy(), u)
