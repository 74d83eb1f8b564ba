"""hovi.vis.video: triangle meshes of the shapes (volumes against the exact ones), mesh simplification,
and MP4/GIF files with the expected frames and size, rendered without a display."""
from pathlib import Path

import numpy as np
import pytest

import hovi
from conftest import erd_urdf

video = pytest.importorskip("hovi.vis.video")
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
    traj = hovi.Integrator(model, s=2, dt=0.01).rollout(np.full(3, 0.5), 50)  # 0.5 s
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


def test_terrain_scene_cuts_the_gaps_and_clips_the_boxes():
    from hovi.contact import Box, Gap, Terrain
    terrain = Terrain(ground=0.1, gaps=[Gap(0.2, 0.4, 0.5), Gap(30.0, 31.0)], boxes=[Box(-0.3, -0.1, 0.3), Box(20, 21, 1)])
    lines, shapes = video.terrain_scene(terrain, np.array([[0.0, 0.0, 0.0], [1.0, 0.5, 0.5]]))
    assert np.all(lines[..., 2] == 0.1)
    xs = lines[..., 0]
    inside = (xs > 0.2 + 1e-12) & (xs < 0.4 - 1e-12)
    assert not inside.any()  # no line end in the gap, and no line along x crosses it:
    assert not ((xs.min(axis=1) < 0.3) & (xs.max(axis=1) > 0.3)).any()
    assert len(lines) > 20
    lo, hi = lines[..., :2].reshape(-1, 2).min(axis=0), lines[..., :2].reshape(-1, 2).max(axis=0)
    names = {s.name: s for s in shapes}
    assert set(names) == {"terrain_gap_0", "terrain_box_0"}  # the far gap and box are out of view
    gap, box = names["terrain_gap_0"], names["terrain_box_0"]
    assert all(s.body == -1 and s.kind == "box" for s in shapes)
    assert gap.size[0] == pytest.approx(0.2) and gap.size[1] == pytest.approx(hi[1] - lo[1])
    assert gap.origin[2, 3] + gap.size[2] / 2 < 0.1  # just under the ground
    assert box.size[:2] == pytest.approx([0.2, hi[1] - lo[1]])  # infinite in y: cut at the grid
    assert box.origin[2, 3] + box.size[2] / 2 == pytest.approx(0.3) and box.origin[2, 3] - box.size[2] / 2 < 0.1


def test_contact_force_arrows(tmp_path):
    """ForceArrows of a landing: none in the air, the mean force of the frame's steps (an impact's
    impulse over the frame), at the end the weight's length over the four feet; the video draws
    them red, with the terrain."""
    import imageio.v3 as iio
    from hovi.contact import Terrain
    from hovi.vis.geometry import sample_configurations
    from test_viewer import littledog_landing
    st, traj, arrows = littledog_landing()
    assert arrows.forces.shape == (60, 4, 3) and arrows.times[1] == pytest.approx(0.005)
    frame_t, frames_q = sample_configurations(traj.q, traj.t, 20)
    origins, vectors, shown = arrows.frames(st.model, frame_t, frames_q, 1 / 20)
    assert not shown[0].any() and shown[-1].all()
    unit = arrows.scale(st.model, traj.q[0]) * arrows.weight
    assert vectors[-1].sum(axis=0)[2] == pytest.approx(unit, rel=1e-3)
    c = traj.contact
    k = np.flatnonzero(c.active.any(axis=1))[0]  # the landing step; frames are 10 steps apart
    f = int(round(traj.t[k] * 20))
    window = (traj.t[:60] >= frame_t[f] - 0.025 - 1e-12) & (traj.t[:60] < frame_t[f] + 0.025 - 1e-12)  # half a frame
    assert window.sum() == 10
    mean = (c.world_impulses[window] / 0.005).mean(axis=0)
    np.testing.assert_allclose(vectors[f], mean * unit / arrows.weight, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(origins[-1, :, 2], 0.0, atol=2e-3)  # where the feet touch the ground
    frames = iio.imread(video.render_video(st.model, traj, tmp_path / "ld.gif", fps=20, size=(320, 240),
                                           terrain=Terrain(), arrows=arrows, time_stamp=False), index=None)
    red = [int(((f[..., 0] > 170) & (f[..., 1] < 80) & (f[..., 2] < 80)).sum()) for f in frames]
    assert red[0] < 5 and red[-1] > 30, red
    with pytest.raises(ValueError, match="ground or terrain, not both"):
        video.render_video(st.model, traj, tmp_path / "x.gif", ground=0.0, terrain=Terrain())
    with pytest.raises(TypeError, match="arrows must be a hovi.vis.video.ForceArrows"):
        video.render_video(st.model, traj, tmp_path / "x.gif", arrows=np.zeros(3))
    with pytest.raises(ValueError, match="forces must be"):
        video.ForceArrows([1], np.zeros((1, 3)), np.zeros(2), np.zeros((3, 1, 3)), 1.0)
    with pytest.raises(ValueError, match="weight must be"):
        video.ForceArrows([1], np.zeros((1, 3)), np.zeros(2), np.zeros((2, 1, 3)), 0.0)
    with pytest.raises(ValueError, match="no contact record"):
        video.ForceArrows.from_contacts(hovi.Integrator(hovi.examples.models.pendulum(1), s=1, dt=0.1).rollout(
            np.zeros(1), 2), st.contacts)
