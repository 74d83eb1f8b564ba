#!/usr/bin/env bash
# The package as a user gets it: build the sdist, check it, build the wheel FROM that sdist (a clean
# compile in pip's temporary directory: build/ of `make build` is not touched), install the wheel
# in a fresh virtual environment outside the repository (numpy from PyPI, nothing else), and run a
# smoke test there: a URDF from models/, an Integrator, a step, a rollout, hovi.Linearizer, finite
# results, a small energy error, the typing files (hovi/_core/*.pyi, py.typed) and the URDFs of
# models/ (hovi/urdf/, loaded by hovi.robots) installed.
#
# Uses .venv's Python (scikit-build-core, pybind11, pybind11-stubgen, numpy, build: make setup) for
# the builds, without build isolation. Leaves dist/hovi-*.tar.gz and dist/hovi-*.whl.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$(pwd)
PY=${PY:-$ROOT/.venv/bin/python}
HOST_PY=${PYTHON:-python3}
JOBS=${JOBS:-$(nproc)}
start=$(date +%s)
work=$(mktemp -d "${TMPDIR:-/tmp}/hovi-wheel-smoke.XXXXXX")
trap 'rm -rf "$work"' EXIT

echo "wheel-smoke: building the sdist"
rm -f dist/hovi-*.tar.gz dist/hovi-*.whl
"$PY" -m build --sdist --no-isolation --outdir dist . >"$work/sdist.log" 2>&1 || { cat "$work/sdist.log"; exit 1; }
sdists=(dist/hovi-*.tar.gz)
[ "${#sdists[@]}" -eq 1 ] && [ -f "${sdists[0]}" ] || { echo "wheel-smoke: expected one sdist in dist/"; exit 1; }
sdist=${sdists[0]}

echo "wheel-smoke: checking $sdist"
"$PY" - "$sdist" <<'EOF'
import sys, tarfile
names = tarfile.open(sys.argv[1]).getnames()
top = names[0].split("/")[0]
rel = {n[len(top) + 1:] for n in names if n.startswith(top + "/")}
need = ["CMakeLists.txt", "pyproject.toml", "README.md", "PKG-INFO", "cmake/stubs.cmake", "scripts/stubgen.py",
        "python/hovi/__init__.py", "python/hovi/py.typed", "python/hovi/_core/__init__.pyi",
        "python/hovi/_baselines.pyi", "cpp/bindings/module.cpp", "cpp/baselines/bindings/module.cpp", "models/double_pendulum.urdf", "models/spring_flamingo.urdf",
        "models/littledog.urdf", "models/atlas.urdf"]
missing = [f for f in need if f not in rel]
assert not missing, f"the sdist lacks {missing}"
assert any(f.startswith("cpp/src/") and f.endswith(".cpp") for f in rel), "the sdist has no cpp/src sources"
assert any(f.startswith("cpp/include/hovi/") for f in rel), "the sdist has no cpp/include headers"
banned = sorted({f.split("/")[0] + "/" for f in rel
                 if f.split("/")[0] in ("build", ".venv", "dist", "bench", "tests", ".git", "results")})
assert not banned, f"the sdist must not contain {banned}"
assert not [f for f in rel if "__pycache__" in f or f.endswith(".so")], "the sdist contains build products"
print(f"wheel-smoke: sdist ok ({len(rel)} files)")
EOF

echo "wheel-smoke: building the wheel from the sdist (a clean compile)"
CMAKE_BUILD_PARALLEL_LEVEL=$JOBS "$PY" -m pip wheel "$sdist" --no-deps --no-build-isolation -w dist \
  >"$work/wheel.log" 2>&1 || { tail -50 "$work/wheel.log"; exit 1; }
wheels=(dist/hovi-*.whl)
[ -f "${wheels[0]}" ] || { echo "wheel-smoke: no wheel was built"; tail -50 "$work/wheel.log"; exit 1; }
wheel=$ROOT/${wheels[0]}
built=$(date +%s)

echo "wheel-smoke: installing $(basename "$wheel") in a fresh virtual environment"
"$HOST_PY" -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q "$wheel" >"$work/install.log" 2>&1 || { cat "$work/install.log"; exit 1; }

mkdir "$work/run"
cd "$work/run"  # outside the repository: only the installed package can be imported
"$work/venv/bin/python" - "$ROOT/models/double_pendulum.urdf" <<'EOF'
import importlib.metadata as md
import sys
from pathlib import Path

import numpy as np

import hovi

assert Path(hovi.__file__).resolve().is_relative_to(Path(sys.prefix).resolve()), hovi.__file__
assert hovi.__version__ == md.version("hovi"), (hovi.__version__, md.version("hovi"))
assert [r for r in md.requires("hovi") or [] if "extra ==" not in r] == ["numpy>=1.22"], md.requires("hovi")
package = Path(hovi.__file__).parent
for f in ("py.typed", "_core/__init__.pyi", "_baselines.pyi", "_core/trajopt.pyi", "urdf/atlas.urdf"):
    assert (package / f).is_file(), f"the wheel did not install hovi/{f}"
assert "def mass_matrix" in (package / "_core" / "__init__.pyi").read_text()
for heavy in ("matplotlib", "scipy", "meshcat", "tqdm"):
    assert heavy not in sys.modules, f"import hovi imported {heavy}"

model = hovi.Model.from_urdf(sys.argv[1])
assert model.n == 2 and model.joint_names == ["shoulder", "elbow"], model.joint_names
integ = hovi.Integrator(model, s=2, dt=0.01)
q0, qd0 = np.array([0.8, -0.4]), np.array([0.0, 0.5])
q1, p1, info = integ.step(q0, integ.momentum(q0, qd0))
assert info.converged and np.all(np.isfinite(q1)) and np.all(np.isfinite(p1))
traj = integ.rollout(q0, 500, qdot0=qd0)
E = traj.energy
assert traj.converged and np.all(np.isfinite(traj.q)) and np.all(np.isfinite(E))
drift = float(np.max(np.abs(E - E[0])) / abs(E[0]))
assert drift < 1e-5, f"energy error {drift:.2e}"  # 4th-order VI, dt = 0.01, 5 s: bounded, ~1e-8
lin = hovi.Linearizer(integ)
step = lin.step_jacobians(q0, integ.momentum(q0, qd0), B=False)
A = step.A
assert A is not None and A.shape == (4, 4) and np.all(np.isfinite(A))
# The step map of a Hamiltonian system is symplectic: A^T J A = J
J = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.eye(2), np.zeros((2, 2))]])
assert np.allclose(A.T @ J @ A, J, atol=1e-8), A.T @ J @ A - J
from hovi.examples import robots
assert [r().model.n for r in (robots.spring_flamingo, robots.littledog, robots.atlas)] == [9, 18, 36]
assert list((package / "trajopt" / "solvers").glob("_ipopt*")), "the wheel has no IPOPT adapter"
print(f"wheel-smoke: hovi {hovi.__version__} from the wheel: 500 steps, energy error {drift:.1e}, "
      f"symplectic step Jacobian, stubs, py.typed and the robots' URDFs installed")
EOF
end=$(date +%s)
echo "wheel-smoke: passed in $((end - start)) s (sdist and wheel build $((built - start)) s)"
