"""LQR at an equilibrium and time-varying LQR along a trajectory, from the exact step Jacobians
A_k, B_k of the integrator (hovi.Linearizer; through contact with the contact state held or
smoothed). Costs are given in the user's terms, on (q, q̇) and u; they act on the integrator's
state x = (q, p) through T = d(q, q̇)/d(q, p) (Q_x = T^T W T, cpp/include/hovi/control/state_map.hpp).
The stage cost is x^T Q x + u^T R u per step (no factor 1/2, no dt)."""
from __future__ import annotations

from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

from .. import _core
from .._checks import real_array, real_number
from .._typing import FloatArray
from ..integrator import ConvergenceError, Integrator
from ..linearizer import Linearizer
from ..trajectory import Trajectory
from .policy import Policy
from .statics import static_controls


def _weight(W: Any, size: int, name: str) -> FloatArray:
    """A weight as a (size, size) symmetric positive semi-definite matrix: a number, `size` numbers
    (the diagonal) or a matrix."""
    a = real_array(W, name)
    if a.ndim == 0 or a.shape == (1,):
        a = np.full(size, float(a.ravel()[0]))
    if a.shape == (size,):
        a = np.diag(a)
    if a.shape != (size, size):
        raise ValueError(f"{name} must be a number, {size} numbers or a ({size}, {size}) matrix, got shape {a.shape}")
    if not np.allclose(a, a.T, rtol=1e-12, atol=1e-14 * (1 + np.abs(a).max())):
        raise ValueError(f"{name} must be symmetric")
    if np.linalg.eigvalsh(a).min() < -1e-12 * (1 + np.abs(a).max()):
        raise ValueError(f"{name} must be positive semi-definite")
    out: FloatArray = 0.5 * (a + a.T)
    return out


def _user_weights(n: int, q_weight: Any, v_weight: Any, Q: Any) -> FloatArray:
    """The (2n, 2n) weight on (q, q̇): Q if given, else blockdiag(q_weight, v_weight)."""
    if Q is not None:
        return _weight(Q, 2 * n, "Q")
    W = np.zeros((2 * n, 2 * n))
    W[:n, :n] = _weight(q_weight, n, "q_weight")
    W[n:, n:] = _weight(v_weight, n, "v_weight")
    return W


def _check_integrator(integrator: Integrator) -> None:
    if not isinstance(integrator, Integrator):
        raise TypeError(f"integrator must be a hovi.Integrator, got {type(integrator).__name__}")
    if integrator.n_constraints:
        raise ValueError("LQR on a model with holonomic constraints is not supported (its state is not (q, p) freely)")
    if integrator.model.n_controls == 0:
        raise ValueError("the model has no controls (add actuators first)")


def _limits(integrator: Integrator, u_limits: Any) -> tuple[FloatArray, FloatArray]:
    m = integrator.model.n_controls
    if u_limits is None:
        return np.full(m, -np.inf), np.full(m, np.inf)
    if isinstance(u_limits, (str, bytes)) or not hasattr(u_limits, "__len__") or len(u_limits) != 2:
        raise ValueError(f"u_limits must be a pair (lower, upper), each a number or {m} numbers, got {u_limits!r}")
    lo = np.broadcast_to(real_array(u_limits[0], "u_limits (lower)", finite=False), (m,)).copy()
    hi = np.broadcast_to(real_array(u_limits[1], "u_limits (upper)", finite=False), (m,)).copy()
    if np.any(np.isnan(lo)) or np.any(np.isnan(hi)) or np.any(lo > hi):
        raise ValueError(f"u_limits must have lower <= upper and no NaN, got {lo.tolist()} and {hi.tolist()}")
    return lo, hi


def equilibrium_controls(integrator: Integrator, q: npt.ArrayLike) -> FloatArray:
    """The held controls u (m,) that balance gravity at q (``static_controls``): least norm over the
    controls and, with contacts, the contact forces (which then carry the weight with them). ``lqr``
    checks that they hold q at rest."""
    q = real_array(q, "q", (integrator.nq,))
    if integrator.contacts is None:
        return static_controls(integrator.model, q)
    with_inputs = integrator.contacts.core_model().with_inputs(integrator.model)  # the plant's, not the contacts' model
    return static_controls(with_inputs, q)[:integrator.model.n_controls]


