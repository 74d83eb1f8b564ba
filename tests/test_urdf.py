"""URDF loading: fixed-joint merging, base expansion, metadata and every bad input."""
import glob
import os

import numpy as np
import pinocchio as pin
import pytest

import hovi
from urdf_snippets import NUMBER_ATTRIBUTES, full_robot, joint, link, robot

RNG = np.random.default_rng(7)

# A chain with an offset, rotated inertial frame, a fixed joint in the middle and a prismatic joint.
CHAIN = robot(
    link("base"),
    link("a", 1.2, (0.02, 0.001, 0, 0.03, 0.002, 0.025), origin="0.1 0.02 -0.3", rpy="0.3 0.1 -0.2"),
    link("a_tool", 0.4, (0.004, 0, 0, 0.005, 0, 0.006), origin="0.0 0.05 0", rpy="0 0.5 0"),
    link("b", 0.8, (0.01, 0, 0, 0.012, 0, 0.009), origin="0 0 -0.1"),
    joint("j1", "base", "a", xyz="0 0 0.5", rpy="0 0.2 0", axis="1 0 0"),
    joint("fix", "a", "a_tool", kind="fixed", xyz="0.2 0 -0.4", rpy="0.1 0 0.3"),
    joint("j2", "a_tool", "b", kind="prismatic", xyz="0 0.1 0", axis="0 1 1"),
)


def pin_model(xml, root_joint=None):
    return pin.buildModelFromXML(xml, root_joint) if root_joint is not None else pin.buildModelFromXML(xml)


