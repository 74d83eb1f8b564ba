"""hovi's contact simulation (rigid, Stewart-Trinkle time stepping, s = 1) against MuJoCo's soft
contact on the same scenes built from the same models:

1. a block dropped on the ground: penetration, normal force at rest against m g, rebound;
2. a block sliding to a stop: distance against v0^2 / (2 mu g) at dt = 0.01, 0.005, 0.0025 and the
   order of its error in dt;
3. a block on an incline (gravity tilted by theta): acceleration against g (sin theta - mu cos theta),
   sticking below the friction angle;
4. a planar 12-link chain (13 point contacts: both ends of every link) dropped nearly flat;
5. LittleDog standing (``hovi.examples.standing``: joint PD springs and dampers about q0 plus the
   static feed-forward torques);
6. cost per step against the number of contacts (a box resting on k = 1..32 contact points).

For every scene: penetration, the closed-form error, energy after the first impact (no rise
expected), run time per simulated second (hovi: ``Trajectory.solve_seconds``, the C++ loop;
MuJoCo: one call of ``mujoco.rollout``, MuJoCo's C loop of mj_step, in the calling thread; best of
``--repeats``, the two alternating) and the largest dt at which the scene stays physically right
(doubling from the scene's dt, then bisection between the last passing and the first failing dt).

The MuJoCo model is the hovi model's tree (joint types, axes, placements, masses and centres of
mass read from the hovi model as bench/mujoco_model.py does; the rotational inertias passed in,
LittleDog's read from its URDF), with each chain of massless bodies of a floating base merged into
the first body with mass as several joints of one MuJoCo body (x, y, z, yaw, pitch, roll: MuJoCo
composes them as hovi's chain does), a ground plane, and a sphere of radius r at each of hovi's
contact points; hovi's contacts are the same spheres (``ContactPoint`` radius r), so both measure
the same gap (sphere to plane). hovi's joint springs and dampers become MuJoCo joint
stiffness / springref / damping; LittleDog's constant feed-forward torques u are folded into the
springs' rest angles (u - kp (q - q0) = -kp (q - (q0 + u / kp))). The two models are checked to
agree (mass matrix, accelerations without contact, contact-point positions) before anything runs.
MuJoCo settings: its defaults unless a row says otherwise: condim 3, pyramidal cone, solref
(0.02, 1), solimp (0.9, 0.95, 0.001, 0.5, 2), Newton solver (tolerance 1e-8, 100 iterations),
Euler integrator (implicit in the joint dampers), friction mu on both geoms (MuJoCo takes the
larger), no margin; spheres collide only with the ground.

    python bench/contact_sim.py [--quick] [--repeats 5]

Writes bench/results/contact_sim.json and .png, and the table in bench/README.md (full mode).
"""
from __future__ import annotations

import os
import time
import xml.etree.ElementTree as ET

import numpy as np

import mujoco_model as mjm
import hovi
from hovi import _core
from hovi.contact import ContactPoint, Contacts, Terrain
from hovi.examples.standing import standing
from common import RESULTS, hovi_commit, json_ready, loglog_slope, study_parser, update_readme_section, write_json

mujoco = mjm.mujoco
G = 9.81
RADIUS = 0.005          # m: the contact spheres of the test scenes (LittleDog's feet: 0.0103)
PENETRATION_OK = 1e-3   # m: the stable-dt criteria's bound on penetration, sinking, rebound, drift
DT_CAP = 0.1            # s: the largest dt tried
TOUCH = 1e-6            # m: a gap below this counts as contact (the first impact)


# ------------------------------------------------------------------------------------------ scenes

class Scene:
    """One scene: the hovi model (without contacts), its contact points [(body, point)] (the sphere
    centres), the bodies' rotational inertias (about the COM, joint-frame axes), the spring rest
    positions ``rest`` (n,), mu, the friction plane ('' or 'xz'), the initial state, a constant
    generalised feed-forward force ``tau`` (n,) on the joints (or None) with the controls ``u`` that
    give it in hovi, and the sphere radius."""

    def __init__(self, name, model, inertias, points, mu, q0, qdot0=None, plane="", rest=None, u=None, tau=None,
                 radius=RADIUS, gravity=None, settle=0.0):
        points = [(p.body, p.point) if isinstance(p, ContactPoint) else p for p in points]
        self.name, self.model, self.inertias, self.points = name, model, inertias, points
        self.settle = settle  # s: MuJoCo first settles at rest this long (see MuJoCo.initial_state)
        self.horizontal = [j for j in range(model.n) if model.joint_types[j] == "prismatic" and
                           abs(model.spatial_twists(np.zeros(model.n))[j][5]) < 1e-12]  # x, y slides
        self.mu, self.plane, self.radius, self.u, self.tau = mu, plane, radius, u, tau
        if gravity is not None:
            model.gravity = tuple(gravity)
        self.q0 = np.asarray(q0, float)
        self.qdot0 = np.zeros(model.n) if qdot0 is None else np.asarray(qdot0, float)
        self.rest = np.zeros(model.n) if rest is None else np.asarray(rest, float)
        self.bodies = [model.body_index(b) if isinstance(b, str) else int(b) for b, _ in points]
        self.local = np.array([p for _, p in points], float)

    def integrator(self, dt):
        contacts = Contacts(self.model, [(b, p, self.radius) for b, p in self.points], Terrain(), mu=self.mu,
                            plane=self.plane)
        return hovi.Integrator(self.model, s=1, dt=dt, contacts=contacts)

    def gaps(self, Q):
        """(K, C): each sphere's distance to the ground at configurations Q (K, n) (< 0: penetration)."""
        X, _ = _core.body_point_kinematics(self.model, np.atleast_2d(Q), self.bodies, self.local)
        return X[..., 2] - self.radius

    def energy(self, Q, Qd):
        """K + V of hovi's model (gravity and springs) at each state: the same function for both simulators."""
        return np.array([self.model.energy(q, qd) for q, qd in zip(Q, Qd)])

    def spring_ref(self, feed_forward=True):
        ref = self.rest.copy()
        if feed_forward and self.tau is not None:
            on = self.tau != 0
            ref[on] += self.tau[on] / self.model.stiffness[on]
        return ref


def rod_inertia(mass, length, radius=0.01):
    """A solid cylinder along the joint frame's x."""
    axial, transverse = mass * radius ** 2 / 2, mass * (3 * radius ** 2 + length ** 2) / 12
    return np.diag([axial, transverse, transverse])


def block_scene(name, q0, qdot0=(0.0, 0.0), mu=0.5, mass=2.0, gravity=None, settle=0.0):
    """tests/test_contact_simulation.py's block: a point mass in the x-z plane (prismatic x, massless,
    then prismatic z), one contact point at the mass; q = (x, height of the sphere's centre)."""
    model = hovi.Model()
    model.add_body("slider", None, "prismatic", axis=(1, 0, 0))
    model.add_body("mass", "slider", "prismatic", axis=(0, 0, 1), mass=mass, inertia=np.eye(3) * 1e-3)
    return Scene(name, model, [np.zeros((3, 3)), np.eye(3) * 1e-3], [("mass", (0.0, 0.0, 0.0))], mu, q0, qdot0,
                 plane="xz", gravity=gravity, settle=settle)


