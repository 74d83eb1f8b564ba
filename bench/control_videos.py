"""Videos and stills of the paper's robots in closed loop (bench/control_robots.py --video): each
example's push case (closed_loop.PUSHES) run in the contact simulator twice, by the time-varying LQR
(closed loop) and by the optimised torques alone (open loop), from the same state with the same push.

  - MP4s (hovi.vis.video.render_video, with the example's scenery, its ground and the contact forces and
    the push as red arrows; slowed down SLOW times, the clock shows the motion's time, the last frame
    held HOLD s) in bench/results/videos/ (not committed): <robot>_push_closed_loop.mp4,
    <robot>_push_open_loop.mp4 and <robot>_push.mp4 (the two side by side, labelled);
  - a still per robot (committed): docs/images/control_<robot>.png, FRAMES of the closed loop above
    the same instants of the open loop, one camera for all, the push's size and time in the title.

    python bench/control_videos.py [--only atlas spring_flamingo] [--solutions DIR]

(--solutions DIR: the solves' arrays DIR/<name>.npz that bench/control_robots.py --solutions keeps;
without it each example is solved once.)
"""
from __future__ import annotations

import argparse
import os
import tempfile
from typing import Any, Dict, List, Optional, Sequence, Tuple

import numpy as np

from common import RESULTS, ROOT, solve_quick_example
from hovi.control import Push, simulate
from hovi.examples.paper import tracking as CL
from hovi.vis.geometry import body_frames, ground_lines, model_shapes, transform_points
from hovi.vis.video import ForceArrows, render_video, shape_triangles, subdivide

VIDEO_DIR = os.path.join(RESULTS, "videos")
IMAGE_DIR = os.path.join(ROOT, "docs", "images")
ROBOTS = ("atlas", "spring_flamingo")
TITLES = {"atlas": "Atlas", "spring_flamingo": "Spring Flamingo"}
# the still's instants (s): the start, the push, after it, the end. Atlas's quick motion lasts 0.3 s (its open
# loop's last step ends at 0.25 s), the Spring Flamingo's 1.1 s (its push at 0.55 s is in flight, the
# push-off before it at 0.2-0.45 s)
FRAMES = {"atlas": (0.0, 0.15, 0.2, 0.25, 0.3), "spring_flamingo": (0.0, 0.4, 0.55, 0.8, 1.1)}
SLOW = {"atlas": 10, "spring_flamingo": 4}   # slow motion: the video lasts SLOW times the motion
FPS = 25                              # of the videos
HOLD = 1.0                            # s of video the last frame is held
SIZE = (640, 480)                     # pixels of each video
RUNS = (("closed_loop", "closed loop (TV-LQR)"), ("open_loop", "open loop (optimised torques)"))


# ----------------------------------------------------------------------------------------- the runs
def runs(example, motion: Any, push: Optional[Push] = None, mass_factor: float = 1.0) -> Dict[str, Dict[str, Any]]:
    """{'closed_loop', 'open_loop'}: {'run' (hovi.control.ClosedLoop), 'figures' (closed_loop.run_figures)}
    of ``example``'s optimised ``motion`` with ``push`` (default: the example's push case) in the plant
    with every mass times ``mass_factor``."""
    push = CL.default_push(example) if push is None else push
    ctl = CL.controller(example, motion)
    figures = CL.closed_loop_figures(example, motion, control=ctl, push=push, mass_factor=mass_factor)
    plant = CL.simulator(example, mass_factor)
    out = {}
    for key, policy in (("closed_loop", ctl.policy), ("open_loop", ctl.policy.without_feedback())):
        run = simulate(plant, policy, ctl.motion.q[0], ctl.motion.steps, qdot0=example.problem.qdot0, pushes=[push])
        out[key] = {"run": run, "figures": figures[key], "plant": plant, "push": push}
    return out


