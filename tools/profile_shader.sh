#!/usr/bin/env bash
# Profiles the tracer on lavapipe by switching features off, one at a time,
# in the same run: shader variants compiled from shaders/whitted.comp with
# -D WHITTED_PROFILE_* (passed to whitted through WHITTED_SHADER_SPV) and
# run-time options (--aov, --max-depth, --no-bvh). Prints the render time of
# each, REPEAT times, interleaved so that machine load affects them alike.
# The shader override is compiled only into a developer build
# (WHITTED_DEVELOPER): the script configures and builds one in build-dev and
# runs its whitted (the build's output goes to stderr).
#
#   tools/profile_shader.sh SCENE [WIDTHxHEIGHT] [SPP] [REPEAT] [VARIANT...]
#   variants: base aov_all no_shadows depth0 no_bvh, or define:NAME for any
#   other -D NAME (e.g. define:WHITTED_PROFILE_NO_SHADOWS; also
#   WHITTED_PROFILE_CAMERA_ONLY, WHITTED_PROFILE_NO_SHADING,
#   WHITTED_PROFILE_NO_LIGHTS). The image is written as PPM: the render
#   time includes writing the bands to the file, and a PNG's compression
#   time depends on the image, which the variants change.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:?usage: tools/profile_shader.sh SCENE [WxH] [SPP] [REPEAT] [VARIANT...]}
size=${2:-640x480}
spp=${3:-1}
repeat=${4:-3}
shift $(( $# < 4 ? $# : 4 ))
variants=("$@")
[ ${#variants[@]} -gt 0 ] || variants=(base aov_all no_shadows depth0 no_bvh)
build=build-dev
cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DWHITTED_DEVELOPER=ON -DWHITTED_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" --target whitted >&2
work=$(mktemp -d /tmp/whitted-profile.XXXXXX)
trap 'rm -rf "$work"' EXIT

compile() {  # compile NAME DEFINE...
    local name=$1; shift
    glslangValidator -V --target-env vulkan1.2 --quiet -Ishaders "$@" -o "$work/$name.spv" shaders/whitted.comp
}
declare -A spv args
for v in "${variants[@]}"; do
    case $v in
        base) args[$v]="--aov none" ;;
        aov_all) args[$v]="--aov all" ;;
        depth0) args[$v]="--aov none --max-depth 0" ;;
        no_bvh) args[$v]="--aov none --no-bvh" ;;
        no_shadows) compile "$v" -DWHITTED_PROFILE_NO_SHADOWS; spv[$v]=$work/$v.spv; args[$v]="--aov none" ;;
        define:*) compile "${v#define:}" "-D${v#define:}"; spv[$v]=$work/${v#define:}.spv; args[$v]="--aov none" ;;
        *) echo "profile_shader.sh: unknown variant '$v'" >&2; exit 2 ;;
    esac
done
w=${size%x*}; h=${size#*x}
for ((r = 1; r <= repeat; ++r)); do
    for v in "${variants[@]}"; do
        WHITTED_SHADER_SPV=${spv[$v]:-} "$build/whitted" render "$scene" -o "$work/out.ppm" --width "$w" --height "$h" \
            --aa uniform --spp "$spp" ${args[$v]} -q
        python3 -c "import json,sys; r=json.load(open(sys.argv[1])); t=r['timings_s']; n=r['rays'];
print(f\"{sys.argv[2]:28s} render {t['render']:7.3f} s  pipeline {t['pipeline']:.3f} s  {n['per_second']/1e6:6.2f} Mrays/s  \"
      f\"p {n['primary']} s {n['shadow']} r {n['secondary']}\")" "$work/out.json" "$v"
    done
done