def chain_scene(links=12, length=0.1, mass=0.1, mu=0.5, height=0.1, seed=0):
    """A planar chain of ``links`` rods (floating base x, z, pitch; revolute joints about y) with a
    contact at every node (both ends of every link: links + 1 points), released nearly flat
    (joint angles uniform in +-0.1 rad) ``height`` above the ground, sliding at 0.3 m/s."""
    model = hovi.Model()
    model.add_body("x", None, "prismatic", axis=(1, 0, 0))
    model.add_body("z", "x", "prismatic", axis=(0, 0, 1))
    I = rod_inertia(mass, length)
    inertias = [np.zeros((3, 3))] * 2
    place = np.eye(4)
    place[0, 3] = length
    for i in range(links):
        model.add_body(f"link{i}", "z" if i == 0 else f"link{i - 1}", "revolute", axis=(0, 1, 0),
                       placement=None if i == 0 else place, mass=mass, com=(length / 2, 0, 0), inertia=I)
        inertias.append(I)
    points = [("link0", (0.0, 0.0, 0.0))] + [(f"link{i}", (length, 0.0, 0.0)) for i in range(links)]
    rng = np.random.default_rng(seed)
    q0 = np.concatenate([[0.0, height + RADIUS], rng.uniform(-0.1, 0.1, links)])
    # lift it so that its lowest node starts `height` above the ground
    scene = Scene("chain", model, inertias, points, mu, q0, np.r_[0.3, np.zeros(links + 1)], plane="xz")
    scene.q0[1] += height - scene.gaps(scene.q0)[0].min()
    return scene


def box_scene(k, mass=1.0, a=0.2, b=0.15, c=0.1, mu=0.6):
    """tests/test_contact_simulation.py's box (floating base x, y, z, yaw, pitch, roll) resting on k
    points of its bottom face: the centre (k = 1), two points on x (k = 2), else a circle of radius
    0.05 m about the centre."""
    model = hovi.Model()
    for name, parent, kind, axis in (("x", None, "prismatic", (1, 0, 0)), ("y", "x", "prismatic", (0, 1, 0)),
                                     ("z", "y", "prismatic", (0, 0, 1)), ("yaw", "z", "revolute", (0, 0, 1)),
                                     ("pitch", "yaw", "revolute", (0, 1, 0))):
        model.add_body(name, parent, kind, axis=axis)
    I = mass / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    model.add_body("box", "pitch", "revolute", axis=(1, 0, 0), mass=mass, inertia=I)
    if k == 1:
        xy = [(0.0, 0.0)]
    elif k == 2:
        xy = [(-0.05, 0.0), (0.05, 0.0)]
    else:
        xy = [(0.05 * np.cos(2 * np.pi * j / k), 0.05 * np.sin(2 * np.pi * j / k)) for j in range(k)]
    points = [("box", (x, y, -c / 2)) for x, y in xy]
    return Scene(f"box, {k} contacts", model, [np.zeros((3, 3))] * 5 + [I], points, mu,
                 [0.0, 0.0, c / 2 + RADIUS, 0.0, 0.0, 0.0])


def urdf_inertias(model, path):
    """Rotational inertias (about the COM, link-frame axes) of the model's bodies from the URDF's
    <inertial> (origin rpy applied); zero for bodies the URDF does not name (the base's joints)."""
    links = {l.get("name"): l for l in ET.parse(path).getroot().iter("link")}
    out = []
    for body in model.body_names:
        inertial = links[body].find("inertial") if body in links else None
        if inertial is None:
            out.append(np.zeros((3, 3)))
            continue
        e = inertial.find("inertia").attrib
        I = np.array([[e["ixx"], e["ixy"], e["ixz"]], [e["ixy"], e["iyy"], e["iyz"]], [e["ixz"], e["iyz"], e["izz"]]],
                     dtype=float)
        origin = inertial.find("origin")
        r, p, y = map(float, (origin.get("rpy", "0 0 0") if origin is not None else "0 0 0").split())
        cr, sr, cp, sp, cy, sy = np.cos(r), np.sin(r), np.cos(p), np.sin(p), np.cos(y), np.sin(y)
        R = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]) @ np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]]) \
            @ np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
        out.append(R @ I @ R.T)
    return out


def littledog_scene(dt=None):
    """hovi.examples.standing('littledog'): the PD model (springs kp about q0, dampers kd) and its
    feed-forward u; MuJoCo gets the same springs and dampers and u through the springs' rest angles."""
    st = standing("littledog", dt)
    model = st.model
    tau = np.zeros(model.n)
    for k, joint in enumerate(st.robot.actuated):
        tau[model.joint_index(joint)] = st.u[k]
    rest = np.where(model.stiffness != 0, st.q0, 0.0)
    scene = Scene("LittleDog standing", model, urdf_inertias(model, st.robot.urdf), st.robot.contact_points,
                  st.contacts.mu, st.q0, rest=rest, u=st.u, tau=tau, radius=st.robot.contact_radius)
    scene.hovi_dt = st.integrator.dt
    return scene


# ------------------------------------------------------------------------------------------ MuJoCo

def _vec(v):
    return " ".join(repr(float(x)) for x in v)


def mjcf(scene, dt, integrator="Euler", cone="pyramidal", contact=True, feed_forward=True, energy=False):
    """The MJCF of a scene (see the module docstring)."""
    model, n = scene.model, scene.model.n
    q0 = np.zeros(n)
    oMi, poses, twists = model.joint_placements(q0), model.body_poses(q0), model.spatial_twists(q0)
    children = {i: [] for i in range(-1, n)}
    for i, parent in enumerate(model.parents):
        children[parent].append(i)
    carries = set(scene.bodies)
    ref = scene.spring_ref(feed_forward)
    stiffness, damping = model.stiffness, model.joint_damping

    def merged(i):
        """Body i is folded into its only child: massless, no contact point, the child's joint frame its own."""
        if model.masses[i] != 0 or i in carries or len(children[i]) != 1:
            return False
        return np.allclose(np.linalg.inv(oMi[i]) @ oMi[children[i][0]], np.eye(4), atol=1e-14)

    def joint(i, pad):
        kind = model.joint_types[i]
        if kind not in mjm.JOINT_TYPES:
            raise ValueError(f"joint {model.joint_names[i]} is {kind}: only revolute and prismatic are mapped")
        s = twists[i][:3] if kind == "revolute" else twists[i][3:]
        axis = oMi[i][:3, :3].T @ s
        extra = f' stiffness="{float(stiffness[i])!r}" springref="{float(ref[i])!r}"' if stiffness[i] else ""
        extra += f' damping="{float(damping[i])!r}"' if damping[i] else ""
        return f'{pad}  <joint name="{model.joint_names[i]}" type="{mjm.JOINT_TYPES[kind]}" axis="{_vec(axis)}"{extra}/>'

    def body(i, frame, joints, indent):
        pad = " " * indent
        if merged(i):
            return body(children[i][0], frame, joints + [i], indent)
        if model.masses[i] <= 0:
            raise ValueError(f"body {model.body_names[i]}: MuJoCo needs a mass on every moving body")
        local = np.linalg.inv(frame) @ oMi[i]
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, local[:3, :3].flatten())
        com = (np.linalg.inv(oMi[i]) @ poses[i][:, 3])[:3]
        I = np.asarray(scene.inertias[i], float)
        lines = [f'{pad}<body name="{model.body_names[i]}" pos="{_vec(local[:3, 3])}" quat="{_vec(quat)}">',
                 f'{pad}  <inertial pos="{_vec(com)}" mass="{float(model.masses[i])!r}" '
                 f'fullinertia="{_vec([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]])}"/>']
        lines += [joint(j, pad) for j in joints + [i]]
        for c, (b, p) in enumerate(zip(scene.bodies, scene.local)):
            if b == i:
                lines += [f'{pad}  <geom name="contact{c}" type="sphere" size="{scene.radius!r}" pos="{_vec(p)}" '
                          f'contype="1" conaffinity="0" condim="3" friction="{scene.mu!r} 0.005 0.0001"/>',
                          f'{pad}  <site name="point{c}" pos="{_vec(p)}"/>']
        for c in children[i]:
            lines += body(c, oMi[i], [], indent + 2)
        return lines + [f"{pad}</body>"]

    tree = [line for root in children[-1] for line in body(root, np.eye(4), [], 4)]
    flags = (f'contact="{"enable" if contact else "disable"}" autoreset="disable" '
             f'energy="{"enable" if energy else "disable"}"')
    return "\n".join([
        '<mujoco model="contact_sim">',
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{float(dt)!r}" integrator="{integrator}" cone="{cone}" gravity="{_vec(model.gravity)}">',
        f"    <flag {flags}/>",
        "  </option>",
        '  <default><joint armature="0" damping="0" frictionloss="0" stiffness="0" limited="false"/></default>',
        "  <worldbody>",
        f'    <geom name="ground" type="plane" size="0 0 1" contype="0" conaffinity="1" condim="3" '
        f'friction="{scene.mu!r} 0.005 0.0001"/>',
        *tree, "  </worldbody>", "</mujoco>"])


