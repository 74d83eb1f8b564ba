"""Issue 45: hostile input to hovi.control and FDDP. What was accepted without a word (a trajectory or
policy of another model, dt or s; a diverging Riccati recursion) is refused naming the argument; a
run that stops early (a failed plant step, a solve that raises) is flagged and warned about, never
silently short; FDDP stopped by a held sticking contact is not a success; unclear errors
(AttributeError, IndexError, KeyError, numpy broadcasting, internal names) are ValueError or
TypeError naming the caller's argument; Policy.open_loop reproduces Integrator.rollout."""
import dataclasses

import numpy as np
import pytest

import hovi
from hovi import control, trajopt
from hovi.contact import Contacts, Terrain
from hovi.examples import models
from conftest import planar_point_mass

INF = (-np.inf, np.inf)
HUGE_PUSH = [control.Push(0.05, "pole", [1e12, 0, 0])]  # the plant's Newton solve fails at step 5


@pytest.fixture(scope="module")
def cartpole():
    integ = hovi.Integrator(models.cartpole(), s=1, dt=0.01)
    return integ, control.lqr(integ, [0, np.pi])


def held_problem(model, N=10, T=0.1, **state):
    pr = trajopt.Problem(model, N, T, controls="held", q_bounds=INF)
    return pr.initial_state([0, 3], **state).add_cost(trajopt.ControlEffort())


def fields(policy, **changes):
    return {**policy.__dict__, **changes}


# --- 1. accepted without a word before -------------------------------------------------------------

def test_tvlqr_refuses_a_trajectory_of_another_model_dt_or_s(cartpole):
    integ, _ = cartpole
    U = np.zeros((5, 1))
    with pytest.raises(ValueError, match=r"trajectory is of another model \(n = 3"):
        control.tvlqr(integ, hovi.Integrator(models.pendulum(3), s=1, dt=0.01).rollout([0, 0, 0], 5), U)
    other_dt = hovi.Integrator(integ.model, s=1, dt=0.02).rollout([0, 3], 5, u=U)
    with pytest.raises(ValueError, match=r"trajectory was computed with s = 1, dt = 0.02.*must match"):
        control.tvlqr(integ, other_dt, U)
    with pytest.raises(ValueError, match=r"trajectory was computed with s = 1, dt = 0.02"):  # loaded without it
        control.tvlqr(integ, dataclasses.replace(other_dt, discretization=None), U)
    with pytest.raises(ValueError, match=r"trajectory was computed with s = 2"):
        control.tvlqr(integ, hovi.Integrator(integ.model, s=2, dt=0.01).rollout([0, 3], 5, u=U), U)


def test_a_policy_runs_only_on_a_plant_of_its_dt(cartpole):
    integ, policy = cartpole
    coarse = hovi.Integrator(integ.model, s=1, dt=0.05)
    with pytest.raises(ValueError, match=r"plant's dt \(0.05\) is not the policy's \(0.01\)"):
        control.simulate(coarse, policy, [0, 3], 5)
    with pytest.raises(ValueError, match=r"plant's dt \(0.05\) is not the policy's"):
        control.simulate_batch([integ, coarse], policy, [0, 3], 5)


@pytest.mark.parametrize("growth,b,what", [(10.0, 0.0, "overflowed .*not finite from step"),
                                           (50.0, 1.0, "broke down")])
def test_riccati_policy_on_a_diverging_A_raises_naming_the_cause(cartpole, growth, b, what):
    integ, _ = cartpole
    K = 400 if b == 0 else 40
    q = np.tile([0.0, np.pi], (K + 1, 1))
    with pytest.raises(ValueError, match=f"Riccati recursion over the K = {K} steps {what}.*largest "
                                         rf"\|eigenvalue\| {growth:g}"):
        control.riccati_policy(integ, q, np.zeros((K + 1, 2)), np.zeros((K, 2, 1)),
                               np.tile(growth * np.eye(4), (K, 1, 1)), np.full((K, 4, 1), b))


@pytest.mark.parametrize("steps", [2.5, 5.0, "5", True, -1])
def test_simulate_refuses_a_step_count_that_is_not_a_whole_number(cartpole, steps):
    integ, policy = cartpole
    with pytest.raises(ValueError, match="steps must be"):
        control.simulate(integ, policy, [0, 3], steps)


# --- 2. a run that stops early is flagged and warned about ------------------------------------------

