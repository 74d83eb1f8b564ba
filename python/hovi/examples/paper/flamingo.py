"""Spring Flamingo jumps over an obstacle 0.16 m high on its way to a goal (the paper's Sec. 6):
contact-implicit trajectory optimisation of the planar 9-DoF biped (``trajopt.solve_contact``: no
contact schedule is given; the toe and heel of each foot touch the ground with Coulomb friction),
from walking at 0.26 m/s to its hip over a goal 0.74 m ahead after 1.1 s.

The obstacle is a path constraint, not terrain: ``hovi.contact.Terrain`` boxes are steps in the
ground height, so the gap row of a contact point jumps by the box's height where the point crosses
its edge, and IPOPT's line search cannot cross that step (bench/README.md, "The paper's robots"
and "Design measurements", flamingo.py). The feet instead stay outside circles that cover the box
in the sagittal plane (``obstacle_circles``, smooth ``trajopt.Clearance`` rows, also every
SAMPLE_SPACING between the configuration points, where fewer samples let a toe cut the box's
corner), and the contacts see flat ground. The check ``obstacle_clearance`` measures the real box against points all along both
soles and shins, at the configuration points and 200 times between each two.

The contact rows hold at the configuration points only. Between them the VI's polynomial (linear in
q for s = 1) sags a leg whose foot stands still at both ends by about L cos(a) da^2 / 8 per link
turning da, so a push-off done inside one stage with both feet flat at both of its points sank a
toe 61 mm into the ground (N = 11) and a toe leaving the ground at a point could dip just after
it. ``feet_above_ground`` keeps the toes and heels at most FEET_BELOW under the ground at the
points and every SAMPLE_SPACING between them; ``contact_figures.between_knot_penetration`` checks
them against BETWEEN_TOLERANCE far more densely.

The guess is a kinematic two-footed jump (``JumpPlan``: hip and ankle paths, legs by inverse
kinematics with the soles level); the posture cost pulls gently towards it, which picks the jump
among the motions that clear the box, and its velocity term keeps the hips and knees near the
plan's speeds (the homotopy then finds the jump reliably: bench/README.md, "The paper's robots")."""
from __future__ import annotations

from typing import Dict, List, Tuple

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from ... import trajopt
from ...contact import DEFAULT_FRICTION, Contacts, Terrain
from ...contact.terrain import Box
from ..robots import Robot, spring_flamingo
from ...trajopt import Problem, Result
from .contact_figures import BETWEEN_TOLERANCE, CONTACT_BOUNDS, contact_figures, path_configurations
from .example import Example, Scenery, samples_between

T = 1.1                           # duration (s), the paper's
START_SPEED = 0.26                # forward (-x) speed of the hip at t = 0 (m/s), the paper's
GOAL = -0.74                      # hip x at t = T (m): 0.67 m/s on average
OBSTACLE = Box(-0.50, -0.26, 0.16)  # 0.24 m long, 0.16 m high (the paper's height), across the path
THIGH = SHIN = 0.42               # hip-knee and knee-ankle lengths (models/spring_flamingo.urdf)
SOLE = 0.035                      # the sole below the ankle axis
HIP_HEIGHT = 0.6                  # the hip stays above this (m)
KNEE_HEIGHT = 0.1                 # the knees stay above this (m)
SAMPLE_SPACING = 0.01             # s: the obstacle circles and feet_above_ground hold this often between the points
FEET_BELOW = BETWEEN_TOLERANCE / 2  # m: feet_above_ground lets a contact point this far below the ground
JOINT_SPEED_WEIGHT = 0.15         # of the hip and knee velocities' distance from the plan's (posture cost)


