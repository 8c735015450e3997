#!/usr/bin/env bash
# Builds the host and the tests with AddressSanitizer and
# UndefinedBehaviorSanitizer (WHITTED_SANITIZE, build folder build-asan) and
# runs the tests that exercise host code under them: the readers and loaders
# (XML, glTF, OBJ/MTL, textures, every bad and legal scene of the
# catalogue), the writer and convert, the command line and the files it
# writes, packing, the BVH builder and its parts, bands and regions, the
# pipeline cache, the ray-tree recorder's host side and the masks' legend.
# The renders whose subject is the shader's arithmetic (golden images,
# POV-Ray, analytic, intersection, lights, distribution, watertight, the
# window) run once, unsanitized, in tools/run_tests.sh. Any report fails the
# run.
#
# Mesa's lavapipe, LLVM and the validation layer are not instrumented. The
# sanitized executables keep every Vulkan driver and layer mapped (see
# WHITTED_SANITIZE in CMakeLists.txt) so that their own leaks carry their
# names; tools/lsan.supp suppresses those, naming driver libraries only.
#
#   tools/run_sanitized_tests.sh                     the host-code tests above
#   tools/run_sanitized_tests.sh [CTEST ARGS...]     e.g. -R 'BadInput|Cli'; -R . for every test
set -euo pipefail
cd "$(dirname "$0")/.."

build=build-asan
# Not a unity build (CMakeLists.txt): here every source compiles on its own
# includes, but for the precompiled vulkan_raii.hpp and nlohmann/json.hpp
# (WHITTED_PCH), which most of the build's time would otherwise parse again
# for each source (tools/benchmark_results/notes-build.md). Without the
# Python module, which no test here loads. -O1 -g1 (line tables only): full
# debug info makes the sanitized vulkan.hpp code compile far slower for no
# better stack traces.
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" \
  -DWHITTED_SANITIZE=ON -DWHITTED_BUILD_TESTS=ON -DCMAKE_UNITY_BUILD=OFF -DWHITTED_PCH=ON -DWHITTED_BUILD_PYTHON=OFF \
  >/dev/null
cmake --build "$build"

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1
export LSAN_OPTIONS=suppressions=$PWD/tools/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
host_tests='^(BadInput/|BadSceneCatalogue|DegenerateButLegal/|LegalSceneCatalogue|[A-Za-z]+/SceneLoaderErrorTest|'
host_tests+='SceneLoaderTest|SceneWriter|Cli\.|CliOptions|Convert|QuickLook|ImageOutput|ImageLibrary|MeshFile|'
host_tests+='MeshPlacement|GltfHardening|Authored(Gltf|Obj|Camera)\.|Texture(File|Loader)\.|CsgLoader|LightsLoader|'
host_tests+='Bvh\.|BvhParts|Bands|Region|PipelineCache|DescriptorLimits|RayTree\.|Masks)'
(($#)) || set -- -R "$host_tests"
# One test per core: much of a test's time is starting a sanitized process.
ctest --test-dir "$build" --output-on-failure -j "$(nproc)" "$@"
