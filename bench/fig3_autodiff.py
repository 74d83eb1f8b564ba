"""Paper Fig. 3: hovi's recursive algorithms against automatic differentiation for the Simpson
variational integrator (s = 2) on n-link pendulums: time of the DEL evaluation (Algorithm 1 vs
the AD gradient of L_d, O(n) vs O(n^2)), the Newton direction (Algorithms A.1/A.2 vs a nested-AD
Jacobian and dense LU, O(n) vs O(n^3)) and the linearisation D^2 L_d (Algorithms 2/3 + chain
rule vs nested AD, O(n^2) vs O(n^3)); states with q0, qdot0 uniform in [-pi/2, pi/2]. Both run in
C++ in this process (hovi.baselines.fig3_batch), timed per call.

    python bench/fig3_autodiff.py [--quick]

Writes bench/results/fig3_autodiff.json and .png, and the headline ratios to bench/README.md.
AD at large n costs seconds per call, so it is timed on fewer states there (recorded in the JSON).
"""
from __future__ import annotations


import numpy as np
from tqdm import tqdm

import hovi
import hovi.baselines
from common import RESULTS, loglog_slope, publish, save_figure, study_parser, write_json

OPS = {"del_residual": "DEL evaluation", "newton_direction": "Newton direction", "d2Ld": "linearisation D²L_d"}


def states(n, count, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(-np.pi / 2, np.pi / 2, (count, n)), rng.uniform(-np.pi / 2, np.pi / 2, (count, n))


def main():
    ap = study_parser(__doc__, "n = 2..16, 5 states")
    args = ap.parse_args()
    ns = [2, 4, 8, 16] if args.quick else [2, 4, 8, 16, 32, 64, 128]
    n_states = 5 if args.quick else 100
    rows = []
    for n in tqdm(ns, desc="n"):
        model = hovi.examples.models.pendulum(n)
        q0, qd0 = states(n, n_states, n)
        row = {"n": n}
        for method in ("recursive", "autodiff"):
            count = n_states if (method == "recursive" or n <= 16) else max(3, n_states * 16 // (n * n // 16))
            d = hovi.baselines.fig3_batch(model, 2, 0.01, q0[:count], qd0[:count], method)
            row[method] = {op: float(np.mean(d[op])) for op in OPS}
            row[method]["states"] = int(min(count, n_states))
        rows.append(row)
    slopes = {m: {op: loglog_slope([r["n"] for r in rows if r["n"] >= 8], [r[m][op] for r in rows if r["n"] >= 8])
                  for op in OPS} for m in ("recursive", "autodiff")}
    name = "fig3_autodiff_quick" if args.quick else "fig3_autodiff"
    write_json(f"{name}.json", {"s": 2, "dt": 0.01, "rows": rows, "slopes_n_ge_8": slopes})

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3), sharey=False)
    x = [r["n"] for r in rows]
    for ax, (op, title) in zip(axes, OPS.items()):
        for method, style in (("recursive", "o-"), ("autodiff", "s--")):
            ax.loglog(x, [r[method][op] * 1e6 for r in rows], style,
                      label=f"{method} (slope {slopes[method][op]:.2f})")
        ax.set_title(title + " (Simpson)")
        ax.set_xlabel("n (links)")
        ax.set_ylabel("time per call [µs]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    save_figure(fig, f"{RESULTS}/{name}.png")

    lines = ["| n | DEL evaluation: AD / recursive | Newton direction: AD / recursive | D²L_d: AD / recursive |",
             "|---|---|---|---|"]
    for r in rows:
        lines.append(f"| {r['n']} | " + " | ".join(
            f"{r['autodiff'][op] / r['recursive'][op]:.1f} ({r['recursive'][op] * 1e6:.1f} µs vs "
            f"{r['autodiff'][op] * 1e6:.4g} µs)" for op in OPS) + " |")
    lines.append("")
    lines.append("Fitted slopes for n ≥ 8: " + "; ".join(
        f"{m}: " + ", ".join(f"{OPS[op]} {v:.2f}" for op, v in slopes[m].items()) for m in slopes))
    publish("fig3", "\n".join(lines), args.quick)


if __name__ == "__main__":
    main()
