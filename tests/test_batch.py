"""Batched rollouts, steps and linearisations (Integrator.rollout_batch, Integrator.step_batch,
Linearizer.rollout_jacobians_batch, baselines.one_step_batch's threads): B = 100 states on 2 C++
threads give, bit for bit, the single calls made one after another; a failed item does not fail
the batch; bad input raises ValueError."""
import dataclasses
import re

import numpy as np
import pytest

import hovi
import hovi.baselines
from mechanisms import fourbar

B = 100


def forced_pendulum():
    model = hovi.examples.models.pendulum(5)
    model.add_spring(0, 3.0, 0.2)
    model.add_damper(1, 0.4)
    model.add_actuator(2)
    model.add_actuator(4, gear=2.0)
    model.add_drag(3, 0.3, 0.1)
    return model


def states(rng, count, n, spread=1.0):
    return rng.uniform(-spread, spread, (count, n)), rng.uniform(-2 * spread, 2 * spread, (count, n))


def assert_same_trajectory(a, b):
    for f in dataclasses.fields(a):
        if f.name not in ("solve_seconds", "discretization"):
            x, y = getattr(a, f.name), getattr(b, f.name)
            assert (x is None and y is None) or np.array_equal(x, y), f.name


@pytest.fixture
def pendulum_batch(rng):
    integ = hovi.Integrator(forced_pendulum(), s=2, dt=0.01)
    Q, V = states(rng, B, 5)
    V[7] = 400.0  # this state's first step fails
    U = rng.uniform(-1, 1, (B, 40, 3, 2))
    return integ, Q, V, U


def test_rollouts_are_the_single_rollouts(pendulum_batch):
    integ, Q, V, U = pendulum_batch
    batch = integ.rollout_batch(Q, 40, qdot0s=V, u=U, threads=2)
    assert len(batch) == B and batch.q.shape == (B, 41, 5) and batch.control_points.shape == (B, 40, 3, 5)
    for b in range(B):
        one = integ.rollout(Q[b], 40, qdot0=V[b], u=U[b], raise_on_failure=False)
        assert_same_trajectory(batch.trajectory(b), one)
    assert batch.status[7] != "converged" and batch.steps[7] == 0 and np.isnan(batch.q[7, 1:]).all()
    assert batch.converged.sum() == B - 1 and all(e is None for e in batch.errors)
    assert (batch.iterations[7, 1:] == -1).all() and np.isnan(batch.residuals[7, 1:]).all()
    single = integ.rollout_batch(Q, 40, qdot0s=V, u=U, threads=1)
    for f in ("q", "p", "control_points", "iterations", "residuals", "factorizations", "steps", "status"):
        np.testing.assert_array_equal(getattr(single, f), getattr(batch, f))


def test_momenta_controls_held_and_shared(pendulum_batch):
    integ, Q, V, U = pendulum_batch
    P = np.array([integ.momentum(q, v) for q, v in zip(Q[:10], V[:10])])
    held = U[:10, :, 0]
    batch = integ.rollout_batch(Q[:10], 40, p0s=P, u=held, threads=2)
    shared = integ.rollout_batch(Q[:10], 40, p0s=P, u=np.broadcast_to(U[0, :, 0], (10, 40, 2)))
    constant = integ.rollout_batch(Q[:10], 40, p0s=P, u=U[:10, 0, 0])
    for b in range(10):
        assert_same_trajectory(batch.trajectory(b), integ.rollout(Q[b], 40, p0=P[b], u=held[b], raise_on_failure=False))
        assert_same_trajectory(shared.trajectory(b), integ.rollout(Q[b], 40, p0=P[b], u=U[0, :, 0], raise_on_failure=False))
        assert_same_trajectory(constant.trajectory(b), integ.rollout(Q[b], 40, p0=P[b], u=U[b, 0, 0], raise_on_failure=False))
    at_rest = integ.rollout_batch(Q[:3], 5)
    assert_same_trajectory(at_rest.trajectory(1), integ.rollout(Q[1], 5, u=np.zeros(2)))
    empty = integ.rollout_batch(Q[:3], 0)
    assert empty.q.shape == (3, 1, 5) and list(empty.status) == ["converged"] * 3


