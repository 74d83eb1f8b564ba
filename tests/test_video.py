"""hovi.video: triangle meshes of the shapes (volumes against the exact ones), mesh simplification,
and MP4/GIF files with the expected frames and size, rendered without a display."""
from pathlib import Path

import numpy as np
import pytest

import hovi
from conftest import erd_urdf

video = pytest.importorskip("hovi.video")
pytest.importorskip("imageio_ffmpeg", reason="hovi[viewer] (imageio-ffmpeg) is not installed")


def volume(tris):
    """Enclosed volume by the divergence theorem (outward-oriented or not: absolute value)."""
    return abs(np.einsum("ij,ij->i", tris[:, 0], np.cross(tris[:, 1], tris[:, 2])).sum()) / 6


def test_primitive_triangles_enclose_the_right_volume():
    assert volume(video.box_triangles(np.array([0.1, 0.2, 0.3]))) == pytest.approx(0.006, rel=1e-12)
    sides = 16  # a regular 16-gon prism: area (sides / 2) r^2 sin(2 pi / sides)
    assert volume(video.cylinder_triangles(0.5, 2.0, sides)) == pytest.approx(sides / 2 * 0.25 * np.sin(2 * np.pi / sides) * 2.0, rel=1e-12)
    fine = volume(video.sphere_triangles(1.0, 48, 96))
    assert fine == pytest.approx(4 / 3 * np.pi, rel=2e-3)


def test_large_faces_are_subdivided_keeping_the_volume():
    box = video.box_triangles(np.array([3.0, 1.0, 0.02]))
    fine = video.subdivide(box, 0.3)
    assert len(fine) > 12 * 16
    edges = np.linalg.norm(fine - np.roll(fine, 1, axis=1), axis=-1)
    assert edges.max() <= 0.3 and volume(fine) == pytest.approx(0.06, rel=1e-12)
    assert len(video.subdivide(box, 10.0)) == 12


def test_vertex_clustering_keeps_the_shape_with_fewer_faces():
    tris = video.sphere_triangles(1.0, 60, 120)  # 14400 faces as an indexed mesh
    vertices, faces = np.unique(tris.reshape(-1, 3).round(12), axis=0, return_inverse=True)
    faces = faces.reshape(-1, 3)
    simple = video.cluster_vertices(vertices, faces, 2000)
    assert 100 < len(simple) <= 2000
    assert volume(simple) == pytest.approx(4 / 3 * np.pi, rel=0.05)
    np.testing.assert_allclose(np.abs(simple.reshape(-1, 3)).max(axis=0), 1.0, atol=0.05)


@pytest.mark.parametrize("suffix", [".mp4", ".gif"])
def test_video_has_the_expected_frames_and_size(tmp_path, suffix):
    import imageio.v3 as iio

    model = hovi.examples.models.pendulum(3)
    traj = hovi.Integrator(model, order=4, dt=0.01).rollout(np.full(3, 0.5), 50)  # 0.5 s
    out = video.render_video(model, traj, tmp_path / f"swing{suffix}", fps=20, size=(320, 240))
    frames = iio.imread(out, index=None)
    assert frames.shape[0] == 11 and frames.shape[1:3] == (240, 320)
    changed = np.abs(frames[0].astype(int) - frames[-1].astype(int)).max(axis=-1) > 40
    assert changed.sum() > 100  # the pendulum moved


def test_meshes_render(tmp_path):
    path = Path(erd_urdf("ur_description/urdf/ur5_robot.urdf"))
    model = hovi.Model.from_urdf(str(path))
    q = np.array([[0, -1.0, 1.0, 0, 0.5, 0], [0.5, -0.5, 1.5, 0, 0.5, 0]])
    out = video.render_video(model, q, tmp_path / "ur5.mp4", times=[0, 0.1], fps=10, package_dirs=[path.parents[3]])
    import imageio.v3 as iio
    frames = iio.imread(out, index=None)
    assert frames.shape == (2, 480, 640, 3)
    assert (frames[0] < 200).any(axis=-1).sum() > 2000  # the arm's grey on the white background


def robot_box(frame, background=255, threshold=40):
    """(width, height) fractions of the frame spanned by the pixels that are not the white background."""
    rows, cols = np.nonzero((background - frame.astype(int)).max(axis=-1) > threshold)
    return (cols.max() - cols.min() + 1) / frame.shape[1], (rows.max() - rows.min() + 1) / frame.shape[0]


def test_the_camera_fits_the_motion_and_frames_show_the_time(tmp_path, monkeypatch):
    """A UR5 with its example-robot-data meshes (found without package_dirs) fills the frame: its
    bounding box covers more than half of it; the time stamp is drawn in the top left corner."""
    import imageio.v3 as iio

    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    model = hovi.Model.from_urdf(erd_urdf("ur_description/urdf/ur5_robot.urdf"))
    q = np.array([[0, -1.0, 1.0, 0, 0.5, 0], [0.5, -0.5, 1.5, 0, 0.5, 0]])
    plain = iio.imread(video.render_video(model, q, tmp_path / "ur5.gif", times=[0, 0.1], fps=10, time_stamp=False),
                       index=None)
    width, height = robot_box(plain[0])
    assert width * height > 0.5 and max(width, height) > 0.85, f"the UR5 spans {width:.0%} x {height:.0%}"
    stamped = iio.imread(video.render_video(model, q, tmp_path / "ur5_t.gif", times=[0, 0.1], fps=10), index=None)
    corner = np.abs(stamped[1, :40, :160].astype(int) - plain[1, :40, :160].astype(int)).max(axis=-1) > 40
    assert corner.sum() > 50  # "t = 0.10 s"


def test_ground_grid_and_progress_bar(tmp_path, capsys):
    import imageio.v3 as iio

    model = hovi.examples.models.pendulum(2)
    q = np.array([[0.3, 0.2], [0.5, 0.1]])
    bare = iio.imread(video.render_video(model, q, tmp_path / "a.gif", times=[0, 0.1], fps=10, time_stamp=False),
                      index=None)
    grid = iio.imread(video.render_video(model, q, tmp_path / "b.gif", times=[0, 0.1], fps=10, time_stamp=False,
                                         ground=-1.2, progress=True), index=None)
    assert (np.abs(bare[0].astype(int) - grid[0].astype(int)).max(axis=-1) > 40).sum() > 200
    assert "rendering b.gif" in capsys.readouterr().err
    with pytest.raises(ValueError, match="ground must be a finite height"):
        video.render_video(model, q, tmp_path / "c.gif", times=[0, 0.1], ground=np.inf)


def test_bad_arguments_raise(tmp_path):
    model = hovi.examples.models.pendulum(2)
    with pytest.raises(ValueError, match=r"\.mp4 or \.gif"):
        video.render_video(model, np.zeros((2, 2)), tmp_path / "a.avi")
    with pytest.raises(ValueError, match="multiples of 16"):
        video.render_video(model, np.zeros((2, 2)), tmp_path / "a.mp4", size=(100, 100))
