"""LittleDog walks over terrain with two gaps (the paper's Sec. 6: 18 DoF, about 0.25 m/s over 3.2 s),
as a contact-implicit trajectory optimisation: the four foot spheres are point contacts with
Coulomb friction (hovi.contact.Contacts) and ``trajopt.solve_contact`` finds when each foot is on
the ground; no gait or contact schedule is given to the solver.

The paper gives no terrain dimensions. Here: flat ground with two gaps across the path, each
GAP_WIDTH (4 cm, twice the foot's diameter) wide and GAP_DEPTH (0.5 m, out of a leg's reach)
deep, the first 0.22 m and the second 0.50 m ahead of the body's start, with a keep-out circle
over each that the feet stay out of (``gap_clearances``). The dog starts at rest in its home
pose with the feet on the ground (x = -0.067 and 0.067 m) and its body must be 0.8 m ahead after
3.2 s, so every foot crosses both gaps. The quick version crosses one gap nearer the start in
1.2 s with N = 16 stages and one relaxed solve (QUICK_EPSILONS) before the exact one.

The solver starts from a kinematic trot (``Gait``): the body moving forward at a constant height,
diagonal feet swinging together on footholds that avoid the gaps, the leg angles by inverse
kinematics, the weight shared by the feet on the ground. It is only a start: the solver chooses
the contact sequence, the footholds and the forces."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Tuple

import numpy as np
from scipy.optimize import least_squares

from ... import _core, trajopt
from ...contact import DEFAULT_FRICTION, Contacts, Gap, Terrain
from ..robots import Robot, littledog
from ...trajopt import Problem, Result
from ...control.statics import static_controls
from .contact_figures import BETWEEN_TOLERANCE, CONTACT_BOUNDS, contact_figures, path_configurations
from .example import Example, Scenery, samples_between

SPEED = 0.25          # the average forward speed the body must reach (m/s; the paper's)
GAP_WIDTH = 0.04      # m
GAP_DEPTH = 0.5       # m below the ground: out of a foot's reach
FEET = ("FL", "FR", "BL", "BR")  # robot.contacts' order
LOADED = 1e-6         # a normal force above this (N) loads a foot


@dataclass(frozen=True)
class Course:
    """The horizon T (s) in N stages, the gaps' near edges (m, along x) and width (m), and the gait
    of the guess: a trot of ``period`` (s) whose diagonal pairs swing for ``swing`` (s) to
    ``height`` (m) above the ground, starting at ``start`` (s); footholds at least ``margin`` (m)
    from a gap's edge."""
    T: float
    N: int
    gaps: Tuple[float, ...]
    width: float = GAP_WIDTH
    period: float = 0.4
    swing: float = 0.16
    height: float = 0.03
    start: float = 0.05
    margin: float = 0.02

    @property
    def distance(self) -> float:
        return SPEED * self.T


FULL = Course(T=3.2, N=64, gaps=(0.22, 0.50))
QUICK = Course(T=1.2, N=16, gaps=(0.12,))
# The quick problem's relaxation homotopy: one relaxed solve, then the exact one (the full problem
# keeps solve_contact's default); the fastest of the schedules compared in bench/README.md
# ("Design measurements", littledog.py).
QUICK_EPSILONS = (1e-3,)


def terrain(robot: Robot, course: Course) -> Terrain:
    """The ground at z = 0 with the course's gaps (the feet are spheres: their contacts have the radius)."""
    return Terrain(ground=0.0, gaps=[Gap(x, x + course.width, GAP_DEPTH) for x in course.gaps])


def feet_at(robot: Robot, q: np.ndarray) -> np.ndarray:
    """World positions (4, 3) of the foot-sphere centres at configuration q (n,)."""
    X, _ = _feet_kinematics(robot, q)
    return X


def _feet_kinematics(robot: Robot, q: np.ndarray):
    m = robot.model
    bodies = [m.body_index(c.body) for c in robot.contacts]
    points = np.array([c.point for c in robot.contacts])
    X, J = _core.body_point_kinematics(m, np.asarray(q, float)[None], bodies, points)
    return X[0], J[0]


