"""Every benchmark script runs in --quick mode (a smoke run: the full studies live in bench/)."""
import os
import subprocess
import sys

import pytest

from conftest import BENCH, bench_module  # noqa: E402
SCRIPTS = ["speed.py", "linearization.py", "constraints.py", "constrained_energy.py", "fig2_quasi_newton.py", "fig3_autodiff.py",
           "fig4_hermite_simpson.py", "stability.py", "trajopt.py", "pareto.py", "energy_runtime.py",
           "direction_crossover.py", "jacobian_reuse.py", "step_floor.py", "fuzz_urdf.py", "soak_threads.py", "robot_sweep.py", "long_run.py",
           "robot_examples.py --only spring_flamingo atlas", "scaling.py",  # LittleDog's quick solve: tests/test_robot_examples.py
           "contact_sim.py",  # hovi's contact simulation against MuJoCo
           "contact_order.py",  # impacts located on the step's polynomial: order 2s kept
           "ipopt_options.py",  # IPOPT's Hessian and barrier options on the swing-ups
           "acrobot_basins.py",  # which acrobot optimum each pipeline reaches
           "hessian_cost.py",  # the VI's own Hessian against coloured differences on the robots
           # the studies over many states, on local threads and on a Dask LocalCluster
           "fig2_quasi_newton.py --workers 2", "stability.py --scheduler local --workers 2"]


def run_quick(script: str, args: list, results) -> str:
    """Runs bench/<script> --quick writing into the folder ``results`` (HOVI_BENCH_RESULTS); its output."""
    env = dict(os.environ, HOVI_BENCH_RESULTS=str(results))
    done = subprocess.run([sys.executable, os.path.join(BENCH, script), "--quick", *args], cwd=BENCH, env=env,
                          capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-4000:]
    return done.stdout


@pytest.mark.parametrize("command", SCRIPTS)
def test_bench_script_quick_mode(command, tmp_path):
    """Each study's quick run writes its quick JSON into the folder it is given, with the machine it ran
    on and results; a file already in bench/results cannot stand in for it."""
    import json
    script, *args = command.split()
    run_quick(script, args, tmp_path)
    stem = script[:-3].split("_")[0]
    written = [f for f in os.listdir(tmp_path) if f.startswith(stem) and "quick" in f and f.endswith(".json")]
    assert written, os.listdir(tmp_path)
    for name in written:
        with open(tmp_path / name) as f:
            payload = json.load(f)
        assert payload["machine"]["cores"] >= 1 and len(payload) > 1, name


def test_pareto_time_to_reach_takes_the_cheapest_crossing():
    """bench/pareto.py's equal-error run time: log-log interpolation across the level, and the cheapest
    point or crossing when run time falls with dt (large steps needing many Newton iterations)."""
    import numpy as np
    time_to_reach = bench_module("pareto").time_to_reach
    curve = np.array([[1.0, 1e-2], [10.0, 1e-4]])              # (seconds, error) by decreasing dt
    t, bound = time_to_reach(curve, 1e-3)
    assert not bound and abs(t - np.sqrt(10.0)) < 1e-12       # halfway in log error -> halfway in log time
    assert time_to_reach(curve, 1e-5) is None
    assert time_to_reach(curve, 1e-1) == (1.0, True)
    slow_then_fast = np.array([[5.0, 1e-2], [8.0, 5e-4], [3.0, 1e-4]])  # the smaller dt is cheaper
    assert time_to_reach(slow_then_fast, 1e-3)[0] == 3.0


def test_acrobot_basins_smooth_guess():
    """bench/acrobot_basins.py's perturbed straight line: its ends are q0 and qT, and its q̇ is the
    derivative of its q (central differences)."""
    import numpy as np
    smooth_guess = bench_module("acrobot_basins").smooth_guess
    a = np.random.default_rng(1).normal(0.0, 1.5, size=(3, 2))
    q0, qT, T = np.array([0.0, 0.0]), np.array([np.pi, 0.0]), 4.0
    q, qdot, u = smooth_guess(a, T, q0, qT)
    np.testing.assert_allclose(q(np.array([0.0, T])), [q0, qT], atol=1e-14)
    t, eps = np.linspace(0.1, 3.9, 17), 1e-6
    np.testing.assert_allclose(qdot(t), (q(t + eps) - q(t - eps)) / (2 * eps), rtol=1e-8, atol=1e-8)
    assert u(t).shape == (17, 1) and not u(t).any()


