#!/bin/bash
# tools/gpu_kit.sh: builds the GPU kit, one folder (at most 40 MiB) that runs
# whitted and its check (tools/gpu_check.sh) on a Linux machine with a Vulkan
# driver and nothing else installed: no packages, no network (a GPU machine
# lent for a few minutes; tools/README.md "GPU kit").
#
#   tools/gpu_kit.sh [--out DIR] [--build DIR] [--no-references]
#
#   --out DIR        the kit's folder [gpu-kit, in the repository's root; git ignores it]
#   --build DIR      the kit's own build folder [build-kit]
#   --no-references  skip rendering the reference images (a kit without them
#                    cannot run the check's comparison; for trying the build)
#
# What it holds:
#   whitted          a wrapper: bin/whitted with the kit's library path
#   kit_env.sh       that path (sourced by the wrapper and gpu_check.sh)
#   bin/             whitted built headless (-DWHITTED_BUILD_VIEW=OFF: no GLFW,
#                    no ImGui), no Python module, its image module built from
#                    stb_image (-DWHITTED_IMAGE_LIBRARY=stb: OpenImageIO's
#                    module needs hundreds of libraries), and whitted_kit
#                    (tools/gpu_kit/whitted_kit.cpp: PSNR, records, the mesh);
#                    all stripped. The shaders are embedded in whitted.
#   lib/             every shared library these need as ldd lists them but
#                    glibc's own (libc, libm, libdl, libpthread, librt, the
#                    dynamic loader: the machine's must be used); the Vulkan
#                    loader (whitted opens it at run time); and the libraries
#                    NVIDIA's Vulkan driver (libGLX_nvidia.so.0) loads that a
#                    bare system may lack: glvnd's libGLdispatch, libXext and
#                    libX11's chain. lib/cxx/: libstdc++ and libgcc_s, which
#                    need a newer glibc than the rest; kit_env.sh leaves them
#                    out where the machine's glibc is older than they need and
#                    it has a libstdc++ of its own.
#   scenes/          scenes/*.xml and the textures they read
#   bench/           the benchmark's mesh1m scene (tools/generate_scenes.py
#                    mesh 1000000) and its OBJ's SHA-256; the check writes the
#                    OBJ with whitted_kit mesh-obj and checks it against that
#   references/      every scene rendered at 640x480 on both trace paths by
#                    this machine's driver (lavapipe), with the records
#   gpu_check.sh     tools/gpu_check.sh
#   KIT.json         what was built from what: commit, driver, glibc needed
#
# Needs what the ordinary build needs (tools/install_deps.sh --all: libstb-dev among them), and
# a Vulkan driver here (lavapipe) for the references. Exit statuses: 0 built,
# 1 a step failed, 2 bad arguments.
set -euo pipefail

ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
OUT=$ROOT/gpu-kit
BUILD=$ROOT/build-kit
REFERENCES=1
LIMIT_BYTES=$((40 * 1024 * 1024))
# The settings the references and the check's scene renders share (gpu_check.sh reads them from KIT.json's copy).
SCENE_WIDTH=640
SCENE_HEIGHT=480
MESH_TRIANGLES=1000000

fail() { echo "gpu_kit.sh: $1" >&2; exit "${2:-1}"; }

