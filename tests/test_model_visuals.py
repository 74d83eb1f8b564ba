"""Model visuals: URDF <visual> elements (shapes, origins composed through merged fixed joints,
colours, mesh file names) and add_visual, checked against hand-computed poses."""
from pathlib import Path

import numpy as np
import pytest

import hovi

REPO = Path(__file__).resolve().parents[1]


def rot_y(a):
    c, s = np.cos(a), np.sin(a)
    T = np.eye(4)
    T[:3, :3] = [[c, 0, s], [0, 1, 0], [-s, 0, c]]
    return T


def trans(x, y, z):
    T = np.eye(4)
    T[:3, 3] = [x, y, z]
    return T


def test_double_pendulum_visuals_and_their_world_poses():
    model = hovi.Model.from_urdf(str(REPO / "models" / "double_pendulum.urdf"))
    vis = model.visuals
    assert [(v["link"], v["body"], v["shape"]) for v in vis] == [
        ("base", -1, "box"), ("upper", 0, "cylinder"), ("upper", 0, "sphere"), ("lower", 1, "cylinder"),
        ("lower", 1, "sphere")]
    np.testing.assert_allclose(vis[0]["size"], [0.3, 0.1, 0.05])
    np.testing.assert_allclose(vis[1]["size"][:2], [0.02, 1.0])
    np.testing.assert_allclose(vis[1]["rgba"], [0.95, 0.45, 0.1, 1.0], atol=1e-7)  # named material
    # the lower rod's centre at q: shoulder about y, then 1 m down, elbow about y, then 0.5 m down
    q = np.array([0.4, -0.9])
    expected = rot_y(q[0]) @ trans(0, 0, -1) @ rot_y(q[1]) @ trans(0, 0, -0.5)
    got = model.joint_placements(q)[vis[3]["body"]] @ vis[3]["origin"]
    np.testing.assert_allclose(got, expected, atol=1e-14)


def test_fixed_joints_carry_visuals_to_the_parent_body(tmp_path):
    xml = """<robot name="r"><link name="base"/>
      <link name="arm"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <link name="tool"><visual><origin xyz="0.1 0 0" rpy="0 0.5 0"/><geometry><sphere radius="0.05"/></geometry></visual>
        <visual><geometry><mesh filename="meshes/tool.stl" scale="2 2 2"/></geometry></visual>
        <visual><geometry><mesh filename="package://pkg/tool.dae"/></geometry></visual>
        <visual><geometry><mesh filename="file:///abs/tool.obj"/></geometry></visual></link>
      <joint name="j" type="continuous"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/></joint>
      <joint name="weld" type="fixed"><parent link="arm"/><child link="tool"/><origin xyz="0 0 -1" rpy="0 0 0.3"/></joint>
    </robot>"""
    path = tmp_path / "r.urdf"
    path.write_text(xml)
    model = hovi.Model.from_urdf(str(path))
    sphere, stl, dae, obj = model.visuals
    assert sphere["body"] == 0 and sphere["link"] == "tool"
    c, s = np.cos(0.3), np.sin(0.3)
    weld = np.array([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, -1], [0, 0, 0, 1]])
    np.testing.assert_allclose(sphere["origin"], weld @ trans(0.1, 0, 0) @ rot_y(0.5), atol=1e-15)
    assert stl["filename"] == str(tmp_path / "meshes" / "tool.stl")  # relative to the URDF's directory
    np.testing.assert_allclose(stl["scale"], [2, 2, 2])
    assert dae["filename"] == "package://pkg/tool.dae"
    assert obj["filename"] == "/abs/tool.obj"
    # from XML text a relative name stays relative (there is no directory to resolve it against)
    assert hovi.Model.from_urdf(xml).visuals[1]["filename"] == "meshes/tool.stl"


def test_bad_visuals_are_refused_naming_the_link():
    bad = ('<robot name="r"><link name="base"/><link name="a"><inertial><mass value="1"/><inertia ixx="1" ixy="0" '
           'ixz="0" iyy="1" iyz="0" izz="1"/></inertial><visual><geometry><box size="1 -2 1"/></geometry></visual>'
           '</link><joint name="j" type="continuous"><parent link="base"/><child link="a"/></joint></robot>')
    with pytest.raises(hovi.URDFError, match="visual of 'a': sizes must be positive"):
        hovi.Model.from_urdf(bad)


def test_add_visual_validates_and_does_not_touch_the_dynamics():
    model = hovi.examples.models.pendulum(2)
    integ = hovi.Integrator(model, s=1, dt=0.01)
    model.add_visual("link2", "cylinder", [0.05, 0.5], origin=trans(0, 0, -0.25), rgba=[0.2, 0.4, 0.6, 1.0])
    model.add_visual(None, "sphere", 0.1)
    assert [(v["body"], v["link"], v["shape"]) for v in model.visuals] == [(1, "link2", "cylinder"), (-1, "world", "sphere")]
    integ.step(np.zeros(2), np.zeros(2))  # metadata only: the integrator stays valid
    with pytest.raises(hovi.ModelError, match="no body named 'nope'"):
        model.add_visual("nope", "box", [1, 1, 1])
    with pytest.raises(ValueError, match="shape must be"):
        model.add_visual(0, "cone", [1, 1])
    with pytest.raises(ValueError, match="size must be a 1-D array of length 3"):
        model.add_visual(0, "box", [1, 1])
    with pytest.raises(hovi.ModelError, match="rgba"):
        model.add_visual(0, "sphere", 0.1, rgba=[2, 0, 0, 1])
    with pytest.raises(hovi.ModelError, match="mesh without a filename"):
        model.add_visual(0, "mesh")
    with pytest.raises(ValueError, match="origin must be a homogeneous transform"):
        model.add_visual(0, "sphere", 0.1, origin=np.ones((4, 4)))
    assert len(model.visuals) == 2
    assert len(model.copy().visuals) == 2
