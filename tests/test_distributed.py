"""hovi.distributed on a LocalCluster of 2 worker processes (started here, closed at the end even
when a test fails): rollouts, steps, the one-step study and trajectory optimisations of B = 100
items come back bit for bit as the sequential single-thread calls give them."""
import dataclasses

import numpy as np
import pytest

import hovi
import hovi.baselines
from hovi import distributed

dd = pytest.importorskip("distributed")

B = 100


@pytest.fixture(scope="module")
def client():
    cluster = dd.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
    try:
        with dd.Client(cluster) as c:
            yield c
    finally:
        cluster.close()


@pytest.fixture(scope="module")
def setup():
    model = hovi.examples.models.pendulum(5)
    model.add_spring(0, 3.0, 0.2)
    model.add_damper(1, 0.4)
    model.add_actuator(2)
    rng = np.random.default_rng(11)
    Q, V = rng.uniform(-1, 1, (B, 5)), rng.uniform(-2, 2, (B, 5))
    V[5] = 400.0  # a state whose first step fails
    return hovi.Integrator(model, s=2, dt=0.01), Q, V, rng.uniform(-1, 1, (B, 30, 1))


def assert_same(a, b, skip=("solve_seconds", "discretization")):
    for f in dataclasses.fields(a):
        if f.name not in skip:
            x, y = getattr(a, f.name), getattr(b, f.name)
            if isinstance(x, list) or x is None:
                assert x == y, f.name
            else:
                assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), f.name


def test_rollouts(client, setup):
    integ, Q, V, U = setup
    batch = distributed.rollout_batch(integ, Q, 30, qdot0s=V, u=U, client=client, chunk_size=30)
    assert batch.discretization is integ.discretization and len(batch) == B and batch.status[5] != "converged"
    assert_same(batch, integ.rollout_batch(Q, 30, qdot0s=V, u=U, threads=1))
    for b in (0, 5, 99):
        one = integ.rollout(Q[b], 30, qdot0=V[b], u=U[b], raise_on_failure=False)
        assert np.array_equal(batch.trajectory(b).q, one.q) and batch.trajectory(b).status == one.status


def test_steps(client, setup):
    integ, Q, V, U = setup
    P = np.array([integ.momentum(q, v) for q, v in zip(Q, V)])
    batch = distributed.step_batch(integ, Q, P, U[:, 0], client=client.scheduler.address)  # by address
    assert_same(batch, integ.step_batch(Q, P, U[:, 0], threads=1))
    assert np.array_equal(batch.q_next[3], integ.step(Q[3], P[3], U[3, 0])[0])


def test_one_step_study(client):
    model = hovi.examples.models.pendulum(8)
    q0, qd0 = np.random.default_rng(2).uniform(-np.pi / 2, np.pi / 2, (2, B, 8))
    mine = distributed.one_step_batch(model, 0.05, q0, qd0, "newton+continuation", client=client)
    local = hovi.baselines.one_step_batch(model, 0.05, q0, qd0, "newton+continuation", threads=1)
    assert mine.keys() == local.keys()
    for key in local:
        if key != "seconds":
            np.testing.assert_array_equal(mine[key], local[key], err_msg=key)


def test_trajectory_optimisations(client):
    from hovi import trajopt
    from hovi.examples import swingups as examples
    problems = [examples.EXAMPLES["pendulum"](N=12) for _ in range(2)]
    problems[1].final_state([2.5], qdot=[0.0])
    results = distributed.solve_trajopt(problems, trajopt.VI(s=1), client=client)
    for problem, result in zip(problems, results):
        local = trajopt.solve(problem, trajopt.VI(s=1), verbose=False)
        assert result.success and result.status == local.status and result.iterations == local.iterations
        assert np.array_equal(result.x, local.x)
        assert np.array_equal(result.replay().q, local.replay().q)


def test_chunks_and_bad_input(client, setup):
    integ, Q, V, _ = setup
    with pytest.raises(ValueError, match="chunk_size must be a positive integer"):
        distributed.rollout_batch(integ, Q, 3, client=client, chunk_size=0)
    with pytest.raises(ValueError, match="the batch is empty"):
        distributed.rollout_batch(integ, Q[:0], 3, client=client)
    with pytest.raises(ValueError, match=r"u must have shape \(100, 1\) or \(100, 3, 1\)"):
        distributed.step_batch(integ, Q, u=np.zeros((3, 1)), client=client)
    with pytest.raises(TypeError, match="client must be"):
        distributed.step_batch(integ, Q, client=42)
    for bad in (Q + 1j, Q.astype(object), Q.astype(str)):  # refused before anything is sent, never cast
        with pytest.raises(ValueError, match="q0s must be an array of real numbers"):
            distributed.rollout_batch(integ, bad, 3, client=client)
        with pytest.raises(ValueError, match="q0 must be an array of real numbers"):
            distributed.one_step_batch(integ.model, 0.05, bad, V, "newton", client=client)
    # the default chunks: SOLVES_PER_TASK solves a task, at most as many items as give every worker one
    assert [s.stop - s.start for s in distributed._chunks(B, 30, client, None)] == [50, 50]
    assert [s.stop - s.start for s in distributed._chunks(10_000, 1, client, None)] == [4000, 4000, 2000]


def test_default_local_cluster(setup):
    integ, Q, V, _ = setup
    batch = distributed.step_batch(integ, Q[:4], qdots=V[:4])  # starts and closes a LocalCluster
    assert np.array_equal(batch.q_next, integ.step_batch(Q[:4], qdots=V[:4], threads=1).q_next)
