"""The free base (``Model.from_urdf(path, base="floating")``, ``add_body(..., "free")``): the free joint
integrated on the group, its state in Pinocchio's conventions (q = (x, y, z, qx, qy, qz, qw, joints),
the base's velocity in its own frame). Checked against Pinocchio (mass matrix, nonlinear effects,
kinetic energy, integrate and difference at random unit quaternions), against a high-accuracy
reference of the same continuous system (hovi's forward dynamics of the free base, itself checked
against Pinocchio's here, and the quaternion's own kinematics, DOP853 at 1e-13: the order 2s), by Noether (the world momenta of a free body through the
Dzhanibekov flip) and by a cube that tips over an edge the Euler angles cannot pass."""
import numpy as np
import pytest

import hovi
from conftest import bench_module, erd_urdf
from hovi.contact import Contacts, Terrain

# the test models, the reference and the cube's poses are bench/free_base.py's (one home for each)
fb = bench_module("free_base")
quaternion_matrix, reference, edge_pose = fb.quaternion_matrix, fb.reference, fb.edge_pose

ROBOTS = ["solo_description/robots/solo12.urdf", "talos_data/robots/talos_reduced.urdf",
          "anymal_b_simple_description/robots/anymal.urdf", "hyq_description/robots/hyq_no_sensors.urdf",
          "go1_description/urdf/go1.urdf", "romeo_description/urdf/romeo_small.urdf"]


def random_quaternion(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


class PinPair:
    """A URDF loaded by hovi with base='floating' and by Pinocchio with its free flyer; joints
    after the base matched by name, Pinocchio's continuous joints (nq = 2) handled."""

    def __init__(self, path):
        import pinocchio as pin
        self.pin = pin
        self.h = hovi.Model.from_urdf(path, base="floating")
        self.pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer())
        self.pd = self.pm.createData()
        names = list(self.pm.names)
        assert self.h.nq == self.pm.nq - sum(nq == 2 for nq in self.pm.nqs) and self.h.nv == self.pm.nv
        self.jid = [names.index(jn) for jn in self.h.joint_names[6:]]
        self.vidx = np.r_[np.arange(6), [self.pm.idx_vs[j] for j in self.jid]]

    def q_pin(self, q):
        qp = self.pin.neutral(self.pm)
        qp[:7] = q[:7]
        for i, j in enumerate(self.jid):
            k = self.pm.idx_qs[j]
            if self.pm.nqs[j] == 2:
                qp[k:k + 2] = np.cos(q[7 + i]), np.sin(q[7 + i])
            else:
                qp[k] = q[7 + i]
        return qp

    def v_pin(self, v):
        vp = np.zeros(self.pm.nv)
        vp[self.vidx] = v
        return vp

    def random_state(self, rng):
        q = np.r_[rng.uniform(-1, 1, 3), random_quaternion(rng), rng.uniform(-1.5, 1.5, self.h.n - 6)]
        return q, rng.uniform(-2, 2, self.h.n)


