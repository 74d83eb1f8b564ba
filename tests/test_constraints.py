"""Holonomic constraints: values and Jacobians, the constrained Newton direction against a dense
solve of the finite-difference KKT system, long runs, the four-bar against an index-reduced
DOP853 reference with order 2s, the constrained linearisation, and bad inputs."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hovi
from conftest import observed_order
from mechanisms import fourbar, pinned_chain, rod, translate


def with_every_kind():
    """A 9-link pendulum with a planar point constraint on its tip (2 equations), the orientation
    of body 4 held (3) and a joint coupling q6 - q8 = const (1): m = 6, 3 degrees of freedom."""
    model = hovi.examples.models.pendulum(9)
    q0 = 0.3 * np.sin(np.arange(1, 10))
    X = model.joint_placements(q0)
    model.add_point_constraint(8, point=[0, 0, -0.5], target=(X[8] @ [0, 0, -0.5, 1])[:3], axes="xz")
    model.add_orientation_constraint(4, model.body_poses(q0)[4][:3, :3])
    c = np.zeros(9)
    c[6], c[8] = 1.0, -1.0
    model.add_joint_coupling(c, offset=q0[6] - q0[8])
    return model, q0


def test_constraint_jacobians_match_finite_differences():
    model, q0 = with_every_kind()
    other = hovi.examples.models.pendulum(9)
    other.add_loop_constraint(2, [0, 0, -0.5], 8, [0, 0, -0.5])
    rng = np.random.default_rng(1)
    for m in (model, other):
        q = q0 + rng.normal(scale=0.1, size=9)
        J = m.constraint_jacobian(q)
        h = 1e-6
        J_fd = np.array([(m.constraint_values(q + h * e) - m.constraint_values(q - h * e)) / (2 * h)
                         for e in np.eye(9)]).T
        np.testing.assert_allclose(J, J_fd, rtol=0, atol=1e-8)


def test_constraint_forces_are_dh_transpose_lambda():
    """The augmented model's force elements add exactly w^a dt Dh(q^a)^T λ^a to the residual."""
    model, q0 = with_every_kind()
    s, n, mc = 2, 9, model.n_constraints
    integ = hovi.Integrator(model, s=s, dt=0.02)
    rng = np.random.default_rng(2)
    qc = q0 + rng.normal(scale=0.05, size=(s + 1, n))
    lam, p = rng.normal(size=(s, mc)), rng.normal(size=n)
    r_c, H, pn_c = integ.constrained_residual(qc, lam, p)
    r, pn = integ.del_residual(qc, p)
    for a in range(s):
        expected = integ.weights[a] * integ.dt * model.constraint_jacobian(qc[a]).T @ lam[a]
        np.testing.assert_allclose(r_c[a] - r[a], expected, atol=1e-12)
    np.testing.assert_allclose(pn_c, pn, atol=1e-12)  # no constraint force in p^{k+1}
    np.testing.assert_allclose(H, [model.constraint_values(qc[g]) for g in range(1, s + 1)], atol=1e-14)


def kkt_fd(integ, qc, lam, p, h=1e-3):
    """Dense Jacobian of (r + C^T λ, h) with respect to (q^{k,1..s}, λ): fourth-order central
    differences in q; in λ, where the equations are affine, a unit difference (exact)."""
    s, n = integ.s, integ.n
    mc = lam.shape[1]

    def F(y):
        q2 = qc.copy()
        q2[1:] = y[:s * n].reshape(s, n)
        r, H, _ = integ.constrained_residual(q2, y[s * n:].reshape(s, mc), p)
        return np.concatenate([r.ravel(), H.ravel()])

    y0 = np.concatenate([qc[1:].ravel(), lam.ravel()])
    cols = []
    for k, e in enumerate(np.eye(len(y0))):
        if k < s * n:
            cols.append((-F(y0 + 2 * h * e) + 8 * F(y0 + h * e) - 8 * F(y0 - h * e) + F(y0 - 2 * h * e)) / (12 * h))
        else:
            cols.append((F(y0 + e) - F(y0 - e)) / 2)
    return np.array(cols).T, F(y0)


def dense_solve(J, F0):
    """-J^{-1} F0 with rows and columns equilibrated (λ and q have very different scales)."""
    c = 1 / np.abs(J).max(axis=0)
    r = 1 / np.abs(J * c).max(axis=1)
    return c * np.linalg.solve((J * c) * r[:, None], -F0 * r)


