"""Run time against error: hovi's variational integrators (s = 1..4) and its Hermite-Simpson
baseline against MuJoCo's fixed-step integrators (RK4, Euler, implicitfast) on the paper's Fig. 4
problem: the n-link pendulum released at rest from q0 uniform in ±π/12, error (1/T) ∫ ||q - q_ref|| dt
(trapezoid on the step grid) against DOP853 (rtol = atol = 1e-12) of hovi's forward dynamics,
n = 12 (T = 10 s), 32 (T = 2 s) and 64 (T = 1 s), over a log-spaced dt sweep per method.

Run time: hovi's ``traj.solve_seconds`` / the baseline's ``seconds`` (the C++ loops' own time) and
one call of MuJoCo's C rollout (bench/mujoco_model.py); model building and DOP853 are not timed.
MuJoCo's model is checked against hovi's (mass matrix, accelerations, poses, energy) first.

    python bench/pareto.py [--quick] [--states 20]

Writes bench/results/pareto.json and .png, and the table in bench/README.md (full mode).
"""
from __future__ import annotations

import inspect
import json

import numpy as np
from tqdm import tqdm

import mujoco_model as mjm
import hovi
from hovi.baselines import HermiteSimpson
from common import COMMITTED, RESULTS, save_figure, study_parser, update_readme_section, write_json
from fig4_hermite_simpson import dop853, mean_error

# Keyword options of each hovi method, in one place (a new solver option is one more entry). The
# Integrator's defaults converge each step to round-off (step_tol = 1e-15, residual test tol = 0
# off), so that the errors measure the discretisation; a tol > 0 would add a looser residual test.
# (Builds before the step_tol option stopped on the residual: give them {"tol": 1e-12}.)
# Each VI also runs with a looser solver stop, step_tol = 1e-10 ("VI s=k, step_tol 1e-10"), a
# curve of its own with its own measured errors: at the large steps of errors 1e-3 .. 1e-5 it
# changes the median error by under 2% and saves Newton iterations; at smaller errors its error
# floors. The envelope and the table take the faster of the two settings at each error level.
VI_OPTIONS = {}
LOOSE = {"step_tol": 1e-10}
VI_NAMES = [f"VI s={s}" for s in (1, 2, 3, 4)]
LOOSE_NAMES = [f"{name}, step_tol 1e-10" for name in VI_NAMES]
OPTIONS = {**{name: VI_OPTIONS for name in VI_NAMES}, **{name: LOOSE for name in LOOSE_NAMES},
           "Hermite-Simpson": {"tol": 1e-12}}
MUJOCO = {"MuJoCo RK4": "RK4", "MuJoCo Euler": "Euler", "MuJoCo implicitfast": "implicitfast"}
# dt sweeps per n: (largest, smallest, points), log-spaced, each dt then rounded so that T / dt is
# an integer; chosen so that each method's error spans ~1e-2 .. 1e-11 where its run time allows
# (measured at one state). The quick mode takes the two largest dts of the n = 12 sweeps.
SWEEPS = {
    12: {"VI s=1": (0.02, 2e-4, 7), "VI s=2": (0.04, 5e-4, 7), "VI s=3": (0.06, 2e-3, 6), "VI s=4": (0.08, 4e-3, 6),
         "Hermite-Simpson": (0.04, 5e-4, 7), "MuJoCo RK4": (0.02, 1e-4, 8), "MuJoCo Euler": (5e-3, 2e-5, 5),
         "MuJoCo implicitfast": (5e-3, 2e-5, 5)},
    32: {"VI s=1": (0.01, 5e-5, 7), "VI s=2": (0.02, 2.5e-4, 7), "VI s=3": (0.04, 1e-3, 6), "VI s=4": (0.04, 2.5e-3, 5),
         "Hermite-Simpson": (0.04, 2.5e-4, 7), "MuJoCo RK4": (0.02, 1e-4, 8), "MuJoCo Euler": (5e-3, 1e-5, 5),
         "MuJoCo implicitfast": (5e-3, 1e-5, 5)},
    64: {"VI s=1": (5e-3, 5e-5, 6), "VI s=2": (0.01, 2e-4, 6), "VI s=3": (0.015, 1e-3, 5), "VI s=4": (0.03, 2e-3, 5),
         "Hermite-Simpson": (0.02, 2.5e-4, 7), "MuJoCo RK4": (0.02, 1e-4, 8), "MuJoCo Euler": (5e-3, 1e-5, 5),
         "MuJoCo implicitfast": (5e-3, 1e-5, 5)},
}
for sweeps in SWEEPS.values():  # the loose-stop variants sweep the same dts as their VI
    sweeps.update({loose: sweeps[name] for name, loose in zip(VI_NAMES, LOOSE_NAMES)})