@pytest.mark.filterwarnings("ignore:link .* rotational inertia violates:UserWarning")
@pytest.mark.parametrize("rel", ROBOTS)
def test_robots_with_the_free_joint_match_pinocchio(rel, rng):
    pytest.importorskip("pinocchio")
    pair = PinPair(erd_urdf(rel))
    pin, pm, pd, h = pair.pin, pair.pm, pair.pd, pair.h
    for _ in range(5):
        q, v = pair.random_state(rng)
        qp, vp = pair.q_pin(q), pair.v_pin(v)
        M = pin.crba(pm, pd, qp)
        M = np.triu(M) + np.triu(M, 1).T
        Mh = h.mass_matrix(q)
        np.testing.assert_allclose(Mh, M[np.ix_(pair.vidx, pair.vidx)], rtol=0, atol=1e-10 * np.abs(M).max())
        nle = pin.nonLinearEffects(pm, pd, qp, vp)[pair.vidx]
        np.testing.assert_allclose(h.inverse_dynamics(q, v, np.zeros(h.n)), nle, rtol=0, atol=1e-10 * np.abs(nle).max())
        K = pin.computeKineticEnergy(pm, pd, qp, vp)
        assert abs(h.kinetic_energy(q, v) - K) <= 1e-10 * K
        a = pin.aba(pm, pd, qp, vp, np.zeros(pm.nv))[pair.vidx]
        np.testing.assert_allclose(h.forward_dynamics(q, v), a, rtol=0, atol=1e-9 * np.abs(a).max())
        # integrate and difference as Pinocchio's (the quaternion up to its sign)
        dv = rng.uniform(-1, 1, h.n)
        q1 = h.integrate(q, dv)
        q1p = pin.integrate(pm, qp, pair.v_pin(dv))
        np.testing.assert_allclose(q1[:3], q1p[:3], atol=1e-12)
        assert abs(abs(q1[3:7] @ q1p[3:7]) - 1) < 1e-12
        np.testing.assert_allclose(h.difference(q, q1), dv, atol=1e-10)
        np.testing.assert_allclose(h.difference(q, q1), pin.difference(pm, qp, q1p)[pair.vidx], atol=1e-10)


def free_body(gravity=True):
    """An asymmetric rigid body on the free joint (principal moments 1, 2, 3 kg m^2 about axes turned
    from its frame's, its centre of mass off the joint frame's origin)."""
    return fb.body(gravity=gravity)


def floating_chain():
    """The free body with a two-link arm on skewed revolute joints."""
    return fb.chain()


def test_forward_dynamics_is_pinocchios_on_the_test_models(rng):
    """The reference's dynamics, hovi's forward dynamics of the free base (checked against Pinocchio's
    on the robots above), on the test models: a = FD(q, v, tau) solves ID(q, v, a) = tau."""
    m = floating_chain()
    for _ in range(3):
        q = np.r_[rng.uniform(-1, 1, 3), random_quaternion(rng), rng.uniform(-1, 1, 2)]
        v, tau = rng.uniform(-2, 2, m.n), rng.uniform(-1, 1, m.n)
        np.testing.assert_allclose(m.inverse_dynamics(q, v, m.forward_dynamics(q, v, tau)), tau, atol=1e-12)


@pytest.mark.parametrize("s, dts", [(1, (0.02, 0.01, 0.005)), (2, (0.1, 0.05, 0.025)), (3, (0.2, 0.1, 0.05))])
@pytest.mark.parametrize("build", [free_body, floating_chain])
def test_order_2s_against_a_reference(build, s, dts):
    m = build()
    q0 = np.r_[0.1, -0.2, 0.3, np.array([0.3, -0.1, 0.2, 0.9]) / np.linalg.norm([0.3, -0.1, 0.2, 0.9]),
               np.full(m.nq - 7, 0.4)]
    v0 = np.r_[0.3, -0.1, 0.2, 1.5, -1.0, 0.8, np.full(m.n - 6, -0.7)]
    T = 0.8
    q_ref, v_ref = reference(m, q0, v0, T)
    errors = []
    for dt in dts:
        integ = hovi.Integrator(m, s=s, dt=dt)
        traj = integ.rollout(q0, int(round(T / dt)), qdot0=v0)
        assert traj.converged
        q, v = traj.q[-1], integ.velocity(traj.q[-1], traj.p[-1])
        errors.append(max(np.abs(m.difference(q_ref, q)).max(), np.abs(v - v_ref).max()))
    orders = np.log2(np.array(errors[:-1]) / errors[1:])
    assert orders.min() > 2 * s - 0.3, (errors, orders)