def rest_momentum(integrator: Integrator, q: FloatArray, u: FloatArray) -> FloatArray:
    """The momentum p (n,) of rest at q under held controls u: zero, or with contacts the momentum each
    step starts from before its knot's impulse (the policy's state; one step from rest reaches it).
    ValueError unless the step maps (q, p) to itself (q is not an equilibrium with u)."""
    p = np.zeros(integrator.n)
    if integrator.contacts is not None:
        _, p, _ = integrator.step(q, p, u)
    q_next, p_next, info = integrator.step(q, p, u)
    scale = 1.0 + np.abs(q).max()
    dq = integrator.model.difference(q, q_next) if integrator.model.free_base else q_next - q
    drift = max(np.abs(dq).max() / scale, np.abs(p_next - p).max() * integrator.dt / scale)
    if drift > 1e-9:
        loose = ""
        if integrator.contacts is not None:
            gaps = integrator.contacts.gaps(q)
            far = np.flatnonzero(gaps > integrator.contact_tol)
            loose = (f"; contacts {far.tolist()} do not touch the terrain at q (gaps {np.round(gaps[far], 6).tolist()} m): "
                     "a standing pose has its feet on it (let the robot settle, e.g. a rollout of "
                     "hovi.examples.standing, and take its last q)") if far.size else ""
        raise ValueError(f"q is not an equilibrium with controls u = {np.round(u, 6).tolist()}: a step from rest moves it "
                         f"by {drift:.2e} (relative){loose}; give u_eq (held controls that hold q at rest)")
    return p


def lqr(integrator: Integrator, q_eq: npt.ArrayLike, u_eq: Optional[npt.ArrayLike] = None, *, q_weight: Any = 1.0,
        v_weight: Any = 0.1, u_weight: Any = 0.01, Q: Any = None, u_limits: Any = None) -> Policy:
    """Infinite-horizon discrete LQR of ``integrator`` at rest at q_eq (nq,) with held controls u_eq
    (m,) (default: ``equilibrium_controls``), from the exact step Jacobians A, B there. On a free base
    the state is in tangent coordinates (``Model.difference``, Pinocchio's): the base's position and
    attitude errors in its own frame, so any attitude can be the reference.

    Costs per step: (q, q̇) weighted by Q (2n, 2n), or blockdiag(q_weight, v_weight) (numbers, n
    numbers or (n, n)), and u by u_weight (R: number, m numbers or (m, m), positive definite);
    u_limits = (lower, upper) saturates the policy. Returns a stationary Policy (its cost_to_go P).
    ValueError if q_eq is not an equilibrium or (A, B) is not stabilisable."""
    _check_integrator(integrator)
    n, m = integrator.n, integrator.model.n_controls
    q_eq = real_array(q_eq, "q_eq", (integrator.nq,))
    u = equilibrium_controls(integrator, q_eq) if u_eq is None else real_array(u_eq, "u_eq", (m,))
    p_eq = rest_momentum(integrator, q_eq, u)
    lin = Linearizer(integrator).step_jacobians(q_eq, p_eq, u, hold=True)  # with contacts: the stance held
    assert lin.A is not None and lin.B is not None
    T = _core.control.velocity_state_map(integrator.model, q_eq[None], p_eq[None])[0]
    Qx = T.T @ _user_weights(n, q_weight, v_weight, Q) @ T
    R = _weight(u_weight, m, "u_weight")
    if np.linalg.eigvalsh(R).min() <= 0:
        raise ValueError("u_weight must be positive definite")
    P, K = (_core.control.discrete_are(lin.A, lin.B, Qx, R)[:2] if integrator.contacts is None
            else _stance_gains(lin.A, lin.B, Qx, R))
    lo, hi = _limits(integrator, u_limits)
    return Policy(x_ref=np.concatenate([q_eq, p_eq])[None], u_ref=np.tile(u, (1, integrator.s + 1, 1)),
                  gains=K[None], lower=lo, upper=hi, cost_to_go=P[None], dt=integrator.dt, s=integrator.s)


