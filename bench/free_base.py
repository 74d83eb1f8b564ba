"""The free base on SE(3) (``Model.from_urdf(path, base="floating")``, ``add_body(..., "free")``):
a free body's momenta, energy and order, and a cube that tips over and rests, against the Euler-angle
base and MuJoCo's free joint.

1. Order: an asymmetric rigid body and a floating chain (the body with a two-link arm) from a
   tumbling state, with gravity, against a reference of the same continuous system (hovi's forward
   dynamics of the free base, checked against Pinocchio in tests/test_free_base.py, and the
   quaternion's kinematics, DOP853 at rtol = atol = 1e-13): the error of (q ⊖ q_ref, v - v_ref) at
   T = 0.8 s and its order in dt, s = 1, 2, 3.
2. The Dzhanibekov flip: the body (principal moments 1, 2, 3 kg m^2) spun at 3 rad/s about its
   intermediate axis (0.05 rad/s off it) in zero gravity for 20 s, through several flips. World
   linear and angular momentum about the origin (P = R p_lin, L = x × P + R p_ang) and energy, the
   largest deviation from the start; run time per simulated second. hovi's free base for s = 1, 2,
   3 over dt; hovi's Euler-angle base (base 'euler') from the same state; MuJoCo's free joint with
   its Euler, implicitfast and RK4 integrators over dt (one call of ``mujoco.rollout`` timed).
3. The cube (1 kg, 0.2 m, its 8 corners as contacts, mu = 0.8): released on an edge at 50° it must
   tip onto its side; dropped from 0.3 m in 100 random attitudes with a random spin it must come to
   rest on a face within 3 s. Free base and Euler base, s = 1 and 2, dt = 0.01 and 0.005: runs that
   converged at every step, runs at rest on a face, run time per simulated second.
4. Newton on the floating chain (dt = 0.01, 300 steps from a tumbling state, s = 1, 2, 3): iterations
   a step and time per step on the dense direction (with the chart term's derivative at s >= 2) and on
   the recursive one (without it).
5. The linearisation: A and B of a step (``Linearizer.rollout_jacobians`` over a 20-step rollout
   from a tumbling state with random controls), on the free base (tangent coordinates) and on the
   Euler base, for the actuated floating chain and Solo12 (example-robot-data, every joint
   actuated); time per step and the free base's ratio.

    python bench/free_base.py [--quick]

Writes bench/results/free_base.json (quick: free_base_quick.json) and, in full mode, the section
"Free bodies on SE(3)" of bench/README.md.
"""
from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.integrate import solve_ivp

import hovi
from common import erd_urdf, markdown_table, publish, study_parser, write_json
from hovi.contact import Contacts, Terrain

INERTIA = np.array([1.0, 2.0, 3.0])             # principal moments (kg m^2)
TURN = np.array([0.2, -0.3, 0.1, 0.9])          # the principal axes' attitude in the body frame (x y z w)


def quaternion_matrix(q) -> np.ndarray:
    x, y, z, w = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def zyx_angles(R) -> np.ndarray:
    """(yaw, pitch, roll) of R = Rz Ry Rx: the Euler base's coordinates."""
    return np.array([np.arctan2(R[1, 0], R[0, 0]), -np.arcsin(np.clip(R[2, 0], -1, 1)), np.arctan2(R[2, 1], R[2, 2])])


def based(name: str, base: str, **inertial) -> hovi.Model:
    """A model of one body on the free joint, or on the Euler-angle joints (x, y, z, yaw, pitch, roll)."""
    m = hovi.Model()
    if base == "free":
        m.add_body(name, None, "free", **inertial)
        return m
    parent = None
    for joint, kind, axis in [("x", "prismatic", (1, 0, 0)), ("y", "prismatic", (0, 1, 0)),
                              ("z", "prismatic", (0, 0, 1)), ("yaw", "revolute", (0, 0, 1)),
                              ("pitch", "revolute", (0, 1, 0))]:
        m.add_body(joint, parent, kind, axis=axis)
        parent = joint
    m.add_body(name, parent, "revolute", axis=(1, 0, 0), **inertial)
    return m


def body(base: str = "free", gravity: bool = True, com=(0.05, -0.02, 0.03)) -> hovi.Model:
    """The asymmetric body on the free joint, or on the Euler-angle joints (x, y, z, yaw, pitch, roll)."""
    R = quaternion_matrix(TURN)
    inertia = R @ np.diag(INERTIA) @ R.T
    m = based("body", base, mass=2.0, com=com, inertia=inertia)
    if not gravity:
        m.gravity = np.zeros(3)
    return m


