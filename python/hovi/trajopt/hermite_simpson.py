"""Hermite-Simpson direct collocation as the transcription, implicit or explicit (the paper's
Table 1 and its footnote): the C++ HermiteSimpsonTranscription (hermite_simpson_transcription.hpp)
plus its layout. Points i = 0..2N: even i the knots, odd i the midpoints; variables q, v (and, in
the implicit form, a) at every point."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .. import _core
from ..integrator import Integrator
from .problem import Problem
from .samples import SampleMap
from .transcription import Transcription, TranscriptionMethod, piecewise_polynomial

# the VI whose rollout starts a Hermite-Simpson solve ('rollout' guess)
ROLLOUT_ORDER = 2


@dataclass(frozen=True)
class HermiteSimpson(TranscriptionMethod):
    """Hermite-Simpson direct collocation, ``form`` 'implicit' (accelerations as variables) or
    'explicit' (forward dynamics in the constraints)."""
    form: str = "implicit"

    def __post_init__(self):
        if self.form not in ("implicit", "explicit"):
            raise ValueError(f"form must be 'implicit' or 'explicit', got {self.form!r}")

    @property
    def name(self) -> str:
        """A short label of the transcription (reports, plots)."""
        return f"hs-{self.form}"

    def transcribe(self, problem: Problem) -> HermiteSimpsonTranscription:
        """The HermiteSimpsonTranscription of ``problem`` in this form."""
        return HermiteSimpsonTranscription(problem, implicit=self.form == "implicit")


class HermiteSimpsonTranscription(Transcription):
    """A Problem transcribed by Hermite-Simpson collocation (``HermiteSimpson(form).transcribe(problem)``)."""

    def __init__(self, problem: Problem, implicit: bool = True):
        core = _core.trajopt.HermiteSimpsonTranscription(problem.model, problem.N, problem.dt, problem.controls,
                                                         bool(implicit))
        super().__init__(problem, core)
        self.implicit, self.N, self.dt = bool(implicit), problem.N, problem.dt
        self.name = "hs-implicit" if implicit else "hs-explicit"
        off = core.offsets
        self.q_off, self.v_off, self.u_off, self.l_off = off["q"], off["v"], off["u"], off["lambda"]
        self.a_off = off.get("a")
        self.n_points, self.n_u = core.n_points, core.n_control_values

    def _points_of_samples(self):
        return 2 * np.arange(self.N)[:, None] + np.arange(3)[None, :]

    def _u_of_sample(self):
        j = self._points_of_samples()
        return j if self.problem.controls == "per_point" else np.repeat(np.arange(self.N)[:, None], 3, 1)

    def sample_map(self) -> SampleMap:
        n, m, N, h = self.n, self.m, self.N, self.dt
        K, nv = 3 * N, self.core.n_variables
        j = self._points_of_samples().ravel()
        rows = (np.arange(K)[:, None] * n + np.arange(n)).ravel()
        ones = np.ones(K * n)
        Sq = sp.csr_matrix((ones, (rows, (self.q_off + j[:, None] * n + np.arange(n)).ravel())), (K * n, nv))
        Sv = sp.csr_matrix((ones, (rows, (self.v_off + j[:, None] * n + np.arange(n)).ravel())), (K * n, nv))
        ju = self._u_of_sample().ravel()
        urows = (np.arange(K)[:, None] * m + np.arange(m)).ravel()
        Su = sp.csr_matrix((np.ones(K * m), (urows, (self.u_off + ju[:, None] * m + np.arange(m)).ravel())), (K * m, nv))
        return SampleMap(j * h / 2, np.tile(np.array([1.0, 4.0, 1.0]) * h / 6, N), Sq, Sv, Su, n, m, final=K - 1)

    def q_points(self):
        return np.arange(self.n_points) * self.dt / 2, self.q_off + np.arange(self.n_points) * self.n

    def stage_nodes(self):
        return np.array([0.0, 0.5, 1.0])  # knot, midpoint, knot: the quadratic of ``interpolants``

    def bounds(self):
        pr, n, nv = self.problem, self.n, self.core.n_variables
        lb, ub = np.full(nv, -np.inf), np.full(nv, np.inf)
        lb[self.q_off:self.q_off + self.n_points * n], ub[self.q_off:self.q_off + self.n_points * n] = \
            self._tile_bounds(pr.q_lower, pr.q_upper, self.n_points)
        lb[self.u_off:self.u_off + self.n_u * self.m], ub[self.u_off:self.u_off + self.n_u * self.m] = \
            self._tile_bounds(pr.u_lower, pr.u_upper, self.n_u)
        fixes = [(self.q_off, pr.q0), (self.v_off, pr.qdot0)]
        last = (self.n_points - 1) * n
        if pr.qT is not None:
            fixes.append((self.q_off + last, pr.qT))
        if pr.qdotT is not None:
            fixes.append((self.v_off + last, pr.qdotT))
        for off, value in fixes:
            lb[off:off + n] = ub[off:off + n] = value
        return lb, ub

    @property
    def method(self) -> HermiteSimpson:
        """The TranscriptionMethod that gives this transcription."""
        return HermiteSimpson("implicit" if self.implicit else "explicit")

    def rollout_guess(self):
        """x from a rollout of the VI of order 2 ROLLOUT_ORDER from the initial state with zero
        controls (q and v its polynomials), or None if the rollout fails."""
        pr, s = self.problem, ROLLOUT_ORDER
        integ = Integrator(pr.model, s=s, dt=pr.dt)
        U = np.zeros((pr.N, s + 1, self.m))
        traj = integ.rollout(pr.q0, pr.N, qdot0=pr.qdot0, u=U if self.m else None, raise_on_failure=False)
        if traj.steps != pr.N:
            return None
        cp = traj.control_points
        return self.guess(lambda t: piecewise_polynomial(pr.dt, integ.s, cp, t),
                          lambda t: piecewise_polynomial(pr.dt, integ.s, cp, t, derivative=True),
                          self.linear_interpolants()[2])

    def guess(self, q_of_t, v_of_t, u_of_t):
        x = np.zeros(self.core.n_variables)
        t, _ = self.q_points()
        Q, V = q_of_t(t), v_of_t(t)
        n, P = self.n, self.n_points
        x[self.q_off:self.q_off + P * n] = Q.ravel()
        x[self.v_off:self.v_off + P * n] = V.ravel()
        tu = t if self.problem.controls == "per_point" else (np.arange(self.N) + 0.5) * self.dt
        U = u_of_t(tu) if self.m else np.zeros((len(tu), 0))
        x[self.u_off:self.u_off + self.n_u * self.m] = U.ravel()
        if self.implicit:  # accelerations by forward dynamics at the guess
            Up = U if self.problem.controls == "per_point" else U[np.minimum(np.arange(P) // 2, self.N - 1)]
            B = self.model.actuation
            A = np.array([self.model.forward_dynamics(q, v, B @ u if self.m else None) for q, v, u in zip(Q, V, Up)])
            x[self.a_off:self.a_off + P * n] = A.ravel()
        return x

    def trajectory(self, x) -> dict:
        n, P = self.n, self.n_points
        t, _ = self.q_points()
        out = {"t": t, "q": x[self.q_off:self.q_off + P * n].reshape(P, n), "v": x[self.v_off:self.v_off + P * n].reshape(P, n),
               "u": x[self.u_off:self.u_off + self.n_u * self.m].reshape(self.n_u, self.m),
               "multipliers": x[self.l_off:self.l_off + P * self.mc].reshape(P, self.mc) if self.mc else None}
        if self.implicit:
            out["a"] = x[self.a_off:self.a_off + P * n].reshape(P, n)
        return out

    def control_function(self, x):
        """u(t): per point, the quadratic through each interval's knot, midpoint and knot values
        (the Hermite-Simpson control interpolation); held, constant over each interval."""
        U = x[self.u_off:self.u_off + self.n_u * self.m].reshape(self.n_u, self.m)
        if self.problem.controls == "held":
            return lambda t: U[np.clip((np.atleast_1d(t) / self.dt).astype(int), 0, self.N - 1)]
        return lambda t: piecewise_polynomial(self.dt, 2, U[self._points_of_samples()], t)

    def interpolants(self, x):
        """q(t) and v(t): the quadratics through each interval's knot, midpoint and knot values."""
        tr, j = self.trajectory(x), self._points_of_samples()
        Q, V = tr["q"][j], tr["v"][j]
        return (lambda t: piecewise_polynomial(self.dt, 2, Q, t), lambda t: piecewise_polynomial(self.dt, 2, V, t),
                self.control_function(x))
