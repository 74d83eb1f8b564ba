"""What a viewer draws: a model's visual shapes, with mesh files found, or default shapes.

A model's visuals (URDF ``<visual>`` elements, or ``Model.add_visual``) are attached to bodies
(or to the world) with an origin in the body's joint frame, so a shape's world pose at q is
``joint_placements(q)[body] @ origin``. A model without visuals (``hovi.examples.models.pendulum(n)``)
gets default shapes: a capsule (a cylinder with spherical ends) from each joint to each child
joint, or to the far end of a leaf body (twice its centre of mass), and a sphere at each centre
of mass with a radius growing as mass^(1/3); a body with mass on a prismatic joint (a cart, a
slider) gets a box along its axis, and, fixed to the world, a rail (``rail_lines``).
"""
from __future__ import annotations

import functools
import importlib.util
import os
import sys
import warnings
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, List, Optional, Sequence

import numpy as np

from .._core import Model

__all__ = ["Shape", "Motion", "LINK_RGBA", "COM_RGBA", "MeshNotFoundWarning", "package_search_path",
           "example_robot_data_dirs", "resolve_mesh", "model_shapes", "shape_corners", "ground_lines",
           "default_shapes", "carriages", "rail_lines", "round_scale", "segment_frame", "translation", "transform_points",
           "body_frames", "motion_arrays", "sample_configurations"]

#: Colours of the default shapes (links, centres of mass) and of visuals without a material.
LINK_RGBA = np.array([0.55, 0.6, 0.68, 1.0])
COM_RGBA = np.array([0.95, 0.45, 0.1, 1.0])


@dataclass(frozen=True)
class Shape:
    """One shape to draw, attached to a body (-1: the world): size (3,), origin (4, 4), rgba (4,), scale (3,)."""

    body: int
    name: str
    kind: str                 #: 'box', 'cylinder' (axis z, centred), 'sphere' or 'mesh'
    size: np.ndarray          #: (3,) box x, y, z; cylinder radius, length, 0; sphere radius, 0, 0
    origin: np.ndarray        #: (4, 4) pose in the body's joint frame
    rgba: np.ndarray          #: (4,) colour in [0, 1]
    mesh_path: Optional[str] = None  #: an existing file (meshes only)
    scale: np.ndarray = field(default_factory=lambda: np.ones(3))  #: (3,) mesh scale


class MeshNotFoundWarning(UserWarning):
    """A visual's mesh file was not found: a simple shape is drawn in its place (``model_shapes``)."""


def example_robot_data_dirs() -> List[Path]:
    """The folders of the installed ``example-robot-data`` (pip ``example-robot-data``) that hold
    ``package://`` names: its share folder (``package://example-robot-data/robots/...``) and its
    ``robots`` folder (``package://ur_description/...``); empty when it is not installed.

    Found as ``example_robot_data.getModelPath`` finds it (``../../../share/example-robot-data/robots``
    beside the package's site-packages folder, or beside an entry of ``sys.path``), without importing
    the package (which imports pinocchio)."""
    return list(_example_robot_data_dirs())


@functools.lru_cache(maxsize=1)
def _example_robot_data_dirs() -> tuple[Path, ...]:
    try:
        spec = importlib.util.find_spec("example_robot_data")
    except (ImportError, ValueError):
        spec = None
    if spec is None:
        return ()
    roots = [Path(d).parent for d in (spec.submodule_search_locations or [])]
    roots += [Path(p) for p in sys.path if p]
    for root in roots:
        robots = (root / ".." / ".." / ".." / "share" / "example-robot-data" / "robots").resolve()
        if robots.is_dir():
            return (robots.parent.parent, robots)
    return ()


def package_search_path(package_dirs: Iterable[str | os.PathLike[str]] = ()) -> List[Path]:
    """The directories searched for ``package://NAME/...``: ``package_dirs`` (the command line's
    ``--package-dir``), then ``ROS_PACKAGE_PATH``, then the installed example-robot-data
    (``example_robot_data_dirs``)."""
    dirs = [Path(d) for d in package_dirs]
    dirs += [Path(d) for d in os.environ.get("ROS_PACKAGE_PATH", "").split(os.pathsep) if d]
    return dirs + [d for d in example_robot_data_dirs() if d not in dirs]


