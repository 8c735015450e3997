#!/usr/bin/env bash
# Runs every test: installs what is missing (tools/install_deps.sh --all),
# builds everything (WHITTED_BUILD_TESTS), runs the ctest suite
# (lavapipe, validation layer on), then the extra suites below.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install_deps.sh --all
# In README command 1's build folder when it exists: the Python module is
# decided at every configure (WHITTED_BUILD_PYTHON=AUTO) and built for the
# interpreter that runs its tests.
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DWHITTED_WARNINGS_AS_ERRORS=ON -DWHITTED_BUILD_TESTS=ON \
  -DPython3_EXECUTABLE=/usr/bin/python3
cmake --build build
if ! compgen -G 'build/python/whitted*.so' >/dev/null; then
  echo "run_tests: build/python has no module whitted: is pybind11-dev installed?" >&2
  exit 1
fi
# Two tests at a time: a test's process spends much of its time on one core
# (start-up, lavapipe compiling the tracer), so two fill the machine. The
# GPU-readiness tier (label gpu_readiness, tests/README.md "GPU readiness")
# runs by itself: GPU-assisted validation makes lavapipe compile each
# pipeline for minutes.
ctest --test-dir build --output-on-failure -j "$(nproc)" -LE gpu_readiness
# The Python module (tests/python/): the same pixels as the CLI, uploads,
# errors, threads, Ctrl+C, memory, and `pip install .` into a fresh venv.
PYTHONPATH=build/python WHITTED_VALIDATION=1 /usr/bin/python3 -m pytest tests/python -q

# ---- Extra suites (sanitizers, fuzzing) ----
# The tests that exercise host code again, built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan; the list is in the script).
tools/run_sanitized_tests.sh
# The XML, glTF/GLB, OBJ/MTL and texture readers under libFuzzer, 45 s each
# from a fixed seed, one per core at a time (build-fuzz).
tools/run_fuzzer.sh 45
