"""The Galerkin variational integrator as the transcription (the paper's Sec. 6): the C++
VariationalTranscription (variational_transcription.hpp) plus its layout for costs, bounds,
guesses and results. Momenta are variables (see the C++ header for why)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from .. import _core
from ..integrator import Integrator
from ..trajectory import Trajectory
from .problem import Problem
from .samples import SampleMap
from .transcription import Transcription, TranscriptionMethod, piecewise_polynomial


@dataclass(frozen=True)
class VI(TranscriptionMethod):
    """The Galerkin variational integrator of order 2s as the transcription (the paper's Sec. 6):
    the DEL equations of every stage are the dynamics constraints, momenta are variables."""
    s: int = 2

    def __post_init__(self):
        if isinstance(self.s, bool) or int(self.s) != self.s or self.s < 1:
            raise ValueError(f"s must be a positive integer, got {self.s}")
        object.__setattr__(self, "s", int(self.s))

    @property
    def name(self) -> str:
        """A short label of the transcription (reports, plots)."""
        return f"vi (s={self.s})"

    def transcribe(self, problem: Problem) -> VariationalTranscription:
        """The VariationalTranscription of ``problem`` with this order."""
        return VariationalTranscription(problem, self.s)


class VariationalTranscription(Transcription):
    """A Problem transcribed by the Galerkin VI of order 2s (``VI(s).transcribe(problem)``)."""
    name = "vi"

    def __init__(self, problem: Problem, s: int = 2):
        VI(s)  # checks s
        core = _core.trajopt.VariationalTranscription(problem.model, int(s), problem.N, problem.dt, problem.controls)
        super().__init__(problem, core)
        self.s, self.N, self.dt = int(s), problem.N, problem.dt
        self.integrator = Integrator(problem.model, s=self.s, dt=self.dt, tol=1e-13)
        self.nodes, self.weights = self.integrator.nodes, self.integrator.weights
        off = core.offsets
        self.q_off, self.p_off, self.u_off, self.l_off = off["q"], off["p"], off["u"], off["lambda"]
        self.n_points, self.n_u = core.n_points, core.n_control_values
        self.name = f"vi (s={self.s})"

    # Points of stage k: global control points k s + a, a = 0..s.
    def _stage_points(self):
        return np.arange(self.N)[:, None] * self.s + np.arange(self.s + 1)[None, :]

    def _u_of_sample(self):
        j = self._stage_points()
        return j if self.problem.controls == "per_point" else np.repeat(np.arange(self.N)[:, None], self.s + 1, 1)

    def sample_map(self) -> SampleMap:
        n, m, s, N, dt = self.n, self.m, self.s, self.N, self.dt
        K, nv = N * (s + 1), self.core.n_variables
        j = self._stage_points().ravel()                      # sample i = k (s+1) + a -> point j
        rows = (np.arange(K)[:, None] * n + np.arange(n)).ravel()
        Sq = sp.csr_matrix((np.ones(K * n), (rows, (self.q_off + j[:, None] * n + np.arange(n)).ravel())), (K * n, nv))
        # q̇^{k,a} = (1/dt) sum_b b^{ab} q^{k,b}
        B = self.integrator.differentiation_matrix / dt
        a_idx = np.tile(np.arange(s + 1), N)
        k_idx = np.repeat(np.arange(N), s + 1)
        vr = np.repeat(rows.reshape(K, n)[:, None, :], s + 1, axis=1)              # (K, s+1, n)
        vc = self.q_off + ((k_idx[:, None] * s + np.arange(s + 1))[:, :, None] * n + np.arange(n))
        vv = np.repeat(B[a_idx][:, :, None], n, axis=2)
        Sv = sp.csr_matrix((vv.ravel(), (vr.ravel(), vc.ravel())), (K * n, nv))
        ju = self._u_of_sample().ravel()
        urows = (np.arange(K)[:, None] * m + np.arange(m)).ravel()
        Su = sp.csr_matrix((np.ones(K * m), (urows, (self.u_off + ju[:, None] * m + np.arange(m)).ravel())), (K * m, nv))
        t = ((k_idx + self.nodes[a_idx]) * dt)
        w = self.weights[a_idx] * dt
        return SampleMap(t, w, Sq, Sv, Su, n, m, final=K - 1)

    def q_points(self):
        t = (np.arange(self.N)[:, None] + self.nodes[None, :-1]).ravel() * self.dt
        t = np.append(t, self.N * self.dt)
        return t, self.q_off + np.arange(self.n_points) * self.n

    def stage_nodes(self):
        return self.nodes  # Lobatto points: q(t) interpolates a stage's s + 1 control points (Sec. 2, eq. (2))

    def _momentum(self, q, qdot):
        return self.model.mass_matrix(q) @ qdot

    def bounds(self):
        pr, n, nv = self.problem, self.n, self.core.n_variables
        lb, ub = np.full(nv, -np.inf), np.full(nv, np.inf)
        lb[self.q_off:self.p_off], ub[self.q_off:self.p_off] = self._tile_bounds(pr.q_lower, pr.q_upper, self.n_points)
        lb[self.u_off:self.l_off], ub[self.u_off:self.l_off] = self._tile_bounds(pr.u_lower, pr.u_upper, self.n_u)
        lb[self.q_off:self.q_off + n] = ub[self.q_off:self.q_off + n] = pr.q0
        lb[self.p_off:self.p_off + n] = ub[self.p_off:self.p_off + n] = self._momentum(pr.q0, pr.qdot0)
        if pr.qT is not None:
            last = self.q_off + (self.n_points - 1) * n
            lb[last:last + n] = ub[last:last + n] = pr.qT
        return lb, ub

    def linear_rows(self):
        """A final velocity q̇_T: p^N = M(q_T) q̇_T up to Dh(q_T)^T μ, i.e. Z^T (p^N - M q̇_T) = 0 with
        Z spanning the null space of Dh(q_T) (Z = I without constraints)."""
        pr, n, nv = self.problem, self.n, self.core.n_variables
        if pr.qdotT is None:
            return super().linear_rows()
        Z = np.eye(n) if not self.mc else scipy.linalg.null_space(self.model.constraint_jacobian(pr.qT))
        A = sp.lil_matrix((Z.shape[1], nv))
        pN = self.p_off + self.N * n
        A[:, pN:pN + n] = Z.T
        return A.tocsr(), Z.T @ self._momentum(pr.qT, pr.qdotT)

    def guess(self, q_of_t, v_of_t, u_of_t):
        x = np.zeros(self.core.n_variables)
        tq, _ = self.q_points()
        Q = q_of_t(tq)
        x[self.q_off:self.p_off] = Q.ravel()
        knots = np.arange(self.N + 1) * self.dt
        Vk = v_of_t(knots)
        P = np.array([self._momentum(q, v) for q, v in zip(Q[::self.s], Vk)])
        x[self.p_off:self.u_off] = P.ravel()
        if self.m:
            tu = tq if self.problem.controls == "per_point" else (np.arange(self.N) + 0.5) * self.dt
            x[self.u_off:self.l_off] = u_of_t(tu).ravel()
        return x

    @property
    def method(self) -> VI:
        """The TranscriptionMethod that gives this transcription."""
        return VI(self.s)

    def rollout_guess(self):
        """x from a rollout of this transcription's integrator from the initial state with zero
        controls (exact, multipliers included), or None if the rollout fails."""
        pr = self.problem
        U = np.zeros((pr.N, self.s + 1, self.m))
        traj = self.integrator.rollout(pr.q0, pr.N, qdot0=pr.qdot0, u=U if self.m else None, raise_on_failure=False)
        return self.guess_from_rollout(traj, U) if traj.steps == pr.N else None

    def guess_from_rollout(self, traj, U):
        """x from a rollout of this transcription's integrator (same s and dt) with controls U
        (N, s+1, m): exact, multipliers included."""
        s = self.s
        x = np.zeros(self.core.n_variables)
        x[self.q_off:self.p_off] = traj.configuration_points.ravel()
        x[self.p_off:self.u_off] = traj.p.ravel()
        if self.m:
            u = U[:, :s, :].reshape(-1, self.m) if self.problem.controls == "per_point" else U[:, 0, :]
            if self.problem.controls == "per_point":
                u = np.vstack([u, U[-1:, s, :]])
            x[self.u_off:self.l_off] = u.ravel()
        if self.mc:
            x[self.l_off:] = traj.multipliers.ravel()
        return x

    def trajectory(self, x) -> dict:
        n, s, N = self.n, self.s, self.N
        tq, _ = self.q_points()
        return {"t": tq, "q": x[self.q_off:self.p_off].reshape(-1, n),
                "t_knots": np.arange(N + 1) * self.dt, "p": x[self.p_off:self.u_off].reshape(N + 1, n),
                "u": x[self.u_off:self.l_off].reshape(self.n_u, self.m),
                "multipliers": x[self.l_off:].reshape(N, s, self.mc) if self.mc else None}

    def stage_controls(self, x) -> np.ndarray:
        """The controls at every stage's control points, (N, s+1, m), as Integrator.rollout takes them."""
        U = x[self.u_off:self.l_off].reshape(self.n_u, self.m)
        return U[self._u_of_sample()]

    def control_function(self, x):
        """u(t): per point, the degree-s polynomial through each stage's control-point values;
        held, constant over each stage."""
        U = self.stage_controls(x)
        if self.problem.controls == "held":
            return lambda t: U[np.clip((np.atleast_1d(t) / self.dt).astype(int), 0, self.N - 1), 0]
        return lambda t: piecewise_polynomial(self.dt, self.s, U, t)

    def interpolants(self, x):
        """q(t): the degree-s polynomial through each stage's control points; v(t) its derivative."""
        Q = x[self.q_off:self.p_off].reshape(-1, self.n)[self._stage_points()]
        return (lambda t: piecewise_polynomial(self.dt, self.s, Q, t),
                lambda t: piecewise_polynomial(self.dt, self.s, Q, t, derivative=True), self.control_function(x))

    def solution_trajectory(self, x) -> Trajectory:
        """The solution x as a hovi.Trajectory (``save``, ``load_trajectory``): its own configurations,
        control points, momenta, multipliers and controls, status 'optimized' (no Newton iterations,
        residuals NaN)."""
        arrays = self.trajectory(x)
        cp = arrays["q"][self._stage_points()]                               # (N, s+1, n)
        return Trajectory(t=arrays["t_knots"], q=np.vstack([cp[:, 0, :], cp[-1:, -1, :]]), p=arrays["p"],
                          control_points=cp, iterations=np.zeros(self.N, dtype=np.int64),
                          residuals=np.full(self.N, np.nan), factorizations=np.zeros(self.N, dtype=np.int64),
                          status=["optimized"] * self.N, multipliers=arrays["multipliers"],
                          controls=self.stage_controls(x) if self.m else None,
                          discretization=self.integrator.discretization)

    def replay(self, x):
        """Re-simulate the optimised controls with the Integrator from the optimised (q^0, p^0)."""
        tr = self.trajectory(x)
        return self.integrator.rollout(tr["q"][0], self.N, p0=tr["p"][0],
                                       u=self.stage_controls(x) if self.m else None, raise_on_failure=False)
