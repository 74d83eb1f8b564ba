"""Atlas picks a ball with its left hand while balancing on its right foot (the paper's Sec. 6):
the right foot flat on the ground for the whole motion (hovi.contact.FlatFoot: its contact wrench
inside the cone of its sole, with the centre of pressure in the sole), the left foot clear of the
ground, the left hand at the ball at the final time, from a single-support stance at rest."""
from __future__ import annotations

from typing import Dict

import numpy as np
from scipy.optimize import least_squares

from ... import _core, trajopt
from ...contact import DEFAULT_FRICTION, Contacts, FlatFoot, Terrain, wrench_cone
from ..robots import Robot, atlas
from ...trajopt import Problem, Result
from .contact_figures import BETWEEN_TOLERANCE, between_knot_penetration
from .example import Example, Scenery
from ...control.statics import static_controls

LIFT = 0.05       # the left sole's height above the ground at the start (m)
BALL = (0.30, 0.05, -0.20)  # the ball relative to the left hand at the start (m)
BALL_RADIUS = 0.06


def sole(robot: Robot, side: str):
    """(centre (3,), half-length X, half-width Y) of a sole from its four corner contacts (foot frame)."""
    corners = np.array([c.point for c in robot.contacts if c.body == f"{side}_foot"])
    lo, hi = corners.min(0), corners.max(0)
    return (lo + hi) / 2, (hi[0] - lo[0]) / 2, (hi[1] - lo[1]) / 2


def centre_of_mass(robot: Robot, q: np.ndarray) -> np.ndarray:
    """The whole robot's centre of mass (3,) at configuration q (n,)."""
    m = robot.model
    return m.masses @ m.body_poses(q)[:, :3, 3] / m.total_mass


def body_point(robot: Robot, q: np.ndarray, body: str, point: np.ndarray):
    pose = robot.model.joint_placements(q)[robot.model.body_index(body)]
    return pose[:3, :3] @ point + pose[:3, 3], pose[:3, :3]


def single_support(robot: Robot, lift: float = LIFT) -> np.ndarray:
    """The stance q0 moved (pelvis, leg joints) so that the right sole stays where it is, flat, the
    centre of mass is over its centre and the left sole is ``lift`` above the ground, level."""
    q0 = robot.q0
    right, left = sole(robot, "r")[0], sole(robot, "l")[0]
    where0, _ = body_point(robot, q0, "r_foot", right)
    free = [robot.model.joint_index(j) for j in
            ("pelvis_base_x", "pelvis_base_y", "pelvis_base_z", "pelvis_base_rx", *(f"{s}_leg_{j}" for s in "rl"
             for j in ("hpx", "akx", "hpy", "kny", "aky")))]

    def residual(z, regularise):
        q = q0.copy()
        q[free] = z
        r, R = body_point(robot, q, "r_foot", right)
        lp, Rl = body_point(robot, q, "l_foot", left)
        com = centre_of_mass(robot, q)
        return np.concatenate([r - where0, R[:2, 2], [R[0, 1]], com[:2] - r[:2], [lp[2] - lift], Rl[:2, 2],
                               regularise * (z - q0[free])])

    z = least_squares(residual, q0[free], args=(1e-2,), xtol=1e-15, ftol=1e-15, gtol=1e-15).x
    z = least_squares(residual, z, args=(0.0,), xtol=1e-15, ftol=1e-15, gtol=1e-15).x  # the conditions exactly
    q = q0.copy()
    q[free] = z
    return q