def resolve_mesh(filename: str, package_dirs: Iterable[str | os.PathLike[str]] = ()) -> str:
    """The file a URDF mesh name refers to.

    ``package://NAME/rest`` is looked up as ``DIR/NAME/rest`` or, when DIR is itself named NAME,
    ``DIR/rest`` for each DIR of ``package_search_path(package_dirs)``; other names must exist
    as given (the URDF loader already made relative names absolute). Raises FileNotFoundError
    naming the file and the directories searched.
    """
    prefix = "package://"
    if not filename.startswith(prefix):
        if Path(filename).is_file():
            return filename
        raise FileNotFoundError(f"mesh file '{filename}' does not exist")
    package, _, rest = filename[len(prefix):].partition("/")
    dirs = package_search_path(package_dirs)
    for d in dirs:
        for candidate in (d / package / rest, d / rest if d.name == package else None):
            if candidate is not None and candidate.is_file():
                return str(candidate)
    searched = ", ".join(str(d) for d in dirs) or "(no directory)"
    raise FileNotFoundError(f"mesh '{filename}': package '{package}' not found in {searched}; give the directory "
                            f"that holds '{package}' (package_dirs; on the command line --package-dir DIR) or set "
                            f"ROS_PACKAGE_PATH")


def model_shapes(model: Model, package_dirs: Iterable[str | os.PathLike[str]] = (), *,
                 missing: str = "warn") -> List[Shape]:
    """The shapes to draw for ``model``: its visuals (meshes resolved), or default shapes if it has none.

    missing: what a mesh that cannot be found becomes: 'warn' (default) draws the body's default
    shapes (``default_shapes``: its capsules; a small box for a shape on the world) in its place and
    warns once (MeshNotFoundWarning) naming the meshes; 'raise' raises FileNotFoundError.
    """
    if missing not in ("warn", "raise"):
        raise ValueError(f"missing must be 'warn' or 'raise', got {missing!r}")
    if not model.visuals:
        return default_shapes(model)
    dirs = list(package_dirs)
    shapes: List[Shape] = []
    lost: List[tuple[str, str]] = []  # (mesh name, why)
    replaced: set[int] = set()
    defaults: Optional[List[Shape]] = None
    for k, v in enumerate(model.visuals):
        rgba = LINK_RGBA if v["rgba"] is None else np.asarray(v["rgba"], dtype=float)
        mesh = None
        if v["shape"] == "mesh":
            try:
                mesh = resolve_mesh(v["filename"], dirs)
            except FileNotFoundError as e:
                if missing == "raise":
                    raise
                lost.append((v["filename"], str(e)))
                body = int(v["body"])
                if body in replaced:
                    continue
                replaced.add(body)
                if body < 0:
                    shapes.append(Shape(body, f"{v['link']}_{k}_missing", "box", np.full(3, 0.05), np.asarray(v["origin"]),
                                        LINK_RGBA))
                    continue
                defaults = default_shapes(model) if defaults is None else defaults
                shapes += [Shape(s.body, f"{v['link']}_{k}_missing_{s.name}", s.kind, s.size, s.origin, s.rgba)
                           for s in defaults if s.body == body and not s.name.startswith("com")]
                continue
        shapes.append(Shape(v["body"], f"{v['link']}_{k}", v["shape"], np.asarray(v["size"]), np.asarray(v["origin"]),
                            rgba, mesh, np.asarray(v["scale"])))
    if lost:
        names = ", ".join(f"'{name}'" for name, _ in lost[:5]) + (f" and {len(lost) - 5} more" if len(lost) > 5 else "")
        warnings.warn(f"{len(lost)} mesh file(s) not found, drawn as simple shapes (the link's default capsule): "
                      f"{names}. {lost[0][1]}", MeshNotFoundWarning, stacklevel=2)
    return shapes


def shape_corners(shape: Shape) -> np.ndarray:
    """(8, 3) corners of a box around the shape, in its body's joint frame (its origin applied): the
    primitive's extent, or a mesh file's bounding box (read with trimesh; its origin alone if trimesh
    is missing or cannot read it). What cameras fit to the view."""
    if shape.kind == "box":
        half = np.asarray(shape.size, dtype=float) / 2
        lo, hi = -half, half
    elif shape.kind == "cylinder":
        r, length = float(shape.size[0]), float(shape.size[1])
        lo, hi = np.array([-r, -r, -length / 2]), np.array([r, r, length / 2])
    elif shape.kind == "sphere":
        r = float(shape.size[0])
        lo, hi = np.full(3, -r), np.full(3, r)
    else:
        try:
            import trimesh
            bounds = np.asarray(trimesh.load(shape.mesh_path, force="mesh").bounds, dtype=float) * shape.scale
            lo, hi = bounds.min(axis=0), bounds.max(axis=0)
        except Exception:  # no trimesh, or a file it cannot read: the origin
            lo = hi = np.zeros(3)
    corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
    return transform_points(shape.origin, corners)


