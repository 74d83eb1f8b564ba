"""Shared helpers of the benchmark scripts: machine description, JSON output, slopes."""
from __future__ import annotations

import contextlib
import json
import os
import platform
import subprocess
import sys
import sysconfig
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# The committed full runs (what a study reads of another's, or re-tabulates), and where the studies
# write their JSON files and figures: the same folder, or HOVI_BENCH_RESULTS (the quick runs of
# tests/test_bench_quick.py write into a temporary folder and read what they wrote there).
COMMITTED = os.path.join(ROOT, "bench", "results")
RESULTS = os.environ.get("HOVI_BENCH_RESULTS") or COMMITTED


def machine() -> dict:
    cpu = ""
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next((l.split(":", 1)[1].strip() for l in f if l.startswith("model name")), "")
    except OSError:
        pass
    from hovi import _core
    return {"cpu": cpu, "cores": os.cpu_count(), "python": sys.version.split()[0], "platform": platform.platform(),
            "hovi_march": _core.march or "compiler default"}


def study_parser(doc: str, quick: str = "a small smoke run, no README update"):
    """The argument parser of a study: its description (the docstring's first line) and --quick (``quick``: what
    the smoke run does)."""
    import argparse
    ap = argparse.ArgumentParser(description=doc.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help=quick)
    return ap


def add_parallel_arguments(ap) -> None:
    """--workers N and --scheduler ADDRESS of the studies that sweep many states (see parallel())."""
    ap.add_argument("--workers", type=int, default=1,
                    help="local C++ threads over the states (rollout_batch / one-step batch); default 1: the times "
                         "per solve are then those of one core alone; with --scheduler local, the number of worker processes")
    ap.add_argument("--scheduler", default=None,
                    help="run the states on a Dask cluster (hovi.distributed): a scheduler's address "
                         "(tcp://host:8786), or 'local' for a LocalCluster of --workers processes on this machine")


@contextlib.contextmanager
def parallel(args):
    """The Dask Client of --scheduler (None without one: the study runs on --workers local threads);
    a LocalCluster started for 'local' is closed at the end."""
    if args.workers < 1:
        sys.exit("--workers must be at least 1")
    if args.scheduler is None:
        yield None
        return
    from distributed import Client, LocalCluster
    if args.scheduler == "local":
        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True, dashboard_address=None) as cluster, \
                Client(cluster) as client:
            yield client
    else:
        with Client(args.scheduler) as client:
            yield client


def parallel_description(args) -> dict:
    """How the states were spread, for the JSON files."""
    return {"workers": args.workers, "scheduler": args.scheduler}


def hovi_commit() -> str:
    """The short hash of the checkout's HEAD (empty outside a git checkout), for the JSON files."""
    done = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    return done.stdout.strip()


def write_json(name: str, payload: dict) -> str:
    os.makedirs(RESULTS, exist_ok=True)
    path = os.path.join(RESULTS, name)
    with open(path, "w") as f:
        json.dump({"machine": machine(), **payload}, f, indent=1)
    return path


