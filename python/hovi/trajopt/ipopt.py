"""Solving a Problem with IPOPT (through cyipopt, the optional dependency hovi[trajopt]).

The Hessian of the Lagrangian is IPOPT's limited-memory quasi-Newton (L-BFGS) approximation: the
paper gives no second derivatives of the DEL equations. Each IPOPT callback is one vectorised
evaluation: the dynamics constraints and their Jacobian are single C++ calls with the GIL
released; costs and path constraints are vectorised numpy over all samples.
"""
from __future__ import annotations

import time

from typing import Any, Callable, Tuple, Union

import numpy as np

from .hermite_simpson import HermiteSimpsonTranscription
from .nlp import NLP
from .problem import Problem
from .result import Result
from .transcription import Transcription
from .variational import VariationalTranscription

# An initial guess: None or 'rollout', 'linear', a Result, or (q(t), v(t), u(t)) functions
Guess = Union[None, str, Result, Tuple[Callable[[np.ndarray], np.ndarray], ...]]

DEFAULT_OPTIONS = {
    "hessian_approximation": "limited-memory",
    "tol": 1e-8,
    "constr_viol_tol": 1e-10,
    "bound_relax_factor": 0.0,  # bounds and inequality constraints hold exactly at the solution (measured: no cost in iterations)
    "acceptable_iter": 0,  # no early stop on the looser "acceptable" level
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    "mu_strategy": "adaptive",
    "limited_memory_max_history": 30,  # fewer iterations than the default 6 on the examples (measured)
}


def transcribe(problem: Problem, transcription: str = "vi", s: int = 2) -> Transcription:
    """The transcription named 'vi' (the Galerkin VI of order 2s), 'hs' or 'hs-implicit' (implicit
    Hermite-Simpson) or 'hs-explicit'."""
    if transcription == "vi":
        return VariationalTranscription(problem, s)
    if transcription in ("hs", "hs-implicit"):
        return HermiteSimpsonTranscription(problem, implicit=True)
    if transcription == "hs-explicit":
        return HermiteSimpsonTranscription(problem, implicit=False)
    raise ValueError(f"transcription must be 'vi', 'hs-implicit' or 'hs-explicit', got '{transcription}'")


def _linear_guess(problem: Problem):
    qT = problem.q0 if problem.qT is None else problem.qT
    T = problem.T
    return (lambda t: problem.q0 + np.outer(np.atleast_1d(t) / T, qT - problem.q0),
            lambda t: np.tile((qT - problem.q0) / T, (len(np.atleast_1d(t)), 1)),
            lambda t: np.zeros((len(np.atleast_1d(t)), problem.model.n_controls)))


def initial_guess(tr, guess):
    """x0 from: None or 'rollout' (simulate from the initial state with zero controls with the VI
    of the transcription's order; if that fails, 'linear'), 'linear' (q from q0 to qT in a straight
    line, zero controls), a Result (warm start from another solve of the same transcription),
    or a tuple of functions (q(t), v(t), u(t))."""
    problem = tr.problem
    if isinstance(guess, Result):
        if len(guess.x) != tr.core.n_variables:
            raise ValueError("the guess Result comes from a problem of a different size")
        return guess.x.copy()
    if isinstance(guess, tuple):
        return tr.guess(*guess)
    if guess in (None, "rollout"):
        from ..integrator import Integrator
        s = getattr(tr, "s", 2)
        integ = tr.integrator if isinstance(tr, VariationalTranscription) else Integrator(problem.model, s=s, dt=problem.dt)
        U = np.zeros((problem.N, s + 1, problem.model.n_controls))
        traj = integ.rollout(problem.q0, problem.N, qdot0=problem.qdot0, u=U if problem.model.n_controls else None,
                             raise_on_failure=False)
        if traj.steps == problem.N:
            if isinstance(tr, VariationalTranscription):
                return tr.guess_from_rollout(traj, U)
            from .transcription import piecewise_polynomial
            cp = traj.control_points
            return tr.guess(lambda t: piecewise_polynomial(problem.dt, integ.nodes, cp, t),
                            lambda t: piecewise_polynomial(problem.dt, integ.nodes, cp, t, derivative=True),
                            _linear_guess(problem)[2])
        guess = "linear"
    if guess == "linear":
        return tr.guess(*_linear_guess(problem))
    raise ValueError(f"guess must be None, 'rollout', 'linear', a Result or (q(t), v(t), u(t)), got {guess!r}")


class _Callbacks:
    """The cyipopt problem object: forwards to the NLP, times the callbacks, prints progress.

    An exception in a callback must not cross into IPOPT: cyipopt lets some propagate through C
    (the Jacobian callback) and answers others with uninitialised values. The first exception is
    kept, IPOPT is told the evaluation failed (CyIpoptEvaluationError) and stopped at the next
    iteration, and ``solve`` raises the kept exception."""

    def __init__(self, nlp: NLP, verbose: bool, evaluation_error: type):
        self.nlp, self.verbose = nlp, verbose
        self.evaluation_error = evaluation_error
        self.error: BaseException | None = None
        self.callback_seconds = 0.0
        self.iterations = 0

    def _time(self, f, x):
        if self.error is not None:
            raise self.evaluation_error("an earlier callback failed")
        t0 = time.perf_counter()
        try:
            return f(x)
        except Exception as e:  # kept and raised by solve(); IPOPT only learns the evaluation failed
            self.error = e
            raise self.evaluation_error(str(e)) from e
        finally:
            self.callback_seconds += time.perf_counter() - t0

    def objective(self, x):
        return self._time(self.nlp.objective, x)

    def gradient(self, x):
        return self._time(self.nlp.gradient, x)

    def constraints(self, x):
        return self._time(self.nlp.constraints, x)

    def jacobian(self, x):
        return self._time(self.nlp.jacobian, x)

    def jacobianstructure(self):
        return self.nlp.jac_rows, self.nlp.jac_cols

    def intermediate(self, alg_mod, iter_count, obj_value, inf_pr, inf_du, mu, d_norm, regularization_size,
                     alpha_du, alpha_pr, ls_trials):
        self.iterations = iter_count
        if self.error is not None:
            return False
        if self.verbose:
            if iter_count % 20 == 0:
                print(f"{'iter':>5} {'cost':>14} {'primal inf':>11} {'dual inf':>10} {'log mu':>7}", flush=True)
            print(f"{iter_count:5d} {obj_value:14.7e} {inf_pr:11.3e} {inf_du:10.3e} {np.log10(mu):7.2f}", flush=True)
        return True