def leg_angles(hip: np.ndarray, ankle: np.ndarray) -> np.ndarray:
    """(hip, knee, ankle) joint angles (K, 3) that put the ankle axis at ``ankle`` (K, 2) (x, z) below
    a hip at ``hip`` (K, 2), knee flexed (negative), with the base and the sole level. With a = hip
    angle, b = knee angle, the ankle sits at hip - (L1 sin a + L2 sin(a + b), L1 cos a + L2 cos(a + b))."""
    d = np.atleast_2d(np.asarray(ankle, float) - np.asarray(hip, float))
    reach = np.minimum(np.hypot(d[:, 0], d[:, 1]), THIGH + SHIN - 1e-4)
    knee = -np.arccos(np.clip((reach ** 2 - THIGH ** 2 - SHIN ** 2) / (2 * THIGH * SHIN), -1.0, 1.0))
    a = np.arctan2(-d[:, 0], -d[:, 1]) - np.arctan2(SHIN * np.sin(knee), THIGH + SHIN * np.cos(knee))
    return np.column_stack([a, knee, -(a + knee)])


class JumpPlan:
    """The guess: a kinematic two-footed jump over OBSTACLE. The hip (x, z) and both ankles (x, z)
    follow cubic Hermite paths through waypoints (times, positions, velocities): 0.45 s of stance
    (crouch and push), 0.35 s of flight with the feet tucked over the box, 0.3 s of stance after
    landing; the base stays level."""
    HIP = ([0.0, 0.30, 0.45, 0.625, 0.80, 0.95, T],
           [(0.0, 0.86), (-0.12, 0.76), (-0.22, 0.80), (-0.385, 0.95), (-0.55, 0.80), (-0.66, 0.75), (GOAL, 0.80)],
           [(-START_SPEED, 0.0), (-0.7, 0.0), (-0.95, 1.72), (-0.95, 0.0), (-0.95, -1.72), (-0.6, 0.0), (-0.3, 0.0)])
    ANKLE = ([0.0, 0.45, 0.52, 0.62, 0.72, 0.80, T],
             [(0.0, SOLE), (0.0, SOLE), (-0.08, 0.24), (-0.3, 0.27), (-0.56, 0.23), (-0.62, SOLE), (-0.62, SOLE)],
             [(0.0, 0.0), (0.0, 0.0), (-2.5, 1.5), (-2.5, 0.0), (-2.0, -1.5), (0.0, 0.0), (0.0, 0.0)])
    FLIGHT = (0.45, 0.80)

    def __init__(self, robot: Robot) -> None:
        self.model = robot.model
        self.hip = CubicHermiteSpline(*(np.asarray(w, float) for w in self.HIP), axis=0)
        self.ankle = CubicHermiteSpline(*(np.asarray(w, float) for w in self.ANKLE), axis=0)
        self.legs = [[self.model.joint_index(f"{side}_{j}") for j in ("hip", "knee", "ankle")]
                     for side in ("left", "right")]

    def configurations(self, t: np.ndarray) -> np.ndarray:
        """q (K, n) at times t (K,)."""
        t = np.atleast_1d(np.asarray(t, float))
        q = np.zeros((len(t), self.model.n))
        q[:, :2] = self.hip(t)
        angles = leg_angles(q[:, :2], self.ankle(t))
        for joints in self.legs:
            q[:, joints] = angles
        return q

    def velocities(self, t: np.ndarray, h: float = 1e-6) -> np.ndarray:
        """q-dot (K, n) at times t (K,) (central differences of the smooth plan)."""
        t = np.atleast_1d(np.asarray(t, float))
        return (self.configurations(t + h) - self.configurations(t - h)) / (2 * h)


CIRCLE_RADIUS = 0.13  # of the circles that keep the contact points off the obstacle (m)
CIRCLE_INSET = 0.08   # their outer centres inside the box's sides (m)
CORNER_MARGIN = 0.01  # the box's top corners this far inside the outer circles (m)


def obstacle_circles(box: Box) -> List[Tuple[float, float]]:
    """Centres (x, z) of three circles of CIRCLE_RADIUS in the x-z plane that cover the box (from
    the ground to its top): centres CIRCLE_INSET inside each side and at mid-length, all at the
    height that puts the top corners CORNER_MARGIN inside the outer circles (a path sampled every
    SAMPLE_SPACING cuts a circle's chords between its samples). Their overhang beyond the box's
    sides at the ground is sqrt(r^2 - z^2) - CIRCLE_INSET (31 mm for OBSTACLE)."""
    reach = np.sqrt(CIRCLE_RADIUS ** 2 - CIRCLE_INSET ** 2)  # the height a circle covers above or below its centre at the sides
    z = box.top - reach + CORNER_MARGIN
    if box.x1 - box.x0 < 2 * CIRCLE_INSET or z > reach:
        raise ValueError(f"three circles of radius {CIRCLE_RADIUS} do not cover a box {box.x1 - box.x0:.3g} m long "
                         f"and {box.top:.3g} m high")
    return [(box.x0 + CIRCLE_INSET, z), ((box.x0 + box.x1) / 2, z), (box.x1 - CIRCLE_INSET, z)]


