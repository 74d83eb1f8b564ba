"""Cross-check hovi's kinematics and dynamics against Pinocchio.

Models compared (all with a fixed base on both sides):

* hovi's built-in n-link pendulum (n = 1, 5, 32), rebuilt independently in Pinocchio from its
  documented geometry and inertia (not from hovi's data);
* example-robot-data URDFs: an arm (Franka panda), a quadruped (solo12) and a humanoid
  (talos_reduced), loaded by ``hovi.Model.from_urdf`` and ``pin.buildModelFromUrdf``/``...XML``.

Quantities: joint-frame poses, COM-frame poses, spatial velocities, kinetic and potential energy,
mass matrix, forward dynamics (ABA with gravity) and inverse dynamics (RNEA), at several random
(fixed-seed) states. Joints are matched between the two libraries by name. Everything must agree
to 1e-10 relative (absolute tolerance 1e-10 times the magnitude of the quantity compared).
"""
import functools

import numpy as np
import pytest

import hovi
from conftest import erd_urdf

pin = pytest.importorskip("pinocchio")

RTOL = 1e-10
N_SAMPLES = 6

PANDA = "panda_description/urdf/panda.urdf"
SOLO12 = "solo_description/robots/solo12.urdf"
TALOS = "talos_data/robots/talos_reduced.urdf"


# --------------------------------------------------------------------------------------------
# Model construction
# --------------------------------------------------------------------------------------------


def pin_pendulum(n, length=0.5, mass=1.0, radius=0.02):
    """The pendulum of ``hovi.examples.models.pendulum``, built from its documented description."""
    model = pin.Model()
    I_t = mass * (3 * radius**2 + length**2) / 12
    I_a = mass * radius**2 / 2
    inertia = pin.Inertia(mass, np.array([0.0, 0.0, -length / 2]), np.diag([I_t, I_t, I_a]))
    parent = 0
    for i in range(1, n + 1):
        joint = pin.JointModelRX() if i % 2 == 1 else pin.JointModelRY()
        offset = np.zeros(3) if i == 1 else np.array([0.0, 0.0, -length])
        placement = pin.SE3(np.eye(3), offset)
        parent = model.addJoint(parent, joint, placement, f"joint{i}")
        model.appendBodyToJoint(parent, inertia, pin.SE3.Identity())
    model.gravity = pin.Motion(np.array([0.0, 0.0, -9.81]), np.zeros(3))
    return model


class Pair:
    """A hovi model and the equivalent Pinocchio model, with the joint mapping between them."""

    def __init__(self, name, h, pm):
        self.name = name
        self.h = h
        self.pm = pm
        self.pd = pm.createData()
        names = list(pm.names)
        assert h.n == pm.nv, f"{name}: hovi has {h.n} DoF, Pinocchio nv = {pm.nv}"
        assert sorted(h.joint_names) == sorted(names[1:]), f"{name}: joint names differ"
        # jid[i]: Pinocchio joint id of hovi joint i
        self.jid = [names.index(jn) for jn in h.joint_names]  # plain ints (pinocchio containers)
        self.vidx = np.array([pm.idx_vs[j] for j in self.jid])
        for j in self.jid:
            assert pm.nvs[j] == 1 and pm.nqs[j] in (1, 2), f"{name}: joint {names[j]} is not 1-DoF"
        types = np.array(h.joint_types)
        self.revolute = types == "revolute"

    # -- state conversion (hovi order -> Pinocchio vectors) --
    def q_pin(self, q):
        qp = pin.neutral(self.pm)
        for i, j in enumerate(self.jid):
            k = self.pm.idx_qs[j]
            if self.pm.nqs[j] == 2:  # continuous joint: (cos θ, sin θ)
                qp[k : k + 2] = np.cos(q[i]), np.sin(q[i])
            else:
                qp[k] = q[i]
        return qp

    def v_pin(self, v):
        vp = np.zeros(self.pm.nv)
        vp[self.vidx] = v
        return vp

    def v_hovi(self, vp):
        return np.asarray(vp)[self.vidx]

    # -- random states (hovi order) --
    def random_q(self, rng):
        return np.where(
            self.revolute,
            rng.uniform(-np.pi, np.pi, self.h.n),
            rng.uniform(-0.5, 0.5, self.h.n),
        )

    def random_v(self, rng, scale=2.0):
        return rng.uniform(-scale, scale, self.h.n)


