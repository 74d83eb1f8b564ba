"""Models, integrators, linearizers and trajectories pickle (to other processes and cluster
workers): a restored model is the same model (joints, inertias, force elements, constraints,
visuals), and what it computes (mass matrices, DEL residuals, rollouts) is bit for bit the
original's."""
import pickle
import sys

import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from urdf_snippets import full_robot

PROPERTIES = ["n", "total_mass", "gravity", "body_names", "joint_names", "joint_types", "parents", "masses",
              "lower_limits", "upper_limits", "velocity_limits", "effort_limits", "damping", "friction", "mimic",
              "n_constraints", "n_controls", "actuation", "stiffness", "joint_damping", "n_wrenches"]


def everything():
    """A 4-link pendulum with every force element, armature, every kind of constraint and visuals."""
    model = hovi.examples.models.pendulum(4)
    model.gravity = [0.2, 0.0, -9.7]
    model.add_spring(0, 3.0, 0.2)
    model.add_spring(0, 1.0, -0.1)
    model.add_damper(2, 0.4)
    model.set_armature(1, 0.05)
    model.add_actuator(1, gear=2.0)
    c = model.add_control()
    model.add_point_wrench(3, force=[1, 0, 2], torque=[0, 0.1, 0], point=[0, 0, -0.5], frame="body", control=c)
    model.add_point_wrench(1, force=[0, 0.5, 0])
    model.add_drag(2, 0.3, 0.1)
    model.add_point_constraint(3, point=[0, 0, -0.5], target=[0.1, 0.0, -1.9], axes="xz")
    model.add_joint_coupling([1, 0, -1, 0], 0.1)
    model.add_visual(2, "box", [0.1, 0.2, 0.3], rgba=[1, 0, 0, 1])
    model.add_visual(None, "mesh", filename="/meshes/base.stl", scale=[0.001, 0.001, 0.001])
    return model


def constrained_pair():
    """Two pendulums with a loop closure between them and an orientation held."""
    model = hovi.examples.models.pendulum(2)
    model.add_body("other", None, axis=[1, 0, 0], placement=np.diag([1.0, 1, 1, 1]) + np.eye(4, k=3) * 0.3,
                   mass=1.0, com=[0, 0, -0.25], inertia=np.eye(3) * 0.02)
    model.add_loop_constraint(1, [0, 0, -0.5], 2, [0, 0, -0.5], axes="y")
    model.add_orientation_constraint(0, np.eye(3))
    return model


def roundtrip(obj):
    return pickle.loads(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))


def assert_same_model(a, b, rng):
    for name in PROPERTIES:
        x, y = getattr(a, name), getattr(b, name)
        assert np.array_equal(x, y) if not isinstance(x, dict) else x == y, name
    assert a.summary() == b.summary()
    for va, vb in zip(a.visuals, b.visuals, strict=True):
        for key in va:
            assert np.array_equal(va[key], vb[key]) if va[key] is not None else vb[key] is None, key
    for _ in range(3):
        v, qd = rng.uniform(-1, 1, (2, a.n))
        q = a.integrate(a.neutral(), v)
        for f in (a.mass_matrix, a.body_poses, a.joint_placements, a.potential_energy, a.constraint_values,
                  a.constraint_jacobian) + (() if a.free_base else (a.gravity_hessian,)):
            assert np.array_equal(f(q), getattr(b, f.__name__)(q)), f.__name__
        u = rng.uniform(-1, 1, a.n_controls)
        if not a.free_base:  # in joint coordinates only
            for x, y in zip(a.force_jacobians(q, qd, u), b.force_jacobians(q, qd, u)):
                assert np.array_equal(x, y)
        assert np.array_equal(a.forward_dynamics(q, qd), b.forward_dynamics(q, qd))


def test_model_with_everything(rng):
    model = everything()
    copy = roundtrip(model)
    assert copy is not model
    assert_same_model(model, copy, rng)
    assert copy.n_wrenches == 3 and copy.n_constraints == 3 and len(copy.visuals) == 2
    assert np.array_equal(copy.stiffness, model.stiffness)  # two springs on one joint, summed as before
    assert np.array_equal(copy.armature, [0, 0.05, 0, 0])
    a, b = hovi.Integrator(model, s=2, dt=0.01), hovi.Integrator(copy, s=2, dt=0.01)
    q, qd = a.project(np.array([0.3, -0.2, 0.5, 0.1]), np.zeros(4))
    p = a.momentum(q, qd)
    qc = q + np.outer(a.nodes, [0.01, -0.02, 0.01, 0.0])
    lam = rng.uniform(-1, 1, (2, 3))
    u = rng.uniform(-1, 1, 2)
    assert all(np.array_equal(x, y) for x, y in zip(a.del_residual(qc, p, u), b.del_residual(qc, p, u)))
    assert all(np.array_equal(x, y) for x, y in zip(a.constrained_residual(qc, lam, p, u),
                                                     b.constrained_residual(qc, lam, p, u)))
    ta, tb = a.rollout(q, 50, qdot0=qd, u=u), b.rollout(q, 50, qdot0=qd, u=u)
    for name in ("q", "p", "control_points", "multipliers", "iterations"):
        assert np.array_equal(getattr(ta, name), getattr(tb, name)), name
    copy.add_damper(0, 1.0)  # the copy is a model of its own
    assert model.joint_damping[0] == 0 and copy.joint_damping[0] == 1


