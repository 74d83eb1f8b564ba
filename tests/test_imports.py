"""hovi's module structure, read from the source with ``ast`` (nothing is imported).

(a) No import cycle among hovi's modules. Every import counts: at module level, inside
    functions, and under ``if TYPE_CHECKING:``. Importing ``hovi.a.b`` from a module M runs
    ``hovi/a/__init__.py`` as well, so it is an edge M -> hovi.a.b and an edge M -> hovi.a for each
    package on the way that is not a package of M itself (M's own packages are initialised
    before M runs). ``from X import name`` is an edge to the submodule X.name when there is one,
    else to X (the package's ``__init__``, even M's own package). A package-level back-arrow
    such as hovi.contact -> hovi.trajopt -> hovi.contact is therefore a cycle.

(b) No use of a private name across modules:
    - ``from .x import _y`` where ``_y`` is not a module is refused (a private function, class or
      constant belongs to its module);
    - a private module (``_name.py``, a private package, or the compiled extensions ``_core`` and
      ``_baselines``) is private to the package that holds it: any module inside that package may
      import it (``hovi._bodies``, ``hovi._typing``, ``hovi._core`` from anywhere in hovi), no
      module outside may;
    - ``obj._name`` where ``obj`` is an imported module (``module._helper``), or any other object
      but ``self``/``cls`` when no class or function of this module defines or assigns ``_name``
      (``rows._input(...)`` in a module that does not define ``_input``): reaching into another
      module's object. Dunder names and the namedtuple API (``_replace``, ``_asdict``, ``_fields``,
      ``_make``) are public.
"""
from __future__ import annotations

import ast
from pathlib import Path
from typing import Dict, Iterator, List, Optional, Set, Tuple

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "python" / "hovi"
EXTENSIONS = {"hovi._core", "hovi._baselines", "hovi.trajopt.solvers._ipopt"}  # compiled: no source here
PUBLIC_UNDERSCORE = {"_replace", "_asdict", "_fields", "_make", "_field_defaults"}


def module_files() -> Dict[str, Path]:
    """hovi's modules by dotted name (a package by the name of its ``__init__``)."""
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        parts = ("hovi",) + path.relative_to(PACKAGE).with_suffix("").parts
        if parts[-1] == "__init__":
            parts = parts[:-1]
        found[".".join(parts)] = path
    return found


MODULES = module_files()
PACKAGES = {name for name, path in MODULES.items() if path.name == "__init__.py"}
KNOWN = set(MODULES) | EXTENSIONS


def ancestors(name: str) -> List[str]:
    """The packages above ``name``: hovi.a.b -> [hovi, hovi.a]."""
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


def is_known(name: str) -> bool:
    """A hovi module, or a submodule of a compiled extension (hovi._core.trajopt)."""
    return name in KNOWN or any(name.startswith(e + ".") for e in EXTENSIONS)


def owner(name: str) -> str:
    """The module that holds ``name``'s source: a compiled extension's submodule is the extension."""
    for e in EXTENSIONS:
        if name == e or name.startswith(e + "."):
            return e
    return name