def test_constrained_rollouts_and_steps():
    integ = hovi.Integrator(fourbar(), s=2, dt=0.01)
    Q, V = [], []
    for k, crank in enumerate(np.linspace(-1.4, -1.0, 8)):
        q, qd = integ.project(np.array([crank, 0.9, -1.8]), np.array([1.0 + 0.2 * k, 0, 0]))
        Q.append(q)
        V.append(qd)
    Q, V = np.array(Q), np.array(V)
    batch = integ.rollout_batch(Q, 30, qdot0s=V, threads=2)
    assert batch.multipliers.shape == (8, 30, 2, 2)
    steps = integ.step_batch(Q, qdots=V, threads=2)
    for b in range(8):
        assert_same_trajectory(batch.trajectory(b), integ.rollout(Q[b], 30, qdot0=V[b]))
        q_next, p_next, info = integ.step(Q[b], integ.momentum(Q[b], V[b]))
        assert np.array_equal(steps.q_next[b], q_next) and np.array_equal(steps.p_next[b], p_next)
        assert np.array_equal(steps.info(b).multipliers, info.multipliers)
    bad = Q.copy()
    bad[3, 0] += 0.1
    with pytest.raises(ValueError, match="state 3 of the batch: the initial configuration violates"):
        integ.rollout_batch(bad, 5)
    lin = hovi.Linearizer(integ)
    jac = lin.rollout_jacobians_batch(batch, threads=2)
    for b in range(8):
        A, Bm = lin.rollout_jacobians(batch.trajectory(b))
        assert np.array_equal(jac.A[b], A) and np.array_equal(jac.B[b], Bm)


def test_steps_are_the_single_steps(pendulum_batch):
    integ, Q, V, U = pendulum_batch
    batch = integ.step_batch(Q, u=U[:, 0], qdots=V, threads=2)
    assert batch.q_next.shape == (B, 5) and batch.control_points.shape == (B, 3, 5) and len(batch) == B
    for b in range(B):
        q_next, p_next, info = integ.step(Q[b], integ.momentum(Q[b], V[b]), U[b, 0], raise_on_failure=False)
        assert np.array_equal(batch.q_next[b], q_next) and np.array_equal(batch.p_next[b], p_next)
        mine = batch.info(b)
        for f in dataclasses.fields(info):
            x, y = getattr(mine, f.name), getattr(info, f.name)
            assert (x is None and y is None) or np.array_equal(x, y), (b, f.name)
    held = integ.step_batch(Q[:5], V[:5], U[:5, 0, 0])
    assert np.array_equal(held.q_next[2], integ.step(Q[2], V[2], U[2, 0, 0], raise_on_failure=False)[0])


def test_linearisations_are_the_single_ones(pendulum_batch):
    integ, Q, V, U = pendulum_batch
    lin = hovi.Linearizer(integ)
    batch = integ.rollout_batch(Q[:20], 40, qdot0s=V[:20], u=U[:20])
    jac = lin.rollout_jacobians_batch(batch, U[:20], threads=2, hold=True)
    assert jac.A.shape == (20, 40, 10, 10) and jac.B.shape == (20, 40, 10, 2)
    assert not jac.ok[7] and "did not converge" in jac.errors[7] and np.isnan(jac.A[7]).all()
    for b in (0, 5, 19):
        A, Bm = lin.rollout_jacobians(batch.trajectory(b), U[b], hold=True)
        assert np.array_equal(jac.A[b], A) and np.array_equal(jac.B[b], Bm)
    only_a = lin.rollout_jacobians_batch(batch, U[:20], B=False)
    assert only_a.B is None and np.array_equal(only_a.A, jac.A, equal_nan=True)


def test_one_step_study_threads():
    model = hovi.examples.models.pendulum(8)
    rng = np.random.default_rng(3)
    q0, qd0 = rng.uniform(-np.pi / 2, np.pi / 2, (2, B, 8))
    one = hovi.baselines.one_step_batch(model, 0.05, q0, qd0, "newton+continuation", threads=1)
    two = hovi.baselines.one_step_batch(model, 0.05, q0, qd0, "newton+continuation", threads=2)
    for key in one:
        if key != "seconds":
            np.testing.assert_array_equal(one[key], two[key], err_msg=key)
    assert one["errors"] == [None] * B


def test_thread_count_from_the_environment(pendulum_batch, monkeypatch):
    integ, Q, V, _ = pendulum_batch
    monkeypatch.setenv("HOVI_NUM_THREADS", "2")
    assert integ.rollout_batch(Q[:4], 3).steps.tolist() == [3] * 4
    monkeypatch.setenv("HOVI_NUM_THREADS", "many")
    with pytest.raises(ValueError, match="HOVI_NUM_THREADS must be a positive integer, got 'many'"):
        integ.rollout_batch(Q[:4], 3)
    assert integ.rollout_batch(Q[:4], 3, threads=1).steps.tolist() == [3] * 4  # an argument wins


