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
import zipfile
import zlib
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Protocol, Tuple

import numpy as np
import numpy.typing as npt

from . import _core
from ._typing import BoolArray, FloatArray, IntArray

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
class ContactRecord:
    """The contacts of a rollout with contacts (``Integrator(..., contacts=...)``), per step k and
    contact c (in the order of the Contacts' points), as the contact step solves them
    (cpp/include/hovi/integrators/contact_solver.hpp): the impulses act at q^k and decide q^{k+1}."""
    impulses: FloatArray    # (K, C, 2 + d): the normal impulse λ (N s), friction impulses β_1..d, sliding γ (m)
    gaps: FloatArray        # (K, C): φ_c(q^{k+1}), the height of each point above the terrain (m)
    directions: FloatArray  # (d, 3): the friction directions D_i
    pivots: IntArray        # (attempted,) LCP pivots per step (0: no contact solve, or the guessed active set held)
    impact: Optional[FloatArray] = None  # (K,) θ of a step split at an impact at t^k + θ dt (its impulses act
                                         # there; Integrator locate_impacts), else 0
    step_momenta: Optional[FloatArray] = None  # (K+1, n): the momentum each step starts from, before its knot's
                                               # impulse: the state of the contact Jacobians and of feedback policies
                                               # (``p`` adds half the knot impulse for 0 < k < K)
    added_energy: Optional[FloatArray] = None  # (K,) J: the work of normal impulses that pushed their points up
                                               # (``Integrator.contact_work``); > 0 flags energy the contact added

    @property
    def normal(self) -> FloatArray:
        """(K, C) normal impulses λ (N s, >= 0)."""
        return self.impulses[..., 0]

    @property
    def friction(self) -> FloatArray:
        """(K, C, 3) world friction impulses sum_i β_i D_i (N s)."""
        d = len(self.directions)
        return np.asarray(self.impulses[..., 1:1 + d] @ self.directions, dtype=np.float64)

    @property
    def sliding(self) -> FloatArray:
        """(K, C) the sliding displacement γ of each point over the step (m; 0 when it sticks)."""
        return self.impulses[..., -1]

    @property
    def active(self) -> BoolArray:
        """(K, C) whether the contact pushed in step k (normal impulse > 0)."""
        return np.asarray(self.normal > 0)

    @property
    def world_impulses(self) -> FloatArray:
        """(K, C, 3) the total world impulse of each contact, λ e_z + friction (N s)."""
        out = self.friction.copy()
        out[..., 2] += self.normal
        return out


@dataclass
class StepInfo:
    """How the Newton solve of one step went (``Integrator.step``); ``control_points`` (s+1, n) holds
    q^{k,0..s} of the step and, for a constrained model, ``multipliers`` (s, n_constraints)
    λ^{k,0..s-1}."""
    status: str            # 'converged', 'max_iterations', 'line_search_failed', 'singular_jacobian', 'non_finite',
                           # 'continuation_stalled' (no step on the solution branch from q^k: it turns back before dt),
                           # 'lcp_failed' (a contact step), 'controller_failed' (an MPC solve from the state failed)
    converged: bool
    iterations: int        # Newton directions computed
    factorizations: int    # of them, those with a fresh Jacobian factorisation (the rest reused one)
    residual_evaluations: int
    residual: float        # ||r||_inf at exit
    control_points: Optional[FloatArray] = field(default=None, repr=False)  # (s+1, n), set by Integrator.step
    multipliers: Optional[FloatArray] = field(default=None, repr=False)     # (s, n_constraints), constrained models
    impulses: Optional[FloatArray] = field(default=None, repr=False)  # (C, 2 + d): with contacts, λ, β, γ per contact
    gaps: Optional[FloatArray] = field(default=None, repr=False)      # (C,): with contacts, φ_c(q_next)
    pivots: int = 0                                                   # with contacts: LCP pivots
    impact: float = 0.0                                               # with contacts: θ of a step split at an impact


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
    contact: Optional[ContactRecord] = None  # impulses and gaps of a rollout with contacts
    controls: Optional[FloatArray] = None  # (K, s+1, m): the controls of each step at its control points (a
                                           # rollout's, a closed loop's applied ones, an optimiser's)
    solve_seconds: float = 0.0  # time spent in the C++ loop
    discretization: Optional[Discretization] = field(default=None, repr=False)

    @property
    def steps(self) -> int:
        """Number of steps K taken (len(t) - 1)."""
        return len(self.t) - 1

    @property
    def converged(self) -> bool:
        """Whether every attempted step converged: solved by the integrator ('converged') or by a
        trajectory optimiser ('optimized': the DEL equations are its constraints)."""
        return all(s in ("converged", "optimized") for s in self.status)

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
    """Write ``trajectory`` (a hovi.Trajectory made by an Integrator) to ``path`` (.npz). ValueError,
    and nothing written, if its arrays do not fit its model, s and dt (the checks of ``load_trajectory``)."""
    if not isinstance(trajectory, Trajectory):
        raise TypeError(f"trajectory must be a hovi.Trajectory, got {type(trajectory).__name__}")
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
    if trajectory.controls is not None:
        arrays["controls"] = trajectory.controls
    if trajectory.contact is not None:
        c = trajectory.contact
        arrays.update(contact_impulses=c.impulses, contact_gaps=c.gaps, contact_directions=c.directions,
                      contact_pivots=c.pivots)
        if c.impact is not None:
            arrays["contact_impact"] = c.impact
        if c.step_momenta is not None:
            arrays["contact_step_momenta"] = c.step_momenta
    try:
        arrays = check_arrays(arrays, d.model.n_constraints)
    except ValueError as e:
        raise ValueError(f"cannot save this trajectory (nothing written): {e}") from None
    np.savez_compressed(path, **arrays)