# A small URDF exercising what the robots above do not: a continuous joint (nq = 2 in Pinocchio),
# unaligned revolute/prismatic axes, rotated joint origins and inertial frames with products of
# inertia, and a fixed joint whose child's inertia must be merged into the parent body.
SYNTHETIC_URDF = """<?xml version="1.0"?>
<robot name="synthetic">
  <link name="base">
    <inertial><mass value="3.0"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>
  </link>
  <link name="l1">
    <inertial>
      <origin xyz="0.05 -0.02 0.1" rpy="0.3 -0.2 0.5"/>
      <mass value="1.3"/>
      <inertia ixx="0.02" ixy="0.001" ixz="-0.002" iyy="0.03" iyz="0.0015" izz="0.025"/>
    </inertial>
  </link>
  <link name="l1_tool">
    <inertial>
      <origin xyz="0.0 0.03 -0.01" rpy="0.1 0.2 0.3"/>
      <mass value="0.4"/>
      <inertia ixx="0.004" ixy="0.0002" ixz="0" iyy="0.005" iyz="-0.0003" izz="0.003"/>
    </inertial>
  </link>
  <link name="l2">
    <inertial>
      <origin xyz="0.1 0.0 0.0" rpy="0 0.4 0"/>
      <mass value="0.8"/>
      <inertia ixx="0.01" ixy="0" ixz="0.001" iyy="0.012" iyz="0" izz="0.008"/>
    </inertial>
  </link>
  <link name="l3">
    <inertial>
      <origin xyz="0.0 0.0 -0.15" rpy="-0.2 0.1 1.0"/>
      <mass value="0.6"/>
      <inertia ixx="0.006" ixy="-0.0005" ixz="0.0004" iyy="0.007" iyz="0.0002" izz="0.004"/>
    </inertial>
  </link>
  <link name="l4">
    <inertial>
      <origin xyz="0.02 0.01 0.03"/>
      <mass value="0.25"/>
      <inertia ixx="0.001" ixy="0" ixz="0" iyy="0.002" iyz="0" izz="0.0015"/>
    </inertial>
  </link>
  <joint name="j_cont" type="continuous">
    <parent link="base"/><child link="l1"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.1 -0.3 0.7"/>
    <axis xyz="0 0 1"/>
  </joint>
  <joint name="j_fixed" type="fixed">
    <parent link="l1"/><child link="l1_tool"/>
    <origin xyz="0.0 0.1 0.25" rpy="0.5 0.0 -0.4"/>
  </joint>
  <joint name="j_rev" type="revolute">
    <parent link="l1_tool"/><child link="l2"/>
    <origin xyz="0.05 0.0 0.1" rpy="0 0.6 0"/>
    <axis xyz="0.6 0.8 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/>
  </joint>
  <joint name="j_pri" type="prismatic">
    <parent link="l2"/><child link="l3"/>
    <origin xyz="0.2 0.0 0.0" rpy="-0.4 0.2 0.1"/>
    <axis xyz="1 -2 2"/>
    <limit lower="-0.5" upper="0.5" effort="10" velocity="1"/>
  </joint>
  <joint name="j_branch" type="revolute">
    <parent link="l1_tool"/><child link="l4"/>
    <origin xyz="-0.1 0.05 0.0" rpy="1.2 0 0"/>
    <axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="10" velocity="5"/>
  </joint>
</robot>
"""