def place_feet(robot: Robot, base: np.ndarray, feet: np.ndarray, start: np.ndarray) -> np.ndarray:
    """The configuration (n,) with the base coordinates ``base`` (6,) and the leg joints (from
    ``start`` (n,)) that put the foot-sphere centres at ``feet`` (4, 3) (inverse kinematics)."""
    q = np.asarray(start, float).copy()
    q[:6] = base

    def residual(z):
        q[6:] = z
        return (feet_at(robot, q) - feet).ravel()

    def jacobian(z):
        q[6:] = z
        return _feet_kinematics(robot, q)[1][:, :, 6:].reshape(-1, len(z))

    fit = least_squares(residual, q[6:], jac=jacobian, xtol=1e-14, ftol=1e-14, gtol=1e-14)
    if np.abs(fit.fun).max() > 1e-9:
        raise ValueError(f"the feet cannot reach their targets: a foot is {np.abs(fit.fun).max():.3g} m from it")
    q[6:] = fit.x
    return q


def standing_pose(robot: Robot) -> np.ndarray:
    """The home pose (robot.q0) with the legs moved so that every foot sphere touches the ground
    exactly where its centre is over at home (the published pose leaves them up to 0.35 mm above)."""
    feet = feet_at(robot, robot.q0)
    feet[:, 2] = robot.contact_radius
    return place_feet(robot, robot.q0[:6], feet, robot.q0)


class Gait:
    """The kinematic trot the solver starts from, on ``course`` from the standing pose q0 (n,):
    the body moves along x, accelerating evenly over the first period, to ``course.distance`` at
    T; feet FL, BR and then FR, BL swing in turns, each landing where its place in the home pose
    will be at the middle of its next stance (moved out of a gap by ``course.margin``)."""

    def __init__(self, robot: Robot, course: Course, q0: np.ndarray, terrain: Terrain) -> None:
        self.robot, self.course, self.q0, self.terrain = robot, course, q0, terrain
        c = course
        self.ramp = c.period
        self.speed = c.distance / (c.T - self.ramp / 2)
        self.home = feet_at(robot, q0)
        self.steps: List[List[Tuple[float, float, float]]] = [self._steps(f) for f in range(4)]

    def base_x(self, t: np.ndarray) -> np.ndarray:
        """The body's x (m) at times t: constant acceleration up to the speed, then the speed."""
        t = np.asarray(t, float)
        return np.where(t < self.ramp, self.speed * t ** 2 / (2 * self.ramp), self.speed * (t - self.ramp / 2))

    def _steps(self, foot: int) -> List[Tuple[float, float, float]]:
        """The foot's swings: (lift time, landing time, landing x)."""
        c = self.course
        stance = c.period - c.swing
        lift = c.start + (0.0 if FEET[foot] in ("FL", "BR") else c.period / 2)
        steps = []
        while lift + c.swing / 2 <= c.T:  # the last swing may be shortened to end at T
            land = min(lift + c.swing, c.T)
            x = float(self.base_x(min(land + stance / 2, c.T))) + self.home[foot, 0]
            steps.append((lift, land, self._off_gaps(x)))
            lift += c.period
        return steps

    def _off_gaps(self, x: float) -> float:
        """x moved to the nearer side of a gap (with the margin) if it lands in one or near its edge."""
        m = self.course.margin
        for g in self.terrain.gaps:
            if g.x0 - m < x < g.x1 + m:
                return g.x0 - m if x - (g.x0 - m) < (g.x1 + m) - x else g.x1 + m
        return x

    def foot(self, f: int, t: float) -> np.ndarray:
        """The centre (3,) of foot f at time t: on its last foothold, or swinging (x by a smooth step,
        z up by height sin^2) to the next."""
        x0, ground = self.home[f, 0], self.terrain.ground + self.robot.contact_radius  # a resting centre
        for lift, land, x in self.steps[f]:
            if t < lift:
                break
            if t < land:
                s = (t - lift) / (land - lift)
                blend = s * s * (3 - 2 * s)
                return np.array([x0 + blend * (x - x0), self.home[f, 1],
                                 ground + self.course.height * np.sin(np.pi * s) ** 2])
            x0 = x
        return np.array([x0, self.home[f, 1], ground])

    def on_ground(self, t: float) -> np.ndarray:
        """Which feet (4,) are on the ground at time t."""
        return np.array([not any(lift < t < land for lift, land, _ in self.steps[f]) for f in range(4)])

    def configuration(self, t: float, start: np.ndarray) -> np.ndarray:
        """q (n,) at time t by inverse kinematics (legs from ``start``)."""
        base = self.q0[:6].copy()
        base[0] += float(self.base_x(t))
        return place_feet(self.robot, base, np.array([self.foot(f, t) for f in range(4)]), start)

    def guess(self, contacts: Contacts, dt: float, samples_per_stage: int = 4):
        """(q(t), v(t), u(t)) for the solver: the trot on a grid of dt / samples_per_stage,
        interpolated. The controls at t act on the motion to t + dt (hovi.contact: the last point's
        equal those before it): they hold the configuration at t + dt at rest with the feet on the
        ground over the interval carrying the weight (normal forces, no friction), and a foot's
        slack is the largest component of its velocity over [t, t + dt] (so its sliding rows hold)."""
        c = self.course
        h = dt / samples_per_stage
        t = np.arange(0.0, c.T + h / 2, h)
        q = [self.q0]
        for tk in t[1:]:
            q.append(self.configuration(tk, q[-1]))
        q = np.array(q)
        v = np.gradient(q, h, axis=0)
        ahead = int(round(dt / h))
        u = np.array([self._controls(contacts, q[min(k + ahead, len(t) - 1)], min(tk, c.T - dt), dt)
                      for k, tk in enumerate(t)])

        def table(values):
            return lambda tt: np.column_stack([np.interp(tt, t, values[:, j]) for j in range(values.shape[1])])
        return table(q), table(v), table(u)

    def _controls(self, contacts: Contacts, q_next: np.ndarray, t: float, dt: float) -> np.ndarray:
        """The guess's controls (m,) at time t (see ``guess``), q_next (n,) the configuration at t + dt."""
        down = self.on_ground(t) & self.on_ground(t + dt)  # a landing foot slides in the guess: no load
        columns = list(range(contacts.m_user)) + [contacts.input_index(f, "normal") for f in range(4) if down[f]]
        u = static_controls(contacts.with_inputs, q_next, columns)
        for f in range(4):
            velocity = (self.foot(f, t + dt) - self.foot(f, t)) / dt
            u[contacts.input_index(f, "slack")] = np.abs(velocity[:2]).max()
        return u