def scene(example, slab: bool = True) -> Tuple[Any, float]:
    """(the robot's model with the example's scenery added as world visuals, the ground's height): as
    report.animate draws an example; without ``slab`` the ground's wide flat box is left out (the
    video's ground grid shows the ground, and its camera, which fits everything drawn, comes closer)."""
    model = example.robot.model.copy()
    for shape, size, centre, rgba in example.scenery.shapes:
        if not slab and _is_slab(shape, size):
            continue
        origin = np.eye(4)
        origin[:3, 3] = centre
        model.add_visual(None, shape, size=size, origin=origin, rgba=rgba)
    tops = [centre[2] + size[2] / 2 for shape, size, centre, _ in example.scenery.shapes if shape == "box"]
    return model, (min(tops) - 1e-3 if tops else 0.0)


def _is_slab(shape: str, size: np.ndarray) -> bool:
    """The scenery's ground: a box at least a metre long and a few centimetres thick."""
    return shape == "box" and size[0] >= 1.0 and size[2] <= 0.05


def arrows(model, run, plant, push: Push) -> ForceArrows:
    """The contact forces of ``run`` (its impulses / dt) and the push (its impulse / dt at its step),
    drawn the model's weight to its size."""
    tr = run.trajectory
    contact = ForceArrows.from_contacts(tr, plant.contacts)
    K = contact.forces.shape[0]
    step = int(np.ceil(push.time / plant.dt - 1e-9))
    push_force = np.zeros((K, 1, 3))
    if step < K:
        push_force[step, 0] = np.asarray(push.impulse, float) / plant.dt
    body = model.body_index(push.body) if isinstance(push.body, str) else int(push.body)
    return ForceArrows(list(contact.bodies) + [body], np.vstack([contact.points, np.asarray(push.point, float)]),
                       contact.times, np.concatenate([contact.forces, push_force], axis=1), contact.weight,
                       active=np.concatenate([contact.active, np.linalg.norm(push_force, axis=-1) > 0], axis=1),
                       names=list(contact.names) + ["push"])


# --------------------------------------------------------------------------------------- the videos
def _label(frame: np.ndarray, text: str, colour: Tuple[int, int, int]) -> np.ndarray:
    from PIL import Image, ImageDraw, ImageFont
    img = Image.fromarray(frame)
    draw = ImageDraw.Draw(img)
    try:
        font = ImageFont.load_default(size=18)
    except TypeError:   # Pillow < 10.1: one small bitmap font
        font = ImageFont.load_default()
    x0, y0, x1, y1 = draw.textbbox((0, 0), text, font=font)
    x, y = (img.width - (x1 - x0)) / 2, img.height - (y1 - y0) - 14
    draw.rectangle((x - 6, y - 4, x + x1 - x0 + 6, y + y1 - y0 + 6), fill=(255, 255, 255))
    draw.text((x - x0, y - y0), text, fill=colour, font=font)
    return np.asarray(img)


def _frames(path: str) -> List[np.ndarray]:
    import imageio.v2 as imageio
    with imageio.get_reader(path) as reader:
        return [np.asarray(f) for f in reader]


def _write(path: str, frames: Sequence[np.ndarray]) -> str:
    import imageio.v2 as imageio
    with imageio.get_writer(path, fps=FPS, codec="libx264", quality=7, macro_block_size=16) as writer:
        for f in frames:
            writer.append_data(f)
    return path