def test_model_with_loop_and_orientation_constraints(rng):
    model = constrained_pair()
    assert_same_model(model, roundtrip(model), rng)


def test_urdf_models(rng):
    for model in (hovi.Model.from_urdf(full_robot()), hovi.Model.from_urdf(erd_urdf("panda_description/urdf/panda.urdf")),
                  hovi.Model.from_urdf(erd_urdf("solo_description/robots/solo12.urdf"), base="floating")):
        copy = roundtrip(model)
        assert_same_model(model, copy, rng)
        v, qd = rng.uniform(-0.5, 0.5, (2, model.n))
        q = model.integrate(model.neutral(), v)
        a, b = hovi.Integrator(model, s=3, dt=0.005), hovi.Integrator(copy, s=3, dt=0.005)
        assert np.array_equal(a.rollout(q, 20, qdot0=qd).q, b.rollout(q, 20, qdot0=qd).q)
    assert roundtrip(hovi.Model.from_urdf(full_robot())).mimic == {"j2": ("j1", 2.0, 0.1)}


def test_integrator_linearizer_and_trajectories(rng):
    model = everything()
    integ = hovi.Integrator(model, s=3, dt=0.005, tol=1e-12, direction="dense", reuse_jacobian=False,
                            max_iterations=17)
    q, qd = integ.project(np.array([0.3, -0.2, 0.5, 0.1]), np.zeros(4))
    copy = roundtrip(integ)
    assert (copy.s, copy.dt, copy.direction_path, copy._options) == (3, 0.005, "dense", integ._options)
    traj = integ.rollout(q, 30, qdot0=qd)
    again = copy.rollout(q, 30, qdot0=qd)
    assert np.array_equal(traj.q, again.q) and np.array_equal(traj.multipliers, again.multipliers)
    t2 = roundtrip(traj)
    assert np.array_equal(t2.q, traj.q) and t2.status == traj.status and np.array_equal(t2.energy, traj.energy)
    lin = roundtrip(hovi.Linearizer(integ))
    assert np.array_equal(lin.rollout_jacobians(t2)[0], hovi.Linearizer(integ).rollout_jacobians(traj)[0])
    batch = roundtrip(integ.rollout_batch(np.array([q, q]), 10, qdot0s=np.array([qd, -qd])))
    assert np.array_equal(batch.trajectory(0).q, integ.rollout(q, 10, qdot0=qd).q)
    shared = roundtrip([integ, integ.model])  # one pickle keeps one integrator with its model
    assert shared[0].model is shared[1]


def test_a_stale_integrator_does_not_pickle():
    model = hovi.examples.models.pendulum(3)
    integ = hovi.Integrator(model)
    model.add_damper(0, 1.0)
    with pytest.raises(hovi.ModelError, match="the model was changed"):
        pickle.dumps(integ)


@pytest.mark.parametrize("state,match", [(b"", "not a serialised hovi model"),
                                         (b"rubbish" * 10, "not a serialised hovi model"),
                                         (None, "truncated or corrupt")])
def test_bad_state_raises(state, match):
    if state is None:
        state = everything().__getstate__()[:-5]
    model = hovi.Model.__new__(hovi.Model)
    with pytest.raises(hovi.ModelError, match=match):
        model.__setstate__(state)


def test_mutated_or_truncated_bytes_are_refused_never_loaded():
    """Issue 30: the bytes carry a checksum of the model data; 400 random single-byte changes and
    truncations (seeded) are each refused with a ModelError, none loads (as another model)."""
    state = everything().__getstate__()
    rng = np.random.default_rng(30)
    messages = set()
    for trial in range(400):
        b = bytearray(state)
        if trial % 5 == 4:
            b = b[:int(rng.integers(0, len(state)))]
        else:
            k = int(rng.integers(len(b)))
            b[k] = (b[k] + int(rng.integers(1, 256))) % 256
        model = hovi.Model.__new__(hovi.Model)
        with pytest.raises(hovi.ModelError) as err:
            model.__setstate__(bytes(b))
        messages.add(str(err.value).split(":")[0])
    assert "model bytes are corrupted (checksum mismatch)" in messages  # most changes fall in the model data
    header = state.index(b"hovi.Model") + 10 + 4 + 4 + 8 + 8  # magic, version, byte order, length, checksum
    payload_byte = bytearray(state)
    payload_byte[header + 40] ^= 1
    with pytest.raises(hovi.ModelError, match=r"^model bytes are corrupted \(checksum mismatch\)"):
        hovi.Model.__new__(hovi.Model).__setstate__(bytes(payload_byte))


def test_bytes_of_the_previous_format_are_refused_with_the_version():
    state = bytearray(everything().__getstate__())
    start = state.index(b"hovi.Model") + len(b"hovi.Model")
    state[start:start + 4] = (3).to_bytes(4, sys.byteorder)
    with pytest.raises(hovi.ModelError, match="format 3: this hovi reads format 4"):
        hovi.Model.__new__(hovi.Model).__setstate__(bytes(state))


def test_a_urdf_model_with_an_inertia_outside_the_triangle_inequality_pickles(rng):
    from urdf_snippets import joint, link, robot
    with pytest.warns(UserWarning, match="link 'b': rotational inertia violates the triangle inequality"):
        model = hovi.Model.from_urdf(robot(link("a"), link("b", inertia=(0.1, 0, 0, 0.1, 0, 0.3)), joint("j", "a", "b")))
    assert_same_model(model, roundtrip(model), rng)