def chain(base: str = "free") -> hovi.Model:
    """The body with a two-link arm, on the free joint or on the Euler-angle joints."""
    m = body(base)
    place = lambda x, z: np.block([[np.eye(3), np.array([[x], [0.0], [z]])], [np.zeros((1, 3)), np.ones((1, 1))]])
    m.add_body("upper", "body", "revolute", axis=(0.3, 1, 0.2), placement=place(0.2, 0.1), mass=0.6,
               com=(0.15, 0, 0), inertia=np.diag([0.002, 0.01, 0.01]))
    m.add_body("lower", "upper", "revolute", axis=(0, 0, 1), placement=place(0.3, 0.0), mass=0.4,
               com=(0.12, 0.01, 0), inertia=np.diag([0.001, 0.006, 0.006]))
    return m


def reference(model, q0, v0, T):
    """(q, v) at T: hovi's forward dynamics of the free base and the free joint's kinematics
    (ẋ = R v_lin, quaternion rate q ⊗ (ω/2, 0)), DOP853 at 1e-13."""
    def rhs(_, y):
        q, v = y[:model.nq], y[model.nq:]
        quat = q[3:7] / np.linalg.norm(q[3:7])
        x, yq, z, s = quat
        w = v[3:6]
        dquat = 0.5 * np.array([s * w[0] + yq * w[2] - z * w[1], s * w[1] + z * w[0] - x * w[2],
                                s * w[2] + x * w[1] - yq * w[0], -(x * w[0] + yq * w[1] + z * w[2])])
        return np.r_[quaternion_matrix(quat) @ v[:3], dquat, v[6:], model.forward_dynamics(np.r_[q[:3], quat, q[7:]], v)]

    y = solve_ivp(rhs, (0, T), np.r_[q0, v0], method="DOP853", rtol=1e-13, atol=1e-13).y[:, -1]
    q = y[:model.nq]
    q[3:7] /= np.linalg.norm(q[3:7])
    return q, y[model.nq:]


def order_study(quick: bool) -> dict:
    T = 0.8
    cases = {1: (0.02, 0.01, 0.005), 2: (0.1, 0.05, 0.025), 3: (0.2, 0.1, 0.05)}
    out = {}
    for name, build in [("body", body), ("chain", chain)]:
        m = build()
        quat = np.array([0.3, -0.1, 0.2, 0.9]) / np.linalg.norm([0.3, -0.1, 0.2, 0.9])
        q0 = np.r_[0.1, -0.2, 0.3, quat, np.full(m.nq - 7, 0.4)]
        v0 = np.r_[0.3, -0.1, 0.2, 1.5, -1.0, 0.8, np.full(m.n - 6, -0.7)]
        q_ref, v_ref = reference(m, q0, v0, T)
        for s in ([1] if quick else [1, 2, 3]):
            errors = []
            for dt in cases[s]:
                integ = hovi.Integrator(m, s=s, dt=dt)
                traj = integ.rollout(q0, int(round(T / dt)), qdot0=v0)
                v = integ.velocity(traj.q[-1], traj.p[-1])
                errors.append(max(np.abs(m.difference(q_ref, traj.q[-1])).max(), np.abs(v - v_ref).max()))
            out[f"{name} s={s}"] = dict(dt=list(cases[s]), error=errors,
                                        order=float(np.log2(errors[-2] / errors[-1])))
    return out


def world_momenta(q, p):
    """(P, L) (K, 3): a free base's world linear momentum and angular momentum about the origin."""
    R = np.array([quaternion_matrix(x) for x in q[:, 3:7]])
    P = np.einsum("kij,kj->ki", R, p[:, :3])
    return P, np.cross(q[:, :3], P) + np.einsum("kij,kj->ki", R, p[:, 3:6])


def deviation(X):
    return float(np.abs(X - X[0]).max() / np.linalg.norm(X[0]))


def flip_state():
    R = quaternion_matrix(TURN)
    return np.r_[0.2, -0.1, 0.3], 3.0 * R[:, 1] + 0.05 * R[:, 0]  # v_lin (body frame), ω (body frame)