def test_a_failed_plant_step_is_flagged_and_warned(cartpole):
    integ, policy = cartpole
    with pytest.warns(RuntimeWarning, match=r"closed-loop run ended early, at step 5 of 20 .*Newton solve failed"):
        run = control.simulate(integ, policy, [0, 3], 20, pushes=HUGE_PUSH)
    assert run.trajectory.steps == 5 and not run.converged
    assert run.failure.startswith("step 5 of 20 (t = 0.05 s): the plant's Newton solve failed (")
    assert "FAILED at step 5" in repr(run) and len(run.u) == 6  # the failed step's controls last
    with pytest.warns(RuntimeWarning, match=r"1 of 2 closed-loop runs ended early \(run 1: at step 5 of 20"):
        runs = control.simulate_batch(integ, policy, [0, 3], 20, pushes=[[], HUGE_PUSH], threads=1)
    assert runs[0].failure is None and runs[0].trajectory.steps == 20 and "completed" in repr(runs[0])
    assert runs[1].failure == run.failure


def test_an_mpc_solve_that_fails_ends_the_run_flagged_with_what_was_done(cartpole):
    integ, _ = cartpole
    mpc = control.MPC(held_problem(integ.model))
    with pytest.warns(RuntimeWarning, match=r"MPC run ended early, at step 5 of 20 .*solve .*failed"):
        run = mpc.run(integ, [0, 3], 20, pushes=HUGE_PUSH)
    assert run.trajectory.steps == 5 and len(run.u) == 5 and len(run.solve_seconds) == 5
    assert run.trajectory.status[-1] == "controller_failed"  # the C++ loop ended there, in one run
    assert "the step from the initial guess failed" in run.failure and "FAILED at step 5" in repr(run)
    done = mpc.run(integ, [0, 3], 5)  # the part before the push, as a run of its own
    np.testing.assert_array_equal(run.trajectory.q, done.trajectory.q)
    np.testing.assert_array_equal(run.u, done.u)
    with pytest.warns(RuntimeWarning, match="at step 0 of 20"):  # the first solve
        first = mpc.run(integ, [0, 3], 20, qdot0=[1e6, 1e6])
    assert first.trajectory.steps == 0 and first.u.shape == (0, 2, 1)


def test_an_mpc_plant_step_that_fails_between_solves_is_flagged(cartpole):
    integ, _ = cartpole
    with pytest.warns(RuntimeWarning, match=r"at step 3 of 20 .*the plant's Newton solve failed"):
        run = control.MPC(held_problem(integ.model), period=5).run(
            integ, [0, 3], 20, pushes=[control.Push(0.03, "pole", [1e12, 0, 0])])
    assert run.trajectory.steps == 3 and run.failure.startswith("step 3 of 20")


# --- 3. FDDP stopped by a held sticking contact --------------------------------------------------------

def block_problem():
    model = planar_point_mass(2.0, actuated=True)
    contacts = Contacts(model, [("mass", (0.0, 0.0, 0.0))], Terrain(), mu=0.5, plane="xz")
    pr = trajopt.Problem(model, 20, 0.4, controls="held", u_bounds=(-40.0, 40.0), q_bounds=INF)
    pr.initial_state([0.0, 0.0]).add_cost(trajopt.ControlEffort(0.01))
    return contacts, pr.add_cost(trajopt.TerminalCost([0.3, 0.0], [1e3, 0.0], velocity_weight=[10.0, 0.0]))


def test_fddp_stopped_by_a_held_sticking_contact_is_not_a_success():
    contacts, pr = block_problem()
    held = trajopt.FDDP(contacts=contacts).solve(pr, trajopt.VI(1))
    assert not held.success and held.iterations == 0
    assert held.status.startswith("zero gradient through a held contact") and "smoothing > 0" in held.status
    smoothed = trajopt.FDDP(contacts=contacts, smoothing=1e-8).solve(pr, trajopt.VI(1))
    assert smoothed.success and smoothed.cost < held.cost / 20 < held.solver["held_contact_descent"]
    sliding = trajopt.FDDP(contacts=contacts).solve(pr, trajopt.VI(1), guess=np.full(1, 15.0))  # a real optimum
    assert sliding.success and sliding.status == "converged" and sliding.solver["held_contact_descent"] < 1e-9


# --- 4. messages that name the caller's argument --------------------------------------------------------

