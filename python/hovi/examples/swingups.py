"""The built-in trajectory-optimisation examples (``hovi optimize NAME``, the tests and bench/trajopt.py):
swing-ups of a pendulum, an acrobot and a cart-pole with torque limits and a fixed final time,
and a slider-crank driven to a target crank angle (a closed chain: constraint multipliers)."""
from __future__ import annotations

import numpy as np

from . import OPTIMIZATION, entries, models
from .._core import Model
from ..trajopt import ControlEffort, Problem


def pendulum_swingup(N: int = 40, T: float = 2.0, controls: str = "per_point") -> Problem:
    """A 1-link pendulum (0.5 m, 1 kg) from hanging at rest to upright at rest, |u| <= 4 N m."""
    model = models.pendulum(1)
    model.add_actuator(0)
    prob = Problem(model, N, T, controls=controls, u_bounds=(-4.0, 4.0))
    prob.initial_state([0.0]).final_state([np.pi], qdot=[0.0])
    return prob.add_cost(ControlEffort())


def acrobot_swingup(N: int = 60, T: float = 4.0, controls: str = "per_point") -> Problem:
    """The acrobot (two 1 m, 1 kg links, elbow torque only, |u| <= 15 N m) from hanging to upright."""
    model = models.acrobot()
    prob = Problem(model, N, T, controls=controls, u_bounds=(-15.0, 15.0))
    prob.initial_state([0.0, 0.0]).final_state([np.pi, 0.0], qdot=[0.0, 0.0])
    return prob.add_cost(ControlEffort())


def cartpole_swingup(N: int = 50, T: float = 2.5, controls: str = "per_point") -> Problem:
    """The cart-pole (1 kg cart, 0.3 kg 0.5 m pole, |force| <= 20 N, cart within ±1 m) from hanging
    to upright, cart back at the origin."""
    model = models.cartpole()
    prob = Problem(model, N, T, controls=controls, u_bounds=(-20.0, 20.0), q_bounds=([-1.0, -np.inf], [1.0, np.inf]))
    prob.initial_state([0.0, 0.0]).final_state([0.0, np.pi], qdot=[0.0, 0.0])
    return prob.add_cost(ControlEffort())


def close_mechanism(model: Model, q0, driver: int = 0) -> np.ndarray:
    """The configuration of a closed mechanism with joint ``driver`` held at q0[driver]: Newton on
    the constraints in the other joints, from q0."""
    q = np.array(q0, dtype=float)
    others = [j for j in range(model.n) if j != driver]
    for _ in range(50):
        h = model.constraint_values(q)
        if np.abs(h).max() < 1e-14:
            return q
        q[others] -= np.linalg.lstsq(model.constraint_jacobian(q)[:, others], h, rcond=None)[0]
    raise ValueError(f"the mechanism cannot close with joint {driver} at {q0[driver]}")


def slider_crank_to_target(N: int = 30, T: float = 1.0, controls: str = "per_point") -> Problem:
    """A slider-crank (models.slider_crank) driven at the crank (|u| <= 10 N m) from rest at crank
    angle 0.6 to rest at 2.0: a closed chain, with constraint multipliers as variables."""
    model = models.slider_crank()
    model.add_actuator(0)
    prob = Problem(model, N, T, controls=controls, u_bounds=(-10.0, 10.0))
    prob.initial_state(close_mechanism(model, [0.6, -1.0])).final_state(close_mechanism(model, [2.0, -1.0]),
                                                                        qdot=np.zeros(2))
    return prob.add_cost(ControlEffort())


EXAMPLES = {entry.name: globals()[entry.target.partition(":")[2]] for entry in entries(OPTIMIZATION).values()}
"""name -> the function that builds the problem, for the registry's optimisation examples."""

__all__ = ["pendulum_swingup", "acrobot_swingup", "cartpole_swingup", "slider_crank_to_target", "close_mechanism",
           "EXAMPLES"]