def segment_points(model, q: np.ndarray, body: str, a: np.ndarray, b: np.ndarray, k: int = 25) -> np.ndarray:
    """k world points (k, 3) on the segment from a to b (3,) of ``body`` (its joint frame) at q."""
    pose = model.joint_placements(q)[model.body_index(body)]
    local = a + np.linspace(0.0, 1.0, k)[:, None] * (b - a)
    return local @ pose[:3, :3].T + pose[:3, 3]


def box_distance(points: np.ndarray, box: Box) -> np.ndarray:
    """Signed distance (P,) in the x-z plane of points (P, 3) from the box (ground to top): positive
    outside, minus the depth inside."""
    x, z = points[:, 0], points[:, 2]
    dx = np.maximum.reduce([box.x0 - x, np.zeros_like(x), x - box.x1])
    dz = np.maximum(z - box.top, 0.0)
    inside = (dx == 0) & (dz == 0)
    depth = np.minimum.reduce([x - box.x0, box.x1 - x, box.top - z])
    return np.where(inside, -depth, np.hypot(dx, dz))


def leg_points(robot: Robot, q: np.ndarray) -> np.ndarray:
    """World points (K, 3) along both soles (toe to heel) and both shins (knee to ankle) at q."""
    model = robot.model
    toe, heel = (np.array(c.point) for c in robot.contacts[:2])
    ankle = np.array([0.0, 0.0, -SHIN])  # in the lower leg's frame, whose origin is the knee axis
    out = []
    for side in ("left", "right"):
        out.append(segment_points(model, q, f"{side}_foot", toe, heel))
        out.append(segment_points(model, q, f"{side}_lower_leg", np.zeros(3), ankle))
    return np.concatenate(out)


def feet_above_ground(robot: Robot, dt: float) -> List[trajopt.BodyPoint]:
    """Every contact point (toes and heels) no lower than FEET_BELOW under the ground (z = 0) at
    every configuration point and every SAMPLE_SPACING between each two (on the trajectory's
    polynomial, dt apart), LittleDog's mechanism (littledog.feet_above_ground). FEET_BELOW, half the
    feasibility tolerance (contact_figures.BETWEEN_TOLERANCE), rather than 0: a standing leg that
    bends between two points sags a little between them (it could not move at all with 0), and
    between the samples the path may sag a little further."""
    return [trajopt.BodyPoint(body, point, axes="z", lower=[-FEET_BELOW], window=(0.0, T),
                              between=samples_between(dt, SAMPLE_SPACING))
            for body, point in ((c.body, c.point) for c in robot.contacts)]