@pytest.mark.parametrize("s", [1, 2, 3])
@pytest.mark.parametrize("mechanism", ["every_kind", "fourbar"])
def test_constrained_direction_matches_dense_kkt_solve(s, mechanism):
    if mechanism == "fourbar":
        model = fourbar()
        q0 = np.array([-1.32360923, 0.94215318, -1.37640415])
    else:
        model, q0 = with_every_kind()
    n, mc = model.n, model.n_constraints
    integ = hovi.Integrator(model, s=s, dt=0.02)
    rng = np.random.default_rng(10 + s)
    qc = q0 + np.cumsum(rng.normal(scale=0.02, size=(s + 1, n)), axis=0)
    qc[0] = q0
    lam, p = rng.normal(size=(s, mc)), rng.normal(size=n)
    J, F0 = kkt_fd(integ, qc, lam, p)
    y_ref = dense_solve(J, F0)
    dz, dl = integ.constrained_direction(qc, lam, p)
    dz_ref, dl_ref = y_ref[:s * n].reshape(s, n), y_ref[s * n:].reshape(s, mc)
    np.testing.assert_allclose(dz, dz_ref, rtol=0, atol=1e-6 * np.abs(dz_ref).max())
    np.testing.assert_allclose(dl, dl_ref, rtol=0, atol=1e-6 * np.abs(dl_ref).max())


@pytest.mark.parametrize("s", [1, 2])
def test_long_runs_keep_the_constraints_and_the_energy(s):
    # four-bar (loop closure) and a 5-link pendulum with its tip pinned (point constraint)
    mech = fourbar()
    integ = hovi.Integrator(mech, s=s, dt=0.01)
    q, qd = integ.project(np.array([-1.2, 0.9, -1.8]), np.array([1.0, 0, 0]))
    chain, q_pin = pinned_chain(5)
    integ2 = hovi.Integrator(chain, s=s, dt=0.01)
    q2, qd2 = integ2.project(q_pin + 0.05, np.zeros(5))
    for model, it, x0, v0 in ((mech, integ, q, qd), (chain, integ2, q2, qd2)):
        traj = it.rollout(x0, 10_000, qdot0=v0)
        h = np.array([model.constraint_values(x) for x in traj.control_points.reshape(-1, model.n)])
        assert np.abs(h).max() < 1e-10
        err = np.abs(traj.energy - traj.energy[0])
        tenth = len(err) // 10
        assert err[-tenth:].mean() <= 2 * err[1:tenth].mean(), (err[1:tenth].mean(), err[-tenth:].mean())
        assert traj.multipliers.shape == (10_000, s, model.n_constraints)


def fourbar_reference(model, q0, qd0, T):
    """DOP853 on the index-reduced equations [M -Dh^T; Dh 0] (q̈, λ) = (-bias, -Ḋh q̇), with Ḋh q̇
    by a central difference of Dh along q̇."""
    n = model.n

    def f(t, y):
        q, qd = y[:n], y[n:]
        M = model.mass_matrix(q)
        bias = model.inverse_dynamics(q, qd, np.zeros(n))
        D = model.constraint_jacobian(q)
        e = 1e-6
        gamma = (model.constraint_jacobian(q + e * qd) - model.constraint_jacobian(q - e * qd)) / (2 * e) @ qd
        m = D.shape[0]
        K = np.block([[M, -D.T], [D, np.zeros((m, m))]])
        sol = np.linalg.solve(K, np.concatenate([-bias, -gamma]))
        return np.concatenate([qd, sol[:n]])

    sol = solve_ivp(f, (0, T), np.concatenate([q0, qd0]), method="DOP853", rtol=1e-12, atol=1e-12)
    assert sol.success
    return sol.y[:n, -1]


@pytest.mark.parametrize("s, dts", [(1, [0.02, 0.01, 0.005, 0.0025]), (2, [0.05, 0.025, 0.0125, 0.00625])])
def test_fourbar_converges_at_order_2s_to_an_independent_reference(s, dts):
    model = fourbar()
    integ = hovi.Integrator(model, s=s, dt=dts[0])
    q0, qd0 = integ.project(np.array([-2.0, 1.2, -1.5]), np.array([1.0, 0, 0]))
    ref = fourbar_reference(model, q0, qd0, 1.0)
    slope, errors = observed_order(lambda dt: hovi.Integrator(model, s=s, dt=dt, tol=1e-13), q0, qd0, ref, dts)
    assert abs(slope - 2 * s) <= 0.3, (slope, errors)


def test_constrained_linearization_matches_finite_differences():
    model = fourbar()
    model.add_actuator(0)
    s = 2
    integ = hovi.Integrator(model, s=s, dt=0.02, tol=1e-13)
    lin = hovi.Linearizer(integ)
    q, qd = integ.project(np.array([-1.2, 0.9, -1.8]), np.array([1.5, 0, 0]))
    p = integ.momentum(q, qd)
    u = np.array([[0.3], [0.2], [0.1]])
    res = lin.step_jacobians(q, p, u)

    def step(x, uu=u):
        q1, p1, _ = integ.step(x[:3], x[3:], uu)
        return np.concatenate([q1, p1])

    x0, h = np.concatenate([q, p]), 1e-6
    # Perturbations tangent to the constraint manifold would be needed for a consistent state; the
    # step map is defined for any (q^k, p^k), and so is its derivative.
    A_fd = np.array([(step(x0 + h * e) - step(x0 - h * e)) / (2 * h) for e in np.eye(6)]).T
    np.testing.assert_allclose(res.A, A_fd, rtol=0, atol=1e-5 * np.abs(A_fd).max())
    B_fd = np.zeros((6, 3))
    for a in range(3):
        e = np.zeros_like(u)
        e[a, 0] = h
        B_fd[:, a] = (step(x0, u + e) - step(x0, u - e)) / (2 * h)
    np.testing.assert_allclose(res.B, B_fd, rtol=0, atol=1e-5 * np.abs(B_fd).max())


