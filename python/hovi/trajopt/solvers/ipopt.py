"""IPOPT as a solver of the NLP, through IPOPT's C++ interface (``_ipopt`` here, built where
pkg-config finds IPOPT: every callback in C++, the GIL released).

The Hessian of the Lagrangian is, by default, the VI's own (``hessian='directional'``: the DEL
equations' second derivatives along the multipliers, del_hessian.hpp) and the built-in rows'
exact ones (path constraints on body points, contact rows), with the Python terms' part by
coloured differences (hessian.py); or coloured differences of everything (``hessian='fd'``); or
IPOPT's limited-memory quasi-Newton approximation (``hessian='lbfgs'``). Python is called only for
the costs and path constraints written in Python: one vectorised call over all samples per
evaluation.
"""
from __future__ import annotations

import difflib
import functools
import contextlib
import time
from typing import Any, Callable, Iterator

import numpy as np

from ..hessian import LagrangianHessian
from ..nlp import NLP
from ..._checks import whole_number
from ..costs import CallbackCost
from ..problem import Problem
from ..result import Result
from ..transcription import Guess, TranscriptionMethod
from ..transcriptions import DEFAULT_TRANSCRIPTION, transcription_method
from ..variational import VI
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

HESSIANS = ("auto", "lbfgs", "fd", "directional")
EXACT_HESSIANS = ("auto", "fd", "directional")  # IPOPT gets hovi's Hessian
CONTINUATIONS = ("lbfgs",)  # besides True (VI(s=1) with this solver's Hessian) and False
# IPOPT iterations a continued solve gets before the direct solve replaces it: on the swing-ups the
# useful ones take 4-37, the lost ones 499-3000 (bench/README.md, "Design measurements", ipopt.py)
CONTINUED_MAX_ITER = 100

# IPOPT's return codes (ApplicationReturnStatus) and their messages, as IPOPT's C interface words them.
STATUS_MESSAGES = {
    0: "Algorithm terminated successfully at a locally optimal point, satisfying the convergence tolerances "
       "(can be specified by options).",
    1: "Algorithm stopped at a point that was converged, not to \"desired\" tolerances, but to \"acceptable\" "
       "tolerances (see the acceptable-... options).",
    2: "Algorithm converged to a point of local infeasibility. Problem may be infeasible.",
    3: "Algorithm proceeds with very little progress.",
    4: "It seems that the iterates diverge.",
    5: "The user call-back function intermediate_callback (see Section 3.3.1 in the documentation) returned false, "
       "i.e., the user code requested a premature termination of the optimization.",
    6: "Feasible point for square problem found.",
    -1: "Maximum number of iterations exceeded (can be specified by an option).",
    -2: "Restoration phase failed, algorithm doesn't know how to continue.",
    -3: "An unrecoverable error occurred while Ipopt tried to compute the search direction.",
    -4: "Maximum CPU time exceeded.",
    -10: "Problem has too few degrees of freedom.",
    -11: "Problem has inconsistent variable bounds or constraint sides.",
    -12: "Invalid option encountered.",
    -13: "Invalid number in NLP function or derivative detected.",
    -100: "Unrecoverable exception occurred.",
    -101: "Unknown exception caught in Ipopt.",
    -102: "Not enough memory.",
    -199: "INTERNAL ERROR: Unknown SolverReturn value - Notify IPOPT Authors.",
}


def _start(nlp: NLP, guess: Guess) -> np.ndarray:
    """The starting point x0 of a solve of ``nlp`` from ``guess``, within the bounds; the errors of
    user costs and path constraints are raised here, before IPOPT runs."""
    x0 = np.clip(nlp.transcription.initial_guess(guess), nlp.lower, nlp.upper)
    nlp.check_start(x0)
    return x0


