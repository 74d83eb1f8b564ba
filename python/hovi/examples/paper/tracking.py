"""The paper's robots in closed loop in the contact simulator (``hovi example NAME --closed-loop``,
and the studies of bench/control_robots.py, control_margin.py and control_videos.py): the optimised
motion of an example tracked by time-varying LQR (``hovi.control``) on the robot's own joint torques,
saturated at the example's torque limits, in the contact simulator (``Example.simulation`` on the
robot's model, s = 1, the optimiser's dt), from the optimised initial state: as is, after a push,
with every body's mass off by a factor, or both; each run also open loop (the same torques without
feedback) for comparison. Success is the example's own goal (``GOALS``), with the tracking error against the
optimised knots, the deepest penetration and the first failure.

The nominal (``nominal``): where the simulator's open-loop replay of the optimised torques follows
the optimised motion (Atlas, Spring Flamingo: contact_replay.py), the replay and its step Jacobians
(contact state held, or smoothed); where it departs (LittleDog), the optimised knots themselves as
a trajectory of the simulator, each step linearised at the optimiser's own control points and
contact impulses (a contact without load adds nothing).

The simulator's state at knot k is (q^k, p^k) with p^k the momentum the step starts from, before the
knot's contact impulse (what a closed loop's policy sees: ``Trajectory.contact.step_momenta``). A
rollout's recorded p^k (0 < k < K) and the optimiser's knot momenta include half of that impulse
(the Galerkin weight w^s / (w^0 + w^s) of s = 1); the references take it out (``knot_impulses``
for the optimiser's knots), so that the feedback vanishes on the nominal also when the Jacobians
are smoothed (with the recorded p^k a smoothed policy pushed the Spring Flamingo's nominal
1.7e-3 rad away at smoothing = 1e-4 and 0.17 rad at 1e-3, measured before ``step_momenta``).

Weights (``Weights``, per example in ``WEIGHTS``; the choice and what else was tried:
bench/control_robots.py and bench/README.md): a diagonal cost per step on (q, q̇), the floating
base's coordinates weighted apart from the joints, torques relative to their limits, a final cost
``final`` times the stage cost, plus for Atlas the hand's distance from the ball at the end (the
goal; J^T J of the hand's position Jacobian on q).

What it measures on the quick examples, and where the loop fails: bench/README.md, "The paper's
robots in closed loop" (bench/results/control_robots.json)."""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Mapping, Optional, Tuple

import numpy as np

from ... import _core
from ...control import ClosedLoop, Policy, Push, riccati_policy, simulate
from ...integrator import Integrator
from ...linearizer import Linearizer
from ...trajopt.path_constraints import BodyPoint
from .contact_figures import BETWEEN_TOLERANCE
from .example import Example

DEPARTED = 1e-3        # m or rad: a run has departed from the optimised knots beyond this (contact_replay.DEPARTED)
UNLOADED = 1e-9        # N s: an optimiser's knot impulse at or below this is no contact (its Jacobian adds nothing)
BETWEEN = 20           # configurations sampled on each step's path (linear for s = 1) for penetration and clearance
MASS_FACTOR = 1.1      # the model error of the bench's mass cases: every body's mass and inertia times this
JUMP = 2.0             # m or rad: a coordinate moving this much in one step (40 rad/s at dt = 0.05; the optimised
                       # motions move at most 0.94 in a step, the Spring Flamingo's free ankles) is checked by
                       # re-stepping it in SUBSTEPS: the coarse step may have converged to another root of the DEL equations
SUBSTEPS = 10
FLAMINGO_FALLEN = 0.45  # m: the Spring Flamingo has fallen with its hip below this (a leg is 0.84 m; the optimised
                        # motion keeps it above flamingo.HIP_HEIGHT, 0.6 m, a shaping bound, not the task)
FLAMINGO_TIPPED = 0.8   # rad: it lands standing with its body pitched less than this (the optimised motion
                        # leans 2.16 rad forward over the obstacle and ends at 0.012 rad)


@dataclass(frozen=True)
class Weights:
    """The time-varying LQR's costs per step on the state's deviation: ``base`` on each floating-base
    coordinate (m^-2 or rad^-2), ``joints`` on each other coordinate, ``velocity`` on every velocity
    ((m/s)^-2 or (rad/s)^-2), ``torque`` on each torque relative to its limit (u / limit)^2; at the
    end ``final`` times the stage cost plus ``task`` (m^-2) on the example's goal point (Atlas: the
    hand at the ball); ``smoothing``: the smoothing ((N s)^2) of the contact Jacobians (0: contact state held)."""
    base: float = 10.0
    joints: float = 1.0
    velocity: float = 0.1
    torque: float = 1e-2
    final: float = 10.0
    task: float = 0.0
    smoothing: float = 0.0