REQUIRED = ("format_version", "joint_names", "s", "dt", "t", "q", "p", "control_points", "iterations", "residuals",
            "status", "solve_seconds")
OPTIONAL = ("factorizations", "multipliers", "controls", "contact_impact", "contact_step_momenta")
CONTACT = ("contact_impulses", "contact_gaps", "contact_directions", "contact_pivots")  # all or none


def _scalar(a: np.ndarray, name: str, kinds: str, what: str) -> np.ndarray:
    if a.shape != () or a.dtype.kind not in kinds:
        raise ValueError(f"{name} must be {what}, got {a.dtype} of shape {a.shape}")
    return a


def _numbers(value: Any, name: str, shape: Tuple[int, ...], kinds: str = "iuf", finite: bool = True) -> np.ndarray:
    a: np.ndarray = np.asarray(value)
    if a.dtype.kind not in kinds:
        raise ValueError(f"{name} must be an array of {'integers' if kinds == 'iu' else 'real numbers'}, got {a.dtype}")
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {a.shape}")
    if finite and a.dtype.kind == "f" and not np.all(np.isfinite(a)):
        raise ValueError(f"{name} holds NaN or infinity (at index {tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])})")
    return a


def check_arrays(arrays: Dict[str, Any], n_constraints: Optional[int] = None) -> Dict[str, Any]:
    """The arrays of a trajectory file (as ``save_trajectory`` writes them), checked against each
    other: format_version an integer 1..FORMAT_VERSION, n joint names, s >= 1, dt > 0, t (K+1,) = k dt,
    q and p (K+1, n), control_points (K, s+1, n) starting at q^k and ending at q^{k+1}, per attempted
    step (K, or K+1 when the last step failed) iterations, residuals, status and factorizations,
    multipliers (K, s, n_constraints) (``n_constraints`` of the model when known; they must be given
    exactly when it is > 0), solve_seconds >= 0. Returns the arrays as numpy arrays; ValueError
    naming the array and what is wrong."""
    missing = [k for k in REQUIRED if k not in arrays]
    if missing:
        raise ValueError(f"not a hovi trajectory (missing {', '.join(missing)})")
    unknown = sorted(set(arrays) - set(REQUIRED) - set(OPTIONAL) - set(CONTACT))
    if unknown:
        raise ValueError(f"unknown entries {unknown} (a trajectory file holds {', '.join(REQUIRED + OPTIONAL + CONTACT)})")
    a: Dict[str, Any] = {k: np.asarray(v) for k, v in arrays.items()}
    version = a["format_version"]
    if version.shape != () or version.dtype.kind not in "iu" or not 1 <= int(version) <= FORMAT_VERSION:
        if version.shape == () and version.dtype.kind in "iu" and int(version) > FORMAT_VERSION:
            raise ValueError(f"written by a newer hovi (format_version {int(version)}; this hovi reads "
                             f"format_version 1..{FORMAT_VERSION})")
        raise ValueError(f"format_version must be an integer from 1 to {FORMAT_VERSION}, got "
                         f"{version.tolist() if version.size < 10 else version.dtype} ({version.dtype})")
    names = a["joint_names"]
    if names.ndim != 1 or names.dtype.kind != "U" or len(names) == 0:
        raise ValueError(f"joint_names must be a non-empty 1-D array of strings, got {names.dtype} of shape {names.shape}")
    n = len(names)
    s = int(_scalar(a["s"], "s", "iu", "an integer"))
    if s < 1:
        raise ValueError(f"s must be >= 1, got {s}")
    dt = float(_scalar(a["dt"], "dt", "f", "a real number"))
    if not (np.isfinite(dt) and dt > 0):
        raise ValueError(f"dt must be positive and finite, got {dt}")
    t = a["t"]
    if t.ndim != 1 or len(t) == 0:
        raise ValueError(f"t must be a non-empty 1-D array (K+1,), got shape {t.shape}")
    K = len(t) - 1
    t = _numbers(t, "t", (K + 1,))
    if not np.allclose(t, np.arange(K + 1) * dt, rtol=1e-12, atol=1e-12 * dt):
        k = int(np.argmax(np.abs(t - np.arange(K + 1) * dt)))
        raise ValueError(f"t must be k dt (dt = {dt}), got t[{k}] = {t[k]}")
    # a free base: q has n + 1 columns (its quaternion) and each step's control points are in its own chart
    free = np.ndim(a["q"]) == 2 and np.shape(a["q"])[1] == n + 1
    q = _numbers(a["q"], "q", (K + 1, n + free))
    _numbers(a["p"], "p", (K + 1, n))
    cp = _numbers(a["control_points"], "control_points", (K, s + 1, n))
    if K and not free and not (np.allclose(cp[:, 0], q[:-1], rtol=1e-12, atol=1e-12)
                  and np.allclose(cp[:, -1], q[1:], rtol=1e-12, atol=1e-12)):
        raise ValueError("control_points must start at q^k and end at q^{k+1} in every step k, they do not")
    status = a["status"]
    if status.ndim != 1 or (status.dtype.kind != "U" and len(status)):
        raise ValueError(f"status must be a 1-D array of strings, got {status.dtype} of shape {status.shape}")
    attempted = len(status)
    if attempted not in (K, K + 1):
        raise ValueError(f"status must have one entry per attempted step ({K} or {K + 1} for K = {K} steps), "
                         f"got {attempted}")
    if attempted == K + 1 and str(status[-1]) == "converged":
        raise ValueError(f"status has {K + 1} entries for {K} steps but its last step converged")
    its = _numbers(a["iterations"], "iterations", (attempted,), "iu")
    if np.any(its < 0):
        raise ValueError("iterations must be >= 0")
    _numbers(a["residuals"], "residuals", (attempted,), finite=False)
    if "factorizations" in a:
        fac = _numbers(a["factorizations"], "factorizations", (attempted,), "iu")
        if np.any(fac < 0):
            raise ValueError("factorizations must be >= 0")
    seconds = float(_scalar(a["solve_seconds"], "solve_seconds", "iuf", "a real number"))
    if not (np.isfinite(seconds) and seconds >= 0):
        raise ValueError(f"solve_seconds must be finite and >= 0, got {seconds}")
    if "multipliers" in a:
        mult = a["multipliers"]
        if n_constraints == 0:
            raise ValueError("multipliers given for a model without constraints")
        if mult.ndim != 3:
            raise ValueError(f"multipliers must be a 3-D array (K, s, n_constraints) with K = {K}, s = {s}, "
                             f"got shape {mult.shape}")
        _numbers(mult, "multipliers", (K, s, mult.shape[2] if n_constraints is None else n_constraints))
    elif n_constraints:
        raise ValueError(f"multipliers (K, s, {n_constraints}) are missing for a model with {n_constraints} constraints")
    if "controls" in a:
        u = a["controls"]
        if u.ndim != 3 or u.shape[:2] != (K, s + 1):
            raise ValueError(f"controls must have shape (K, s+1, m) with K = {K}, s = {s}, got {u.shape}")
        _numbers(u, "controls", u.shape)
    given = [k for k in CONTACT if k in a]
    if given and len(given) != len(CONTACT):
        raise ValueError(f"a trajectory with contacts holds all of {', '.join(CONTACT)}; got only {', '.join(given)}")
    if given:
        D = a["contact_directions"]
        if D.ndim != 2 or D.shape[1] != 3 or len(D) == 0:
            raise ValueError(f"contact_directions must have shape (d, 3), got {D.shape}")
        _numbers(D, "contact_directions", D.shape)
        gaps = a["contact_gaps"]
        if gaps.ndim != 2 or gaps.shape[1] == 0:
            raise ValueError(f"contact_gaps must have shape (K, C) with K = {K}, got {gaps.shape}")
        C = gaps.shape[1]
        _numbers(gaps, "contact_gaps", (K, C))
        z = _numbers(a["contact_impulses"], "contact_impulses", (K, C, len(D) + 2))
        if K and z.min() < -1e-9 * (1 + np.abs(z).max()):  # λ, β, γ >= 0 (the solver's to round-off)
            step, contact, entry = (int(x) for x in np.unravel_index(int(np.argmin(z)), z.shape))
            what = ("normal impulse" if entry == 0 else "slack" if entry == len(D) + 1
                    else f"friction impulse {entry - 1}")
            raise ValueError(f"contact_impulses must be >= 0 (normal and friction impulses, slacks), got the "
                             f"{what} of contact {contact} at step {step} = {z[step, contact, entry]:.6g}")
        _numbers(a["contact_pivots"], "contact_pivots", (attempted,), "iu")
    if "contact_impact" in a:
        if not given:
            raise ValueError("contact_impact given without the other contact arrays")
        theta = _numbers(a["contact_impact"], "contact_impact", (K,))
        if np.any((theta < 0) | (theta >= 1)):
            raise ValueError("contact_impact must lie in [0, 1)")
    if "contact_step_momenta" in a:
        if not given:
            raise ValueError("contact_step_momenta given without the other contact arrays")
        _numbers(a["contact_step_momenta"], "contact_step_momenta", (K + 1, a["p"].shape[1]))
    return a