def _cpp_ipopt() -> Any:
    """The extension _ipopt (IPOPT's C++ interface on the NLP program); ImportError saying how to get it
    where hovi was built without IPOPT."""
    try:
        from . import _ipopt
    except ImportError as e:  # pragma: no cover - depends on the build
        raise ImportError("hovi was built without IPOPT: install it (Debian: apt-get install coinor-libipopt-dev "
                          "pkg-config; scripts/setup.sh does) and reinstall hovi") from e
    return _ipopt


def ipopt_version() -> str:
    """The version of the IPOPT hovi was built against (ImportError without IPOPT)."""
    version: str = _cpp_ipopt().ipopt_version
    return version

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


# IPOPT's options by the type of their value (IPOPT 3.11 to 3.14; the subset of its options
# reference users reach for). Only for the messages: whether IPOPT takes an option is IPOPT's say.
_NUMBER, _INTEGER, _TEXT = "a number", "an integer", "a string"
IPOPT_OPTION_TYPES = {
    **dict.fromkeys((
        "tol", "dual_inf_tol", "constr_viol_tol", "compl_inf_tol", "acceptable_tol", "acceptable_dual_inf_tol",
        "acceptable_constr_viol_tol", "acceptable_compl_inf_tol", "acceptable_obj_change_tol", "diverging_iterates_tol",
        "max_cpu_time", "max_wall_time", "mu_init", "mu_max", "mu_min", "mu_target", "mu_max_fact",
        "mu_linear_decrease_factor", "mu_superlinear_decrease_power", "barrier_tol_factor", "bound_relax_factor",
        "bound_push", "bound_frac", "slack_bound_push", "slack_bound_frac", "constr_mult_init_max",
        "bound_mult_init_val", "obj_scaling_factor", "nlp_scaling_max_gradient", "nlp_scaling_obj_target_gradient",
        "nlp_scaling_constr_target_gradient", "nlp_scaling_min_value", "nlp_lower_bound_inf", "nlp_upper_bound_inf",
        "warm_start_bound_push", "warm_start_bound_frac", "warm_start_slack_bound_push",
        "warm_start_slack_bound_frac", "warm_start_mult_bound_push", "warm_start_mult_init_max",
        "required_infeasibility_reduction", "expect_infeasible_problem_ctol", "expect_infeasible_problem_ytol",
        "kappa_d", "s_max", "tau_min", "alpha_for_y_tol", "point_perturbation_radius",
        "derivative_test_perturbation", "derivative_test_tol", "findiff_perturbation", "limited_memory_init_val",
        "limited_memory_init_val_max", "limited_memory_init_val_min", "mumps_pivtol", "mumps_pivtolmax",
        "mumps_dep_tol", "ma27_pivtol", "ma27_pivtolmax", "ma57_pivtol", "ma57_pivtolmax", "ma86_u", "ma97_u",
        "fixed_mu_oracle_tol", "mu_oracle_quality_function_tol", "recalc_y_feas_tol", "max_cpu_time_resto",
        "resto_penalty_parameter", "resto_proximity_weight", "bound_mult_reset_threshold",
        "constr_mult_reset_threshold", "residual_ratio_max", "residual_ratio_singular", "residual_improvement_factor",
        "neg_curv_test_tol", "max_hessian_perturbation", "min_hessian_perturbation", "first_hessian_perturbation",
        "perturb_inc_fact_first", "perturb_inc_fact", "perturb_dec_fact", "jacobian_regularization_value",
        "jacobian_regularization_exponent", "theta_max_fact", "theta_min_fact", "eta_phi", "delta", "s_phi",
        "s_theta", "gamma_phi", "gamma_theta", "alpha_min_frac", "kappa_soc", "obj_max_inc", "watchdog_trial_iter_max",
        "soft_resto_pderror_reduction_factor", "tiny_step_tol", "tiny_step_y_tol", "sigma_max", "sigma_min", "quality_function_section_sigma_tol", "quality_function_section_qf_tol",
        "adaptive_mu_monotone_init_factor", "adaptive_mu_kkterror_red_fact", "filter_margin_fact", "filter_max_margin",
        "adaptive_mu_safeguard_factor"), _NUMBER),
    **dict.fromkeys((
        "max_iter", "print_level", "file_print_level", "acceptable_iter", "limited_memory_max_history",
        "limited_memory_max_skipping", "max_resto_iter", "max_soc", "watchdog_shortened_iter_trigger",
        "print_frequency_iter", "derivative_test_first_index", "mumps_mem_percent", "mumps_permuting_scaling",
        "mumps_pivot_order", "mumps_scaling", "max_refinement_steps", "min_refinement_steps",
        "accept_after_max_steps", "adaptive_mu_kkt_norm_type", "max_filter_resets", "filter_reset_trigger",
        "num_linear_variables", "ma57_pivot_order", "ma57_block_size", "ma57_node_amalgamation",
        "ma57_small_pivot_flag", "quality_function_max_section_steps", "ma27_liw_init_factor",
        "ma27_la_init_factor", "ma27_meminc_factor"), _INTEGER),
    **dict.fromkeys((
        "hessian_approximation", "mu_strategy", "mu_oracle", "fixed_mu_oracle", "linear_solver",
        "nlp_scaling_method", "warm_start_init_point", "derivative_test", "sb", "print_user_options",
        "print_options_documentation", "output_file", "option_file_name", "print_timing_statistics",
        "honor_original_bounds", "check_derivatives_for_naninf", "fixed_variable_treatment", "jac_c_constant",
        "jac_d_constant", "hessian_constant", "limited_memory_update_type", "limited_memory_initialization",
        "limited_memory_special_for_resto", "limited_memory_aug_solver", "line_search_method",
        "accept_every_trial_step", "corrector_type", "expect_infeasible_problem", "start_with_resto", "recalc_y",
        "alpha_for_y", "adaptive_mu_globalization", "mehrotra_algorithm", "dependency_detector",
        "linear_system_scaling", "linear_scaling_on_demand", "skip_finalize_solution_call", "print_info_string",
        "inf_pr_output", "timing_statistics", "bound_mult_init_method", "least_square_init_primal",
        "least_square_init_duals", "mu_allow_fast_monotone_decrease", "evaluate_orig_obj_at_resto_trial",
        "hessian_approximation_space", "replace_bounds", "derivative_test_print_all", "jacobian_approximation",
        "gradient_approximation", "ma57_automatic_scaling", "warm_start_same_structure", "warm_start_entire_iterate",
        "dependency_detection_with_rhs", "fast_step_computation", "neg_curv_test_reg", "perturb_always_cd",
        "skip_corr_if_neg_curv", "skip_corr_in_monotone_mode", "print_advanced_options", "file_append",
        "quality_function_norm_type", "quality_function_centrality", "quality_function_balancing_term",
        "constraint_violation_norm_type", "hsllib", "pardisolib", "grad_f_constant"), _TEXT),
}


