"""What a robot example is: a trajectory-optimisation problem on one of the paper's robots, where
its solver starts, and the figures that say whether its answer is feasible (``hovi example NAME``)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from ...contact import Contacts
from ..robots import Robot
from ...trajopt import Guess, Problem, Result


def samples_between(dt: float, spacing: float) -> int:
    """How many samples between two configuration points dt apart hold a path constraint at least
    every ``spacing`` seconds (``between=`` of a ``trajopt.PathConstraint``)."""
    return int(np.ceil(dt / spacing - 1e-9)) - 1


@dataclass
class Scenery:
    """World shapes shown with the robot (terrain, obstacles, a ball): (shape, size (as Model.add_visual takes it),
    centre (3,), rgba (4,))."""
    shapes: List[Tuple[str, np.ndarray, np.ndarray, Tuple[float, float, float, float]]] = field(default_factory=list)

    def add(self, shape: str, size, centre, rgba=(0.6, 0.6, 0.6, 1.0)) -> Scenery:
        self.shapes.append((shape, np.asarray(size, float), np.asarray(centre, float), tuple(rgba)))
        return self


@dataclass
class Example:
    """``problem`` on ``robot``, solved from ``guess`` with IPOPT ``options`` (``report.solve``);
    ``checks(result)`` the example's feasibility figures (each a float, with the bound it must meet
    in ``bounds``);
    ``contact_forces(u (P, m))`` the contact forces (P, k) named by ``force_labels``; ``epsilons`` the
    relaxation homotopy of a contact-implicit problem (``trajopt.solve_contact``; None: its default);
    ``from_trapezoidal``: VI orders above 2 and Hermite-Simpson start from the trapezoidal VI's
    solution (``report.solve``: on its contact sides, or without contacts from its interpolants),
    else from ``guess`` (through contact, the homotopy runs from it);
    ``warm_up``: an easier version of the example (the same variables and contacts, looser
    constraints), solved first with the trapezoidal VI: the trapezoidal solve starts on its
    solution's contact sides; ``replay_options``: IPOPT options over ``options`` for a VI solve
    whose answer is reported, hence replayed (``report.replay_figures``), not for the solves that
    only start another (the warm-up, the trapezoidal VI before a higher order or Hermite-Simpson)."""
    name: str
    description: str
    robot: Robot
    problem: Problem
    guess: Guess
    options: Dict[str, Any]
    checks: Callable[[Result], Dict[str, float]]
    bounds: Dict[str, Tuple[str, float]]               # figure -> ('<=' or '>=', bound)
    contact_forces: Callable[[np.ndarray], np.ndarray]
    force_labels: List[str]
    scenery: Scenery = field(default_factory=Scenery)
    epsilons: Optional[Tuple[float, ...]] = None
    from_trapezoidal: bool = False
    simulation: Optional[Contacts] = None  # the contacts (on robot.model) the contact simulator executes it with
    warm_up: Optional["Example"] = None
    replay_options: Dict[str, Any] = field(default_factory=dict)

    def failures(self, figures: Dict[str, float]) -> List[str]:
        """The figures that miss their bounds, as readable sentences (empty: feasible)."""
        out = []
        for key, (op, bound) in self.bounds.items():
            value = figures[key]
            ok = value <= bound if op == "<=" else value >= bound
            if not ok:
                out.append(f"{key} = {value:.3g}, needs {op} {bound:.3g}")
        return out
