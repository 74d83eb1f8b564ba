"""Offline video of a motion (MP4 through imageio-ffmpeg, or GIF), rendered without a display.

matplotlib's Agg backend draws the model's shapes (``hovi.vis.geometry``) as shaded triangles, so no
browser, GPU or window is needed (``pip install hovi[viewer]``). Mesh files are read with
trimesh (STL, OBJ; DAE through pycollada) and, above ``max_faces`` triangles, simplified by
vertex clustering. The camera looks at the whole motion from the side, as the HTML export does,
and fits it to the frame; the axes are equal (a metre is as long along x, y and z). A frame shows
its time (``t = 1.23 s``) and, with ``ground``, a ground grid; with ``terrain`` (a
``hovi.contact.Terrain``) its ground grid with the gaps left open and drawn as dark strips, and its boxes
(both behind the model, so that a robot sunk below the ground shows); a cart's rail (``rail_lines``);
with ``arrows`` (``ForceArrows``, e.g. a contact simulation's forces) an arrow per active contact;
with ``pushes`` (``hovi.control.Push``) an arrow onto each pushed point while it acts, labelled
with its impulse; a legend states the arrows' scales (``forces: 100 N per m``); a progress bar
(tqdm, on stderr) follows long renders.

``terrain_scene``, ``ForceArrows`` and the pushes' arrows (``push_frames``) are shared with
``hovi.vis.viewer`` (the HTML animation) and ``hovi.vis.plots`` (the pictures).
"""
from __future__ import annotations

import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Sequence, Tuple, Union

import numpy as np

from .._core import Model
from .geometry import (Motion, Shape, body_frames, ground_lines, model_shapes, motion_arrays, rail_lines, round_scale,
                       sample_configurations, transform_points, translation)

__all__ = ["render_video", "shape_triangles", "box_triangles", "cylinder_triangles", "sphere_triangles",
           "cluster_vertices", "subdivide", "terrain_scene", "ForceArrows", "push_scale", "push_label",
           "push_frames"]

#: Colours of the terrain's boxes and gaps, of force arrows and of push arrows.
TERRAIN_BOX_RGBA = np.array([0.55, 0.6, 0.55, 1.0])
TERRAIN_GAP_RGBA = np.array([0.22, 0.24, 0.27, 1.0])
ARROW_RGBA = np.array([0.85, 0.1, 0.1, 1.0])
PUSH_RGBA = np.array([0.1, 0.35, 0.9, 1.0])
#: How long a push's arrow shows at least (s): a push without a duration is one step's impulse.
PUSH_SHOWN = 0.2


def model_size(model: Model, q: np.ndarray) -> float:
    """The model's size at q (n,): the largest extent of its joint frames' origins and centres of mass
    (at least 5 cm)."""
    points = np.vstack([body_frames(model, q)[:-1, :3, 3], model.body_poses(np.asarray(q, dtype=float))[:, :3, 3]])
    return max(float(np.ptp(points, axis=0).max()) if len(points) else 0.0, 0.05)


def _terrain_check(terrain: Any) -> None:
    from ..contact.terrain import Terrain
    if not isinstance(terrain, Terrain):
        raise TypeError(f"terrain must be a hovi.contact.Terrain, got {type(terrain).__name__}")


