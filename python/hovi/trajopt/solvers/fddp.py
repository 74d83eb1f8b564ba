"""Box-FDDP (cpp/include/hovi/control/box_fddp.hpp) as a solver of a Problem transcribed by the VI:
single shooting on the integrator, so every iterate that closes its gaps is a VI trajectory. The
Problem's costs become quadratic terms on the samples of the VI transcription (the same samples,
weights and velocities, so the same cost as IPOPT's on ``VI(s)``); the solution is returned as that
transcription's x, so ``Result.replay``, ``as_guess`` and plots work as for IPOPT.

What FDDP handles: held controls (``Problem(..., controls='held')``) within bounds, and the costs
ControlEffort, StateTracking, TerminalCost (in C++) and CallbackCost with its Hessian (Python, one
call per rollout and per linearisation). A fixed final state, joint bounds, path or input
constraints and contact-implicit problems need IPOPT (the final state as a TerminalCost here). Through contact, FDDP shoots with the contact simulator instead (``contacts``:
the robot's contacts, s = 1) and its Jacobians through contact, held or smoothed (``smoothing``)."""
from __future__ import annotations

import time
from typing import Any, Optional

import numpy as np

from ... import _core
from ..._checks import real_array, real_number, whole_number
from ...integrator import Integrator
from ..costs import CallbackCost, ControlEffort, StateTracking, TerminalCost, checked_cost
from ..samples import Samples
from ..problem import Problem
from ..result import Result
from ..transcription import Guess, TranscriptionMethod
from ..variational import VI, VariationalTranscription
from .base import Solver


def sample_costs(problem: Problem, transcription: VariationalTranscription) -> list[dict[str, Any]]:
    """The Problem's costs as the shooting problem's quadratic sample terms (see ShootingProblem)."""
    smap = transcription.sample_map()
    t, w, K, n, m = smap.t, smap.w, len(smap.t), problem.model.n, problem.model.n_controls
    zq, zu = np.zeros((K, n)), np.zeros((K, m))
    terms = []
    for cost in problem.costs:  # the weights and targets checked by the costs themselves (errors name them)
        if isinstance(cost, ControlEffort):
            terms.append(dict(terminal=False, Wq=zq, q_ref=zq, Wv=zq, v_ref=zq, R=np.outer(w, cost.weights(m)),
                              u_ref=zu))
        elif isinstance(cost, StateTracking):
            (q_ref, v_ref), (Wq, Wv) = cost.references(t, n), cost.weights(n)
            terms.append(dict(terminal=False, Wq=np.outer(w, Wq), q_ref=np.array(q_ref), Wv=np.outer(w, Wv),
                              v_ref=np.array(v_ref), R=zu, u_ref=zu))
        elif isinstance(cost, TerminalCost):
            (q_T, v_T), (Wq, Wv) = cost.targets(n), cost.weights(n)
            terms.append(dict(terminal=True, Wq=Wq[None], q_ref=q_T[None], Wv=Wv[None], v_ref=v_T[None],
                              R=np.zeros((1, m)), u_ref=np.zeros((1, m))))
        elif isinstance(cost, CallbackCost):
            if cost.hessian is None:
                raise ValueError("FDDP needs the Hessian of a CallbackCost: CallbackCost(fun, hessian=...) (each "
                                 "sample's (2n+m, 2n+m) Hessian in (q, v, u))")
        else:
            raise ValueError(f"FDDP handles ControlEffort, StateTracking, TerminalCost and CallbackCost with a hessian; "
                             f"{type(cost).__name__} needs IPOPT (hovi.trajopt.Ipopt)")
    return terms


def user_cost(problem: Problem, transcription: VariationalTranscription) -> Any:
    """The Problem's CallbackCosts as the shooting problem's user_cost (one Python call per rollout and
    per linearisation, every step at once), or None: the samples are each step's control points q^{k,a},
    q̇^{k,a} = (1/dt) sum_b b^{ab} q^{k,b} and its held u, as the VI transcription's."""
    costs = [c for c in problem.costs if isinstance(c, CallbackCost)]
    if not costs:
        return None
    smap = transcription.sample_map()
    t, w = smap.t, smap.w
    n, m, S1, dt = problem.model.n, problem.model.n_controls, transcription.s + 1, problem.dt
    b = transcription.integrator.differentiation_matrix
    L = np.zeros((S1, 2 * n + m, S1 * n + m))      # (q^a, q̇^a, u) = L_a (vec Q, u)
    for a in range(S1):
        L[a, :n, a * n:(a + 1) * n] = np.eye(n)
        for c in range(S1):
            L[a, n:2 * n, c * n:(c + 1) * n] = b[a, c] / dt * np.eye(n)
        L[a, 2 * n:, S1 * n:] = np.eye(m)

    def samples(cps: np.ndarray, us: np.ndarray) -> Samples:
        N = len(us)
        v = np.einsum("ab,kbn->kan", b, cps) / dt
        return Samples(t, w, cps.reshape(N * S1, n), v.reshape(N * S1, n), np.repeat(us, S1, axis=0), N * S1 - 1)

    def fun(kind: str, cps: np.ndarray, us: np.ndarray) -> Any:
        s = samples(cps, us)
        N = len(us)
        if kind == "value":
            return sum(checked_cost(c, s, "CallbackCost", finite=True)[0] for c in costs)
        g = np.zeros((N, S1 * n + m))
        H = np.zeros((N, S1 * n + m, S1 * n + m))
        for c in costs:
            _, dq, dv, du = checked_cost(c, s, "CallbackCost", finite=True)
            per = np.concatenate([dq, dv, du], axis=1).reshape(N, S1, 2 * n + m)
            g += np.einsum("kai,aij->kj", per, L)
            Hs = real_array(c.hessian(s.t, s.w, s.q, s.v, s.u), "CallbackCost hessian", (N * S1, 2 * n + m, 2 * n + m))
            H += np.einsum("aij,kaip,apl->kjl", L, Hs.reshape(N, S1, 2 * n + m, 2 * n + m), L)
        return g, H
    return fun