METHODS = list(SWEEPS[12])
PROBLEMS = {12: 10.0, 32: 2.0, 64: 1.0}  # n -> T
QUICK_PROBLEMS = {4: 0.5, 6: 0.5}
LEVELS = [10.0 ** -k for k in range(3, 11)]
# The footnote of runs recorded before --conditions existed (they all ran beside one other job).
LOADED = "Measured with one other single-threaded job on the machine's second core."


def integrator_defaults():
    """hovi.Integrator's keyword defaults in this build (the solver changes; the JSON records them)."""
    params = inspect.signature(hovi.Integrator.__init__).parameters.values()
    return {p.name: p.default for p in params if p.default is not inspect.Parameter.empty and p.name not in ("s", "order")}


def dts_for(name, n, T, points=None):
    """The sweep's dts (only its `points` largest if given), each rounded so that T / dt is an integer."""
    hi, lo, k = SWEEPS.get(n, SWEEPS[12])[name]
    dts = np.geomspace(hi, lo, k)[:points]
    return sorted({T / max(1, round(T / dt)) for dt in dts}, reverse=True)


def method(name, model, dt, inertias):
    """A function (q0, steps) -> (q (steps+1, n), seconds, ok, energy), energy() giving K + V per step."""
    if name in MUJOCO:
        runner = mjm.Runner(mjm.build(model, inertias, MUJOCO[name], dt))

        def run_mj(q0, steps):
            q, qd, seconds, ok = runner.run(q0, steps)
            return q, seconds, ok, lambda: runner.energies(q, qd)
        return run_mj
    if name == "Hermite-Simpson":
        hs = HermiteSimpson(model, dt, **OPTIONS[name])

        def run_hs(q0, steps):
            d = hs.rollout(q0, np.zeros(model.n), steps)
            return d["q"], d["seconds"], d["steps"] == steps, lambda: np.array([model.energy(q, v) for q, v in zip(d["q"], d["v"])])
        return run_hs
    integ = hovi.Integrator(model, s=int(name.split("=")[1].split(",")[0]), dt=dt, **OPTIONS[name])

    def run_vi(q0, steps):
        traj = integ.rollout(q0, steps, raise_on_failure=False)
        return traj.q, traj.solve_seconds, traj.converged and traj.steps == steps, lambda: traj.energy
    return run_vi


def sweep(n, T, n_states, points=None, methods=None):
    model, inertias = hovi.examples.models.pendulum(n), mjm.pendulum_inertias(n)
    agreement = mjm.check(model, inertias)
    print(f"n = {n}: MuJoCo vs hovi, largest relative difference {agreement}")
    q0s = np.random.default_rng(0).uniform(-np.pi / 12, np.pi / 12, (n_states, n))
    refs = [dop853(model, q0, T) for q0 in tqdm(q0s, desc=f"DOP853 references, n = {n}")]
    runs = []
    for name in methods or METHODS:
        for dt in tqdm(dts_for(name, n, T, points), desc=f"{name}, n = {n}"):
            run, steps = method(name, model, dt, inertias), round(T / dt)
            run(q0s[0], min(steps, 100))  # warm-up (caches, first calls), not recorded
            errors, seconds, ok = [], [], []
            for q0, ref in zip(q0s, refs):
                q, sec, conv, _ = run(q0, steps)
                ok.append(bool(conv))
                seconds.append(float(sec))
                errors.append(mean_error(q, ref(np.arange(steps + 1) * dt), dt, T) if conv else None)
            good = [e for e in errors if e is not None]
            runs.append({"method": name, "n": n, "T": T, "dt": dt, "steps": steps, "errors": errors,
                         "seconds": seconds, "converged": ok, "all_converged": all(ok),
                         "mean_error": float(np.mean(good)) if good else None,
                         "median_error": float(np.median(good)) if all(ok) else None,
                         "median_seconds": float(np.median(seconds)) if all(ok) else None})
    return agreement, runs


