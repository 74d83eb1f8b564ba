"""The contact conditions of ``hovi.contact.Contacts`` as rows of the NLP: their bounds and sparse
Jacobian structure here, their values, Jacobian and exact Hessian in C++ (``ContactRows.block``,
cpp/include/hovi/trajopt/complementarity_rows.hpp).

Pairing (see ``hovi.contact.contacts`` for why): the contact inputs u_i at configuration point i
act on the motion that follows it, so they are complementary to the gap at the next point and to
the contact point's velocity over the interval [t_i, t_{i+1}]. Per contact c and pair i = 0..P-2
(r = 4 + 2 d rows), bounds in brackets:
    phi(q_{i+1})                          [0, inf)      gap to the terrain
    psi = mu lambda_i - sum_k beta_i,k    [0, inf)      inside the friction cone
    zeta_k = gamma_i + D_k . v_i          [0, inf)      k = 1..d, v_i = (x(q_{i+1}) - x(q_i)) / (t_{i+1} - t_i)
    lambda phi                            (-inf, eps]
    gamma psi                             (-inf, eps]
    beta_k zeta_k                         (-inf, eps]   k = 1..d
and, at the last point (no later motion to act on), its contact inputs equal those of the point
before (2 + d rows, [0, 0]).

``sides`` replaces the relaxed products by a choice per pair (``Sides``): either the input
is zero (a fixed variable: ``fixed_inputs``) or the gap-like row is zero (an equality); the
product rows are then dropped from the bounds (-inf, inf). That is a smooth NLP whose solution
satisfies the complementarity exactly (``hovi.trajopt.solve_contact`` uses it to finish).
A ``ComplementarityRelaxation`` (epsilon, sides) is what the NLP is given
(``hovi.trajopt.NLP(problem, transcription, relaxation=...)``); the Problem holds no relaxation.

The transcription gives the offsets of q_j and of the controls u_j at its configuration points
(``q_points``, ``u_points``) and the configuration size ``n``; nothing else of it is used. The same rows serve every transcription
with per-point controls. In the VI the points are a stage's control points, and the inputs at
point i enter the DEL equations of the stage after it. In Hermite-Simpson collocation they are the
knots and midpoints (pairs over half intervals), and the inputs at point i enter the acceleration
a_i collocated there; that acceleration moves the next point, which the pairing needs: with h the
interval, q_m = q_k + h v_k / 2 + h^2 (3 a_k + 4 a_m - a_{k+1}) / 48 and q_{k+1} = q_k + h v_k
+ h^2 (a_k + 2 a_m) / 6, so a knot's force moves the midpoint after it (3 h^2 / 48 of a_k, and h^2 / 12 more through
v_k = v_{k-1} + h (a_{k-1} + 4 a_{m-1} + a_k) / 6 after the first knot) and a midpoint's force
the next knot (h^2 / 3 of a_m).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, List, Optional, Tuple

import numpy as np

from .. import _core
from ..contact.contacts import Contacts

if TYPE_CHECKING:
    from .transcription import Transcription


@dataclass
class Sides:
    """One side of every complementarity pair, (E, C) booleans each (E = P - 1 pairs, C contacts):
    True where the gap-like quantity is zero (an equality row), False where the input is zero."""
    normal: np.ndarray     # phi = 0 (else lambda = 0)
    cone: np.ndarray       # psi = 0 (else gamma = 0)
    friction: np.ndarray   # (E, C, d): zeta_k = 0 (else beta_k = 0)


@dataclass(frozen=True, eq=False)
class ComplementarityRelaxation:
    """How the NLP states the complementarity products of a problem's contacts: bounded by
    ``epsilon`` >= 0 (Scholtes' relaxation), or, with ``sides``, one side of every pair fixed
    (the exact conditions as a smooth NLP). epsilon = 0 without sides is the exact conditions,
    which IPOPT cannot solve directly (the NLP refuses them)."""
    epsilon: float = 0.0
    sides: Optional[Sides] = None

    def __post_init__(self):
        if not (np.isfinite(self.epsilon) and self.epsilon >= 0):
            raise ValueError(f"the complementarity relaxation must be finite and >= 0, got {self.epsilon}")
        object.__setattr__(self, "epsilon", float(self.epsilon))

    @property
    def exact(self) -> bool:
        """True for the exact conditions with no sides (not a smooth NLP)."""
        return self.epsilon == 0 and self.sides is None


class ContactRows:
    """The complementarity rows of ``contacts`` on the configuration points of the transcription
    ``tr``, with the products bounded by ``epsilon`` or one side of every pair fixed (``sides``)."""

    def __init__(self, contacts: Contacts, tr: Transcription, epsilon: float,
                 sides: Optional[Sides] = None) -> None:
        if not (np.isfinite(epsilon) and epsilon >= 0):
            raise ValueError(f"the complementarity relaxation must be finite and >= 0, got {epsilon}")
        self.contacts, self.epsilon, self.sides = contacts, float(epsilon), sides
        self.t, self.q_off = tr.q_points()
        self.u_off = tr.u_points()
        P, C, d, n = len(self.t), contacts.n_contacts, contacts.d, tr.n
        if P < 2:
            raise ValueError("contact conditions need at least two configuration points")
        self.n, self.P, self.E, self.C, self.d = n, P, P - 1, C, d
        self.dt = np.diff(self.t)
        self.rows_per_pair = 4 + 2 * d
        self.n_pair_rows = self.E * C * self.rows_per_pair
        self.n_hold = C * contacts.inputs_per_contact
        self.count = self.n_pair_rows + self.n_hold
        self.lower, self.upper = self._bounds()
        self.rows, self.cols = self._structure()

    # Rows are grouped by kind (0: phi, 1: psi, 2..2+d-1: zeta, 2+d: lambda phi, 3+d: gamma psi,
    # 4+d..: beta zeta), then by pair, then by contact; the hold rows come last.
    def _row(self, kind: int, e) -> np.ndarray:
        return kind * self.E * self.C + np.asarray(e)

    def _bounds(self) -> Tuple[np.ndarray, np.ndarray]:
        lower, upper = np.zeros(self.count), np.full(self.count, np.inf)
        EC, d = self.E * self.C, self.d
        products = slice(self._row(2 + d, 0), self.n_pair_rows)
        lower[products], upper[products] = -np.inf, self.epsilon
        upper[self.n_pair_rows:] = 0.0  # hold rows: equalities
        b = self.sides
        if b is not None:
            lower[products], upper[products] = -np.inf, np.inf
            gaps = np.concatenate([b.normal.ravel(), b.cone.ravel(), b.friction.transpose(2, 0, 1).ravel()])
            upper[:(2 + d) * EC][gaps] = 0.0
        return lower, upper

    def fixed_inputs(self) -> np.ndarray:
        """Offsets in x (k,) of the contact inputs that the sides fix at zero (none when relaxed)."""
        b = self.sides
        if b is None:
            return np.zeros(0, dtype=np.int64)
        parts = [self.input_offsets("normal")[~b.normal], self.input_offsets("slack")[~b.cone]]
        parts += [self.input_offsets("friction", k)[~b.friction[..., k]] for k in range(self.d)]
        return np.concatenate(parts).astype(np.int64)

    def input_offsets(self, what: str, k: int = 0, points: Optional[np.ndarray] = None) -> np.ndarray:
        """(len(points), C) offsets in x of an input of every contact at ``points`` (default: the
        pairs' force points 0..P-2)."""
        points = np.arange(self.E) if points is None else points
        idx = np.array([self.contacts.input_index(c, what, k) for c in range(self.C)])
        return self.u_off[points][:, None] + idx[None, :]

    def _q_cols(self, which: np.ndarray) -> np.ndarray:
        """(E, C, n) offsets of q at points ``which`` (E,)."""
        cols = self.q_off[which][:, None] + np.arange(self.n)[None, :]
        return np.broadcast_to(cols[:, None, :], (self.E, self.C, self.n))

    def _pieces(self) -> List[Tuple[int, np.ndarray]]:
        """(row kind, columns (E, C, k)) of every pair row kind, in the order ``evaluate`` fills values."""
        lam, gam = self.input_offsets("normal")[..., None], self.input_offsets("slack")[..., None]
        beta = np.stack([self.input_offsets("friction", k) for k in range(self.d)], axis=-1)
        qa, qb = self._q_cols(np.arange(1, self.P)), self._q_cols(np.arange(self.E))
        d = self.d
        pieces = [(0, qa), (1, np.concatenate([lam, beta], -1))]
        pieces += [(2 + k, np.concatenate([qa, qb, gam], -1)) for k in range(d)]
        pieces += [(2 + d, np.concatenate([qa, lam], -1)), (3 + d, np.concatenate([gam, lam, beta], -1))]
        pieces += [(4 + d + k, np.concatenate([qa, qb, gam, beta[..., k:k + 1]], -1)) for k in range(d)]
        return pieces

    def hold_inputs(self) -> Tuple[np.ndarray, np.ndarray]:
        """Offsets (n_hold,) of every contact input at the last point and at the point before (n_hold =
        C (2 + d))."""
        first = self.contacts.first_input
        idx = first + np.arange(self.n_hold)
        return self.u_off[self.P - 1] + idx, self.u_off[self.P - 2] + idx

    def _structure(self):
        grid = np.arange(self.E * self.C).reshape(self.E, self.C)
        rows, cols = [], []
        for kind, c in self._pieces():
            rows.append(np.broadcast_to(self._row(kind, grid)[..., None], c.shape).ravel())
            cols.append(c.ravel())
        last, before = self.hold_inputs()
        hold = self.n_pair_rows + np.arange(self.n_hold)
        rows += [np.repeat(hold, 2)]
        cols += [np.stack([last, before], -1).ravel()]
        return np.concatenate(rows), np.concatenate(cols)

    def kinematics(self, x: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
        """Contact positions X (P, C, 3) and their Jacobians J (P, C, 3, n) at all points of x (n_variables,)."""
        Q = x[self.q_off[:, None] + np.arange(self.n)]
        points = self.contacts.points
        return _core.body_point_kinematics(self.contacts.with_inputs, Q, [c.body for c in points],
                                                   np.array([c.point for c in points]))

    def quantities(self, x: np.ndarray) -> dict:
        """The pair quantities at x: phi, psi (E, C), zeta (E, C, d), lambda, gamma (E, C), beta (E, C, d)."""
        X, _ = self.kinematics(x)
        ct = self.contacts
        phi = ct.core_model().gaps(X[1:])
        lam, gam = x[self.input_offsets("normal")], x[self.input_offsets("slack")]
        beta = np.stack([x[self.input_offsets("friction", k)] for k in range(self.d)], axis=-1)
        v = (X[1:] - X[:-1]) / self.dt[:, None, None]
        zeta = gam[..., None] + v @ ct.D.T
        return {"phi": phi, "psi": ct.mu * lam - beta.sum(-1), "zeta": zeta, "lambda": lam, "gamma": gam,
                "beta": beta, "v": v}

    def block(self, n_variables: int) -> _core.trajopt.ComplementarityRows:
        """These rows in C++ (complementarity_rows.hpp): values, the Jacobian's values in the order
        of (rows, cols), and their exact Hessian, for the NLP's program over ``n_variables``."""
        ct = self.contacts
        return _core.trajopt.ComplementarityRows(ct.with_inputs, n_variables, ct.core_model(), ct.first_input, self.t,
                                                 self.q_off.astype(np.int32), self.u_off.astype(np.int32))

    def violations(self, x: np.ndarray) -> dict:
        """Largest penetration, friction-cone violation and complementarity product at x (n_variables,)
        (the products of the pairs, whatever the relaxation or sides)."""
        k = self.quantities(x)
        cone = np.concatenate([k["psi"].ravel(), k["zeta"].ravel()])
        products = np.concatenate([(k["lambda"] * k["phi"]).ravel(), (k["gamma"] * k["psi"]).ravel(),
                                   (k["beta"] * k["zeta"]).ravel()])
        return {"penetration": float(max(0.0, -k["phi"].min())), "cone": float(max(0.0, -cone.min())),
                "complementarity": float(np.abs(products).max())}
