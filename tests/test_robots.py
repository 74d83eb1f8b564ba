"""The paper's three robots (hovi.examples.robots, models/*.urdf) against the cross-check figures of their
sources (each URDF's header comment): DoF, total mass, standing heights, contacts on the ground in the
nominal stance, the sign conventions stated there, a free fall from the stance, and hovi's mass
matrix and gravity torques against Pinocchio's for the same URDF."""
import numpy as np
import pinocchio as pin
import pytest

import hovi
from hovi.examples import robots
from hovi.contact import Contacts, Terrain

ROBOTS = {"spring_flamingo": robots.spring_flamingo, "littledog": robots.littledog, "atlas": robots.atlas}
# (DoF, controls, total mass: the sheets' sums of the tabulated masses)
FIGURES = {"spring_flamingo": (9, 4, 12 + 2 * (0.4598 + 0.306 + 0.3466)),                     # 14.2248 kg
           "littledog": (18, 12, 1.8 + 4 * (0.0623 + 0.1279 + 0.0464)),                         # 2.7464 kg
           "atlas": (36, 30, 98.4069 + 2 * 19.7107 + 2 * 18.111)}                               # 174.0503 kg


@pytest.fixture(scope="module", params=list(ROBOTS))
def robot(request):
    return ROBOTS[request.param]()


def world_points(robot, q):
    """(C, 3) world positions of the robot's contact points at q."""
    poses = robot.model.joint_placements(q)
    return np.array([poses[robot.model.body_index(c.body)] @ [*c.point, 1.0] for c in robot.contacts])[:, :3]


def test_dof_controls_mass(robot):
    n, m, mass = FIGURES[robot.name]
    model = robot.model
    assert model.n == n and robot.q0.shape == (n,)
    assert model.n_controls == m == len(robot.actuated)
    assert model.total_mass == pytest.approx(mass, rel=1e-9)
    assert robot.urdf.is_file() and robot.urdf.parent == robots.URDF_DIR
    B = model.actuation
    for k, joint in enumerate(robot.actuated):
        assert B[model.joint_index(joint), k] == 1.0
    assert np.all(robot.effort_limits > 0) and np.all(np.isfinite(robot.effort_limits))
    assert {v["shape"] for v in model.visuals} <= {"box", "cylinder", "sphere"}
    root = 5 if robot.base == "euler" else 2                  # the root link's body, after the base's
    assert {v["link"] for v in model.visuals} >= set(model.body_names[root:])


def test_mass_sums_are_the_sheets_totals():
    """The sheets' cross-check totals: 14.2248 kg, 2.7464 kg and, for Atlas's 31 joint-carrying bodies,
    174.050 kg (rounded; 175.118 kg with the sensor placeholder bodies the URDF leaves out)."""
    assert [round(FIGURES[r][2], 4) for r in ("spring_flamingo", "littledog")] == [14.2248, 2.7464]
    assert round(FIGURES["atlas"][2], 3) == 174.050 and round(FIGURES["atlas"][2] + 1.01 + 0.057664, 3) == 175.118


def test_nominal_stance_stands_on_the_ground(robot):
    """Every contact of q0 on flat ground (LittleDog: its foot spheres, home() within 0.35 mm), as
    hovi.contact sees them, and the centre of mass over the feet."""
    contacts = Contacts(robot.model, robot.contact_points, Terrain(), mu=1.0,
                        plane="xz" if robot.base == "planar" else "")
    gaps = contacts.gaps(robot.q0)
    if robot.name == "littledog":
        assert np.all((gaps >= 0) & (gaps < 3.5e-4))
    else:
        np.testing.assert_allclose(gaps, 0.0, atol=1e-12)
    com = robot.model.masses @ robot.model.body_poses(robot.q0)[:, :3, 3] / robot.model.total_mass
    feet = world_points(robot, robot.q0)
    assert feet[:, 0].min() < com[0] < feet[:, 0].max() and feet[:, 1].min() <= com[1] <= feet[:, 1].max()


def test_free_fall_from_the_stance(robot):
    """Without contacts, 0.1 s from q0 at rest: the base drops g t^2 / 2, the posture holds, energy is kept."""
    traj = hovi.Integrator(robot.model, s=2, dt=0.005).rollout(robot.q0, 20)
    z = 1 if robot.base == "planar" else 2
    assert traj.converged and traj.q[-1, z] - robot.q0[z] == pytest.approx(-9.81 * 0.1**2 / 2, rel=1e-9)
    np.testing.assert_allclose(np.delete(traj.q[-1], z), np.delete(robot.q0, z), atol=1e-12)
    assert np.ptp(traj.energy) < 1e-9 * robot.model.total_mass


