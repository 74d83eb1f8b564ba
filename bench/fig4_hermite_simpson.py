"""Paper Fig. 4: the Simpson variational integrator against Hermite-Simpson direct collocation
(used as an implicit simulator) on the 12-link pendulum, T = 10 s, q0 uniform in
[-pi/12, pi/12], qdot0 = 0, over a dt sweep; with the trapezoidal (s = 1) and s = 3 variational
integrators as extra curves. Error (1/T) int ||q - q_ref|| dt against two references, the
paper's (Hermite-Simpson at dt = 5e-4) and a tight DOP853 solution of the forward dynamics
(rtol = atol = 1e-12, dense output); run time is the C++ loop's own time; and error against run
time, the plot a user picks an integrator from. Every solver runs at tol = 1e-12 so that the
errors measure the discretisation, not the Newton tolerance.

    python bench/fig4_hermite_simpson.py [--quick]

Writes bench/results/fig4_hermite_simpson.json and .png, and the table in bench/README.md.
"""
from __future__ import annotations


import numpy as np
from scipy.integrate import solve_ivp
from tqdm import tqdm

import hovi
from hovi.baselines import HermiteSimpson
from common import RESULTS, publish, save_figure, study_parser, write_json

DTS = [0.0025, 0.005, 0.01, 0.02, 0.04]
TOL = 1e-12


def dop853(model, q0, T):
    """The dense-output solution q(t) of the forward dynamics from (q0, 0)."""
    n = model.n

    def f(t, y):
        return np.concatenate([y[n:], model.forward_dynamics(y[:n], y[n:])])

    sol = solve_ivp(f, (0, T), np.concatenate([q0, np.zeros(n)]), method="DOP853", rtol=1e-12, atol=1e-12,
                    dense_output=True)
    assert sol.success
    return lambda times: sol.sol(times)[:n].T


def mean_error(q, q_ref, dt, T):
    e = np.linalg.norm(q - q_ref, axis=1)
    return float(np.trapezoid(e, dx=dt) / T)


def integrators(model, dt):
    """name -> function(q0, steps) -> (q on the grid, seconds, converged)."""
    def vi(s):
        integ = hovi.Integrator(model, s=s, dt=dt, tol=TOL)

        def run(q0, steps):
            traj = integ.rollout(q0, steps, raise_on_failure=False)
            return traj.q, traj.solve_seconds, traj.converged and traj.steps == steps
        return run

    hs = HermiteSimpson(model, dt, tol=TOL)

    def run_hs(q0, steps):
        d = hs.rollout(q0, np.zeros(model.n), steps)
        return d["q"], d["seconds"], d["steps"] == steps

    return {"VI s=1 (trapezoidal)": vi(1), "VI s=2 (Simpson)": vi(2), "VI s=3": vi(3), "Hermite-Simpson": run_hs}


def main():
    ap = study_parser(__doc__, "2 initial conditions, T = 1 s, two time steps")
    ap.add_argument("--states", type=int, default=100, help="initial conditions in full mode (default 100)")
    args = ap.parse_args()
    n_links, T = 12, (1.0 if args.quick else 10.0)
    dts = [0.01, 0.02] if args.quick else DTS
    n_states = 2 if args.quick else args.states
    model = hovi.examples.models.pendulum(n_links)
    rng = np.random.default_rng(0)
    q0s = rng.uniform(-np.pi / 12, np.pi / 12, (n_states, n_links))
    results = {}  # name -> dt -> lists
    dt_ref = 5e-4
    hs_ref = HermiteSimpson(model, dt_ref, tol=TOL)
    for q0 in tqdm(q0s, desc="initial conditions"):
        ref_hs = hs_ref.rollout(q0, np.zeros(n_links), int(round(T / dt_ref)))["q"]
        q_dop = dop853(model, q0, T)
        for dt in dts:
            steps = int(round(T / dt))
            ref_dop = q_dop(np.arange(steps + 1) * dt)
            ref_paper = ref_hs[::int(round(dt / dt_ref))]
            for name, run in integrators(model, dt).items():
                q, seconds, ok = run(q0, steps)
                r = results.setdefault(name, {}).setdefault(dt, {"err_dop853": [], "err_hs_ref": [], "seconds": [],
                                                                  "failed": 0})
                if not ok:
                    r["failed"] += 1
                    continue
                r["err_dop853"].append(mean_error(q, ref_dop, dt, T))
                r["err_hs_ref"].append(mean_error(q, ref_paper, dt, T))
                r["seconds"].append(seconds)
    summary = {name: [{"dt": dt, "failed": r["failed"],
                       **{k: float(np.mean(r[k])) if r[k] else None for k in ("err_dop853", "err_hs_ref", "seconds")}}
                      for dt, r in sorted(per_dt.items())] for name, per_dt in results.items()}
    name = "fig4_hermite_simpson_quick" if args.quick else "fig4_hermite_simpson"
    ratio = equal_time_ratio(summary)
    write_json(f"{name}.json", {"n_links": n_links, "T": T, "states": n_states, "tol": TOL, "summary": summary,
                                "simpson_over_hs_error_at_equal_time": ratio})
    plot(summary, f"{RESULTS}/{name}.png")
    publish("fig4", table(summary, ratio), args.quick)


