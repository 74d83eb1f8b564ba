"""Contact-implicit trajectory optimisation without a mode schedule: a relaxation homotopy, then an
exact solve on the sides of the complementarity pairs it found.

1. The complementarity products of a Problem with contacts (hovi.contact.Contacts) are bounded by
   epsilon (Scholtes' relaxation), and epsilon is driven down over IPOPT solves, each started
   from the last solution.
2. After each relaxed solve with epsilon <= FINISH_BELOW, ``branches_of`` reads which side of every
   pair is zero: each input is converted, through the contact point's mobility J M^-1 J^T, to
   what it does to its partner over the interval (a normal force to a displacement, a friction
   force to a velocity change), and the smaller side is zero; where the contact sticks, the
   friction inputs of opposite directions are first reduced by their common part (``canonical``).
   With those sides fixed (``complementarity.Branches``: an input fixed at zero, or the gap, cone
   or sliding row as an equality) the problem is a smooth NLP; its solution satisfies
   complementarity exactly and the free phases carry exactly zero contact force. If it fails,
   the homotopy goes on.

NOTES (measurements, s = 1 unless said; 18 problems: drops from 0.05-0.5 m with N = 25, 50,
landing while sliding with mu = 0.5 and 0.1, a long slide, a push beyond friction, 3D slide and
landing, sliding off a ledge into a gap, a tilted bar dropped on two contacts, a bar sliding flat,
pushing a block to a target with an effort cost and a final state; guess 'rollout'):
- The pairing decides everything. With the inputs at point j paired with phi(q_j) (the first
  version) the conditions have no solution at half of the impacts and rebound at the others (see
  hovi.contact.contacts), and no solver setting helped (measured on that version, the drop test:
  eps = 0.1 needed bound_relax_factor 1e-8 and 163 iterations, eps <= 0.01 failed, with or without
  warm starts or regularising costs on beta and gamma; a penalty formulation diverged). With the
  pairing of hovi.contact all 18 problems end with the exact solve: 1120 IPOPT iterations, 7.5 s
  in all (the three closed-form tests: 0.2-0.4 s each); with s = 2, 2288 iterations and 29 s,
  all exact (but see hovi.contact for the rebound of s = 2).
- Hermite-Simpson with the same rows on its knots and midpoints (``transcription='hs-implicit'``),
  the drop from 0.3 m (N = 25) and the slide of the tests, against the VI s = 1 / s = 2: 402 and
  119 IPOPT iterations against 49 / 98 and 57 / 59 (explicit Hermite-Simpson 293 and 184), all
  exact; the drop rebounds 18.8 mm (VI s = 2: 3.3 mm, s = 1: none) and the slide stops at the
  same 0.1019 m.
- Stopping the relaxed solves at eps = 1e-6 instead leaves lambda ~ eps / phi in flight (a
  free-fall error of 8e-8); the exact solve gives complementarity 1e-9 .. 1e-18.
- Sides read at eps = 1e-3: all 18 exact solves succeed at once; at 1e-2: 4 fail (then 1e-3
  does it: 1041 iterations in all); at 1e-1: all 18 fail. Starting at eps = 1: 1388 iterations.
- tol 1e-6 for the relaxed solves (RELAXED_TOL): with zero cost one stalled at dual
  infeasibility 3.5e-8 for 400 iterations at tol 1e-8.
- Not kept: guess 'linear' (3867 iterations, 42 s); mu_init (no effect with the adaptive mu
  strategy); mu_strategy monotone (2659); limited_memory_max_history 6 (1104, no gain);
  nlp_scaling_method none (1117); warm starts with IPOPT's multipliers (warm_start_init_point:
  1325; with tight warm-start bound pushes 2 of 18 fail); the products as equalities
  lambda phi = eps (the smoothed central path): 8 of 18 fail, 17341 iterations.
- Not tried: explicit slack variables for the gaps (the NLP has no variables of its own beyond
  the transcription's), Fischer-Burmeister, an exact Hessian of the contact rows (IPOPT's
  Hessian stays L-BFGS); with the pairing fixed the solves take 4-60 iterations each, so the
  headroom is small.
"""
from __future__ import annotations

import dataclasses
import os
import time
import zipfile
from typing import Any, Sequence

import numpy as np

from .complementarity import Branches, ContactRows
from .ipopt import Guess, initial_guess, solve, transcribe
from .nlp import NLP
from .problem import Problem
from .result import Result

