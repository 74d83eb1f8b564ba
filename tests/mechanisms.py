"""Constrained mechanisms built in code for the constraint tests and benchmarks."""
import numpy as np

import hovi


def rod(L, mass=1.0):
    """A slender rod along x from its joint: centre of mass at L/2."""
    return dict(mass=mass, com=[L / 2, 0, 0], inertia=np.diag([1e-4, mass * L * L / 12, mass * L * L / 12]))


def translate(x=0.0, y=0.0, z=0.0):
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


def fourbar(L1=0.3, L2=0.8, L3=0.6, d=0.7, loop=True):
    """A planar crank-rocker four-bar in the x-z plane (joints about y, gravity -z): crank and
    coupler from the origin, rocker from (d, 0, 0); the coupler's end meets the rocker's end.
    loop=True closes it with a loop constraint between the two branches; loop=False instead
    pins the coupler's end to the world point where the rocker's end is at the projected state
    (a 2-DoF chain with a point constraint), used for the pinned-tip checks."""
    m = hovi.Model()
    m.add_body("crank", None, axis=[0, 1, 0], **rod(L1))
    m.add_body("coupler", "crank", axis=[0, 1, 0], placement=translate(L1), **rod(L2))
    m.add_body("rocker", None, axis=[0, 1, 0], placement=translate(d), **rod(L3))
    m.add_loop_constraint("coupler", [L2, 0, 0], "rocker", [L3, 0, 0], axes="xz")
    return m


def pinned_chain(n=5, length=0.5):
    """The n-link 3D pendulum with its tip (end of the last link) pinned where it is at the
    configuration q_pin (a bent chain, so that the constraint is regular)."""
    model = hovi.models.pendulum(n, length=length)
    q_pin = np.array([0.4 * (-1) ** i for i in range(n)])
    tip = model.joint_placements(q_pin)[-1] @ np.array([0, 0, -length, 1.0])
    model.add_point_constraint(n - 1, point=[0, 0, -length], target=tip[:3])
    return model, q_pin
