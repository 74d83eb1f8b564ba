"""Energy error against run time: hovi's variational integrators (s = 1..4) and Hermite-Simpson
against MuJoCo's RK4, Euler and implicitfast over 10^5 fixed steps of the n-link pendulum
(n = 12 and 32) released at rest from q0 uniform in ±π/12, two dts per method.

Relative energy error |E - E0| / |E0| at every step: its maximum and its means over the first and
the last tenth of the run. hovi's energies are ``traj.energy`` (q̇ read back from the discrete
momenta), Hermite-Simpson's ``model.energy(q, v)``, MuJoCo's ``mjData.energy`` (energy flag on, its
agreement with hovi's energy checked first, with the mass matrices and accelerations). Run time as
in pareto.py: the C++ loops' own time, MuJoCo's rollout with the energy flag off.

    python bench/energy_runtime.py [--quick] [--states 3]

Writes bench/results/energy_runtime.json and .png, and the table in bench/README.md (full mode).
"""
from __future__ import annotations


import numpy as np
from tqdm import tqdm

import mujoco_model as mjm
import hovi
from common import RESULTS, publish, save_figure, study_parser, write_json
from pareto import OPTIONS, integrator_defaults, method

DTS = {"VI s=1": [0.01, 0.005], "VI s=2": [0.01, 0.005], "VI s=3": [0.02, 0.01], "VI s=4": [0.02, 0.01],
       "Hermite-Simpson": [0.01, 0.005], "MuJoCo RK4": [0.005, 0.002], "MuJoCo Euler": [1e-3, 2e-4],
       "MuJoCo implicitfast": [1e-3, 2e-4]}
LINKS = [12, 32]


def energy_stats(E):
    rel = np.abs(E - E[0]) / abs(E[0])
    tenth = max(1, len(rel) // 10)
    return {"max_rel": float(rel.max()), "first_tenth_mean": float(rel[1:tenth + 1].mean()),
            "last_tenth_mean": float(rel[-tenth:].mean())}, rel


def study(n, steps, n_states):
    model, inertias = hovi.examples.models.pendulum(n), mjm.pendulum_inertias(n)
    agreement = mjm.check(model, inertias)
    print(f"n = {n}: MuJoCo vs hovi, largest relative difference {agreement}")
    q0s = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, (n_states, n))
    runs = []
    for name, dts in DTS.items():
        for dt in tqdm(dts, desc=f"{name}, n = {n}"):
            run = method(name, model, dt, inertias)
            run(q0s[0], 100)  # warm-up (caches, first calls), not recorded
            per_state = []
            for i, q0 in enumerate(q0s):
                q, seconds, ok, energy = run(q0, steps)
                r = {"seconds": float(seconds), "converged": bool(ok)}
                if ok:
                    stats, rel = energy_stats(energy())
                    r.update(stats)
                    if i == 0:
                        r["trace"] = rel[::max(1, len(rel) // 2000)].tolist()
                per_state.append(r)
            done = [r for r in per_state if r["converged"]]
            runs.append({"method": name, "n": n, "dt": dt, "steps": steps, "horizon_s": steps * dt, "states": per_state,
                         "all_converged": len(done) == len(per_state),
                         "median_seconds": float(np.median([r["seconds"] for r in per_state])),
                         **{f"median_{k}": float(np.median([r[k] for r in done])) if done else None
                            for k in ("max_rel", "first_tenth_mean", "last_tenth_mean")}})
    return agreement, runs


def plot(runs, links, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker
    fig, axes = plt.subplots(2, len(links), figsize=(6 * len(links), 8.5), squeeze=False)
    for j, n in enumerate(links):
        top, bottom = axes[0][j], axes[1][j]
        for k, name in enumerate(DTS):
            rows = [r for r in runs if r["n"] == n and r["method"] == name and r["median_max_rel"] is not None]
            color = f"C{k}"
            top.loglog([r["median_seconds"] for r in rows], [r["median_max_rel"] for r in rows], "o-", color=color, label=name)
            top.loglog([r["median_seconds"] for r in rows], [r["median_last_tenth_mean"] for r in rows], "x:", color=color)
            for r in rows:
                top.annotate(f"{r['dt']:g}", (r["median_seconds"], r["median_max_rel"]), fontsize=6)
            if rows and "trace" in rows[-1]["states"][0]:
                trace = np.maximum(rows[-1]["states"][0]["trace"], 1e-17)
                t = np.linspace(0, rows[-1]["horizon_s"], len(trace))
                bottom.loglog(t[1:], trace[1:], "--" if name.startswith("MuJoCo") else "-", lw=0.7, color=color,
                              label=f"{name}, dt = {rows[-1]['dt']:g}")
        top.set_title(f"{n}-link pendulum, {runs[0]['steps']} steps (o: max, x: mean of the last tenth; labels: dt)",
                      fontsize=9)
        top.set_xlabel("run time [s] (median over states)")
        top.set_ylabel("|E - E0| / |E0|")
        bottom.set_title(f"{n}-link pendulum, first state, each method's smaller dt", fontsize=9)
        bottom.set_xlabel("simulated time [s]")
        bottom.set_ylabel("|E - E0| / |E0|")
        top.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        for ax in (top, bottom):
            ax.grid(True, which="both", alpha=0.3)
            ax.legend(fontsize=7)
    save_figure(fig, path)


def table(runs, n_states):
    lines = ["| n | method | dt | simulated [s] | run time [s] | per step [µs] | relative energy error: max / mean first tenth / "
             "mean last tenth |", "|---|---|---|---|---|---|---|"]
    for r in runs:
        failed = sum(not s["converged"] for s in r["states"])
        cell = ("failed" if r["median_max_rel"] is None else
                f"{r['median_max_rel']:.1e} / {r['median_first_tenth_mean']:.1e} / {r['median_last_tenth_mean']:.1e}")
        lines.append(f"| {r['n']} | {r['method']} | {r['dt']:g} | {r['horizon_s']:g} | {r['median_seconds']:.3g} | "
                     f"{r['median_seconds'] / r['steps'] * 1e6:.1f} | {cell}" + (f" ({failed} of {n_states} failed)" if failed else "")
                     + " |")
    lines += ["", f"Medians over {n_states} initial states; every run has {runs[0]['steps']} steps, so the simulated time "
              "is steps × dt and differs between rows."]
    return "\n".join(lines)


def main():
    ap = study_parser(__doc__, "n = 4, 1000 steps, 2 states")
    ap.add_argument("--states", type=int, default=3, help="initial states in full mode (default 3)")
    args = ap.parse_args()
    links, steps = ([4], 1000) if args.quick else (LINKS, 100_000)
    n_states = 2 if args.quick else args.states
    agreement, runs = {}, []
    for n in links:
        agreement[n], r = study(n, steps, n_states)
        runs += r
    name = "energy_runtime_quick" if args.quick else "energy_runtime"
    write_json(f"{name}.json", {"links": links, "steps": steps, "states": n_states, "options": OPTIONS, "integrator_defaults": integrator_defaults(),
                                "dts": DTS,
                                "mujoco_version": mjm.mujoco.__version__,
                                "mujoco_check_max_relative_difference": {str(n): a for n, a in agreement.items()},
                                "runs": runs})
    plot(runs, links, f"{RESULTS}/{name}.png")
    publish("energy_runtime", table(runs, n_states) + "\n\n" + mjm.describe(agreement), args.quick)


if __name__ == "__main__":
    main()