while [[ $# -gt 0 ]]; do
    case $1 in
        --out) [[ $# -ge 2 ]] || fail "--out needs a folder" 2; OUT=$(realpath -m "$2"); shift 2 ;;
        --build) [[ $# -ge 2 ]] || fail "--build needs a folder" 2; BUILD=$(realpath -m "$2"); shift 2 ;;
        --no-references) REFERENCES=0; shift ;;
        -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        *) fail "unknown argument '$1' (see --help)" 2 ;;
    esac
done
case $OUT in "$ROOT"|/) fail "--out must be a folder of its own, not $OUT" 2 ;; esac

# ---- Build: headless, no Python module, the stb image module, whitted_kit ----
launcher=()
if command -v ccache >/dev/null; then
    launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S "$ROOT" -B "$BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release -DWHITTED_BUILD_VIEW=OFF \
    -DWHITTED_BUILD_PYTHON=OFF -DWHITTED_BUILD_TESTS=OFF -DWHITTED_IMAGE_LIBRARY=stb -DWHITTED_BUILD_KIT=ON \
    "${launcher[@]}" >/dev/null || fail "configuring $BUILD failed"
nice cmake --build "$BUILD" --target whitted whitted_image_io whitted_kit || fail "building $BUILD failed"

# ---- Assemble into OUT.partial, renamed to OUT when complete ----
STAGE=$OUT.partial
rm -rf "$STAGE"
mkdir -p "$STAGE"/{bin,lib,scenes,bench,references}
trap 'rm -rf "$STAGE"' EXIT
for f in whitted whitted_image_io.so whitted_kit; do
    cp "$BUILD/$f" "$STAGE/bin/$f"
    strip --strip-unneeded "$STAGE/bin/$f"
done

# Every library ldd resolves for the binaries; the Vulkan loader, which whitted opens at run time
# (vk::raii::Context's dynamic loader); and what NVIDIA's driver may need beyond the machine's driver files (its
# ICD libGLX_nvidia.so.0 needs glvnd's libGLdispatch and libXext). glibc's libraries stay the machine's: they
# must match its dynamic loader.
is_glibc() { [[ $1 =~ ^(libc|libm|libdl|libpthread|librt|libresolv|libutil|ld-linux-x86-64)\.so ]]; }
copy_closure() {  # copy_closure FILE...: FILEs' libraries (ldd's closure) into lib/ under their sonames
    local name path
    while read -r name path; do
        is_glibc "$name" || [[ -e $STAGE/lib/$name ]] || cp -L "$path" "$STAGE/lib/$name"
    done < <(ldd "$@" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | sort -u)
}
copy_closure "$STAGE"/bin/*
extras=()
for soname in libvulkan.so.1 libGLdispatch.so.0 libXext.so.6; do
    path=$(ldconfig -p | awk -v n="$soname" '$1 == n && /x86-64/ {print $NF; exit}')
    [[ -n $path ]] || fail "$soname not found here (Debian: libvulkan1, libglvnd0, libxext6)"
    cp -L "$path" "$STAGE/lib/$soname"
    extras+=("$STAGE/lib/$soname")
done
copy_closure "${extras[@]}"
chmod u+w "$STAGE"/lib/*
strip --strip-unneeded "$STAGE"/lib/*
# libstdc++ and libgcc_s need a newer glibc than the rest (Debian 12's 2.36): in lib/cxx/, used unless the
# machine's glibc is older and it has a libstdc++ of its own (kit_env.sh).
mkdir "$STAGE/lib/cxx"
mv "$STAGE/lib/libstdc++.so.6" "$STAGE/lib/libgcc_s.so.1" "$STAGE/lib/cxx/"
# Every library must now resolve inside the kit (glibc's apart).
missing=$(LD_LIBRARY_PATH=$STAGE/lib:$STAGE/lib/cxx ldd "$STAGE"/bin/* "$STAGE"/lib/*.so* "$STAGE"/lib/cxx/* \
          2>/dev/null | awk '$2 == "=>" {print $1, $3}' | while read -r name path; do
              is_glibc "$name" || [[ $path == "$STAGE/lib/"* ]] || echo "$name ($path)"; done | sort -u)
[[ -z $missing ]] || fail "libraries that resolve outside the kit: $missing"
glibc_of() { objdump -T "$@" 2>/dev/null | grep -o 'GLIBC_2\.[0-9]*' | sort -uV | tail -1 | sed 's/GLIBC_//'; }
glibc_needed=$(glibc_of "$STAGE"/bin/* "$STAGE"/lib/*.so*)
glibc_needed_cxx=$(glibc_of "$STAGE"/lib/cxx/*)

cat > "$STAGE/kit_env.sh" <<ENV
# The GPU kit's library path (tools/gpu_kit.sh), sourced by ./whitted and gpu_check.sh with \$kit set: lib/,
# and lib/cxx/ (libstdc++ and libgcc_s, which need glibc $glibc_needed_cxx) unless this machine's glibc is older
# and it has a libstdc++ of its own. The rest needs glibc $glibc_needed.
kit_glibc_needed=$glibc_needed
kit_glibc_needed_cxx=$glibc_needed_cxx
ENV
cat >> "$STAGE/kit_env.sh" <<'ENV'
kit_glibc=$(getconf GNU_LIBC_VERSION 2>/dev/null | cut -d' ' -f2)
kit_libraries="$kit/lib:$kit/lib/cxx"
if [ -n "$kit_glibc" ] && [ "$(printf '%s\n%s\n' "$kit_glibc_needed_cxx" "$kit_glibc" | sort -V | head -1)" != \
     "$kit_glibc_needed_cxx" ] && ldconfig -p 2>/dev/null | grep -q 'libstdc++\.so\.6 '; then
    kit_libraries="$kit/lib"
fi
export LD_LIBRARY_PATH="$kit_libraries${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
ENV
cat > "$STAGE/whitted" <<'WRAPPER'
#!/bin/sh
# The GPU kit's whitted (tools/gpu_kit.sh): the kit's libraries first (kit_env.sh).
kit=$(cd "$(dirname "$0")" && pwd)
. "$kit/kit_env.sh"
exec "$kit/bin/whitted" "$@"
WRAPPER
chmod +x "$STAGE/whitted"
cp "$ROOT/tools/gpu_check.sh" "$STAGE/gpu_check.sh"

# ---- Scenes, and the benchmark's mesh (the XML and the OBJ's hash; the check writes the OBJ) ----
cp "$ROOT"/scenes/*.xml "$STAGE/scenes/"
cp -r "$ROOT/scenes/textures" "$STAGE/scenes/"
mesh_work=$(mktemp -d)
trap 'rm -rf "$STAGE" "$mesh_work"' EXIT
/usr/bin/python3 "$ROOT/tools/generate_scenes.py" mesh "$MESH_TRIANGLES" "$mesh_work/mesh1m.xml" 2>/dev/null ||
    fail "tools/generate_scenes.py mesh failed"
"$STAGE/bin/whitted_kit" mesh-obj "$MESH_TRIANGLES" "$mesh_work/kit.obj" || fail "whitted_kit mesh-obj failed"
cmp -s "$mesh_work/mesh1m.obj" "$mesh_work/kit.obj" ||
    fail "whitted_kit mesh-obj $MESH_TRIANGLES differs from tools/generate_scenes.py's OBJ"
cp "$mesh_work/mesh1m.xml" "$STAGE/bench/"
(cd "$mesh_work" && sha256sum mesh1m.obj) > "$STAGE/bench/mesh1m.obj.sha256"
rm -rf "$mesh_work"

# ---- References: every scene on both trace paths, this machine's driver ----
driver="none"
if [[ $REFERENCES == 1 ]]; then
    for path in bvh rayquery; do
        for scene in "$STAGE"/scenes/*.xml; do
            name=$(basename "$scene" .xml)
            "$STAGE/whitted" render "$scene" -o "$STAGE/references/$name.$path.png" --width $SCENE_WIDTH \
                --height $SCENE_HEIGHT --aov none --trace $path -q ||
                fail "the reference of $name ($path) did not render"
        done
    done
    record=$(ls "$STAGE"/references/*.json | head -1)
    driver=$(grep -o '"driver": *"[^"]*"' "$record" | head -1 | sed 's/.*: *"//; s/"$//')
fi

commit=$(git -C "$ROOT" rev-parse HEAD 2>/dev/null || echo unknown)
dirty=$(git -C "$ROOT" status --porcelain --untracked-files=no 2>/dev/null | grep -q . && echo true || echo false)
cat > "$STAGE/KIT.json" <<EOF
{
  "built": "$(date -u +%Y-%m-%dT%H:%M:%SZ)",
  "commit": "$commit",
  "uncommitted_changes": $dirty,
  "built_on": "$(. /etc/os-release && echo "$PRETTY_NAME")",
  "glibc_needed": "$glibc_needed",
  "glibc_needed_by_libstdcxx": "$glibc_needed_cxx",
  "reference_driver": "$driver",
  "scene_width": $SCENE_WIDTH,
  "scene_height": $SCENE_HEIGHT,
  "scene_settings": "--aov none (default sampling and depth)",
  "mesh_triangles": $MESH_TRIANGLES
}
EOF

size=$(du -sb "$STAGE" | cut -f1)
((size <= LIMIT_BYTES)) || { du -ab "$STAGE" | sort -n | tail -15 >&2; fail "the kit is $size bytes, over 40 MiB"; }
rm -rf "$OUT"
mv "$STAGE" "$OUT"
trap - EXIT
echo "gpu_kit.sh: $OUT: $size bytes ($(du -sh "$OUT" | cut -f1)), glibc >= $glibc_needed ($glibc_needed_cxx for" \
     "its libstdc++), references by $driver"
