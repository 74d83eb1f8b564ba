"""The paper's robot examples (hovi example NAME) in their quick versions: solved, feasible by
every figure the issue names, replayed by the integrator, and written out."""
import json

import numpy as np
import pytest

from hovi.cli import main
from hovi.examples.paper import build
from hovi.examples.paper import littledog as littledog_example
from hovi.examples.paper.atlas import centre_of_mass, single_support, sole
from hovi.control import static_controls
from hovi.contact.terrain import Box
from hovi.examples.paper import flamingo
from hovi.examples.paper.flamingo import JumpPlan, box_distance, leg_points, obstacle_circles
from hovi.examples.robots import atlas, littledog, spring_flamingo



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
    u = static_controls(ff.with_inputs, q)
    zero = np.zeros(robot.model.n)
    qdd = ff.with_inputs.forward_dynamics(q, zero, ff.with_inputs.force_jacobians(q, zero, u)[0])
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
    assert "replay: 6 of 6 stages reproduced" in out
    assert s["between_knot_penetration"] <= 1e-3 and s["between_knot_contact"].startswith(("l_", "r_"))
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


@pytest.fixture(scope="module")
def flamingo_run(tmp_path_factory):
    """The quick Spring Flamingo solved once through the command line: (output directory, stdout, exit code)."""
    import contextlib
    import io
    out = tmp_path_factory.mktemp("flamingo")
    checkpoint = out / "homotopy.npz"
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        code = main(["example", "spring_flamingo", "--quick", "--quiet", "--no-animate", "--no-progress", "--output", str(out),
                     "--checkpoint", str(checkpoint)])
    return out, text.getvalue(), code


def test_flamingo_jumps_the_obstacle(flamingo_run):
    tmp_path, out, code = flamingo_run
    assert code == 0, out
    assert not (tmp_path / "homotopy.npz").exists()     # written after each relaxed solve, removed when finished
    s = json.loads((tmp_path / "spring_flamingo.json").read_text())
    assert s["success"] and s["feasible"], s["failures"]
    assert s["constraint_violation"] <= 1e-6 and s["exact_solve"] == 1.0
    assert s["complementarity"] <= 1e-6 and s["normal_complementarity"] <= 1e-6 and s["penetration"] <= 1e-6
    assert s["obstacle_clearance"] >= 0 and s["feet_beyond_obstacle"] >= 0   # over the box all along, both feet past it
    assert s["replay_stage_residual"] <= 1e-6   # each stage is the integrator's step, to IPOPT's constr_viol_tol 1e-8
    # and the step the integrator's Newton solve finds from its own start: every stage reproduced
    assert s["replay_failed_steps"] == 0 and s["replay_steps_elsewhere"] == 0
    assert s["replay_stages_reproduced"] == s["replay_stages"] == 22
    assert "replay: 22 of 22 stages reproduced" in out
    assert s["between_knot_penetration"] <= 1e-3                # the feet stay above the ground between the knots
    assert "between the configuration points:" in out
    forces = np.load(tmp_path / "spring_flamingo.npz")["contact_forces"]
    assert np.any(forces[:-1].sum(1) == 0)                                   # a flight phase: no contact force


def test_between_knot_penetration_matches_a_dense_evaluation_of_the_solution(flamingo_run):
    """The figure of the quick Spring Flamingo's solution against the contact points evaluated on its
    trapezoidal VI's polynomial (linear in q between the points, s = 1) at 2000 times a stage."""
    from hovi import _core
    tmp_path, _, _ = flamingo_run
    s = json.loads((tmp_path / "spring_flamingo.json").read_text())
    data = np.load(tmp_path / "spring_flamingo.npz")
    t, q = data["t"], data["q"]
    tau = np.linspace(0.0, 1.0, 2001)[1:-1]
    dense_t = (t[:-1, None] + tau[None, :] * np.diff(t)[:, None]).ravel()
    dense_q = (q[:-1, None, :] * (1 - tau)[None, :, None] + q[1:, None, :] * tau[None, :, None]).reshape(-1, q.shape[1])
    robot = spring_flamingo()
    X, _ = _core.body_point_kinematics(robot.model, dense_q, [robot.model.body_index(c.body) for c in robot.contacts],
                                       np.array([c.point for c in robot.contacts]))
    z = X[..., 2]                                                            # the ground at z = 0
    k, c = np.unravel_index(np.argmin(z), z.shape)
    assert s["between_knot_penetration"] == pytest.approx(max(0.0, -z[k, c]), abs=1e-4)  # 19+ samples a stage: 0.1 mm
    if z[k, c] < -1e-5:                                                                  # the same dip, if any
        assert s["between_knot_contact"] == robot.contacts[c].name
        assert s["between_knot_time"] == pytest.approx(dense_t[k], abs=0.006)


