"""Section 4: Algorithms 2 and 3 against finite differences of the energies, the DEL Jacobian
against finite differences of the residual, and the step Jacobians A, B against finite
differences of the converged step map, symplecticity and second-order prediction."""
import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from del_reference import ForcedScene, fd4
from test_del_residual import random_point

H = 1e-4  # step of the nested finite differences of the energies


def fd_hessian(f, x, h=H):
    """Second derivative matrix of scalar f by central differences of a fourth-order gradient."""
    n = len(x)
    return np.array([(fd4(f, x + h * e, h) - fd4(f, x - h * e, h)) / (2 * h) for e in np.eye(n)]).T


def models():
    return {"pendulum": lambda: hovi.examples.models.pendulum(5),
            "panda": lambda: hovi.Model.from_urdf(erd_urdf("panda_description/urdf/panda.urdf")),
            "solo12": lambda: hovi.Model.from_urdf(erd_urdf("solo_description/robots/solo12.urdf"))}


@pytest.mark.parametrize("name", ["pendulum", "panda", "solo12"])
def test_algorithms_2_and_3_match_finite_differences(name):
    model = models()[name]()
    if name == "panda":  # joint armature: 1/2 a q̇^2 in K, diag(a) in Kvv only
        model.armature = np.linspace(0.0, 0.3, model.n)
    rng = np.random.default_rng(1)
    q, qd = rng.uniform(-1, 1, model.n), rng.uniform(-1, 1, model.n)
    Kvv, Kvq, Kqv, Kqq = model.kinetic_energy_hessians(q, qd)

    def dK_dqd(q_, qd_):
        return fd4(lambda x: model.kinetic_energy(q_, x), qd_, H)

    def dK_dq(q_, qd_):
        return fd4(lambda x: model.kinetic_energy(x, qd_), q_, H)

    # [Kvq]_ij = d/dq_j (dK/dq̇_i), [Kqv]_ij = d/dq̇_j (dK/dq_i)
    Kvq_fd = np.array([(dK_dqd(q + H * e, qd) - dK_dqd(q - H * e, qd)) / (2 * H) for e in np.eye(model.n)]).T
    Kqv_fd = np.array([(dK_dq(q, qd + H * e) - dK_dq(q, qd - H * e)) / (2 * H) for e in np.eye(model.n)]).T
    Kqq_fd = fd_hessian(lambda x: model.kinetic_energy(x, qd), q)
    Kvv_fd = fd_hessian(lambda x: model.kinetic_energy(q, x), qd)
    Vqq_fd = fd_hessian(model.potential_energy, q)
    for got, want, what in [(Kvv, Kvv_fd, "Kvv"), (Kvq, Kvq_fd, "Kvq"), (Kqv, Kqv_fd, "Kqv"), (Kqq, Kqq_fd, "Kqq"),
                            (model.gravity_hessian(q), Vqq_fd, "Vqq")]:
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-7 * max(1.0, np.abs(want).max()), err_msg=what)
    np.testing.assert_allclose(Kqv, Kvq.T, atol=1e-14)
    np.testing.assert_allclose(Kvv, model.mass_matrix(q), atol=1e-14)


def residual_map(integ, p):
    def out(qc, u):
        r, pn = integ.del_residual(qc, p, u)
        return np.concatenate([r.ravel(), pn])
    return out


@pytest.mark.parametrize("s", [1, 2, 3, 4])
@pytest.mark.parametrize("name", ["pendulum", "panda"])
def test_del_jacobian_matches_finite_differences(s, name):
    rng = np.random.default_rng(20 + s)
    model = models()[name]()
    ForcedScene(model, rng)  # every force type
    integ = hovi.Integrator(model, s=s, dt=0.02)
    lin = hovi.Linearizer(integ)
    n, m = model.n, model.n_controls
    qc, p = random_point(integ, rng)
    u = rng.normal(size=(s + 1, m))
    J = lin.del_jacobian(qc, u)
    out = residual_map(integ, p)
    h = 1e-5
    dq_fd = np.zeros(((s + 1) * n, (s + 1) * n))
    for c in range(s + 1):
        for j in range(n):
            e = np.zeros_like(qc)
            e[c, j] = h
            dq_fd[:, c * n + j] = (-out(qc + 2 * e, u) + 8 * out(qc + e, u) - 8 * out(qc - e, u) + out(qc - 2 * e, u)) / (12 * h)
    np.testing.assert_allclose(J.dq, dq_fd, rtol=0, atol=1e-6 * np.abs(dq_fd).max())
    # the residual is affine in u: a unit difference is exact up to round-off
    du_fd = np.zeros(((s + 1) * n, (s + 1) * m))
    for c in range(s + 1):
        for j in range(m):
            e = np.zeros_like(u)
            e[c, j] = 1.0
            du_fd[:, c * m + j] = (out(qc, u + e) - out(qc, u - e)) / 2
    np.testing.assert_allclose(J.du, du_fd, rtol=0, atol=1e-6 * np.abs(du_fd).max())
    assert J.blocks().shape == (s + 1, s + 1, n, n)


def step_map(integ, u):
    def f(x):
        n = integ.n
        q1, p1, _ = integ.step(x[:n], x[n:], u)
        return np.concatenate([q1, p1])
    return f