def test_fixed_joint_is_merged_and_matches_pinocchio():
    model = hovi.Model.from_urdf(CHAIN)
    assert model.n == 2 and model.joint_names == ["j1", "j2"]
    assert model.joint_types == ["revolute", "prismatic"]
    assert model.total_mass == pytest.approx(1.2 + 0.4 + 0.8)  # base is welded to the world
    pm = pin_model(CHAIN)
    pd = pm.createData()
    for _ in range(3):
        q, qd = RNG.uniform(-1, 1, 2), RNG.uniform(-1, 1, 2)
        np.testing.assert_allclose(model.mass_matrix(q), pin.crba(pm, pd, q), rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(model.forward_dynamics(q, qd, np.zeros(2)), pin.aba(pm, pd, q, qd, np.zeros(2)),
                                   rtol=1e-10, atol=1e-10)


def test_euler_base_matches_pinocchio_composite_joint():
    model = hovi.Model.from_urdf(CHAIN, base="euler")
    assert model.n == 8
    assert model.joint_types[:6] == ["prismatic"] * 3 + ["revolute"] * 3
    # The same base as a Pinocchio composite joint: translations x, y, z then rotations z, y, x.
    comp = pin.JointModelComposite()
    for j in (pin.JointModelPX(), pin.JointModelPY(), pin.JointModelPZ(),
              pin.JointModelRZ(), pin.JointModelRY(), pin.JointModelRX()):
        comp.addJoint(j)
    pm = pin_model(CHAIN, comp)
    pd = pm.createData()
    for _ in range(3):
        q, qd, tau = RNG.uniform(-1, 1, 8), RNG.uniform(-1, 1, 8), RNG.uniform(-1, 1, 8)
        np.testing.assert_allclose(model.mass_matrix(q), pin.crba(pm, pd, q), rtol=1e-11, atol=1e-11)
        np.testing.assert_allclose(model.forward_dynamics(q, qd, tau), pin.aba(pm, pd, q, qd, tau),
                                   rtol=1e-9, atol=1e-9)
        assert model.kinetic_energy(q, qd) == pytest.approx(pin.computeKineticEnergy(pm, pd, q, qd), rel=1e-12)


def test_planar_base_and_expanded_planar_joint():
    model = hovi.Model.from_urdf(CHAIN, base="planar")
    assert model.n == 5 and model.joint_types[:3] == ["prismatic", "prismatic", "revolute"]
    poses = model.joint_placements(np.array([0.3, -0.2, 0.0, 0, 0]))
    # x-z plane by default: the first two joints translate the root along x and z.
    np.testing.assert_allclose(poses[2][:3, 3], [0.3, 0.0, -0.2], atol=1e-14)
    xml = robot(link("w"), link("a"), joint("p", "w", "a", kind="planar", axis="0 0 1"))
    with pytest.raises(hovi.URDFError, match="'p' is planar"):
        hovi.Model.from_urdf(xml)
    assert hovi.Model.from_urdf(xml, expand_joints=True).n == 3


def test_metadata_limits_mimic_dynamics():
    xml = robot(link("w"), link("a"), link("b"),
                joint("j1", "w", "a", extra='<dynamics damping="0.5" friction="0.1"/>'),
                joint("j2", "a", "b", extra='<mimic joint="j1" multiplier="2" offset="0.1"/>'),
                joint("j3", "w", "c", kind="continuous"),
                link("c"))
    model = hovi.Model.from_urdf(xml)
    i1, i3 = model.joint_index("j1"), model.joint_index("j3")
    assert model.lower_limits[i1] == -1 and model.upper_limits[i1] == 1
    assert np.isinf(model.lower_limits[i3]) and np.isinf(model.upper_limits[i3])  # continuous
    assert model.effort_limits[i1] == 10 and model.velocity_limits[i1] == 2
    assert model.damping[i1] == 0.5 and model.friction[i1] == 0.1
    assert model.mimic == {"j2": ("j1", 2.0, 0.1)}
    assert model.parents[model.body_index("b")] == model.body_index("a")


def test_path_like_and_file_input(tmp_path):
    f = tmp_path / "chain.urdf"
    f.write_text(CHAIN)
    assert hovi.Model.from_urdf(f).n == 2
    assert hovi.Model.from_urdf(str(f)).n == 2


@pytest.mark.parametrize("xml, pattern", [
    ('<robot name="r"><link name="a"></robot>', "malformed or invalid URDF"),
    (robot(link("a"), link("b"), joint("j", "a", "b", kind="spherical")), r"\[j\] has no known type"),
    (robot(link("a"), link("b"), joint("j", "a", "b", kind="floating")), "'j' is floating"),
    (robot(link("a"), link("b", mass=-1), joint("j", "a", "b")), "link 'b': mass must be"),
    (robot(link("a"), link("b", inertia=(-0.1, 0, 0, 0.1, 0, 0.1)), joint("j", "a", "b")),
     "link 'b': rotational inertia is not positive definite"),
    (robot(link("a"), link("b", inertia=(0.1, 0.2, 0, 0.1, 0, 0.1)), joint("j", "a", "b")),
     "link 'b': rotational inertia is not positive definite"),
    (robot(link("a"), link("b"), link("c"), joint("j1", "a", "b"), joint("j2", "b", "c"), joint("j3", "c", "b")),
     "link 'b' is the child of more than one joint"),
    (robot(link("a"), link("b"), joint("j1", "a", "b"), joint("j2", "b", "a")), "No root link"),
    (robot(link("a"), link("b"), joint("j1", "zz", "b")), r"parent link \[zz\] of joint \[j1\]"),
    (robot(link("a"), link("b"), joint("j", "a", "b", kind="fixed")), "has no movable joint"),
    (robot(link("a"), link("b"), joint("j", "a", "b", axis="0 0 0")), "'j' has a zero axis"),
])
def test_bad_urdf_raises_named_error(xml, pattern):
    with pytest.raises(hovi.URDFError, match=pattern):
        hovi.Model.from_urdf(xml)


def test_missing_file_and_bad_base():
    with pytest.raises(hovi.URDFError, match="cannot open URDF file"):
        hovi.Model.from_urdf("/nonexistent/robot.urdf")
    with pytest.raises(ValueError, match="base must be"):
        hovi.Model.from_urdf(CHAIN, base="wobbly")


def test_urdf_error_is_a_value_error():
    assert issubclass(hovi.URDFError, hovi.ModelError) and issubclass(hovi.ModelError, ValueError)


def test_point_mass_link_is_accepted():
    # Zero principal moments (point masses such as force-sensor links) are valid; negative ones are not.
    xml = robot(link("a"), link("b"), link("tip", inertia=(0, 0, 0, 0, 0, 0)), joint("j", "a", "b"),
                joint("weld", "b", "tip", kind="fixed", xyz="0 0 -1"))
    model = hovi.Model.from_urdf(xml)
    assert model.total_mass == pytest.approx(2.0)


# ---- Numbers: every number attribute must hold finite numbers, as many as it takes ----------------

BAD_NUMBERS = ["nan", "inf", "-inf", "1e999", "abc", "1.0.0"]


def bad_values(good):
    """Replacements for the good value `good`: each bad number in place of one of its numbers, no value,
    one number too many and (for lists) one too few."""
    numbers = good.split()
    k = len(numbers) // 2
    values = [" ".join(numbers[:k] + [bad] + numbers[k + 1:]) for bad in BAD_NUMBERS]
    values += ["", " ".join(numbers + ["1"])]
    if len(numbers) > 1:
        values.append(" ".join(numbers[:-1]))
    return values


@pytest.mark.parametrize("key, value", [(key, value) for key, (good, _, _) in NUMBER_ATTRIBUTES.items()
                                        for value in bad_values(good)])
def test_bad_number_raises_error_naming_element_and_attribute(key, value):
    _, where, attribute = NUMBER_ATTRIBUTES[key]
    with pytest.raises(hovi.URDFError) as err:
        hovi.Model.from_urdf(full_robot(**{key: value}))
    message = str(err.value)
    assert message.startswith(f'{where} {attribute}="{value}">: not '), message
    assert "finite number" in message


def test_bad_number_message():
    with pytest.raises(hovi.URDFError) as err:
        hovi.Model.from_urdf(full_robot(ixx="nan"))
    assert str(err.value) == 'link \'arm\': <inertial><inertia ixx="nan">: not a finite number of magnitude at most 1e12'
    with pytest.raises(hovi.URDFError) as err:
        hovi.Model.from_urdf(full_robot(axis="1 2"))
    assert str(err.value) == 'joint \'j1\': <axis xyz="1 2">: not 3 finite numbers of magnitude at most 1e12'
    with pytest.raises(hovi.URDFError) as err:  # finite, but the mass matrix would overflow (bench/fuzz_urdf.py)
        hovi.Model.from_urdf(full_robot(inertial_xyz="1e308 0 0"))
    assert "1e308" in str(err.value) and "magnitude at most 1e12" in str(err.value)


def test_robot_with_every_number_attribute_loads():
    model = hovi.Model.from_urdf(full_robot())
    assert model.joint_names == ["j1", "j2"] and model.total_mass == pytest.approx(2.0)
    assert model.mimic == {"j2": ("j1", 2.0, 0.1)} and model.damping[0] == 0.5
    # Other spellings urdfdom reads as finite numbers still load, to the same model.
    same = hovi.Model.from_urdf(full_robot(mass="+1", ixx=" 0.1", ixy="1e-400", iyy="1E-1", damping="5e-1",
                                           inertial_xyz=" 0  0 -0.1 ", axis="1.0 0 0", visual_box="1 1 1 "))
    q, qd = np.array([0.3, -0.2]), np.array([0.1, 0.4])
    np.testing.assert_array_equal(same.mass_matrix(q), model.mass_matrix(q))
    np.testing.assert_array_equal(same.forward_dynamics(q, qd, np.zeros(2)), model.forward_dynamics(q, qd, np.zeros(2)))
    assert same.damping[0] == 0.5


def test_example_robot_data_urdfs_pass_the_number_check():
    erd = pytest.importorskip("example_robot_data")
    root = erd.getModelPath("panda_description/urdf/panda.urdf")
    paths = glob.glob(os.path.join(root, "**", "*.urdf"), recursive=True)
    assert paths
    loaded = 0
    for path in paths:
        try:
            hovi.Model.from_urdf(path)
            loaded += 1
        except hovi.URDFError as e:  # some are refused for other reasons (no movable joint, bad inertia, ...)
            assert "finite number" not in str(e), path
    assert loaded >= len(paths) // 2
