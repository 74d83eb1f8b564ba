"""Numerical stability under stress: for each integrator (the variational integrators s = 1, 2, 3
and Hermite-Simpson collocation) on the 12-link pendulum (q0 uniform in [-pi/12, pi/12],
qdot0 = 0): the largest dt at which 2 s rollouts still converge from at least 99% of the initial
conditions, and the energy error over 10^5 steps at that dt, or, where a 10^5-step run does not
complete there, at the largest smaller dt of the grid where it does (both recorded).

    python bench/stability.py [--quick] [--workers N] [--scheduler ADDRESS|local]

The rollouts of the variational integrators run as one batch per dt: on --workers C++ threads
(Integrator.rollout_batch) or on a Dask cluster (--scheduler, hovi.distributed.rollout_batch),
with the same results; Hermite-Simpson's run one by one.

Writes bench/results/stability.json and .png, and the table in bench/README.md.
"""
from __future__ import annotations

import argparse

import numpy as np
from tqdm import tqdm

import hovi
import hovi.distributed
from hovi.baselines import HermiteSimpson
from common import RESULTS, add_parallel_arguments, parallel, parallel_description, update_readme_section, write_json

DTS = [0.01, 0.02, 0.04, 0.06, 0.08, 0.1, 0.12, 0.15, 0.2, 0.25, 0.3]
NAMES = ["VI s=1 (trapezoidal)", "VI s=2 (Simpson)", "VI s=3", "Hermite-Simpson"]


def make(name, model, dt):
    """A function q0 -> (converged, q, energy) for `steps` steps."""
    if name.startswith("VI"):
        integ = hovi.Integrator(model, s=int(name[5]), dt=dt)

        def run(q0, steps):
            traj = integ.rollout(q0, steps, raise_on_failure=False)
            ok = traj.converged and traj.steps == steps
            return ok, (traj.energy if ok else None)
        return run
    hs = HermiteSimpson(model, dt)

    def run(q0, steps):
        d = hs.rollout(q0, np.zeros(model.n), steps)
        ok = d["steps"] == steps
        return ok, (np.array([model.energy(q, v) for q, v in zip(d["q"], d["v"])]) if ok else None)
    return run


def converged_share(name, model, dt, q0s, steps, workers, client):
    """The share of the rollouts from q0s (at rest) that complete `steps` steps."""
    if not name.startswith("VI"):
        run = make(name, model, dt)
        return float(np.mean([run(q0, steps)[0] for q0 in q0s]))
    integ = hovi.Integrator(model, s=int(name[5]), dt=dt)
    if client is None:
        batch = integ.rollout_batch(q0s, steps, threads=workers)
    else:
        batch = hovi.distributed.rollout_batch(integ, q0s, steps, client=client)
    return float(np.mean(batch.converged & (batch.steps == steps)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="10 initial conditions, 1000 energy steps")
    add_parallel_arguments(ap)
    args = ap.parse_args()
    with parallel(args) as client:
        study(args, client)


def study(args, client):
    model = hovi.models.pendulum(12)
    n_states, energy_steps, T = (10, 1000, 0.5) if args.quick else (100, 100_000, 2.0)
    dts = DTS[:4] if args.quick else DTS
    q0s = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, (n_states, 12))
    success = {}
    for name in NAMES:
        success[name] = {}
        for dt in tqdm(dts, desc=name):
            steps = max(1, int(round(T / dt)))
            success[name][dt] = converged_share(name, model, dt, q0s, steps, args.workers, client)
            if success[name][dt] < 0.5:  # far beyond the limit: larger steps only fail more
                break
    largest = {name: max([dt for dt, r in success[name].items() if r >= 0.99], default=None) for name in NAMES}
    energy = {}
    for name in NAMES:
        if largest[name] is None:
            continue
        tried = []
        for dt in sorted([d for d in dts if d <= largest[name]], reverse=True):
            ok, E = make(name, model, dt)(q0s[0], energy_steps)
            tried.append(dt)
            if ok:
                break
        if not ok:
            energy[name] = {"dt": None, "tried": tried, "completed": False}
            continue
        rel = np.abs(E - E[0]) / abs(E[0])
        tenth = len(rel) // 10
        energy[name] = {"dt": dt, "tried": tried, "completed": True, "max_rel": float(rel.max()),
                        "first_tenth_mean": float(rel[1:tenth].mean()), "last_tenth_mean": float(rel[-tenth:].mean()),
                        "trace": rel[:: max(1, len(rel) // 2000)].tolist()}
    name = "stability_quick" if args.quick else "stability"
    write_json(f"{name}.json", {"n_links": 12, "states": n_states, "rollout_T": T, "energy_steps": energy_steps,
                                "parallel": parallel_description(args),
                                "success": {k: {str(dt): v for dt, v in d.items()} for k, d in success.items()},
                                "largest_dt_99": largest, "energy": energy})
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.3))
    for nm in NAMES:
        d = success[nm]
        axes[0].plot(list(d), [100 * v for v in d.values()], "o-", label=nm)
        e = energy.get(nm)
        if e and e.get("completed"):
            t = np.arange(len(e["trace"])) * (energy_steps / len(e["trace"])) * e["dt"]
            axes[1].semilogy(t, np.maximum(e["trace"], 1e-17), lw=0.8, label=f"{nm}, dt = {e['dt']}")
    axes[0].set_xlabel("dt [s]")
    axes[0].set_ylabel(f"% of {n_states} rollouts of {T} s that converge")
    axes[0].set_title("(a) convergence against dt")
    axes[1].set_xlabel("time [s]")
    axes[1].set_ylabel("|E - E0| / |E0|")
    axes[1].set_title(f"(b) energy error over {energy_steps} steps")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(f"{RESULTS}/{name}.png", dpi=120)
    plt.close(fig)
    lines = [f"| integrator | largest dt with ≥ 99% of {n_states} rollouts converged | dt of the {energy_steps}-step run "
             "(tried) | relative energy error: max / mean first tenth / mean last tenth |", "|---|---|---|---|"]
    for nm in NAMES:
        e = energy.get(nm)
        if not e:
            lines.append(f"| {nm} | {largest[nm]} | – | – |")
            continue
        cell = ("no dt of the grid completed" if not e["completed"] else
                f"{e['max_rel']:.1e} / {e['first_tenth_mean']:.1e} / {e['last_tenth_mean']:.1e}")
        lines.append(f"| {nm} | {largest[nm]} | {e['dt']} ({', '.join(map(str, e['tried']))}) | {cell} |")
    text = "\n".join(lines)
    print(text)
    if not args.quick:
        update_readme_section("stability", text)


if __name__ == "__main__":
    main()