SAMPLE_SPACING = 0.01  # s: the gap circles hold at least this often between the configuration points
FEET_BELOW = BETWEEN_TOLERANCE / 2  # m: feet_above_ground lets a foot-sphere centre this far below its rest


def feet_above_ground(robot: Robot, terrain: Terrain, T: float, dt: float, below: float) -> List[trajopt.BodyPoint]:
    """Every foot-sphere centre no lower than ``below`` under its resting height on the ground
    (``terrain.ground`` plus the radius), gaps included, at every configuration point and every SAMPLE_SPACING
    between each two. The contact rows act at the configuration points only; between them a swing
    foot follows the trajectory's polynomial, which without this bound swung through the ground and
    a gap's wall. Below the resting height, not at it, so as not to duplicate the contact rows: the
    example's FEET_BELOW (half the between-knot tolerance, as the Flamingo's), its warm-up's half a
    radius (bench/README.md, "Design measurements", littledog.py)."""
    return [trajopt.BodyPoint(c.body, c.point, axes="z", lower=[terrain.ground + c.radius - below],
                              window=(0.0, T), between=samples_between(dt, SAMPLE_SPACING))
            for c in robot.contacts]


def gap_clearances(robot: Robot, terrain: Terrain, T: float, dt: float) -> List[trajopt.Clearance]:
    """Every foot-sphere centre outside a circle (in the x-z plane) over each gap, centred on it at
    the ground's surface, reaching a foot radius beyond its edges, at every configuration point in
    [0, T] and every SAMPLE_SPACING between each two (on the trajectory's polynomial, dt apart): the
    feet keep out of the gaps (a loaded foot stands fully on the ground) and step over them (a
    sphere's centre 2 cm above its resting height over the gap's centre, 1.25 cm over its edges).
    A centre outside the circle keeps a radius from both edges' corners, above and below the
    surface. The gap itself, a step in the terrain's height, gives the solver no gradient that
    moves a foot out of it; the circles do, held between the points too, with ``feet_above_ground``
    keeping the feet out from under them (what happened without them: bench/README.md, "Design
    measurements", littledog.py, and "What the checks see between the points")."""
    r = robot.contact_radius
    return [trajopt.Clearance(c.body, c.point, center=((g.x0 + g.x1) / 2, 0.0, terrain.ground),
                              radius=(g.x1 - g.x0) / 2 + r, axes="xz", window=(0.0, T),
                              between=samples_between(dt, SAMPLE_SPACING))
            for g in terrain.gaps for c in robot.contacts]