@pytest.mark.parametrize("s", [1, 2, 3])
def test_step_jacobians_match_finite_differences(s):
    rng = np.random.default_rng(30 + s)
    model = hovi.examples.models.pendulum(4)
    ForcedScene(model, rng)
    integ = hovi.Integrator(model, s=s, dt=0.02, tol=1e-13)
    lin = hovi.Linearizer(integ)
    n, m = model.n, model.n_controls
    q = rng.uniform(-0.5, 0.5, n)
    p = integ.momentum(q, rng.uniform(-0.5, 0.5, n))
    u = rng.normal(size=(s + 1, m))
    res = lin.step_jacobians(q, p, u)
    f = step_map(integ, u)
    x0, h = np.concatenate([q, p]), 1e-5
    A_fd = np.array([(f(x0 + h * e) - f(x0 - h * e)) / (2 * h) for e in np.eye(2 * n)]).T
    np.testing.assert_allclose(res.A, A_fd, rtol=0, atol=1e-5 * np.abs(A_fd).max())
    B_fd = np.zeros((2 * n, (s + 1) * m))
    for c in range(s + 1):
        for j in range(m):
            e = np.zeros_like(u)
            e[c, j] = h
            fp, fm = step_map(integ, u + e), step_map(integ, u - e)
            B_fd[:, c * m + j] = (fp(x0) - fm(x0)) / (2 * h)
    np.testing.assert_allclose(res.B, B_fd, rtol=0, atol=1e-5 * np.abs(B_fd).max())
    np.testing.assert_allclose(res.q_next, f(x0)[:n], atol=1e-12)
    # held controls: the column blocks summed
    held = lin.step_jacobians(q, p, u, A=False, hold=True)
    assert held.A is None and held.B.shape == (2 * n, m)
    np.testing.assert_allclose(held.B, res.B.reshape(2 * n, s + 1, m).sum(axis=1), atol=1e-14)


@pytest.mark.parametrize("s", [1, 2, 3])
def test_conservative_step_is_symplectic(s):
    model = hovi.examples.models.pendulum(6)
    integ = hovi.Integrator(model, s=s, dt=0.05, tol=1e-13)
    lin = hovi.Linearizer(integ)
    rng = np.random.default_rng(40 + s)
    q = rng.uniform(-1, 1, 6)
    A = lin.step_jacobians(q, integ.momentum(q, rng.uniform(-1, 1, 6)), B=False).A
    Jsym = np.block([[np.zeros((6, 6)), np.eye(6)], [-np.eye(6), np.zeros((6, 6))]])
    np.testing.assert_allclose(A.T @ Jsym @ A, Jsym, rtol=0, atol=1e-8)
    # ... and a damped one is not (the check can fail)
    damped = hovi.examples.models.pendulum(6)
    for j in range(6):
        damped.add_damper(j, 0.5)
    integ_d = hovi.Integrator(damped, s=s, dt=0.05, tol=1e-13)
    Ad = hovi.Linearizer(integ_d).step_jacobians(q, integ_d.momentum(q, np.zeros(6)), B=False).A
    assert np.abs(Ad.T @ Jsym @ Ad - Jsym).max() > 1e-3


def test_linear_prediction_error_is_second_order():
    model = hovi.examples.models.pendulum(5)
    integ = hovi.Integrator(model, s=2, dt=0.02, tol=1e-14)
    lin = hovi.Linearizer(integ)
    rng = np.random.default_rng(5)
    q = rng.uniform(-0.5, 0.5, 5)
    p = integ.momentum(q, rng.uniform(-0.5, 0.5, 5))
    res = lin.step_jacobians(q, p)
    f = step_map(integ, None)
    x0 = np.concatenate([q, p])
    dx = rng.normal(size=10)
    dx /= np.linalg.norm(dx)
    errors = []
    for eps in [1e-2, 5e-3, 2.5e-3]:
        errors.append(np.linalg.norm(f(x0 + eps * dx) - f(x0) - res.A @ (eps * dx)))
    assert 3.5 < errors[0] / errors[1] < 4.5 and 3.5 < errors[1] / errors[2] < 4.5, errors


def test_rollout_jacobians_match_steps():
    model = hovi.examples.models.pendulum(3)
    k = model.add_actuator(1)
    integ = hovi.Integrator(model, s=2, dt=0.02)
    lin = hovi.Linearizer(integ)
    rng = np.random.default_rng(6)
    u = rng.normal(size=(10, 3, 1))
    traj = integ.rollout(rng.uniform(-0.5, 0.5, 3), 10, u=u)
    As, Bs = lin.rollout_jacobians(traj, u)
    assert As.shape == (10, 6, 6) and Bs.shape == (10, 6, 3)
    for j in (0, 9):
        A, B = lin.linearize_at(traj.control_points[j], u[j])
        np.testing.assert_allclose(As[j], A, atol=1e-14)
        np.testing.assert_allclose(Bs[j], B, atol=1e-14)
    A_only, none = lin.rollout_jacobians(traj, u, B=False)
    assert none is None and np.array_equal(A_only, As)
    assert k == 0


def test_linearizer_bad_inputs():
    with pytest.raises(TypeError, match="hovi.Integrator"):
        hovi.Linearizer(hovi.examples.models.pendulum(2))
    lin = hovi.Linearizer(hovi.Integrator(hovi.examples.models.pendulum(2), s=2))
    with pytest.raises(ValueError, match=r"control_points must be a 2-D array of shape \(3, 2\)"):
        lin.del_jacobian(np.zeros((2, 2)))
    with pytest.raises(ValueError, match="NaN"):
        lin.del_jacobian(np.full((3, 2), np.nan))