def curve(runs, name, n):
    """(median seconds, median error) of the dts where every state converged, by decreasing dt."""
    pts = [(r["median_seconds"], r["median_error"]) for r in runs
           if r["method"] == name and r["n"] == n and r["all_converged"]]
    return np.array(pts).reshape(-1, 2)


def time_to_reach(pts, level):
    """The least run time at which a curve (by decreasing dt) reaches `level`: any point at or below
    it, or a log-log interpolation between consecutive points across it (at large steps the run
    time can fall with dt, as Newton needs fewer iterations); (time, upper_bound_only) or None,
    upper_bound_only when the sweep's largest dt is the cheapest point already below."""
    best = None
    for i, (t, e) in enumerate(pts):
        if e > level:
            continue
        hits = [(float(t), i == 0)]
        if i > 0 and pts[i - 1][1] > level:  # crossing between the previous point and this one
            (t0, e0) = pts[i - 1]
            w = (np.log(level) - np.log(e0)) / (np.log(e) - np.log(e0))
            hits.append((float(np.exp(np.log(t0) + w * (np.log(t) - np.log(t0)))), False))
        best = min(hits + ([best] if best else []), key=lambda h: h[0])
    return best


def fmt(hit):
    return "not reached" if hit is None else ("≤ " if hit[1] else "") + f"{hit[0] * 1e3:.3g} ms"


def table(runs, ns, conditions):
    """Per n and error level: the run time of hovi's VI envelope (the fastest s) and of MuJoCo RK4."""
    lines = ["| n | error | hovi VI (best s, solver stop) | MuJoCo RK4 | VI / RK4 run time | Hermite-Simpson (hovi) |",
             "|---|---|---|---|---|---|"]
    rows = []
    for n in ns:
        for level in LEVELS:
            hits = [(time_to_reach(curve(runs, name, n), level), name[3:]) for name in VI_NAMES + LOOSE_NAMES]
            vi, s = min(((h, s) for h, s in hits if h), key=lambda x: x[0][0], default=(None, None))
            rk4 = time_to_reach(curve(runs, "MuJoCo RK4", n), level)
            hs = time_to_reach(curve(runs, "Hermite-Simpson", n), level)
            ratio = vi[0] / rk4[0] if vi and rk4 else None
            rows.append({"n": n, "level": level, "vi_seconds": vi and vi[0], "vi_setting": s, "rk4_seconds": rk4 and rk4[0],
                         "ratio": ratio, "hs_seconds": hs and hs[0]})
            lines.append(f"| {n} | {level:.0e} | {fmt(vi)}{f' ({s})' if vi else ''} | {fmt(rk4)} | "
                         f"{f'{ratio:.3g}' if ratio else '–'} | {fmt(hs)} |")
    lines += ["", "Median over the initial states of the run time to reach each error level (the cheapest point of "
              "each method's dt sweep at or below it, or log-log interpolation across it; ≤: the sweep's largest dt, "
              "already below). Ratio > 1: MuJoCo RK4 is faster. " + conditions]
    return "\n".join(lines), rows


