"""The whole NLP Jacobian of a transcribed problem (VI of orders 2..6, implicit and explicit
Hermite-Simpson; dynamics, holonomic rows, every path-constraint kind, linear boundary rows,
contact complementarity rows) against central finite differences of its constraint function, and
the sparsity structure against every nonzero the differences find."""
import numpy as np
import pytest
import scipy.sparse as sp

import hovi
from hovi import trajopt
from hovi.contact import Box, Contacts, Terrain
from hovi.trajopt import Sides, ComplementarityRelaxation
from hovi.examples.swingups import close_mechanism



def every_path_constraint(prob):
    n = prob.model.n
    prob.add_constraint(trajopt.BodyPoint(n - 1, [0, 0, -0.5], target=[0.1, 0.2, -0.9], at=0.5 * prob.T))
    prob.add_constraint(trajopt.BodyPoint(0, [0, 0, -0.5], axes="z", lower=-0.6, window=(0, prob.T)))
    prob.add_constraint(trajopt.Clearance(1, [0, 0, -0.25], center=[0.3, 0.0, -0.6], radius=0.1, window=(0.2, 0.6),
                                          between=2))
    prob.add_constraint(trajopt.Clearance(n - 1, [0, 0, -0.25], center=[0.3, 0.1, -0.8], radius=0.1, window=(0.2, 0.6),
                                          between=2))  # the same configurations: one kinematics call for both
    c = np.arange(1, n + 1.0)
    prob.add_constraint(trajopt.CallbackPathConstraint(
        lambda t, Q: np.sin(Q) @ c[:, None] * t[:, None], lambda t, Q: (np.cos(Q) * c)[:, None, :] * t[:, None, None],
        lower=-1.0, upper=1.0, window=(0, prob.T), between=1))
    prob.add_constraint(trajopt.PoseHeld(n - 1, prob.q0, point=[0, 0, -0.4], size=(0.2, 0.1), window=(0.3, prob.T)))
    A = np.arange(1.0, 2 * prob.model.n_controls + 1).reshape(2, -1) * [[1], [-1]]
    prob.add_constraint(trajopt.InputConstraint(A, lower=[-5.0, -np.inf], upper=[np.inf, 5.0]))
    return prob


def actuated_chain():
    model = hovi.examples.models.pendulum(3)
    for j in range(3):
        model.add_actuator(j, 1.0 + j)
    model.add_damper(1, 0.3)
    model.add_spring(2, 5.0, 0.1)
    model.armature = [0.2, 0.0, 0.05]  # in M(q) of Hermite-Simpson, in L_d of the VI
    return model


def problems():
    out = []
    for controls in ("per_point", "held"):
        prob = trajopt.Problem(actuated_chain(), N=3, T=0.9, controls=controls)
        prob.initial_state([0.1, -0.2, 0.3], [0.5, 0.0, -0.5]).final_state([0.2, 0.1, 0.0], qdot=[0.0, 0.3, 0.0])
        out.append((f"chain-{controls}", every_path_constraint(prob.add_cost(trajopt.ControlEffort()))))
    model = hovi.examples.models.fourbar()
    model.add_actuator(0)
    prob = trajopt.Problem(model, N=3, T=0.6)
    prob.initial_state(close_mechanism(model, [-1.2, 0.9, -1.8])).final_state(close_mechanism(model, [-1.0, 0.9, -1.8]),
                                                                              qdot=np.zeros(3))
    out.append(("fourbar", prob.add_cost(trajopt.ControlEffort())))
    return out


def dense_jacobian(nlp, x):
    return sp.coo_matrix((nlp.jacobian(x), (nlp.jac_rows, nlp.jac_cols)), shape=(nlp.n_constraints, nlp.n_variables)).toarray()


METHODS = [trajopt.VI(1), trajopt.VI(2), trajopt.VI(3), trajopt.HermiteSimpson("implicit"),
           trajopt.HermiteSimpson("explicit")]


def check_against_finite_differences(nlp, x):
    J = dense_jacobian(nlp, x)
    h = 1e-6
    J_fd = np.array([(nlp.constraints(x + h * e) - nlp.constraints(x - h * e)) / (2 * h) for e in np.eye(nlp.n_variables)]).T
    scale = np.abs(J_fd).max()
    np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-6 * scale)
    in_structure = np.zeros(J.shape, bool)
    in_structure[nlp.jac_rows, nlp.jac_cols] = True
    assert np.abs(J_fd[~in_structure]).max(initial=0) < 1e-9 * scale  # every nonzero is in the structure
    assert len(set(zip(nlp.jac_rows.tolist(), nlp.jac_cols.tolist()))) == nlp.nnz  # no duplicates


@pytest.mark.parametrize("method", METHODS, ids=repr)
@pytest.mark.parametrize("k", range(3), ids=["chain-per_point", "chain-held", "fourbar"])
def test_jacobian_matches_finite_differences(method, k):
    _, prob = problems()[k]
    nlp = trajopt.NLP(prob, method)
    rng = np.random.default_rng(getattr(method, "s", 2) + 10 * k)
    check_against_finite_differences(nlp, rng.normal(scale=0.3, size=nlp.n_variables))


