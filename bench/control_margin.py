"""The Spring Flamingo re-optimised with torque margin, then tracked with its full torque limits (a
lever bench/control_robots.py's failure analysis pointed to: the quick jump's push-off runs at the
50 N m limits from 0.2 to 0.45 s, so the TV-LQR has no authority left there, and a 10% heavier plant
fails). The optimiser's limits on the robot's own joint torques (the first m controls, not the
contact force inputs) times MARGIN (0.8), solved once (report.solve) and checked as the example's
report checks a solution; then the bench's four cases (nominal, push, every mass x1.1, both) in
closed loop on the example with its FULL limits, also without limits, and more mass factors; and
the same closed loop stepped in Python with each contact step started at the optimiser's impulses
(``guided``: the contact step can have more than one solution), for this solve and the example's own.

Measured (bench/results/control_margin.json, quick example, margin 0.8): IPOPT succeeds in 565 s
(the example's own: 81 s; 2 cores shared), the jump clears the obstacle by 7.6 mm and lands 0.14 m
beyond it, but the solve misses one of the example's bounds (a toe 2.1 mm below the ground between
the knots at 0.505 s; the bound is 1 mm), and it rides its 80% limits 22% of the time (the example's
own solve: its full limits 12.5%). It does not make the closed loop succeed: the simulator's contact
step from the first knot, started without a guess, takes another solution of the contact conditions
than the optimiser's (the left knee 0.6 rad away after one step), and every case fails, the nominal
too (a leg in the obstacle at 0.03 s; with 10% more mass a step jumps 2.2 rad at 0.3 s), with or
without torque limits. Guided to the optimiser's impulses, the nominal still
fails at 0.85 s (that step converges to another root of the DEL equations, an ankle a full turn
away), the push alone succeeds (error 0.053 rad), and 1%, 5% and 10% more mass fail (a leg in the
obstacle at 0.74, 0.60 and 0.61 s; the example's own solve at 0.71-0.73 s), also without torque
limits: the limits are not what fails the heavier jump.

    python bench/control_margin.py [--only spring_flamingo] [--margin 0.8] [--solutions DIR]

(--solutions DIR: keep / reuse the solve in DIR/<name>_margin<M>.npz and .json, and the example's
own solve DIR/<name>.npz from bench/control_robots.py --solutions.) Writes
bench/results/control_margin.json.
"""
from __future__ import annotations

import argparse
import json
import os
import time
from typing import Any, Dict, Optional, Tuple

import numpy as np

from common import hovi_commit, write_json
from hovi import _core
from hovi.examples.paper import build, report
from hovi.examples.paper import tracking as CL

MASS_FACTORS = (1.02, 1.05, 1.1, 1.15, 1.2)


def margin_example(name: str, margin: float):
    """The quick example ``name`` with its robot's torque limits (problem.u_lower/u_upper of its m
    joint torques) times ``margin``; the contact inputs' bounds are left as they are."""
    example = build(name, quick=True)
    m = example.robot.model.n_controls
    example.problem.u_lower[:m] *= margin
    example.problem.u_upper[:m] *= margin
    return example


