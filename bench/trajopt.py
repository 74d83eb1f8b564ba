"""Trajectory optimisation: the Galerkin VI transcription against implicit and explicit
Hermite-Simpson collocation on the built-in examples (pendulum, acrobot and cart-pole swing-ups,
the slider-crank driven to a target), each solved by IPOPT (limited-memory Hessian) over a sweep of N.

For every solve: problem size (variables, constraints, Jacobian nonzeros), IPOPT iterations,
solve time, time per iteration and where it goes (hovi's C++ evaluations, all of hovi's callbacks,
IPOPT's own work), the optimal cost, and the accuracy of the optimised trajectory: the largest
difference between its configurations and a tight reference rollout of its optimal controls
(hovi's order-6 VI at a step 64x finer than the stage, u(t) as the transcription interprets it).
Also: Table 1 counted from the built NLPs against the paper's formulas, the VI's cost
convergence order in N, and the time per iteration against n on a chain swinging to a target.

    python bench/trajopt.py [--quick]

Writes bench/results/trajopt.json, trajopt.png and the tables in bench/README.md.
"""
from __future__ import annotations


import numpy as np

import hovi
from hovi import trajopt
from hovi.examples import swingups as examples
from hovi.trajopt.transcription import piecewise_polynomial
from hovi.trajopt.transcriptions import from_name
from common import RESULTS, loglog_slope, publish, save_figure, study_parser, write_json

METHODS = [("vi", 1), ("vi", 2), ("vi", 3), ("hs-implicit", 2), ("hs-explicit", 2)]
# Each transcription on its own, as the tables below were measured (the limited-memory Hessian, no
# continuation); hovi's default pipeline against CasADi is casadi_baseline.py's.
SOLVER = {"hessian": "lbfgs", "continuation": False}


def label(name, s):
    return f"VI s={s}" if name == "vi" else name


def reference_error(result, prob, refine=64):
    """max |q(t) - q_ref(t)| over the transcription's configuration points, q_ref a rollout of the
    optimal controls by the order-6 VI at dt = T / (N refine)."""
    steps = prob.N * refine
    integ = hovi.Integrator(prob.model, s=3, dt=prob.T / steps, tol=1e-13)
    u_of_t = result.control_function()
    tc = (np.arange(steps)[:, None] + integ.nodes[None, :]) * integ.dt
    U = u_of_t(tc.ravel()).reshape(steps, 4, -1) if prob.model.n_controls else None
    traj = integ.rollout(prob.q0, steps, qdot0=prob.qdot0, u=U, raise_on_failure=False)
    if traj.steps < steps:
        return float("nan")
    t, q = result.trajectory["t"], result.trajectory["q"]
    q_ref = piecewise_polynomial(integ.dt, integ.s, traj.control_points, t)
    return float(np.abs(q - q_ref).max())


def solve_row(example, N, name, s, guess=None):
    prob = examples.EXAMPLES[example](N=N)
    r = trajopt.solve(prob, from_name(name, s), verbose=False, guess=guess if guess is not None else
                      ("linear" if example == "acrobot" else None), **SOLVER)
    row = {"example": example, "method": label(name, s), "N": N, "success": r.success, "status": r.status,
           "cost": r.cost, "violation": r.constraint_violation, "iterations": r.iterations, "seconds": r.wall_seconds,
           **r.sizes, **{f"t_{k}": v for k, v in r.timing.items()}}
    row["error"] = reference_error(r, prob) if r.success else float("nan")
    return row, r


def table1(N=10, n=4, m=2):
    """Variables and constraints (dynamics and holonomic rows; boundary conditions are bounds) of
    each transcription's NLP for a fully actuated n-link chain with m constraint equations,
    against the paper's Table 1."""
    model = hovi.examples.models.pendulum(n)
    for j in range(n):
        model.add_actuator(j)
    q0 = np.zeros(n)
    tip = model.joint_placements(q0)[-1] @ np.array([0, 0, -0.5, 1.0])
    model.add_point_constraint(n - 1, point=[0, 0, -0.5], target=tip[:3], axes="xyz"[:m])
    paper = {"vi": ((4 * N + 3) * n + (2 * N + 1) * m, 3 * N * n + (2 * N + 1) * m),
             "hs-explicit": ((6 * N + 3) * n + (2 * N + 1) * m, 4 * N * n + (6 * N + 3) * m),
             "hs-implicit": ((8 * N + 4) * n + (2 * N + 1) * m, (6 * N + 1) * n + (6 * N + 3) * m)}
    rows = []
    for name, controls in (("vi", "per_point"), ("vi", "held"), ("hs-explicit", "per_point"), ("hs-implicit", "per_point")):
        prob = trajopt.Problem(model, N, 1.0, controls=controls).initial_state(q0).add_cost(trajopt.ControlEffort())
        core = from_name(name, 2).transcribe(prob).core
        rows.append({"transcription": name, "controls": controls, "N": N, "n": n, "m": m, "variables": core.n_variables,
                     "constraints": core.n_constraints, "nonzeros": core.nnz, "paper_variables": paper[name][0],
                     "paper_constraints": paper[name][1]})
    return rows