def resolve(module: str, node: ast.ImportFrom) -> str:
    """The absolute name of a relative ``from ... import``."""
    if not node.level:
        return node.module or ""
    base = module.split(".") if module in PACKAGES else module.split(".")[:-1]
    if node.level > 1:
        base = base[:len(base) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


class Import:
    """One imported hovi module: ``target`` (the module whose code runs), ``name`` the private name
    imported from it (None for a module or a public name), at ``line``."""

    def __init__(self, target: str, line: int, name: Optional[str] = None, module_itself: bool = True):
        self.target, self.line, self.name, self.module_itself = target, line, name, module_itself


def imports_of(module: str, tree: ast.AST) -> Iterator[Import]:
    """Every hovi import of ``module``, wherever it is in the file."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                if alias.name == "hovi" or alias.name.startswith("hovi."):
                    yield Import(alias.name, node.lineno)
        elif isinstance(node, ast.ImportFrom):
            source = resolve(module, node)
            if source != "hovi" and not source.startswith("hovi."):
                continue
            for alias in node.names:
                sub = f"{source}.{alias.name}"
                if is_known(sub):
                    yield Import(sub, node.lineno)
                else:
                    yield Import(source, node.lineno, name=alias.name, module_itself=False)


def edges_of(module: str, imp: Import) -> Set[str]:
    """The modules whose code runs (or must have run) for ``imp`` in ``module``."""
    target = owner(imp.target)
    if not is_known(target):
        return set()
    mine = set(ancestors(module))
    runs = {p for p in ancestors(target) if p not in mine}
    if target not in mine or not imp.module_itself:  # a name from M's own package needs its __init__
        runs.add(target)
    runs.discard(module)
    return {r for r in runs if r in MODULES}


def import_graph() -> Tuple[Dict[str, Set[str]], Dict[Tuple[str, str], int]]:
    graph: Dict[str, Set[str]] = {m: set() for m in MODULES}
    lines: Dict[Tuple[str, str], int] = {}
    for module, path in MODULES.items():
        for imp in imports_of(module, ast.parse(path.read_text(), str(path))):
            for target in edges_of(module, imp):
                graph[module].add(target)
                lines.setdefault((module, target), imp.line)
    return graph, lines


def cycles(graph: Dict[str, Set[str]]) -> List[List[str]]:
    """The strongly connected components with more than one module (Tarjan), each with one cycle
    through it spelled out."""
    index: Dict[str, int] = {}
    low: Dict[str, int] = {}
    stack: List[str] = []
    on: Set[str] = set()
    found: List[List[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def one_cycle(graph: Dict[str, Set[str]], component: List[str]) -> List[str]:
    """A shortest cycle through the first module of ``component`` (breadth first)."""
    start, inside = component[0], set(component)
    previous: Dict[str, str] = {}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(graph[v] & inside):
                if w == start:
                    path = [v]
                    while path[-1] != start:
                        path.append(previous[path[-1]])
                    return [start] + path[::-1][1:] + [start] if len(path) > 1 else [start, start]
                if w not in previous:
                    previous[w] = v
                    nxt.append(w)
        frontier = nxt
    return component


def test_the_walk_sees_the_package():
    assert {"hovi", "hovi.integrator", "hovi.trajopt", "hovi.contact"} <= set(MODULES)
    graph, _ = import_graph()
    assert "hovi.integrator" in graph["hovi"]  # the package imports its integrator


def test_no_import_cycles():
    graph, lines = import_graph()
    found = []
    for component in cycles(graph):
        path = one_cycle(graph, component)
        steps = ", ".join(f"{a} -> {b} ({MODULES[a].relative_to(PACKAGE.parent)}:{lines[a, b]})"
                          for a, b in zip(path, path[1:]))
        found.append(f"{' <-> '.join(component)}: {steps}")
    assert not found, "import cycles among hovi's modules:\n  " + "\n  ".join(found)


BENCH = PACKAGE.parent.parent / "bench"


def bench_graph() -> Dict[str, Set[str]]:
    """The benchmark scripts' imports of each other (bench/ is on sys.path when a script runs: ``import
    common``, ``from common import ...``), at module level and inside functions."""
    scripts = {p.stem: p for p in BENCH.glob("*.py")}
    graph: Dict[str, Set[str]] = {}
    for name, path in scripts.items():
        found = set()
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                found.update(a.name.split(".")[0] for a in node.names)
            elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
                found.add(node.module.split(".")[0])
        graph[name] = {m for m in found if m in scripts and m != name}
    return graph


def test_no_import_cycles_among_the_benchmarks():
    graph = bench_graph()
    assert "common" in graph["speed"] and "common" in graph["control_robots"]  # the walk sees them
    found = [" <-> ".join(component) for component in cycles(graph)]
    assert not found, "import cycles among bench/'s scripts:\n  " + "\n  ".join(found)


def private(name: str) -> bool:
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def private_module_home(name: str) -> Optional[str]:
    """The package a private module is private to (the package above its first private part), or
    None for a public module."""
    parts = name.split(".")
    for i, part in enumerate(parts):
        if private(part):
            return ".".join(parts[:i])
    return None


def defined_names(tree: ast.AST) -> Set[str]:
    """Names this module defines or assigns as attributes: functions, classes, ``x._name = ...``,
    class-level assignments."""
    names: Set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            names.add(node.name)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store):
            names.add(node.attr)
        elif isinstance(node, (ast.Assign, ast.AnnAssign)):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                for t in ast.walk(target):
                    if isinstance(t, ast.Name):
                        names.add(t.id)
    return names


def module_aliases(module: str, tree: ast.AST) -> Set[str]:
    """Local names bound to modules by imports (``import numpy as np``, ``from . import _core``)."""
    names: Set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                names.add(alias.asname or alias.name.split(".")[0])
        elif isinstance(node, ast.ImportFrom):
            source = resolve(module, node)
            for alias in node.names:
                if is_known(f"{source}.{alias.name}"):
                    names.add(alias.asname or alias.name)
    return names


def private_uses(module: str, tree: ast.AST, where: str) -> List[str]:
    """Every use of a private name across modules in ``module`` (its source parsed as ``tree``), by line."""
    found = {(line, text) for line, text in private_uses_unsorted(module, tree)}
    return [f"{where}:{line}: {text}" for line, text in sorted(found)]


def private_uses_unsorted(module: str, tree: ast.AST) -> Iterator[Tuple[int, str]]:
    for imp in imports_of(module, tree):
        if imp.name is not None and private(imp.name):
            yield imp.line, f"imports the private name {imp.name} from {imp.target}"
        home = private_module_home(owner(imp.target))
        if home is not None and not (module == home or module.startswith(home + ".")):
            yield imp.line, f"imports {imp.target}, private to {home}"
    own, modules = defined_names(tree), module_aliases(module, tree)
    for node in ast.walk(tree):
        if not (isinstance(node, ast.Attribute) and private(node.attr)) or node.attr in PUBLIC_UNDERSCORE:
            continue
        value = node.value
        if isinstance(value, ast.Name) and value.id in ("self", "cls"):
            continue
        if isinstance(value, ast.Name) and value.id in modules:
            yield node.lineno, f"{value.id}.{node.attr}: a private name of another module"
        elif node.attr not in own:
            yield node.lineno, f"{ast.unparse(node)}: a private attribute this module does not define"


def test_no_private_names_across_modules():
    found = [use for module, path in MODULES.items()
             for use in private_uses(module, ast.parse(path.read_text(), str(path)), str(path.relative_to(PACKAGE.parent)))]
    assert not found, "private names used across modules:\n  " + "\n  ".join(found)


@pytest.mark.parametrize("source,expected", [
    ("from .contact import Contacts", {"hovi.contact"}),
    ("from .contact.contacts import Contacts", {"hovi.contact", "hovi.contact.contacts"}),
    ("from . import trajopt", {"hovi.trajopt"}),
    ("import hovi.trajopt.problem", {"hovi.trajopt", "hovi.trajopt.problem"}),
])
def test_the_edges_of_an_import(source, expected):
    module = "hovi.integrator"
    edges = set()
    for imp in imports_of(module, ast.parse(source)):
        edges |= edges_of(module, imp)
    assert edges == expected


def test_the_checks_catch_what_they_should():
    graph = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}
    assert cycles(graph) == [["a", "b", "c"]] and one_cycle(graph, ["a", "b", "c"]) == ["a", "b", "c", "a"]
    # a module's own package: its __init__ runs first, so a submodule import is no edge to it, a name is
    inside = "hovi.trajopt.nlp"
    (imp,) = imports_of(inside, ast.parse("from . import problem"))
    assert edges_of(inside, imp) == {"hovi.trajopt.problem"}
    (imp,) = imports_of(inside, ast.parse("from . import Problem"))
    assert edges_of(inside, imp) == {"hovi.trajopt"}
    source = ("from .x import _hidden\nfrom .. import _core\nfrom ..contact import _rows\nimport numpy as np\n"
              "def f(rows, other):\n    np._private\n    rows._input(1)\n    other._own\n    t._replace(a=1)\n"
              "class A:\n    def _own(self):\n        return self._x, cls._y\n")
    uses = list(private_uses("hovi.trajopt.probe", ast.parse(source), "probe.py"))
    assert list(private_uses("hovi.probe", ast.parse("from .trajopt import _helpers"), "p.py")) == [
        "p.py:1: imports the private name _helpers from hovi.trajopt"]
    assert uses == ["probe.py:1: imports the private name _hidden from hovi.trajopt.x",
                    "probe.py:3: imports the private name _rows from hovi.contact",
                    "probe.py:6: np._private: a private name of another module",
                    "probe.py:7: rows._input: a private attribute this module does not define"], uses
    assert private_module_home("hovi._core") == "hovi" and private_module_home("hovi.trajopt.nlp") is None
    assert private_module_home("hovi.trajopt._x.y") == "hovi.trajopt"
