"""Dojo's "astronaut" benchmark: Atlas floating free in zero gravity, pushed by random joint torques
for 1 s and then coasting for 4 s with zero torque; hovi's variational integrators (s = 1, 2, 3 at
dt = 0.02, 0.01, 0.005) against MuJoCo's Euler, implicitfast and RK4 (dt = 0.01 ... 0.001) on the
same model.

The joint torques are internal, so the system's linear and angular momentum (world frame, angular
momentum about the world origin) are conserved throughout the continuous motion, and its energy
(kinetic only: no gravity) is conserved while it coasts. Per configuration: the largest relative
deviation of the momenta from their initial values over the whole 5 s, max_k |P_k - P_0| / |P_0|
and the same for L, the energy drift while coasting, max |E - E(1 s)| / E(1 s), and the run time
per simulated second.

Model: models/atlas.urdf (30 revolute joints, 174.05 kg) on a free root joint: hovi loads it with
base="floating" (q = x, y, z, qx, qy, qz, qw, joints; v = the pelvis's linear then angular velocity
in its own frame, then the joint rates). MuJoCo compiles the same URDF through mjSpec (no XML
round trip, so no rounding of the numbers): a free joint added to the pelvis, every joint's damping,
armature, friction loss and stiffness set to 0 and its limits removed (checked on the compiled
model), gravity 0, contact, constraints, limits, equality and friction loss disabled, and a motor
of gear 1 on every joint (unclamped). Before anything is timed, both libraries evaluate 3 random
states (hovi's q, v mapped to MuJoCo's qpos = x, y, z, qw, qx, qy, qz, joints by name and qvel =
R v_lin (world frame), v_ang (body frame), joint rates): kinetic energy, mass matrix (hovi's in
MuJoCo's velocity coordinates), world linear and angular momentum must agree to 1e-9 relative.

Momenta: hovi's from the discrete momenta of its trajectory: for a free-floating tree p[:6] is
the spatial momentum of the whole system in the base frame, P = R p[0:3], L = x × P + R p[3:6]
(R, x: the base's rotation and position). MuJoCo's from mj_subtreeVel at every step: P = M
subtree_linvel[root], L = subtree_com × P + subtree_angmom (about the COM). Energies: hovi's
``traj.energy`` (the velocity read back from the discrete momenta), MuJoCo's mjData.energy (energy
flag on, a copy of the model; not timed).

Torques (seed 0): piecewise constant, a new value every 0.1 s for the first 1 s, zero on the
base. Each joint's is uniform in ±min(10 N m, 10 rad/s^2 × M_jj(q0)), M_jj the diagonal of the
mass matrix at the start: a plain ±10 N m on every joint spins the light wrist and elbow joints
(M_jj down to 5e-4 kg m^2) to thousands of rad/s within the second (hovi s = 3, dt = 0.005: 7840
rad/s, 10 kJ), which no fixed-step method resolves at these dts; with the cap the fastest joints
reach 50-90 rad/s and the robot 84 J. The same torque on both (hovi: add_actuator of gear 1 on each
joint, u held per step; MuJoCo: ctrl of the motors per step). Initial state: the neutral pose
(arms out sideways) at the origin, the pelvis tumbling at (0.2, 0.5, 0.1) rad/s and moving at
(0.1, 0, 0.05) m/s (its own frame), the joints at rest, so that P and L are not zero.

Run time: hovi ``traj.solve_seconds`` (its C++ loop); MuJoCo one call of ``mujoco.rollout`` (its C
loop of mj_step in the calling thread, the controls passed as an array, energy flag off), and for
reference a Python loop of ``data.ctrl[:] = ...; mj_step``. Best of --repeats runs each. A hovi
cell whose rollout fails (a step that does not converge) is dropped and recorded as failed; a MuJoCo
run that goes non-finite or raises a bad qpos/qvel/qacc warning likewise.

    python bench/astronaut.py [--quick] [--repeats 3]

Writes bench/results/astronaut.json (astronaut_quick.json with --quick) and prints the table.
"""
from __future__ import annotations

