"""Packaging: the version is kept in one place, the core install needs only numpy, the URDFs of
models/ are installed with the package, and `import hovi` loads none of the optional dependencies. (scripts/wheel_smoke.sh checks the sdist and the wheel.)"""
from __future__ import annotations

import importlib.metadata as md
import re
import subprocess
import sys
from pathlib import Path

import pytest

import hovi

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = ("matplotlib", "scipy", "meshcat", "tqdm", "mujoco", "pinocchio", "imageio", "trimesh")


def test_version_is_the_distributions():
    assert hovi.__version__ == md.version("hovi")
    assert re.fullmatch(r"\d+\.\d+\.\d+([.-]?\w+)?", hovi.__version__)


def test_version_is_kept_in_one_place():
    tomllib = pytest.importorskip("tomllib")
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert "version" not in project and "version" in project["dynamic"]
    init = (ROOT / "python" / "hovi" / "__init__.py").read_text()
    assert re.findall(r'^__version__ = "([^"]+)"', init, re.M) == [hovi.__version__]
    assert "VERSION" not in re.search(r"project\((.*?)\)", (ROOT / "CMakeLists.txt").read_text()).group(1)


def test_core_install_requires_only_numpy():
    requires = md.requires("hovi") or []
    core = [r for r in requires if "extra ==" not in r]
    assert [re.split(r"[<>=!~; ]", r)[0].lower() for r in core] == ["numpy"], core
    extras = set(md.metadata("hovi").get_all("Provides-Extra") or [])
    assert {"test", "plot", "trajopt", "bench", "viewer"} <= extras, extras


def _imported(statement: str) -> list[str]:
    """The optional dependencies in sys.modules after `statement` in a fresh interpreter."""
    code = f"import sys\n{statement}\nprint(sorted(m for m in {OPTIONAL!r} if m in sys.modules))"
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          cwd=Path(hovi.__file__).parents[2])
    assert proc.returncode == 0, proc.stderr
    return eval(proc.stdout.strip())


def test_import_hovi_loads_no_optional_dependency():
    assert _imported("import hovi, hovi.examples.models, hovi.baselines, hovi.examples.robots") == []


def test_import_trajopt_loads_only_its_extra():
    """hovi.trajopt needs scipy (the trajopt extra); IPOPT is the compiled adapter, loaded by a solve."""
    assert _imported("import hovi.trajopt") == ["scipy"]


def test_models_are_installed_with_the_package():
    """Every URDF of models/ ships as hovi/urdf/ (hovi.examples.robots loads its robots from there)."""
    installed = Path(hovi.__file__).parent / "urdf"
    shipped = sorted(p.name for p in (ROOT / "models").glob("*.urdf"))
    assert {"spring_flamingo.urdf", "littledog.urdf", "atlas.urdf"} <= set(shipped)
    assert sorted(p.name for p in installed.glob("*.urdf")) == shipped
    for name in shipped:
        assert (installed / name).read_bytes() == (ROOT / "models" / name).read_bytes(), f"stale {name}: make build"
