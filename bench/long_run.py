"""Long runs: 10^6 steps of the 12-link pendulum (the paper's Fig. 4 set-up: q0 uniform in
[-pi/12, pi/12], zero velocity) with the variational integrators s = 1, 2, 3 at dt = 0.01.

The run goes in rollouts of CHUNK steps, each continuing from the last state, so that memory
stays bounded and its growth is visible: the resident set size (VmRSS of /proc/self/status) is
read before the first chunk and after every chunk; the growth over the last nine tenths of the run
(after the allocator has settled) is what a leak would show. Per run: the
relative energy error |E - E0| / |E0| at every step (largest, and the means over the first and
the last tenth of the run, whose ratio shows drift), the least-squares drift over the run, the
Newton iterations and failed steps, and the run time.

    python bench/long_run.py            # 10^6 steps each, results/long_run.json and bench/README.md
    python bench/long_run.py --quick    # 10^4 steps each (the test suite)
"""
from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import update_readme_section, write_json  # noqa: E402

import hovi  # noqa: E402

DT = 0.01
CHUNK = 10_000


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS:")) / 1024


def long_run(s: int, steps: int, chunk: int) -> dict:
    model = hovi.examples.models.pendulum(12)
    q = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, 12)
    integ = hovi.Integrator(model, s=s, dt=DT)
    p = integ.momentum(q, np.zeros(12))
    E0 = integ.energy(q, p)
    err = np.full(steps + 1, np.nan)  # written now: its pages are resident before "before"
    err[0] = 0.0
    iterations = failed = done = 0
    rss_before, rss_trace = rss_mb(), []
    t0 = time.perf_counter()
    while done < steps:
        n = min(chunk, steps - done)
        traj = integ.rollout(q, n, p0=p, raise_on_failure=False)
        err[done + 1:done + 1 + traj.steps] = np.abs(traj.energy[1:] - E0) / abs(E0)
        iterations += int(traj.iterations.sum())
        done += traj.steps
        rss_trace.append(rss_mb())
        if traj.steps < n:  # a failed step ends the run: recorded, not hidden
            failed += 1
            break
        q, p = traj.q[-1], traj.p[-1]
    seconds = time.perf_counter() - t0
    err = err[:done + 1]
    tenth = max(1, done // 10)
    t = np.arange(done + 1) * DT
    signed_drift = float(np.polyfit(t, err, 1)[0] * t[-1]) if done > 1 else 0.0
    return {"s": s, "dt": DT, "steps": done, "requested_steps": steps, "failed_steps": failed, "E0": E0,
            "max_rel_energy_error": float(err.max()), "mean_first_tenth": float(err[1:tenth + 1].mean()),
            "mean_last_tenth": float(err[-tenth:].mean()), "fitted_drift_over_run": signed_drift,
            "newton_iterations": iterations, "iterations_per_step": iterations / max(done, 1),
            "rss_mb": {"before": rss_before, "after_first_tenth": rss_trace[max(0, len(rss_trace) // 10 - 1)],
                       "after": rss_trace[-1], "trace": rss_trace}, "seconds": seconds}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="10^4 steps each")
    ap.add_argument("--steps", type=int, default=0, help="steps per run (default 10^6, quick 10^4)")
    args = ap.parse_args()
    steps = args.steps or (10_000 if args.quick else 1_000_000)
    chunk = min(CHUNK, max(1, steps // 10))
    runs = []
    for s in (1, 2, 3):
        r = long_run(s, steps, chunk)
        runs.append(r)
        print(f"s={s}: {r['steps']} steps in {r['seconds']:.0f} s, max rel. energy error {r['max_rel_energy_error']:.2e}, "
              f"first/last tenth {r['mean_first_tenth']:.2e}/{r['mean_last_tenth']:.2e}, RSS before, after a tenth, at "
              f"the end {[round(r['rss_mb'][k], 1) for k in ('before', 'after_first_tenth', 'after')]} MB", flush=True)
    path = write_json("long_run_quick.json" if args.quick else "long_run.json",
                      {"model": "pendulum(12)", "chunk": chunk, "runs": runs})
    print(path)
    if not args.quick:
        rows = ["| s | dt | steps | failed | max rel. energy error | mean, first tenth | mean, last tenth | "
                "fitted drift over the run | Newton iterations / step | RSS before, after a tenth, at the end (MB) | run time |",
                "|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in runs:
            m = r["rss_mb"]
            rows.append(f"| {r['s']} | {r['dt']} | {r['steps']} | {r['failed_steps']} | {r['max_rel_energy_error']:.2e} | "
                        f"{r['mean_first_tenth']:.2e} | {r['mean_last_tenth']:.2e} | {r['fitted_drift_over_run']:.1e} | "
                        f"{r['iterations_per_step']:.2f} | {m['before']:.1f}, {m['after_first_tenth']:.1f}, "
                        f"{m['after']:.1f} | {r['seconds']:.0f} s |")
        update_readme_section("long_run", "\n".join(rows))
    if any(r["failed_steps"] for r in runs):
        sys.exit("a long run stopped at a failed step")


if __name__ == "__main__":
    main()
