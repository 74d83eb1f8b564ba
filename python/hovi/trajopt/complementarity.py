"""The contact conditions of ``hovi.contact.Contacts`` as rows of the NLP, at every configuration
point of a transcription, with their exact sparse Jacobian (from the contact points' positions
and position Jacobians: one vectorised C++ call for all points and contacts).

Rows per contact c and point j (r = 4 + 2 d), bounds in brackets:
    phi                                  [0, inf)      gap to the terrain
    psi = mu lambda - sum_i beta_i       [0, inf)      inside the friction cone
    zeta_i = gamma + D_i . v             [0, inf)      i = 1..d
    lambda phi                           (-inf, eps]
    gamma psi                            (-inf, eps]
    beta_i zeta_i                        (-inf, eps]   i = 1..d
v = (x_c(q_after) - x_c(q_before)) / (t_after - t_before) over the interval ending at j (the
first interval for j = 0). The transcription gives the offsets of q_j and of the controls u_j at
its configuration points (``q_points``, ``u_points``).
"""
from __future__ import annotations

from typing import List, Tuple

import numpy as np

from .. import _core
from ..contact.contacts import Contacts


class ContactRows:
    def __init__(self, contacts: Contacts, tr, epsilon: float) -> None:
        if not hasattr(tr, "u_points"):
            raise ValueError(f"contact conditions need a transcription with controls at its configuration points; "
                             f"{tr.name} has none")
        self.contacts, self.epsilon = contacts, float(epsilon)
        self.t, self.q_off = tr.q_points()
        self.u_off = tr.u_points()
        P, C, d, n = len(self.t), contacts.n_contacts, contacts.d, tr.n
        self.before = np.maximum(np.arange(P) - 1, 0)
        self.after = np.maximum(np.arange(P), 1)
        self.dt = self.t[self.after] - self.t[self.before]
        self.n, self.P, self.C, self.d = n, P, C, d
        self.rows_per_point = 4 + 2 * d
        self.count = P * C * self.rows_per_point
        self.lower = np.zeros(self.count)
        self.upper = np.full(self.count, np.inf)
        self.lower[self._row(3, 0):] = -np.inf
        self.upper[self._row(3, 0):] = self.epsilon
        self.rows, self.cols = self._structure()

    # Row index of the block of row type k (0: phi, 1: psi, 2..2+d-1: zeta, then products) for entry e
    # of the (P, C) grid; rows are grouped by type, then by point, then by contact.
    def _row(self, kind: int, e) -> np.ndarray:
        return kind * self.P * self.C + np.asarray(e)

    def _input(self, what: str, i: int = 0) -> np.ndarray:
        """(P, C) offsets in x of an input of every contact at every point."""
        idx = np.array([self.contacts.input_index(c, what, i) for c in range(self.C)])
        return self.u_off[:, None] + idx[None, :]

    def _q_cols(self, which: np.ndarray) -> np.ndarray:
        """(P, C, n) offsets of q at points ``which`` (P,)."""
        cols = self.q_off[which][:, None] + np.arange(self.n)[None, :]
        return np.broadcast_to(cols[:, None, :], (self.P, self.C, self.n))

    def _pieces(self) -> List[Tuple[int, np.ndarray]]:
        """(row kind, columns (P, C, k)) of every row kind, in the order ``evaluate`` fills values."""
        lam, gam = self._input("normal")[..., None], self._input("slack")[..., None]
        beta = np.stack([self._input("friction", i) for i in range(self.d)], axis=-1)
        qj, qa, qb = self._q_cols(np.arange(self.P)), self._q_cols(self.after), self._q_cols(self.before)
        pieces = [(0, qj), (1, np.concatenate([lam, beta], -1))]
        pieces += [(2 + i, np.concatenate([qa, qb, gam], -1)) for i in range(self.d)]
        pieces += [(2 + self.d, np.concatenate([qj, lam], -1)), (3 + self.d, np.concatenate([gam, lam, beta], -1))]
        pieces += [(4 + self.d + i, np.concatenate([qa, qb, gam, beta[..., i:i + 1]], -1)) for i in range(self.d)]
        return pieces

    def _structure(self):
        grid = np.arange(self.P * self.C).reshape(self.P, self.C)
        rows, cols = [], []
        for kind, c in self._pieces():
            rows.append(np.broadcast_to(self._row(kind, grid)[..., None], c.shape).ravel())
            cols.append(c.ravel())
        return np.concatenate(rows), np.concatenate(cols)

    def kinematics(self, x: np.ndarray):
        """Contact positions X (P, C, 3) and their Jacobians J (P, C, 3, n) at the points."""
        Q = x[self.q_off[:, None] + np.arange(self.n)]
        Qc = np.repeat(Q, self.C, axis=0)
        bodies = [c.body for c in self.contacts.points] * self.P
        points = np.tile(np.array([c.point for c in self.contacts.points]), (self.P, 1))
        X, J = _core.trajopt.body_point_kinematics(self.contacts.model, Qc, bodies, points)
        return X.reshape(self.P, self.C, 3), J.reshape(self.P, self.C, 3, self.n)

    def evaluate(self, x: np.ndarray, with_jacobian: bool) -> np.ndarray:
        X, J = self.kinematics(x)
        ct, D, d = self.contacts, self.contacts.D, self.d
        phi = ct.terrain.gap(X.reshape(-1, 3)).reshape(self.P, self.C)
        lam, gam = x[self._input("normal")], x[self._input("slack")]
        beta = np.stack([x[self._input("friction", i)] for i in range(d)], axis=-1)       # (P, C, d)
        psi = ct.mu * lam - beta.sum(-1)
        inv_dt = (1.0 / self.dt)[:, None, None]
        v = (X[self.after] - X[self.before]) * inv_dt                                        # (P, C, 3)
        zeta = gam[..., None] + v @ D.T                                                       # (P, C, d)
        if not with_jacobian:
            return np.concatenate([phi.ravel(), psi.ravel(), zeta.transpose(2, 0, 1).ravel(), (lam * phi).ravel(),
                                   (gam * psi).ravel(), (beta * zeta).transpose(2, 0, 1).ravel()])
        dphi = J[..., 2, :]                                                                   # (P, C, n)
        ones = np.ones((self.P, self.C, 1))
        dzeta_a = np.einsum("id,pcdn->ipcn", D, J[self.after]) * inv_dt[None]                # (d, P, C, n)
        dzeta_b = -np.einsum("id,pcdn->ipcn", D, J[self.before]) * inv_dt[None]
        values = [dphi, np.concatenate([ct.mu * ones, -np.ones((self.P, self.C, d))], -1)]
        values += [np.concatenate([dzeta_a[i], dzeta_b[i], ones], -1) for i in range(d)]
        values += [np.concatenate([lam[..., None] * dphi, phi[..., None]], -1),
                   np.concatenate([psi[..., None], gam[..., None] * ct.mu, -gam[..., None] * np.ones((1, 1, d))], -1)]
        values += [np.concatenate([beta[..., i:i + 1] * dzeta_a[i], beta[..., i:i + 1] * dzeta_b[i],
                                   beta[..., i:i + 1], zeta[..., i:i + 1]], -1) for i in range(d)]
        return np.concatenate([v.ravel() for v in values])

    def violations(self, x: np.ndarray) -> dict:
        """Largest penetration, cone violation and complementarity product at x."""
        g = self.evaluate(x, False)
        PC = self.P * self.C
        return {"penetration": float(max(0.0, -g[:PC].min())),
                "cone": float(max(0.0, -g[PC:(2 + self.d) * PC].min())),
                "complementarity": float(np.abs(g[(2 + self.d) * PC:]).max())}
