"""Plots of simulations (matplotlib, Agg backend)."""
from __future__ import annotations

import numpy as np


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


def plot_configuration(model, q, path, title=""):
    """The kinematic tree at q: joint origins joined parent to child, centres of mass as dots."""
    plt = pyplot()
    X = model.joint_placements(q)[:, :3, 3]
    C = model.body_poses(q)[:, :3, 3]
    fig = plt.figure(figsize=(6, 6))
    ax = fig.add_subplot(projection="3d")
    for i, par in enumerate(model.parents):
        a = X[par] if par >= 0 else np.zeros(3)
        ax.plot(*np.stack([a, X[i]]).T, color="tab:gray", lw=1)
        ax.plot(*np.stack([X[i], C[i]]).T, color="tab:blue", lw=2)
    # the last link of each leaf: from its joint through its centre of mass and as far again
    children = {p for p in model.parents}
    for i in range(model.n):
        if i not in children:
            ax.plot(*np.stack([X[i], 2 * C[i] - X[i]]).T, color="tab:blue", lw=2)
    ax.scatter(*C.T, s=8, color="tab:red")
    pts = np.vstack([X, C, np.zeros((1, 3))])
    mid, half = pts.mean(axis=0), max(np.ptp(pts, axis=0).max() / 2, 1e-3)
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.set_zlabel("z")
    ax.set_title(title or "configuration")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


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
    for k in range(problem.model.n_controls):
        axes[1].plot(t, u[:, k], lw=1, label=f"u[{k}]")
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("control")
    axes[1].legend(fontsize=8)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