class MuJoCo:
    """A scene in MuJoCo at one dt: ``run(steps)`` -> (Q, Qd (steps+1, n) in hovi's joint order,
    seconds of the C rollout, ok: finite and no bad qpos / qvel / qacc warning)."""

    SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS

    def __init__(self, scene, dt, **options):
        self.scene, self.dt = scene, dt
        self.m = mujoco.MjModel.from_xml_string(mjcf(scene, dt, **options))
        self.d = mujoco.MjData(self.m)
        names = scene.model.joint_names
        self.perm = np.array([self.m.jnt_qposadr[mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_JOINT, j)] for j in names])
        vperm = np.array([self.m.jnt_dofadr[mujoco.mj_name2id(self.m, mujoco.mjtObj.mjOBJ_JOINT, j)] for j in names])
        assert np.array_equal(self.perm, vperm) and self.m.nq == self.m.nv == scene.model.n
        self.nstate = mujoco.mj_stateSize(self.m, self.SPEC)
        self.pool = mjm.mj_rollout.Rollout(nthread=0)

    def set(self, q, qd):
        self.d.qpos[self.perm], self.d.qvel[self.perm] = q, qd

    def initial_state(self):
        """The state at q0, qdot0; with ``scene.settle`` > 0, q0 first settled into MuJoCo's own rest on
        the ground: ``settle`` seconds from q0 at rest under gravity's vertical component, then the
        horizontal coordinates put back to q0's and the velocity set to qdot0 (a block resting on
        the ground, then pushed or tilted: MuJoCo's soft contact rests a little below the surface,
        hovi's on it, so each starts from its own rest). Not timed."""
        m, d, scene = self.m, self.d, self.scene
        mujoco.mj_resetData(m, d)
        self.set(scene.q0, np.zeros(scene.model.n))
        if scene.settle > 0:
            gravity = m.opt.gravity.copy()
            m.opt.gravity[:2] = 0.0
            for _ in range(int(np.ceil(scene.settle / self.dt))):
                mujoco.mj_step(m, d)
            m.opt.gravity[:] = gravity
            d.qpos[self.perm[scene.horizontal]] = scene.q0[scene.horizontal]
            d.time = 0.0
        d.qvel[self.perm] = scene.qdot0
        x0 = np.zeros(self.nstate)
        mujoco.mj_getState(m, d, x0, self.SPEC)
        return x0

    def run(self, steps):
        m, d = self.m, self.d
        x0 = self.initial_state()
        out = np.empty((1, steps, self.nstate))
        t = time.perf_counter()
        self.pool.rollout([m], [d], x0[None], nstep=steps, state=out, skip_checks=True)
        seconds = time.perf_counter() - t
        x = np.concatenate([x0[None], out[0]])
        qpos, qvel = x[:, 1:1 + m.nq], x[:, 1 + m.nq:1 + m.nq + m.nv]
        ok = bool(np.isfinite(x).all()) and not any(d.warning[w].number for w in mjm.BAD)
        return qpos[:, self.perm], qvel[:, self.perm], seconds, ok

    def normal_force(self, q, qd):
        """Sum of the contacts' normal forces (N) MuJoCo computes at state (q, qd)."""
        m, d = self.m, self.d
        self.set(q, qd)
        mujoco.mj_forward(m, d)
        f, total = np.zeros(6), 0.0
        for i in range(d.ncon):
            mujoco.mj_contactForce(m, d, i, f)
            total += f[0]
        return total


def check(scene, states=4, seed=1, rtol=1e-9):
    """Largest relative differences between MuJoCo's model and hovi's at random states near q0:
    mass matrix, accelerations without contact and without the springs and dampers (hovi's
    ``forward_dynamics`` has neither), the springs' and dampers' force (MuJoCo's qfrc_passive against
    -k (q - rest) - c q̇), energy K + V with the springs (mjData.energy against ``Model.energy``: the
    springs' rest positions) and the contact points' positions. Exits above rtol."""
    sim = MuJoCo(scene, 0.01, contact=False, feed_forward=False, energy=True)
    m, d = sim.m, sim.d
    rng = np.random.default_rng(seed)
    worst = {"mass_matrix": 0.0, "qacc": 0.0, "passive": 0.0, "energy": 0.0, "points": 0.0}
    M = np.zeros((m.nv, m.nv))
    P = sim.perm
    sites = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, f"point{c}") for c in range(len(scene.bodies))]
    k, c = scene.model.stiffness, scene.model.joint_damping
    passive_bits = int(mujoco.mjtDisableBit.mjDSBL_SPRING) | int(mujoco.mjtDisableBit.mjDSBL_DAMPER)
    for _ in range(states):
        q = scene.q0 + rng.uniform(-0.3, 0.3, scene.model.n)
        qd = rng.normal(0.0, 1.0, scene.model.n)
        m.opt.disableflags &= ~passive_bits
        sim.set(q, qd)
        mujoco.mj_forward(m, d)
        passive, energy = d.qfrc_passive[P].copy(), float(d.energy.sum())
        mjm.full_mass_matrix(m, d, M)
        X, _ = _core.body_point_kinematics(scene.model, q[None], scene.bodies, scene.local)
        m.opt.disableflags |= passive_bits
        mujoco.mj_forward(m, d)
        Mh, ah = scene.model.mass_matrix(q), scene.model.forward_dynamics(q, qd)
        Qp = -k * (q - scene.rest) - c * qd
        E = scene.model.energy(q, qd)
        worst["mass_matrix"] = max(worst["mass_matrix"], np.abs(M[np.ix_(P, P)] - Mh).max() / np.abs(Mh).max())
        worst["qacc"] = max(worst["qacc"], np.abs(d.qacc[P] - ah).max() / np.abs(ah).max())
        worst["passive"] = max(worst["passive"], np.abs(passive - Qp).max() / max(1.0, np.abs(Qp).max()))
        worst["energy"] = max(worst["energy"], abs(energy - E) / max(1.0, abs(E)))
        worst["points"] = max(worst["points"], np.abs(d.site_xpos[sites] - X[0]).max() / max(1.0, np.abs(X).max()))
    bad = {key: float(v) for key, v in worst.items() if not v <= rtol}
    if bad:
        raise SystemExit(f"{scene.name}: MuJoCo's model does not match hovi's ({bad}, tolerance {rtol:g})")
    return {key: float(v) for key, v in worst.items()}


