"""A model changed after an Integrator (or a Linearizer, or a baseline) was made from it: every
later call raises hovi.ModelError naming the change, instead of silently using the old copy."""
import copy

import numpy as np
import pytest

import hovi
import hovi.baselines


def changes():
    """(name, change) for every way the Python API can change a model."""
    return [
        ("add_spring", lambda m: m.add_spring(0, 100.0)),
        ("add_damper", lambda m: m.add_damper(1, 0.5)),
        ("add_actuator", lambda m: m.add_actuator(0)),
        ("add_control", lambda m: m.add_control()),
        ("add_point_wrench", lambda m: m.add_point_wrench(1, force=[1.0, 0, 0])),
        ("add_drag", lambda m: m.add_drag(1, 0.1)),
        ("gravity", lambda m: setattr(m, "gravity", [0, 0, -1.62])),
        ("add_body", lambda m: m.add_body("extra", 2, axis=[1, 0, 0], mass=1.0, inertia=np.eye(3) * 0.01)),
        ("add_point_constraint", lambda m: m.add_point_constraint(2, target=[0, 0, -1.25], axes="z")),
        ("add_loop_constraint", lambda m: m.add_loop_constraint(0, [0, 0, 0], 2, [0, 0, 0], axes="x")),
        ("add_orientation_constraint", lambda m: m.add_orientation_constraint(0, np.eye(3))),
        ("add_joint_coupling", lambda m: m.add_joint_coupling([1.0, -1.0, 0.0])),
        ("set_armature", lambda m: m.set_armature("joint2", 0.05)),
        ("armature", lambda m: setattr(m, "armature", [0.1, 0.0, 0.2])),
    ]


@pytest.mark.parametrize("name,change", changes(), ids=[c[0] for c in changes()])
def test_every_call_raises_after_a_change(name, change):
    model = hovi.examples.models.pendulum(3)
    integ = hovi.Integrator(model, s=2, dt=0.01)
    lin = hovi.Linearizer(integ)
    q = np.zeros(3)
    traj = integ.rollout(q, 2)  # works before the change
    change(model)
    calls = [
        lambda: integ.rollout(q, 2),
        lambda: integ.step(q, np.zeros(3)),
        lambda: integ.momentum(q, q),
        lambda: integ.velocity(q, q),
        lambda: integ.energy(q, q),
        lambda: integ.del_residual(traj.control_points[0], np.zeros(3)),
        lambda: integ.newton_direction(traj.control_points[0], np.zeros(3)),
        lambda: integ.project(q),
        lambda: lin.del_jacobian(traj.control_points[0]),
        lambda: lin.linearize_at(traj.control_points[0]),
    ]
    for call in calls:
        with pytest.raises(hovi.ModelError, match=rf"model was changed \({name}\).*new hovi\.Integrator"):
            call()
    assert "order 4" in repr(integ)  # still printable


def test_a_new_integrator_sees_the_change_and_a_copy_keeps_the_old_model():
    model = hovi.examples.models.pendulum(2)
    old = model.copy()
    integ_old = hovi.Integrator(old, s=1)
    model.add_spring(0, 100.0)
    q0 = np.array([0.1, 0.0])
    with_spring = hovi.Integrator(model, s=1).rollout(q0, 50)
    without = integ_old.rollout(q0, 50)  # the copy was not changed: its integrator still works
    assert np.abs(with_spring.q - without.q).max() > 1e-3
    assert model.stiffness[0] == 100.0 and old.stiffness[0] == 0.0
    for c in (copy.copy(model), copy.deepcopy(model)):
        assert c.stiffness[0] == 100.0
        c.add_damper(0, 1.0)  # a copy changes independently
        assert model.joint_damping[0] == 0.0


def test_baselines_raise_after_a_change():
    model = hovi.examples.models.pendulum(2)
    hs = hovi.baselines.HermiteSimpson(model, 0.01)
    ad = hovi.baselines.AutodiffDel(model, 1, 0.01)
    model.add_spring(0, 10.0)
    with pytest.raises(hovi.ModelError, match=r"changed \(add_spring\).*HermiteSimpson"):
        hs.rollout(np.zeros(2), np.zeros(2), 3)
    with pytest.raises(hovi.ModelError, match=r"changed \(add_spring\).*AutodiffDel"):
        ad.residual(np.zeros((2, 2)), np.zeros(2))
