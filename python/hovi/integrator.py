"""The Galerkin variational integrator: the Pythonic layer over hovi._core.Integrator."""
from __future__ import annotations

import os
import warnings
from typing import Any, Dict, List, Optional, Tuple

import numpy as np
import numpy.typing as npt

from . import _core
from ._typing import FloatArray
from .batch import StepBatch, TrajectoryBatch
from .contact.contacts import Contacts
from ._checks import real_number, step_count, whole_number
from .trajectory import ContactRecord, Discretization, StepInfo, Trajectory

__all__ = ["ConvergenceError", "Integrator", "StepInfo", "Trajectory"]


def check_trajectory_memory(steps: int, s: int, n: int, count: int = 1) -> None:
    """MemoryError, before anything is allocated, if ``count`` trajectories of ``steps`` steps (q, p
    and control points, (steps+1) (s+3) n doubles each) need more than this machine's physical memory."""
    need = count * (steps + 1) * (s + 3) * n * 8
    try:
        have = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):  # not POSIX: let the allocation decide
        return
    if need > have:
        raise MemoryError(f"{count} rollout(s) of {steps} steps need {need / 1e9:.3g} GB for its trajectory, more than this "
                          f"machine's {have / 1e9:.3g} GB: simulate in pieces (rollout from the last state)")


class ConvergenceError(RuntimeError):
    """A Newton solve of the DEL equations did not converge."""

    def __init__(self, message: str, info: StepInfo | dict[str, Any] | None = None,
                 trajectory: Trajectory | None = None):
        super().__init__(message)
        self.info = info
        self.trajectory = trajectory


