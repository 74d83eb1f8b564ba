"""Type stubs of the compiled modules hovi._core and hovi._baselines, by pybind11-stubgen, with one set
of options for the build (CMakeLists.txt runs this after the modules link), ``make stubs`` and
tests/test_stubs.py.

    python scripts/stubgen.py OUTPUT_DIR [--path DIR]

writes OUTPUT_DIR/hovi/_core/__init__.pyi (and trajopt.pyi: _core has a submodule, so its stubs are
a package) and OUTPUT_DIR/hovi/_baselines.pyi (when that extension is built) from the modules that
Python imports; ``--path DIR`` is searched first (the build puts the just-linked modules in DIR/hovi/
next to an empty __init__.py, so that only the extensions are imported). Any error of pybind11-stubgen (a type it cannot express, an
unresolved name) fails with exit status 1 and writes nothing.
"""
from __future__ import annotations

import argparse
import importlib.util
import shutil
import sys
from pathlib import Path

# --exit-code: every problem is an error (no silently degraded annotations).
STUBGEN_OPTIONS = ["--exit-code"]


def generate(output_dir: Path, path: str | None = None) -> int:
    """Write the stubs under ``output_dir``; returns pybind11-stubgen's exit status."""
    if path:
        sys.path.insert(0, path)
    try:
        from pybind11_stubgen import main as stubgen_main
    except ImportError:
        print("stubgen: pybind11-stubgen is not installed (pip install pybind11-stubgen); "
              "or build with -DHOVI_STUBS=OFF", file=sys.stderr)
        return 1
    target = output_dir / "hovi" / "_core"
    shutil.rmtree(target, ignore_errors=True)  # no stale stubs of a removed submodule
    baselines = output_dir / "hovi" / "_baselines.pyi"
    baselines.unlink(missing_ok=True)
    modules = ["hovi._core"] + (["hovi._baselines"] if importlib.util.find_spec("hovi._baselines") else [])
    for module in modules:
        try:
            stubgen_main([*STUBGEN_OPTIONS, "-o", str(output_dir), module])
        except SystemExit as e:  # --exit-code exits on an error
            if e.code:
                return int(e.code)
    return 0 if (target / "__init__.pyi").is_file() else 1


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("output_dir", type=Path)
    parser.add_argument("--path", help="directory searched first for the hovi package")
    args = parser.parse_args()
    status = generate(args.output_dir, args.path)
    if status:
        print("stubgen: generating the stubs of hovi._core / hovi._baselines failed (see the errors above): give the binding "
              "an argument or return type pybind11-stubgen can express (cpp/bindings/common.hpp has typed "
              "argument classes), or build with -DHOVI_STUBS=OFF to ship the committed python/hovi/_core/*.pyi",
              file=sys.stderr)
    return status


if __name__ == "__main__":
    sys.exit(main())
