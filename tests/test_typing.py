"""The typed API: mypy --strict passes on tests/typed_usage.py (which uses the installed hovi, its
py.typed and the stubs of hovi._core), the script runs, and the package ships py.typed."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

import hovi

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "tests" / "typed_usage.py"


def test_mypy_strict_on_typed_example(tmp_path):
    pytest.importorskip("mypy")
    # From a directory outside the repository, so that mypy checks the installed package (the one
    # with the generated stubs) and not a source tree; no cache shared with other runs.
    proc = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                           "--cache-dir", str(tmp_path / "cache"), str(EXAMPLE)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"mypy --strict failed:\n{proc.stdout}\n{proc.stderr}"
    assert "Success" in proc.stdout


def test_mypy_catches_a_wrong_type(tmp_path):
    """The check has teeth: a misuse of the typed API is an error."""
    pytest.importorskip("mypy")
    bad = tmp_path / "bad.py"
    bad.write_text("import hovi\n\nmodel: hovi.Model = hovi.examples.models.pendulum(2)\nn: str = model.n\n"
                   "integ = hovi.Integrator(model, s=2)\nx: int = integ.rollout([0.0, 0.0], 3).q\n")
    proc = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental",
                           "--cache-dir", str(tmp_path / "cache"), str(bad)],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert 'bad.py:4: error: Incompatible types in assignment (expression has type "int", variable has type "str")' \
        in proc.stdout, proc.stdout
    assert "bad.py:6: error" in proc.stdout, proc.stdout


def test_typed_example_runs(tmp_path):
    proc = subprocess.run([sys.executable, str(EXAMPLE)], cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "typed_usage: ok" in proc.stdout
    error = float(proc.stdout.split("relative energy error")[1])
    assert error < 1e-4  # a 4th-order VI at dt = 0.01: bounded energy error


def test_package_is_typed():
    package = Path(hovi.__file__).parent
    assert (package / "py.typed").is_file()
    assert (package / "_core" / "__init__.pyi").is_file()


def test_mypy_strict_on_the_core_modules(tmp_path):
    """The modules of `import hovi` (not the optional trajopt, plotting, cli) and hovi.distributed are
    themselves strict-clean."""
    pytest.importorskip("mypy")
    modules = ["hovi", "hovi.integrator", "hovi.linearizer", "hovi.batch", "hovi.trajectory", "hovi.examples.models",
               "hovi.examples.robots", "hovi._typing", "hovi.distributed"]
    proc = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", "--cache-dir",
                           str(tmp_path / "cache"), *[a for m in modules for a in ("-m", m)]],
                          cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"mypy --strict failed:\n{proc.stdout}\n{proc.stderr}"
