#!/usr/bin/env bash
# Runs every test: installs what is missing, builds, runs the ctest suite
# (lavapipe, validation layer on), then the extra suites below.
set -euo pipefail
cd "$(dirname "$0")/.."

tools/install_deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build
ctest --test-dir build --output-on-failure

# ---- Extra suites (sanitizers, fuzzing) ----
