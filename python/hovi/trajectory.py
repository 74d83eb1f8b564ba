"""What a simulation produces, and its file format: ``StepInfo`` (one step's solve), ``Trajectory``
(a rollout), the ``Discretization`` they were computed with (the model, s and dt, and the velocity
and energy of a state), and trajectories saved as ``.npz`` files (numpy only, no pickle).

This module knows nothing of the Integrator: the Integrator makes these objects and hands each
trajectory its Discretization, which is all ``qdot``, ``energy`` and ``save`` need.

A file holds the rollout's arrays (t, q, p, control points, multipliers), the solver statistics
per step (iterations, factorisations, residuals, status, the C++ loop's time) and what is needed
to use it again: the model's joint names, s and dt. ``load_trajectory`` checks them against an
Integrator when one is given (so that ``qdot`` and ``energy`` work on the loaded trajectory).
"""
from __future__ import annotations

import os
import warnings
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Protocol

import numpy as np
import numpy.typing as npt

from . import _core
from ._typing import FloatArray, IntArray

FORMAT_VERSION = 1


class Discretization:
    """The model and the discretisation (s, dt) a trajectory was computed with, and what a
    trajectory evaluates with them: ``velocity(q, p)`` and ``energies(q, p)``. Made by an Integrator
    (``Integrator.discretization``) on that integrator's copy of the model, so a change to the model
    afterwards raises hovi.ModelError here as it does in the integrator. Pickles as the model and
    the integrator's options."""

    def __init__(self, model: _core.Model, options: Dict[str, Any], core: Optional[_core.Integrator] = None) -> None:
        self.model = model
        self._options = dict(options)
        self._core = core if core is not None else _core.Integrator(model, **self._options)

    @property
    def s(self) -> int:
        """Number of Lobatto intervals of a step; s+1 control points."""
        return int(self._options["s"])

    @property
    def dt(self) -> float:
        """The time step (s)."""
        return float(self._options["dt"])

    def velocity(self, q: npt.ArrayLike, p: npt.ArrayLike) -> FloatArray:
        """q, p (n,): the velocity q̇ (n,) of the discrete momentum p (as ``Integrator.velocity``)."""
        return self._core.velocity(q, p)

    def energies(self, q: npt.ArrayLike, p: npt.ArrayLike) -> FloatArray:
        """K + V (K,) of every row of q, p (arrays (K, n)), as ``Integrator.energies``."""
        return self._core.energies(q, p)

    def __getstate__(self) -> Dict[str, Any]:
        self._core.n_constraints  # any call of the core raises ModelError once the model has changed
        return {"model": self.model, "options": self._options}

    def __setstate__(self, state: Dict[str, Any]) -> None:
        self.__init__(state["model"], state["options"])  # type: ignore[misc]

    def __repr__(self) -> str:
        return f"<hovi.Discretization s={self.s}, dt={self.dt}, n={self.model.n}>"


class HasDiscretization(Protocol):
    """What ``load_trajectory`` needs of an Integrator: its ``discretization``."""

    @property
    def discretization(self) -> Discretization: ...


@dataclass
class StepInfo:
    """How the Newton solve of one step went (``Integrator.step``); ``control_points`` (s+1, n) holds
    q^{k,0..s} of the step and, for a constrained model, ``multipliers`` (s, n_constraints)
    λ^{k,0..s-1}."""
    status: str            # 'converged', 'max_iterations', 'line_search_failed', 'singular_jacobian', 'non_finite',
                           # 'continuation_stalled' (no step on the solution branch from q^k: it turns back before dt)
    converged: bool
    iterations: int        # Newton directions computed
    factorizations: int    # of them, those with a fresh Jacobian factorisation (the rest reused one)
    residual_evaluations: int
    residual: float        # ||r||_inf at exit
    control_points: Optional[FloatArray] = field(default=None, repr=False)  # (s+1, n), set by Integrator.step
    multipliers: Optional[FloatArray] = field(default=None, repr=False)     # (s, n_constraints), constrained models


