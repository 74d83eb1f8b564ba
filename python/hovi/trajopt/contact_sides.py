"""Reading the sides of the complementarity pairs off a (relaxed) solution, for the exact solve of
a contact-implicit problem (``hovi.trajopt.solve_contact``): which side of every pair is zero
(``sides_of``), another transcription's sides at these pairs (``sides_of_solution``), the
friction inputs reduced to one direction where the contact sticks (``canonical``), and the least
sliding slacks of a solution (``least_slack``)."""
from __future__ import annotations

from typing import List, Tuple

import numpy as np

from .complementarity import Sides, ContactRows


def opposite_pairs(D: np.ndarray) -> List[Tuple[int, int]]:
    """(k, l) index pairs of opposite friction directions, D_l = -D_k."""
    return [(k, l) for k in range(len(D)) for l in range(k + 1, len(D)) if np.allclose(D[k], -D[l])]


def canonical(rows: ContactRows, x: np.ndarray) -> np.ndarray:
    """x with the friction inputs of opposite directions reduced by their common part (the same
    friction force, the least sum): where the contact sticks, the split between +D and -D is
    not determined by the conditions, and only one of them carries the force."""
    x = x.copy()
    for k, l in opposite_pairs(rows.contacts.D):
        ik, il = rows.input_offsets("friction", k), rows.input_offsets("friction", l)
        common = np.minimum(np.maximum(x[ik], 0), np.maximum(x[il], 0))
        x[ik] -= common
        x[il] -= common
    return x


def sides_of(rows: ContactRows, x: np.ndarray) -> Sides:
    """The side of every complementarity pair that is zero at (a relaxed solution) x: each input
    is converted to what it does to its gap-like partner over the pair's interval dt, through the
    contact point's mobility J M^-1 J^T at the force's configuration (a normal force lambda moves
    the point by lambda w_n dt^2, a friction force beta_k changes its velocity by beta_k w_k dt,
    a cone margin psi its sliding speed by psi w dt), and the smaller of the two is zero."""
    k = rows.quantities(x)
    _, J = rows.kinematics(x)
    model, D, P = rows.contacts.with_inputs, rows.contacts.D, rows.E
    Q = x[rows.q_off[:P, None] + np.arange(rows.n)]
    W = np.empty((P, rows.C, 3, 3))
    for i in range(P):
        Minv_Jt = np.linalg.lstsq(model.mass_matrix(Q[i]), J[i].reshape(-1, rows.n).T, rcond=None)[0]
        W[i] = np.einsum("cxn,ncy->cxy", J[i], Minv_Jt.reshape(rows.n, rows.C, 3))
    dt = rows.dt[:, None]
    w_n = W[..., 2, 2]                                             # (E, C)
    w_t = np.einsum("kx,ecxy,ky->eck", D, W, D)                    # (E, C, d)
    normal = k["phi"] < np.maximum(k["lambda"], 0) * w_n * dt ** 2
    friction = k["zeta"] < np.maximum(k["beta"], 0) * w_t * dt[..., None]
    cone = np.maximum(k["psi"], 0) * w_t.max(-1) * dt < k["gamma"]
    return Sides(normal=normal, cone=cone, friction=friction)


def sides_of_solution(rows: ContactRows, result) -> Sides:
    """The sides of the pairs of ``result`` (a solution of the same contacts with another
    transcription or order, e.g. the trapezoidal VI's) at the pairs of ``rows``: each pair takes the
    sides of the result's pair whose interval holds its point. Read at the result's own points,
    where its forces and gaps belong together; read at its interpolation instead, a fine point in
    an interval with a force gets its interpolated force and a side of its own, which disagree
    (bench/README.md, "Design measurements")."""
    coarse = ContactRows(rows.contacts, result.transcription, 0.0)
    B = sides_of(coarse, canonical(coarse, result.x))
    slack = 1e-9 * coarse.dt.min()                                 # a fine point on a coarse one is in its pair
    j = np.clip(np.searchsorted(coarse.t, rows.t[:-1] + slack, side="right") - 1, 0, coarse.E - 1)
    return Sides(B.normal[j], B.cone[j], B.friction[j])


def least_slack(rows: ContactRows, x: np.ndarray) -> np.ndarray:
    """x with every sliding slack gamma lowered to the least value its rows allow,
    max(0, max_k -D_k v) (zeta_k = gamma + D_k v >= 0), never raised. gamma exerts no force; where
    the contact carries none (lambda = 0, every beta = 0) its pair's psi is zero and gamma is free
    above that bound, so an exact solve can leave it anywhere (bench/README.md, "Design
    measurements"); the least value is the same solution."""
    x = x.copy()
    k = rows.quantities(x)
    slack = rows.input_offsets("slack")
    least = np.maximum(0.0, (-(k["v"] @ rows.contacts.D.T)).max(-1))
    x[slack] = np.minimum(x[slack], least)
    last, before = rows.hold_inputs()
    x[last] = x[before]                                            # the hold rows: the last point repeats
    return x