@pytest.mark.parametrize("s, dt", [(1, 0.01), (2, 0.02), (3, 0.05)])
def test_the_dzhanibekov_flip_keeps_the_world_momenta(s, dt):
    """Zero gravity, spun about the intermediate axis: it flips many times in 20 s; the linear and
    angular momentum in the world (P = R p_lin, L = x × P + R p_ang) are kept to round-off."""
    m = free_body(gravity=False)
    integ = hovi.Integrator(m, s=s, dt=dt)
    # about the body's intermediate principal axis (the inertia's second column, turned), slightly off
    R = quaternion_matrix(fb.TURN)
    w = 3.0 * R[:, 1] + 0.05 * R[:, 0]
    traj = integ.rollout(m.neutral(), int(round(20 / dt)), qdot0=np.r_[0.2, -0.1, 0.3, w])
    assert traj.converged
    Rs = np.array([quaternion_matrix(x) for x in traj.q[:, 3:7]])
    P = np.einsum("kij,kj->ki", Rs, traj.p[:, :3])
    L = np.cross(traj.q[:, :3], P) + np.einsum("kij,kj->ki", Rs, traj.p[:, 3:6])
    assert np.abs(P - P[0]).max() <= 1e-11 * np.linalg.norm(P[0])
    assert np.abs(L - L[0]).max() <= 1e-11 * np.linalg.norm(L[0])
    # it flips: the body's intermediate axis turns over in the world
    axis = np.einsum("kij,j->ki", Rs, R[:, 1]) @ (L[0] / np.linalg.norm(L[0]))
    assert axis.max() > 0.9 and axis.min() < -0.9
    E = traj.energy
    assert np.ptp(E) <= {1: 1e-2, 2: 1e-4, 3: 1e-5}[s] * E[0]


def cube():
    """The 1 kg, 0.2 m cube on the free joint and its eight corners."""
    return fb.cube("free")


@pytest.mark.parametrize("s, dt", [(1, 0.01), (1, 0.005), (2, 0.01), (2, 0.005)])
def test_a_cube_on_an_edge_at_50_degrees_tips_over_and_rests_on_its_side(s, dt):
    """The Euler-angle base cannot: its pitch passes 90° on the way (line search failures)."""
    m, corners = cube()
    integ = hovi.Integrator(m, s=s, dt=dt, contacts=Contacts(m, corners, Terrain(), mu=0.8))
    q0 = edge_pose(np.radians(50))
    assert integ.contacts.gaps(q0).min() > -1e-12
    traj = integ.rollout(q0, int(round(2.0 / dt)))
    assert traj.converged
    R = quaternion_matrix(traj.q[-1, 3:7])
    assert abs(abs(R[2, 0]) - 1) < 1e-9          # its x axis (a side's normal) now vertical: on its side
    assert abs(traj.q[-1, 2] - 0.1) < 1e-9       # the centre at half the side above the ground
    assert np.abs(traj.qdot[-2]).max() < 1e-7    # at rest (the last row's p is before its knot's impulse)


def test_a_free_base_trajectory_is_saved_and_loaded(tmp_path):
    m, corners = cube()
    integ = hovi.Integrator(m, s=2, dt=0.01, contacts=Contacts(m, corners, Terrain(), mu=0.8))
    traj = integ.rollout(edge_pose(np.radians(50)), 30)
    traj.save(tmp_path / "cube.npz")
    back = hovi.load_trajectory(tmp_path / "cube.npz", integ)
    assert back.q.shape == (31, m.nq) and np.array_equal(back.q, traj.q) and np.array_equal(back.p, traj.p)
    np.testing.assert_array_equal(back.energy, traj.energy)


def test_what_is_not_on_the_free_base_yet_says_so():
    m, _ = cube()
    integ = hovi.Integrator(m, s=1, dt=0.01)
    with pytest.raises(hovi.ModelError, match="free base"):
        m.gravity_hessian(m.neutral())
    with pytest.raises(ValueError, match="norm 1"):
        integ.rollout(np.r_[0, 0, 0, 1.0, 1.0, 0, 0], 1)


@pytest.mark.parametrize("rel, free", [("solo_description/robots/solo12.urdf", True),
                                       ("panda_description/urdf/panda.urdf", False)])
