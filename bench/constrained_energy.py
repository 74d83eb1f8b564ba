"""Energy and constraints of constrained rollouts over 10^4 steps: the four-bar (loop closure)
and the 5-link pendulum with its tip pinned (dt = 0.01), the slider-crank (dt = 0.005), s = 1, 2, 3.

    python bench/constrained_energy.py [--quick]

Reports max |h| at every control point, the velocity constraint |Dh q̇| / |q̇| of the reported
velocities, and the relative energy error (max, mean of the first and of the last tenth) with
velocities read back on the constraint manifold (Integrator.velocity, the KKT projection), next
to the read-back q̇ = M^{-1} p used before (which leaves the manifold). Writes
bench/results/constrained_energy.json and the table in bench/README.md.
"""
from __future__ import annotations

import os
import sys
import time

import numpy as np

from common import ROOT, publish, study_parser, write_json

sys.path.insert(0, os.path.join(ROOT, "tests"))
import hovi  # noqa: E402
from mechanisms import fourbar, pinned_chain, slider_crank  # noqa: E402


def cases():
    chain, q_pin = pinned_chain(5)
    return [("four-bar", fourbar(), [-1.2, 0.9, -1.8], [1.0, 0, 0], 0.01),
            ("pinned 5-link chain", chain, q_pin + 0.05, np.zeros(5), 0.01),
            ("slider-crank", slider_crank(), [0.6, -1.0], [2.0, 0.0], 0.005)]


# (s, Newton tolerance): the default tol = 1e-10 and, for s = 3, a tighter one (see README).
SETTINGS = [(1, 1e-10), (2, 1e-10), (3, 1e-10), (3, 1e-12)]


def energy_stats(E):
    err = np.abs(E - E[0]) / abs(E[0])
    tenth = max(len(err) // 10, 1)
    return {"max": float(err.max()), "first_tenth": float(err[1:tenth + 1].mean()),
            "last_tenth": float(err[-tenth:].mean())}


def run_case(name, model, q0, qd0, dt, s, tol, steps):
    integ = hovi.Integrator(model, s=s, dt=dt, tol=tol)
    q, qd = integ.project(np.asarray(q0, float), np.asarray(qd0, float))
    t0 = time.perf_counter()
    traj = integ.rollout(q, steps, qdot0=qd)
    seconds = time.perf_counter() - t0
    V = traj.qdot
    h = np.array([model.constraint_values(x) for x in traj.control_points.reshape(-1, model.n)])
    vc = max(np.abs(model.constraint_jacobian(x) @ v).max() / max(np.abs(v).max(), 1e-300) for x, v in zip(traj.q, V))
    raw = np.array([model.energy(x, np.linalg.solve(model.mass_matrix(x), p)) for x, p in zip(traj.q, traj.p)])
    return {"mechanism": name, "s": s, "tol": tol, "dt": dt, "steps": steps, "seconds": seconds, "max_h": float(np.abs(h).max()),
            "velocity_constraint": float(vc), "energy": energy_stats(traj.energy), "energy_minv_p": energy_stats(raw)}


def main():
    ap = study_parser(__doc__, "500 steps, no README update")
    args = ap.parse_args()
    steps = 500 if args.quick else 10_000
    rows = []
    for name, model, q0, qd0, dt in cases():
        for s, tol in SETTINGS:
            rows.append(run_case(name, model, q0, qd0, dt, s, tol, steps))
            r = rows[-1]
            print(f"{name}, s = {s}, tol {tol:g}: max |h| {r['max_h']:.1e}, energy {r['energy']['max']:.2e}", flush=True)
    write_json("constrained_energy_quick.json" if args.quick else "constrained_energy.json", {"rows": rows})
    lines = [f"| mechanism | dt | s | tol | max \\|h\\| | max \\|Dh q̇\\|/\\|q̇\\| | energy error: max | first tenth | last tenth "
             f"| with q̇ = M⁻¹p: max |", "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        e, raw = r["energy"], r["energy_minv_p"]
        lines.append(f"| {r['mechanism']} | {r['dt']} | {r['s']} | {r['tol']:g} | {r['max_h']:.1e} | {r['velocity_constraint']:.1e} | "
                     f"{e['max']:.2e} | {e['first_tenth']:.2e} | {e['last_tenth']:.2e} | {raw['max']:.2e} |")
    publish("constrained_energy", "\n".join(lines), args.quick)


if __name__ == "__main__":
    main()
