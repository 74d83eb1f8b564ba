"""Concurrency soak: 8 threads share one model, Integrator and Linearizer each of a
12-link pendulum and of a constrained four-bar and make mixed calls (steps, 20-step rollouts,
step linearisations, constrained rollouts, projections); every result must equal, bit for bit,
the same call made alone, and the resident memory must not grow from one round to the next.

    python bench/soak_threads.py            # 8 threads x 10^4 calls, results/soak_threads.json
    python bench/soak_threads.py --quick    # 8 threads x 100 calls (the test suite)
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import update_readme_section, write_json  # noqa: E402

import hovi  # noqa: E402

THREADS = 8
KINDS = ("step", "rollout", "linearize", "constrained_rollout", "project")


def rss_mb() -> float:
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith("VmRSS")) / 1024


class Calls:
    """Call k (any k >= 0) with inputs that depend on k only."""

    def __init__(self) -> None:
        self.pendulum = hovi.Integrator(hovi.examples.models.pendulum(12), s=2, dt=0.01)
        self.linearizer = hovi.Linearizer(self.pendulum)
        self.fourbar = hovi.Integrator(hovi.examples.models.fourbar(), s=2, dt=0.01)
        self.q_fourbar, _ = self.fourbar.project(np.array([-1.2, 0.9, -1.8]))  # away from the folded singularity

    def __call__(self, k: int):
        rng = np.random.default_rng(k)
        kind = KINDS[k % len(KINDS)]
        if kind == "step":
            q = rng.uniform(-0.5, 0.5, 12)
            return kind, self.pendulum.step(q, self.pendulum.momentum(q, rng.uniform(-1, 1, 12)))[:2]
        if kind == "rollout":
            t = self.pendulum.rollout(rng.uniform(-0.5, 0.5, 12), 20, qdot0=rng.uniform(-1, 1, 12))
            return kind, (t.q, t.p, t.iterations)
        if kind == "linearize":
            q = rng.uniform(-0.5, 0.5, 12)
            lin = self.linearizer.step_jacobians(q, self.pendulum.momentum(q, np.zeros(12)))
            return kind, (lin.A, lin.q_next)
        if kind == "constrained_rollout":
            q0, v0 = self.fourbar.project(self.q_fourbar + rng.uniform(-0.05, 0.05, 3), rng.uniform(-1, 1, 3))
            t = self.fourbar.rollout(q0, 20, qdot0=v0)
            return kind, (t.q, t.p, t.multipliers)
        return kind, self.fourbar.project(self.q_fourbar + rng.uniform(-0.1, 0.1, 3))


def same(a, b) -> bool:
    if isinstance(a, (tuple, list)):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    return bool(np.array_equal(a, b))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="100 calls per thread")
    ap.add_argument("--calls", type=int, default=0, help="calls per thread (default 10^4, quick 100)")
    args = ap.parse_args()
    per_thread = args.calls or (100 if args.quick else 10_000)
    total = THREADS * per_thread
    calls = Calls()
    t0 = time.perf_counter()
    expected = [calls(k)[1] for k in range(total)]
    sequential_s = time.perf_counter() - t0

    def worker(first: int) -> tuple[int, dict]:
        """Its share of the calls, each compared at once (nothing kept: the memory is hovi's)."""
        bad, kinds = 0, {kind: 0 for kind in KINDS}
        for k in range(first, total, THREADS):
            kind, value = calls(k)
            kinds[kind] += 1
            bad += not same(value, expected[k])
        return bad, kinds

    rounds, mismatches, counts = [], 0, {kind: 0 for kind in KINDS}
    for r in range(3):  # memory must be flat from the first round on
        t0 = time.perf_counter()
        with ThreadPoolExecutor(THREADS) as pool:
            parts = list(pool.map(worker, range(THREADS)))
        seconds = time.perf_counter() - t0
        mismatches += sum(bad for bad, _ in parts)
        if r == 0:
            counts = {kind: sum(c[kind] for _, c in parts) for kind in KINDS}
        rounds.append({"seconds": seconds, "rss_mb": rss_mb()})
    growth = rounds[-1]["rss_mb"] - rounds[0]["rss_mb"]
    payload = {"threads": THREADS, "calls_per_thread": per_thread, "calls_per_round": total, "rounds": rounds,
               "calls_by_kind": counts, "mismatches": mismatches, "sequential_seconds": sequential_s,
               "rss_growth_mb_rounds_1_to_3": growth}
    path = write_json("soak_threads_quick.json" if args.quick else "soak_threads.json", payload)
    print(f"{len(rounds)} rounds of {total} calls on {THREADS} threads: {mismatches} results differ from the "
          f"sequential calls; RSS {rounds[0]['rss_mb']:.1f} -> {rounds[-1]['rss_mb']:.1f} MB; wrote {path}")
    if not args.quick:
        update_readme_section("soak_threads", (
            f"{len(rounds)} rounds of {total} calls ({per_thread} per thread, kinds {counts}) on {THREADS} threads "
            f"sharing one pendulum Integrator, its Linearizer and one four-bar Integrator: {mismatches} results "
            f"differ from the same call made alone (bit for bit); resident memory "
            f"{rounds[0]['rss_mb']:.1f} MB after the first round, {rounds[-1]['rss_mb']:.1f} MB after the third "
            f"({growth:+.1f} MB). A round takes {np.mean([r['seconds'] for r in rounds]):.1f} s on the threads against "
            f"{sequential_s:.1f} s sequentially (2 cores; not a timing study)."))
    sys.exit(1 if mismatches or growth > 5.0 else 0)


if __name__ == "__main__":
    main()
