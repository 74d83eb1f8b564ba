"""The pictures people want (issue 45), checked on the figures' artists and on rendered pixels: the
final configuration's ground and scale bar, the arrows' scales in the legends (N per m), pushes drawn
where and while they act, the cart-pole's cart and rail, a robot sunk below the ground still drawn,
and legends of many curves off the data."""
import numpy as np
import pytest

import hovi
from hovi.contact import Box, Terrain
from hovi.control import Push
from hovi.vis import geometry, plots

video = pytest.importorskip("hovi.vis.video")


def gid_lines(ax, gid):
    return [line for line in ax.lines if line.get_gid() == gid]


def gid_texts(ax, gid):
    return [text.get_text() for text in ax.texts if text.get_gid() == gid]


def legend_texts(ax):
    return [t.get_text() for t in ax.get_legend().get_texts()]


def is_round(x):
    """x is 1, 2 or 5 times a power of ten."""
    return round(x / 10 ** np.floor(np.log10(x)), 9) in (1, 2, 5)


def pixels(fig):
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int)


def test_the_final_configuration_shows_the_ground_across_the_view_and_a_scale_bar():
    from mpl_toolkits.mplot3d import proj3d
    fig = plots.configuration_figure(hovi.examples.models.pendulum(3), [0.3, 0.5, 0.2], ground=-1.2)
    ax = fig.axes[0]
    (plane,) = [c for c in ax.collections if c.get_gid() == "ground"]
    fig.canvas.draw()
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    x, y, _ = proj3d.proj_transform(np.array([x0, x1, x1, x0]), np.array([y0, y0, y1, y1]), np.full(4, -1.2),
                                    ax.get_proj())
    # its corners are the view's at z = -1.2 (compared as drawn: projected)
    np.testing.assert_allclose(plane.get_paths()[0].vertices[:4], np.column_stack([x, y]), atol=1e-9)
    assert any(t.startswith("ground (z = -1.2 m)") for t in legend_texts(ax))
    (bar,) = gid_lines(ax, "scale_bar")
    bx, by, bz = (np.asarray(v) for v in bar.get_data_3d())
    length = float(np.hypot(bx[1] - bx[0], by[1] - by[0]))
    assert gid_texts(ax, "scale_bar_label") == [f"{length:g} m"] and is_round(length)
    assert 0.1 < length / (x1 - x0) < 0.31 and np.all(bz == -1.2) and x0 < bx.min() and bx.max() < x1
    plots.pyplot().close(fig)


def test_a_robot_sunk_below_the_ground_is_drawn_over_it(tmp_path):
    """The ground is drawn first (zorder below every link, not sorted by depth): the links' pixels keep
    their colour with the ground behind them; in the video, a terrain box does not hide the pendulum
    standing in it."""
    import imageio.v3 as iio
    plt = plots.pyplot()
    model = hovi.examples.models.pendulum(2)
    q = [0.4, 0.3]
    bare, sunk = plots.configuration_figure(model, q), plots.configuration_figure(model, q, ground=-0.3)
    ax = sunk.axes[0]
    (plane,) = [c for c in ax.collections if c.get_gid() == "ground"]
    assert not ax.computed_zorder and plane.get_zorder() < min(line.get_zorder() for line in ax.lines)

    def blue(image):  # the links' tab:blue
        return int((np.abs(image - [31, 119, 180]).max(axis=-1) < 12).sum())

    assert blue(pixels(sunk)) > 0.95 * blue(pixels(bare)) > 100
    plt.close(bare)
    plt.close(sunk)
    pendulum = hovi.examples.models.pendulum(1)  # hanging from z = 0 to -0.5, inside a box from -0.62 to 0.2
    frames = iio.imread(video.render_video(pendulum, np.zeros((2, 1)), tmp_path / "sunk.gif",
                                           times=[0, 0.1], fps=10, size=(240, 240), time_stamp=False,
                                           terrain=Terrain(ground=-0.6, boxes=[Box(-1.0, 1.0, 0.2)])), index=None)
    r, g, b = frames[0].astype(int).transpose(2, 0, 1)
    assert ((b > r + 12) & (b > g + 5)).sum() > 150  # the link's blue grey (none when the box hid it)