def terrain_scene(terrain: Any, points: np.ndarray, margin: float = 0.5,
                  spacing: Optional[float] = None) -> Tuple[np.ndarray, List[Shape]]:
    """What draws a ``hovi.contact.Terrain`` under a motion: (grid lines (L, 2, 3) on the ground
    plane z = terrain.ground under ``points`` (K, 3) widened by ``margin`` m, as
    ``hovi.vis.geometry.ground_lines``, with the gaps cut out; world shapes (body -1): a dark strip per
    gap just under the ground (a hole in the grid; seen from the side, a box as deep as the gap
    would stand out as a wall), and a box per terrain box, from below the ground to its top), over the
    grid's extent (infinite box sides and gaps are cut there; pieces outside it are left out).
    The heights are the terrain's: for foot spheres, whose centres the terrain holds, pass the
    terrain lowered by the radius."""
    _terrain_check(terrain)
    g = float(terrain.ground)
    lines = ground_lines(points, g, margin, spacing)
    lo, hi = lines[..., :2].reshape(-1, 2).min(axis=0), lines[..., :2].reshape(-1, 2).max(axis=0)
    gaps = [(max(gap.x0, lo[0]), min(gap.x1, hi[0]), float(gap.depth)) for gap in terrain.gaps
            if gap.x1 > lo[0] and gap.x0 < hi[0]]
    kept = []
    for a, b in lines:
        if a[0] == b[0]:  # a line along y at x = a[0]: gone inside a gap
            if not any(x0 < a[0] < x1 for x0, x1, _ in gaps):
                kept.append((a, b))
            continue
        pieces = [(a[0], b[0])]  # a line along x: the pieces outside the gaps
        for x0, x1, _ in gaps:
            pieces = [p for u, v in pieces for p in ((u, min(v, x0)), (max(u, x1), v)) if p[1] - p[0] > 1e-12]
        kept += [((u, a[1], g), (v, a[1], g)) for u, v in pieces]
    shapes: List[Shape] = []

    def box(name: str, x0: float, x1: float, y0: float, y1: float, z0: float, z1: float, rgba: np.ndarray) -> None:
        size = np.array([x1 - x0, y1 - y0, z1 - z0])
        shapes.append(Shape(-1, name, "box", size, translation(np.array([x0 + x1, y0 + y1, z0 + z1]) / 2), rgba))

    for k, (x0, x1, depth) in enumerate(gaps):
        box(f"terrain_gap_{k}", x0, x1, lo[1], hi[1], g - min(depth, 0.01), g - 1e-3, TERRAIN_GAP_RGBA)
    for k, b in enumerate(terrain.boxes):
        x0, x1 = max(b.x0, lo[0]), min(b.x1, hi[0])
        y0, y1 = max(b.y0, lo[1]), min(b.y1, hi[1])
        if x1 <= x0 or y1 <= y0:
            continue
        below = max([depth for gx0, gx1, depth in gaps if gx1 > x0 and gx0 < x1] + [0.02])
        box(f"terrain_box_{k}", x0, x1, y0, y1, min(g, float(b.top)) - below, float(b.top), TERRAIN_BOX_RGBA)
    return np.array(kept, dtype=float).reshape(-1, 2, 3), shapes


