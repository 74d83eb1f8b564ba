"""Rollouts, one-step studies and trajectory optimisations mapped over a Dask cluster (the optional
dependency ``hovi[distributed]``, i.e. ``dask.distributed``).

Each function splits its items into chunks, one task each, runs every chunk on a worker with the
batched C++ call a single machine uses (``Integrator.rollout_batch``, ``Integrator.step_batch``,
``hovi.baselines.one_step_batch``; ``hovi.trajopt.solve`` for each problem) and gathers the
pieces into the same result as that local call, bit for bit: every item is computed by the same
code from the same inputs, wherever it runs. The integrator or model is sent to every worker once
(``Client.scatter``); it travels as a pickle, which holds the whole model.

``client``: a ``distributed.Client``, the address of a scheduler (``"tcp://host:8786"``), or None for
a ``LocalCluster`` of worker processes on this machine (one per core, one thread each), started for
the call and closed at its end; pass a Client to reuse one cluster for many calls.

Chunks: by default a task carries about ``SOLVES_PER_TASK`` solves (Newton solves of one step:
a rollout of K steps counts K), so that the scheduler's overhead per task is a few per cent of the
task's work (bench/README.md, "Many rollouts"), and no more items than give every worker thread a
chunk. ``chunk_size`` (items per task) overrides it. Inside a task the C++ batch runs on
``threads_per_task`` threads (default 1: the cluster's workers are the parallelism).
"""
from __future__ import annotations

import dataclasses
import importlib
import math
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any, Callable, Iterator, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from . import _core
from ._checks import step_count
from .batch import StepBatch, TrajectoryBatch
from .integrator import Integrator

if TYPE_CHECKING:
    from distributed import Client

    from .trajopt import Problem, Result, TranscriptionMethod

__all__ = ["rollout_batch", "step_batch", "one_step_batch", "solve_trajopt", "SOLVES_PER_TASK"]

# Solves a task carries by default: enough that the cost of a task beyond its solves stays at a few
# per cent (bench/README.md, "Many rollouts" and "Design measurements", distributed.py).
SOLVES_PER_TASK = 4000

ClientLike = Union["Client", str, None]
"""A ``distributed.Client``, a scheduler's address, or None (a LocalCluster for the call)."""


@contextmanager
def _connect(client: ClientLike) -> Iterator[Any]:
    """The given Client; a Client of the scheduler at an address; or a new LocalCluster of worker
    processes, closed (with its Client) when the block ends, whatever happens in it."""
    try:
        dd: Any = importlib.import_module("distributed")  # untyped: Any
    except ImportError as e:  # pragma: no cover - depends on the installation
        raise ImportError("hovi.distributed needs dask.distributed: pip install 'hovi[distributed]'") from e
    if isinstance(client, dd.Client):
        yield client
    elif isinstance(client, str):
        with dd.Client(client) as c:
            yield c
    elif client is None:
        with dd.LocalCluster(processes=True, threads_per_worker=1, dashboard_address=None) as cluster, \
                dd.Client(cluster) as c:
            yield c
    else:
        raise TypeError(f"client must be a distributed.Client, a scheduler address or None, got {type(client).__name__}")


def _chunks(count: int, solves_per_item: int, client: Any, chunk_size: Optional[int]) -> list[slice]:
    """Consecutive slices of ``count`` items, ``chunk_size`` each (default: see the module docstring)."""
    if chunk_size is None:
        threads = max(1, sum(client.nthreads().values()))
        chunk_size = min(max(1, math.ceil(SOLVES_PER_TASK / max(solves_per_item, 1))), math.ceil(count / threads))
    elif int(chunk_size) != chunk_size or chunk_size < 1:
        raise ValueError(f"chunk_size must be a positive integer, got {chunk_size}")
    size = int(chunk_size)
    return [slice(i, min(i + size, count)) for i in range(0, count, size)]


def _map(client: Any, task: Callable[..., Any], shared: Any, pieces: Sequence[tuple[Any, ...]]) -> list[Any]:
    """task(shared, *piece) for every piece on the cluster, results in the order of the pieces;
    ``shared`` is sent to every worker once."""
    on_workers = client.scatter(shared, broadcast=True, hash=False)
    futures = [client.submit(task, on_workers, *piece, pure=False) for piece in pieces]
    return list(client.gather(futures))


def _part(x: Optional[npt.ArrayLike], sl: slice) -> Optional[np.ndarray]:
    return None if x is None else np.asarray(x)[sl]


def _rollout_task(integrator: Integrator, q0s: np.ndarray, p0s: Optional[np.ndarray], qdot0s: Optional[np.ndarray],
                  steps: int, u: Optional[np.ndarray], threads: int) -> TrajectoryBatch:
    batch = integrator.rollout_batch(q0s, steps, p0s=p0s, qdot0s=qdot0s, u=u, threads=threads)
    return dataclasses.replace(batch, discretization=None)  # the client has it


