"""Cost terms of a trajectory optimisation. Each sees the trajectory's samples (samples.py) and
returns its value and its gradients with respect to the samples' q, v and u; none knows the
transcription. Running costs are integrals, sum_j w_j L(t_j, q_j, v_j, u_j); terminal costs use
the sample at the final time."""
from __future__ import annotations

from typing import Callable, Tuple

import numpy as np
import numpy.typing as npt

from .._checks import real_array
from .samples import Samples

# (value, dq (K, n), dv (K, n), du (K, m)): a cost and its gradients with respect to the samples
CostValue = Tuple[float, np.ndarray, np.ndarray, np.ndarray]


class Cost:
    """Base class: ``__call__(samples) -> (value, dq (K, n), dv (K, n), du (K, m))``. A term
    quadratic in the samples with a diagonal Hessian also gives ``curvature(samples)``, its second
    derivatives (hq (K, n), hv (K, n), hu (K, m)); the NLP then evaluates it in C++ without Python."""

    def __call__(self, s: Samples) -> CostValue:
        raise NotImplementedError

    def curvature(self, s: Samples) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """The constant diagonal second derivatives (hq, hv, hu) of a quadratic term, or None."""
        return None


def _vector(value: npt.ArrayLike, name: str, size: int | None = None, *, nonnegative: bool = False) -> np.ndarray:
    """A number or ``size`` numbers (any length when size is None), finite (and >= 0 with
    ``nonnegative``), as an array of shape () or (size,); errors name ``name``."""
    v = real_array(value, name)
    if v.ndim > 1 or (size is not None and v.shape not in ((), (size,), (1,))):
        raise ValueError(f"{name} must be a number or {'a vector (one per coordinate)' if size is None else f'{size} numbers'}"
                         f", got shape {v.shape}")
    if nonnegative and np.any(v < 0):
        raise ValueError(f"{name} must be non-negative, got {v.tolist()}")
    return v if size is None else np.broadcast_to(v, (size,)).copy()


def _weights(W: npt.ArrayLike, size: int, name: str) -> np.ndarray:
    """A weight given to a cost as ``size`` non-negative numbers; errors name it ``name``."""
    return _vector(W, name, size, nonnegative=True)


def _reference_or_function(ref, name: str):
    """A reference given to a cost: None, a callable, or checked numbers."""
    if ref is None or callable(ref):
        return ref
    _vector(ref, name)
    return ref


def checked_cost(cost: Cost, s: Samples, name: str, *, finite: bool = False) -> CostValue:
    """``cost(s)``, checked: a tuple (value, dq, dv, du) with value a real number and the gradients
    of the samples' shapes, all real (and, with ``finite``, finite); ValueError naming the cost term
    ``name`` and what it returned otherwise."""
    out = cost(s)
    if not isinstance(out, (tuple, list)) or len(out) != 4:
        raise ValueError(f"{name} must return (value, dq, dv, du), got {type(out).__name__}"
                         f"{'' if not hasattr(out, '__len__') else ' of length ' + str(len(out))}")
    value, dq, dv, du = out
    if (isinstance(value, (bool, np.bool_, str, bytes)) or np.ndim(value) != 0
            or np.asarray(value).dtype.kind not in "iuf"):
        raise ValueError(f"{name} returned a cost value that is not a real number: {value!r}")
    value = float(value)
    grads = []
    for g_name, g, ref in (("dq", dq, s.q), ("dv", dv, s.v), ("du", du, s.u)):
        try:
            g = real_array(g, f"{name}: its gradient {g_name}", tuple(ref.shape), finite=False)
        except TypeError as e:
            raise ValueError(str(e)) from None
        grads.append(g)
    if finite:
        if not np.isfinite(value):
            raise ValueError(f"{name} returned the cost value {value} (not finite)")
        for g_name, g in zip(("dq", "dv", "du"), grads):
            if not np.all(np.isfinite(g)):
                raise ValueError(f"{name} returned NaN or infinity in its gradient {g_name}")
    return value, grads[0], grads[1], grads[2]