# ------------------------------------------------------------------------------------------ runs

def run_hovi(scene, dt, steps, integ=None):
    integ = integ or scene.integrator(dt)
    try:
        traj = integ.rollout(scene.q0, steps, qdot0=scene.qdot0, u=scene.u, raise_on_failure=False)
    except Exception as e:  # noqa: BLE001 - a failed rollout is a measured failure, reported
        return {"ok": False, "error": f"{type(e).__name__}: {e}"[:200]}
    ok = traj.converged and traj.steps == steps and bool(np.isfinite(traj.q).all())
    return {"ok": ok, "Q": traj.q, "Qd": traj.qdot, "seconds": traj.solve_seconds, "traj": traj}


def run_mujoco(scene, dt, steps, sim=None, **options):
    sim = sim or MuJoCo(scene, dt, **options)
    Q, Qd, seconds, ok = sim.run(steps)
    return {"ok": ok, "Q": Q, "Qd": Qd, "seconds": seconds, "sim": sim}


def run(which, scene, dt, steps, **options):
    return run_hovi(scene, dt, steps) if which == "hovi" else run_mujoco(scene, dt, steps, **options)


def common_metrics(scene, r, dt):
    """Penetration (largest over the run, over its second half, at the end), the first impact, the
    lift after it (the lowest sphere's largest height after the first contact: rebound), speed at
    the end (difference quotient of the last two configurations), energy (``Scene.energy`` at
    states 0..K-1: hovi's velocity at the last state lacks the impulse of the step that would
    follow) and its largest rise above its running minimum after the first impact (J and relative
    to the energy dissipated), and its largest excess over the initial energy."""
    if "Q" not in r or not np.isfinite(r["Q"]).all():
        return {"ok": False, "error": r.get("error", "not finite")}
    Q, Qd = r["Q"], r["Qd"]
    gaps = scene.gaps(Q)
    half = len(Q) // 2
    touched = np.nonzero(gaps.min(1) < TOUCH)[0]
    E = scene.energy(Q[:-1], Qd[:-1])
    dissipated = float(E.max() - E.min())
    out = {"ok": bool(r["ok"]), "penetration_max": float(max(0.0, -gaps[1:].min())),
           "penetration_rest": float(max(0.0, -gaps[half:].min())), "penetration_end": float(max(0.0, -gaps[-1].min())),
           "gap_end_max": float(gaps[-1].max()), "speed_end": float(np.abs(Q[-1] - Q[-2]).max() / dt),
           "simulated_s": (len(Q) - 1) * dt, "energy_excess_over_initial": float(E.max() - E[0]),
           "energy_dissipated": dissipated}
    if len(touched):
        k1 = int(touched[0])
        after = E[k1:]
        rise = float(np.max(after - np.minimum.accumulate(after))) if len(after) else 0.0
        out.update({"first_impact_step": k1, "energy_rise_after_impact": rise,
                    "energy_rise_rel": rise / dissipated if dissipated > 0 else 0.0,
                    "rebound": float(max(0.0, gaps[k1:].min(1).max()))})
    return out


def finite(r):
    return "Q" in r and bool(np.isfinite(r["Q"]).all())


# ------------------------------------------------------------------------------------------ scenes' studies

def study_drop(which, dt, T=1.0, **options):
    """Block (2 kg) dropped from 0.1 m: rests at m g, no rebound, no sinking."""
    m, h = 2.0, 0.1
    scene = block_scene("drop", [0.0, h + RADIUS])
    steps = int(np.ceil(T / dt))
    r = run(which, scene, dt, steps, **options)
    out = common_metrics(scene, r, dt)
    if finite(r):
        if which == "hovi":
            normal = float(r["traj"].contact.normal[-1].sum() / dt)
        else:
            normal = r["sim"].normal_force(r["Q"][-1], r["Qd"][-1])
        out["normal_force_rel_error"] = abs(normal - m * G) / (m * G)
        out["passes"] = bool(out["ok"] and out["penetration_rest"] <= PENETRATION_OK and out.get("rebound", 1.0) <= PENETRATION_OK
                             and abs(out["gap_end_max"]) <= PENETRATION_OK and out["speed_end"] <= 1e-3
                             and out["normal_force_rel_error"] <= 1e-2)
    else:
        out["passes"] = False
    return out, scene, r


def study_slide(which, dt, T=0.5, v0=1.0, mu=0.5, **options):
    """Block sliding from v0 on the ground: stops at v0^2 / (2 mu g)."""
    scene = block_scene("slide", [0.0, RADIUS], [v0, 0.0], mu=mu, settle=1.0)
    exact = v0 ** 2 / (2 * mu * G)
    r = run(which, scene, dt, int(np.ceil(T / dt)), **options)
    out = common_metrics(scene, r, dt)
    if finite(r):
        out["stop_distance"] = float(r["Q"][-1, 0])
        out["stop_error_rel"] = abs(out["stop_distance"] - exact) / exact
        out["passes"] = bool(out["ok"] and out["penetration_rest"] <= PENETRATION_OK and out["stop_error_rel"] <= 1e-2
                             and out["speed_end"] <= 1e-4)
    else:
        out["passes"] = False
    return out, scene, r


INCLINE = [(0.3, 0.5), (0.3, 0.2), (0.5, 0.5)]  # (theta, mu): sticks (tan 0.3 = 0.31 < 0.5), slides, slides


def study_incline(which, dt, T=1.0, **options):
    """Block on flat ground under gravity tilted by theta: sticks for tan theta < mu (x drift), else
    slides at g (sin theta - mu cos theta) (the acceleration of a quadratic fit of x over [0.3, T])."""
    cases, passes, seconds, ok = [], True, 0.0, True
    for theta, mu in INCLINE:
        scene = block_scene(f"incline {theta}/{mu}", [0.0, RADIUS], mu=mu,
                            gravity=(G * np.sin(theta), 0.0, -G * np.cos(theta)), settle=1.0)
        r = run(which, scene, dt, int(np.ceil(T / dt)), **options)
        seconds, ok = seconds + r.get("seconds", np.nan), ok and r["ok"]
        out = common_metrics(scene, r, dt)
        out.update({"theta": theta, "mu": mu, "sticks": bool(np.tan(theta) < mu)})
        if finite(r):
            x = r["Q"][:, 0]
            if out["sticks"]:
                out["drift"] = float(np.abs(x).max())
                good = out["drift"] <= PENETRATION_OK
            else:
                t = np.arange(len(x)) * dt
                late = t >= 0.3
                a = 2 * np.polyfit(t[late], x[late], 2)[0]
                exact = G * (np.sin(theta) - mu * np.cos(theta))
                out["acceleration_rel_error"] = float(abs(a - exact) / exact)
                good = out["acceleration_rel_error"] <= 1e-2
            out["passes"] = bool(out["ok"] and good and out["penetration_rest"] <= PENETRATION_OK)
        else:
            out["passes"] = False
        passes &= out["passes"]
        cases.append(out)
    # the three runs together: run time per simulated second over their 3 T
    return {"cases": cases, "passes": bool(passes), "simulated_s": sum(c.get("simulated_s", np.nan) for c in cases),
            **{k: max(c.get(k, np.inf) for c in cases) for k in ("penetration_max", "penetration_rest")}}, None, \
        {"ok": ok, "seconds": seconds}


