"""Which local optimum of the acrobot swing-up hovi's pipelines reach from the straight-line guess
(the best known optimum, cost 22.44, that CasADi's Hermite-Simpson finds at N = 160).

The problem is bench/casadi_baseline.py's: hovi.examples.swingups' acrobot at N = 160, T = 4,
guess 'linear', the target transcription VI(s = 3). Four studies:

    pipelines  first stage then VI(3) at N = 160 from the first stage's interpolants: none (direct),
               order continuation (VI(1) at N = 160, Newton or 50 L-BFGS iterations), mesh
               continuation (VI(s1) at a coarse Nc, s1 = 2, 3, 4, Nc = 20, 40, Newton or L-BFGS)
    options    IPOPT's barrier options (mu_init, mu_strategy) with and without continuation
    basin      is the 22.44 optimum representable at the coarse levels? VI(s1) at Nc from CasADi's
               N = 160 solution, then VI(3) at N = 160 from that (casadi needed; skipped without it)
    multistart the straight line plus random smooth perturbations (sum_k a_k sin(k pi t / T), k = 1..3,
               a_k ~ N(0, 1.5) per joint, seed 0) solved at a coarse level (VI(3), Nc = 20), then
               VI(3) at N = 160 from each

Each row: first-stage cost and iterations, final cost, iterations, success and wall time (one run,
one thread). Writes bench/results/acrobot_basins.json (acrobot_basins_quick.json with --quick: one
row of each study but 'basin').

    python bench/acrobot_basins.py [--quick]
"""
from __future__ import annotations

import copy
import time

import numpy as np

from common import study_parser

N, S = 160, 3
MAX_ITER = 300


def problem(N_: int = N):
    from hovi.examples import swingups
    prob = swingups.EXAMPLES["acrobot"](N=N)
    coarse = copy.copy(prob)   # the same problem on another grid: only N differs
    coarse.N = N_
    return coarse


def ipopt(first: str = "newton", options: dict | None = None, continuation=False):
    from hovi import trajopt
    if first == "lbfgs":
        return trajopt.Ipopt({"max_iter": 50, **(options or {})}, verbose=False, hessian="lbfgs", continuation=False)
    return trajopt.Ipopt({"max_iter": MAX_ITER, **(options or {})}, verbose=False, continuation=continuation)


def two_stage(Nc: int | None, s1: int, first: str, guess="linear") -> dict:
    """VI(s1) at Nc (Newton or 50 L-BFGS iterations) from ``guess``, then VI(S) at N from its
    interpolants; Nc None: VI(S) at N directly."""
    from hovi import trajopt
    t0 = time.perf_counter()
    row = {"Nc": Nc, "s1": s1, "first": first}
    if Nc is not None:
        r1 = ipopt(first).solve(problem(Nc), trajopt.VI(s1), guess)
        row.update(first_cost=r1.cost, first_iterations=r1.iterations, first_success=bool(r1.success))
        guess = r1.as_guess()
    r = ipopt().solve(problem(), trajopt.VI(S), guess)
    return {**row, "cost": r.cost, "iterations": r.iterations, "success": bool(r.success),
            "seconds": time.perf_counter() - t0}


def pipelines(quick: bool) -> list[dict]:
    if quick:
        return [two_stage(20, 3, "newton")]
    rows = [two_stage(None, S, "direct"), two_stage(N, 1, "newton"), two_stage(N, 1, "lbfgs")]
    return rows + [two_stage(Nc, s1, first) for Nc in (20, 40) for s1 in (2, 3, 4) for first in ("newton", "lbfgs")]


def options_rows(quick: bool) -> list[dict]:
    from hovi import trajopt
    rows = []
    settings = [{"mu_init": 1e-3}] if quick else [{"mu_init": 1e-3}, {"mu_init": 1.0}, {"mu_init": 10.0},
                                                  {"mu_strategy": "monotone", "mu_init": 1.0}]
    for opts in settings:
        for continuation in ((True,) if quick else (True, False)):
            t0 = time.perf_counter()
            r = ipopt(options=opts, continuation=continuation).solve(problem(), trajopt.VI(S), "linear")
            rows.append({"options": opts, "continuation": continuation, "cost": r.cost, "iterations": r.iterations,
                         "success": bool(r.success), "seconds": time.perf_counter() - t0})
    return rows


def basin_rows() -> list[dict]:
    import casadi_baseline as cb
    sol = cb.solve("acrobot", N=N, guess="linear")
    rows = [{"casadi_cost": sol.cost, "casadi_iterations": sol.iterations}]
    return rows + [two_stage(Nc, s1, "newton", guess=sol.as_guess()) for Nc, s1 in ((10, 4), (20, 2), (20, 3), (40, 2))]


def smooth_guess(a: np.ndarray, T: float, q0: np.ndarray, qT: np.ndarray):
    """(q(t), q̇(t), u(t)): the straight line q0 -> qT plus sum_k a_k sin(k pi t / T), zero controls."""
    k = np.arange(1, len(a) + 1)[:, None]

    def q(t):
        tau = np.asarray(t)[:, None] / T
        return q0 + (qT - q0) * tau + np.sin(np.pi * tau * k.T) @ a

    def qdot(t):
        tau = np.asarray(t)[:, None] / T
        return (qT - q0) / T + (np.pi * k.T / T * np.cos(np.pi * tau * k.T)) @ a

    return q, qdot, lambda t: np.zeros((len(t), 1))


def multistart(quick: bool, Nc: int = 20, s1: int = 3) -> list[dict]:
    prob = problem(Nc)
    rng = np.random.default_rng(0)
    rows = []
    for i in range(2 if quick else 10):
        a = rng.normal(0.0, 1.5, size=(3, 2)) if i else np.zeros((3, 2))
        guess = smooth_guess(a, prob.T, np.asarray(prob.q0), np.asarray(prob.qT))
        rows.append({"start": i, **two_stage(Nc, s1, "newton", guess=guess)})
    return rows


def run(quick: bool, log=print) -> dict:
    out = {}
    for name, study in (("pipelines", lambda: pipelines(quick)), ("options", lambda: options_rows(quick)),
                        ("multistart", lambda: multistart(quick))):
        out[name] = study()
        for row in out[name]:
            log(name, {k: round(v, 4) if isinstance(v, float) else v for k, v in row.items()})
    if not quick:
        try:
            out["basin"] = basin_rows()
        except ImportError:
            out["basin"] = "skipped: casadi is not installed"
        log("basin", out["basin"])
    return out


def main():
    ap = study_parser(__doc__, "one row of each study but 'basin'")
    args = ap.parse_args()
    from common import write_json
    out = {"N": N, "s": S, "max_iter": MAX_ITER, **run(args.quick)}
    print("wrote", write_json("acrobot_basins_quick.json" if args.quick else "acrobot_basins.json", out))


if __name__ == "__main__":
    main()