def test_contact_force_arrows_state_their_scale(tmp_path):
    """The picture's arrows carry the weight at a round number of newtons per metre that the legend
    states; the video's legend and the HTML animation's say the same."""
    import imageio.v3 as iio
    from test_viewer import littledog_landing
    viewer = pytest.importorskip("hovi.vis.viewer")
    st, traj, arrows = littledog_landing(40)
    per_metre = arrows.per_metre(st.model, traj.q[0])
    assert is_round(per_metre) and arrows.legend(st.model, traj.q[0]) == f"forces: {per_metre:g} N per m"
    assert 0.4 < arrows.weight / per_metre / video.model_size(st.model, traj.q[0]) < 2.5  # about the model's size
    fig = plots.configuration_figure(st.model, traj.q[-1], terrain=Terrain(), arrows=arrows)
    ax = fig.axes[0]
    assert f"forces: {per_metre:g} N per m" in legend_texts(ax)
    shafts = gid_lines(ax, "forces")
    assert len(shafts) == 4
    up = sum(float(np.diff(np.asarray(line.get_data_3d()[2]))[0]) for line in shafts) * per_metre
    assert up == pytest.approx(arrows.forces[-1, :, 2].sum(), rel=1e-9)
    assert up == pytest.approx(arrows.weight, rel=0.05)  # standing
    plots.pyplot().close(fig)
    kwargs = dict(times=traj.t[[0, -1]], fps=1 / (traj.t[-1] - traj.t[0]), size=(320, 240), time_stamp=False,
                  terrain=Terrain())
    q = traj.q[[0, -1]]
    plain = iio.imread(video.render_video(st.model, q, tmp_path / "plain.gif", **kwargs), index=None)
    legend = iio.imread(video.render_video(st.model, q, tmp_path / "legend.gif", arrows=arrows, **kwargs), index=None)
    corner = np.abs(plain[0, -30:, :150].astype(int) - legend[0, -30:, :150].astype(int)).max(axis=-1) > 40
    assert corner.sum() > 50  # "forces: 100 N per m" in the bottom left corner
    html = viewer.animation_html(st.model, traj, tmp_path / "ld.html", fps=10, arrows=arrows).read_text()
    assert f"forces: {per_metre:g} N per m" in html and "hovi-legend" in html
    assert "hovi-legend" not in viewer.animation_html(st.model, traj, tmp_path / "plain.html", fps=10).read_text()


def test_pushes_are_arrows_onto_the_pushed_points_while_they_act(tmp_path):
    import imageio.v3 as iio
    from test_viewer import animation_tracks
    viewer = pytest.importorskip("hovi.vis.viewer")
    model = hovi.examples.models.cartpole()
    pushes = [Push(0.2, "cart", [5.0, 0.0, 0.0]), Push(0.3, 1, [0.0, 0.0, -2.0], point=[0.0, 0.0, -0.5], duration=0.3)]
    q = np.array([0.1, 0.4])
    per_metre = video.push_scale(model, pushes, q)
    assert is_round(per_metre) and 0.4 < 5.0 / per_metre / video.model_size(model, q) < 2.5
    t = np.arange(8) / 10
    origins, vectors, shown = video.push_frames(model, pushes, t, np.tile(q, (8, 1)), per_metre)
    tip = model.joint_placements(q)[1] @ [0.0, 0.0, -0.5, 1.0]
    np.testing.assert_allclose(origins[:, 1] + vectors[:, 1], np.tile(tip[:3], (8, 1)), atol=1e-12)
    np.testing.assert_allclose(vectors[0], np.array([[5.0, 0, 0], [0, 0, -2.0]]) / per_metre)
    np.testing.assert_array_equal(shown.T, [[0, 0, 1, 1, 0, 0, 0, 0], [0, 0, 0, 1, 1, 1, 0, 0]])  # 0.2 s, or 0.3
    # the picture: each arrow ends at its pushed point, labelled at its tail with its impulse and time
    fig = plots.configuration_figure(model, q, pushes=pushes)
    ax = fig.axes[0]
    assert f"pushes: {per_metre:g} N s per m" in legend_texts(ax)
    ends = [[np.asarray(v)[1] for v in line.get_data_3d()] for line in gid_lines(ax, "pushes")]
    np.testing.assert_allclose(ends, [model.joint_placements(q)[0, :3, 3], tip[:3]], atol=1e-12)
    assert gid_texts(ax, "push_label") == ["push 5 N s at t = 0.2 s ", "push 2 N s at t = 0.3 s "]
    np.testing.assert_allclose([text.get_position_3d() for text in ax.texts if text.get_gid() == "push_label"],
                               origins[0], atol=1e-12)
    plots.pyplot().close(fig)
    # the video: blue arrows in the frames of the pushes only; the animation: hidden outside them
    traj = hovi.Integrator(model, s=2, dt=0.01).rollout(q, 70)
    frames = iio.imread(video.render_video(model, traj, tmp_path / "cp.gif", fps=10, size=(320, 240), pushes=pushes,
                                           time_stamp=False), index=None)
    r, g, b = frames.astype(int).transpose(3, 0, 1, 2)
    blue = ((b > 170) & (r < 90) & (g < 140)).sum(axis=(1, 2))
    assert (blue[[2, 3, 4, 5]] > 30).all() and (blue[[0, 1, 6, 7]] < 5).all(), blue
    html = viewer.animation_html(model, traj, tmp_path / "cp.html", fps=10, pushes=pushes)
    scale = [value[1] for _, value in animation_tracks(html)["/meshcat/hovi/pushes/00_push/shaft"][".scale"]]
    assert [s > 1e-3 for s in scale] == [False, False, True, True, False, False, False, False]
    text = html.read_text()
    assert f"pushes: {per_metre:g} N s per m" in text and "push 5 N s at t = 0.2 s" in text