def flip_hovi(s, dt, T):
    m = body(gravity=False)
    integ = hovi.Integrator(m, s=s, dt=dt)
    v_lin, w = flip_state()
    traj = integ.rollout(m.neutral(), int(round(T / dt)), qdot0=np.r_[v_lin, w], raise_on_failure=False)
    P, L = world_momenta(traj.q, traj.p)
    E = traj.energy
    return dict(library="hovi", base="free", s=s, dt=dt, converged=bool(traj.converged),
                seconds_per_second=traj.solve_seconds / T, momentum=max(deviation(P), deviation(L)),
                energy=float(np.ptp(E) / E[0]), iterations=float(traj.iterations.mean()))


def euler_rotation(angles) -> np.ndarray:
    a, b, c = angles
    return (quaternion_matrix([0, 0, np.sin(a / 2), np.cos(a / 2)]) @ quaternion_matrix([0, np.sin(b / 2), 0, np.cos(b / 2)])
            @ quaternion_matrix([np.sin(c / 2), 0, 0, np.cos(c / 2)]))


def rates_to_omega(angles) -> np.ndarray:
    """E(θ): the body's angular velocity (its frame) from the Z-Y-X Euler rates."""
    _, b, c = angles
    cb, sb, cc, sc = np.cos(b), np.sin(b), np.cos(c), np.sin(c)
    return np.array([[-sb, 0, 1], [cb * sc, cc, 0], [cb * cc, -sc, 0]])


def flip_hovi_euler(s, dt, T):
    """The Euler-angle base from the same state: it passes pitch ±90° as the body flips. Its momenta
    are read through the free base's (the same body's state as q, v of the free joint)."""
    m = body("euler", gravity=False)
    integ = hovi.Integrator(m, s=s, dt=dt)
    v_lin, w = flip_state()
    traj = integ.rollout(np.zeros(6), int(round(T / dt)), qdot0=np.r_[v_lin, w[2], w[1], w[0]], raise_on_failure=False)
    free = hovi.Integrator(body(gravity=False), s=s, dt=dt)
    q_free, p_free = [], []
    for q, qd in zip(traj.q, traj.qdot):
        R = euler_rotation(q[3:])
        quat = np.r_[q[:3], rotation_quaternion(R)]
        q_free.append(quat)
        p_free.append(free.momentum(quat, np.r_[R.T @ qd[:3], rates_to_omega(q[3:]) @ qd[3:]]))
    P, L = world_momenta(np.array(q_free), np.array(p_free))
    E = traj.energy
    return dict(library="hovi", base="euler", s=s, dt=dt, converged=bool(traj.converged), steps=int(traj.steps),
                seconds_per_second=traj.solve_seconds / max(traj.t[-1], dt),
                momentum=max(deviation(P), deviation(L)), energy=float(np.ptp(E) / E[0]))


def rotation_quaternion(R) -> np.ndarray:
    """A unit quaternion (x, y, z, w) of R (Shepperd's method by its largest diagonal term)."""
    t = np.trace(R)
    if t > 0:
        w = np.sqrt(1 + t) / 2
        return np.array([(R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w), w])
    i = int(np.argmax(np.diag(R)))
    j, k = (i + 1) % 3, (i + 2) % 3
    r = np.sqrt(1 + R[i, i] - R[j, j] - R[k, k])
    q = np.zeros(4)
    q[i] = r / 2
    q[j] = (R[j, i] + R[i, j]) / (2 * r)
    q[k] = (R[k, i] + R[i, k]) / (2 * r)
    q[3] = (R[k, j] - R[j, k]) / (2 * r)
    return q


