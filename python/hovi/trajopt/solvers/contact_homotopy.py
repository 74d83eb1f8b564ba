"""Contact-implicit trajectory optimisation without a mode schedule, as a solver strategy over
IPOPT: a relaxation homotopy, then an exact solve on the sides of the complementarity pairs it
found.

1. The complementarity products of a Problem with contacts (hovi.contact.Contacts) are bounded by
   epsilon (Scholtes' relaxation: ``ComplementarityRelaxation(epsilon)`` given to the NLP), and
   epsilon is driven down over IPOPT solves, each started from the last solution.
2. After each relaxed solve with epsilon <= FINISH_BELOW, ``hovi.trajopt.contact_sides.sides_of`` reads which
   side of every pair is zero: each input is converted, through the contact point's mobility
   J M^-1 J^T, to what it does to its partner over the interval (a normal force to a
   displacement, a friction force to a velocity change), and the smaller side is zero; where the
   contact sticks, the friction inputs of opposite directions are first reduced by their common
   part (``hovi.trajopt.contact_sides.canonical``). With those sides fixed (``ComplementarityRelaxation(0,
   sides)``: an input fixed at zero, or the gap, cone or sliding row as an equality) the
   problem is a smooth NLP; its solution satisfies complementarity exactly and the free phases
   carry exactly zero contact force. If it fails, the homotopy goes on.

The variants tried and dropped (pairings, schedules, IPOPT settings) and their figures are in
bench/README.md, "Design measurements".
"""
from __future__ import annotations

import dataclasses
import os
import time
import zipfile
from typing import Any, Sequence

import numpy as np

from ..complementarity import ComplementarityRelaxation, ContactRows
from ..contact_sides import sides_of_solution, sides_of, canonical, least_slack
from ..nlp import NLP
from ..problem import Problem
from ..result import Result
from ..transcription import Guess, Transcription, TranscriptionMethod
from ..transcriptions import DEFAULT_TRANSCRIPTION, transcription_method
from .base import Solver
from .ipopt import Ipopt

DEFAULT_EPSILONS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6)
FINISH_BELOW = 1e-3  # the exact solve is tried from relaxed solutions with epsilon <= this
# IPOPT's tol for the relaxed solves: only a path to the exact one (some stall near hovi's default 1e-8)
RELAXED_TOL = 1e-6
# IPOPT's options (under the caller's) for the solves that start on another solution's sides
# (sides_from): a small barrier from the start, the start kept near the bounds it touches
# (bench/README.md, "Design measurements", contact_homotopy.py)
NEAR_START_OPTIONS = {"mu_strategy": "monotone", "mu_init": 1e-6, "bound_push": 1e-8, "bound_frac": 1e-8}


