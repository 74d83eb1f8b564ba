"""Numerical stability under stress: for each integrator (the variational integrators s = 1, 2, 3
and Hermite-Simpson collocation) on the 12-link pendulum (q0 uniform in [-pi/12, pi/12],
qdot0 = 0): the largest dt at which 2 s rollouts still converge from at least 99% of the initial
conditions, and the energy error over 10^5 steps at that dt, or, where a 10^5-step run does not
complete there, at the largest smaller dt of the grid where it does (both recorded).

    python bench/stability.py [--quick] [--stress] [--workers N] [--scheduler ADDRESS|local]

The rollouts of the variational integrators run as one batch per dt: on --workers C++ threads
(Integrator.rollout_batch) or on a Dask cluster (--scheduler, hovi.distributed.rollout_batch),
with the same results; Hermite-Simpson's run one by one.

Writes bench/results/stability.json and .png, and the table in bench/README.md.

The stress matrix (stability_stress.json and its table): chains of n = 2..128 links
(the pendulum), s = 1..4, dt from 1e-5 up to the failure point (the first dt at which fewer
than half the steps converge), under each condition of CONDITIONS (stiff springs up to 1e8,
large velocities, a floating base next to its Euler-angle singularity). Each cell takes single
steps from random states and records the share that converges and the failure statuses; every
step reported converged is checked independently: finite, and one more exact Newton correction at
its control points below SILENT_TOL (1 + |q|), else it is counted as a silent failure.
"""
from __future__ import annotations

import sys
import time
from collections import Counter

import numpy as np
from tqdm import tqdm

import hovi
import hovi.distributed
from hovi.baselines import HermiteSimpson
from common import RESULTS, add_parallel_arguments, parallel, parallel_description, publish, save_figure, study_parser, update_readme_section, write_json

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
    ap = study_parser(__doc__, "10 initial conditions, 1000 energy steps")
    ap.add_argument("--stress", action="store_true", help="only the stress matrix")
    add_parallel_arguments(ap)
    args = ap.parse_args()
    if args.stress:
        return stress_matrix(args.quick)
    with parallel(args) as client:
        study(args, client)


def study(args, client):
    model = hovi.examples.models.pendulum(12)
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
    save_figure(fig, f"{RESULTS}/{name}.png")
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
    publish("stability", "\n".join(lines), args.quick)
    stress_matrix(args.quick)


# ---- The stress matrix ------------------------------------------------------------------------

STRESS_DTS = [1e-5, 1e-4, 1e-3, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5]
SILENT_TOL = 1e-8  # a converged step's next exact Newton correction, relative to 1 + |q|
PITCH_OFFSET = 1e-4  # the floating base's pitch: pi/2 - PITCH_OFFSET, M(q) condition ~ 1/offset^2


def floating_pendulum(n, length=0.5, mass=1.0, radius=0.02):
    """hovi.examples.models.pendulum(n) whose joint 1 is replaced by a floating base (x, y, z, then Z-Y-X
    Euler angles, as Model.from_urdf(base='euler')) carrying link 1: n + 5 joints."""
    model = hovi.Model()
    base = [("prismatic", [1, 0, 0]), ("prismatic", [0, 1, 0]), ("prismatic", [0, 0, 1]),
            ("revolute", [0, 0, 1]), ("revolute", [0, 1, 0])]
    for k, (kind, axis) in enumerate(base):
        model.add_body(f"base{k}", parent=k - 1 if k else None, joint_type=kind, axis=axis)
    transverse, axial = mass * (3 * radius ** 2 + length ** 2) / 12, mass * radius ** 2 / 2
    for i in range(n):
        placement = np.eye(4)
        placement[2, 3] = 0.0 if i == 0 else -length
        model.add_body(f"link{i + 1}", parent=len(base) + i - 1, axis=[1, 0, 0] if i % 2 == 0 else [0, 1, 0],
                       placement=placement, mass=mass, com=[0, 0, -length / 2],
                       inertia=np.diag([transverse, transverse, axial]))
    return model


def stress_case(condition, n, rng):
    """(model, q0, qdot0) of one random state of a condition."""
    if condition == "near_singular":
        model = floating_pendulum(n)
        q = np.concatenate([rng.uniform(-0.1, 0.1, 4), [np.pi / 2 - PITCH_OFFSET], rng.uniform(-0.2, 0.2, n)])
        return model, q, rng.uniform(-0.5, 0.5, model.n)
    model = hovi.examples.models.pendulum(n)
    q = rng.uniform(-np.pi / 12, np.pi / 12, n)
    if condition.startswith("stiff"):
        for j in range(n):
            model.add_spring(j, float(condition.split()[1]))
        return model, q, np.zeros(n)
    if condition.startswith("fast"):
        return model, q, rng.uniform(-1, 1, n) * float(condition.split()[1])
    return model, q, np.zeros(n)