def ground_lines(points: np.ndarray, height: float = 0.0, margin: float = 0.5,
                 spacing: Optional[float] = None) -> np.ndarray:
    """(L, 2, 3) segments of a square grid on the plane z = height under ``points`` (K, 3) (the
    motion's extent in x and y, widened by ``margin`` m on each side), ``spacing`` m apart (default:
    a round 0.1, 0.25, 0.5 or 1 m giving 10 to 40 lines each way)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    lo, hi = pts[:, :2].min(axis=0) - margin, pts[:, :2].max(axis=0) + margin
    if spacing is None:
        span = float((hi - lo).max())
        spacing = next((d for d in (0.1, 0.25, 0.5, 1.0, 2.0, 5.0) if span / d <= 40), 10.0)
    lo, hi = np.floor(lo / spacing) * spacing, np.ceil(hi / spacing) * spacing
    xs = np.arange(lo[0], hi[0] + spacing / 2, spacing)
    ys = np.arange(lo[1], hi[1] + spacing / 2, spacing)
    lines = [[[x, lo[1], height], [x, hi[1], height]] for x in xs] + [[[lo[0], y, height], [hi[0], y, height]] for y in ys]
    return np.array(lines, dtype=float)


def segment_frame(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(4, 4) frame centred between a and b with z along b - a (a cylinder's frame)."""
    d = (b - a) / np.linalg.norm(b - a)
    helper = np.array([1.0, 0.0, 0.0]) if abs(d[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, d)
    x /= np.linalg.norm(x)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, np.cross(d, x), d])
    T[:3, 3] = (a + b) / 2
    return T


def translation(p: np.ndarray) -> np.ndarray:
    """(4, 4) pure translation by p (3,)."""
    T = np.eye(4)
    T[:3, 3] = p
    return T


