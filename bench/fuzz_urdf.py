"""URDF fuzzing by structured mutation: every input must end in a model with finite parameters or
in a hovi.URDFError; a crash (the worker process dies), a hang (no answer within the time limit),
another exception, or a model with a non-finite parameter is a finding.

Seeds: the URDFs in models/ and every URDF of example-robot-data. Mutations (one or a few per
input): delete / duplicate an element, set a number attribute to a hostile value (NaN, inf, 1e308,
text, empty, a wrong count), delete an attribute, unicode / empty / clashing names, a joint whose
child is its own ancestor (a cycle), an unknown joint type, truncated XML; plus synthetic deep
chains (up to 3000 links). Inputs run in worker processes, one at a time, restarted after a crash.

    python bench/fuzz_urdf.py            # 10^4 inputs, results/fuzz_urdf.json and bench/README.md
    python bench/fuzz_urdf.py --quick    # a few hundred (the test suite)
"""
from __future__ import annotations

import argparse
import glob
import multiprocessing as mp
import os
import random
import sys
import time
import xml.etree.ElementTree as ET
from collections import Counter

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from common import ROOT, update_readme_section, write_json  # noqa: E402

HOSTILE_NUMBERS = ["nan", "NaN", "inf", "-inf", "1e308", "-1e308", "1e-320", "abc", "", "1 2", "0x10", "1,5",
                   "0", "-1", "1e999", "   ", "1 2 3 4", "+-1"]
HOSTILE_NAMES = ["", "ß∂ƒ©", "🤖", "a/b", "a b", "x" * 5000, "base", "\u0000"]
JOINT_TYPES = ["spherical", "bogus", "", "floating", "planar", "fixed", "continuous", "prismatic"]
MUTATIONS = ["delete_element", "duplicate_element", "hostile_number", "delete_attribute", "hostile_name",
             "cycle", "joint_type", "truncate"]
TIME_LIMIT = 20.0  # seconds per input


def seeds() -> list[tuple[str, str]]:
    files = sorted(glob.glob(os.path.join(ROOT, "models", "*.urdf")))
    try:
        import example_robot_data
        robots = example_robot_data.getModelPath("ur_description/urdf/ur5_robot.urdf")
        files += sorted(glob.glob(os.path.join(robots, "*", "urdf", "*.urdf")))
    except ImportError:
        pass
    out = []
    for f in files:
        with open(f, encoding="utf-8") as fh:
            out.append((os.path.relpath(f, ROOT) if f.startswith(ROOT) else f.split("robots/")[-1], fh.read()))
    return out


def mutate(xml: str, rng: random.Random, kind: str) -> str:
    """One structured mutation of a URDF text."""
    if kind == "truncate":
        return xml[:rng.randrange(1, max(2, len(xml)))]
    root = ET.fromstring(xml)
    elements = [e for e in root.iter() if e is not root]
    parents = {c: p for p in root.iter() for c in p}
    if not elements:
        return xml
    e = rng.choice(elements)
    if kind == "delete_element":
        parents[e].remove(e)
    elif kind == "duplicate_element":
        parents[e].append(ET.fromstring(ET.tostring(e)))
    elif kind == "hostile_number":
        numeric = [(el, a) for el in elements for a in el.attrib if a not in ("name", "link", "type", "filename", "joint")]
        if numeric:
            el, a = rng.choice(numeric)
            value = rng.choice(HOSTILE_NUMBERS)
            parts = el.attrib[a].split()
            if len(parts) > 1 and rng.random() < 0.5:
                parts[rng.randrange(len(parts))] = value
                value = " ".join(parts)
            el.set(a, value)
    elif kind == "delete_attribute":
        if e.attrib:
            del e.attrib[rng.choice(list(e.attrib))]
    elif kind == "hostile_name":
        named = [el for el in elements if "name" in el.attrib or "link" in el.attrib]
        if named:
            el = rng.choice(named)
            el.set("name" if "name" in el.attrib else "link", rng.choice(HOSTILE_NAMES).replace("\u0000", ""))
    elif kind == "cycle":
        joints = root.findall("joint")
        if joints:
            j = rng.choice(joints)
            child, parent = j.find("child"), j.find("parent")
            if child is not None and parent is not None:
                child.set("link", root.findall("link")[0].get("name", ""))
    elif kind == "joint_type":
        joints = root.findall("joint")
        if joints:
            rng.choice(joints).set("type", rng.choice(JOINT_TYPES))
    return ET.tostring(root, encoding="unicode")


def deep_chain(n: int) -> str:
    links = ['<link name="l0"/>'] + [
        f'<link name="l{i}"><inertial><mass value="0.1"/><inertia ixx="1e-3" ixy="0" ixz="0" iyy="1e-3" iyz="0" '
        f'izz="1e-3"/></inertial></link>' for i in range(1, n + 1)]
    joints = [f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
              f'<origin xyz="0 0 -0.01"/><axis xyz="{(i % 2)} {((i + 1) % 2)} 0"/><limit lower="-1" upper="1" '
              f'effort="1" velocity="1"/></joint>' for i in range(1, n + 1)]
    return '<robot name="chain">' + "".join(links + joints) + "</robot>"