def torque_use(example, motion: Any, limits: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> Dict[str, Any]:
    """How the optimised torques use ``limits`` (default: the example's): the peak |u| / limit per joint
    and the fraction of control points within 1% of a limit."""
    m = example.robot.model.n_controls
    lo, hi = limits if limits is not None else (example.problem.u_lower[:m], example.problem.u_upper[:m])
    U = CL.optimised_motion(example, motion).U[:, :, :m]
    bound = np.maximum(np.abs(lo), np.abs(hi))
    near = (U <= lo + 0.01 * bound) | (U >= hi - 0.01 * bound)
    return {"peak_over_limit": dict(zip(example.robot.actuated, (np.abs(U).max(axis=(0, 1)) / bound).tolist())),
            "near_limit_fraction": float(near.mean()),
            "near_limit_times": sorted({round(float(k * example.problem.dt), 4) for k in np.flatnonzero(near.any(axis=(1, 2)))})}


def solve(name: str, margin: float, solutions: Optional[str] = None) -> Tuple[Any, Dict[str, Any], Dict[str, Any]]:
    """(the margin example, the solve's arrays, its figures: time, IPOPT status, the feasibility figures
    and failures of report.check); kept in / loaded from DIR/<name>_margin<M>.npz and .json."""
    example = margin_example(name, margin)
    base = None if solutions is None else os.path.join(solutions, f"{name}_margin{margin:g}")
    if base is not None and os.path.exists(base + ".npz") and os.path.exists(base + ".json"):
        with open(base + ".json") as f:
            figures = json.load(f)
        return example, dict(np.load(base + ".npz")), {**figures, "loaded_from": base + ".npz"}
    t0 = time.perf_counter()
    result = report.solve(example)
    wall = time.perf_counter() - t0
    checks, replay, failures = report.check(example, result)
    tr, tc = result.trajectory, result.transcription
    arrays = {"knots": tr["q"][::tc.s], "p": tr["p"], "U": tc.stage_controls(result.x), "success": result.success}
    figures = {"margin": margin, "solve_seconds": wall, "success": bool(result.success), "status": result.status,
               "cost": float(result.cost), "feasible": not failures, "failures": failures,
               "figures": {k: float(v) if isinstance(v, (int, float, np.number)) else v for k, v in checks.items()},
               "replay": {k: v for k, v in replay.items() if not isinstance(v, list)}}
    if base is not None:
        os.makedirs(solutions, exist_ok=True)
        np.savez(base + ".npz", **arrays)
        with open(base + ".json", "w") as f:
            json.dump(figures, f, indent=1, default=float)
    return example, arrays, figures


def knot_impulses(example, motion: Any, plant) -> np.ndarray:
    """The optimiser's contact impulses at the knots (K, C, 2+d) in the simulator's units (as
    closed_loop's nominal takes them: the knot inputs times dt, half at knot 0, unloaded ones zero)."""
    mo = CL.optimised_motion(example, motion)
    c, m = plant.contacts, example.robot.model.n_controls
    Z = mo.dt * mo.U[:, 0, m:].reshape(mo.steps, c.n_contacts, c.inputs_per_contact).copy()
    Z[0] *= 0.5
    Z[Z[:, :, 0] <= CL.UNLOADED] = 0.0
    return Z


def guided(example, motion: Any, mass_factor: float = 1.0, push: Optional[Any] = None,
           saturate: bool = True) -> Dict[str, Any]:
    """The closed loop stepped in Python with each contact step started at the optimiser's impulses at
    that knot (``Integrator.step(impulses=...)``; the C++ loop starts without a guess and the contact
    step can have more than one solution): does the policy track where the simulator keeps to the
    optimiser's contact solution? Success by the example's goal (closed_loop.GOALS), tracking error."""
    mo = CL.optimised_motion(example, motion)
    policy = CL.controller(example, mo, saturate=saturate).policy
    plant = CL.simulator(example, mass_factor)
    Z = knot_impulses(example, mo, plant)
    q, p = mo.q[0].copy(), plant.momentum(mo.q[0], example.problem.qdot0)
    kicks = push.knots(plant.model, plant.dt) if push is not None else []
    Q, normal, status = [q], [], "converged"
    for k in range(mo.steps):
        for step, body, point, impulse, _ in kicks:   # a push: J^T impulse on the step's momentum
            if step == k:
                _, J = _core.body_point_kinematics(plant.model, q[None], [body], np.asarray(point)[None])
                p = p + J[0, 0].T @ impulse
        q, p, info = plant.step(q, p, policy.control(k, q, p), impulses=Z[k], raise_on_failure=False)
        if not info.converged:
            status = info.status
            break
        Q.append(q)
        normal.append(info.impulses[:, 0])
    Qa = np.array(Q)
    complete = len(Qa) == mo.steps + 1
    figures, events = CL.GOALS[example.name](example, plant, Qa, np.array(normal).reshape(len(Qa) - 1, -1),
                                             complete, mo.dt)
    if not complete:
        events.append((float((len(Qa) - 1) * mo.dt), f"the contact step fails ({status})"))
    events.sort(key=lambda e: e[0])
    err = np.abs(Qa - mo.q[:len(Qa)]).max(axis=1)
    return {"mass_factor": mass_factor, "push": push is not None, "torque_limits": saturate,
            "success": not events, "steps": len(Qa) - 1, "max_tracking_error": float(err.max()),
            "final_tracking_error": float(err[-1]),
            "failure": {"time": events[0][0], "what": events[0][1]} if events else None,
            "obstacle_clearance": figures.get("obstacle_clearance")}


GUIDED = ((1.0, False, True), (1.0, True, True), (1.01, False, True), (1.05, False, True), (1.1, False, True),
          (1.1, True, True), (1.01, False, False), (1.1, False, False))   # (mass factor, push, torque limits)


def brief(fig: Dict[str, Any]) -> Dict[str, Any]:
    keys = ("success", "steps", "max_tracking_error", "final_tracking_error", "worst_coordinate", "departs_at",
            "penetration", "saturated_fraction", "most_saturated", "failure", "obstacle_clearance", "landed",
            "final_pitch", "goal_distance", "ball_distance", "past_last_gap")
    return {k: fig[k] for k in keys if k in fig}


def study(name: str, margin: float, solutions: Optional[str] = None, nominal: Any = None) -> Dict[str, Any]:
    """The margin solve, its torque use (against the full and the scaled limits), the bench's four
    cases in closed and open loop with the FULL limits, and the mass factors the closed loop holds
    (with a push too); ``nominal``: the example's own solve (its arrays), for its torque use beside."""
    t0 = time.perf_counter()
    scaled, motion, solved = solve(name, margin, solutions)
    full = build(name, quick=True)                      # the plant's and the policy's limits: the robot's own
    out: Dict[str, Any] = {"margin": margin, "solve": solved,
                           "torque_use_full_limits": torque_use(full, motion),
                           "torque_use_scaled_limits": torque_use(scaled, motion)}
    if nominal is not None:
        out["nominal_solve_torque_use"] = torque_use(full, nominal)
    cases = CL.cases(full, motion)
    out["nominal"] = cases["nominal"]["nominal"]
    out["cases"] = {c: {k: brief(f[k]) for k in ("closed_loop", "open_loop")} for c, f in cases.items()}
    free = CL.controller(full, motion, saturate=False)     # what the torque limits cost: none at all
    for c, f in cases.items():
        out["cases"][c]["no_torque_limits"] = brief(CL.closed_loop_figures(
            full, motion, control=free, push=f["push"] and CL.default_push(full), mass_factor=f["mass_factor"],
            open_loop_too=False)["closed_loop"])
    ctl = CL.controller(full, motion)
    push = CL.default_push(full)
    rows = []
    for factor in MASS_FACTORS:
        alone = CL.closed_loop_figures(full, motion, control=ctl, mass_factor=factor, open_loop_too=False)["closed_loop"]
        pushed = CL.closed_loop_figures(full, motion, control=ctl, mass_factor=factor, push=push,
                                        open_loop_too=False)["closed_loop"]
        rows.append({"mass_factor": factor, "closed_loop": brief(alone), "with_push": brief(pushed)})
    out["mass"] = rows
    push = CL.default_push(full)
    out["guided"] = [guided(full, motion, f, push if pu else None, sat) for f, pu, sat in GUIDED]
    if nominal is not None:
        out["nominal_solve_guided"] = [guided(full, nominal, f, push if pu else None, sat) for f, pu, sat in GUIDED]
    out["seconds"] = time.perf_counter() - t0
    return out


def text(name: str, out: Dict[str, Any]) -> str:
    s = out["solve"]
    lines = [f"{name} re-optimised with its joint torque limits x{out['margin']:g}: "
             f"{'feasible' if s['feasible'] else 'NOT feasible: ' + '; '.join(s['failures'])} "
             f"(IPOPT {'success' if s['success'] else s['status']}, "
             f"{s.get('solve_seconds', float('nan')):.0f} s; obstacle clearance "
             f"{s['figures'].get('obstacle_clearance', float('nan')):.3g} m)"]
    for case, f in out["cases"].items():
        for loop in ("closed_loop", "open_loop", "no_torque_limits"):
            r = f[loop]
            fail = "" if r["failure"] is None else f"; fails at t = {r['failure']['time']:.3g} s: {r['failure']['what']}"
            lines.append(f"  {case:9s} {loop.replace('_', ' '):16s} {'succeeds' if r['success'] else 'fails'}: "
                         f"tracking error max {r['max_tracking_error']:.2g} final {r['final_tracking_error']:.2g}, "
                         f"torques at a limit {100 * r['saturated_fraction']:.0f}%{fail}")
    for row in out["mass"]:
        lines.append(f"  mass x{row['mass_factor']:g}: closed loop {'succeeds' if row['closed_loop']['success'] else 'fails'}"
                     f" (error max {row['closed_loop']['max_tracking_error']:.2g}), with the push "
                     f"{'succeeds' if row['with_push']['success'] else 'fails'}")
    for key, what in (("guided", "this solve"), ("nominal_solve_guided", "the example's own solve")):
        for r in out.get(key, []):
            fail = "" if r["failure"] is None else f": t = {r['failure']['time']:.3g} s, {r['failure']['what']}"
            lines.append(f"  guided ({what}) mass x{r['mass_factor']:g}{' + push' if r['push'] else ''}"
                         f"{'' if r['torque_limits'] else ', no torque limits'}: "
                         f"{'succeeds' if r['success'] else 'fails'} (error max {r['max_tracking_error']:.2g}){fail}")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", default=["spring_flamingo"], help="the quick examples (default: spring_flamingo)")
    ap.add_argument("--margin", type=float, default=0.8, help="the optimiser's joint torque limits times this")
    ap.add_argument("--solutions", default=None, metavar="DIR",
                    help="keep / reuse the solve in DIR/<name>_margin<M>.npz (+ .json); DIR/<name>.npz: the example's own")
    args = ap.parse_args()
    t0 = time.perf_counter()
    results = {}
    for name in args.only:
        nominal = None
        if args.solutions and os.path.exists(os.path.join(args.solutions, f"{name}.npz")):
            nominal = dict(np.load(os.path.join(args.solutions, f"{name}.npz")))
        results[name] = study(name, args.margin, args.solutions, nominal)
        print(text(name, results[name]), flush=True)
    commit = hovi_commit()
    path = write_json("control_margin.json", {"hovi_commit": commit, "examples": "quick", "margin": args.margin,
                                              "mass_factor": CL.MASS_FACTOR, "results": results,
                                              "load_average_end": os.getloadavg(),
                                              "wall_seconds": time.perf_counter() - t0})
    print(f"wrote {path}")


if __name__ == "__main__":
    main()
