"""Cost of a constrained Newton direction (paper Sec. 3.3: the recursive solver applied to the
residual and to the s m columns of the constraint Jacobian, then an (s m) x (s m) Schur
complement) against the number of constraint equations m = 1..12 and the number of links n, in
C++ (bench/cpp/speed.cpp): the n-link pendulum with m single-axis point constraints spread along
the chain, s = 1 and 2.

    python bench/constraints.py [--quick]

Writes bench/results/constraints.json, constraints.png and the table in bench/README.md. A
least-squares fit t = a n + b m n + c m^3 per s shows the O(mn) + O(m^3) growth.
"""
from __future__ import annotations


import numpy as np

from common import RESULTS, build_cpp_bench, loglog_slope, publish, save_figure, study_parser, write_json
from speed import run


def fit(rows, s):
    pts = [r for r in rows if r["s"] == s]
    X = np.array([[r["n"], r["m"] * r["n"], r["m"] ** 3] for r in pts], dtype=float)
    y = np.array([r["direction"] for r in pts])
    coef, *_ = np.linalg.lstsq(X / y[:, None], np.ones(len(y)), rcond=None)  # relative least squares
    rel = np.abs(X @ coef - y) / y
    return {"a_per_n": coef[0], "b_per_mn": coef[1], "c_per_m3": coef[2], "max_rel_residual": float(rel.max())}


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    s0 = min(r["s"] for r in rows)
    for n in sorted({r["n"] for r in rows}):
        pts = sorted((r["m"], r["direction"]) for r in rows if r["n"] == n and r["s"] == s0)
        x, y = np.array(pts).T
        axes[0].plot(x, y * 1e6, "o-", label=f"n={n}")
    axes[0].set_xlabel("m (constraint equations)")
    axes[0].set_ylabel("constrained Newton direction [µs]")
    axes[0].set_title(f"cost against m (s = {s0})")
    axes[0].legend(fontsize=8)
    axes[0].grid(True, alpha=0.3)
    for m in sorted({r["m"] for r in rows}):
        if m not in (1, 4, 12):
            continue
        pts = sorted((r["n"], r["direction"]) for r in rows if r["m"] == m and r["s"] == s0)
        x, y = np.array(pts).T
        axes[1].loglog(x, y * 1e6, "o-", label=f"m={m} (slope {loglog_slope(x, y):.2f})")
    axes[1].set_xlabel("n (links)")
    axes[1].set_title(f"cost against n (s = {s0})")
    axes[1].legend(fontsize=8)
    axes[1].grid(True, which="both", alpha=0.3)
    save_figure(fig, path)


def main():
    ap = study_parser(__doc__, "a small smoke run, no README update")
    args = ap.parse_args()
    binary = build_cpp_bench()
    ns = [8, 16] if args.quick else [8, 16, 32, 64, 128]
    ms = [1, 2, 4] if args.quick else [1, 2, 3, 4, 6, 8, 10, 12]
    ss = [1] if args.quick else [1, 2]
    rows = []
    for s in ss:
        for n in ns:
            print(f"s = {s}, n = {n}", flush=True)
            rows += run(binary, "constrained", n, s, *[m for m in ms if 2 * m < n])
    assert all(r["ok"] for r in rows), "a constrained direction failed"
    fits = {s: fit(rows, s) for s in ss}
    name = "constraints_quick" if args.quick else "constraints"
    write_json(f"{name}.json", {"rows": rows, "fits": fits})
    plot(rows, f"{RESULTS}/{name}.png")
    lines = ["| s | n | m = 1 [µs] | m = 4 [µs] | m = 12 [µs] | residual eval., m = 12 [µs] |", "|---|---|---|---|---|---|"]
    for s in ss:
        for n in ns:
            d = {r["m"]: r for r in rows if r["s"] == s and r["n"] == n}
            cell = lambda m, k="direction": f"{d[m][k] * 1e6:.1f}" if m in d else "–"
            lines.append(f"| {s} | {n} | {cell(1)} | {cell(4)} | {cell(12)} | {cell(12, 'residual')} |")
    lines.append("")
    for s, f in fits.items():
        lines.append(f"Fit for s = {s}: t ≈ {f['a_per_n'] * 1e9:.1f} ns · n + {f['b_per_mn'] * 1e9:.2f} ns · m n + "
                     f"{f['c_per_m3'] * 1e9:.2f} ns · m³ (largest relative misfit {f['max_rel_residual']:.0%}).")
    publish("constraints", "\n".join(lines), args.quick)


if __name__ == "__main__":
    main()
