"""hovi.vis.geometry: default shapes sit on the model's joints and centres of mass (checked against the
kinematics), package:// resolution, motion sampling."""
import warnings
from pathlib import Path

import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from hovi.vis.geometry import (MeshNotFoundWarning, body_frames, default_shapes, ground_lines, model_shapes, motion_arrays,
                           resolve_mesh, sample_configurations, shape_corners)

MISSING_MESH_URDF = ('<robot name="r"><link name="base"/><link name="a"><inertial><origin xyz="0 0 -0.3"/><mass value="1"/>'
                     '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial><visual><geometry>'
                     '<mesh filename="package://nowhere/a.stl"/></geometry></visual></link><joint name="j" '
                     'type="continuous"><parent link="base"/><child link="a"/></joint></robot>')


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
    with pytest.raises(FileNotFoundError, match="package 'other' not found in .*--package-dir"):
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
    traj = hovi.Integrator(model, s=1, dt=0.1).rollout(np.zeros(2), 3)
    t_traj, q_traj = motion_arrays(model, traj)
    np.testing.assert_array_equal(q_traj, traj.q)
    np.testing.assert_allclose(motion_arrays(model, q, rate=10)[0], [0, 0.1, 0.2])
    with pytest.raises(ValueError, match=r"\(N, 2\)"):
        motion_arrays(model, np.zeros((3, 5)))


@pytest.mark.parametrize("urdf", ["ur_description/urdf/ur5_robot.urdf", "panda_description/urdf/panda.urdf"])
def test_example_robot_data_meshes_are_found_without_a_flag(urdf, monkeypatch):
    """package://example-robot-data/... meshes of the installed example-robot-data resolve with no
    package_dirs and no ROS_PACKAGE_PATH (its robots folder, found as getModelPath finds it)."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    model = hovi.Model.from_urdf(erd_urdf(urdf))
    meshes = [v["filename"] for v in model.visuals if v["shape"] == "mesh"]
    assert meshes and all(m.startswith("package://") for m in meshes)
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshNotFoundWarning)
        shapes = model_shapes(model)
    assert [s.kind for s in shapes].count("mesh") == len(meshes)
    assert all(Path(s.mesh_path).is_file() for s in shapes if s.kind == "mesh")


def test_a_missing_mesh_is_drawn_as_the_links_capsule_with_a_warning(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    urdf = tmp_path / "mesh.urdf"
    urdf.write_text(MISSING_MESH_URDF)
    model = hovi.Model.from_urdf(str(urdf))
    with pytest.warns(MeshNotFoundWarning, match=r"1 mesh file\(s\) not found.*'package://nowhere/a.stl'.*--package-dir"):
        shapes = model_shapes(model)
    assert {s.kind for s in shapes} == {"cylinder", "sphere"} and all(s.body == 0 for s in shapes)
    capsule = next(s for s in shapes if s.kind == "cylinder")
    assert capsule.size[1] == pytest.approx(0.6)  # from the joint through the centre of mass and as far again
    with pytest.raises(FileNotFoundError, match="package 'nowhere' not found"):
        model_shapes(model, missing="raise")
    with pytest.raises(ValueError, match="missing must be"):
        model_shapes(model, missing="ignore")


def test_shape_corners_and_the_ground_grid():
    model = hovi.examples.models.pendulum(2)
    model.add_visual(0, "box", [0.1, 0.2, 0.3])
    (box,) = model_shapes(model)
    corners = shape_corners(box)
    np.testing.assert_allclose(corners.min(axis=0), [-0.05, -0.1, -0.15])
    np.testing.assert_allclose(corners.max(axis=0), [0.05, 0.1, 0.15])
    lines = ground_lines(np.array([[0.0, 0.0, 1.0], [2.0, 1.0, 3.0]]), height=-0.5, margin=0.5)
    assert lines.shape[1:] == (2, 3) and np.all(lines[:, :, 2] == -0.5)
    assert lines[:, :, 0].min() <= -0.5 and lines[:, :, 0].max() >= 2.5
    assert lines[:, :, 1].min() <= -0.5 and lines[:, :, 1].max() >= 1.5
    assert 10 <= len(lines) <= 90