def build(quick: bool = False) -> Example:
    """The jump with N = 44 stages (dt = 0.025 s) or, ``quick``, with N = 22 (dt = 0.05 s), same task.
    (N = 11, dt = 0.1 s, was the quick grid before ``feet_above_ground``: with it no solve finished
    there in 300-780 s.)"""
    robot = spring_flamingo()
    N = 22 if quick else 44
    plan = JumpPlan(robot)
    contacts = Contacts(robot.model, robot.contact_points, Terrain(), mu=DEFAULT_FRICTION, plane="xz")
    model = contacts.with_inputs
    prob = Problem(model, N=N, T=T)
    prob.initial_state(plan.configurations(0.0)[0], plan.velocities(0.0)[0])
    prob.add_cost(trajopt.ControlEffort(weight=contacts.effort_weights(1e-3)))
    # hip height, base pitch, joints (not the progress x); the light feet on their soft ankle springs would
    # otherwise whirl in flight (over 10 rad/s at N = 11). The hips and knees near the plan's velocities:
    # without it the legs swung up to 40 rad/s and the homotopy with feet_above_ground was a lottery at
    # N = 22 (velocity weight 0: 113 s but 3.75 mm between the knots; 0.08: out of time at 600 s; 0.1:
    # 110 s; 0.115 to 0.2: all feasible in 67-94 s, bench/README.md)
    posture = np.r_[0.0, 1.0, 10.0, np.tile([0.1, 0.1, 1.0], 2)]
    joint_speed = np.tile([JOINT_SPEED_WEIGHT, JOINT_SPEED_WEIGHT, 0.1], 2)
    prob.add_cost(trajopt.StateTracking(plan.configurations, weight=posture, v_ref=plan.velocities,
                                        velocity_weight=np.r_[np.zeros(3), joint_speed]))
    prob.add_cost(trajopt.TerminalCost(plan.configurations(T)[0], weight=10 * posture, velocity_weight=0.1))
    prob.add_constraint(trajopt.BodyPoint("base_link", target=GOAL, axes="x", at=T))
    prob.add_constraint(trajopt.BodyPoint("base_link", lower=HIP_HEIGHT, axes="z", window=(0.0, T)))
    for side in ("left", "right"):
        prob.add_constraint(trajopt.BodyPoint(f"{side}_lower_leg", lower=KNEE_HEIGHT, axes="z", window=(0.0, T)))
    between = samples_between(prob.dt, SAMPLE_SPACING)
    for cx, cz in obstacle_circles(OBSTACLE):
        for body, point in ((c.body, c.point) for c in robot.contacts):
            prob.add_constraint(trajopt.Clearance(body, point, center=(cx, 0.0, cz), radius=CIRCLE_RADIUS, axes="xz",
                                                  window=(0.0, T), between=between))
    for constraint in feet_above_ground(robot, prob.dt):
        prob.add_constraint(constraint)
    prob.add_contacts(contacts)

    weight = robot.model.total_mass * 9.81

    def inputs(t: np.ndarray) -> np.ndarray:
        u = np.zeros((len(t), model.n_controls))
        stance = (t < plan.FLIGHT[0]) | (t > plan.FLIGHT[1])
        for c in range(contacts.n_contacts):
            u[stance, contacts.input_index(c, "normal")] = weight / contacts.n_contacts
        return u

    def checks(result: Result) -> Dict[str, float]:
        q = result.trajectory["q"]
        clearance = min(float(box_distance(leg_points(robot, qk), OBSTACLE).min()) for qk in path_configurations(result))
        feet = np.concatenate([segment_points(robot.model, q[-1], c.body, np.array(c.point), np.array(c.point), 1)
                               for c in robot.contacts])
        return {"constraint_violation": float(result.constraint_violation),
                **contact_figures(contacts, result, [c.name for c in robot.contacts]),
                "obstacle_clearance": clearance, "feet_beyond_obstacle": float(OBSTACLE.x0 - feet[:, 0].max()),
                "start_speed": float(-prob.qdot0[0]), "average_speed": float((q[0, 0] - q[-1, 0]) / T)}

    bounds = {"constraint_violation": ("<=", 1e-6), **CONTACT_BOUNDS, "obstacle_clearance": (">=", 0.0),
              "feet_beyond_obstacle": (">=", 0.0)}
    scenery = Scenery().add("box", (3.0, 1.0, 0.02), (-0.4, 0.0, -0.01), (0.55, 0.6, 0.55, 1.0))
    scenery.add("box", (OBSTACLE.x1 - OBSTACLE.x0, 0.6, OBSTACLE.top),
                ((OBSTACLE.x0 + OBSTACLE.x1) / 2, 0.0, OBSTACLE.top / 2), (0.8, 0.35, 0.1, 1.0))
    labels = [c.name for c in robot.contacts]
    return Example("spring_flamingo", "jumps over an obstacle 0.16 m high on its way to a goal", robot, prob,
                   (plan.configurations, plan.velocities, inputs), {"constr_viol_tol": 1e-8}, checks, bounds,
                   lambda u: contacts.forces(u)[:, :, 2], labels, scenery, from_trapezoidal=True,
                   simulation=contacts)
