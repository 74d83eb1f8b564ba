"""The paper's robot examples (hovi.robot_examples, ``hovi example NAME``) in full: each solved with
the trapezoidal VI (s = 1), the Simpson VI (s = 2, the paper's) and implicit Hermite-Simpson
collocation of the same problem, all by IPOPT with the Lagrangian's Hessian (trajopt.hessian):
iterations, solve time, the feasibility figures and, for the VIs, the one-stage replay drift.
A contact-implicit example (point contacts: LittleDog) is solved with the trapezoidal VI only:
Hermite-Simpson has no controls at its configuration points, where the contact conditions pair
forces with gaps (trajopt.complementarity refuses it), and with s = 2 an impact inside a stage
rebounds (hovi.contact.contacts).

    python bench/robot_examples.py [--quick] [NAME ...]

NAMEs (default: all) rerun only those examples; the other examples' rows stay as they were.

Writes bench/results/robot_examples.json (robot_examples_quick.json) and the table in bench/README.md.
"""
from __future__ import annotations

import argparse
import json
import os
import time

from common import RESULTS, update_readme_section, write_json
from hovi.robot_examples import NAMES, build, report

METHODS = [("vi", 1), ("vi", 2), ("hs-implicit", 2)]
CONTACT_METHODS = [("vi", 1)]  # see the module docstring


def run_one(name: str, quick: bool, method: str, s: int) -> dict:
    example = build(name, quick=quick)
    t0 = time.perf_counter()
    result = report.solve(example, method, s)
    wall = time.perf_counter() - t0
    figures = example.checks(result)
    row = {"example": name, "method": method if method != "vi" else f"vi s={s}", "N": example.problem.N,
           "T": example.problem.T, "success": bool(result.success), "status": result.status,
           "iterations": int(result.contact.get("iterations", result.iterations)),  # all the contact solves'
           "solve_seconds": wall, **result.sizes, **figures,
           "feasible": bool(result.success) and not example.failures(figures)}
    if method == "vi":
        row.update(report.replay_figures(example, result))
    print(f"{name:8s} {row['method']:12s} N = {row['N']:3d}: {row['iterations']:4d} iterations, {wall:7.1f} s, "
          f"feasible {row['feasible']}", flush=True)
    return row


def methods(name: str, quick: bool):
    """The (transcription, s) pairs for example ``name``: all of METHODS (the first only if ``quick``),
    CONTACT_METHODS for a contact-implicit problem."""
    if build(name, quick=quick).problem.contacts is not None:
        return CONTACT_METHODS
    return METHODS[:1] if quick else METHODS


def earlier_rows(filename: str, rerun) -> list:
    """The rows of the examples not in ``rerun`` from the results file written before (if any)."""
    path = os.path.join(RESULTS, filename)
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return [r for r in json.load(f)["rows"] if r["example"] not in rerun]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the quick problems, the trapezoidal VI only")
    ap.add_argument("names", nargs="*", metavar="NAME", help=f"examples to run (default: all of {', '.join(NAMES)})")
    args = ap.parse_args()
    unknown = sorted(set(args.names) - set(NAMES))
    if unknown:
        ap.error(f"unknown example(s) {', '.join(unknown)} (choose from {', '.join(NAMES)})")
    names = args.names or list(NAMES)
    filename = "robot_examples_quick.json" if args.quick else "robot_examples.json"
    rows = earlier_rows(filename, names) + [run_one(name, args.quick, method, s) for name in names
                                            for method, s in methods(name, args.quick)]
    rows.sort(key=lambda r: NAMES.index(r["example"]))
    path = write_json(filename, {"rows": rows})
    print(f"wrote {path}")
    if args.quick:
        return
    lines = ["| example | transcription | N | variables | IPOPT iterations | solve [s] | feasible | constraint violation "
             "| one-stage replay drift |", "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        drift = f"{r['replay_one_step_drift']:.1e}" if "replay_one_step_drift" in r else "-"
        lines.append(f"| {r['example']} | {r['method']} | {r['N']} | {r['variables']} | {r['iterations']} | "
                     f"{r['solve_seconds']:.1f} | {'yes' if r['feasible'] else 'no: ' + r['status']} | "
                     f"{r['constraint_violation']:.1e} | {drift} |")
    update_readme_section("robot_examples", "\n".join(lines))

if __name__ == "__main__":
    main()
