"""The paper's robots in closed loop in the contact simulator: each quick example solved
once (report.solve, the trapezoidal VI), its optimised motion tracked by time-varying LQR on the
robot's torques (hovi.examples.paper.tracking, saturated at the torque limits) from the optimised
initial state: as is, with a push that breaks the open loop, with every body's mass x1.1 in the
plant, and both; each also open loop. Per run: success by the example's goal, tracking error
against the optimised knots (max, final), deepest penetration, torque saturation, first failure.

Beside the four cases, what was measured to choose the weights and to find where a robot fails:
  - weights: the four cases under a few alternative weights (the chosen ones: closed_loop.WEIGHTS);
  - smoothing: the contact Jacobians smoothed (smoothing = 1e-6, 1e-4, 1e-3) for every case that fails;
  - saturation: the same policy without torque limits for every case that fails;
  - margins: the largest push (a multiple of the case's push) and mass factor the closed and the
    open loop still succeed with (from a short list).

    python bench/control_robots.py [--quick] [--only atlas spring_flamingo littledog] [--solutions DIR] [--video]

--quick: Atlas only (its quick solve takes ~3 s), no weights study. --solutions DIR: keep each
solve's arrays in DIR/<name>.npz and reuse them when present (the solve times are then not
measured again). --video: also the push case of Atlas and the Spring Flamingo, closed and open loop,
as MP4s in bench/results/videos/ and as stills docs/images/control_<robot>.png (bench/control_videos.py).
Writes bench/results/control_robots.json (control_robots_quick.json). Times are indicative (2 cores
shared with other work).
"""
from __future__ import annotations

import argparse
import dataclasses
import os
import time

import numpy as np

import control_videos
from common import hovi_commit, solve_quick_example, write_json
from hovi.control import Push
from hovi.examples.paper import tracking as CL

ROBOTS = ("atlas", "spring_flamingo", "littledog")
# alternatives to the chosen weights (closed_loop.WEIGHTS), by example
ALTERNATIVES = {
    "atlas": [CL.Weights(base=10.0, joints=1.0, velocity=0.1, torque=1e-2, final=10.0),        # no task weight
              CL.Weights(base=10.0, joints=1.0, velocity=0.1, torque=1e-2, final=10.0, task=1e5),
              CL.Weights(base=100.0, joints=100.0, velocity=0.01, torque=1e-6, final=10.0, task=1e6),
              CL.Weights(base=10.0, joints=1000.0, velocity=0.01, torque=1e-2, final=10.0, task=1e5),
              CL.Weights(base=100.0, joints=100.0, velocity=0.01, torque=1e-2, final=1.0, task=1e6)],
    "spring_flamingo": [CL.Weights(base=1.0, joints=1.0, velocity=0.1, torque=0.25, final=10.0),
                 CL.Weights(base=100.0, joints=10.0, velocity=1.0, torque=0.25, final=10.0),
                 CL.Weights(base=10.0, joints=1.0, velocity=0.1, torque=25.0, final=10.0),
                 CL.Weights(base=1000.0, joints=10.0, velocity=1.0, torque=0.25, final=10.0)],
    "littledog": [CL.Weights(base=1.0, joints=1.0, velocity=0.1, torque=0.25, final=10.0),
                  CL.Weights(base=100.0, joints=1.0, velocity=1.0, torque=0.25, final=10.0),
                  CL.Weights(base=10.0, joints=1.0, velocity=0.1, torque=25.0, final=10.0)],
}
SMOOTHING = (1e-6, 1e-4, 1e-3)
PUSH_SCALES = (0.1, 0.25, 0.5, 1.0, 2.0, 4.0)
PUSH_TIMES = (0.1, 0.25, 0.5, 0.75, 0.9)   # fractions of the horizon
MASS_FACTORS = (1.002, 1.005, 1.01, 1.02, 1.05, 1.1, 1.2)


def brief(fig: dict) -> dict:
    """A run's figures without the lists (for the studies)."""
    keys = ("success", "steps", "max_tracking_error", "final_tracking_error", "penetration", "saturated_fraction",
            "failure", "ball_distance", "obstacle_clearance", "past_last_gap")
    return {k: fig[k] for k in keys if k in fig}