def plot(runs, problems, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(problems), figsize=(5.2 * len(problems), 4.5), squeeze=False)
    for ax, (n, T) in zip(axes[0], problems.items()):
        for name in METHODS:
            pts = curve(runs, name, n)
            if len(pts):
                style = "o-" if name in VI_NAMES else ("x:" if name in LOOSE_NAMES else ("s--" if name in MUJOCO else "^:"))
                ax.loglog(pts[:, 0], pts[:, 1], style, ms=3.5, lw=1, label=name)
        env = envelope([curve(runs, name, n) for name in VI_NAMES + LOOSE_NAMES])
        if env is not None:
            ax.loglog(*env, "k-", lw=2.5, alpha=0.35, label="hovi VI envelope (s = 1..4, both stops)")
        ax.set_title(f"{n}-link pendulum, T = {T} s")
        ax.set_xlabel("run time [s] (median over states)")
        ax.set_ylabel("(1/T) ∫ ||q - q_ref|| dt (median)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    save_figure(fig, path)


def envelope(curves):
    """The Pareto front of error-vs-time curves on a common time grid: the smallest error any curve
    reaches within each run time (each curve interpolated log-log within its own time range)."""
    curves = [c[np.argsort(c[:, 0])] for c in curves if len(c) >= 2]
    if not curves:
        return None
    grid = np.geomspace(min(c[:, 0].min() for c in curves), max(c[:, 0].max() for c in curves), 200)
    lg = np.log(grid)
    err = np.full(len(grid), np.inf)
    for c in curves:
        inside = (grid >= c[:, 0].min()) & (grid <= c[:, 0].max())
        err[inside] = np.minimum(err[inside], np.exp(np.interp(lg[inside], np.log(c[:, 0]), np.log(c[:, 1]))))
    err = np.minimum.accumulate(err)  # a larger time budget can always run the faster setting
    keep = np.isfinite(err)
    return grid[keep], err[keep]


def replot():
    """Table, plot and README section from the committed full run (after a change to the table's rules)."""
    with open(f"{COMMITTED}/pareto.json") as f:
        data = json.load(f)
    problems = {int(n): T for n, T in data["problems"].items()}
    text, rows = table(data["runs"], list(problems), data.get("conditions", LOADED))
    text += "\n\n" + mjm.describe({int(n): a for n, a in data["mujoco_check_max_relative_difference"].items()})
    write_json("pareto.json", {**data, "equal_error_table": rows})
    plot(data["runs"], problems, f"{RESULTS}/pareto.png")
    print(text)
    update_readme_section("pareto", text)


def main():
    ap = study_parser(__doc__, "n = 4 and 6, T = 0.5 s, 2 states, 2 dts per method")
    ap.add_argument("--states", type=int, default=20, help="initial states in full mode (default 20)")
    ap.add_argument("--links", type=int, nargs="+", help="a partial run: these n only (with --T), "
                    "written to pareto_partial.json/.png, README untouched")
    ap.add_argument("--T", type=float, help="horizon of a partial run (default: the full run's for each n)")
    ap.add_argument("--points", type=int, help="a partial run: this many dts per method (the largest ones)")
    ap.add_argument("--methods", nargs="+", choices=METHODS, help="a partial run: these methods only")
    ap.add_argument("--conditions", default="Nothing else ran on the machine.",
                    help="what else ran on the machine during the run (the table's footnote and the JSON say so)")
    ap.add_argument("--replot", action="store_true", help="no runs: the table, plot and README section again "
                    "from bench/results/pareto.json")
    args = ap.parse_args()
    if args.replot:
        return replot()
    partial = bool(args.links or args.T or args.points or args.methods)
    problems = QUICK_PROBLEMS if args.quick else PROBLEMS
    if partial and not args.quick:
        problems = {n: args.T or PROBLEMS.get(n, 1.0) for n in (args.links or PROBLEMS)}
    n_states = 2 if args.quick else args.states
    agreement, runs = {}, []
    for n, T in problems.items():
        agreement[n], r = sweep(n, T, n_states, 2 if args.quick else args.points, args.methods)
        runs += r
    text, rows = table(runs, list(problems), args.conditions)
    text += "\n\n" + mjm.describe(agreement)
    name = "pareto_quick" if args.quick else ("pareto_partial" if partial else "pareto")
    write_json(f"{name}.json", {"problems": {str(n): T for n, T in problems.items()}, "states": n_states,
                                "options": OPTIONS, "integrator_defaults": integrator_defaults(),
                                "sweeps": {str(n): sw for n, sw in SWEEPS.items()}, "mujoco_version": mjm.mujoco.__version__,
                                "mujoco_check_max_relative_difference": {str(n): a for n, a in agreement.items()},
                                "equal_error_table": rows, "conditions": args.conditions, "runs": runs})
    plot(runs, problems, f"{RESULTS}/{name}.png")
    print(text)
    if name == "pareto":
        update_readme_section("pareto", text)


if __name__ == "__main__":
    main()
