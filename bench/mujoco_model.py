"""MuJoCo's counterpart of a hovi model, for the benchmarks against MuJoCo (pareto.py,
energy_runtime.py): the MJCF of the same kinematic tree, a check that both libraries compute the
same dynamics, and a rollout timed in MuJoCo's own C loop.

The joint types, parents, axes, placements, masses, centres of mass and gravity are read from the
hovi model (``joint_placements`` and ``spatial_twists`` at q = 0, ``body_poses``, ``masses``,
``gravity``). hovi's Python API does not expose the bodies' rotational inertias, so they are
passed in (``pendulum_inertias``: the solid cylinders of ``hovi.examples.models.pendulum``); ``check``
compares the mass matrices, accelerations, poses and energies and so catches any mismatch.
MuJoCo gets no damping, armature, friction loss, joint limits or contacts.
"""
from __future__ import annotations

import copy
import sys
import time

import numpy as np

try:
    import mujoco
    from mujoco import rollout as mj_rollout
except ImportError:  # a clear message instead of a traceback: MuJoCo is a benchmark-only dependency
    sys.exit("the MuJoCo comparison needs the `mujoco` package: .venv/bin/pip install 'mujoco>=3.2' "
             "(it is in requirements-dev.txt and the `bench` extra)")

# MuJoCo's warnings (an unstable run) would go to stderr and MUJOCO_LOG.TXT in the working
# directory; the runs read them from mjData.warning instead (Runner.run), so silence them here.
mujoco.set_mju_user_warning(lambda message: None)

JOINT_TYPES = {"revolute": "hinge", "prismatic": "slide"}
BAD = [mujoco.mjtWarning.mjWARN_BADQPOS, mujoco.mjtWarning.mjWARN_BADQVEL, mujoco.mjtWarning.mjWARN_BADQACC]


def pendulum_inertias(n: int, length: float = 0.5, mass: float = 1.0, radius: float = 0.02) -> list:
    """Rotational inertias about the centre of mass (joint-frame axes) of ``hovi.examples.models.pendulum``:
    uniform solid cylinders along z."""
    transverse, axial = mass * (3 * radius ** 2 + length ** 2) / 12, mass * radius ** 2 / 2
    return [np.diag([transverse, transverse, axial])] * n


def _vec(v) -> str:
    return " ".join(repr(float(x)) for x in v)


def mjcf(model, inertias, integrator: str = "RK4", dt: float = 0.01, energy: bool = False) -> str:
    """The MJCF of hovi ``model`` (a fixed-base tree of revolute / prismatic joints)."""
    n, q0 = model.n, np.zeros(model.n)
    oMi, g = model.joint_placements(q0), model.body_poses(q0)
    twists = model.spatial_twists(q0)
    children = {i: [] for i in range(-1, n)}
    for i, parent in enumerate(model.parents):
        children[parent].append(i)

    def body(i, indent):
        kind = model.joint_types[i]
        if kind not in JOINT_TYPES:
            raise ValueError(f"mujoco_model: joint {model.joint_names[i]} is {kind}; only revolute and prismatic are mapped")
        parent = model.parents[i]
        local = oMi[i] if parent < 0 else np.linalg.inv(oMi[parent]) @ oMi[i]  # placement in the parent's joint frame
        quat = np.zeros(4)
        mujoco.mju_mat2Quat(quat, local[:3, :3].flatten())
        R = oMi[i][:3, :3]
        s = twists[i][:3] if kind == "revolute" else twists[i][3:]  # world axis at q = 0 -> joint frame
        axis = R.T @ s
        com = (np.linalg.inv(oMi[i]) @ g[i][:, 3])[:3]
        I = np.asarray(inertias[i], dtype=float)
        pad = " " * indent
        lines = [f'{pad}<body name="{model.body_names[i]}" pos="{_vec(local[:3, 3])}" quat="{_vec(quat)}">',
                 f'{pad}  <inertial pos="{_vec(com)}" mass="{float(model.masses[i])!r}" '
                 f'fullinertia="{_vec([I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]])}"/>',
                 f'{pad}  <joint name="{model.joint_names[i]}" type="{JOINT_TYPES[kind]}" axis="{_vec(axis)}"/>']
        for c in children[i]:
            lines += body(c, indent + 2)
        return lines + [f"{pad}</body>"]

    tree = [line for root in children[-1] for line in body(root, 4)]
    flags = f'contact="disable" constraint="disable" autoreset="disable" energy="{"enable" if energy else "disable"}"'
    return "\n".join([
        '<mujoco model="hovi">',
        '  <compiler angle="radian" inertiafromgeom="false" autolimits="true"/>',
        f'  <option timestep="{dt!r}" integrator="{integrator}" gravity="{_vec(model.gravity)}">',
        f"    <flag {flags}/>",
        "  </option>",
        '  <default><joint armature="0" damping="0" frictionloss="0" stiffness="0" limited="false"/></default>',
        "  <worldbody>", *tree, "  </worldbody>",
        "</mujoco>"])


def build(model, inertias, integrator: str = "RK4", dt: float = 0.01, energy: bool = False):
    return mujoco.MjModel.from_xml_string(mjcf(model, inertias, integrator, dt, energy))


