"""Running a robot example and writing what it produced: the solved trajectory (npz), the solver's
statistics and feasibility figures (JSON), plots of joint angles, torques and contact forces (PNG),
and an animation (standalone HTML and MP4); the optimised controls replayed with the integrator
give the drift from the optimised states and the energy along the motion."""
from __future__ import annotations

import json
import os
import time
from typing import Any, Dict, Optional, Tuple

import numpy as np

from ... import trajopt
from ...control import Push
from ...trajopt import Result
from ...trajopt.variational import VariationalTranscription
from ...trajopt.transcriptions import from_name
from .contact_figures import between_knot_text
from .contact_replay import simulated_figures, simulated_text
from .example import Example


def ipopt_totals(result: Result) -> Tuple[int, float]:
    """(iterations, seconds in IPOPT) of the whole solve: for a contact-implicit one, of all its
    relaxed and exact solves; with order continuation, its first stage's iterations and time too."""
    if result.contact:
        return int(result.contact["iterations"]), float(result.contact["wall_seconds"])
    first = result.solver.get("continuation", {})
    return (int(result.iterations) + int(first.get("iterations", 0)),
            float(result.wall_seconds) + float(first.get("seconds", 0.0)))


REPLAY_TOLERANCE = 1e-6  # m or rad: a stage is reproduced when the integrator's step lands this close to q^{k+1}


def replay_figures(example: Example, result: Result) -> Dict[str, Any]:
    """The optimised motion checked with the integrator. Each stage's configuration points, momentum,
    controls and contact forces put into the integrator's own DEL equations (Algorithm 1): the
    largest residual |r^{k,a}| and |p^{k+1} - p^{k+1}_optimised| (how exactly each stage is a step of
    the integrator). Each stage stepped from its optimised (q^k, p^k) with its optimised controls
    and contact forces by the integrator's Newton solve from its own start (what a simulator would
    do): the largest distance of the step's end from q^{k+1}, and how many stages land more than
    REPLAY_TOLERANCE away (with a small residual: on a coarse grid the DEL equations can have more
    than one root, and Newton found another one) or fail to converge; the stages reproduced
    ('replay_stages_reproduced' of 'replay_stages', to 'replay_reproduced_to') and the worst stage
    ('replay_worst_stage', 1-based, its coordinate 'replay_worst_joint' and 'replay_worst_unit').
    The whole horizon from the start (open loop: a robot balancing on prescribed contact forces has
    no feedback, so its drift shows how fast errors grow); the robot's energy (kinetic + potential +
    springs) along the optimised motion, which the actuators and contacts change."""
    tr, tc = result.trajectory, result.transcription
    knots, P, U = tr["q"][::tc.s], tr["p"], tc.stage_controls(result.x)
    integ, model = tc.integrator, example.problem.model
    residual, drift, elsewhere, failed, worst = 0.0, [], 0, 0, (0.0, 0, 0)
    for k in range(len(knots) - 1):
        points = tr["q"][k * tc.s:(k + 1) * tc.s + 1]
        if tr.get("multipliers") is None:
            r, p_next = integ.del_residual(points, P[k], U[k])
        else:                                                  # r includes Dh^T λ; h(q^{k,a}) = 0 too
            r, h, p_next = integ.constrained_residual(points, tr["multipliers"][k], P[k], U[k])
            r = np.concatenate([r.ravel(), h.ravel()])
        residual = max(residual, float(np.abs(r).max()), float(np.abs(p_next - P[k + 1]).max()))
        q_next, _, info = integ.step(knots[k], P[k], U[k], raise_on_failure=False)
        d = np.abs(q_next - knots[k + 1])
        drift.append(float(d.max()) if info.converged and np.all(np.isfinite(d)) else np.inf)
        failed += not info.converged
        elsewhere += bool(info.converged and drift[-1] > REPLAY_TOLERANCE)
        if info.converged and np.isfinite(drift[-1]) and drift[-1] > worst[0]:
            worst = (drift[-1], k, int(np.argmax(d)))
    drift_arr = np.array(drift)
    reproduced = drift_arr <= REPLAY_TOLERANCE
    replay = result.replay()
    steps = min(replay.steps, len(knots) - 1)
    energy = np.array([model.energy(q, integ.velocity(q, p)) for q, p in zip(knots, P)])
    names, types = list(model.joint_names), list(model.joint_types)
    return {"replay_stage_residual": residual, "replay_one_step_drift": float(drift_arr.max()),
            "replay_steps_elsewhere": int(elsewhere), "replay_failed_steps": int(failed),
            "replay_stages": len(drift), "replay_stages_reproduced": int(reproduced.sum()),
            "replay_reproduced_to": float(drift_arr[reproduced].max()) if reproduced.any() else float("nan"),
            "replay_worst_stage": worst[1] + 1, "replay_worst_drift": worst[0], "replay_worst_joint": names[worst[2]],
            "replay_worst_unit": "m" if types[worst[2]] == "prismatic" else "rad",
            "replay_failed_stages": [k + 1 for k, d in enumerate(drift) if not np.isfinite(d)],
            "replay_elsewhere_stages": [k + 1 for k, d in enumerate(drift) if np.isfinite(d) and d > REPLAY_TOLERANCE],
            "replay_open_loop_drift": float(np.abs(replay.q[:steps + 1] - knots[:steps + 1]).max()),
            "replay_open_loop_steps": int(replay.steps), "energy_start": float(energy[0]),
            "energy_end": float(energy[-1]), "energy_min": float(energy.min()), "energy_max": float(energy.max())}