def scaling(ns, N=20, T=2.0):
    """Time per IPOPT iteration against n: an n-link chain, every joint actuated, from hanging at
    rest to a slightly bent configuration at rest (0.1 sin(j) rad), minimum effort."""
    rows = []
    for n in ns:
        model = hovi.examples.models.pendulum(n)
        for j in range(n):
            model.add_actuator(j)
        qT = 0.1 * np.sin(np.arange(1, n + 1))
        for name, s in (("vi", 2), ("hs-implicit", 2), ("hs-explicit", 2)):
            prob = trajopt.Problem(model, N, T).initial_state(np.zeros(n)).final_state(qT, qdot=np.zeros(n))
            prob.add_cost(trajopt.ControlEffort())
            r = trajopt.solve(prob, from_name(name, s), verbose=False, options={"max_iter": 300}, **SOLVER)
            rows.append({"n": n, "method": label(name, s), "iterations": r.iterations, "seconds": r.wall_seconds,
                         "per_iteration": r.timing["per_iteration"], "evaluation_share": r.timing["evaluations"] / r.wall_seconds,
                         "callback_share": r.timing["callbacks"] / r.wall_seconds, **r.sizes, "success": r.success})
            print(f"  n = {n}, {label(name, s)}: {1e3 * r.timing['per_iteration']:.2f} ms/iteration", flush=True)
    return rows


def cost_order(example, Ns, N_ref):
    """Observed convergence order of the optimal cost in N for each method, against the VI s = 3 at N_ref."""
    ref, ref_result = solve_row(example, N_ref, "vi", 3)
    out = {"reference_cost": ref["cost"], "N_ref": N_ref, "methods": {}}
    for name, s in METHODS:
        costs = []
        for N in Ns:
            row, _ = solve_row(example, N, name, s, guess=ref_result.as_guess())
            costs.append(row["cost"] if row["success"] else float("nan"))
        err = np.abs(np.array(costs) - ref["cost"])
        ok = np.isfinite(err) & (err > 0)
        out["methods"][label(name, s)] = {"N": Ns, "cost": costs, "error": err.tolist(),
                                          "order": -loglog_slope(np.array(Ns)[ok], err[ok]) if ok.sum() >= 2 else None}
    return out


