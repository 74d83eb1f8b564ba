"""Offline video of a motion (MP4 through imageio-ffmpeg, or GIF), rendered without a display.

matplotlib's Agg backend draws the model's shapes (``hovi.geometry``) as shaded triangles, so no
browser, GPU or window is needed (``pip install hovi[viewer]``). Mesh files are read with
trimesh (STL, OBJ; DAE through pycollada) and, above ``max_faces`` triangles, simplified by
vertex clustering. The camera looks at the whole motion from the side, as the HTML export does,
and fits it to the frame; the axes are equal (a metre is as long along x, y and z). A frame shows
its time (``t = 1.23 s``) and, with ``ground``, a ground grid; a progress bar (tqdm, on stderr)
follows long renders.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from ._core import Model
from .geometry import (Motion, Shape, body_frames, ground_lines, model_shapes, motion_arrays, sample_configurations,
                       transform_points)

__all__ = ["render_video", "shape_triangles", "box_triangles", "cylinder_triangles", "sphere_triangles",
           "cluster_vertices", "subdivide"]

_LIGHT = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])


def box_triangles(size: np.ndarray) -> np.ndarray:
    """(12, 3, 3) triangles of a box of edge lengths size (3,), centred."""
    c = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float) * np.asarray(size) / 2
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    return np.array([[c[a], c[b], c[d]] for a, b, _, d in quads] + [[c[b], c[e], c[d]] for _, b, e, d in quads])


def cylinder_triangles(radius: float, length: float, sides: int = 16) -> np.ndarray:
    """(4 sides, 3, 3) triangles of a closed cylinder along z, centred."""
    a = np.linspace(0, 2 * np.pi, sides + 1)
    ring = np.column_stack([radius * np.cos(a), radius * np.sin(a)])
    lo = np.column_stack([ring, np.full(sides + 1, -length / 2)])
    hi = np.column_stack([ring, np.full(sides + 1, length / 2)])
    tris = []
    for k in range(sides):
        tris += [[lo[k], lo[k + 1], hi[k + 1]], [lo[k], hi[k + 1], hi[k]]]
        tris += [[np.array([0, 0, -length / 2]), lo[k + 1], lo[k]], [np.array([0, 0, length / 2]), hi[k], hi[k + 1]]]
    return np.array(tris)


def sphere_triangles(radius: float, rings: int = 6, segments: int = 10) -> np.ndarray:
    """(2 rings segments, 3, 3) triangles of a UV sphere."""
    th = np.linspace(0, np.pi, rings + 1)
    ph = np.linspace(0, 2 * np.pi, segments + 1)
    p = radius * np.stack([np.outer(np.sin(th), np.cos(ph)), np.outer(np.sin(th), np.sin(ph)),
                           np.outer(np.cos(th), np.ones_like(ph))], axis=-1)
    tris = []
    for i in range(rings):
        for j in range(segments):
            tris += [[p[i, j], p[i + 1, j], p[i + 1, j + 1]], [p[i, j], p[i + 1, j + 1], p[i, j + 1]]]
    return np.array(tris)


def cluster_vertices(vertices: np.ndarray, faces: np.ndarray, max_faces: int) -> np.ndarray:
    """(F, 3, 3) triangles of a mesh simplified by vertex clustering to at most about max_faces.

    Vertices are merged per cell of a grid over the bounding box (each cluster at its mean),
    faces that collapse are dropped; the grid is refined until the face count fits.
    """
    v, f = np.asarray(vertices, dtype=float), np.asarray(faces, dtype=int)
    if len(f) <= max_faces:
        return v[f]
    lo, span = v.min(axis=0), np.ptp(v, axis=0).max() or 1.0
    best = None
    for cells in (64, 48, 32, 24, 16, 12, 8, 6, 4):
        keys = np.floor((v - lo) / span * (cells - 1e-9)).astype(np.int64)
        _, cluster, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
        cluster = cluster.ravel()
        centres = np.zeros((len(counts), 3))
        np.add.at(centres, cluster, v)
        centres /= counts[:, None]
        g = cluster[f]
        keep = (g[:, 0] != g[:, 1]) & (g[:, 1] != g[:, 2]) & (g[:, 0] != g[:, 2])
        g = np.unique(g[keep], axis=0)
        best = centres[g]
        if len(g) <= max_faces:
            break
    return best


def shape_triangles(shape: Shape, max_faces: int = 2000) -> np.ndarray:
    """(F, 3, 3) triangles of a shape in its body's joint frame (its origin and mesh scale applied)."""
    if shape.kind == "box":
        tris = box_triangles(shape.size)
    elif shape.kind == "cylinder":
        tris = cylinder_triangles(float(shape.size[0]), float(shape.size[1]))
    elif shape.kind == "sphere":
        tris = sphere_triangles(float(shape.size[0]))
    else:
        try:
            import trimesh
        except ImportError as e:  # pragma: no cover - exercised only without the extra
            raise ImportError("meshes in videos need trimesh: pip install 'hovi[viewer]'") from e
        mesh = trimesh.load(shape.mesh_path, force="mesh")
        tris = cluster_vertices(mesh.vertices * shape.scale, mesh.faces, max_faces)
    return transform_points(shape.origin, tris)


