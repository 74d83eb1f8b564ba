"""hovi.vis.viewer: a model and its motions in the browser, through meshcat (``pip install hovi[viewer]``).

``Viewer(model)`` starts meshcat's local server (it serves its own JavaScript: no internet
needed) and shows the model; ``display(q)`` poses it, ``play(trajectory)`` loads an animation
with meshcat's play / pause / reset buttons and time scrubber (the "Animations" folder of its
controls), ``add_marker`` / ``add_arrow`` draw points (contacts, targets) and forces, and
``export_html(path)`` writes everything shown so far as one standalone HTML file that opens
without a server. ``Viewer(model, server=False)`` records without starting a server (scripts,
tests, the command line); ``animation_html`` does that in one call.

``add_ground(height)`` draws a ground grid under the motion (models with a floating or planar
base, the robot examples; world shapes such as terrain boxes are the model's visuals on the
world, ``Model.add_visual(None, ...)``); ``frame_model`` fits the camera to the bounding box of
the motion. ``add_terrain(terrain)`` draws a ``hovi.contact.Terrain`` (its ground grid with the
gaps open and shown as dark strips, and its boxes), and ``play(motion, arrows=..., pushes=...)``
animates forces as arrows with the motion (``hovi.vis.video.ForceArrows``: a contact simulation's forces at its active
contacts) and pushes (``hovi.control.Push``) as arrows onto the pushed points while they act. A cart
(a body with mass on a prismatic joint to the world) runs on a rail (``/meshcat/hovi/rails``). An
exported animation shows its time (``t = 1.23 s``) in the top left corner and the arrows' scales
(``forces: 100 N per m``) in the bottom left one, and an address ending in ``#t=1.5`` pauses it at 1.5 s.
"""
from __future__ import annotations

import base64
import os
from collections import OrderedDict
from html import escape as html_escape
from pathlib import Path
from typing import Any, Iterable, Optional, Sequence, Union

import numpy as np

from .._core import Model
from .geometry import (Motion, Shape, body_frames, ground_lines, model_shapes, motion_arrays, rail_lines,
                       sample_configurations, segment_frame, shape_corners, transform_points, translation)
from .video import (ARROW_RGBA, PUSH_RGBA, ForceArrows, model_size, push_frames, push_label, push_scale,
                    terrain_scene)

__all__ = ["Viewer", "animation_html"]


def _meshcat() -> Any:
    try:
        import meshcat  # noqa: F401
        import meshcat.animation
        import meshcat.commands
        import meshcat.geometry
    except ImportError as e:  # pragma: no cover - exercised only without the extra
        raise ImportError("hovi.vis.viewer needs meshcat: pip install 'hovi[viewer]'") from e
    return meshcat


def _material(rgba: Sequence[float]) -> Any:
    """A meshcat (Lambert) material of colour rgba (4,) in [0, 1]."""
    rgba = np.asarray(rgba, dtype=float)
    r, g, b = (np.clip(rgba[:3], 0, 1) * 255).round().astype(int)
    return _meshcat().geometry.MeshLambertMaterial(color=(int(r) << 16) | (int(g) << 8) | int(b), opacity=float(rgba[3]))


def _geometry(shape: Shape) -> Any:
    g = _meshcat().geometry
    if shape.kind == "box":
        return g.Box(list(shape.size))
    if shape.kind == "sphere":
        return g.Sphere(float(shape.size[0]))
    if shape.kind == "cylinder":
        return g.Cylinder(float(shape.size[1]), float(shape.size[0]))
    suffix = Path(str(shape.mesh_path)).suffix.lower()
    readers = {".stl": g.StlMeshGeometry, ".obj": g.ObjMeshGeometry, ".dae": g.DaeMeshGeometry}
    if suffix not in readers:
        raise ValueError(f"mesh '{shape.mesh_path}': meshcat reads .stl, .obj and .dae files, not '{suffix}'")
    return readers[suffix].from_file(shape.mesh_path)


