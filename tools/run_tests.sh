#!/usr/bin/env bash
# Runs every test: installs what is missing (tools/install_deps.sh --all),
# builds everything (WHITTED_BUILD_TESTS), runs the ctest suite
# (lavapipe, validation layer on), then the extra suites below.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install_deps.sh --all
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DWHITTED_WARNINGS_AS_ERRORS=ON -DWHITTED_BUILD_TESTS=ON
cmake --build build
# The GPU-readiness tier (ctest -L gpu_readiness) takes far longer than the rest on lavapipe:
# run it by itself (tests/README.md "GPU readiness").
ctest --test-dir build --output-on-failure -LE gpu_readiness
# The Python module (tests/python/): the same pixels as the CLI, uploads,
# errors, threads, Ctrl+C, memory, and `pip install .` into a fresh venv.
PYTHONPATH=build/python WHITTED_VALIDATION=1 /usr/bin/python3 -m pytest tests/python -q

# ---- Extra suites (sanitizers, fuzzing) ----
# The whole ctest suite again, built with AddressSanitizer and
# UndefinedBehaviorSanitizer (build-asan; about 5 minutes on 2 cores).
tools/run_sanitized_tests.sh
# The XML, glTF/GLB, OBJ/MTL and texture readers under libFuzzer, 45 s each
# from a fixed seed (build-fuzz).
tools/run_fuzzer.sh 45