# The weights chosen per example, measured on the quick examples (bench/control_robots.py records the
# alternatives). Atlas: the hand's final position (task) is what brings the hand to the ball: without it a
# 20 N s push leaves it 2.4 cm away and a 10% mass error 3.2 cm (the goal: 1 cm); joints 100 and velocities
# 0.01 rather than 1 and 0.1 cut the tracking error after the push from 0.10 to 0.015 rad and under the mass
# error from 0.22 to 0.058 rad; the torque weight (1e-6 to 1e-2) changed nothing (no torque saturates).
# Spring Flamingo and LittleDog: every alternative tried (base 1 to 1000, joints 1 to 100, velocities 0.01
# to 1, torques 0.025 to 25) succeeds and fails in the same cases.
WEIGHTS: Dict[str, Weights] = {
    "atlas": Weights(base=100.0, joints=100.0, velocity=0.01, torque=1e-2, final=10.0, task=1e6),
    "spring_flamingo": Weights(base=10.0, joints=1.0, velocity=0.1, torque=0.25, final=10.0),
    "littledog": Weights(base=10.0, joints=1.0, velocity=0.1, torque=0.25, final=10.0),
}

# The push of each example's push cases: a horizontal impulse (N s) on the floating base's body at
# mid-motion of the quick horizon, chosen so that the open loop fails (bench/control_robots.py: the open
# loop fails from 5 N s on Atlas and from 0.1 N s on the Spring Flamingo; its pushes at 0.55 s are in flight).
PUSHES: Dict[str, Push] = {
    "atlas": Push(0.15, "pelvis", (20.0, 0.0, 0.0)),
    "spring_flamingo": Push(0.55, "base_link", (-1.0, 0.0, 0.0)),
    "littledog": Push(0.6, "body", (0.2, 0.0, 0.0)),
}


def default_push(example: Example) -> Push:
    """The push of ``example``'s push cases (PUSHES)."""
    return PUSHES[example.name]


# ------------------------------------------------------------------------------ the optimised motion
@dataclass
class Motion:
    """The optimised motion at its knots: q (K+1, n), the optimiser's momenta p (K+1, n), the stage
    controls U (K, 2, m_all) (the robot's torques, then any contact inputs), the step dt."""
    q: np.ndarray
    p: np.ndarray
    U: np.ndarray
    dt: float

    @property
    def steps(self) -> int:
        return int(len(self.U))


def optimised_motion(example: Example, result: Any) -> Motion:
    """The Motion of a VI (s = 1) solution of ``example``: a ``trajopt.Result``, or a mapping with
    'knots' (K+1, n), 'p' (K+1, n), 'U' (K, 2, m_all) (e.g. an npz of a solve saved earlier)."""
    if isinstance(result, Motion):
        return result
    if isinstance(result, Mapping) or hasattr(result, "files"):
        q, p, U = (np.asarray(result[k], float) for k in ("knots", "p", "U"))
    else:
        tr, tc = result.trajectory, result.transcription
        if tc.s != 1:
            raise ValueError(f"the contact simulator steps with s = 1: give a solution of the VI with s = 1, not s = {tc.s}")
        q, p, U = tr["q"][::tc.s], tr["p"], tc.stage_controls(result.x)
    if U.shape[1] != 2 or len(q) != len(U) + 1 or p.shape != q.shape:
        raise ValueError(f"an optimised motion of s = 1 has K+1 knots and (K, 2, m) controls, got q {q.shape}, "
                         f"p {p.shape}, U {U.shape}")
    return Motion(q, p, U, float(example.problem.dt))


def _robot_controls(example: Example, motion: Motion) -> np.ndarray:
    m = example.robot.model.n_controls
    return np.ascontiguousarray(motion.U[:, :, :m])


def _torque_limits(example: Example) -> Tuple[np.ndarray, np.ndarray]:
    m = example.robot.model.n_controls
    return np.asarray(example.problem.u_lower[:m], float), np.asarray(example.problem.u_upper[:m], float)


def simulator(example: Example, mass_factor: float = 1.0) -> Integrator:
    """The contact simulator of ``example`` (its robot's model with ``example.simulation``, s = 1,
    the optimiser's dt), on a copy of the model with every body's mass and inertia times
    ``mass_factor`` (a plant the controller was not made for) unless it is 1."""
    model = example.robot.model
    if mass_factor != 1.0:
        model = model.copy()
        for b in range(len(model.body_names)):
            model.scale_mass(b, float(mass_factor))
    if example.simulation is None:
        raise ValueError(f"the example {example.name} has no contact simulation (Example.simulation)")
    return Integrator(model, s=1, dt=float(example.problem.dt), contacts=example.simulation)


