"""The flat-foot contact wrench (hovi.contact.FlatFoot): its wrench cone against a linear program
over the sole's corner forces, and a block standing on its sole under a push, against statics."""
import numpy as np
import pytest
from scipy.optimize import linprog

import hovi
from hovi import trajopt
from hovi.contact import FlatFoot, wrench_cone

G = 9.81


def corner_forces_exist(w, X, Y, mu):
    """Is w = (f, tau) (at the sole centre) a sum of forces at the corners (+-X, +-Y, 0), each in
    the friction pyramid |f_x|, |f_y| <= mu f_z? (a feasibility LP over the 12 corner forces)"""
    corners = [(sx * X, sy * Y, 0.0) for sx in (1, -1) for sy in (1, -1)]
    A_eq = np.zeros((6, 12))
    for i, p in enumerate(corners):
        A_eq[:3, 3 * i:3 * i + 3] = np.eye(3)
        A_eq[3:, 3 * i:3 * i + 3] = np.array([[0, -p[2], p[1]], [p[2], 0, -p[0]], [-p[1], p[0], 0]])  # p x
    A_ub = []
    for i in range(4):
        for axis in (0, 1):
            for sign in (1, -1):
                row = np.zeros(12)
                row[3 * i + axis], row[3 * i + 2] = sign, -mu
                A_ub.append(row)
        row = np.zeros(12)
        row[3 * i + 2] = -1
        A_ub.append(row)
    res = linprog(np.zeros(12), A_ub=np.array(A_ub), b_ub=np.zeros(len(A_ub)), A_eq=A_eq, b_eq=w,
                  bounds=[(None, None)] * 12, method="highs")
    return res.status == 0


def test_wrench_cone_is_exactly_the_set_of_corner_force_sums():
    X, Y, mu = 0.12, 0.05, 0.7
    G_ = wrench_cone(X, Y, mu)
    rng = np.random.default_rng(3)
    inside = outside = 0
    for _ in range(600):
        w = np.concatenate([rng.uniform(-1, 1, 2) * mu, [1.0], rng.uniform(-1, 1, 2) * [Y, X],
                            rng.uniform(-1, 1, 1) * mu * (X + Y)]) * rng.uniform(0.5, 20)
        margin = (G_ @ w).min() / np.linalg.norm(w)
        if abs(margin) < 1e-9:
            continue
        assert (margin > 0) == corner_forces_exist(w, X, Y, mu), w
        inside += margin > 0
        outside += margin < 0
    assert inside > 100 and outside > 100  # both sides of every face are sampled


def block_model():
    """A 2 kg block (0.3 x 0.2 x 0.2 m) on a floating base (x, y, z, yaw, pitch, roll), its joint frame
    5 cm below its centre of mass, with a control pushing it along world +x 0.1 m above that frame."""
    model = hovi.Model()
    for name, parent, kind, axis in (("x", None, "prismatic", (1, 0, 0)), ("y", "x", "prismatic", (0, 1, 0)),
                                     ("z", "y", "prismatic", (0, 0, 1)), ("yaw", "z", "revolute", (0, 0, 1)),
                                     ("pitch", "yaw", "revolute", (0, 1, 0))):
        model.add_body(name, parent, kind, axis=axis)
    model.add_body("block", "pitch", "revolute", axis=(1, 0, 0), mass=2.0, com=(0, 0, 0.05),
                   inertia=np.diag([0.013, 0.022, 0.022]))
    model.add_point_wrench("block", force=(1.0, 0, 0), point=(0, 0, 0.1), control=model.add_control())
    return model


def standing_block(push):
    """The block standing on its sole (0.1 m below its joint frame, yawed 0.3 rad), pushed by ``push``."""
    q0 = np.array([0.0, 0.0, 0.1, 0.3, 0.0, 0.0])
    foot = FlatFoot(block_model(), "block", centre=(0, 0, -0.1), X=0.15, Y=0.1, mu=0.8, q0=q0)
    prob = trajopt.Problem(foot.with_inputs, N=10, T=0.5)
    prob.u_lower[0] = prob.u_upper[0] = push
    prob.initial_state(q0)
    prob.add_cost(trajopt.ControlEffort(weight=1e-3))
    prob.add_constraint(foot.stance()).add_constraint(foot.cone())
    return foot, prob, q0


