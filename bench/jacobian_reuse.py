"""Can a rollout step reuse the previous step's factorisation of the DEL Jacobian?

A simplified Newton iteration that keeps the Jacobian J_{k-1} of step k-1 while solving step k
contracts asymptotically by the spectral radius rho = rho(I - J_{k-1}^{-1} J_k); keeping it pays
only where rho is well below the solver's reuse_contraction (0.1), and it diverges where rho > 1.
Measured on the Fig. 4 problem (the n-link pendulum released at rest from q0 uniform in ±π/12,
its horizon T per n) with the exact Jacobians of the converged steps (hovi.Linearizer, the
s n x s n window of the Newton direction), at steps spread evenly over the horizon.

    python bench/jacobian_reuse.py [--quick]

Writes bench/results/jacobian_reuse.json and the table in bench/README.md (full mode).
"""
from __future__ import annotations


import numpy as np

import hovi
from common import markdown_table, publish, study_parser, write_json

# (n, T, s, dts): the pendulums of pareto.py and steps from its sweeps (accurate to loose)
CASES = [(12, 10.0, 2, [0.005, 0.01, 0.02]), (12, 10.0, 4, [0.02, 0.04]),
         (32, 2.0, 2, [0.002, 0.005, 0.01]), (32, 2.0, 4, [0.01, 0.02]),
         (64, 1.0, 2, [0.001, 0.002, 0.005]), (64, 1.0, 3, [0.002, 0.004, 0.008])]
QUICK = [(6, 0.5, 2, [0.01])]


def newton_window(linearizer, control_points, s, n):
    """dr^{k,0..s-1} / dq^{k,1..s}: the matrix each Newton direction solves with."""
    return linearizer.del_jacobian(control_points, with_u=False).dq[:s * n, n:]


def stale_contraction(n, T, s, dt, samples):
    """rho(I - J_{k-1}^{-1} J_k) at `samples` steps k spread over the horizon, and cond(J_k)."""
    model = hovi.examples.models.pendulum(n)
    q0 = np.random.default_rng(n).uniform(-np.pi / 12, np.pi / 12, n)
    integ = hovi.Integrator(model, s=s, dt=dt)
    steps = int(round(T / dt))
    traj = integ.rollout(q0, steps)
    lin = hovi.Linearizer(integ)
    rhos, conds = [], []
    for k in np.unique(np.linspace(1, steps - 1, samples).astype(int)):
        J_old = newton_window(lin, traj.control_points[k - 1], s, n)
        J = newton_window(lin, traj.control_points[k], s, n)
        E = np.linalg.solve(J_old, J) - np.eye(s * n)
        rhos.append(float(np.max(np.abs(np.linalg.eigvals(E)))))
        conds.append(float(np.linalg.cond(J)))
    return rhos, conds


def main():
    ap = study_parser(__doc__, "n = 6, s = 2, one dt, 3 steps")
    args = ap.parse_args()
    cases, samples = (QUICK, 3) if args.quick else (CASES, 12)
    rows = []
    for n, T, s, dts in cases:
        for dt in dts:
            rhos, conds = stale_contraction(n, T, s, dt, samples)
            rows.append({"n": n, "s": s, "dt": dt, "T": T, "rho_median": float(np.median(rhos)),
                         "rho_max": float(np.max(rhos)), "cond_median": float(np.median(conds)), "rho": rhos})
            print(f"n={n:3d} s={s} dt={dt:6.3f}: rho median {np.median(rhos):8.3g}, max {np.max(rhos):8.3g}; "
                  f"cond(J) median {np.median(conds):.1e}", flush=True)
    write_json("jacobian_reuse_quick.json" if args.quick else "jacobian_reuse.json",
               {"samples": samples, "rows": rows})
    lines = markdown_table(["n", "s", "dt", "rho(I - J_{k-1}^{-1} J_k): median", "max", "cond(J_k), median"],
                           [[r["n"], r["s"], f"{r['dt']:g}", f"{r['rho_median']:.3g}", f"{r['rho_max']:.3g}",
                             f"{r['cond_median']:.1e}"] for r in rows])
    lines += ["", f"Exact DEL Jacobians at {samples} converged steps spread over each horizon (T = 10, 2, 1 s for "
              "n = 12, 32, 64); rho is the asymptotic contraction per iteration of a simplified Newton "
              "solve of step k with step k-1's factorisation."]
    publish("jacobian_reuse", "\n".join(lines), args.quick)


if __name__ == "__main__":
    main()