def subdivide(tris: np.ndarray, max_edge: float) -> np.ndarray:
    """(F', 3, 3) the triangles (F, 3, 3) split in four (at their edges' midpoints) until no edge is
    longer than max_edge: matplotlib sorts whole triangles by depth, so a large one (a terrain box's
    face) would be drawn over what stands on it."""
    tris = np.asarray(tris, dtype=float)
    for _ in range(8):
        edges = np.linalg.norm(tris - np.roll(tris, 1, axis=1), axis=-1).max(axis=1)
        big = edges > max_edge
        if not big.any():
            break
        a, b, c = tris[big, 0], tris[big, 1], tris[big, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        split = np.concatenate([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
        tris = np.concatenate([tris[~big], split])
    return tris


def _shade(tris: np.ndarray, rgba: np.ndarray) -> np.ndarray:
    n = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    light = 0.35 + 0.65 * np.abs(n @ _LIGHT)
    out = np.empty((len(tris), 4))
    out[:, :3] = np.clip(rgba[:, :3] * light[:, None], 0, 1)
    out[:, 3] = rgba[:, 3]
    return out


def _fit_view(ax: Any, canvas: Any, points: np.ndarray, aspect: Tuple[float, float, float], width: int,
              height: int, fill: float = 0.9) -> None:
    """Zoom the 3D axes (box ``aspect``) and shift them in the figure so that ``points`` (K, 3) span
    ``fill`` of the frame's width or height, centred. A few passes: the perspective makes the zoom
    not quite a scaling. The shapes are drawn unclipped, so the view may use the whole frame (a 3D
    axes is a square)."""
    from mpl_toolkits.mplot3d import proj3d

    zoom, offset, middle = 1.0, np.zeros(2), np.array([width, height]) / 2
    for _ in range(5):
        canvas.draw()
        x, y, _ = proj3d.proj_transform(points[:, 0], points[:, 1], points[:, 2], ax.get_proj())
        pixels = ax.transData.transform(np.column_stack([x, y]))
        lo, hi = pixels.min(axis=0), pixels.max(axis=0)
        extent = np.maximum(hi - lo, 1.0)
        factor = min(fill * width / extent[0], fill * height / extent[1])
        centre = (lo + hi) / 2
        if abs(factor - 1) < 0.01 and np.abs(centre - middle).max() < 2:
            break
        relative = centre - middle - offset  # the content's centre from the axes' centre
        zoom *= factor
        offset = -factor * relative  # zoom scales about the axes' centre; the shift brings it to the middle
        ax.set_box_aspect(aspect, zoom=zoom)
        ax.set_position((offset[0] / width, offset[1] / height, 1, 1))


def render_video(model: Model, motion: Motion, path: Union[str, os.PathLike[str]],
                 times: Optional[Sequence[float]] = None, fps: float = 30.0, size: Tuple[int, int] = (640, 480),
                 package_dirs: Iterable[Union[str, os.PathLike[str]]] = (), max_faces: int = 2000, *,
                 ground: Optional[float] = None, time_stamp: bool = True, progress: Optional[bool] = False) -> Path:
    """Render a motion to an MP4 (``.mp4``) or GIF (``.gif``) file; returns its path.

    motion: a hovi.Trajectory or (N, n) configurations at ``times`` (N,) seconds (default 1/fps
    apart), sampled at ``fps`` (one frame per 1/fps s of motion). size: (width, height) pixels,
    multiples of 16 for MP4. max_faces: triangles per mesh file before simplification.
    ground: a height in m: a ground grid on that plane under the motion (None: none; world shapes
    such as terrain boxes are the model's visuals). time_stamp: the time in the top left corner.
    progress: a progress bar on stderr (tqdm): True, False, or None for only when stderr is a terminal.
    The camera fits the bounding box of the motion's shapes (equal axes).
    """
    out = Path(path)
    suffix = out.suffix.lower()
    if suffix not in (".mp4", ".gif"):
        raise ValueError(f"video path must end in .mp4 or .gif, got '{out.name}'")
    width, height = (int(s) for s in size)
    if width < 16 or height < 16 or (suffix == ".mp4" and (width % 16 or height % 16)):
        raise ValueError(f"size must be at least 16 x 16 pixels (multiples of 16 for MP4), got {size}")
    if ground is not None and not np.isfinite(ground):
        raise ValueError(f"ground must be a finite height in m or None, got {ground!r}")
    t, q = motion_arrays(model, motion, times, fps)
    frame_t, frames_q = sample_configurations(q, t, fps)
    shapes = model_shapes(model, package_dirs)
    local: Dict[int, List[np.ndarray]] = {}
    colours: Dict[int, List[np.ndarray]] = {}
    shape_tris = [shape_triangles(s, max_faces) for s in shapes]
    frames0 = body_frames(model, frames_q[0])
    scene = np.concatenate([transform_points(frames0[s.body], t.reshape(-1, 3)) for s, t in zip(shapes, shape_tris)])
    max_edge = max(float(np.ptp(scene, axis=0).max()), 1e-3) / 12
    for s, tris in zip(shapes, shape_tris):
        if s.body < 0:  # scenery (terrain boxes): split large faces so that the depth order holds
            tris = subdivide(tris, max_edge)
        local.setdefault(s.body, []).append(tris)
        colours.setdefault(s.body, []).append(np.tile(s.rgba, (len(tris), 1)))
    bodies = sorted(local)
    local_tris = [np.concatenate(local[b]) for b in bodies]
    rgba = np.concatenate([np.concatenate(colours[b]) for b in bodies])

    def world_triangles(qk: np.ndarray) -> np.ndarray:
        frames = body_frames(model, qk)
        return np.concatenate([transform_points(frames[b], tris) for b, tris in zip(bodies, local_tris)])

    from matplotlib.figure import Figure  # with its Agg canvas directly: the user's pyplot backend is untouched
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

    sample = np.concatenate([world_triangles(qk).reshape(-1, 3) for qk in frames_q[:: max(1, len(frames_q) // 40)]])
    lo, hi = sample.min(axis=0), sample.max(axis=0)
    if ground is not None:  # the limits (equal axes) reach down or up to the ground
        lo[2], hi[2] = min(lo[2], float(ground)), max(hi[2], float(ground))
    pad = 0.02 * max(float(np.ptp(sample, axis=0).max()), 0.05)
    lo, hi = lo - pad, hi + pad
    fig = Figure(figsize=(width / 100, height / 100), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0, 0, 1, 1), projection="3d")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    aspect = (float(hi[0] - lo[0]), float(hi[1] - lo[1]), float(hi[2] - lo[2]))
    ax.set_box_aspect(aspect)  # equal axes: the limits are the box, its sides in proportion
    ax.view_init(elev=15, azim=-70)
    ax.set_axis_off()
    ax.computed_zorder = False  # the grid under everything, the shapes sorted by depth among themselves
    if ground is not None:
        grid = Line3DCollection(ground_lines(sample, float(ground)), colors=[(0.55, 0.57, 0.6, 1.0)], linewidths=0.6,
                                zorder=0)
        ax.add_collection3d(grid, autolim=False)
        grid.set_clip_on(False)
    collection = Poly3DCollection(world_triangles(frames_q[0]), linewidths=0, zorder=1)
    ax.add_collection3d(collection, autolim=False)
    collection.set_clip_on(False)
    fit = sample[:: max(1, len(sample) // 200000)]
    if ground is not None:  # the ground under the motion in view too
        fit = np.vstack([fit, [[x, y, float(ground)] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]])
    _fit_view(ax, canvas, fit, aspect, width, height)
    clock = fig.text(0.015, 0.975, "", ha="left", va="top", family="monospace", fontsize=11, color="#222222",
                     bbox={"facecolor": "white", "alpha": 0.7, "edgecolor": "none", "pad": 2}) if time_stamp else None

    import imageio.v2 as imageio

    if suffix == ".mp4":
        kwargs: Dict[str, Any] = {"fps": fps, "codec": "libx264", "quality": 7, "macro_block_size": 16}
    else:
        kwargs = {"duration": 1000.0 / fps, "loop": 0}
    out.parent.mkdir(parents=True, exist_ok=True)
    bar = None
    if progress is not False:
        from tqdm import tqdm  # type: ignore[import-untyped, unused-ignore]
        bar = tqdm(total=len(frames_q), unit="frame", desc=f"rendering {out.name}", file=sys.stderr,
                   disable=None if progress is None else False)
    try:
        with imageio.get_writer(str(out), **kwargs) as writer:
            for tk, qk in zip(frame_t, frames_q):
                tris = world_triangles(qk)
                collection.set_verts(tris)
                collection.set_facecolor(_shade(tris, rgba))
                if clock is not None:
                    clock.set_text(f"t = {tk:.2f} s")
                canvas.draw()
                writer.append_data(np.asarray(canvas.buffer_rgba())[:, :, :3].copy())
                if bar is not None:
                    bar.update(1)
    finally:
        if bar is not None:
            bar.close()
    return out