def study_chain(which, dt, T=2.0, **options):
    """The 12-link chain dropped nearly flat: no explosion (the energy never above its initial value by
    more than 1% of the energy dissipated), penetration at most 1 mm over the second half, flat
    (every node within 1 mm of the ground) and at rest at the end."""
    scene = chain_scene()
    r = run(which, scene, dt, int(np.ceil(T / dt)), **options)
    out = common_metrics(scene, r, dt)
    out["passes"] = bool(out["ok"] and out["penetration_rest"] <= PENETRATION_OK and out["gap_end_max"] <= PENETRATION_OK
                         and out["energy_excess_over_initial"] <= 1e-2 * out["energy_dissipated"]
                         and out["speed_end"] <= 1e-2) if finite(r) else False
    return out, scene, r


def study_dog(which, dt, T=2.0, penetration_ok=PENETRATION_OK, **options):
    """LittleDog standing for T: over the second half of the run penetration and base drift at most
    1 mm; base height within 5 mm of q0's and base angles within 0.05 rad throughout."""
    scene = littledog_scene(dt)
    r = run(which, scene, dt, int(np.ceil(T / dt)), **options)
    out = common_metrics(scene, r, dt)
    if finite(r):
        Q = r["Q"]
        half = len(Q) // 2
        out["base_drift_second_half"] = float(np.abs(Q[half:, :3] - Q[half, :3]).max())
        out["base_height_offset"] = float(Q[-1, 2] - scene.q0[2])
        out["base_orientation_max"] = float(np.abs(Q[:, 3:6]).max())
        out["joint_offset_max"] = float(np.abs(Q[-1, 6:] - scene.q0[6:]).max())
        out["base_end"] = Q[-1, :6].tolist()
        out["passes"] = bool(out["ok"] and out["penetration_rest"] <= penetration_ok and abs(out["base_height_offset"]) <= 5e-3
                             and out["base_drift_second_half"] <= PENETRATION_OK and out["base_orientation_max"] <= 0.05)
    else:
        out["passes"] = False
    return out, scene, r


STUDIES = {"drop": (study_drop, 0.01), "slide": (study_slide, 0.01), "incline": (study_incline, 0.01),
           "chain": (study_chain, 0.005), "littledog": (study_dog, 0.005)}


def largest_dt(study, which, dt0, iterations, **kw):
    """The largest dt at which study(which, dt) passes: halve from dt0 until it passes (down to
    dt0 / 64), double until it fails (up to DT_CAP), then bisect (geometrically) between the last
    pass and the first failure ``iterations`` times. Every dt tried is recorded (a failure below a
    pass would show there: the criterion need not be monotone in dt)."""
    tried = []

    def passes(dt):
        ok = bool(study(which, dt, **kw)[0]["passes"])
        tried.append((float(dt), ok))
        return ok

    lo = dt0
    while not passes(lo):
        lo /= 2
        if lo < dt0 / 64:
            return {"largest": None, "tried": tried}
    hi = None
    while lo < DT_CAP:
        cand = min(2 * lo, DT_CAP)
        if passes(cand):
            lo = cand
        else:
            hi = cand
            break
    if hi is None:
        return {"largest": lo, "capped": True, "tried": tried}
    for _ in range(iterations):
        mid = float(np.sqrt(lo * hi))
        if passes(mid):
            lo = mid
        else:
            hi = mid
    return {"largest": float(lo), "first_failure": float(hi), "capped": False, "tried": tried}


def time_per_second(study, dts, repeats, **kw):
    """Best-of-``repeats`` run time per simulated second of hovi at dts['hovi'] and MuJoCo at
    dts['mujoco'], the two alternating; None for a simulator whose run failed."""
    best = {"hovi": np.inf, "mujoco": np.inf}
    for _ in range(repeats):
        for which in ("hovi", "mujoco"):
            if dts.get(which) is None:
                continue
            out, _, r = study(which, dts[which], **kw)
            if r is not None and r.get("ok"):
                best[which] = min(best[which], r["seconds"] / out["simulated_s"])
    return {k: (float(v) if np.isfinite(v) else None) for k, v in best.items()}


def cheapest(study, largest, repeats, **kw):
    """Run time per simulated second at every dt the search passed (``largest[which]['tried']``), best
    of ``repeats`` with hovi and MuJoCo alternating, and the cheapest of them: near its largest
    passing dt a simulator can cost more per simulated second than at a smaller one (hovi's Newton
    iterations grow there)."""
    passing = {w: sorted({dt for dt, ok in largest[w]["tried"] if ok}) for w in ("hovi", "mujoco")}
    best = {w: {dt: np.inf for dt in dts} for w, dts in passing.items()}
    for _ in range(repeats):
        for w in ("hovi", "mujoco"):
            for dt in passing[w]:
                best[w][dt] = min(best[w][dt], time_per_second(study, {w: dt}, 1, **kw)[w] or np.inf)
    out = {}
    for w, by_dt in best.items():
        finite_dts = {dt: t for dt, t in by_dt.items() if np.isfinite(t)}
        dt = min(finite_dts, key=finite_dts.get) if finite_dts else None
        out[w] = {"dt": dt, "time_per_s": finite_dts.get(dt), "by_dt": [[d, t] for d, t in sorted(finite_dts.items())]}
    return out


def contacts_scaling(ks, steps, dt, repeats):
    """Cost per step of a box resting on k contact points, hovi and MuJoCo alternating, best of repeats."""
    rows = []
    for k in ks:
        scene = box_scene(k)
        integ, sim = scene.integrator(dt), MuJoCo(scene, dt)
        best = {"hovi": np.inf, "mujoco": np.inf}
        info = {}
        for rep in range(repeats + 1):  # the first round warms up, not recorded
            rh = run_hovi(scene, dt, steps, integ)
            rm = run_mujoco(scene, dt, steps, sim)
            if rep:
                for which, r in (("hovi", rh), ("mujoco", rm)):
                    if r["ok"]:
                        best[which] = min(best[which], r["seconds"] / steps)
            for which, r in (("hovi", rh), ("mujoco", rm)):
                m = common_metrics(scene, r, dt)
                info[which] = {"ok": m.get("ok", False), "penetration_max": m.get("penetration_max"),
                               "drift": float(np.abs(r["Q"][-1] - scene.q0).max()) if "Q" in r else None}
        rows.append({"contacts": k, "hovi_per_step_s": float(best["hovi"]) if np.isfinite(best["hovi"]) else None,
                     "mujoco_per_step_s": float(best["mujoco"]) if np.isfinite(best["mujoco"]) else None, **{
                         f"{w}_{key}": v for w, d in info.items() for key, v in d.items()}})
    slopes = {}
    for which in ("hovi", "mujoco"):
        pts = [(r["contacts"], r[f"{which}_per_step_s"]) for r in rows if r[f"{which}_per_step_s"]]
        if len(pts) >= 2:
            slopes[which] = loglog_slope(*zip(*pts))
            big = [p for p in pts if p[0] >= 4]
            slopes[f"{which}_k>=4"] = loglog_slope(*zip(*big)) if len(big) >= 2 else None
    return rows, slopes