@functools.lru_cache(maxsize=None)
def get_pair(case):
    if case.startswith("pendulum-"):
        n = int(case.split("-")[1])
        return Pair(case, hovi.examples.models.pendulum(n), pin_pendulum(n))
    if case == "synthetic-urdf":
        return Pair(case, hovi.Model.from_urdf(SYNTHETIC_URDF), pin.buildModelFromXML(SYNTHETIC_URDF))
    path = erd_urdf({"panda": PANDA, "solo12": SOLO12, "talos_reduced": TALOS}[case])
    return Pair(case, hovi.Model.from_urdf(path), pin.buildModelFromUrdf(path))


CASES = [
    "pendulum-1",
    "pendulum-5",
    "pendulum-32",
    "synthetic-urdf",
    "panda",
    "solo12",
    "talos_reduced",
]


@pytest.fixture(params=CASES)
def pair(request):
    return get_pair(request.param)


def states(pair, rng, n=N_SAMPLES):
    for k in range(n):
        yield k, pair.random_q(rng), pair.random_v(rng)


def close(actual, desired, scale, what):
    """assert_allclose with rtol 1e-10 and atol 1e-10 * scale (scale: magnitude of the quantity)."""
    np.testing.assert_allclose(actual, desired, rtol=RTOL, atol=RTOL * max(scale, 1e-300), err_msg=what)


# --------------------------------------------------------------------------------------------
# Structure
# --------------------------------------------------------------------------------------------


def test_structure(pair):
    h, pm = pair.h, pair.pm
    names = list(pm.names)
    for i, j in enumerate(pair.jid):
        # parent joint
        p_h = h.parents[i]
        p_pin = pm.parents[j]
        assert (p_h == -1 and p_pin == 0) or (p_h >= 0 and h.joint_names[p_h] == names[p_pin]), (
            f"{pair.name}: parent of {names[j]}"
        )
        # joint type
        short = pm.joints[j].shortname()
        is_prismatic = short.startswith("JointModelP")
        assert h.joint_types[i] == ("prismatic" if is_prismatic else "revolute"), (short, h.joint_types[i])
    # total mass: Pinocchio puts the (welded) root link's inertia on the universe joint 0
    m_pin = sum(pm.inertias[j].mass for j in range(1, pm.njoints))
    close(h.total_mass, m_pin, m_pin, "total mass")
    close(np.asarray(h.gravity), pm.gravity.linear, 9.81, "gravity")


# --------------------------------------------------------------------------------------------
# Kinematics
# --------------------------------------------------------------------------------------------


def test_joint_placements(pair, rng):
    pm, pd = pair.pm, pair.pd
    for k, q, _ in states(pair, rng):
        pin.forwardKinematics(pm, pd, pair.q_pin(q))
        got = np.asarray(pair.h.joint_placements(q))
        want = np.array([pd.oMi[j].homogeneous for j in pair.jid])
        assert got.shape == want.shape
        scale = 1.0 + np.abs(want[:, :3, 3]).max()
        close(got, want, scale, f"{pair.name}: joint placements, sample {k}")


def test_body_poses(pair, rng):
    """COM frames: joint frame orientation, origin at the (merged) body's centre of mass."""
    pm, pd = pair.pm, pair.pd
    for k, q, _ in states(pair, rng):
        pin.forwardKinematics(pm, pd, pair.q_pin(q))
        got = np.asarray(pair.h.body_poses(q))
        want = np.array(
            [(pd.oMi[j] * pin.SE3(np.eye(3), pm.inertias[j].lever)).homogeneous for j in pair.jid]
        )
        massive = np.array([pm.inertias[j].mass > 0 for j in pair.jid])
        scale = 1.0 + np.abs(want[:, :3, 3]).max()
        close(got[massive], want[massive], scale, f"{pair.name}: COM poses, sample {k}")


def test_spatial_velocities(pair, rng):
    pm, pd = pair.pm, pair.pd
    for k, q, v in states(pair, rng):
        pin.forwardKinematics(pm, pd, pair.q_pin(q), pair.v_pin(v))
        got = np.asarray(pair.h.spatial_velocities(q, v))
        want = []
        for j in pair.jid:
            tw = pd.oMi[j].act(pd.v[j])  # world-frame (spatial) twist
            want.append(np.concatenate([tw.angular, tw.linear]))
        want = np.array(want)
        close(got, want, np.abs(want).max(), f"{pair.name}: spatial velocities, sample {k}")


