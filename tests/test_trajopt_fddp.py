"""Box-FDDP on the VI (hovi.trajopt.FDDP over hovi._core.control.ShootingProblem), each part checked
against an independent computation:

- the shooting problem's cost is the IPOPT transcription's: the sum of ShootingProblem.stage_cost
  over a rollout equals NLP.objective (Python cost terms through the sample map) at that rollout;
- ShootingProblem.derivatives against central differences: A, B of Integrator.step, lx, lu of the
  stage cost through the step, and the Gauss-Newton blocks against J^T H J built here from
  difference Jacobians of the control points and the (exact, quadratic) Hessian of stage_cost;
- FDDP reaches IPOPT's optimum (exact-Hessian IPOPT on the same VI transcription) on the pendulum,
  cart-pole and acrobot swing-ups, and with binding control bounds (the same active set);
- warm starts, replays, refusals and stopped solves.

Iterations and times are printed (pytest -rP shows them); no assertion is on time."""
import time

import numpy as np
import pytest

import hovi
from hovi import Integrator, trajopt
from hovi.contact import Contacts, Terrain
from hovi.examples import models
from hovi.examples.swingups import close_mechanism


INF = (-np.inf, np.inf)


def tight_ipopt(problem, s, guess=None):
    """IPOPT with the exact (difference) Hessian at tight tolerances on VI(s)."""
    t0 = time.perf_counter()
    r = trajopt.solve(problem, trajopt.VI(s), guess=guess, verbose=False, options={"tol": 1e-13}, hessian="fd")
    return r, time.perf_counter() - t0


# --- 1. the shooting problem's cost is the transcription's -------------------------------------

def acrobot_problem(costs, N=8, T=1.2):
    pr = trajopt.Problem(models.acrobot(), N, T, controls="held", u_bounds=(-20, 20), q_bounds=INF)
    pr.initial_state([0.3, -0.2], [0.5, -1.0])
    for c in costs:
        pr.add_cost(c)
    return pr


def q_ref_of_t(t):
    return np.column_stack([np.sin(2 * t), 0.5 * t - 0.3])


def v_ref_of_t(t):
    return np.column_stack([2 * np.cos(2 * t), np.full_like(t, 0.5)])


COST_SETS = {
    "effort": lambda: [trajopt.ControlEffort(0.7)],
    "tracking_constant": lambda: [trajopt.StateTracking([0.4, -0.6], [3.0, 1.5], v_ref=[0.2, 0.1],
                                                        velocity_weight=[0.5, 2.0])],
    "tracking_callable": lambda: [trajopt.StateTracking(q_ref_of_t, [2.0, 4.0], v_ref=v_ref_of_t,
                                                        velocity_weight=[0.3, 0.8])],
    "terminal": lambda: [trajopt.TerminalCost([np.pi, 0.1], [1000.0, 300.0], v_target=[0.2, -0.4],
                                              velocity_weight=[100.0, 30.0])],
    "all": lambda: [trajopt.ControlEffort(0.7), trajopt.StateTracking(q_ref_of_t, [2.0, 4.0], v_ref=v_ref_of_t,
                                                                      velocity_weight=[0.3, 0.8]),
                    trajopt.TerminalCost([np.pi, 0.1], 1000.0, velocity_weight=100.0)],
}


@pytest.mark.parametrize("s", [1, 2, 3])
@pytest.mark.parametrize("costs", list(COST_SETS))
def test_shooting_cost_equals_transcription_objective(costs, s, rng):
    pr = acrobot_problem(COST_SETS[costs]())
    tr = trajopt.VI(s).transcribe(pr)
    sp = trajopt.FDDP().shooting_problem(pr, tr)
    np.testing.assert_allclose(sp.x0, np.r_[pr.q0, pr.model.mass_matrix(pr.q0) @ pr.qdot0], rtol=1e-14, atol=1e-14)
    for _ in range(2):
        U = rng.uniform(-3, 3, (pr.N, pr.model.n_controls))
        Us = np.repeat(U[:, None, :], s + 1, axis=1)
        traj = tr.integrator.rollout(pr.q0, pr.N, p0=sp.x0[2:], u=Us)
        shooting = sum(sp.stage_cost(k, traj.control_points[k], U[k]) for k in range(pr.N))
        objective = trajopt.NLP(pr, tr).objective(tr.guess_from_rollout(traj, Us))
        assert objective > 1e-3
        assert abs(shooting - objective) <= 1e-12 * abs(objective), (shooting, objective)
    if costs == "tracking_callable":  # offset j: step k takes stage k + j's references
        sp.offset = 3
        shifted = sp.stage_cost(1, traj.control_points[1], U[1])
        sp.offset = 0
        assert shifted == pytest.approx(sp.stage_cost(4, traj.control_points[1], U[1]), rel=1e-14)
        assert shifted != pytest.approx(sp.stage_cost(1, traj.control_points[1], U[1]), rel=1e-3)