@pytest.mark.parametrize("call,match", [
    (lambda i, Q: i.rollout_batch(Q[0], 3), r"q0s must be a 2-D array of shape \(B, 5\)"),
    (lambda i, Q: i.rollout_batch(Q[:, :4], 3), r"q0s must be a 2-D array of shape \(B, 5\)"),
    (lambda i, Q: i.rollout_batch(Q[:0], 3), "the batch is empty"),
    (lambda i, Q: i.rollout_batch(Q, 3, qdot0s=Q[:3]), "qdot0s must have shape"),
    (lambda i, Q: i.rollout_batch(Q, 3, qdot0s=Q, p0s=Q), "give p0s or qdot0s, not both"),
    (lambda i, Q: i.rollout_batch(np.where(Q > 0.5, np.nan, Q), 3), "q0s contains NaN or infinity"),
    (lambda i, Q: i.rollout_batch(Q, 3, qdot0s=np.full(Q.shape, np.inf)), "qdot0s contains NaN or infinity"),
    (lambda i, Q: i.rollout_batch(Q, -1), "steps must be non-negative"),
    (lambda i, Q: i.rollout_batch(Q, 3, u=np.zeros((3, 2))), r"u must have shape \(10, 2\)"),
    (lambda i, Q: i.rollout_batch(Q, 3, u=np.full((10, 2), np.nan)), "u contains NaN"),
    (lambda i, Q: i.rollout_batch(Q, 3, threads=0), "threads must be a positive integer"),
    (lambda i, Q: i.rollout_batch(Q, 3, threads=-2), "threads must be a positive integer"),
    (lambda i, Q: i.rollout_batch(Q, 3, threads=True), "threads must be a positive integer or None"),
    (lambda i, Q: i.rollout_batch(Q, 3, threads=1.5), "threads must be a positive integer or None"),
    (lambda i, Q: i.step_batch(Q[:0]), "the batch is empty"),
    (lambda i, Q: i.step_batch(Q, u=np.zeros((10, 4, 2))), r"u must have shape \(10, 2\) or \(10, 3, 2\)"),
    (lambda i, Q: i.step_batch(Q, Q, threads=0), "threads must be a positive integer"),
    (lambda i, Q: hovi.baselines.one_step_batch(i.model, 0.01, Q, Q, "newton", threads=0), "threads must be"),
])
def test_bad_input_raises(call, match):
    integ = hovi.Integrator(forced_pendulum(), s=2, dt=0.01)
    with pytest.raises(ValueError, match=match):
        call(integ, np.random.default_rng(1).uniform(-1, 1, (10, 5)))


@pytest.mark.parametrize("check,call", [
    (lambda i, Q: i.check_rollout_batch(Q[:0], 3), lambda i, Q: i.rollout_batch(Q[:0], 3)),
    (lambda i, Q: i.check_rollout_batch(Q, 3, qdot0s=Q[:3]), lambda i, Q: i.rollout_batch(Q, 3, qdot0s=Q[:3])),
    (lambda i, Q: i.check_rollout_batch(Q, 3, u=np.zeros((3, 2))), lambda i, Q: i.rollout_batch(Q, 3, u=np.zeros((3, 2)))),
    (lambda i, Q: i.check_step_batch(Q, u=np.zeros((10, 4, 2))), lambda i, Q: i.step_batch(Q, u=np.zeros((10, 4, 2)))),
    (lambda i, Q: i.controls_per_point(np.zeros(3), 4), lambda i, Q: i.rollout(Q[0], 4, u=np.zeros(3))),
])
def test_inputs_are_checked_without_computing(check, call):
    integ = hovi.Integrator(forced_pendulum(), s=2, dt=0.01)
    Q = np.random.default_rng(1).uniform(-1, 1, (10, 5))
    with pytest.raises(ValueError) as expected:
        call(integ, Q)
    with pytest.raises(ValueError, match=re.escape(str(expected.value))):
        check(integ, Q)


def test_controls_per_point():
    integ = hovi.Integrator(forced_pendulum(), s=2, dt=0.01)
    u = np.arange(8.0).reshape(4, 2)
    U = integ.controls_per_point(u, 4)
    assert U.shape == (4, 3, 2) and (U == u[:, None, :]).all() and integ.controls_per_point(None, 4) is None
    assert integ.controls_per_point(np.ones((3, 2)), 4, batch=3).shape == (3, 4, 3, 2)
    assert integ.check_rollout_batch(np.zeros((2, 5)), 4, u=np.zeros((2, 4, 2))) is None


def test_numpy_integer_thread_count(pendulum_batch):
    integ, Q, _, _ = pendulum_batch
    assert integ.step_batch(Q[:3], threads=np.int64(2)).converged.all()


def test_batches_concatenate(pendulum_batch):
    integ, Q, V, U = pendulum_batch
    whole = integ.rollout_batch(Q[:9], 10, qdot0s=V[:9], u=U[:9, :10])
    parts = [integ.rollout_batch(Q[i:i + 3], 10, qdot0s=V[i:i + 3], u=U[i:i + 3, :10]) for i in (0, 3, 6)]
    joined = hovi.TrajectoryBatch.concatenate(parts)
    for b in range(9):
        assert_same_trajectory(joined.trajectory(b), whole.trajectory(b))
    with pytest.raises(ValueError, match="nothing to concatenate"):
        hovi.StepBatch.concatenate([])
