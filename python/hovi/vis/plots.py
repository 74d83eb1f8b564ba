"""hovi.vis.plots: figures of simulations and optimisations as image files (matplotlib, Agg backend).

What ``hovi simulate`` and ``hovi optimize`` write (``energy_error.png``, ``contact_forces.png``,
``final_configuration.png``, ``optimize_NAME.png``); each function takes arrays or a result and a path and draws without a
window. Curves per joint carry the joint's name in a legend (beside the axes, off the curves, when
there are more than ``LEGEND_INSIDE`` of them); a configuration in space is drawn with equal axes (a
metre is as long along x, y and z), a scale bar, the ground, and the forces and pushes as arrows.
"""
from __future__ import annotations

from typing import Any, Optional, Sequence

import numpy as np

#: Legends of more entries than this go beside their axes (a 12-joint robot's would cover its curves).
LEGEND_INSIDE = 6


def control_labels(model) -> list:
    """A legend label per control: ``u[k]`` and, for an actuator on one joint, that joint's name."""
    actuation = np.asarray(model.actuation, dtype=float).reshape(model.n, -1)
    labels = []
    for k in range(model.n_controls):
        joints = np.flatnonzero(actuation[:, k]) if k < actuation.shape[1] else []
        labels.append(f"u[{k}] ({model.joint_names[joints[0]]})" if len(joints) == 1 else f"u[{k}]")
    return labels