class _CallbacksWithHessian(_Callbacks):
    """_Callbacks plus the Lagrangian's Hessian (hessian.LagrangianHessian) for IPOPT's exact Newton steps."""

    def __init__(self, nlp: NLP, verbose: bool, evaluation_error: type, probe: np.ndarray):
        super().__init__(nlp, verbose, evaluation_error)
        from .hessian import LagrangianHessian
        self.H = LagrangianHessian(nlp, probe)

    def hessianstructure(self):
        return self.H.structure

    def hessian(self, x, lagrange, obj_factor):
        return self._time(lambda y: self.H.values(y, lagrange, obj_factor), x)


def solve(problem: Problem, transcription: str = "vi", *, s: int = 2, guess: Guess = None,
          options: dict[str, Any] | None = None, verbose: bool = True, hessian: str = "lbfgs") -> Result:
    """Transcribe ``problem`` ('vi' with order 2s, 'hs-implicit' or 'hs-explicit') and solve it with
    IPOPT. ``options`` are passed to IPOPT over hovi's defaults (limited-memory Hessian, tol 1e-8,
    constraint violation 1e-10, bounds not relaxed). ``verbose`` prints one line per iteration.

    guess: see ``initial_guess``: None or 'rollout', 'linear', a Result, or functions (q(t), v(t),
    u(t)) of times t (K,) returning (K, n), (K, n), (K, m).

    hessian: 'lbfgs' (IPOPT's limited-memory approximation: cheap iterations, many of them) or 'fd'
    (the Lagrangian's Hessian by coloured differences of the exact gradient, hessian.py, its
    pattern probed near the starting point: about a hundred Jacobian evaluations per iteration on
    the paper's robots, far fewer iterations on large robots).

    The result's ``timing`` splits the wall time: 'evaluations' (the C++ transcription calls),
    'callbacks' (all time in hovi's callbacks: evaluations, costs, path constraints, Python and
    copies), 'ipopt' (the rest: IPOPT's own work, mostly the sparse linear algebra)."""
    try:
        import cyipopt
    except ImportError as e:  # pragma: no cover - depends on the installation
        raise ImportError("hovi.trajopt.solve needs cyipopt: pip install 'hovi[trajopt]' (it builds against "
                          "IPOPT: apt-get install coinor-libipopt-dev pkg-config, or `make trajopt-deps`)") from e
    tr = transcribe(problem, transcription, s)
    nlp = NLP(tr)
    x0 = np.clip(initial_guess(tr, guess), nlp.lower, nlp.upper)
    for f in (nlp.objective, nlp.gradient, nlp.constraints, nlp.jacobian):
        f(x0)  # user costs and path constraints raise their errors here, before IPOPT runs
    nlp.eval_seconds = 0.0
    if hessian not in ("lbfgs", "fd"):
        raise ValueError(f"hessian must be 'lbfgs' or 'fd', got '{hessian}'")
    if hessian == "lbfgs":
        cb = _Callbacks(nlp, verbose, cyipopt.CyIpoptEvaluationError)
    else:  # the Hessian's pattern probed near the start (hessian.LagrangianHessian)
        cb = _CallbacksWithHessian(nlp, verbose, cyipopt.CyIpoptEvaluationError, x0)
    ip = cyipopt.Problem(n=nlp.n_variables, m=nlp.n_constraints, problem_obj=cb, lb=nlp.lower, ub=nlp.upper,
                         cl=nlp.cl, cu=nlp.cu)
    defaults = dict(DEFAULT_OPTIONS)
    if hessian == "fd":
        defaults["hessian_approximation"] = "exact"
        del defaults["limited_memory_max_history"]
    for key, value in {**defaults, **(options or {})}.items():
        ip.add_option(key, value)
    t0 = time.perf_counter()
    x, info = ip.solve(x0)
    wall = time.perf_counter() - t0
    if cb.error is not None:
        raise cb.error
    status = info["status_msg"].decode() if isinstance(info["status_msg"], bytes) else str(info["status_msg"])
    result = Result(status=status, success=info["status"] in (0, 1), cost=float(info["obj_val"]),
                    constraint_violation=nlp.violation(x), iterations=cb.iterations, wall_seconds=wall,
                    trajectory=tr.trajectory(x), x=x,
                    timing={"evaluations": nlp.eval_seconds, "callbacks": cb.callback_seconds,
                            "ipopt": wall - cb.callback_seconds,
                            "per_iteration": wall / max(cb.iterations, 1)},
                    sizes={"variables": nlp.n_variables, "constraints": nlp.n_constraints, "nonzeros": nlp.nnz,
                           "dynamics_constraints": tr.core.n_constraints},
                    transcription=tr)
    if verbose:
        print(f"{tr.name}: {status} after {cb.iterations} iterations, {wall:.3f} s; cost {result.cost:.8g}, "
              f"constraint violation {result.constraint_violation:.2e}")
    return result
