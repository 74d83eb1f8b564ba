"""The crossover between the two exact Newton directions: Algorithms A.1/A.2 (recursive,
O(s^3 n)) and a dense LU of the DEL Jacobian from the linearisation (O(s^2 n^2) + O(s^3 n^3)).
Each is timed as it is used, per step of a rollout of the n-link pendulum (one factorisation
per step with simplified Newton, plus the residual evaluations and solves), q0 uniform in
±π/12 from rest, dt = 0.005; best of 3 rollouts. The automatic choice (direction='auto') takes
the dense path up to the largest n at which it won here, per s (dense_direction.cpp).

    python bench/direction_crossover.py [--quick]

Writes bench/results/direction_crossover.json and the table in bench/README.md.
"""
from __future__ import annotations


import numpy as np

import hovi
from common import best_rollout, markdown_table, publish, study_parser, write_json

NS = [2, 4, 8, 12, 16, 24, 32, 48]


def per_step_seconds(model, s, direction, q0, steps, repeats):
    integ = hovi.Integrator(model, s=s, dt=0.005, direction=direction)
    return best_rollout(integ, q0, steps, repeats)


def main():
    ap = study_parser(__doc__, "s = 1, 2; n = 4, 16; 20 steps")
    args = ap.parse_args()
    ss, ns = ([1, 2], [4, 16]) if args.quick else ([1, 2, 3, 4], NS)
    steps, repeats = (20, 1) if args.quick else (200, 3)
    rows = []
    for s in ss:
        for n in ns:
            model = hovi.examples.models.pendulum(n)
            q0 = np.random.default_rng(n).uniform(-np.pi / 12, np.pi / 12, n)
            t_rec, it, fac = per_step_seconds(model, s, "recursive", q0, steps, repeats)
            t_den, _, _ = per_step_seconds(model, s, "dense", q0, steps, repeats)
            auto = hovi.Integrator(model, s=s, dt=0.005).direction_path
            rows.append({"s": s, "n": n, "recursive_us": t_rec * 1e6, "dense_us": t_den * 1e6, "iterations": it,
                         "factorizations": fac, "auto": auto, "faster": "dense" if t_den < t_rec else "recursive"})
            print(f"s={s} n={n:3d}: recursive {t_rec * 1e6:8.1f} µs/step, dense {t_den * 1e6:8.1f} µs/step, "
                  f"auto -> {auto}", flush=True)
    crossover = {s: max([r["n"] for r in rows if r["s"] == s and r["faster"] == "dense"], default=0) for s in ss}
    write_json("direction_crossover_quick.json" if args.quick else "direction_crossover.json",
               {"dt": 0.005, "steps": steps, "rows": rows, "crossover": crossover})
    lines = markdown_table(
        ["s", "n", "recursive [µs/step]", "dense [µs/step]", "dense / recursive", "auto picks", "faster"],
        [[r["s"], r["n"], f"{r['recursive_us']:.1f}", f"{r['dense_us']:.1f}", f"{r['dense_us'] / r['recursive_us']:.2f}",
          r["auto"], r["faster"]] for r in rows])
    lines += ["", "Largest n at which the dense path was faster: " +
              ", ".join(f"s = {s}: {c}" for s, c in crossover.items()) + "."]
    publish("direction_crossover", "\n".join(lines), args.quick)


if __name__ == "__main__":
    main()