def case_push(example, case: str):
    return CL.default_push(example) if "push" in case else None


def case_mass(case: str) -> float:
    return CL.MASS_FACTOR if "mass" in case else 1.0


def motion_dt(example) -> float:
    return float(example.problem.dt)


def study(example, motion, cases: dict) -> dict:
    """Smoothing and saturation for the failing cases; push and mass margins."""
    out: dict = {"smoothing": {}, "no_torque_limits": {}}
    weights = CL.WEIGHTS[example.name]
    for case, fig in cases.items():
        if fig["closed_loop"]["success"]:
            continue
        push, mass = case_push(example, case), case_mass(case)
        rows = {}
        for smoothing in SMOOTHING:
            try:
                ctl = CL.controller(example, motion, dataclasses.replace(weights, smoothing=smoothing))
                rows[str(smoothing)] = brief(CL.closed_loop_figures(example, motion, control=ctl, push=push, mass_factor=mass,
                                                                open_loop_too=False)["closed_loop"])
            except ValueError as e:  # a Jacobian that cannot be smoothed
                rows[str(smoothing)] = {"error": str(e)}
        out["smoothing"][case] = rows
        ctl = CL.controller(example, motion, weights, saturate=False)
        out["no_torque_limits"][case] = brief(CL.closed_loop_figures(example, motion, control=ctl, push=push,
                                                                     mass_factor=mass, open_loop_too=False)["closed_loop"])
    free = CL.controller(example, motion, weights, saturate=False)
    ctl = CL.controller(example, motion, weights)
    base = CL.default_push(example)
    margins: dict = {"push": [], "push_times": [], "mass": []}
    for scale in PUSH_SCALES + tuple(-x for x in PUSH_SCALES):   # the push's direction, then the opposite
        push = Push(base.time, base.body, tuple(scale * np.asarray(base.impulse)))
        fig = CL.closed_loop_figures(example, motion, control=ctl, push=push)
        margins["push"].append({"impulse": [float(x) for x in push.impulse],
                                "closed_loop": fig["closed_loop"]["success"], "open_loop": fig["open_loop"]["success"],
                                "closed_loop_final_error": fig["closed_loop"]["final_tracking_error"],
                                "closed_loop_failure": fig["closed_loop"]["failure"]})
    T = example.problem.T
    for frac in PUSH_TIMES:                                       # the push's size at other times
        push = Push(round(frac * T / motion_dt(example)) * motion_dt(example), base.body, base.impulse)
        fig = CL.closed_loop_figures(example, motion, control=ctl, push=push)
        margins["push_times"].append({"time": float(push.time), "closed_loop": fig["closed_loop"]["success"],
                                      "open_loop": fig["open_loop"]["success"],
                                      "closed_loop_failure": fig["closed_loop"]["failure"]})
    for factor in MASS_FACTORS:
        fig = CL.closed_loop_figures(example, motion, control=ctl, mass_factor=factor)
        unlimited = CL.closed_loop_figures(example, motion, control=free, mass_factor=factor, open_loop_too=False)
        margins["mass"].append({"mass_factor": factor, "closed_loop": fig["closed_loop"]["success"],
                                "open_loop": fig["open_loop"]["success"],
                                "closed_loop_final_error": fig["closed_loop"]["final_tracking_error"],
                                "closed_loop_failure": fig["closed_loop"]["failure"],
                                "no_torque_limits": unlimited["closed_loop"]["success"],
                                "no_torque_limits_failure": unlimited["closed_loop"]["failure"]})
    out["margins"] = margins
    return out


