"""Every public class, function, method and property of the API has a docstring; those that take or
return arrays state shapes, e.g. "q: (n,) ...; returns (n, 4, 4)"; pure-Python public functions
are annotated.

The public API: ``hovi.__all__``, ``hovi.examples.models``, ``hovi.examples.robots``, ``hovi.trajopt.__all__``, ``hovi.distributed``, the viewer modules
``hovi.vis.geometry``, ``hovi.vis.viewer`` and ``hovi.vis.video`` (when hovi[viewer] is installed), and every
class and function of the compiled module ``hovi._core`` (and its submodules)."""
from __future__ import annotations

import inspect
import re
import types

import pytest

import hovi
import hovi.distributed
import hovi.vis.geometry
import hovi.examples.models
import hovi.examples.robots
import hovi.trajopt
from hovi import _baselines, _core

try:  # the viewer extra
    import hovi.vis.video
    import hovi.vis.viewer
    VIEWER_MODULES: tuple[types.ModuleType, ...] = (hovi.vis.viewer, hovi.vis.video)
except ImportError:
    VIEWER_MODULES = ()

# A parenthesised, comma-separated shape: (n,), (s+1, n), (K, 2n, 2n), ((s+1) n, s m_c), (n, 4, 4).
SHAPE = re.compile(r"\((?:\(?[\w+\-*]+\)?[\w ]*)(?:,\s*(?:\(?[\w+\-*]+\)?[\w ]*))*,\s*(?:\(?[\w+\-*]+\)?[\w ]*)?\)")
ARRAY_WORDS = ("ArrayLike", "NDArray", "ndarray")


def _public_api() -> dict[str, object]:
    """Qualified name -> object for every public class and function."""
    api: dict[str, object] = {}
    for name in hovi.__all__:
        obj = getattr(hovi, name)
        if not isinstance(obj, types.ModuleType):
            api[f"hovi.{name}"] = obj
    for module in (hovi.examples.models, hovi.examples.robots, hovi.trajopt, hovi.distributed, hovi.vis.geometry, *VIEWER_MODULES):
        names = getattr(module, "__all__", None) or [n for n in vars(module) if not n.startswith("_")]
        for name in names:
            obj = getattr(module, name)
            if (inspect.isclass(obj) or inspect.isroutine(obj)) and getattr(obj, "__module__", "").startswith("hovi"):
                api[f"{module.__name__}.{name}"] = obj
    for module in (_core, _baselines, _core.trajopt):
        for name, obj in vars(module).items():
            if not name.startswith("_") and (inspect.isclass(obj) or inspect.isroutine(obj)):
                api[f"{module.__name__}.{name}"] = obj
    return api


def _members(cls: type) -> dict[str, object]:
    """The public methods and properties a class defines itself (not those of object or an exception
    base), and its __init__ (a Python class documents construction in the class docstring, so its
    __init__ is checked for annotations only)."""
    out = {}
    for name, attr in vars(cls).items():
        if name.startswith("_") and name != "__init__":
            continue
        if isinstance(attr, (staticmethod, classmethod)):
            attr = attr.__func__
        if isinstance(attr, property) or inspect.isroutine(attr):
            out[name] = attr
    return out


def _items() -> list[tuple[str, object]]:
    items: list[tuple[str, object]] = []
    for qual, obj in _public_api().items():
        items.append((qual, obj))
        if inspect.isclass(obj):
            items += [(f"{qual}.{name}", attr) for name, attr in _members(obj).items()]
    return items


def _is_compiled(obj: object) -> bool:
    f = obj.fget if isinstance(obj, property) else obj
    return not isinstance(f, types.FunctionType)


def _doc(qual: str, obj: object) -> str:
    """The docstring without pybind11's signature (its first line, ``name(...)``) or a dataclass's
    generated one (its whole docstring, ``Name(field: type, ...)``)."""
    own = vars(obj).get("__doc__") if inspect.isclass(obj) else obj.__doc__  # not a base class's
    doc = inspect.cleandoc(own or "")
    name = qual.rsplit(".", 1)[-1]
    lines = doc.splitlines()
    if lines and lines[0].startswith(name + "("):
        lines = [] if inspect.isclass(obj) else lines[1:]
    return "\n".join(lines).strip()


