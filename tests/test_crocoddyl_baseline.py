"""bench/crocoddyl_baseline.py, the Crocoddyl side of the FDDP benchmark: its Pinocchio models are
hovi's (mass matrix, forward dynamics, actuation), its Crocoddyl problem's cost is the benchmark's
formula, its built-in actuations give the iterates of tau = B u, its re-simulation is exact, and
box-FDDP swings the pendulum up.

Skipped without pinocchio (the model checks) or crocoddyl (the rest), and when the installed
crocoddyl binary disagrees with the installed Pinocchio (crocoddyl 3.2.1's wheels are built against
libpinocchio 4.0.0 and compute garbage dynamics with 4.1.0; see the module's docstring)."""
import os
import subprocess
import sys

import numpy as np
import pytest

from conftest import BENCH, bench_module  # noqa: E402

cb = bench_module("crocoddyl_baseline")

NAMES = ["pendulum", "cartpole", "acrobot"]


@pytest.fixture(scope="module")
def crocoddyl():
    """crocoddyl, when installed and consistent with the installed Pinocchio."""
    croc = pytest.importorskip("crocoddyl")
    pytest.importorskip("pinocchio")
    try:
        cb.build_problem("pendulum", N=2)
    except cb.CrocoddylPinocchioMismatch as e:
        pytest.skip(str(e))
    return croc


def _relerr(a, b):
    return np.abs(np.asarray(a) - np.asarray(b)).max() / max(1.0, np.abs(b).max())


@pytest.mark.parametrize("name", NAMES)
def test_pinocchio_model_is_hovis(name, rng):
    """Mass matrix and forward dynamics (tau = B u) of the hand-built Pinocchio model equal hovi's to
    1e-12 relative on 20 random states each; same actuation matrix, joints in the same order."""
    pin = pytest.importorskip("pinocchio")
    h, pm = cb.hovi_model(name), cb.pinocchio_model(name)
    pd = pm.createData()
    B = cb.actuation_matrix(name)
    assert pm.nq == pm.nv == h.n and B.shape == (h.n, h.n_controls)
    np.testing.assert_array_equal(np.asarray(h.actuation), B)
    np.testing.assert_array_equal(np.asarray(pm.gravity.linear), h.gravity)
    u_max = cb.SWINGUPS[name]["u_max"]
    for _ in range(20):
        q = rng.uniform(-np.pi, np.pi, h.n)
        M = pin.crba(pm, pd, q)
        M = np.triu(M) + np.triu(M, 1).T
        assert _relerr(M, h.mass_matrix(q)) < 1e-12
        assert abs(pin.computePotentialEnergy(pm, pd, q) - h.potential_energy(q)) < 1e-12 * max(1.0, abs(h.potential_energy(q)))
    for _ in range(20):
        q, v, u = rng.uniform(-np.pi, np.pi, h.n), rng.uniform(-3, 3, h.n), rng.uniform(-u_max, u_max, h.n_controls)
        a_pin = pin.aba(pm, pd, q, v, B @ u)
        assert _relerr(a_pin, h.forward_dynamics(q, v, B @ u)) < 1e-12


def _rk4_rollout(name, x0, us, dt):
    """Classical RK4 with the control held over the stage, on pinocchio.aba (independent of Crocoddyl)."""
    f = cb._ABA(name)
    xs = [np.asarray(x0, dtype=float)]
    for u in us:
        tau = f.B @ u
        x = xs[-1]
        k1 = f.xdot(x, tau)
        k2 = f.xdot(x + dt / 2 * k1, tau)
        k3 = f.xdot(x + dt / 2 * k2, tau)
        k4 = f.xdot(x + dt * k3, tau)
        xs.append(x + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4))
    return np.array(xs)


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("weights", [dict(), dict(Wq=3.0, Wv=7.0, R=0.5)])
def test_problem_cost_is_the_formula(crocoddyl, name, weights, rng):
    """Crocoddyl's total cost of a random control sequence equals sum dt R |u|^2 + Wq |q_N - q_T|^2 +
    Wv |v_N|^2 computed from an RK4 rollout of our own (which equals Crocoddyl's rollout)."""
    problem, info = cb.build_problem(name, **weights)
    m = info["B"].shape[1]
    us = rng.uniform(-info["u_max"], info["u_max"], (info["N"], m)) * 0.3
    us_croc = np.hstack([us, np.zeros((info["N"], info["nu"] - m))])      # the cart-pole's pinned hinge torque
    xs = _rk4_rollout(name, info["x0"], us, info["dt"])
    xs_croc = np.array(problem.rollout(list(us_croc)))
    assert np.abs(xs_croc - xs).max() < 1e-12 * max(1.0, np.abs(xs).max())
    cost = problem.calc(list(xs_croc), list(us_croc))
    expected = cb.cost_formula(xs, us, info["dt"], info["q_T"], **weights)
    assert abs(cost - expected) < 1e-12 * expected, (cost, expected)
    assert info["dt"] == cb.SWINGUPS[name]["T"] / cb.SWINGUPS[name]["N"]


