"""The paper's robot examples (hovi.examples.paper, ``hovi example NAME``) in full: each solved with
the trapezoidal VI (s = 1), the Simpson VI (s = 2, the paper's) and implicit Hermite-Simpson
collocation of the same problem and contact model, all by IPOPT with the Lagrangian's Hessian
(trajopt.hessian): iterations, solve time, the feasibility figures and, for the VIs, the replay
figures (report.replay_figures).

    python bench/robot_examples.py [--quick [--readme]] [--only NAME ...] [--methods vi1 vi2 hs] [--time-limit S]
                                   [--checkpoints DIR] [--verbose]

Writes bench/results/robot_examples.json (robot_examples_quick.json) after each run, the row run
replacing its (example, method) and the others kept as the file has them then (two runs with
different --only or --methods can share the file), and the table in bench/README.md (--quick: only
with --readme, so the test suite's quick run changes no tracked file). With
--checkpoints, each contact-implicit solve keeps its homotopy's state in DIR/<example>_<method>.npz
and a run started again resumes from it (a solve of hours can span several processes; the row's
iterations and time are then those of all of them, the time in IPOPT); a finished solve removes it.
"""
from __future__ import annotations

import argparse
import json
import os
import time

from common import RESULTS, update_readme_section, write_json
from hovi.examples.paper import NAMES, build, report

METHODS = {"vi1": ("vi", 1), "vi2": ("vi", 2), "hs": ("hs-implicit", 2)}


def label(method: str, s: int) -> str:
    return f"vi s={s}" if method == "vi" else method


def run_one(name: str, quick: bool, method: str, s: int, time_limit: float | None = None,
            verbose: bool = False, checkpoints: str | None = None) -> dict:
    example = build(name, quick=quick)
    checkpoint = None
    if checkpoints is not None:
        os.makedirs(checkpoints, exist_ok=True)
        checkpoint = os.path.join(checkpoints, f"{name}_{label(method, s).replace(' ', '').replace('=', '')}.npz")
    resumed = checkpoint is not None and os.path.exists(checkpoint)
    t0 = time.perf_counter()
    result = report.solve(example, method, s, verbose=verbose, time_limit=time_limit, checkpoint=checkpoint)
    wall = time.perf_counter() - t0
    if resumed:  # the time of all its processes
        wall = max(wall, report.ipopt_totals(result)[1])
    figures, replay, failures = report.check(example, result, method)
    row = {"example": name, "method": label(method, s), "N": example.problem.N,
           "T": example.problem.T, "success": bool(result.success), "status": result.status,
           "iterations": report.ipopt_totals(result)[0], "solve_seconds": wall, **result.sizes, **figures,
           "contact_solves": result.contact.get("solves", []), "time_limit": time_limit,
           "out_of_time": bool(result.contact.get("out_of_time", False)),
           **replay, "failures": failures}
    row["feasible"] = not row["failures"]
    print(f"{name:8s} {row['method']:12s} N = {row['N']:3d}: {row['iterations']:4d} iterations, {wall:7.1f} s, "
          f"between-knot penetration {row.get('between_knot_penetration', float('nan')) * 1e3:.3g} mm, "
          f"feasible {row['feasible']}", flush=True)
    for line in ([report.between_knot_text(figures)] if "between_knot_penetration" in figures else []) + (
            [report.replay_text(replay)] if replay else []):
        print("  " + line, flush=True)
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the quick problems, the trapezoidal VI only")
    ap.add_argument("--only", nargs="+", choices=NAMES, default=list(NAMES), help="the examples to run")
    ap.add_argument("--methods", nargs="+", choices=list(METHODS), default=list(METHODS),
                    help="the transcriptions (--quick: the trapezoidal VI only)")
    ap.add_argument("--time-limit", type=float, default=None,
                    help="seconds for each example and transcription (IPOPT's max_cpu_time; default: none)")
    ap.add_argument("--checkpoints", default=None, metavar="DIR",
                    help="keep each contact-implicit solve's homotopy state in DIR and resume from it")
    ap.add_argument("--verbose", action="store_true", help="IPOPT's progress, one line per iteration")
    ap.add_argument("--readme", action="store_true",
                    help="with --quick: also write the quick table into bench/README.md (a full run always does)")
    args = ap.parse_args()
    name = "robot_examples_quick.json" if args.quick else "robot_examples.json"
    methods = [METHODS["vi1"]] if args.quick else [METHODS[m] for m in args.methods]
    runs = [(example, method, s) for example in args.only for method, s in methods]
    for example, method, s in runs:
        rows = merge(name, run_one(example, args.quick, method, s, args.time_limit, args.verbose,
                                    args.checkpoints))
    if args.readme or not args.quick:  # the test suite's quick run leaves the committed README alone
        write_table(rows, quick=args.quick)


def merge(name: str, row: dict) -> list:
    """Writes ``row`` into results/<name> in place of the row of its (example, method), keeping the
    others as they are in the file now (another run may have written since this one started: each
    finished run is saved at once); returns the rows in table order."""
    rows = []
    if os.path.exists(os.path.join(RESULTS, name)):
        with open(os.path.join(RESULTS, name)) as f:
            rows = [r for r in json.load(f)["rows"] if (r["example"], r["method"]) != (row["example"], row["method"])]
    rows.append(row)
    order = [label(*m) for m in METHODS.values()]
    rows.sort(key=lambda r: (NAMES.index(r["example"]), order.index(r["method"])))
    print(f"wrote {write_json(name, {'rows': rows})}", flush=True)
    return rows


def feasibility(row: dict) -> str:
    """The table's cell for an infeasible row: out of its time limit or not, and what failed."""
    out = " (out of time)" if row.get("out_of_time") else ""
    return f"no{out}: " + "; ".join(row.get("failures", [row["status"]]))


def between_cell(r: dict) -> str:
    """The worst between-knot penetration (mm) with its contact and time, '-' if not measured."""
    if "between_knot_penetration" not in r:
        return "-"
    return f"{r['between_knot_penetration'] * 1e3:.3g} ({r['between_knot_contact']}, {r['between_knot_time']:.3f} s)"


def replay_cell(r: dict) -> str:
    """The stages the integrator reproduces, '-' for a collocation."""
    if "replay_stages" not in r:
        return "-"
    return f"{r['replay_stages_reproduced']} of {r['replay_stages']}"


def write_table(rows: list, quick: bool = False) -> None:
    """The README table of the rows (one per example and method): the full rows in 'robot_examples',
    the quick ones in 'robot_examples_quick'."""
    lines = ["| example | transcription | N | variables | IPOPT iterations | solve [s] | feasible | constraint violation "
             "| stage DEL residual | one-stage replay drift | stages replayed | between-knot penetration [mm] (where) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        residual = f"{r['replay_stage_residual']:.1e}" if "replay_stage_residual" in r else "-"
        drift = f"{r['replay_one_step_drift']:.1e}" if "replay_one_step_drift" in r else "-"
        if r.get("replay_steps_elsewhere"):
            drift += f" ({r['replay_steps_elsewhere']} elsewhere)"
        lines.append(f"| {r['example']} | {r['method']} | {r['N']} | {r['variables']} | {r['iterations']} | "
                     f"{r['solve_seconds']:.1f} | {'yes' if r['feasible'] else feasibility(r)} | "
                     f"{r['constraint_violation']:.1e} | {residual} | {drift} | {replay_cell(r)} | {between_cell(r)} |")
    update_readme_section("robot_examples_quick" if quick else "robot_examples", "\n".join(lines))

if __name__ == "__main__":
    main()