def test_bad_constraints_give_clear_errors():
    # redundant: the same point constraint twice
    model, q_pin = pinned_chain(4)
    model.add_point_constraint(3, point=[0, 0, -0.5], target=(model.joint_placements(q_pin)[-1] @ [0, 0, -0.5, 1])[:3])
    with pytest.raises(ValueError, match="redundant or singular"):
        hovi.Integrator(model, s=2).project(q_pin, np.zeros(4))
    # inconsistent: one point held at two places
    model, q_pin = pinned_chain(4)
    model.add_point_constraint(3, point=[0, 0, -0.5], target=[5.0, 5.0, 5.0], axes="x")
    with pytest.raises(ValueError, match="too far from the constraint manifold|redundant"):
        hovi.Integrator(model, s=2).project(q_pin, np.zeros(4))
    # an initial state off the manifold is refused by rollout
    model, q_pin = pinned_chain(4)
    integ = hovi.Integrator(model, s=2)
    with pytest.raises(ValueError, match="violates the constraints"):
        integ.rollout(q_pin + 0.3, 5)
    with pytest.raises(ValueError, match="initial velocity violates"):
        integ.rollout(q_pin, 5, qdot0=np.ones(4))
    # locked: a planar 2-link arm with its tip pinned in the plane
    arm = hovi.Model()
    arm.add_body("a", None, axis=[0, 1, 0], **rod(0.5))
    arm.add_body("b", "a", axis=[0, 1, 0], placement=translate(0.5), **rod(0.5))
    arm.add_point_constraint("b", point=[0.5, 0, 0], target=[0.6, 0, 0.5], axes="xz")
    with pytest.raises(ValueError, match="no degree of freedom"):
        hovi.Integrator(arm, s=1).project(np.array([0.5, -1.0]), np.zeros(2))
    # malformed constraints
    m = hovi.examples.models.pendulum(3)
    with pytest.raises(hovi.ModelError, match="out of range"):
        m.add_point_constraint(7, target=[0, 0, 0])
    with pytest.raises(hovi.ModelError, match="subset of 'xyz'"):
        m.add_point_constraint(1, target=[0, 0, 0], axes="xw")
    with pytest.raises(hovi.ModelError, match="bodies must differ"):
        m.add_loop_constraint(1, [0, 0, 0], 1, [0, 0, 1])
    with pytest.raises(ValueError, match="coefficients"):
        m.add_joint_coupling([1.0, 2.0])
    with pytest.raises(hovi.ModelError, match="not a rotation"):
        m.add_orientation_constraint(0, 2 * np.eye(3))


def test_constrained_del_jacobian_matches_finite_differences():
    model, q0 = with_every_kind()
    s, n, mc = 2, 9, model.n_constraints
    integ = hovi.Integrator(model, s=s, dt=0.02)
    lin = hovi.Linearizer(integ)
    rng = np.random.default_rng(7)
    qc = q0 + rng.normal(scale=0.02, size=(s + 1, n))
    lam, p = rng.normal(size=(s, mc)), rng.normal(size=n)
    J = lin.del_jacobian(qc, multipliers=lam)

    def out(x, l):
        r, H, pn = integ.constrained_residual(x, l, p)
        return np.concatenate([r.ravel(), pn]), H.ravel()

    h = 1e-4
    dq = np.zeros(((s + 1) * n, (s + 1) * n))
    dh = np.zeros((s * mc, (s + 1) * n))
    for c in range(s + 1):
        for j in range(n):
            e = np.zeros_like(qc)
            e[c, j] = h
            f = [out(qc + k * e, lam) for k in (2, 1, -1, -2)]
            dq[:, c * n + j] = (-f[0][0] + 8 * f[1][0] - 8 * f[2][0] + f[3][0]) / (12 * h)
            dh[:, c * n + j] = (-f[0][1] + 8 * f[1][1] - 8 * f[2][1] + f[3][1]) / (12 * h)
    np.testing.assert_allclose(J.dq, dq, rtol=0, atol=1e-7 * np.abs(dq).max())
    np.testing.assert_allclose(J.dh, dh, rtol=0, atol=1e-7 * np.abs(dh).max())
    dl = np.zeros(((s + 1) * n, s * mc))
    for k in range(s * mc):
        e = np.zeros(s * mc)
        e[k] = 1.0
        dl[:, k] = (out(qc, lam + e.reshape(s, mc))[0] - out(qc, lam - e.reshape(s, mc))[0]) / 2  # affine in λ
    np.testing.assert_allclose(J.dlambda, dl, rtol=0, atol=1e-10 * np.abs(dl).max())