def _option_type(value: Any) -> str:
    if isinstance(value, str):
        return _TEXT
    if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
        return _INTEGER
    if isinstance(value, (float, np.floating)):
        return _NUMBER
    return type(value).__name__


def apply_options(problem: Any, options: dict[str, Any]) -> None:
    """``problem.add_option(key, value)`` (the extension's ``Ipopt``) for every option, numpy scalars as
    Python numbers; ValueError (TypeError for a name that is not a string) naming the option,
    its value and, for a name IPOPT does not know, the closest one it does."""
    for key, value in options.items():
        if not isinstance(key, str):
            raise TypeError(f"IPOPT option names are strings, got {key!r} ({type(key).__name__})")
        kind = _option_type(value)
        if kind not in (_TEXT, _INTEGER, _NUMBER):
            raise ValueError(f"IPOPT option {key!r}: the value must be a string, an integer or a number, got "
                             f"{type(value).__name__} {value!r:.60}")
        if kind == _INTEGER and IPOPT_OPTION_TYPES.get(key) == _NUMBER:
            kind = _NUMBER                     # tol=1: IPOPT takes a number option only as a float
        plain = str(value) if kind == _TEXT else int(value) if kind == _INTEGER else float(value)
        if kind == _NUMBER and np.isnan(plain):
            raise ValueError(f"IPOPT option {key!r}: the value is NaN")
        try:
            problem.add_option(key, plain)
        except (TypeError, ValueError) as e:
            expected = IPOPT_OPTION_TYPES.get(key)
            if expected is None:
                close = difflib.get_close_matches(key, list(dict.fromkeys([*IPOPT_OPTION_TYPES, *DEFAULT_OPTIONS])), n=3)
                hint = f" (did you mean {' or '.join(repr(c) for c in close)}?)" if close else ""
                raise ValueError(f"unknown IPOPT option {key!r}{hint}: IPOPT refused {key!r} = {value!r:.60} "
                                 f"(see IPOPT's options reference)") from e
            if expected != kind and not (expected == _NUMBER and kind == _INTEGER):
                raise ValueError(f"IPOPT option {key!r} takes {expected}, got {kind} {value!r:.60}") from e
            raise ValueError(f"IPOPT refused the value {value!r:.60} of option {key!r} (out of its range, or not one "
                             f"of its choices; see IPOPT's options reference)") from e