@pytest.mark.parametrize("method", [trajopt.VI(s=2), trajopt.HermiteSimpson("implicit")], ids=repr)
def test_pushed_block_stands_with_its_centre_of_pressure_where_statics_puts_it(method):
    push, m = 4.0, 2.0
    foot, prob, q0 = standing_block(push)
    result = trajopt.solve(prob, method, verbose=False, options={"tol": 1e-10, "constr_viol_tol": 1e-10})
    assert result.success, result.status
    assert result.constraint_violation < 1e-10
    tr = result.trajectory
    np.testing.assert_allclose(tr["q"], np.tile(q0, (len(tr["q"]), 1)), atol=1e-9)   # the foot holds
    if method == trajopt.VI(s=2):  # the wrench at the last point acts only on the final momentum, which is free here
        u, tol = tr["u"][:-1], 1e-6
    else:  # collocation fixes each stage's Simpson average (1, 4, 1) / 6 of the forces, up to the velocities
        # at the held points, which only their own collocation rows tie (IPOPT leaves ~3e-8 m/s: 1e-6 N)
        u, tol = (tr["u"][0:-1:2] + 4 * tr["u"][1::2] + tr["u"][2::2]) / 6, 1e-5
    w = foot.wrench(u)
    R = np.array([[np.cos(0.3), np.sin(0.3)], [-np.sin(0.3), np.cos(0.3)]])             # world -> sole (yaw 0.3)
    np.testing.assert_allclose(w[:, :2], np.tile(R @ [-push, 0.0], (len(w), 1)), atol=tol)  # friction holds
    np.testing.assert_allclose(w[:, 2], m * G, atol=tol)                                # the weight
    cop = foot.centre_of_pressure(u)
    np.testing.assert_allclose(cop, np.tile(R @ [0.2 * push / (m * G), 0.0], (len(w), 1)), atol=tol / (m * G))
    assert (w @ wrench_cone(foot.X, foot.Y, foot.mu).T).min() >= -1e-8


def test_a_push_that_would_tip_the_block_has_no_stance():
    tipping = 0.15 * 2.0 * G / 0.2                     # the centre of pressure reaches the sole's edge
    assert trajopt.solve(standing_block(0.95 * tipping)[1], verbose=False).success
    assert not trajopt.solve(standing_block(1.05 * tipping)[1], verbose=False).success


def test_bad_flat_foot_input_is_refused_with_a_reason():
    q0 = np.array([0.0, 0.0, 0.1, 0.0, 0.0, 0.0])
    for kwargs, match in (({"body": "heel"}, "unknown foot body 'heel'"), ({"body": 9}, "unknown foot body 9"),
                          ({"X": 0.0}, "half-size X"), ({"mu": -1.0}, "mu must be"),
                          ({"centre": (0, 0)}, "centre must be 3"), ({"q0": q0[:3]}, "q0 must be"),
                          ({"q0": q0 + [0, 0, 0, 0, 0.2, 0]}, "not flat at q0: its z axis is 11.5 degrees"),
                          ({"scale": 0.0}, "scale must be > 0")):
        args = {"body": "block", "centre": (0, 0, -0.1), "X": 0.1, "Y": 0.1, "mu": 0.5, "q0": q0, **kwargs}
        with pytest.raises(ValueError, match=match):
            FlatFoot(block_model(), **args)
    foot, prob, _ = standing_block(0.0)
    # stance() and cone() are plain data (hovi.contact imports nothing of trajopt); the Problem makes the constraints
    assert isinstance(prob.path_constraints[0], trajopt.PoseHeld)
    assert isinstance(prob.input_constraints[0], trajopt.InputConstraint)
    assert foot.cone(n_controls=foot.with_inputs.n_controls + 3).A.shape == (17, 10)  # inputs appended after the foot's
    with pytest.raises(ValueError, match="7 columns"):
        prob.add_constraint(trajopt.InputConstraint(np.ones((2, 3)), 0.0, 1.0))
    with pytest.raises(ValueError, match="lower <= upper"):
        trajopt.InputConstraint(np.ones((1, 7)), 1.0, 0.0)


def test_bad_pose_held_input_is_refused_with_a_reason():
    model = block_model()
    q0 = np.array([0.0, 0.0, 0.1, 0.0, 0.0, 0.0])
    for kwargs, match in (({"point": (0, 0)}, "point must be 3"), ({"point": (0, 0, np.nan)}, "point must be 3"),
                          ({"size": (0.1, 0.0)}, "size must be two positive"), ({"size": (0.1,)}, "size must be two")):
        with pytest.raises(ValueError, match=match):
            trajopt.PoseHeld("block", q0, **kwargs)
    prob = trajopt.Problem(model, N=4, T=0.2)
    with pytest.raises(ValueError, match="q0 must be 6 finite numbers"):
        prob.add_constraint(trajopt.PoseHeld("block", q0[:5]))
    with pytest.raises(ValueError, match="unknown body 'foot'"):
        prob.add_constraint(trajopt.PoseHeld("foot", q0))


def test_a_flat_foot_of_another_model_is_refused():
    """A foot built on one model, added to a problem or a simulator of another, was taken without a
    word (its body index and q0 meant another robot's)."""
    from hovi.contact import Terrain, flat_feet_contacts
    foot, _, q0 = standing_block(0.0)
    other = hovi.examples.models.pendulum(6)
    prob = trajopt.Problem(other, N=4, T=0.2)
    with pytest.raises(ValueError, match=r"the flat foot's stance was built on another model \(bodies \['x'"):
        prob.add_constraint(foot.stance())
    with pytest.raises(ValueError, match="the flat foot's wrench cone was built on another model"):
        prob.add_constraint(foot.cone())
    with pytest.raises(ValueError, match=r"feet\[0\] was built on another model"):
        flat_feet_contacts(other, [foot], Terrain())
    flat_feet_contacts(block_model(), [foot], Terrain())  # a copy of the foot's model is the same robot
