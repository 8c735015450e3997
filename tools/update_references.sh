#!/usr/bin/env bash
# Re-renders every golden reference image (tests/references/*.png) from the
# scenes in scenes/. Look at each image before committing it.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DWHITTED_BUILD_TESTS=ON >/dev/null
cmake --build build
WHITTED_UPDATE_REFERENCES=1 WHITTED_VALIDATION=1 build/tests/whitted_tests --gtest_filter='Scenes/GoldenImage.*'
git status --short tests/references
