"""The paper's robot examples (hovi example NAME) in their quick versions: solved, feasible by
every figure the issue names, replayed by the integrator, and written out."""
import json

import numpy as np
import pytest

from hovi.cli import main
from hovi.examples.paper import build
from hovi.examples.paper import littledog as littledog_example
from hovi.examples.paper.atlas import centre_of_mass, single_support, sole
from hovi.examples.paper.statics import static_controls
from hovi.contact.terrain import Box
from hovi.examples.paper import flamingo
from hovi.examples.paper.flamingo import JumpPlan, box_distance, leg_points, obstacle_circles
from hovi.examples.robots import atlas, littledog, spring_flamingo

pytest.importorskip("cyipopt")


def test_atlas_single_support_stance_is_balanced_at_rest():
    robot = atlas()
    q = single_support(robot)
    centre, X, Y = sole(robot, "r")
    foot = robot.model.joint_placements(q)[robot.model.body_index("r_foot")]
    where = foot[:3, :3] @ centre + foot[:3, 3]
    assert abs(where[2]) < 1e-9 and abs(foot[2, 2] - 1) < 1e-12                 # the right sole flat on the ground
    np.testing.assert_allclose(centre_of_mass(robot, q)[:2], where[:2], atol=1e-9)  # the centre of mass above it
    from hovi.contact import FlatFoot
    ff = FlatFoot(robot.model, "r_foot", centre, X, Y, mu=0.8, q0=q)
    u = static_controls(ff.model, q)
    zero = np.zeros(robot.model.n)
    qdd = ff.model.forward_dynamics(q, zero, ff.model.force_jacobians(q, zero, u)[0])
    np.testing.assert_allclose(qdd, 0, atol=1e-8)  # held at rest (round-off 1e-9 at the light wrist joints)
    w = ff.wrench(u[None])[0]
    np.testing.assert_allclose(w, [0, 0, robot.model.total_mass * 9.81, 0, 0, 0], atol=1e-6)  # the weight, at the centre


