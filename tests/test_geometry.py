"""hovi.geometry: default shapes sit on the model's joints and centres of mass (checked against the
kinematics), package:// resolution, motion sampling."""
import numpy as np
import pytest

import hovi
from hovi.geometry import body_frames, default_shapes, model_shapes, motion_arrays, resolve_mesh, sample_configurations


def world(model, q, shape):
    return body_frames(model, q)[shape.body] @ shape.origin


def test_default_capsules_join_the_joints_and_spheres_sit_at_the_centres_of_mass(rng):
    model = hovi.examples.models.pendulum(4)
    q = rng.uniform(-1, 1, 4)
    shapes = default_shapes(model)
    joints = model.joint_placements(q)[:, :3, 3]
    coms = model.body_poses(q)[:, :3, 3]
    cylinders = [s for s in shapes if s.kind == "cylinder"]
    assert len(cylinders) == 4
    for s in cylinders:
        T = world(model, q, s)
        half = T[:3, 2] * s.size[1] / 2  # the cylinder runs along its z axis
        start, end = T[:3, 3] - half, T[:3, 3] + half
        np.testing.assert_allclose(start, joints[s.body], atol=1e-12)
        expected_end = joints[s.body + 1] if s.body + 1 < 4 else 2 * coms[s.body] - joints[s.body]
        np.testing.assert_allclose(end, expected_end, atol=1e-12)
    com_spheres = sorted((s for s in shapes if s.name.startswith("com")), key=lambda s: s.body)
    np.testing.assert_allclose([world(model, q, s)[:3, 3] for s in com_spheres], coms, atol=1e-12)


def test_a_model_with_visuals_keeps_them():
    model = hovi.examples.models.pendulum(2)
    model.add_visual(0, "box", [0.1, 0.2, 0.3])
    (shape,) = model_shapes(model)
    assert shape.kind == "box" and shape.body == 0
    np.testing.assert_allclose(shape.size, [0.1, 0.2, 0.3])


def test_package_names_resolve_through_the_search_path(tmp_path, monkeypatch):
    (tmp_path / "share" / "my_robot" / "meshes").mkdir(parents=True)
    mesh = tmp_path / "share" / "my_robot" / "meshes" / "a.stl"
    mesh.write_bytes(b"solid a\nendsolid a\n")
    assert resolve_mesh("package://my_robot/meshes/a.stl", [tmp_path / "share"]) == str(mesh)
    assert resolve_mesh("package://my_robot/meshes/a.stl", [tmp_path / "share" / "my_robot"]) == str(mesh)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(tmp_path / "share"))
    assert resolve_mesh("package://my_robot/meshes/a.stl") == str(mesh)
    assert resolve_mesh(str(mesh)) == str(mesh)
    with pytest.raises(FileNotFoundError, match="package 'other' not found in"):
        resolve_mesh("package://other/a.stl")
    with pytest.raises(FileNotFoundError, match="does not exist"):
        resolve_mesh(str(tmp_path / "missing.stl"))


def test_motion_sampling_interpolates_and_checks_its_input():
    t = np.array([0.0, 0.5, 1.0])
    q = np.array([[0.0, 1.0], [1.0, 3.0], [0.0, 5.0]])
    frame_t, frames = sample_configurations(q, t, fps=4)
    np.testing.assert_allclose(frame_t, [0, 0.25, 0.5, 0.75, 1.0])
    np.testing.assert_allclose(frames, [[0, 1], [0.5, 2], [1, 3], [0.5, 4], [0, 5]])
    with pytest.raises(ValueError, match="strictly increasing"):
        sample_configurations(q, t[::-1], fps=4)
    with pytest.raises(ValueError, match="fps must be positive"):
        sample_configurations(q, t, fps=0)
    with pytest.raises(ValueError, match="finite"):
        sample_configurations(q * np.nan, t, fps=4)
    model = hovi.examples.models.pendulum(2)
    traj = hovi.Integrator(model, order=2, dt=0.1).rollout(np.zeros(2), 3)
    t_traj, q_traj = motion_arrays(model, traj)
    np.testing.assert_array_equal(q_traj, traj.q)
    np.testing.assert_allclose(motion_arrays(model, q, rate=10)[0], [0, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        motion_arrays(model, np.zeros((3, 5)))