POLICY_ERRORS = [
    (dict(x_ref=np.zeros((3, 4))), ValueError, r"x_ref, u_ref and gains must each have one row per stage"),
    (dict(u_ref=np.zeros((1, 3, 1))), ValueError, r"u_ref must have shape \(1, 2, 1\)"),
    (dict(gains=np.zeros((1, 4))), ValueError, r"gains must have shape \(S, m, 2n\)"),
    (dict(gains="K"), ValueError, "gains must be an array of real numbers"),
    (dict(lower=[1.0], upper=[-1.0]), ValueError, "lower and upper must be numbers with lower <= upper"),
    (dict(lower=[0.0, 0.0]), ValueError, r"lower must have shape \(1,\)"),
    (dict(cost_to_go=np.zeros((1, 3, 3))), ValueError, r"cost_to_go must have shape \(any, 4, 4\)"),
    (dict(dt=0.0), ValueError, "dt must be > 0"),
    (dict(dt="0.01"), ValueError, "dt must be a real number"),
    (dict(s=0), ValueError, "s must be >= 1"),
    (dict(s=1.5), ValueError, "s must be a whole number"),
]


@pytest.mark.parametrize("changes,error,match", POLICY_ERRORS, ids=[m for _, _, m in POLICY_ERRORS])
def test_a_policy_of_bad_fields_is_refused_naming_the_field(cartpole, changes, error, match):
    _, policy = cartpole
    with pytest.raises(error, match=match):
        control.Policy(**fields(policy, **changes))


def test_a_policy_of_nested_lists_is_one_of_arrays(cartpole):
    integ, policy = cartpole
    listed = control.Policy(**{k: v.tolist() if isinstance(v, np.ndarray) else v for k, v in policy.__dict__.items()})
    assert isinstance(listed.gains, np.ndarray) and listed.gains.dtype == np.float64
    np.testing.assert_array_equal(listed.control(3, [0.1, 3.0], [0.0, 0.2]), policy.control(3, [0.1, 3.0], [0.0, 0.2]))


def test_bad_calls_are_named(cartpole):
    integ, policy = cartpole
    with pytest.raises(ValueError, match="k must be non-negative"):
        policy.control(-5, [0, 3], [0, 0])
    with pytest.raises(ValueError, match="k must be a whole number"):
        policy.control(1.5, [0, 3], [0, 0])
    with pytest.raises(ValueError, match="steps must be >= 1"):
        control.simulate(integ, policy, [0, 3], 0)
    with pytest.raises(ValueError, match="steps must be >= 1"):
        control.MPC(held_problem(integ.model)).run(integ, [0, 3], 0)
    with pytest.raises(TypeError, match=r"pushes must be a list of lists of hovi.control.Push.*got a flat list"):
        control.simulate_batch(integ, policy, [0, 3], 5, pushes=HUGE_PUSH)
    with pytest.raises(TypeError, match="pushes must be a list of hovi.control.Push, got one Push"):
        control.simulate(integ, policy, [0, 3], 5, pushes=HUGE_PUSH[0])
    with pytest.raises(TypeError, match=r"pushes\[0\] must be a list of hovi.control.Push"):
        control.simulate_batch(integ, policy, [0, 3], 5, pushes=[["push"]])
    for runs in (0, -1):
        with pytest.raises(ValueError, match="runs must be >= 1"):
            control.simulate_batch(integ, policy, [0, 3], 5, runs=runs)
    with pytest.raises(TypeError, match="plants must be a hovi.Integrator or a non-empty list"):
        control.simulate_batch([], policy, [0, 3], 5)


@pytest.mark.parametrize("cost,match", [
    (trajopt.TerminalCost([0, 1, 2]), r"TerminalCost q_target must be a number or 2 numbers, got shape \(3,\)"),
    (trajopt.TerminalCost([0, 1], weight=[1, 2, 3]), r"TerminalCost weight must be a number or 2 numbers"),
    (trajopt.TerminalCost([0, 1], v_target=[0, 0, 0]), r"TerminalCost v_target must be a number or 2 numbers"),
    (trajopt.StateTracking([0, 1], [1, 2, 3]), r"StateTracking weight must be a number or 2 numbers"),
    (trajopt.StateTracking([0, 1], velocity_weight=[1, 2, 3]), "StateTracking velocity_weight must be a number or 2"),
    (trajopt.ControlEffort([1.0, 2.0]), r"ControlEffort weight must be a number or 1 numbers"),
])
def test_fddp_costs_of_the_wrong_length_are_named(cartpole, cost, match):
    integ, _ = cartpole
    with pytest.raises(ValueError, match=match):
        trajopt.FDDP().solve(held_problem(integ.model).add_cost(cost), trajopt.VI(1))
    with pytest.raises(ValueError, match=match):
        control.MPC(held_problem(integ.model).add_cost(cost))