# meshcat's (three.js's) cylinders run along y, URDF's along z: turn y into z.
_Y_TO_Z = np.array([[1.0, 0, 0, 0], [0, 0, -1, 0], [0, 1, 0, 0], [0, 0, 0, 1]])


def _local_transform(shape: Shape) -> np.ndarray:
    """The shape node's pose in its body node (its origin, turned for cylinders, scaled for meshes)."""
    if shape.kind == "cylinder":
        return shape.origin @ _Y_TO_Z
    if shape.kind == "mesh":
        return shape.origin @ np.diag(np.append(shape.scale, 1.0))
    return shape.origin


class Viewer:
    """A meshcat scene of one model: pose it, animate motions, draw markers, export HTML.

    model: the hovi.Model to draw (its visuals, or default capsules and centre-of-mass spheres).
    package_dirs: directories searched for ``package://`` meshes (then ROS_PACKAGE_PATH).
    server: start meshcat's server (default); False records the scene for ``export_html`` only.
    zmq_url: connect to a running meshcat server instead of starting one.
    """

    def __init__(self, model: Model, package_dirs: Iterable[Union[str, os.PathLike[str]]] = (), *,
                 server: bool = True, zmq_url: Optional[str] = None) -> None:
        mc = _meshcat()
        self.model = model
        self.shapes = model_shapes(model, package_dirs)
        self._visualizer = mc.Visualizer(zmq_url=zmq_url) if server or zmq_url else None
        self._commands: "OrderedDict[tuple[str, str], Any]" = OrderedDict()
        self._camera: Optional[tuple[np.ndarray, np.ndarray]] = None
        self._corners: Optional[list[np.ndarray]] = None
        self._start_time: Optional[float] = None  # of the last motion given to play (the time stamp)
        self._legend: list[str] = []  # the arrows' scales of the last motion given to play
        self.duration = 0.0  #: length of the last motion given to play (s)
        self._body_paths = [self._path("hovi", "bodies", f"{i:03d}_{self._safe(name)}")
                            for i, name in enumerate(model.body_names)] + [self._path("hovi", "world")]
        for shape in self.shapes:
            path = self._body_paths[shape.body].append(self._safe(shape.name))
            self._send(mc.commands.SetObject(_geometry(shape), _material(shape.rgba), path))
            self._send(mc.commands.SetTransform(_local_transform(shape), path))
        self._rails(model.neutral())
        self.display(model.neutral())

    @staticmethod
    def _safe(name: str) -> str:
        return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)

    @staticmethod
    def _path(*entries: str) -> Any:
        return _meshcat().path.Path(("meshcat",) + entries)

    def _send(self, command: Any) -> None:
        lowered = command.lower()
        self._commands[(lowered["type"], lowered["path"])] = command
        if self._visualizer is not None:
            self._visualizer.window.send(command)

    @property
    def url(self) -> Optional[str]:
        """The address of the live view (None without a server)."""
        return None if self._visualizer is None else self._visualizer.url()

    def close(self) -> None:
        """Stop the meshcat server this viewer started (the recorded scene stays exportable)."""
        if self._visualizer is not None:
            process = getattr(self._visualizer.window, "server_proc", None)
            if process is not None:
                process.kill()
                process.wait()
            self._visualizer = None

    def display(self, q: Sequence[float] | np.ndarray) -> None:
        """Pose the model at q: (nq,) joint positions (a free base: position and quaternion first)."""
        q = np.asarray(q, dtype=float)
        if q.shape != (self.model.nq,) or not np.all(np.isfinite(q)):
            raise ValueError(f"q must be {self.model.nq} finite numbers, got shape {q.shape}")
        commands = _meshcat().commands
        for path, frame in zip(self._body_paths, body_frames(self.model, q)):
            self._send(commands.SetTransform(frame, path))

    def play(self, motion: Motion, times: Optional[Sequence[float]] = None, fps: float = 30.0,
             repetitions: int = 1, arrows: Optional[ForceArrows] = None,
             pushes: Optional[Sequence[Any]] = None) -> "Viewer":
        """Animate a motion: a hovi.Trajectory, or (N, n) configurations at ``times`` (N,) seconds.

        The motion is sampled at ``fps`` frames per second (linear interpolation in q). meshcat's
        controls play, pause, reset and scrub it. ``arrows`` (``hovi.vis.video.ForceArrows``): forces
        animated with it as red arrows (``/meshcat/hovi/forces/NAME/shaft`` and ``head``), shown
        while active, drawn over the model. ``pushes`` (a list of ``hovi.control.Push``): blue arrows
        onto the pushed points (``/meshcat/hovi/pushes/NN_push/...``), each from its time for
        max(duration, 0.2 s) (``hovi.vis.video.push_frames``). The exported page states their scales
        and the pushes' impulses in its bottom left corner. Returns the viewer.
        """
        if arrows is not None and not isinstance(arrows, ForceArrows):
            raise TypeError(f"arrows must be a hovi.vis.video.ForceArrows, got {type(arrows).__name__}")
        t, q = motion_arrays(self.model, motion, times, fps)
        frame_t, frames_q = sample_configurations(q, t, fps)
        mc = _meshcat()
        anim = mc.animation.Animation(default_framerate=fps)
        for k, qk in enumerate(frames_q):
            for path, frame in zip(self._body_paths[:-1], body_frames(self.model, qk)):
                mc.animation.AnimationFrameVisualizer(anim, path, k).set_transform(frame)
        self.display(frames_q[0])
        self._rails(frames_q)
        self._legend = []
        if arrows is not None:
            at = arrows.frames(self.model, frame_t, frames_q, 1.0 / fps)
            self._animate_arrows(anim, "forces", list(arrows.names or []), at, frames_q[0], ARROW_RGBA)
            self._legend.append(arrows.legend(self.model, frames_q[0]))
        if pushes:
            per_metre = push_scale(self.model, pushes, frames_q[0])
            at = push_frames(self.model, pushes, frame_t, frames_q, per_metre)
            self._animate_arrows(anim, "pushes", ["push"] * len(pushes), at, frames_q[0], PUSH_RGBA)
            self._legend.append(f"pushes: {per_metre:.3g} N s per m (" +
                                "; ".join(f"{push_label(p)} at t = {float(p.time):.3g} s" for p in pushes) + ")")
        self._send(mc.commands.SetAnimation(anim, play=True, repetitions=int(repetitions)))
        self.duration = float(frame_t[-1] - frame_t[0])
        self._start_time = float(frame_t[0])
        return self

    def _animate_arrows(self, anim: Any, group: str, names: Sequence[str],
                        at: tuple[np.ndarray, np.ndarray, np.ndarray], q0: np.ndarray, rgba: np.ndarray) -> None:
        """The arrows' objects (``/meshcat/hovi/GROUP/NN_NAME``: a unit cylinder as the shaft, scaled
        to length, and a cone as the head) and their tracks in the animation ``anim``: position,
        orientation and scale per frame (``at``: origins (F, A, 3), vectors (F, A, 3), shown (F, A)),
        scaled to nothing while an arrow is not shown; their thickness from the model's size at q0."""
        mc = _meshcat()
        origins, vectors, shown = at
        radius = 0.012 * model_size(self.model, q0)
        head = 6 * radius
        r, g, b = (rgba[:3] * 255).round().astype(int)
        # drawn over the model (after the opaque shapes, without the depth test), as the video does: a
        # vertical force on a foot otherwise hides inside a vertical shin
        material = mc.geometry.MeshLambertMaterial(color=(int(r) << 16) | (int(g) << 8) | int(b), opacity=1.0,
                                                   transparent=True, depthTest=False)
        hidden = np.diag([1e-6, 1e-6, 1e-6, 1.0])
        for c in range(origins.shape[1]):
            base = self._path("hovi", group, f"{c:02d}_{self._safe(str(names[c]))}")
            parts = {"shaft": (base.append("shaft"), mc.geometry.Cylinder(1.0, radius)),
                     "head": (base.append("head"),
                              mc.geometry.Cylinder(head, 0.0, radiusTop=0.0, radiusBottom=2.5 * radius))}
            for k in range(len(origins)):
                poses = self._arrow_poses(origins[k, c], vectors[k, c], bool(shown[k, c]), head, hidden)
                for part, (path, _) in parts.items():
                    frame, scale = poses[part]
                    visualizer = mc.animation.AnimationFrameVisualizer(anim, path, k)
                    visualizer.set_transform(frame)
                    visualizer.set_property("scale", "vector3", [float(x) for x in scale])
                    if k == 0:
                        self._send(mc.commands.SetObject(parts[part][1], material, path))
                        self._send(mc.commands.SetTransform(frame @ np.diag(np.append(scale, 1.0)), path))

    @staticmethod
    def _arrow_poses(origin: np.ndarray, vector: np.ndarray, shown: bool, head: float,
                     hidden: np.ndarray) -> dict:
        """{part: (pose (4, 4) with meshcat's cylinder axis y along the vector, scale (3,))} of one
        arrow's shaft (a unit cylinder) and head (a cone ``head`` long, shortened for a short arrow)."""
        length = float(np.linalg.norm(vector))
        if not shown or length <= 1e-9:
            pose = translation(origin)
            return {"shaft": (pose, np.diag(hidden)[:3]), "head": (pose, np.diag(hidden)[:3])}
        h = min(head, 0.5 * length)
        d = vector / length
        tip_base = origin + (length - h) * d
        return {"shaft": (segment_frame(origin, tip_base) @ _Y_TO_Z, np.array([1.0, length - h, 1.0])),
                "head": (segment_frame(tip_base, origin + vector) @ _Y_TO_Z, np.full(3, h / head))}

    def _rails(self, q: np.ndarray) -> None:
        """The carts' rails (``hovi.vis.geometry.rail_lines``) under configurations q ((n,) or (N, n)),
        as lines (``/meshcat/hovi/rails``)."""
        lines = rail_lines(self.model, q)
        if len(lines):
            mc = _meshcat()
            geometry = mc.geometry.PointsGeometry(position=lines.reshape(-1, 3).astype(np.float32).T)
            rails = mc.geometry.LineSegments(geometry, mc.geometry.LineBasicMaterial(color=0x404048, linewidth=3))
            self._send(mc.commands.SetObject(rails, path=self._path("hovi", "rails")))

    def add_ground(self, height: float = 0.0, q: Optional[np.ndarray] = None, margin: float = 0.5,
                   spacing: Optional[float] = None) -> None:
        """A ground grid on the plane z = height (world shapes, such as terrain boxes, are the
        model's visuals): under the model at configurations q ((n,) or (N, n); default zeros) with
        ``margin`` m around it, lines ``spacing`` m apart (default: 10 to 40 lines each way, see
        ``hovi.vis.geometry.ground_lines``). Replaces meshcat's own grid (at z = 0, 20 m wide)."""
        if not np.isfinite(height):
            raise ValueError(f"height must be a finite number, got {height!r}")
        self._grid(ground_lines(self._points(q), float(height), margin, spacing))

    def add_terrain(self, terrain: Any, q: Optional[np.ndarray] = None, margin: float = 0.5,
                    spacing: Optional[float] = None) -> None:
        """A ``hovi.contact.Terrain`` under the model at configurations q ((n,) or (N, n); default
        zeros): the ground grid (as ``add_ground`` at ``terrain.ground``) with its gaps left open,
        each gap a dark strip, and its boxes (``hovi.vis.video.terrain_scene``), as world shapes
        (``/meshcat/hovi/world/terrain_*``) over the grid's extent. For foot spheres (contact points
        at their centres) give the terrain lowered by the radius."""
        lines, shapes = terrain_scene(terrain, self._points(q), margin, spacing)
        self._grid(lines)
        mc = _meshcat()
        for shape in shapes:
            path = self._body_paths[-1].append(self._safe(shape.name))
            self._send(mc.commands.SetObject(_geometry(shape), _material(shape.rgba), path))
            self._send(mc.commands.SetTransform(_local_transform(shape), path))
        self.shapes = list(self.shapes) + shapes
        self._corners = None

    def _grid(self, lines: np.ndarray) -> None:
        """Grid lines (L, 2, 3) as the ground (``/meshcat/hovi/ground/grid``), meshcat's own grid hidden."""
        mc = _meshcat()
        geometry = mc.geometry.PointsGeometry(position=lines.reshape(-1, 3).astype(np.float32).T)
        grid = mc.geometry.LineSegments(geometry, mc.geometry.LineBasicMaterial(color=0x8a8f98))
        self._send(mc.commands.SetObject(grid, path=self._path("hovi", "ground", "grid")))
        self._send(mc.commands.SetProperty("visible", False, mc.path.Path(("Grid",))))

    def add_marker(self, name: str, position: Sequence[float], radius: float = 0.03,
                   rgba: Sequence[float] = (0.1, 0.8, 0.2, 1.0)) -> None:
        """A sphere at a world position (3,), e.g. a contact point or a target."""
        mc = _meshcat()
        path = self._path("hovi", "markers", self._safe(name))
        self._send(mc.commands.SetObject(mc.geometry.Sphere(float(radius)), _material(rgba), path))
        self._send(mc.commands.SetTransform(translation(_finite3(position, "position")), path))

    def add_arrow(self, name: str, origin: Sequence[float], vector: Sequence[float], radius: float = 0.01,
                  rgba: Sequence[float] = (0.85, 0.1, 0.1, 1.0)) -> None:
        """An arrow from a world point (3,) along a vector (3,) (its length in metres), e.g. a force."""
        mc = _meshcat()
        a, v = _finite3(origin, "origin"), _finite3(vector, "vector")
        length = float(np.linalg.norm(v))
        if length == 0:
            raise ValueError("vector must be non-zero")
        material = _material(rgba)
        head = min(0.3 * length, 6 * radius)
        base = self._path("hovi", "markers", self._safe(name))
        shaft_end = a + v * (1 - head / length)
        for part, (p0, p1, geometry) in {
            "shaft": (a, shaft_end, mc.geometry.Cylinder(length - head, radius)),
            "head": (shaft_end, a + v, mc.geometry.Cylinder(head, 0.0, radiusTop=0.0, radiusBottom=2.5 * radius)),
        }.items():
            path = base.append(part)
            self._send(mc.commands.SetObject(geometry, material, path))
            self._send(mc.commands.SetTransform(segment_frame(p0, p1) @ _Y_TO_Z, path))

    def show_model(self, visible: bool = True) -> None:
        """Show or hide the model (markers and arrows stay)."""
        mc = _meshcat()
        self._send(mc.commands.SetProperty("visible", bool(visible), self._path("hovi", "bodies")))
        self._send(mc.commands.SetProperty("visible", bool(visible), self._path("hovi", "world")))

    def delete_markers(self) -> None:
        """Remove every marker and arrow."""
        path = self._path("hovi", "markers")
        prefix = path.lower()
        for key in [k for k in self._commands if k[1] == prefix or k[1].startswith(prefix + "/")]:
            del self._commands[key]
        if self._visualizer is not None:
            self._visualizer.window.send(_meshcat().commands.Delete(path))

    def set_camera(self, target: Sequence[float], position: Sequence[float]) -> None:
        """Look at a world point (3,) from a world position (3,).

        Exported HTML uses both; a live meshcat view (whose orbit centre stays at the origin)
        takes the position only.
        """
        self._camera = (_finite3(target, "target"), _finite3(position, "position"))
        mc = _meshcat()
        self._send(mc.commands.SetProperty("position", _y_up(self._camera[1]).tolist(),
                                           mc.path.Path(("Cameras", "default", "rotated", "<object>"))))

    def _points(self, q: Optional[np.ndarray] = None) -> np.ndarray:
        """(K, 3) world corners of the shapes' boxes (``hovi.vis.geometry.shape_corners``) at up to 50 of
        the configurations q ((n,) or (N, n); default zeros)."""
        if self._corners is None:
            self._corners = [shape_corners(s) for s in self.shapes]
        qs = np.atleast_2d(self.model.neutral() if q is None else np.asarray(q, dtype=float))
        points = []
        for qk in qs[:: max(1, len(qs) // 50)]:
            frames = body_frames(self.model, qk)
            points += [transform_points(frames[s.body], c) for s, c in zip(self.shapes, self._corners)]
            points.append(frames[:-1, :3, 3])
        return np.concatenate(points)

    def frame_model(self, q: Optional[np.ndarray] = None, aspect: float = 4 / 3) -> None:
        """Point the camera at the model from the side, fitting the bounding box of its shapes.

        q: (n,) one configuration, or (N, n) configurations (a motion) to keep in view; default zeros.
        The camera looks at the centre of the box from the front left, above, as close as keeps
        the box's corners inside meshcat's 75 degree (vertical) view in a window of ``aspect``
        (width / height).
        """
        points = self._points(q)
        centre = (points.min(axis=0) + points.max(axis=0)) / 2
        direction = np.array([0.4, -1.0, 0.5])
        direction /= np.linalg.norm(direction)
        right = np.cross(direction, [0.0, 0.0, 1.0])
        right /= np.linalg.norm(right)
        up = np.cross(right, direction)
        rel = points - centre
        depth, x, y = rel @ direction, np.abs(rel @ right), np.abs(rel @ up)
        tan_v = np.tan(np.radians(75.0) / 2) * 0.92  # a small margin
        distance = float(np.max(np.maximum(depth + x / (aspect * tan_v), depth + y / tan_v)))
        self.set_camera(centre, centre + max(distance, 0.1) * direction)

    def html(self) -> str:
        """The standalone HTML of everything shown so far (meshcat's JavaScript included)."""
        import umsgpack

        script = (Path(_meshcat().__file__).parent / "viewer" / "dist" / "main.min.js").read_text()
        blobs = ",\n".join('"' + base64.b64encode(umsgpack.packb(c.lower())).decode() + '"'
                           for c in self._commands.values())
        camera = ""
        if self._camera is not None:
            (tx, ty, tz), (px, py, pz) = (_y_up(p) for p in self._camera)
            camera = (f"viewer.camera.position.set({px}, {py}, {pz});\n"
                      f"viewer.controls.target.set({tx}, {ty}, {tz});\n")
        clock = "" if self._start_time is None else _CLOCK.format(start=self._start_time)
        if self._legend:
            clock += _LEGEND.format(text="<br>".join(html_escape(line) for line in self._legend))
        return _HTML.format(script=script.replace("</script", "<\\/script"), commands=blobs, camera=camera,
                            clock=clock)

    def export_html(self, path: Union[str, os.PathLike[str]]) -> Path:
        """Write ``html()`` to a file; returns its path. Open it in any browser, no server needed."""
        out = Path(path)
        out.parent.mkdir(parents=True, exist_ok=True)
        out.write_text(self.html())
        return out


def _y_up(p: np.ndarray) -> np.ndarray:
    """A world point (z up) in the frame of meshcat's camera (three.js, y up)."""
    return np.array([p[0], p[2], -p[1]], dtype=float)


def _finite3(x: Sequence[float], name: str) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be 3 finite numbers, got {x!r}")
    return a


def animation_html(model: Model, motion: Motion, path: Union[str, os.PathLike[str]],
                   times: Optional[Sequence[float]] = None, fps: float = 30.0,
                   package_dirs: Iterable[Union[str, os.PathLike[str]]] = (), *,
                   ground: Optional[float] = None, terrain: Any = None,
                   arrows: Optional[ForceArrows] = None, pushes: Optional[Sequence[Any]] = None) -> Path:
    """Write a standalone HTML animation of a motion (see Viewer.play) without starting a server:
    the camera fits the motion (``Viewer.frame_model``), the time shows in the top left corner, and
    ``ground`` (a height in m; None: none) draws a ground grid under the motion (``Viewer.add_ground``),
    or ``terrain`` (a ``hovi.contact.Terrain``) its ground, gaps and boxes (``Viewer.add_terrain``);
    ``arrows`` (``hovi.vis.video.ForceArrows``): forces animated as arrows (e.g. contact forces);
    ``pushes`` (a list of ``hovi.control.Push``): an arrow onto each pushed point while it acts (see
    ``Viewer.play``), the scales and the pushes' impulses stated in the bottom left corner."""
    if ground is not None and terrain is not None:
        raise ValueError("give ground or terrain, not both (a terrain has its own ground height)")
    viewer = Viewer(model, package_dirs, server=False)
    q = motion_arrays(model, motion, times, fps)[1]
    if ground is not None:
        viewer.add_ground(ground, q)
    if terrain is not None:
        viewer.add_terrain(terrain, q)
    viewer.frame_model(q)
    viewer.play(motion, times, fps, arrows=arrows, pushes=pushes)
    return viewer.export_html(path)


_HTML = """<!DOCTYPE html>
<html>
<head><meta charset="utf-8"><title>hovi</title>
<style>html, body {{ margin: 0; height: 100%; overflow: hidden; }} #meshcat-pane {{ width: 100%; height: 100%; }}</style>
</head>
<body>
<div id="meshcat-pane"></div>
{clock}<script>{script}</script>
<script>
var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));
for (const blob of [{commands}]) {{
  const text = atob(blob), bytes = new Uint8Array(text.length);
  for (let i = 0; i < text.length; ++i) bytes[i] = text.charCodeAt(i);
  viewer.handle_command_bytearray(bytes);
}}
{camera}viewer.controls.update();
// An address ending in #t=SECONDS pauses the animation there (stills, tests).
const at = /[#&]t=([0-9.eE+-]+)/.exec(window.location.hash);
if (at) {{ viewer.animator.pause(); viewer.animator.seek(parseFloat(at[1])); }}
const clock = document.getElementById("hovi-time");
if (clock) {{
  const tick = () => {{
    const action = viewer.animator.actions[0];
    if (action) clock.textContent = "t = " + (Number(clock.dataset.start) + action.time).toFixed(2) + " s";
    requestAnimationFrame(tick);
  }};
  tick();
}}
</script>
</body>
</html>
"""

# The time stamp of an exported animation (updated from meshcat's animation clock by _HTML's script).
_CLOCK = ('<div id="hovi-time" data-start="{start}" style="position: absolute; left: 10px; top: 8px; '
          'font: 15px monospace; color: #222; background: rgba(255, 255, 255, 0.7); padding: 1px 4px; '
          'pointer-events: none;">t = {start:.2f} s</div>\n')
# The arrows' scales of an exported animation.
_LEGEND = ('<div id="hovi-legend" style="position: absolute; left: 10px; bottom: 8px; font: 13px sans-serif; '
           'color: #222; background: rgba(255, 255, 255, 0.7); padding: 1px 4px; pointer-events: none;">{text}</div>\n')