def flip_mujoco(integrator, dt, T):
    import mujoco
    from mujoco import rollout as mj_rollout
    R = quaternion_matrix(TURN)
    J = R @ np.diag(INERTIA) @ R.T
    xml = f"""<mujoco><option timestep="{dt!r}" integrator="{integrator}" gravity="0 0 0">
      <flag contact="disable" constraint="disable" energy="enable"/></option>
      <worldbody><body name="b"><freejoint/><inertial pos="0.05 -0.02 0.03" mass="2"
        fullinertia="{' '.join(repr(float(J[i, j])) for i, j in [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)])}"/>
      </body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    v_lin, w = flip_state()
    d.qpos[:] = [0, 0, 0, 1, 0, 0, 0]
    d.qvel[:] = np.r_[v_lin, w]  # at the identity attitude the world and body frames agree
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x0 = np.zeros(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, x0, spec)
    steps = int(round(T / dt))
    out = np.empty((1, steps, len(x0)))
    pool = mj_rollout.Rollout(nthread=0)
    t0 = time.perf_counter()
    pool.rollout([m], [d], x0[None], nstep=steps, state=out, skip_checks=True)
    seconds = time.perf_counter() - t0
    x = np.concatenate([x0[None], out[0]])
    P, L, E = [], [], []
    for k in range(0, len(x), max(1, len(x) // 2000)):
        d.qpos[:], d.qvel[:] = x[k, 1:8], x[k, 8:14]
        mujoco.mj_forward(m, d)
        mujoco.mj_subtreeVel(m, d)
        Pk = 2.0 * d.subtree_linvel[1]
        P.append(Pk)
        L.append(np.cross(d.subtree_com[1], Pk) + d.subtree_angmom[1])
        E.append(d.energy.sum())
    E = np.array(E)
    ok = bool(np.isfinite(x).all())
    return dict(library="mujoco", base="free", integrator=integrator, dt=dt, converged=ok,
                seconds_per_second=seconds / T, momentum=max(deviation(np.array(P)), deviation(np.array(L))),
                energy=float(np.ptp(E) / E[0]))


def flip_study(quick: bool) -> list:
    T = 2.0 if quick else 20.0
    rows = []
    grid = {1: [0.01] if quick else [0.02, 0.01, 0.005], 2: [0.05, 0.02], 3: [0.1, 0.05]}
    for s in ([1] if quick else [1, 2, 3]):
        for dt in grid[s]:
            rows.append(flip_hovi(s, dt, T))
    for s, dt in ([(1, 0.01)] if quick else [(1, 0.01), (2, 0.02)]):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            rows.append(flip_hovi_euler(s, dt, T))
    for integrator in (["RK4"] if quick else ["Euler", "implicitfast", "RK4"]):
        for dt in ([0.01] if quick else [0.01, 0.002, 0.0005]):
            rows.append(flip_mujoco(integrator, dt, T))
    return rows


def cube(base: str, a: float = 0.2):
    m = based("cube", base, mass=1.0, inertia=np.eye(3) * a * a / 6)
    corners = [("cube", (sx * a / 2, sy * a / 2, sz * a / 2)) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
    return m, corners


def edge_pose(angle: float, a: float = 0.2) -> np.ndarray:
    """The free cube turned by ``angle`` about y (0: flat), its edge (a/2, ±a/2, -a/2) on the ground at x = 0."""
    h, c, s = a / 2, np.cos(angle), np.sin(angle)
    return np.r_[h * (s - c), 0.0, h * (s + c), 0.0, np.sin(angle / 2), 0.0, np.cos(angle / 2)]


def to_base(base, q_free):
    """A free-base configuration as the Euler base's (x, y, z, yaw, pitch, roll)."""
    return q_free if base == "free" else np.r_[q_free[:3], zyx_angles(quaternion_matrix(q_free[3:7])), q_free[7:]]


def velocity_to_base(base, q_free, v):
    if base == "free":
        return v
    R = quaternion_matrix(q_free[3:7])
    return np.r_[R @ v[:3], np.linalg.solve(rates_to_omega(zyx_angles(R)), v[3:6]), v[6:]]


def on_a_face(q, base) -> bool:
    """A face down (one body axis vertical) with the centre half a side above the ground."""
    R = quaternion_matrix(q[3:7]) if base == "free" else euler_rotation(q[3:6])
    return bool(abs(np.abs(R[2]).max() - 1) < 1e-6 and abs(q[2] - 0.1) < 1e-6)


def cube_run(base, s, dt, q_free, v, T):
    m, corners = cube(base)
    integ = hovi.Integrator(m, s=s, dt=dt, contacts=Contacts(m, corners, Terrain(), mu=0.8))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        traj = integ.rollout(to_base(base, q_free), int(round(T / dt)), qdot0=velocity_to_base(base, q_free, v),
                             raise_on_failure=False)
    end = traj.q[-1]
    # at rest: the velocity of the last full knot (the last row's p is before its knot's impulse)
    try:
        rest = traj.converged and on_a_face(end, base) and np.abs(traj.qdot[-2]).max() < 1e-6
    except hovi.ModelError:  # the Euler base at pitch ±90°: its mass matrix is singular there
        rest = False
    return dict(converged=bool(traj.converged), rest=bool(rest), seconds=traj.solve_seconds,
                simulated=float(traj.t[-1]), status=traj.status[-1] if traj.status else "converged")