def transform_points(T: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Points (..., 3) mapped by the pose T (4, 4): R p + t."""
    return points @ T[:3, :3].T + T[:3, 3]


def round_scale(x: float, at_most: bool = False) -> float:
    """The 1, 2 or 5 times a power of ten nearest to x > 0 (in ratio), or the largest at most x: the
    round numbers of arrow scales and scale bars."""
    decade = 10.0 ** np.floor(np.log10(x))
    steps = [m * decade for m in (1, 2, 5, 10)]
    if at_most:
        return max(v for v in steps if v <= x * (1 + 1e-12))
    return min(steps, key=lambda v: abs(np.log(v / x)))


def carriages(model: Model) -> List[tuple[int, np.ndarray]]:
    """(body, unit axis (3,) in its joint frame) of each body with mass on a prismatic joint: a cart or a
    slider, drawn as a box on a rail (the massless prismatic joints of a floating or planar base are not)."""
    q0 = model.neutral()
    at0 = model.joint_placements(q0)
    out = []
    for i, (kind, mass) in enumerate(zip(model.joint_types, model.masses)):
        if kind == "prismatic" and mass > 0:
            q1 = model.integrate(q0, np.eye(model.n)[i])
            axis = at0[i, :3, :3].T @ (model.joint_placements(q1)[i, :3, 3] - at0[i, :3, 3])
            out.append((i, axis / np.linalg.norm(axis)))
    return out


def rail_lines(model: Model, q: Sequence[float] | np.ndarray, margin: Optional[float] = None) -> np.ndarray:
    """(R, 2, 3) the rails of the carriages (``carriages``) fixed to the world: each along its axis
    over the positions its joint takes at configurations q ((n,) or (N, n)), ``margin`` m further
    each way (default: the length of its box in ``default_shapes``)."""
    qs = np.atleast_2d(np.asarray(q, dtype=float))
    margin = _segments(model)[3] if margin is None else float(margin)
    lines = []
    for body, axis in carriages(model):
        if model.parents[body] >= 0:
            continue
        frames = np.array([model.joint_placements(qk)[body] for qk in qs])
        a = frames[0, :3, :3] @ axis
        s = (frames[:, :3, 3] - frames[0, :3, 3]) @ a
        lines.append([frames[0, :3, 3] + (s.min() - margin) * a, frames[0, :3, 3] + (s.max() + margin) * a])
    return np.array(lines, dtype=float).reshape(-1, 2, 3)


def _segments(model: Model) -> tuple[list, list, float, float]:
    """What ``default_shapes`` draws: (segments (body, a, b, b is a leaf end) in the body's joint frame,
    the centres of mass in them, the capsules' radius, the carriage box's length) at q = 0."""
    q0 = model.neutral()
    joints = model.joint_placements(q0)
    coms = model.body_poses(q0)[:, :3, 3]
    parents = model.parents
    segments: List[tuple[int, np.ndarray, np.ndarray, bool]] = []
    com_local = []
    for i in range(model.n):
        inv = np.linalg.inv(joints[i])
        com_local.append(transform_points(inv, coms[i]))
        children = [c for c in range(model.n) if parents[c] == i]
        ends = [(transform_points(inv, joints[c][:3, 3]), False) for c in children] or [(2 * com_local[i], True)]
        segments += [(i, np.zeros(3), e, leaf) for e, leaf in ends if np.linalg.norm(e) > 1e-9]
    longest = max((float(np.linalg.norm(b - a)) for _, a, b, _ in segments), default=0.0)
    points = np.vstack([joints[:, :3, 3], coms])
    r = max(0.05 * longest, 0.015 * float(np.ptp(points, axis=0).max()), 1e-3)
    return segments, com_local, r, max(0.4 * longest, 8 * r)


def default_shapes(model: Model, radius: Optional[float] = None) -> List[Shape]:
    """Capsules between joints (to twice the centre of mass for leaves), spheres at centres of mass,
    and a box (``cart{i}``) along each carriage's axis (``carriages``): 40% of the longest segment
    (at least 8 radii) long, half that across.

    radius: the capsules' radius; default the larger of 5% of the longest segment and 1.5% of the
    model's size at q = 0 (at least 1 mm).
    """
    segments, com_local, default_radius, cart = _segments(model)
    r = radius if radius is not None else default_radius
    shapes = [Shape(i, f"joint{i}", "sphere", np.array([r, 0.0, 0.0]), np.eye(4), LINK_RGBA) for i in range(model.n)]
    for k, (body, a, b, leaf) in enumerate(segments):
        length = float(np.linalg.norm(b - a))
        shapes.append(Shape(body, f"link{body}_{k}", "cylinder", np.array([r, length, 0.0]), segment_frame(a, b), LINK_RGBA))
        if leaf:
            shapes.append(Shape(body, f"link{body}_{k}_end", "sphere", np.array([r, 0.0, 0.0]), translation(b), LINK_RGBA))
    masses = np.asarray(model.masses, dtype=float)
    m_max = masses.max() if masses.size and masses.max() > 0 else 1.0
    for i in range(model.n):
        if masses[i] > 0:
            rc = 1.3 * r * (masses[i] / m_max) ** (1 / 3)
            shapes.append(Shape(i, f"com{i}", "sphere", np.array([rc, 0.0, 0.0]), translation(com_local[i]), COM_RGBA))
    for body, axis in carriages(model):
        shapes.append(Shape(body, f"cart{body}", "box", np.array([cart / 2, cart / 2, cart]),
                            segment_frame(-axis * cart / 2, axis * cart / 2), LINK_RGBA))
    return shapes


def body_frames(model: Model, q: Sequence[float] | np.ndarray) -> np.ndarray:
    """(n+1, 4, 4) world poses of the joint frames at q (n,), the world (identity) last: index with body, -1 included."""
    frames = np.empty((model.n + 1, 4, 4))
    frames[:-1] = model.joint_placements(np.asarray(q, dtype=float))
    frames[-1] = np.eye(4)
    return frames


#: What viewers animate: a hovi.Trajectory (its t and q) or an (N, n) array of configurations.
Motion = Any


def motion_arrays(model: Model, motion: Motion, times: Optional[Sequence[float]] = None,
                  rate: float = 30.0) -> tuple[np.ndarray, np.ndarray]:
    """(times (N,), configurations (N, n)) of a Trajectory, or of an array at ``times`` (default 1/rate apart)."""
    if hasattr(motion, "q") and hasattr(motion, "t"):
        q, t = np.asarray(motion.q, dtype=float), np.asarray(motion.t, dtype=float)
    else:
        q = np.atleast_2d(np.asarray(motion, dtype=float))
        t = np.arange(q.shape[0]) / rate if times is None else np.asarray(times, dtype=float)
    if q.ndim != 2 or q.shape[1] != model.nq:
        raise ValueError(f"configurations must be (N, {model.nq}) for this model, got shape {q.shape}")
    return t, q


def sample_configurations(q: np.ndarray, t: np.ndarray, fps: float) -> tuple[np.ndarray, np.ndarray]:
    """Configurations at ``fps`` frames per second over [t[0], t[-1]] (linear interpolation in q).

    q: (N, n) configurations at increasing times t: (N,). Returns (frame times (F,), (F, n)).
    """
    q = np.asarray(q, dtype=float)
    t = np.asarray(t, dtype=float)
    if q.ndim != 2 or t.shape != (q.shape[0],):
        raise ValueError(f"q must be (N, n) and t (N,), got {q.shape} and {t.shape}")
    if q.shape[0] < 1 or not np.all(np.isfinite(q)) or not np.all(np.isfinite(t)):
        raise ValueError("q and t must be non-empty and finite")
    if np.any(np.diff(t) <= 0):
        raise ValueError("times must be strictly increasing")
    if not fps > 0:
        raise ValueError(f"fps must be positive, got {fps}")
    count = int(np.floor((t[-1] - t[0]) * fps + 1e-9)) + 1
    frame_t = t[0] + np.arange(count) / fps
    return frame_t, np.column_stack([np.interp(frame_t, t, q[:, j]) for j in range(q.shape[1])])