def check_problem(problem: Problem) -> None:
    """ValueError naming what a Problem asks that FDDP does not handle."""
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a hovi.trajopt.Problem, got {type(problem).__name__}")
    problem.check()
    if problem.controls != "held":
        raise ValueError("FDDP needs held controls: Problem(..., controls='held') (one control per step)")
    if problem.qT is not None:
        raise ValueError("FDDP has no hard final state: express it as a TerminalCost (or solve with IPOPT)")
    if problem.path_constraints or problem.input_constraints:
        raise ValueError("FDDP handles control bounds only: path and input constraints need IPOPT")
    if problem.contacts is not None:
        raise ValueError("FDDP does not handle contact-implicit problems: use solve_contact")
    if problem.model.n_constraints:
        raise ValueError("FDDP does not handle models with holonomic constraints")
    if np.any(np.isfinite(problem.q_lower)) or np.any(np.isfinite(problem.q_upper)):
        raise ValueError("FDDP does not enforce joint bounds: give q_bounds=(-np.inf, np.inf) (or solve with IPOPT)")


class FDDP(Solver):
    """Box-FDDP on the VI (Mastalli et al. 2020 with Tassa's box-QP for the control bounds), in C++:
    the dynamics are the integrator's step and its exact Jacobians, the costs the Problem's on the
    VI transcription's samples (Gauss-Newton Hessian). Stops when the iterate is a VI trajectory
    (no gaps) and the projected control gradient sum_k |Q_u|^2 < tol.

    guess: None (zero controls), a Result (its controls), controls (N, m) or (m,), or functions
    (q(t), v(t), u(t)) (u sampled at the middle of each step); FDDP starts from their rollout.

    Through contact with the contact state held (smoothing = 0) a sticking contact has no
    sensitivity to pushes below its friction limit: from rest FDDP stops where it starts (its
    stopping test holds there). Such a stop is not reported as a success: when one FDDP iteration
    with smoothed contact Jacobians from there lowers the cost, the Result has success False and a
    status saying so (``solver['held_contact_descent']``: that decrease). Smooth (``smoothing`` > 0)
    or start from controls that make it move."""

    CHECK_SMOOTHING = 1e-10  # (N s)^2: the held-contact check's; any small one gives the gradient across a stick

    def __init__(self, max_iterations: int = 500, tol: float = 1e-9, threads: int = 1, *, contacts: Any = None,
                 smoothing: float = 0.0):
        self.max_iterations = whole_number(max_iterations, "max_iterations")
        self.tol = real_number(tol, "tol", minimum=0.0, strict_minimum=True)
        self.threads = whole_number(threads, "threads", minimum=1)
        self.contacts = contacts
        self.smoothing = real_number(smoothing, "smoothing", minimum=0.0)
        if self.smoothing and contacts is None:
            raise ValueError("smoothing is for shooting through contact (give contacts)")

    def dynamics(self, problem: Problem, transcription: VariationalTranscription) -> Integrator:
        """The integrator FDDP shoots with: the transcription's, or with ``contacts`` the contact simulator (s = 1)."""
        if self.contacts is None:
            return transcription.integrator
        if transcription.s != 1:
            raise ValueError(f"FDDP through contact needs VI(1) (the contact time-stepping), got VI({transcription.s})")
        return Integrator(problem.model, s=1, dt=problem.dt, tol=1e-13, contacts=self.contacts, locate_impacts=False)

    def shooting_problem(self, problem: Problem, transcription: VariationalTranscription,
                         integrator: Optional[Integrator] = None, *, smoothing: Optional[float] = None) -> Any:
        """The C++ ShootingProblem of ``problem`` on ``integrator`` (default ``dynamics``: the
        transcription's integrator, or the contact simulator) with ``smoothing`` (default this solver's)."""
        check_problem(problem)
        integ = self.dynamics(problem, transcription) if integrator is None else integrator
        integ.check_start(problem.q0, "the problem's q0")
        x0 = np.concatenate([problem.q0, integ.momentum(problem.q0, problem.qdot0)])
        return _core.control.ShootingProblem(integ.core, problem.N, x0, sample_costs(problem, transcription),
                                             problem.u_lower, problem.u_upper,
                                             self.smoothing if smoothing is None else smoothing)

    def solve(self, problem: Problem, transcription: TranscriptionMethod = VI(2), guess: Guess = None) -> Result:
        """Solve ``problem`` on ``VI(s)`` from ``guess``; a Result whose x is the VI transcription's."""
        if not isinstance(transcription, VI):
            raise ValueError(f"FDDP shoots with the variational integrator: give hovi.trajopt.VI(s), got {transcription!r}")
        t0 = time.perf_counter()
        check_problem(problem)  # before transcribing: its errors name what FDDP does not handle
        tr = transcription.transcribe(problem)
        integ = self.dynamics(problem, tr)
        sp = self.shooting_problem(problem, tr, integ)
        us = self._initial_controls(problem, guess)
        setup = time.perf_counter() - t0
        user = user_cost(problem, tr)
        out = sp.solve(None, us, self.max_iterations, self.tol, self.threads, user)
        if out["converged"] and self.contacts is not None and self.smoothing == 0:
            self._check_held_contact(out, problem, tr, integ, user)
        n, N, s = problem.model.n, problem.N, tr.s
        U = np.repeat(out["us"][:, None, :], s + 1, axis=1)
        traj = integ.rollout(problem.q0, N, p0=out["xs"][0, n:], u=U, raise_on_failure=False)
        x = tr.guess_from_rollout(traj, U) if traj.steps == N else np.full(tr.core.n_variables, np.nan)
        res = self._result(out, tr, x, setup, t0)
        res.solver["trajectory"] = traj  # the solution simulated (through contact: with its impulses)
        if "held_contact_descent" in out:
            res.solver["held_contact_descent"] = out["held_contact_descent"]
        return res

    def _check_held_contact(self, out: dict[str, Any], problem: Problem, tr: VariationalTranscription,
                            integ: Integrator, user: Any) -> None:
        """A solve through contact that stopped with the contact state held: one iteration with smoothed
        Jacobians from its solution (on the same simulator); if that lowers the cost, the stop was a
        sticking contact's zero gradient, not an optimum, and ``out`` says so (not converged)."""
        smoothed = self.shooting_problem(problem, tr, integ, smoothing=self.CHECK_SMOOTHING)
        decrease = float(out["cost"] - smoothed.solve(out["xs"], out["us"], 1, self.tol, self.threads, user)["cost"])
        out["held_contact_descent"] = decrease
        if decrease > 1e-6 * (1 + abs(out["cost"])):
            out["converged"] = False
            out["status"] = (f"zero gradient through a held contact: stationary only with each contact's state "
                             f"held (a sticking contact hides pushes beyond friction; one smoothed iteration lowers "
                             f"the cost by {decrease:.3g}): solve with smoothing > 0, or from a guess that makes it "
                             "slide")

    @staticmethod
    def _result(out: dict[str, Any], tr: VariationalTranscription, x: np.ndarray, setup: float, t0: float) -> Result:
        res = Result(status=out["status"], success=bool(out["converged"]), cost=float(out["cost"]),
                     constraint_violation=float(out["gaps"]), iterations=int(out["iterations"]),
                     wall_seconds=time.perf_counter() - t0, trajectory=tr.trajectory(x), x=x,
                     timing={"setup": setup, "solver": float(out["seconds"])},
                     sizes={"steps": tr.N}, transcription=tr,
                     solver={k: out[k] for k in ("xs", "us", "K", "trace", "stop", "feasible")})
        return res

    @staticmethod
    def _initial_controls(problem: Problem, guess: Guess) -> Optional[np.ndarray]:
        if guess is None or (isinstance(guess, str) and guess == "rollout"):
            return None
        m = problem.model.n_controls
        if isinstance(guess, Result):
            f = guess.control_function()
        elif isinstance(guess, tuple) and len(guess) == 3 and callable(guess[2]):
            f = guess[2]
        elif isinstance(guess, (np.ndarray, list)):
            u = real_array(guess, "guess (controls)")
            if u.shape not in ((m,), (problem.N, m)):
                raise ValueError(f"FDDP guess controls must be ({m},) or ({problem.N}, {m}), got {u.shape}")
            return np.clip(np.broadcast_to(u, (problem.N, m)), problem.u_lower, problem.u_upper)
        else:
            raise ValueError("FDDP guess must be None, a Result, controls (N, m) or (m,), or functions (q(t), v(t), u(t))")
        t = (np.arange(problem.N) + 0.5) * problem.dt
        name = f"FDDP guess: u(t) at the middles t ({problem.N},) of the steps"
        u = real_array(f(t), name)
        if u.shape != (problem.N, m) and not (m == 1 and u.shape == (problem.N,)):
            raise ValueError(f"{name} must be ({problem.N}, {m}) controls, got shape {u.shape}")
        return np.clip(u.reshape(problem.N, m), problem.u_lower, problem.u_upper)
