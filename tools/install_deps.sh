#!/usr/bin/env bash
# Installs every build and test dependency of whitted from Debian 12 packages.
# Safe to run repeatedly: apt-get skips what is already installed.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libvulkan-dev vulkan-tools vulkan-validationlayers
  glslang-tools spirv-tools
  libglfw3-dev libglm-dev libtinyxml2-dev libopenimageio-dev openimageio-tools
  libpng-dev  # PNG written without the image module (host/io/png_file.cpp)
  libgtest-dev libcli11-dev
  libembree-dev  # the benchmark's limit anchor (tools/embree_anchor.cpp); whitted itself does not link it
  povray xvfb xauth
  assimp-testmodels  # real models for tests (BoxTextured.glb, ClearCoatTest.gltf, quick looks)
  python3-matplotlib
  clang-14 libfuzzer-14-dev libclang-rt-14-dev
  libassimp-dev
  libimgui-dev xdotool
  nlohmann-json3-dev
  python3-distributed python3-openimageio
  pybind11-dev python3-pytest python3-numpy python3-venv python3-pip  # the Python module (host/python/), its tests
)

# Packages taken from bookworm-backports (the standard Debian route for a
# newer version): Mesa 25's lavapipe is 3-8x faster than Debian 12's 22.3 on
# the same shader and offers VK_KHR_ray_query. whitted stays correct on 22.3.
# scikit-build-core (`pip install .`, pyproject.toml) exists only there.
backports=(mesa-vulkan-drivers python3-scikit-build-core)
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
# /usr/share/doc (CMakeLists.txt compiles them). Minimal images often tell
# dpkg to skip /usr/share/doc; then take them from the package itself.
backends=/usr/share/doc/libimgui-dev/examples/backends
if [ ! -f "$backends/imgui_impl_vulkan.cpp" ] || [ ! -f "$backends/imgui_impl_glfw.cpp" ]; then
  echo "install_deps: restoring the ImGui back-end sources into $backends" >&2
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO=sudo
  work=$(mktemp -d)
  chmod 755 "$work"  # apt downloads as the _apt user
  (cd "$work" && apt-get download -qq libimgui-dev && dpkg-deb -x libimgui-dev_*.deb extracted)
  $SUDO mkdir -p "$backends"
  $SUDO cp "$work"/extracted/usr/share/doc/libimgui-dev/examples/backends/imgui_impl_{glfw,vulkan}.cpp "$backends/"
  rm -rf "$work"
fi
