"""Many rollouts at once: how batched and distributed runs scale on this machine, and
what that means for a cluster.

1. ``Integrator.rollout_batch`` (12-link pendulum, Simpson, dt = 0.01): steps per second on 1 and
   2 C++ threads, and the efficiency (throughput on 2 threads / on 1).
2. The Fig. 2 one-step study (32-link pendulum, trapezoidal, exact Newton, dt = 0.01) on a Dask
   LocalCluster of 1 and 2 worker processes (``hovi.distributed.one_step_batch``) against the same
   study on one local thread: solves per second.
3. The overhead of a task: the wall time per task of many empty tasks on the 2-worker cluster (the
   scheduler's rate, tasks per second) and of ``hovi.distributed`` tasks of one solve each
   (scatter, chunking, transfers and gathering included), against the time of one solve.

From these the README section derives what to expect on a cluster of many machines: the tasks
per second the scheduler handles, and the chunk (solves per task) that amortises the overhead.
Every timing is the best of several repetitions (for the threads, 1 and 2 taken in turn, 15
times); the machine is shared, so rerun it on a quiet one for figures to quote.

    python bench/scaling.py [--quick]

Writes bench/results/scaling.json (and the README section "scaling").
"""
from __future__ import annotations

import math
import os
import resource
import time

import numpy as np

import hovi
import hovi.baselines
import hovi.distributed
from common import study_parser, update_readme_section, write_json

REPEATS = 3


def best_time(run, repeats=REPEATS) -> float:
    """The shortest wall time of `repeats` calls of run()."""
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    return min(times)


def timed(run) -> dict:
    """Wall time, CPU time of this process (all its threads) and its context switches over run():
    cpu / wall is the number of cores the run got; voluntary switches are waits (on a lock, say),
    involuntary ones preemption by other processes."""
    r0, t0 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
    run()
    wall, r1 = time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_SELF)
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    return {"seconds": wall, "cpu_seconds": cpu, "cores_used": cpu / wall,
            "voluntary_switches": r1.ru_nvcsw - r0.ru_nvcsw, "involuntary_switches": r1.ru_nivcsw - r0.ru_nivcsw}


def rollout_threads(states, steps, thread_counts, repeats):
    """Steps per second of rollout_batch on each thread count: the best of `repeats` runs, the
    counts taken in turn, so that a moment when other jobs leave the cores free serves each."""
    integ = hovi.Integrator(hovi.examples.models.pendulum(12), s=2, dt=0.01)
    rng = np.random.default_rng(0)
    q0s = rng.uniform(-0.5, 0.5, (states, 12))
    integ.rollout_batch(q0s[:2], 10, threads=1)  # warm up (workspaces, pages)
    best: dict[int, dict] = {}
    for _ in range(repeats):
        for threads in thread_counts:
            r = timed(lambda: integ.rollout_batch(q0s, steps, threads=threads))
            if threads not in best or r["seconds"] < best[threads]["seconds"]:
                best[threads] = r
    rows = [{"threads": t, **best[t], "steps_per_second": states * steps / best[t]["seconds"]} for t in thread_counts]
    for r in rows:
        r["efficiency"] = r["steps_per_second"] / rows[0]["steps_per_second"]
        # the same per core the run actually got (less than `threads` when other jobs hold cores)
        r["efficiency_per_core_used"] = (r["steps_per_second"] / r["cores_used"]) / (
            rows[0]["steps_per_second"] / rows[0]["cores_used"])
    return {"model": "pendulum(12)", "s": 2, "dt": 0.01, "states": states, "steps": steps, "repeats": repeats,
            "rows": rows}


def fig2_states(count):
    rng = np.random.default_rng(0)
    return rng.uniform(-np.pi / 2, np.pi / 2, (2, count, 32))


def dask_fig2(states, worker_counts, tasks):
    from distributed import Client, LocalCluster
    model = hovi.examples.models.pendulum(32)
    q0, qd0 = fig2_states(states)
    local = best_time(lambda: hovi.baselines.one_step_batch(model, 0.01, q0, qd0, "newton", threads=1))
    rows = [{"run": "local, 1 thread", "workers": 0, "seconds": local, "solves_per_second": states / local}]
    overhead = {}
    for workers in worker_counts:
        with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            def study():
                return hovi.distributed.one_step_batch(model, 0.01, q0, qd0, "newton", client=client)
            study()  # warm up: the workers import hovi
            seconds = best_time(study)
            rows.append({"run": f"Dask LocalCluster, {workers} worker process{'es' if workers > 1 else ''}",
                         "workers": workers,
                         "tasks": len(hovi.distributed._chunks(states, 1, client, None)),
                         "seconds": seconds, "solves_per_second": states / seconds})
            if workers == max(worker_counts):
                overhead = task_overhead(client, model, tasks)
    for r in rows:
        r["speedup_over_local"] = r["solves_per_second"] / rows[0]["solves_per_second"]
    return {"model": "pendulum(32)", "method": "newton", "dt": 0.01, "states": states, "rows": rows, "overhead": overhead}


def _empty(i):
    return i