def mouth_clearance(terrain: Terrain, radius: float, centres: np.ndarray) -> float:
    """How far the foot spheres (centres (P, 3)) that are over a gap's mouth keep from its edges:
    for a centre above the ground's surface the distance to the nearer edge's corner, below it to
    the nearer wall, less the radius; negative: the sphere cuts an edge. inf if none is over a gap."""
    x, z = centres[:, 0], centres[:, 2] - terrain.ground      # height above the surface
    out = np.inf
    for g in terrain.gaps:
        over = (x > g.x0) & (x < g.x1)
        dx = np.minimum(x[over] - g.x0, g.x1 - x[over])
        d = np.where(z[over] >= 0, np.hypot(dx, np.maximum(z[over], 0)), dx)
        out = min(out, float(d.min(initial=np.inf)) - radius)
    return out


def gap_margin(terrain: Terrain, x: np.ndarray) -> np.ndarray:
    """The distances (P,) of the points x (P,) (along the course) from the gaps: positive outside
    every gap (to the nearest edge), negative inside one (to its nearer edge)."""
    x = np.asarray(x, float)
    return np.min([np.maximum(g.x0 - x, x - g.x1) for g in terrain.gaps], axis=0)


def figures(robot: Robot, contacts: Contacts, course: Course, result: Result) -> Dict[str, float]:
    """The walk's feasibility, from the optimised configurations and controls: constraint
    violation; the contact figures of ``contact_figures`` (penetration below the terrain, the gap's
    bottom over a gap; the normal complementarity recomputed from the feet's positions; the
    solver's largest product; whether the exact solve finished); friction beyond the cone; how far
    the loaded feet stand from the gaps (a foot carrying a normal force at one point stands at the
    next; negative: inside a gap); how far the feet keep from the gaps' edges along the whole
    trajectory (``mouth_clearance`` at the points and 200 configurations between each two); how far
    the last foot ends beyond the last gap; the body's average speed."""
    tr = result.trajectory
    q, u = tr["q"], tr["u"]
    feet = np.array([feet_at(robot, qk) for qk in q])                                   # (P, 4, 3)
    path = np.array([feet_at(robot, qk) for qk in path_configurations(result)])          # (P', 4, 3)
    force = contacts.forces(u)                                                          # (P, 4, 3)
    normal = force[:-1, :, 2]
    friction = np.abs(force[:-1, :, :2]).sum(-1)         # the friction pyramid: |f_x| + |f_y| <= mu f_z
    standing = feet[1:, :, 0][normal > LOADED]
    return {"constraint_violation": float(result.constraint_violation),
            **contact_figures(contacts, result, [c.name for c in robot.contacts]),
            "friction_beyond_cone": float(max(0.0, (friction - contacts.mu * normal).max())),
            "foothold_gap_margin": float(gap_margin(contacts.terrain, standing).min()) if len(standing) else np.inf,
            "edge_clearance": mouth_clearance(contacts.terrain, robot.contact_radius, path.reshape(-1, 3)),
            "past_last_gap": float(feet[-1, :, 0].min() - max(g.x1 for g in contacts.terrain.gaps)),
            "average_speed": float((q[-1, 0] - q[0, 0]) / course.T)}


