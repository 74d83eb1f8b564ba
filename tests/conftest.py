"""Shared helpers and fixtures for the hovi test suite."""
import importlib
import os
import sys

import numpy as np
import pytest


def erd_urdf(rel):
    """Absolute path of an example-robot-data URDF, e.g. 'panda_description/urdf/panda.urdf'.

    ``example_robot_data.getModelPath(rel)`` returns the 'robots' directory that contains ``rel``.
    """
    erd = pytest.importorskip("example_robot_data")
    path = os.path.join(erd.getModelPath(rel), rel)
    if not os.path.isfile(path):
        pytest.skip(f"example-robot-data file not found: {rel}")
    return path


BENCH = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench")


def bench_module(name):
    """The benchmark script bench/<name>.py imported as a module (bench/ on sys.path only while it
    imports, so its own ``from common import ...`` resolves)."""
    sys.path.insert(0, BENCH)
    try:
        return importlib.import_module(name)
    finally:
        sys.path.remove(BENCH)


@pytest.fixture
def rng():
    """A fixed-seed random generator (a fresh one per test, so tests are order-independent)."""
    return np.random.default_rng(20180611)


def observed_order(integrator_for, q0, qd0, reference, dts, T=1.0):
    """Fitted log-log slope of ||q(T) - reference|| over the time steps dts, each run by
    integrator_for(dt).rollout from (q0, qd0); returns (slope, errors)."""
    errors = []
    for dt in dts:
        traj = integrator_for(dt).rollout(q0, int(round(T / dt)), qdot0=qd0)
        errors.append(np.linalg.norm(traj.q[-1] - reference))
    return np.polyfit(np.log(dts), np.log(errors), 1)[0], errors


def planar_point_mass(mass=1.0, actuated=False):
    """A point mass moving in the x-z plane: prismatic x (massless) then prismatic z (the mass), its x
    actuated if ``actuated`` (the contact tests' block)."""
    import hovi
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=mass, inertia=np.eye(3) * 1e-3)
    if actuated:
        model.add_actuator(0)
    return model


@pytest.fixture(scope="module")
def cartpole_lqr():
    """The cart-pole (s = 2, dt = 0.01) and its LQR policy at the upright (q = (0, pi))."""
    import hovi
    from hovi import control
    from hovi.examples import models
    integ = hovi.Integrator(models.cartpole(), s=2, dt=0.01)
    return integ, control.lqr(integ, np.array([0.0, np.pi]))

