"""hovi.vis.plots: figures of simulations and optimisations as image files (matplotlib, Agg backend).

What ``hovi simulate`` and ``hovi optimize`` write (``energy_error.png``, ``contact_forces.png``,
``final_configuration.png``, ``optimize_NAME.png``); each function takes arrays or a result and a path and draws without a
window. Curves per joint carry the joint's name in a legend; a configuration in space is drawn with
equal axes (a metre is as long along x, y and z).
"""
from __future__ import annotations

import numpy as np


def control_labels(model) -> list:
    """A legend label per control: ``u[k]`` and, for an actuator on one joint, that joint's name."""
    actuation = np.asarray(model.actuation, dtype=float).reshape(model.n, -1)
    labels = []
    for k in range(model.n_controls):
        joints = np.flatnonzero(actuation[:, k]) if k < actuation.shape[1] else []
        labels.append(f"u[{k}] ({model.joint_names[joints[0]]})" if len(joints) == 1 else f"u[{k}]")
    return labels


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
    ax.legend(fontsize=7, ncol=2, loc="upper right")
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_configuration(model, q, path, title=""):
    """Write ``configuration_figure(model, q, title)`` to ``path``."""
    plt = pyplot()
    fig = configuration_figure(model, q, title)
    fig.savefig(path, dpi=120)
    plt.close(fig)


def configuration_figure(model, q, title=""):
    """The kinematic tree at q (n,) as a matplotlib figure: joint origins joined parent to child,
    centres of mass as dots, with equal axes, a legend, and the joints' names beside them (up to
    12 joints)."""
    plt = pyplot()
    X = model.joint_placements(q)[:, :3, 3]
    C = model.body_poses(q)[:, :3, 3]
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    for i, par in enumerate(model.parents):
        a = X[par] if par >= 0 else np.zeros(3)
        ax.plot(*np.stack([a, X[i]]).T, color="tab:gray", lw=1, label="joint to joint" if i == 0 else None)
        ax.plot(*np.stack([X[i], C[i]]).T, color="tab:blue", lw=2, label="joint to centre of mass" if i == 0 else None)
    # the last link of each leaf: from its joint through its centre of mass and as far again
    children = {p for p in model.parents}
    for i in range(model.n):
        if i not in children:
            ax.plot(*np.stack([X[i], 2 * C[i] - X[i]]).T, color="tab:blue", lw=2)
    ax.scatter(*X.T, s=10, color="tab:gray", label="joints")
    ax.scatter(*C.T, s=8, color="tab:red", label="centres of mass")
    if model.n <= 12:
        for i, name in enumerate(model.joint_names):
            ax.text(*X[i], f" {name}", fontsize=7, color="0.25")
    ax.legend(fontsize=7, loc="upper left")
    pts = np.vstack([X, C, np.zeros((1, 3))])
    mid, half = pts.mean(axis=0), max(np.ptp(pts, axis=0).max() / 2, 1e-3)
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
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
    axes[0].legend(fontsize=8)
    t = np.linspace(0, problem.T, 400)
    u = result.control_function()(t)
    for k, label in enumerate(control_labels(problem.model)):
        axes[1].plot(t, u[:, k], lw=1, label=label)
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("control")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