DEFAULT_EPSILONS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
FINISH_BELOW = 1e-3  # the exact solve is tried from relaxed solutions with epsilon <= this
# IPOPT's tol for the relaxed solves: only a path to the exact one (with zero cost some stall at a
# dual infeasibility of ~3e-8 for hundreds of iterations at hovi's default 1e-8)
RELAXED_TOL = 1e-6


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
        Minv_Jt = np.linalg.lstsq(model.mass_matrix(Q[i]), J[i].reshape(-1, rows.n).T, rcond=None)[0]
        W[i] = np.einsum("cxn,ncy->cxy", J[i], Minv_Jt.reshape(rows.n, rows.C, 3))
    dt = rows.dt[:, None]
    w_n = W[..., 2, 2]                                             # (E, C)
    w_t = np.einsum("kx,ecxy,ky->eck", D, W, D)                    # (E, C, d)
    normal = k["phi"] < np.maximum(k["lambda"], 0) * w_n * dt ** 2
    friction = k["zeta"] < np.maximum(k["beta"], 0) * w_t * dt[..., None]
    cone = np.maximum(k["psi"], 0) * w_t.max(-1) * dt < k["gamma"]
    return Branches(normal=normal, cone=cone, friction=friction)


def least_slack(rows: ContactRows, x: np.ndarray) -> np.ndarray:
    """x with every sliding slack gamma lowered to the least value its rows allow,
    max(0, max_k -D_k v) (zeta_k = gamma + D_k v >= 0), never raised. gamma exerts no force; where
    the contact carries none (lambda = 0, every beta = 0) its pair's psi is zero and gamma is free
    above that bound, so an exact solve can leave it anywhere (measured: 4e4 on LittleDog, a
    product gamma psi of 2.6e-6 from psi = 6e-11); the least value is the same solution."""
    x = x.copy()
    k = rows.quantities(x)
    slack = rows._input("slack")
    least = np.maximum(0.0, (-(k["v"] @ rows.contacts.D.T)).max(-1))
    x[slack] = np.minimum(x[slack], least)
    last, before = rows._hold_inputs()
    x[last] = x[before]                                            # the hold rows: the last point repeats
    return x


