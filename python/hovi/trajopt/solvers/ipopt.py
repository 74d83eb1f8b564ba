"""IPOPT (through cyipopt, the optional dependency hovi[trajopt]) as a solver of the NLP.

The Hessian of the Lagrangian is IPOPT's limited-memory quasi-Newton (L-BFGS) approximation by
default (the paper gives no second derivatives of the DEL equations), or coloured differences of
the exact gradient (``hessian='fd'``, hessian.py). Each IPOPT callback is one vectorised
evaluation: the dynamics constraints and their Jacobian are single C++ calls with the GIL
released; costs and path constraints are vectorised numpy over all samples.
"""
from __future__ import annotations

import contextlib
import time
from typing import Any, Callable, Iterator

import numpy as np

from ..hessian import LagrangianHessian
from ..nlp import NLP
from ..problem import Problem
from ..result import Result
from ..transcription import Guess, TranscriptionMethod
from ..transcriptions import DEFAULT_TRANSCRIPTION, resolve
from .base import NLPSolver

# hovi's IPOPT defaults; why each differs from IPOPT's own: bench/README.md, "Design measurements"
DEFAULT_OPTIONS = {
    "hessian_approximation": "limited-memory",
    "tol": 1e-8,
    "constr_viol_tol": 1e-10,
    "bound_relax_factor": 0.0,  # bounds and inequality constraints hold exactly at the solution
    "acceptable_iter": 0,  # no early stop on the looser "acceptable" level
    "max_iter": 3000,
    "print_level": 0,
    "sb": "yes",
    "mu_strategy": "adaptive",
    "limited_memory_max_history": 30,  # IPOPT's default is 6
}

HESSIANS = ("lbfgs", "fd")

# Called after every IPOPT iteration of every solve in this process (on_iteration).
_ITERATION_HOOKS: list[Callable[[int, float, float, float], None]] = []
_SOLVING = [0]  # IPOPT solves running in this process (solving())


def solving() -> bool:
    """Whether an IPOPT solve is running in this process (a heartbeat stays quiet between solves)."""
    return _SOLVING[0] > 0


@contextlib.contextmanager
def on_iteration(callback: Callable[[int, float, float, float], None]) -> Iterator[None]:
    """Within the block, ``callback(iteration, cost, primal_infeasibility, dual_infeasibility)``
    after every IPOPT iteration of every solve (also ``verbose=False`` ones, and the solves of a
    contact homotopy): a heartbeat for long solves (``hovi example``). An exception it raises
    stops the solve and is raised by it."""
    _ITERATION_HOOKS.append(callback)
    try:
        yield
    finally:
        _ITERATION_HOOKS.remove(callback)


class IpoptCallbacks:
    """The cyipopt problem object: forwards to the NLP, times the callbacks, prints progress.

    An exception in a callback must not cross into IPOPT: cyipopt lets some propagate through C
    (the Jacobian callback) and answers others with uninitialised values. The first exception is
    kept, IPOPT is told the evaluation failed (CyIpoptEvaluationError) and stopped at the next
    iteration, and ``Ipopt.solve_nlp`` raises the kept exception."""

    def __init__(self, nlp: NLP, verbose: bool, evaluation_error: type):
        self.nlp, self.verbose = nlp, verbose
        self.evaluation_error = evaluation_error
        self.error: BaseException | None = None
        self.callback_seconds = 0.0
        self.iterations = 0

    def timed(self, f, x):
        """f(x), its time added to ``callback_seconds``; an exception kept and reported to IPOPT."""
        if self.error is not None:
            raise self.evaluation_error("an earlier callback failed")
        t0 = time.perf_counter()
        try:
            return f(x)
        except Exception as e:  # kept and raised by solve_nlp(); IPOPT only learns the evaluation failed
            self.error = e
            raise self.evaluation_error(str(e)) from e
        finally:
            self.callback_seconds += time.perf_counter() - t0

    def objective(self, x):
        return self.timed(self.nlp.objective, x)

    def gradient(self, x):
        return self.timed(self.nlp.gradient, x)

    def constraints(self, x):
        return self.timed(self.nlp.constraints, x)

    def jacobian(self, x):
        return self.timed(self.nlp.jacobian, x)

    def jacobianstructure(self):
        return self.nlp.jac_rows, self.nlp.jac_cols

    def intermediate(self, alg_mod, iter_count, obj_value, inf_pr, inf_du, mu, d_norm, regularization_size,
                     alpha_du, alpha_pr, ls_trials):
        self.iterations = iter_count
        if self.error is not None:
            return False
        for hook in tuple(_ITERATION_HOOKS):
            try:
                hook(iter_count, obj_value, inf_pr, inf_du)
            except Exception as e:  # kept and raised by solve_nlp(), like a callback's
                self.error = e
                return False
        if self.verbose:
            if iter_count % 20 == 0:
                print(f"{'iter':>5} {'cost':>14} {'primal inf':>11} {'dual inf':>10} {'log mu':>7}", flush=True)
            print(f"{iter_count:5d} {obj_value:14.7e} {inf_pr:11.3e} {inf_du:10.3e} {np.log10(mu):7.2f}", flush=True)
        return True


class IpoptCallbacksWithHessian(IpoptCallbacks):
    """IpoptCallbacks plus the Lagrangian's Hessian (hessian.LagrangianHessian) for IPOPT's exact Newton steps."""

    def __init__(self, nlp: NLP, verbose: bool, evaluation_error: type, probe: np.ndarray):
        super().__init__(nlp, verbose, evaluation_error)
        self.H = LagrangianHessian(nlp, probe)

    def hessianstructure(self):
        return self.H.structure

    def hessian(self, x, lagrange, obj_factor):
        return self.timed(lambda y: self.H.values(y, lagrange, obj_factor), x)


