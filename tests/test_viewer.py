"""hovi.vis.viewer: standalone HTML animations rendered by a headless browser (the robot is drawn and
moves), markers, the live meshcat server, and clear errors."""
import base64
import re
import warnings
from pathlib import Path

import numpy as np
import pytest

import hovi
from conftest import erd_urdf
from headless_browser import changed_fraction, screenshot

viewer = pytest.importorskip("hovi.vis.viewer", reason="hovi[viewer] (meshcat) is not installed")

UR5 = "ur_description/urdf/ur5_robot.urdf"


def ur5_and_package_dir():
    path = Path(erd_urdf(UR5))
    return hovi.Model.from_urdf(str(path)), path.parents[3]  # .../share holds example-robot-data/robots/...


def scene_objects(html):
    """{path: object type} of the set_object commands recorded in an exported HTML file."""
    import umsgpack
    blobs = re.search(r"for \(const blob of \[(.*?)\]\)", Path(html).read_text(), re.S).group(1)
    commands = [umsgpack.unpackb(base64.b64decode(b)) for b in re.findall(r'"([A-Za-z0-9+/=]+)"', blobs)]
    return {c["path"]: c["object"]["object"]["type"] for c in commands if c["type"] == "set_object"}


def animation_tracks(html):
    """{path: {track name: [(frame, value), ...]}} of the set_animation command of an exported HTML file."""
    import umsgpack
    blobs = re.search(r"for \(const blob of \[(.*?)\]\)", Path(html).read_text(), re.S).group(1)
    commands = [umsgpack.unpackb(base64.b64decode(b)) for b in re.findall(r'"([A-Za-z0-9+/=]+)"', blobs)]
    animation = next(c for c in commands if c["type"] == "set_animation")
    return {a["path"]: {t["name"]: [(k["time"], k["value"]) for k in t["keys"]] for t in a["clip"]["tracks"]}
            for a in animation["animations"]}


def drawn_box(image, background, threshold=40):
    """(width, height) fractions of the frame spanned by the pixels that differ from background."""
    rows, cols = np.nonzero(np.abs(image.astype(int) - background.astype(int)).max(axis=2) > threshold)
    return (cols.max() - cols.min() + 1) / image.shape[1], (rows.max() - rows.min() + 1) / image.shape[0]


def check_animation(model, traj, tmp_path, name, package_dirs=()):
    """Screenshots at two times and with the model hidden: the model is drawn and moves; returns
    the early screenshot and the background."""
    html = viewer.animation_html(model, traj, tmp_path / f"{name}.html", package_dirs=package_dirs)
    early = screenshot(html, tmp_path / f"{name}_early.png", "t=0.1")
    late = screenshot(html, tmp_path / f"{name}_late.png", "t=0.9")
    hidden = viewer.Viewer(model, package_dirs, server=False)
    hidden.frame_model(traj.q)
    hidden.show_model(False)
    background = screenshot(hidden.export_html(tmp_path / f"{name}_hidden.html"), tmp_path / f"{name}_hidden.png")
    assert early.shape == (480, 640, 3)
    pixels = early.shape[0] * early.shape[1]
    for when, image in (("0.1", early), ("0.9", late)):
        drawn = changed_fraction(image, background) * pixels
        assert drawn > 500, f"{name} at t = {when} s: the model covers only {drawn:.0f} pixels"
    moved = changed_fraction(early, late) * pixels
    assert moved > 500, f"{name}: only {moved:.0f} pixels changed between t = 0.1 and 0.9 s"
    return early, background


def test_pendulum_animation_is_drawn_and_moves(tmp_path):
    model = hovi.examples.models.pendulum(5)
    traj = hovi.Integrator(model, s=2, dt=0.01).rollout(np.full(5, 0.6), 100)
    check_animation(model, traj, tmp_path, "pendulum5")


def test_urdf_with_meshes_animation_is_drawn_and_moves(tmp_path, monkeypatch):
    """A UR5 of the installed example-robot-data, its meshes found without package_dirs, fills the view."""
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    model, _ = ur5_and_package_dir()
    assert {v["shape"] for v in model.visuals} == {"mesh"}
    traj = hovi.Integrator(model, s=2, dt=0.01).rollout(np.array([0, -1.0, 1.0, 0, 0.5, 0]), 100)
    from hovi.vis.geometry import MeshNotFoundWarning
    with warnings.catch_warnings():
        warnings.simplefilter("error", MeshNotFoundWarning)  # every mesh found
        early, background = check_animation(model, traj, tmp_path, "ur5")
    width, height = drawn_box(early, background)
    assert max(width, height) > 0.6, f"the UR5 spans only {width:.0%} x {height:.0%} of the view"
    assert '<div id="hovi-time"' in (tmp_path / "ur5.html").read_text()


