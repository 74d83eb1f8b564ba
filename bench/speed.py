"""Speed of hovi's DEL evaluation, Newton direction and converged step against Pinocchio's
rnea/aba on the same tree, in one C++ process (bench/cpp/speed.cpp); the n-link pendulum for
n = 4..256 and s = 1..4, and the Talos humanoid (fixed base). Also: the cost of the work a
scene may skip (gravity, force elements), and a 1000-step rollout from Python against the same
loop timed inside C++.

    python bench/speed.py [--quick]

Writes bench/results/speed.json, speed_vs_n.png and the table in bench/README.md.
"""
from __future__ import annotations

import json
import subprocess
import time

import numpy as np

import hovi
from common import RESULTS, build_cpp_bench, erd_urdf, loglog_slope, publish, save_times_against_n, study_parser, write_json

TALOS = "talos_data/robots/talos_reduced.urdf"


def run(binary, *args):
    out = subprocess.run([binary, *map(str, args)], check=True, capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines() if line.startswith("{")]


def python_vs_cpp_rollout(n=32, s=2, steps=1000, repeats=7):
    """Wall time of Integrator.rollout from Python against the C++ loop's own time, same process."""
    model = hovi.examples.models.pendulum(n)
    integ = hovi.Integrator(model, s=s, dt=0.01)
    q0 = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, n)
    ratios, walls = [], []
    for _ in range(repeats):
        t0 = time.perf_counter()
        traj = integ.rollout(q0, steps)
        wall = time.perf_counter() - t0
        ratios.append(wall / traj.solve_seconds)
        walls.append(wall)
    return {"n": n, "s": s, "steps": steps, "python_wall_s": float(np.median(walls)),
            "overhead_ratio_median": float(np.median(ratios)), "converged": traj.converged}


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    pend = [r for r in rows if r["model"] == "pendulum"]
    ref = {r["n"]: r for r in pend if r["op"] == "reference"}
    ns = sorted(ref)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5), sharey=True)
    titles = ["DEL evaluation (Alg. 1)", "Newton direction (Alg. A.1/A.2)", "full step / Newton iterations"]
    for ax, op in zip(axes, ["del_residual", "newton_direction", "per_iteration"]):
        for s in sorted({r["s"] for r in pend if r["op"] == "integrator"}):
            pts = sorted((r["n"], r[op] if op != "per_iteration" else r["step"] / max(r["step_iterations"], 1))
                         for r in pend if r["op"] == "integrator" and r["s"] == s)
            x, y = np.array(pts).T
            ax.loglog(x, y * 1e6, "o-", label=f"s={s} (slope {loglog_slope(x, y):.2f})")
        ax.loglog(ns, [ref[n]["pin_rnea"] * 1e6 for n in ns], "k--", label="Pinocchio rnea")
        ax.loglog(ns, [ref[n]["pin_aba"] * 1e6 for n in ns], "k:", label="Pinocchio aba")
    save_times_against_n(fig, list(zip(axes, titles)), path)


def table(rows, slopes, rollout):
    ref = {(r["model"], r["n"]): r for r in rows if r["op"] == "reference"}
    lines = ["| model | n | s | DEL eval [µs] | / rnea | Newton dir. [µs] | / aba | step [µs] (iters) |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r["op"] != "integrator" or (r["model"] == "pendulum" and r["n"] not in (8, 32, 128)):
            continue
        f = ref[(r["model"], r["n"])]
        lines.append(f"| {r['model']} | {r['n']} | {r['s']} | {r['del_residual'] * 1e6:.2f} | "
                     f"{r['del_residual'] / f['pin_rnea']:.2f} | {r['newton_direction'] * 1e6:.2f} | "
                     f"{r['newton_direction'] / f['pin_aba']:.2f} | {r['step'] * 1e6:.1f} ({r['step_iterations']}) |")
    lines.append("")
    lines.append("The step starts from rest at a random configuration (±π/12 per joint) with dt = 0.01 s and the "
                 "velocity guess; its iteration count grows with n because a longer chain (0.5 m links) moves faster "
                 "at the same dt (at n = 256 some solves fail: see speed.json), so the plot shows the step time per "
                 "Newton iteration.")
    lines.append("")
    lines.append("Fitted log-log slopes in n (pendulum, n = 4..256): " + ", ".join(
        f"s={s}: evaluation {v['del_residual']:.2f}, direction {v['newton_direction']:.2f}" for s, v in slopes.items()))
    for r in rows:
        if r["op"] == "skip":
            lines.append(f"\nWork skipped ({r['model']}, n = {r['n']}, Simpson DEL evaluation): no gravity "
                         f"{r['no_forces'] * 1e6:.2f} µs, gravity only {r['gravity_only'] * 1e6:.2f} µs, with a spring, "
                         f"damper and actuator on every joint and drag on every fourth body {r['all_forces'] * 1e6:.2f} µs.")
    lines.append(f"\nRollout of {rollout['steps']} steps (pendulum n = {rollout['n']}, s = {rollout['s']}) from Python: "
                 f"wall time / C++ loop time = {rollout['overhead_ratio_median']:.4f} (median of 7).")
    return "\n".join(lines)


def main():
    ap = study_parser(__doc__, "a small smoke run (n <= 16, s <= 2), no README update")
    args = ap.parse_args()
    binary = build_cpp_bench()
    ns = [4, 8, 16] if args.quick else [4, 8, 16, 32, 64, 128, 256]
    ss = [1, 2] if args.quick else [1, 2, 3, 4]
    rows = []
    for n in ns:
        print(f"pendulum n = {n}", flush=True)
        rows += run(binary, "pendulum", n, *ss)
    talos = erd_urdf(TALOS)
    if not args.quick:
        print("talos", flush=True)
        rows += run(binary, "urdf", talos, 1, 2, 3)
        rows += run(binary, "skip", talos)
    for r in rows:
        if r["op"] == "reference":
            assert r["rnea_max_diff"] < 1e-8, r  # both libraries integrate the same tree
    slopes = {}
    for s in ss:
        pts = sorted((r["n"], r) for r in rows if r["model"] == "pendulum" and r["op"] == "integrator" and r["s"] == s)
        x = np.array([n for n, _ in pts])
        slopes[s] = {op: loglog_slope(x, [r[op] for _, r in pts]) for op in ("del_residual", "newton_direction", "step")}
    rollout = python_vs_cpp_rollout(steps=200 if args.quick else 1000)
    name = "speed_quick" if args.quick else "speed"
    write_json(f"{name}.json", {"rows": rows, "slopes": slopes, "rollout": rollout})
    plot(rows, f"{RESULTS}/{name}_vs_n.png")
    publish("speed", table(rows, slopes, rollout), args.quick)


if __name__ == "__main__":
    main()
