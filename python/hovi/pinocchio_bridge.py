"""A Pinocchio model as a hovi model in one call: ``hovi.from_pinocchio(pin_model)``.

Joints map one to one, in Pinocchio's order: revolute (RX, RY, RZ, unaligned, and the unbounded
'continuous' ones, whose configuration Pinocchio stores as (cos, sin) and hovi as the angle),
prismatic (PX, PY, PZ, unaligned), and a free flyer at the root (hovi's free joint: q and v then
pass between the two unchanged). Each joint's placement, inertia (mass, centre of mass, rotational
inertia about it), position limits and name are kept; a joint's body is named after the first
body frame on it (the link; frames merged into it through fixed joints are not kept yet), and the
model's gravity is Pinocchio's. Other joint types (spherical, planar, composite, ...) and a free
flyer below the root raise hovi.ModelError naming the joint. Needs the ``pinocchio`` package (not a
dependency of hovi's core)."""
from __future__ import annotations

from typing import Any

import numpy as np

from ._core import Model, ModelError

AXES = {"X": (1.0, 0.0, 0.0), "Y": (0.0, 1.0, 0.0), "Z": (0.0, 0.0, 1.0)}


def _joint_kind(joint: Any, name: str) -> tuple[str, tuple[float, ...]]:
    """('revolute' | 'prismatic' | 'free', axis) of a Pinocchio joint model."""
    short = joint.shortname()
    kind = short[len("JointModel"):]
    if kind in ("RX", "RY", "RZ", "RUBX", "RUBY", "RUBZ"):
        return "revolute", AXES[kind[-1]]
    if kind in ("PX", "PY", "PZ"):
        return "prismatic", AXES[kind[-1]]
    if kind in ("RevoluteUnaligned", "RevoluteUnboundedUnaligned", "PrismaticUnaligned"):
        axis = tuple(float(x) for x in joint.extract().axis)
        return ("prismatic" if kind.startswith("Prismatic") else "revolute"), axis
    if kind == "FreeFlyer":
        return "free", (0.0, 0.0, 1.0)
    raise ModelError(f"from_pinocchio: joint '{name}' is a {short}, which hovi does not have (it takes revolute, "
                     "prismatic and a free flyer at the root)")


def from_pinocchio(pin_model: Any) -> Model:
    """The hovi Model of a ``pinocchio.Model`` (see the module's docstring)."""
    import pinocchio as pin  # type: ignore[import-untyped, unused-ignore]
    if not isinstance(pin_model, pin.Model):
        raise TypeError(f"pin_model must be a pinocchio.Model, got {type(pin_model).__name__}")
    body_of = {}
    for frame in pin_model.frames:
        if frame.type == pin.FrameType.BODY and frame.parentJoint not in body_of:
            body_of[frame.parentJoint] = frame.name
    model = Model()
    lower, upper = np.asarray(pin_model.lowerPositionLimit), np.asarray(pin_model.upperPositionLimit)
    for j in range(1, pin_model.njoints):
        name = str(pin_model.names[j])
        kind, axis = _joint_kind(pin_model.joints[j], name)
        inertia = pin_model.inertias[j]
        body = body_of.get(j, name)
        parent = int(pin_model.parents[j])
        placement = np.asarray(pin_model.jointPlacements[j].homogeneous)
        mass, com, rotational = float(inertia.mass), np.asarray(inertia.lever), np.asarray(inertia.inertia)
        if kind == "free":
            if parent != 0 or not np.allclose(placement, np.eye(4), atol=1e-12):
                raise ModelError(f"from_pinocchio: the free flyer '{name}' must be the root joint at the world's "
                                 "origin (hovi's free joint is the model's first body)")
            model.add_body(body, None, "free", joint_name=name, mass=mass, com=com, inertia=rotational)
            continue
        q = pin_model.joints[j].idx_q
        bounded = pin_model.joints[j].nq == 1
        model.add_body(body, None if parent == 0 else body_of.get(parent, str(pin_model.names[parent])), kind,
                       axis=axis, placement=placement, joint_name=name,
                       lower=float(lower[q]) if bounded else -np.inf, upper=float(upper[q]) if bounded else np.inf,
                       mass=mass, com=com, inertia=rotational)
    model.gravity = np.asarray(pin_model.gravity.linear)
    return model