def _contact_kinematics(integ: Integrator, Q: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """Positions (P, C, 3) and Jacobians (P, C, 3, n) of the contact points at configurations Q (P, n)."""
    c = integ.contacts
    X, J = _core.body_point_kinematics(integ.model, np.atleast_2d(Q), [pt.body for pt in c.points],
                                       np.array([pt.point for pt in c.points]))
    return X, J


def knot_impulses(integ: Integrator, Q: np.ndarray, Z: np.ndarray) -> np.ndarray:
    """The generalized impulses (P, n) sum_c J_c(q)^T (λ_c e_z + D^T β_c) of contact impulses Z (P, C, 2+d)
    at configurations Q (P, n) (ContactSolver::knot_impulse)."""
    c = integ.contacts
    _, J = _contact_kinematics(integ, Q)
    F = np.zeros(Z.shape[:2] + (3,))
    F[..., 2] = Z[..., 0]
    F += Z[..., 1:1 + c.d] @ c.D
    return np.einsum("pcin,pci->pn", J, F)


# ------------------------------------------------------------------------------------ the nominal
@dataclass
class Nominal:
    """The reference of the policy: kind 'replay' (the simulator's open-loop replay, which follows the
    optimised motion) or 'knots' (the optimised knots, each step linearised on its own); q, p (K+1, n)
    the state (p before the knot's impulse), U (K, 2, m) the torques, A (K, 2n, 2n), B (K, 2n, m) the
    step Jacobians (held controls); figures: how the replay and the steps from each knot went."""
    kind: str
    q: np.ndarray
    p: np.ndarray
    U: np.ndarray
    A: np.ndarray
    B: np.ndarray
    figures: Dict[str, Any] = field(default_factory=dict)


def _replay(example: Example, motion: Motion, integ: Integrator):
    U = _robot_controls(example, motion)
    sim = integ.rollout(motion.q[0], motion.steps, qdot0=example.problem.qdot0, u=U, raise_on_failure=False)
    dev = np.abs(sim.q - motion.q[:sim.steps + 1]).max(axis=1)
    departed = np.flatnonzero(dev > DEPARTED)
    figures = {"replay_steps": int(sim.steps), "replay_status": sim.status[-1] if sim.status else "converged",
               "replay_max_deviation": float(dev.max()),
               "replay_departs_at": float(sim.t[departed[0]]) if departed.size else None}
    return sim, figures


def _optimiser_impulses(example: Example, motion: Motion, integ: Integrator) -> np.ndarray:
    """The optimiser's contact impulses at the knots (K, C, 2+d) in the simulator's units: its knot
    inputs times dt (half at knot 0, whose force acts on one stage only), the slack (a sliding speed)
    times dt a displacement; a contact at or below UNLOADED carries nothing."""
    c, m, K = integ.contacts, example.robot.model.n_controls, motion.steps
    per = c.inputs_per_contact
    if motion.U.shape[2] != m + c.n_contacts * per:
        raise ValueError(f"the example's controls are not the robot's {m} and {c.n_contacts} point contacts' "
                         f"{per} inputs each (its forces are another model's): no knot impulses")
    Z = motion.dt * motion.U[:, 0, m:].reshape(K, c.n_contacts, per).copy()
    Z[0] *= 0.5
    Z[Z[:, :, 0] <= UNLOADED] = 0.0
    return Z


def _knot_steps(integ: Integrator, motion: Motion, U: np.ndarray, p: np.ndarray, Z: np.ndarray) -> Dict[str, Any]:
    """The simulator's own step from each optimised knot (warm-started at the optimiser's impulses):
    how far it lands from the next knot, and at which steps the simulator loads a contact the optimiser
    left without load (a foot skimming the ground: the LCP's other choice)."""
    K = len(U)
    land, failed, differs = [], [], []
    names = [integ.model.body_names[pt.body] for pt in integ.contacts.points]
    for k in range(K):
        # the optimiser's impulses as the first guess: without one the contact step found another root of
        # the DEL equations (12-15 rad away) at 4 of LittleDog's 16 knots (measured)
        _, _, info = integ.step(motion.q[k], p[k], U[k], impulses=Z[k], raise_on_failure=False)
        if not info.converged:
            failed.append((k, info.status))
            land.append(np.inf)
            continue
        qc = info.control_points
        land.append(float(np.abs(qc[-1] - motion.q[k + 1]).max()))
        z = info.impulses.reshape(Z[k].shape)
        loaded = (z[:, 0] > UNLOADED) & (Z[k][:, 0] == 0.0)
        if land[-1] > DEPARTED and loaded.any():
            differs.append((k, [names[i] for i in np.flatnonzero(loaded)]))
    arr = np.array(land)
    return {"knot_steps_landing": arr.tolist(), "knot_steps_failed": [(float(k * motion.dt), s) for k, s in failed],
            "knot_steps_elsewhere": [float(k * motion.dt) for k in np.flatnonzero(np.isfinite(arr) & (arr > DEPARTED))],
            "knot_steps_loaded_unloaded": [(float(k * motion.dt), c) for k, c in differs]}


def nominal(example: Example, motion: Motion, integ: Optional[Integrator] = None, *, smoothing: float = 0.0,
            kind: Optional[str] = None) -> Nominal:
    """The policy's reference and step Jacobians (``smoothing``): the open-loop replay if it
    follows the optimised knots to DEPARTED over the whole horizon (or ``kind`` = 'replay'), else (or
    ``kind`` = 'knots') the optimised knots, each step linearised at the optimiser's control points
    and impulses."""
    integ = simulator(example) if integ is None else integ
    U = _robot_controls(example, motion)
    K, n, m = motion.steps, integ.n, U.shape[2]
    sim, figures = _replay(example, motion, integ)
    follows = sim.steps == K and figures["replay_departs_at"] is None
    kind = kind or ("replay" if follows else "knots")
    if kind == "replay":
        if sim.steps < K:
            raise ValueError(f"the replay stops at step {sim.steps} of {K} ({figures['replay_status']}): use kind='knots'")
        A, B = Linearizer(integ).rollout_jacobians(sim, U, hold=True, smoothing=smoothing)
        q, p = sim.q.copy(), sim.contact.step_momenta.copy()   # the state the policy sees
    elif kind == "knots":
        Z = _optimiser_impulses(example, motion, integ)
        q, p = motion.q.copy(), motion.p.copy()
        p[1:K] -= 0.5 * knot_impulses(integ, q[1:K], Z[1:K])
        A, Bs = Linearizer(integ).linearize_at(np.stack([q[:-1], q[1:]], axis=1), U.reshape(K, 2, m),
                                               impulses=Z, smoothing=smoothing)
        B = Bs.reshape(K, 2 * n, 2, m).sum(axis=2)
        figures.update(_knot_steps(integ, motion, U, p, Z))
    else:
        raise ValueError(f"kind must be 'replay' or 'knots', got {kind!r}")
    return Nominal(kind, q, p, U, A, B, figures)


# ------------------------------------------------------------------------------------- the policy
def _base_coordinates(example: Example) -> int:
    return 3 if example.robot.base == "planar" else 6


def _task_weight(example: Example, q_final: np.ndarray, weight: float) -> np.ndarray:
    """(n, n) weight * J^T J of the example's goal point at the end (Atlas: the hand), or zeros."""
    n = example.robot.model.n
    if weight == 0.0:
        return np.zeros((n, n))
    goal = _goal_point(example)
    if goal is None:
        raise ValueError(f"the example {example.name} has no goal point for a task weight")
    _, J = _core.body_point_kinematics(example.robot.model, q_final[None], [goal.index], goal.point[None])
    Jr = J[0, 0][goal.rows]
    return weight * Jr.T @ Jr


def _goal_point(example: Example) -> Optional[BodyPoint]:
    """The example's body-point target at the final time (a BodyPoint with target= and at=T), if any."""
    for c in example.problem.path_constraints:
        if type(c) is BodyPoint and c.at is not None and np.all(c.lower == c.upper) and abs(c.at - example.problem.T) < 1e-9:
            return c
    return None


def make_policy(example: Example, nom: Nominal, weights: Weights, saturate: bool = True) -> Policy:
    """The time-varying LQR policy along ``nom`` with ``weights``, saturated at the torque limits
    (unless not ``saturate``: to measure what the limits cost)."""
    model = example.robot.model
    n, nb = model.n, _base_coordinates(example)
    lo, hi = _torque_limits(example)
    W = np.zeros((2 * n, 2 * n))
    W[:n, :n] = np.diag(np.r_[np.full(nb, weights.base), np.full(n - nb, weights.joints)])
    W[n:, n:] = weights.velocity * np.eye(n)
    WN = weights.final * W
    WN[:n, :n] += _task_weight(example, nom.q[-1], weights.task)
    R = weights.torque * np.diag(1.0 / np.maximum(np.abs(lo), np.abs(hi)) ** 2)
    integ = simulator(example)
    return riccati_policy(integ, nom.q, nom.p, nom.U, nom.A, nom.B, Q=W, u_weight=R, final_weight=WN,
                          u_limits=(lo, hi) if saturate else None)


@dataclass
class Controller:
    """What the runs share: the nominal, the policy and the weights."""
    nominal: Nominal
    policy: Policy
    weights: Weights
    motion: Motion


def controller(example: Example, result: Any, weights: Optional[Weights] = None, *, kind: Optional[str] = None,
               saturate: bool = True) -> Controller:
    """The nominal and TV-LQR policy of ``example``'s optimised motion ``result`` (a Result, a mapping
    as ``optimised_motion`` takes, or a Motion), WEIGHTS by default; ``kind`` and ``saturate`` as
    ``nominal`` and ``make_policy`` take them."""
    weights = WEIGHTS.get(example.name, Weights()) if weights is None else weights
    motion = result if isinstance(result, Motion) else optimised_motion(example, result)
    nom = nominal(example, motion, smoothing=weights.smoothing, kind=kind)
    return Controller(nom, make_policy(example, nom, weights, saturate), weights, motion)


# ------------------------------------------------------------------------------------------ goals
Event = Tuple[float, str]  # (time (s), what happened)


def _path(q: np.ndarray, between: int = BETWEEN) -> Tuple[np.ndarray, np.ndarray]:
    """(fractions of a step (P,), configurations (P, n)): the knots and ``between`` - 1 points on each
    step's straight path (s = 1) between them; fractions count steps from 0."""
    K = len(q) - 1
    a = np.linspace(0.0, 1.0, between + 1)[:-1]
    s = (np.arange(K)[:, None] + a[None]).ravel()
    Q = (q[:-1, None] * (1 - a)[None, :, None] + q[1:, None] * a[None, :, None]).reshape(-1, q.shape[1])
    return np.r_[s, K], np.vstack([Q, q[-1:]])


def _first(mask: np.ndarray, times: np.ndarray) -> Optional[float]:
    idx = np.flatnonzero(mask)
    return float(times[idx[0]]) if idx.size else None


def _atlas_goal(example: Example, integ: Integrator, q: np.ndarray, normal: np.ndarray, complete: bool,
                dt: float) -> Tuple[Dict[str, Any], List[Event]]:
    from hovi.examples.paper import atlas
    robot, prob = example.robot, example.problem
    t = np.arange(len(q)) * dt
    figures: Dict[str, Any] = {}
    events: List[Event] = []
    goal = _goal_point(example)
    bound = example.bounds["ball_distance"][1]
    hand = atlas.body_point(robot, q[-1], goal.body, goal.point)[0]
    distance = float(np.linalg.norm(hand - goal.lower))
    figures["ball_distance"] = distance
    if complete and distance > bound:
        events.append((float(t[-1]), f"the hand ends {distance:.3g} m from the ball (needs <= {bound:g})"))
    feet = [robot.model.body_names[pt.body] for pt in integ.contacts.points]
    left = np.array([f == "l_foot" for f in feet])
    # on one foot: the left sole never loaded and its centre above its clearance (the example's l_foot constraint)
    lifted = [c for c in prob.path_constraints if type(c) is BodyPoint and c.body == "l_foot"][0]
    height = lifted.evaluate(robot.model, t, q)[0][:, 0]
    figures["left_sole_height_min"] = float(height.min())
    low = _first(height < lifted.lower[0] - 1e-9, t)
    if low is not None:
        events.append((low, f"the left sole comes down below {lifted.lower[0]:g} m (the example's clearance)"))
    touched = _first(normal[:, left].max(axis=1) > 0, t[1:])
    figures["left_foot_loaded"] = bool(normal[:, left].max() > 0) if len(normal) else False
    if touched is not None:
        events.append((touched - dt, "the left foot touches the ground"))
    right = normal[:, ~left].sum(axis=1)
    off = _first(right <= 0, t)
    if off is not None:
        events.append((off, "the stance foot leaves the ground"))
    centre = atlas.sole(robot, "r")[0]
    held = np.array([atlas.body_point(robot, qk, "r_foot", centre)[0] for qk in q])
    slip = float(np.abs(held - held[0]).max())
    figures["stance_foot_motion"] = slip
    slip_bound = example.bounds["stance_foot_motion"][1]        # the example's own: the sole held
    moved = _first(np.abs(held - held[0]).max(axis=1) > slip_bound, t)
    if moved is not None:
        events.append((moved, f"the stance sole moves more than {slip_bound:g} m (tips or slides)"))
    return figures, events


def _flamingo_goal(example: Example, integ: Integrator, q: np.ndarray, normal: np.ndarray, complete: bool,
                   dt: float) -> Tuple[Dict[str, Any], List[Event]]:
    from hovi.examples.paper import flamingo as F
    robot = example.robot
    t = np.arange(len(q)) * dt
    figures: Dict[str, Any] = {}
    events: List[Event] = []
    s, Q = _path(q)
    clearance = np.array([float(F.box_distance(F.leg_points(robot, qk), F.OBSTACLE).min()) for qk in Q])
    figures["obstacle_clearance"] = float(clearance.min())
    hit = _first(clearance < 0, s * dt)
    if hit is not None:
        events.append((hit, f"a leg enters the obstacle ({-clearance.min():.3g} m deep)"))
    hip, pitch = q[:, 1], q[:, 2]
    figures["hip_height_min"] = float(hip.min())            # the optimiser kept it >= F.HIP_HEIGHT
    low = _first(hip < FLAMINGO_FALLEN, t)
    if low is not None:
        events.append((low, f"falls (the hip below {FLAMINGO_FALLEN:g} m)"))
    figures["final_pitch"] = float(pitch[-1])
    if complete and abs(pitch[-1]) > FLAMINGO_TIPPED:
        events.append((float(t[-1]), f"ends with the body pitched {pitch[-1]:.2g} rad (not upright)"))
    knees = np.array([[robot.model.joint_placements(qk)[robot.model.body_index(f"{side}_lower_leg")][2, 3]
                       for side in ("left", "right")] for qk in q]).min(axis=1)
    figures["knee_height_min"] = float(knees.min())         # the optimiser kept it >= F.KNEE_HEIGHT
    down = _first(knees <= 0, t)
    if down is not None:
        events.append((down, "a knee touches the ground"))
    points = np.concatenate([F.segment_points(robot.model, q[-1], c.body, np.array(c.point), np.array(c.point), 1)
                             for c in robot.contacts])
    figures["feet_beyond_obstacle"] = float(F.OBSTACLE.x0 - points[:, 0].max())
    figures["goal_distance"] = float(q[-1, 0] - F.GOAL)
    if complete and figures["feet_beyond_obstacle"] < 0:
        events.append((float(t[-1]), f"a foot ends {-figures['feet_beyond_obstacle']:.3g} m short of the obstacle's far side"))
    # landed standing: each foot on the ground at the end (a toe or heel loaded in the last step)
    names = [robot.model.body_names[pt.body] for pt in integ.contacts.points]
    if complete:
        for side in ("left", "right"):
            on = [i for i, b in enumerate(names) if b == f"{side}_foot"]
            if not normal[-1, on].max() > 0:
                events.append((float(t[-1]), f"the {side} foot is not on the ground at the end"))
        figures["landed"] = not any("not on the ground" in e[1] for e in events)
    else:
        figures["landed"] = False
    return figures, events


def _littledog_goal(example: Example, integ: Integrator, q: np.ndarray, normal: np.ndarray, complete: bool,
                    dt: float) -> Tuple[Dict[str, Any], List[Event]]:
    from hovi.examples.paper import littledog as L
    robot = example.robot
    terrain = integ.contacts.terrain
    t = np.arange(len(q)) * dt
    figures: Dict[str, Any] = {}
    events: List[Event] = []
    last = max(g.x1 for g in terrain.gaps)
    feet = L.feet_at(robot, q[-1])
    target = [c for c in example.problem.path_constraints if type(c) is BodyPoint and c.body == "body"
              and c.at is not None][0].lower[0]
    figures["base_past_last_gap"] = float(q[-1, 0] - last)
    figures["past_last_gap"] = float(feet[:, 0].min() - last)
    figures["target_distance"] = float(q[-1, 0] - target)
    if complete and figures["base_past_last_gap"] <= 0:
        events.append((float(t[-1]), f"the body ends {-figures['base_past_last_gap']:.3g} m before the last gap's far edge"))
    if complete and figures["past_last_gap"] < 0:
        events.append((float(t[-1]), f"a foot ends {-figures['past_last_gap']:.3g} m short of the last gap's far edge"))
    s, Q = _path(q)
    centres = np.array([L.feet_at(robot, qk) for qk in Q])
    depth = terrain.ground + robot.contact_radius - robot.contact_radius / 2 - centres[..., 2].min(axis=1)   # the example's feet_above_ground
    figures["lowest_foot"] = float(centres[..., 2].min() - (terrain.ground + robot.contact_radius))
    fell = _first(depth > 0, s * dt)
    if fell is not None:
        events.append((fell, "a foot goes below the ground's surface (into a gap)"))
    base_drop = q[0, 2] - q[:, 2]
    figures["body_drop_max"] = float(base_drop.max())
    return figures, events


GOALS: Dict[str, Callable[..., Tuple[Dict[str, Any], List[Event]]]] = {
    "atlas": _atlas_goal, "spring_flamingo": _flamingo_goal, "littledog": _littledog_goal}
# the goals that include "no foot below the terrain": a contact point deeper than BETWEEN_TOLERANCE (the
# examples' feasibility bound) at a knot or on a step's path fails them (the others report the depth)
NO_PENETRATION = {"littledog"}


# ------------------------------------------------------------------------------------------ a run
def _jump(integ: Integrator, run: ClosedLoop, names: List[str], dt: float) -> Optional[Dict[str, Any]]:
    """The first step of ``run`` that moves a coordinate more than JUMP, re-stepped from the same state
    with the same torques (linear between the step's two control points) in SUBSTEPS steps: how far
    apart the two ends are (far: the coarse step found another root of the DEL equations, a failure
    of the simulator at this dt, not of the robot or its controller), or None."""
    tr = run.trajectory
    if tr.steps == 0:
        return None
    moved = np.abs(np.diff(tr.q, axis=0))
    big = np.flatnonzero(moved.max(axis=1) > JUMP)
    if not big.size:
        return None
    k = int(big[0])
    j = int(np.argmax(moved[k]))
    fine = Integrator(integ.model, s=1, dt=dt / SUBSTEPS, contacts=integ.contacts)
    a = np.arange(SUBSTEPS + 1) / SUBSTEPS
    pts = (1 - a)[:, None] * run.u[k, 0] + a[:, None] * run.u[k, -1]
    sub = fine.rollout(tr.q[k], SUBSTEPS, p0=tr.contact.step_momenta[k], u=np.stack([pts[:-1], pts[1:]], axis=1),
                       raise_on_failure=False)
    apart = float(np.abs(sub.q[-1] - tr.q[k + 1]).max()) if sub.steps == SUBSTEPS else None
    return {"time": float(k * dt), "coordinate": names[j], "moved": float(moved[k, j]),
            "substeps_converged": sub.steps == SUBSTEPS, "substeps_apart": apart,
            "substeps_moved": float(np.abs(sub.q[-1] - tr.q[k]).max()) if sub.steps == SUBSTEPS else None}


def run_figures(example: Example, motion: Motion, run: ClosedLoop, integ: Integrator,
                limits: Tuple[np.ndarray, np.ndarray]) -> Dict[str, Any]:
    """A run's figures: success by the example's goal (``GOALS``), how far it got, tracking error
    against the optimised knots (max, final, the coordinate, where it first exceeds DEPARTED),
    the deepest penetration (at the knots and on each step's path), torque saturation, the first failure."""
    tr = run.trajectory
    K, steps, dt = motion.steps, tr.steps, motion.dt
    names = list(example.robot.model.joint_names)
    actuated = list(example.robot.actuated)
    dev = np.abs(tr.q - motion.q[:steps + 1])
    per_knot = dev.max(axis=1)
    departed = np.flatnonzero(per_knot > DEPARTED)
    complete = steps == K
    events: List[Event] = []
    if not complete:
        events.append((float(steps * dt), f"the contact step fails ({tr.status[-1]})"))
    jump = _jump(integ, run, names, dt)
    if jump is not None:
        what = f"the step jumps {jump['moved']:.2g} (m or rad, {jump['coordinate']})"
        if jump["substeps_apart"] is not None and jump["substeps_apart"] > JUMP / 2:
            what += (f"; in {SUBSTEPS} substeps it moves {jump['substeps_moved']:.2g} and ends {jump['substeps_apart']:.2g} "
                     "away: the simulator's step converged to another root of the DEL equations at this dt")
        events.append((jump["time"], what))
    normal = tr.contact.normal[:steps] if steps else np.zeros((0, integ.contacts.n_contacts))
    goal, goal_events = GOALS[example.name](example, integ, tr.q, normal, complete, dt)
    events += goal_events
    # penetration below the terrain: at the knots (the simulator's gaps) and on each step's path
    c = integ.contacts
    _, Q = _path(tr.q) if steps else (None, tr.q)
    X, _ = _contact_kinematics(integ, Q)
    gaps = c.core_model().gaps(X)
    knot_gap = float(tr.contact.gaps[:steps].min()) if steps else 0.0
    deepest = float(max(0.0, -gaps.min()))
    if deepest > BETWEEN_TOLERANCE and example.name in NO_PENETRATION:
        k = int(np.argmin(gaps.min(axis=1)))
        events.append((float(k / BETWEEN * dt), f"a contact point {deepest:.3g} m below the terrain between the knots"))
    lo, hi = limits
    u = run.u[:steps]
    sat = (u <= lo + 1e-9) | (u >= hi - 1e-9)
    worst_u = int(np.argmax(sat.reshape(-1, len(lo)).mean(axis=0))) if u.size else 0
    events.sort(key=lambda e: e[0])
    return {"success": not events, "steps": int(steps), "of_steps": int(K),
            "status": tr.status[-1] if tr.status else "converged",
            "max_tracking_error": float(per_knot.max()), "final_tracking_error": float(per_knot[-1]),
            "worst_coordinate": names[int(np.unravel_index(np.argmax(dev), dev.shape)[1])],
            "departs_at": float(departed[0] * dt) if departed.size else None,
            "departs_coordinate": names[int(np.argmax(dev[departed[0]]))] if departed.size else None,
            "penetration_knots": float(max(0.0, -knot_gap)), "penetration": deepest,
            "saturated_fraction": float(sat.mean()) if u.size else 0.0,
            "most_saturated": actuated[worst_u] if u.size and sat.any() else None,
            "failure": {"time": events[0][0], "what": events[0][1]} if events else None, "jump": jump,
            "failures": [{"time": t, "what": w} for t, w in events], **goal}


def _push_dict(push: Optional[Push]) -> Optional[Dict[str, Any]]:
    if push is None:
        return None
    return {"time": float(push.time), "body": push.body, "impulse": [float(x) for x in push.impulse],
            "duration": float(push.duration)}


def closed_loop_figures(example: Example, result: Any, *, push: Optional[Push] = None, mass_factor: float = 1.0,
                        weights: Optional[Weights] = None, control: Optional[Controller] = None,
                        open_loop_too: bool = True) -> Dict[str, Any]:
    """The optimised motion of ``example`` (``result``: a Result of the VI with s = 1, or a mapping as
    ``optimised_motion`` takes) tracked in closed loop in the contact simulator from the optimised
    initial state, with ``push`` (a ``hovi.control.Push``; ``default_push(example)`` is the bench's)
    and every body's mass times ``mass_factor`` in the plant; ``weights`` (default WEIGHTS[name]) or
    a prepared ``control`` (``controller``: its nominal and policy, to reuse across cases).

    Returns {'example', 'push', 'mass_factor', 'weights', 'nominal' (its kind and replay figures),
    'closed_loop' and (``open_loop_too``) 'open_loop': ``run_figures`` of each run}."""
    ctl = controller(example, result, weights) if control is None else control
    motion = ctl.motion
    plant = simulator(example, mass_factor)
    limits = _torque_limits(example)
    pushes = [] if push is None else [push]
    q0, v0 = motion.q[0], example.problem.qdot0   # the optimised initial velocity (a heavier plant: more momentum)
    out: Dict[str, Any] = {"example": example.name, "push": _push_dict(push), "mass_factor": float(mass_factor),
                           "weights": dataclasses.asdict(ctl.weights),
                           "nominal": {"kind": ctl.nominal.kind, **ctl.nominal.figures}}
    runs = {"closed_loop": ctl.policy}
    if open_loop_too:
        runs["open_loop"] = ctl.policy.without_feedback()
    for key, policy in runs.items():
        run = simulate(plant, policy, q0, motion.steps, qdot0=v0, pushes=pushes)
        out[key] = run_figures(example, motion, run, plant, limits)
    return out


def cases(example: Example, result: Any, *, weights: Optional[Weights] = None, push: Optional[Push] = None,
          mass_factor: float = MASS_FACTOR) -> Dict[str, Dict[str, Any]]:
    """The four cases of the bench: 'nominal', 'push', 'mass', 'push+mass' (push: default_push)."""
    ctl = controller(example, result, weights)
    push = default_push(example) if push is None else push
    return {"nominal": closed_loop_figures(example, result, control=ctl),
            "push": closed_loop_figures(example, result, control=ctl, push=push),
            "mass": closed_loop_figures(example, result, control=ctl, mass_factor=mass_factor),
            "push+mass": closed_loop_figures(example, result, control=ctl, push=push, mass_factor=mass_factor)}


# ------------------------------------------------------------------------------------------- text
def _run_text(name: str, run: Dict[str, Any]) -> str:
    verdict = "succeeds" if run["success"] else "fails"
    text = (f"{name} {verdict}: {run['steps']} of {run['of_steps']} steps, tracking error max "
            f"{run['max_tracking_error']:.2g} final {run['final_tracking_error']:.2g} (m or rad, {run['worst_coordinate']}), "
            f"deepest point {run['penetration']:.1e} m below the terrain")
    if run["saturated_fraction"]:
        text += f", torques at a limit {100 * run['saturated_fraction']:.0f}% of the time (most: {run['most_saturated']})"
    if run["departs_at"] is not None:
        text += f"; departs from the optimised motion at t = {run['departs_at']:.3g} s ({run['departs_coordinate']})"
    if run["failure"] is not None:
        text += f"; first failure at t = {run['failure']['time']:.3g} s: {run['failure']['what']}"
    return text


def closed_loop_text(fig: Dict[str, Any]) -> str:
    """A case of ``closed_loop_figures`` in plain words with units."""
    what = []
    if fig["push"] is not None:
        p = fig["push"]
        what.append(f"a push of {np.linalg.norm(p['impulse']):g} N s on {p['body']} at t = {p['time']:g} s")
    if fig["mass_factor"] != 1.0:
        what.append(f"every mass x{fig['mass_factor']:g} in the plant")
    head = f"{fig['example']} in closed loop in the contact simulator" + (f" with {' and '.join(what)}" if what else "")
    nom = fig["nominal"]
    if nom["kind"] == "replay":
        head += f" (nominal: the open-loop replay, {nom['replay_max_deviation']:.1g} (m or rad) from the optimised knots)"
    else:
        head += (f" (nominal: the optimised knots; the open-loop replay departs at t = {nom['replay_departs_at']:.3g} s and "
                 f"stops after {nom['replay_steps']} steps ({nom['replay_status']})")
        skims = nom.get("knot_steps_loaded_unloaded") or []
        if skims:
            head += ("; the simulator's step from an optimised knot loads a contact the optimiser leaves unloaded at " +
                     ", ".join(f"t = {t:.3g} s ({', '.join(c)})" for t, c in skims))
        if nom.get("knot_steps_failed"):
            head += "; it fails from the knot at " + ", ".join(f"t = {t:.3g} s ({st})" for t, st in nom["knot_steps_failed"])
        head += ")"
    lines = [head, "  " + _run_text("closed loop", fig["closed_loop"])]
    if "open_loop" in fig:
        lines.append("  " + _run_text("open loop", fig["open_loop"]))
    return "\n".join(lines)
