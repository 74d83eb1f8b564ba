"""The whole NLP Jacobian of a transcribed problem (VI of orders 2..6, implicit and explicit
Hermite-Simpson; dynamics, holonomic rows, every path-constraint kind, linear boundary rows)
against central finite differences of its constraint function, and the sparsity structure
against every nonzero the differences find."""
import numpy as np
import pytest
import scipy.sparse as sp

import hovi
from hovi import trajopt
from hovi.trajopt.examples import close_mechanism

pytest.importorskip("cyipopt")


def every_path_constraint(prob):
    n = prob.model.n
    prob.add_constraint(trajopt.BodyPoint(n - 1, [0, 0, -0.5], target=[0.1, 0.2, -0.9], at=0.5 * prob.T))
    prob.add_constraint(trajopt.BodyPoint(0, [0, 0, -0.5], axes="z", lower=-0.6, window=(0, prob.T)))
    prob.add_constraint(trajopt.Clearance(1, [0, 0, -0.25], center=[0.3, 0.0, -0.6], radius=0.1, window=(0.2, 0.6)))
    c = np.arange(1, n + 1.0)
    prob.add_constraint(trajopt.CallbackPathConstraint(
        lambda t, Q: np.sin(Q) @ c[:, None] * t[:, None], lambda t, Q: (np.cos(Q) * c)[:, None, :] * t[:, None, None],
        lower=-1.0, upper=1.0, window=(0, prob.T)))
    return prob


def actuated_chain():
    model = hovi.models.pendulum(3)
    for j in range(3):
        model.add_actuator(j, 1.0 + j)
    model.add_damper(1, 0.3)
    model.add_spring(2, 5.0, 0.1)
    return model


def problems():
    out = []
    for controls in ("per_point", "held"):
        prob = trajopt.Problem(actuated_chain(), N=3, T=0.9, controls=controls)
        prob.initial_state([0.1, -0.2, 0.3], [0.5, 0.0, -0.5]).final_state([0.2, 0.1, 0.0], qdot=[0.0, 0.3, 0.0])
        out.append((f"chain-{controls}", every_path_constraint(prob.add_cost(trajopt.ControlEffort()))))
    model = hovi.models.fourbar()
    model.add_actuator(0)
    prob = trajopt.Problem(model, N=3, T=0.6)
    prob.initial_state(close_mechanism(model, [-1.2, 0.9, -1.8])).final_state(close_mechanism(model, [-1.0, 0.9, -1.8]),
                                                                              qdot=np.zeros(3))
    out.append(("fourbar", prob.add_cost(trajopt.ControlEffort())))
    return out


def dense_jacobian(nlp, x):
    return sp.coo_matrix((nlp.jacobian(x), (nlp.jac_rows, nlp.jac_cols)), shape=(nlp.n_constraints, nlp.n_variables)).toarray()


METHODS = [("vi", 1), ("vi", 2), ("vi", 3), ("hs-implicit", 2), ("hs-explicit", 2)]


@pytest.mark.parametrize("name,s", METHODS, ids=[f"{m}-{s}" for m, s in METHODS])
@pytest.mark.parametrize("k", range(3), ids=["chain-per_point", "chain-held", "fourbar"])
def test_jacobian_matches_finite_differences(name, s, k):
    _, prob = problems()[k]
    nlp = trajopt.NLP(trajopt.transcribe(prob, name, s))
    rng = np.random.default_rng(s + 10 * k)
    x = rng.normal(scale=0.3, size=nlp.n_variables)
    J = dense_jacobian(nlp, x)
    h = 1e-6
    J_fd = np.array([(nlp.constraints(x + h * e) - nlp.constraints(x - h * e)) / (2 * h) for e in np.eye(nlp.n_variables)]).T
    scale = np.abs(J_fd).max()
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-6 * scale)
    in_structure = np.zeros(J.shape, bool)
    in_structure[nlp.jac_rows, nlp.jac_cols] = True
    assert np.abs(J_fd[~in_structure]).max(initial=0) < 1e-9 * scale  # every nonzero is in the structure
    assert len(set(zip(nlp.jac_rows.tolist(), nlp.jac_cols.tolist()))) == nlp.nnz  # no duplicates


def test_objective_gradient_matches_finite_differences():
    _, prob = problems()[0]
    prob.add_cost(trajopt.StateTracking(lambda t: np.outer(np.sin(t), [1.0, 0.5, 0.2]), weight=[1.0, 2.0, 3.0],
                                        velocity_weight=0.1))
    prob.add_cost(trajopt.TerminalCost([0.3, 0.2, 0.1], weight=4.0, velocity_weight=0.5))
    for name in ("vi", "hs-implicit", "hs-explicit"):
        nlp = trajopt.NLP(trajopt.transcribe(prob, name, 2))
        x = np.random.default_rng(3).normal(scale=0.3, size=nlp.n_variables)
        g = nlp.gradient(x)
        h = 1e-6
        g_fd = np.array([(nlp.objective(x + h * e) - nlp.objective(x - h * e)) / (2 * h) for e in np.eye(nlp.n_variables)])
        np.testing.assert_allclose(g, g_fd, rtol=0, atol=1e-6 * np.abs(g_fd).max())