# --------------------------------------------------------------------------------------------
# Energies and dynamics
# --------------------------------------------------------------------------------------------


def test_kinetic_energy(pair, rng):
    for k, q, v in states(pair, rng):
        want = pin.computeKineticEnergy(pair.pm, pair.pd, pair.q_pin(q), pair.v_pin(v))
        got = pair.h.kinetic_energy(q, v)
        close(got, want, abs(want), f"{pair.name}: kinetic energy, sample {k}")


def test_potential_energy(pair, rng):
    for k, q, _ in states(pair, rng):
        want = pin.computePotentialEnergy(pair.pm, pair.pd, pair.q_pin(q))
        got = pair.h.potential_energy(q)
        # scale: |V| can pass through zero; use m g times the size of the configuration
        pin.forwardKinematics(pair.pm, pair.pd, pair.q_pin(q))
        reach = 1.0 + max(np.abs(pair.pd.oMi[j].translation).max() for j in pair.jid)
        scale = max(abs(want), pair.h.total_mass * 9.81 * reach)
        close(got, want, scale, f"{pair.name}: potential energy, sample {k}")


def pin_mass_matrix(pair, q):
    M = pin.crba(pair.pm, pair.pd, pair.q_pin(q))
    M = np.triu(M) + np.triu(M, 1).T  # Pinocchio fills the upper triangle only
    return M[np.ix_(pair.vidx, pair.vidx)]


def test_mass_matrix(pair, rng):
    for k, q, _ in states(pair, rng):
        got = np.asarray(pair.h.mass_matrix(q))
        want = pin_mass_matrix(pair, q)
        scale = np.abs(want).max()
        np.testing.assert_array_equal(got, got.T, err_msg=f"{pair.name}: M not exactly symmetric")
        close(got, want, scale, f"{pair.name}: mass matrix, sample {k}")


def test_forward_dynamics(pair, rng):
    for k, q, v in states(pair, rng):
        tau = rng.uniform(-10.0, 10.0, pair.h.n)
        got = np.asarray(pair.h.forward_dynamics(q, v, tau)).ravel()
        want = pair.v_hovi(pin.aba(pair.pm, pair.pd, pair.q_pin(q), pair.v_pin(v), pair.v_pin(tau)))
        close(got, want, np.abs(want).max(), f"{pair.name}: forward dynamics, sample {k}")


def test_forward_dynamics_default_tau(pair, rng):
    """tau omitted = zero torque (passive motion under gravity)."""
    q, v = pair.random_q(rng), pair.random_v(rng)
    got = np.asarray(pair.h.forward_dynamics(q, v)).ravel()
    want = pair.v_hovi(pin.aba(pair.pm, pair.pd, pair.q_pin(q), pair.v_pin(v), np.zeros(pair.pm.nv)))
    close(got, want, np.abs(want).max(), f"{pair.name}: forward dynamics with tau=None")


def test_inverse_dynamics(pair, rng):
    for k, q, v in states(pair, rng):
        a = rng.uniform(-5.0, 5.0, pair.h.n)
        got = np.asarray(pair.h.inverse_dynamics(q, v, a)).ravel()
        want = pair.v_hovi(pin.rnea(pair.pm, pair.pd, pair.q_pin(q), pair.v_pin(v), pair.v_pin(a)))
        close(got, want, np.abs(want).max(), f"{pair.name}: inverse dynamics, sample {k}")


