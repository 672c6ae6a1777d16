# a2l: every target does its own set-up, idempotently and without questions.
#   make demo    set up, then run the main job (a2l demo); prints the set-up and demo wall times
#   make results set up, then run a2l results: PROFILE=full (hours) regenerates docs/results/
#                and the README's tables; PROFILE=quick (default, ~30 min on an idle 2-core
#                machine) is a check that writes docs/results/quick/ only
#   make test    set up, then run the C++ tests (ctest), the real-time tests again with Eigen's
#                allocation guard, the Python tests (pytest) and the fuzzer; print the counts
#   make test-fast  set up, then the Python tests not marked slow (a developer's quick loop);
#                prints its wall time
#   make bench   set up, then run the benchmarks and rewrite BENCHMARKS.md
#   make lint    ruff + the import-layer contracts (lint-imports) + clang-format --dry-run
#                + CITATION.cff against the Citation File Format 1.2.0 schema
#   make docs    set up, then build the API reference (Sphinx, docs/api) into build/docs
# Variables: VENV (virtual environment, default .venv), BUILD (build tree, default build),
# JOBS (parallel compile jobs).
SHELL := /bin/bash
.SHELLFLAGS := -eu -o pipefail -c
.DEFAULT_GOAL := help

VENV ?= .venv
BUILD ?= build
JOBS ?= $(shell nproc 2>/dev/null || echo 2)
PY := $(VENV)/bin/python
PIP := $(PY) -m pip --disable-pip-version-check
comma := ,

APT_PACKAGES := build-essential git libeigen3-dev libbullet-dev liborocos-kdl-dev liburdfdom-dev \
  libompl-dev libgtest-dev libbenchmark-dev nlohmann-json3-dev zlib1g-dev libssl-dev \
  libboost-serialization-dev libboost-filesystem-dev libboost-system-dev clang clang-format libclang-rt-14-dev \
  ccache

CXX_SOURCES := $(shell find cpp bindings -name '*.cpp' -o -name '*.hpp' 2>/dev/null) CMakeLists.txt
CXX_TEST_SOURCES := $(shell find tests/cpp benchmarks/cpp -name '*.cpp' 2>/dev/null)
STAMP_APT := $(BUILD)/.stamp-apt
STAMP_VENV := $(VENV)/.stamp-venv
STAMP_INSTALL := $(VENV)/.stamp-install
# The editable install maps each Python module to its file when installed: a module added or
# removed needs a reinstall. The list of modules is rewritten only when it changes.
PY_MODULES := $(BUILD)/.python-modules
# (a file of its own per make: `make test` runs makes side by side)
$(shell mkdir -p $(BUILD) && find python -name '*.py' | sort > $(PY_MODULES).$$$$ && \
  { cmp -s $(PY_MODULES).$$$$ $(PY_MODULES) || mv $(PY_MODULES).$$$$ $(PY_MODULES); }; \
  rm -f $(PY_MODULES).$$$$)
SUDO := $(shell [ "$$(id -u)" = 0 ] || echo sudo)
# Every C++ build goes through ccache when it is installed: the Python module's build and the
# test build compile the same core sources with the same flags, so the second one reuses them.
LAUNCHER = -DCMAKE_CXX_COMPILER_LAUNCHER=$$(command -v ccache || true)
# Paths under the build tree reach ccache relative to the compiler's directory: the unity
# batches (CMakeLists.txt) of the module build and of the test build, each in its own tree,
# are then the same entry.
export CCACHE_BASEDIR := $(abspath $(BUILD))
# One compiler name for every gcc build ($(CXX): make's default g++ unless the environment
# names another): ccache keys on it, and CMake alone would pick c++ for the tests, g++ for the
# module.
export CXX
# Phase timing: a phase starts its clock with $(call CLOCK,name) and ends with $(call LAP,name,
# label), which appends "label: N s (CPU M s)" to $(BUILD)/times.log; `make test` prints the log.
# N is wall time; M is the user + system time of the phase's processes: the CPU time make's
# finished children used (fields cutime and cstime of make's /proc/PID/stat, in clock ticks),
# which the machine's load does not inflate.
CPU_TICKS = awk '{print $$16 + $$17}' /proc/$$PPID/stat
CLOCK = echo "$$(date +%s) $$($(CPU_TICKS))" > $(BUILD)/.clock-$(1)
LAP = read t0 c0 < $(BUILD)/.clock-$(1) && echo "$(2): $$(( $$(date +%s) - t0 )) s (CPU \
  $$(( ($$($(CPU_TICKS)) - c0) / $$(getconf CLK_TCK) )) s)" >> $(BUILD)/times.log

