"""Saving and loading trajectories as ``.npz`` files (numpy only, no pickle).

A file holds the rollout's arrays (t, q, p, control points, multipliers), the solver statistics
per step (iterations, factorisations, residuals, status, the C++ loop's time) and what is needed
to use it again: the model's joint names, s and dt. ``load_trajectory`` checks them against an
Integrator when one is given (so that ``qdot`` and ``energy`` work on the loaded trajectory).
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any, Dict, Optional

import numpy as np

if TYPE_CHECKING:
    from .integrator import Integrator, Trajectory

FORMAT_VERSION = 1


def save_trajectory(trajectory: Trajectory, path: str | os.PathLike[str]) -> None:
    """Write ``trajectory`` (a hovi.Trajectory made by an Integrator) to ``path`` (.npz)."""
    integ = trajectory.integrator
    if integ is None:
        raise ValueError("this trajectory has no integrator: its joint names, s and dt are unknown")
    arrays: Dict[str, Any] = {
        "format_version": np.array(FORMAT_VERSION),
        "joint_names": np.array(integ.model.joint_names, dtype=str),
        "s": np.array(integ.s), "dt": np.array(integ.dt),
        "t": trajectory.t, "q": trajectory.q, "p": trajectory.p, "control_points": trajectory.control_points,
        "iterations": trajectory.iterations, "residuals": trajectory.residuals,
        "status": np.array(trajectory.status, dtype=str), "solve_seconds": np.array(trajectory.solve_seconds),
    }
    if trajectory.factorizations is not None:
        arrays["factorizations"] = trajectory.factorizations
    if trajectory.multipliers is not None:
        arrays["multipliers"] = trajectory.multipliers
    np.savez_compressed(path, **arrays)


def load_trajectory(path: str | os.PathLike[str], integrator: Optional[Integrator] = None) -> Trajectory:
    """Read a trajectory written by ``Trajectory.save``. With ``integrator``, its model's joint
    names, s and dt must match the file's (ValueError naming the difference otherwise) and it is
    attached to the trajectory. Arrays as saved: t (K+1,), q and p (K+1, n), control_points (K, s+1, n)."""
    from .integrator import Trajectory

    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as e:
        raise ValueError(f"{path}: not a trajectory file ({e})") from e
    with data:
        missing = {"format_version", "joint_names", "s", "dt", "t", "q", "p", "control_points"} - set(data.files)
        if missing:
            raise ValueError(f"{path}: not a hovi trajectory (missing {', '.join(sorted(missing))})")
        if int(data["format_version"]) > FORMAT_VERSION:
            raise ValueError(f"{path}: written by a newer hovi (format {int(data['format_version'])})")
        names, s, dt = [str(x) for x in data["joint_names"]], int(data["s"]), float(data["dt"])
        if integrator is not None:
            if list(integrator.model.joint_names) != names:
                raise ValueError(f"{path}: joint names {names} differ from the integrator's model "
                                 f"{list(integrator.model.joint_names)}")
            if integrator.s != s or integrator.dt != dt:
                raise ValueError(f"{path}: s = {s}, dt = {dt} differ from the integrator's s = {integrator.s}, "
                                 f"dt = {integrator.dt}")
        optional = {k: data[k] for k in ("factorizations", "multipliers") if k in data.files}
        traj = Trajectory(t=data["t"], q=data["q"], p=data["p"], control_points=data["control_points"],
                          iterations=data["iterations"], residuals=data["residuals"],
                          status=[str(x) for x in data["status"]], solve_seconds=float(data["solve_seconds"]),
                          integrator=integrator, **optional)
    return traj
