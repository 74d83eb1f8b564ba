"""Paper Fig. 2: hovi's exact O(n) Newton method against the O(n) quasi-Newton method of Lee et
al. (2016) on the trapezoidal variational integrator of the 32-link pendulum: one step from
random initial conditions (q0, qdot0 uniform in [-pi/2, pi/2]) for dt from 0.001 to 0.06; time
per solve and iterations over the successful solves, and the success rate. Both start from
q0 + dt qdot0 and stop at ||r||_inf <= 1e-10 (1 + ||p0||_inf); at most 100 iterations. Beside
them, the continuation in the step length (step_continuation.hpp), which returns the step on
the solution branch through q0 or reports that the branch turns back before dt; Newton's roots
are classified as on or off that branch.

    python bench/fig2_quasi_newton.py [--quick] [--workers N] [--scheduler ADDRESS|local]

--workers N spreads the states over N C++ threads (hovi.baselines.one_step_batch); --scheduler runs
them on a Dask cluster (hovi.distributed.one_step_batch). The results are the same bit for bit;
the times per solve are each solve's own, measured while the other workers run beside it.

Writes bench/results/fig2_quasi_newton.json and .png.
"""
from __future__ import annotations


import numpy as np
from tqdm import tqdm

import hovi
import hovi.baselines
import hovi.distributed
from common import RESULTS, add_parallel_arguments, parallel, parallel_description, save_figure, study_parser, update_readme_section, write_json

DTS = [0.001, 0.002, 0.005, 0.01, 0.02, 0.03, 0.04, 0.05, 0.06]
METHODS = {"newton": "hovi exact Newton (Alg. 1 + A.1/A.2)", "quasi_newton": "quasi-Newton (Lee et al. 2016)",
           "continuation": "continuation in the step length (physical branch)"}


def run(n_links, n_states, dts, seed=0, workers=1, client=None):
    """The study; the states of each (dt, method) on `workers` local threads, or on the Dask `client`."""
    model = hovi.examples.models.pendulum(n_links)
    rng = np.random.default_rng(seed)
    q0 = rng.uniform(-np.pi / 2, np.pi / 2, (n_states, n_links))
    qd0 = rng.uniform(-np.pi / 2, np.pi / 2, (n_states, n_links))
    out = {m: [] for m in METHODS}
    for dt in tqdm(dts, desc="dt"):
        batch = {}
        for method in METHODS:
            if client is None:
                d = hovi.baselines.one_step_batch(model, dt, q0, qd0, method, threads=workers)
            else:
                d = hovi.distributed.one_step_batch(model, dt, q0, qd0, method, client=client)
            batch[method] = d
            ok = d["converged"].astype(bool)
            out[method].append({
                "dt": dt, "success_rate": float(ok.mean()),
                "mean_seconds": float(d["seconds"][ok].mean()) if ok.any() else None,
                "mean_iterations": float(d["iterations"][ok].mean()) if ok.any() else None,
                "iterations": d["iterations"].tolist(), "converged": ok.tolist(),
                "status": list(d["status"])})
        # Which of Newton's roots are the step on the physical branch (the continuation's root)?
        newton_ok, cont_ok = batch["newton"]["converged"].astype(bool), batch["continuation"]["converged"].astype(bool)
        same = np.abs(batch["newton"]["q_next"] - batch["continuation"]["q_next"]).max(axis=1) < 1e-6
        out["newton"][-1]["roots_on_branch"] = int((newton_ok & cont_ok & same).sum())
        out["newton"][-1]["roots_off_branch"] = int((newton_ok & ~(cont_ok & same)).sum())
    return out


def plot(out, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    for method, label in METHODS.items():
        rows = out[method]
        dt = [r["dt"] for r in rows]
        t = [r["mean_seconds"] * 1e6 if r["mean_seconds"] else np.nan for r in rows]
        it = [r["mean_iterations"] if r["mean_iterations"] else np.nan for r in rows]
        axes[0].semilogy(dt, t, "o-", label=label)
        axes[1].plot(dt, it, "o-", label=label)
        axes[2].plot(dt, [100 * r["success_rate"] for r in rows], "o-", label=label)
    for ax, title, ylabel in zip(axes, ["(a) time per solve", "(b) iterations", "(c) success rate"],
                                 ["µs (successful solves)", "iterations (successful solves)", "%"]):
        ax.set_title(title)
        ax.set_xlabel("dt [s]")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
    save_figure(fig, path)


def table(out) -> str:
    lines = ["| dt | Newton: success | its roots on / off the physical branch | continuation: step on the branch "
             "(iterations) | quasi-Newton: success |", "|---|---|---|---|---|"]
    for nw, ct, qn in zip(out["newton"], out["continuation"], out["quasi_newton"]):
        it = f" ({ct['mean_iterations']:.1f})" if ct["mean_iterations"] else ""
        lines.append(f"| {nw['dt']} | {100 * nw['success_rate']:.1f}% | {nw['roots_on_branch']} / {nw['roots_off_branch']} | "
                     f"{100 * ct['success_rate']:.1f}%{it} | {100 * qn['success_rate']:.1f}% |")
    return "\n".join(lines)


def main():
    ap = study_parser(__doc__, "20 states, 3 time steps")
    add_parallel_arguments(ap)
    args = ap.parse_args()
    n_states, dts = (20, [0.001, 0.01, 0.06]) if args.quick else (1000, DTS)
    with parallel(args) as client:
        out = run(32, n_states, dts, workers=args.workers, client=client)
    name = "fig2_quasi_newton_quick" if args.quick else "fig2_quasi_newton"
    write_json(f"{name}.json", {"n_links": 32, "n_states": n_states, "parallel": parallel_description(args),
                                "results": out})
    plot(out, f"{RESULTS}/{name}.png")
    if not args.quick:
        update_readme_section("fig2", table(out))
    for method in METHODS:
        for r in out[method]:
            t = f"{r['mean_seconds'] * 1e6:.1f} µs" if r["mean_seconds"] else "-"
            it = f"{r['mean_iterations']:.2f}" if r["mean_iterations"] else "-"
            branch = (f"  roots on / off the physical branch {r['roots_on_branch']} / {r['roots_off_branch']}"
                      if "roots_on_branch" in r else "")
            print(f"{method:13s} dt={r['dt']:<6} success {100 * r['success_rate']:5.1f}%  iterations {it:>6}  time {t}"
                  f"{branch}")


if __name__ == "__main__":
    main()