def replay_failures(replay: Dict[str, Any]) -> list:
    """The replay's verdict as failure sentences (empty: every stage reproduced): a solution is only
    feasible when stepping each stage's optimised state, controls and contact forces through the
    integrator lands on the next optimised configuration point."""
    out = []
    if replay["replay_failed_steps"]:
        out.append(f"replay: the integrator's Newton solve failed on stage(s) "
                   f"{', '.join(map(str, replay['replay_failed_stages']))}")
    if replay["replay_steps_elsewhere"]:
        out.append(f"replay: {replay['replay_steps_elsewhere']} of {replay['replay_stages']} stages not reproduced "
                   f"(stage(s) {', '.join(map(str, replay['replay_elsewhere_stages']))}; worst: stage "
                   f"{replay['replay_worst_stage']}, {replay['replay_worst_joint']} differs by "
                   f"{replay['replay_worst_drift']:.2g} {replay['replay_worst_unit']})")
    return out


def replay_text(replay: Dict[str, Any]) -> str:
    """The replay per stage in plain words with units."""
    n, ok = replay["replay_stages"], replay["replay_stages_reproduced"]
    to = f" to {replay['replay_reproduced_to']:.1g} (m or rad)" if ok else ""
    text = f"replay: {ok} of {n} stages reproduced{to} by the integrator from their optimised states, controls and forces"
    if replay["replay_steps_elsewhere"]:
        root = ("another root of the DEL equations" if replay["replay_stage_residual"] <= REPLAY_TOLERANCE
                else "another point (the stage is no step of the integrator)")
        text += (f"; stage {replay['replay_worst_stage']} converged to {root}: {replay['replay_worst_joint']} differs by "
                 f"{replay['replay_worst_drift']:.2g} {replay['replay_worst_unit']}")
        others = [k for k in replay["replay_elsewhere_stages"] if k != replay["replay_worst_stage"]]
        if others:
            text += f" (also stage(s) {', '.join(map(str, others))})"
    if replay["replay_failed_steps"]:
        text += f"; the Newton solve failed on stage(s) {', '.join(map(str, replay['replay_failed_stages']))}"
    return text


def check(example: Example, result: Result, method: str = "vi") -> Tuple[Dict[str, Any], Dict[str, Any], list]:
    """(figures, replay figures, failures) of ``result``: the example's figures against its bounds
    (between-knot penetration included), IPOPT's status and, for the VI, the replay's verdict
    (``replay_failures``): the one verdict of ``run`` and bench/robot_examples.py."""
    figures = example.checks(result)
    replay = replay_figures(example, result) if method == "vi" else {}
    failures = (([] if result.success else [f"IPOPT: {result.status}"]) + example.failures(figures)
                + (replay_failures(replay) if replay else []))
    return figures, replay, failures