def check(model, inertias, states: int = 5, rtol: float = 1e-10, seed: int = 1) -> dict:
    """Largest relative differences between MuJoCo and hovi at random states (q uniform in ±π,
    q̇ normal): mass matrix (mj_fullM), accelerations (qacc after mj_forward), joint frames and
    centres of mass (xpos, xmat, xipos: the same q is the same configuration) and energy
    (mjData.energy, energy flag on). Exits with a message if any exceeds rtol."""
    m = build(model, inertias, energy=True)
    d = mujoco.MjData(m)
    rng = np.random.default_rng(seed)
    worst = {"mass_matrix": 0.0, "qacc": 0.0, "poses": 0.0, "energy": 0.0}
    M = np.zeros((m.nv, m.nv))
    for _ in range(states):
        q, qd = rng.uniform(-np.pi, np.pi, model.n), rng.normal(0.0, 1.0, model.n)
        d.qpos[:], d.qvel[:] = q, qd
        mujoco.mj_forward(m, d)
        full_mass_matrix(m, d, M)
        Mh, ah = model.mass_matrix(q), model.forward_dynamics(q, qd)
        oMi, g = model.joint_placements(q), model.body_poses(q)
        pose_diff = max(np.abs(d.xpos[1:] - oMi[:, :3, 3]).max(), np.abs(d.xmat[1:].reshape(-1, 3, 3) - oMi[:, :3, :3]).max(),
                        np.abs(d.xipos[1:] - g[:, :3, 3]).max())
        E = model.energy(q, qd)
        worst["mass_matrix"] = max(worst["mass_matrix"], np.abs(M - Mh).max() / np.abs(Mh).max())
        worst["qacc"] = max(worst["qacc"], np.abs(d.qacc - ah).max() / np.abs(ah).max())
        worst["poses"] = max(worst["poses"], pose_diff / max(1.0, np.abs(oMi[:, :3, 3]).max()))
        worst["energy"] = max(worst["energy"], abs(d.energy.sum() - E) / abs(E))
    bad = {k: float(v) for k, v in worst.items() if not v <= rtol}
    if bad:
        sys.exit(f"MuJoCo's model does not match hovi's (relative differences {bad}, tolerance {rtol:g}): "
                 "fix bench/mujoco_model.py before timing anything")
    return {k: float(v) for k, v in worst.items()}


def describe(agreement: dict) -> str:
    """One README line from {n: check(...)}."""
    worst = {k: max(a[k] for a in agreement.values()) for k in next(iter(agreement.values()))}
    return (f"MuJoCo {mujoco.__version__} against hovi at random states (n = {', '.join(map(str, agreement))}), "
            "largest relative difference: " + ", ".join(f"{k.replace('_', ' ')} {v:.1e}" for k, v in worst.items())
            + " (the scripts stop above 1e-10).")


def full_mass_matrix(m, d, M):
    """mj_fullM into M: mj_fullM(m, d, M) in recent MuJoCo, mj_fullM(m, M, d.qM) in older ones."""
    try:
        mujoco.mj_fullM(m, d, M)
    except TypeError:
        mujoco.mj_fullM(m, M, d.qM)


class Runner:
    """Fixed-step rollouts of one MuJoCo model from rest: ``run(q0, steps)`` -> (q (steps+1, n),
    qdot (steps+1, n), seconds, ok). Timed: one call of MuJoCo's rollout (``mujoco.rollout``, in
    the calling thread: MuJoCo's C loop of mj_step, writing the state after every step), nothing
    else. ok: the states are finite and MuJoCo raised no bad-qpos/qvel/qacc warning (automatic
    reset is off, so an unstable run is not silently restarted)."""

    SPEC = mujoco.mjtState.mjSTATE_FULLPHYSICS

    def __init__(self, mj_model):
        self.m, self.d = mj_model, mujoco.MjData(mj_model)
        self.nstate = mujoco.mj_stateSize(mj_model, self.SPEC)
        self.pool = mj_rollout.Rollout(nthread=0)  # nthread = 0: in the calling thread

    def run(self, q0, steps):
        m, d = self.m, self.d
        mujoco.mj_resetData(m, d)
        d.qpos[:] = q0
        x0 = np.zeros(self.nstate)
        mujoco.mj_getState(m, d, x0, self.SPEC)
        out = np.empty((1, steps, self.nstate))
        t = time.perf_counter()
        self.pool.rollout([m], [d], x0[None], nstep=steps, state=out, skip_checks=True)
        seconds = time.perf_counter() - t
        x = np.concatenate([x0[None], out[0]])
        q, qd = x[:, 1:1 + m.nq], x[:, 1 + m.nq:1 + m.nq + m.nv]  # FULLPHYSICS: time, qpos, qvel, ...
        warned = any(d.warning[w].number for w in BAD)
        return q, qd, seconds, bool(np.isfinite(x).all()) and not warned

    def energies(self, q, qd):
        """K + V from mjData.energy (energy flag on, a copy of the model) at each state; not timed."""
        m = copy.copy(self.m)
        m.opt.enableflags |= mujoco.mjtEnableBit.mjENBL_ENERGY
        d, E = mujoco.MjData(m), np.empty(len(q))
        for k in range(len(q)):
            d.qpos[:], d.qvel[:] = q[k], qd[k]
            mujoco.mj_forward(m, d)
            E[k] = d.energy.sum()
        return E
