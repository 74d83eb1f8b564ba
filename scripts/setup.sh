#!/usr/bin/env bash
# Installs what is missing on a Debian machine: system packages (apt-get) and a .venv with
# the Python dependencies. Idempotent: does nothing when everything is present.
# `scripts/setup.sh test` also installs what only the tests need (chromium: the headless browser
# that renders the viewer's HTML in tests/test_viewer.py).
set -euo pipefail
cd "$(dirname "$0")/.."

# IPOPT (trajectory optimisation: hovi's IPOPT adapter is compiled against it); OpenBLAS (serial)
# in place of the reference BLAS under IPOPT's MUMPS: its dense frontal matrices are BLAS-3 work
# (bench/README.md, "Design measurements")
APT_PACKAGES="g++ make cmake libeigen3-dev liburdfdom-dev libtinyxml-dev libgtest-dev coinor-libipopt-dev liblapack-dev libblas-dev libopenblas0-serial pkg-config"
[ "${1:-}" = "test" ] && APT_PACKAGES="$APT_PACKAGES chromium"
missing=""
for p in $APT_PACKAGES; do
  dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"
done
if [ -n "$missing" ]; then
  echo "setup: installing Debian packages:$missing"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq $missing
fi

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  echo "setup: creating .venv"
  "$PY" -m venv .venv || { echo "setup: python3 -m venv failed; install python3-venv"; exit 1; }
fi
if [ ! -f .venv/.requirements.stamp ] || [ requirements-dev.txt -nt .venv/.requirements.stamp ]; then
  echo "setup: installing Python packages into .venv"
  .venv/bin/python -m pip install -q --upgrade pip
  .venv/bin/python -m pip install -q -r requirements-dev.txt
  touch .venv/.requirements.stamp
fi
