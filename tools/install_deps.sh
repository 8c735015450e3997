#!/usr/bin/env bash
# Installs whitted's dependencies from Debian 12 packages.
#   tools/install_deps.sh        what building whitted and rendering need (README command 1)
#   tools/install_deps.sh --all  also what the tests, the fuzzers, the benchmark and the Python module need
#                                (tools/run_tests.sh runs this)
# Safe to run repeatedly: only missing packages are installed. Every package is
# listed once, below, with what needs it.
set -euo pipefail

all=0
case ${1:-} in
  "") ;;
  --all) all=1 ;;
  *) echo "usage: tools/install_deps.sh [--all]" >&2; exit 2 ;;
esac

# ---- The renderer: `cmake --build build` and `build/whitted render` ----
packages=(
  build-essential cmake ninja-build pkg-config         # the compiler and the build
  libvulkan-dev                                        # the Vulkan loader and headers (host/vk/)
  glslang-tools                                        # shaders/*.comp to SPIR-V at build time
  spirv-tools                                          # spirv-opt: less SPIR-V for the driver to compile
  libglm-dev libtinyxml2-dev libcli11-dev nlohmann-json3-dev  # vectors, the XML scenes, the command line, the render record
  libopenimageio-dev                                   # EXR/TIFF/JPEG and textures (the image module, host/io/)
  openimageio-tools                                    # OpenImageIO's CMake package names these binaries (iconvert ...): without them
                                                       # `cmake -S . -B build` stops; the tests use its oiiotool as an independent reader
  libpng-dev                                           # PNG written without the image module (host/io/png_file.cpp)
  libassimp-dev                                        # model files: OBJ, glTF, PLY ... (host/io/mesh_file.cpp)
  libglfw3-dev libimgui-dev                            # `whitted view`, the live window (host/view/)
)
# Packages taken from bookworm-backports (the standard Debian route for a
# newer version). Mesa 25's lavapipe, the Vulkan device of a machine without
# a GPU, runs the same shader 3-8x faster than Debian 12's 22.3 and offers
# VK_KHR_ray_query; whitted stays correct on 22.3, but a first render should
# not be the slow one, so it is in the default set.
backports=(mesa-vulkan-drivers)

# ---- --all: the tests and tools (tools/run_tests.sh) ----
test_packages=(
  libgtest-dev                                         # build/tests/whitted_tests (tests/CMakeLists.txt)
  vulkan-validationlayers                              # every test renders with the Khronos validation layer (--validate)
  vulkan-tools                                         # vulkaninfo, to see which devices a failing test had
  xvfb xauth xdotool                                   # `whitted view` under a virtual X server (tests/view_test.cpp)
  assimp-testmodels                                    # real models for the tests and the glTF/OBJ fuzzers' seeds
  povray                                               # the POV-Ray cross-check and the benchmark's opponent
  libembree-dev                                        # the benchmark's limit anchor (tools/embree_anchor.cpp)
  libstb-dev                                           # the GPU kit's image module (tools/gpu_kit.sh, -DWHITTED_IMAGE_LIBRARY=stb)
  python3-matplotlib                                   # the benchmark's plot (tools/bench/plot.py)
  python3-distributed python3-openimageio              # the render farm and its test (tools/farm.py, tests/farm_test.py)
  clang-14 libfuzzer-14-dev libclang-rt-14-dev         # the fuzz targets (tools/run_fuzzer.sh)
  pybind11-dev python3-pytest python3-numpy python3-venv python3-pip  # the Python module (host/python/), its tests
)
# scikit-build-core (`pip install .`, pyproject.toml; tests/python) exists only in backports.
test_backports=(python3-scikit-build-core)
if ((all)); then
  packages+=("${test_packages[@]}")
  backports+=("${test_backports[@]}")
fi
backports_list=/etc/apt/sources.list.d/whitted-bookworm-backports.sources

SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
export DEBIAN_FRONTEND=noninteractive

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# A backported package counts as installed only in its backports version.
missing_bpo=()
for p in "${backports[@]}"; do
  dpkg-query -W -f='${Version}' "$p" 2>/dev/null | grep -q "bpo" || missing_bpo+=("$p")
done

if ((${#missing[@]} + ${#missing_bpo[@]})); then
  echo "install_deps: installing ${missing[*]} ${missing_bpo[*]}" >&2
  if [ ! -f "$backports_list" ]; then
    printf 'Types: deb\nURIs: http://deb.debian.org/debian\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' |
      $SUDO tee "$backports_list" >/dev/null
  fi
  $SUDO apt-get update -qq
  ((${#missing[@]} == 0)) || $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
  ((${#missing_bpo[@]} == 0)) ||
    $SUDO apt-get install -y -qq --no-install-recommends -t bookworm-backports "${missing_bpo[@]}" >/dev/null
fi

# Dear ImGui's GLFW and Vulkan back ends ship as example sources under
# /usr/share/doc (host/CMakeLists.txt compiles them). Minimal images often tell
# dpkg to skip /usr/share/doc; then take them from the package itself.
backends=/usr/share/doc/libimgui-dev/examples/backends
if [ ! -f "$backends/imgui_impl_vulkan.cpp" ] || [ ! -f "$backends/imgui_impl_glfw.cpp" ]; then
  echo "install_deps: restoring the ImGui back-end sources into $backends" >&2
  work=$(mktemp -d)
  chmod 755 "$work"  # apt downloads as the _apt user
  (cd "$work" && apt-get download -qq libimgui-dev && dpkg-deb -x libimgui-dev_*.deb extracted)
  $SUDO mkdir -p "$backends"
  $SUDO cp "$work"/extracted/usr/share/doc/libimgui-dev/examples/backends/imgui_impl_{glfw,vulkan}.cpp "$backends/"
  rm -rf "$work"
fi