def test_spring_flamingo_hip_line_and_signs():
    r = robots.spring_flamingo()
    model, q = r.model, r.q0.copy()
    hip, knee, ankle = (model.joint_index(f"right_{j}") for j in ("hip", "knee", "ankle"))
    assert model.joint_placements(q)[hip][2, 3] == pytest.approx(0.875, abs=1e-12)  # straight legs (Drake q0)
    assert model.joint_placements(q)[ankle][2, 3] == pytest.approx(0.035, abs=1e-12)
    assert world_points(r, q)[0, 0] < world_points(r, q)[1, 0]  # toe at -x, the walking direction
    q[hip] = 0.3                                                  # positive hip: the leg swings toward -x
    assert model.joint_placements(q)[knee][0, 3] < 0
    q[hip], q[knee] = 0.0, -0.5                                   # flexion is negative: the foot trails
    assert model.joint_placements(q)[ankle][0, 3] > 0
    assert model.lower_limits[knee] == pytest.approx(-np.pi) and model.upper_limits[knee] == 0
    assert model.stiffness[ankle] == 1.0 and model.joint_damping[ankle] == 0.1 and model.stiffness[knee] == 0
    assert r.actuated == ("left_hip", "left_knee", "right_hip", "right_knee")


def test_littledog_home_pose():
    r = robots.littledog()
    feet = world_points(r, r.q0)
    assert r.q0[2] == 0.146
    np.testing.assert_allclose(r.q0[2] - feet[:, 2] + r.contact_radius, [0.1457, 0.1457, 0.1457, 0.1459], atol=5e-5)
    np.testing.assert_allclose(feet[:, :2], [[0.0667, 0.0735], [0.0667, -0.0735], [-0.0667, 0.0735],
                                             [-0.0667, -0.0707]], atol=5e-5)


def test_atlas_standing_height_and_mirror_symmetry():
    r = robots.atlas()
    model = r.model
    q = np.zeros(model.n)
    q[2] = 0.93845                                   # pelvis above the sole at zero angles (the sheet)
    soles = world_points(r, q)
    np.testing.assert_allclose(soles[:, 2], 0.0, atol=1e-12)
    assert soles[:, 0].mean() == pytest.approx(0.0426, abs=1e-12)  # the sole 0.0426 m ahead of the pelvis
    # The left arm and leg are built by rotation: the mirror image (y -> -y) of a right-side pose is
    # the left side with the x- and z-rotations negated.
    signs = {"shz": -1, "shx": -1, "ely": 1, "elx": -1, "uwy": 1, "mwx": -1, "lwy": 1,
             "hpz": -1, "hpx": -1, "hpy": 1, "kny": 1, "aky": 1, "akx": -1}
    rng = np.random.default_rng(3)
    for joint, sign in signs.items():
        limb = "arm" if joint in ("shz", "shx", "ely", "elx", "uwy", "mwx", "lwy") else "leg"
        right, left = model.joint_index(f"r_{limb}_{joint}"), model.joint_index(f"l_{limb}_{joint}")
        q[right] = rng.uniform(model.lower_limits[right], model.upper_limits[right])
        q[left] = sign * q[right]
        lo, hi = model.lower_limits, model.upper_limits
        assert (lo[left], hi[left]) == pytest.approx((lo[right], hi[right]) if sign > 0 else (-hi[right], -lo[right]))
    poses = model.joint_placements(q)
    for body in ("hand", "foot"):
        p_left, p_right = poses[model.body_index(f"l_{body}")][:3, 3], poses[model.body_index(f"r_{body}")][:3, 3]
        np.testing.assert_allclose(p_left, p_right * [1, -1, 1], atol=1e-12)


def pinocchio_model(robot):
    """Pinocchio's model of the robot's URDF, its base the same chain of 1-DoF joints as hovi's."""
    root = pin.JointModelComposite()
    chain = ((pin.JointModelPX(), pin.JointModelPZ(), pin.JointModelRY()) if robot.base == "planar" else
             (pin.JointModelPX(), pin.JointModelPY(), pin.JointModelPZ(),
              pin.JointModelRZ(), pin.JointModelRY(), pin.JointModelRX()))
    for joint in chain:
        root.addJoint(joint)
    return pin.buildModelFromUrdf(str(robot.urdf), root), len(chain)


def test_mass_matrix_and_gravity_match_pinocchio(robot):
    pm, nb = pinocchio_model(robot)
    pd = pm.createData()
    model = robot.model
    assert pm.nv == model.n
    names = list(pm.names)
    joints = [names.index(j) for j in model.joint_names[nb:]]
    v_index = np.r_[np.arange(nb) + pm.idx_vs[1], [pm.idx_vs[j] for j in joints]]
    rng = np.random.default_rng(11)
    for _ in range(4):
        q = robot.q0 + rng.uniform(-1, 1, model.n)
        qp = pin.neutral(pm)
        qp[pm.idx_qs[1]:pm.idx_qs[1] + nb] = q[:nb]
        for i, j in zip(range(nb, model.n), joints):
            k = pm.idx_qs[j]
            qp[k:k + pm.nqs[j]] = (np.cos(q[i]), np.sin(q[i])) if pm.nqs[j] == 2 else q[i]
        M = pin.crba(pm, pd, qp)
        M = np.triu(M) + np.triu(M, 1).T
        M_hovi = model.mass_matrix(q)
        np.testing.assert_allclose(M_hovi, M[np.ix_(v_index, v_index)], rtol=0, atol=1e-10 * np.abs(M).max())
        g = pin.computeGeneralizedGravity(pm, pd, qp)[v_index]
        g_hovi = model.inverse_dynamics(q, np.zeros(model.n), np.zeros(model.n))  # rigid-body terms only
        np.testing.assert_allclose(g_hovi, g, rtol=0, atol=1e-10 * np.abs(g).max())