class Integrator:
    """Galerkin variational integrator of order 2s on s+1 Lobatto points (Fan et al. 2018).

    ``s``: the number of Lobatto intervals of a step, the integrator's order of accuracy being 2s (s = 1
    trapezoidal, s = 2 Simpson, the default; any s up to 16).
    Each step solves the DEL equations for q^{k,1..s} by Newton's method with a backtracking
    line search. The direction is exact (on a free base, but for its chart's term at s = 1 and on the
    recursive path: docs/how-it-works.md, "The free base"): ``direction="recursive"`` is the paper's O(s^3 n)
    recursion (appendix Algorithms A.1/A.2), ``"dense"`` an LU of the DEL Jacobian from the
    linearisation (O(s^2 n^2) + O(s^3 n^3), cheaper for small n) and ``"auto"`` (default) the
    faster of the two for this model and s (the crossover: bench/direction_crossover.py).
    ``reuse_jacobian`` (default True, simplified Newton) factors the Jacobian once per step at the
    predicted control points and keeps it while the iteration contracts by at least
    ``reuse_contraction`` per iteration, refactoring otherwise; False refactors every iteration
    (the paper's Newton). The first guess of a rollout step (``predictor``): ``"history"``
    extrapolates the last two steps' control points (cheap); ``"flow"`` integrates the continuous
    dynamics over the step from q^k and M^{-1} p^k by classical Runge-Kutta, O(s n), which helps
    at steps that resolve fast modes only barely; ``"auto"`` (default) switches from the history to
    the flow for higher s when a step needed many iterations and tries the history again later.
    The substep counts and switching thresholds have one home, the C++ FlowPredictor and
    PredictorChoice (cpp/include/hovi/integrators/flow_predictor.hpp); measurements in
    bench/README.md.
    The converged step does not depend on the guess (to round-off, on the same solution branch).

    A step has converged when the next Newton correction, the estimated error of the iterate,
    is below ``step_tol`` (1 + ||q||_inf): by default 1e-15, round-off, so that neither the
    trajectory error nor the energy carries a solver floor over long runs (whichever Jacobian
    was used). ``tol`` > 0 adds a looser residual test, ||r||_inf <= tol (1 + ||p^k||_inf), for
    speed at the cost of accuracy.

    The model is copied: after a change to the model (a force, a constraint, gravity, a body),
    every call of this integrator (and of Linearizers made from it) raises hovi.ModelError; make
    a new Integrator from the changed model (``model.copy()`` keeps the old version).

    Threads: one Integrator may be used from several threads at once (each call runs on its own
    workspace, with the GIL released in rollouts and steps); results are those of the same calls
    made in sequence. Each call depends on its arguments only. ``rollout_batch`` and
    ``step_batch`` run many initial states on a pool of C++ threads in one call.

    Controls ``u`` are given per control point, shape (s+1, m), or held constant over a step,
    shape (m,). Samples of a smooth u(t) keep order 2s; a zero-order hold is first-order
    accurate with respect to a smooth u(t).

    Contacts: ``contacts`` (a ``hovi.contact.Contacts`` built on this model: points, terrain,
    friction) makes every step a contact step, the trajectory optimiser's contact model solved in
    C++ (cpp/include/hovi/integrators/contact_solver.hpp): hard contact, no penetration of the
    terrain at the configuration points and Coulomb friction on the polyhedral cone, each
    complementarity condition to ``contact_tol`` (m and N s). A step whose contacts were all
    inactive before is first solved without them, so flight costs what it costs without contacts.
    ``locate_impacts`` (default: for s > 1, which needs it) splits a step at an impact found on its
    polynomial, so that flight keeps the order 2s and impacts happen at their time; with s = 1 and
    without it the step is the trajectory optimiser's time-stepping (a ``solve_contact`` solution is
    a rollout of it). Rollouts record the impulses and gaps (``Trajectory.contact``).
    """

    def __init__(self, model: _core.Model, *, s: int = 2, dt: float = 0.01,
                 tol: float = 0.0, step_tol: float = 1e-15, max_iterations: int = 30, max_backtracks: int = 12,
                 line_search: bool = True, direction: str = "auto", reuse_jacobian: bool = True,
                 reuse_contraction: float = 0.1, predictor: str = "auto", contacts: Optional[Contacts] = None,
                 contact_tol: float = 1e-10, locate_impacts: Optional[bool] = None) -> None:
        s = whole_number(s, "s", minimum=1)
        if not isinstance(model, _core.Model):
            raise TypeError(f"model must be a hovi.Model, got {type(model).__name__}")
        for name, flag in (("line_search", line_search), ("reuse_jacobian", reuse_jacobian)):
            if not isinstance(flag, (bool, np.bool_)):
                raise ValueError(f"{name} must be True or False, got {type(flag).__name__} {flag!r:.60}")
        # A string or a float count is never cast; the ranges that need the model or s are checked in C++.
        self._options: Dict[str, Any] = dict(
            s=int(s), dt=real_number(dt, "dt", minimum=0.0, strict_minimum=True),
            tol=real_number(tol, "tol", minimum=0.0), step_tol=real_number(step_tol, "step_tol", minimum=0.0,
                                                                           strict_minimum=True),
            max_iterations=whole_number(max_iterations, "max_iterations"),
            max_backtracks=whole_number(max_backtracks, "max_backtracks"), line_search=bool(line_search),
            direction=direction, reuse_jacobian=bool(reuse_jacobian),
            reuse_contraction=real_number(reuse_contraction, "reuse_contraction"), predictor=predictor)
        self.model = model
        self.contacts = contacts
        self.contact_tol = contact_tol
        self.locate_impacts = locate_impacts
        self._core = _core.Integrator(model, **self._options, **self._contact_arguments(model, contacts, contact_tol,
                                                                                        locate_impacts))
        self.discretization = Discretization(model, self._options, self._core)
        """What this integrator's trajectories carry: the model, s and dt, velocity and energies."""

    def _contact_arguments(self, model: _core.Model, contacts: Any, tol: Any, locate: Any) -> Dict[str, Any]:
        """The C++ integrator's contact arguments (none without contacts); errors naming the argument."""
        if contacts is None:
            return {}
        if not isinstance(contacts, Contacts):
            raise TypeError(f"contacts must be a hovi.contact.Contacts, got {type(contacts).__name__}")
        contacts.check_model(model)
        s = self._options["s"]
        if locate is None:
            locate = s > 1
        if not isinstance(locate, (bool, np.bool_)):
            raise ValueError(f"locate_impacts must be True, False or None, got {locate!r}")
        if s > 1 and not locate:
            raise ValueError(f"contacts with s = {s} need locate_impacts (the default for s > 1): without it an "
                             "impact inside a step happens at its end, a first-order time-stepper that throws away "
                             "the order 2s (bench/README.md, \"Contact simulation\")")
        tol = real_number(tol, "contact_tol", minimum=0.0, strict_minimum=True)
        return dict(contacts=contacts.core_model(), contact_tol=tol, locate_impacts=bool(locate))

    # Pickling (to other processes, cluster workers): the model (which pickles in full), the
    # options and the contacts; the copy is made anew from them and computes exactly what this one does.
    def __getstate__(self) -> Dict[str, Any]:
        self._core.direction_path  # any call of the core raises ModelError once the model has changed
        state: Dict[str, Any] = {"model": self.model, "options": self._options}
        if self.contacts is not None:
            state.update(contacts=self.contacts, contact_tol=self.contact_tol, locate_impacts=self.locate_impacts)
        return state

    def __setstate__(self, state: Dict[str, Any]) -> None:
        extra = {k: state[k] for k in ("contacts", "contact_tol", "locate_impacts") if k in state}
        self.__init__(state["model"], **state["options"], **extra)  # type: ignore[misc]

    # --- properties -------------------------------------------------------------------------
    @property
    def core(self) -> _core.Integrator:
        """The C++ object that steps this integrator, hovi._core.Integrator (what hovi's C++ loops take:
        closed loops, FDDP, MPC)."""
        return self._core

    @property
    def s(self) -> int:
        """Number of Lobatto intervals; s+1 control points."""
        return self._core.s

    @property
    def order(self) -> int:
        """Order of accuracy 2s."""
        return 2 * self._core.s

    @property
    def direction_path(self) -> str:
        """The Newton direction this integrator computes: 'dense' or 'recursive'."""
        return self._core.direction_path

    @property
    def dt(self) -> float:
        """The time step (s)."""
        return self._core.dt

    @property
    def n(self) -> int:
        """Number of joints n of the model: the size of a velocity or momentum (nv)."""
        return self._core.n

    @property
    def nq(self) -> int:
        """The size of a configuration: n, or n + 1 for a model with a free base (its attitude a
        quaternion, as Pinocchio's free flyer)."""
        return self._core.nq

    @property
    def nodes(self) -> FloatArray:
        """(s+1,) Lobatto nodes c^a on [0, 1]."""
        return self._core.nodes

    @property
    def weights(self) -> FloatArray:
        """(s+1,) Lobatto weights w^a."""
        return self._core.weights

    @property
    def differentiation_matrix(self) -> FloatArray:
        """(s+1, s+1) b^{ab} = l_b'(c^a): q̇^a = (1/dt) sum_b b^{ab} q^b."""
        return self._core.differentiation_matrix

    def __repr__(self) -> str:
        return f"<hovi.Integrator order {self.order} (s={self.s}), dt={self.dt}, n={self.n}>"

    # --- constraints ---------------------------------------------------------------------------
    @property
    def n_constraints(self) -> int:
        """Number of constraint equations m_c of the model."""
        return self._core.n_constraints

    def project(self, q: npt.ArrayLike, qdot: Optional[npt.ArrayLike] = None,
                tol: float = 1e-12) -> Tuple[FloatArray, FloatArray]:
        """A consistent initial state for a constrained model: (q (n,), qdot (n,)) with h(q) = 0 (Gauss-Newton,
        minimum-norm corrections) and Dh(q) qdot = 0 (the kinetic-energy-nearest velocity).
        Raises ValueError for redundant or inconsistent constraints, a configuration too far from
        the constraint manifold, or constraints that lock every degree of freedom."""
        qdot = np.zeros(self.n) if qdot is None else qdot
        return self._core.project(q, qdot, tol)

    def constrained_residual(self, control_points: npt.ArrayLike, multipliers: npt.ArrayLike, p: npt.ArrayLike,
                             u: Optional[npt.ArrayLike] = None) -> Tuple[FloatArray, FloatArray, FloatArray]:
        """(r, h, p_next) of the constrained DEL equations: r (s, n) includes the constraint forces
        w^a dt Dh(q^a)^T λ^a, h (s, m_c) = h(q^{k,1..s}), p_next (n,); control_points (s+1, n), p (n,),
        multipliers (s, m_c) = λ^{k,0..s-1}."""
        return self._core.constrained_residual(control_points, multipliers, p, u)

    def constrained_direction(self, control_points: npt.ArrayLike, multipliers: npt.ArrayLike, p: npt.ArrayLike,
                              u: Optional[npt.ArrayLike] = None) -> Tuple[FloatArray, FloatArray]:
        """The constrained Newton direction (dq (s, n), dλ (s, m_c)) at control_points (s+1, n),
        multipliers (s, m_c), p (n,): the recursive solver and the Schur complement of the KKT system."""
        return self._core.constrained_direction(control_points, multipliers, p, u)

    def check_start(self, q: npt.ArrayLike, name: str = "q0") -> None:
        """ValueError if a contact point of configuration q (n,) is deeper in the terrain than
        ``contact_tol``: a step from there would throw the body out with energy it never had."""
        if self.contacts is None:
            return
        gaps = self.contacts.gaps(_core.real_array(q, name))
        c = int(np.argmin(gaps))
        if gaps[c] < -self.contact_tol:
            point = self.contacts.points[c]
            body = self.model.body_names[int(point.body)]
            label = f"contact {c}" + (f" ({point.name!r}, body {body!r})" if point.name else f" (body {body!r})")
            raise ValueError(f"{name}: {label} starts {-gaps[c]:.6g} m inside the terrain, deeper than contact_tol = "
                             f"{self.contact_tol:g}; start it on or above the terrain (a step from inside would "
                             "throw it out with energy it does not have)")

    def _check_consistent(self, q0: FloatArray, qdot0: Optional[FloatArray], name: str = "q0") -> None:
        self.check_start(q0, name)
        if self.n_constraints == 0:
            return
        h = self.model.constraint_values(q0)
        if np.abs(h).max() > 1e-8:
            raise ValueError(f"the initial configuration violates the constraints (|h| = {np.abs(h).max():.3e}); "
                             "use Integrator.project(q0, qdot0) for a consistent initial state")
        if qdot0 is not None:
            v = self.model.constraint_jacobian(q0) @ qdot0
            if np.abs(v).max() > 1e-8 * (1 + np.abs(qdot0).max()):
                raise ValueError(f"the initial velocity violates the constraints (|Dh qdot| = {np.abs(v).max():.3e}); "
                                 "use Integrator.project(q0, qdot0) for a consistent initial state")

    # --- momentum and energy -----------------------------------------------------------------
    def momentum(self, q: npt.ArrayLike, qdot: npt.ArrayLike) -> FloatArray:
        """q (nq,), qdot (n,); returns p = dL/dq̇ = M(q) q̇ (n,): the discrete momentum to start from (for a
        constrained model give a q̇ with Dh(q) q̇ = 0, e.g. from ``project``; a free base: q̇ its velocity
        in its own frame, as Pinocchio's, and p the conjugate)."""
        return self._core.momentum(q, qdot)

    def velocity(self, q: npt.ArrayLike, p: npt.ArrayLike) -> FloatArray:
        """q (nq,), p (n,); returns the velocity q̇ (n,) of a discrete momentum p: M(q)^{-1} p, O(n).

        For a constrained model, the q̇ with Dh(q) q̇ = 0 nearest to M^{-1} p in the kinetic-energy
        metric: ``[M Dh^T; Dh 0] [q̇; μ] = [p; 0]``, solved in O(n m + m^3) with the recursive
        mass-matrix solve (the momentum projection of RATTLE-type methods). The discrete momentum
        p^k of a constrained step is defined up to Dh(q^k)^T μ (the next step's constraint impulse
        absorbs that part), so M^{-1} p alone is not a tangent velocity.
        """
        return self._core.velocity(q, p)

    def energy(self, q: npt.ArrayLike, p: npt.ArrayLike) -> float:
        """q (nq,), p (n,); returns K + V at (q, ``velocity(q, p)``)."""
        return self._core.energy(q, p)

    def energies(self, q: npt.ArrayLike, p: npt.ArrayLike) -> FloatArray:
        """``energy`` (K,) of every row of q, p (arrays (K, n)), in C++."""
        return self._core.energies(q, p)

    # --- the DEL equations ---------------------------------------------------------------------
    def del_residual(self, control_points: npt.ArrayLike, p: npt.ArrayLike,
                     u: Optional[npt.ArrayLike] = None) -> Tuple[FloatArray, FloatArray]:
        """Algorithm 1: (r, p_next) with r of shape (s, n) (row a = r^{k,a}) and p_next (n,) for control
        points (s+1, n), momentum p (n,) and controls u (m,) or (s+1, m)."""
        return self._core.del_residual(control_points, p, u)

    def newton_direction(self, control_points: npt.ArrayLike, p: npt.ArrayLike,
                         u: Optional[npt.ArrayLike] = None) -> FloatArray:
        """The Newton direction dq of shape (s, n) (row gamma-1 = δq^{k,gamma}) with J dq = -r, on
        this integrator's ``direction`` path (Algorithms A.1/A.2, or the dense LU)."""
        return self._core.newton_direction(control_points, p, u)

    # --- stepping --------------------------------------------------------------------------------
    def step(self, q: npt.ArrayLike, p: npt.ArrayLike, u: Optional[npt.ArrayLike] = None, *,
             guess: Optional[npt.ArrayLike] = None, multipliers: Optional[npt.ArrayLike] = None,
             impulses: Optional[npt.ArrayLike] = None, raise_on_failure: bool = True
             ) -> Tuple[FloatArray, FloatArray, StepInfo]:
        """One step from q (nq,), p (n,) with controls u ((m,) or (s+1, m)): returns (q_next (nq,), p_next
        (n,), info) (a free base: the control points in the chart about q's attitude). ``info.control_points`` holds q^{k,0..s} and,
        for a constrained model, ``info.multipliers`` λ^{k,0..s-1} (s, n_constraints).

        guess: initial control points (s+1, n) for a single Newton solve; by default Newton starts
        from q + c^a dt q̇ (q̇ = ``velocity(q, p)``) and, if that fails, from q^{k,a} = q, and last
        (without constraints) the step is continued in its length from h = 0 to dt along the
        solution branch through q (status 'continuation_stalled' if that branch turns back first).
        multipliers: the first guess of λ^{k,0..s-1} of a constrained model (default zero).
        impulses: with contacts, the first guess of the step's impulses (C, 2 + d) (default: none
        active), e.g. a known solution's: the contact step's equations can have more than one solution.
        Raises ConvergenceError if the solve fails and raise_on_failure (else check info.converged).
        """
        z0 = None if impulses is None else _core.real_array(impulses, "impulses").ravel()
        self.check_start(q, "q")
        qc, p_next, raw = self._core.step(q, p, u, guess, multipliers, z0)
        q_next = raw.pop("q_next", qc[-1])  # a free base: its end state (the points are in its chart)
        lam = raw.pop("multipliers")
        contact = {k: raw.pop(k) for k in ("impulses", "gaps", "pivots", "impact") if k in raw}
        info = StepInfo(**raw)
        if not info.converged and raise_on_failure:
            raise ConvergenceError(f"{self.step_kind} did not converge ({info.status}) after {info.iterations} "
                                   f"iterations, residual {info.residual:.3e}; try a smaller dt", info=info)
        info.control_points = qc
        if self.n_constraints:
            info.multipliers = lam
        if contact:
            info.impulses, info.gaps = contact["impulses"].reshape(-1, self._core.per_contact), contact["gaps"]
            info.pivots, info.impact = int(contact["pivots"]), float(contact["impact"])
        return np.array(q_next, copy=True), p_next, info

    @property
    def step_kind(self) -> str:
        """What a step solves, for the messages of failed steps."""
        return "Newton solve" if self.contacts is None else "contact step"

    def rollout(self, q0: npt.ArrayLike, steps: int, *, p0: Optional[npt.ArrayLike] = None,
                qdot0: Optional[npt.ArrayLike] = None, u: Optional[npt.ArrayLike] = None,
                raise_on_failure: bool = True, progress: bool = False, chunk: int = 500) -> Trajectory:
        """Simulate ``steps`` steps from q0 (nq,) with p0 (n,) (or qdot0 (n,), default zero velocity), in C++.

        Each step starts Newton from the control points of the last two steps extrapolated; if that solve
        fails it retries from q^k + c^a dt q̇^k (q̇^k = ``velocity(q^k, p^k)``), then from
        q^{k,a} = q^k, then (without constraints) by continuation in the step length along the
        solution branch through q^k. A constrained model's multipliers start from zero and then
        from the previous step's.

        u: None, (m,) constant, (steps, m) held per step, or (steps, s+1, m) per control point.
        progress: show a progress bar (the C++ loop runs in chunks of ``chunk`` steps).
        Raises ConvergenceError at the first failed step (its .trajectory holds what was done),
        unless raise_on_failure=False, in which case the trajectory stops there.
        """
        steps = step_count(steps)
        check_trajectory_memory(steps, self.s, self.n)
        q0 = _core.real_array(q0, "q0")  # complex, text and object arrays refused, never cast
        if q0.shape != (self.nq,):  # named here: the momentum below would call it q
            raise ValueError(f"q0 must be a 1-D array of length {self.nq}, got shape {q0.shape}")
        if p0 is not None and qdot0 is not None:
            raise ValueError("give p0 or qdot0, not both")
        if p0 is None:
            v0 = np.zeros(self.n) if qdot0 is None else _core.real_array(qdot0, "qdot0")
            self._check_consistent(q0, v0)
            p0 = self.momentum(q0, v0)
        else:
            p0 = _core.real_array(p0, "p0")
            self._check_consistent(q0, None)
        U = self._core.rollout_controls(u, steps)
        bar = None
        if progress:
            from tqdm import tqdm  # type: ignore[import-untyped, unused-ignore]
            bar = tqdm(total=steps, unit="step", desc="simulating")
        parts = self._chunks(q0, p0, steps, U, bar, chunk)
        traj = self.trajectory_of(parts)
        m = self.model.n_controls
        if m:  # the controls of the steps taken, per control point (zero when none were given)
            traj.controls = (np.zeros((traj.steps, self.s + 1, m)) if U is None
                             else U[:traj.steps].reshape(traj.steps, self.s + 1, m).copy())
        if not traj.converged and raise_on_failure:
            k = traj.steps
            raise ConvergenceError(f"{self.step_kind} did not converge at step {k} (t = {k * self.dt:.6g} s): "
                                   f"{traj.status[-1]}, residual {traj.residuals[-1]:.3e}; try a smaller dt",
                                   trajectory=traj)
        return traj

    def _chunks(self, q0: FloatArray, p0: FloatArray, steps: int, U: Optional[FloatArray], bar: Any,
                chunk: int) -> List[Dict[str, Any]]:
        """The C++ rollouts of ``rollout``: one, or chunks of ``chunk`` steps when a progress ``bar`` is
        shown, each continuing the last (its control points, multipliers or contact impulses)."""
        parts: List[Dict[str, Any]] = []
        q, p, done = q0, p0, 0
        last: Optional[Dict[str, Any]] = None
        while True:
            n_chunk = min(chunk, steps - done) if bar is not None else steps - done
            U_chunk = None if U is None else U[done:done + n_chunk]
            previous = lam = z = None
            if last is not None:  # what the last chunk's last step left
                previous = last["control_points"][-1].reshape(self.s + 1, self.n)
                lam = last["multipliers"][-1].reshape(self.s, self.n_constraints) if self.n_constraints else None
                z = last["impulses"][-1] if "impulses" in last else None
            res = self._core.rollout(q, p, n_chunk, U_chunk, previous, lam, z)
            parts.append(res)
            done += res["steps"]
            if bar is not None:
                bar.update(res["steps"])
            if res["steps"] < n_chunk or done >= steps:
                break
            q, p, last = res["q"][-1], res["p"][-1], res
        if bar is not None:
            bar.close()
        return parts

    def _batch_states(self, q: npt.ArrayLike, p: Optional[npt.ArrayLike], qdot: Optional[npt.ArrayLike],
                      names: Tuple[str, str, str]) -> Tuple[FloatArray, FloatArray, bool]:
        """(q (B, n), second (B, n), velocities) of a batch of states given with momenta or
        velocities (default: at rest); each checked against the constraints as a single call does."""
        Q = _core.real_array(q, names[0])  # complex, text and object arrays refused, never cast
        if Q.ndim != 2 or Q.shape[1] != self.nq:
            raise ValueError(f"{names[0]} must be a 2-D array of shape (B, {self.nq}), got shape {Q.shape}")
        if len(Q) == 0:
            raise ValueError(f"the batch is empty: {names[0]} has no rows (B = 0)")
        if p is not None and qdot is not None:
            raise ValueError(f"give {names[1]} or {names[2]}, not both")
        velocities = p is None
        second = (_core.real_array(p, names[1]) if p is not None else np.zeros((len(Q), self.n)) if qdot is None
                  else _core.real_array(qdot, names[2]))
        if second.shape != (len(Q), self.n):
            raise ValueError(f"{names[1] if p is not None else names[2]} must have shape {(len(Q), self.n)}, "
                             f"got {second.shape}")
        if self.n_constraints or self.contacts is not None:
            for b in range(len(Q)):
                try:
                    self._check_consistent(Q[b], second[b] if velocities else None, f"{names[0]}[{b}]")
                except ValueError as e:
                    raise ValueError(f"state {b} of the batch: {e}") from None
        return Q, second, velocities

    def rollout_batch(self, q0s: npt.ArrayLike, steps: int, *, p0s: Optional[npt.ArrayLike] = None,
                      qdot0s: Optional[npt.ArrayLike] = None, u: Optional[npt.ArrayLike] = None,
                      threads: Optional[int] = None) -> TrajectoryBatch:
        """``steps`` steps from each of B initial states at once: q0s (B, nq) with p0s (B, n) or qdot0s
        (B, n) (default: at rest), in C++ on ``threads`` threads (default: the environment variable
        HOVI_NUM_THREADS, else every core), with the GIL released.

        Item b is exactly ``rollout(q0s[b], steps, qdot0=qdot0s[b], u=u[b], raise_on_failure=False)``,
        bit for bit, whatever the number of threads (``TrajectoryBatch.trajectory(b)``). A failed
        solve does not fail the batch: that item stops there and its status says why.
        u: None, or per state (B, m) constant, (B, steps, m) held per step, or (B, steps, s+1, m) per
        control point (np.broadcast_to shares one control sequence among the states).
        Raises ValueError for bad input (shapes, B = 0, NaN or infinity, threads < 1, an initial
        state that violates the constraints).
        """
        steps = step_count(steps)
        Q, second, velocities = self._batch_states(q0s, p0s, qdot0s, ("q0s", "p0s", "qdot0s"))
        check_trajectory_memory(steps, self.s, self.n, 2 * len(Q))  # the C++ results and the stacked arrays
        U = self._core.rollout_controls(u, steps, len(Q))
        raw = self._core.rollout_batch(Q, second, velocities, steps, None if U is None else U.reshape(-1, U.shape[-1]),
                                       threads)
        B, S1 = len(Q), self.s + 1
        contact = None
        if "impulses" in raw:
            contact = ContactRecord(raw["impulses"].reshape(B, steps, -1, self._core.per_contact), raw["gaps"],
                                    self._directions(), raw["pivots"], raw["impact"])
            contact.added_energy = self.contact_work(raw["q"], contact.normal)
            self._warn_added_energy(contact.added_energy)
        return TrajectoryBatch(
            t=np.arange(steps + 1, dtype=np.float64) * self.dt, q=raw["q"], p=raw["p"],
            control_points=raw["control_points"].reshape(B, steps, S1, self.n), iterations=raw["iterations"],
            residuals=raw["residual"], factorizations=raw["factorizations"], steps=raw["steps"], status=raw["status"],
            errors=raw["errors"], solve_seconds=raw["seconds"], discretization=self.discretization,
            multipliers=raw["multipliers"].reshape(B, steps, self.s, self.n_constraints) if self.n_constraints else None,
            contact=contact, controls=self._batch_controls(U, B, steps))

    def _batch_controls(self, U: Optional[FloatArray], B: int, steps: int) -> Optional[FloatArray]:
        """(B, steps, s+1, m) controls of a batch as rollout_batch took them (zero when none were given)."""
        m = self.model.n_controls
        if not m:
            return None
        if U is None:
            return np.zeros((B, steps, self.s + 1, m))
        return np.array(U, dtype=np.float64).reshape(B, steps, self.s + 1, m)

    def step_batch(self, qs: npt.ArrayLike, ps: Optional[npt.ArrayLike] = None, u: Optional[npt.ArrayLike] = None, *,
                   qdots: Optional[npt.ArrayLike] = None, threads: Optional[int] = None) -> StepBatch:
        """One step from each of B states at once: qs (B, nq) with ps (B, n) or qdots (B, n) (default: at
        rest), controls u (B, m) held or (B, s+1, m) per control point; in C++ on ``threads``
        threads (default: HOVI_NUM_THREADS, else every core), GIL released.

        Item b is exactly ``step(qs[b], p, u[b], raise_on_failure=False)`` (with p = ps[b], or
        ``momentum(qs[b], qdots[b])``), bit for bit (``StepBatch.info(b)``); a failed solve is that
        item's status and does not fail the batch. Raises ValueError for bad input (shapes,
        B = 0, NaN or infinity, threads < 1, a state that violates the constraints).
        """
        Q, second, velocities = self._batch_states(qs, ps, qdots, ("qs", "ps", "qdots"))
        U = self._core.step_controls(u, len(Q))
        raw = self._core.step_batch(Q, second, velocities, U, threads)
        cp = raw["control_points"]
        contact = {}
        if "impulses" in raw:
            contact = dict(impulses=raw["impulses"].reshape(len(Q), -1, self._core.per_contact), gaps=raw["gaps"],
                           pivots=raw["pivots"])
        return StepBatch(q_next=raw["q_next"], p_next=raw["p_next"], control_points=cp, converged=raw["converged"],
                         iterations=raw["iterations"], factorizations=raw["factorizations"],
                         residual_evaluations=raw["residual_evaluations"], residuals=raw["residual"],
                         status=raw["status"], errors=raw["errors"], solve_seconds=raw["seconds"],
                         multipliers=raw["multipliers"] if self.n_constraints else None, **contact)

    def _directions(self) -> FloatArray:
        """The friction directions D (d, 3) of this integrator's contacts."""
        assert self.contacts is not None
        return self.contacts.D.copy()

    def trajectory_of(self, parts: List[Dict[str, Any]]) -> Trajectory:
        """The Trajectory of consecutive C++ rollouts of this integrator (``_core`` rollout dicts, each
        continuing the last: ``rollout``'s chunks, a closed loop of ``hovi.control``), with its contact
        record when the integrator has contacts."""
        traj = self._join(parts)
        if "controls" in parts[0] and self.model.n_controls:  # a closed loop's applied controls, of its steps taken
            applied = np.vstack([r["controls"] for r in parts]).reshape(-1, self.s + 1, self.model.n_controls)
            traj.controls = applied[:traj.steps].copy()
        if "impulses" in parts[0]:
            pc = self._core.per_contact
            traj.contact = ContactRecord(
                impulses=np.vstack([r["impulses"] for r in parts]).reshape(-1, self._core.n_contacts, pc),
                gaps=np.vstack([r["gaps"] for r in parts]).reshape(-1, self._core.n_contacts),
                directions=self._directions(), pivots=np.concatenate([r["pivots"] for r in parts]),
                impact=np.concatenate([r["impact"] for r in parts]),
                step_momenta=np.vstack([r["step_p"][:-1] for r in parts[:-1]] + [parts[-1]["step_p"]]))
            traj.contact.added_energy = self.contact_work(traj.q, traj.contact.normal)
            self._warn_added_energy(traj.contact.added_energy)
        return traj

    def contact_work(self, q: FloatArray, normal: FloatArray) -> FloatArray:
        """(..., K) the work (J) of the normal impulses ``normal`` (..., K, C) of steps along q (..., K+1, n)
        where they pushed their point up by more than 10 contact_tol over the step, else 0: λ rise / (2 dt),
        an impulse's work taking its point from rest to rise / dt along the normal. Hard
        inelastic contact on horizontal faces never lifts a pushing point (λ > 0 holds it at the
        surface it started on), so work here is energy the contact added: a start inside the terrain,
        or a point carried onto a higher face at an edge."""
        assert self.contacts is not None
        K = normal.shape[-2]
        q = np.where(np.isfinite(q), q, 0.0)  # the rows a failed batch item never reached
        z = self.contacts.positions(q.reshape(-1, self.nq)).reshape(*q.shape[:-1], -1, 3)[..., 2]
        rise = z[..., 1:K + 1, :] - z[..., :K, :]
        lifted = (normal > 0) & (rise > 10 * self.contact_tol)
        work: FloatArray = np.where(lifted, normal * rise, 0.0).sum(axis=-1) / (2 * self.dt)
        return work

    @staticmethod
    def _warn_added_energy(work: FloatArray) -> None:
        """A RuntimeWarning naming the first step where the contact added energy (``contact_work``)."""
        if work.size and work.max() > 0:
            k = np.unravel_index(int(np.argmax(work > 0)), work.shape)
            warnings.warn(f"the contact added energy at {int((work > 0).sum())} step(s), the first at step "
                          f"{k[-1]}{f' of run {k[0]}' if work.ndim > 1 else ''} ({work[k]:.3g} J): a pushing contact "
                          "lifted its point (a start inside the terrain, or a step onto a higher face at an edge); "
                          "Trajectory.contact.added_energy has it per step", RuntimeWarning, stacklevel=3)

    def _join(self, parts: List[Dict[str, Any]]) -> Trajectory:
        q = np.vstack([parts[0]["q"]] + [r["q"][1:] for r in parts[1:]])
        # each part's last momentum is its state (with contacts, before its knot's impulse): the next part's first row
        p = np.vstack([r["p"][:-1] for r in parts[:-1]] + [parts[-1]["p"]])
        cp = np.vstack([r["control_points"] for r in parts]).reshape(-1, self.s + 1, self.n)
        mult = None
        if self.n_constraints:
            mult = np.vstack([r["multipliers"] for r in parts]).reshape(-1, self.s, self.n_constraints)
        return Trajectory(t=np.arange(len(q), dtype=np.float64) * self.dt, q=q, p=p, control_points=cp,
                          iterations=np.concatenate([r["iterations"] for r in parts]),
                          residuals=np.concatenate([r["residual"] for r in parts]),
                          factorizations=np.concatenate([r["factorizations"] for r in parts]),
                          status=sum((r["status"] for r in parts), []), multipliers=mult,
                          solve_seconds=sum(r["seconds"] for r in parts), discretization=self.discretization)

    # --- inputs checked without computing (Linearizer, hovi.distributed) -----------------------
    def controls_per_point(self, u: Optional[npt.ArrayLike], steps: int, *,
                           batch: Optional[int] = None) -> Optional[FloatArray]:
        """Controls ``u`` as ``rollout`` (or, with ``batch`` = B, ``rollout_batch``) takes them, given
        per control point: (steps, s+1, m) (or (B, steps, s+1, m)); None for None. ValueError for a
        shape rollout does not take, NaN or infinity."""
        lead = () if batch is None else (int(batch),)
        U = self._core.rollout_controls(u, int(steps), None if batch is None else int(batch))
        return None if U is None else U.reshape(lead + (int(steps), self.s + 1, self._core.n_controls))

    def check_rollout_batch(self, q0s: npt.ArrayLike, steps: int, *, p0s: Optional[npt.ArrayLike] = None,
                            qdot0s: Optional[npt.ArrayLike] = None, u: Optional[npt.ArrayLike] = None) -> None:
        """ValueError as ``rollout_batch`` raises it for the shapes of the states (q0s, p0s or qdot0s
        (B, n)) and controls and for states that violate the constraints, without computing anything."""
        Q, _, _ = self._batch_states(q0s, p0s, qdot0s, ("q0s", "p0s", "qdot0s"))
        self._core.rollout_controls(u, step_count(steps), len(Q))

    def check_step_batch(self, qs: npt.ArrayLike, ps: Optional[npt.ArrayLike] = None,
                         u: Optional[npt.ArrayLike] = None, *, qdots: Optional[npt.ArrayLike] = None) -> None:
        """ValueError as ``step_batch`` raises it for the shapes of the states (qs, ps or qdots (B, n))
        and controls and for states that violate the constraints, without computing anything."""
        Q, _, _ = self._batch_states(qs, ps, qdots, ("qs", "ps", "qdots"))
        self._core.step_controls(u, len(Q))
