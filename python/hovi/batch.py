"""The results of the batched calls (``Integrator.rollout_batch``, ``Integrator.step_batch``,
``Linearizer.rollout_jacobians_batch``): B items computed in C++ on several threads, stacked along
a leading axis of length B, with a status per item (one failed item does not fail the batch).
``hovi.distributed`` gathers the pieces computed on a cluster into the same classes."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, List, Optional, Sequence, Type, TypeVar

import numpy as np

from ._typing import BoolArray, FloatArray, IntArray
from .trajectory import ContactRecord, Discretization, StepInfo, Trajectory

_Batch = TypeVar("_Batch", "TrajectoryBatch", "StepBatch", "JacobianBatch")


def _concatenate(cls: Type[_Batch], parts: Sequence[_Batch], shared: tuple[str, ...] = ()) -> _Batch:
    """One batch of ``cls`` from consecutive pieces: arrays joined along their first axis, lists
    added; the ``shared`` fields (the same in every piece) taken from the first."""
    if not parts:
        raise ValueError("nothing to concatenate: no batches given")
    joined: dict[str, Any] = {}
    for f in dataclasses.fields(cls):
        values = [getattr(p, f.name) for p in parts]
        if f.name in shared or values[0] is None:
            joined[f.name] = values[0]
        elif isinstance(values[0], list):
            joined[f.name] = sum(values, [])
        elif isinstance(values[0], ContactRecord):
            joined[f.name] = ContactRecord(np.concatenate([v.impulses for v in values]),
                                           np.concatenate([v.gaps for v in values]), values[0].directions,
                                           np.concatenate([v.pivots for v in values]),
                                           None if values[0].impact is None else
                                           np.concatenate([v.impact for v in values]),
                                           added_energy=None if values[0].added_energy is None else
                                           np.concatenate([v.added_energy for v in values]))
        else:
            joined[f.name] = np.concatenate(values)
    return cls(**joined)


@dataclass
class TrajectoryBatch:
    """B rollouts of K steps from B initial states (``Integrator.rollout_batch``), stacked: t (K+1,),
    q and p (B, K+1, n), control_points (B, K, s+1, n), multipliers (B, K, s, n_constraints) of a
    constrained model, and per step iterations, factorizations (-1 where no step was attempted)
    and residuals (NaN there), (B, K). An item whose solve failed at step k stops there: its rows
    after q[b, k] are NaN, ``steps[b]`` = k and ``status[b]`` says why. ``trajectory(b)`` is item b
    as a Trajectory, identical to what ``Integrator.rollout`` returns for it (with the same
    ``discretization``)."""
    t: FloatArray                # (K+1,)
    q: FloatArray                # (B, K+1, n)
    p: FloatArray                # (B, K+1, n)
    control_points: FloatArray   # (B, K, s+1, n)
    iterations: IntArray         # (B, K) Newton iterations per step, -1 where not attempted
    residuals: FloatArray        # (B, K) final ||r||_inf per step, NaN where not attempted
    factorizations: IntArray     # (B, K) Jacobian factorisations per step, -1 where not attempted
    steps: IntArray              # (B,) steps completed
    status: List[str] = field(default_factory=list)  # (B,) 'converged' (every step), a failed step's status, or 'error'
    errors: List[Optional[str]] = field(default_factory=list)  # (B,) the message of an exception an item raised, or None
    multipliers: Optional[FloatArray] = None  # (B, K, s, n_constraints), constrained models
    solve_seconds: Optional[FloatArray] = None  # (B,) time of each item's rollout in C++
    discretization: Optional[Discretization] = field(default=None, repr=False)  # the integrator's model, s and dt
    contact: Optional[ContactRecord] = None  # with contacts: impulses (B, K, C, 2+d), gaps (B, K, C) and impact
                                             # (B, K), NaN where not reached; pivots (B, K), -1 there
    controls: Optional[FloatArray] = None  # (B, K, s+1, m): each item's controls at the control points (m > 0)

    def __len__(self) -> int:
        return len(self.status)

    @property
    def converged(self) -> BoolArray:
        """(B,) whether every step of each item converged."""
        return np.array([s == "converged" for s in self.status], dtype=bool)

    def trajectory(self, b: int) -> Trajectory:
        """Item b as a Trajectory (what ``Integrator.rollout(..., raise_on_failure=False)`` returns
        for its initial state, bit for bit); ValueError for an item that raised an exception."""
        if self.errors[b] is not None:
            raise ValueError(f"item {b} of the batch raised an exception: {self.errors[b]}")
        k = int(self.steps[b])
        attempted = k + (self.status[b] != "converged")
        return Trajectory(t=self.t[:k + 1].copy(), q=self.q[b, :k + 1].copy(), p=self.p[b, :k + 1].copy(),
                          control_points=self.control_points[b, :k].copy(),
                          iterations=self.iterations[b, :attempted].copy(), residuals=self.residuals[b, :attempted].copy(),
                          factorizations=self.factorizations[b, :attempted].copy(),
                          status=["converged"] * k + ([self.status[b]] if attempted > k else []),
                          multipliers=None if self.multipliers is None else self.multipliers[b, :k].copy(),
                          solve_seconds=float(self.solve_seconds[b]) if self.solve_seconds is not None else 0.0,
                          discretization=self.discretization,
                          contact=None if self.contact is None else ContactRecord(
                              self.contact.impulses[b, :k].copy(), self.contact.gaps[b, :k].copy(),
                              self.contact.directions, self.contact.pivots[b, :attempted].copy(),
                              None if self.contact.impact is None else self.contact.impact[b, :k].copy(),
                              added_energy=None if self.contact.added_energy is None else
                              self.contact.added_energy[b, :k].copy()),
                          controls=None if self.controls is None else self.controls[b, :k].copy())

    @classmethod
    def concatenate(cls, parts: Sequence[TrajectoryBatch]) -> TrajectoryBatch:
        """One batch from consecutive pieces (of the same integrator and number of steps)."""
        return _concatenate(cls, parts, shared=("t", "discretization"))


@dataclass
class StepBatch:
    """One step from each of B states (``Integrator.step_batch``): q_next, p_next (B, n),
    control_points (B, s+1, n) (the last iterate where a solve failed), multipliers
    (B, s, n_constraints) of a constrained model, and per item converged, status, iterations,
    factorizations, residual_evaluations, residuals, errors and solve_seconds, (B,). ``info(b)`` is
    item b's StepInfo, identical to what ``Integrator.step`` returns for it."""
    q_next: FloatArray          # (B, n)
    p_next: FloatArray          # (B, n)
    control_points: FloatArray  # (B, s+1, n)
    converged: BoolArray   # (B,)
    iterations: IntArray        # (B,)
    factorizations: IntArray    # (B,)
    residual_evaluations: IntArray  # (B,)
    residuals: FloatArray       # (B,) ||r||_inf at exit
    status: List[str] = field(default_factory=list)  # (B,) as StepInfo.status, or 'error'
    errors: List[Optional[str]] = field(default_factory=list)  # (B,) the message of an exception an item raised, or None
    multipliers: Optional[FloatArray] = None  # (B, s, n_constraints), constrained models
    solve_seconds: Optional[FloatArray] = None  # (B,) time of each item's step in C++
    impulses: Optional[FloatArray] = None  # (B, C, 2 + d) with contacts
    gaps: Optional[FloatArray] = None      # (B, C) with contacts
    pivots: Optional[IntArray] = None      # (B,) with contacts

    def __len__(self) -> int:
        return len(self.status)

    def info(self, b: int) -> StepInfo:
        """Item b's StepInfo (what ``Integrator.step(..., raise_on_failure=False)`` returns);
        ValueError for an item that raised an exception."""
        if self.errors[b] is not None:
            raise ValueError(f"item {b} of the batch raised an exception: {self.errors[b]}")
        return StepInfo(status=self.status[b], converged=bool(self.converged[b]), iterations=int(self.iterations[b]),
                        factorizations=int(self.factorizations[b]),
                        residual_evaluations=int(self.residual_evaluations[b]), residual=float(self.residuals[b]),
                        control_points=self.control_points[b].copy(),
                        multipliers=None if self.multipliers is None else self.multipliers[b].copy(),
                        impulses=None if self.impulses is None else self.impulses[b].copy(),
                        gaps=None if self.gaps is None else self.gaps[b].copy(),
                        pivots=0 if self.pivots is None else int(self.pivots[b]))

    @classmethod
    def concatenate(cls, parts: Sequence[StepBatch]) -> StepBatch:
        """One batch from consecutive pieces."""
        return _concatenate(cls, parts)


@dataclass
class JacobianBatch:
    """The step Jacobians along every trajectory of a TrajectoryBatch
    (``Linearizer.rollout_jacobians_batch``): A (B, K, 2n, 2n) and B (B, K, 2n, (s+1) m), or
    (B, K, 2n, m) for held controls; None for what was not asked for. Items that were not
    linearised (their rollout did not complete, or a step's DEL Jacobian is singular) are NaN and
    ``errors[b]`` says why."""
    A: Optional[FloatArray]     # (B, K, 2n, 2n)
    B: Optional[FloatArray]     # (B, K, 2n, (s+1) m) or (B, K, 2n, m)
    errors: List[Optional[str]] = field(default_factory=list)  # (B,) None where the item was linearised

    def __len__(self) -> int:
        return len(self.errors)

    @property
    def ok(self) -> BoolArray:
        """(B,) whether each item was linearised."""
        return np.array([e is None for e in self.errors], dtype=bool)

    @classmethod
    def concatenate(cls, parts: Sequence[JacobianBatch]) -> JacobianBatch:
        """One batch from consecutive pieces."""
        return _concatenate(cls, parts)