def finer_replays(example, motion, factors=(1, 2, 5, 10)) -> list:
    """The optimised torques open loop in the simulator with dt / r (each stage's torques interpolated
    linearly over its r steps): does a finer plant follow the optimised knots further?"""
    import hovi
    rows = []
    U = motion.U[:, :, :example.robot.model.n_controls]
    for r in factors:
        plant = hovi.Integrator(example.robot.model, s=1, dt=motion.dt / r, contacts=example.simulation)
        a = np.arange(r + 1) / r
        pts = (1 - a)[None, :, None] * U[:, :1] + a[None, :, None] * U[:, 1:]     # (K, r+1, m)
        Uf = np.stack([pts[:, :-1], pts[:, 1:]], axis=2).reshape(-1, 2, U.shape[2])
        tr = plant.rollout(motion.q[0], motion.steps * r, qdot0=example.problem.qdot0, u=Uf, raise_on_failure=False)
        k = tr.steps // r
        dev = np.abs(tr.q[::r][:k + 1] - motion.q[:k + 1]).max(axis=1)
        far = np.flatnonzero(dev > CL.DEPARTED)
        rows.append({"r": r, "dt": motion.dt / r, "steps": int(tr.steps), "of_steps": motion.steps * r,
                     "status": tr.status[-1] if tr.status else "converged",
                     "departs_at": float(far[0] * motion.dt) if far.size else None,
                     "deviation_at_knots": dev.tolist()})
    return rows


def weights_study(example, motion) -> list:
    rows = []
    for w in ALTERNATIVES.get(example.name, []):
        try:
            cases = CL.cases(example, motion, weights=w)
            rows.append({"weights": dataclasses.asdict(w),
                         "cases": {c: brief(f["closed_loop"]) for c, f in cases.items()}})
        except ValueError as e:
            rows.append({"weights": dataclasses.asdict(w), "error": str(e)})
    return rows


def table(results: dict) -> str:
    lines = ["| robot | case | loop | success | max error | final error | penetration (m) | first failure |",
             "|---|---|---|---|---|---|---|---|"]
    for name, r in results.items():
        for case, fig in r["cases"].items():
            for loop in ("closed_loop", "open_loop"):
                f = fig[loop]
                fail = "" if f["failure"] is None else f"t = {f['failure']['time']:.3g} s: {f['failure']['what']}"
                lines.append(f"| {name} | {case} | {loop.replace('_', ' ')} | {'yes' if f['success'] else 'no'} | "
                             f"{f['max_tracking_error']:.2g} | {f['final_tracking_error']:.2g} | {f['penetration']:.1e} | {fail} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="Atlas only, no weights study")
    ap.add_argument("--only", nargs="+", choices=ROBOTS, default=None, help="the robots (default: all; --quick: atlas)")
    ap.add_argument("--solutions", default=None, metavar="DIR", help="keep / reuse each solve's arrays in DIR")
    ap.add_argument("--video", action="store_true", help="MP4s and stills of the push cases (bench/control_videos.py)")
    args = ap.parse_args()
    robots = args.only or (["atlas"] if args.quick else list(ROBOTS))
    t_start = time.perf_counter()
    load_start = os.getloadavg()
    results: dict = {}
    for name in robots:
        t0 = time.perf_counter()
        example, motion, solved = solve_quick_example(name, args.solutions)
        cases = CL.cases(example, motion)
        for fig in cases.values():
            print(CL.closed_loop_text(fig), flush=True)
        entry = {"solve": solved, "weights": dataclasses.asdict(CL.WEIGHTS[name]),
                 "push": cases["push"]["push"], "mass_factor": CL.MASS_FACTOR,
                 "nominal": cases["nominal"]["nominal"], "cases": {c: {k: f[k] for k in ("closed_loop", "open_loop")}
                                                                    for c, f in cases.items()}}
        entry["study"] = study(example, motion, cases)
        if cases["nominal"]["nominal"]["kind"] == "knots":   # the replay departs: would a finer plant follow?
            entry["study"]["finer_replays"] = finer_replays(example, CL.optimised_motion(example, motion))
        if not args.quick:
            entry["weights_study"] = weights_study(example, motion)
        if args.video and name in control_videos.ROBOTS:
            entry["video"] = control_videos.write(name, example, motion)
        entry["seconds"] = time.perf_counter() - t0
        results[name] = entry
    text = table(results)
    print(text)
    commit = hovi_commit()
    payload = {"quick": args.quick, "hovi_commit": commit, "examples": "quick", "robots": robots,
               "load_average_start": load_start, "load_average_end": os.getloadavg(),
               "departed": CL.DEPARTED, "results": results, "table": text,
               "wall_seconds": time.perf_counter() - t_start}
    path = write_json("control_robots_quick.json" if args.quick else "control_robots.json", payload)
    print(f"wrote {path} in {time.perf_counter() - t_start:.1f} s")


if __name__ == "__main__":
    main()
