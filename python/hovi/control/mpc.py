"""Model-predictive control with the FDDP solver on the VI (cpp/include/hovi/control/mpc.hpp): a
held-control trajopt Problem is the controller's horizon; in the plant's C++ step loop FDDP is
re-solved from the plant's state every ``period`` steps, warm-started from its shifted last plan."""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from typing import Any, Optional, Sequence

import numpy as np
import numpy.typing as npt

from .. import _core
from .._checks import real_array, real_number, whole_number
from .._typing import FloatArray, IntArray
from ..integrator import Integrator, check_trajectory_memory
from ..trajectory import Trajectory
from ..trajopt.costs import CallbackCost
from ..trajopt.problem import Problem
from ..trajopt.solvers.fddp import FDDP
from ..trajopt.variational import VI
from .closed_loop import Push, failure_of, push_list, run_steps


@dataclass
class MpcRun:
    """An MPC run: the plant's trajectory, the controls applied (K, s+1, m), and per solve its time (s),
    FDDP iterations and whether it converged. ``failure``: None when every step ran, else which step
    ended the run and why: the plant failed that step (``u`` then has its controls last), or the
    solve there raised."""
    trajectory: Trajectory
    u: FloatArray
    solve_seconds: FloatArray
    iterations: IntArray
    converged: IntArray
    period: int
    dt: float
    failure: Optional[str] = None

    @property
    def real_time_factor(self) -> float:
        """Simulated time over the time spent solving: > 1 means the solves keep up with real time."""
        total = float(self.solve_seconds.sum())
        return float("inf") if total == 0 else self.trajectory.steps * self.dt / total

    @property
    def worst_solve_seconds(self) -> float:
        """The longest solve (s): it must stay below the control period period * dt for real time."""
        return float(self.solve_seconds.max()) if len(self.solve_seconds) else 0.0

    def __repr__(self) -> str:
        how = "completed" if self.failure is None else f"FAILED at {self.failure}"
        return f"<MpcRun {self.trajectory.steps} steps, {len(self.solve_seconds)} solves, {how}>"


class MPC:
    """Receding-horizon FDDP on ``problem`` (held controls, FDDP's costs and bounds; its N steps of
    T / N are the horizon; its initial state is replaced by the plant's at every solve; time-varying
    cost references move on with the plant's time), with the VI of order 2s as the model. ``period``:
    plant steps per solve (the plan's feedback policy runs in between); ``max_iterations`` and ``tol``
    per solve; ``contacts`` and ``smoothing``: plan through contact (FDDP's, s = 1). CallbackCosts
    are not taken (the loop runs in C++)."""

    def __init__(self, problem: Problem, s: int = 1, *, period: int = 1, max_iterations: int = 10, tol: float = 1e-8,
                 contacts: Any = None, smoothing: float = 0.0):
        if not isinstance(problem, Problem):
            raise TypeError(f"problem must be a hovi.trajopt.Problem, got {type(problem).__name__}")
        if any(isinstance(c, CallbackCost) for c in problem.costs):
            raise ValueError("MPC does not take a CallbackCost (its loop runs in C++ without Python): express the cost "
                             "as ControlEffort, StateTracking or TerminalCost")
        self.problem, self.method = problem, VI(whole_number(s, "s", minimum=1))
        self.period = whole_number(period, "period", minimum=1)
        if self.period > problem.N:
            raise ValueError(f"period ({self.period}) must not exceed the horizon N = {problem.N}")
        self.max_iterations = whole_number(max_iterations, "max_iterations", minimum=1)
        self.tol = real_number(tol, "tol", minimum=0.0, strict_minimum=True)
        self.transcription = self.method.transcribe(problem)
        self._solver = FDDP(self.max_iterations, self.tol, contacts=contacts, smoothing=smoothing)
        self._shooting = self._solver.shooting_problem(problem, self.transcription)

    @property
    def dt(self) -> float:
        """The control step T / N (the plant's dt must be this)."""
        return self.problem.dt

    def run(self, plant: Integrator, q0: npt.ArrayLike, steps: int, *, qdot0: Optional[npt.ArrayLike] = None,
            pushes: Sequence[Push] = (), warm_start: Optional[npt.ArrayLike] = None) -> MpcRun:
        """``steps`` >= 1 steps of ``plant`` (an Integrator with dt = T / N; another model, order or
        contacts allowed) from q0 (n,) with qdot0 (n,) (default rest) under MPC, with ``pushes`` (a list
        of Push), all in C++. warm_start: controls (N, m) for the first solve (default zeros).

        A run that cannot go on ends there, flagged (``MpcRun.failure``) with a RuntimeWarning: when
        the plant fails a step, and when a solve fails from the plant's state (e.g. FDDP's first
        rollout from it, after a push): the trajectory's last status is then 'controller_failed'."""
        if not isinstance(plant, Integrator):
            raise TypeError(f"plant must be a hovi.Integrator, got {type(plant).__name__}")
        if abs(plant.dt - self.dt) > 1e-12 * self.dt:
            raise ValueError(f"the plant's dt ({plant.dt:g}) must be the controller's T / N = {self.dt:g}")
        n, m, N = self.problem.model.n, self.problem.model.n_controls, self.problem.N
        if plant.n != n or plant.model.n_controls != m:
            raise ValueError(f"the plant (n = {plant.n}, m = {plant.model.n_controls}) must have the controller "
                             f"model's n = {n} and m = {m}")
        steps = run_steps(steps)
        check_trajectory_memory(steps, plant.s, n)
        q0 = real_array(q0, "q0", (n,))
        plant.check_start(q0, "q0")
        p0 = plant.momentum(q0, np.zeros(n) if qdot0 is None else real_array(qdot0, "qdot0", (n,)))
        warm = None if warm_start is None else real_array(warm_start, "warm_start", (N, m))
        knots = [[k for push in push_list(pushes) for k in push.knots(plant.model, plant.dt, steps)]]

        res = _core.control.mpc(plant.core, self._shooting, q0, p0, steps, self.period, self.max_iterations, self.tol,
                                knots, warm)
        failure = None
        if res["solve_failure"] is not None:  # the solve from the plant's state failed: the C++ loop ended there
            k = int(res["steps"])
            failure = (f"step {k} of {steps} (t = {k * plant.dt:.6g} s): the FDDP solve from the plant's state "
                       f"failed: {res['solve_failure']}")
        traj = plant.trajectory_of([res])
        failure = failure or failure_of(traj, plant, steps)
        if failure is not None:
            warnings.warn(f"the MPC run ended early, at {failure}; see MpcRun.failure", RuntimeWarning, stacklevel=2)
        controls = res.get("controls", np.zeros((0, (plant.s + 1) * m)))  # none when no step ran
        if res["solve_failure"] is not None:  # the step without controls is no step
            controls = controls[:int(res["steps"])]
        return MpcRun(trajectory=traj, u=controls.reshape(-1, plant.s + 1, m), solve_seconds=res["solve_seconds"],
                      iterations=res["solve_iterations"], converged=res["solve_converged"], period=self.period,
                      dt=self.dt, failure=failure)
