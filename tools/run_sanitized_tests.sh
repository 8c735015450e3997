#!/usr/bin/env bash
# Builds the host and the tests with AddressSanitizer and
# UndefinedBehaviorSanitizer (WHITTED_SANITIZE, build folder build-asan) and
# runs the whole ctest suite under them. Any report fails the run.
#
# Mesa's lavapipe, LLVM and the validation layer are not instrumented. The
# sanitized executables keep every Vulkan driver and layer mapped (see
# WHITTED_SANITIZE in CMakeLists.txt) so that their own leaks carry their
# names; tools/lsan.supp suppresses those, naming driver libraries only.
#
#   tools/run_sanitized_tests.sh [CTEST ARGS...]     e.g. -R 'BadInput|Cli'
set -euo pipefail
cd "$(dirname "$0")/.."

build=build-asan
# Not a unity build (CMakeLists.txt): here every source compiles on its own
# includes. -O1 -g1 (line tables only): full debug info makes the sanitized
# vulkan.hpp code compile six times slower for no better stack traces.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DWHITTED_SANITIZE=ON -DWHITTED_BUILD_TESTS=ON -DCMAKE_UNITY_BUILD=OFF >/dev/null
cmake --build "$build"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1
export LSAN_OPTIONS=suppressions=$PWD/tools/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# One test per core: much of a test's time is starting a sanitized process.
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "$@"