BOUNDS = {"constraint_violation": ("<=", 1e-6), **CONTACT_BOUNDS, "friction_beyond_cone": ("<=", 1e-6),
          "foothold_gap_margin": (">=", 0.0), "edge_clearance": (">=", 0.0), "past_last_gap": (">=", 0.0), "average_speed": (">=", SPEED - 1e-6)}


def scenery(robot: Robot, terrain: Terrain, x_range: Tuple[float, float]) -> Scenery:
    """Boxes for the pieces of ground between the gaps over x_range, 0.3 m wide, their tops the
    terrain's surface; the gaps are left open."""
    out = Scenery()
    for x0, x1, h in terrain.segments(x_range):
        if h >= terrain.ground:
            out.add("box", (x1 - x0, 0.3, 0.02), ((x0 + x1) / 2, 0.0, h - 0.01), (0.55, 0.6, 0.55, 1.0))
    return out


def build(quick: bool = False) -> Example:
    """The walk over both gaps in 3.2 s (N = 64) or, ``quick``, over one gap in 1.2 s (N = 16, one
    relaxed solve before the exact one: QUICK_EPSILONS). The feet keep within FEET_BELOW of the
    ground between the points; from the trot guess that bound cost the first relaxed solve its
    convergence (3000 iterations), so the example's ``warm_up`` is the same walk with half a radius
    (about 5 mm), and the walk starts on its solution's contact sides (``report.solve``). A VI solve
    that is reported holds the constraints to 1e-10 (``replay_options``: at 1e-8 the integrator's
    replay of some stages lands 1.6e-6 rad away); the others to 1e-8, as the other robots (at 1e-10
    the Hermite-Simpson solve crept on for hundreds of iterations: bench/README.md)."""
    robot, course = littledog(), (QUICK if quick else FULL)
    ground = terrain(robot, course)
    q0 = standing_pose(robot)
    contacts = Contacts(robot.model, robot.contact_points, ground, mu=DEFAULT_FRICTION)
    labels = [f"{f} normal" for f in FEET]

    def walk(below: float, replay_options: Dict[str, float], warm_up: Example | None) -> Example:
        prob = problem(robot, course, ground, contacts, q0, below)
        return Example("littledog", f"walks over {len(course.gaps)} gap{'s' if len(course.gaps) > 1 else ''} "
                       f"at {SPEED} m/s", robot, prob, Gait(robot, course, q0, ground).guess(contacts, prob.dt),
                       {"constr_viol_tol": 1e-8}, lambda result: figures(robot, contacts, course, result), BOUNDS,
                       lambda u: contacts.forces(u)[:, :, 2], labels,
                       scenery(robot, ground, (-0.2, course.distance + 0.25)), QUICK_EPSILONS if quick else None,
                       from_trapezoidal=True, simulation=contacts, warm_up=warm_up,
                       replay_options=replay_options)

    return walk(FEET_BELOW, {"constr_viol_tol": 1e-10}, walk(robot.contact_radius / 2, {}, None))


def problem(robot: Robot, course: Course, ground: Terrain, contacts: Contacts, q0: np.ndarray,
            below: float) -> Problem:
    """The walk's problem, its feet within ``below`` of the ground between the points."""
    model = contacts.with_inputs
    prob = Problem(model, N=course.N, T=course.T)
    prob.initial_state(q0)
    prob.add_cost(trajopt.ControlEffort(weight=contacts.effort_weights(1e-2)))
    posture = np.r_[0.0, 1.0, 0.0, 1.0, 1.0, 1.0, np.full(12, 1e-2)]  # y, yaw, pitch, roll; the legs lightly
    prob.add_cost(trajopt.StateTracking(q0, weight=posture, velocity_weight=1e-3))
    prob.add_contacts(contacts)
    for constraint in gap_clearances(robot, ground, course.T, prob.dt) + feet_above_ground(robot, ground, course.T,
                                                                                          prob.dt, below):
        prob.add_constraint(constraint)
    prob.add_constraint(trajopt.BodyPoint("body", lower=q0[0] + course.distance, axes="x", at=course.T))
    return prob