def _stance_gains(A: FloatArray, B: FloatArray, Qx: FloatArray, R: FloatArray) -> tuple[FloatArray, FloatArray]:
    """(P, K) of LQR with the stance held: the gains of the backward Riccati recursion, run until they
    stop changing. Held contacts keep the feet where they are, modes of eigenvalue 1 that no control
    moves, so the DARE has no stabilising solution; the gains converge all the same (P grows along
    those modes: it is the cost-to-go of the horizon run)."""
    chunk, K, P0 = 500, None, Qx
    for _ in range(40):
        gains, P = _core.control.backward_riccati(np.repeat(A[None], chunk, 0), np.repeat(B[None], chunk, 0),
                                                  np.repeat(Qx[None], chunk, 0), R, P0)
        P0 = P[0]
        if K is not None and np.abs(gains[0] - K).max() <= 1e-9 * (1 + np.abs(K).max()):
            rho = float(np.abs(np.linalg.eigvals(A - B @ gains[0])).max())
            if rho > 1 + 1e-8:
                raise ValueError(f"LQR with the stance held does not stabilise the robot (closed-loop |eigenvalue| up to "
                                 f"{rho:.6g}): some motion with the feet held is not controllable")
            return P0, gains[0]
        K = gains[0]
    raise ValueError("LQR with the stance held: the Riccati gains did not converge over 20,000 steps")


def tvlqr(integrator: Integrator, trajectory: Union[Trajectory, Any], u: Optional[npt.ArrayLike] = None, *,
          q_weight: Any = 1.0, v_weight: Any = 0.1, u_weight: Any = 0.01, Q: Any = None, final_weight: Any = None,
          u_limits: Any = None, smoothing: float = 0.0) -> Policy:
    """Finite-horizon time-varying LQR along a trajectory of ``integrator``: a Trajectory it computed
    with controls u (as ``Integrator.rollout`` takes them; default the trajectory's own,
    ``Trajectory.controls``, e.g. of a loaded optimised motion), or a ``hovi.trajopt.Result`` of a VI
    transcription with this integrator's s and dt (its replay and controls are used).

    Weights as ``lqr``; final_weight (2n, 2n) on (q, q̇) at the end (default: 10 Q). With contacts the
    Jacobians hold each contact's state, or are smoothed (Linearizer). Returns
    a Policy with a reference and gain per step."""
    _check_integrator(integrator)
    if not isinstance(trajectory, Trajectory):
        trajectory, u = _from_result(integrator, trajectory)
    _check_trajectory(integrator, trajectory)
    if not trajectory.converged:
        raise ConvergenceError("the trajectory has unconverged steps; track its converged part")
    K = trajectory.steps
    if K < 1:
        raise ValueError("the trajectory has no steps")
    U = integrator.controls_per_point(trajectory.controls if u is None else u, K)
    if U is None:
        raise ValueError("give the trajectory's controls u (as Integrator.rollout takes them; a trajectory that "
                         "carries them, Trajectory.controls, needs none)")
    A, B = Linearizer(integrator).rollout_jacobians(trajectory, U, hold=True, smoothing=real_number(smoothing, "smoothing", minimum=0.0))
    # with contacts the policy's state is each step's own momentum (before its knot's impulse, as the Jacobians')
    p = trajectory.p if trajectory.contact is None or trajectory.contact.step_momenta is None \
        else trajectory.contact.step_momenta
    return riccati_policy(integrator, trajectory.q, p, U, A, B, q_weight=q_weight, v_weight=v_weight,
                          u_weight=u_weight, Q=Q, final_weight=final_weight, u_limits=u_limits)


