"""Built-in models (``hovi simulate NAME``; the registry is ``hovi.examples.REGISTRY``) and the paths of
the URDF files installed with hovi (``urdf_path``)."""
from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, Tuple

import numpy as np

from .. import _core
from .._typing import FloatArray
from .robots import URDF_DIR

__all__ = ["pendulum", "acrobot", "cartpole", "fourbar", "slider_crank", "urdf_path"]


def pendulum(n: int, length: float = 0.5, mass: float = 1.0, radius: float = 0.02) -> _core.Model:
    """The paper's n-link 3D pendulum benchmark (Fan et al. 2018, Sec. 5).

    A serial chain of ``n`` identical uniform solid cylinders (``length`` m, ``mass`` kg,
    ``radius`` m) hanging along -z at q = 0. Joint 1 is at the world origin and joint i at the
    lower end of link i-1; the revolute axes alternate between x (joints 1, 3, ...) and y
    (joints 2, 4, ...), so the chain moves in 3D. Gravity is (0, 0, -9.81).
    """
    return _core.pendulum(int(n), float(length), float(mass), float(radius))


def _rod(length: float, mass: float) -> Dict[str, Any]:
    """A slender rod hanging along -z from its joint: centre of mass and inertia about it."""
    I = mass * length ** 2 / 12
    return dict(mass=mass, com=[0.0, 0.0, -length / 2], inertia=np.diag([I, I, 1e-4 * mass * length ** 2]))


def _below(dz: float) -> FloatArray:
    T = np.eye(4)
    T[2, 3] = -dz
    return T


def acrobot(length: float = 1.0, mass: float = 1.0) -> _core.Model:
    """A planar double pendulum (x-z plane, joints about y) hanging along -z at q = 0, actuated at
    the elbow only (control 0 is the elbow torque): the acrobot."""
    m = _core.Model()
    m.add_body("link1", None, axis=[0, 1, 0], joint_name="shoulder", **_rod(length, mass))
    m.add_body("link2", "link1", axis=[0, 1, 0], placement=_below(length), joint_name="elbow", **_rod(length, mass))
    m.add_actuator("elbow")
    return m


def cartpole(cart_mass: float = 1.0, pole_mass: float = 0.3, pole_length: float = 0.5) -> _core.Model:
    """A cart on a rail along x (prismatic joint 'slider') with a pole hanging along -z at q = 0
    (revolute joint 'hinge' about y), pushed by a force on the cart (control 0)."""
    m = _core.Model()
    m.add_body("cart", None, joint_type="prismatic", axis=[1, 0, 0], joint_name="slider", mass=cart_mass,
               inertia=np.eye(3) * 0.01 * cart_mass)
    m.add_body("pole", "cart", axis=[0, 1, 0], joint_name="hinge", **_rod(pole_length, pole_mass))
    m.add_actuator("slider")
    return m


def quadrotor(mass: float = 1.0, arm: float = 0.2, drag: float = 0.02) -> _core.Model:
    """A quadrotor on the free joint (q = (x, y, z, qx, qy, qz, qw), nq = 7, n = 6): a body of ``mass``
    with four rotors at ``arm`` along +x, +y, -x, -y, rotor k's thrust u[k] (N) along the body's z and
    its drag torque ``drag`` u[k] (N m) about z, turning the other way on neighbouring rotors. Hovers at
    u = mass g / 4 each."""
    m = _core.Model()
    m.add_body("body", None, "free", mass=mass, inertia=mass * np.diag([0.01, 0.01, 0.018]))
    for k, (x, y) in enumerate([(arm, 0.0), (0.0, arm), (-arm, 0.0), (0.0, -arm)]):
        m.add_point_wrench("body", force=(0.0, 0.0, 1.0), torque=(0.0, 0.0, drag * (-1) ** k), point=(x, y, 0.0),
                           frame="body", control=m.add_control())
    return m


def _along_x(L: float, mass: float) -> Dict[str, Any]:
    """A slender rod along x from its joint: centre of mass at L/2."""
    return dict(mass=mass, com=[L / 2, 0, 0], inertia=np.diag([1e-4, mass * L * L / 12, mass * L * L / 12]))


def _at_x(x: float) -> FloatArray:
    T = np.eye(4)
    T[0, 3] = x
    return T


def fourbar(L1: float = 0.3, L2: float = 0.8, L3: float = 0.6, d: float = 0.7) -> _core.Model:
    """A planar crank-rocker four-bar in the x-z plane (joints about y, 1 kg rods): crank and coupler
    from the origin, rocker from (d, 0, 0); a loop constraint joins the coupler's end to the
    rocker's end. 3 joints, 2 constraint equations, 1 DoF."""
    m = _core.Model()
    m.add_body("crank", None, axis=[0, 1, 0], **_along_x(L1, 1.0))
    m.add_body("coupler", "crank", axis=[0, 1, 0], placement=_at_x(L1), **_along_x(L2, 1.0))
    m.add_body("rocker", None, axis=[0, 1, 0], placement=_at_x(d), **_along_x(L3, 1.0))
    m.add_loop_constraint("coupler", [L2, 0, 0], "rocker", [L3, 0, 0], axes="xz")
    return m


def slider_crank(crank: float = 0.2, rod_length: float = 0.5) -> _core.Model:
    """A slider-crank in the x-z plane (joints about y): a crank (1 kg) from the origin and a rod
    (0.7 kg) from the crank's end, whose end slides on the line z = 0 (a one-axis point
    constraint: a prismatic-like joint without a slider body). 2 joints, 1 DoF."""
    m = _core.Model()
    m.add_body("crank", None, axis=[0, 1, 0], **_along_x(crank, 1.0))
    m.add_body("rod", "crank", axis=[0, 1, 0], placement=_at_x(crank), **_along_x(rod_length, 0.7))
    m.add_point_constraint("rod", point=[rod_length, 0, 0], target=[0, 0, 0], axes="z")
    return m


def _installed_urdfs() -> Tuple[str, ...]:
    """The names (without .urdf) of the URDF files installed with hovi, sorted."""
    return tuple(sorted(p.stem for p in URDF_DIR.glob("*.urdf")))


def urdf_path(name: str) -> Path:
    """The path of the URDF file ``name`` installed with hovi (the repository's ``models/``, installed
    as ``hovi/urdf/``), valid from any working directory:
    ``hovi.Model.from_urdf(urdf_path("two_link_arm"))``. ``name`` is the file's name with or without
    ``.urdf``: ``'atlas'``, ``'cartpole'``, ``'double_pendulum'``, ``'littledog'``,
    ``'spring_flamingo'``, ``'two_link_arm'``. ValueError naming the available files for an unknown
    name; FileNotFoundError if the package was installed without its URDFs."""
    stem = name[:-len(".urdf")] if name.endswith(".urdf") else name
    available = _installed_urdfs()
    if not available:
        raise FileNotFoundError(f"no URDF files in {URDF_DIR}: hovi's URDFs are installed with the package "
                                f"(pip install .); a copy of the source tree has them in models/")
    if stem not in available:
        raise ValueError(f"no URDF named '{name}' is installed with hovi (available: {', '.join(available)})")
    return URDF_DIR / f"{stem}.urdf"