def build(quick: bool = False) -> Example:
    """The example over 1.3 s (N = 26) or, ``quick``, over 0.3 s (N = 6) reaching a nearer ball."""
    robot = atlas()
    N, T, reach = (6, 0.3, 0.25) if quick else (26, 1.3, 1.0)
    qs = single_support(robot)
    centre, X, Y = sole(robot, "r")
    left_centre = sole(robot, "l")[0]
    foot = FlatFoot(robot.model, "r_foot", centre, X, Y, mu=DEFAULT_FRICTION, q0=qs)
    model = foot.with_inputs
    hand0, _ = body_point(robot, qs, "l_hand", np.zeros(3))
    ball = hand0 + reach * np.asarray(BALL)
    prob = Problem(model, N=N, T=T)
    prob.initial_state(qs)
    m = len(robot.actuated)
    effort = np.zeros(model.n_controls)
    effort[:m] = 1e-4
    effort[m:] = 1e-3  # the wrench is fixed by the stance except at the last point, where it sets only p^N
    prob.add_cost(trajopt.ControlEffort(weight=effort))
    prob.add_cost(trajopt.StateTracking(qs, weight=np.r_[np.zeros(6), np.ones(model.n - 6)], velocity_weight=0.1))
    prob.add_cost(trajopt.TerminalCost(qs, weight=0.0, velocity_weight=10.0))  # still balanced at the end
    prob.add_constraint(foot.stance()).add_constraint(foot.cone())
    prob.add_constraint(trajopt.BodyPoint("l_hand", target=ball, at=T))
    prob.add_constraint(trajopt.BodyPoint("l_foot", left_centre, lower=0.02, axes="z", window=(0.0, T)))
    u0 = static_controls(model, qs)

    guess = (lambda t: np.tile(qs, (len(t), 1)), lambda t: np.zeros((len(t), model.n)),
             lambda t: np.tile(u0, (len(t), 1)))
    options = {"constr_viol_tol": 1e-8}  # the dynamics' round-off floor of a 174 kg robot is ~5e-10

    G = wrench_cone(X, Y, DEFAULT_FRICTION)
    corners = ([robot.model.body_index(c.body) for c in robot.contacts], np.array([c.point for c in robot.contacts]))

    def heights(q: np.ndarray) -> np.ndarray:
        """The sole corners' heights (K, 8) above the ground (z = 0, the right sole's plane)."""
        return _core.body_point_kinematics(robot.model, np.atleast_2d(q), *corners)[0][..., 2]

    def checks(result: Result) -> Dict[str, float]:
        tr = result.trajectory
        u = tr["u"][:-1]                    # the last point's wrench acts only on the final momentum
        w = foot.wrench(u)
        q = tr["q"]
        held = np.array([body_point(robot, qk, "r_foot", centre)[0] for qk in q])
        hand = body_point(robot, q[-1], "l_hand", np.zeros(3))[0]
        cop = foot.centre_of_pressure(u)
        return {"constraint_violation": float(result.constraint_violation),
                "ball_distance": float(np.linalg.norm(hand - ball)),
                "stance_foot_motion": float(np.abs(held - held[0]).max()),
                "wrench_cone_margin": float((w @ G.T).min() / max(1.0, np.abs(w).max())),
                "cop_margin": float(min(X - np.abs(cop[:, 0]).max(), Y - np.abs(cop[:, 1]).max())),
                "normal_force_min": float(w[:, 2].min()),
                **between_knot_penetration(result, heights, [c.name for c in robot.contacts])}

    bounds = {"constraint_violation": ("<=", 1e-6), "ball_distance": ("<=", 0.01), "stance_foot_motion": ("<=", 1e-6),
              "wrench_cone_margin": (">=", -1e-8), "cop_margin": (">=", 0.0), "normal_force_min": (">=", 0.0),
              "between_knot_penetration": ("<=", BETWEEN_TOLERANCE)}

    scenery = Scenery().add("sphere", (BALL_RADIUS,), ball, (0.9, 0.3, 0.1, 1.0))
    scenery.add("box", (2.0, 2.0, 0.02), (0.0, 0.0, -0.01), (0.55, 0.6, 0.55, 1.0))
    labels = ["f_x", "f_y", "f_z"]
    return Example("atlas", "picks a ball with its left hand while balancing on its right foot", robot, prob, guess,
                   options, checks, bounds, lambda u: foot.wrench(u)[:, :3], labels, scenery,
                   from_trapezoidal=True, simulation=Contacts(robot.model, robot.contact_points, Terrain(), mu=DEFAULT_FRICTION))
    # the simulation's contacts are both soles' corners: the stance foot as the simulator takes a
    # FlatFoot (flat_feet_contacts), the other able to land