def plot(rows, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    exs = sorted({r["example"] for r in rows})
    fig, axes = plt.subplots(1, len(exs), figsize=(4.2 * len(exs), 3.8))
    for ax, ex in zip(np.atleast_1d(axes), exs):
        for m in sorted({r["method"] for r in rows}):
            pts = sorted((r["seconds"], r["error"]) for r in rows if r["example"] == ex and r["method"] == m
                         and r["success"] and np.isfinite(r["error"]))
            if pts:
                x, y = np.array(pts).T
                ax.loglog(x, y, "o-", label=m)
        ax.set_title(ex)
        ax.set_xlabel("solve time [s]")
        ax.grid(True, which="both", alpha=0.3)
    np.atleast_1d(axes)[0].set_ylabel("max |q - q_ref| of the optimised trajectory")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    save_figure(fig, path)


def main():
    ap = study_parser(__doc__, "a small smoke run, no README update")
    args = ap.parse_args()
    if args.quick:
        sweeps = {"pendulum": [10, 20], "cartpole": [20], "slider_crank": [10]}
        ns, order_Ns, N_ref = [4, 8], [10, 20], 40
    else:
        sweeps = {"pendulum": [10, 20, 40, 80], "acrobot": [50, 100, 150], "cartpole": [25, 50, 100],
                  "slider_crank": [15, 30, 60]}
        ns, order_Ns, N_ref = [4, 8, 16, 32, 64], [12, 25, 50, 100], 200
    rows = []
    for ex, Ns in sweeps.items():
        for N in Ns:
            for name, s in METHODS:
                row, _ = solve_row(ex, N, name, s)
                rows.append(row)
                print(f"{ex} N={N} {row['method']}: {row['status'][:40]}, {row['iterations']} it, "
                      f"{row['seconds']:.2f} s, error {row['error']:.2e}", flush=True)
    counts = table1()
    print("scaling:", flush=True)
    scale = scaling(ns)
    order = cost_order("cartpole", order_Ns, N_ref)
    name = "trajopt_quick" if args.quick else "trajopt"
    write_json(f"{name}.json", {"solves": rows, "table1": counts, "scaling": scale, "cost_order": order})
    plot(rows, f"{RESULTS}/{name}.png")
    publish("trajopt", report(rows, counts, scale, order), args.quick)


def report(rows, counts, scale, order):
    lines = ["| example | N | method | variables | constraints | nonzeros | iterations | solve [s] | per iteration [ms] "
             "| hovi's C++ evaluations | all of hovi's callbacks | cost | error vs reference |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ok = "" if r["success"] else " (failed)"
        lines.append(f"| {r['example']} | {r['N']} | {r['method']}{ok} | {r['variables']} | {r['constraints']} | "
                     f"{r['nonzeros']} | {r['iterations']} | {r['seconds']:.2f} | {1e3 * r['t_per_iteration']:.2f} | "
                     f"{100 * r['t_evaluations'] / r['seconds']:.1f}% | {100 * r['t_callbacks'] / r['seconds']:.1f}% | "
                     f"{r['cost']:.6g} | {r['error']:.1e} |")
    lines += ["", "Table 1 (N = 10 stages, n = 4, m = 2 constraint equations, fully actuated; counted from the built "
              "NLPs, boundary conditions as bounds):", "",
              "| transcription | controls | variables | paper | constraints | paper | Jacobian nonzeros |",
              "|---|---|---|---|---|---|---|"]
    for c in counts:
        lines.append(f"| {c['transcription']} | {c['controls']} | {c['variables']} | {c['paper_variables']} | {c['constraints']} | "
                     f"{c['paper_constraints']} | {c['nonzeros']} |")
    lines += ["", f"Cost convergence on the cart-pole (reference: VI s = 3 at N = {order['N_ref']}, cost "
              f"{order['reference_cost']:.8g}):", "", "| method | " + " | ".join(f"N = {N}" for N in order["methods"]
              [next(iter(order["methods"]))]["N"]) + " | observed order |", "|---|" + "---|" * (len(
              next(iter(order["methods"].values()))["N"]) + 1)]
    for m, d in order["methods"].items():
        o = "–" if d["order"] is None else f"{d['order']:.2f}"
        lines.append(f"| {m} | " + " | ".join(f"{e:.1e}" for e in d["error"]) + f" | {o} |")
    lines += ["", "Time per IPOPT iteration against n (chain to a bent target, N = 20; iterations in brackets, * = not "
              "converged in 300):", "",
              "| n | " + " | ".join(sorted({r["method"] for r in scale})) + " |", "|---|" + "---|" * len({r["method"] for r in scale})]
    for n in sorted({r["n"] for r in scale}):
        cells = [f"{1e3 * r['per_iteration']:.2f} ms ({r['iterations']}{'' if r['success'] else '*'})"
                 for m in sorted({r["method"] for r in scale}) for r in scale if r["n"] == n and r["method"] == m]
        lines.append(f"| {n} | " + " | ".join(cells) + " |")
    lines.append("")
    for m in sorted({r["method"] for r in scale}):
        pts = [(r["n"], r["per_iteration"]) for r in scale if r["method"] == m]
        x, y = np.array(pts).T
        big = max((r for r in scale if r["method"] == m), key=lambda r: r["n"])
        lines.append(f"- {m}: fitted slope of the time per iteration in n {loglog_slope(x, y):.2f}; at n = {big['n']} "
                     f"({big['variables']} variables, {big['nonzeros']} nonzeros) {100 * big['callback_share']:.1f}% of "
                     f"the solve time in hovi's callbacks ({100 * big['evaluation_share']:.1f}% in its C++ evaluations)")
    return "\n".join(lines)


if __name__ == "__main__":
    main()
