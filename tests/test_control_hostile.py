"""Hostile input to hovi.control and the FDDP solver: every bad argument is a ValueError (or the
model's ModelError) naming it, never a crash, a hang or silent garbage; a run the plant cannot
finish is reported as such."""
import dataclasses

import numpy as np
import pytest

import hovi
from hovi import _core, control, trajopt
from hovi.examples import models


@pytest.fixture(scope="module")
def setup():
    m = models.cartpole()
    integ = hovi.Integrator(m, s=1, dt=0.01)
    return m, integ, control.lqr(integ, [0, np.pi])


def held_problem(m, **state):
    pr = trajopt.Problem(m, 10, 0.1, controls="held", q_bounds=(-np.inf, np.inf))
    return pr.initial_state([0, 3], **state)


def replace(policy, **fields):
    return control.Policy(**{**policy.__dict__, **fields})


@pytest.mark.parametrize("what,call,error,match", [
    ("NaN gains", lambda m, I, P: control.simulate(I, replace(P, gains=P.gains * np.nan), [0, 3], 5),
     ValueError, "gains must be finite"),
    ("infinite feed-forward", lambda m, I, P: control.simulate(I, replace(P, u_ref=P.u_ref + np.inf), [0, 3], 5),
     ValueError, "u_ref must be finite"),
    ("gains of another shape", lambda m, I, P: control.simulate(I, replace(P, gains=np.zeros((1, 1, 3))), [0, 3], 5),
     ValueError, r"gains must have shape \(S, m, 2n\)"),
    ("negative steps", lambda m, I, P: control.simulate(I, P, [0, 3], -1), ValueError, "steps"),
    ("fractional steps", lambda m, I, P: control.simulate(I, P, [0, 3], 2.5), ValueError, "steps must be a whole"),
    ("MPC fractional steps", lambda m, I, P: control.MPC(held_problem(m).add_cost(trajopt.ControlEffort())).run(
        I, [0, 3], 5.0), ValueError, "steps must be a whole"),
    ("NaN state", lambda m, I, P: control.simulate(I, P, [np.nan, 3], 5), ValueError, "q0 must be finite"),
    ("NaN push", lambda m, I, P: control.simulate(I, P, [0, 3], 5, pushes=[control.Push(0.0, "pole", [np.nan, 0, 0])]),
     ValueError, "Push impulse must be finite"),
    ("push on no body", lambda m, I, P: control.simulate(I, P, [0, 3], 5, pushes=[control.Push(0.0, 7, [1, 0, 0])]),
     ValueError, "Push body"),
    ("plant of other sizes", lambda m, I, P: control.simulate(hovi.Integrator(models.pendulum(3), s=1, dt=0.01), P,
                                                              [0, 0, 0], 5), ValueError, "does not fit the policy"),
    ("DARE with NaN", lambda m, I, P: _core.control.discrete_are(np.full((2, 2), np.nan), np.ones((2, 1)), np.eye(2),
                                                                 np.eye(1)), ValueError, "A contains NaN"),
    ("DARE sizes", lambda m, I, P: _core.control.discrete_are(np.eye(2), np.ones((3, 1)), np.eye(2), np.eye(1)),
     ValueError, "B must be"),
    ("no stages", lambda m, I, P: _core.control.backward_riccati(np.zeros((0, 2, 2)), np.zeros((0, 2, 1)), np.eye(2),
                                                                 np.eye(1), np.eye(2)), ValueError, "at least one stage"),
    ("mass factor 0", lambda m, I, P: m.copy().scale_mass(0, 0.0), hovi.ModelError, r"factor must lie in \[1e-12, 1e12\]"),
    ("MPC period beyond the horizon", lambda m, I, P: control.MPC(held_problem(m).add_cost(trajopt.ControlEffort()),
                                                                   period=20), ValueError, "period"),
    ("MPC plant of another dt", lambda m, I, P: control.MPC(held_problem(m).add_cost(trajopt.ControlEffort())).run(
        hovi.Integrator(m, s=1, dt=0.02), [0, 3], 5), ValueError, "dt"),
    ("NaN weight", lambda m, I, P: trajopt.FDDP().solve(held_problem(m).add_cost(trajopt.StateTracking(
        [0, 3], [np.nan, 1])), trajopt.VI(1)), ValueError, "StateTracking weight must be finite"),
    ("a first step that cannot be taken", lambda m, I, P: trajopt.FDDP(max_iterations=20).solve(
        held_problem(m, qdot0=[1e6, 1e6]).add_cost(trajopt.TerminalCost([0, 0], 1e12)), trajopt.VI(1)),
     ValueError, "the step from the initial guess failed"),
    ("tvlqr without controls", lambda m, I, P: control.tvlqr(I, dataclasses.replace(I.rollout([0, 3], 5), controls=None)), ValueError, "controls u"),
])
def test_bad_input_is_named(setup, what, call, error, match):
    m, integ, policy = setup
    with pytest.raises(error, match=match):
        call(m, integ, policy)


def test_a_push_the_plant_cannot_take_ends_the_run_as_failed(setup):
    _, integ, policy = setup
    with pytest.warns(RuntimeWarning, match="ended early, at step 10 of 50"):
        run = control.simulate(integ, policy, [0, 3], 50, pushes=[control.Push(0.1, "pole", [1e12, 0, 0])])
    assert not run.converged and run.trajectory.steps == 10 and run.failure.startswith("step 10 of 50")
    assert np.all(np.isfinite(run.trajectory.q))