def tumbling_block():
    """A block free to move in x, y, z and to pitch and roll (nonlinear contact kinematics), one
    actuator, two corners in contact with a raised terrain (3D friction, d = 4)."""
    model = hovi.Model()
    for name, parent, axis in (("x", None, (1, 0, 0)), ("y", "x", (0, 1, 0)), ("z", "y", (0, 0, 1))):
        model.add_body(name, parent, "prismatic", axis=axis)
    model.add_body("pitch", "z", "revolute", axis=(0, 1, 0))
    model.add_body("block", "pitch", "revolute", axis=(1, 0, 0), mass=2.0, inertia=np.diag([0.02, 0.03, 0.04]))
    model.add_actuator(3)
    terrain = Terrain(ground=-1.0, boxes=[Box(-10.0, 10.0, top=0.05)])  # every point above the box
    contacts = Contacts(model, [("block", (0.2, 0.1, -0.1)), ("block", (-0.2, -0.1, -0.1))], terrain, mu=0.7)
    prob = trajopt.Problem(contacts.with_inputs, N=3, T=0.3)
    prob.initial_state([0.0, 0.0, 0.3, 0.1, -0.1]).add_cost(trajopt.ControlEffort(weight=contacts.effort_weights()))
    return contacts, prob.add_contacts(contacts)


CONTACT_METHODS = METHODS


@pytest.mark.parametrize("method", CONTACT_METHODS, ids=repr)
@pytest.mark.parametrize("exact", [False, True], ids=["relaxed", "exact-sides"])
def test_contact_jacobian_matches_finite_differences(method, exact):
    contacts, prob = tumbling_block()
    s = getattr(method, "s", 2)
    relaxation = ComplementarityRelaxation(1e-2)
    E = prob.N * s  # pairs: the VI's control points, Hermite-Simpson's knots and midpoints, less the last
    if exact:  # one side of every pair fixed: the same rows, other bounds
        rng = np.random.default_rng(5)
        C = contacts.n_contacts
        relaxation = ComplementarityRelaxation(1e-2, Sides(rng.random((E, C)) < 0.5, rng.random((E, C)) < 0.5,
                                                              rng.random((E, C, contacts.d)) < 0.5))
    nlp = trajopt.NLP(prob, method, relaxation=relaxation)
    assert nlp.contact_rows.count == E * 2 * (4 + 2 * 4) + 2 * 6
    check_against_finite_differences(nlp, np.random.default_rng(s).normal(scale=0.3, size=nlp.n_variables))


def test_exact_sides_fix_inputs_and_rows():
    """Sides: a pair's input at zero is a fixed variable, its gap-like row an equality; the
    products are unbounded; the last point's inputs equal the previous point's."""
    contacts, prob = tumbling_block()
    E, C, d = prob.N, contacts.n_contacts, contacts.d
    normal = np.zeros((E, C), bool)
    normal[1, 0] = True  # phi(q_2) = 0 for contact 0, lambda = 0 elsewhere
    sides = Sides(normal, np.ones((E, C), bool), np.zeros((E, C, d), bool))
    nlp = trajopt.NLP(prob, trajopt.VI(s=1), relaxation=ComplementarityRelaxation(0.0, sides))
    cr, u_off = nlp.contact_rows, nlp.transcription.u_points()
    lam = u_off[:E, None] + np.array([contacts.input_index(c, "normal") for c in range(C)])
    fixed = ~normal
    assert np.all(nlp.lower[lam[fixed]] == 0) and np.all(nlp.upper[lam[fixed]] == 0)
    assert np.all(nlp.upper[lam[~fixed]] == np.inf)
    beta = u_off[:E, None] + np.array([contacts.input_index(c, "friction", 2) for c in range(C)])
    assert np.all(nlp.upper[beta] == 0)
    gamma = u_off[:E, None] + np.array([contacts.input_index(c, "slack") for c in range(C)])
    assert np.all(nlp.upper[gamma] == np.inf)  # psi = 0 chosen: gamma free
    row0 = nlp.core.n_constraints + sum(len(t) * len(c.lower) for c, t, _, _ in nlp.paths)
    cl, cu = nlp.cl[row0:row0 + cr.count], nlp.cu[row0:row0 + cr.count]
    EC = E * C
    np.testing.assert_array_equal(cu[:EC], np.where(normal.ravel(), 0.0, np.inf))   # phi rows
    np.testing.assert_array_equal(cu[EC:2 * EC], 0.0)                                # psi rows
    assert np.all(cu[(2 + d) * EC:cr.n_pair_rows] == np.inf) and np.all(cl[(2 + d) * EC:cr.n_pair_rows] == -np.inf)
    np.testing.assert_array_equal(cl[cr.n_pair_rows:], 0.0)
    np.testing.assert_array_equal(cu[cr.n_pair_rows:], 0.0)


def test_objective_gradient_matches_finite_differences():
    _, prob = problems()[0]
    prob.add_cost(trajopt.StateTracking(lambda t: np.outer(np.sin(t), [1.0, 0.5, 0.2]), weight=[1.0, 2.0, 3.0],
                                        velocity_weight=0.1))
    prob.add_cost(trajopt.TerminalCost([0.3, 0.2, 0.1], weight=4.0, velocity_weight=0.5))
    for method in (trajopt.VI(s=2), trajopt.HermiteSimpson("implicit"), trajopt.HermiteSimpson("explicit")):
        nlp = trajopt.NLP(prob, method)
        x = np.random.default_rng(3).normal(scale=0.3, size=nlp.n_variables)
        g = nlp.gradient(x)
        h = 1e-6
        g_fd = np.array([(nlp.objective(x + h * e) - nlp.objective(x - h * e)) / (2 * h) for e in np.eye(nlp.n_variables)])
        np.testing.assert_allclose(g, g_fd, rtol=0, atol=1e-6 * np.abs(g_fd).max())
