"""
Riccati equations and closed-loop runs in C++ (hovi.control)
"""
from __future__ import annotations
import collections.abc
import hovi._core
import numpy
import numpy.typing
import typing
__all__: list[str] = ['ShootingProblem', 'backward_riccati', 'closed_loop', 'discrete_are', 'mpc', 'velocity_state_map']
class ShootingProblem:
    """
    The VI as the dynamics of an optimal control problem (control/shooting_problem.hpp): N steps of an
    Integrator from x0 = (q, p) (2n,), held controls within u_lower, u_upper (m,), and quadratic cost terms
    on the steps' control points (hovi.trajopt.FDDP builds it from a Problem).
    """
    def __init__(self, integrator: hovi._core.Integrator, N: typing.SupportsInt | typing.SupportsIndex, x0: numpy.typing.ArrayLike, costs: list, u_lower: numpy.typing.ArrayLike, u_upper: numpy.typing.ArrayLike, smoothing: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        """
        integrator: a _core.Integrator; with contacts (s = 1) the problem shoots through contact with its
        Jacobians held (smoothing = 0) or smoothed (smoothing > 0, contact_jacobians.hpp).
        costs: a list of dicts, each a term with `terminal` (bool) and diagonal weights and references per sample,
        Wq, q_ref, Wv, v_ref (rows, n), R, u_ref (rows, m): rows = S (s+1) for a running term (S stages; step k
        uses stage min(offset + k, S - 1)), 1 for a terminal term (the horizon's last sample).
        """
    def derivatives(self, k: typing.SupportsInt | typing.SupportsIndex, control_points: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike, impulses: numpy.typing.ArrayLike | None = None) -> dict[str, typing.Any]:
        """
        Step k's derivatives (through contact: at the step's impulses) at converged control points (s+1, n) with held u (m,): A (2n, 2n), B (2n, m), the cost
        gradient lx (2n,), lu (m,) and Gauss-Newton Hessian lxx, luu, lux.
        """
    def solve(self, xs: numpy.typing.ArrayLike | None = None, us: numpy.typing.ArrayLike | None = None, max_iterations: typing.SupportsInt | typing.SupportsIndex = 500, tol: typing.SupportsFloat | typing.SupportsIndex = 1e-09, threads: typing.SupportsInt | typing.SupportsIndex = 1, user_cost: collections.abc.Callable | None = None) -> dict[str, typing.Any]:
        """
        Box-FDDP (control/box_fddp.hpp) from xs (N+1, 2n) (None: the rollout of us from x0) and us (N, m) (None:
        zeros), in C++ with the GIL released. user_cost: None, or fun(kind, control_points (N, s+1, n), us (N, m))
        for costs computed in Python, one call per rollout ("value": the total) and per linearisation
        ("derivatives": g (N, (s+1) n + m) and the Gauss-Newton Hessian H (N, (s+1) n + m, (s+1) n + m) in each
        step's (vec(q^{k,0..s}) by points, u^k)); an exception it raises is raised. Returns a dict: xs, us,
        control_points (N, (s+1) n), K (N, m, 2n) (u = us + K (x - xs)), cost, stop, gaps, iterations, converged,
        feasible, status, trace (iterations, 5: cost, stop, step, regularisation, gaps), seconds.
        """
    def stage_cost(self, k: typing.SupportsInt | typing.SupportsIndex, control_points: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike) -> float:
        """
        The cost l^k of step k at its control points (s+1, n) with held controls u (m,).
        """
    @property
    def offset(self) -> int:
        """
        The stage of the cost terms' references that step 0 uses.
        """
    @offset.setter
    def offset(self, arg1: typing.SupportsInt | typing.SupportsIndex) -> None:
        ...
    @property
    def x0(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        The initial state (q, p), (2n,).
        """
    @x0.setter
    def x0(self, arg1: numpy.typing.ArrayLike) -> None:
        ...
def backward_riccati(A: numpy.typing.ArrayLike, B: numpy.typing.ArrayLike, Q: numpy.typing.ArrayLike, R: numpy.typing.ArrayLike, QN: numpy.typing.ArrayLike) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    """
    Finite-horizon LQR: A (N, n, n), B (N, n, m), Q (n, n) or (N, n, n), R (m, m) or (N, m, m), QN (n, n);
    returns (K (N, m, n), P (N+1, n, n)), u^k = -K^k x^k, cost-to-go x^T P^k x.
    """
def closed_loop(plants: list, x_ref: numpy.typing.ArrayLike, u_ref: numpy.typing.ArrayLike, gains: numpy.typing.ArrayLike, lower: numpy.typing.ArrayLike, upper: numpy.typing.ArrayLike, pushes: list, q0s: numpy.typing.ArrayLike, p0s: numpy.typing.ArrayLike, steps: typing.SupportsInt | typing.SupportsIndex, threads: int | None = None) -> tuple:
    """
    B closed-loop runs of `steps` steps in C++ (GIL released, `threads` threads): plants, a list of one or
    B _core.Integrator (with or without contacts); the policy u^{k,a} = clamp(u_ref^{k,a} - K^k (x - x_ref^k))
    from x_ref (S, nq + n), u_ref (S, (s+1) m), gains (S, m, 2n), lower, upper (m,); pushes: a list of one or
    B lists of (step, body, point (3,) in the joint frame, world impulse (3,)[, world angular impulse (3,)]);
    q0s (B, nq), p0s (B, n). Returns
    (items: B rollout dicts with `controls` (K, (s+1) m), or None for an item that raised, errors (B,)).
    """
def discrete_are(A: numpy.typing.ArrayLike, B: numpy.typing.ArrayLike, Q: numpy.typing.ArrayLike, R: numpy.typing.ArrayLike) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], int]:
    """
    The stabilising solution of the discrete algebraic Riccati equation for A (n, n), B (n, m), Q (n, n),
    R (m, m) (stage cost x^T Q x + u^T R u): returns (P (n, n), K (m, n), doublings), u = -K x.
    """
def mpc(plant: hovi._core.Integrator, problem: ShootingProblem, q0: numpy.typing.ArrayLike, p0: numpy.typing.ArrayLike, steps: typing.SupportsInt | typing.SupportsIndex, period: typing.SupportsInt | typing.SupportsIndex, max_iterations: typing.SupportsInt | typing.SupportsIndex, tol: typing.SupportsFloat | typing.SupportsIndex, pushes: list, us_init: numpy.typing.ArrayLike | None = None) -> dict[str, typing.Any]:
    """
    `steps` steps of plant (a _core.Integrator, with or without contacts, with the problem's dt) from q0, p0
    (n,) under MPC (control/mpc.hpp): FDDP on `problem` re-solved every `period` steps (at most max_iterations,
    tol), warm-started from the last plan shifted; pushes: a list with one list of (step, body, point,
    impulse). Returns the plant's rollout dict with controls, and per solve solve_seconds, solve_iterations,
    solve_converged; a solve that fails from the plant's state ends the run (status 'controller_failed'),
    solve_failure its message (else None).
    """
def velocity_state_map(model: hovi._core.Model, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]:
    """
    T = d(q, q̇)/d(q, p) (K, 2n, 2n) at states q (K, nq), p (K, n), q̇ = M(q)^{-1} p: a cost x_user^T W x_user on
    (q, q̇) is x^T (T^T W T) x on the integrator's state x = (q, p) (a free base: q's part a tangent vector).
    """
