# make demo   set up (apt + .venv), build, install and run the demo
# make test   set up, build, then ctest and pytest
# make bench  run the benchmarks in bench/ (slow; writes bench/results/)
# make docs   build the documentation site into site/ (mkdocs build --strict: warnings fail)
# make stubs  refresh the committed type stubs of hovi._core and hovi._baselines (python/hovi/_core/*.pyi,
#             python/hovi/_baselines.pyi) after a binding changed
# make sanitize  the C++ library and ctest suite under AddressSanitizer + UndefinedBehaviorSanitizer
# make sanitize-python  the Python extension under ASan + UBSan, and pytest on ASAN_TESTS with it
# make wheel-smoke  sdist -> wheel -> fresh venv -> smoke test (scripts/wheel_smoke.sh; a clean compile)
SHELL := /bin/bash
VENV := .venv
PY := $(VENV)/bin/python
JOBS ?= $(shell nproc)
# -march of the C++ core (CMake's HOVI_ARCH), empty: the compiler's portable default. `make
# HOVI_ARCH=x86-64-v3 build` is faster on AVX2 machines but breaks bench/speed.py (see CMakeLists.txt).
HOVI_ARCH ?=
SOURCES := $(shell find cpp python -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.py' \)) $(wildcard models/*.urdf) \
           CMakeLists.txt pyproject.toml \
           cmake/stubs.cmake scripts/stubgen.py

.PHONY: setup setup-test build demo test ctest pytest bench docs clean stubs wheel-smoke sanitize sanitize-python

setup:
	@./scripts/setup.sh

setup-test:
	@./scripts/setup.sh test

# The Python package, rebuilt (incrementally, in its CMake tree build/py) when a source changed.
PIP_INSTALL = CMAKE_BUILD_PARALLEL_LEVEL=$(JOBS) $(PY) -m pip install -q --no-build-isolation --no-deps \
              -C cmake.define.HOVI_ARCH=$(HOVI_ARCH)
$(VENV)/.hovi.stamp: $(SOURCES) | setup
	$(PIP_INSTALL) .
	@touch $@

build: setup $(VENV)/.hovi.stamp

# The C++ tests and the C++ benchmark against Pinocchio (bench/cpp/speed.cpp, linked with the pin wheel's
# Pinocchio), built in the package's own tree with the package, so that the core is compiled once and
# bench/speed.py and linearization.py --quick only run the benchmark.
ctest: setup
	$(PIP_INSTALL) -C cmake.define.HOVI_BUILD_TESTS=ON -C cmake.define.HOVI_BUILD_BENCH=ON \
	  -C cmake.define.HOVI_PINOCCHIO_PREFIX="$$($(PY) -c 'import sysconfig, os; print(os.path.join(sysconfig.get_paths()["purelib"], "cmeel.prefix"))')" .
	@touch $(VENV)/.hovi.stamp
	cd build/py && ctest --output-on-failure -j $(JOBS)

pytest: build setup-test
	$(PY) -m pytest -q --durations=15 tests

demo: build
	$(PY) -m hovi simulate pendulum:32 -s 2 --dt 0.01 --duration 10 --output results --animate

test: ctest pytest

# The C++ tests built with -O1 and ASan + UBSan (any finding fails the test that hit it); a separate
# tree, build/sanitize, so it does not disturb the Release build.
sanitize: setup
	cmake -S . -B build/sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
	      -DHOVI_BUILD_TESTS=ON -DHOVI_BUILD_PYTHON=OFF -DHOVI_SANITIZE=ON
	cmake --build build/sanitize -j $(JOBS)
	cd build/sanitize && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j $(JOBS)

# The extension module built with ASan + UBSan (build/asan-py, -O1, no stubs) and pytest run on it
# from a staged copy of the package (PYTHONPATH). Python is not built with ASan, so libasan is
# preloaded, and libstdc++ with it: without it ASan's __cxa_throw interceptor finds no real
# __cxa_throw at start-up and the first C++ exception aborts. Leak checks off (the interpreter's own
# allocations would drown them); any ASan or UBSan finding aborts the test run.
ASAN_TESTS ?= tests/test_model_api.py tests/test_del_residual.py tests/test_newton_direction.py tests/test_exceptions.py \
              tests/test_urdf.py tests/test_model_changes.py tests/test_integrator.py tests/test_linearization.py \
              tests/test_baselines.py tests/test_constraints.py tests/test_api_fuzz.py tests/test_threads.py \
              tests/test_model_vs_pinocchio.py tests/test_tangent_velocity.py
sanitize-python: setup
	cmake -S . -B build/asan-py -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" \
	      -DHOVI_BUILD_PYTHON=ON -DHOVI_BUILD_TESTS=OFF -DHOVI_SANITIZE=ON -DHOVI_STUBS=OFF -DPython_EXECUTABLE=$(abspath $(PY))
	cmake --build build/asan-py -j $(JOBS) --target _core _baselines
	rm -rf build/asan-py/stage && mkdir -p build/asan-py/stage && cp -r python/hovi build/asan-py/stage/
	cp build/asan-py/_core*.so build/asan-py/_baselines*.so build/asan-py/stage/hovi/
	LD_PRELOAD="$$(gcc -print-file-name=libasan.so) $$(gcc -print-file-name=libstdc++.so)" ASAN_OPTIONS=detect_leaks=0 \
	  UBSAN_OPTIONS=print_stacktrace=1 PYTHONPATH=build/asan-py/stage $(PY) -m pytest -q -p no:cacheprovider $(ASAN_TESTS)

bench: build
	$(PY) bench/run_all.py

# The API reference documents the installed package (hovi._core is inspected), hence `build`.
docs: build
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict --site-dir site

# pybind11-stubgen on the installed hovi._core, with the build's options (tests/test_stubs.py checks the copy)
stubs: build
	$(PY) scripts/stubgen.py build/stubs
	rm -rf python/hovi/_core && cp -r build/stubs/hovi/_core python/hovi/_core && cp build/stubs/hovi/_baselines.pyi python/hovi/

wheel-smoke: setup
	JOBS=$(JOBS) ./scripts/wheel_smoke.sh

clean:
	rm -rf build $(VENV)/.hovi.stamp
