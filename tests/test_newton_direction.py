"""Algorithms A.1/A.2 against a dense solve of the finite-difference Jacobian (direction="recursive":
for models this small, "auto" would take the dense LU of the analytic Jacobian instead)."""
import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from del_reference import ForcedScene, fd_jacobian
from test_del_residual import random_point


@pytest.mark.parametrize("s", [1, 2, 3, 4])
@pytest.mark.parametrize("name", ["pendulum", "panda"])
@pytest.mark.parametrize("forces", [False, True])
def test_direction_matches_dense_solve(s, name, forces):
    rng = np.random.default_rng(100 + 10 * s + forces)
    model = hovi.examples.models.pendulum(5) if name == "pendulum" else hovi.Model.from_urdf(
        erd_urdf("panda_description/urdf/panda.urdf"))
    if forces:
        ForcedScene(model, rng)
    integ = hovi.Integrator(model, s=s, dt=0.02, direction="recursive")
    for _ in range(2):
        qc, p = random_point(integ, rng)
        u = rng.normal(size=(s + 1, model.n_controls)) if forces else None
        r, _ = integ.del_residual(qc, p, u)
        J = fd_jacobian(integ, qc, p, u)
        dq_ref = -np.linalg.solve(J, r.ravel()).reshape(s, model.n)
        dq = integ.newton_direction(qc, p, u)
        np.testing.assert_allclose(dq, dq_ref, rtol=0, atol=1e-6 * np.abs(dq_ref).max())


def test_branched_tree_with_prismatic_joint():
    # solo12: four legs branching from the base (fixed here), plus a prismatic-jointed test chain.
    model = hovi.Model.from_urdf(erd_urdf("solo_description/robots/solo12.urdf"))
    rng = np.random.default_rng(3)
    ForcedScene(model, rng)
    integ = hovi.Integrator(model, s=2, dt=0.01, direction="recursive")
    qc, p = random_point(integ, rng)
    u = rng.normal(size=(3, model.n_controls))
    r, _ = integ.del_residual(qc, p, u)
    dq_ref = -np.linalg.solve(fd_jacobian(integ, qc, p, u), r.ravel()).reshape(2, model.n)
    np.testing.assert_allclose(integ.newton_direction(qc, p, u), dq_ref, rtol=0, atol=1e-6 * np.abs(dq_ref).max())


def test_newton_converges_quadratically():
    model = hovi.examples.models.pendulum(6)
    integ = hovi.Integrator(model, s=2, dt=0.05, direction="recursive")
    rng = np.random.default_rng(5)
    q = rng.uniform(-1, 1, 6)
    p = integ.momentum(q, rng.uniform(-1, 1, 6))
    qc = np.tile(q, (3, 1))
    norms = []
    for _ in range(6):
        r, _ = integ.del_residual(qc, p)
        norms.append(np.abs(r).max())
        qc[1:] += integ.newton_direction(qc, p)
    # quadratic convergence: ||r_{k+1}|| <= C ||r_k||^2 with a modest C, down to round-off
    for k in (1, 2):
        assert norms[k + 1] <= 0.1 * norms[k] ** 2
    assert norms[4] < 1e-12 and norms[5] < 1e-12
