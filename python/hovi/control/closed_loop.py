"""Closed-loop runs in C++: a Policy applied inside the step loop (no Python per step), with control
saturation, pushes (impulses or short forces on bodies) and a plant that may differ from the model
the policy was made on (``Model.scale_mass``, other lengths: model mismatch); with contacts when
the plant has them; many runs at once on C++ threads for Monte-Carlo studies."""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Any, List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .. import _core
from .._checks import real_array, real_number, step_count, whole_number
from .._typing import FloatArray
from ..integrator import Integrator, check_trajectory_memory
from ..trajectory import Trajectory
from .policy import Policy


@dataclass(frozen=True)
class Push:
    """A push on a body: the world impulse ``impulse`` (3,) (N s) at ``point`` (3,) in the body's
    joint frame (default its origin) and the world angular impulse ``angular`` (3,) (N m s) on the
    body (together a wrench impulse), at time ``time`` (s; applied at the first knot at or after it).
    With ``duration`` > 0 it is a constant wrench (impulse, angular) / duration over
    [time, time + duration), applied as equal impulses at the knots in that interval."""
    time: float
    body: Union[int, str]
    impulse: Sequence[float]
    point: Sequence[float] = (0.0, 0.0, 0.0)
    duration: float = 0.0
    angular: Sequence[float] = (0.0, 0.0, 0.0)

    def knots(self, model: Any, dt: float, steps: Optional[int] = None
              ) -> list[tuple[int, int, FloatArray, FloatArray, FloatArray]]:
        """The push as (step, body index, point, impulse, angular impulse) at the knots of a step dt
        (only those before step ``steps`` when given: what a run of that many steps applies)."""
        t = real_number(self.time, "Push time", minimum=0.0)
        duration = real_number(self.duration, "Push duration", minimum=0.0)
        body = self.body
        if isinstance(body, str):
            try:
                body = model.body_index(body)
            except KeyError:
                raise ValueError(f"Push body: the model has no body named {self.body!r}") from None
        if isinstance(body, bool) or not isinstance(body, (int, np.integer)) or not 0 <= int(body) < model.n:
            raise ValueError(f"Push body must be a body index in [0, {model.n}) or a body name, got {self.body!r}")
        imp = real_array(self.impulse, "Push impulse", (3,))
        point = real_array(self.point, "Push point", (3,))
        angular = real_array(self.angular, "Push angular", (3,))
        start = t / dt - 1e-9
        if steps is not None and not start <= steps:  # after the run (or at an overflowing time): never applied
            return []
        first = int(math.ceil(start))
        count = max(1.0, float(np.rint(duration / dt))) if duration > 0 else 1.0  # inf: a push that never ends
        applied = count if steps is None else max(0.0, min(count, steps - first))
        return [(first + i, int(body), point, imp / count, angular / count) for i in range(int(applied))]


@dataclass
class ClosedLoop:
    """A closed-loop run: the plant's trajectory and the controls (K, s+1, m) the policy applied
    (saturated), step by step. The policy sees (q^k, p^k); with contacts p^k is the step's own momentum
    before its knot's impulse, ``trajectory.contact.step_momenta``.

    A run whose plant fails a step ends there: ``failure`` says which step and why (the step's status,
    e.g. 'max_iterations' of the Newton solve or 'lcp_failed' of a contact step, and its residual; the
    trajectory's ``status``, ``residuals`` and ``contact`` record hold the rest), ``u`` then has the
    failed step's controls last, and ``simulate`` warns (RuntimeWarning). None: every step ran."""
    trajectory: Trajectory
    u: FloatArray
    failure: Optional[str] = None

    @property
    def converged(self) -> bool:
        """Every step of the plant solved (a failed step ends the run: ``failure`` says why)."""
        return self.trajectory.converged

    def __repr__(self) -> str:
        how = "completed" if self.failure is None else f"FAILED at {self.failure}"
        return f"<ClosedLoop {self.trajectory.steps} steps, {how}>"


def failure_of(trajectory: Trajectory, plant: Integrator, steps: int) -> Optional[str]:
    """Why a run of ``plant`` asked for ``steps`` steps ended early (which step, the plant's status
    and residual there), or None when it ran them all."""
    if trajectory.steps == steps or not trajectory.status:
        return None
    k = trajectory.steps
    if trajectory.status[-1] == "controller_failed":
        return (f"step {k} of {steps} (t = {k * plant.dt:.6g} s): the controller gave no finite controls "
                "(controller_failed: e.g. feedback that overflowed on a state far from its reference)")
    return (f"step {k} of {steps} (t = {k * plant.dt:.6g} s): the plant's {plant.step_kind} failed "
            f"({trajectory.status[-1]}, residual {trajectory.residuals[-1]:.3e})")