CONDITIONS = ["nominal", "stiff 1e4", "stiff 1e6", "stiff 1e8", "fast 10", "fast 100", "near_singular"]


def stress_cell(condition, n, s, dt, states, seed):
    """Single steps from `states` random states: converged share, statuses, silent failures."""
    rng = np.random.default_rng(seed)
    statuses, silent, worst = Counter(), 0, 0.0
    model = integ = None
    for _ in range(states):
        m, q0, qd0 = stress_case(condition, n, rng)
        if model is None:
            model, integ = m, hovi.Integrator(m, s=s, dt=dt)
        p0 = integ.momentum(q0, qd0)
        q1, p1, info = integ.step(q0, p0, raise_on_failure=False)
        statuses[info.status] += 1
        if info.converged:  # the solver's claim, checked: finite, and at the root to round-off
            finite = np.isfinite(q1).all() and np.isfinite(p1).all()
            correction = np.abs(integ.newton_direction(info.control_points, p0)).max() if finite else np.inf
            rel = correction / (1 + np.abs(info.control_points).max())
            worst = max(worst, rel)
            silent += not (rel <= SILENT_TOL)
    return {"condition": condition, "n": n, "s": s, "dt": dt, "steps": states,
            "converged": statuses["converged"] / states, "statuses": dict(statuses), "silent": silent,
            "worst_next_correction": worst}


def stress_matrix(quick):
    ns, ss, states = ([2, 8], [1, 2], 3) if quick else ([2, 4, 8, 16, 32, 64, 128], [1, 2, 3, 4], 10)
    dts = STRESS_DTS[::3] if quick else STRESS_DTS
    t0 = time.perf_counter()
    cells = []
    for condition in CONDITIONS:
        for n in ns:
            for s in ss:
                for k, dt in enumerate(dts):
                    cell = stress_cell(condition, n, s, dt, states, seed=1000 * n + 10 * s + k)
                    cells.append(cell)
                    if cell["converged"] < 0.5:  # the failure point: larger steps only fail more
                        break
            print(f"stress {condition}: {len(cells)} cells, {time.perf_counter() - t0:.0f} s", flush=True)
    silent = sum(c["silent"] for c in cells)
    payload = {"conditions": CONDITIONS, "n": ns, "s": ss, "dts": dts, "states_per_cell": states,
               "silent_tol": SILENT_TOL, "pitch_offset": PITCH_OFFSET, "silent_failures": silent,
               "steps": sum(c["steps"] for c in cells), "seconds": time.perf_counter() - t0, "cells": cells}
    write_json("stability_stress_quick.json" if quick else "stability_stress.json", payload)
    text = stress_text(payload)
    print(text)
    if not quick:
        update_readme_section("stability_stress", text)
    if silent:
        sys.exit(f"{silent} steps reported converged are not at the root (next Newton correction > {SILENT_TOL})")


def stress_text(payload):
    """Per condition and s: the largest dt at which every step converged, per n; the failure
    statuses met; the worst next correction of a converged step."""
    lines = ["| condition | s | largest dt with every step converged, n = " + ", ".join(map(str, payload["n"])) +
             " | failure statuses met | worst next correction of a converged step |", "|---|---|---|---|---|"]
    for condition in payload["conditions"]:
        for s in payload["s"]:
            cells = [c for c in payload["cells"] if c["condition"] == condition and c["s"] == s]
            largest = []
            for n in payload["n"]:
                ok = [c["dt"] for c in cells if c["n"] == n and c["converged"] == 1.0]
                largest.append(str(max(ok)) if ok else "none")
            failures = Counter()
            for c in cells:
                failures.update({k: v for k, v in c["statuses"].items() if k != "converged"})
            worst = max(c["worst_next_correction"] for c in cells)
            lines.append(f"| {condition} | {s} | {' / '.join(largest)} | "
                         f"{', '.join(f'{k} ({v})' for k, v in sorted(failures.items())) or 'none'} | {worst:.1e} |")
    lines += ["", f"{payload['steps']} single steps ({payload['states_per_cell']} random states per cell, dt from "
              f"{payload['dts'][0]} up to the first dt where fewer than half converge) in {payload['seconds']:.0f} s: "
              f"{payload['silent_failures']} silent failures (a step reported converged whose next exact Newton "
              f"correction exceeds {payload['silent_tol']:g} (1 + |q|), or that is not finite). near_singular: the "
              f"pendulum on a floating base at pitch pi/2 - {payload['pitch_offset']:g} (Euler-angle singularity)."]
    return "\n".join(lines)


if __name__ == "__main__":
    main()