# --- 2. derivatives against central differences ------------------------------------------------

def derivative_problem(name, s):
    if name == "acrobot":
        pr = trajopt.Problem(models.acrobot(), 6, 0.6, controls="held", u_bounds=(-20, 20), q_bounds=INF)
        pr.initial_state([0.2, -0.1])
        qT = [np.pi, 0.0]
    else:
        pr = trajopt.Problem(models.cartpole(), 6, 0.6, controls="held", u_bounds=(-30, 30), q_bounds=INF)
        pr.initial_state([0.0, 0.1])
        qT = [0.0, np.pi]
    pr.add_cost(trajopt.ControlEffort(0.9))
    pr.add_cost(trajopt.StateTracking(q_ref_of_t, [2.0, 4.0], v_ref=v_ref_of_t, velocity_weight=[0.3, 0.8]))
    pr.add_cost(trajopt.TerminalCost(qT, [1000.0, 500.0], v_target=[0.3, -0.2], velocity_weight=[100.0, 40.0]))
    tr = trajopt.VI(s).transcribe(pr)
    return pr, trajopt.FDDP().shooting_problem(pr, tr)


def central(f, z, h):
    """Central differences of f (vector-valued) at z: (len(f), len(z))."""
    cols = []
    for i in range(len(z)):
        e = np.zeros(len(z))
        e[i] = h
        cols.append((f(z + e) - f(z - e)) / (2 * h))
    return np.column_stack(cols)


def quadratic_hessian(f, z):
    """The Hessian of a quadratic f at z: second differences with unit steps are exact (to round-off)."""
    d = len(z)
    H = np.zeros((d, d))
    I = np.eye(d)
    for i in range(d):
        for j in range(i, d):
            H[i, j] = H[j, i] = (f(z + I[i] + I[j]) - f(z + I[i] - I[j]) - f(z - I[i] + I[j])
                                 + f(z - I[i] - I[j])) / 4
    return H


def rel_err(a, b):
    return np.abs(a - b).max() / max(1.0, np.abs(b).max())


@pytest.mark.parametrize("s", [1, 2, 3])
@pytest.mark.parametrize("name", ["acrobot", "cartpole"])
def test_stage_derivatives_against_differences(name, s, rng):
    pr, sp = derivative_problem(name, s)
    n, m, N = pr.model.n, pr.model.n_controls, pr.N
    integ = Integrator(pr.model, s=s, dt=pr.dt)  # its own Newton solves, converged to round-off
    for k in (1, N - 1):  # a running stage, and the last (with the terminal term)
        q, p, u = rng.uniform(-1, 1, n), rng.uniform(-0.5, 0.5, n), rng.uniform(-3, 3, m)
        _, _, info = integ.step(q, p, np.tile(u, (s + 1, 1)))
        qc0 = info.control_points

        def step(z):
            qz, pz, uz = z[:n], z[n:2 * n], z[2 * n:]
            qn, pn, inf = integ.step(qz, pz, np.tile(uz, (s + 1, 1)), guess=qc0 + (qz - q))
            assert inf.converged
            return np.r_[qn, pn], inf.control_points

        z0 = np.r_[q, p, u]
        d = sp.derivatives(k, qc0, u)
        F = central(lambda z: step(z)[0], z0, 1e-5)
        errs = {"A": rel_err(d["A"], F[:, :2 * n]), "B": rel_err(d["B"], F[:, 2 * n:])}
        G = central(lambda z: np.array([sp.stage_cost(k, step(z)[1], z[2 * n:])]), z0, 1e-5)[0]
        errs["lx"], errs["lu"] = rel_err(d["lx"], G[:2 * n]), rel_err(d["lu"], G[2 * n:])
        # Gauss-Newton: J^T H J with J = d(control points, u)/d(x, u) and H the cost's Hessian in them
        Jq = central(lambda z: step(z)[1].ravel(), z0, 1e-5)               # ((s+1) n, 2n + m)
        J = np.vstack([Jq, np.hstack([np.zeros((m, 2 * n)), np.eye(m)])])
        H = quadratic_hessian(lambda w: sp.stage_cost(k, w[:-m].reshape(s + 1, n), w[-m:]), np.r_[qc0.ravel(), u])
        GN = J.T @ H @ J
        errs["lxx"] = rel_err(d["lxx"], GN[:2 * n, :2 * n])
        errs["lux"] = rel_err(d["lux"], GN[2 * n:, :2 * n])
        errs["luu"] = rel_err(d["luu"], GN[2 * n:, 2 * n:])
        print(f"{name} s={s} k={k}: " + ", ".join(f"{key} {v:.1e}" for key, v in errs.items()))
        assert max(errs.values()) < 1e-7, errs
        assert np.abs(d["lux"]).max() > 1e-3 and np.abs(d["B"]).max() > 1e-3  # nothing vanishes trivially


