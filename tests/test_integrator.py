"""The Galerkin integrator end to end: order of accuracy against DOP853, energy behaviour,
stress, and the Python API's checks."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp

import hovi
from conftest import observed_order
from test_urdf import CHAIN


def dop853_reference(model, q0, qd0, T):
    n = model.n

    def f(t, y):
        return np.concatenate([y[n:], model.forward_dynamics(y[:n], y[n:])])

    sol = solve_ivp(f, (0, T), np.concatenate([q0, qd0]), method="DOP853", rtol=1e-13, atol=1e-13)
    assert sol.success
    return sol.y[:n, -1]


@pytest.mark.parametrize("s, dts", [
    (1, [0.02, 0.01, 0.005, 0.0025]),
    (2, [0.05, 0.025, 0.0125, 0.00625]),
    (3, [0.1, 0.05, 0.025, 0.0125]),
])
def test_order_of_accuracy_is_2s(s, dts):
    model = hovi.examples.models.pendulum(5)
    rng = np.random.default_rng(1)
    q0, qd0 = rng.uniform(-0.5, 0.5, 5), rng.uniform(-0.5, 0.5, 5)
    ref = dop853_reference(model, q0, qd0, 1.0)
    slope, errors = observed_order(lambda dt: hovi.Integrator(model, s=s, dt=dt, tol=1e-13), q0, qd0, ref, dts)
    assert abs(slope - 2 * s) <= 0.3, (slope, errors)


@pytest.mark.parametrize("s", [1, 2, 3])
def test_energy_error_is_bounded_without_drift(s):
    # The paper's Fig. 4 set-up: 12 links, q0 uniform in [-pi/12, pi/12], zero velocity.
    model = hovi.examples.models.pendulum(12)
    rng = np.random.default_rng(0)
    integ = hovi.Integrator(model, s=s, dt=0.01)
    traj = integ.rollout(rng.uniform(-np.pi / 12, np.pi / 12, 12), 10_000)
    signed = traj.energy - traj.energy[0]
    err = np.abs(signed)
    tenth = len(err) // 10
    first, last = err[1:tenth].mean(), err[-tenth:].mean()
    assert last <= 2 * first, (first, last)
    # no secular trend: the least-squares drift over the run is small next to the oscillation
    drift = np.polyfit(traj.t, signed, 1)[0] * traj.t[-1]
    assert abs(drift) < 0.5 * err.max(), (drift, err.max())
    assert err.max() < [2e-2, 1e-4, 1e-6][s - 1] * abs(traj.energy[0])


@pytest.mark.parametrize("s", [1, 2])
def test_armature_energy_is_conserved_and_zero_armature_changes_nothing(s):
    """Joint armature (1/2 a q̇^2 in K) belongs to the conserved energy: its error stays bounded,
    without drift; the motion differs from the model without it; an all-zero armature takes the
    armature-free path, bit for bit."""
    model = hovi.examples.models.pendulum(6)
    rng = np.random.default_rng(60 + s)
    q0 = rng.uniform(-np.pi / 6, np.pi / 6, 6)
    plain = hovi.Integrator(model, s=s, dt=0.01).rollout(q0, 3000)
    zero = model.copy()
    zero.armature = np.zeros(6)
    again = hovi.Integrator(zero, s=s, dt=0.01).rollout(q0, 3000)
    np.testing.assert_array_equal(again.q, plain.q)
    np.testing.assert_array_equal(again.p, plain.p)
    geared = model.copy()
    geared.armature = rng.uniform(0.05, 0.3, 6)
    traj = hovi.Integrator(geared, s=s, dt=0.01).rollout(q0, 3000)
    assert np.abs(traj.q - plain.q).max() > 0.1
    # E = 1/2 p^T (M + diag(a))^{-1} p + V from the mass matrix (checked against Pinocchio's)
    energy = np.array([0.5 * p @ np.linalg.solve(geared.mass_matrix(q), p) + geared.potential_energy(q)
                       for q, p in zip(traj.q, traj.p)])
    np.testing.assert_allclose(traj.energy, energy, rtol=1e-12, atol=1e-12 * np.abs(energy).max())
    err = np.abs(energy - energy[0])
    tenth = len(err) // 10
    assert err[-tenth:].mean() <= 2 * err[1:tenth].mean()
    assert err.max() < [2e-3, 1e-6][s - 1] * abs(energy[0]), err.max() / abs(energy[0])


def test_momentum_velocity_round_trip_and_energy():
    model = hovi.examples.models.pendulum(6)
    integ = hovi.Integrator(model, s=2)
    rng = np.random.default_rng(3)
    q, qd = rng.uniform(-1, 1, 6), rng.uniform(-1, 1, 6)
    p = integ.momentum(q, qd)
    np.testing.assert_allclose(p, model.mass_matrix(q) @ qd, rtol=1e-12)
    np.testing.assert_allclose(integ.velocity(q, p), qd, rtol=1e-10)
    assert integ.energy(q, p) == pytest.approx(model.energy(q, qd), rel=1e-12)


def test_step_and_rollout_agree_and_report():
    model = hovi.examples.models.pendulum(4)
    integ = hovi.Integrator(model, s=2, dt=0.01)
    q0 = np.array([0.3, -0.2, 0.5, 0.1])
    p0 = integ.momentum(q0, np.zeros(4))
    q1, p1, info = integ.step(q0, p0)
    assert info.converged and info.status == "converged" and 1 <= info.iterations <= 10
    assert info.control_points.shape == (3, 4)
    np.testing.assert_array_equal(info.control_points[0], q0)
    r, p_next = integ.del_residual(info.control_points, p0)
    assert np.abs(r).max() <= 1e-10 * (1 + np.abs(p0).max())
    np.testing.assert_allclose(p_next, p1, rtol=1e-12, atol=1e-14)
    traj = integ.rollout(q0, 50, p0=p0)
    assert traj.q.shape == (51, 4) and traj.p.shape == (51, 4) and traj.control_points.shape == (50, 3, 4)
    np.testing.assert_allclose(traj.q[1], q1, atol=1e-10)
    assert traj.converged and traj.iterations.shape == (50,) and np.all(traj.residuals < 1e-9)
    assert traj.t[-1] == pytest.approx(0.5)
    # chunked (progress) rollouts continue the same trajectory
    chunked = integ.rollout(q0, 50, p0=p0, progress=False, chunk=7)
    np.testing.assert_allclose(chunked.q, traj.q, atol=1e-12)


def test_controls_drive_the_system():
    model = hovi.examples.models.pendulum(2)
    model.gravity = [0, 0, 0]
    k = model.add_actuator(0)
    integ = hovi.Integrator(model, s=2, dt=0.01)
    steps = 100
    free = integ.rollout(np.zeros(2), steps)
    np.testing.assert_allclose(free.q, 0, atol=1e-14)
    pushed = integ.rollout(np.zeros(2), steps, u=[1.0])
    # constant torque from rest: the total angular momentum about the joint-1 axis grows as tau t
    assert pushed.p[-1, 0] == pytest.approx(1.0 * steps * integ.dt, rel=1e-9)
    per_point = integ.rollout(np.zeros(2), steps, u=np.ones((steps, 3, 1)))
    np.testing.assert_allclose(per_point.q, pushed.q, atol=1e-14)
    with pytest.raises(ValueError, match="u must have shape"):
        integ.rollout(np.zeros(2), steps, u=np.ones((steps, 2)))
    assert k == 0


def test_stress_large_steps_never_return_nan():
    model = hovi.examples.models.pendulum(32)
    integ = hovi.Integrator(model, s=2, dt=0.1, max_iterations=20)
    rng = np.random.default_rng(4)
    outcomes = set()
    for _ in range(20):
        q0, qd0 = rng.uniform(-np.pi / 2, np.pi / 2, (2, 32))
        p0 = integ.momentum(q0, qd0)
        q1, p1, info = integ.step(q0, p0, raise_on_failure=False)
        outcomes.add(info.status)
        if info.converged:
            assert np.all(np.isfinite(q1)) and np.all(np.isfinite(p1))
            r, _ = integ.del_residual(info.control_points, p0)
            assert np.abs(r).max() <= 1e-10 * (1 + np.abs(p0).max())
        else:
            with pytest.raises(hovi.ConvergenceError):
                integ.step(q0, p0)
    assert outcomes <= {"converged", "max_iterations", "line_search_failed", "singular_jacobian", "non_finite",
                        "continuation_stalled"}


def test_stress_stiff_springs_and_singular_base():
    model = hovi.examples.models.pendulum(5)
    for j in range(5):
        model.add_spring(j, 1e7)
    integ = hovi.Integrator(model, s=2, dt=0.05)
    q0 = np.full(5, 0.5)
    traj = integ.rollout(q0, 20, raise_on_failure=False)
    assert np.all(np.isfinite(traj.q)) and np.all(np.isfinite(traj.p))
    # A floating base at the Euler-angle singularity (pitch = pi/2): the mass matrix is singular.
    floating = hovi.Model.from_urdf(CHAIN, base="euler")
    q = np.zeros(8)
    q[4] = np.pi / 2
    integ = hovi.Integrator(floating, s=2, dt=0.01)
    with pytest.raises((hovi.ModelError, hovi.ConvergenceError)):
        integ.rollout(q, 10, qdot0=np.ones(8))
    q[4] = np.pi / 2 - 1e-3  # near the singularity: converges or reports, never NaN
    traj = integ.rollout(q, 10, qdot0=np.full(8, 0.1), raise_on_failure=False)
    assert np.all(np.isfinite(traj.q))


@pytest.mark.parametrize("kwargs, exc, pattern", [
    (dict(dt=0.0), ValueError, "dt must be > 0"),
    (dict(dt=-0.01), ValueError, "dt must be > 0"),
    (dict(dt=float("nan")), ValueError, "dt must be a finite number"),
    (dict(dt="0.01"), ValueError, "dt must be a real number, got str '0.01'"),  # was taken as 0.01
    (dict(tol="1e-9"), ValueError, "tol must be a real number, got str"),
    (dict(max_iterations=2.5), ValueError, "max_iterations must be a whole number, got 2.5"),  # was 2
    (dict(max_backtracks="3"), ValueError, "max_backtracks must be a whole number, got str"),
    (dict(line_search="no"), ValueError, "line_search must be True or False, got str 'no'"),  # was True
    (dict(reuse_jacobian=None), ValueError, "reuse_jacobian must be True or False"),
    (dict(s=0), ValueError, "s must be >= 1"),
    (dict(s=17), ValueError, "between 1 and 16"),
    (dict(s=2.5), ValueError, "s must be a whole number"),
    (dict(order=4), TypeError, "order"),
    (dict(tol=-1e-10), ValueError, "tol must be >= 0"),
    (dict(step_tol=0.0), ValueError, "step_tol must be > 0"),
    (dict(reuse_contraction=1.0), ValueError, "reuse_contraction"),
    (dict(direction="qr"), ValueError, "direction must be"),
    (dict(predictor="euler"), ValueError, "predictor must be"),
    (dict(max_iterations=0), ValueError, "max_iterations"),
])
def test_bad_integrator_options(kwargs, exc, pattern):
    with pytest.raises(exc, match=pattern):
        hovi.Integrator(hovi.examples.models.pendulum(2), **kwargs)


def test_bad_step_inputs():
    integ = hovi.Integrator(hovi.examples.models.pendulum(3), s=2)
    with pytest.raises(ValueError, match="q must be a 1-D array of length 3"):
        integ.step(np.zeros(2), np.zeros(3))
    with pytest.raises(ValueError, match="p contains NaN"):
        integ.step(np.zeros(3), np.array([0, np.nan, 0]))
    with pytest.raises(ValueError, match="no controls"):
        integ.step(np.zeros(3), np.zeros(3), u=[1.0])
    with pytest.raises(ValueError, match=r"control_points must be a 2-D array of shape \(3, 3\)"):
        integ.del_residual(np.zeros((2, 3)), np.zeros(3))
    with pytest.raises(ValueError, match="give p0 or qdot0"):
        integ.rollout(np.zeros(3), 5, p0=np.zeros(3), qdot0=np.zeros(3))
    with pytest.raises(TypeError, match="hovi.Model"):
        hovi.Integrator("pendulum")


@pytest.mark.parametrize("direction", ["recursive", "dense"])
def test_simplified_newton_gives_the_full_newton_trajectory(direction):
    """Simplified Newton (a kept factorisation) stops on the same round-off test as full Newton,
    so over 10^3 steps from a small-amplitude state the trajectories agree to 1e-10, with fewer
    factorisations."""
    model = hovi.examples.models.pendulum(8)
    q0 = np.random.default_rng(8).uniform(-np.pi / 24, np.pi / 24, 8)
    exact = hovi.Integrator(model, s=2, dt=0.01, direction=direction, reuse_jacobian=False).rollout(q0, 1000)
    reused = hovi.Integrator(model, s=2, dt=0.01, direction=direction).rollout(q0, 1000)
    assert np.all(exact.factorizations == exact.iterations)
    np.testing.assert_allclose(reused.q, exact.q, rtol=0, atol=1e-10)
    np.testing.assert_allclose(reused.p, exact.p, rtol=0, atol=1e-10)
    assert reused.factorizations.sum() < 0.6 * exact.factorizations.sum()


def test_flow_predictor_gives_the_same_trajectory_with_fewer_factorisations():
    """The flow predictor (the continuous dynamics integrated over the step) only changes where
    Newton starts: the 64-link pendulum with s = 3 at dt = 0.015 (a step at which the history's
    extrapolation lands far from the solution) gives the same trajectory with the history, the
    flow and the automatic choice (each step converged to round-off; the chain amplifies the
    difference of the last digits over 60 steps to about 1e-11, the bound of the simplified-Newton
    test above), and the flow and the automatic choice need under a third of the history's
    factorisations (measured: 172 and 195 against 787 over the 60 steps)."""
    model = hovi.examples.models.pendulum(64)
    q0 = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, 64)
    runs = {p: hovi.Integrator(model, s=3, dt=0.015, predictor=p).rollout(q0, 60) for p in ("history", "flow", "auto")}
    for p in ("flow", "auto"):
        np.testing.assert_allclose(runs[p].q, runs["history"].q, rtol=0, atol=1e-10)
        np.testing.assert_allclose(runs[p].p, runs["history"].p, rtol=0, atol=1e-10 * np.abs(runs["history"].p).max())
    for p in ("flow", "auto"):
        assert runs[p].factorizations.sum() < runs["history"].factorizations.sum() / 3


def test_automatic_predictor_keeps_the_history_where_it_suffices():
    """At a small step the history's extrapolation converges in two or three iterations: 'auto'
    never pays for the flow's forward dynamics there (its steps equal the history's, iteration
    for iteration), and for s = 1, 2 it always keeps the history."""
    model = hovi.examples.models.pendulum(12)
    q0 = np.random.default_rng(1).uniform(-np.pi / 12, np.pi / 12, 12)
    for s, dt in ((4, 0.005), (1, 0.02), (2, 0.04)):
        history = hovi.Integrator(model, s=s, dt=dt, predictor="history").rollout(q0, 100)
        auto = hovi.Integrator(model, s=s, dt=dt).rollout(q0, 100)
        np.testing.assert_array_equal(auto.iterations, history.iterations)
        np.testing.assert_array_equal(auto.q, history.q)


@pytest.mark.parametrize("s", [1, 2, 3, 4])
def test_dense_and_recursive_directions_agree(s):
    """The dense LU of the linearisation's DEL Jacobian and Algorithms A.1/A.2 give the same
    Newton direction (every force type and joint armature present) and the same converged steps."""
    model = hovi.examples.models.pendulum(5)
    for j in range(5):
        model.add_spring(j, 3.0 + j, 0.1 * j)
        model.add_damper(j, 0.2)
    model.add_actuator(2)
    model.armature = [0.3, 0.0, 0.05, 0.1, 0.0]
    rng = np.random.default_rng(s)
    q = rng.uniform(-1, 1, 5)
    qd = rng.uniform(-1, 1, 5)
    out = {}
    for direction in ("recursive", "dense"):
        integ = hovi.Integrator(model, s=s, dt=0.02, direction=direction, reuse_jacobian=False)
        p = integ.momentum(q, qd)
        u = rng.uniform(-1, 1, (s + 1, 1)) if direction == "recursive" else out["u"]
        guess = np.array([q + c * 0.02 * qd for c in integ.nodes])
        out["u"] = u
        out[direction] = (integ.newton_direction(guess, p, u), integ.rollout(q, 50, qdot0=qd, u=np.tile(u, (50, 1, 1))).q)
    d_rec, q_rec = out["recursive"]
    d_den, q_den = out["dense"]
    assert np.abs(d_rec).max() > 1e-4
    np.testing.assert_allclose(d_den, d_rec, rtol=0, atol=1e-9 * np.abs(d_rec).max())
    np.testing.assert_allclose(q_den, q_rec, rtol=0, atol=1e-10)


@pytest.mark.parametrize("direction", ["recursive", "dense"])
def test_steps_stop_at_the_round_off_floor_on_a_long_chain(direction):
    """On the 64-link pendulum the corrections bottom out near 1e-13, above step_tol: the solver
    must recognise the floor (a fresh correction that no longer shrinks) instead of running to
    max_iterations (it did on the dense path at step 177 before the floor test compared with the
    smallest trusted correction)."""
    model = hovi.examples.models.pendulum(64)
    q0 = np.random.default_rng(64).uniform(-np.pi / 12, np.pi / 12, 64)
    integ = hovi.Integrator(model, s=1, dt=0.005, direction=direction)
    traj = integ.rollout(q0, 200)
    assert traj.steps == 200 and traj.converged
    # converged means at round-off: one more exact Newton correction at the converged control
    # points is below 1e-12 (checked at every tenth step)
    for k in range(0, 200, 10):
        dq = integ.newton_direction(traj.control_points[k], traj.p[k])
        assert np.abs(dq).max() < 1e-12, (k, np.abs(dq).max())


def test_automatic_direction_follows_the_measured_crossover():
    """direction='auto' takes the path that was faster in bench/direction_crossover.py wherever
    the two differ by more than 10% (the committed measurement; no timing here)."""
    import json
    import os
    path = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "bench", "results",
                        "direction_crossover.json")
    rows = json.load(open(path))["rows"]
    assert len(rows) >= 16
    for row in rows:
        auto = hovi.Integrator(hovi.examples.models.pendulum(row["n"]), s=row["s"], dt=0.005).direction_path
        ratio = row["dense_us"] / row["recursive_us"]
        if abs(ratio - 1) > 0.1:
            assert auto == ("dense" if ratio < 1 else "recursive"), row


def test_the_integrators_options_are_keyword_only_and_steps_a_whole_number():
    model = hovi.examples.models.pendulum(2)
    with pytest.raises(TypeError):
        hovi.Integrator(model, 4, dt=0.01)  # the options are keywords: s=2
    integ = hovi.Integrator(model, s=2, dt=0.01)
    assert integ.order == 4 and hovi.Integrator(model, s=2, dt=0.01).s == 2
    for steps in (10.0, 10.5, "10", True):
        with pytest.raises(ValueError, match="steps must be a whole number"):
            integ.rollout(np.zeros(2), steps)
        with pytest.raises(ValueError, match="steps must be a whole number"):
            integ.rollout_batch(np.zeros((2, 2)), steps)
        with pytest.raises(ValueError, match="steps must be a whole number"):
            integ.check_rollout_batch(np.zeros((2, 2)), steps)
    assert integ.rollout(np.zeros(2), np.int64(3)).steps == 3
    assert list(integ.rollout_batch(np.zeros((2, 2)), np.int64(3)).steps) == [3, 3]
