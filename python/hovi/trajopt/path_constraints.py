"""Path constraints: conditions on the configuration at the transcription's configuration points
(the VI's control points, Hermite-Simpson's knots and midpoints) at one time or over a window,
``lower <= c(q) <= upper``; over a window optionally also at ``between`` configurations between
each two consecutive points, on the trajectory's polynomial (Transcription.q_samples). Each is
evaluated for all its points in one vectorised call."""
from __future__ import annotations

from typing import Callable, Tuple

import numpy as np
import numpy.typing as npt

from .. import _core
from .._bodies import body_index
from .._checks import real_array, real_number

# (values (P, r), jacobians (P, r, n)) of a path constraint at P configuration points
PathValue = Tuple[np.ndarray, np.ndarray]


_AXES = {"x": 0, "y": 1, "z": 2}


def _rows(value: npt.ArrayLike, r: int, name: str, *, finite: bool = False) -> np.ndarray:
    """A number or r numbers (no NaN; finite with ``finite``) as (r,), errors naming ``name``."""
    v = real_array(value, name, finite=False)
    if v.shape not in ((), (1,), (r,)):
        raise ValueError(f"{name} must be a number or {r} numbers (one per axis), got shape {v.shape}")
    if np.any(np.isnan(v)) or (finite and not np.all(np.isfinite(v))):
        raise ValueError(f"{name} must be {'finite' if finite else 'numbers, not NaN'}, got {v.tolist()}")
    return np.broadcast_to(v, (r,)).copy()


def _axes(axes: str) -> list[int]:
    if not axes or any(a not in _AXES for a in axes) or len(set(axes)) != len(axes):
        raise ValueError(f"axes must be a combination of 'x', 'y', 'z', got '{axes}'")
    return [_AXES[a] for a in axes]


class PathConstraint:
    """Base: ``at`` a time (the configuration point nearest to it) or ``window`` (t0, t1) (every
    configuration point in it and, with ``between`` = b > 0, b evenly spaced configurations between
    each two consecutive points in it: an obstacle a point could otherwise pass within one stage);
    ``evaluate(model, t, Q) -> (values (P, r), jacobians (P, r, n))`` at the points' times t (P,)
    and configurations Q (P, n)."""

    def __init__(self, at: float | None = None, window: tuple[float, float] | None = None, between: int = 0):
        if (at is None) == (window is None):
            raise ValueError("give exactly one of at= (a time) or window= (t0, t1)")
        if at is not None:
            at = real_number(at, "at")
        if window is not None:
            w = real_array(window, "window", finite=False)
            if w.shape != (2,) or np.any(np.isnan(w)):
                raise ValueError(f"window must be two times (t0, t1), got {window!r}")
            window = (float(w[0]), float(w[1]))
        if window is not None and not window[0] <= window[1]:
            raise ValueError(f"window must satisfy t0 <= t1, got {window}")
        if isinstance(between, bool) or not isinstance(between, (int, np.integer)) or between < 0:
            raise ValueError(f"between must be a non-negative integer, got {between!r}")
        if between and window is None:
            raise ValueError("between= samples a window; a constraint at= one time has none")
        self.at, self.window, self.between = at, window, int(between)

    def points(self, t: np.ndarray) -> np.ndarray:
        """Indices (P,) of the points (times t (N,)) where the constraint applies."""
        if self.at is not None:
            if not t[0] - 1e-12 <= self.at <= t[-1] + 1e-12:
                raise ValueError(f"time {self.at} lies outside the horizon [{t[0]}, {t[-1]}]")
            return np.array([int(np.argmin(np.abs(t - self.at)))])
        idx = self.in_window(t)
        if len(idx) == 0:
            raise ValueError(f"no configuration point lies in the window {self.window}")
        return idx

    def in_window(self, t: np.ndarray) -> np.ndarray:
        """Indices (P,) of the times t (N,) in the window (P may be 0)."""
        eps = 1e-9 * max(np.max(t), 1.0)
        return np.nonzero((t >= self.window[0] - eps) & (t <= self.window[1] + eps))[0]

    def bind(self, model: _core.Model) -> PathConstraint:
        """Resolve names against the model (raises ValueError naming what is unknown); returns self."""
        return self

    def evaluate(self, model: _core.Model, t: np.ndarray, Q: np.ndarray) -> PathValue:
        """At the points' times t (P,) and configurations Q (P, n): (values (P, r), jacobians (P, r, n))."""
        raise NotImplementedError

    lower: np.ndarray
    upper: np.ndarray