def test_between_knot_penetration_sees_a_dip_that_the_points_do_not():
    """A trajectory whose points are all on the ground and whose polynomial dips between them (a
    foot swung through the ground): found, measured and placed (contact, time) as a dense sampling
    of the same polynomial finds it; bounded by BETWEEN_TOLERANCE in the example's bounds."""
    from hovi import trajopt
    from hovi.examples.paper.contact_figures import (BETWEEN_TOLERANCE, CONTACT_BOUNDS, between_knot_penetration,
                                                     contact_gaps)
    from hovi.contact import Contacts, Terrain
    robot = spring_flamingo()
    contacts = Contacts(robot.model, robot.contact_points, Terrain(), mu=0.8, plane="xz")
    prob = trajopt.Problem(contacts.with_inputs, N=4, T=0.4)
    q0 = JumpPlan(robot).configurations(0.0)[0]                   # both soles level on the ground
    prob.initial_state(q0)
    prob.add_cost(trajopt.ControlEffort())
    for method in (trajopt.VI(s=1), trajopt.VI(s=2)):
        tc = method.transcribe(prob)
        x = tc.initial_guess((lambda t: np.tile(q0, (len(t), 1)), lambda t: np.zeros((len(t), prob.model.n)),
                              lambda t: np.zeros((len(t), prob.model.n_controls))))
        r = tc.at(x, "guess", False)
        P = len(r.trajectory["q"])
        assert P == 4 * method.s + 1
        # the whole robot pitched by +-0.3 rad at alternate points and lowered there until its lowest
        # contact point touches the ground: on the ground at every configuration point, while the
        # pitch passing through 0 between them swings the soles through it
        gaps = contact_gaps(contacts)
        q = np.tile(q0, (P, 1))
        q[:, 2] = 0.3 * (-1.0) ** np.arange(P)
        q[:, 1] -= gaps(q).min(1)
        assert np.abs(gaps(q).min(1)).max() < 1e-12
        x = x.copy()
        x[tc.q_off:tc.q_off + q.size] = q.ravel()
        r = tc.at(x, "guess", False)
        f = between_knot_penetration(r, gaps, [c.name for c in robot.contacts])
        dense = np.linspace(0.0, prob.T, 40001)
        phi = gaps(tc.interpolants(x)[0](dense))                    # the transcription's interpolant, densely
        k, c = np.unravel_index(np.argmin(phi), phi.shape)
        assert -phi[k, c] > 0.01                                    # a dip of centimetres
        assert f["between_knot_penetration"] == pytest.approx(-phi[k, c], rel=0.01)
        assert f["between_knot_contact"][2:] == robot.contacts[c].name[2:]   # a toe or a heel (either side: the same)
        assert np.abs(r.trajectory["t"] - f["between_knot_time"]).min() > 1e-3    # between the points
    assert CONTACT_BOUNDS["between_knot_penetration"] == ("<=", BETWEEN_TOLERANCE) and BETWEEN_TOLERANCE == 1e-3


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
    terrain = Terrain(gaps=[Gap(0.0, 0.04, 0.5)])                                 # the surface at z = 0
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
    # the warm-up (feet half a radius below the ground between the points) first, then the walk on its sides
    assert [e for e, _, ok in s["contact_solves"] if ok] == [1e-3, 0.0, 0.0]
    assert s["complementarity"] <= 1e-6 and s["penetration"] <= 1e-6 and s["normal_complementarity"] <= 1e-6
    assert s["past_last_gap"] >= 0 and s["foothold_gap_margin"] >= 0
    assert s["edge_clearance"] >= 0                           # no foot clips a gap's edge between the points
    assert s["average_speed"] >= littledog_example.SPEED - 1e-6
    assert s["replay_stage_residual"] <= 1e-8                 # each stage is the integrator's step
    assert s["replay_steps_elsewhere"] == 0 and s["replay_failed_steps"] == 0   # and the one its Newton solve finds
    assert f"replay: {littledog_example.QUICK.N} of {littledog_example.QUICK.N} stages reproduced" in out
    assert s["between_knot_penetration"] <= 1e-3            # the feet above the ground between the points too
    data = np.load(tmp_path / "littledog.npz")
    assert data["q"].shape == (littledog_example.QUICK.N + 1, 18)
    assert data["contact_forces"].shape == (littledog_example.QUICK.N + 1, 4)
    assert np.all(data["contact_forces"] >= 0)
    assert np.any(data["contact_forces"][:-1] == 0)                          # feet lifted: no force on them
    for name in ("littledog.png", "littledog.html", "littledog.mp4"):
        assert (tmp_path / name).stat().st_size > 10_000


