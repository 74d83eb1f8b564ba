"""Contact-implicit trajectory optimisation without a mode schedule: a relaxation homotopy.

The complementarity products of a Problem with contacts (hovi.contact.Contacts) are bounded by
epsilon, and epsilon is driven down over a few IPOPT solves, each warm-started from the last
(Scholtes' relaxation). The result reports the final penetration, friction-cone violation and
largest complementarity product."""
from __future__ import annotations

from typing import Sequence

from .complementarity import ContactRows
from .ipopt import solve
from .problem import Problem
from .result import Result

DEFAULT_EPSILONS = (1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6)


def solve_contact(problem: Problem, epsilons: Sequence[float] = DEFAULT_EPSILONS, *, s: int = 2, guess="linear",
                  options: dict | None = None, verbose: bool = False) -> Result:
    """Solve ``problem`` (with ``add_contacts``) with the VI of order 2s for each relaxation epsilon
    in turn (decreasing); returns the last Result with ``result.contact`` = {'penetration', 'cone',
    'complementarity', 'epsilon', 'iterations' (per solve), 'wall_seconds' (total)}."""
    if problem.contacts is None:
        raise ValueError("the problem has no contacts: call problem.add_contacts(contacts)")
    eps = [float(e) for e in epsilons]
    if not eps or any(e <= 0 for e in eps) or any(b >= a for a, b in zip(eps, eps[1:])):
        raise ValueError(f"epsilons must be positive and decreasing, got {epsilons}")
    result, iterations, wall = None, [], 0.0
    for k, e in enumerate(eps):
        problem.complementarity_epsilon = e
        opts = dict(options or {})
        if result is not None:
            opts.setdefault("mu_init", 1e-5)  # stay near the warm start
        result = solve(problem, "vi", s=s, guess=guess if result is None else result, options=opts, verbose=verbose)
        iterations.append(result.iterations)
        wall += result.wall_seconds
    rows = ContactRows(problem.contacts, result.transcription, eps[-1])
    result.contact = {**rows.violations(result.x), "epsilon": eps[-1], "iterations": iterations, "wall_seconds": wall}
    return result