class OnBodyPoints(PathConstraint):
    """Base of the constraints on the world positions of body points: ``bind`` sets ``bodies`` (m,)
    and ``local`` (m, 3) (points in the bodies' joint frames), and ``form`` states the rows as
    functions of the points' world positions x_b (3,):

        row i = c_i + sum_b L[i, b] . x_b + sum_b D[i, b] . (x_b * x_b)

    (linear in the positions, or a weighted sum of squares: a clearance). The NLP evaluates all such
    constraints on the same configurations together in C++, with their exact Hessian
    (``hovi._core.trajopt.BodyPointRows``: one forward kinematics per configuration for all their
    points); ``of_points`` evaluates one in Python."""

    bodies: list[int]
    local: np.ndarray

    def form(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(c (r,), L (r, m, 3), D (r, m, 3)) of the rows (see the class)."""
        raise NotImplementedError

    def of_points(self, X: np.ndarray, J: np.ndarray) -> PathValue:
        """(values (P, r), jacobians (P, r, n)) from the points' positions X (P, m, 3) and Jacobians J (P, m, 3, n)."""
        c, L, D = self.form()
        values = c + np.einsum("rmx,pmx->pr", L, X) + np.einsum("rmx,pmx->pr", D, X * X)
        return values, np.einsum("prmx,pmxn->prn", L + 2 * D * X[:, None], J)

    def evaluate(self, model: _core.Model, t: np.ndarray, Q: np.ndarray) -> PathValue:
        """At configurations Q (P, n): (values (P, r), jacobians (P, r, n)); the times t do not enter."""
        return self.of_points(*_core.body_point_kinematics(model, Q, self.bodies, self.local))


class BodyPoint(OnBodyPoints):
    """A point (3,) of a body (in its joint frame) with world coordinates ``axes`` (e.g. 'z', 'xz':
    r rows) equal to ``target`` (r,) (a hand at a target) or within [lower, upper] (r,) (a foot above
    an obstacle: axes='z', lower=height)."""

    def __init__(self, body: int | str, point: npt.ArrayLike = (0.0, 0.0, 0.0), *, target: npt.ArrayLike | None = None,
                 lower: npt.ArrayLike | None = None, upper: npt.ArrayLike | None = None, axes: str = "xyz",
                 at: float | None = None, window: tuple[float, float] | None = None, between: int = 0):
        super().__init__(at, window, between)
        if not isinstance(axes, str):
            raise ValueError(f"axes must be a combination of 'x', 'y', 'z', got {axes!r}")
        self.rows = _axes(axes)
        self.point = real_array(point, "point", finite=False)
        if self.point.shape != (3,) or not np.all(np.isfinite(self.point)):
            raise ValueError(f"point must have 3 coordinates, finite, got {point!r:.60}")
        self.body = body
        r = len(self.rows)
        if target is not None:
            if lower is not None or upper is not None:
                raise ValueError("give target= or lower=/upper=, not both")
            self.lower = self.upper = _rows(target, r, "target", finite=True)
        else:
            self.lower = _rows(-np.inf if lower is None else lower, r, "lower")
            self.upper = _rows(np.inf if upper is None else upper, r, "upper")
        if np.any(self.lower > self.upper):
            raise ValueError(f"lower > upper in a body-point constraint: {self.lower} > {self.upper}")

    def bind(self, model: _core.Model) -> BodyPoint:
        """Resolve the body (index or name) against the model; returns self."""
        self.index = body_index(model, self.body)
        self.bodies, self.local = [self.index], self.point[None]
        return self

    def form(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The point's world coordinates `axes`: c (r,) = 0, L (r, 1, 3) selecting them, D (r, 1, 3) = 0."""
        r = len(self.rows)
        L = np.zeros((r, 1, 3))
        L[np.arange(r), 0, self.rows] = 1.0
        return np.zeros(r), L, np.zeros((r, 1, 3))


class Clearance(BodyPoint):
    """A point (3,) of a body stays at least ``radius`` from a world point ``center`` (3,) (a spherical
    obstacle; with axes='xz', a circle in that plane): |P (x - center)|^2 >= radius^2."""

    def __init__(self, body: int | str, point: npt.ArrayLike = (0.0, 0.0, 0.0), *, center: npt.ArrayLike,
                 radius: float, axes: str = "xyz", at: float | None = None, window: tuple[float, float] | None = None,
                 between: int = 0):
        super().__init__(body, point, axes=axes, at=at, window=window, between=between)
        self.center = real_array(center, "center", (3,))
        radius = real_number(radius, "radius")
        if radius <= 0:
            raise ValueError("radius must be positive")
        self.lower, self.upper = np.array([radius ** 2]), np.array([np.inf])

    def form(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """|P (x - center)|^2 = |P center|^2 - 2 (P center) . x + sum over the axes of x_a^2: c (1,),
        L (1, 1, 3), D (1, 1, 3)."""
        L, D = np.zeros((1, 1, 3)), np.zeros((1, 1, 3))
        L[0, 0, self.rows] = -2.0 * self.center[self.rows]
        D[0, 0, self.rows] = 1.0
        return np.array([np.sum(self.center[self.rows] ** 2)]), L, D


class PoseHeld(OnBodyPoints):
    """A body held at its pose at configuration q0 (n,) over ``window`` (default: every point; a
    stance foot): its point ``point`` (3 rows), the point size[0] ahead of it along the body's x axis
    across and up (2 rows, along the body's y and z axes at q0) and the point size[1] to its side up
    (1 row): six independent rows."""

    def __init__(self, body: int | str, q0: npt.ArrayLike, point: npt.ArrayLike = (0.0, 0.0, 0.0),
                 size: tuple[float, float] = (0.1, 0.1), window: tuple[float, float] = (-np.inf, np.inf),
                 between: int = 0):
        super().__init__(window=window, between=between)
        self.body, self.q0, self.point = body, np.asarray(q0, float), np.asarray(point, float)
        if self.point.shape != (3,) or not np.all(np.isfinite(self.point)):
            raise ValueError(f"point must be 3 finite numbers, got {point!r}")
        if len(size) != 2 or not all(np.isfinite(a) and a > 0 for a in size):
            raise ValueError(f"size must be two positive lengths, got {size!r}")
        self.local = np.array([self.point, self.point + (size[0], 0, 0), self.point + (0, size[1], 0)])

    def bind(self, model: _core.Model) -> PoseHeld:
        """Resolve the body and record the three points' world positions at q0; returns self."""
        self.index = body_index(model, self.body)
        self.bodies = [self.index] * 3
        if self.q0.shape != (model.n,) or not np.all(np.isfinite(self.q0)):
            raise ValueError(f"q0 must be {model.n} finite numbers, got shape {self.q0.shape}")
        pose = model.joint_placements(self.q0)[self.index]
        R0 = pose[:3, :3]
        self.P = np.zeros((6, 3, 3))                                   # row r = sum_k P[r, k] . x_k
        self.P[0:3, 0] = np.eye(3)
        self.P[3, 1], self.P[4, 1], self.P[5, 2] = R0[:, 1], R0[:, 2], R0[:, 2]
        self.lower = self.upper = np.einsum("rkx,kx->r", self.P, pose[:3, 3] + self.local @ R0.T)
        return self

    def form(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The six rows, linear in the three points' positions: c (6,) = 0, L = P (6, 3, 3), D (6, 3, 3) = 0."""
        return np.zeros(6), self.P, np.zeros_like(self.P)


class CallbackPathConstraint(PathConstraint):
    """A user condition ``lower <= fun(t, Q) <= upper`` on configurations, vectorised over the points:
    ``fun(t (P,), Q (P, n)) -> (P, r)`` and ``jac(t, Q) -> (P, r, n)``."""

    def __init__(self, fun: Callable[[np.ndarray, np.ndarray], npt.ArrayLike],
                 jac: Callable[[np.ndarray, np.ndarray], npt.ArrayLike], lower: npt.ArrayLike, upper: npt.ArrayLike, *,
                 at: float | None = None, window: tuple[float, float] | None = None, between: int = 0):
        super().__init__(at, window, between)
        self.fun, self.jac = fun, jac
        if not (callable(fun) and callable(jac)):
            raise TypeError("CallbackPathConstraint fun and jac must be callable")
        self.lower = np.atleast_1d(real_array(lower, "lower", finite=False))
        self.upper = np.atleast_1d(real_array(upper, "upper", finite=False))
        if np.any(np.isnan(self.lower)) or np.any(np.isnan(self.upper)):
            raise ValueError("CallbackPathConstraint lower and upper must not be NaN")
        if self.lower.shape != self.upper.shape or np.any(self.lower > self.upper):
            raise ValueError("lower and upper must have the same shape with lower <= upper")

    def evaluate(self, model: _core.Model, t: np.ndarray, Q: np.ndarray) -> PathValue:
        """fun(t, Q) (P, r) and jac(t, Q) (P, r, n) at times t (P,) and configurations Q (P, n), checked."""
        P, r = len(Q), len(self.lower)
        values, jac = np.asarray(self.fun(t, Q), float), np.asarray(self.jac(t, Q), float)
        if values.shape != (P, r) or jac.shape != (P, r, Q.shape[1]):
            raise ValueError(f"CallbackPathConstraint: fun must return ({P}, {r}) and jac ({P}, {r}, {Q.shape[1]}), "
                             f"got {values.shape} and {jac.shape}")
        return values, jac