import os
import time

import numpy as np

import mujoco_model as mjm  # MuJoCo import (a clear message when missing), its warnings silenced
import hovi
from common import ROOT, hovi_commit, json_ready, markdown_table, study_parser, write_json

mujoco = mjm.mujoco
from mujoco import rollout as mj_rollout  # noqa: E402

URDF = os.path.join(ROOT, "models", "atlas.urdf")
PUSH, COAST, SEGMENT = 1.0, 4.0, 0.1  # s: torques for PUSH, then zero torque; a new torque every SEGMENT
TORQUE, ACCEL, SEED = 10.0, 10.0, 0    # N m cap, rad/s^2 cap × M_jj, random seed
BASE_V0 = [0.1, 0.0, 0.05, 0.2, 0.5, 0.1]  # the pelvis's initial linear, angular velocity (its frame)
HOVI = {1: [0.02, 0.01, 0.005], 2: [0.02, 0.01, 0.005], 3: [0.02, 0.01, 0.005]}
MUJOCO = {"Euler": [0.01, 0.005, 0.002, 0.001], "implicitfast": [0.01, 0.005, 0.002, 0.001],
          "RK4": [0.01, 0.005, 0.002, 0.001]}
QUICK_HOVI, QUICK_MUJOCO = {2: [0.01]}, {"RK4": [0.005]}
CHECK_RTOL = 1e-9
DISABLED = ["mjDSBL_CONTACT", "mjDSBL_CONSTRAINT", "mjDSBL_LIMIT", "mjDSBL_EQUALITY", "mjDSBL_FRICTIONLOSS",
            "mjDSBL_GRAVITY", "mjDSBL_CLAMPCTRL", "mjDSBL_AUTORESET"]


# ------------------------------------------------------------------------------------------ models

def hovi_model():
    """Atlas on a free base, no gravity, a gear-1 actuator on every joint (u columns in joint order)."""
    model = hovi.Model.from_urdf(URDF, base="floating")
    model.gravity = np.zeros(3)
    for name in joints(model):
        model.add_actuator(name, 1.0)
    return model


def joints(model) -> list:
    """The names of the robot's joints (the first 6 entries of joint_names are the free base's)."""
    return list(model.joint_names[6:])


def mujoco_model(names, integrator: str = "RK4", dt: float = 0.01, energy: bool = False):
    """The same URDF compiled by MuJoCo with a free joint on the pelvis and a gear-1 motor on each of
    ``names`` (in that order); see the module docstring for what is zeroed and disabled."""
    spec = mujoco.MjSpec.from_file(URDF)
    spec.compiler.fusestatic = False  # the pelvis has no joint in the URDF: keep it a body of its own
    spec.compiler.discardvisual = True
    spec.worldbody.first_body().add_freejoint()
    for j in spec.joints:
        j.damping = np.zeros_like(np.asarray(j.damping, dtype=float))
        j.stiffness = np.zeros_like(np.asarray(j.stiffness, dtype=float))
        j.armature, j.frictionloss = 0.0, 0.0
        j.limited = mujoco.mjtLimited.mjLIMITED_FALSE
        j.actfrclimited = mujoco.mjtLimited.mjLIMITED_FALSE
    for name in names:
        spec.add_actuator(name=f"motor_{name}", target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT,
                          gear=[1, 0, 0, 0, 0, 0], ctrllimited=mujoco.mjtLimited.mjLIMITED_FALSE)
    spec.option.gravity = [0.0, 0.0, 0.0]
    spec.option.timestep = dt
    spec.option.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
    for bit in DISABLED:
        spec.option.disableflags |= int(getattr(mujoco.mjtDisableBit, bit))
    if energy:
        spec.option.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)
    m = spec.compile()
    passive = {"dof_armature": m.dof_armature, "dof_damping": m.dof_damping, "dof_frictionloss": m.dof_frictionloss,
               "jnt_stiffness": m.jnt_stiffness, "jnt_limited": m.jnt_limited, "ngeom": m.ngeom}
    bad = {k: np.abs(np.asarray(v, dtype=float)).max() for k, v in passive.items() if np.any(v)}
    assert not bad, f"MuJoCo's Atlas has passive elements left: {bad}"
    assert m.jnt_type[0] == mujoco.mjtJoint.mjJNT_FREE and m.nv == 6 + len(names) and m.nu == len(names)
    return m