def after_iteration(verbose: bool, iteration: int, cost: float, inf_pr: float, inf_du: float, mu: float) -> bool:
    """After an IPOPT iteration: the ``on_iteration`` hooks and, verbose, a line of progress; True (go
    on). A hook's exception propagates."""
    for hook in tuple(_ITERATION_HOOKS):
        hook(iteration, cost, inf_pr, inf_du)
    if verbose:
        if iteration % 20 == 0:
            print(f"{'iter':>5} {'cost':>14} {'primal inf':>11} {'dual inf':>10} {'log mu':>7}", flush=True)
        print(f"{iteration:5d} {cost:14.7e} {inf_pr:11.3e} {inf_du:10.3e} {np.log10(mu):7.2f}", flush=True)
    return True


def _set_colouring(program: Any, H: LagrangianHessian, threads: int | None, by_differences: bool) -> None:
    """Give the C++ program the Hessian of ``H``'s colouring."""
    program.set_colouring(H.colour.astype(np.int32), H.rows.astype(np.int32), H.cols.astype(np.int32),
                          H.read_row.astype(np.int32), H.read_col.astype(np.int32), threads, by_differences)


def with_continuation(result: Result, first: Result, seconds: float, used: bool) -> Result:
    """``result`` with the first stage of an order continuation recorded: ``timing['continuation']``
    (its seconds) and ``solver['continuation']`` (its transcription, success, iterations, cost,
    seconds, and whether ``result`` started from it)."""
    result.timing["continuation"] = seconds
    result.solver["continuation"] = {"transcription": first.transcription.method, "success": first.success,
                                     "iterations": first.iterations, "cost": first.cost, "seconds": seconds,
                                     "used": used}
    return result