@dataclass
class Trajectory:
    """A rollout of K steps. Arrays are indexed by step k; t[k] = k dt: t (K+1,), q and p (K+1, n),
    control_points (K, s+1, n), per attempted step iterations, residuals, factorizations and
    status, multipliers (K, s, n_constraints) of a constrained model. ``discretization`` (the model,
    s and dt it was computed with; set by the Integrator) is what ``qdot``, ``energy`` and ``save``
    need."""
    t: FloatArray               # (K+1,)
    q: FloatArray               # (K+1, n) configurations q^k
    p: FloatArray               # (K+1, n) discrete momenta p^k
    control_points: FloatArray  # (K, s+1, n): q^{k,0..s}
    iterations: IntArray        # (attempted,) Newton iterations per step
    residuals: FloatArray       # (attempted,) final ||r||_inf per step
    factorizations: Optional[IntArray] = None  # (attempted,) Jacobian factorisations per step
    status: List[str] = field(default_factory=list)
    multipliers: Optional[FloatArray] = None  # (K, s, n_constraints): λ^{k,0..s-1} of constrained steps
    solve_seconds: float = 0.0  # time spent in the C++ loop
    discretization: Optional[Discretization] = field(default=None, repr=False)

    @property
    def steps(self) -> int:
        """Number of steps K taken (len(t) - 1)."""
        return len(self.t) - 1

    @property
    def converged(self) -> bool:
        """Whether every attempted step converged."""
        return all(s == "converged" for s in self.status)

    @property
    def integrator(self) -> Optional[Discretization]:
        """Deprecated: ``discretization`` (the model, s, dt, ``velocity`` and ``energies``)."""
        warnings.warn("Trajectory.integrator is deprecated: use Trajectory.discretization (the model, s, dt, "
                      "velocity and energies)", DeprecationWarning, stacklevel=2)
        return self.discretization

    def _discretization(self) -> Discretization:
        if self.discretization is None:
            raise ValueError("this trajectory has no integrator (load it with hovi.load_trajectory(path, integrator))")
        return self.discretization

    @property
    def configuration_points(self) -> FloatArray:
        """(K s + 1, n): the configuration at every control point in time order, q^{k,0..s-1} of
        each step and then q^K (each shared end point once): the layout of a VI transcription's
        configuration variables."""
        K, S1, n = self.control_points.shape
        return np.vstack([self.control_points[:, :S1 - 1, :].reshape(K * (S1 - 1), n), self.q[-1:]])

    @property
    def qdot(self) -> FloatArray:
        """(K+1, n) velocities q̇^k read back from (q^k, p^k) by ``Integrator.velocity`` (M^{-1} p,
        projected onto Dh(q) q̇ = 0 for a constrained model)."""
        d = self._discretization()
        return np.array([d.velocity(q, p) for q, p in zip(self.q, self.p)])

    @property
    def energy(self) -> FloatArray:
        """(K+1,) total energy K + V at every step, with q̇ as in ``qdot``."""
        return self._discretization().energies(self.q, self.p)

    def save(self, path: str | os.PathLike[str]) -> None:
        """Write to ``path`` (.npz): the arrays, solver statistics, joint names, s and dt
        (``hovi.load_trajectory`` reads it back)."""
        save_trajectory(self, path)


def save_trajectory(trajectory: Trajectory, path: str | os.PathLike[str]) -> None:
    """Write ``trajectory`` (a hovi.Trajectory made by an Integrator) to ``path`` (.npz)."""
    d = trajectory.discretization
    if d is None:
        raise ValueError("this trajectory has no integrator: its joint names, s and dt are unknown")
    arrays: Dict[str, Any] = {
        "format_version": np.array(FORMAT_VERSION),
        "joint_names": np.array(d.model.joint_names, dtype=str),
        "s": np.array(d.s), "dt": np.array(d.dt),
        "t": trajectory.t, "q": trajectory.q, "p": trajectory.p, "control_points": trajectory.control_points,
        "iterations": trajectory.iterations, "residuals": trajectory.residuals,
        "status": np.array(trajectory.status, dtype=str), "solve_seconds": np.array(trajectory.solve_seconds),
    }
    if trajectory.factorizations is not None:
        arrays["factorizations"] = trajectory.factorizations
    if trajectory.multipliers is not None:
        arrays["multipliers"] = trajectory.multipliers
    np.savez_compressed(path, **arrays)


def load_trajectory(path: str | os.PathLike[str], integrator: Optional[HasDiscretization] = None) -> Trajectory:
    """Read a trajectory written by ``Trajectory.save``. With ``integrator`` (a hovi.Integrator),
    its model's joint names, s and dt must match the file's (ValueError naming the difference
    otherwise) and its discretization is attached to the trajectory. Arrays as saved: t (K+1,),
    q and p (K+1, n), control_points (K, s+1, n)."""
    d = None if integrator is None else integrator.discretization
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
        if d is not None:
            if list(d.model.joint_names) != names:
                raise ValueError(f"{path}: joint names {names} differ from the integrator's model "
                                 f"{list(d.model.joint_names)}")
            if d.s != s or d.dt != dt:
                raise ValueError(f"{path}: s = {s}, dt = {dt} differ from the integrator's s = {d.s}, dt = {d.dt}")
        optional = {k: data[k] for k in ("factorizations", "multipliers") if k in data.files}
        traj = Trajectory(t=data["t"], q=data["q"], p=data["p"], control_points=data["control_points"],
                          iterations=data["iterations"], residuals=data["residuals"],
                          status=[str(x) for x in data["status"]], solve_seconds=float(data["solve_seconds"]),
                          discretization=d, **optional)
    return traj