def load_trajectory(path: str | os.PathLike[str], integrator: Optional[HasDiscretization] = None) -> Trajectory:
    """Read a trajectory written by ``Trajectory.save``. With ``integrator`` (a hovi.Integrator),
    its model's joint names, s and dt must match the file's (ValueError naming the difference
    otherwise) and its discretization is attached to the trajectory. Arrays as saved: t (K+1,),
    q and p (K+1, n), control_points (K, s+1, n).

    Every array is checked against the others, the file's s and dt and the integrator's model
    (``check_arrays``): a file whose arrays do not fit is refused with a ValueError naming the
    array. FileNotFoundError for a missing file; ValueError for an empty, damaged or truncated
    file, one that is not a trajectory, and a format_version that is missing, not an integer or
    newer than this hovi's."""
    d = None
    if integrator is not None:
        d = getattr(integrator, "discretization", None)
        if not isinstance(d, Discretization):
            raise TypeError(f"integrator must be a hovi.Integrator (or None), got {type(integrator).__name__}")
    where = os.fspath(path) if isinstance(path, (str, os.PathLike)) else repr(path)
    if isinstance(path, (str, os.PathLike)):
        if not os.path.exists(path):
            raise FileNotFoundError(f"no trajectory file at {where}")
        if os.path.isdir(path):
            raise ValueError(f"{where}: is a directory, not a trajectory file (.npz)")
        if os.path.getsize(path) == 0:
            raise ValueError(f"{where}: the file is empty (0 bytes), not a trajectory file (.npz)")
    try:
        data = np.load(path, allow_pickle=False)
    except FileNotFoundError:
        raise
    except (OSError, ValueError, EOFError, MemoryError, NotImplementedError, zipfile.BadZipFile, zlib.error) as e:
        raise ValueError(f"{where}: not a trajectory file ({type(e).__name__}: {e})") from e
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise ValueError(f"{where}: not a trajectory file (a single array, .npy, not an .npz archive)")
    with data:
        arrays = {}
        for k in data.files:
            try:
                arrays[k] = data[k]
            except (OSError, ValueError, EOFError, KeyError, MemoryError, NotImplementedError, zipfile.BadZipFile,
                    zlib.error) as e:
                raise ValueError(f"{where}: entry {k!r} cannot be read (a damaged or truncated file? {e})") from e
    try:
        check_arrays(arrays, None if d is None else d.model.n_constraints)
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None
    names, s, dt = [str(x) for x in arrays["joint_names"]], int(arrays["s"]), float(arrays["dt"])
    if d is not None:
        if list(d.model.joint_names) != names:
            raise ValueError(f"{where}: joint names {names} differ from the integrator's model "
                             f"{list(d.model.joint_names)}")
        if d.s != s or d.dt != dt:
            raise ValueError(f"{where}: s = {s}, dt = {dt} differ from the integrator's s = {d.s}, dt = {d.dt}")
    optional: Dict[str, Any] = {k: arrays[k] for k in OPTIONAL if k in arrays and not k.startswith("contact_")}
    if "contact_impulses" in arrays:
        optional["contact"] = ContactRecord(arrays["contact_impulses"], arrays["contact_gaps"],
                                            arrays["contact_directions"], arrays["contact_pivots"],
                                            arrays.get("contact_impact"), arrays.get("contact_step_momenta"))
    return Trajectory(t=arrays["t"], q=arrays["q"], p=arrays["p"], control_points=arrays["control_points"],
                      iterations=arrays["iterations"], residuals=arrays["residuals"],
                      status=[str(x) for x in arrays["status"]], solve_seconds=float(arrays["solve_seconds"]),
                      discretization=d, **optional)