def test_littledog_holds_only_its_reported_vi_solve_to_the_replay_options(monkeypatch):
    """report.solve: the reported VI solve gets ``replay_options`` (constraints to 1e-10); the solves
    that only start another (the warm-up, the trapezoidal VI before VI s = 2 or Hermite-Simpson) and
    Hermite-Simpson itself keep the example's 1e-8."""
    from types import SimpleNamespace
    from hovi.examples.paper import report
    tolerances = []

    def solve_contact(problem, method, options=None, **kwargs):
        tolerances.append(options["constr_viol_tol"])
        return SimpleNamespace(contact={"iterations": 1, "wall_seconds": 0.0, "solves": [(0.0, 1, True)]})

    monkeypatch.setattr(report.trajopt, "solve_contact", solve_contact)
    example = littledog_example.build(quick=True)
    for method, s, expected in [("vi", 1, [1e-8, 1e-10]), ("vi", 2, [1e-8, 1e-8, 1e-10]),
                                ("hs-implicit", 2, [1e-8, 1e-8, 1e-8])]:
        tolerances.clear()
        r = report.solve(example, method, s)
        assert tolerances == expected, (method, s, tolerances)
        assert r.contact["iterations"] == len(expected)


def test_atlas_higher_orders_start_from_the_trapezoidal_solution(monkeypatch):
    """report.solve without contacts (Atlas, from_trapezoidal): VI s = 2 and Hermite-Simpson start from
    the trapezoidal VI's solution (its interpolants), which is reported as their continuation's first
    stage and counted in the totals; the trapezoidal VI starts from the example's guess; a failed
    first stage leaves the example's guess: the order continuation of trajopt.Ipopt (its second stage,
    Ipopt.continue_from), the NLP solves replaced by a record of their transcription and guess."""
    from types import SimpleNamespace
    from hovi.examples.paper import atlas, report
    from hovi.trajopt import VI, NLPSolver
    calls, first_success = [], [True]

    def solve(solver, problem, method, guess=None):
        calls.append((method, guess))
        ok = first_success[0] if method == VI(1) else True
        return SimpleNamespace(success=ok, iterations=10 * len(calls), cost=1.0, wall_seconds=0.5, solver={},
                               timing={"setup": 0.0}, contact={},
                               transcription=SimpleNamespace(method=method), as_guess=lambda: "first's interpolants")

    monkeypatch.setattr(NLPSolver, "solve", solve)
    example = atlas.build(quick=True)
    report.solve(example, "vi", 1)
    assert calls == [(VI(1), example.guess)]
    for method, s in [("vi", 2), ("hs-implicit", 2)]:
        calls.clear()
        r = report.solve(example, method, s)
        assert [m for m, _ in calls] == [VI(1), report.from_name(method, s)]
        assert calls[0][1] is example.guess and calls[1][1] == "first's interpolants"
        assert r.solver["continuation"]["iterations"] == 10 and r.solver["continuation"]["used"]
        assert report.ipopt_totals(r)[0] == 10 + 20
    calls.clear()
    first_success[0] = False
    r = report.solve(example, "hs-implicit", 2)
    assert calls[1][1] is example.guess and not r.solver["continuation"]["used"]


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


def test_replay_verdict_calls_a_solution_with_one_unreproduced_stage_infeasible():
    """report.check: the replay is part of the verdict. A solution whose stages the integrator
    reproduces passes; the same solution doctored at one stage (its momentum off) is infeasible,
    and the report says which stage, which coordinate and by how much, with units."""
    import dataclasses
    from types import SimpleNamespace
    from hovi import trajopt
    from hovi.examples import swingups as examples
    from hovi.examples.paper import report
    prob = examples.EXAMPLES["pendulum"](N=10)
    r = trajopt.solve(prob, trajopt.VI(s=1), verbose=False)
    example = SimpleNamespace(problem=prob, checks=lambda result: {}, failures=lambda figures: [])
    figures, replay, failures = report.check(example, r)
    assert r.success and failures == [], failures
    assert replay["replay_stages_reproduced"] == replay["replay_stages"] == 10
    assert report.replay_text(replay).startswith("replay: 10 of 10 stages reproduced to ")
    tc = r.transcription
    x = r.x.copy()
    x[tc.p_off + 7 * prob.model.n] += 0.05                    # p^7 off: stage 7 (from q^7, p^7) lands elsewhere
    bad = dataclasses.replace(r, x=x, trajectory=tc.trajectory(x))
    _, replay, failures = report.check(example, bad)
    assert replay["replay_steps_elsewhere"] >= 1 and 8 in replay["replay_elsewhere_stages"]
    assert len(failures) == 1 and failures[0].startswith("replay: ") and "not reproduced" in failures[0]
    text = report.replay_text(replay)
    assert "of 10 stages reproduced" in text and f"stage {replay['replay_worst_stage']} converged to another point" in text
    assert f"{prob.model.joint_names[0]} differs by" in text and text.count(" rad") >= 1
    assert report.replay_failures(replay) == failures
