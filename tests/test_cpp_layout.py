"""The C++ tree's include graph (the ``#include "hovi/..."`` lines of cpp/include, cpp/src and
cpp/baselines): no include cycle at header level (a .cpp counts as the .hpp it implements), and no
include against the layer order

    spatial -> model -> {algorithms, forces} -> constraints -> parsers -> integrators -> trajopt
        -> control

(the bindings above all). model/ holds the Model and the interfaces it stores (BodyWrench,
Constraint, JointForces) and the contact model the simulator and the optimiser share, so that algorithms compute through the interfaces only; forces/ and
constraints/ hold the built-in kinds (a constraint's multipliers act through force elements, so
constraints sit above forces); parsers/ read and write models (URDF, the byte format of
model_serialization), every kind included. The baselines may include the product; the product
never includes the baselines. Directories outside the named layers (util, quadrature, parallel,
errors.hpp) sit at the bottom, beside spatial; models (built-in models) is a peer of algorithms.
integrators/ holds the one stepper with its contact stages (contact is a stage of the step, not a
second simulator) and its linearisation. control (Riccati, policies, FDDP, MPC) steps the integrator
and solves with its linearisation, so it sits above it."""
from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
# Each tree with the include path of its files (a .cpp of src/ implements the .hpp of the same path).
TREES = {ROOT / "cpp" / "include": "", ROOT / "cpp" / "src": "hovi/", ROOT / "cpp" / "baselines" / "include": "",
         ROOT / "cpp" / "baselines" / "src": "hovi/baselines/"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"(hovi/[^"]+)"', re.M)
# Layer of each area: an area may include its own and lower layers; the peers of one layer
# (algorithms, forces, models) may not include each other.
LAYERS = {"errors.hpp": 0, "spatial": 1, "util": 2, "quadrature": 2, "parallel": 2, "model": 3,
          "algorithms": 4, "forces": 4, "models": 4, "constraints": 5, "parsers": 6,
          "integrators": 7, "trajopt": 8, "control": 9, "baselines": 10}
# Arrows against the order and cycles that the tree is allowed to keep: none (a new one fails).
KNOWN: set[str] = set()
KNOWN_CYCLES: set[str] = set()


def _header_of(path: Path) -> str:
    """The hovi/... header a file is, or implements (a .cpp: its .hpp)."""
    for tree, prefix in TREES.items():
        if path.is_relative_to(tree):
            rel = prefix + path.relative_to(tree).as_posix()
            return rel[:-len(".cpp")] + ".hpp" if rel.endswith(".cpp") else rel


def _area(header: str) -> str:
    return header.split("/")[1]


def include_graph() -> dict[str, set[str]]:
    graph: dict[str, set[str]] = {}
    for tree in TREES:
        for path in sorted(tree.rglob("*.[ch]pp")):
            node = _header_of(path)
            graph.setdefault(node, set()).update(
                inc for inc in INCLUDE.findall(path.read_text()) if inc != node)
    return graph


def test_layers_are_known():
    unknown = sorted({_area(h) for h in include_graph()} - set(LAYERS))
    assert not unknown, f"areas without a layer in tests/test_cpp_layout.py: {unknown}"


def test_no_include_against_the_layer_order():
    bad = []
    for node, includes in include_graph().items():
        for inc in includes:
            a, b = _area(node), _area(inc)
            if a != b and LAYERS[b] >= LAYERS[a] and f"{node} includes {inc}" not in KNOWN:
                bad.append(f"{node} includes {inc} ({a} may not include {b})")
    assert not bad, "\n".join(sorted(bad))


def test_no_include_cycle():
    graph = include_graph()
    state: dict[str, int] = {}
    stack: list[str] = []
    cycles = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if state.get(nxt) == 1:
                cycle = " -> ".join(stack[stack.index(nxt):] + [nxt])
                if cycle not in KNOWN_CYCLES:
                    cycles.append(cycle)
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert not cycles, "include cycles:\n" + "\n".join(cycles)


def test_the_product_never_includes_the_baselines():
    product = [p for tree in (ROOT / "cpp" / "include", ROOT / "cpp" / "src") for p in tree.rglob("*.[ch]pp")]
    product += list((ROOT / "cpp" / "bindings").glob("*.[ch]pp"))
    bad = [str(p.relative_to(ROOT)) for p in product if "hovi/baselines/" in p.read_text()]
    assert not bad, bad
