"""What every transcription offers the NLP (nlp.py), on top of its C++ constraint function and
sparse Jacobian: the samples where costs are evaluated, the configuration points where path
constraints apply, the bounds and boundary conditions of a Problem in its variables, an initial
guess, and the trajectory read back from a solution.

Two kinds of object: a ``TranscriptionMethod`` is the choice (``VI(s=2)``, ``HermiteSimpson(form=
"implicit")``: small, immutable, comparable, picklable), and ``method.transcribe(problem)`` gives the
``Transcription`` of that problem (its variable layout, C++ core, guesses and trajectories)."""
from __future__ import annotations

from typing import Any, Callable, Tuple, Union

import numpy as np
import scipy.sparse as sp

from .. import _core
from .._checks import real_array
from .problem import Problem
from .result import Result
from .samples import SampleMap

# An initial guess: None or 'rollout', 'linear', a Result, or (q(t), v(t), u(t)) functions
Guess = Union[None, str, Result, Tuple[Callable[[np.ndarray], np.ndarray], ...]]
# Functions of time, vectorised: t (K,) -> (K, n) or (K, m)
TimeFunction = Callable[[np.ndarray], np.ndarray]


class TranscriptionMethod:
    """A way of transcribing a Problem into an NLP (``VI``, ``HermiteSimpson``): ``transcribe(problem)``
    builds its ``Transcription``. Subclasses are frozen dataclasses (repr, equality, pickling)."""

    name = "?"

    def transcribe(self, problem: Problem) -> Transcription:
        """The transcription of ``problem`` by this method."""
        raise NotImplementedError