def test_a_pinocchio_model_becomes_a_hovi_model_in_one_call(rel, free, rng):
    """hovi.from_pinocchio: Pinocchio's joints in its own order (a free flyer as the free joint), so q
    and v pass unchanged; mass matrix, nonlinear effects and limits as Pinocchio's."""
    pin = pytest.importorskip("pinocchio")
    path = erd_urdf(rel)
    pm = pin.buildModelFromUrdf(path, pin.JointModelFreeFlyer()) if free else pin.buildModelFromUrdf(path)
    pd = pm.createData()
    h = hovi.from_pinocchio(pm)
    assert h.nq == pm.nq and h.nv == pm.nv and h.free_base == free
    assert h.joint_names[-(pm.njoints - 1 - free):] == list(pm.names)[1 + free:]
    for _ in range(3):
        q = pin.randomConfiguration(pm, -np.ones(pm.nq), np.ones(pm.nq)) if not free else \
            np.r_[rng.uniform(-1, 1, 3), random_quaternion(rng), rng.uniform(-1, 1, pm.nq - 7)]
        v = rng.uniform(-1, 1, pm.nv)
        M = pin.crba(pm, pd, q)
        M = np.triu(M) + np.triu(M, 1).T
        np.testing.assert_allclose(h.mass_matrix(q), M, rtol=0, atol=1e-10 * np.abs(M).max())
        nle = pin.nonLinearEffects(pm, pd, q, v)
        np.testing.assert_allclose(h.inverse_dynamics(q, v, np.zeros(h.n)), nle, rtol=0, atol=1e-10 * np.abs(nle).max())


def test_what_hovi_has_no_joint_for_is_named():
    pin = pytest.importorskip("pinocchio")
    pm = pin.Model()
    pm.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball")
    with pytest.raises(hovi.ModelError, match="'ball' is a JointModelSpherical"):
        hovi.from_pinocchio(pm)
    with pytest.raises(TypeError, match="pinocchio.Model"):
        hovi.from_pinocchio("solo12")


def test_a_batch_of_steps_is_the_single_steps(rng):
    """step_batch on a free base: each item's end state as Integrator.step gives it, bit for bit."""
    m = free_body()
    integ = hovi.Integrator(m, s=2, dt=0.02)
    Q = np.array([np.r_[rng.uniform(-1, 1, 3), random_quaternion(rng)] for _ in range(4)])
    V = rng.uniform(-2, 2, (4, 6))
    batch = integ.step_batch(Q, qdots=V)
    for b in range(4):
        q1, p1, _ = integ.step(Q[b], integ.momentum(Q[b], V[b]))
        assert np.array_equal(batch.q_next[b], q1) and np.array_equal(batch.p_next[b], p1)


def test_a_free_joint_only_at_the_root_and_states_of_its_size():
    """add_body(..., 'free') takes the model's first body on the world only; integrate, difference and
    the rollout take q of nq entries and v of n; each refusal names the argument, the model unchanged."""
    m, _ = cube()
    with pytest.raises(hovi.ModelError, match="first body, on the world"):
        m.add_body("second", None, "free", mass=1.0, inertia=np.eye(3))
    with pytest.raises(hovi.ModelError, match="first body, on the world"):
        m.add_body("child", "cube", "free", mass=1.0, inertia=np.eye(3))
    bad = hovi.Model()
    with pytest.raises(hovi.ModelError):
        bad.add_body("b", None, "free", mass=-1.0, inertia=np.eye(3))  # the body's own checks first
    assert bad.n == 0
    assert m.n == 6 and m.nq == 7
    with pytest.raises(ValueError, match="q"):
        m.integrate(np.zeros(6), np.zeros(6))
    with pytest.raises(ValueError, match="v"):
        m.integrate(m.neutral(), np.zeros(7))
    with pytest.raises(ValueError, match="q1"):
        m.difference(m.neutral(), np.zeros(6))
    with pytest.raises(ValueError, match="q0"):
        hovi.Integrator(m, s=1, dt=0.01).rollout(np.zeros(6), 1)