class Ipopt(NLPSolver):
    """IPOPT on the NLP. ``options`` are passed to IPOPT over hovi's ``DEFAULT_OPTIONS``
    (limited-memory Hessian, tol 1e-8, constraint violation 1e-10, bounds not relaxed);
    ``verbose`` prints one line per iteration.

    hessian: 'lbfgs' (IPOPT's limited-memory approximation: cheap iterations, many of them) or 'fd'
    (the Lagrangian's Hessian by coloured differences of the exact gradient, hessian.py, its
    pattern probed near the starting point: many Jacobian evaluations per iteration, far fewer
    iterations on large robots).

    The result's ``timing`` splits the wall time: 'evaluations' (the C++ transcription calls),
    'callbacks' (all time in hovi's callbacks: evaluations, costs, path constraints, Python and
    copies), 'ipopt' (the rest: IPOPT's own work, mostly the sparse linear algebra)."""

    def __init__(self, options: dict[str, Any] | None = None, *, verbose: bool = True, hessian: str = "lbfgs"):
        if hessian not in HESSIANS:
            raise ValueError(f"hessian must be 'lbfgs' or 'fd', got '{hessian}'")
        self.options, self.verbose, self.hessian = dict(options or {}), bool(verbose), hessian

    def __repr__(self) -> str:
        return f"Ipopt(options={self.options!r}, verbose={self.verbose}, hessian={self.hessian!r})"

    def with_options(self, options: dict[str, Any]) -> Ipopt:
        """A copy with ``options`` over this one's."""
        return Ipopt({**self.options, **options}, verbose=self.verbose, hessian=self.hessian)

    def ipopt_options(self) -> dict[str, Any]:
        """The options IPOPT gets: hovi's defaults (for hessian 'fd': the exact Hessian) and ``options``."""
        defaults = dict(DEFAULT_OPTIONS)
        if self.hessian == "fd":
            defaults["hessian_approximation"] = "exact"
            del defaults["limited_memory_max_history"]
        return {**defaults, **self.options}

    def solve_nlp(self, nlp: NLP, guess: Guess = None) -> Result:
        """Solve ``nlp`` with IPOPT from ``guess`` (``Transcription.initial_guess``: None or
        'rollout', 'linear', a Result, or functions (q(t), v(t), u(t)) of times t (K,) returning
        (K, n), (K, n), (K, m))."""
        try:
            import cyipopt
        except ImportError as e:  # pragma: no cover - depends on the installation
            raise ImportError("hovi.trajopt.solve needs cyipopt: pip install 'hovi[trajopt]' (it builds against "
                              "IPOPT: apt-get install coinor-libipopt-dev pkg-config, or `make trajopt-deps`)") from e
        tr = nlp.transcription
        x0 = np.clip(tr.initial_guess(guess), nlp.lower, nlp.upper)
        for f in (nlp.objective, nlp.gradient, nlp.constraints, nlp.jacobian):
            f(x0)  # user costs and path constraints raise their errors here, before IPOPT runs
        nlp.eval_seconds = 0.0
        if self.hessian == "lbfgs":
            cb = IpoptCallbacks(nlp, self.verbose, cyipopt.CyIpoptEvaluationError)
        else:  # the Hessian's pattern probed near the start (hessian.LagrangianHessian)
            cb = IpoptCallbacksWithHessian(nlp, self.verbose, cyipopt.CyIpoptEvaluationError, x0)
        ip = cyipopt.Problem(n=nlp.n_variables, m=nlp.n_constraints, problem_obj=cb, lb=nlp.lower, ub=nlp.upper,
                             cl=nlp.cl, cu=nlp.cu)
        for key, value in self.ipopt_options().items():
            ip.add_option(key, value)
        t0 = time.perf_counter()
        _SOLVING[0] += 1
        try:
            x, info = ip.solve(x0)
        finally:
            _SOLVING[0] -= 1
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
        if self.verbose:
            print(f"{tr.name}: {status} after {cb.iterations} iterations, {wall:.3f} s; cost {result.cost:.8g}, "
                  f"constraint violation {result.constraint_violation:.2e}")
        return result


def solve(problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION, *, s: int | None = None,
          guess: Guess = None, options: dict[str, Any] | None = None, verbose: bool = True,
          hessian: str = "lbfgs") -> Result:
    """Transcribe ``problem`` with ``transcription`` (``VI(s=2)`` by default: the Galerkin VI of order
    4; ``HermiteSimpson("implicit")`` or ``HermiteSimpson("explicit")``) and solve it with IPOPT:
    ``Ipopt(options, verbose=verbose, hessian=hessian).solve(problem, transcription, guess)``.

    guess: None or 'rollout' (simulate from the initial state with zero controls; if that fails,
    'linear'), 'linear', a Result (warm start from a solve of the same transcription), or
    functions (q(t), v(t), u(t)) of times t (K,) returning (K, n), (K, n), (K, m).

    options, hessian, verbose and the result's ``timing``: see ``Ipopt``. The old spellings
    ``solve(problem, "vi", s=2)``, ``solve(problem, "hs-implicit")`` still work for one release
    (DeprecationWarning)."""
    method = resolve(transcription, s, old_default_s=2, caller="solve")
    return Ipopt(options, verbose=verbose, hessian=hessian).solve(problem, method, guess)
