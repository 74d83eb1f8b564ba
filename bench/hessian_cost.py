"""The cost of one Hessian of the Lagrangian on the paper's robots: the VI's own Hessian
of its DEL equations (del_hessian.hpp) and the built-in rows' exact Hessians (path constraints on
body points, contact rows: trajopt/body_point_rows.cpp, complementarity_rows.cpp) ('directional')
against coloured differences of the whole gradient ('fd'), at the example's starting point with
random multipliers; and where the time goes (the built-in rows' Hessians). One thread, the fastest
of --repeat evaluations.

    python bench/hessian_cost.py [--quick] [--repeat R]

Writes bench/results/hessian_cost.json (hessian_cost_quick.json with --quick: the Flamingo's quick
problem at s = 1 only).
"""
from __future__ import annotations

import time

import numpy as np

from common import study_parser


def row(name: str, s: int, quick: bool, repeat: int) -> dict:
    from hovi import trajopt
    from hovi.trajopt.complementarity import ComplementarityRelaxation
    from hovi.examples.paper import build
    from hovi.trajopt.hessian import LagrangianHessian
    example = build(name, quick=quick)
    prob = example.problem
    relaxation = ComplementarityRelaxation(1e-2) if prob.contacts is not None else None
    nlp = trajopt.NLP(prob, trajopt.VI(s), relaxation=relaxation)
    x = np.clip(nlp.transcription.initial_guess(None), nlp.lower, nlp.upper)
    t0 = time.perf_counter()
    H = LagrangianHessian(nlp, x)
    setup = time.perf_counter() - t0
    program = nlp.program()
    lam = np.random.default_rng(0).normal(size=nlp.n_constraints)
    out = {"example": name, "quick": quick, "s": s, "N": prob.N, "n": prob.model.n, "n_variables": nlp.n_variables,
           "hessian_nnz": len(H.rows), "colours": H.n_colours, "pattern_and_colouring_seconds": setup}
    values = {}
    for mode in ("fd", "directional"):
        program.set_colouring(*(np.asarray(a, np.int32) for a in (H.colour, H.rows, H.cols, H.read_row, H.read_col)),
                              1, mode == "fd")
        best = np.inf
        for _ in range(repeat):
            t0 = time.perf_counter()
            values[mode] = program.hessian(x, lam, 1.0)
            best = min(best, time.perf_counter() - t0)
        out[f"{mode}_seconds"] = best
    # the built-in rows' part of 'directional': their own Hessians
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        for block, places, _ in nlp._blocks():
            block.hessian(x, lam[places])
        best = min(best, time.perf_counter() - t0)
    out["rows_hessian_seconds"] = best
    scale = np.abs(values["directional"]).max()
    out["fd_vs_directional"] = float(np.abs(values["fd"] - values["directional"]).max() / scale)
    return out


def main():
    ap = study_parser(__doc__, "the Flamingo's quick problem at s = 1 only")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    from common import write_json
    cases = [("spring_flamingo", 1, True)] if args.quick else [(name, s, False) for name in ("atlas", "spring_flamingo", "littledog")
                                                          for s in (1, 2)]
    rows = []
    for name, s, quick in cases:
        rows.append(row(name, s, quick, 1 if args.quick else args.repeat))
        r = rows[-1]
        print(f"{name:9s} s={s} n={r['n']:2d} colours {r['colours']:3d}: fd {r['fd_seconds'] * 1e3:7.1f} ms, "
              f"directional {r['directional_seconds'] * 1e3:7.1f} ms (built-in rows {r['rows_hessian_seconds'] * 1e3:.1f} ms), "
              f"agree to {r['fd_vs_directional']:.1e}", flush=True)
    print("wrote", write_json("hessian_cost_quick.json" if args.quick else "hessian_cost.json", {"rows": rows}))


if __name__ == "__main__":
    main()