def cube_study(quick: bool) -> dict:
    edge = edge_pose(np.radians(50))
    rng = np.random.default_rng(7)
    drops = []
    for _ in range(5 if quick else 100):
        quat = rng.normal(size=4)
        drops.append((np.r_[0, 0, 0.3, quat / np.linalg.norm(quat)], np.r_[0, 0, 0, rng.uniform(-3, 3, 3)]))
    out = {}
    for base in ("free", "euler"):
        for s, dt in ([(1, 0.01)] if quick else [(1, 0.01), (1, 0.005), (2, 0.01), (2, 0.005)]):
            tip = cube_run(base, s, dt, edge, np.zeros(6), 2.0)
            runs = [cube_run(base, s, dt, q, v, 3.0) for q, v in drops]
            simulated = sum(r["simulated"] for r in runs)
            failures = sorted({r["status"] for r in runs if not r["converged"]})
            out[f"{base} s={s} dt={dt}"] = dict(
                edge_tips_and_rests=tip["rest"], edge_status=tip["status"], drops=len(runs),
                converged=sum(r["converged"] for r in runs), rest_on_a_face=sum(r["rest"] for r in runs),
                failures=failures, seconds_per_second=sum(r["seconds"] for r in runs) / simulated)
    return out


def newton_study(quick: bool) -> list:
    q0 = np.r_[0, 0, 0, 0.1, 0.2, 0.3, 0.927, 0, 0]
    q0[3:7] /= np.linalg.norm(q0[3:7])
    v0 = np.r_[0.5, 0, 0, 2, 3, 1, 1, -1]
    out = []
    for s in ([2] if quick else [1, 2, 3]):
        for direction in ("dense", "recursive"):
            integ = hovi.Integrator(chain(), s=s, dt=0.01, direction=direction)
            best = np.inf
            for _ in range(1 if quick else 3):
                traj = integ.rollout(q0, 300, qdot0=v0)
                best = min(best, traj.solve_seconds / 300)
            out.append(dict(s=s, direction=direction, converged=bool(traj.converged),
                            iterations=float(np.mean(traj.iterations)), us_per_step=1e6 * best))
    return out


def actuated(model: hovi.Model, first: int) -> hovi.Model:
    """The model with every joint from index ``first`` on actuated."""
    for name in model.joint_names[first:]:
        model.add_actuator(name)
    return model


def linearisation_study(quick: bool) -> list:
    rng = np.random.default_rng(3)
    chain_models = {b: (lambda b=b: actuated(chain(b), 6)) for b in ("free", "euler")}
    solo = erd_urdf("solo_description/robots/solo12.urdf")
    solo_models = {b: (lambda b=b: actuated(hovi.Model.from_urdf(solo, base="floating" if b == "free" else b), 6))
                   for b in ("free", "euler")}
    out = []
    for name, builders in (("floating chain", chain_models), ("solo12", solo_models)):
        state = None
        for s in ([1] if quick else [1, 2]):
            for base, build in builders.items():
                model = build()
                integ = hovi.Integrator(model, s=s, dt=0.01)
                if state is None:  # one tumbling state, given to both bases
                    quat = rng.normal(size=4)
                    q_free = np.r_[0, 0, 1.0, quat / np.linalg.norm(quat), 0.3 * rng.normal(size=model.nq - 7)]
                    v = np.r_[rng.normal(size=6), rng.normal(size=model.nv - 6)]
                    state = q_free, v
                q0, v0 = to_base(base, state[0]), velocity_to_base(base, state[0], state[1])
                u = 0.5 * rng.normal(size=(20, s + 1, model.n_controls))
                traj = integ.rollout(q0, 20, qdot0=v0, u=u)
                lin = hovi.Linearizer(integ)
                runs, t0 = 0, time.perf_counter()
                while runs < 2 or time.perf_counter() - t0 < (0.1 if quick else 0.5):
                    lin.rollout_jacobians(traj, u)
                    runs += 1
                out.append(dict(system=name, n=model.nv, s=s, base=base,
                                ms_per_step=1e3 * (time.perf_counter() - t0) / (runs * 20)))
    return out