# --- 3. the same optimum as IPOPT ---------------------------------------------------------------

SWINGUPS = {  # model, N, T, |u| max, q0, q_T
    "pendulum": (lambda: models.pendulum(1), 40, 2.0, 4.0, [0.0], [np.pi]),
    "cartpole": (models.cartpole, 50, 2.5, 20.0, [0.0, 0.0], [0.0, np.pi]),
    "acrobot": (models.acrobot, 60, 4.0, 15.0, [0.0, 0.0], [np.pi, 0.0]),
}


def swingup(name, u_max=None):
    make, N, T, default_max, q0, qT = SWINGUPS[name]
    model = make()
    if name == "pendulum":
        model.add_actuator(0)
    u_max = default_max if u_max is None else u_max
    pr = trajopt.Problem(model, N, T, controls="held", u_bounds=(-u_max, u_max), q_bounds=INF)
    pr.initial_state(q0)
    pr.add_cost(trajopt.ControlEffort())
    pr.add_cost(trajopt.TerminalCost(qT, 1000.0, velocity_weight=100.0))
    return pr


def solve_fddp(problem, s, **options):
    t0 = time.perf_counter()
    r = trajopt.FDDP(**options).solve(problem, trajopt.VI(s))
    return r, time.perf_counter() - t0


# FDDP's stop test is Crocoddyl's: sum_k |Q_u|^2 < tol, absolute. On the cart-pole's flat directions
# tol = 1e-12 leaves the controls 2.9e-5 from IPOPT's (|du| ~ |Q_u| / lambda_min), so it is solved to 1e-14.
@pytest.mark.parametrize("name,s,tol", [
    ("pendulum", 1, 1e-12), ("pendulum", 2, 1e-12),
    ("cartpole", 2, 1e-14), ("acrobot", 2, 1e-12)])
def test_fddp_reaches_ipopts_optimum(name, s, tol):
    r, t_fddp = solve_fddp(swingup(name), s, tol=tol)
    assert r.success and r.status == "converged" and r.solver["feasible"], (r.status, r.iterations)
    assert r.constraint_violation == 0
    # From its default guess (the zero-control rollout) IPOPT finds another local optimum of the acrobot
    # (cost 19.50 against FDDP's 18.585): there it starts from FDDP's solution and must reconverge to
    # its own tolerance; the pendulum and cart-pole are solved by IPOPT from its default guess.
    ri, t_ipopt = tight_ipopt(swingup(name), s, guess=r if name == "acrobot" else None)
    assert ri.success, ri.status
    du = np.abs(r.trajectory["u"] - ri.trajectory["u"]).max()
    dq = np.abs(r.trajectory["q"] - ri.trajectory["q"]).max()
    rel = abs(r.cost - ri.cost) / ri.cost
    print(f"{name} s={s} tol={tol:g}: FDDP {r.iterations} it {t_fddp:.3f} s (stop {r.solver['stop']:.1e}), "
          f"IPOPT {ri.iterations} it {t_ipopt:.3f} s; cost {r.cost:.12g} vs {ri.cost:.12g} (rel {rel:.1e}), "
          f"max|du| {du:.1e}, max|dq| {dq:.1e}")
    assert rel <= 1e-6
    assert du <= 1e-5