def quat_matrix(xyzw) -> np.ndarray:
    """The rotation matrix of a unit quaternion (x, y, z, w)."""
    R = np.zeros(9)
    mujoco.mju_quat2Mat(R, np.asarray(xyzw, dtype=float)[[3, 0, 1, 2]])
    return R.reshape(3, 3)


class Mapping:
    """hovi's (q, v) <-> MuJoCo's (qpos, qvel): the free joint's conventions and the joints by name."""

    def __init__(self, model, m):
        names = joints(model)
        ids = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, name) for name in names]
        self.qpos = np.array([m.jnt_qposadr[i] for i in ids])
        self.dof = np.array([m.jnt_dofadr[i] for i in ids])
        self.nq, self.nv = m.nq, m.nv

    def to_mujoco(self, q, v):
        R = quat_matrix(q[3:7])
        qpos, qvel = np.zeros(self.nq), np.zeros(self.nv)
        qpos[:3], qpos[3:7], qpos[self.qpos] = q[:3], q[[6, 3, 4, 5]], q[7:]
        qvel[:3], qvel[3:6], qvel[self.dof] = R @ v[:3], v[3:6], v[6:]
        return qpos, qvel

    def velocity_map(self, q) -> np.ndarray:
        """T with qvel = T v (so M_hovi = T^T M_mujoco T)."""
        T = np.zeros((self.nv, self.nv))
        T[:3, :3], T[3:6, 3:6] = quat_matrix(q[3:7]), np.eye(3)
        T[self.dof, np.arange(6, self.nv)] = 1.0
        return T


def hovi_momenta(q, p):
    """World linear momentum P and angular momentum L about the origin, from states q (K, nq) and the
    base's momentum p[:, :6] (the system's spatial momentum in the base frame)."""
    R = np.array([quat_matrix(x) for x in q[:, 3:7]])
    P = np.einsum("kij,kj->ki", R, p[:, :3])
    return P, np.cross(q[:, :3], P) + np.einsum("kij,kj->ki", R, p[:, 3:6])


def mujoco_momenta(m, d):
    """P, L about the origin (after mj_forward: kinematics and velocities at d's state)."""
    mujoco.mj_subtreeVel(m, d)
    P = d.subtree_linvel[1] * m.body_subtreemass[1]
    return P, np.cross(d.subtree_com[1], P) + d.subtree_angmom[1]


def check(model, names, states: int = 3, seed: int = 1) -> dict:
    """Largest relative differences between hovi and MuJoCo at random states (position normal, random
    orientation, joints uniform in ±1 rad, velocities normal): kinetic energy, mass matrix, P and L.
    Stops the script above CHECK_RTOL."""
    m = mujoco_model(names, energy=True)
    d, mp = mujoco.MjData(m), Mapping(model, m)
    rng = np.random.default_rng(seed)
    worst = {"kinetic_energy": 0.0, "mass_matrix": 0.0, "linear_momentum": 0.0, "angular_momentum": 0.0}
    M = np.zeros((m.nv, m.nv))
    for _ in range(states):
        q = model.neutral()
        quat = rng.normal(size=4)
        q[:3], q[3:7], q[7:] = rng.normal(0, 1, 3), quat / np.linalg.norm(quat), rng.uniform(-1, 1, model.n - 6)
        v = rng.normal(0, 1, model.n)
        d.qpos[:], d.qvel[:] = mp.to_mujoco(q, v)
        mujoco.mj_forward(m, d)
        mjm.full_mass_matrix(m, d, M)
        Mh = model.mass_matrix(q)
        T = mp.velocity_map(q)
        K = model.kinetic_energy(q, v)
        P, L = hovi_momenta(q[None], (Mh @ v)[None])
        Pm, Lm = mujoco_momenta(m, d)
        for key, diff in (("kinetic_energy", abs(d.energy[1] - K) / K),
                          ("mass_matrix", np.abs(T.T @ M @ T - Mh).max() / np.abs(Mh).max()),
                          ("linear_momentum", np.linalg.norm(Pm - P[0]) / np.linalg.norm(P[0])),
                          ("angular_momentum", np.linalg.norm(Lm - L[0]) / np.linalg.norm(L[0]))):
            worst[key] = max(worst[key], float(diff))
    bad = {k: v for k, v in worst.items() if not v <= CHECK_RTOL}
    if bad:
        raise SystemExit(f"MuJoCo's Atlas does not match hovi's (relative differences {bad}): fix the model first")
    return {**worst, "states": states, "tolerance": CHECK_RTOL}