class ContactHomotopy(Solver):
    """The relaxation homotopy over ``epsilons`` (positive, decreasing) with ``ipopt`` (an ``Ipopt``;
    its options go to every solve, the relaxed ones default to tol = RELAXED_TOL), and after each
    relaxed solve with epsilon <= ``finish_below`` the exact solve on the sides of the
    complementarity pairs it shows, until one succeeds (finish_below = 0: relaxed solves only).
    ``time_limit`` (seconds, default none): a budget for all the solves together; each IPOPT solve
    gets what is left (at least 1 s) as its max_cpu_time, and no solve starts once it is spent.
    ``solve`` runs it on a problem (see ``solve_contact`` for the arguments and the result)."""

    def __init__(self, ipopt: Ipopt | None = None, epsilons: Sequence[float] = DEFAULT_EPSILONS, *,
                 finish_below: float = FINISH_BELOW, time_limit: float | None = None):
        eps = [float(e) for e in epsilons]
        if not eps or any(not np.isfinite(e) or e <= 0 for e in eps) or any(b >= a for a, b in zip(eps, eps[1:])):
            raise ValueError(f"epsilons must be positive, finite and decreasing, got {epsilons}")
        if not (np.isfinite(finish_below) and finish_below >= 0):
            raise ValueError(f"finish_below must be finite and >= 0, got {finish_below}")
        if time_limit is not None and not (np.isfinite(time_limit) and time_limit > 0):
            raise ValueError(f"time_limit must be a positive number of seconds, got {time_limit}")
        self.ipopt = Ipopt(verbose=False) if ipopt is None else ipopt
        self.epsilons, self.finish_below, self.time_limit = eps, float(finish_below), time_limit

    def solve(self, problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION,
              guess: Guess = "rollout", *, checkpoint: str | os.PathLike | None = None,
              sides_from: Result | None = None) -> Result:
        """The homotopy on ``problem`` (with ``add_contacts``) transcribed by ``transcription``, from
        ``guess``; ``checkpoint`` and ``sides_from`` as in ``solve_contact``."""
        if not isinstance(problem, Problem):
            raise TypeError(f"problem must be a hovi.trajopt.Problem, got {type(problem).__name__}")
        if problem.contacts is None:
            raise ValueError("the problem has no contacts: call problem.add_contacts(contacts)")
        if not isinstance(transcription, TranscriptionMethod):
            raise TypeError(f"transcription must be a hovi.trajopt.VI or HermiteSimpson, got "
                            f"{type(transcription).__name__}")
        if sides_from is not None and not (isinstance(sides_from, Result)
                                           and hasattr(sides_from.transcription, "interpolants")):
            raise TypeError(f"sides_from must be a Result of solve_contact, got {type(sides_from).__name__}")
        if sides_from is not None:   # its pairs are mapped onto these by time, its inputs by index
            other, ct = sides_from.transcription.problem, problem.contacts
            if (other.contacts is None or not np.isclose(other.T, problem.T)
                    or (other.model.n, other.model.n_controls) != (problem.model.n, problem.model.n_controls)
                    or (other.contacts.n_contacts, other.contacts.d) != (ct.n_contacts, ct.d)):
                raise ValueError("sides_from must solve a problem with the same horizon T, configuration, "
                                 "controls and contacts as this one")
        eps, finish_below = self.epsilons, self.finish_below
        deadline = None if self.time_limit is None else time.perf_counter() + self.time_limit
        solves, wall, resumed = [], 0.0, None
        if checkpoint is not None and not os.path.isdir(os.path.dirname(os.path.abspath(checkpoint))):
            raise ValueError(f"the checkpoint's folder does not exist: {os.fspath(checkpoint)}")
        tr = transcription.transcribe(problem)
        if checkpoint is not None and os.path.exists(checkpoint):
            resumed, solves, wall = load_checkpoint(checkpoint, tr, eps)

        def out_of_time() -> bool:
            return deadline is not None and time.perf_counter() >= deadline

        near = {} if sides_from is None else {k: v for k, v in NEAR_START_OPTIONS.items()
                                              if k not in self.ipopt.options}

        def run(start, epsilon, sides=None):
            nonlocal wall
            opts = dict(near)
            if epsilon > 0:
                opts["tol"] = self.ipopt.options.get("tol", RELAXED_TOL)
            if deadline is not None:
                opts["max_cpu_time"] = max(1.0, deadline - time.perf_counter())
            nlp = NLP(problem, tr, relaxation=ComplementarityRelaxation(epsilon, sides))
            r = self.ipopt.with_options(opts).solve_nlp(nlp, start)
            solves.append((epsilon, r.iterations, r.success))
            wall += r.wall_seconds
            if epsilon == 0 and r.success:
                x = least_slack(ContactRows(problem.contacts, tr, 0.0), r.x)
                r = dataclasses.replace(r, x=x, trajectory=tr.trajectory(x), constraint_violation=nlp.violation(x))
            return r

        relaxed, exact, last, schedule = guess, None, eps[0], eps
        if sides_from is not None and resumed is None:
            rows = ContactRows(problem.contacts, tr, 0.0)
            x0 = canonical(rows, tr.initial_guess(sides_from.as_guess()))
            relaxed = tr.at(x0, f"the interpolation of {sides_from.transcription.name}'s solution", True)
            attempt = run(relaxed, 0.0, sides_of_solution(rows, sides_from))
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
                    save_checkpoint(checkpoint, relaxed, transcription, eps, epsilon, solves, wall)
            if relaxed.success and epsilon <= finish_below and not out_of_time():
                rows = ContactRows(problem.contacts, tr, epsilon)
                start = dataclasses.replace(relaxed, x=canonical(rows, relaxed.x))
                attempt = run(start, 0.0, sides_of(rows, start.x))
                if attempt.success:
                    exact = attempt
                    break
        if exact is not None and checkpoint is not None and os.path.exists(checkpoint):
            os.remove(checkpoint)                      # finished: a new solve starts afresh
        result = exact or relaxed
        stopped = exact is None and out_of_time() and (finish_below > 0 or last != schedule[-1])
        if stopped:   # the budget ran out before the exact solve (or, finish_below = 0, the last relaxation)
            before = "the exact solve" if finish_below > 0 else f"the last relaxation (epsilon = {eps[-1]:g})"
            result = dataclasses.replace(
                result, success=False,
                status=f"stopped by time_limit = {self.time_limit:g} s before {before}; the last relaxed "
                       f"solve (epsilon = {last:g}) ended: {result.status}")
        elif exact is None and finish_below > 0:  # every exact attempt failed: only a relaxed answer
            result = dataclasses.replace(
                result, success=False,
                status=f"no exact solve succeeded; the last relaxed solve (epsilon = {last:g}) ended: {result.status}")
        rows = ContactRows(problem.contacts, result.transcription, 0.0)
        result.contact = {**rows.violations(result.x), "epsilon": 0.0 if exact else last,
                          "finished": exact is not None, "solves": solves,
                          "iterations": sum(it for _, it, _ in solves), "wall_seconds": wall,
                          "out_of_time": stopped,
                          "sides_from": None if sides_from is None else sides_from.transcription.name}
        return result