def rollout_batch(integrator: Integrator, q0s: npt.ArrayLike, steps: int, *, p0s: Optional[npt.ArrayLike] = None,
                  qdot0s: Optional[npt.ArrayLike] = None, u: Optional[npt.ArrayLike] = None,
                  client: ClientLike = None, chunk_size: Optional[int] = None,
                  threads_per_task: int = 1) -> TrajectoryBatch:
    """``integrator.rollout_batch(q0s, steps, p0s=..., qdot0s=..., u=...)`` on a Dask cluster: q0s (B, n),
    p0s or qdot0s (B, n), u per state as rollout_batch takes it; the same TrajectoryBatch, bit for
    bit. The input is checked here, before anything is sent."""
    integrator.check_rollout_batch(q0s, steps, p0s=p0s, qdot0s=qdot0s, u=u)
    steps = step_count(steps)
    Q = np.asarray(q0s, dtype=float)
    with _connect(client) as c:
        parts = _map(c, _rollout_task, integrator,
                     [(Q[sl], _part(p0s, sl), _part(qdot0s, sl), steps, _part(u, sl), threads_per_task)
                      for sl in _chunks(len(Q), max(steps, 1), c, chunk_size)])
    return dataclasses.replace(TrajectoryBatch.concatenate(parts), discretization=integrator.discretization)


def _step_task(integrator: Integrator, qs: np.ndarray, ps: Optional[np.ndarray], qdots: Optional[np.ndarray],
               u: Optional[np.ndarray], threads: int) -> StepBatch:
    return integrator.step_batch(qs, ps, u, qdots=qdots, threads=threads)


def step_batch(integrator: Integrator, qs: npt.ArrayLike, ps: Optional[npt.ArrayLike] = None,
               u: Optional[npt.ArrayLike] = None, *, qdots: Optional[npt.ArrayLike] = None, client: ClientLike = None,
               chunk_size: Optional[int] = None, threads_per_task: int = 1) -> StepBatch:
    """``integrator.step_batch(qs, ps, u, qdots=...)`` on a Dask cluster: qs (B, n), ps or qdots (B, n),
    u (B, m) or (B, s+1, m); the same StepBatch, bit for bit."""
    integrator.check_step_batch(qs, ps, u, qdots=qdots)
    Q = np.asarray(qs, dtype=float)
    with _connect(client) as c:
        parts = _map(c, _step_task, integrator,
                     [(Q[sl], _part(ps, sl), _part(qdots, sl), _part(u, sl), threads_per_task)
                      for sl in _chunks(len(Q), 1, c, chunk_size)])
    return StepBatch.concatenate(parts)


def _one_step_task(model: _core.Model, dt: float, q0: np.ndarray, qdot0: np.ndarray, method: str, tol: float,
                   max_iterations: int, threads: int) -> dict[str, Any]:
    from . import baselines  # on the worker: the baselines extension, an optional part of the install
    result: dict[str, Any] = baselines.one_step_batch(model, dt, q0, qdot0, method, tol, max_iterations, threads)
    return result


def one_step_batch(model: _core.Model, dt: float, q0: npt.ArrayLike, qdot0: npt.ArrayLike, method: str, *,
                   tol: float = 1e-10, max_iterations: int = 100, client: ClientLike = None,
                   chunk_size: Optional[int] = None, threads_per_task: int = 1) -> dict[str, Any]:
    """``hovi.baselines.one_step_batch`` (the one-step study of bench/fig2_quasi_newton.py) on a Dask
    cluster: one trapezoidal step from every state, q0 and qdot0 (N, n); the same dict of per-state
    arrays (N,) and lists, bit for bit (the times per solve are those measured on the workers)."""
    Q, QD = _core.real_array(q0, "q0"), _core.real_array(qdot0, "qdot0")  # complex, text, object refused
    if Q.ndim != 2 or Q.shape[1] != model.n or QD.shape != Q.shape:
        raise ValueError(f"q0 and qdot0 must be two arrays of shape (N, {model.n}), got {Q.shape} and {QD.shape}")
    with _connect(client) as c:
        parts = _map(c, _one_step_task, model,
                     [(dt, Q[sl], QD[sl], method, tol, max_iterations, threads_per_task)
                      for sl in _chunks(len(Q), 1, c, chunk_size)])
    return {key: sum((p[key] for p in parts), []) if isinstance(parts[0][key], list)
            else np.concatenate([p[key] for p in parts]) for key in parts[0]}


def _solve_task(problem: Problem, transcription: TranscriptionMethod, guess: Any,
                options: Optional[dict[str, Any]]) -> Result:
    from .trajopt import solve
    result = solve(problem, transcription, guess=guess, options=options, verbose=False)
    result.transcription = None  # C++ state that does not travel: the client makes it again
    return result


def solve_trajopt(problems: Sequence[Problem], transcription: Optional[TranscriptionMethod] = None, *,
                  guess: Any = None, options: Optional[dict[str, Any]] = None,
                  client: ClientLike = None) -> list[Result]:
    """``hovi.trajopt.solve(problem, transcription, guess=guess, options=options)`` for every problem
    (``transcription`` a ``hovi.trajopt.VI`` or ``HermiteSimpson``, default
    ``hovi.trajopt.DEFAULT_TRANSCRIPTION``),
    one task each (a trajectory optimisation is thousands of solves), on a Dask cluster; the
    Results in the order of the problems, as the local solves give them (their transcription made
    again here, so that ``replay`` and ``as_guess`` work)."""
    from .trajopt.transcriptions import DEFAULT_TRANSCRIPTION, transcription_method
    method = transcription_method(DEFAULT_TRANSCRIPTION if transcription is None else transcription)
    problems = list(problems)
    with _connect(client) as c:
        futures = [c.submit(_solve_task, p, method, guess, options, pure=False) for p in problems]
        results: list[Result] = list(c.gather(futures))
    for problem, result in zip(problems, results):
        result.transcription = method.transcribe(problem)
    return results