def json_ready(x, nonfinite_as_text: bool = False):
    """JSON-ready: numpy scalars and arrays to Python; infinities and NaN to None (or to their text)."""
    if isinstance(x, dict):
        return {str(k): json_ready(v, nonfinite_as_text) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [json_ready(v, nonfinite_as_text) for v in x]
    if isinstance(x, np.ndarray):
        return json_ready(x.tolist(), nonfinite_as_text)
    if isinstance(x, (np.bool_, bool)):
        return bool(x)
    if isinstance(x, (np.integer, int)):
        return int(x)
    if isinstance(x, (np.floating, float)):
        return float(x) if np.isfinite(x) else (str(x) if nonfinite_as_text else None)
    return x


def markdown_table(header, rows) -> list:
    """The lines of a Markdown table: the header's cells, then one line per row of cells (any values)."""
    return ["| " + " | ".join(map(str, header)) + " |", "|" + "---|" * len(header)] + \
        ["| " + " | ".join(map(str, row)) + " |" for row in rows]


def publish(tag: str, text: str, quick: bool) -> None:
    """Prints a study's table and, after a full run, writes it into bench/README.md's ``tag`` section."""
    print(text)
    if not quick:
        update_readme_section(tag, text)


def save_figure(fig, path: str) -> None:
    """Lays out a matplotlib figure, writes it (120 dpi) and closes it."""
    import matplotlib.pyplot as plt
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def save_times_against_n(fig, panels, path: str) -> None:
    """Finishes the panels of a figure of times per call against n (``panels``: (axes, title) pairs,
    log-log, the first with the axis label) and saves it."""
    for ax, title in panels:
        ax.set_title(title)
        ax.set_xlabel("n (links)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    panels[0][0].set_ylabel("time per call [µs]")
    save_figure(fig, path)


def best_rollout(integ, q0, steps: int, repeats: int):
    """(the least C++ time per step over ``repeats`` rollouts of ``steps`` steps from q0 at rest, mean
    Newton iterations and factorisations per step of the last)."""
    best = np.inf
    for _ in range(repeats):
        traj = integ.rollout(q0, steps)
        best = min(best, traj.solve_seconds / steps)
    return best, float(np.mean(traj.iterations)), float(np.mean(traj.factorizations))


def loglog_slope(x, y) -> float:
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def pinocchio_prefix() -> str:
    """The pin wheel's install prefix (headers and libpinocchio_default)."""
    return os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix")


def build_cpp_bench() -> str:
    """The C++ benchmark against Pinocchio's C++ (bench/cpp/speed.cpp); returns the binary's path. It
    lives in the package's CMake tree, build/py, where `make ctest` builds it with the C++ tests (so
    that a quick run only runs it); if missing there, it is configured and built (the core library
    is reused)."""
    build = os.path.join(ROOT, "build", "py")
    binary = os.path.join(build, "hovi_bench_speed")
    cmds = [] if os.path.isfile(binary) else [
        ["cmake", "-S", ROOT, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DHOVI_BUILD_BENCH=ON",
         f"-DHOVI_PINOCCHIO_PREFIX={pinocchio_prefix()}"]]
    cmds.append(["cmake", "--build", build, "-j", str(os.cpu_count() or 2), "--target", "hovi_bench_speed"])
    for cmd in cmds:
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode:
            sys.exit(f"building the C++ benchmark failed:\n{done.stdout}\n{done.stderr}")
    return binary


def update_readme_section(tag: str, text: str):
    """Replace the text between <!-- tag:begin --> and <!-- tag:end --> in bench/README.md."""
    path = os.path.join(ROOT, "bench", "README.md")
    begin, end = f"<!-- {tag}:begin -->", f"<!-- {tag}:end -->"
    doc = open(path).read() if os.path.exists(path) else ""
    block = f"{begin}\n{text.rstrip()}\n{end}"
    if begin in doc and end in doc:
        doc = doc[:doc.index(begin)] + block + doc[doc.index(end) + len(end):]
    else:
        doc = doc.rstrip() + "\n\n" + block + "\n"
    with open(path, "w") as f:
        f.write(doc)


def erd_urdf(rel: str) -> str:
    import example_robot_data as erd
    return os.path.join(erd.getModelPath(rel), rel)


def solve_quick_example(name: str, solutions: str | None):
    """(example, motion arrays, solve figures) of the quick example ``name``: solved once, or loaded
    from DIR/<name>.npz (``solutions``, written there after a solve)."""
    from hovi.examples.paper import build, report
    example = build(name, quick=True)
    path = None if solutions is None else os.path.join(solutions, f"{name}.npz")
    if path is not None and os.path.exists(path):
        d = dict(np.load(path))
        return example, d, {"loaded_from": path, "success": bool(d["success"])}
    t0 = time.perf_counter()
    result = report.solve(example)
    wall = time.perf_counter() - t0
    tr, tc = result.trajectory, result.transcription
    d = {"knots": tr["q"][::tc.s], "p": tr["p"], "U": tc.stage_controls(result.x), "success": result.success}
    if path is not None:
        os.makedirs(solutions, exist_ok=True)
        np.savez(path, **d)
    return example, d, {"solve_seconds": wall, "success": bool(result.success), "status": result.status}