def riccati_policy(integrator: Integrator, q: npt.ArrayLike, p: npt.ArrayLike, u: npt.ArrayLike, A: npt.ArrayLike,
                   B: npt.ArrayLike, *, q_weight: Any = 1.0, v_weight: Any = 0.1, u_weight: Any = 0.01, Q: Any = None,
                   final_weight: Any = None, u_limits: Any = None) -> Policy:
    """The time-varying LQR Policy of given step Jacobians A (K, 2n, 2n), B (K, 2n, m) (held controls)
    along references q (K+1, nq), p (K+1, n) with controls u (K, s+1, m): what ``tvlqr`` does after linearising,
    for Jacobians computed otherwise (e.g. each step of a contact motion linearised on its own).
    Weights as ``tvlqr``."""
    _check_integrator(integrator)
    n, m, s = integrator.n, integrator.model.n_controls, integrator.s
    A = real_array(A, "A")
    K = A.shape[0] if A.ndim == 3 else -1
    if A.shape != (K, 2 * n, 2 * n) or K < 1:
        raise ValueError(f"A must have shape (K, {2 * n}, {2 * n}), got {A.shape}")
    B = real_array(B, "B", (K, 2 * n, m))
    q, p = real_array(q, "q", (K + 1, integrator.nq)), real_array(p, "p", (K + 1, n))
    U = real_array(u, "u", (K, s + 1, m))
    T = _core.control.velocity_state_map(integrator.model, q, p)
    W = _user_weights(n, q_weight, v_weight, Q)
    WN = 10 * W if final_weight is None else _weight(final_weight, 2 * n, "final_weight")
    Qx = np.einsum("kji,jl,klm->kim", T[:-1], W, T[:-1])
    R = _weight(u_weight, m, "u_weight")
    if np.linalg.eigvalsh(R).min() <= 0:
        raise ValueError("u_weight must be positive definite")
    try:
        gains, P = _core.control.backward_riccati(A, B, Qx, R, T[-1].T @ WN @ T[-1])
    except ValueError as e:  # R + B^T P B not positive definite: with R > 0, P overflowed or lost symmetry
        raise ValueError(_diverged(A, "broke down (R + B^T P B lost positive definiteness)")) from e
    finite = np.isfinite(P).all(axis=(1, 2))
    finite[:K] &= np.isfinite(gains).all(axis=(1, 2))
    if not finite.all():
        k = int(np.flatnonzero(~finite).max())
        raise ValueError(_diverged(A, f"overflowed (its cost-to-go or gains are not finite from step {k} back)"))
    lo, hi = _limits(integrator, u_limits)
    return Policy(x_ref=np.hstack([q[:K], p[:K]]), u_ref=U, gains=gains, lower=lo, upper=hi, cost_to_go=P,
                  dt=integrator.dt, s=s)


def _diverged(A: FloatArray, what: str) -> str:
    """The message of a backward Riccati recursion that ``what``, with the growth of A that caused it."""
    rho = float(np.abs(np.linalg.eigvals(A)).max())
    return (f"the backward Riccati recursion over the K = {len(A)} steps {what}: the step Jacobians A_k grow too fast "
            f"(largest |eigenvalue| {rho:.3g}; the cost-to-go grows like {rho:.3g}^(2K)); use fewer steps or a "
            "smaller dt, or check A")


def _check_trajectory(integrator: Integrator, trajectory: Trajectory) -> None:
    """ValueError unless ``trajectory`` is of the integrator's model (n, bodies), s and dt: linearised
    by this integrator, another system's trajectory gives silently wrong gains."""
    d = trajectory.discretization
    if d is not None:
        n, bodies, s, dt = d.model.n, list(d.model.body_names), d.s, d.dt
    else:  # loaded without its integrator: what its arrays say
        n, bodies, s = trajectory.p.shape[1], None, trajectory.control_points.shape[1] - 1
        dt = float(trajectory.t[1] - trajectory.t[0]) if len(trajectory.t) > 1 else integrator.dt
    if n != integrator.n or bodies not in (None, list(integrator.model.body_names)):
        raise ValueError(f"trajectory is of another model (n = {n}, bodies {bodies}) than the integrator's (n = "
                         f"{integrator.n}, bodies {list(integrator.model.body_names)}): give a trajectory of this "
                         "integrator")
    if s != integrator.s or abs(dt - integrator.dt) > 1e-9 * integrator.dt:
        raise ValueError(f"trajectory was computed with s = {s}, dt = {dt:g}; the integrator has s = {integrator.s}, "
                         f"dt = {integrator.dt:g}: they must match (linearise the integrator that computed it)")


def _from_result(integrator: Integrator, result: Any) -> tuple[Trajectory, FloatArray]:
    """(replayed trajectory, controls (N, s+1, m)) of a trajopt Result of a VI transcription that
    matches the integrator."""
    tr = getattr(result, "transcription", None)
    if tr is None or not hasattr(tr, "stage_controls"):
        raise TypeError("trajectory must be a hovi Trajectory or a hovi.trajopt.Result of a VI transcription, got "
                        f"{type(result).__name__}")
    if tr.s != integrator.s or abs(tr.dt - integrator.dt) > 1e-12 * tr.dt:
        raise ValueError(f"the Result's transcription has s = {tr.s}, dt = {tr.dt:g}; the integrator s = "
                         f"{integrator.s}, dt = {integrator.dt:g}: they must match")
    U = tr.stage_controls(result.x)
    traj = integrator.rollout(tr.trajectory(result.x)["q"][0], len(U), p0=tr.trajectory(result.x)["p"][0], u=U,
                              raise_on_failure=False)
    return traj, U
