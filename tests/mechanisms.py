"""Constrained mechanisms built in code for the constraint tests and benchmarks."""
import numpy as np

import hovi
from hovi.examples.models import fourbar, slider_crank  # noqa: F401 (the shared mechanisms)


def rod(L, mass=1.0):
    """A slender rod along x from its joint: centre of mass at L/2."""
    return dict(mass=mass, com=[L / 2, 0, 0], inertia=np.diag([1e-4, mass * L * L / 12, mass * L * L / 12]))


def translate(x=0.0, y=0.0, z=0.0):
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


def pinned_chain(n=5, length=0.5):
    """The n-link 3D pendulum with its tip (end of the last link) pinned where it is at the
    configuration q_pin (a bent chain, so that the constraint is regular)."""
    model = hovi.examples.models.pendulum(n, length=length)
    q_pin = np.array([0.4 * (-1) ** i for i in range(n)])
    tip = model.joint_placements(q_pin)[-1] @ np.array([0, 0, -length, 1.0])
    model.add_point_constraint(n - 1, point=[0, 0, -length], target=tip[:3])
    return model, q_pin