def test_atlas_reaches_the_ball_on_one_foot(tmp_path, capsys):
    pytest.importorskip("meshcat")
    assert main(["example", "atlas", "--quick", "--quiet", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "ball_distance" in out and "a step from each optimised state lands" in out
    s = json.loads((tmp_path / "atlas.json").read_text())
    assert s["success"] and s["feasible"], s["failures"]
    assert s["constraint_violation"] <= 1e-6
    assert s["ball_distance"] <= 0.01
    assert s["stance_foot_motion"] <= 1e-6 and s["wrench_cone_margin"] >= -1e-8 and s["cop_margin"] >= 0
    assert s["replay_stage_residual"] <= 1e-8                 # each stage is the integrator's step
    assert s["replay_steps_elsewhere"] == 0 and s["replay_failed_steps"] == 0   # and the one its Newton solve finds
    data = np.load(tmp_path / "atlas.npz")
    assert data["q"].shape == (build("atlas", quick=True).problem.N + 1, 36)
    assert np.all(data["contact_forces"][:-1, 2] > 0)
    for name in ("atlas.png", "atlas.html", "atlas.mp4"):
        assert (tmp_path / name).stat().st_size > 10_000


def test_flamingo_plan_puts_the_ankles_where_it_says_with_level_soles():
    robot = spring_flamingo()
    plan = JumpPlan(robot)
    t = np.linspace(0.0, 1.1, 23)
    q = plan.configurations(t)
    model = robot.model
    for qk, ankle in zip(q, plan.ankle(t)):
        for side in ("left", "right"):
            foot = model.joint_placements(qk)[model.body_index(f"{side}_foot")]
            np.testing.assert_allclose(foot[[0, 2], 3], ankle, atol=1e-12)  # inverse kinematics, checked forward
            np.testing.assert_allclose(foot[:3, :3], np.eye(3), atol=1e-12)  # the sole level
    np.testing.assert_allclose(plan.velocities(np.zeros(1))[0, 0], -0.26, atol=1e-8)
    points = leg_points(robot, q[0]).reshape(4, 25, 3)  # left sole, left shin, right sole, right shin
    np.testing.assert_allclose(points[1, [0, -1]][:, [0, 2]], [model.joint_placements(q[0])[model.body_index(b)][[0, 2], 3]
                                                               for b in ("left_lower_leg", "left_foot")], atol=1e-12)
    np.testing.assert_allclose(points[0, :, 2], 0.0, atol=1e-12)  # the sole on the ground at the start


def test_obstacle_circles_cover_the_box_and_distance_is_signed():
    box = flamingo.OBSTACLE
    x, z = np.meshgrid(np.linspace(box.x0, box.x1, 41), np.linspace(0.0, box.top, 17))
    inside = np.column_stack([x.ravel(), np.zeros(x.size), z.ravel()])
    centres = np.array(obstacle_circles(box))
    d = np.hypot(inside[:, None, 0] - centres[None, :, 0], inside[:, None, 2] - centres[None, :, 1]).min(1)
    assert d.max() < flamingo.CIRCLE_RADIUS                      # every point of the box inside a circle
    probe = np.array([[box.x0 - 0.1, 0, 0.05], [(box.x0 + box.x1) / 2, 0, box.top + 0.2], [box.x1 - 0.01, 0, 0.1]])
    np.testing.assert_allclose(box_distance(probe, box), [0.1, 0.2, -0.01], atol=1e-12)
    with pytest.raises(ValueError, match="do not cover"):
        obstacle_circles(Box(0.0, 0.1, 0.16))


def test_contact_figures_refuse_a_trajectory_without_controls_at_every_point():
    from types import SimpleNamespace
    from hovi.examples.paper.contact_figures import contact_figures
    result = SimpleNamespace(trajectory={"q": np.zeros((5, 9)), "u": np.zeros((3, 20))})
    with pytest.raises(ValueError, match="controls at every configuration point"):
        contact_figures(None, result)


def test_flamingo_jumps_the_obstacle(tmp_path, capsys):
    checkpoint = tmp_path / "homotopy.npz"
    assert main(["example", "flamingo", "--quick", "--quiet", "--no-animate", "--output", str(tmp_path),
                 "--checkpoint", str(checkpoint)]) == 0
    assert not checkpoint.exists()                      # written after each relaxed solve, removed when finished
    s = json.loads((tmp_path / "flamingo.json").read_text())
    assert s["success"] and s["feasible"], s["failures"]
    assert s["constraint_violation"] <= 1e-6 and s["exact_solve"] == 1.0
    assert s["complementarity"] <= 1e-6 and s["normal_complementarity"] <= 1e-6 and s["penetration"] <= 1e-6
    assert s["obstacle_clearance"] >= 0 and s["feet_beyond_obstacle"] >= 0   # over the box all along, both feet past it
    assert s["replay_stage_residual"] <= 1e-6   # each stage is the integrator's step, to IPOPT's constr_viol_tol 1e-8
    # stepped from its own start, Newton may find another root of the quick problem's DEL equations
    # (dt = 0.1 s, joints turning up to 1.7 rad a stage): counted in replay_steps_elsewhere; none may fail
    assert s["replay_failed_steps"] == 0
    forces = np.load(tmp_path / "flamingo.npz")["contact_forces"]
    assert np.any(forces[:-1].sum(1) == 0)                                   # a flight phase: no contact force


def test_unknown_example_is_refused():
    with pytest.raises(ValueError, match="unknown example 'flamingo2'"):
        build("flamingo2")


def test_littledog_standing_pose_and_trot_guess():
    robot = littledog()
    course = littledog_example.QUICK
    q0 = littledog_example.standing_pose(robot)
    np.testing.assert_allclose(littledog_example.feet_at(robot, q0)[:, 2], robot.contact_radius, atol=1e-12)
    terrain = littledog_example.terrain(robot, course)
    gait = littledog_example.Gait(robot, course, q0, terrain)
    landings = np.array([x for steps in gait.steps for _, _, x in steps])
    assert littledog_example.gap_margin(terrain, landings).min() >= course.margin - 1e-12  # footholds off the gaps
    t = np.linspace(0.0, course.T, 13)
    q = [q0]
    for tk in t[1:]:
        q.append(gait.configuration(tk, q[-1]))
    feet = np.array([littledog_example.feet_at(robot, qk) for qk in q])
    down = np.array([gait.on_ground(tk) for tk in t])
    np.testing.assert_allclose(feet[down][:, 2], robot.contact_radius, atol=1e-9)   # the stance feet on the ground
    assert np.all(feet[~down][:, 2] >= robot.contact_radius - 1e-12)
    assert q[-1][0] == pytest.approx(course.distance)
    with pytest.raises(ValueError, match="cannot reach"):
        littledog_example.place_feet(robot, q0[:6], feet[0] + [0.3, 0, 0], q0)


def test_littledog_mouth_clearance_measures_the_spheres_against_the_gap_edges():
    from hovi.contact import Gap, Terrain
    r = 0.01
    terrain = Terrain(ground=r, gaps=[Gap(0.0, 0.04, 0.5)])                      # the surface at z = 0
    clearance = littledog_example.mouth_clearance
    assert clearance(terrain, r, np.array([[-0.1, 0, r], [0.2, 0, 0.0]])) == np.inf           # none over the gap
    assert clearance(terrain, r, np.array([[0.02, 0, 0.05]])) == pytest.approx(np.hypot(0.02, 0.05) - r)
    assert clearance(terrain, r, np.array([[0.035, 0, r]])) == pytest.approx(np.hypot(0.005, r) - r)
    assert clearance(terrain, r, np.array([[0.004, 0, -0.02], [0.02, 0, 0.05]])) == pytest.approx(0.004 - r)


def test_littledog_walks_over_a_gap(tmp_path, capsys):
    pytest.importorskip("meshcat")
    assert main(["example", "littledog", "--quick", "--quiet", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "foothold_gap_margin" in out
    s = json.loads((tmp_path / "littledog.json").read_text())
    assert s["success"] and s["feasible"], s["failures"]
    assert s["exact_solve"] == 1.0 and s["constraint_violation"] <= 1e-6
    assert s["complementarity"] <= 1e-6 and s["penetration"] <= 1e-6 and s["normal_complementarity"] <= 1e-6
    assert s["past_last_gap"] >= 0 and s["foothold_gap_margin"] >= 0
    assert s["edge_clearance"] >= 0                           # no foot clips a gap's edge between the points
    assert s["average_speed"] >= littledog_example.SPEED - 1e-6
    assert s["replay_stage_residual"] <= 1e-8                 # each stage is the integrator's step
    assert s["replay_steps_elsewhere"] == 0 and s["replay_failed_steps"] == 0   # and the one its Newton solve finds
    data = np.load(tmp_path / "littledog.npz")
    assert data["q"].shape == (littledog_example.QUICK.N + 1, 18)
    assert data["contact_forces"].shape == (littledog_example.QUICK.N + 1, 4)
    assert np.all(data["contact_forces"] >= 0)
    assert np.any(data["contact_forces"][:-1] == 0)                          # feet lifted: no force on them
    for name in ("littledog.png", "littledog.html", "littledog.mp4"):
        assert (tmp_path / name).stat().st_size > 10_000


@pytest.mark.parametrize("make", ["pendulum", "slider_crank"])
def test_replay_figures_measure_how_far_the_stages_are_from_integrator_steps(make):
    import dataclasses
    from types import SimpleNamespace
    from hovi import trajopt
    from hovi.examples.paper.report import replay_figures
    from hovi.examples import swingups as examples
    prob = examples.EXAMPLES[make](N=10) if make == "pendulum" else examples.slider_crank_to_target(N=10)
    r = trajopt.solve(prob, trajopt.VI(s=2), verbose=False)
    example = SimpleNamespace(problem=prob)
    f = replay_figures(example, r)
    assert f["replay_stage_residual"] <= 1e-9 and f["replay_one_step_drift"] <= 1e-8
    assert f["replay_steps_elsewhere"] == 0 and f["replay_failed_steps"] == 0
    tc = r.transcription
    x = r.x.copy()
    x[tc.p_off + 5 * prob.model.n] += 1e-3                  # p^5 off by 1e-3: stages 4 and 5 are no steps
    bad = replay_figures(example, dataclasses.replace(r, x=x, trajectory=tc.trajectory(x)))
    assert 1e-4 <= bad["replay_stage_residual"] <= 1e-2
    assert bad["replay_one_step_drift"] >= 1e-6 and bad["replay_steps_elsewhere"] >= 1