# ------------------------------------------------------------------------------------------ main

SLIDE_DTS = [0.01, 0.005, 0.0025]                     # the issue's three dts
SLIDE_SWEEP = [0.02, 0.015, 0.01, 0.0075, 0.005, 0.004, 0.0025, 0.002, 0.0015, 0.001]  # for the order in dt
LABELS = {"drop": "block drop (2 kg, 0.1 m)", "slide": "sliding stop (v0 1 m/s, mu 0.5)",
          "incline": "incline (theta/mu 0.3/0.5 sticks; 0.3/0.2, 0.5/0.5 slide)",
          "chain": "12-link chain, 13 contacts, dropped", "littledog": "LittleDog standing (4 feet)"}


def main():
    ap = study_parser(__doc__, "short runs, coarse dt searches, 3 contact counts, 1 repeat")
    ap.add_argument("--repeats", type=int, default=5, help="timing repeats (best of; default 5)")
    args = ap.parse_args()
    quick = args.quick
    repeats = 1 if quick else args.repeats
    bisect = 1 if quick else 5
    horizon = {"drop": 0.5, "slide": 0.3, "incline": 0.6, "chain": 0.5, "littledog": 1.0} if quick else \
        {"drop": 1.0, "slide": 0.5, "incline": 1.0, "chain": 2.0, "littledog": 5.0}
    t_start, load_start = time.perf_counter(), os.getloadavg()

    scenes = {"drop": block_scene("drop", [0.0, 0.1]), "chain": chain_scene(), "littledog": littledog_scene(),
              "box (k = 8)": box_scene(8)}
    agreement = {name: check(s) for name, s in scenes.items()}
    print("MuJoCo vs hovi, largest relative differences:", agreement)

    results = {}
    # 1 - 5: each scene at its dt (the same for both), the largest dt each passes at, run times at both
    for name, (study, dt0) in STUDIES.items():
        T = horizon[name]
        row = {"dt": dt0, "T": T, "largest_dt": {}}
        for which in ("hovi", "mujoco"):
            row[which] = study(which, dt0, T=T)[0]
            row["largest_dt"][which] = largest_dt(study, which, dt0, bisect, T=T)
        dts = {w: row["largest_dt"][w]["largest"] for w in ("hovi", "mujoco")}
        time_per_second(study, {"hovi": dt0, "mujoco": dt0}, 1, T=T)  # warm-up, not recorded
        row["time_per_s_at_dt"] = time_per_second(study, {"hovi": dt0, "mujoco": dt0}, repeats, T=T)
        row["time_per_s_at_largest_dt"] = time_per_second(study, dts, repeats, T=T)
        row["cheapest_passing"] = cheapest(study, row["largest_dt"], repeats, T=T)
        results[name] = row
        print(f"{name}: {summary_line(row)}", flush=True)
    dog = study_dog("mujoco", 0.002, T=horizon["littledog"])[0]
    dog["time_per_s"] = time_per_second(study_dog, {"mujoco": 0.002}, repeats, T=horizon["littledog"])["mujoco"]
    results["littledog"]["mujoco_default_dt"] = {"dt": 0.002, **dog}
    # MuJoCo's LittleDog dt is set by the 1 mm bound on its resting penetration: the same search with
    # 5 mm instead (the base drift bound kept), and its run time there
    relaxed = largest_dt(study_dog, "mujoco", 0.00125, bisect, T=horizon["littledog"], penetration_ok=5e-3)
    relaxed_dt = relaxed["largest"]
    relaxed["time_per_s"] = time_per_second(study_dog, {"mujoco": relaxed_dt}, repeats, T=horizon["littledog"],
                                            penetration_ok=5e-3)["mujoco"] if relaxed_dt else None
    relaxed["at_largest"] = study_dog("mujoco", relaxed_dt, T=horizon["littledog"], penetration_ok=5e-3)[0] if relaxed_dt else None
    results["littledog"]["mujoco_penetration_bound_5mm"] = relaxed
    results["traces"] = traces(horizon, results)

    # 2: the stop distance at the issue's three dts and over a finer sweep (MuJoCo: pyramidal and elliptic cones)
    sweep = SLIDE_DTS if quick else sorted(set(SLIDE_SWEEP) | set(SLIDE_DTS), reverse=True)
    variants = {"hovi": ("hovi", {}), "MuJoCo (pyramidal)": ("mujoco", {}), "MuJoCo (elliptic)": ("mujoco", {"cone": "elliptic"})}
    sliding = {k: {} for k in variants}
    for dt in sweep:
        for k, (which, options) in variants.items():
            out = study_slide(which, dt, T=horizon["slide"], **options)[0]
            sliding[k][dt] = {key: out.get(key) for key in ("stop_distance", "stop_error_rel", "penetration_max",
                                                            "penetration_rest", "rebound", "passes")}
    orders = {}
    for k, by_dt in sliding.items():
        for label, dts in (("issue_dts", SLIDE_DTS), ("sweep", sweep)):
            errs = [by_dt[dt].get("stop_error_rel") for dt in dts]
            ok = all(e is not None and e > 0 for e in errs)
            orders.setdefault(k, {})[label] = loglog_slope(dts, errs) if ok else None
        orders[k]["largest_error_over_sweep"] = max(by_dt[dt]["stop_error_rel"] or np.inf for dt in sweep)
    results["sliding_vs_dt"] = {"issue_dts": SLIDE_DTS, "sweep": sweep, "exact": 1.0 / (2 * 0.5 * G),
                                "runs": {k: [{"dt": dt, **v} for dt, v in by_dt.items()] for k, by_dt in sliding.items()},
                                "order": orders}

    # 6: cost per step against the number of contacts
    ks = [1, 4, 16] if quick else [1, 2, 4, 8, 16, 32]
    steps = 50 if quick else 400
    rows, slopes = contacts_scaling(ks, steps, 0.005, repeats)
    results["contacts_scaling"] = {"dt": 0.005, "steps": steps, "rows": rows, "slopes": slopes}
    results["goals"] = goals(results)

    load = os.getloadavg()
    name = "contact_sim_quick" if quick else "contact_sim"
    commit = hovi_commit()
    payload = {"quick": quick, "hovi_commit": commit, "repeats": repeats, "bisection_steps": bisect, "horizons_s": horizon,
               "load_average_start": load_start, "load_average_end": load, "mujoco_version": mujoco.__version__,
               "mujoco_settings": mujoco_settings(), "model_agreement": agreement, "criteria": CRITERIA,
               "results": results, "wall_seconds": time.perf_counter() - t_start}
    path = write_json(f"{name}.json", json_ready(payload))
    text = table(results, load_start, load, repeats, horizon)
    print(text)
    try:
        plot(results, f"{RESULTS}/{name}.png")
    except ImportError:
        print("matplotlib missing: no plot")
    print(f"wrote {path} in {time.perf_counter() - t_start:.1f} s")
    if not quick:
        update_readme_section("contact_sim", text)


