"""The Python Model API: building in code, inputs checked with clear errors."""
import numpy as np
import pytest

import hovi


def test_build_in_code_matches_builtin_pendulum():
    n, L, m, r = 3, 0.5, 1.0, 0.02
    It, Ia = m * (3 * r * r + L * L) / 12, m * r * r / 2
    model = hovi.Model()
    for i in range(n):
        T = np.eye(4)
        T[2, 3] = 0.0 if i == 0 else -L
        model.add_body(f"link{i + 1}", parent=None if i == 0 else i - 1, axis=[1, 0, 0] if i % 2 == 0 else [0, 1, 0],
                       placement=T, mass=m, com=[0, 0, -L / 2], inertia=np.diag([It, It, Ia]))
    ref = hovi.examples.models.pendulum(n, L, m, r)
    q = np.array([0.3, -0.5, 1.1])
    np.testing.assert_array_equal(model.mass_matrix(q), ref.mass_matrix(q))
    assert "link2" in model.summary() and model.parents == [-1, 0, 1]


@pytest.mark.parametrize("q, pattern", [
    (np.zeros(2), r"q must be a 1-D array of length 3, got shape \(2,\)"),
    (np.zeros((3, 1)), r"q must be a 1-D array of length 3, got shape \(3, 1\)"),
    (np.array([0.0, np.nan, 0.0]), "q contains NaN"),
    (np.array([0.0, np.inf, 0.0]), "q contains NaN or infinity"),
    (["a", "b", "c"], "q must be an array of real numbers"),
])
def test_bad_state_raises_value_error(q, pattern):
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(ValueError, match=pattern):
        model.mass_matrix(q)


def test_bad_velocity_and_torque():
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(ValueError, match="qdot must be a 1-D array of length 3"):
        model.kinetic_energy(np.zeros(3), np.zeros(4))
    with pytest.raises(ValueError, match="tau contains NaN"):
        model.forward_dynamics(np.zeros(3), np.zeros(3), np.array([0, np.nan, 0]))


@pytest.mark.parametrize("kwargs, pattern", [
    (dict(name="b", parent=5), "parent index 5 does not name an existing body"),
    (dict(name="b", parent="nope"), "no body named 'nope'"),
    (dict(name="b", parent=None, mass=-2.0), "mass must be finite and non-negative"),
    (dict(name="b", parent=None, mass=1.0, inertia=np.diag([1.0, -1.0, 1.0])), "not positive definite"),
    (dict(name="b", parent=None, axis=[0, 0, 0]), "zero length"),
    (dict(name="b", parent=None, joint_type="helical"), "joint_type must be"),
    (dict(name="b", parent=None, placement=np.diag([2.0, 1, 1, 1])), "not a rotation matrix"),
])
def test_add_body_rejects_invalid_bodies(kwargs, pattern):
    model = hovi.Model()
    with pytest.raises(hovi.ModelError, match=pattern):
        model.add_body(**kwargs)


def test_massless_joint_is_reported_with_the_fixes():
    model = hovi.Model()
    model.add_body("ghost", parent=None)
    with pytest.raises(hovi.ModelError, match="'ghost_joint' moves no mass.*fixed joint, or set an armature"):
        model.forward_dynamics([0.0], [0.0])
    model.set_armature("ghost_joint", 0.1)  # a rotor alone: q̈ = tau / a
    np.testing.assert_allclose(model.forward_dynamics([0.0], [0.0], [0.5]), [5.0], rtol=1e-15)


def test_armature_api():
    model = hovi.examples.models.pendulum(3)
    np.testing.assert_array_equal(model.armature, np.zeros(3))
    model.set_armature("joint2", 0.25)
    model.set_armature(0, 0.5)
    np.testing.assert_array_equal(model.armature, [0.5, 0.25, 0.0])
    model.armature = [0.0, 0.0, 1.0]  # replaces every value
    np.testing.assert_array_equal(model.armature, [0.0, 0.0, 1.0])
    assert model.copy().armature[2] == 1.0
    for bad, exc, pattern in [(-0.1, hovi.ModelError, "armature must be finite and non-negative, got -0.1"),
                              (float("inf"), hovi.ModelError, "finite and non-negative")]:
        with pytest.raises(exc, match=pattern):
            model.set_armature(1, bad)
    with pytest.raises(hovi.ModelError, match="no joint named 'elbow'"):
        model.set_armature("elbow", 0.1)
    with pytest.raises(ValueError, match=r"armature must be a 1-D array of length 3, got shape \(2,\)"):
        model.armature = [0.1, 0.2]
    with pytest.raises(ValueError, match="armature contains NaN"):
        model.armature = [0.1, np.nan, 0.2]
    with pytest.raises(hovi.ModelError, match="joint 'joint3': armature must be finite and non-negative"):
        model.armature = [0.1, 0.2, -1.0]
    np.testing.assert_array_equal(model.armature, [0.0, 0.0, 1.0])  # all or nothing