def test_ground_grid_terrain_and_time_stamp(tmp_path):
    """A robot example's animation (report.animate) holds its terrain boxes, a ground grid and the clock."""
    from hovi.examples import ROBOT_EXAMPLE, get
    from hovi.examples.paper import report

    example = get(ROBOT_EXAMPLE, "littledog").build(quick=True)
    t = np.array([0.0, 0.3])

    class Motion:  # what animate reads of a trajopt.Result: the example's guess (a trot) over 0.3 s
        trajectory = {"t": t, "q": np.asarray(example.guess[0](t))}

    html, mp4 = report.animate(example, Motion(), str(tmp_path), fps=5)
    objects = scene_objects(html)
    assert objects.get("/meshcat/hovi/ground/grid") == "LineSegments"
    terrain = [p for p in objects if p.startswith("/meshcat/hovi/world/")]
    assert len(terrain) == len(example.scenery.shapes) >= 2
    text = Path(html).read_text()
    assert '<div id="hovi-time" data-start="0.0"' in text
    still = screenshot(Path(html), tmp_path / "littledog.png", "t=0.2")
    assert still.shape == (480, 640, 3)
    assert Path(mp4).stat().st_size > 1000


def test_markers_and_arrows_are_drawn(tmp_path):
    model = hovi.examples.models.pendulum(2)
    plain = viewer.Viewer(model, server=False)
    plain.frame_model()
    marked = viewer.Viewer(model, server=False)
    marked.frame_model()
    marked.add_marker("target", [0.3, 0.0, -0.5], radius=0.08)
    marked.add_arrow("force", [0.0, 0.0, -1.0], [0.5, 0.0, 0.0], radius=0.03)
    a = screenshot(plain.export_html(tmp_path / "plain.html"), tmp_path / "plain.png")
    b = screenshot(marked.export_html(tmp_path / "marked.html"), tmp_path / "marked.png")
    assert changed_fraction(a, b) > 0.002
    marked.delete_markers()
    c = screenshot(marked.export_html(tmp_path / "cleared.html"), tmp_path / "cleared.png")
    assert changed_fraction(a, c) < 0.0005


def littledog_landing(steps=60):
    """LittleDog's standing scene dropped from 2 cm, 0.3 s, and its contact forces as arrows."""
    from hovi.examples.standing import standing
    from hovi.vis.video import ForceArrows
    st = standing("littledog")
    q0 = st.q0.copy()
    q0[2] += 0.02
    traj = st.integrator.rollout(q0, steps, u=st.u)
    arrows = ForceArrows.from_contacts(traj, st.contacts,
                                       names=[c.name for c in st.robot.contacts])
    return st, traj, arrows