# --------------------------------------------------------------------------------------------
# Non-default gravity (fresh models, so the cached ones are not mutated)
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", ["pendulum-5", "panda"])
def test_custom_gravity(case, rng):
    base = get_pair(case)
    if case == "panda":
        path = erd_urdf(PANDA)
        fresh = Pair(case, hovi.Model.from_urdf(path), pin.buildModelFromUrdf(path))
    else:
        n = int(case.split("-")[1])
        fresh = Pair(case, hovi.examples.models.pendulum(n), pin_pendulum(n))
    g = np.array([1.5, -2.0, -7.0])
    fresh.h.gravity = g
    fresh.pm.gravity = pin.Motion(g, np.zeros(3))
    close(np.asarray(fresh.h.gravity), g, 10.0, "gravity setter")
    for k, q, v in states(fresh, rng, n=2):
        qp, vp = fresh.q_pin(q), fresh.v_pin(v)
        a = rng.uniform(-5.0, 5.0, fresh.h.n)
        want = fresh.v_hovi(pin.rnea(fresh.pm, fresh.pd, qp, vp, fresh.v_pin(a)))
        close(np.asarray(fresh.h.inverse_dynamics(q, v, a)).ravel(), want, np.abs(want).max(), f"RNEA {k}")
        tau = rng.uniform(-10.0, 10.0, fresh.h.n)
        want = fresh.v_hovi(pin.aba(fresh.pm, fresh.pd, qp, vp, fresh.v_pin(tau)))
        close(np.asarray(fresh.h.forward_dynamics(q, v, tau)).ravel(), want, np.abs(want).max(), f"ABA {k}")
        want = pin.computePotentialEnergy(fresh.pm, fresh.pd, qp)
        close(fresh.h.potential_energy(q), want, fresh.h.total_mass * 10.0 * 3.0, f"V {k}")
    # the cached default-gravity model is untouched
    close(np.asarray(base.h.gravity), [0.0, 0.0, -9.81], 9.81, "cached model gravity")


# --------------------------------------------------------------------------------------------
# Joint armature (fresh models: Model.armature and Pinocchio's model.armature set alike)
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("case", ["pendulum-5", "synthetic-urdf", "solo12"])
def test_armature(case, rng):
    """Armature a adds diag(a) to M(q): mass matrix, kinetic energy, ABA and RNEA as Pinocchio's."""
    base = get_pair(case)
    fresh = Pair(case, base.h.copy(), pin.Model(base.pm))
    a = rng.uniform(0.01, 0.5, fresh.h.n)
    a[0] = 0.0  # a joint without armature among those with
    fresh.h.armature = a
    fresh.pm.armature = fresh.v_pin(a)
    fresh.pd = fresh.pm.createData()
    np.testing.assert_array_equal(fresh.h.armature, a)
    np.testing.assert_array_equal(base.h.armature, np.zeros(base.h.n))  # the cached model is untouched
    for k, q, v in states(fresh, rng, n=3):
        qp, vp = fresh.q_pin(q), fresh.v_pin(v)
        M = pin_mass_matrix(fresh, q)
        close(fresh.h.mass_matrix(q), M, np.abs(M).max(), f"M {k}")
        close(fresh.h.mass_matrix(q) - base.h.mass_matrix(q), np.diag(a), np.abs(M).max(), f"diag(a) {k}")
        # K against 1/2 v^T M v with Pinocchio's M: Pinocchio 4.1's computeKineticEnergy leaves out
        # the armature of its JointModelRevoluteUnaligned joints (found here, synthetic-urdf's j_rev)
        want = 0.5 * v @ M @ v
        close(fresh.h.kinetic_energy(q, v), want, abs(want), f"K {k}")
        tau = rng.uniform(-10.0, 10.0, fresh.h.n)
        want = fresh.v_hovi(pin.aba(fresh.pm, fresh.pd, qp, vp, fresh.v_pin(tau)))
        close(np.asarray(fresh.h.forward_dynamics(q, v, tau)), want, np.abs(want).max(), f"ABA {k}")
        acc = rng.uniform(-5.0, 5.0, fresh.h.n)
        want = fresh.v_hovi(pin.rnea(fresh.pm, fresh.pd, qp, vp, fresh.v_pin(acc)))
        close(np.asarray(fresh.h.inverse_dynamics(q, v, acc)), want, np.abs(want).max(), f"RNEA {k}")
