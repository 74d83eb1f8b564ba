"""Linearisation of the Galerkin integrator (paper Section 4): the Pythonic layer over
hovi._core.Linearizer."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

import numpy as np
import numpy.typing as npt

from . import _core
from ._checks import real_number
from ._typing import FloatArray
from .batch import JacobianBatch, TrajectoryBatch
from .integrator import ConvergenceError, Integrator
from .trajectory import Trajectory


@dataclass
class DelJacobian:
    """The Jacobian of the DEL equations at control points q^{k,0..s}.

    Rows are stacked in blocks of n: blocks 0..s-1 are the residuals r^{k,a} and block s is the
    momentum p^{k+1}. ``dq`` has column blocks q^{k,0..s}; ``du`` has column blocks u^{k,0..s}
    (m columns each); d r^{k,0}/d p^k is the identity and no other row depends on p^k.
    ``blocks()`` views ``dq`` as (s+1, s+1, n, n).
    """
    dq: FloatArray                      # ((s+1) n, (s+1) n)
    du: Optional[FloatArray]            # ((s+1) n, (s+1) m)
    s: int
    n: int
    dlambda: Optional[FloatArray] = None  # constrained: d(rows)/dλ^{k,0..s-1}, ((s+1) n, s m_c)
    dh: Optional[FloatArray] = None       # constrained: dh(q^{k,1..s})/dq^{k,0..s}, (s m_c, (s+1) n)

    def blocks(self) -> FloatArray:
        """``dq`` as (s+1, s+1, n, n) blocks: [a, b] = d(row block a)/dq^{k,b}."""
        S1, n = self.s + 1, self.n
        blocks: FloatArray = self.dq.reshape(S1, n, S1, n).transpose(0, 2, 1, 3)
        return blocks


@dataclass
class StepLinearization:
    """One converged step and its Jacobians. State ordering x = (q, p).

    A = d(q^{k+1}, p^{k+1}) / d(q^k, p^k), (2n, 2n). On a model with a free base the state is in tangent
    coordinates, (q ⊖ q_ref, p - p_ref) with ⊖ ``Model.difference``.
    B = d(q^{k+1}, p^{k+1}) / du: (2n, (s+1) m) with column block a for u^{k,a}, or (2n, m) for a
    control held over the step (hold=True, the sum of the blocks).
    """
    q_next: FloatArray          # (n,)
    p_next: FloatArray          # (n,)
    control_points: FloatArray  # (s+1, n)
    A: Optional[FloatArray]
    B: Optional[FloatArray]


def _hold(B: FloatArray, m: int) -> FloatArray:
    """Per-control-point columns -> one held control: sum the (s+1) column blocks."""
    held: FloatArray = B.reshape(*B.shape[:-1], -1, m).sum(axis=-2)
    return held


class Linearizer:
    """Exact linearisation of an Integrator's DEL equations and of its one-step map.

    D^2 L_d is assembled in O(s^2 n^2) from Algorithms 2 and 3 at each control point; the step
    Jacobians A, B follow by the implicit function theorem with one LU factorisation of the
    (sn x sn) DEL Jacobian serving every right-hand side. Asking only for A does no work for B.

    With contacts (``Integrator(..., contacts=...)``): ``step_jacobians`` and ``rollout_jacobians``
    linearise the contact step with its contact state held (each contact in flight, sticking or
    sliding as in the step: cpp/include/hovi/integrators/contact_jacobians.hpp), exact away from
    contact switches; the momentum is the step's state, before the next knot's impulse.

    With a free base (``Model.free_base``) A and B act on tangent coordinates, (q ⊖ q_ref, p - p_ref)
    (cpp/include/hovi/integrators/free_base_jacobians.hpp), through contact too.
    """

    def __init__(self, integrator: Integrator) -> None:
        if not isinstance(integrator, Integrator):
            raise TypeError(f"integrator must be a hovi.Integrator, got {type(integrator).__name__}")
        self.integrator = integrator
        self._core = _core.Linearizer(integrator._core)

    def __getstate__(self) -> dict[str, Integrator]:
        return {"integrator": self.integrator}  # pickled with its integrator, made anew from it

    def __setstate__(self, state: dict[str, Integrator]) -> None:
        self.__init__(state["integrator"])  # type: ignore[misc]

    def del_jacobian(self, control_points: npt.ArrayLike, u: Optional[npt.ArrayLike] = None, *, with_u: bool = True,
                     multipliers: Optional[npt.ArrayLike] = None) -> DelJacobian:
        """Jacobian of (r^{k,0..s-1}, p^{k+1}) with respect to q^{k,0..s} (and u^{k,0..s}) at control
        points (s+1, n) with controls u (m,) or (s+1, m): ``dq`` ((s+1) n, (s+1) n), ``du``
        ((s+1) n, (s+1) m).

        For a constrained model give the multipliers (s, m_c) = λ^{k,0..s-1}: the rows then include
        the constraint forces w^a dt Dh(q^a)^T λ^a (with their λ·d²h terms), and the result carries
        ``dlambda`` and ``dh`` (the Jacobian of the constraint rows h(q^{k,1..s})).
        """
        dq, du, dh = self._core.del_jacobian(control_points, u, with_u, multipliers)
        s, n = self.integrator.s, self.integrator.n
        dlambda = None
        if multipliers is not None:
            assert du is not None
            m, mc = self.integrator.model.n_controls, self.integrator.n_constraints
            blocks = du.reshape((s + 1) * n, s + 1, m + mc)
            dlambda = blocks[:, :s, m:].reshape((s + 1) * n, s * mc)
            du = blocks[:, :, :m].reshape((s + 1) * n, (s + 1) * m) if with_u else None
        return DelJacobian(dq=dq, du=du, s=s, n=n, dlambda=dlambda, dh=dh)

    def step_jacobians(self, q: npt.ArrayLike, p: npt.ArrayLike, u: Optional[npt.ArrayLike] = None, *, A: bool = True,
                       B: bool = True, hold: bool = False, guess: Optional[npt.ArrayLike] = None,
                       smoothing: float = 0.0) -> StepLinearization:
        """Take one step from (q, p) (n,) with controls u ((m,) or (s+1, m)) and linearise it: A (2n, 2n),
        B (2n, (s+1) m) or (2n, m) with hold=True (see StepLinearization). With contacts, ``smoothing``
        > 0 (in (N s)^2) linearises the complementarity on the central path (across contact switches:
        cpp/include/hovi/integrators/contact_jacobians.hpp); 0 holds each contact's state."""
        q_next, p_next, info = self.integrator.step(q, p, u, guess=guess)
        assert info.control_points is not None
        if info.impact:
            raise ValueError(f"the step was split at an impact (at {info.impact:.3g} of the step, locate_impacts): "
                             "not differentiable there (a contact switch); linearise away from impacts")
        impulses = None if info.impulses is None else info.impulses.reshape(1, -1)
        Am, Bm = self._core.step_jacobians(info.control_points, u, A, B, info.multipliers, impulses,
                                           real_number(smoothing, "smoothing", minimum=0.0), self._start(q))
        if Bm is not None and hold:
            Bm = _hold(Bm, self.integrator.model.n_controls)
        return StepLinearization(q_next, p_next, info.control_points, Am, Bm)

    def _start(self, q: npt.ArrayLike) -> Optional[FloatArray]:
        """A free base's step start q^k (its attitude places the step's chart), else None."""
        return _core.real_array(q, "q") if self.integrator.model.free_base else None

    def linearize_at(self, control_points: npt.ArrayLike, u: Optional[npt.ArrayLike] = None, *, A: bool = True,
                     B: bool = True, hold: bool = False, multipliers: Optional[npt.ArrayLike] = None,
                     impulses: Optional[npt.ArrayLike] = None, smoothing: float = 0.0,
                     start: Optional[npt.ArrayLike] = None) -> Tuple[Optional[FloatArray], Optional[FloatArray]]:
        """(A (2n, 2n), B (2n, (s+1) m)) at given converged control points (s+1, n) of a step, with its
        multipliers (s, m_c) for a constrained model, or with contacts its impulses (C, 2 + d) and
        ``smoothing`` as for ``step_jacobians``; None for what was not asked for. Control points (K, s+1, n)
        (with u (K, s+1, m), multipliers (K, s, m_c), impulses (K, C, 2 + d)) give K steps at once, in C++:
        (K, 2n, 2n) and (K, 2n, (s+1) m). A model with a free base needs the step's ``start`` q^k (nq,), or
        (K, nq): its control points are in the chart about that attitude."""
        smoothing = real_number(smoothing, "smoothing", minimum=0.0)
        cps = _core.real_array(control_points, "control_points")
        if cps.ndim == 3:
            K = len(cps)
            rows = [None if x is None else np.ascontiguousarray(_core.real_array(x, name).reshape(K, -1))
                    for x, name in ((u, "u"), (multipliers, "multipliers"), (impulses, "impulses"))]
            starts = None if start is None else np.ascontiguousarray(_core.real_array(start, "start").reshape(K, -1))
            Am, Bm = self._core.rollout_jacobians(np.ascontiguousarray(cps.reshape(K, -1)), rows[0], A, B, rows[1],
                                                  rows[2], smoothing, starts)
        else:
            z = None if impulses is None else _core.real_array(impulses, "impulses").reshape(1, -1)
            Am, Bm = self._core.step_jacobians(cps, u, A, B, multipliers, z, smoothing, start)
        if Bm is not None and hold:
            Bm = _hold(Bm, self.integrator.model.n_controls)
        return Am, Bm

    def rollout_jacobians(self, trajectory: Trajectory, u: Optional[npt.ArrayLike] = None, *, A: bool = True,
                          B: bool = True, hold: bool = False, smoothing: float = 0.0
                          ) -> Tuple[Optional[FloatArray], Optional[FloatArray]]:
        """(A_k, B_k) along a trajectory, computed in C++: arrays (K, 2n, 2n) and (K, 2n, (s+1) m)
        (or (K, 2n, m) with hold=True). u as given to Integrator.rollout; ``smoothing`` as for
        ``step_jacobians``."""
        integ = self.integrator
        if not trajectory.converged:
            raise ConvergenceError("the trajectory has unconverged steps; linearise the converged part only")
        K = trajectory.control_points.shape[0]
        U = integ.controls_per_point(u, K)
        if U is not None:
            U = np.ascontiguousarray(U.reshape(K, -1))
        cps = np.ascontiguousarray(trajectory.control_points.reshape(K, -1))
        impulses = mult = None
        if trajectory.contact is not None:
            impact = trajectory.contact.impact
            if impact is not None and np.any(impact[:K] > 0):
                k = int(np.argmax(impact[:K] > 0))
                raise ValueError(f"step {k} was split at an impact (locate_impacts): not differentiable there (a "
                                 "contact switch); linearise the steps away from impacts, or simulate with s = 1 "
                                 "without locate_impacts (the trajectory optimiser's time-stepping)")
            impulses = np.ascontiguousarray(trajectory.contact.impulses.reshape(K, -1))
        if trajectory.multipliers is not None:
            mult = np.ascontiguousarray(trajectory.multipliers.reshape(K, -1))
        starts = np.ascontiguousarray(trajectory.q[:K]) if integ.model.free_base else None
        As, Bs = self._core.rollout_jacobians(cps, U, A, B, mult, impulses,
                                              real_number(smoothing, "smoothing", minimum=0.0), starts)
        if Bs is not None and hold:
            Bs = _hold(Bs, integ.model.n_controls)
        return As, Bs

    def rollout_jacobians_batch(self, batch: TrajectoryBatch, u: Optional[npt.ArrayLike] = None, *, A: bool = True,
                                B: bool = True, hold: bool = False, threads: Optional[int] = None) -> JacobianBatch:
        """``rollout_jacobians`` of every trajectory of a TrajectoryBatch (``Integrator.rollout_batch``
        of this linearizer's integrator) at once, in C++ on ``threads`` threads (default:
        HOVI_NUM_THREADS, else every core), GIL released: A (B, K, 2n, 2n), B (B, K, 2n, (s+1) m) (or
        (B, K, 2n, m) with hold=True), item b bit for bit what ``rollout_jacobians(batch.trajectory(b))``
        gives. u as given to rollout_batch. Items whose rollout did not complete are not linearised
        (NaN, and ``errors[b]`` says why); neither does a singular step fail the batch."""
        integ = self.integrator
        count, K = len(batch), batch.control_points.shape[1]
        n, S1, m = integ.n, integ.s + 1, integ.model.n_controls
        U = integ.controls_per_point(u, K, batch=count)
        errors: list[Optional[str]] = [None] * count
        for b in range(count):
            if batch.status[b] != "converged":
                errors[b] = (batch.errors[b] or f"the rollout did not converge ({batch.status[b]}) at step "
                             f"{batch.steps[b]}: linearise the converged part only")
            elif batch.contact is not None and batch.contact.impact is not None and np.any(batch.contact.impact[b] > 0):
                errors[b] = "a step was split at an impact (locate_impacts): not differentiable there (a contact switch)"
        As = np.full((count, K, 2 * n, 2 * n), np.nan) if A else None
        Bs = np.full((count, K, 2 * n, S1 * m), np.nan) if B else None
        todo = np.flatnonzero([e is None for e in errors])
        if K and todo.size:
            mult = None if batch.multipliers is None else batch.multipliers[todo].reshape(todo.size * K, -1)
            z = None if batch.contact is None else batch.contact.impulses[todo].reshape(todo.size * K, -1)
            starts = batch.q[todo, :K].reshape(todo.size * K, -1) if integ.model.free_base else None
            a, b_, errs = self._core.rollout_jacobians_batch(
                batch.control_points[todo].reshape(todo.size * K, -1), K,
                None if U is None else U[todo].reshape(todo.size * K, -1), A, B, mult, z, 0.0, threads, starts)
            for i, e in zip(todo, errs):
                errors[i] = e
            linearised = todo[[e is None for e in errs]]
            ok = np.array([e is None for e in errs], dtype=bool)
            if As is not None and a is not None:
                As[linearised] = a[ok]
            if Bs is not None and b_ is not None:
                Bs[linearised] = b_[ok]
        if Bs is not None and hold:
            Bs = _hold(Bs, m)
        return JacobianBatch(A=As, B=Bs, errors=errors)