def _signature_text(obj: object) -> str:
    """The signature as text: pybind11's first docstring line, or inspect's with annotations."""
    f = obj.fget if isinstance(obj, property) else obj
    if _is_compiled(obj):
        doc = f.__doc__ or ""
        first = doc.strip().splitlines()[0] if doc.strip() else ""
        return first if re.match(r"^\w+\(.*\)", first) else ""
    try:
        return str(inspect.signature(f))
    except (TypeError, ValueError):
        return ""


ITEMS = _items()


def test_public_api_is_found():
    names = {q for q, _ in ITEMS}
    for expected in ("hovi.Model.mass_matrix", "hovi.Integrator.rollout", "hovi.Linearizer.step_jacobians",
                     "hovi.Trajectory.energy", "hovi.examples.models.pendulum", "hovi.trajopt.Problem.add_cost",
                     "hovi._core.Integrator.step", "hovi._core.trajopt.VariationalTranscription.jacobian",
                     "hovi.Integrator.rollout_batch", "hovi.TrajectoryBatch.trajectory", "hovi.distributed.rollout_batch"):
        assert expected in names
    assert len(names) > 150


DOC_ITEMS = [(q, o) for q, o in ITEMS if not (q.endswith(".__init__") and not _is_compiled(o))]


@pytest.mark.parametrize("qual,obj", DOC_ITEMS, ids=[q for q, _ in DOC_ITEMS])
def test_has_docstring(qual, obj):
    assert _doc(qual, obj), f"{qual} has no docstring"


def _takes_or_returns_arrays(obj: object) -> bool:
    sig = _signature_text(obj)
    return any(w in sig for w in ARRAY_WORDS)


def _documented_by(qual: str, obj: object) -> tuple[str, object]:
    """Where the shapes of obj's arrays are stated: the class docstring for a Python __init__."""
    if qual.endswith(".__init__") and not _is_compiled(obj):
        cls = qual[: -len(".__init__")]
        return cls, dict(ITEMS)[cls]
    return qual, obj


ARRAY_ITEMS = [_documented_by(q, o) for q, o in ITEMS if not inspect.isclass(o) and _takes_or_returns_arrays(o)]


def test_array_items_are_found():
    names = {q for q, _ in ARRAY_ITEMS}
    assert {"hovi.Model.body_poses", "hovi.Integrator.momentum", "hovi._core.Integrator.del_residual"} <= names


@pytest.mark.parametrize("qual,obj", ARRAY_ITEMS, ids=[q for q, _ in ARRAY_ITEMS])
def test_array_docstring_states_shapes(qual, obj):
    assert SHAPE.search(_doc(qual, obj)), f"{qual} takes or returns arrays but its docstring states no shape like (n,)"


PYTHON_FUNCTIONS = [(q, o) for q, o in ITEMS if not inspect.isclass(o) and not _is_compiled(o)]


@pytest.mark.parametrize("qual,obj", PYTHON_FUNCTIONS, ids=[q for q, _ in PYTHON_FUNCTIONS])
def test_python_functions_are_annotated(qual, obj):
    f = obj.fget if isinstance(obj, property) else obj
    sig = inspect.signature(f)
    missing = [p.name for i, p in enumerate(sig.parameters.values())
               if p.annotation is inspect.Parameter.empty and not (i == 0 and p.name in ("self", "cls"))
               and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD)]
    assert not missing, f"{qual}: parameters without annotations: {missing}"
    if f.__name__ != "__init__":
        assert sig.return_annotation is not inspect.Signature.empty, f"{qual}: no return annotation"


def test_shape_pattern():
    for text in ("(n,)", "(s+1, n)", "(K, 2n, 2n)", "((s+1) n, s m_c)", "(n, 4, 4)", "(rows (nnz,), cols (nnz,))"):
        assert SHAPE.search(text), text
    for text in ("(n)", "no shape", "K + V"):
        assert not SHAPE.search(text), text
