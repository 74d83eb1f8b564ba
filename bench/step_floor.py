"""A lower bound on hovi's run time at the loose end of pareto.py's table.

The cheapest converged step the Newton solver can take is one factorisation of the DEL Jacobian,
two DEL evaluations and two solves. Its cost is measured where every step does exactly that: a
rollout of the same pendulum at dt / 8 (step_tol 1e-10, the loose stop of pareto.py's table; the
cost of those operations does not depend on dt). That floor times the steps each VI needs for an
error level (its dt from the committed pareto run: log-log interpolation between the sweep's
points where every state converged, or, past its largest such dt, extrapolation by the order 2s)
is a lower bound on the VI's run time there, compared with MuJoCo RK4's from the same run.

    python bench/step_floor.py [--quick]

Reads bench/results/pareto.json; writes bench/results/step_floor.json and the table in
bench/README.md (full mode).
"""
from __future__ import annotations

import json

import numpy as np

import hovi
from common import COMMITTED, best_rollout, study_parser, update_readme_section, write_json

LEVELS = [1e-3, 1e-4]
ORDERS = [2, 3, 4]


def dt_for_level(runs, n, s, level):
    """(dt at which the VI s reaches `level`, extrapolated?) from pareto.json's runs, or None."""
    pts = sorted((r["dt"], r["median_error"]) for r in runs
                 if r["n"] == n and r["method"] == f"VI s={s}" and r["all_converged"])
    if not pts:
        return None
    for (d0, e0), (d1, e1) in zip(pts, pts[1:]):
        if e0 <= level <= e1:
            w = np.log(level / e0) / np.log(e1 / e0)
            return float(d0 * (d1 / d0) ** w), False
    d, e = pts[-1]
    return (float(d * (level / e) ** (1 / (2 * s))), True) if e < level else None


def floor_seconds(n, s, dt, steps, repeats):
    """Per step: the fastest of `repeats` rollouts at dt where each step is one factorisation and two iterations."""
    model = hovi.examples.models.pendulum(n)
    q0 = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, n)
    integ = hovi.Integrator(model, s=s, dt=dt, step_tol=1e-10)
    return best_rollout(integ, q0, steps, repeats)


def main():
    ap = study_parser(__doc__, "n = 12, s = 2, 1e-3 only, 20 steps")
    args = ap.parse_args()
    with open(f"{COMMITTED}/pareto.json") as f:
        pareto = json.load(f)
    rk4 = {(r["n"], r["level"]): r["rk4_seconds"] for r in pareto["equal_error_table"]}
    ns, orders, levels = ([12], [2], [1e-3]) if args.quick else ([int(n) for n in pareto["problems"]], ORDERS, LEVELS)
    rows = []
    for n in ns:
        T = pareto["problems"][str(n)]
        for s in orders:
            found = {level: dt_for_level(pareto["runs"], n, s, level) for level in levels}
            if not any(found.values()):
                continue
            dt = min(d for d, _ in filter(None, found.values())) / 8
            per_step, it, fac = floor_seconds(n, s, dt, 20 if args.quick else int(min(T, 0.2 if n > 12 else 1.0) / dt),
                                              1 if args.quick else 3)
            for level, hit in found.items():
                if hit is None or rk4.get((n, level)) is None:
                    continue
                steps = T / hit[0]
                rows.append({"n": n, "s": s, "level": level, "dt": hit[0], "extrapolated": hit[1], "steps": steps,
                             "floor_us": per_step * 1e6, "iterations": it, "factorizations": fac,
                             "bound_seconds": steps * per_step, "rk4_seconds": rk4[(n, level)],
                             "ratio": steps * per_step / rk4[(n, level)]})
                print(f"n={n} s={s} level={level:g}: {per_step * 1e6:.1f} µs x {steps:.0f} steps "
                      f"({it:.2f} iterations, {fac:.2f} factorisations per step) >= {rows[-1]['ratio']:.2f} x RK4",
                      flush=True)
    write_json("step_floor_quick.json" if args.quick else "step_floor.json", {"rows": rows})
    if args.quick:
        return
    lines = ["| n | level | s | floor per step | steps | lower bound / RK4's run time |", "|---|---|---|---|---|---|"]
    for r in sorted(rows, key=lambda r: (r["n"], -r["level"], r["s"])):
        mark = " (dt extrapolated)" if r["extrapolated"] else ""
        lines.append(f"| {r['n']} | {r['level']:.0e} | {r['s']} | {r['floor_us']:.1f} µs | {r['steps']:.0f}{mark} | "
                     f"≥ {r['ratio']:.2f} |")
    lines += ["", "Floor: per step of a rollout at dt / 8 (every step one factorisation and two iterations, "
              "step_tol 1e-10; fastest of 3); steps and RK4's run time from the committed pareto run."]
    update_readme_section("step_floor", "\n".join(lines))


if __name__ == "__main__":
    main()