def test_fddp_threads_give_the_same_iterates():
    r1, _ = solve_fddp(swingup("pendulum"), 2, tol=1e-12)
    r2, _ = solve_fddp(swingup("pendulum"), 2, tol=1e-12, threads=2)
    assert r2.iterations == r1.iterations
    np.testing.assert_array_equal(r2.solver["us"], r1.solver["us"])


# --- 4. binding control bounds -----------------------------------------------------------------

@pytest.mark.parametrize("s", [1, 2])
def test_bounds_active_same_optimum_as_ipopt(s):
    # |u| <= 1.5 does not bind on this swing-up (the |u| <= 4 optimum peaks at 1.24 (s=1), 1.20 (s=2));
    # |u| <= 1 puts 12-14 of the 40 controls on a bound.
    ub = 1.0
    # tol 1e-13: at 1e-12 the controls agree to 8.1e-6 (s=1), 6.8e-6 (s=2), close to the 1e-5 asked.
    r, t_fddp = solve_fddp(swingup("pendulum", ub), s, tol=1e-13)
    assert r.success and r.solver["feasible"], r.status
    u = r.trajectory["u"]
    np.testing.assert_array_equal(r.solver["us"], u)
    assert np.all(u >= -ub) and np.all(u <= ub)
    active = np.abs(u) == ub  # the box-QP clamps: a control on a bound is exactly there
    assert active.sum() >= 1
    ri, t_ipopt = tight_ipopt(swingup("pendulum", ub), s)
    assert ri.success, ri.status
    ui = ri.trajectory["u"]
    du = np.abs(u - ui).max()
    rel = abs(r.cost - ri.cost) / ri.cost
    print(f"pendulum |u|<={ub} s={s}: FDDP {r.iterations} it {t_fddp:.3f} s, IPOPT {ri.iterations} it {t_ipopt:.3f} s;"
          f" {active.sum()} controls at a bound; cost rel {rel:.1e}, max|du| {du:.1e}")
    assert du <= 1e-5
    assert rel <= 1e-6
    np.testing.assert_array_equal(active, np.abs(ui) >= ub - 1e-8)  # the same active set as IPOPT's KKT point


# --- 5. warm start and replay ------------------------------------------------------------------

@pytest.mark.parametrize("name", ["pendulum", "cartpole"])
def test_warm_start_and_replay(name):
    r, t_cold = solve_fddp(swingup(name), 2, tol=1e-12)
    assert r.success, r.status
    pr = swingup(name)
    t0 = time.perf_counter()
    w = trajopt.FDDP(tol=1e-12).solve(pr, trajopt.VI(2), guess=r)
    print(f"{name}: cold {r.iterations} it {t_cold:.3f} s, warm {w.iterations} it {time.perf_counter() - t0:.4f} s")
    assert w.success and w.iterations <= 2, (w.status, w.iterations)
    assert np.abs(w.trajectory["u"] - r.trajectory["u"]).max() <= 1e-9
    assert abs(w.cost - r.cost) <= 1e-10 * r.cost
    c = trajopt.FDDP(tol=1e-12).solve(swingup(name), trajopt.VI(2), guess=r.trajectory["u"])  # the controls (N, m)
    assert c.success and c.iterations <= 2, (c.status, c.iterations)
    assert np.abs(c.trajectory["u"] - r.trajectory["u"]).max() <= 1e-9
    n, N, s = pr.model.n, pr.N, 2
    assert r.solver["K"].shape == (N, pr.model.n_controls, 2 * n)
    traj = r.replay()
    assert traj.steps == N
    np.testing.assert_allclose(traj.configuration_points, r.trajectory["q"], rtol=0, atol=1e-9)
    # FDDP's own iterate (its C++ steps from other Newton guesses) is the same VI trajectory
    xs = r.solver["xs"]
    np.testing.assert_allclose(traj.q, xs[:, :n], rtol=0, atol=1e-9)
    np.testing.assert_allclose(traj.p, xs[:, n:], rtol=0, atol=1e-9)
    # and a feasible point of IPOPT's NLP, where its objective is FDDP's cost
    nlp = trajopt.NLP(r.transcription)
    assert nlp.violation(r.x) <= 1e-9
    assert nlp.objective(r.x) == pytest.approx(r.cost, rel=1e-10)
    assert traj.control_points.shape == (N, s + 1, n)


