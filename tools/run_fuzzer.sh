#!/usr/bin/env bash
# Builds the scene loader fuzzer (clang-14, libFuzzer + ASan + UBSan) in
# build-fuzz and runs it for SECONDS [60], seeded from tests/fuzz_corpus.
# Fails on any finding: a crash, a sanitizer report, an exception other than
# SceneError, a loaded scene that breaks the loader's promises, a timeout or
# an out-of-memory. The input that caused it is left in build-fuzz/findings/.
#
#   tools/run_fuzzer.sh [SECONDS]
#   build-fuzz/scene_loader_fuzzer build-fuzz/findings/crash-...   # replay one
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-60}
build=build-fuzz

cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DWHITTED_FUZZ=ON -DWHITTED_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target scene_loader_fuzzer

# New inputs found go to a working corpus in the build folder (kept between
# runs); tests/fuzz_corpus only seeds it and is never written to.
mkdir -p "$build/corpus" "$build/findings"
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
echo "run_fuzzer: fuzzing the scene loader for ${seconds} s" >&2
"$build/scene_loader_fuzzer" "$build/corpus" tests/fuzz_corpus \
  -dict=tools/fuzz/scene.dict -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
  -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/"