def task_overhead(client, model, tasks):
    """Wall time per task: empty tasks (the scheduler and the round trips alone), and hovi tasks of
    one Fig. 2 solve each, against one such solve on this process."""
    client.gather(client.map(_empty, range(10), pure=False))
    empty = best_time(lambda: client.gather(client.map(_empty, range(tasks), pure=False)))
    q0, qd0 = fig2_states(tasks)
    one_each = best_time(lambda: hovi.distributed.one_step_batch(model, 0.01, q0, qd0, "newton", client=client,
                                                                 chunk_size=1))
    solve = np.median(hovi.baselines.one_step_batch(model, 0.01, q0, qd0, "newton", threads=1)["seconds"])
    workers = len(client.nthreads())
    return {"tasks": tasks, "workers": workers,
            "empty_task_seconds": empty / tasks, "scheduler_tasks_per_second": tasks / empty,
            # each worker runs tasks / workers of them one after another
            "hovi_task_seconds": one_each / tasks, "hovi_task_overhead_seconds": one_each * workers / tasks - solve,
            "solve_seconds": float(solve)}


def duration(seconds: float) -> str:
    return f"{1e3 * seconds:.0f} ms" if seconds < 1 else f"{seconds:.1f} s"


def cluster_section(out) -> str:
    """What a user should expect on a cluster of many machines, from the measurements."""
    thr = out["threads"]["rows"]
    eff = thr[-1]["efficiency"] if len(thr) > 1 else float("nan")
    dk = out["dask"]["rows"]
    ov = out["dask"]["overhead"]
    rate = ov["scheduler_tasks_per_second"]
    per_task = ov["hovi_task_overhead_seconds"]
    solve = ov["solve_seconds"]
    step = thr[0]["seconds"] / (out["threads"]["states"] * out["threads"]["steps"])
    # chunks that keep the overhead at 5% of a task's work; tasks long enough that 100 workers
    # (or 1000) do not ask more of the scheduler than a tenth of its rate
    amortise = math.ceil(per_task / (0.05 * solve))
    default_task = hovi.distributed.SOLVES_PER_TASK * solve  # seconds of a default task of Fig. 2 solves
    lines = [
        f"| measured (this machine: {out['machine_cores']} cores; load average {out['load_average'][0]:.1f} "
        "when the run began) | |",
        "|---|---|",
        f"| `rollout_batch`, 12-link pendulum, Simpson: steps per second on 1 / 2 threads | "
        f"{thr[0]['steps_per_second']:.0f} / {thr[-1]['steps_per_second']:.0f} (efficiency {eff:.2f}x; target ≥ 1.8x) |",
        f"| … cores the runs got (CPU time / wall time); waits of a thread on another (voluntary context switches) | "
        f"{thr[0]['cores_used']:.2f} / {thr[-1]['cores_used']:.2f}; {thr[-1]['voluntary_switches']} |",
        f"| … steps per second per core got, 2 threads against 1 | {thr[-1]['efficiency_per_core_used']:.2f}x |",
    ]
    for r in dk:
        lines.append(f"| Fig. 2 study ({out['dask']['states']} one-step solves, 32 links): {r['run']} | "
                     f"{r['solves_per_second']:.0f} solves/s ({r['speedup_over_local']:.2f}x the local thread) |")
    lines += [
        f"| empty Dask tasks on {ov['workers']} workers: wall time per task; tasks per second | "
        f"{1e3 * ov['empty_task_seconds']:.2f} ms; {rate:.0f} |",
        f"| `hovi.distributed` tasks of one solve: overhead per task beyond the solve | {1e3 * per_task:.2f} ms |",
        f"| one Fig. 2 solve (dt = 0.01); one rollout step (12 links, Simpson) | {1e6 * solve:.0f} µs; {1e6 * step:.0f} µs |",
        "",
        "**On a cluster of many machines.** Two costs bound how finely the work can be cut. The "
        f"scheduler handled {rate:.0f} empty tasks per second here (the Dask documentation quotes about "
        "1 ms of overhead per task): with W workers each task must last at least W / rate for the "
        "scheduler to keep up, and ten times that to leave it idle most of the time, i.e. "
        f"{duration(10 * 100 / rate)} for 100 workers and {duration(10 * 1000 / rate)} for 1000. Each "
        f"task also pays about {1e3 * per_task:.1f} ms of its own "
        "(sending the chunk and the result, deserialising, the Python around the C++ batch): for that to "
        f"be 5% of the task, a chunk needs {amortise} solves of {1e6 * solve:.0f} µs. "
        f"`hovi.distributed` puts {hovi.distributed.SOLVES_PER_TASK} solves in a task by default (a rollout "
        f"of K steps counts K): {duration(default_task)} of such solves, which keeps the scheduler within its "
        f"rate up to about {default_task * rate:.0f} workers ({default_task * rate / 10:.0f} with the tenfold "
        "margin); for more, raise `chunk_size` so that a task lasts seconds. The results travel back with each task (a rollout "
        "returns (s+3) n doubles per step), so on a network the chunk size also sets the message size. "
        "Within a machine the C++ threads of `rollout_batch` have no such costs (a workspace per thread, "
        "no copies beyond the results): use them for the cores of one machine and Dask across machines, "
        "with `threads_per_task` set to the cores of a worker.",
    ]
    return "\n".join(lines)


def main():
    ap = study_parser(__doc__, "a few states and steps (a smoke run)")
    args = ap.parse_args()
    states, steps, repeats, fig2, tasks = (8, 40, 2, 60, 100) if args.quick else (64, 200, 15, 2000, 1000)
    out = {"load_average": list(os.getloadavg()), "machine_cores": os.cpu_count(),
           "threads": rollout_threads(states, steps, [1, 2], repeats), "dask": dask_fig2(fig2, [1, 2], tasks),
           "solves_per_task": hovi.distributed.SOLVES_PER_TASK}
    text = cluster_section(out)
    name = "scaling_quick" if args.quick else "scaling"
    write_json(f"{name}.json", out)
    print(text)
    if not args.quick:
        update_readme_section("scaling", text)


if __name__ == "__main__":
    main()