def test_terrain_and_contact_force_arrows(tmp_path):
    """A contact simulation's animation: the terrain's gap and box as world shapes, an arrow per contact
    (shaft and head) animated with the motion, hidden in the air, as long as the force over the weight
    times the model's size when it stands; drawn over the model (a screenshot differs from one without)."""
    from hovi.contact import Box, Gap, Terrain
    from hovi.vis.video import model_size
    st, traj, arrows = littledog_landing()
    terrain = Terrain(gaps=[Gap(0.25, 0.4, 0.3)], boxes=[Box(-0.5, -0.3, 0.05, y0=-0.1)])
    html = viewer.animation_html(st.model, traj, tmp_path / "ld.html", fps=20, terrain=terrain, arrows=arrows)
    objects = scene_objects(html)
    assert objects.get("/meshcat/hovi/ground/grid") == "LineSegments"
    assert objects.get("/meshcat/hovi/world/terrain_gap_0") == objects.get("/meshcat/hovi/world/terrain_box_0") == "Mesh"
    tracks = animation_tracks(html)
    shafts = [f"/meshcat/hovi/forces/{c:02d}_{name}/shaft" for c, name in enumerate(arrows.names)]
    frames = len(tracks["/meshcat/hovi/bodies/000_body_x"][".position"])
    assert frames == 7  # 0.3 s at 20 frames per second
    for path in shafts + [p.replace("shaft", "head") for p in shafts]:
        assert {".position", ".quaternion", ".scale"} <= set(tracks[path]) and len(tracks[path][".scale"]) == frames
        assert tracks[path][".scale"][0][1] == pytest.approx([1e-6] * 3)  # in the air at t = 0
    unit = arrows.scale(st.model, traj.q[0]) * arrows.weight  # the weight's length
    head = 6 * 0.012 * model_size(st.model, traj.q[0])  # the arrows are as thick as the model is large
    standing = sum(tracks[p][".scale"][-1][1][1] + head for p in shafts)
    assert standing == pytest.approx(unit, rel=1e-2)  # the four forces carry the weight
    # on flat ground (the camera on the robot): the arrows show, over the legs
    plain = viewer.animation_html(st.model, traj, tmp_path / "plain.html", fps=20, terrain=Terrain())
    assert not any(p.startswith("/meshcat/hovi/forces") for p in scene_objects(plain))
    flat = viewer.animation_html(st.model, traj, tmp_path / "flat.html", fps=20, terrain=Terrain(), arrows=arrows)
    a = screenshot(plain, tmp_path / "plain.png", "t=0.3")
    b = screenshot(flat, tmp_path / "arrows.png", "t=0.3")
    assert changed_fraction(a, b) * a.shape[0] * a.shape[1] > 500
    with pytest.raises(ValueError, match="ground or terrain, not both"):
        viewer.animation_html(st.model, traj, tmp_path / "x.html", ground=0.0, terrain=terrain)
    with pytest.raises(TypeError, match="arrows must be a hovi.vis.video.ForceArrows"):
        viewer.Viewer(st.model, server=False).play(traj, arrows="forces")
    with pytest.raises(TypeError, match="terrain must be a hovi.contact.Terrain"):
        viewer.Viewer(st.model, server=False).add_terrain(0.0)


def test_html_is_standalone():
    model = hovi.examples.models.pendulum(3)
    html = viewer.Viewer(model, server=False).html()
    assert "MeshCat.Viewer" in html and "<script src=" not in html  # meshcat's JavaScript is inlined


def test_live_viewer_starts_a_local_server():
    model = hovi.examples.models.pendulum(3)
    v = viewer.Viewer(model)
    try:
        assert v.url.startswith("http://127.0.0.1:")
        v.display(np.full(3, 0.2))
        v.play(np.zeros((10, 3)))
        assert v.duration == pytest.approx(9 / 30)
        v.close()
        assert v.url is None and "MeshCat.Viewer" in v.html()  # the recording outlives the server
    finally:
        v.close()


def test_bad_input_raises_clear_errors(tmp_path):
    model = hovi.examples.models.pendulum(3)
    v = viewer.Viewer(model, server=False)
    with pytest.raises(ValueError, match="3 finite numbers"):
        v.display([0.0, np.nan, 0.0])
    with pytest.raises(ValueError, match=r"\(N, 3\)"):
        v.play(np.zeros((10, 4)))
    with pytest.raises(ValueError, match="strictly increasing"):
        v.play(np.zeros((3, 3)), times=[0.0, 0.2, 0.1])
    with pytest.raises(ValueError, match="non-zero"):
        v.add_arrow("f", [0, 0, 0], [0, 0, 0])
    with pytest.raises(ValueError, match="position must be 3 finite numbers"):
        v.add_marker("m", [0.0, np.inf, 0.0])
    with pytest.raises(ValueError, match="target must be 3 finite numbers"):
        v.set_camera([0.0, 0.0], [1.0, 0.0, 0.0])
    urdf = tmp_path / "mesh.urdf"
    urdf.write_text('<robot name="r"><link name="base"/><link name="a"><inertial><mass value="1"/>'
                    '<inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial><visual><geometry>'
                    '<mesh filename="package://nowhere/a.stl"/></geometry></visual></link><joint name="j" '
                    'type="continuous"><parent link="base"/><child link="a"/></joint></robot>')
    from hovi.vis.geometry import MeshNotFoundWarning
    with pytest.warns(MeshNotFoundWarning, match="package://nowhere/a.stl"):
        drawn = viewer.Viewer(hovi.Model.from_urdf(str(urdf)), server=False)
    assert {s.kind for s in drawn.shapes} <= {"cylinder", "sphere"}  # the link's capsule in its place
    with pytest.raises(ValueError, match="height must be a finite number"):
        v.add_ground(np.nan)