def videos(name: str, example, result: Dict[str, Dict[str, Any]], out: Optional[str] = None) -> List[str]:
    """The push case's MP4s in ``out`` (default VIDEO_DIR): each run alone and both side by side (see
    the module's doc)."""
    out = VIDEO_DIR if out is None else out
    os.makedirs(out, exist_ok=True)
    model, ground = scene(example, slab=False)
    slow, hold = SLOW[name], int(round(HOLD * FPS))
    files, clips = [], []
    with tempfile.TemporaryDirectory() as tmp:
        for key, label in RUNS:
            r = result[key]
            tr = r["run"].trajectory
            raw = os.path.join(tmp, f"{key}.mp4")
            # one frame per 1/(FPS slow) s of motion, played at FPS: slow motion with the motion's own clock
            render_video(model, tr.q, raw, times=tr.t, fps=FPS * slow, size=SIZE, ground=ground,
                         arrows=arrows(example.robot.model, r["run"], r["plant"], r["push"]))
            frames = _frames(raw)
            frames += [frames[-1]] * hold
            files.append(_write(os.path.join(out, f"{name}_push_{key}.mp4"), frames))
            verdict = _verdict(r["figures"], short=True)
            colour = (26, 127, 55) if r["figures"]["success"] else (180, 35, 24)
            clips.append([_label(f, f"{label}: {verdict}", colour) for f in frames])
    length = max(len(c) for c in clips)
    both = [np.hstack([c[min(i, len(c) - 1)] for c in clips]) for i in range(length)]
    files.append(_write(os.path.join(out, f"{name}_push.mp4"), both))
    return files


# ---------------------------------------------------------------------------------------- the still
def _verdict(fig: Dict[str, Any], short: bool = False, model: Any = None) -> str:
    if fig["success"]:
        if short:
            return "succeeds"
        unit = " (m or rad)"
        if model is not None:
            kind = list(model.joint_types)[list(model.joint_names).index(fig["worst_coordinate"])]
            unit = " m" if kind == "prismatic" else " rad"
        return f"succeeds (tracking error at most {fig['max_tracking_error']:.2g}{unit}, {fig['worst_coordinate']})"
    f = fig["failure"]
    return f"fails at t = {f['time']:.2f} s" + ("" if short else f": {f['what']}")


def _shade(tris: np.ndarray, rgba: np.ndarray) -> np.ndarray:
    """Face colours: the colour dimmed by the angle to a light (hovi.vis.video's shading)."""
    light = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    out = rgba.copy()
    out[:, :3] = np.clip(rgba[:, :3] * (0.35 + 0.65 * np.abs(n @ light))[:, None], 0, 1)
    return out


class _Drawer:
    """The model's triangles in world coordinates at q (scenery split small: matplotlib sorts whole triangles)."""

    def __init__(self, model, q0: np.ndarray) -> None:
        self.model = model
        shapes = model_shapes(model)
        tris = [shape_triangles(s) for s in shapes]
        frames0 = body_frames(model, q0)
        span = np.concatenate([transform_points(frames0[s.body], t.reshape(-1, 3)) for s, t in zip(shapes, tris)])
        max_edge = float(np.ptp(span, axis=0).max()) / 12
        self.parts = [(s.body, subdivide(t, max_edge) if s.body < 0 else t) for s, t in zip(shapes, tris)]
        self.rgba = np.concatenate([np.tile(s.rgba, (len(t), 1)) for s, (_, t) in zip(shapes, self.parts)])

    def triangles(self, q: np.ndarray) -> np.ndarray:
        frames = body_frames(self.model, q)
        return np.concatenate([transform_points(frames[b], t) for b, t in self.parts])


def _at(tr, t: float) -> Tuple[np.ndarray, bool]:
    """(q at time t on the run (its last state after it stopped), whether it reached t)."""
    if t > tr.t[-1] + 1e-9:
        return tr.q[-1], False
    return np.array([np.interp(t, tr.t, tr.q[:, j]) for j in range(tr.q.shape[1])]), True


