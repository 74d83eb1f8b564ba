"""Algorithm 1 against an independent finite-difference evaluation of the DEL equations."""
import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from del_reference import ForcedScene, reference_del


def random_point(integ, rng, spread=0.8):
    s, n = integ.s, integ.n
    q0 = rng.uniform(-spread, spread, n)
    qc = q0 + np.cumsum(rng.uniform(-0.05, 0.05, (s + 1, n)), axis=0)
    qc[0] = q0
    return qc, rng.uniform(-1, 1, n)


def models():
    yield "pendulum", hovi.examples.models.pendulum(4)
    yield "panda", hovi.Model.from_urdf(erd_urdf("panda_description/urdf/panda.urdf"))


@pytest.mark.parametrize("s", [1, 2, 3, 4])
@pytest.mark.parametrize("name", ["pendulum", "panda"])
@pytest.mark.parametrize("forces", [False, True])
def test_residual_matches_finite_differences(s, name, forces):
    rng = np.random.default_rng(10 * s + forces)
    model = dict(models())[name]
    scene = ForcedScene(model, rng) if forces else None
    integ = hovi.Integrator(model, s=s, dt=0.02)
    for _ in range(2):
        qc, p = random_point(integ, rng)
        u = rng.normal(size=(s + 1, model.n_controls)) if forces else None
        r, p_next = integ.del_residual(qc, p, u)
        r_ref, p_ref = reference_del(integ, qc, p, u, scene)
        scale = max(np.abs(r_ref).max(), np.abs(p_ref).max())
        np.testing.assert_allclose(r, r_ref, rtol=0, atol=1e-8 * scale)
        np.testing.assert_allclose(p_next, p_ref, rtol=0, atol=1e-8 * scale)


def test_simpson_and_trapezoid_weights():
    model = hovi.examples.models.pendulum(2)
    simpson = hovi.Integrator(model, s=2)
    np.testing.assert_allclose(simpson.weights, [1 / 6, 4 / 6, 1 / 6], rtol=1e-14)
    np.testing.assert_allclose(simpson.differentiation_matrix, [[-3, 4, -1], [-1, 0, 1], [1, -4, 3]], atol=1e-13)
    trap = hovi.Integrator(model, s=1)
    np.testing.assert_allclose(trap.weights, [0.5, 0.5])
    np.testing.assert_allclose(trap.differentiation_matrix, [[-1, 1], [-1, 1]], atol=1e-14)