class Transcription:
    """A Problem transcribed: the C++ core (constraints, Jacobian, variable offsets) and the layout of
    the variables x; ``method`` is the TranscriptionMethod that made it."""
    name = "?"

    def __init__(self, problem: Problem, core: Any):
        problem.check()
        self.problem, self.core = problem, core
        self.model = problem.model
        # Hessian patterns probed on NLPs over this transcription (hessian.py): NLPs that differ only
        # in bounds, such as a contact homotopy's solves, probe once
        self.probed_patterns: dict[tuple, Any] = {}
        self.n, self.m, self.mc = self.model.n, self.model.n_controls, self.model.n_constraints

    # --- implemented by each transcription ----------------------------------------------------
    def sample_map(self) -> SampleMap:
        """Where the costs are evaluated: sample times, weights and the sparse maps from x (samples.py)."""
        raise NotImplementedError

    def q_points(self) -> Tuple[np.ndarray, np.ndarray]:
        """(t (P,), offsets (P,)): times of the configuration variables and their offsets in x."""
        raise NotImplementedError

    def stage_nodes(self) -> np.ndarray:
        """Nodes (K,) on [0, 1] of a stage's configuration points, the Lobatto nodes of s = K - 1: stage
        k's configuration is the polynomial through q_points k (K - 1) .. k (K - 1) + K - 1 at these
        nodes (``interpolants``)."""
        raise NotImplementedError

    def bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        """(lower (n_variables,), upper (n_variables,)) of x: joint and control bounds, boundary
        conditions as fixed variables."""
        raise NotImplementedError

    def linear_rows(self) -> Tuple[sp.csr_matrix, np.ndarray]:
        """(A (r, n_variables) sparse, b (r,)): boundary conditions that are linear equalities A x = b."""
        return sp.csr_matrix((0, self.core.n_variables)), np.zeros(0)

    @property
    def method(self) -> TranscriptionMethod:
        """The TranscriptionMethod that gives this transcription."""
        raise NotImplementedError

    def guess(self, q_of_t: TimeFunction, v_of_t: TimeFunction, u_of_t: TimeFunction) -> np.ndarray:
        """x (n_variables,) from functions of time (vectorised: t (K,) -> (K, n) / (K, m))."""
        raise NotImplementedError

    def rollout_guess(self) -> np.ndarray | None:
        """x (n_variables,) from a simulation from the initial state with zero controls, or None if it fails."""
        raise NotImplementedError

    def linear_interpolants(self) -> Tuple[TimeFunction, TimeFunction, TimeFunction]:
        """(q(t), v(t), u(t)), t (K,) -> (K, n), (K, n), (K, m): q from q0 to qT (q0 without a final
        state) in a straight line, zero controls."""
        problem = self.problem
        q0 = problem.q0
        qT = q0 if problem.qT is None else problem.qT
        T, m = problem.T, problem.model.n_controls
        return (lambda t: q0 + np.outer(np.atleast_1d(t) / T, qT - q0),
                lambda t: np.tile((qT - q0) / T, (len(np.atleast_1d(t)), 1)),
                lambda t: np.zeros((len(np.atleast_1d(t)), m)))

    def initial_guess(self, guess: Guess = None) -> np.ndarray:
        """x0 (n_variables,) from: None or 'rollout' (simulate from the initial state with zero
        controls, ``rollout_guess``; if that fails, 'linear'), 'linear' (q from q0 to qT in a
        straight line, zero controls), a Result (warm start from another solve of the same
        transcription), or a tuple of functions (q(t), v(t), u(t))."""
        if isinstance(guess, Result):
            return self._result_guess(guess)
        if isinstance(guess, tuple):
            if len(guess) != 3 or not all(callable(f) for f in guess):
                raise ValueError(f"guess: a tuple guess must be three functions (q(t), v(t), u(t)) of times t (K,), got "
                                 f"{len(guess)} items of types {[type(f).__name__ for f in guess]}")
            names = ("q(t)", "v(t)", "u(t)")
            widths = (self.n, self.n, self.m)
            return self.guess(*(self._checked_function(f, name, width) for f, name, width in zip(guess, names, widths)))
        if guess is None or (isinstance(guess, str) and guess == "rollout"):
            x = self.rollout_guess()
            if x is not None:
                return x
            guess = "linear"
        if isinstance(guess, str) and guess == "linear":
            return self.guess(*self.linear_interpolants())
        raise ValueError(f"guess must be None, 'rollout', 'linear', a Result or (q(t), v(t), u(t)), got "
                         f"{type(guess).__name__} {guess!r:.80}")

    def _result_guess(self, guess: Result) -> np.ndarray:
        """x (n_variables,) of a Result of this transcription of a problem of this size (warm start)."""
        other = guess.transcription
        here = f"{self.method!r}, N = {self.problem.N}, {self.core.n_variables} variables"
        there = (f"{other.method!r}, N = {other.problem.N}, " if isinstance(other, Transcription) else "") + \
            f"{np.size(guess.x)} variables"
        if isinstance(other, Transcription) and (other.method != self.method or other.problem.N != self.problem.N
                                                 or other.model.n != self.n or other.m != self.m):
            raise ValueError(f"guess: the Result comes from another problem or transcription ({there}; this solve: "
                             f"{here}); pass result.as_guess() to interpolate it")
        x = np.asarray(guess.x)
        if x.shape != (self.core.n_variables,):
            raise ValueError(f"guess: the Result comes from a problem of a different size ({there}; this solve: "
                             f"{here}); pass result.as_guess() to interpolate it")
        x = real_array(x, "guess (the Result's x)")
        return x.copy()

    def _checked_function(self, f: TimeFunction, name: str, width: int) -> TimeFunction:
        """f, with its values at times t checked: (len(t), width) finite real numbers (ValueError
        naming the guess function ``name`` otherwise)."""
        def checked(t: np.ndarray) -> np.ndarray:
            label = f"guess {name}"
            try:
                out = real_array(f(t), f"{label} at the {len(t)} times t", (len(t), width))
            except TypeError as e:
                raise ValueError(str(e)) from None
            except ValueError as e:
                raise ValueError(f"{e}: {label} must be vectorised, times t (K,) -> (K, {width})") from None
            return out
        return checked

    def locate_variable(self, i: int) -> Tuple[str, int, int]:
        """(block, point, component) of x[i]: its block ('q', 'p', 'v', 'a', 'u', or 'l' for the
        multipliers), the configuration or control point and the joint, input or row within it;
        ('variable', -1, i) outside the blocks."""
        blocks = sorted((getattr(self, f"{name}_off"), name) for name in ("q", "p", "v", "a", "u", "l")
                        if isinstance(getattr(self, f"{name}_off", None), (int, np.integer)))
        name, off = "variable", 0
        for o, nm in blocks:
            if o <= i:
                name, off = nm, o
        width = self.m if name == "u" else self.mc if name == "l" else self.n
        if name == "variable" or not width:
            return "variable", -1, i
        point, j = divmod(i - off, width)
        return name, point, j

    def describe_variable(self, i: int) -> str:
        """Which variable x[i] is: its block (q, p, v, a, u or a multiplier), joint or input and point."""
        name, point, j = self.locate_variable(i)
        if name == "variable":
            return f"variable {i}"
        what = {"l": "multiplier", "u": "u"}.get(name, name)
        who = self.model.joint_names[j] if name in ("q", "p", "v", "a") else f"{'input' if name == 'u' else 'row'} {j}"
        return f"{what} of {who} at point {point}"

    def at(self, x: np.ndarray, status: str, success: bool) -> Result:
        """A Result holding the point x (n_variables,) of this transcription (a start for a solver;
        no solve behind it)."""
        return Result(status=status, success=success, cost=float("nan"), constraint_violation=float("nan"),
                      iterations=0, wall_seconds=0.0, trajectory=self.trajectory(x), x=x, transcription=self)

    def trajectory(self, x: np.ndarray) -> dict:
        """The arrays of the solution x (n_variables,): t, q (P, n), p or v, u, multipliers."""
        raise NotImplementedError

    def control_function(self, x: np.ndarray) -> TimeFunction:
        """u(t) of a solution x (n_variables,): the controls as the transcription interprets them,
        vectorised (t (K,) -> (K, m))."""
        raise NotImplementedError

    def interpolants(self, x: np.ndarray) -> Tuple[TimeFunction, TimeFunction, TimeFunction]:
        """(q(t), v(t), u(t)) of a solution x (n_variables,), vectorised (t (K,) -> (K, n), (K, n),
        (K, m)): a guess for another transcription or N."""
        raise NotImplementedError

    # --- shared helpers ---------------------------------------------------------------------
    def u_points(self) -> np.ndarray:
        """(P,) offsets of the controls at the configuration points of q_points (per-point controls:
        the VI's control points, Hermite-Simpson's knots and midpoints)."""
        if self.problem.controls != "per_point":
            raise ValueError("controls at the configuration points need controls='per_point'")
        return self.u_off + np.arange(self.n_points) * self.m

    def q_samples(self, between: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``between`` (>= 1) evenly spaced configurations between each two consecutive
        configuration points, on the stage's polynomial (``stage_nodes``), as weighted sums of the
        stage's points: (t (P,), points (P, K), weights (P, K)), sample p = sum_k weights[p, k]
        q_points[points[p, k]]."""
        tq, _ = self.q_points()
        nodes = self.stage_nodes()
        K = len(nodes)
        N = (len(tq) - 1) // (K - 1)
        frac = np.arange(1, between + 1) / (between + 1)
        tau = (nodes[:-1, None] + frac[None, :] * np.diff(nodes)[:, None]).ravel()  # ((K - 1) between,) in (0, 1)
        first = np.arange(N) * (K - 1)
        h = tq[first + K - 1] - tq[first]
        t = (tq[first][:, None] + h[:, None] * tau[None, :]).ravel()
        points = np.repeat((first[:, None] + np.arange(K))[:, None, :], len(tau), 1).reshape(-1, K)
        return t, points, np.tile(_core.lagrange_basis(K - 1, tau), (N, 1))

    def _tile_bounds(self, lower, upper, count):
        return np.tile(lower, count), np.tile(upper, count)


def piecewise_polynomial(t_stage: float, s: int, values: np.ndarray, t: np.ndarray, derivative=False):
    """Evaluate at t the piecewise polynomial with values[k, a] at stage k's Lobatto nodes c^a of s
    (Integrator.nodes; s = 2: start, midpoint, end), or its time derivative."""
    N = values.shape[0]
    t = np.atleast_1d(np.asarray(t, float))
    k = np.clip(np.floor(t / t_stage).astype(int), 0, N - 1)
    x = t / t_stage - k
    out = np.zeros((len(t),) + values.shape[2:])
    for kk in np.unique(k):
        sel = k == kk
        B = _core.lagrange_basis(s, x[sel], derivative) / (t_stage if derivative else 1.0)
        out[sel] = np.tensordot(B, values[kk], axes=(1, 0))
    return out