def _fit(canvas, ax, points: np.ndarray, aspect: Tuple[float, float, float], cell: Tuple[float, float, float, float],
         fill: float = 0.96) -> Tuple[float, Tuple[float, float]]:
    """(zoom, the axes' offset from its cell (figure fractions)) that make ``points`` (P, 3) span ``fill``
    of the ``cell`` (x, y, w, h in figure fractions) and centre them in it (as hovi.vis.video fits its frames)."""
    from mpl_toolkits.mplot3d import proj3d
    fig = ax.figure
    W, H = fig.bbox.width, fig.bbox.height
    x0, y0, w, h = cell
    target = np.array([(x0 + w / 2) * W, (y0 + h / 2) * H])
    zoom = 1.0
    for _ in range(6):
        canvas.draw()
        x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], ax.get_proj())
        px = ax.transData.transform(np.column_stack([x, y]))
        lo, hi = px.min(axis=0), px.max(axis=0)
        factor = min(fill * w * W / max(hi[0] - lo[0], 1.0), fill * h * H / max(hi[1] - lo[1], 1.0))
        centre = (lo + hi) / 2
        if abs(factor - 1) < 0.005 and np.abs(centre - target).max() < 0.5:
            break
        pos = ax.get_position(original=True)
        middle = np.array([(pos.x0 + pos.width / 2) * W, (pos.y0 + pos.height / 2) * H])
        zoom *= factor            # the zoom scales about the axes' centre; the shift brings the points to the cell's
        new = target - factor * (centre - middle)
        ax.set_box_aspect(aspect, zoom=zoom)
        ax.set_position((new[0] / W - pos.width / 2, new[1] / H - pos.height / 2, pos.width, pos.height))
    pos = ax.get_position(original=True)
    return zoom, (pos.x0 - x0, pos.y0 - y0)


def filmstrip(name: str, example, result: Dict[str, Dict[str, Any]], path: str, times: Optional[Sequence[float]] = None,
              dpi: int = 80) -> str:
    """The still: ``times`` (default FRAMES[name]) of the closed loop (top row) and the open loop (bottom
    row), one camera (the side view of the videos) fitted to every frame, with the contact forces and
    the push as red arrows, each row labelled with its run's outcome, the push's size, body and time in
    the title."""
    from matplotlib.figure import Figure
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    times = FRAMES[name] if times is None else times
    model, ground = scene(example, slab=False)
    push = result["closed_loop"]["push"]
    drawer = _Drawer(model, result["closed_loop"]["run"].trajectory.q[0])
    panels: Dict[str, list] = {}
    fit = []
    for key, _ in RUNS:
        arrow = arrows(example.robot.model, result[key]["run"], result[key]["plant"], push)
        panels[key] = []
        for t in times:
            q, reached = _at(result[key]["run"].trajectory, t)
            tris = drawer.triangles(q)
            o, v = np.zeros((0, 3)), np.zeros((0, 3))
            if reached:
                origins, vectors, shown = arrow.frames(example.robot.model, np.array([t]), q[None], 1e-3)
                o, v = origins[0][shown[0]], vectors[0][shown[0]]
            panels[key].append((t, reached, tris, o, v))
            fit += [tris.reshape(-1, 3), o, o + v]
    pts = np.concatenate(fit)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    lo[2] = min(lo[2], ground)
    pad = 0.03 * float(np.ptp(pts, axis=0).max())
    lo[:2], hi[:2] = lo[:2] - pad, hi[:2] + pad
    hi[2] += pad
    corners = np.array([[x, y, ground] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])])
    pts = np.vstack([pts, corners])
    floor = corners[[0, 1, 3, 2]][None]
    grid = ground_lines(np.array([lo, hi]), ground, margin=0.0)
    grid = grid[(grid[:, :, :2] >= lo[:2] - 1e-9).all(axis=(1, 2)) & (grid[:, :, :2] <= hi[:2] + 1e-9).all(axis=(1, 2))]
    aspect = tuple(float(x) for x in hi - lo)
    cols = len(times)
    fig = Figure(figsize=(2.2 * cols, 5.0), dpi=dpi)
    canvas = FigureCanvasAgg(fig)
    mag = float(np.linalg.norm(push.impulse))
    fig.suptitle(f"{TITLES[name]}: a {mag:g} N s push on the {push.body} at t = {push.time:g} s "
                 f"(red arrows: the push and the contact forces)", fontsize=11)
    w, h = 1.0 / cols, 0.40
    placed = None
    for row, (key, label) in enumerate(RUNS):
        verdict = _verdict(result[key]["figures"], model=example.robot.model)
        fig.text(0.5, 0.905 - 0.45 * row, f"{label}: {verdict}", ha="center", va="top",
                 fontsize=9, color="#1a7f37" if result[key]["figures"]["success"] else "#b42318")
        for c, (t, reached, tris, o, v) in enumerate(panels[key]):
            cell = (c * w, 0.47 - 0.45 * row, w, h)
            ax = fig.add_axes(cell if placed is None else (cell[0] + placed[1][0], cell[1] + placed[1][1], w, h),
                              projection="3d")
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_zlim(lo[2], hi[2])
            ax.set_box_aspect(aspect, zoom=1.0 if placed is None else placed[0])
            ax.view_init(elev=15, azim=-70)
            ax.set_axis_off()
            ax.computed_zorder = False
            if placed is None:     # one camera for every panel: fitted on the first, to every frame's points
                placed = _fit(canvas, ax, pts, aspect, cell)
            ground_art = [Poly3DCollection(floor, facecolors=[(0.93, 0.94, 0.95, 1.0)], linewidths=0, zorder=0),
                          Line3DCollection(grid, colors=[(0.72, 0.74, 0.77, 1.0)], linewidths=0.4, zorder=0)]
            art = ground_art + [Poly3DCollection(tris, linewidths=0, zorder=1, facecolors=_shade(tris, drawer.rgba))]
            if len(o):
                from hovi.vis.video import arrow_segments
                shafts, heads = arrow_segments(o, v, np.ones(len(o), bool), 0.05 * float(np.ptp(pts, axis=0).max()))
                art += [Line3DCollection(shafts, colors=[(0.85, 0.1, 0.1, 1.0)], linewidths=1.6, zorder=2),
                        Line3DCollection(heads, colors=[(0.85, 0.1, 0.1, 1.0)], linewidths=1.2, zorder=2)]
            for a in art:
                ax.add_collection3d(a, autolim=False)
                a.set_clip_on(False)
            stopped = result[key]["run"].trajectory.t[-1]
            fig.text(cell[0] + 0.01, cell[1] + h - 0.005, f"t = {t:.2f} s" if reached else f"(stopped at {stopped:.2f} s)",
                     ha="left", va="top", fontsize=8, color="#222222" if reached else "#b42318")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    fig.savefig(path, dpi=dpi)
    return path


