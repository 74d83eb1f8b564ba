"""hovi._core.lagrange_basis (the C++ Quadrature's Lagrange basis, used by the transcriptions'
interpolants) against numpy's polynomial fit through the same Lobatto nodes, and the stage nodes
of every transcription against the integrator's."""
import numpy as np
import pytest

import hovi
from hovi import _core, trajopt
from hovi.examples import swingups


@pytest.mark.parametrize("s", [1, 2, 3, 5])
@pytest.mark.parametrize("derivative", [False, True])
def test_basis_against_polyfit(s, derivative):
    nodes = hovi.Integrator(hovi.examples.models.pendulum(1), s=s, dt=0.1).nodes
    x = np.linspace(-0.2, 1.2, 17)
    L = _core.lagrange_basis(s, x, derivative)
    for b in range(s + 1):  # l_b: the polynomial of degree s through the unit vector e_b at the nodes
        poly = np.polynomial.Polynomial.fit(nodes, np.eye(s + 1)[b], s)
        expected = poly.deriv()(x) if derivative else poly(x)
        np.testing.assert_allclose(L[:, b], expected, atol=1e-10)


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="x"):
        _core.lagrange_basis(2, [[0.1, 0.2]])
    with pytest.raises(ValueError):
        _core.lagrange_basis(0, [0.5])


@pytest.mark.parametrize("method", [trajopt.VI(s=1), trajopt.VI(s=3), trajopt.HermiteSimpson("implicit")])
def test_stage_nodes_are_lobatto_nodes(method):
    tr = method.transcribe(swingups.pendulum_swingup(N=4))
    nodes = tr.stage_nodes()
    expected = hovi.Integrator(tr.model, s=len(nodes) - 1, dt=0.1).nodes
    np.testing.assert_allclose(nodes, expected, atol=1e-15)