def test_fddp_and_mpc_name_the_callers_arguments(cartpole):
    integ, _ = cartpole
    pr = held_problem(integ.model)
    mpc = control.MPC(pr)
    with pytest.raises(ValueError, match=r"warm_start must have shape \(10, 1\), got shape \(3, 1\)"):
        mpc.run(integ, [0, 3], 3, warm_start=np.zeros((3, 1)))
    with pytest.raises(ValueError, match=r"q0 must have shape \(2,\)"):
        mpc.run(integ, [0, 3, 4], 3)
    with pytest.raises(ValueError, match=r"qdot0 must have shape \(2,\)"):
        mpc.run(integ, [0, 3], 3, qdot0=[0.0])
    with pytest.raises(ValueError, match="MPC does not take a CallbackCost"):
        control.MPC(held_problem(integ.model).add_cost(trajopt.CallbackCost(lambda *a: None, lambda *a: None)))
    with pytest.raises(ValueError, match="s must be a whole number"):
        control.MPC(pr, s=float("inf"))
    with pytest.raises(ValueError, match=r"FDDP guess: u\(t\) at the middles t \(10,\) of the steps must be \(10, 1\)"):
        trajopt.FDDP().solve(pr, trajopt.VI(1), guess=(None, None, lambda t: np.zeros((3, 3))))
    with pytest.raises(ValueError, match=r"FDDP guess: u\(t\) .* must be an array of real numbers"):
        trajopt.FDDP().solve(pr, trajopt.VI(1), guess=(None, None, lambda t: "x"))
    with pytest.raises(TypeError, match="problem must be a hovi.trajopt.Problem"):
        trajopt.FDDP().solve("problem", trajopt.VI(1))


# --- 5. the open loop -----------------------------------------------------------------------------

@pytest.mark.parametrize("held", [False, True])
def test_an_open_loop_policy_is_the_rollout_of_its_controls(cartpole_lqr, held):
    integ, lqr = cartpole_lqr  # s = 2
    K = 80
    t = (np.arange(K)[:, None] + integ.nodes[None, :]) * integ.dt
    U = (np.sin(3 * t[:, :1]) if held else 2.0 * np.sin(3 * t) + 0.5 * t)[..., None]
    U = U[:, 0] if held else U  # (K, m) held, or (K, s+1, m) per control point
    policy = control.Policy.open_loop(U, integ.dt, integ.s, integ.n)
    assert policy.stages == K and np.all(policy.gains == 0) and policy.u_ref.shape == (K, 3, 1)
    run = control.simulate(integ, policy, [0.0, 0.4], K, qdot0=[0.1, 0.0])
    ref = integ.rollout([0.0, 0.4], K, qdot0=[0.1, 0.0], u=U)
    scale = np.abs(ref.q).max()
    np.testing.assert_allclose(run.trajectory.q, ref.q, rtol=0, atol=1e-12 * scale)
    np.testing.assert_allclose(run.trajectory.p, ref.p, rtol=0, atol=1e-12 * np.abs(ref.p).max())
    np.testing.assert_array_equal(run.u, policy.u_ref)
    bare = lqr.without_feedback()
    assert np.all(bare.gains == 0) and np.array_equal(bare.u_ref, lqr.u_ref) and np.any(lqr.gains != 0)


def test_open_loop_refuses_controls_of_another_shape():
    with pytest.raises(ValueError, match=r"u must have shape \(K, 3, m\) \(per control point\) or \(K, m\)"):
        control.Policy.open_loop(np.zeros((5, 2, 1)), 0.01, 2, 2)
    with pytest.raises(ValueError, match=r"u must have shape"):
        control.Policy.open_loop(np.zeros(5), 0.01, 2, 2)
    with pytest.raises(ValueError, match="n must be >= 1"):
        control.Policy.open_loop(np.zeros((5, 1)), 0.01, 2, 0)