def write(name: str, example, motion: Any, video: bool = True, still: bool = True) -> Dict[str, Any]:
    """The push case of ``name`` run both ways; its videos and its still. Returns the files and the
    two runs' outcomes."""
    result = runs(example, motion)
    files = []
    if still:
        files.append(filmstrip(name, example, result, os.path.join(IMAGE_DIR, f"control_{name}.png")))
    if video:
        files += videos(name, example, result)
    return {"files": [os.path.relpath(f, ROOT) for f in files],
            "push": {"time": result["closed_loop"]["push"].time, "body": result["closed_loop"]["push"].body,
                     "impulse": [float(x) for x in result["closed_loop"]["push"].impulse]},
            **{key: {"success": result[key]["figures"]["success"], "failure": result[key]["figures"]["failure"],
                     "max_tracking_error": result[key]["figures"]["max_tracking_error"]} for key, _ in RUNS}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", choices=ROBOTS, default=list(ROBOTS))
    ap.add_argument("--solutions", default=None, metavar="DIR", help="reuse DIR/<name>.npz (control_robots.py --solutions)")
    ap.add_argument("--no-video", action="store_true", help="the stills only")
    args = ap.parse_args()
    for name in args.only:
        example, motion, _ = solve_quick_example(name, args.solutions)
        out = write(name, example, motion, video=not args.no_video)
        print(name, out, flush=True)


if __name__ == "__main__":
    main()
