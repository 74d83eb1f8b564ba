"""One Integrator, Linearizer or baseline object shared by many threads: every call gives exactly
the result of the same call made alone (each call runs on its own workspace)."""
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

import hovi
import hovi.baselines
from mechanisms import fourbar

THREADS, REPEATS = 6, 4


def run_concurrently(jobs):
    """Runs every job REPEATS times, interleaved over THREADS threads; returns the results in job
    order (a list of REPEATS results per job)."""
    with ThreadPoolExecutor(THREADS) as pool:
        futures = [[pool.submit(job) for _ in range(REPEATS)] for job in jobs]
        return [[f.result() for f in fs] for fs in futures]


def assert_same(a, b):
    """Bit-for-bit equality of nested tuples, lists, dicts and arrays."""
    if isinstance(a, (tuple, list)):
        assert len(a) == len(b)
        for x, y in zip(a, b):
            assert_same(x, y)
    elif isinstance(a, dict):
        assert a.keys() == b.keys()
        for k in a:
            assert_same(a[k], b[k])
    else:
        np.testing.assert_array_equal(a, b)


def check(jobs):
    sequential = [job() for job in jobs]
    for expected, results in zip(sequential, run_concurrently(jobs)):
        for r in results:
            assert_same(r, expected)


def states(n, count, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(-0.5, 0.5, (count, n)), rng.uniform(-1, 1, (count, n))


def rollout_result(t):
    return (t.q, t.p, t.control_points, t.iterations, t.status, t.multipliers)


@pytest.mark.parametrize("reuse_jacobian", [False, True])
def test_shared_integrator_steps_and_rollouts(reuse_jacobian):
    integ = hovi.Integrator(hovi.examples.models.pendulum(16), s=2, dt=0.01, reuse_jacobian=reuse_jacobian)
    Q, QD = states(16, 8, 1)
    jobs = []
    for q, qd in zip(Q, QD):
        p = integ.momentum(q, qd)
        jobs.append(lambda q=q, qd=qd: rollout_result(integ.rollout(q, 200, qdot0=qd)))
        jobs.append(lambda q=q, p=p: integ.step(q, p)[:2])
    check(jobs)


def test_shared_integrator_residuals_directions_and_energies():
    integ = hovi.Integrator(hovi.examples.models.pendulum(16), s=3, dt=0.01)
    Q, QD = states(16, 8, 2)
    jobs = []
    for q, qd in zip(Q, QD):
        qc = q + np.outer(integ.nodes, 0.01 * qd)
        p = integ.momentum(q, qd)
        jobs += [lambda qc=qc, p=p: integ.del_residual(qc, p),
                 lambda qc=qc, p=p: integ.newton_direction(qc, p),
                 lambda q=q, p=p: (integ.velocity(q, p), integ.energy(q, p)),
                 lambda q=q, p=p: integ.energies(np.tile(q, (50, 1)), np.tile(p, (50, 1)))]
    check(jobs)


def test_shared_constrained_integrator():
    integ = hovi.Integrator(fourbar(), s=2, dt=0.01)
    jobs = []
    for k, crank in enumerate(np.linspace(-1.4, -1.0, 6)):
        q, qd = integ.project(np.array([crank, 0.9, -1.8]), np.array([1.0 + 0.2 * k, 0, 0]))
        p = integ.momentum(q, qd)
        jobs.append(lambda q=q, qd=qd: rollout_result(integ.rollout(q, 40, qdot0=qd)))
        jobs.append(lambda q=q, p=p: (lambda r: (r[0], r[1], r[2].multipliers))(integ.step(q, p)))
        jobs.append(lambda q=q, p=p: integ.velocity(q, p))
    check(jobs)


def test_shared_linearizer():
    integ = hovi.Integrator(hovi.examples.models.pendulum(8), s=2, dt=0.01)
    lin = hovi.Linearizer(integ)
    Q, QD = states(8, 6, 3)
    jobs = []
    for q, qd in zip(Q, QD):
        traj = integ.rollout(q, 10, qdot0=qd)
        jobs += [lambda qc=traj.control_points[0]: lin.del_jacobian(qc).dq,
                 lambda qc=traj.control_points[0]: lin.linearize_at(qc),
                 lambda traj=traj: lin.rollout_jacobians(traj, B=False)[0]]
    check(jobs)


def test_shared_baselines():
    model = hovi.examples.models.pendulum(6)
    hs = hovi.baselines.HermiteSimpson(model, 0.01)
    Q, QD = states(6, 6, 4)
    check([lambda q=q, qd=qd: (lambda r: (r["q"], r["v"], r["iterations"]))(hs.rollout(q, qd, 50))
           for q, qd in zip(Q, QD)])