def solve_contact(problem: Problem, epsilons: Sequence[float] = DEFAULT_EPSILONS, *, s: int = 1,
                  transcription: str = "vi", guess: Guess = "rollout", finish_below: float = FINISH_BELOW,
                  options: dict[str, Any] | None = None, verbose: bool = False, hessian: str = "lbfgs",
                  time_limit: float | None = None, checkpoint: str | os.PathLike | None = None,
                  sides_from: Result | None = None) -> Result:
    """Solve ``problem`` (with ``add_contacts``) with ``transcription`` (as in ``solve``: the VI of
    order 2s by default, or 'hs-implicit' / 'hs-explicit' collocation with the same contact
    conditions on its knots and midpoints): the relaxation homotopy over ``epsilons`` (positive,
    decreasing), and after each relaxed solve with epsilon <= ``finish_below`` the exact solve on
    the sides of the complementarity pairs it shows, until one succeeds (finish_below = 0: relaxed
    solves only). ``options`` go to every IPOPT solve (the relaxed ones default to tol =
    RELAXED_TOL); ``hessian`` as in ``solve``. ``time_limit`` (seconds, default none): a budget for
    all the solves together; each IPOPT solve gets what is left (at least 1 s) as its max_cpu_time,
    and no solve starts once it is spent (``result.contact['out_of_time']``).

    ``checkpoint`` (a path, default none): after each relaxed solve the homotopy's state (its
    solution, the epsilon reached, the solves so far) is written there (``save_checkpoint``); if the
    file exists when the solve starts, the homotopy resumes from it instead of from ``guess``, so a
    solve of hours survives a stopped process; it is removed once the exact solve succeeds. The file
    must come from the same problem size, transcription, s and epsilons (ValueError otherwise).

    ``sides_from`` (a Result of ``solve_contact`` on the same problem with another transcription or
    order, e.g. the trapezoidal VI, whose contact model is well posed and whose solves are cheap):
    before any relaxed solve, the exact solve on the sides of the complementarity pairs that its
    solution shows at this transcription's points (``branches_of`` on its interpolation), started
    from that interpolation; if it fails (a transition between contact phases the two discretisations
    place differently), the homotopy runs from the interpolation over the epsilons <= ``finish_below``
    (from its start, close to the answer, the large relaxations are not needed). Measured on the
    quick LittleDog problem with s = 2 (hovi.robot_examples): the exact solve on the sides of the
    s = 1 solution took 477 IPOPT iterations (after 392 for s = 1), 351 s in all on a shared
    machine, and ended feasible; the homotopy from the example's guess had not finished its first
    relaxed solve after 400 iterations (before the example's feet_above_ground rows).

    s = 1 (default) is the contact model that is inelastic and well posed (see hovi.contact); s >= 2
    lets an impact inside a stage rebound.

    Returns the exact Result (or the last relaxed one) with ``result.contact`` = {'penetration',
    'cone', 'complementarity' (largest product), 'epsilon' (0 after the exact solve), 'finished',
    'solves' ([(epsilon, iterations, success), ...], epsilon 0 for an exact attempt),
    'iterations' (total), 'wall_seconds' (in IPOPT, total), 'out_of_time', 'sides_from' (the
    transcription whose sides were tried, or None)}. The exact result's sliding slacks are the
    least their rows allow (``least_slack``)."""
    if problem.contacts is None:
        raise ValueError("the problem has no contacts: call problem.add_contacts(contacts)")
    eps = [float(e) for e in epsilons]
    if not eps or any(not np.isfinite(e) or e <= 0 for e in eps) or any(b >= a for a, b in zip(eps, eps[1:])):
        raise ValueError(f"epsilons must be positive, finite and decreasing, got {epsilons}")
    if int(s) != s or s < 1:
        raise ValueError(f"s must be a positive integer, got {s}")
    if not (np.isfinite(finish_below) and finish_below >= 0):
        raise ValueError(f"finish_below must be finite and >= 0, got {finish_below}")
    if time_limit is not None and not (np.isfinite(time_limit) and time_limit > 0):
        raise ValueError(f"time_limit must be a positive number of seconds, got {time_limit}")
    if sides_from is not None and not (isinstance(sides_from, Result)
                                       and hasattr(sides_from.transcription, "interpolants")):
        raise TypeError(f"sides_from must be a Result of solve_contact, got {type(sides_from).__name__}")
    deadline = None if time_limit is None else time.perf_counter() + time_limit
    saved = problem.complementarity_epsilon, problem.complementarity_branches
    solves, wall, resumed = [], 0.0, None
    if checkpoint is not None and not os.path.isdir(os.path.dirname(os.path.abspath(checkpoint))):
        raise ValueError(f"the checkpoint's folder does not exist: {os.fspath(checkpoint)}")
    if checkpoint is not None and os.path.exists(checkpoint):
        resumed, solves, wall = load_checkpoint(checkpoint, problem, transcription, s, eps)

    def out_of_time() -> bool:
        return deadline is not None and time.perf_counter() >= deadline

    def run(start, epsilon, branches=None):
        nonlocal wall
        problem.complementarity_epsilon, problem.complementarity_branches = epsilon, branches
        opts = dict(options or {})
        if epsilon > 0:
            opts.setdefault("tol", RELAXED_TOL)
        if deadline is not None:
            opts["max_cpu_time"] = max(1.0, deadline - time.perf_counter())
        r = solve(problem, transcription, s=s, guess=start, options=opts, verbose=verbose, hessian=hessian)
        solves.append((epsilon, r.iterations, r.success))
        wall += r.wall_seconds
        if epsilon == 0 and r.success:
            x = least_slack(ContactRows(problem.contacts, r.transcription, 0.0), r.x)
            r = dataclasses.replace(r, x=x, trajectory=r.transcription.trajectory(x),
                                    constraint_violation=NLP(r.transcription).violation(x))
        return r

    try:
        relaxed, exact, last, schedule = guess, None, eps[0], eps
        if sides_from is not None and resumed is None:
            tr = transcribe(problem, transcription, s)
            rows = ContactRows(problem.contacts, tr, 0.0)
            x0 = canonical(rows, initial_guess(tr, sides_from.as_guess()))
            relaxed = _at(tr, x0, f"the interpolation of {sides_from.transcription.name}'s solution", True)
            attempt = run(relaxed, 0.0, branches_of(rows, x0))
            exact = attempt if attempt.success else None
            schedule = [e for e in eps if e <= finish_below] or eps   # near the answer: the small relaxations only
        first = 0 if resumed is None else schedule.index(resumed[0])
        for epsilon in schedule[first:] if exact is None else ():
            if resumed is not None and epsilon == resumed[0]:
                relaxed, last = resumed[1], epsilon
            else:
                if out_of_time():
                    break
                relaxed, last = run(relaxed, epsilon), epsilon
                if checkpoint is not None:
                    save_checkpoint(checkpoint, relaxed, transcription, s, eps, epsilon, solves, wall)
            if relaxed.success and epsilon <= finish_below and not out_of_time():
                rows = ContactRows(problem.contacts, relaxed.transcription, epsilon)
                start = dataclasses.replace(relaxed, x=canonical(rows, relaxed.x))
                attempt = run(start, 0.0, branches_of(rows, start.x))
                if attempt.success:
                    exact = attempt
                    break
    finally:
        problem.complementarity_epsilon, problem.complementarity_branches = saved
    if exact is not None and checkpoint is not None and os.path.exists(checkpoint):
        os.remove(checkpoint)                      # finished: a new solve starts afresh
    result = exact or relaxed
    rows = ContactRows(problem.contacts, result.transcription, 0.0)
    result.contact = {**rows.violations(result.x), "epsilon": 0.0 if exact else last, "finished": exact is not None,
                      "solves": solves, "iterations": sum(it for _, it, _ in solves), "wall_seconds": wall,
                      "out_of_time": exact is None and out_of_time(),
                      "sides_from": None if sides_from is None else sides_from.transcription.name}
    return result