def _plants(plants: Union[Integrator, Sequence[Integrator]], policy: Policy) -> List[Integrator]:
    items = [plants] if isinstance(plants, Integrator) else list(plants) if isinstance(plants, (list, tuple)) else []
    if not items:
        raise TypeError(f"plants must be a hovi.Integrator or a non-empty list of them, got {plants!r:.60}")
    for p in items:
        if not isinstance(p, Integrator):
            raise TypeError(f"a plant must be a hovi.Integrator, got {type(p).__name__}")
        if p.n != policy.n or p.nq != policy.nq or p.model.n_controls != policy.m or p.s != policy.s:
            raise ValueError(f"the plant (nq = {p.nq}, n = {p.n}, m = {p.model.n_controls}, s = {p.s}) does not fit the "
                             f"policy (nq = {policy.nq}, n = {policy.n}, m = {policy.m}, s = {policy.s})")
        if abs(p.dt - policy.dt) > 1e-12 * policy.dt:
            raise ValueError(f"the plant's dt ({p.dt:g}) is not the policy's ({policy.dt:g}): its gains are those of "
                             "steps of its dt; make the policy on an integrator of the plant's dt")
        if (p.contacts is None) != (items[0].contacts is None):
            raise ValueError("the plants must all have contacts, or none")
    return items


def push_list(pushes: Any, name: str = "pushes") -> List[Push]:
    """``pushes`` as a list of Push; TypeError naming ``name`` for anything else (a lone Push too)."""
    if isinstance(pushes, Push):
        raise TypeError(f"{name} must be a list of hovi.control.Push, got one Push: give [push]")
    items = list(pushes) if isinstance(pushes, (list, tuple)) else None
    if items is None or not all(isinstance(x, Push) for x in items):
        raise TypeError(f"{name} must be a list of hovi.control.Push, got {pushes!r:.80}")
    return items


def _push_lists(pushes: Any) -> List[List[Push]]:
    """simulate_batch's pushes: a list of lists of Push (one per run, or one for all)."""
    if not isinstance(pushes, (list, tuple)) or any(isinstance(x, Push) for x in pushes):
        got = "a flat list of Push" if isinstance(pushes, (list, tuple)) else f"{pushes!r:.60}"
        raise TypeError(f"pushes must be a list of lists of hovi.control.Push, one list per run (or one for every "
                        f"run: [pushes]), got {got}")
    return [push_list(p, f"pushes[{b}]") for b, p in enumerate(pushes)]


def run_steps(steps: Any) -> int:
    """A run's step count: a whole number, >= 1 and below 2^31 (the C++ loop's int)."""
    steps = step_count(steps)
    if steps == 0:
        raise ValueError("steps must be >= 1 (a run of 0 steps has nothing to simulate)")
    if steps >= 2**31:
        raise ValueError(f"steps must be < 2^31 (the C++ loop counts steps in an int), got {steps}")
    return steps


def _per_run(value: Any, name: str, B: int, n: int) -> FloatArray:
    """``value`` as (B, n): one state (n,) or (1, n) for every run, or one per run (B, n)."""
    a = real_array(value, name)
    return np.broadcast_to(a, (B, n)).copy() if a.shape in ((n,), (1, n)) else real_array(value, name, (B, n))


def _states(plants: List[Integrator], q0: Any, p0: Any, qdot0: Any, B: int) -> tuple[FloatArray, FloatArray]:
    """The runs' initial q (B, nq) and p (B, n); p from qdot0 (default rest) when p0 is not given."""
    n = plants[0].n
    if p0 is not None and qdot0 is not None:
        raise ValueError("give p0 or qdot0, not both")
    Q = _per_run(q0, "q0", B, plants[0].nq)
    if p0 is not None:
        return Q, _per_run(p0, "p0", B, n)
    V = np.zeros((B, n)) if qdot0 is None else _per_run(qdot0, "qdot0", B, n)
    return Q, np.array([plants[0 if len(plants) == 1 else b].momentum(Q[b], V[b]) for b in range(B)])


