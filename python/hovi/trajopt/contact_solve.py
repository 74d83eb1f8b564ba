"""Contact-implicit trajectory optimisation without a mode schedule: a relaxation homotopy, then an
exact finish.

1. The complementarity products of a Problem with contacts (hovi.contact.Contacts) are bounded by
   epsilon, and epsilon is driven down over a few IPOPT solves, each warm-started from the last
   (Scholtes' relaxation).
2. The last relaxed solution tells, for every complementarity pair, which side is zero (each side
   scaled by its largest value over the trajectory; the smaller one is taken as zero). With that
   choice fixed (``complementarity.Branches``: a contact input fixed at zero, or a gap, cone or
   sliding row as an equality) the problem is a smooth NLP, solved from the relaxed solution: its
   solution satisfies complementarity exactly, and the free phases carry exactly zero contact
   force. If that solve fails (a wrong guess of the sides), the relaxed homotopy goes on to the
   smallest epsilon instead.

The result reports the final penetration, friction-cone violation and largest complementarity
product.
"""
from __future__ import annotations

import dataclasses
import time
from typing import Sequence

import numpy as np

from .complementarity import Branches, ContactRows
from .ipopt import solve
from .problem import Problem
from .result import Result

DEFAULT_EPSILONS = (1e-1, 1e-2, 1e-3)
FALLBACK_EPSILONS = (1e-4, 1e-5, 1e-6)


def _opposite_pairs(D: np.ndarray):
    """(k, l) index pairs of opposite friction directions, D_l = -D_k."""
    return [(k, l) for k in range(len(D)) for l in range(k + 1, len(D)) if np.allclose(D[k], -D[l])]


def canonical(rows: ContactRows, x: np.ndarray) -> np.ndarray:
    """x with the friction inputs of opposite directions reduced by their common part (the same
    friction force, the least sum): where the contact sticks, the split between +D and -D is
    not determined by the conditions, and only one of them carries the force."""
    x = x.copy()
    for k, l in _opposite_pairs(rows.contacts.D):
        ik, il = rows._input("friction", k), rows._input("friction", l)
        common = np.minimum(np.maximum(x[ik], 0), np.maximum(x[il], 0))
        x[ik] -= common
        x[il] -= common
    return x


def branches_of(rows: ContactRows, x: np.ndarray) -> Branches:
    """The side of every complementarity pair that is zero at (a relaxed solution) x: each input
    is converted to what it does to its gap-like partner over the pair's interval dt, through the
    contact point's mobility J M^-1 J^T at the force's configuration (a normal force lambda moves
    the point by lambda w_n dt^2, a friction force beta_k changes its velocity by beta_k w_k dt,
    a cone margin psi its sliding speed by psi w dt), and the smaller of the two is zero."""
    k = rows.quantities(x)
    _, J = rows.kinematics(x)
    model, D, P = rows.contacts.model, rows.contacts.D, rows.E
    Q = x[rows.q_off[:P, None] + np.arange(rows.n)]
    W = np.empty((P, rows.C, 3, 3))
    for i in range(P):
        Minv_Jt = np.linalg.lstsq(model.mass_matrix(Q[i]), J[i].transpose(0, 2, 1).reshape(rows.n, -1), rcond=None)[0]
        W[i] = np.einsum("cxn,ncy->cxy", J[i], Minv_Jt.reshape(rows.n, rows.C, 3))
    dt = rows.dt[:, None]
    w_n = W[..., 2, 2]                                             # (E, C)
    w_t = np.einsum("kx,ecxy,ky->eck", D, W, D)                    # (E, C, d)
    normal = k["phi"] < np.maximum(k["lambda"], 0) * w_n * dt ** 2
    friction = k["zeta"] < np.maximum(k["beta"], 0) * w_t * dt[..., None]
    cone = np.maximum(k["psi"], 0) * w_t.max(-1) * dt < k["gamma"]
    return Branches(normal=normal, cone=cone, friction=friction)


def solve_contact(problem: Problem, epsilons: Sequence[float] = DEFAULT_EPSILONS, *, s: int = 1, guess="rollout",
                  finish: bool = True, options: dict | None = None, verbose: bool = False) -> Result:
    """Solve ``problem`` (with ``add_contacts``) with the VI of order 2s: the relaxation homotopy
    over ``epsilons`` (positive, decreasing), then (``finish``) the exact solve on the sides of the
    complementarity pairs the last relaxed solution shows.

    s = 1 (default) is the contact model that is inelastic and well posed (see hovi.contact); s >= 2
    lets an impact inside a stage rebound.

    Returns the last Result with ``result.contact`` = {'penetration', 'cone', 'complementarity',
    'epsilon' (0 after an exact finish), 'finished' (bool), 'iterations' (per solve),
    'wall_seconds' (total)}."""
    if problem.contacts is None:
        raise ValueError("the problem has no contacts: call problem.add_contacts(contacts)")
    eps = [float(e) for e in epsilons]
    if not eps or any(not np.isfinite(e) or e <= 0 for e in eps) or any(b >= a for a, b in zip(eps, eps[1:])):
        raise ValueError(f"epsilons must be positive, finite and decreasing, got {epsilons}")
    if int(s) != s or s < 1:
        raise ValueError(f"s must be a positive integer, got {s}")
    saved = problem.complementarity_epsilon, problem.complementarity_branches
    iterations, wall, t0 = [], 0.0, time.perf_counter()

    def run(start, epsilon, branches=None):
        nonlocal wall
        problem.complementarity_epsilon, problem.complementarity_branches = epsilon, branches
        opts = dict(options or {})
        if isinstance(start, Result):
            opts.setdefault("mu_init", 1e-5)  # stay near the warm start
        r = solve(problem, "vi", s=s, guess=start, options=opts, verbose=verbose)
        iterations.append(r.iterations)
        wall += r.wall_seconds
        return r

    try:
        result = guess
        for e in eps:
            result = run(result, e)
        relaxed, finished = result, False
        if finish and relaxed.success:
            rows = ContactRows(problem.contacts, relaxed.transcription, eps[-1])
            start = dataclasses.replace(relaxed, x=canonical(rows, relaxed.x))
            result = run(start, 0.0, branches_of(rows, start.x))
            finished = result.success
        if not finished:
            result = relaxed
            for e in (e for e in FALLBACK_EPSILONS if e < eps[-1]):
                result = run(result, e)
    finally:
        problem.complementarity_epsilon, problem.complementarity_branches = saved
    rows = ContactRows(problem.contacts, result.transcription, 0.0)
    result.contact = {**rows.violations(result.x), "epsilon": 0.0 if finished else problem_epsilon(result, eps),
                      "finished": finished, "iterations": iterations, "wall_seconds": wall,
                      "total_seconds": time.perf_counter() - t0}
    return result


def problem_epsilon(result: Result, eps) -> float:
    return min([*eps, *(e for e in FALLBACK_EPSILONS if e < eps[-1])])
