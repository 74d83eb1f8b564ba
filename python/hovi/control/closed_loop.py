"""Closed-loop runs in C++: a Policy applied inside the step loop (no Python per step), with control
saturation, pushes (impulses or short forces on bodies) and a plant that may differ from the model
the policy was made on (``Model.scale_mass``, other lengths: model mismatch); with contacts when
the plant has them; many runs at once on C++ threads for Monte-Carlo studies."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, List, Optional, Sequence, Union

import numpy as np
import numpy.typing as npt

from .. import _core
from .._checks import real_array, real_number, step_count
from .._typing import FloatArray
from ..integrator import Integrator
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

    def knots(self, model: Any, dt: float) -> list[tuple[int, int, FloatArray, FloatArray, FloatArray]]:
        """The push as (step, body index, point, impulse, angular impulse) at the knots of a step dt."""
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
        first = int(math.ceil(t / dt - 1e-9))
        count = max(1, int(round(duration / dt))) if duration > 0 else 1
        return [(first + i, int(body), point, imp / count, angular / count) for i in range(count)]


@dataclass
class ClosedLoop:
    """A closed-loop run: the plant's trajectory and the controls (K, s+1, m) the policy applied
    (saturated), step by step. The policy sees (q^k, p^k); with contacts p^k is the step's own momentum
    before its knot's impulse, ``trajectory.contact.step_momenta``."""
    trajectory: Trajectory
    u: FloatArray

    @property
    def converged(self) -> bool:
        """Every step of the plant solved (a failed step ends the run)."""
        return self.trajectory.converged


def _plants(plants: Union[Integrator, Sequence[Integrator]], policy: Policy) -> List[Integrator]:
    items = [plants] if isinstance(plants, Integrator) else list(plants)
    if not items:
        raise ValueError("give a plant (a hovi.Integrator)")
    for p in items:
        if not isinstance(p, Integrator):
            raise TypeError(f"a plant must be a hovi.Integrator, got {type(p).__name__}")
        if p.n != policy.n or p.model.n_controls != policy.m or p.s != policy.s:
            raise ValueError(f"the plant (n = {p.n}, m = {p.model.n_controls}, s = {p.s}) does not fit the policy "
                             f"(n = {policy.n}, m = {policy.m}, s = {policy.s})")
        if (p.contacts is None) != (items[0].contacts is None):
            raise ValueError("the plants must all have contacts, or none")
    return items


def _per_run(value: Any, name: str, B: int, n: int) -> FloatArray:
    """``value`` as (B, n): one state (n,) or (1, n) for every run, or one per run (B, n)."""
    a = real_array(value, name)
    return np.broadcast_to(a, (B, n)).copy() if a.shape in ((n,), (1, n)) else real_array(value, name, (B, n))


def _states(plants: List[Integrator], q0: Any, p0: Any, qdot0: Any, B: int) -> tuple[FloatArray, FloatArray]:
    """The runs' initial (q, p), each (B, n); p from qdot0 (default rest) when p0 is not given."""
    n = plants[0].n
    if p0 is not None and qdot0 is not None:
        raise ValueError("give p0 or qdot0, not both")
    Q = _per_run(q0, "q0", B, n)
    if p0 is not None:
        return Q, _per_run(p0, "p0", B, n)
    V = np.zeros((B, n)) if qdot0 is None else _per_run(qdot0, "qdot0", B, n)
    return Q, np.array([plants[0 if len(plants) == 1 else b].momentum(Q[b], V[b]) for b in range(B)])


def simulate_batch(plants: Union[Integrator, Sequence[Integrator]], policy: Policy, q0: npt.ArrayLike, steps: int, *,
                   qdot0: Optional[npt.ArrayLike] = None, p0: Optional[npt.ArrayLike] = None,
                   pushes: Sequence[Sequence[Push]] = (), runs: Optional[int] = None,
                   threads: Optional[int] = None) -> List[ClosedLoop]:
    """``runs`` closed-loop runs of ``steps`` steps in C++ on ``threads`` threads (GIL released).

    plants: one Integrator (the plant of every run) or one per run (e.g. each with another mass);
    q0 and qdot0 (or p0): (n,) for all runs or (runs, n); pushes: one list of Push for all runs, or one
    per run. runs defaults to the longest of these. A run whose plant fails a step ends there
    (``ClosedLoop.converged`` False)."""
    if not isinstance(policy, Policy):
        raise TypeError(f"policy must be a hovi.control.Policy, got {type(policy).__name__}")
    items = _plants(plants, policy)
    push_lists = [list(p) for p in pushes]
    if push_lists and not all(isinstance(x, Push) for p in push_lists for x in p):
        raise TypeError("pushes must be lists of hovi.control.Push, one per run (or one for all)")
    q0s = real_array(q0, "q0")  # named errors for text, ragged lists, NaN
    B = runs if runs is not None else max(len(items), len(push_lists), q0s.shape[0] if q0s.ndim == 2 else 1)
    if len(items) not in (1, B) or len(push_lists) not in (0, 1, B):
        raise ValueError(f"give one plant or {B}, and the pushes of one run or of {B}")
    steps = step_count(steps)
    Q, P = _states(items, q0, p0, qdot0, B)
    dt = items[0].dt
    knots = [[k for push in run for k in push.knots(items[0].model, dt)] for run in push_lists]
    cores = [p.core for p in items]
    out, errors = _core.control.closed_loop(
        cores, policy.x_ref, policy.u_ref.reshape(policy.stages, -1), policy.gains, policy.lower, policy.upper, knots,
        Q, P, steps, threads)
    results = []
    for b, (res, err) in enumerate(zip(out, errors)):
        if err is not None:
            raise ValueError(f"closed-loop run {b}: {err}")
        plant = items[0 if len(items) == 1 else b]
        results.append(ClosedLoop(plant.trajectory_of([res]), res["controls"].reshape(-1, policy.s + 1, policy.m)))
    return results


def simulate(plant: Integrator, policy: Policy, q0: npt.ArrayLike, steps: int, *, qdot0: Optional[npt.ArrayLike] = None,
             p0: Optional[npt.ArrayLike] = None, pushes: Sequence[Push] = ()) -> ClosedLoop:
    """One closed-loop run of ``steps`` steps of ``plant`` under ``policy`` from q0 (n,) with qdot0 or
    p0 (default at rest) and ``pushes``, in C++."""
    return simulate_batch(plant, policy, q0, steps, qdot0=qdot0, p0=p0, pushes=[list(pushes)], runs=1, threads=1)[0]