def equal_time_ratio(summary):
    """Simpson-VI error / Hermite-Simpson error at equal run time (log-log interpolation of each
    error-vs-time curve, at the run times both cover), against the DOP853 reference."""
    def curve(name):
        pts = sorted((r["seconds"], r["err_dop853"]) for r in summary[name] if r["seconds"])
        return np.log(np.array(pts).T)
    tv, ev = curve("VI s=2 (Simpson)")
    th, eh = curve("Hermite-Simpson")
    lo, hi = max(tv.min(), th.min()), min(tv.max(), th.max())
    if lo >= hi:
        return None
    grid = np.linspace(lo, hi, 5)
    ratios = np.exp(np.interp(grid, tv, ev) - np.interp(grid, th, eh))
    return {"run_time_s": np.exp(grid).tolist(), "ratio": ratios.tolist()}


def plot(summary, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.3))
    for name, rows in summary.items():
        rows = [r for r in rows if r["seconds"]]
        dt = [r["dt"] for r in rows]
        axes[0].loglog(dt, [r["err_dop853"] for r in rows], "o-", label=name)
        axes[0].loglog(dt, [r["err_hs_ref"] for r in rows], ":", color=axes[0].lines[-1].get_color())
        axes[1].loglog(dt, [r["seconds"] for r in rows], "o-", label=name)
        axes[2].loglog([r["seconds"] for r in rows], [r["err_dop853"] for r in rows], "o-", label=name)
    axes[0].set_title("(a) error vs dt (solid: DOP853 ref., dotted: HS dt=5e-4 ref.)", fontsize=9)
    axes[0].set_xlabel("dt [s]")
    axes[0].set_ylabel("(1/T) ∫ ||q - q_ref|| dt")
    axes[1].set_title("(b) run time of a 10 s trajectory")
    axes[1].set_xlabel("dt [s]")
    axes[1].set_ylabel("s")
    axes[2].set_title("(c) error vs run time")
    axes[2].set_xlabel("run time [s]")
    axes[2].set_ylabel("error (DOP853 ref.)")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    save_figure(fig, path)


def table(summary, ratio):
    names = list(summary)
    dts = sorted({r["dt"] for rows in summary.values() for r in rows})
    lines = ["| dt | " + " | ".join(f"{n}: error / run time" for n in names) + " |",
             "|---|" + "---|" * len(names)]
    for dt in dts:
        cells = []
        for n in names:
            r = next(r for r in summary[n] if r["dt"] == dt)
            cells.append("failed" if r["seconds"] is None else
                         f"{r['err_dop853']:.2e} / {r['seconds'] * 1e3:.1f} ms" + (f" ({r['failed']} failed)" if r["failed"] else ""))
        lines.append(f"| {dt} | " + " | ".join(cells) + " |")
    if ratio:
        lines.append("")
        lines.append("Simpson VI error / Hermite-Simpson error at equal run time: " + ", ".join(
            f"{x:.2f} at {t * 1e3:.0f} ms" for t, x in zip(ratio["run_time_s"], ratio["ratio"])))
    return "\n".join(lines)


if __name__ == "__main__":
    main()
