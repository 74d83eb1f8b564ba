"""IPOPT's options on the swing-ups: the Hessian (hovi's default L-BFGS with
history 30 or 6, or the coloured finite differences of the exact gradient, hessian='fd') and the
barrier strategy (adaptive or monotone mu), each on the default VI transcription of
hovi.examples.swingups: wall time of the whole solve (best of R), IPOPT's share, iterations, cost.

    python bench/ipopt_options.py [--quick]

Writes bench/results/ipopt_options.json (or ipopt_options_quick.json)."""
from __future__ import annotations

import argparse
import time

from hovi import trajopt
from hovi.examples import swingups as ex
from common import write_json

VARIANTS = {
    "L-BFGS 30, adaptive mu (default)": ({}, "lbfgs"),
    "L-BFGS 6, adaptive mu": ({"limited_memory_max_history": 6}, "lbfgs"),
    "L-BFGS 30, monotone mu": ({"mu_strategy": "monotone"}, "lbfgs"),
    "L-BFGS 6, monotone mu": ({"limited_memory_max_history": 6, "mu_strategy": "monotone"}, "lbfgs"),
    "FD Hessian, adaptive mu": ({}, "fd"),
    "FD Hessian, monotone mu": ({"mu_strategy": "monotone"}, "fd"),
}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the pendulum at s = 1 only, one run each")
    args = ap.parse_args()
    cases = [("pendulum_swingup", 1)] if args.quick else [
        ("pendulum_swingup", 1), ("pendulum_swingup", 2), ("cartpole_swingup", 1), ("cartpole_swingup", 2),
        ("acrobot_swingup", 2)]
    rows = []
    for name, s in cases:
        repeats = 1 if args.quick or name == "acrobot_swingup" else 2
        for label, (options, hessian) in VARIANTS.items():
            best = None
            for _ in range(repeats):
                t0 = time.perf_counter()
                r = trajopt.solve(getattr(ex, name)(), trajopt.VI(s), verbose=False, options=options, hessian=hessian)
                t = time.perf_counter() - t0
                if best is None or t < best[0]:
                    best = (t, r)
            t, r = best
            rows.append(dict(case=name, s=s, variant=label, seconds=t, ipopt_seconds=r.timing.get("ipopt"),
                             callbacks_seconds=r.timing.get("callbacks"), iterations=r.iterations, cost=r.cost,
                             success=r.success))
            print(f"{name:18s} s={s} {label:34s} {t:7.3f} s  IPOPT {r.timing.get('ipopt', 0):7.3f} s  "
                  f"{r.iterations:5d} it  cost {r.cost:.6f}  {'ok' if r.success else r.status}", flush=True)
    write_json("ipopt_options_quick.json" if args.quick else "ipopt_options.json", {"quick": args.quick, "rows": rows})


if __name__ == "__main__":
    main()
