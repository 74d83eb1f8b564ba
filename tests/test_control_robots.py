"""The paper's Atlas example (quick) in closed loop in the contact simulator
(hovi.examples.paper.tracking): time-varying LQR on its torques tracks the optimised motion
exactly from the optimised state, and still reaches the ball on one foot after a push and with
every mass 10% off, where the open loop fails. The Spring Flamingo and LittleDog cases take minutes
to solve: bench/control_robots.py."""
import dataclasses

import numpy as np
import pytest

from hovi import control
from hovi.control import Push
from hovi.examples.paper import build, report

from hovi.examples.paper import tracking as CL



@pytest.fixture(scope="module")
def atlas():
    example = build("atlas", quick=True)
    result = report.solve(example)
    assert result.success
    return example, result, CL.controller(example, result)


def test_the_policy_state_is_the_step_momentum_and_holds_the_nominal(atlas):
    """The references are the replay's configurations with each step's own momentum (before its knot's
    impulse: what the C++ loop's policy sees), the recorded momenta less half the knot impulse; on the
    closed loop's own states the policy gives the optimised torques (no feedback on the nominal)."""
    example, result, ctl = atlas
    integ = CL.simulator(example)
    motion, nom = ctl.motion, ctl.nominal
    assert nom.kind == "replay"
    replay = integ.rollout(motion.q[0], motion.steps, qdot0=example.problem.qdot0, u=nom.U)
    K = motion.steps
    p = replay.p.copy()
    p[1:K] -= 0.5 * CL.knot_impulses(integ, replay.q[1:K], replay.contact.impulses[1:K])
    scale = np.abs(replay.p).max()                                # ~43 N m s: Atlas's knot impulses are large
    assert np.abs(replay.p - nom.p)[1:K].max() > 1.0              # the two conventions differ by the impulse
    np.testing.assert_allclose(p, nom.p, atol=1e-12 * scale)
    run = control.simulate(integ, ctl.policy, motion.q[0], K, qdot0=example.problem.qdot0)
    state = run.trajectory.contact.step_momenta
    for k in range(K):
        np.testing.assert_allclose(ctl.policy.control(k, run.trajectory.q[k], state[k]), run.u[k], atol=1e-9)
    np.testing.assert_allclose(run.u, nom.U, atol=1e-8)           # the optimised torques: feedback ~0


def test_closed_loop_from_the_optimised_state_tracks_it(atlas):
    example, result, ctl = atlas
    fig = CL.closed_loop_figures(example, result, control=ctl)
    for loop in ("closed_loop", "open_loop"):
        run = fig[loop]
        assert run["success"] and run["failure"] is None, run["failures"]
        assert run["steps"] == run["of_steps"] == example.problem.N
        assert run["max_tracking_error"] <= 1e-8                   # measured 4.0e-11: the nominal is exact
        assert run["ball_distance"] <= 1e-8                        # 1.7e-13
        assert run["stance_foot_motion"] <= 1e-12                  # 1.9e-15: the sole held by the contact
        assert not run["left_foot_loaded"] and run["left_sole_height_min"] >= 0.02
        assert run["penetration"] <= 1e-4                          # 4.9e-5, on the stance sole's path between knots
        assert run["saturated_fraction"] == 0.0
    assert fig["nominal"]["replay_max_deviation"] <= 1e-8


def test_a_push_breaks_the_open_loop_and_not_the_closed_loop(atlas):
    example, result, ctl = atlas
    push = CL.default_push(example)
    assert np.linalg.norm(push.impulse) == 20.0 and push.body == "pelvis"
    fig = CL.closed_loop_figures(example, result, control=ctl, push=push)
    closed, opened = fig["closed_loop"], fig["open_loop"]
    # open loop: the stance sole tips (3.0 cm), a corner dips 3.4 cm below the ground between the knots
    # and the contact step fails at t = 0.25 s, 1.3 rad from the optimised motion
    assert not opened["success"]
    assert opened["steps"] < opened["of_steps"] and opened["max_tracking_error"] > 0.5
    assert opened["stance_foot_motion"] > 0.01
    # closed loop: the hand 7.0e-5 m from the ball (the goal: 0.01), on one foot, 0.043 rad at most from
    # the optimised motion (r_leg_hpy) and 0.015 at the end
    assert closed["success"], closed["failures"]
    assert closed["ball_distance"] <= 2e-4
    assert closed["max_tracking_error"] <= 0.06 and closed["final_tracking_error"] <= 0.025
    assert closed["stance_foot_motion"] <= 1e-12 and not closed["left_foot_loaded"]
    assert closed["penetration"] <= 1e-4 and closed["saturated_fraction"] == 0.0
    text = CL.closed_loop_text(fig)
    assert "closed loop succeeds" in text and "open loop fails" in text and "20 N s on pelvis" in text


def test_a_ten_percent_mass_error_with_and_without_the_push(atlas):
    example, result, ctl = atlas
    heavy = CL.closed_loop_figures(example, result, control=ctl, mass_factor=1.1)
    both = CL.closed_loop_figures(example, result, control=ctl, mass_factor=1.1, push=CL.default_push(example))
    for fig, ball, final in ((heavy, 1.48e-3, 0.058), (both, 1.31e-3, 0.042)):   # measured
        closed, opened = fig["closed_loop"], fig["open_loop"]
        assert closed["success"], closed["failures"]
        assert closed["ball_distance"] <= 1.5 * ball
        # the knee sags under the 10% heavier robot (r_leg_kny): proportional feedback, no integral action
        assert closed["final_tracking_error"] <= 1.5 * final and closed["max_tracking_error"] <= 0.1
        assert not opened["success"] and opened["steps"] < opened["of_steps"]    # the contact step fails at 0.25 s
        assert opened["max_tracking_error"] > 0.5
    assert heavy["mass_factor"] == 1.1


def test_the_plant_scales_every_mass_and_keeps_the_contacts():
    example = build("atlas", quick=True)
    plant = CL.simulator(example, 1.1)
    assert plant.model.total_mass == pytest.approx(1.1 * example.robot.model.total_mass, rel=1e-12)
    assert example.robot.model.total_mass == pytest.approx(174.0503, rel=1e-9)        # the example's own unchanged
    assert plant.contacts is example.simulation


def test_atlas_has_no_knot_impulses_of_point_contacts(atlas):
    """Atlas's optimiser holds the stance foot by a wrench (FlatFoot), not the simulator's point contacts:
    its knots cannot be linearised with the optimiser's impulses (its replay is the nominal)."""
    example, result, ctl = atlas
    with pytest.raises(ValueError, match="point contacts"):
        CL.nominal(example, ctl.motion, kind="knots")


def test_open_loop_is_the_policy_without_feedback(atlas):
    _, _, ctl = atlas
    ol = ctl.policy.without_feedback()
    assert np.all(ol.gains == 0) and np.array_equal(ol.u_ref, ctl.policy.u_ref)
    assert np.array_equal(ol.lower, ctl.policy.lower) and np.any(ctl.policy.gains != 0)
    assert dataclasses.asdict(CL.WEIGHTS["atlas"])["task"] > 0
    assert isinstance(CL.PUSHES["spring_flamingo"], Push)