@dataclass
class ForceArrows:
    """Forces at points of a model's bodies, drawn as arrows in ``render_video`` and
    ``hovi.vis.viewer`` (contact forces: ``from_contacts``).

    bodies (C,) and points (C, 3): the points, each in its body's joint frame (as
    ``hovi.contact.Contacts`` holds them); times (K,): when the forces (K, C, 3) (world, N) act,
    e.g. a rollout's steps k dt; active (K, C): which to draw (default: the non-zero ones).
    A force of ``weight`` N is drawn ``length`` m long (default: at a round number of newtons per
    metre, ``per_metre``, at which the weight is about the size of the model at the first frame,
    ``model_size``); the legends state it (``legend``); an arrow starts at its point moved by ``offset``
    (3,) (e.g. down by a foot sphere's radius, to where it touches the ground). A frame draws the
    mean force of the steps within half a frame (or a step) of its time, so that an impact's
    impulse shows as the force it is over a frame, and an arrow where any of them was active."""
    bodies: Sequence[int]
    points: np.ndarray
    times: np.ndarray
    forces: np.ndarray
    weight: float
    active: Optional[np.ndarray] = None
    length: Optional[float] = None
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    names: Optional[Sequence[str]] = None

    def __post_init__(self) -> None:
        self.bodies = [int(b) for b in self.bodies]
        self.points = np.asarray(self.points, dtype=float).reshape(len(self.bodies), 3)
        self.times = np.asarray(self.times, dtype=float).ravel()
        self.forces = np.asarray(self.forces, dtype=float)
        C = len(self.bodies)
        if self.forces.shape != (len(self.times), C, 3):
            raise ValueError(f"forces must be (K, C, 3) = ({len(self.times)}, {C}, 3), got {self.forces.shape}")
        if len(self.times) == 0 or not (np.all(np.isfinite(self.forces)) and np.all(np.isfinite(self.times))):
            raise ValueError("ForceArrows needs at least one time and finite forces and times")
        self.active = (np.linalg.norm(self.forces, axis=-1) > 0 if self.active is None
                       else np.asarray(self.active, dtype=bool).reshape(len(self.times), C))
        if not (np.isfinite(self.weight) and self.weight > 0):
            raise ValueError(f"weight must be a finite force > 0 (N), got {self.weight!r}")
        if self.length is not None and not (np.isfinite(self.length) and self.length > 0):
            raise ValueError(f"length must be a finite length > 0 (m) or None, got {self.length!r}")
        self.offset = np.asarray(self.offset, dtype=float).reshape(3)
        if self.names is None:
            self.names = [f"contact_{c}" for c in range(C)]

    @classmethod
    def from_contacts(cls, trajectory: Any, contacts: Any, weight: Optional[float] = None,
                      length: Optional[float] = None, names: Optional[Sequence[str]] = None) -> "ForceArrows":
        """The contact forces of a rollout with contacts: its ``contact`` record's world impulses
        divided by dt, acting at t[k] (step k's impulses act at q[k]), drawn for the active contacts;
        ``weight`` (default: the model's weight, total mass times gravity) is drawn ``length`` m long;
        contacts with a radius (foot spheres) have their arrows start where they touch the ground;
        ``names`` default to the contacts' own."""
        record = trajectory.contact
        if record is None:
            raise ValueError("this trajectory has no contact record (simulate with Integrator(..., contacts=...))")
        t = np.asarray(trajectory.t, dtype=float)
        K = record.normal.shape[0]
        dt = float(t[1] - t[0]) if len(t) > 1 else 1.0
        if weight is None:
            model = contacts.with_inputs
            weight = float(model.total_mass * np.linalg.norm(np.asarray(model.gravity, dtype=float)))
        radius = max(c.radius for c in contacts.points)
        if names is None and all(c.name for c in contacts.points):
            names = [c.name for c in contacts.points]
        return cls([c.body for c in contacts.points], np.array([c.point for c in contacts.points]), t[:K],
                   np.asarray(record.world_impulses) / dt, float(weight), np.asarray(record.active), length,
                   np.array([0.0, 0.0, -float(radius)]), names)

    def per_metre(self, model: Model, q: np.ndarray) -> float:
        """Newtons per metre of arrow: ``weight`` over ``length``, or by default the round number (1, 2 or 5
        times a power of ten, ``round_scale``) nearest to the weight over the model's size at q (n,)."""
        if self.length is not None:
            return self.weight / self.length
        return round_scale(self.weight / model_size(model, q))

    def scale(self, model: Model, q: np.ndarray) -> float:
        """Metres per newton at q (n,): 1 / ``per_metre``."""
        return 1.0 / self.per_metre(model, q)

    def legend(self, model: Model, q: np.ndarray) -> str:
        """The arrows' scale at q (n,) as the legends state it, e.g. ``forces: 100 N per m``."""
        return f"forces: {self.per_metre(model, q):.3g} N per m"

    def frames(self, model: Model, frame_t: np.ndarray, frames_q: np.ndarray,
               period: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(origins (F, C, 3), vectors (F, C, 3) in m, shown (F, C)) of the arrows at the frames
        (times (F,), configurations (F, n), ``period`` s apart)."""
        K, C = len(self.times), len(self.bodies)
        origins = np.empty((len(frame_t), C, 3))
        for f, qk in enumerate(frames_q):
            fr = body_frames(model, qk)
            for c, (b, p) in enumerate(zip(self.bodies, self.points)):
                origins[f, c] = transform_points(fr[b], p)
        origins += self.offset
        step = float(np.median(np.diff(self.times))) if K > 1 else period
        half = max(float(period), step) / 2
        lo = np.minimum(np.searchsorted(self.times, frame_t - half - 1e-12), K - 1)
        hi = np.minimum(np.maximum(np.searchsorted(self.times, frame_t + half - 1e-12), lo + 1), K)
        total = np.concatenate([np.zeros((1, C, 3)), np.cumsum(self.forces, axis=0)])
        count = np.concatenate([np.zeros((1, C)), np.cumsum(self.active, axis=0)])
        mean = (total[hi] - total[lo]) / (hi - lo)[:, None, None]
        vectors = mean * self.scale(model, frames_q[0])
        shown = ((count[hi] - count[lo]) > 0) & (np.linalg.norm(vectors, axis=-1) > 1e-9)
        return origins, vectors, shown


def push_scale(model: Model, pushes: Sequence[Any], q: np.ndarray) -> float:
    """Newton seconds per metre of push arrow: the round number (``round_scale``) nearest to the largest
    push's impulse over the model's size at q (n,) (``model_size``)."""
    largest = max((float(np.linalg.norm(p.impulse)) for p in pushes), default=0.0)
    return round_scale(largest / model_size(model, q)) if largest > 0 else 1.0


def push_label(push: Any) -> str:
    """What stands beside a push's arrow: its impulse (and angular impulse), e.g. ``push 20 N s``."""
    angular = float(np.linalg.norm(push.angular))
    return f"push {np.linalg.norm(push.impulse):.3g} N s" + (f" + {angular:.3g} N m s" if angular > 0 else "")


def push_frames(model: Model, pushes: Sequence[Any], frame_t: np.ndarray, frames_q: np.ndarray,
                per_metre: float) -> Tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(origins (F, P, 3), vectors (F, P, 3) in m, shown (F, P)) of the arrows of pushes (``hovi.control.Push``:
    time, body (index or name), impulse (N s), point in the body's joint frame, duration) at the frames
    (times (F,), configurations (F, n)): each ends at its pushed point, its impulse ``per_metre`` N s per m,
    shown from its time for its duration, at least ``PUSH_SHOWN`` s."""
    bodies = [model.body_index(p.body) if isinstance(p.body, str) else int(p.body) for p in pushes]
    points = np.array([np.asarray(p.point, dtype=float) for p in pushes]).reshape(-1, 3)
    tips = np.array([[transform_points(body_frames(model, qk)[b], x) for b, x in zip(bodies, points)]
                     for qk in frames_q]).reshape(len(frame_t), len(pushes), 3)
    vectors = np.broadcast_to(np.array([np.asarray(p.impulse, dtype=float) for p in pushes]).reshape(-1, 3) / per_metre,
                              tips.shape)
    start = np.array([float(p.time) for p in pushes])
    end = start + np.array([max(float(p.duration), PUSH_SHOWN) for p in pushes])
    t = np.asarray(frame_t, dtype=float)[:, None]
    shown = (t >= start - 1e-9) & (t < end - 1e-9) & (np.linalg.norm(vectors, axis=-1) > 0)
    return tips - vectors, vectors.copy(), shown


def arrow_segments(origins: np.ndarray, vectors: np.ndarray, shown: np.ndarray,
                   head: float) -> Tuple[np.ndarray, np.ndarray]:
    """(shafts (A, 2, 3), heads (4 A, 2, 3)) line segments of the shown arrows of one frame: a shaft
    from each origin to its tip and a head of four lines from the tip back ``head`` m (at most half
    the arrow) around its axis."""
    o, v = origins[shown], vectors[shown]
    if len(o) == 0:
        return np.zeros((0, 2, 3)), np.zeros((0, 2, 3))
    tip = o + v
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    d = v / length
    h = np.minimum(head, 0.5 * length)
    helper = np.where(np.abs(d[:, :1]) < 0.9, np.array([[1.0, 0, 0]]), np.array([[0.0, 1.0, 0]]))
    e1 = np.cross(helper, d)
    e1 /= np.linalg.norm(e1, axis=-1, keepdims=True)
    e2 = np.cross(d, e1)
    base = tip - h * d
    heads = [np.stack([tip, base + 0.4 * h * s * e], axis=1) for e in (e1, e2) for s in (1, -1)]
    return np.stack([o, tip], axis=1), np.concatenate(heads)


#: The white box behind a frame's texts (time, legend, push labels), so that they read over the model.
_LABEL_BOX = {"facecolor": "white", "alpha": 0.7, "edgecolor": "none", "pad": 2}

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
                 ground: Optional[float] = None, time_stamp: bool = True, progress: Optional[bool] = False,
                 terrain: Any = None, arrows: Optional[ForceArrows] = None,
                 pushes: Optional[Sequence[Any]] = None) -> Path:
    """Render a motion to an MP4 (``.mp4``) or GIF (``.gif``) file; returns its path.

    motion: a hovi.Trajectory or (N, n) configurations at ``times`` (N,) seconds (default 1/fps
    apart), sampled at ``fps`` (one frame per 1/fps s of motion). size: (width, height) pixels,
    multiples of 16 for MP4. max_faces: triangles per mesh file before simplification.
    ground: a height in m: a ground grid on that plane under the motion (None: none; world shapes
    such as terrain boxes are the model's visuals). terrain: a ``hovi.contact.Terrain`` instead of
    ``ground``: its ground grid with the gaps cut out, its gaps as dark strips and its boxes
    (``terrain_scene``). The ground and terrain are drawn behind the model: a link below them shows.
    arrows: forces drawn as red arrows (``ForceArrows``). pushes: a list of ``hovi.control.Push``
    (time, body, impulse in N s, point in the body's joint frame, duration), each drawn as a blue
    arrow onto its pushed point from its time for max(duration, ``PUSH_SHOWN``) s, labelled with its
    impulse (``push_label``). A legend in the bottom left corner states the arrows' scales
    (``forces: 100 N per m``, ``pushes: 20 N s per m``). time_stamp: the time in the top left
    corner. progress: a progress bar on stderr (tqdm): True, False, or None for only when stderr is
    a terminal. The camera fits the bounding box of the motion's shapes (equal axes).
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
    if terrain is not None:
        _terrain_check(terrain)
        if ground is not None:
            raise ValueError("give ground or terrain, not both (a terrain has its own ground height)")
        ground = float(terrain.ground)
    if arrows is not None and not isinstance(arrows, ForceArrows):
        raise TypeError(f"arrows must be a hovi.vis.video.ForceArrows, got {type(arrows).__name__}")
    t, q = motion_arrays(model, motion, times, fps)
    frame_t, frames_q = sample_configurations(q, t, fps)
    shapes = model_shapes(model, package_dirs)
    local: Dict[int, List[np.ndarray]] = {}
    colours: Dict[int, List[np.ndarray]] = {}
    shape_tris = [shape_triangles(s, max_faces) for s in shapes]
    grid_lines = None
    scenery = np.zeros((0, 3, 3))  # the terrain's gaps and boxes, in the world
    scenery_rgba = np.zeros((0, 4))
    if terrain is not None:  # under the model's motion: its shapes at up to 40 frames
        moving = np.concatenate([transform_points(frames[s.body], tris).reshape(-1, 3)
                                 for frames in (body_frames(model, qk) for qk in frames_q[:: max(1, len(frames_q) // 40)])
                                 for s, tris in zip(shapes, shape_tris)])
        grid_lines, extra = terrain_scene(terrain, moving)
        if extra:
            extra_tris = [shape_triangles(s) for s in extra]
            scenery = np.concatenate(extra_tris)
            scenery_rgba = np.concatenate([np.tile(s.rgba, (len(tris), 1)) for s, tris in zip(extra, extra_tris)])
    frames0 = body_frames(model, frames_q[0])
    scene = np.concatenate([transform_points(frames0[s.body], t.reshape(-1, 3)) for s, t in zip(shapes, shape_tris)])
    max_edge = max(float(np.ptp(scene, axis=0).max()), 1e-3) / 12
    for s, tris in zip(shapes, shape_tris):
        if s.body < 0:  # the model's world shapes: split large faces so that the depth order holds
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

    rails = rail_lines(model, frames_q)
    sample = np.concatenate([world_triangles(qk).reshape(-1, 3) for qk in frames_q[:: max(1, len(frames_q) // 40)]]
                            + [scenery.reshape(-1, 3), rails.reshape(-1, 3)])
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
    # the ground, terrain and rails under everything, the shapes sorted by depth among themselves, arrows on top
    ax.computed_zorder = False
    if grid_lines is None and ground is not None:
        grid_lines = ground_lines(sample, float(ground))
    for lines, colour, lw in ((grid_lines, (0.55, 0.57, 0.6, 1.0), 0.6), (rails, (0.25, 0.25, 0.28, 1.0), 2.0)):
        if lines is not None and len(lines):
            grid = Line3DCollection(lines, colors=[colour], linewidths=lw, zorder=0)
            ax.add_collection3d(grid, autolim=False)
            grid.set_clip_on(False)
    if len(scenery):
        terrain_faces = Poly3DCollection(scenery, facecolors=_shade(scenery, scenery_rgba), linewidths=0, zorder=0.5)
        ax.add_collection3d(terrain_faces, autolim=False)
        terrain_faces.set_clip_on(False)
    collection = Poly3DCollection(world_triangles(frames_q[0]), linewidths=0, zorder=1)
    ax.add_collection3d(collection, autolim=False)
    collection.set_clip_on(False)
    fit = sample[:: max(1, len(sample) // 200000)]
    if ground is not None:  # the ground under the motion in view too
        fit = np.vstack([fit, [[x, y, float(ground)] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]])
    _fit_view(ax, canvas, fit, aspect, width, height)
    clock = fig.text(0.015, 0.975, "", ha="left", va="top", family="monospace", fontsize=11, color="#222222",
                     bbox=_LABEL_BOX) if time_stamp else None
    # the force and push arrows, over the model (drawn last), so that a force on a foot behind a leg still shows:
    # (shafts, heads, (origins, vectors, shown) per frame)
    drawn: List[Tuple[Any, Any, Tuple[np.ndarray, np.ndarray, np.ndarray]]] = []
    head = 0.08 * model_size(model, frames_q[0])

    def add_arrows(at: Tuple[np.ndarray, np.ndarray, np.ndarray], colour: np.ndarray) -> None:
        lines = [Line3DCollection([], colors=[tuple(colour)], linewidths=lw, zorder=2) for lw in (2.4, 1.6)]
        for lines3d in lines:
            ax.add_collection3d(lines3d, autolim=False)
            lines3d.set_clip_on(False)
        drawn.append((lines[0], lines[1], at))

    legend, labels = [], []
    if arrows is not None:
        add_arrows(arrows.frames(model, frame_t, frames_q, 1.0 / fps), ARROW_RGBA)
        legend.append(arrows.legend(model, frames_q[0]))
    if pushes:
        per_metre = push_scale(model, pushes, frames_q[0])
        push_at = push_frames(model, pushes, frame_t, frames_q, per_metre)
        add_arrows(push_at, PUSH_RGBA)
        legend.append(f"pushes: {per_metre:.3g} N s per m")
        labels = [ax.text(0, 0, 0, push_label(p), color=tuple(PUSH_RGBA), fontsize=9, ha="right", va="bottom", zorder=3,
                          bbox=_LABEL_BOX) for p in pushes]
    if legend:
        fig.text(0.015, 0.02, "\n".join(legend), ha="left", va="bottom", fontsize=10, color="#222222", bbox=_LABEL_BOX)

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
            for f, (tk, qk) in enumerate(zip(frame_t, frames_q)):
                tris = world_triangles(qk)
                collection.set_verts(tris)
                collection.set_facecolor(_shade(tris, rgba))
                for shafts, heads, (origins, vectors, shown) in drawn:
                    shaft_lines, head_lines = arrow_segments(origins[f], vectors[f], shown[f], head)
                    shafts.set_segments(list(shaft_lines))
                    heads.set_segments(list(head_lines))
                for p, label in enumerate(labels):  # at the arrow's tail
                    label.set_visible(bool(push_at[2][f, p]))
                    label.set_position_3d(push_at[0][f, p])
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
