"""hovi.control's LQR layer against independent computations: discrete_are (SDA in C++) against
scipy.linalg.solve_discrete_are on random systems and on the cart-pole's exact step Jacobians at the
upright; a free point mass on a prismatic joint, whose VI step is known in closed form for every s
(q+ = q + h p/m + h^2 F/(2m), p+ = p + h F with the held force F), so its A, B and its LQR are
exact; backward_riccati against brute-force least squares over the stacked controls; the state map
T = d(q, q̇)/d(q, p) against central differences of (q, M(q)^{-1} p); lqr() stabilising the cart-pole
(and the same policy without feedback falling) and refusing bad input; tvlqr() against a numpy
Riccati recursion on Linearizer.rollout_jacobians, reproducing its trajectory and tracking it from a
perturbed start, also from a hovi.trajopt.Result of an FDDP solve."""
import dataclasses

import numpy as np
import pytest
import scipy.linalg as sl

import hovi
from hovi import _core, control, trajopt
from hovi.examples import models

UPRIGHT = np.array([0.0, np.pi])


def rel_err(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(np.asarray(b)).max()


def gain(A, B, Q, R, P):
    """K = (R + B^T P B)^{-1} B^T P A."""
    return np.linalg.solve(R + B.T @ P @ B, B.T @ P @ A)


# --- 1. discrete_are -------------------------------------------------------------------------------

@pytest.mark.parametrize("seed", range(8))
def test_discrete_are_equals_scipy_on_random_stabilisable_systems(seed):
    rng = np.random.default_rng(seed)
    n, m = int(rng.integers(2, 7)), int(rng.integers(1, 4))
    A = rng.normal(size=(n, n))
    A *= 1.2 / np.abs(np.linalg.eigvals(A)).max()                    # spectral radius 1.2: unstable
    B = rng.normal(size=(n, m))
    C = rng.normal(size=(n if seed % 2 else 1, n))                    # Q full rank, or rank 1 (detectable)
    Q = C.T @ C
    D = rng.normal(size=(m, m))
    R = D.T @ D + 0.1 * np.eye(m)
    assert np.abs(np.linalg.eigvals(A)).max() > 1.0
    P, K, iterations = _core.control.discrete_are(A, B, Q, R)
    P_ref = sl.solve_discrete_are(A, B, Q, R)
    assert rel_err(P, P_ref) <= 1e-10
    assert rel_err(K, gain(A, B, Q, R, P_ref)) <= 1e-10
    assert np.abs(np.linalg.eigvals(A - B @ K)).max() < 1.0
    assert 1 <= iterations <= 100


def test_discrete_are_with_a_stable_uncontrollable_mode_and_without_controls():
    # (A, B) stabilisable but not controllable: the uncontrollable mode 0.5 is stable
    A, B, Q, R = np.diag([1.5, 0.5]), np.array([[1.0], [0.0]]), np.eye(2), np.eye(1)
    P, K, _ = _core.control.discrete_are(A, B, Q, R)
    assert rel_err(P, sl.solve_discrete_are(A, B, Q, R)) <= 1e-10
    # B = 0 with A stable: P is the Lyapunov solution P = A^T P A + Q, K = 0
    A = np.array([[0.9, 0.3], [-0.2, 0.5]])
    P, K, _ = _core.control.discrete_are(A, np.zeros((2, 1)), Q, R)
    assert rel_err(P, sl.solve_discrete_lyapunov(A.T, Q)) <= 1e-10
    assert np.all(K == 0)


@pytest.mark.parametrize("B", [np.zeros((2, 1)), np.array([[0.0], [1.0]])])
def test_discrete_are_refuses_a_system_that_is_not_stabilisable(B):
    # the unstable mode 1.5 is not reachable from the controls
    with pytest.raises(ValueError, match="no stabilising solution"):
        _core.control.discrete_are(np.diag([1.5, 0.5]), B, np.eye(2), np.eye(1))


def test_discrete_are_refuses_an_indefinite_R_and_mismatched_sizes():
    with pytest.raises(ValueError, match="R"):
        _core.control.discrete_are(np.eye(2), np.ones((2, 1)), np.eye(2), -np.eye(1))
    with pytest.raises(ValueError):
        _core.control.discrete_are(np.eye(2), np.ones((3, 1)), np.eye(2), np.eye(1))


def test_discrete_are_on_the_cartpole_step_jacobians_at_the_upright():
    model = models.cartpole()
    integ = hovi.Integrator(model, s=2, dt=0.01)
    lin = hovi.Linearizer(integ).step_jacobians(UPRIGHT, np.zeros(2), np.zeros(1), hold=True)
    A, B = lin.A, lin.B
    assert A.shape == (4, 4) and B.shape == (4, 1)
    assert np.abs(np.linalg.eigvals(A)).max() > 1.0                   # the upright is unstable
    T = _core.control.velocity_state_map(model, UPRIGHT[None], np.zeros((1, 2)))[0]
    W = np.diag([1.0, 2.0, 0.1, 0.2])
    Qx, R = T.T @ W @ T, np.array([[0.01]])
    P, K, _ = _core.control.discrete_are(A, B, Qx, R)
    P_ref = sl.solve_discrete_are(A, B, Qx, R)
    assert rel_err(P, P_ref) <= 1e-10
    assert rel_err(K, gain(A, B, Qx, R, P_ref)) <= 1e-10
    assert np.abs(np.linalg.eigvals(A - B @ K)).max() < 1.0
    # lqr() builds the same problem: the same P and K
    policy = control.lqr(integ, UPRIGHT, Q=W, u_weight=0.01)
    assert rel_err(policy.cost_to_go[0], P_ref) <= 1e-10
    assert rel_err(policy.gains[0], K) <= 1e-12


# --- 2. a free point mass: closed-form VI step ----------------------------------------------------

def point_mass(mass, axis):
    model = hovi.Model()
    model.add_body("mass", None, joint_type="prismatic", axis=axis, mass=mass, inertia=np.eye(3) * 0.05)
    model.add_actuator(0)
    return model


@pytest.mark.parametrize("axis, g_axis", [((1.0, 0.0, 0.0), 0.0), ((0.0, 0.0, 1.0), -9.81)])
@pytest.mark.parametrize("s", [1, 2, 3])
def test_point_mass_step_and_jacobians_are_the_closed_form(s, axis, g_axis):
    """L = m q̇^2/2 + F q with the constant force F = u + m g_axis: the trajectory is a parabola; the
    Lobatto quadrature integrates the Galerkin action exactly (degree <= 2s - 1), so for s >= 2 the
    exact solution is the discrete one, and for s = 1 the DEL m (q+ - q)/h - hF/2 = p gives the same:
    q+ = q + h p/m + h^2 F/(2m), p+ = p + h F for every s."""
    m, h = 2.0, 0.05
    integ = hovi.Integrator(point_mass(m, axis), s=s, dt=h)
    A_exact = np.array([[1.0, h / m], [0.0, 1.0]])
    B_exact = np.array([[h * h / (2 * m)], [h]])
    rng = np.random.default_rng(s)
    for _ in range(3):
        q, p, u = rng.normal(size=1), rng.normal(size=1), rng.normal(size=1)
        F = u[0] + m * g_axis
        q1, p1, _ = integ.step(q, p, u)
        np.testing.assert_allclose(q1, q + h * p / m + h * h * F / (2 * m), rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(p1, p + h * F, rtol=1e-12, atol=1e-14)
        lin = hovi.Linearizer(integ).step_jacobians(q, p, u, hold=True)
        np.testing.assert_allclose(lin.A, A_exact, rtol=0, atol=1e-12)
        np.testing.assert_allclose(lin.B, B_exact, rtol=0, atol=1e-12)


@pytest.mark.parametrize("axis, g_axis", [((1.0, 0.0, 0.0), 0.0), ((0.0, 0.0, 1.0), -9.81)])
@pytest.mark.parametrize("s", [1, 2, 3])
def test_point_mass_lqr_is_scipys_dare_on_the_closed_form(s, axis, g_axis):
    m, h = 2.0, 0.05
    integ = hovi.Integrator(point_mass(m, axis), s=s, dt=h)
    q_eq = np.array([0.3])
    u_eq = control.equilibrium_controls(integ, q_eq)
    np.testing.assert_allclose(u_eq, [-m * g_axis], rtol=1e-14, atol=1e-14)   # holds the weight m g
    T = _core.control.velocity_state_map(integ.model, q_eq[None], np.zeros((1, 1)))[0]
    np.testing.assert_allclose(T, np.diag([1.0, 1.0 / m]), rtol=1e-14, atol=0)
    qw, vw, uw = 3.0, 0.5, 0.02
    policy = control.lqr(integ, q_eq, q_weight=qw, v_weight=vw, u_weight=uw)
    A = np.array([[1.0, h / m], [0.0, 1.0]])
    B = np.array([[h * h / (2 * m)], [h]])
    Tm = np.diag([1.0, 1.0 / m])
    Qx, R = Tm.T @ np.diag([qw, vw]) @ Tm, np.array([[uw]])
    P_ref = sl.solve_discrete_are(A, B, Qx, R)
    assert rel_err(policy.cost_to_go[0], P_ref) <= 1e-10
    assert rel_err(policy.gains[0], gain(A, B, Qx, R, P_ref)) <= 1e-10
    np.testing.assert_array_equal(policy.x_ref, [[0.3, 0.0]])
    np.testing.assert_allclose(policy.u_ref, np.full((1, s + 1, 1), -m * g_axis), rtol=1e-14)


# --- 3. backward_riccati against brute force ---------------------------------------------------------

def brute_force(As, Bs, Qs, Rs, QN):
    """The finite-horizon LQR by least squares over the stacked controls U = (u_0..u_{N-1}):
    x_k = Phi_k x_0 + G_k U, cost = U^T H U + 2 x_0^T F U + x_0^T E x_0, optimum U = -H^{-1} F^T x_0
    and cost x_0^T (E - F H^{-1} F^T) x_0. Returns (P_0, K_0 with u_0 = -K_0 x_0, H, F, E, Phi, G)."""
    N, n, m = len(As), As[0].shape[0], Bs[0].shape[1]
    Phi, G = [np.eye(n)], [np.zeros((n, N * m))]
    for k in range(N):
        Phi.append(As[k] @ Phi[-1])
        Gk = As[k] @ G[-1]
        Gk[:, k * m:(k + 1) * m] += Bs[k]
        G.append(Gk)
    H, F, E = np.zeros((N * m, N * m)), np.zeros((n, N * m)), np.zeros((n, n))
    for k in range(N + 1):
        Qk = QN if k == N else Qs[k]
        H += G[k].T @ Qk @ G[k]
        F += Phi[k].T @ Qk @ G[k]
        E += Phi[k].T @ Qk @ Phi[k]
        if k < N:
            H[k * m:(k + 1) * m, k * m:(k + 1) * m] += Rs[k]
    L = np.linalg.solve(H, F.T)                  # U* = -L x_0
    return E - F @ L, L[:m], H, F, E, Phi, G


def random_spd(rng, size, floor=0.1):
    C = rng.normal(size=(size, size))
    return C.T @ C + floor * np.eye(size)


@pytest.mark.parametrize("time_varying", [False, True])
def test_backward_riccati_is_the_brute_force_optimum(time_varying):
    rng = np.random.default_rng(7 + time_varying)
    n, m, N = 3, 2, 5
    As = rng.normal(size=(N, n, n))
    Bs = rng.normal(size=(N, n, m))
    if time_varying:
        Qs, Rs = np.array([random_spd(rng, n, 0.0) for _ in range(N)]), np.array([random_spd(rng, m) for _ in range(N)])
        Qarg, Rarg = Qs, Rs
    else:
        Q, R = random_spd(rng, n, 0.0), random_spd(rng, m)
        Qs, Rs = np.array([Q] * N), np.array([R] * N)
        Qarg, Rarg = Q, R
    QN = random_spd(rng, n)
    K, P = _core.control.backward_riccati(As, Bs, Qarg, Rarg, QN)
    assert K.shape == (N, m, n) and P.shape == (N + 1, n, n)
    np.testing.assert_array_equal(P[N], QN)
    for k in range(N):                            # the tail problem from stage k
        Pk, Kk, *_ = brute_force(As[k:], Bs[k:], Qs[k:], Rs[k:], QN)
        assert rel_err(P[k], Pk) <= 1e-10, k
        assert rel_err(K[k], Kk) <= 1e-10, k
    _, _, H, F, E, Phi, G = brute_force(As, Bs, Qs, Rs, QN)
    for x0 in rng.normal(size=(4, n)):
        U = -np.linalg.solve(H, F.T @ x0)
        best = U @ H @ U + 2 * x0 @ F @ U + x0 @ E @ x0
        np.testing.assert_allclose(x0 @ P[0] @ x0, best, rtol=1e-10)
        np.testing.assert_allclose(-K[0] @ x0, U[:m], rtol=1e-10, atol=1e-12 * np.abs(U).max())
        # the feedback law u_k = -K_k x_k applied forward gives the optimal controls and cost
        x, cost, applied = x0.copy(), 0.0, []
        for k in range(N):
            u = -K[k] @ x
            applied.append(u)
            cost += x @ Qs[k] @ x + u @ Rs[k] @ u
            x = As[k] @ x + Bs[k] @ u
        cost += x @ QN @ x
        np.testing.assert_allclose(np.concatenate(applied), U, rtol=1e-9, atol=1e-10 * np.abs(U).max())
        np.testing.assert_allclose(cost, best, rtol=1e-10)
        # any other controls cost more
        U2 = U + 1e-3 * rng.normal(size=U.shape)
        assert U2 @ H @ U2 + 2 * x0 @ F @ U2 + x0 @ E @ x0 > best


def test_backward_riccati_refuses_mismatched_stage_counts():
    A, B = np.tile(np.eye(2), (3, 1, 1)), np.ones((3, 2, 1))
    with pytest.raises(ValueError, match="one Q per stage"):
        _core.control.backward_riccati(A, B, np.tile(np.eye(2), (2, 1, 1)), np.eye(1), np.eye(2))
    with pytest.raises(ValueError, match="as many B"):
        _core.control.backward_riccati(A, B[:2], np.eye(2), np.eye(1), np.eye(2))


# --- 4. the state map (q, p) -> (q, q̇) --------------------------------------------------------------

def velocity_map_fd(model, q, p, eps=1e-6):
    """Central differences of f(q, p) = (q, M(q)^{-1} p)."""
    n = model.n

    def f(x):
        return np.concatenate([x[:n], np.linalg.solve(model.mass_matrix(x[:n]), x[n:])])

    x = np.concatenate([q, p])
    J = np.zeros((2 * n, 2 * n))
    for j in range(2 * n):
        e = np.zeros(2 * n)
        e[j] = eps
        J[:, j] = (f(x + e) - f(x - e)) / (2 * eps)
    return J


@pytest.mark.parametrize("name", ["acrobot", "pendulum3", "cartpole"])
def test_velocity_state_map_equals_central_differences(name):
    model = {"acrobot": models.acrobot, "pendulum3": lambda: models.pendulum(3), "cartpole": models.cartpole}[name]()
    rng = np.random.default_rng(3)
    n = model.n
    q, p = rng.uniform(-2, 2, size=(4, n)), rng.normal(size=(4, n))
    T = _core.control.velocity_state_map(model, q, p)
    assert T.shape == (4, 2 * n, 2 * n)
    for k in range(4):
        J = velocity_map_fd(model, q[k], p[k])
        assert rel_err(T[k], J) <= 1e-7, k
        np.testing.assert_array_equal(T[k][:n], np.hstack([np.eye(n), np.zeros((n, n))]))


# --- 5. lqr() on the cart-pole ---------------------------------------------------------------------

def test_lqr_holds_the_cartpole_upright_and_without_feedback_it_falls(cartpole_lqr):
    integ, policy = cartpole_lqr
    assert np.abs(control.equilibrium_controls(integ, UPRIGHT)).max() <= 1e-12
    np.testing.assert_array_equal(policy.x_ref, [[0.0, np.pi, 0.0, 0.0]])
    assert np.abs(policy.u_ref).max() <= 1e-12 and policy.u_ref.shape == (1, 3, 1)
    assert policy.dt == 0.01 and policy.s == 2 and policy.stages == 1
    q0 = UPRIGHT + np.array([0.0, 0.2])
    run = control.simulate(integ, policy, q0, 500)                           # 5 s
    assert run.converged and run.trajectory.steps == 500
    x_end = np.concatenate([run.trajectory.q[-1], run.trajectory.p[-1]])
    assert np.abs(x_end - policy.x_ref[0]).max() < 1e-3
    # the same policy without feedback: the pole falls (it swings through the bottom)
    open_loop = dataclasses.replace(policy, gains=0 * policy.gains)
    fall = control.simulate(integ, open_loop, q0, 500)
    assert np.abs(fall.u).max() <= 1e-12
    assert np.abs(fall.trajectory.q[:, 1] - np.pi).max() > 2.0


def test_lqr_cost_to_go_is_the_closed_loop_cost_of_the_linearisation(cartpole_lqr):
    """x_0^T P x_0 = sum_k x_k^T Q x_k + u_k^T R u_k along x+ = (A - B K) x (summed until it decays)."""
    integ, policy = cartpole_lqr
    lin = hovi.Linearizer(integ).step_jacobians(UPRIGHT, np.zeros(2), np.zeros(1), hold=True)
    T = _core.control.velocity_state_map(integ.model, UPRIGHT[None], np.zeros((1, 2)))[0]
    Qx, R = T.T @ np.diag([1.0, 1.0, 0.1, 0.1]) @ T, np.array([[0.01]])
    K = policy.gains[0]
    x0 = np.array([0.1, -0.05, 0.02, 0.03])
    x, cost = x0.copy(), 0.0
    for _ in range(20000):
        u = -K @ x
        cost += x @ Qx @ x + u @ R @ u
        x = (lin.A - lin.B @ K) @ x
    assert np.abs(x).max() < 1e-12
    np.testing.assert_allclose(x0 @ policy.cost_to_go[0] @ x0, cost, rtol=1e-9)


def test_lqr_refuses_bad_input(cartpole_lqr):
    integ, _ = cartpole_lqr
    with pytest.raises(ValueError, match="equilibrium"):
        control.lqr(integ, np.array([0.0, 0.5]))
    with pytest.raises(ValueError, match="equilibrium"):
        control.lqr(integ, UPRIGHT, u_eq=[1.0])                               # pushes the cart
    with pytest.raises(ValueError, match="q_weight must be positive semi-definite"):
        control.lqr(integ, UPRIGHT, q_weight=-1.0)
    with pytest.raises(ValueError, match="q_weight must be a number, 2 numbers"):
        control.lqr(integ, UPRIGHT, q_weight=np.ones(3))
    with pytest.raises(ValueError, match="v_weight must be symmetric"):
        control.lqr(integ, UPRIGHT, v_weight=np.array([[1.0, 0.5], [0.0, 1.0]]))
    Q = np.eye(4)
    Q[0, 3] = 0.3
    with pytest.raises(ValueError, match="Q must be symmetric"):
        control.lqr(integ, UPRIGHT, Q=Q)
    with pytest.raises(ValueError, match="Q must be a number, 4 numbers"):
        control.lqr(integ, UPRIGHT, Q=np.eye(3))
    with pytest.raises(ValueError, match="u_weight must be positive definite"):
        control.lqr(integ, UPRIGHT, u_weight=0.0)
    with pytest.raises(ValueError, match="u_weight must be positive semi-definite"):
        control.lqr(integ, UPRIGHT, u_weight=-1.0)
    with pytest.raises(ValueError, match="u_weight must be a number, 1 numbers"):
        control.lqr(integ, UPRIGHT, u_weight=np.eye(2))
    with pytest.raises(ValueError, match="u_limits"):
        control.lqr(integ, UPRIGHT, u_limits=(1.0, -1.0))
    with pytest.raises(ValueError, match="q_eq"):
        control.lqr(integ, np.zeros(3))
    unactuated = hovi.Integrator(models.pendulum(1), s=2, dt=0.01)
    with pytest.raises(ValueError, match="no controls"):
        control.lqr(unactuated, np.zeros(1))
    with pytest.raises(TypeError, match="hovi.Integrator"):
        control.lqr(integ.model, UPRIGHT)


def test_lqr_limits_saturate_the_policy(cartpole_lqr):
    integ, _ = cartpole_lqr
    policy = control.lqr(integ, UPRIGHT, u_limits=(-3.0, 2.0))
    np.testing.assert_array_equal(policy.lower, [-3.0])
    np.testing.assert_array_equal(policy.upper, [2.0])
    u = policy.control(0, UPRIGHT + [0.0, 0.3], np.zeros(2))
    assert u.shape == (3, 1) and np.all((u == -3.0) | (u == 2.0))            # a large error saturates


# --- 9. tvlqr() along a trajectory -------------------------------------------------------------------

N_TV, DT_TV = 150, 0.01


@pytest.fixture(scope="module")
def cartpole_trajectory():
    """1.5 s of the cart-pole falling from near the upright under smooth controls (per control point)."""
    integ = hovi.Integrator(models.cartpole(), s=2, dt=DT_TV)
    t = (np.arange(N_TV)[:, None] + integ.nodes[None, :]) * DT_TV
    U = np.sin(2 * np.pi * t / 1.5)[..., None]
    q0 = np.array([0.0, np.pi - 0.1])
    traj = integ.rollout(q0, N_TV, u=U)
    return integ, traj, U


def numpy_riccati(A, B, Q, R, QN):
    """P_N = QN, K_k = (R + B^T P B)^{-1} B^T P A, P_k = Q_k + A^T P A - A^T P B K_k (standard form)."""
    P, Ks = QN, []
    for k in reversed(range(len(A))):
        K = np.linalg.solve(R + B[k].T @ P @ B[k], B[k].T @ P @ A[k])
        P = Q[k] + A[k].T @ P @ A[k] - A[k].T @ P @ B[k] @ K
        P = 0.5 * (P + P.T)
        Ks.append(K)
    return np.array(Ks[::-1]), P


def test_tvlqr_gains_are_the_riccati_recursion_on_the_step_jacobians(cartpole_trajectory):
    integ, traj, U = cartpole_trajectory
    W = np.diag([2.0, 1.0, 0.2, 0.1])
    policy = control.tvlqr(integ, traj, U, Q=W, u_weight=0.05)
    A, B = hovi.Linearizer(integ).rollout_jacobians(traj, U, hold=True)
    assert A.shape == (N_TV, 4, 4) and B.shape == (N_TV, 4, 1)
    T = _core.control.velocity_state_map(integ.model, traj.q, traj.p)
    Qk = np.array([T[k].T @ W @ T[k] for k in range(N_TV)])
    QN = T[-1].T @ (10 * W) @ T[-1]                                          # default final weight 10 W
    K_ref, P0_ref = numpy_riccati(A, B, Qk, np.array([[0.05]]), QN)
    assert policy.gains.shape == (N_TV, 1, 4) and policy.cost_to_go.shape == (N_TV + 1, 4, 4)
    assert rel_err(policy.gains, K_ref) <= 1e-10
    assert rel_err(policy.cost_to_go[0], P0_ref) <= 1e-10
    assert rel_err(policy.cost_to_go[-1], QN) <= 1e-14
    np.testing.assert_array_equal(policy.x_ref, np.hstack([traj.q[:-1], traj.p[:-1]]))
    np.testing.assert_array_equal(policy.u_ref, U)
    # final_weight replaces 10 W
    WN = np.diag([5.0, 5.0, 1.0, 1.0])
    pol2 = control.tvlqr(integ, traj, U, Q=W, u_weight=0.05, final_weight=WN)
    assert rel_err(pol2.cost_to_go[-1], T[-1].T @ WN @ T[-1]) <= 1e-14


def test_tvlqr_reproduces_its_trajectory_and_tracks_it_from_a_perturbed_start(cartpole_trajectory):
    integ, traj, U = cartpole_trajectory
    policy = control.tvlqr(integ, traj, U)
    run = control.simulate(integ, policy, traj.q[0], N_TV, p0=traj.p[0])
    np.testing.assert_allclose(run.trajectory.q, traj.q, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.trajectory.p, traj.p, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.u, U, rtol=0, atol=1e-9)
    q0 = traj.q[0] + np.array([-0.03, 0.05])
    closed = control.simulate(integ, policy, q0, N_TV).trajectory
    opened = integ.rollout(q0, N_TV, u=U)

    def err(tr):
        return np.linalg.norm(np.concatenate([tr.q[-1] - traj.q[-1], tr.qdot[-1] - traj.qdot[-1]]))

    assert err(closed) < 0.1 * err(opened)                                   # measured 0.007
    assert err(opened) > 1.0                                                 # open loop loses the trajectory


def test_tvlqr_takes_the_trajectorys_own_controls_and_refuses_one_without(cartpole_trajectory):
    """A rollout (or a loaded file) carries its controls: tvlqr reads them; without them it refuses."""
    import dataclasses
    integ, traj, U = cartpole_trajectory
    own, given = control.tvlqr(integ, traj), control.tvlqr(integ, traj, U)
    np.testing.assert_array_equal(own.gains, given.gains)
    np.testing.assert_array_equal(own.u_ref, given.u_ref)
    with pytest.raises(ValueError, match="give the trajectory's controls u"):
        control.tvlqr(integ, dataclasses.replace(traj, controls=None))
    with pytest.raises(TypeError, match="Trajectory or a hovi.trajopt.Result"):
        control.tvlqr(integ, "trajectory")


def test_tvlqr_of_an_fddp_result_tracks_its_swing_up():
    model = models.pendulum(1)
    model.add_actuator(0)
    N, T = 40, 2.0
    problem = trajopt.Problem(model, N, T, controls="held", q_bounds=(-np.inf, np.inf), u_bounds=(-4.0, 4.0))
    problem.initial_state(np.zeros(1))
    problem.add_cost(trajopt.ControlEffort(0.1))
    problem.add_cost(trajopt.TerminalCost(np.array([np.pi]), weight=100.0, velocity_weight=10.0))
    result = trajopt.FDDP().solve(problem, trajopt.VI(2))
    assert result.success
    integ = hovi.Integrator(model, s=2, dt=T / N)
    policy = control.tvlqr(integ, result)
    tr = result.transcription
    U = tr.stage_controls(result.x)
    np.testing.assert_array_equal(policy.u_ref, U)
    assert np.all(U == U[:, :1])                                             # held: one control per step
    arrays = tr.trajectory(result.x)
    q_knots, p_knots = arrays["q"][::2], arrays["p"]
    assert q_knots.shape == (N + 1, 1) and p_knots.shape == (N + 1, 1)
    # the same policy as tvlqr on the replayed trajectory with the Result's controls
    replay = integ.rollout(q_knots[0], N, p0=p_knots[0], u=U)
    direct = control.tvlqr(integ, replay, U)
    np.testing.assert_array_equal(policy.gains, direct.gains)
    np.testing.assert_array_equal(policy.x_ref, direct.x_ref)
    # from the solution's initial state the closed loop is the solution
    run = control.simulate(integ, policy, q_knots[0], N, p0=p_knots[0])
    np.testing.assert_allclose(run.trajectory.q, q_knots, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.trajectory.p, p_knots, rtol=0, atol=1e-9)
    # a perturbed start: the feedback ends much nearer the solution's final state than open loop
    q0 = q_knots[0] + 0.15
    closed = control.simulate(integ, policy, q0, N).trajectory
    opened = integ.rollout(q0, N, u=U)
    assert abs(closed.q[-1, 0] - q_knots[-1, 0]) < 0.1 * abs(opened.q[-1, 0] - q_knots[-1, 0])
    with pytest.raises(ValueError, match="must match"):
        control.tvlqr(hovi.Integrator(model, s=1, dt=T / N), result)
    with pytest.raises(ValueError, match="must match"):
        control.tvlqr(hovi.Integrator(model, s=2, dt=0.01), result)
