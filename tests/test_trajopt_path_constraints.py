"""Body-point kinematics (trajopt/body_points.cpp), which the path constraints, the contact rows and
the examples use: positions against the joint placements, Jacobians against finite differences;
and the NLP's shared kinematics call for path constraints on the same configurations against each
constraint evaluated on its own."""
import numpy as np
import pytest

import hovi
from hovi import trajopt


def branched_model():
    model = hovi.examples.models.pendulum(3)
    model.add_body("side", 0, "revolute", axis=(1, 0, 0), mass=0.5, inertia=np.diag([0.01, 0.02, 0.03]))
    return model


def test_body_point_kinematics_against_placements_and_finite_differences():
    model = branched_model()
    rng = np.random.default_rng(3)
    Q = rng.uniform(-np.pi, np.pi, size=(4, model.n))
    bodies = [3, 1, 3, 0]
    points = rng.normal(size=(4, 3))
    X, J = hovi._core.body_point_kinematics(model, Q, bodies, points)
    assert X.shape == (4, 4, 3) and J.shape == (4, 4, 3, model.n)
    h = 1e-6
    for p, q in enumerate(Q):
        poses = model.joint_placements(q)
        for i, (b, r) in enumerate(zip(bodies, points)):
            np.testing.assert_allclose(X[p, i], poses[b][:3, :3] @ r + poses[b][:3, 3], rtol=0, atol=1e-14)
        for j in range(model.n):
            e = h * np.eye(model.n)[j]
            Xp = hovi._core.body_point_kinematics(model, [q + e], bodies, points)[0][0]
            Xm = hovi._core.body_point_kinematics(model, [q - e], bodies, points)[0][0]
            np.testing.assert_allclose(J[p, :, :, j], (Xp - Xm) / (2 * h), rtol=0, atol=1e-9)


def test_body_point_kinematics_refuses_bad_input():
    model = branched_model()
    with pytest.raises(hovi.ModelError, match="out of range"):
        hovi._core.body_point_kinematics(model, np.zeros((1, model.n)), [7], np.zeros((1, 3)))
    with pytest.raises(ValueError):
        hovi._core.body_point_kinematics(model, np.zeros((1, model.n)), [0, 1], np.zeros((1, 3)))
    with pytest.raises(ValueError):
        hovi._core.body_point_kinematics(model, np.zeros((1, model.n + 1)), [0], np.zeros((1, 3)))


def test_shared_kinematics_equal_each_constraint_alone():
    """Constraints on body points over the same configurations are one C++ block of the NLP's
    program (trajopt/body_point_rows.cpp: one kinematics per configuration); its rows and Jacobian
    values, placed in the NLP's order (a CallbackPathConstraint among them, evaluated in Python),
    equal those of each constraint's own evaluate (Python, its form on body_point_kinematics) at the
    same configurations (to 1e-14: the sums run in another order)."""
    model = branched_model()
    prob = trajopt.Problem(model, N=4, T=0.8)
    prob.initial_state(np.zeros(model.n)).add_cost(trajopt.ControlEffort())
    window = (0.1, 0.7)
    constraints = [trajopt.Clearance(3, [0, 0.1, 0], center=[0.2, 0, -0.5], radius=0.1, window=window, between=2),
                   trajopt.CallbackPathConstraint(lambda t, Q: np.sin(Q[:, :1]) + t[:, None],
                                                  lambda t, Q: np.eye(Q.shape[1])[None, :1] * np.cos(Q[:, :1])[:, :, None],
                                                  [-2.0], [2.0], window=window),
                   trajopt.BodyPoint(2, [0, 0, -0.5], axes="xz", lower=-1.0, window=window, between=2),
                   trajopt.PoseHeld(1, np.zeros(model.n), window=window, between=2),
                   trajopt.Clearance(0, [0, 0, -0.2], center=[0, 0.3, 0], radius=0.2, window=(0.3, 0.8))]
    for c in constraints:
        prob.add_constraint(c)
    nlp = trajopt.NLP(prob, trajopt.VI(s=2))
    assert len(nlp._point_groups) < len(nlp.paths) - 1  # some entries share a call
    x = np.random.default_rng(0).normal(scale=0.3, size=nlp.n_variables)
    rows0, nnz0 = nlp.core.n_constraints, nlp.core.nnz
    shared_values = nlp.constraints(x)[rows0:rows0 + len(nlp._path_place)]
    shared_jacobians = nlp.jacobian(x)[nnz0:nnz0 + len(nlp._path_jac_place)]
    alone = [c.evaluate(model, t, nlp._configurations(x, points, weights)) + (weights,)
             for c, t, points, weights in nlp.paths]
    np.testing.assert_allclose(shared_values, np.concatenate([v.ravel() for v, _, _ in alone]), rtol=0, atol=1e-14)
    np.testing.assert_allclose(shared_jacobians, np.concatenate([np.einsum("pk,prj->prkj", w, J).ravel()
                                                                 for _, J, w in alone]), rtol=0, atol=1e-14)


def test_body_point_rows_equal_their_closed_forms():
    """Each OnBodyPoints constraint's rows from its form (c + L x + D x^2) against its definition
    written out on the points' world positions (Model.joint_placements): a BodyPoint's coordinates,
    a Clearance's squared distance, a PoseHeld's six rows (zero at its q0's pose)."""
    model = branched_model()
    Q = np.random.default_rng(4).normal(scale=0.5, size=(5, model.n))
    q0 = np.zeros(model.n)

    def world(body, point, q):
        T = model.joint_placements(q)[body]
        return T[:3, :3] @ point + T[:3, 3]

    point = np.array([0.0, 0.1, -0.3])
    cases = [(trajopt.BodyPoint(2, point, axes="xz", lower=-1.0, window=(0, 1)),
              lambda q: world(2, point, q)[[0, 2]]),
             (trajopt.Clearance(3, point, center=[0.2, 0.1, -0.5], radius=0.1, axes="yz", window=(0, 1)),
              lambda q: [np.sum((world(3, point, q) - [0.2, 0.1, -0.5])[[1, 2]] ** 2)]),
             (trajopt.PoseHeld(1, q0, point=point, size=(0.2, 0.1)),
              None)]
    for c, closed in cases:
        c.bind(model)
        values, _ = c.evaluate(model, np.zeros(len(Q)), Q)
        if closed is None:   # the held pose: rows equal to their value at q0, moving with the body
            np.testing.assert_allclose(c.evaluate(model, np.zeros(1), q0[None])[0][0], c.lower, atol=1e-14)
            R = model.joint_placements(q0)[1][:3, :3]
            closed = lambda q: np.concatenate([world(1, point, q), [R[:, 1] @ world(1, point + [0.2, 0, 0], q),
                                                                    R[:, 2] @ world(1, point + [0.2, 0, 0], q),
                                                                    R[:, 2] @ world(1, point + [0, 0.1, 0], q)]])
        np.testing.assert_allclose(values, [closed(q) for q in Q], rtol=0, atol=1e-13)