.PHONY: help setup demo results test test-fast test-clock test-layers test-cpp guard-build guard-run \
  test-guarded test-python fuzz-build fuzz-run fuzz bench docs lint format clean

help:
	@sed -n '2,14p' Makefile | sed 's/^# \{0,1\}//'

# --- set-up ---------------------------------------------------------------
$(STAMP_APT):
	@mkdir -p $(BUILD) && $(call CLOCK,apt)
	@missing=$$(for p in $(APT_PACKAGES); do dpkg -s $$p >/dev/null 2>&1 || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "[setup] installing Debian packages:" $$missing; \
	  $(SUDO) apt-get update -qq; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq --no-install-recommends $$missing; \
	fi
	@python3 -c 'import venv, ensurepip' 2>/dev/null || { \
	  echo "[setup] installing python3-venv python3-dev"; \
	  DEBIAN_FRONTEND=noninteractive $(SUDO) apt-get install -y -qq python3-venv python3-dev; }
	@$(call LAP,apt,set-up: Debian packages) && touch $@

$(STAMP_VENV): $(STAMP_APT)
	@$(call CLOCK,venv)
	@[ -x $(PY) ] || { echo "[setup] creating $(VENV)"; python3 -m venv $(VENV); }
	@$(PIP) install -q "scikit-build-core>=0.10" "pybind11>=2.13" "cmake>=3.20" ninja setuptools wheel
	@$(call LAP,venv,set-up: virtual environment and build tools) && touch $@

# a2l's dependencies (pyproject.toml: the package's own, and the extras dev, ros and gym) are
# installed by uv: it downloads side by side, pip one after the other (3 min against 1 on a fresh
# machine, the same versions), and compiles their bytecode as pip does (where
# PYTHONDONTWRITEBYTECODE is set, as on this project's CI machines, Python writes none, and
# every process would compile every import again: the tests ran 1.7 times slower). pip builds and
# installs a2l itself, editable (every change to the C++ sources rebuilds it); it finds the
# dependencies there, or installs them when uv could not. a2l's own bytecode is compiled beside
# its sources (0.2 s less for each of the tests' many processes that import it; a stale file is
# only recompiled in memory).
EXTRAS := dev,ros,gym
$(STAMP_INSTALL): $(STAMP_VENV) pyproject.toml $(CXX_SOURCES) $(PY_MODULES)
	@echo "[setup] installing a2l's dependencies into $(VENV) (uv)"
	@$(call CLOCK,install)
	@{ [ -x $(VENV)/bin/uv ] || $(PIP) install -q "uv>=0.5"; } && \
	$(VENV)/bin/uv pip install -q --compile-bytecode --python $(PY) -r pyproject.toml \
	  $(foreach e,$(subst $(comma), ,$(EXTRAS)),--extra $(e)) || \
	echo "[setup] uv could not install them (it reads UV_INDEX_URL, not pip's configuration):" \
	  "pip installs them with a2l below, one after the other"
	@$(call LAP,install,set-up: a2l's dependencies) && $(call CLOCK,install)
	@echo "[setup] building and installing a2l into $(VENV) (C++ core + Python package)"
	@$(PIP) install -q --no-build-isolation -C build-dir=$(BUILD)/py \
	  -C cmake.define.CMAKE_CXX_COMPILER_LAUNCHER=$$(command -v ccache || true) -e ".[$(EXTRAS)]"
	@$(PY) -m compileall -q python/a2l >/dev/null
	@$(call LAP,install,set-up: the Python module's C++ build) && touch $@

setup: $(STAMP_INSTALL)

# --- main job ---------------------------------------------------------------
# The set-up (a no-op when done) and the demo are timed apart: the README quotes both.
demo:
	@t0=$$(date +%s); $(MAKE) --no-print-directory setup; t1=$$(date +%s); rc=0; \
	$(VENV)/bin/a2l demo || rc=$$?; t2=$$(date +%s); \
	echo "[make demo] set-up $$((t1 - t0)) s, a2l demo $$((t2 - t1)) s (wall time, $$(nproc) cores, load average $$(cut -d' ' -f1-3 /proc/loadavg))"; \
	exit $$rc

# --- published results ------------------------------------------------------
PROFILE ?= quick
results: setup
	@$(VENV)/bin/a2l results --profile $(PROFILE)

# --- tests ----------------------------------------------------------------
$(BUILD)/cpp/build.ninja: $(STAMP_VENV) CMakeLists.txt
	@$(VENV)/bin/cmake -S . -B $(BUILD)/cpp -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DA2L_BUILD_PYTHON=OFF -DA2L_BUILD_TESTS=ON -DA2L_BUILD_BENCHMARKS=ON $(LAUNCHER) \
	  -DCMAKE_MAKE_PROGRAM=$(abspath $(VENV))/bin/ninja >/dev/null

test-cpp: setup $(BUILD)/cpp/build.ninja
	@echo "[test] C++ (gtest via ctest)"
	@$(call CLOCK,cpp)
	@$(VENV)/bin/cmake --build $(BUILD)/cpp -j $(JOBS)
	@$(call LAP,cpp,C++ build (core, tests, benchmarks, a2l-run)) && $(call CLOCK,cpp)
	@export A2L_ROBOTS_DIR=$$($(PY) -m a2l.robot --robots-dir); \
	cd $(BUILD)/cpp && $(abspath $(VENV))/bin/ctest --output-on-failure -j $(JOBS) \
	  2>&1 | tee ctest.log
	@$(call LAP,cpp,C++ tests (ctest))

# The real-time tests (every gtest whose suite or test name holds `NoAlloc`, and the allocation
# counter's self-tests) again, in a build with Eigen's allocation guard on and assertions
# enabled (tests/cpp/alloc_counter.hpp): an Eigen heap allocation inside a real-time section
# aborts there. Its own build tree; only the test executable is built, from the test files that
# name a real-time test, on the real-time path alone (CMakeLists.txt: A2L_GUARD_TESTS).
GUARD_TESTS := NoAlloc|AllocationCounter
# The build needs only the build tools (no a2l install): `make test` runs it beside the set-up.
guard-build: $(STAMP_VENV)
	@$(call CLOCK,guard)
	@$(VENV)/bin/cmake -S . -B $(BUILD)/cpp-guard -G Ninja -DCMAKE_BUILD_TYPE=Release \
	  -DA2L_MALLOC_GUARD=ON "-DA2L_GUARD_TESTS=$(GUARD_TESTS)" -DA2L_BUILD_PYTHON=OFF \
	  -DA2L_BUILD_TESTS=ON $(LAUNCHER) \
	  -DA2L_BUILD_BENCHMARKS=OFF -DCMAKE_MAKE_PROGRAM=$(abspath $(VENV))/bin/ninja >/dev/null
	@$(VENV)/bin/cmake --build $(BUILD)/cpp-guard -j $(JOBS) --target a2l_tests
	@$(call LAP,guard,C++ build with the guard (real-time path and its tests))

# (prerequisites are made left to right: the build, then the run)
test-guarded: guard-build guard-run
guard-run: setup
	@echo "[test] real-time tests with Eigen's allocation guard (A2L_MALLOC_GUARD, assertions on)"
	@$(call CLOCK,guard)
	@export A2L_ROBOTS_DIR=$$($(PY) -m a2l.robot --robots-dir); \
	cd $(BUILD)/cpp-guard && $(abspath $(VENV))/bin/ctest --output-on-failure -j $(JOBS) \
	  --no-tests=error -R '$(GUARD_TESTS)' 2>&1 | tee ctest.log
	@$(call LAP,guard,C++ real-time tests with the guard)

# --dist worksteal: a process that runs out of tests takes some of the other's (a slow test near
# the end would otherwise leave one core idle); --durations lists the slowest tests;
# A2L_NO_SKIPS=1: a skipped test fails the run (tests/python/conftest.py).
test-python: setup
	@echo "[test] Python (pytest, $(JOBS) processes)"
	@mkdir -p $(BUILD) && $(call CLOCK,pytest)
	@A2L_NO_SKIPS=1 $(PY) -m pytest -q -n $(JOBS) --dist worksteal --durations=15 \
	  tests/python 2>&1 | tee $(BUILD)/pytest.log
	@$(call LAP,pytest,Python tests (pytest))

# The quick lane: the Python tests not marked `slow` (golden runs, the demo, sweeps and whole
# experiments are; one short case of each family stays here). make test runs both lanes.
test-fast: setup
	@t0=$$(date +%s); A2L_NO_SKIPS=1 $(PY) -m pytest -q -n $(JOBS) --dist worksteal -m "not slow" \
	  --durations=10 tests/python 2>&1 | tee $(BUILD)/pytest-fast.log; \
	echo "[make test-fast] fast lane $$(( $$(date +%s) - t0 )) s (wall time, $$(nproc) cores, load average $$(cut -d' ' -f1-3 /proc/loadavg))"

# libFuzzer on the bundle loader under ASan + UBSan (clang; its own build tree).
FUZZ_RUNS ?= 200000
# The build needs only the build tools: `make test` runs it beside the set-up.
fuzz-build: $(STAMP_VENV)
	@$(call CLOCK,fuzz)
	@$(VENV)/bin/cmake -S . -B $(BUILD)/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DA2L_BUILD_PYTHON=OFF -DA2L_BUILD_FUZZERS=ON -DCMAKE_CXX_COMPILER=clang++ $(LAUNCHER) \
	  "-DCMAKE_CXX_FLAGS=-fsanitize=address,undefined,fuzzer-no-link -fno-sanitize-recover=all" \
	  -DCMAKE_MAKE_PROGRAM=$(abspath $(VENV))/bin/ninja >/dev/null
	@$(VENV)/bin/cmake --build $(BUILD)/fuzz -j $(JOBS) --target fuzz_bundle
	@$(call LAP,fuzz,fuzzer build (skill library under ASan + UBSan))

fuzz: fuzz-build fuzz-run
fuzz-run: setup
	@echo "[fuzz] bundle loader: $(FUZZ_RUNS) inputs under ASan + UBSan"
	@$(call CLOCK,fuzz)
	@mkdir -p $(BUILD)/fuzz/corpus && $(PY) tests/fuzz/make_seeds.py $(BUILD)/fuzz/corpus
	@$(BUILD)/fuzz/fuzz_bundle -runs=$(FUZZ_RUNS) -seed=1 -max_len=8192 -print_final_stats=1 \
	  -artifact_prefix=$(BUILD)/fuzz/ $(BUILD)/fuzz/corpus > $(BUILD)/fuzz/fuzz.log 2>&1 \
	  || { tail -n 40 $(BUILD)/fuzz/fuzz.log; exit 1; }
	@grep -E '^stat::number_of_executed_units' $(BUILD)/fuzz/fuzz.log | sed 's/^/[fuzz] /'
	@$(call LAP,fuzz,fuzzing)

# The import-layer contracts of the Python package (pyproject.toml, docs/architecture.md).
test-layers: setup
	@echo "[test] import layers (lint-imports)"
	@$(call CLOCK,layers)
	@$(VENV)/bin/lint-imports --no-cache 2>&1 | tee $(BUILD)/layers.log | grep -E 'KEPT|BROKEN|Contracts:'
	@$(call LAP,layers,import layers)

# The clock of `make test` starts before its set-up: on a fresh clone the total is the time to a
# first green run, set-up included. Its phases are printed after the counts.
test-clock:
	@rm -f $(BUILD)/times.log && $(call CLOCK,total)

# Two lanes keep both cores busy where a phase alone would leave one idle (pip's downloads and
# unpacking, links, the single-threaded fuzzer): the guarded and fuzzer builds (each with flags
# of its own, nothing to share) run beside the set-up, the fuzzer beside the guarded tests and
# pytest. Each side lane is a make of its own, its output in $(BUILD)/lane-*.log (printed after
# its lane), its phases timed apart: the phases' wall times overlap, their CPU times do not.
# The plain C++ build follows the set-up: it reuses the module build's objects (ccache).
LANE = $(MAKE) --no-print-directory
# the real-time tests of a build tree, sorted: every one of the plain build must be in the
# guarded build (which has one more, the guard's own death test)
RT_TESTS = cd $(BUILD)/$(1) && $(abspath $(VENV))/bin/ctest -N -R '$(GUARD_TESTS)' \
  | sed -n 's/^ *Test *\#[0-9]*: //p' | sort
test: test-clock $(STAMP_VENV)
	@trap 'kill $$(jobs -p) 2>/dev/null || true' EXIT; \
	$(LANE) guard-build fuzz-build > $(BUILD)/lane-builds.log 2>&1 & lane=$$!; \
	$(LANE) setup test-layers test-cpp; \
	wait $$lane || { tail -n 40 $(BUILD)/lane-builds.log; exit 1; }; \
	$(LANE) fuzz-run > $(BUILD)/lane-fuzz.log 2>&1 & lane=$$!; \
	$(LANE) guard-run test-python; \
	wait $$lane || { tail -n 40 $(BUILD)/lane-fuzz.log; exit 1; }; cat $(BUILD)/lane-fuzz.log
	@missing=$$(comm -23 <($(call RT_TESTS,cpp)) <($(call RT_TESTS,cpp-guard))); \
	[ -z "$$missing" ] || { echo "[test] real-time tests not in the guarded build:" $$missing; exit 1; }
	@echo "[test] import layers:               $$(grep -E '^Contracts:' $(BUILD)/layers.log)"
	@echo "[test] C++ (ctest):                 $$(grep -E 'tests passed' $(BUILD)/cpp/ctest.log)"
	@echo "[test] C++ with Eigen's guard:      $$(grep -E 'tests passed' $(BUILD)/cpp-guard/ctest.log)"
	@echo "[test] Python (pytest):             $$(grep -E '^[0-9]+ passed' $(BUILD)/pytest.log | tail -n 1)"
	@echo "[test] all C++ and Python tests passed"
	@sed 's/^/[time] /' $(BUILD)/times.log
	@$(call LAP,total,total) && echo "[time] $$(tail -n 1 $(BUILD)/times.log)"

# --- benchmarks -------------------------------------------------------------
# the extras `bench` (into $(VENV)) and `bench-mplib` (into an environment of its own, see
# pyproject.toml) hold the transit benchmark's peers
# (tomllib from Python 3.11; on 3.10 the TOML reader pip itself vendors)
EXTRA = $(PY) -c 'import sys; exec("try: import tomllib\nexcept ImportError: from pip._vendor import tomli as tomllib"); print(" ".join(tomllib.load(open("pyproject.toml", "rb"))["project"]["optional-dependencies"][sys.argv[1]]))'
MPLIB_VENV := $(BUILD)/venv-mplib
bench: setup $(BUILD)/cpp/build.ninja
	@$(VENV)/bin/cmake --build $(BUILD)/cpp -j $(JOBS)
	@$(PIP) install -q $$($(EXTRA) bench)
	@$(PIP) install -q --index-url https://download.pytorch.org/whl/cpu "torch==2.13.0+cpu" \
	  || $(PIP) install -q "torch==2.13.0"  # the CPU build; offline: a wheel pip finds locally
	@$(PIP) install -q $$($(EXTRA) rl)
	@[ -x $(MPLIB_VENV)/bin/python ] || python3 -m venv $(MPLIB_VENV)
	@$(MPLIB_VENV)/bin/pip install -q $$($(EXTRA) bench-mplib)
	@A2L_BENCH_BIN=$(BUILD)/cpp A2L_MPLIB_PYTHON=$(abspath $(MPLIB_VENV))/bin/python \
	  $(PY) benchmarks/run.py --out BENCHMARKS.md

# --- API reference ----------------------------------------------------------
# Sphinx (autodoc + numpydoc, the extra `docs`) from the package's docstrings: docs/api ->
# $(BUILD)/docs/index.html. Every build reads every page again (-E): a warning fails it (-W),
# also one of a page whose sources did not change since the last build.
docs: setup
	@$(PIP) install -q $$($(EXTRA) docs)
	@$(VENV)/bin/sphinx-build -E -q -W --keep-going -b html -d $(BUILD)/docs-doctrees \
	  docs/api $(BUILD)/docs
	@echo "[docs] $(BUILD)/docs/index.html"

# --- style ----------------------------------------------------------------
# (CITATION.cff: tests/check_cff.py, the vendored schema tests/data/cff-1.2.0.schema.json;
# no package beyond the set-up's)
lint: setup
	@$(VENV)/bin/ruff check python tests benchmarks
	@$(VENV)/bin/lint-imports --no-cache
	@clang-format --dry-run --Werror $$(find cpp bindings tests/cpp benchmarks/cpp -name '*.cpp' -o -name '*.hpp')
	@$(PY) tests/check_cff.py CITATION.cff

format: setup
	@$(VENV)/bin/ruff check --fix python tests benchmarks || true
	@$(VENV)/bin/ruff format python tests benchmarks
	@clang-format -i $$(find cpp bindings tests/cpp benchmarks/cpp -name '*.cpp' -o -name '*.hpp')

clean:
	rm -rf $(BUILD) $(VENV)
