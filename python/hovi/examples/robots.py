"""The paper's three robots (Fan and Murphey 2018, trajectory optimisation): Spring Flamingo,
LittleDog and Atlas v5, loaded from the URDFs shipped in the package (``hovi/urdf/``, the
repository's ``models/``), with what a URDF does not hold: the base joint, the actuators, the
Spring Flamingo's ankle springs, the foot contacts and a nominal standing configuration. The
numbers and their sources are in the header comment of each URDF."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Dict, List, Sequence, Tuple

import numpy as np

from .._core import Model
from .._typing import FloatArray
from ..contact.contacts import ContactPoint

__all__ = ["URDF_DIR", "Robot", "spring_flamingo", "littledog", "atlas"]

URDF_DIR = Path(__file__).parent.parent / "urdf"
"""Where the package's URDFs are installed (the repository's models/)."""


@dataclass(frozen=True, eq=False)
class Robot:
    """A robot ready for simulation and trajectory optimisation: ``model`` has the base joint, one
    control per actuated joint (control k drives ``actuated[k]``, so ``model.effort_limits`` bound
    them in ``hovi.trajopt.Problem``) and any springs; ``q0`` (n,) stands it on flat ground at z = 0
    (LittleDog's published pose leaves its feet up to 0.35 mm above it)."""
    name: str
    model: Model
    urdf: Path                         # the URDF file
    base: str                          # 'planar' (x, z, pitch) or 'floating' (x, y, z, yaw, pitch, roll)
    contacts: Tuple[ContactPoint, ...]  # the feet, named (e.g. 'l_toe', 'fl_foot'), on links by name, with
                                        # their radius (LittleDog's foot spheres)
    q0: FloatArray                     # (n,) nominal standing configuration, in model.joint_names order
    actuated: Tuple[str, ...]          # (m,) the joints driven by controls 0..m-1

    @property
    def contact_points(self) -> List[ContactPoint]:
        """The contacts as ``hovi.contact.Contacts`` takes them."""
        return list(self.contacts)

    @property
    def contact_radius(self) -> float:
        """The feet's radius (0 for points): a foot touches flat ground at height h when its point
        (the sphere's centre) is at h + radius."""
        return max(c.radius for c in self.contacts)

    @property
    def effort_limits(self) -> FloatArray:
        """(m,) effort limit of each actuated joint (N m), from the URDF."""
        return self.model.effort_limits[[self.model.joint_index(j) for j in self.actuated]]


def _robot(name: str, base: str, contacts: Sequence[ContactPoint], base_q: Sequence[float],
           joint_q: Dict[str, float], passive: Sequence[Tuple[str, float]] = ()) -> Robot:
    """The Robot of models/<name>.urdf: a control on every joint but the base's and the ``passive``
    ones, in the model's joint order; on each passive (joint, stiffness) a spring of that stiffness
    about 0 and a damper of the joint's URDF damping; q0 = the base coordinates ``base_q``, then
    the joint angles ``joint_q`` (0 for joints not named)."""
    urdf = URDF_DIR / f"{name}.urdf"
    model = Model.from_urdf(urdf, base=base)
    for joint, stiffness in passive:
        model.add_spring(joint, stiffness)
        model.add_damper(joint, model.damping[model.joint_index(joint)])
    unactuated = {joint for joint, _ in passive}
    actuated = tuple(j for j in model.joint_names[len(base_q):] if j not in unactuated)
    for joint in actuated:
        model.add_actuator(joint)
    q0 = np.zeros(model.n)
    q0[:len(base_q)] = base_q
    for joint, value in joint_q.items():
        q0[model.joint_index(joint)] = value
    return Robot(name, model, urdf, base, tuple(contacts), q0, actuated)


def spring_flamingo(ankle_stiffness: float = 1.0) -> Robot:
    """Spring Flamingo, the MIT Leg Lab planar biped: 9 DoF (planar base x, z, pitch; hip, knee and
    ankle per leg), 14.2248 kg. Hips and knees actuated (4 controls, 50 N m, a chosen bound); the
    ankles are passive, each with a spring of ``ankle_stiffness`` N m/rad about 0 (Drake's 1 N m/rad)
    and the URDF's damper (0.1 N m s/rad). It walks toward -x; knee flexion is negative. Contacts:
    toe and heel of each foot, 0.035 m below the ankle. q0: legs straight, hip line at 0.875 m."""
    contacts = [ContactPoint(f"{side}_foot", (x, 0.0, -0.035), name=f"{side[0]}_{where}")
                for side in ("left", "right") for where, x in (("toe", -0.1725), ("heel", 0.0575))]
    return _robot("spring_flamingo", "planar", contacts, [0.0, 0.875, 0.0], {},
                  passive=[("left_ankle", ankle_stiffness), ("right_ankle", ankle_stiffness)])


_LITTLEDOG_LEGS = ("front_left", "front_right", "back_left", "back_right")


def littledog() -> Robot:
    """LittleDog, the Boston Dynamics quadruped: 18 DoF (floating body; hip roll, hip pitch and knee
    per leg), 2.7464 kg, all 12 joints actuated (50 N m, placeholder limits of a public copy).
    Contacts: one foot sphere per leg (``contact_radius`` 0.0103 m). q0: the home() pose of
    RobotLocomotion/LittleDog (hip roll +-0.1, hip pitch +-1.0, knee -+1.55), body at 0.146 m."""
    joint_q: Dict[str, float] = {}
    contacts = []
    for leg in _LITTLEDOG_LEGS:
        front, left = leg.startswith("front"), leg.endswith("left")
        joint_q[f"{leg}_hip_roll"] = 0.1 if left else -0.1
        joint_q[f"{leg}_hip_pitch"] = 1.0 if front else -1.0
        joint_q[f"{leg}_knee"] = -1.55 if front else 1.55
        contacts.append(ContactPoint(f"{leg}_lower_leg", (-0.0265 if front else 0.0265, 0.0, -0.0985),
                                     radius=0.0103, name=f"{leg[0]}{leg.split('_')[1][0]}_foot"))
    return _robot("littledog", "euler", contacts, [0.0, 0.0, 0.146, 0.0, 0.0, 0.0], joint_q)


_ATLAS_KNEE = 0.8  # the stance's knee flexion (rad); hip and ankle pitch by half of it keep pelvis and soles level


def atlas() -> Robot:
    """Atlas v5, the Boston Dynamics DRC humanoid: 36 DoF (floating pelvis and 30 revolute joints,
    all actuated, A1's effort limits), 174.0503 kg. Contacts: the 4 corners of each sole. q0: a
    chosen bent-knee stance (no source gives one): knees 0.8 rad, hip and ankle pitch -0.4 rad,
    arms lowered 1.3 rad (shoulder roll), elbows bent 0.3 rad off their joint limits (ely, elx),
    the rest 0; the pelvis at the height that puts the soles on
    z = 0 (0.8951 m; 0.93845 m with straight legs) and the centre of mass over the feet."""
    half = _ATLAS_KNEE / 2
    joint_q = {"r_arm_shx": 1.3, "l_arm_shx": -1.3, "l_arm_ely": 0.3, "r_arm_ely": 0.3,  # elbows off their limits:
               "l_arm_elx": 0.3, "r_arm_elx": -0.3}                                       # an optimiser starts inside
    for s in "lr":
        joint_q.update({f"{s}_leg_hpy": -half, f"{s}_leg_kny": _ATLAS_KNEE, f"{s}_leg_aky": -half})
    # hip pitch 0.066 m below the pelvis, the thigh (-0.05, 0, -0.374) and the 0.422 m shin pitched,
    # the sole 0.07645 m below the ankle
    height = 0.066 + 0.05 * np.sin(half) + (0.374 + 0.422) * np.cos(half) + 0.07645
    contacts = [ContactPoint(f"{s}_foot", (x, y, -0.07645), name=f"{s}_{end}_{side}")
                for s, sides in (("l", (("out", 0.066), ("in", -0.0626))), ("r", (("in", 0.0626), ("out", -0.066))))
                for end, x in (("heel", -0.0876), ("toe", 0.1728)) for side, y in sides]
    return _robot("atlas", "euler", contacts, [0.0, 0.0, height, 0.0, 0.0, 0.0], joint_q)
