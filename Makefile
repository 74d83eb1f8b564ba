# make demo   set up (apt + .venv), build, install and run the demo
# make test   set up, build, then ctest and pytest
# make bench  run the benchmarks in bench/ (slow; writes bench/results/)
# make docs   build the documentation site into site/ (mkdocs build --strict: warnings fail)
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
JOBS ?= $(shell nproc)
SOURCES := $(shell find cpp python -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.py' \)) CMakeLists.txt pyproject.toml

.PHONY: setup setup-test build demo test ctest pytest bench docs clean

setup:
	@./scripts/setup.sh

setup-test:
	@./scripts/setup.sh test

# The Python package, rebuilt (incrementally, in build/) when a source changed.
$(VENV)/.hovi.stamp: $(SOURCES) | setup
	CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY) -m pip install -q --no-build-isolation --no-deps .
	@touch $@

build: setup $(VENV)/.hovi.stamp

build/cpp/CMakeCache.txt: CMakeLists.txt | setup
	cmake -S . -B build/cpp -DCMAKE_BUILD_TYPE=Release -DHOVI_BUILD_TESTS=ON -DHOVI_BUILD_PYTHON=OFF

ctest: setup build/cpp/CMakeCache.txt
	cmake --build build/cpp -j $(JOBS)
	cd build/cpp && ctest --output-on-failure -j $(JOBS)

pytest: build setup-test
	$(PY) -m pytest -q tests

demo: build
	$(PY) -m hovi simulate pendulum:32 --order 4 --dt 0.01 --duration 10 --output results --animate

test: ctest pytest

bench: build
	$(PY) bench/run_all.py

# The API reference documents the installed package (hovi._core is inspected), hence `build`.
docs: build
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --site-dir site

clean:
	rm -rf build $(VENV)/.hovi.stamp