# --- 6. refusals -------------------------------------------------------------------------------

def pendulum_problem(**kwargs):
    model = models.pendulum(1)
    model.add_actuator(0)
    pr = trajopt.Problem(model, 10, 1.0, **{"controls": "held", "u_bounds": (-4, 4), "q_bounds": INF, **kwargs})
    return pr.initial_state([0.0]).add_cost(trajopt.ControlEffort())


def test_fddp_refuses_what_it_does_not_handle():
    fddp = trajopt.FDDP()
    with pytest.raises(ValueError, match="held controls"):
        fddp.solve(pendulum_problem(controls="per_point"))
    with pytest.raises(ValueError, match="no hard final state"):
        fddp.solve(pendulum_problem().final_state([np.pi]))
    with pytest.raises(ValueError, match="path and input constraints"):
        fddp.solve(pendulum_problem().add_constraint(trajopt.BodyPoint(0, [0, 0, -0.5], axes="z", lower=-0.6,
                                                                         window=(0.0, 1.0))))
    with pytest.raises(ValueError, match="path and input constraints"):
        fddp.solve(pendulum_problem().add_constraint(trajopt.InputConstraint(np.ones((1, 1)), -1.0, 1.0)))
    with pytest.raises(ValueError, match="joint bounds"):
        fddp.solve(pendulum_problem(q_bounds=(-3.0, 3.0)))
    with pytest.raises(ValueError, match="FDDP needs the Hessian of a CallbackCost"):
        fddp.solve(pendulum_problem().add_cost(trajopt.CallbackCost(lambda t, w, q, v, u: (
            0.0, np.zeros_like(q), np.zeros_like(v), np.zeros_like(u)))))
    with pytest.raises(ValueError, match="variational integrator"):
        fddp.solve(pendulum_problem(), trajopt.HermiteSimpson("implicit"))
    with pytest.raises(ValueError, match="FDDP guess must be None, a Result"):
        fddp.solve(pendulum_problem(), trajopt.VI(2), guess="linear")
    with pytest.raises(ValueError, match=r"FDDP guess controls must be \(1,\) or \(10, 1\)"):
        fddp.solve(pendulum_problem(), trajopt.VI(2), guess=np.zeros((9, 1)))
    crank = models.slider_crank()
    crank.add_actuator(0)
    closed = trajopt.Problem(crank, 10, 1.0, controls="held", u_bounds=(-10, 10), q_bounds=INF)
    closed.initial_state(close_mechanism(crank, [0.6, -1.0])).add_cost(trajopt.ControlEffort())
    with pytest.raises(ValueError, match="holonomic constraints"):
        fddp.solve(closed)


def test_fddp_options_named():
    for tol in (0.0, -1e-9):
        with pytest.raises(ValueError, match="tol must be > 0"):
            trajopt.FDDP(tol=tol)
    with pytest.raises(ValueError, match="tol must be a finite number"):
        trajopt.FDDP(tol=float("nan"))
    with pytest.raises(ValueError, match="max_iterations must be >= 0"):
        trajopt.FDDP(max_iterations=-1)
    with pytest.raises(ValueError, match="max_iterations must be a whole number"):
        trajopt.FDDP(max_iterations=2.5)
    with pytest.raises(ValueError, match="threads must be >= 1"):
        trajopt.FDDP(threads=0)
    with pytest.raises(ValueError, match="smoothing must be >= 0"):
        trajopt.FDDP(smoothing=-1e-6)
    with pytest.raises(ValueError, match="smoothing is for shooting through contact"):
        trajopt.FDDP(smoothing=1e-6)


# --- 7. a stopped solve is reported as stopped --------------------------------------------------