def _runs(plants: Union[Integrator, Sequence[Integrator]], policy: Policy, q0: npt.ArrayLike, steps: int,
          qdot0: Optional[npt.ArrayLike], p0: Optional[npt.ArrayLike], push_lists: List[List[Push]],
          runs: Optional[int], threads: Optional[int]) -> List[ClosedLoop]:
    """The closed-loop runs of ``simulate_batch`` (arguments checked here), failed ones flagged."""
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a hovi.control.Policy, got {type(policy).__name__}")
    items = _plants(plants, policy)
    q0s = real_array(q0, "q0")  # named errors for text, ragged lists, NaN
    B = whole_number(runs, "runs", minimum=1) if runs is not None else \
        max(len(items), len(push_lists), q0s.shape[0] if q0s.ndim == 2 else 1)
    if len(items) not in (1, B) or len(push_lists) not in (0, 1, B):
        raise ValueError(f"give one plant or {B}, and the pushes of one run or of {B}")
    steps = run_steps(steps)
    check_trajectory_memory(steps, items[0].s, items[0].n, B)
    Q, P = _states(items, q0, p0, qdot0, B)
    for b in range(B):
        items[0 if len(items) == 1 else b].check_start(Q[b], f"q0 (run {b})" if B > 1 else "q0")
    dt = items[0].dt
    knots = [[k for push in run for k in push.knots(items[0].model, dt, steps)] for run in push_lists]
    cores = [p.core for p in items]
    out, errors = _core.control.closed_loop(
        cores, policy.x_ref, policy.u_ref.reshape(policy.stages, -1), policy.gains, policy.lower, policy.upper, knots,
        Q, P, steps, threads)
    results = []
    for b, (res, err) in enumerate(zip(out, errors)):
        if err is not None:
            raise ValueError(f"closed-loop run {b}: {err}")
        plant = items[0 if len(items) == 1 else b]
        traj = plant.trajectory_of([res])
        results.append(ClosedLoop(traj, res["controls"].reshape(-1, policy.s + 1, policy.m),
                                  failure_of(traj, plant, steps)))
    return results


def simulate_batch(plants: Union[Integrator, Sequence[Integrator]], policy: Policy, q0: npt.ArrayLike, steps: int, *,
                   qdot0: Optional[npt.ArrayLike] = None, p0: Optional[npt.ArrayLike] = None,
                   pushes: Sequence[Sequence[Push]] = (), runs: Optional[int] = None,
                   threads: Optional[int] = None) -> List[ClosedLoop]:
    """``runs`` closed-loop runs of ``steps`` >= 1 steps in C++ on ``threads`` threads (GIL released).

    plants: one Integrator (the plant of every run) or one per run (e.g. each with another mass), each
    of the policy's n, m, s and dt; q0 and qdot0 (or p0): (n,) for all runs or (runs, n); pushes: a
    list of lists of Push, one for all runs or one per run. runs (>= 1) defaults to the longest of
    these. A run whose plant fails a step ends there, flagged (``ClosedLoop.failure``); one
    RuntimeWarning then says how many runs ended early."""
    results = _runs(plants, policy, q0, steps, qdot0, p0, _push_lists(pushes), runs, threads)
    failed = [(b, r.failure) for b, r in enumerate(results) if r.failure is not None]
    if failed:
        warnings.warn(f"{len(failed)} of {len(results)} closed-loop runs ended early (run {failed[0][0]}: at "
                      f"{failed[0][1]}); see ClosedLoop.failure", RuntimeWarning, stacklevel=2)
    return results


def simulate(plant: Integrator, policy: Policy, q0: npt.ArrayLike, steps: int, *, qdot0: Optional[npt.ArrayLike] = None,
             p0: Optional[npt.ArrayLike] = None, pushes: Sequence[Push] = ()) -> ClosedLoop:
    """One closed-loop run of ``steps`` >= 1 steps of ``plant`` (an Integrator of the policy's n, m, s
    and dt) under ``policy`` from q0 (n,) with qdot0 or p0 (default at rest) and ``pushes`` (a list of
    Push), in C++. If the plant fails a step the run ends there: the ClosedLoop is flagged (its
    ``failure``: which step and why) and a RuntimeWarning says so."""
    if not isinstance(plant, Integrator):
        raise TypeError(f"plant must be a hovi.Integrator, got {type(plant).__name__}")
    run = _runs(plant, policy, q0, steps, qdot0, p0, [push_list(pushes)], 1, 1)[0]
    if run.failure is not None:
        warnings.warn(f"the closed-loop run ended early, at {run.failure}; see ClosedLoop.failure", RuntimeWarning,
                      stacklevel=2)
    return run