def plot(example: Example, result: Result, path: str) -> None:
    """Joint angles, actuator torques and contact forces against time, in one figure."""
    from ...vis.plots import legend, pyplot
    plt = pyplot()
    tr, robot = result.trajectory, example.robot
    model = robot.model
    fig, axes = plt.subplots(1, 3, figsize=(16, 4.2))
    joints = [model.joint_index(j) for j in robot.actuated]
    for j in joints:
        axes[0].plot(tr["t"], tr["q"][:, j], lw=1, label=model.joint_names[j])
    axes[0].set_title("actuated joint angles [rad]")
    m = len(robot.actuated)
    for k in range(m):
        axes[1].plot(tr["t"], tr["u"][:, k], lw=1, label=robot.actuated[k])
    axes[1].set_title("actuator torques [N m]")
    forces = example.contact_forces(tr["u"])
    for k, label in enumerate(example.force_labels):
        axes[2].plot(tr["t"], forces[:, k], lw=1, label=label)
    axes[2].set_title("contact forces [N]")
    for ax in axes:  # many joints: beside the axes, off the data
        legend(ax, fontsize=6)
    for ax in axes:
        ax.set_xlabel("time [s]")
        ax.grid(True, alpha=0.3)
    fig.suptitle(f"{example.name}: {example.description}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def animate(example: Example, result: Result, output: str, fps: float, progress: bool | None = False) -> list[str]:
    """animation.html (meshcat, standalone) and animation.mp4 of the optimised motion with its scenery
    (the terrain: world shapes) on a ground grid at the lowest top of its boxes; ``progress``: the
    video's progress bar (``hovi.vis.video.render_video``)."""
    from ...vis.video import render_video
    from ...vis.viewer import animation_html
    model = example.robot.model.copy()
    for shape, size, centre, rgba in example.scenery.shapes:
        origin = np.eye(4)
        origin[:3, 3] = centre
        model.add_visual(None, shape, size=size, origin=origin, rgba=rgba)
    tr = result.trajectory
    t = np.linspace(0.0, tr["t"][-1], max(2, int(round(tr["t"][-1] * fps)) + 1))
    q = np.column_stack([np.interp(t, tr["t"], tr["q"][:, j]) for j in range(model.n)])
    tops = [centre[2] + size[2] / 2 for shape, size, centre, _ in example.scenery.shapes if shape == "box"]
    ground = min(tops) - 1e-3 if tops else 0.0  # just below the terrain's tops (no flicker where they meet)
    html = animation_html(model, q, os.path.join(output, f"{example.name}.html"), times=t, fps=fps, ground=ground)
    video = render_video(model, q, os.path.join(output, f"{example.name}.mp4"), times=t, fps=fps, ground=ground,
                         progress=progress)
    return [str(html), str(video)]


def solve(example: Example, method: str = "vi", s: int = 1, verbose: bool = False,
          time_limit: float | None = None, checkpoint: str | None = None, *, reported: bool = True) -> Result:
    """Solve the example's problem with ``method`` ('vi' of order 2s, 'hs-implicit', 'hs-explicit') by
    IPOPT with the Lagrangian's Hessian ('auto': the VI's own and the built-in rows' exact Hessians;
    L-BFGS does not converge on these robots, and coloured differences, 'fd', take more iterations:
    bench/README.md, "Design measurements"), from the example's guess; ``time_limit`` (seconds) bounds the whole solve
    (IPOPT's max_cpu_time; a contact-implicit solve starts no further solve once it is spent);
    ``checkpoint`` (a path) lets a contact-implicit solve resume its homotopy (trajopt.solve_contact).

    With ``example.from_trapezoidal`` and the VI of order 2s > 2 or Hermite-Simpson, the
    trapezoidal VI is solved first (its solves are cheap and, through contact, its contact model
    well posed) and the solve starts from its solution: on the sides of the complementarity pairs
    it found (``solve_contact(sides_from=...)``), or without contacts from its interpolants (the
    second stage of the default pipeline's order continuation, ``Ipopt.continue_from``, which
    ``trajopt.solve`` runs only from a guess by name, here without its cap on the iterations; its first stage is reported as there,
    in ``timing['continuation']`` and ``solver['continuation']``); with ``example.warm_up``, the
    trapezoidal solve itself starts on the sides of the warm-up's; a contact-implicit result's
    ``contact['solves']``, 'iterations' and 'wall_seconds' count both, and ``contact['coarse']``
    holds the trapezoidal solve's (iterations, seconds in IPOPT). Iterations and times of both ways:
    bench/README.md ("Design measurements", report.py). ``reported``: a VI solve gets
    ``example.replay_options`` too (False: a solve that only starts another)."""
    options = {**example.options, **(example.replay_options if reported and method == "vi" else {})}
    coarse, first = None, None
    if method == "vi" and s == 1 and example.warm_up is not None:
        first, tag = example.warm_up, "_warm_up"
    elif (method != "vi" or s > 1) and example.from_trapezoidal:
        first, tag = example, "_s1"
    if first is not None:
        t0 = time.perf_counter()
        coarse = solve(first, "vi", 1, verbose, time_limit,
                       None if checkpoint is None else f"{os.path.splitext(checkpoint)[0]}{tag}.npz", reported=False)
        first_seconds = time.perf_counter() - t0
        if time_limit is not None:
            time_limit = max(1.0, time_limit - first_seconds)
    if example.problem.contacts is None:
        if time_limit is not None:
            options["max_cpu_time"] = float(time_limit)
        if coarse is None:
            return trajopt.solve(example.problem, from_name(method, s), guess=example.guess, options=options,
                                 verbose=verbose)
        return trajopt.Ipopt(options, verbose=verbose).continue_from(coarse, example.problem, from_name(method, s),
                                                                     example.guess, max_iter=None, since=t0)
    epsilons = {} if example.epsilons is None else {"epsilons": example.epsilons}
    result = trajopt.solve_contact(example.problem, from_name(method, s), guess=example.guess,
                                   options=options, verbose=verbose, hessian="auto", time_limit=time_limit,
                                   checkpoint=checkpoint, sides_from=coarse, **epsilons)
    if coarse is not None:
        c, r = coarse.contact, result.contact
        r["coarse"] = (c["iterations"], c["wall_seconds"])
        r["solves"] = c["solves"] + r["solves"]
        r["iterations"] += c["iterations"]
        r["wall_seconds"] += c["wall_seconds"]
    return result


def run(example: Example, output: str, *, animation: bool = True, plots: bool = True, fps: float = 25.0,
        verbose: bool = False, method: str = "vi", s: int = 1, checkpoint: str | None = None,
        progress: bool | None = False, closed_loop: bool = False, push: Optional[Push] = None,
        mass_scale: float = 1.0) -> Dict[str, Any]:
    """Solve ``example`` (``method``, ``checkpoint`` as in ``solve``: the VI of order 2s by default),
    check it, replay it (VI only: the replay figures put the solution into the integrator's
    equations), execute it open loop in the contact simulator (VI with s = 1: contact_replay.py) and
    write its files into ``output``; returns the summary (also written as <name>.json) with 'feasible' and, if not,
    'failures'. ``progress``: the video's progress bar (True, False, None: on a terminal).

    closed_loop: also track the optimised motion by time-varying LQR in the contact simulator
    (``tracking.closed_loop_figures``; VI with s = 1), with ``push`` and every mass times
    ``mass_scale`` in the plant: the summary's 'closed_loop' says whether it reached the goal."""
    if closed_loop and (method != "vi" or s != 1):
        raise ValueError("closed loop: the optimised motion is tracked in the contact simulator, whose time-stepping "
                         "is the VI with s = 1; solve with the VI and s = 1")
    if not closed_loop and (push is not None or mass_scale != 1.0):
        raise ValueError("a push or a mass scale is for the closed loop: ask for it (closed_loop=True)")
    os.makedirs(output, exist_ok=True)
    t0 = time.perf_counter()
    result = solve(example, method, s, verbose, checkpoint=checkpoint)
    wall = time.perf_counter() - t0
    figures, replay, failures = check(example, result, method)
    iterations, ipopt_seconds = ipopt_totals(result)
    summary: Dict[str, Any] = {
        "example": example.name, "description": example.description, "dof": example.robot.model.n,
        "N": example.problem.N, "T": example.problem.T, "transcription": result.transcription.name,
        "status": result.status, "success": bool(result.success), "iterations": iterations,
        "solve_seconds": wall, "ipopt_seconds": ipopt_seconds, "cost": float(result.cost),
        "constraint_violation": float(result.constraint_violation), **result.sizes, **figures,
        "contact_solves": result.contact.get("solves", []),
        **replay, "feasible": not failures, "failures": failures}
    sim = simulated_figures(example, result) if method == "vi" and s == 1 else {}
    summary.update(sim)
    summary["report"] = ([between_knot_text(figures)] if "between_knot_penetration" in figures else []) + (
        [replay_text(replay)] if replay else []) + ([simulated_text(sim)] if sim else [])
    base = os.path.join(output, example.name)
    tr = result.trajectory
    np.savez(base + ".npz", t=tr["t"], q=tr["q"], u=tr["u"], contact_forces=example.contact_forces(tr["u"]),
             force_labels=np.array(example.force_labels), joint_names=np.array(example.robot.model.joint_names))
    files = [base + ".npz", base + ".json"]
    if isinstance(result.transcription, VariationalTranscription):  # a hovi trajectory, with its controls
        result.transcription.solution_trajectory(result.x).save(base + "_trajectory.npz")
        files.insert(1, base + "_trajectory.npz")
    if closed_loop:
        from .tracking import closed_loop_figures, closed_loop_text
        loop = closed_loop_figures(example, result, push=push, mass_factor=mass_scale)
        summary["closed_loop"] = loop
        summary["report"].append(closed_loop_text(loop))
    if plots:
        plot(example, result, base + ".png")
        files.append(base + ".png")
    if animation:
        files += animate(example, result, output, fps, progress)
    summary["files"] = files
    with open(base + ".json", "w") as f:
        json.dump(summary, f, indent=2, default=float)
    return summary