def test_max_iterations_reported():
    r = trajopt.FDDP(max_iterations=2).solve(swingup("cartpole"), trajopt.VI(2))
    assert r.success is False
    assert r.status == "max_iterations"
    assert r.iterations == 2 and r.solver["trace"].shape == (2, 5)
    assert r.trajectory["u"].shape == (50, 1) and np.all(np.isfinite(r.trajectory["u"]))


def callback_acrobot(user):
    """An acrobot problem whose running cost is StateTracking + ControlEffort, or the same written as a
    CallbackCost with its Hessian (what FDDP needs of a user cost)."""
    m = models.acrobot()
    pr = trajopt.Problem(m, 30, 3.0, controls="held", u_bounds=(-15, 15), q_bounds=(-np.inf, np.inf))
    pr.initial_state([0.1, 0.0]).add_cost(trajopt.TerminalCost([np.pi, 0], 100.0, velocity_weight=10.0))
    W, Wv, R = np.array([1.0, 2.0]), np.array([0.3, 0.1]), 0.5
    if not user:
        return pr.add_cost(trajopt.StateTracking([0, 0], W, velocity_weight=Wv)).add_cost(trajopt.ControlEffort(R))

    def fun(t, w, q, v, u):
        value = np.sum(w[:, None] * (W * q ** 2 + Wv * v ** 2)) + np.sum(w[:, None] * R * u ** 2)
        return value, 2 * w[:, None] * W * q, 2 * w[:, None] * Wv * v, 2 * w[:, None] * R * u

    def hessian(t, w, q, v, u):
        H = np.zeros((len(t), 5, 5))
        for i, x in enumerate([W[0], W[1], Wv[0], Wv[1], R]):
            H[:, i, i] = 2 * w * x
        return H
    return pr.add_cost(trajopt.CallbackCost(fun, hessian))


@pytest.mark.parametrize("s", [1, 2, 3])
def test_user_cost_in_python_equals_the_built_in_terms(s):
    """A CallbackCost (value, gradient and Hessian in Python, one call per rollout and per
    linearisation) gives FDDP the iterates of the same cost in C++."""
    a = trajopt.FDDP(tol=1e-12).solve(callback_acrobot(False), trajopt.VI(s))
    b = trajopt.FDDP(tol=1e-12).solve(callback_acrobot(True), trajopt.VI(s))
    assert a.success and b.success and a.iterations == b.iterations
    assert abs(a.cost - b.cost) <= 1e-12 * a.cost
    np.testing.assert_allclose(b.solver["us"], a.solver["us"], rtol=0, atol=1e-10)


def test_user_cost_exception_reaches_the_caller():
    pr = callback_acrobot(True)

    def broken(t, w, q, v, u):
        raise KeyError("from the user's cost")
    pr.costs[-1] = trajopt.CallbackCost(broken, pr.costs[-1].hessian)
    with pytest.raises(KeyError, match="from the user's cost"):
        trajopt.FDDP().solve(pr, trajopt.VI(1))


# --- through contact -----------------------------------------------------------------------------

def sliding_block():
    """A point mass on flat ground (x-z plane, mu = 0.5), pushed along x (control 0): its contact
    slides under any push beyond mu m g = 9.81 N, so x-perturbations keep the contact state."""
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=2.0, inertia=np.eye(3) * 1e-3)
    model.add_actuator(0)
    return model, Contacts(model, [("mass", (0.0, 0.0, 0.0))], Terrain(), mu=0.5, plane="xz")


def block_problem(model, N=20, T=0.4):
    pr = trajopt.Problem(model, N, T, controls="held", u_bounds=(-40.0, 40.0), q_bounds=INF)
    pr.initial_state([0.0, 0.0])
    pr.add_cost(trajopt.ControlEffort(0.01))
    return pr.add_cost(trajopt.TerminalCost([0.3, 0.0], [1e3, 0.0], velocity_weight=[10.0, 0.0]))