def save_checkpoint(path, relaxed: Result, transcription: str, s: int, epsilons: Sequence[float], epsilon: float,
                    solves: list, wall: float) -> None:
    """Write the homotopy's state after the relaxed solve at ``epsilon`` to ``path`` (npz, replaced
    atomically): that solve's x and success, the solves so far and their time in IPOPT, and what
    identifies the problem (variables, transcription, s, epsilons)."""
    tmp = f"{os.fspath(path)}.tmp.npz"
    np.savez(tmp, x=relaxed.x, success=relaxed.success, status=relaxed.status, epsilon=epsilon,
             epsilons=np.asarray(epsilons, float), transcription=transcription, s=s,
             solves=np.asarray(solves, float).reshape(-1, 3), wall=wall)
    os.replace(tmp, path)


def load_checkpoint(path, problem: Problem, transcription: str, s: int, epsilons: Sequence[float]):
    """((epsilon, relaxed Result), solves, wall) from a ``save_checkpoint`` file, after checking that
    it belongs to this problem, transcription, s and epsilons."""
    keys = {"x", "success", "status", "epsilon", "epsilons", "transcription", "s", "solves", "wall"}
    try:
        with np.load(path) as f:
            data = {k: f[k] for k in f.files}
    except (OSError, ValueError, TypeError, zipfile.BadZipFile) as e:
        raise ValueError(f"{os.fspath(path)} is not a solve_contact checkpoint (npz): {e}") from e
    if not keys <= set(data):
        raise ValueError(f"{os.fspath(path)} is not a solve_contact checkpoint: it lacks "
                         f"{sorted(keys - set(data))}")
    tr = transcribe(problem, transcription, s)
    found = (str(data["transcription"]), int(data["s"]), len(data["x"]), tuple(data["epsilons"]))
    wanted = (transcription, s, tr.core.n_variables, tuple(float(e) for e in epsilons))
    if found != wanted:
        raise ValueError(f"checkpoint {os.fspath(path)} belongs to another solve: (transcription, s, variables, "
                         f"epsilons) = {found}, this solve has {wanted}")
    relaxed = _at(tr, np.array(data["x"], float), f"{data['status']} (from checkpoint)", bool(data["success"]))
    solves = [(float(e), int(it), bool(ok)) for e, it, ok in data["solves"]]
    return (float(data["epsilon"]), relaxed), solves, float(data["wall"])


def _at(tr, x: np.ndarray, status: str, success: bool) -> Result:
    """A Result holding the point x of transcription tr (a start for ``solve``; no solve behind it)."""
    return Result(status=status, success=success, cost=float("nan"), constraint_violation=float("nan"), iterations=0,
                  wall_seconds=0.0, trajectory=tr.trajectory(x), x=x, transcription=tr)