@pytest.mark.parametrize("name", ["acrobot", "cartpole"])
def test_builtin_actuation_gives_the_matrix_actuations_iterates(crocoddyl, name):
    """The acrobot's ActuationModelFloatingBase (shoulder as "root_joint") and the cart-pole's full
    actuation with the hinge torque pinned to [0, 0] give box-FDDP the very iterates of tau = B u by a
    Python actuation model: same iterations, cost, knots and controls."""
    a = cb.solve_swingup(name)
    b = cb.solve_swingup(name, python_actuation=True)
    assert a["iterations"] == b["iterations"] and a["converged"] == b["converged"]
    assert abs(a["cost"] - b["cost"]) <= 1e-12 * b["cost"]
    assert np.abs(a["xs"] - b["xs"]).max() < 1e-10 and np.abs(a["us"] - b["us"]).max() < 1e-10


def test_resimulate_is_the_limit_of_rk4(crocoddyl):
    """resimulate (DOP853, 1e-12) against our RK4 with each stage split in k substeps: the difference
    falls at fourth order (ratio ~16 per halving) to below 1e-5; hovi's (q, p) -> (q, v) conversion."""
    r = cb.solve_swingup("pendulum")
    ref = cb.resimulate("pendulum", r["xs"][0], r["us"], r["dt"])
    errs = []
    for k in (2, 4, 8):
        fine = _rk4_rollout("pendulum", r["xs"][0], np.repeat(r["us"], k, axis=0), r["dt"] / k)[::k]
        errs.append(np.abs(fine - ref).max())
    assert errs[-1] < 1e-5 and errs[0] / errs[1] > 10 and errs[1] / errs[2] > 10, errs
    h = cb.hovi_model("acrobot")
    q, v = np.array([0.4, -1.2]), np.array([0.7, 2.0])
    np.testing.assert_allclose(cb.hovi_state_to_x("acrobot", q, h.mass_matrix(q) @ v), np.r_[q, v], rtol=1e-13, atol=1e-13)
    Q = np.array([q, -q])
    P = np.array([h.mass_matrix(qk) @ v for qk in Q])
    assert cb.hovi_state_to_x("acrobot", Q, P).shape == (2, 4)


def test_pendulum_swingup_converges(crocoddyl):
    r = cb.solve_swingup("pendulum")
    assert r["converged"] and 0 < r["iterations"] < 500 and r["stop"] < 1e-10
    assert abs(r["xs"][-1, 0] - np.pi) < 0.05
    assert r["xs"].shape == (41, 2) and r["us"].shape == (40, 1)
    assert np.abs(r["us"]).max() <= 4.0
    assert r["cost"] == pytest.approx(cb.cost_formula(r["xs"], r["us"], r["dt"], [np.pi]), rel=1e-12)
    assert r["resim_error"] < 0.05 and r["resim_final_error"] <= r["resim_error"]


def test_quick_mode_prints_the_table(crocoddyl):
    done = subprocess.run([sys.executable, os.path.join(BENCH, "crocoddyl_baseline.py"), "--quick"], cwd=BENCH,
                          capture_output=True, text=True, timeout=300,
                          env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)})
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-4000:]
    rows = [line.split() for line in done.stdout.splitlines() if line.split()[:1] in (["pendulum"], ["cartpole"], ["acrobot"])]
    assert len(rows) == 3 and all(row[4] == "True" for row in rows), done.stdout