class Ipopt(NLPSolver):
    """IPOPT on the NLP. ``options`` are passed to IPOPT over hovi's ``DEFAULT_OPTIONS``
    (limited-memory Hessian, tol 1e-8, constraint violation 1e-10, bounds not relaxed);
    ``verbose`` prints one line per iteration.

    hessian: the Lagrangian's Hessian IPOPT gets, its pattern probed near the starting point
    (hessian.py):
    'directional': the VI's own Hessian of its DEL equations (del_hessian.hpp: two evaluations of
    D^2 L_d per stage, world point forces such as contact forces from the points' kinematics, and
    for other body wrenches differences of their gradients per control point;
    1e-11 relative), the built-in path constraints' and contact rows' exact
    (trajopt/body_point_rows.cpp, complementarity_rows.cpp), the quadratic costs' exact, the Python
    terms' by coloured differences of the gradient; Hermite-Simpson, which has no Hessian of its
    own, differences its transcription's part;
    'fd': coloured differences of the exact gradient for all of it (one Jacobian evaluation per
    colour; 1e-8 relative);
    'lbfgs': IPOPT's limited-memory approximation (cheap iterations, many of them);
    'auto' (the default): 'directional' unless a CallbackCost, which may couple any variables,
    needs 'lbfgs'. Their costs: bench/README.md, "IPOPT's options and the Hessian's cost".

    threads: threads for the transcription's part of the Hessian (its stages, or the colours'
    differences; 1 by default, None: HOVI_NUM_THREADS or every core; costs and path constraints
    written in Python are differenced on the calling thread); the values do not
    depend on it. With threads, ``timing['evaluations']`` sums the threads' times (it can exceed
    the wall time).

    The result's ``timing`` splits the wall time: 'setup' (before IPOPT starts: building the NLP,
    the starting point and the Hessian's pattern and colouring; not in wall_seconds),
    then within the solve 'evaluations' (the C++ transcription calls), 'callbacks' (all time in
    hovi's callbacks: evaluations, costs, path constraints, Python and copies), 'ipopt' (the rest:
    IPOPT's own work, mostly the sparse linear algebra)."""

    def __init__(self, options: dict[str, Any] | None = None, *, verbose: bool = True, hessian: str = "auto",
                 continuation: bool | str = True, threads: int | None = 1):
        if not isinstance(hessian, str) or hessian not in HESSIANS:
            raise ValueError(f"hessian must be 'auto', 'directional', 'fd' or 'lbfgs', got {hessian!r}")
        if options is not None and not isinstance(options, dict):
            raise TypeError(f"options must be a dict of IPOPT options, got {type(options).__name__}")
        if not isinstance(continuation, (bool, np.bool_)) and continuation not in CONTINUATIONS:
            raise ValueError(f"continuation must be True, False or 'lbfgs', got {continuation!r}")
        self.options, self.verbose, self.hessian = dict(options or {}), bool(verbose), hessian
        self.continuation = continuation if isinstance(continuation, str) else bool(continuation)
        self.threads = None if threads is None else whole_number(threads, "threads", minimum=1)
        apply_options(_cpp_ipopt().Ipopt(), self.ipopt_options())

    def __repr__(self) -> str:
        return (f"Ipopt(options={self.options!r}, verbose={self.verbose}, hessian={self.hessian!r}, "
                f"continuation={self.continuation}, threads={self.threads})")

    def with_options(self, options: dict[str, Any]) -> Ipopt:
        """A copy with ``options`` over this one's."""
        return Ipopt({**self.options, **options}, verbose=self.verbose, hessian=self.hessian,
                     continuation=self.continuation, threads=self.threads)

    def solve(self, problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION,
              guess: Guess = None) -> Result:
        """Solve ``problem`` transcribed by ``transcription`` from ``guess``. With ``continuation`` (the
        default), a guess that is not a solution (None, 'rollout', 'linear') and a transcription other
        than VI(s=1): the VI of order 2 (s = 1) is solved first, from that guess, and the transcription
        starts from its solution's interpolants (Result.as_guess), with at most CONTINUED_MAX_ITER
        IPOPT iterations (not after an 'lbfgs' first stage). If either solve fails, the
        transcription is solved from ``guess`` as without continuation (``continue_from``: the second
        stage). Measured (bench/README.md, "IPOPT's options and the Hessian's cost"): it halved the
        cart-pole's time, turned a failed acrobot solve into 11 iterations, and cost the pendulum a
        quarter more than a direct solve. The first solve (and a failed continued one) is reported in
        ``timing['continuation']`` (seconds) and ``solver['continuation']`` ('used': whether the
        result started from the first solve).

        ``continuation='lbfgs'``: the first solve takes at most 50 iterations of IPOPT's limited-memory
        Hessian, converged or not, and the transcription starts from where it stopped. On the
        acrobot the two first stages lead to different local optima, and neither is always the
        better (bench/README.md, "Against CasADi, and the acrobot's optima")."""
        first_order = VI(1)
        if (not self.continuation or transcription == first_order or not (guess is None or isinstance(guess, str))
                or problem.contacts is not None):
            return super().solve(problem, transcription, guess)
        t0 = time.perf_counter()
        quasi_newton = self.continuation == "lbfgs"
        stage = Ipopt({**self.options, "max_iter": 50}, verbose=self.verbose, hessian="lbfgs",
                      continuation=False) if quasi_newton else self
        first = NLPSolver.solve(stage, problem, first_order, guess)
        started = first.success or (quasi_newton and np.all(np.isfinite(first.x)))
        return self.continue_from(first, problem, transcription, guess, since=t0, started=started,
                                  max_iter=None if quasi_newton else CONTINUED_MAX_ITER)

    def continue_from(self, first: Result, problem: Problem, transcription: TranscriptionMethod, guess: Guess,
                      *, max_iter: int | None = CONTINUED_MAX_ITER, since: float | None = None,
                      started: bool | None = None) -> Result:
        """The second stage of an order continuation: ``transcription`` solved from ``first``'s
        interpolants (``first``: a solve of the same problem with another transcription, e.g. VI(s=1))
        with at most ``max_iter`` IPOPT iterations (None: this solver's own limit); if ``first``
        failed (``started``: whether to start from it anyway) or this solve fails, ``transcription``
        from ``guess``. The first stage is recorded (``with_continuation``) with the seconds since
        ``since`` (``time.perf_counter()``, default now) less the returned solve's own."""
        t0 = time.perf_counter() if since is None else since
        started = first.success if started is None else started
        continued = self if max_iter is None else self.with_options(
            {"max_iter": min(self.ipopt_options()["max_iter"], max_iter)})
        result = NLPSolver.solve(continued, problem, transcription, first.as_guess()) if started else None
        used = result is not None and result.success
        seconds = time.perf_counter() - t0 - (result.timing["setup"] + result.wall_seconds if used else 0.0)
        if not used:
            result = NLPSolver.solve(self, problem, transcription, guess)
        return with_continuation(result, first, seconds, used)

    def hessian_for(self, nlp: NLP) -> str:
        """The Hessian used on ``nlp``: 'auto' resolved ('directional' unless the problem has a CallbackCost)."""
        if self.hessian != "auto":
            return self.hessian
        return "lbfgs" if any(isinstance(c, CallbackCost) for c in nlp.problem.costs) else "directional"

    def ipopt_options(self, hessian: str | None = None) -> dict[str, Any]:
        """The options IPOPT gets: hovi's defaults (for hessian 'directional', 'fd' and 'auto' unless
        told ``hessian``: IPOPT's exact-Hessian mode) and ``options``."""
        defaults = dict(DEFAULT_OPTIONS)
        if (hessian or self.hessian) in EXACT_HESSIANS:
            defaults["hessian_approximation"] = "exact"
            del defaults["limited_memory_max_history"]
        return {**defaults, **self.options}

    def solve_nlp(self, nlp: NLP, guess: Guess = None) -> Result:
        """Solve ``nlp`` with IPOPT from ``guess`` (``Transcription.initial_guess``: None or
        'rollout', 'linear', a Result, or functions (q(t), v(t), u(t)) of times t (K,) returning
        (K, n), (K, n), (K, m)): through IPOPT's C++ interface on ``nlp.program()``."""
        if self.hessian == "auto":
            return Ipopt(self.options, verbose=self.verbose, hessian=self.hessian_for(nlp), continuation=self.continuation,
                         threads=self.threads).solve_nlp(nlp, guess)
        return self._solve_in_cpp(_cpp_ipopt(), nlp, guess)

    def _result(self, nlp: NLP, x: np.ndarray, status: str, success: bool, cost: float, iterations: int,
                wall: float, timing: dict[str, float], solver: dict | None = None) -> Result:
        """The Result of a solve of ``nlp`` ending at x; ``timing`` gets
        'ipopt' (the wall time outside the callbacks) and 'per_iteration'. Verbose, a summary line."""
        tr = nlp.transcription
        timing = {**timing, "ipopt": wall - timing["callbacks"], "per_iteration": wall / max(iterations, 1)}
        result = Result(status=status, success=success, cost=cost, constraint_violation=nlp.violation(x),
                        iterations=iterations, wall_seconds=wall, trajectory=tr.trajectory(x), x=x, timing=timing,
                        sizes={"variables": nlp.n_variables, "constraints": nlp.n_constraints, "nonzeros": nlp.nnz,
                               "dynamics_constraints": tr.core.n_constraints},
                        transcription=tr, solver=solver or {})
        if self.verbose:
            print(f"{tr.name}: {status} after {iterations} iterations, {wall:.3f} s; cost {cost:.8g}, "
                  f"constraint violation {result.constraint_violation:.2e}")
        return result

    def _solve_in_cpp(self, cpp: Any, nlp: NLP, guess: Guess) -> Result:
        """solve_nlp through the extension: every callback in C++ (Python only for the NLP's terms
        written in Python, and after an iteration when verbose or an ``on_iteration`` hook asks)."""
        t_setup = time.perf_counter()
        x0 = _start(nlp, guess)
        program = nlp.program()
        exact = self.hessian in EXACT_HESSIANS
        if exact and not program.has_hessian:   # probed near its first start, once per transcription and terms
            H = LagrangianHessian(nlp, x0, own_structures=self.hessian == "directional")
            _set_colouring(program, H, self.threads, self.hessian == "fd")
        elif exact:
            program.set_hessian_options(self.threads, self.hessian == "fd")
        run = cpp.Ipopt()
        apply_options(run, self.ipopt_options())
        progress = functools.partial(after_iteration, self.verbose) if self.verbose or _ITERATION_HOOKS else None
        setup = time.perf_counter() - t_setup
        _SOLVING[0] += 1
        try:
            out = run.solve(program, x0, nlp.lower, nlp.upper, nlp.cl, nlp.cu, exact_hessian=exact,
                            callback=progress)
        finally:
            _SOLVING[0] -= 1
        status = int(out["status"])
        return self._result(nlp, out["x"], STATUS_MESSAGES.get(status, f"IPOPT returned status {status}"),
                            status in (0, 1), float(out["cost"]), int(out["iterations"]), out["seconds"],
                            {"setup": setup, "evaluations": out["cpp_seconds"],
                             "callbacks": out["callback_seconds"], "python": out["python_seconds"],
                             "hessian": out["hessian_seconds"]},
                            {"lambda": out["lambda"], "z_lower": out["z_lower"], "z_upper": out["z_upper"]})


