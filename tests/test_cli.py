"""The command line: hovi simulate / optimize / info."""
import json
import subprocess
import sys

import pytest

from hovi.cli import main


def test_simulate_writes_summary_and_plots(tmp_path, capsys):
    assert main(["simulate", "pendulum:4", "--duration", "0.5", "--dt", "0.01", "--no-progress",
                 "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "steps/s" in out and "Newton iterations per step" in out and "energy" in out
    summary = json.loads((tmp_path / "simulate.json").read_text())
    assert summary["steps"] == 50 and summary["converged"] and summary["dof"] == 4
    assert summary["energy_error_max_relative"] < 1e-4
    assert (tmp_path / "energy_error.png").stat().st_size > 1000
    assert (tmp_path / "final_configuration.png").stat().st_size > 1000


def test_simulate_urdf(tmp_path):
    from conftest import erd_urdf
    path = erd_urdf("panda_description/urdf/panda.urdf")
    assert main(["simulate", path, "--duration", "0.1", "--no-progress", "--no-plot", "--output", str(tmp_path)]) == 0


def test_simulate_animate_writes_html_and_video(tmp_path, capsys):
    pytest.importorskip("hovi.vis.viewer", reason="hovi[viewer] is not installed")
    import imageio.v3 as iio
    assert main(["simulate", "pendulum:3", "--duration", "0.5",
                 "--no-progress", "--no-plot", "--animate", "--fps", "10", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert f"wrote {tmp_path / 'animation.html'}" in out and f"wrote {tmp_path / 'animation.mp4'}" in out
    assert "MeshCat.Viewer" in (tmp_path / "animation.html").read_text()
    assert iio.imread(tmp_path / "animation.mp4", index=None).shape[0] == 6  # 0.5 s at 10 frames per second


def test_help_explains_every_option():
    out = subprocess.run([sys.executable, "-m", "hovi", "simulate", "--help"], capture_output=True, text=True).stdout
    for opt in (" -s S", "--dt", "--duration", "--spread", "--tol", "--output", "--no-plot", "--base", "--seed",
                "--animate", "--fps", "--package-dir", "--ground", "--no-ground", "--contact", "--mu", "--drop",
                "--ground-height"):
        assert opt in out


def test_bad_arguments_exit_with_usage_error():
    with pytest.raises(SystemExit):
        main(["simulate", "pendulum:3", "--dt", "-1"])
    with pytest.raises(SystemExit):
        main(["nonsense"])
    with pytest.raises(SystemExit):
        main(["simulate", "pendulum:3", "--animate", "--fps", "0"])


def test_bad_model_or_option_is_a_clean_error(capsys):
    assert main(["simulate", "/nonexistent.urdf", "--no-progress"]) == 2
    assert "model file '/nonexistent.urdf' not found" in capsys.readouterr().err
    assert main(["simulate", "pendulum:3", "-s", "17", "--no-progress"]) == 2
    assert "between 1 and 16" in capsys.readouterr().err


def test_optimize_solves_writes_and_replays(tmp_path, capsys):
    assert main(["optimize", "pendulum", "--N", "20", "--quiet", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "cost" in out and "replayed with the integrator" in out
    summary = json.loads((tmp_path / "optimize_pendulum.json").read_text())
    assert summary["success"] and summary["N"] == 20 and summary["replay_max_error"] < 1e-8
    assert (tmp_path / "optimize_pendulum.png").stat().st_size > 1000
    help_text = subprocess.run([sys.executable, "-m", "hovi", "optimize", "--help"], capture_output=True, text=True).stdout
    for opt in ("--transcription", " -s S", "--N", "--T", "--controls", "--max-iter", "--output"):
        assert opt in help_text
    with pytest.raises(SystemExit):
        main(["optimize", "pendulum", "-s", "0"])


def test_the_commands_list_every_example_of_the_registry(capsys):
    from hovi import examples
    from hovi.examples.swingups import EXAMPLES
    assert set(examples.names("optimization")) == set(EXAMPLES)
    for command, kinds in (("optimize", ["optimization"]), ("example", ["robot_example"]),
                           ("simulate", ["model", "robot"]), ("info", ["model", "robot"])):
        with pytest.raises(SystemExit):
            main([command, "--help"])
        text = " ".join(capsys.readouterr().out.split())
        for kind in kinds:
            for name in examples.names(kind):
                assert name in text, (command, name)


def test_simulate_and_info_take_the_registry_names(capsys, tmp_path):
    assert main(["info", "acrobot"]) == 0 and "random state" in capsys.readouterr().out
    assert main(["info", "littledog"]) == 0 and "18" in capsys.readouterr().out
    assert main(["simulate", "cartpole", "--duration", "0.05", "--no-progress", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    assert json.loads((tmp_path / "simulate.json").read_text())["dof"] == 2


URDF_2DOF = """<robot name="arm">
  <link name="a"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="c"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 1 0"/></joint>
  <joint name="j2" type="continuous"><parent link="b"/><child link="c"/><origin xyz="0 0 -1"/><axis xyz="0 1 0"/></joint>
</robot>
"""


def test_a_file_named_like_the_pendulum_is_a_file(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "pendulum_arm.urdf").write_text(URDF_2DOF)
    assert main(["info", "pendulum_arm.urdf"]) == 0
    assert capsys.readouterr().out.startswith("hovi.Model: 2 DoF")
    assert main(["info", "pendulum"]) == 0 and "32 DoF" in capsys.readouterr().out
    assert main(["info", "pendulum:5"]) == 0 and "5 DoF" in capsys.readouterr().out
    for name in ("acrobot", "cartpole", "fourbar", "slider_crank", "spring_flamingo"):
        assert main(["info", name]) == 0, name
        capsys.readouterr()


@pytest.mark.parametrize("spec, says", [
    ("pendulum5", "unknown model 'pendulum5'"),
    ("pendulum_arm.urdf", "model file 'pendulum_arm.urdf' not found"),
    ("Acrobot", "unknown model 'Acrobot'"),
    ("pendulum:abc", "N in 'pendulum:N' must be a whole number of links >= 1, got 'abc'"),
    ("pendulum:0", "got '0'"),
    ("pendulum:-2", "got '-2'"),
])
def test_a_bad_model_name_says_what_is_accepted(spec, says, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    for command in ("info", "simulate"):
        assert main([command, spec, "--no-progress"] if command == "simulate" else [command, spec]) == 2
        err = capsys.readouterr().err
        assert says in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
        if "unknown" in says or "not found" in says:
            assert "'pendulum:N'" in err and "cartpole" in err and "atlas" in err and "URDF" in err


def test_a_bad_model_file_says_what_is_wrong(tmp_path, capsys):
    cases = {
        "folder": (None, "is a directory, not a URDF file"),
        "humanoid.xml": ('<mujoco model="h">\n  <worldbody/>\n</mujoco>\n', "MJCF (MuJoCo) file, root element <mujoco>"),
        "broken.urdf": ('<robot name="r">\n  <link name="a">\n</robot>\n', "not well-formed XML at line 3"),
        "sdf.urdf": ('<sdf version="1.6"><model name="m"/></sdf>', "root element <sdf>; hovi reads URDF files"),
        "nolimits.urdf": ('<robot name="r"><link name="a"/><link name="b"/><joint name="j" type="revolute">'
                          '<parent link="a"/><child link="b"/></joint></robot>', "does not specify limits"),
    }
    for name, (text, says) in cases.items():
        path = tmp_path / name
        if text is None:
            path.mkdir()
        else:
            path.write_text(text)
        assert main(["info", str(path)]) == 2, name
        err = capsys.readouterr().err
        assert says in err, (name, err)
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_version(capsys):
    import hovi
    with pytest.raises(SystemExit) as e:
        main(["--version"])
    assert e.value.code == 0 and capsys.readouterr().out.strip() == f"hovi {hovi.__version__}"


@pytest.mark.parametrize("argv, says", [
    (["simulate", "--dt", "0"], "argument --dt: must be a finite number > 0, got '0'"),
    (["simulate", "--dt", "-0.01"], "argument --dt: must be a finite number > 0"),
    (["simulate", "--dt", "nan"], "argument --dt: must be a finite number > 0, got 'nan'"),
    (["simulate", "--dt", "abc"], "argument --dt: 'abc' is not a number"),
    (["simulate", "--duration", "inf"], "argument --duration: must be a finite number > 0, got 'inf'"),
    (["simulate", "--duration", "nan"], "argument --duration: must be a finite number > 0"),
    (["simulate", "--seed", "-1"], "argument --seed: must be a whole number >= 0, got '-1'"),
    (["info", "--seed", "1.5"], "argument --seed: '1.5' is not a whole number"),
    (["simulate", "--fps", "0"], "argument --fps: must be a finite number > 0"),
    (["simulate", "--tol", "-1"], "argument --tol: must be a finite number >= 0"),
    (["optimize", "pendulum", "--max-iter", "-5"], "argument --max-iter: must be a whole number >= 1, got '-5'"),
    (["optimize", "pendulum", "--N", "0"], "argument --N: must be a whole number >= 1, got '0'"),
    (["optimize", "pendulum", "--T", "-1"], "argument --T: must be a finite number > 0, got '-1'"),
    (["optimize", "pendulum", "--T", "0"], "argument --T: must be a finite number > 0, got '0'"),
    (["optimize", "pendulum", "-s", "0"], "argument -s: must be a whole number >= 1, got '0'"),
    (["simulate", "--mu", "-0.5"], "argument --mu: must be a finite number >= 0, got '-0.5'"),
    (["simulate", "--mu", "high"], "argument --mu: 'high' is not a number"),
    (["simulate", "--mu", "2e3"], "argument --mu: must be a friction coefficient from 0 to 1000"),
    (["simulate", "--drop", "-0.1"], "argument --drop: must be a finite number >= 0"),
    (["simulate", "--ground-height", "inf"], "argument --ground-height: must be a finite number, got 'inf'"),
    (["simulate", "--contact", "foot:0,0"], "argument --contact: 'foot:0,0' is not LINK:x,y,z"),
    (["simulate", "--contact", "foot:0,0,x"], "argument --contact: 'foot:0,0,x' is not LINK:x,y,z"),
    (["simulate", "--contact", ":0,0,0"], "argument --contact: ':0,0,0' is not LINK:x,y,z"),
    (["simulate", "--contact", "foot:0,nan,0"], "argument --contact: 'foot:0,nan,0': the point must be 3 finite"),
    (["simulate", "littledog", "--ground", "--no-ground"], "argument --no-ground: not allowed with argument --ground"),
])
def test_bad_numbers_are_refused_naming_the_flag(argv, says, capsys):
    with pytest.raises(SystemExit) as e:
        main(argv)
    err = capsys.readouterr().err
    assert e.value.code == 2 and says in err and "Traceback" not in err


def test_the_speed_figure_is_the_integrators_own_time(tmp_path, capsys):
    assert main(["simulate", "pendulum:3", "--duration", "0.5", "--no-plot", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "simulate.json").read_text())
    assert 0 < summary["solve_seconds"] <= summary["wall_time_s"]
    assert summary["steps_per_second"] == pytest.approx(summary["steps"] / summary["solve_seconds"])
    assert "s in the integrator" in out and "wall with the progress bar" in out


def test_a_floating_base_is_said_to_free_fall(tmp_path, capsys):
    """Without the ground (--no-ground for the robots, which stand on it by default): the note, the free fall."""
    assert main(["simulate", "littledog", "--no-ground", "--duration", "0.05", "--no-progress", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "floating base" in out and "no ground (--no-ground" in out and "free-falls" in out
    assert "0.0123 m in 0.05 s" in out and "order 4" in out and "landed" not in out
    summary = json.loads((tmp_path / "simulate.json").read_text())
    assert summary["ground"] is False and summary["energy_error_max_relative"] < 1e-8
    (tmp_path / "arm.urdf").write_text(URDF_2DOF)
    assert main(["simulate", str(tmp_path / "arm.urdf"), "--duration", "0.05", "--no-progress", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    assert "free-falls" not in capsys.readouterr().out
    assert main(["simulate", str(tmp_path / "arm.urdf"), "--base", "floating", "--duration", "0.05", "--no-progress",
                 "--no-plot", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "floating base" in out and "free-falls" in out and "--ground with --contact LINK:x,y,z" in out


def test_a_robot_lands_and_stands_on_the_ground_by_default(tmp_path, capsys):
    """hovi simulate littledog: the standing scene dropped from 3 cm lands, stands and carries its weight."""
    assert main(["simulate", "littledog", "--duration", "1", "--no-progress", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "s = 1 (order 2), dt = 0.005 s, 200 steps; standing on the ground" in out and "free-falls" not in out
    assert "landed at t = " in out and "of the weight" in out and "steps/s" in out and "on 4 of 4 contacts" in out
    s = json.loads((tmp_path / "simulate.json").read_text())
    assert s["ground"] and s["converged"] and s["s"] == 1 and s["contacts"] == 4
    # dropped from 0.03 m: about sqrt(2 0.03 / 9.81) = 0.078 s of fall (in 0.005 s steps)
    assert 0.06 <= s["landing_time"] <= 0.09
    assert s["max_penetration"] <= 1e-9 and s["gap_min"] >= -1e-9
    assert s["weight"] == pytest.approx(2.7464 * 9.81, rel=1e-4)
    assert s["weight_carried"] == pytest.approx(1.0, abs=1e-4) and s["active_contacts_end"] == 4
    assert s["base_height_end"] == pytest.approx(0.146, abs=2e-3) and s["base_moved_end"] < 1e-4
    assert (tmp_path / "contact_forces.png").stat().st_size > 1000 and not (tmp_path / "energy_error.png").exists()
    assert "wrote " + str(tmp_path) + "/contact_forces.png" in out


def test_a_urdf_on_the_ground_with_contact_points(tmp_path, capsys):
    """--contact LINK:x,y,z (repeatable) and --mu put any model on the ground; a floating base starts --drop
    above it; a fixed base is not moved."""
    (tmp_path / "arm.urdf").write_text(URDF_2DOF)
    arm = str(tmp_path / "arm.urdf")
    assert main(["simulate", arm, "--base", "floating", "--contact", "c:0,0,-0.2", "--contact", "b:0,0,0",
                 "--contact", "a", "--mu", "0.5", "--drop", "0.05", "--duration", "1", "--no-progress", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "on the ground with 3 contact point(s), mu = 0.5, dropped from 0.05 m" in out and "free-falls" not in out
    s = json.loads((tmp_path / "simulate.json").read_text())
    assert s["ground"] and s["contacts"] == 3 and s["s"] == 1 and s["dt"] == 0.005
    assert 0.09 <= s["landing_time"] <= 0.11  # sqrt(2 0.05 / 9.81) = 0.101 s
    assert s["max_penetration"] <= 1e-9 and s["active_contacts_end"] >= 1
    # a fixed base whose contact point hangs below the ground: refused, naming what to change
    assert main(["simulate", arm, "--contact", "c:0,0,0", "--no-progress", "--no-plot", "--output", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "argument --contact: the contact points start below the ground" in err and "--ground-height" in err
    assert main(["simulate", arm, "--contact", "c:0,0,0", "--ground-height", "-1.5", "--duration", "0.1",
                 "--no-progress", "--no-plot", "--output", str(tmp_path)]) == 0
    capsys.readouterr()


@pytest.mark.parametrize("argv, says", [
    (["--base", "floating", "--ground"], "the ground needs contact points: give --contact LINK:x,y,z"),
    (["--base", "floating", "--contact", "foot:0,0,0"], "argument --contact: no link 'foot' in this model; its links:"),
    (["--contact", "a:0,0,0"], "(the root link of a fixed base is the world)"),
    (["--base", "floating", "--contact", "c", "--no-ground"], "argument --contact: contact needs the ground"),
    (["--base", "floating", "--mu", "0", "--no-ground"], "argument --mu: contact needs the ground"),
    (["--mu", "0.5"], "the ground needs contact points: give --contact LINK:x,y,z"),
])
def test_the_ground_without_what_it_needs_is_refused_naming_the_flag(argv, says, tmp_path, capsys):
    (tmp_path / "arm.urdf").write_text(URDF_2DOF)
    assert main(["simulate", str(tmp_path / "arm.urdf")] + argv + ["--no-progress", "--no-plot",
                                                                   "--output", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.parametrize("argv, says", [
    (["--no-ground", "--mu", "0.5"], "argument --mu: contact needs the ground"),
    (["--contact", "body:0,0,0"], "argument --contact: the built-in robot 'littledog' has its feet"),
])
def test_a_robot_on_the_ground_refuses_what_does_not_apply(argv, says, tmp_path, capsys):
    assert main(["simulate", "littledog"] + argv + ["--no-progress", "--no-plot", "--output", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert says in err and "Traceback" not in err


def test_the_ground_animation_draws_the_terrain_and_contact_force_arrows(tmp_path, capsys):
    """animation.html holds an arrow (shaft and head) per contact, animated (scaled to nothing before the
    landing), and the ground grid; the video shows red arrows once the robot stands."""
    pytest.importorskip("hovi.vis.viewer", reason="hovi[viewer] is not installed")
    import imageio.v3 as iio
    import test_viewer
    assert main(["simulate", "littledog", "--duration", "0.4", "--no-progress", "--no-plot", "--animate", "--fps", "10",
                 "--output", str(tmp_path)]) == 0
    html = tmp_path / "animation.html"
    objects = test_viewer.scene_objects(html)
    assert objects.get("/meshcat/hovi/ground/grid") == "LineSegments"
    for c, name in enumerate(("fl_foot", "fr_foot", "bl_foot", "br_foot")):
        for part in ("shaft", "head"):
            assert objects.get(f"/meshcat/hovi/forces/{c:02d}_{name}/{part}") == "Mesh"
    tracks = test_viewer.animation_tracks(html)
    scale = tracks["/meshcat/hovi/forces/00_fl_foot/shaft"][".scale"]
    assert scale[0][1][1] < 1e-5 and scale[-1][1][1] > 1e-3  # hidden in the air at t = 0, shown standing at t = 0.4
    frames = iio.imread(tmp_path / "animation.mp4", index=None)
    assert frames.shape[0] == 5
    red = [int(((f[..., 0] > 170) & (f[..., 1] < 80) & (f[..., 2] < 80)).sum()) for f in frames]
    assert red[0] < 20 and red[-1] > 100, red


def test_optimize_writes_a_trajectory_file(tmp_path, capsys):
    import hovi
    assert main(["optimize", "pendulum", "--N", "10", "--quiet", "--no-plot", "--output", str(tmp_path)]) == 0
    assert f"wrote {tmp_path / 'optimize_pendulum.npz'}" in capsys.readouterr().out
    model = hovi.examples.models.pendulum(1)
    traj = hovi.load_trajectory(tmp_path / "optimize_pendulum.npz", hovi.Integrator(model, s=2, dt=0.2))
    assert traj.steps == 10 and abs(traj.q[-1, 0] - 3.14159265) < 1e-6 and traj.status == ["optimized"] * 10
    assert abs(traj.energy[-1] - 2.4525) < 1e-3  # upright at rest: m g l / 2 of the 1-link pendulum
    summary = json.loads((tmp_path / "optimize_pendulum.json").read_text())
    assert summary["trajectory_file"] == str(tmp_path / "optimize_pendulum.npz")
    # Hermite-Simpson: the optimised controls replayed with the VI
    assert main(["optimize", "pendulum", "--N", "10", "--transcription", "hs-implicit", "--quiet", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    assert "replayed with the order-4 VI: 10 of 10 steps" in capsys.readouterr().out
    assert hovi.load_trajectory(tmp_path / "optimize_pendulum.npz").steps == 10


def test_optimize_animate(tmp_path, capsys):
    pytest.importorskip("hovi.vis.viewer", reason="hovi[viewer] is not installed")
    assert main(["optimize", "pendulum", "--N", "10", "--quiet", "--no-plot", "--animate", "--fps", "5",
                 "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert f"wrote {tmp_path / 'animation.html'}" in out and "MeshCat.Viewer" in (tmp_path / "animation.html").read_text()


def test_an_unsuccessful_solve_names_the_worst_violation(tmp_path, capsys):
    assert main(["optimize", "pendulum", "--N", "10", "--quiet", "--no-plot", "--max-iter", "3",
                 "--output", str(tmp_path)]) == 1
    err = capsys.readouterr().err
    assert "NOT solved (Maximum number of iterations exceeded" in err
    assert "is the dynamics (the discrete equations of motion) of stage" in err and "--N" in err
    worst = json.loads((tmp_path / "optimize_pendulum.json").read_text())["most_violated"]
    assert worst["violation"] > 1e-3 and "row" in worst


def test_most_violated_names_a_bound():
    from hovi import trajopt
    from hovi.cli import most_violated
    from hovi.examples.swingups import pendulum_swingup
    result = trajopt.solve(pendulum_swingup(N=5), trajopt.VI(s=1), verbose=False)
    tr = result.transcription
    result.x[tr.u_off + 2] = 10.0   # |u| <= 4
    worst = most_violated(result)
    assert worst["what"] == "the bound on u of input 0 at point 2" and worst["violation"] == pytest.approx(6.0)
    assert "control limits" in worst["relax"]
    result.x[tr.u_off + 2] = 0.0
    result.x[tr.q_off] = 1.0        # q(0) = 0 is fixed
    worst = most_violated(result)
    assert worst["what"].startswith("the bound on q of ") and "(a fixed boundary value)" in worst["what"]
    assert "boundary" in worst["relax"]


def test_a_quiet_solve_says_how_far_it_is(tmp_path, capsys, monkeypatch):
    """--quiet turns IPOPT's lines off, not the heartbeat: a line on stderr every HEARTBEAT_SECONDS."""
    import hovi.cli
    from hovi.trajopt.solvers import ipopt
    seen = []
    with ipopt.on_iteration(lambda k, cost, inf_pr, inf_du: seen.append(k)):
        monkeypatch.setattr(hovi.cli, "HEARTBEAT_SECONDS", 0.002)
        assert main(["optimize", "pendulum", "--N", "10", "--quiet", "--no-plot", "--output", str(tmp_path)]) == 0
    assert seen[0] == 0 and len(seen) > 5 and ipopt._ITERATION_HOOKS == []  # the CLI's hook is gone
    err = capsys.readouterr().err
    assert "solving pendulum: " in err and "IPOPT iterations so far" in err
    beat = hovi.cli.Heartbeat("x", every=0.01)
    with beat:
        beat.iteration(0, 1.0, 0.5, 0.1)
        beat.iteration(1, 1.0, 0.25, 0.1)
    assert beat.iterations == 1 and beat.infeasibility == 0.25


def test_animations_of_a_floating_base_draw_the_ground_and_missing_meshes_warn(tmp_path, capsys):
    pytest.importorskip("hovi.vis.viewer", reason="hovi[viewer] is not installed")
    (tmp_path / "arm.urdf").write_text(URDF_2DOF)
    assert main(["simulate", str(tmp_path / "arm.urdf"), "--base", "floating", "--duration", "0.1", "--no-progress",
                 "--no-plot", "--animate", "--fps", "10", "--output", str(tmp_path)]) == 0
    html = (tmp_path / "animation.html").read_text()
    assert "hovi-time" in html
    import test_viewer
    assert test_viewer.scene_objects(tmp_path / "animation.html").get("/meshcat/hovi/ground/grid") == "LineSegments"
    from test_geometry import MISSING_MESH_URDF
    (tmp_path / "mesh.urdf").write_text(MISSING_MESH_URDF)
    assert main(["simulate", str(tmp_path / "mesh.urdf"), "--duration", "0.1", "--no-progress", "--no-plot",
                 "--animate", "--fps", "10", "--output", str(tmp_path / "mesh")]) == 0
    err = capsys.readouterr().err
    assert err.count("hovi: warning: 1 mesh file(s) not found") == 1 and "package://nowhere/a.stl" in err
    assert "--package-dir" in err and "Traceback" not in err
    assert (tmp_path / "mesh" / "animation.mp4").stat().st_size > 1000


def test_plots_have_legends_and_equal_axes():
    import hovi
    from hovi.vis.plots import configuration_figure, control_labels, pyplot
    model = hovi.examples.models.acrobot()
    fig = configuration_figure(model, [0.3, 0.4])
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert "centres of mass" in labels and "joints" in labels
    assert {t.get_text().strip() for t in ax.texts} >= set(model.joint_names)
    limits = [ax.get_xlim(), ax.get_ylim(), ax.get_zlim()]
    assert len({round(hi - lo, 9) for lo, hi in limits}) == 1
    aspect = ax.get_box_aspect()
    assert aspect[0] == pytest.approx(aspect[1]) == pytest.approx(aspect[2])
    pyplot().close(fig)
    assert control_labels(model) == ["u[0] (elbow)"]


def test_a_robot_on_the_ground_at_order_four_locates_its_impacts(tmp_path, capsys):
    """-s 2 on the ground: the impacts located on the step's polynomial."""
    assert main(["simulate", "littledog", "-s", "2", "--duration", "0.3", "--no-progress", "--no-plot",
                 "--output", str(tmp_path)]) == 0
    s = json.loads((tmp_path / "simulate.json").read_text())
    assert s["ground"] and s["converged"] and s["s"] == 2


@pytest.mark.parametrize("argv, says", [
    (["simulate", "pendulum:2", "--base", "floating"], "argument --base: the built-in 'pendulum:2' has a fixed base; "
                                                        "--base floating applies to URDF files"),
    (["info", "littledog", "--base", "planar"], "argument --base: the built-in 'littledog' has an Euler-angle floating base"),
])
def test_a_base_other_than_a_built_in_models_own_is_refused(argv, says, tmp_path, capsys):
    """``hovi simulate pendulum:2 --base floating`` ignored the flag and simulated a fixed base."""
    assert main(argv + ["--output", str(tmp_path)] * (argv[0] == "simulate")) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert main(["info", "littledog", "--base", "euler"]) == 0  # its own base, said again, is fine


def test_simulate_pushes_a_standing_robot(tmp_path, capsys):
    """``hovi simulate littledog --push BODY:t,ix,iy,iz`` (repeatable; with an angular impulse the
    wrench form): said in the summary and the JSON; the pushes move the robot, still on its feet 0.1 s
    after the last."""
    out = tmp_path / "pushed"
    assert main(["simulate", "littledog", "--push", "body:0.5,0.3,0,0", "--push", "body:1.4,0,0.2,0,0,0,0.005",
                 "--duration", "1.5", "--no-progress", "--output", str(out)]) == 0
    text = capsys.readouterr().out
    assert "push: body at t = 0.5 s, impulse [0.3, 0.0, 0.0] N s" in text
    assert "angular impulse [0.0, 0.0, 0.005] N m s" in text
    pushed = json.loads((out / "simulate.json").read_text())
    assert [p["time"] for p in pushed["pushes"]] == [0.5, 1.4] and pushed["converged"]
    assert main(["simulate", "littledog", "--duration", "1.5", "--no-progress", "--no-plot", "--output",
                 str(tmp_path / "still")]) == 0
    still = json.loads((tmp_path / "still" / "simulate.json").read_text())
    assert pushed["base_moved_end"] > 100 * still["base_moved_end"] + 1e-4  # it was pushed
    assert pushed["active_contacts_end"] == 4 and not pushed["below_ground_end"]  # on its feet
    assert (out / "final_configuration.png").is_file()


@pytest.mark.parametrize("push, says", [
    ("body:1,2,3", "argument --push: 'body:1,2,3' is not BODY:t,ix,iy,iz"),
    ("body:-1,0,0,0", "the time must be >= 0"),
    ("nobody:1,0,0,0", "Push body: the model has no body named 'nobody'"),
])
def test_bad_pushes_are_refused_in_one_line(push, says, tmp_path, capsys):
    argv = ["simulate", "littledog", "--push", push, "--duration", "0.1", "--no-progress", "--no-plot",
            "--output", str(tmp_path)]
    try:
        code = main(argv)
    except SystemExit as e:  # argparse's own errors
        code = e.code
    assert code == 2
    err = capsys.readouterr().err
    assert says in err.strip().splitlines()[-1] and "Traceback" not in err  # (argparse's usage lines before it)


def test_bodies_below_the_ground_are_named():
    from hovi.cli import below_ground
    from hovi.examples.robots import littledog
    robot = littledog()
    q = robot.q0.copy()
    q[2] = -0.28  # the base sunk 0.28 m under the floor
    sunk = dict(below_ground(robot.model, q, 0.0))
    assert "body" in sunk and sunk["body"] == pytest.approx(-0.28)
    assert below_ground(robot.model, robot.q0, 0.0) == []


def test_example_runs_its_optimised_motion_in_closed_loop(tmp_path, capsys):
    """``hovi example atlas --quick --closed-loop --push pelvis:0.15,20,0,0``: the optimised motion tracked
    by time-varying LQR in the contact simulator, pushed; it says whether the example's goal is reached
    (the open loop, pushed the same, fails), and writes the motion as a hovi trajectory with its controls."""
    import hovi
    assert main(["example", "atlas", "--quick", "--closed-loop", "--push", "pelvis:0.15,20,0,0", "--no-animate",
                 "--quiet", "--no-progress", "--output", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "closed loop succeeds: 6 of 6 steps" in out and "open loop fails" in out
    summary = json.loads((tmp_path / "atlas.json").read_text())
    loop = summary["closed_loop"]
    assert loop["push"]["impulse"] == [20.0, 0.0, 0.0] and loop["closed_loop"]["success"]
    assert not loop["open_loop"]["success"]
    from hovi.examples.paper import build
    prob = build("atlas", quick=True).problem
    traj = hovi.load_trajectory(tmp_path / "atlas_trajectory.npz", hovi.Integrator(prob.model, s=1, dt=prob.dt))
    assert traj.converged and traj.controls.shape == (prob.N, 2, prob.model.n_controls)


@pytest.mark.parametrize("argv, says", [
    (["--push", "pelvis:0.1,1,0,0"], "argument --push/--mass-scale: they act on the closed loop; add --closed-loop"),
    (["--closed-loop", "-s", "2"], "argument --closed-loop: the motion is tracked in the contact simulator"),
    (["--closed-loop", "--push", "pelvis:0.1,1,0,0", "--push", "pelvis:0.2,1,0,0"], "the closed loop takes one push"),
])
def test_closed_loop_arguments_are_checked(argv, says, tmp_path, capsys):
    assert main(["example", "atlas", "--quick", "--no-animate", "--output", str(tmp_path)] + argv) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1