class ControlEffort(Cost):
    """∫ sum_i R_i u_i(t)^2 dt (weight R a scalar or one weight per control, (m,))."""

    def __init__(self, weight: npt.ArrayLike = 1.0):
        _vector(weight, "ControlEffort weight", nonnegative=True)
        self.weight = weight

    def weights(self, m: int) -> np.ndarray:
        """R (m,) for m controls (ValueError naming the weight if it is not a number or m numbers)."""
        return _weights(self.weight, m, "ControlEffort weight")

    def __call__(self, s: Samples) -> CostValue:
        wu = s.w[:, None] * self.weights(s.u.shape[1]) * s.u
        return float(np.sum(wu * s.u)), np.zeros_like(s.q), np.zeros_like(s.v), 2 * wu

    def curvature(self, s: Samples) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(0, 0, 2 w R): second derivatives in the samples' q (K, n), v (K, n), u (K, m)."""
        hu = 2 * s.w[:, None] * self.weights(s.u.shape[1])
        return np.zeros_like(s.q), np.zeros_like(s.v), np.broadcast_to(hu, s.u.shape).copy()


class StateTracking(Cost):
    """∫ sum_i Wq_i (q_i - q_ref,i(t))^2 + Wv_i (v_i - v_ref,i(t))^2 dt: posture regulation
    (a constant q_ref) or tracking (q_ref a vectorised callable: times t (K,) -> (K, n))."""

    def __init__(self, q_ref: npt.ArrayLike | Callable[[np.ndarray], np.ndarray], weight: npt.ArrayLike = 1.0,
                 v_ref: npt.ArrayLike | Callable[[np.ndarray], np.ndarray] | None = None,
                 velocity_weight: npt.ArrayLike = 0.0):
        if q_ref is None:
            raise TypeError("StateTracking q_ref must be numbers or a function of time, got None")
        _reference_or_function(q_ref, "StateTracking q_ref")
        _reference_or_function(v_ref, "StateTracking v_ref")
        _vector(weight, "StateTracking weight", nonnegative=True)
        _vector(velocity_weight, "StateTracking velocity_weight", nonnegative=True)
        self.q_ref, self.weight, self.v_ref, self.velocity_weight = q_ref, weight, v_ref, velocity_weight

    @staticmethod
    def _reference(ref, t, n, name="a reference"):
        if ref is None:
            return np.zeros((len(t), n))
        if callable(ref):
            try:
                r = real_array(ref(t), f"{name} (a function of the sample times t ({len(t)},))", (len(t), n))
            except TypeError as e:
                raise ValueError(f"{e}; it must return ({len(t)}, {n}) real numbers") from None
            except ValueError as e:
                raise ValueError(f"{e}: {name} must be {n} values or a vectorised function of the sample times "
                                 f"t (K,) returning (K, {n})") from None
            return r
        r = real_array(ref, name)
        if r.shape not in ((), (1,), (n,)):
            raise ValueError(f"{name} must be {n} values (one per coordinate) or a vectorised function of the "
                             f"sample times t (K,) returning (K, {n}); got shape {r.shape}")
        return np.broadcast_to(r, (len(t), n))

    def references(self, t: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(q_ref, v_ref) at the sample times t (K,), each (K, n)."""
        return (self._reference(self.q_ref, t, n, "StateTracking q_ref"),
                self._reference(self.v_ref, t, n, "StateTracking v_ref"))

    def weights(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(Wq, Wv), each (n,), for n coordinates (ValueError naming the weight of another length)."""
        return (_weights(self.weight, n, "StateTracking weight"),
                _weights(self.velocity_weight, n, "StateTracking velocity_weight"))

    def __call__(self, s: Samples) -> CostValue:
        n = s.q.shape[1]
        q_ref, v_ref = self.references(s.t, n)
        eq, ev = s.q - q_ref, s.v - v_ref
        Wq, Wv = (s.w[:, None] * W for W in self.weights(n))
        value = float(np.sum(Wq * eq * eq) + np.sum(Wv * ev * ev))
        return value, 2 * Wq * eq, 2 * Wv * ev, np.zeros_like(s.u)

    def curvature(self, s: Samples) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(2 w Wq, 2 w Wv, 0): second derivatives in the samples' q (K, n), v (K, n), u (K, m)."""
        Wq, Wv = self.weights(s.q.shape[1])
        return (np.broadcast_to(2 * s.w[:, None] * Wq, s.q.shape).copy(),
                np.broadcast_to(2 * s.w[:, None] * Wv, s.v.shape).copy(), np.zeros_like(s.u))


class TerminalCost(Cost):
    """Wq |q(T) - q_T|^2 + Wv |v(T) - v_T|^2: targets q_target, v_target (n,) (v_target default
    zero), weights scalars or per joint (n,)."""

    def __init__(self, q_target: npt.ArrayLike, weight: npt.ArrayLike = 1.0, v_target: npt.ArrayLike | None = None,
                 velocity_weight: npt.ArrayLike = 0.0):
        _vector(q_target, "TerminalCost q_target")
        if v_target is not None:
            _vector(v_target, "TerminalCost v_target")
        _vector(weight, "TerminalCost weight", nonnegative=True)
        _vector(velocity_weight, "TerminalCost velocity_weight", nonnegative=True)
        self.q_target, self.weight, self.v_target, self.velocity_weight = q_target, weight, v_target, velocity_weight

    def targets(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(q_target, v_target), each (n,), for n coordinates (ValueError naming a target of another length)."""
        return (_vector(self.q_target, "TerminalCost q_target", n),
                np.zeros(n) if self.v_target is None else _vector(self.v_target, "TerminalCost v_target", n))

    def weights(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """(Wq, Wv), each (n,), for n coordinates (ValueError naming the weight of another length)."""
        return (_weights(self.weight, n, "TerminalCost weight"),
                _weights(self.velocity_weight, n, "TerminalCost velocity_weight"))

    def __call__(self, s: Samples) -> CostValue:
        n, f = s.q.shape[1], s.final
        q_T, v_T = self.targets(n)
        eq, ev = s.q[f] - q_T, s.v[f] - v_T
        Wq, Wv = self.weights(n)
        dq, dv = np.zeros_like(s.q), np.zeros_like(s.v)
        dq[f], dv[f] = 2 * Wq * eq, 2 * Wv * ev
        return float(Wq @ (eq * eq) + Wv @ (ev * ev)), dq, dv, np.zeros_like(s.u)

    def curvature(self, s: Samples) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """2 Wq, 2 Wv at the final sample, zero elsewhere: second derivatives in the samples' q (K, n),
        v (K, n), u (K, m)."""
        n, f = s.q.shape[1], s.final
        hq, hv = np.zeros_like(s.q), np.zeros_like(s.v)
        hq[f], hv[f] = (2 * W for W in self.weights(n))
        return hq, hv, np.zeros_like(s.u)


class CallbackCost(Cost):
    """A user cost on the samples: ``fun(t, w, q, v, u) -> (value, dq, dv, du)`` with arrays of the
    samples' shapes (vectorised over the samples: called once per evaluation, not per stage).
    ``hessian(t, w, q, v, u) -> H`` (K, 2n + m, 2n + m), each sample's (Gauss-Newton) Hessian in its
    (q, v, u), is what FDDP needs of it (IPOPT does not use it)."""

    def __init__(self, fun: Callable[..., tuple[float, npt.ArrayLike, npt.ArrayLike, npt.ArrayLike]],
                 hessian: Callable[..., npt.ArrayLike] | None = None):
        if not callable(fun):
            raise TypeError(f"CallbackCost fun must be callable, got {type(fun).__name__}")
        if hessian is not None and not callable(hessian):
            raise TypeError(f"CallbackCost hessian must be callable, got {type(hessian).__name__}")
        self.fun, self.hessian = fun, hessian

    def __call__(self, s: Samples) -> CostValue:
        out = self.fun(s.t, s.w, s.q, s.v, s.u)
        if not isinstance(out, (tuple, list)) or len(out) != 4:
            raise ValueError(f"CallbackCost: fun must return (value, dq, dv, du), got {type(out).__name__}")
        value, dq, dv, du = out
        for name, g, ref in (("dq", dq, s.q), ("dv", dv, s.v), ("du", du, s.u)):
            if np.shape(g) != ref.shape:
                raise ValueError(f"CallbackCost: {name} must have shape {ref.shape}, got {np.shape(g)}")
        return checked_cost(lambda _: (value, dq, dv, du), s, "CallbackCost")