def solve(problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION, *, guess: Guess = None, options: dict[str, Any] | None = None, verbose: bool = True,
          hessian: str = "auto", continuation: bool | str = True, threads: int | None = 1) -> Result:
    """Transcribe ``problem`` with ``transcription`` (``VI(s=2)`` by default: the Galerkin VI of order
    4; ``HermiteSimpson("implicit")`` or ``HermiteSimpson("explicit")``) and solve it with IPOPT:
    ``Ipopt(options, verbose=verbose, hessian=hessian, continuation=continuation,
    threads=threads).solve(problem, transcription, guess)``. TypeError for a transcription that is not a
    ``VI`` or ``HermiteSimpson``.

    guess: None or 'rollout' (simulate from the initial state with zero controls; if that fails,
    'linear'), 'linear', a Result (warm start from a solve of the same transcription), or
    functions (q(t), v(t), u(t)) of times t (K,) returning (K, n), (K, n), (K, m).

    options, hessian, verbose, continuation (solve VI(s=1) first; 'lbfgs': 50 L-BFGS iterations of
    it), threads (of the Hessian) and the result's ``timing``: see ``Ipopt``."""
    return Ipopt(options, verbose=verbose, hessian=hessian, continuation=continuation, threads=threads).solve(
        problem, transcription_method(transcription), guess)