def solve_contact(problem: Problem, transcription: TranscriptionMethod = DEFAULT_TRANSCRIPTION,
                  epsilons: Sequence[float] = DEFAULT_EPSILONS, *, guess: Guess = "rollout",
                  finish_below: float = FINISH_BELOW, options: dict[str, Any] | None = None, verbose: bool = False,
                  hessian: str = "auto", time_limit: float | None = None,
                  checkpoint: str | os.PathLike | None = None, sides_from: Result | None = None,
                  threads: int | None = 1) -> Result:
    """Solve ``problem`` (with ``add_contacts``) with ``transcription`` (as in ``solve``; use
    ``VI(s=1)``, the contact model that is inelastic and well posed (see hovi.contact): with s >= 2
    an impact inside a stage rebounds; ``HermiteSimpson`` puts the same contact conditions on its
    knots and midpoints): ``ContactHomotopy(Ipopt(options, verbose=verbose, hessian=hessian, threads=threads),
    epsilons, finish_below=finish_below, time_limit=time_limit).solve(problem, transcription,
    guess, checkpoint=checkpoint, sides_from=sides_from)``: the relaxation homotopy over
    ``epsilons`` (positive, decreasing), and after each relaxed solve with epsilon <=
    ``finish_below`` the exact solve on the sides of the complementarity pairs it shows, until one
    succeeds (finish_below = 0: relaxed solves only). ``options`` go to every IPOPT solve (the
    relaxed ones default to tol = RELAXED_TOL); ``hessian`` and ``threads`` as in ``solve`` (the
    default 'auto' over 'lbfgs': on the robot examples L-BFGS does not converge; bench/README.md,
    "Design measurements"). ``time_limit``
    (seconds, default none): a budget for all the solves together; each IPOPT solve gets what is
    left (at least 1 s) as its max_cpu_time, and no solve starts once it is spent
    (``result.contact['out_of_time']``).

    ``checkpoint`` (a path, default none): after each relaxed solve the homotopy's state (its
    solution, the epsilon reached, the solves so far) is written there (``save_checkpoint``); if the
    file exists when the solve starts, the homotopy resumes from it instead of from ``guess``, so a
    solve of hours survives a stopped process; it is removed once the exact solve succeeds. The file
    must come from the same problem size, transcription and epsilons (ValueError otherwise).

    ``sides_from`` (a Result of ``solve_contact`` on the same problem with another transcription or
    order, e.g. the trapezoidal VI, whose contact model is well posed and whose solves are cheap):
    before any relaxed solve, the exact solve on the sides of the complementarity pairs that its
    solution shows (each pair here takes the sides of its pair whose interval holds the point:
    ``sides_of_solution``), started from its interpolation; if it fails (a transition between contact phases the two discretisations
    place differently), the homotopy runs from the interpolation over the epsilons <= ``finish_below``
    (from its start, close to the answer, the large relaxations are not needed). These solves run
    with NEAR_START_OPTIONS under ``options`` (a monotone barrier from mu = 1e-6: IPOPT's defaults
    would push the start off the sides it is on). Each pair takes the sides of the pair holding its
    point, not the sides read at the interpolation, which would fix at zero forces the interpolation
    carries. On the robot examples this finishes where the homotopy from the example's guess is far
    slower (iterations of both ways: bench/README.md, "Design measurements").

    Returns the exact Result, or the last relaxed one with ``success=False`` and a status that says
    why (``time_limit`` stopped the homotopy, or no exact solve succeeded), with
    ``result.contact`` = {'penetration',
    'cone', 'complementarity' (largest product), 'epsilon' (0 after the exact solve), 'finished',
    'solves' ([(epsilon, iterations, success), ...], epsilon 0 for an exact attempt),
    'iterations' (total), 'wall_seconds' (in IPOPT, total), 'out_of_time', 'sides_from' (the
    transcription whose sides were tried, or None)}. The exact result's sliding slacks are the
    least their rows allow (``hovi.trajopt.contact_sides.least_slack``).
    """
    if not isinstance(problem, Problem):
        raise TypeError(f"problem must be a hovi.trajopt.Problem, got {type(problem).__name__}")
    if problem.contacts is None:
        raise ValueError("the problem has no contacts: call problem.add_contacts(contacts)")
    method = transcription_method(transcription)
    homotopy = ContactHomotopy(Ipopt(options, verbose=verbose, hessian=hessian, threads=threads), epsilons,
                               finish_below=finish_below, time_limit=time_limit)
    return homotopy.solve(problem, method, guess, checkpoint=checkpoint, sides_from=sides_from)