def test_pendulum_rejects_bad_parameters():
    with pytest.raises(hovi.ModelError, match="at least 1"):
        hovi.examples.models.pendulum(0)
    with pytest.raises(hovi.ModelError, match="positive"):
        hovi.examples.models.pendulum(3, length=-1)


def test_force_elements_reject_bad_input():
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(hovi.ModelError, match="no joint named 'elbow'"):
        model.add_spring("elbow", 1.0)
    with pytest.raises(hovi.ModelError, match="joint index 7 out of range"):
        model.add_damper(7, 0.1)
    with pytest.raises(hovi.ModelError, match="no body named 'hand'"):
        model.add_drag("hand", 0.1)
    with pytest.raises(hovi.ModelError, match="non-negative"):
        model.add_drag(0, -1.0)
    with pytest.raises(ValueError, match="frame must be 'world' or 'body'"):
        model.add_point_wrench(0, force=[1, 0, 0], frame="tool")
    with pytest.raises(hovi.ModelError, match="control index 0 does not exist"):
        model.add_point_wrench(0, force=[1, 0, 0], control=0)
    with pytest.raises(hovi.ModelError, match="must be finite"):
        model.add_spring(0, float("nan"))
    k = model.add_actuator("joint2", gear=2.0)
    np.testing.assert_array_equal(model.actuation[:, k], [0, 2.0, 0])


@pytest.mark.parametrize("call, pattern", [
    (lambda m: m.add_damper(1, -0.5), r"add_damper: joint 'joint2' \(index 1\): damping must be finite and "
                                      r"non-negative, got -0.5"),
    (lambda m: m.add_damper("joint1", np.nan), r"add_damper: joint 'joint1' .*damping must be finite and non-negative, "
                                               r"got nan"),
    (lambda m: m.add_damper(0, np.inf), "damping must be finite and non-negative, got inf"),
    (lambda m: m.add_spring(0, np.nan), r"add_spring: joint 'joint1' \(index 0\): stiffness must be finite, got nan"),
    (lambda m: m.add_spring(2, 1.0, -np.inf), r"add_spring: joint 'joint3' .*rest must be finite, got -inf"),
    (lambda m: m.add_spring(2, 1e200, 1e200), r"stiffness \* rest \(the preload\) must be finite, got inf"),
    (lambda m: m.add_actuator(0, gear=np.nan), "add_actuator: joint 'joint1' .*gear must be finite, got nan"),
    (lambda m: m.add_drag(1, -1.0), "add_drag: body 'link2': linear and angular must be finite and non-negative, "
                                    "got linear -1, angular 0"),
    (lambda m: m.add_drag("link1", 0.1, np.nan), "add_drag: body 'link1': .*angular nan"),
])
def test_force_elements_refuse_bad_parameters_naming_the_joint(call, pattern):
    """Issue 30: NaN and infinity everywhere, and a negative damper or drag (which would feed energy
    in), are refused naming the joint (or body) and the value; the model is left unchanged."""
    model = hovi.examples.models.pendulum(3)
    with pytest.raises(hovi.ModelError, match=pattern):
        call(model)
    assert not model.joint_damping.any() and not model.stiffness.any() and model.n_wrenches == 0


def test_a_negative_spring_stiffness_is_allowed():
    model = hovi.examples.models.pendulum(2)
    model.add_spring(0, -2.0, 0.1)  # conservative still: V = 1/2 k (q - rest)^2
    assert model.stiffness[0] == -2.0


@pytest.mark.parametrize("inertia, pattern", [
    (np.diag([0.1, 0.1, 0.3]), r"izz = 0.3 exceeds ixx \+ iyy = 0.2"),
    (np.diag([0.5, 0.1, 0.2]), r"ixx = 0.5 exceeds iyy \+ izz = 0.3"),
    (np.full((3, 3), 0.1), r"the largest principal moment 0.3 exceeds the sum of the other two"),  # diagonal fine
])
def test_an_inertia_outside_the_triangle_inequality_is_refused_naming_the_body(inertia, pattern):
    model = hovi.Model()
    with pytest.raises(hovi.ModelError, match=r"^body 'b' \(joint 'b_joint'\): rotational inertia violates the "
                                              r"triangle inequality: " + pattern):
        model.add_body("b", None, mass=1.0, inertia=inertia)
    assert model.n == 0


@pytest.mark.parametrize("inertia", [np.diag([0.0, 0.1, 0.1]), np.diag([0.1, 0.1, 0.2]),
                                     np.diag([0.1, 0.1, 0.2 * (1 + 1e-12)]), np.zeros((3, 3))])
def test_rods_plates_and_round_off_on_the_triangle_inequality_are_accepted(inertia):
    model = hovi.Model()
    model.add_body("b", None, mass=1.0 if inertia.any() else 0.0, inertia=inertia)
    assert model.n == 1