# ------------------------------------------------------------------------------------------ scenario

def scenario(model, push: float):
    """(q0, v0, the torque table (segments, joints) of a push of ``push`` s, the joints' torque bounds)."""
    q0, v0 = model.neutral(), np.zeros(model.n)
    v0[:6] = BASE_V0
    Mjj = np.diag(model.mass_matrix(q0))[6:]
    bound = np.minimum(TORQUE, ACCEL * Mjj)
    segments = int(round(push / SEGMENT))
    return q0, v0, np.random.default_rng(SEED).uniform(-1.0, 1.0, (segments, model.n - 6)) * bound, bound


def controls(table, dt: float, steps: int) -> np.ndarray:
    """Per step k the torque of segment floor(k dt / SEGMENT) (zero after the push), (steps, joints)."""
    seg = np.floor(np.arange(steps) * dt / SEGMENT + 1e-9).astype(int)
    U = np.zeros((steps, table.shape[1]))
    on = seg < len(table)
    U[on] = table[seg[on]]
    return U


def drifts(t, P, L, E, push: float) -> dict:
    """Largest relative deviations from the start (momenta, whole run) and from E(push) (energy, after)."""
    rel = lambda X: np.linalg.norm(X - X[0], axis=1) / np.linalg.norm(X[0])  # noqa: E731
    k1 = int(np.argmin(np.abs(t - push)))
    coast = np.abs(E[k1:] - E[k1]) / abs(E[k1])
    return {"linear_momentum_drift": float(rel(P).max()), "angular_momentum_drift": float(rel(L).max()),
            "energy_drift_coasting": float(coast.max()), "energy_at_push_end": float(E[k1]),
            "energy_start": float(E[0]), "energy_end": float(E[-1]),
            "trace": {"t": t[::max(1, len(t) // 50)], "linear": rel(P)[::max(1, len(t) // 50)],
                      "angular": rel(L)[::max(1, len(t) // 50)]}}


# ------------------------------------------------------------------------------------------ runs

def run_hovi(model, s, dt, q0, v0, table, push, horizon, repeats):
    steps = int(round(horizon / dt))
    U = controls(table, dt, steps)
    row = {"library": "hovi", "integrator": f"VI s={s}", "s": s, "dt": dt, "steps": steps}
    try:
        integ = hovi.Integrator(model, s=s, dt=dt)
        best, traj = np.inf, None
        for _ in range(repeats):
            traj = integ.rollout(q0, steps, qdot0=v0, u=U, raise_on_failure=False)
            if not traj.converged:
                break
            best = min(best, traj.solve_seconds)
    except Exception as e:  # reported, not worked around
        return {**row, "failed": True, "error": f"{type(e).__name__}: {e}"}
    if not traj.converged:
        k = traj.steps  # the steps done before the failed one
        return {**row, "failed": True, "error": f"step {k} (t = {k * dt:g} s): {traj.status[-1]}",
                "seconds_per_simulated_second_until_failure": traj.solve_seconds / max(k * dt, dt)}
    P, L = hovi_momenta(traj.q, traj.p)
    return {**row, "failed": False, "joints_at_push_end": traj.q[int(round(push / dt)), 7:], "seconds": best,
            "seconds_per_simulated_second": best / horizon,
            "mean_newton_iterations": float(np.mean(traj.iterations)),
            "max_joint_speed_rad_s": float(np.abs(traj.qdot[:, 6:]).max()),
            **drifts(np.asarray(traj.t), P, L, np.asarray(traj.energy), push)}


def run_mujoco(names, model, integrator, dt, q0, v0, table, push, horizon, repeats):
    steps = int(round(horizon / dt))
    U = controls(table, dt, steps)
    row = {"library": "MuJoCo", "integrator": integrator, "s": None, "dt": dt, "steps": steps}
    m = mujoco_model(names, integrator, dt)
    d, mp = mujoco.MjData(m), Mapping(model, m)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    mujoco.mj_resetData(m, d)
    d.qpos[:], d.qvel[:] = mp.to_mujoco(q0, v0)
    x0 = np.zeros(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, x0, spec)
    pool = mj_rollout.Rollout(nthread=0)  # in the calling thread
    out = np.empty((1, steps, len(x0)))
    best, loop = np.inf, np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        pool.rollout([m], [d], x0[None], U[None], nstep=steps, state=out, skip_checks=True)
        best = min(best, time.perf_counter() - t0)
        # the same run as a Python loop (setting ctrl each step), for reference
        mujoco.mj_setState(m, d, x0, spec)
        t0 = time.perf_counter()
        for k in range(steps):
            d.ctrl[:] = U[k]
            mujoco.mj_step(m, d)
        loop = min(loop, time.perf_counter() - t0)
    pool.close()
    x = np.concatenate([x0[None], out[0]])
    warned = [w.name.replace("mjWARN_", "") for w in mjm.BAD if d.warning[w].number]
    row.update(seconds_per_simulated_second=best / horizon, python_loop_seconds_per_simulated_second=loop / horizon,
               seconds=best)
    if not np.isfinite(x).all() or warned:
        qvel = x[:, 1 + m.nq:1 + m.nq + m.nv]
        bad = np.flatnonzero(~(np.abs(qvel) < 1e4).all(axis=1))  # non-finite, or a speed above 10^4
        return {**row, "failed": True, "error": (f"|qvel| > 1e4 from t = {bad[0] * dt:g} s; " if len(bad) else "")
                + "MuJoCo warnings " + ", ".join(warned)}
    me = mujoco_model(names, integrator, dt, energy=True)  # analysis only: not timed
    de = mujoco.MjData(me)
    P, L, E = np.empty((steps + 1, 3)), np.empty((steps + 1, 3)), np.empty(steps + 1)
    for k in range(steps + 1):
        de.qpos[:], de.qvel[:] = x[k, 1:1 + m.nq], x[k, 1 + m.nq:1 + m.nq + m.nv]
        mujoco.mj_forward(me, de)
        P[k], L[k] = mujoco_momenta(me, de)
        E[k] = de.energy.sum()
    return {**row, "failed": False, "joints_at_push_end": x[int(round(push / dt)), 1 + mp.qpos],
            **drifts(x[:, 0], P, L, E, push)}


def same_motion(rows) -> dict:
    """The largest joint-angle difference at the push's end between the finest hovi run and the finest
    MuJoCo RK4 run (the same torques on the same model give the same motion)."""
    ok = [r for r in rows if not r["failed"]]
    h = [r for r in ok if r["library"] == "hovi"]
    mj = [r for r in ok if r["library"] == "MuJoCo" and r["integrator"] == "RK4"] or \
        [r for r in ok if r["library"] == "MuJoCo"]
    if not h or not mj:
        return {}
    h = min(h, key=lambda r: (r["dt"] / r["s"] ** 2, -r["s"]))
    mj = min(mj, key=lambda r: r["dt"])
    return {"hovi": f"{h['integrator']} dt={h['dt']:g}", "mujoco": f"{mj['integrator']} dt={mj['dt']:g}",
            "max_abs_joint_difference_rad": float(np.abs(h["joints_at_push_end"] - mj["joints_at_push_end"]).max())}


def table_text(rows, horizon) -> str:
    f = lambda x: "-" if x is None else f"{x:.1e}"  # noqa: E731
    body = []
    for r in rows:
        fail = r.get("failed")
        body.append([r["library"], r["integrator"], r["s"] if r["s"] is not None else "-", f"{r['dt']:g}",
                     "-" if fail else f"{r['seconds_per_simulated_second']:.3g}",
                     "-" if fail else f(r["linear_momentum_drift"]), "-" if fail else f(r["angular_momentum_drift"]),
                     "-" if fail else f(r["energy_drift_coasting"]),
                     ("yes: " + r["error"]) if fail else "no"])
    return "\n".join(markdown_table(["library", "integrator", "s", "dt", "s per simulated s", "P drift", "L drift",
                                     "E drift (coasting)", "failed"], body)) + \
        (f"\n\n{horizon:g} s simulated; P, L drift: max |X - X0| / |X0| over the run; "
         "E drift: max |E - E(push end)| / E(push end).")


def main():
    ap = study_parser(__doc__, "hovi s = 2, dt = 0.01 and MuJoCo RK4, dt = 0.005 only; 0.5 s push + 0.5 s coast")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs per configuration, best kept (default 3)")
    args = ap.parse_args()
    push, coast = (0.5, 0.5) if args.quick else (PUSH, COAST)
    horizon = push + coast
    repeats = 1 if args.quick else args.repeats
    model = hovi_model()
    names = joints(model)
    agreement = check(model, names)
    print("hovi vs MuJoCo at 3 random states, largest relative difference: "
          + ", ".join(f"{k} {v:.1e}" for k, v in agreement.items() if k not in ("states", "tolerance")))
    q0, v0, table, bound = scenario(model, push)
    rows = []
    for s, dts in (QUICK_HOVI if args.quick else HOVI).items():
        for dt in dts:
            rows.append(run_hovi(model, s, dt, q0, v0, table, push, horizon, repeats))
            print(f"  hovi s={s} dt={dt:g}: {'failed' if rows[-1]['failed'] else 'ok'}", flush=True)
    for integrator, dts in (QUICK_MUJOCO if args.quick else MUJOCO).items():
        for dt in dts:
            rows.append(run_mujoco(names, model, integrator, dt, q0, v0, table, push, horizon, repeats))
            print(f"  MuJoCo {integrator} dt={dt:g}: {'failed' if rows[-1]['failed'] else 'ok'}", flush=True)
    text = table_text(rows, horizon)
    same = same_motion(rows)
    if same:
        text += (f"\nSame motion: at the push's end the joint angles of {same['hovi']} and {same['mujoco']} differ by "
                 f"at most {same['max_abs_joint_difference_rad']:.1e} rad.")
    name = "astronaut_quick.json" if args.quick else "astronaut.json"
    path = write_json(name, json_ready({
        "hovi_commit": hovi_commit(), "mujoco_version": mujoco.__version__, "model": os.path.relpath(URDF, ROOT),
        "scenario": {"push_s": push, "coast_s": coast, "segment_s": SEGMENT, "seed": SEED,
                     "torque_bound": {"rule": f"min({TORQUE:g} N m, {ACCEL:g} rad/s^2 * M_jj(q0))",
                                      "per_joint": dict(zip(names, bound))},
                     "torques": table, "q0": q0, "v0": v0, "gravity": [0, 0, 0]},
        "model_agreement": agreement, "same_motion": same,
        "timing": {"hovi": "Trajectory.solve_seconds (the C++ loop), best of repeats",
                   "mujoco": "one call of mujoco.rollout (C loop of mj_step, calling thread, controls as an array), "
                             "best of repeats; python_loop_*: a Python loop setting ctrl and calling mj_step",
                   "repeats": repeats},
        "mujoco_disabled": DISABLED, "configurations": {"hovi": QUICK_HOVI if args.quick else HOVI,
                                                        "mujoco": QUICK_MUJOCO if args.quick else MUJOCO},
        "rows": rows, "table": text}))
    print(text)
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
