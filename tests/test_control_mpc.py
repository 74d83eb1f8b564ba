"""control.MPC (cpp/include/hovi/control/mpc.hpp) against the same receding horizon written out in
Python on the public ShootingProblem: every period, x0 = the plant's state, offset = the step, FDDP
warm-started from the last plan shifted by the period (its first row the plant's state), then the
plan's feedback u = clip(us^j + K^j (x - xs^j)) until the next solve; the plant stepped by
Integrator.step. The C++ loop must apply the same controls and give the same trajectory."""
import numpy as np
import pytest

import hovi
from hovi import control, trajopt
from hovi.examples import models


def horizon(model, N=15, dt=0.02):
    pr = trajopt.Problem(model, N, N * dt, controls="held", u_bounds=(-20.0, 20.0), q_bounds=(-np.inf, np.inf))
    pr.initial_state([0.0, np.pi])
    pr.add_cost(trajopt.ControlEffort(0.01))
    pr.add_cost(trajopt.StateTracking([0.0, np.pi], [1.0, 10.0], velocity_weight=0.1))
    return pr.add_cost(trajopt.TerminalCost([0.0, np.pi], [10.0, 100.0], velocity_weight=1.0))


def python_mpc(problem, plant, q0, steps, period, max_iterations, tol):
    tr = trajopt.VI(1).transcribe(problem)
    sp = trajopt.FDDP().shooting_problem(problem, tr)
    N, lo, hi = problem.N, problem.u_lower, problem.u_upper
    q, p = np.array(q0, float), plant.momentum(q0, np.zeros(plant.n))
    plan, since, U = None, 0, []
    for k in range(steps):
        x = np.concatenate([q, p])
        if plan is None or since >= period:
            xs = us = None
            if plan is not None:
                xs = plan["xs"][np.minimum(np.arange(N + 1) + since, N)]
                us = plan["us"][np.minimum(np.arange(N) + since, N - 1)]
                xs[0] = x
            sp.x0, sp.offset = x, k
            plan, since = sp.solve(xs, us, max_iterations, tol), 0
        u = np.clip(plan["us"][since] + plan["K"][since] @ (x - plan["xs"][since]), lo, hi)
        q, p, _ = plant.step(q, p, u)
        U.append(u)
        since += 1
    return np.array(U), q


@pytest.mark.parametrize("period", [1, 3])
def test_mpc_is_the_receding_horizon_written_out(period):
    model = models.cartpole()
    pr = horizon(model)
    plant = hovi.Integrator(model, s=1, dt=pr.dt)
    q0 = np.array([0.05, np.pi - 0.15])
    run = control.MPC(pr, s=1, period=period, max_iterations=4, tol=1e-8).run(plant, q0, 40)
    U, q_end = python_mpc(pr, plant, q0, 40, period, 4, 1e-8)
    np.testing.assert_allclose(run.u[:, 0, :], U, rtol=0, atol=1e-9)
    np.testing.assert_allclose(run.trajectory.q[-1], q_end, rtol=0, atol=1e-9)
    assert len(run.solve_seconds) == -(-40 // period) and np.all(run.iterations <= 4)
    assert abs(run.trajectory.q[-1, 1] - np.pi) < 0.05  # 0.15 rad off at the start, 0.016-0.019 after 0.8 s