def check(xml: str) -> tuple[str, str]:
    """(outcome, detail) of loading one input: 'model', 'urdf_error', 'non_finite' or 'other_exception'."""
    import hovi
    try:
        model = hovi.Model.from_urdf(xml)
    except hovi.URDFError as e:
        return "urdf_error", str(e)[:300]
    except Exception as e:  # noqa: BLE001 - any other exception type is a finding
        return "other_exception", f"{type(e).__name__}: {str(e)[:300]}"
    q = np.zeros(model.n)
    values = [model.masses, model.mass_matrix(q), model.joint_placements(q), model.potential_energy(q)]
    values += [v[k] for v in model.visuals for k in ("size", "scale", "origin")]
    if not all(np.all(np.isfinite(np.asarray(v, dtype=float))) for v in values):
        return "non_finite", model.summary()[:300]
    return "model", f"{model.n} DoF"


def worker(conn) -> None:
    while True:
        xml = conn.recv()
        if xml is None:
            return
        conn.send(check(xml))


class Runner:
    """One worker process answering one input at a time; restarted after a crash or a hang."""

    def __init__(self, ctx):
        self.ctx = ctx
        self.start()

    def start(self):
        self.conn, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=worker, args=(child,), daemon=True)
        self.proc.start()

    def run(self, xml: str) -> tuple[str, str]:
        self.conn.send(xml)
        if self.conn.poll(TIME_LIMIT):
            try:
                return self.conn.recv()
            except EOFError:
                pass
        crashed = not self.proc.is_alive()
        self.proc.kill()
        self.proc.join()
        code = self.proc.exitcode
        self.start()
        return ("crash", f"exit code {code}") if crashed else ("hang", f"no answer in {TIME_LIMIT} s")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="a few hundred inputs")
    ap.add_argument("--inputs", type=int, default=0, help="number of mutated inputs (default 10^4, quick 300)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--save-findings", metavar="DIR", help="write every finding's whole input to DIR")
    args = ap.parse_args()
    total = args.inputs or (300 if args.quick else 10_000)
    rng = random.Random(args.seed)
    corpus = seeds()
    runner = Runner(mp.get_context("spawn"))
    outcomes: Counter = Counter()
    per_mutation: dict = {m: Counter() for m in MUTATIONS + ["deep_chain"]}
    findings, errors_named, t0 = [], 0, time.perf_counter()
    chains = [10, 100, 1000, 3000] if not args.quick else [10, 300]
    for k in range(total):
        if k < len(chains):
            kind, source, xml = "deep_chain", f"chain of {chains[k]}", deep_chain(chains[k])
        else:
            source, text = corpus[rng.randrange(len(corpus))]
            kinds = [rng.choice(MUTATIONS) for _ in range(rng.choice([1, 1, 1, 2, 3]))]
            kind = kinds[-1]
            xml = text
            for m in kinds:
                try:
                    xml = mutate(xml, rng, m)
                except ET.ParseError:
                    break  # an earlier truncation: the text is already malformed
        outcome, detail = runner.run(xml)
        outcomes[outcome] += 1
        per_mutation[kind][outcome] += 1
        if outcome == "urdf_error" and any(w in detail for w in ("link '", "joint '", "material '", "visual of '", "URDF")):
            errors_named += 1
        if outcome in ("crash", "hang", "other_exception", "non_finite"):
            findings.append({"source": source, "mutation": kind, "outcome": outcome, "detail": detail,
                             "input": xml[:2000]})
            if args.save_findings:
                os.makedirs(args.save_findings, exist_ok=True)
                with open(os.path.join(args.save_findings, f"{k:05d}_{outcome}.urdf"), "w", encoding="utf-8") as fh:
                    fh.write(xml)
    runner.conn.send(None)
    wall = time.perf_counter() - t0
    payload = {"inputs": total, "seconds": wall, "outcomes": dict(outcomes),
               "per_mutation": {m: dict(c) for m, c in per_mutation.items() if c},
               "urdf_errors_naming_the_element": errors_named, "seeds": [s for s, _ in corpus],
               "findings": findings[:50], "time_limit_s": TIME_LIMIT}
    path = write_json("fuzz_urdf_quick.json" if args.quick else "fuzz_urdf.json", payload)
    bad = sum(outcomes[o] for o in ("crash", "hang", "other_exception", "non_finite"))
    print(f"{total} inputs in {wall:.1f} s: {dict(outcomes)}; URDFErrors naming a link, joint, material or "
          f"the URDF: {errors_named} of {outcomes['urdf_error']}; findings {bad}; wrote {path}")
    if not args.quick:
        rows = ["| mutation | inputs | model | URDFError | crash | hang | other exception | non-finite |",
                "|---|---|---|---|---|---|---|---|"]
        for m, c in per_mutation.items():
            if c:
                rows.append(f"| {m} | {sum(c.values())} | {c['model']} | {c['urdf_error']} | {c['crash']} | {c['hang']} "
                            f"| {c['other_exception']} | {c['non_finite']} |")
        rows.append(f"\n{total} inputs from {len(corpus)} seed URDFs in {wall:.0f} s (time limit {TIME_LIMIT:.0f} s each); "
                    f"{errors_named} of {outcomes['urdf_error']} URDFErrors name a link, joint or material (or say "
                    f"the URDF is malformed).")
        update_readme_section("fuzz_urdf", "\n".join(rows))
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
