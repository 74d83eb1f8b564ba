"""The type stubs of hovi._core and hovi._baselines: the committed copy (python/hovi/_core/*.pyi,
python/hovi/_baselines.pyi, for editors) must be what pybind11-stubgen makes of the installed modules
now, and the installed package must ship the same stubs (the build generates them). A binding added or
changed without `make stubs` fails here."""
from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

import hovi

ROOT = Path(__file__).resolve().parents[1]
COMMITTED = ROOT / "python" / "hovi"
INSTALLED = Path(hovi.__file__).parent
HINT = ("the committed stubs of hovi._core / hovi._baselines are stale: run `make stubs` and commit "
        "python/hovi/_core/*.pyi and python/hovi/_baselines.pyi")


def _stubs(package: Path) -> dict[str, str]:
    """The stubs of the extensions in a hovi package folder, by path relative to it."""
    files = sorted(package.glob("_core/*.pyi")) + sorted(package.glob("_baselines.pyi"))
    return {p.relative_to(package).as_posix(): p.read_text() for p in files}


def _differences(expected: dict[str, str], actual: dict[str, str]) -> list[str]:
    out = [f"{name}: missing" for name in sorted(set(expected) - set(actual))]
    out += [f"{name}: unexpected" for name in sorted(set(actual) - set(expected))]
    for name in sorted(set(expected) & set(actual)):
        if expected[name] != actual[name]:
            a, b = expected[name].splitlines(), actual[name].splitlines()
            line = next((i for i, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
            out.append(f"{name}: differs from line {line + 1}: {a[line] if line < len(a) else '<end>'!r} vs "
                       f"{b[line] if line < len(b) else '<end>'!r}")
    return out


@pytest.fixture(scope="module")
def fresh(tmp_path_factory) -> dict[str, str]:
    """The stubs pybind11-stubgen makes of the installed hovi._core now (the build's options)."""
    pytest.importorskip("pybind11_stubgen")
    out = tmp_path_factory.mktemp("stubs")
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "stubgen.py"), str(out)], cwd=out,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return _stubs(out / "hovi")


def test_committed_stubs_are_current(fresh):
    assert _stubs(COMMITTED), f"no committed stubs in {COMMITTED}: run `make stubs`"
    diff = _differences(_stubs(COMMITTED), fresh)
    assert not diff, HINT + "\n" + "\n".join(diff)


def test_installed_package_ships_the_stubs(fresh):
    assert (INSTALLED / "py.typed").is_file()
    diff = _differences(fresh, _stubs(INSTALLED))
    assert not diff, "the installed hovi/_core/*.pyi, hovi/_baselines.pyi differ from the module's stubs (rebuild: make build)\n" + \
        "\n".join(diff)


def test_stubs_are_valid_and_typed():
    stubs = _stubs(COMMITTED)
    assert set(stubs) == {"_core/__init__.pyi", "_core/trajopt.pyi", "_core/control.pyi", "_baselines.pyi"}
    for name, text in stubs.items():
        ast.parse(text, filename=name)  # valid syntax (e.g. no required argument after a defaulted one)
        assert "Incomplete" not in text and "_typeshed" not in text, name
    core = stubs["_core/__init__.pyi"]
    assert "baselines" not in core and "def one_step_batch" in stubs["_baselines.pyi"]  # the product has none
    # Arrays in, numpy arrays out
    assert "def mass_matrix(self, q: numpy.typing.ArrayLike) -> typing.Annotated[numpy.typing.NDArray[numpy.float64]" \
        in core
    assert "def body_poses(self, q: numpy.typing.ArrayLike) -> numpy.typing.NDArray[numpy.float64]" in core
    assert "def step(self, q: numpy.typing.ArrayLike, p: numpy.typing.ArrayLike, u: numpy.typing.ArrayLike | None" \
        in core
    # Untyped arguments are gone: only __deepcopy__'s memo is typing.Any
    untyped = re.findall(r"(\w+): typing\.Any\b", "".join(stubs.values()))
    assert untyped == ["memo"], untyped
    assert re.search(r"def from_urdf\(source: str \| os\.PathLike\[str\]", core)


def test_stubgen_failure_is_an_error_with_a_clear_message(tmp_path):
    """A type pybind11-stubgen cannot resolve fails the generator (so the build), saying what to do."""
    pytest.importorskip("pybind11_stubgen")
    fake = tmp_path / "import" / "hovi"
    fake.mkdir(parents=True)
    (fake / "__init__.py").write_text("")
    (fake / "_core.py").write_text("def f(x: 'no_such_module.Type') -> None:\n    '''f'''\n")
    proc = subprocess.run([sys.executable, str(ROOT / "scripts" / "stubgen.py"), str(tmp_path / "out"),
                           "--path", str(tmp_path / "import")], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "Can't find/import 'no_such_module.Type'" in proc.stderr, proc.stderr
    assert "generating the stubs of hovi._core / hovi._baselines failed" in proc.stderr and "-DHOVI_STUBS=OFF" in proc.stderr
    assert not (tmp_path / "out" / "hovi" / "_core" / "__init__.pyi").exists()
