#!/usr/bin/env bash
# Builds the fuzz targets (clang-14, libFuzzer + ASan + UBSan) in build-fuzz
# and runs each for SECONDS [45], one target per core at a time (four
# targets: 90 s on 2 cores):
#   scene_loader  the XML scene loader, seeded from tests/fuzz_corpus/xml
#   gltf          the glTF/GLB reader and its mapping, seeded from
#                 tests/fuzz_corpus/gltf and assimp-testmodels' glTF 2.0 files
#   obj_mtl       the OBJ and MTL readers and their mapping, seeded from
#                 tests/fuzz_corpus/obj_mtl and assimp-testmodels' OBJ files
#   texture       texture files (PNG, JPEG, EXR, HDR, TGA, BMP, TIFF) and
#                 embedded images decoded, seeded from tests/fuzz_corpus/texture
# Fails on any finding: a crash, a sanitizer report, an exception other than
# SceneError, a loaded scene that breaks the loader's promises
# (tools/fuzz/scene_checks.h), a timeout or an out-of-memory. The input that
# caused it is left in build-fuzz/findings/TARGET/.
# The mutations start from a fixed seed (FUZZ_SEED [1]): a run on a fresh
# working corpus (as CI's, in a clean clone) tries the same inputs in the
# same order as any other such run, so a longer run here has already tried
# what CI will try in its minutes.
#
#   tools/run_fuzzer.sh [SECONDS [TARGET...]]
#   build-fuzz/gltf_fuzzer build-fuzz/findings/gltf/crash-...   # replay one
set -euo pipefail
cd "$(dirname "$0")/.."

seconds=${1:-45}
shift || true
targets=("$@")
((${#targets[@]})) || targets=(scene_loader gltf obj_mtl texture)
build=build-fuzz
models=/usr/share/assimp/models

cmake -S . -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DWHITTED_FUZZ=ON -DWHITTED_BUILD_TESTS=OFF -DCMAKE_UNITY_BUILD=OFF >/dev/null
cmake --build "$build" --target "${targets[@]/%/_fuzzer}"

export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1}
export LSAN_OPTIONS=suppressions=$PWD/tools/fuzz/lsan.supp
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
# One target: its seeds, its dictionary, its working corpus. New inputs
# found go to a working corpus in the build folder (kept between runs); the
# seeds are only read.
fuzz() {
  local target=$1 seeds dict
  case $target in
    scene_loader) seeds=(tests/fuzz_corpus/xml) dict=(-dict=tools/fuzz/scene.dict) ;;
    gltf) seeds=(tests/fuzz_corpus/gltf "$models/glTF2") dict=() ;;
    obj_mtl) seeds=(tests/fuzz_corpus/obj_mtl "$models/OBJ") dict=() ;;
    texture) seeds=(tests/fuzz_corpus/texture) dict=() ;;
    *) echo "run_fuzzer: no target $target" >&2; return 2 ;;
  esac
  mkdir -p "$build/corpus/$target" "$build/findings/$target"
  echo "run_fuzzer: fuzzing $target for ${seconds} s" >&2
  local status=0
  "$build/${target}_fuzzer" "$build/corpus/$target" "${seeds[@]}" "${dict[@]}" \
    -max_total_time="$seconds" -seed="${FUZZ_SEED:-1}" -timeout=10 -rss_limit_mb=2048 \
    -max_len=65536 -print_final_stats=1 -artifact_prefix="$build/findings/$target/" >"$build/$target.log" 2>&1 || status=$?
  cat "$build/$target.log" >&2
  return $status
}

# One target per core; each keeps its own seed and time, so a run finds
# what it would find alone. Any target's failure fails the run.
failed=0
running=0
for target in "${targets[@]}"; do
  if ((running >= $(nproc))); then
    wait -n || failed=1
    running=$((running - 1))
  fi
  fuzz "$target" &
  running=$((running + 1))
done
while ((running > 0)); do
  wait -n || failed=1
  running=$((running - 1))
done
exit $failed