def test_the_cart_pole_is_a_cart_on_a_rail(tmp_path):
    from test_viewer import scene_objects
    viewer = pytest.importorskip("hovi.vis.viewer")
    model = hovi.examples.models.cartpole()
    ((body, axis),) = geometry.carriages(model)
    assert body == 0 and np.allclose(axis, [1, 0, 0])
    (cart,) = [s for s in geometry.default_shapes(model) if s.name == "cart0"]
    assert cart.kind == "box" and cart.body == 0 and abs(cart.origin[0, 2]) == pytest.approx(1.0)  # long along x
    assert cart.size[2] == pytest.approx(0.2) and cart.size[:2] == pytest.approx([0.1, 0.1])  # 40% of the pole
    rail = geometry.rail_lines(model, [[-0.3, 0.0], [0.4, 1.0]])
    np.testing.assert_allclose(rail, [[[-0.5, 0, 0], [0.6, 0, 0]]], atol=1e-12)  # the travel and a cart's length
    from hovi.examples.standing import standing
    assert geometry.carriages(standing("littledog").model) == []  # a floating base's joints have no mass
    fig = plots.configuration_figure(model, [0.2, 0.5])
    ax = fig.axes[0]
    assert [c.get_label() for c in ax.collections if c.get_gid() == "cart"] == ["cart"]
    (line,) = gid_lines(ax, "rail")
    x, y, z = (np.asarray(v) for v in line.get_data_3d())
    assert x.min() < 0.2 - 0.1 and x.max() > 0.2 + 0.1 and np.allclose(y, 0) and np.allclose(z, 0)
    plots.pyplot().close(fig)
    objects = scene_objects(viewer.animation_html(model, np.array([[0.0, 0.0], [0.5, 0.3]]), tmp_path / "cp.html",
                                                  times=[0, 1], fps=2))
    assert objects["/meshcat/hovi/rails"] == "LineSegments"
    assert any(p.startswith("/meshcat/hovi/bodies/000_cart/cart0") for p in objects)


@pytest.mark.parametrize("curves", [3, 12, 30])
def test_legends_of_many_curves_stay_off_the_data(curves):
    """Up to six curves: the legend inside the axes; more (a 12- or 30-joint robot's joints): beside
    them, not over the axes, inside the figure."""
    plt = plots.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    t = np.linspace(0, 1, 20)
    for ax in axes:
        for j in range(curves):
            ax.plot(t, np.sin(j * t), label=f"front_left_hip_roll_{j}")
        plots.legend(ax)
    fig.tight_layout()
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    boxes = [ax.get_legend().get_window_extent(renderer) for ax in axes]
    inside = [box.x0 >= 0 and box.y0 >= 0 and box.x1 <= fig.bbox.x1 and box.y1 <= fig.bbox.y1 for box in boxes]
    assert all(inside)
    overlaps = [box.overlaps(ax.get_window_extent(renderer)) for box in boxes for ax in axes]
    assert not any(overlaps) if curves > plots.LEGEND_INSIDE else overlaps == [True, False, False, True]
    plt.close(fig)