def readme(results) -> str:
    lines = ["Measured by `bench/free_base.py` (bench/results/free_base.json).", "",
             "Order of (q ⊖ q_ref, v - v_ref) at T = 0.8 s against DOP853 at 1e-13, last halving of dt:", ""]
    lines += markdown_table(["system", "s", "dt", "errors", "order"],
                            [[k.split()[0], k.split("=")[1], ", ".join(f"{x:g}" for x in r["dt"]),
                              ", ".join(f"{e:.1e}" for e in r["error"]), f"{r['order']:.2f}"]
                             for k, r in results["order"].items()])
    lines += ["", "The Dzhanibekov flip, 20 s, zero gravity: the largest deviation of the world momenta and of the "
              "energy, and the run time per simulated second:", ""]
    rows = []
    for r in results["flip"]:
        who = (f"hovi {r['base']} s = {r['s']}" if r["library"] == "hovi" else f"MuJoCo {r['integrator']}")
        ok = "" if r["converged"] else f" (stopped at step {r.get('steps', '?')})"
        rows.append([who + ok, f"{r['dt']:g}", f"{r['momentum']:.1e}", f"{r['energy']:.1e}",
                     f"{1e3 * r['seconds_per_second']:.3g} ms"])
    lines += markdown_table(["run", "dt", "momentum", "energy", "time / simulated s"], rows)
    lines += ["", "The cube (8 corners, mu 0.8): on an edge at 50°, and dropped from 100 random attitudes:", ""]
    lines += markdown_table(["base, s, dt", "edge: tips, rests", "drops converged", "rest on a face", "time / simulated s",
                             "failures"],
                            [[k, "yes" if r["edge_tips_and_rests"] else f"no ({r['edge_status']})",
                              f"{r['converged']}/{r['drops']}", f"{r['rest_on_a_face']}/{r['drops']}",
                              f"{1e3 * r['seconds_per_second']:.3g} ms", ", ".join(r["failures"]) or "-"]
                             for k, r in results["cube"].items()])
    lines += ["", "Newton on the floating chain (n = 8, dt 0.01, 300 steps): the dense direction (with the chart "
              "term's derivative at s >= 2) and the recursive one (without it):", ""]
    lines += markdown_table(["s", "direction", "iterations a step", "time a step"],
                            [[str(r["s"]), r["direction"], f"{r['iterations']:.2f}", f"{r['us_per_step']:.1f} µs"]
                             for r in results["newton"]])
    lines += ["", "The linearisation (A and B of a step, `Linearizer.rollout_jacobians`, every joint actuated), per step:",
              ""]
    by = {(r["system"], r["s"], r["base"]): r for r in results["linearisation"]}
    lines += markdown_table(["system", "n", "s", "free base (tangent)", "Euler base", "ratio"],
                            [[sy, str(by[(sy, s, "free")]["n"]), str(s), f"{by[(sy, s, 'free')]['ms_per_step']:.3g} ms",
                              f"{by[(sy, s, 'euler')]['ms_per_step']:.3g} ms",
                              f"{by[(sy, s, 'free')]['ms_per_step'] / by[(sy, s, 'euler')]['ms_per_step']:.2f}"]
                             for (sy, s, base) in by if base == "free"])
    ratios = [by[(sy, s, "free")]["ms_per_step"] / by[(sy, s, "euler")]["ms_per_step"] for (sy, s, b) in by if b == "free"]
    lines += ["", f"Where the free base loses: its linearisation costs {min(ratios):.1f} to {max(ratios):.1f} times the "
              "Euler base's, for the six evaluations of the step's residual that give its derivative by the chart "
              "centre's turn, and for the tangent maps; the share falls as n grows. LQR pays it once, time-varying LQR "
              "once per step of its reference (MPC, which would pay it at every solve, is not on the free base yet)."]
    return "\n".join(lines)


def main() -> None:
    args = study_parser(__doc__).parse_args()
    results = dict(order=order_study(args.quick), flip=flip_study(args.quick), cube=cube_study(args.quick),
                   newton=newton_study(args.quick), linearisation=linearisation_study(args.quick))
    for k, r in results["order"].items():
        print(f"order {k}: errors {', '.join(f'{e:.2e}' for e in r['error'])}, order {r['order']:.2f}")
    for r in results["flip"]:
        print({k: (f"{v:.3g}" if isinstance(v, float) else v) for k, v in r.items()})
    for k, r in results["cube"].items():
        print(k, r)
    for r in results["newton"] + results["linearisation"]:
        print(r)
    write_json("free_base_quick.json" if args.quick else "free_base.json", results)
    publish("free-base", readme(results), args.quick)


if __name__ == "__main__":
    main()