def test_control_quick_mode(tmp_path):
    """bench/control.py --quick: FDDP on the VI against Crocoddyl's (RK4), TVLQR Monte-Carlo,
    the upright LQR's region of attraction, MPC's solve times and FDDP through contact, in one small run."""
    pytest.importorskip("crocoddyl")
    pytest.importorskip("pinocchio")
    cb = bench_module("crocoddyl_baseline")
    try:
        cb.build_problem("pendulum", N=2)
    except cb.CrocoddylPinocchioMismatch as e:
        pytest.skip(str(e))
    run_quick("control.py", [], tmp_path)
    import json
    with open(tmp_path / "control_quick.json") as f:
        res = json.load(f)["results"]
    rows = res["A"]["swingups"]["pendulum"]["rows"]
    by = {(r["N"], r["solver"]): r for r in rows}
    assert by[(40, "hovi VI s=3")]["resim_error"] < 1e-5 < by[(40, "Crocoddyl RK4")]["resim_error"]
    assert all(r["converged"] for r in rows)
    for robot in res["B"]["robots"].values():  # feedback never does worse than the nominal controls
        assert all(c["closed_loop"]["success_rate"] >= c["open_loop"]["success_rate"] for c in robot["conditions"].values())
        assert robot["conditions"]["none"]["closed_loop"]["success_rate"] == 1.0
    assert res["C"]["maps"]["cartpole_q1_v1"]["largest_a_at_b0"] > 0.1
    assert all(r["plant_converged"] for r in res["D"]["runs"])
    assert all(r["min_gap"] > -1e-9 for r in res["E"]["rows"])


def test_free_base_quick_mode(tmp_path):
    """bench/free_base.py --quick: the free base keeps the order 2 at s = 1 against DOP853 and the world
    momenta through the Dzhanibekov flip to round-off where MuJoCo's RK4 drifts; the cube tips over an
    edge at 50 degrees and rests on a face, and so do its random drops, on the free base; the
    Euler-angle base fails the edge (its pitch passes 90 degrees)."""
    import json
    run_quick("free_base.py", [], tmp_path)
    with open(tmp_path / "free_base_quick.json") as f:
        out = json.load(f)
    assert out["machine"]["cores"] >= 1
    for row in out["order"].values():
        assert row["order"] > 1.7, row
    hovi_free = [r for r in out["flip"] if r["library"] == "hovi" and r["base"] == "free"]
    mujoco = [r for r in out["flip"] if r["library"] == "mujoco"]
    assert all(r["converged"] and r["momentum"] < 1e-11 for r in hovi_free)
    assert all(r["momentum"] > 100 * max(h["momentum"] for h in hovi_free) for r in mujoco)
    free, euler = out["cube"]["free s=1 dt=0.01"], out["cube"]["euler s=1 dt=0.01"]
    assert free["edge_tips_and_rests"] and free["converged"] == free["rest_on_a_face"] == free["drops"]
    assert not euler["edge_tips_and_rests"]


def test_quadrotor_quick_mode(tmp_path):
    """bench/quadrotor.py --quick: one LQR at hover brings a heavier quadrotor back from tilts up to upside
    down, and time-varying LQR tracks a flip whose open loop misses by metres."""
    import json
    run_quick("quadrotor.py", [], tmp_path)
    with open(tmp_path / "quadrotor_quick.json") as f:
        out = json.load(f)
    assert out["recovery"] and all(r["recovered"] for r in out["recovery"])
    assert max(r["degrees"] for r in out["recovery"]) >= 179
    assert out["flip"]["turn_degrees"] > 355
    assert out["flip"]["miss_closed"] < 0.1 * out["flip"]["miss_open"]


def test_astronaut_quick_mode(tmp_path):
    """bench/astronaut.py --quick: Atlas floating in zero gravity under random joint torques, then
    coasting: the two libraries' models agree, and hovi keeps the world momenta to round-off where
    MuJoCo's RK4 drifts with its accuracy."""
    import json
    run_quick("astronaut.py", [], tmp_path)
    with open(tmp_path / "astronaut_quick.json") as f:
        out = json.load(f)
    agreement = out["model_agreement"]
    assert max(agreement[k] for k in ("kinetic_energy", "mass_matrix", "linear_momentum", "angular_momentum")) < 1e-9
    rows = {r["library"]: r for r in out["rows"]}
    hovi_row, mujoco_row = rows["hovi"], rows["MuJoCo"]
    assert not hovi_row["failed"] and not mujoco_row["failed"]
    drift = max(hovi_row["linear_momentum_drift"], hovi_row["angular_momentum_drift"])
    assert drift < 1e-11
    assert min(mujoco_row["linear_momentum_drift"], mujoco_row["angular_momentum_drift"]) > 100 * drift