def test_contact_shooting_derivatives_against_differences():
    """Through contact the shooting problem's A, B (the contact step, its sliding state held) and
    lx, lu equal central differences along x (q_x, p_x, u: no contact switch within them)."""
    model, contacts = sliding_block()
    pr = block_problem(model)
    fddp = trajopt.FDDP(contacts=contacts)
    tr = trajopt.VI(1).transcribe(pr)
    integ = fddp.dynamics(pr, tr)
    sp = fddp.shooting_problem(pr, tr, integ)
    q, p, u = np.array([0.1, 0.0]), np.array([0.4, -2.0 * 9.81 * integ.dt / 2]), np.array([15.0])
    _, _, info = integ.step(q, p, u)
    assert info.impulses[0, 0] > 0 and info.impulses[0, -1] > 0  # loaded and sliding
    d = sp.derivatives(3, info.control_points, u, info.impulses.ravel())

    def step(x, uu):
        qn, pn, _ = integ.step(x[:2], x[2:], uu)
        return np.concatenate([qn, pn])

    def cost(x, uu):
        _, _, inf = integ.step(x[:2], x[2:], uu)
        return sp.stage_cost(3, inf.control_points, uu)
    x, h = np.concatenate([q, p]), 1e-6
    for j in (0, 2):  # q_x and p_x
        e = np.zeros(4)
        e[j] = h
        np.testing.assert_allclose(d["A"][:, j], (step(x + e, u) - step(x - e, u)) / (2 * h), rtol=0, atol=1e-7)
        assert abs(d["lx"][j] - (cost(x + e, u) - cost(x - e, u)) / (2 * h)) <= 1e-6 * (1 + abs(d["lx"][j]))
    du = np.array([h])
    np.testing.assert_allclose(d["B"][:, 0], (step(x, u + du) - step(x, u - du)) / (2 * h), rtol=0, atol=1e-7)
    assert abs(d["lu"][0] - (cost(x, u + du) - cost(x, u - du)) / (2 * h)) <= 1e-6 * (1 + abs(d["lu"][0]))


@pytest.mark.parametrize("smoothing,guess", [(0.0, 15.0), (1e-8, 0.0)])
def test_fddp_through_contact_is_stationary_on_the_contact_simulator(smoothing, guess):
    """FDDP shooting with the contact simulator pushes the block to x = 0.3; its solution is a
    trajectory of the simulator (replayed to 1e-12) and stationary: central differences of the total
    cost of simulator rollouts with respect to each control vanish. With the contact state held
    (smoothing = 0) it starts from a push that slides (from rest see the next test); smoothed, from rest."""
    model, contacts = sliding_block()
    pr = block_problem(model)
    fddp = trajopt.FDDP(contacts=contacts, smoothing=smoothing, tol=1e-12)
    r = fddp.solve(pr, trajopt.VI(1), guess=np.full(1, guess))
    assert r.success, (r.status, r.iterations)
    tr = trajopt.VI(1).transcribe(pr)
    integ = fddp.dynamics(pr, tr)
    sp = fddp.shooting_problem(pr, tr, integ)
    us = r.solver["us"]

    def total(U):
        traj = integ.rollout([0.0, 0.0], pr.N, u=U)
        return sum(sp.stage_cost(k, traj.control_points[k], U[k]) for k in range(pr.N)), traj
    J, traj = total(us)
    assert abs(J - r.cost) <= 1e-10 * r.cost
    np.testing.assert_allclose(traj.q, r.solver["trajectory"].q, rtol=0, atol=1e-12)
    assert abs(traj.q[-1, 0] - 0.3) < 0.01 and traj.contact.gaps.min() >= -1e-10
    h = 1e-5
    for k in range(pr.N):
        e = np.zeros_like(us)
        e[k, 0] = h
        g = (total(us + e)[0] - total(us - e)[0]) / (2 * h)
        assert abs(g) <= 1e-4 * (1 + r.cost), (k, g)


def test_fddp_through_a_held_sticking_contact_sees_no_gradient():
    """The limit of the held contact state: a block at rest under stiction has zero sensitivity to
    small pushes in its Jacobians (the stick holds x), so FDDP from zero controls without smoothing
    stops at once where it started, though pushing beyond friction lowers the cost; smoothing
    (smoothing > 0, the previous test) gives the gradient across the switch."""
    model, contacts = sliding_block()
    r = trajopt.FDDP(contacts=contacts).solve(block_problem(model), trajopt.VI(1))
    assert r.iterations == 0 and np.all(r.solver["us"] == 0)
    assert abs(r.solver["trajectory"].q[-1, 0]) == 0.0
