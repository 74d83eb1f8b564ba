"""Cost terms of a trajectory optimisation. Each sees the trajectory's samples (samples.py) and
returns its value and its gradients with respect to the samples' q, v and u; none knows the
transcription. Running costs are integrals, sum_j w_j L(t_j, q_j, v_j, u_j); terminal costs use
the sample at the final time."""
from __future__ import annotations

from typing import Callable, Tuple

import numpy as np
import numpy.typing as npt

from .samples import Samples

# (value, dq (K, n), dv (K, n), du (K, m)): a cost and its gradients with respect to the samples
CostValue = Tuple[float, np.ndarray, np.ndarray, np.ndarray]


class Cost:
    """Base class: ``__call__(samples) -> (value, dq (K, n), dv (K, n), du (K, m))``."""

    def __call__(self, s: Samples) -> CostValue:
        raise NotImplementedError


def _weights(W: npt.ArrayLike, size: int, name: str) -> np.ndarray:
    W = np.broadcast_to(np.asarray(W, dtype=float), (size,)).copy()
    if np.any(W < 0) or not np.all(np.isfinite(W)):
        raise ValueError(f"{name} weights must be finite and non-negative")
    return W


class ControlEffort(Cost):
    """∫ sum_i R_i u_i(t)^2 dt (weight R a scalar or one weight per control, (m,))."""

    def __init__(self, weight: npt.ArrayLike = 1.0):
        self.weight = weight

    def __call__(self, s: Samples) -> CostValue:
        R = _weights(self.weight, s.u.shape[1], "control effort")
        wu = s.w[:, None] * R * s.u
        return float(np.sum(wu * s.u)), np.zeros_like(s.q), np.zeros_like(s.v), 2 * wu


class StateTracking(Cost):
    """∫ sum_i Wq_i (q_i - q_ref,i(t))^2 + Wv_i (v_i - v_ref,i(t))^2 dt: posture regulation
    (a constant q_ref) or tracking (q_ref a vectorised callable: times t (K,) -> (K, n))."""

    def __init__(self, q_ref: npt.ArrayLike | Callable[[np.ndarray], np.ndarray], weight: npt.ArrayLike = 1.0,
                 v_ref: npt.ArrayLike | Callable[[np.ndarray], np.ndarray] | None = None,
                 velocity_weight: npt.ArrayLike = 0.0):
        self.q_ref, self.weight, self.v_ref, self.velocity_weight = q_ref, weight, v_ref, velocity_weight

    @staticmethod
    def _reference(ref, t, n):
        if ref is None:
            return np.zeros((len(t), n))
        r = np.asarray(ref(t) if callable(ref) else np.broadcast_to(np.asarray(ref, dtype=float), (len(t), n)), float)
        if r.shape != (len(t), n):
            raise ValueError(f"a reference must be {n} values or a vectorised function of the sample times "
                             f"t (K,) returning (K, {n}); got shape {r.shape}")
        return r

    def __call__(self, s: Samples) -> CostValue:
        n = s.q.shape[1]
        eq = s.q - self._reference(self.q_ref, s.t, n)
        ev = s.v - self._reference(self.v_ref, s.t, n)
        Wq = s.w[:, None] * _weights(self.weight, n, "state tracking")
        Wv = s.w[:, None] * _weights(self.velocity_weight, n, "velocity tracking")
        value = float(np.sum(Wq * eq * eq) + np.sum(Wv * ev * ev))
        return value, 2 * Wq * eq, 2 * Wv * ev, np.zeros_like(s.u)


class TerminalCost(Cost):
    """Wq |q(T) - q_T|^2 + Wv |v(T) - v_T|^2: targets q_target, v_target (n,) (v_target default
    zero), weights scalars or per joint (n,)."""

    def __init__(self, q_target: npt.ArrayLike, weight: npt.ArrayLike = 1.0, v_target: npt.ArrayLike | None = None,
                 velocity_weight: npt.ArrayLike = 0.0):
        self.q_target, self.weight, self.v_target, self.velocity_weight = q_target, weight, v_target, velocity_weight

    def __call__(self, s: Samples) -> CostValue:
        n, f = s.q.shape[1], s.final
        eq = s.q[f] - np.broadcast_to(np.asarray(self.q_target, dtype=float), (n,))
        ev = s.v[f] - (np.zeros(n) if self.v_target is None else np.broadcast_to(np.asarray(self.v_target, float), (n,)))
        Wq, Wv = _weights(self.weight, n, "terminal"), _weights(self.velocity_weight, n, "terminal velocity")
        dq, dv = np.zeros_like(s.q), np.zeros_like(s.v)
        dq[f], dv[f] = 2 * Wq * eq, 2 * Wv * ev
        return float(Wq @ (eq * eq) + Wv @ (ev * ev)), dq, dv, np.zeros_like(s.u)


class CallbackCost(Cost):
    """A user cost on the samples: ``fun(t, w, q, v, u) -> (value, dq, dv, du)`` with arrays of the
    samples' shapes (vectorised over the samples: called once per evaluation, not per stage)."""

    def __init__(self, fun: Callable[..., tuple[float, npt.ArrayLike, npt.ArrayLike, npt.ArrayLike]]):
        self.fun = fun

    def __call__(self, s: Samples) -> CostValue:
        value, dq, dv, du = self.fun(s.t, s.w, s.q, s.v, s.u)
        for name, g, ref in (("dq", dq, s.q), ("dv", dv, s.v), ("du", du, s.u)):
            if np.shape(g) != ref.shape:
                raise ValueError(f"CallbackCost: {name} must have shape {ref.shape}, got {np.shape(g)}")
        return float(value), np.asarray(dq, float), np.asarray(dv, float), np.asarray(du, float)
