"""
The paper's comparison baselines (Section 5), apart from the hovi._core product
"""
from __future__ import annotations
import hovi._core
import numpy
import numpy.typing
import typing
__all__: list[str] = ['AutodiffDel', 'HermiteSimpson', 'fig3_batch', 'one_step_batch']
class HermiteSimpson:
    """
    Hermite-Simpson direct collocation as an implicit simulator (the paper's Sec. 5.3 baseline): the
    implicit formulation with the end and midpoint accelerations as unknowns and inverse-dynamics
    defects, Newton with an analytic dense Jacobian (RNEA derivatives) and LU; state (q, v).
    """
    def __init__(self, model: hovi._core.Model, dt: typing.SupportsFloat | typing.SupportsIndex, tol: typing.SupportsFloat | typing.SupportsIndex = 1e-10, max_iterations: typing.SupportsInt | typing.SupportsIndex = 30, reuse_jacobian: bool = True) -> None:
        """
        The simulator with step dt on a copy of `model`.
        """
    def rollout(self, q0: numpy.typing.ArrayLike, v0: numpy.typing.ArrayLike, steps: typing.SupportsInt | typing.SupportsIndex) -> dict[str, typing.Any]:
        """
        Simulate `steps` steps from q0, v0 (n,) in C++ (GIL released); stops at a failed solve. Returns a
        dict: q, v (K+1, n), iterations, status (per step), steps K, seconds.
        """
class AutodiffDel:
    """
    The automatic-differentiation baseline (dense, O(n^2)..O(n^3)).
    """
    def __init__(self, model: hovi._core.Model, s: typing.SupportsInt | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex) -> None:
        """
        The order-2s DEL equations with step dt on a copy of `model`.
        """
    def d2Ld(self, control_points: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        control_points (s+1, n); returns D^2 L_d, ((s+1) n, (s+1) n), by automatic differentiation.
        """
    def newton_direction(self, control_points: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        control_points (s+1, n), p (n,); returns the Newton direction dq (s, n) (dense LU of the AD Jacobian).
        """
    def residual(self, control_points: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
        """
        control_points (s+1, n), p (n,); returns (r (s, n), p_next (n,)), by automatic differentiation.
        """
def fig3_batch(model: hovi._core.Model, s: typing.SupportsInt | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex, q0: numpy.typing.ArrayLike, qdot0: numpy.typing.ArrayLike, method: str, min_seconds: typing.SupportsFloat | typing.SupportsIndex = 0.002) -> dict[str, typing.Any]:
    """
    Per-state times (N,) (seconds, timed in C++; states: rows of q0, qdot0 (N, n)) of the DEL evaluation, the Newton direction and D^2 L_d by
    'recursive' (hovi: Algorithm 1, A.1/A.2, Algorithms 2/3 + chain rule) or 'autodiff' (Eigen
    AutoDiffScalar on a scalar-templated Lagrangian, dense LU), at control points q + c^a dt qdot.
    """
def one_step_batch(model: hovi._core.Model, dt: typing.SupportsFloat | typing.SupportsIndex, q0: numpy.typing.ArrayLike, qdot0: numpy.typing.ArrayLike, method: str, tol: typing.SupportsFloat | typing.SupportsIndex = 1e-10, max_iterations: typing.SupportsInt | typing.SupportsIndex = 100, threads: int | None = None) -> dict[str, typing.Any]:
    """
    One trapezoidal (s = 1) step from every state (rows of q0, qdot0, (N, n); p0 = M(q0) qdot0) by 'newton'
    (hovi's exact O(n) Newton with line search) or 'quasi_newton' (Lee et al. 2016), both from the
    guess q0 + dt qdot0, or by 'continuation' in the step length (the step on the solution branch
    continuously connected to q0, or the status 'continuation_stalled' when that branch turns back
    before dt), or 'newton+continuation' (continuation when Newton fails); all converged when
    ||r||_inf <= tol (1 + ||p0||_inf). Returns per-state arrays converged, iterations (Newton
    directions), residual_evaluations, status, seconds (timed in C++), residual, q_next (the last
    iterate; after a stalled continuation the last point of the branch, at h_reached < dt),
    h_reached (continuation: how far in the step length the branch went; NaN otherwise) and errors
    (None, or the message of an exception a state raised: its status is 'error'). The states are
    spread over `threads` C++ threads (None: HOVI_NUM_THREADS or every core; the results do not
    depend on it, the times per solve may, as the threads share the machine).
    """