def save_checkpoint(path, relaxed: Result, transcription: TranscriptionMethod, epsilons: Sequence[float],
                    epsilon: float, solves: list, wall: float) -> None:
    """Write the homotopy's state after the relaxed solve at ``epsilon`` to ``path`` (npz, replaced
    atomically): that solve's x and success, the solves so far and their time in IPOPT, and what
    identifies the problem (variables, transcription, epsilons)."""
    tmp = f"{os.fspath(path)}.tmp.npz"
    np.savez(tmp, x=relaxed.x, success=relaxed.success, status=relaxed.status, epsilon=epsilon,
             epsilons=np.asarray(epsilons, float), transcription=repr(transcription),
             solves=np.asarray(solves, float).reshape(-1, 3), wall=wall)
    os.replace(tmp, path)


def load_checkpoint(path, tr: Transcription, epsilons: Sequence[float]):
    """((epsilon, relaxed Result), solves, wall) from a ``save_checkpoint`` file, after checking that
    it belongs to the transcribed problem ``tr`` (its method and size) and these epsilons."""
    keys = {"x", "success", "status", "epsilon", "epsilons", "transcription", "solves", "wall"}
    try:
        with np.load(path) as f:
            data = {k: f[k] for k in f.files}
    except (OSError, ValueError, TypeError, zipfile.BadZipFile) as e:
        raise ValueError(f"{os.fspath(path)} is not a solve_contact checkpoint (npz): {e}") from e
    if not keys <= set(data):
        raise ValueError(f"{os.fspath(path)} is not a solve_contact checkpoint: it lacks "
                         f"{sorted(keys - set(data))}")
    found = (str(data["transcription"]), len(data["x"]), tuple(data["epsilons"]))
    wanted = (repr(tr.method), tr.core.n_variables, tuple(float(e) for e in epsilons))
    if found != wanted:
        raise ValueError(f"checkpoint {os.fspath(path)} belongs to another solve: (transcription, variables, "
                         f"epsilons) = {found}, this solve has {wanted}")
    relaxed = tr.at(np.array(data["x"], float), f"{data['status']} (from checkpoint)", bool(data["success"]))
    solves = [(float(e), int(it), bool(ok)) for e, it, ok in data["solves"]]
    return (float(data["epsilon"]), relaxed), solves, float(data["wall"])