def traces(horizon, results):
    """Gap of the lowest sphere against time at each scene's dt, both simulators, for the plot: the
    drop, the chain and LittleDog (there also MuJoCo at its default dt and at the cheapest dt at
    which it passed)."""
    out = {}
    for name, make in (("drop", lambda: block_scene("drop", [0.0, 0.1 + RADIUS])), ("chain", chain_scene),
                       ("littledog", littledog_scene)):
        dt0 = STUDIES[name][1]
        runs = [("hovi", dt0), ("mujoco", dt0)]
        if name == "littledog":
            runs += [("mujoco", 0.002), ("mujoco", results[name]["cheapest_passing"]["mujoco"]["dt"])]
        for which, dt in runs:
            if dt is None:
                continue
            scene = make()
            steps = int(np.ceil(horizon[name] / dt))
            r = run(which, scene, dt, steps)
            if finite(r):
                out.setdefault(name, {})[f"{which}, dt = {dt:.3g}"] = {
                    "t": (np.arange(steps + 1) * dt).tolist(), "lowest_gap": scene.gaps(r["Q"]).min(1).tolist()}
    return out


CRITERIA = {  # 'penetration' here: over the second half of the run (at rest); the impact's is reported apart
    "drop": "finite; penetration <= 1 mm; rebound <= 1 mm; at the end resting (|gap| <= 1 mm, speed <= 1e-3) with the normal force within 1% of m g",
    "slide": "finite; penetration <= 1 mm; stop distance within 1% of v0^2/(2 mu g); stopped (speed <= 1e-4)",
    "incline": "finite; penetration <= 1 mm; the sticking case drifts <= 1 mm in 1 s; the sliding cases accelerate within 1% of g (sin - mu cos)",
    "chain": "finite; energy never above the initial by more than 1% of the energy dissipated; penetration <= 1 mm; flat (gaps <= 1 mm) and at rest (speed <= 1e-2) at the end",
    "littledog": "finite; penetration and base drift <= 1 mm over the second half; base height within 5 mm of q0's and base angles <= 0.05 rad throughout",
}


def goals(results):
    """The issue's three goals, measured."""
    pen = max(results[n]["hovi"].get("penetration_max", np.inf) for n in STUDIES)
    pen = max([pen] + [r["hovi_penetration_max"] or 0.0 for r in results["contacts_scaling"]["rows"]])
    slide = {r["dt"]: r["stop_error_rel"] for r in results["sliding_vs_dt"]["runs"]["hovi"]}
    dog = results["littledog"]["cheapest_passing"]
    t_h, t_m = dog["hovi"]["time_per_s"], dog["mujoco"]["time_per_s"]
    return {"hovi_penetration_max": pen, "hovi_penetration_goal_met": pen <= 1e-9,
            "stop_error_at_0.01": slide.get(0.01), "stop_error_goal_met": (slide.get(0.01) or np.inf) <= 1e-3,
            "littledog_time_per_s": {"hovi": t_h, "mujoco": t_m, "hovi_dt": dog["hovi"]["dt"], "mujoco_dt": dog["mujoco"]["dt"]},
            "littledog_time_goal_met": bool(t_h is not None and (t_m is None or t_h <= t_m))}


def mujoco_settings():
    m = mujoco.MjModel.from_xml_string(mjcf(block_scene("drop", [0, 0.1]), 0.01))
    g = m.geom(0)
    return {"integrator": "Euler (semi-implicit; joint dampers implicit)", "cone": "pyramidal (elliptic: a second sliding row)",
            "condim": int(g.condim[0]), "solref": g.solref.tolist(), "solimp": g.solimp.tolist(),
            "solver": int(m.opt.solver), "solver_name": "Newton", "tolerance": float(m.opt.tolerance),
            "iterations": int(m.opt.iterations), "margin": float(g.margin[0]),
            "refsafe": "on: solref's time constant is raised to 2 dt when smaller", "sphere_radius": RADIUS}


def _f(x, fmt=".1e"):
    return "—" if x is None or (isinstance(x, float) and not np.isfinite(x)) else format(x, fmt)


def _dt(big):
    if big["largest"] is None:
        return "none ≥ dt/64"
    return f"≥ {big['largest']:.3g}" if big.get("capped") else f"{big['largest']:.3g}"


def summary_line(row):
    h, m = row["hovi"], row["mujoco"]
    return (f"penetration {_f(h.get('penetration_max'))} / {_f(m.get('penetration_max'))} m, "
            f"largest dt {_dt(row['largest_dt']['hovi'])} / {_dt(row['largest_dt']['mujoco'])}, "
            f"time per simulated s {_f(row['time_per_s_at_dt']['hovi'], '.3g')} / {_f(row['time_per_s_at_dt']['mujoco'], '.3g')} s")


def scene_error(name, out):
    """The scene's closed-form / physical error, as text."""
    if name == "drop":
        return f"normal force {_f(out.get('normal_force_rel_error'))} rel.; rebound {_f(out.get('rebound'))} m"
    if name == "slide":
        return f"stop distance {_f(out.get('stop_error_rel'))} rel.; lift {_f(out.get('rebound'))} m"
    if name == "incline":
        c = out["cases"]
        return (f"stick drift {_f(c[0].get('drift'))} m; accel. {_f(c[1].get('acceleration_rel_error'))}, "
                f"{_f(c[2].get('acceleration_rel_error'))} rel.")
    if name == "chain":
        return f"end: highest node {_f(out.get('gap_end_max'))} m, speed {_f(out.get('speed_end'))}"
    if name == "littledog":
        return (f"base height {_f(out.get('base_height_offset'))} m from q0, drift {_f(out.get('base_drift_second_half'))} m")
    return ""


def energy_text(name, out):
    if name == "littledog":
        return "(PD + feed-forward: not conservative)"
    if "cases" in out:
        rises = [c.get("energy_rise_after_impact") for c in out["cases"] if c.get("energy_rise_after_impact") is not None]
        return "largest rise " + _f(max(rises) if rises else None) + " J"
    return f"largest rise {_f(out.get('energy_rise_after_impact'))} J ({_f(out.get('energy_rise_rel'))} of dissipated)"