def legend(ax, fontsize: float = 8, **inside: Any) -> Any:
    """The axes' legend: inside them (with the keywords ``inside``) for up to ``LEGEND_INSIDE`` entries,
    else to their right in columns of up to 16 (``fig.tight_layout`` makes room for it)."""
    count = len(ax.get_legend_handles_labels()[0])
    if count <= LEGEND_INSIDE:
        return ax.legend(fontsize=fontsize, **inside)
    return ax.legend(fontsize=fontsize, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                     ncol=-(-count // 16))


def pyplot():
    """matplotlib.pyplot on the Agg backend (files, no window)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def plot_energy_error(t, energy, path, title=""):
    """Relative energy error |E - E0| / |E0| over time, log scale."""
    plt = pyplot()
    err = np.abs(energy - energy[0]) / max(abs(energy[0]), 1e-300)
    fig, ax = plt.subplots(figsize=(7, 3.5))
    ax.semilogy(t[1:], np.maximum(err[1:], 1e-17), lw=0.8)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("|E - E0| / |E0|")
    ax.set_title(title or "energy error")
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_contact_forces(t, forces, weight, path, labels=None, title=""):
    """Vertical contact forces over time: each contact's (t (K,), forces (K, C) in N), their sum and
    the weight (N) it carries when the robot stands; an impact's spike is cut at 3 times the weight
    (its peak in the legend)."""
    plt = pyplot()
    t, forces = np.asarray(t, dtype=float), np.asarray(forces, dtype=float).reshape(len(t), -1)
    labels = list(labels) if labels is not None else [f"contact {c}" for c in range(forces.shape[1])]
    total = forces.sum(axis=1)
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for c in range(forces.shape[1]):
        ax.step(t, forces[:, c], where="post", lw=0.8, label=labels[c])
    ax.step(t, total, where="post", lw=1.6, color="k",
            label=f"sum (peak {total.max():.4g} N)" if len(total) else "sum")
    ax.axhline(weight, color="tab:red", ls="--", lw=1, label=f"weight {weight:.4g} N")
    top = max(3 * weight, 1e-9)
    ax.set_ylim(min(0.0, float(forces.min(initial=0.0))) - 0.05 * top, min(top, max(1.2 * float(total.max(initial=0.0)),
                                                                              1.2 * weight)))
    ax.set_xlabel("time [s]")
    ax.set_ylabel("vertical contact force [N]")
    ax.set_title(title or "contact forces")
    legend(ax, fontsize=7, ncol=2, loc="upper right")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_configuration(model, q, path, title="", **kwargs: Any) -> None:
    """Write ``configuration_figure(model, q, title, **kwargs)`` to ``path`` (e.g. ``final_configuration.png``,
    with ``ground=``/``terrain=``, ``arrows=`` and ``pushes=``)."""
    plt = pyplot()
    fig = configuration_figure(model, q, title, **kwargs)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def configuration_figure(model, q, title="", *, ground: Optional[float] = None, terrain: Any = None,
                         arrows: Any = None, time: Optional[float] = None, pushes: Optional[Sequence[Any]] = None):
    """The kinematic tree at q (n,) as a matplotlib figure: joint origins joined parent to child,
    centres of mass as dots, each cart (``hovi.vis.geometry.carriages``) a box on its rail, with
    equal axes in metres, a scale bar of a round length (``gid`` 'scale_bar'), a legend, and the
    joints' names beside them (up to 12 joints).

    ground: a height (m) drawn as a translucent plane across the view (``gid`` 'ground'); terrain (a
    ``hovi.contact.Terrain``) instead: its ground, gaps and boxes (``hovi.vis.video.terrain_scene``).
    Both are drawn behind the model, so that a link sunk below the ground shows.
    arrows (``hovi.vis.video.ForceArrows``): the forces at ``time`` (s; default their last time) as red
    arrows, their scale in the legend (``forces: 100 N per m``).
    pushes (a list of ``hovi.control.Push``: time, body, impulse in N s, point in the body's joint
    frame, duration): each a blue arrow onto its pushed point at q, labelled with its impulse and
    time, their scale in the legend (``pushes: 20 N s per m``)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from .geometry import body_frames, default_shapes, rail_lines, round_scale, transform_points
    from .video import (ARROW_RGBA, PUSH_RGBA, arrow_segments, model_size, push_frames, push_label, push_scale,
                        shape_triangles, terrain_scene)
    plt = pyplot()
    q = np.asarray(q, dtype=float)
    if terrain is not None:
        if ground is not None:
            raise ValueError("give ground or terrain, not both (a terrain has its own ground height)")
        ground = float(terrain.ground)
    X = model.joint_placements(q)[:, :3, 3]
    C = model.body_poses(q)[:, :3, 3]
    frames = body_frames(model, q)
    carts = [transform_points(frames[s.body], shape_triangles(s)) for s in default_shapes(model)
             if s.name.startswith("cart")]
    rails = rail_lines(model, q)
    head = 0.08 * model_size(model, q)
    drawn = []  # (gid, origins, vectors, colour, legend label) of the arrows
    if arrows is not None:
        at = np.array([arrows.times[-1] if time is None else time])
        origins, vectors, shown = arrows.frames(model, at, q[None], 0.0)
        drawn.append(("forces", origins[0][shown[0]], vectors[0][shown[0]], ARROW_RGBA, arrows.legend(model, q)))
    if pushes:
        per_metre = push_scale(model, pushes, q)
        origins, vectors, _ = push_frames(model, pushes, np.zeros(1), q[None], per_metre)
        drawn.append(("pushes", origins[0], vectors[0], PUSH_RGBA, f"pushes: {per_metre:.3g} N s per m"))
    pts = np.vstack([X, C, np.zeros((1, 3)), rails.reshape(-1, 3)] + [c.reshape(-1, 3) for c in carts]
                    + [p for _, o, v, _, _ in drawn for p in (o, o + v)])
    if ground is not None:
        pts = np.vstack([pts, [pts[0, 0], pts[0, 1], ground]])
    mid, half = (pts.min(axis=0) + pts.max(axis=0)) / 2, max(np.ptp(pts, axis=0).max() / 2 * 1.05, 1e-3)
    lo, hi = mid - half, mid + half
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    ax.computed_zorder = False  # drawn in zorder: the ground first, so that a link below it shows
    if ground is not None:
        plane = Poly3DCollection([[(lo[0], lo[1], ground), (hi[0], lo[1], ground), (hi[0], hi[1], ground),
                                   (lo[0], hi[1], ground)]], facecolors=[(0.55, 0.62, 0.5, 0.35)], linewidths=0,
                                 zorder=0, gid="ground", label=f"ground (z = {ground:.3g} m)")
        ax.add_collection3d(plane)
    if terrain is not None:
        _, shapes = terrain_scene(terrain, np.array([lo, hi]), margin=0.0, spacing=half / 50)  # the view's extent
        for shape in shapes:
            ax.add_collection3d(Poly3DCollection(shape_triangles(shape), facecolors=[tuple(shape.rgba[:3]) + (0.5,)],
                                                 linewidths=0, zorder=0.5))
    # a scale bar of a round length, on the ground (or at the bottom of the view) in its front left corner
    bar = round_scale(0.6 * half, at_most=True)
    z0 = lo[2] if ground is None else ground
    start = np.array([lo[0] + 0.1 * half, lo[1] + 0.1 * half, z0])
    ax.plot(*np.stack([start, start + [bar, 0, 0]]).T, color="k", lw=3, zorder=1, gid="scale_bar")
    ax.text(*(start + [bar / 2, 0, 0.04 * half]), f"{bar:g} m", ha="center", va="bottom", fontsize=8, zorder=1,
            gid="scale_bar_label")
    for k, rail in enumerate(rails):
        ax.plot(*rail.T, color="0.25", lw=2, zorder=1, gid="rail", label="rail" if k == 0 else None)
    for k, tris in enumerate(carts):
        ax.add_collection3d(Poly3DCollection(tris, facecolors=[(0.55, 0.6, 0.68, 0.6)], linewidths=0, zorder=2,
                                             gid="cart", label="cart" if k == 0 else None))
    for i, par in enumerate(model.parents):
        a = X[par] if par >= 0 else np.zeros(3)
        ax.plot(*np.stack([a, X[i]]).T, color="tab:gray", lw=1, zorder=3, label="joint to joint" if i == 0 else None)
        ax.plot(*np.stack([X[i], C[i]]).T, color="tab:blue", lw=2, zorder=3,
                label="joint to centre of mass" if i == 0 else None)
    # the last link of each leaf: from its joint through its centre of mass and as far again
    children = {p for p in model.parents}
    for i in range(model.n):
        if i not in children:
            ax.plot(*np.stack([X[i], 2 * C[i] - X[i]]).T, color="tab:blue", lw=2, zorder=3)
    ax.scatter(*X.T, s=10, color="tab:gray", label="joints", zorder=3)
    ax.scatter(*C.T, s=8, color="tab:red", label="centres of mass", zorder=3)
    if model.n <= 12:
        for i, name in enumerate(model.joint_names):
            ax.text(*X[i], f" {name}", fontsize=7, color="0.25", zorder=5)
    for gid, origins, vectors, colour, label in drawn:
        ax.plot([], [], [], color=tuple(colour), lw=2, label=label)  # the scale in the legend, with or without arrows
        shafts, heads = arrow_segments(origins, vectors, np.linalg.norm(vectors, axis=-1) > 0, head)
        for shaft in shafts:
            ax.plot(*shaft.T, color=tuple(colour), lw=2, zorder=4, gid=gid)
        for line in heads:
            ax.plot(*line.T, color=tuple(colour), lw=1.5, zorder=4)
        if gid == "pushes":  # each labelled at its tail
            for p, origin in zip(pushes, origins):
                ax.text(*origin, f"{push_label(p)} at t = {float(p.time):.3g} s ", color=tuple(colour), fontsize=8,
                        ha="right", va="bottom", zorder=5, gid="push_label")
    ax.legend(fontsize=7, loc="upper left")
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect((1, 1, 1))  # equal axes: equal limits in a cube
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    ax.set_title(title or "configuration")
    fig.tight_layout()
    return fig


def plot_optimized(result, problem, path, title=""):
    """An optimised trajectory: joint positions at the configuration points and the controls."""
    plt = pyplot()
    tr = result.trajectory
    fig, axes = plt.subplots(1, 2, figsize=(11, 3.8))
    for j, name in enumerate(problem.model.joint_names):
        axes[0].plot(tr["t"], tr["q"][:, j], ".-", ms=3, lw=0.8, label=name)
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel("q")
    legend(axes[0])
    t = np.linspace(0, problem.T, 400)
    u = result.control_function()(t)
    for k, label in enumerate(control_labels(problem.model)):
        axes[1].plot(t, u[:, k], lw=1, label=label)
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("control")
    legend(axes[1])
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