def table(results, load_start, load_end, repeats, horizon):
    lines = ["| scene | simulator | dt [s] | penetration: largest / at rest [m] | error | energy after the first impact | "
             "time per simulated s at dt [ms] | largest stable dt [s] | time per simulated s at the cheapest passing dt [ms] (dt) |",
             "|---|---|---|---|---|---|---|---|---|"]
    ms = lambda x: _f(x * 1e3 if x is not None else None, ".3g")  # noqa: E731
    for name, label in LABELS.items():
        row = results[name]
        for which, wname in (("hovi", "hovi"), ("mujoco", "MuJoCo")):
            out = row[which]
            lines.append(f"| {label} (T = {horizon[name]:g} s) | {wname} | {row['dt']:g} | {_f(out.get('penetration_max'))} / "
                         f"{_f(out.get('penetration_rest'))} | {scene_error(name, out)} | {energy_text(name, out)} | "
                         f"{ms(row['time_per_s_at_dt'][which])} | {_dt(row['largest_dt'][which])} | "
                         f"{ms(row['cheapest_passing'][which]['time_per_s'])} ({_f(row['cheapest_passing'][which]['dt'], '.3g')}) |")
    dog = results["littledog"]["mujoco_default_dt"]
    lines.append(f"| {LABELS['littledog']} | MuJoCo at its default dt | 0.002 | {_f(dog.get('penetration_max'))} / "
                 f"{_f(dog.get('penetration_rest'))} | {scene_error('littledog', dog)} | | {ms(dog.get('time_per_s'))} | | |")
    rel = results["littledog"]["mujoco_penetration_bound_5mm"]
    if rel.get("at_largest"):
        a = rel["at_largest"]
        lines.append(f"| {LABELS['littledog']}, penetration bound 5 mm | MuJoCo at its largest passing dt | "
                     f"{_f(rel['largest'], '.3g')} | {_f(a.get('penetration_max'))} / {_f(a.get('penetration_rest'))} | "
                     f"{scene_error('littledog', a)} | | {ms(rel.get('time_per_s'))} | {_dt(rel)} | |")
    s = results["sliding_vs_dt"]
    by = {k: {r["dt"]: r for r in rows} for k, rows in s["runs"].items()}
    lines += ["", f"Sliding stop distance, relative error against v0²/(2 mu g) = {s['exact']:.6f} m (T = "
              f"{horizon['slide']:g} s), and its order in dt (log-log slope over the issue's three dts; over the sweep "
              f"{max(s['sweep']):g}..{min(s['sweep']):g}):", "",
              "| simulator | " + " | ".join(f"dt = {dt:g}" for dt in s["issue_dts"]) +
              " | order (3 dts) | order (sweep) | largest error over the sweep |",
              "|---|" + "---|" * (len(s["issue_dts"]) + 3)]
    for k in s["runs"]:
        o = s["order"][k]
        lines.append(f"| {k} | " + " | ".join(_f(by[k][dt].get("stop_error_rel")) for dt in s["issue_dts"]) +
                     f" | {_f(o['issue_dts'], '.2f')} | {_f(o['sweep'], '.2f')} | {_f(o['largest_error_over_sweep'])} |")
    c = results["contacts_scaling"]
    lines += ["", f"Cost per step of a box resting on k contact points (dt = {c['dt']:g}, {c['steps']} steps, best of "
              f"{repeats}):", "", "| k | hovi [µs] | MuJoCo [µs] | hovi / MuJoCo | hovi penetration [m] | MuJoCo penetration [m] |",
              "|---|---|---|---|---|---|"]
    for r in c["rows"]:
        h, m = r["hovi_per_step_s"], r["mujoco_per_step_s"]
        lines.append(f"| {r['contacts']} | {_f(h * 1e6 if h else None, '.1f')} | {_f(m * 1e6 if m else None, '.1f')} | "
                     f"{_f(h / m if h and m else None, '.2f')} | {_f(r.get('hovi_penetration_max'))} | "
                     f"{_f(r.get('mujoco_penetration_max'))} |")
    sl = c["slopes"]
    g = results["goals"]
    d = g["littledog_time_per_s"]
    lines += ["", f"Log-log slope of the cost per step in k: hovi {_f(sl.get('hovi'), '.2f')} (k ≥ 4: "
              f"{_f(sl.get('hovi_k>=4'), '.2f')}), MuJoCo {_f(sl.get('mujoco'), '.2f')} (k ≥ 4: {_f(sl.get('mujoco_k>=4'), '.2f')}).",
              "", "The issue's goals: "
              f"hovi's penetration ≤ 1e-9 m: largest {_f(g['hovi_penetration_max'])} m over every run above "
              f"({'met' if g['hovi_penetration_goal_met'] else 'NOT met'}); stop-distance error ≤ 1e-3 at dt = 0.01: "
              f"{_f(g['stop_error_at_0.01'])} ({'met' if g['stop_error_goal_met'] else 'NOT met'}); LittleDog standing, run "
              f"time per simulated second at the cheapest dt at which each passes the standing criterion: hovi "
              f"{ms(d['hovi'])} ms (dt {_f(d['hovi_dt'], '.3g')}) against MuJoCo {ms(d['mujoco'])} ms (dt "
              f"{_f(d['mujoco_dt'], '.3g')}): {'met' if g['littledog_time_goal_met'] else 'NOT met (hovi is slower)'}.",
              "", f"Load average: {load_start[0]:.2f} / {load_start[1]:.2f} / {load_start[2]:.2f} at the start, "
              f"{load_end[0]:.2f} / {load_end[1]:.2f} / {load_end[2]:.2f} at the end (1 / 5 / 15 min)."]
    return "\n".join(lines)


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(2, 3, figsize=(17, 9))
    ax = axes[0][0]
    s = results["sliding_vs_dt"]
    for k, rows in s["runs"].items():
        pts = [(r["dt"], r["stop_error_rel"]) for r in rows if r.get("stop_error_rel")]
        if pts:
            ax.loglog(*zip(*sorted(pts)), "o-", label=k)
    ax.axhline(1e-3, color="k", lw=0.6, ls=":")
    ax.set_xlabel("dt [s]")
    ax.set_ylabel("stop distance, relative error")
    ax.set_title("sliding stop (dotted: the goal at dt = 0.01)")
    ax.legend(fontsize=8)
    ax = axes[0][1]
    c = results["contacts_scaling"]
    for which in ("hovi", "mujoco"):
        pts = [(r["contacts"], r[f"{which}_per_step_s"] * 1e6) for r in c["rows"] if r[f"{which}_per_step_s"]]
        if pts:
            ax.loglog(*zip(*pts), "o-", label=f"{which} (slope {c['slopes'].get(which) or float('nan'):.2f})")
    ax.set_xlabel("contact points k")
    ax.set_ylabel("cost per step [µs]")
    ax.set_title(f"box resting on k points, dt = {c['dt']:g}")
    ax.legend(fontsize=8)
    ax = axes[0][2]
    names = list(LABELS)
    x = np.arange(len(names))
    for j, which in enumerate(("hovi", "mujoco")):
        for hatch, off in (("", 0.0), ("//", 0.4)):
            vals = [(results[n]["time_per_s_at_dt"][which] if not hatch else
                     results[n]["cheapest_passing"][which]["time_per_s"]) or np.nan for n in names]
            ax.bar(x + off + (j - 0.5) * 0.19, vals, 0.19, color=f"C{j}", hatch=hatch,
                   label=f"{which}, {'scene dt' if not hatch else 'cheapest dt passing the criteria'}")
    ax.set_yscale("log")
    ax.set_xticks(x + 0.2)
    ax.set_xticklabels(names, fontsize=8)
    ax.set_ylabel("run time per simulated second [s]")
    ax.set_title("run time")
    ax.legend(fontsize=7)
    for ax, name in zip(axes[1], ("drop", "chain", "littledog")):
        for label, tr in results["traces"].get(name, {}).items():
            ax.plot(tr["t"], np.array(tr["lowest_gap"]) * 1e3, label=label, lw=0.9)
        ax.axhline(0, color="k", lw=0.5)
        ax.set_xlabel("t [s]")
        ax.set_ylabel("lowest sphere's gap [mm] (< 0: penetration)")
        ax.set_title(LABELS[name], fontsize=9)
        ax.set_ylim(-20 if name != "drop" else -5, 5 if name != "drop" else 10)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
