#!/bin/bash
# gpu_check.sh: whitted's check on a GPU, run from the GPU kit (tools/gpu_kit.sh
# copies it there) on a Linux machine with a Vulkan driver and nothing else
# installed (tools/README.md "GPU kit"). Needs bash, coreutils and the kit.
#
#   gpu-kit/gpu_check.sh OUTDIR [--quick] [--repeats N] [--min-psnr DB] [--allow-cpu]
#                               [--deadline SECONDS] [--work DIR] [--kit DIR]
#
# 1. `whitted devices`.
# 2. Every scene of the kit (scenes/*.xml) at the references' size (640x480,
#    --aov none, default sampling) on each trace path the device offers (bvh,
#    and rayquery where it has ray queries), each compared with the image the
#    reference driver (lavapipe) made for the kit: PSNR as
#    tools/bench/measures.py computes it (whitted_kit psnr), and a diff image.
# 3. The benchmark's GPU part (tools/bench/plan.py's settings: --aa uniform,
#    --max-depth 6, --aov none): the 1M-triangle mesh (tools/generate_scenes.py
#    mesh 1000000, written by whitted_kit mesh-obj and checked against the
#    generator's SHA-256) at 640x480 1 spp and 1920x1080 16 spp, camera plus
#    shadow rays per second; the room at 1920x1080, 1 and 16 spp, all rays per
#    second; the shader's ray counts from each render's record. Each render
#    --repeats times (3), the median reported, on each trace path.
#
# Writes OUTDIR/check.json (every result, the records' numbers, the kit's
# KIT.json), OUTDIR/check.log (what it printed), OUTDIR/devices.txt and
# OUTDIR/images.tar (the scene renders, their diff images and records; tar
# missing: OUTDIR/images/).
# Passes (exit 0) when every render succeeds, every scene is within --min-psnr
# (30 dB) of its reference, no camera sample is lost, the device is not a CPU
# (unless --allow-cpu) and it ends before --deadline (400 s: later renders are
# skipped, one under way is stopped a minute past it, so that the whole check
# ends within 8 minutes). Else exit 1; bad arguments exit 2.
#
#   --quick      the benchmark part at a quarter of each side, once (scenes unchanged)
#   --allow-cpu  pass on a CPU device (lavapipe: testing the kit without a GPU)
#   --work DIR   the working folder (renders, the mesh) [a new one under TMPDIR, removed at the end]
#   --kit DIR    the kit [this script's folder]
set -uo pipefail
export LC_ALL=C  # decimal points in printf's numbers

fail() { echo "gpu_check.sh: $1" >&2; exit "${2:-1}"; }

KIT=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
OUTDIR=""
QUICK=0
REPEATS=3
MIN_PSNR=30
ALLOW_CPU=0
DEADLINE=400
WORK=""
while [[ $# -gt 0 ]]; do
    case $1 in
        --quick) QUICK=1; REPEATS=1; shift ;;
        --repeats) [[ ${2:-} =~ ^[1-9][0-9]*$ ]] || fail "--repeats needs a count >= 1" 2; REPEATS=$2; shift 2 ;;
        --min-psnr) [[ ${2:-} =~ ^[0-9]+$ ]] || fail "--min-psnr needs a whole number of dB" 2; MIN_PSNR=$2; shift 2 ;;
        --allow-cpu) ALLOW_CPU=1; shift ;;
        --deadline) [[ ${2:-} =~ ^[1-9][0-9]*$ ]] || fail "--deadline needs seconds" 2; DEADLINE=$2; shift 2 ;;
        --work) [[ -n ${2:-} ]] || fail "--work needs a folder" 2; WORK=$2; shift 2 ;;
        --kit) [[ -n ${2:-} ]] || fail "--kit needs a folder" 2; KIT=$(cd "$2" 2>/dev/null && pwd) ||
                   fail "--kit $2: no such folder" 2; shift 2 ;;
        -h|--help) sed -n '2,/^set -uo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
        -*) fail "unknown option '$1' (see --help)" 2 ;;
        *) [[ -z $OUTDIR ]] || fail "one OUTDIR only, got '$OUTDIR' and '$1'" 2; OUTDIR=$1; shift ;;
    esac
done
[[ -n $OUTDIR ]] || fail "usage: gpu_check.sh OUTDIR [options] (see --help)" 2
# A copy that lost its modes on the way (run it as `bash gpu_check.sh`) gets them back.
[[ -x $KIT/bin/whitted || ! -f $KIT/bin/whitted ]] || chmod u+x "$KIT"/bin/* "$KIT/whitted" 2>/dev/null
[[ -x $KIT/bin/whitted && -f $KIT/KIT.json ]] ||
    fail "$KIT is not a GPU kit: run the gpu_check.sh inside one (tools/gpu_kit.sh builds it) or pass --kit" 2
mkdir -p "$OUTDIR" || fail "cannot create $OUTDIR"
OUTDIR=$(cd "$OUTDIR" && pwd)
REMOVE_WORK=0
if [[ -z $WORK ]]; then
    WORK=$(mktemp -d "${TMPDIR:-/tmp}/gpu-check.XXXXXX") || fail "cannot create a working folder"
    REMOVE_WORK=1
fi
mkdir -p "$WORK/images" "$WORK/bench" "$WORK/cache" || fail "cannot create $WORK"
# Everything printed also goes into check.log; at the end tee is waited for, so the log is complete on exit.
exec > >(tee "$OUTDIR/check.log") 2>&1
TEE=$!
finish() {
    exec >&- 2>&-
    wait "$TEE" 2>/dev/null
    [[ $REMOVE_WORK == 0 ]] || rm -rf "$WORK"
}
trap finish EXIT

# ---- The environment: the kit's libraries, the machine's Vulkan driver ----
kit=$KIT
. "$KIT/kit_env.sh"  # LD_LIBRARY_PATH: the kit's libraries, its libstdc++ where this glibc can load it
export XDG_CACHE_HOME=$WORK/cache  # whitted's pipeline cache and the driver's shader cache start empty
WHITTED=$KIT/bin/whitted
TOOL=$KIT/bin/whitted_kit
nvidia_icd=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json  # where the lent machines keep it
if [[ -z ${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-} ]] &&
   ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json /usr/local/share/vulkan/icd.d/*.json \
        >/dev/null 2>&1 && [[ -f $nvidia_icd ]]; then
    export VK_DRIVER_FILES=$nvidia_icd
fi
kit_value() { grep -o "\"$1\": *[^,}]*" "$KIT/KIT.json" | head -1 | sed 's/^[^:]*: *//; s/^"//; s/"$//'; }
WIDTH=$(kit_value scene_width)
HEIGHT=$(kit_value scene_height)
TRIANGLES=$(kit_value mesh_triangles)

START=${EPOCHREALTIME/./}
elapsed_ms() { echo $(( (${EPOCHREALTIME/./} - START) / 1000 )); }
seconds() { printf '%d.%03d' $(($1 / 1000)) $(($1 % 1000)); }  # milliseconds as seconds
number() { [[ $2 =~ ^-?[0-9] ]] && printf "$1" "$2" || printf '%s' "${2:-?}"; }  # number FORMAT VALUE, for people
json_string() {  # a JSON string of $1
    local s=${1//\\/\\\\}
    s=${s//\"/\\\"}; s=${s//$'\n'/\\n}; s=${s//$'\t'/\\t}; s=${s//$'\r'/}
    printf '"%s"' "$s"
}
json_field() {  # json_field JSON KEY: a number or null of a flat JSON object whitted_kit printed
    [[ $1 =~ \"$2\":(-?[0-9][0-9.eE+-]*|null) ]] && echo "${BASH_REMATCH[1]}"
}
FAILURES=()
failure() { FAILURES+=("$1"); echo "FAILED: $1"; }
out_of_time() { (( $(elapsed_ms) > DEADLINE * 1000 )); }
SKIPPED=0

# run_whitted LOG ARGS...: whitted render ARGS -q, its output into LOG; sets STATUS and WALL_MS. A render is
# stopped (status 124) a minute past the deadline, so that the check ends within about --deadline + 60 s.
run_whitted() {
    local log=$1 t0 limit=$((DEADLINE + 60 - $(elapsed_ms) / 1000))
    shift
    ((limit >= 10)) || limit=10
    t0=${EPOCHREALTIME/./}
    timeout "$limit" "$WHITTED" render "$@" -q >"$log" 2>&1
    STATUS=$?
    WALL_MS=$(( (${EPOCHREALTIME/./} - t0) / 1000 ))
}

echo "== gpu_check.sh: kit $KIT ($(kit_value commit)), references by $(kit_value reference_driver)"
echo "== $(uname -srm), glibc ${kit_glibc:-?} (the kit needs $kit_glibc_needed, $kit_glibc_needed_cxx with its" \
     "libstdc++); LD_LIBRARY_PATH=$LD_LIBRARY_PATH"
echo "== VK_DRIVER_FILES=${VK_DRIVER_FILES:-${VK_ICD_FILENAMES:-(not set: the loader searches)}}"
command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader

# ---- 1. whitted devices ----
"$WHITTED" devices >"$OUTDIR/devices.txt" 2>&1
devices_status=$?
cat "$OUTDIR/devices.txt"
[[ $devices_status == 0 ]] || failure "whitted devices exited with $devices_status"

# ---- The trace paths: bvh always; rayquery where the device has ray queries ----
PATHS=(bvh)
run_whitted "$WORK/probe.log" "$KIT/scenes/room.xml" -o "$WORK/probe.png" --width 8 --height 6 --aov none \
    --trace rayquery
rayquery_note="offered"
if [[ $STATUS == 0 ]]; then
    PATHS+=(rayquery)
elif grep -q "lacks VK_KHR_ray_query" "$WORK/probe.log"; then
    rayquery_note="not offered: $(tail -1 "$WORK/probe.log")"
else
    PATHS+=(rayquery)  # offered but failing: its renders below fail and say why
    rayquery_note="probe failed (exit $STATUS): $(tail -1 "$WORK/probe.log")"
fi
echo "== trace paths: ${PATHS[*]} (ray queries: $rayquery_note)"

# ---- 2. Every scene against its reference ----
SCENES_JSON=()
printf '%-22s %-9s %10s %9s %10s %s\n' scene trace "PSNR dB" "wall s" "render s" "Mrays/s"
for path in "${PATHS[@]}"; do
    for scene in "$KIT"/scenes/*.xml; do
        name=$(basename "$scene" .xml)
        image=$WORK/images/$name.$path.png
        reference=$KIT/references/$name.$path.png
        if out_of_time; then SKIPPED=$((SKIPPED + 1)); continue; fi
        run_whitted "$WORK/images/$name.$path.log" "$scene" -o "$image" --width "$WIDTH" --height "$HEIGHT" \
            --aov none --trace "$path"
        entry="\"scene\": $(json_string "$name"), \"trace\": \"$path\", \"exit\": $STATUS, \"wall_s\": $(seconds $WALL_MS)"
        if [[ $STATUS != 0 ]]; then
            failure "$name ($path): whitted exited with $STATUS: $(tail -1 "$WORK/images/$name.$path.log")"
            SCENES_JSON+=("{$entry, \"output\": $(json_string "$(tail -5 "$WORK/images/$name.$path.log")")}")
            continue
        fi
        measure=$("$TOOL" measure "${image%.png}.json") || failure "$name ($path): its record could not be read"
        psnr=$("$TOOL" psnr "$image" "$reference" --diff "$WORK/images/$name.$path.diff.png") ||
            failure "$name ($path): no PSNR against $reference"
        db=$(json_field "$psnr" psnr_db)
        if [[ $db != null && -n $db ]] && (( ${db%%.*} < MIN_PSNR )); then
            failure "$name ($path): $db dB from its reference, under $MIN_PSNR dB"
        fi
        [[ $(json_field "$measure" lost_samples) == 0 ]] || failure "$name ($path): camera samples lost"
        reference_measure=$("$TOOL" measure "${reference%.png}.json" 2>/dev/null || echo null)
        SCENES_JSON+=("{$entry, \"psnr\": ${psnr:-null}, \"measures\": ${measure:-null}, \"reference_measures\": $reference_measure}")
        [[ $db == null ]] && db=identical
        printf '%-22s %-9s %10s %9s %10s %s\n' "$name" "$path" "$(number %.2f "$db")" "$(seconds $WALL_MS)" \
            "$(number %.4f "$(json_field "$measure" render_s)")" "$(number %.2f "$(json_field "$measure" mrays_per_s)")"
        DEVICE_TYPE=$(grep -o '"device_type":"[^"]*"' <<<"$measure" | cut -d'"' -f4)
    done
done
if [[ ${DEVICE_TYPE:-} == cpu && $ALLOW_CPU == 0 ]]; then
    failure "whitted rendered on a CPU device (lavapipe?), not a GPU: pass --allow-cpu to accept that"
fi

# ---- 3. The benchmark's GPU part ----
BENCH_JSON=()
mesh_note="not made"
if out_of_time; then
    SKIPPED=$((SKIPPED + 1))
else
    t0=${EPOCHREALTIME/./}
    cp "$KIT/bench/mesh1m.xml" "$WORK/bench/mesh1m.xml" || failure "the kit has no bench/mesh1m.xml"
    if "$TOOL" mesh-obj "$TRIANGLES" "$WORK/bench/mesh1m.obj"; then
        if ! command -v sha256sum >/dev/null; then
            mesh_note="written; sha256sum missing here, not checked"
        elif (cd "$WORK/bench" && sha256sum --quiet -c "$KIT/bench/mesh1m.obj.sha256"); then
            mesh_note="written and identical to tools/generate_scenes.py's (SHA-256)"
        else
            failure "the mesh whitted_kit wrote differs from tools/generate_scenes.py's (SHA-256)"
            mesh_note="differs from tools/generate_scenes.py's"
        fi
    else
        failure "whitted_kit mesh-obj failed"
    fi
    echo "== mesh1m: $mesh_note ($(( (${EPOCHREALTIME/./} - t0) / 1000 )) ms)"
fi
scale=1
[[ $QUICK == 1 ]] && scale=4
# name scene width height spp measure (the benchmark's: all rays, or camera plus shadow rays)
PARTS=("mesh1m_small $WORK/bench/mesh1m.xml 640 480 1 primary_shadow_mrays_per_s"
       "mesh1m_full $WORK/bench/mesh1m.xml 1920 1080 16 primary_shadow_mrays_per_s"
       "room_full_1spp $KIT/scenes/room.xml 1920 1080 1 mrays_per_s"
       "room_full_16spp $KIT/scenes/room.xml 1920 1080 16 mrays_per_s")
printf '%-16s %-9s %11s %4s %12s %s\n' part trace size spp "render s" "Mrays/s (median)"
for path in "${PATHS[@]}"; do
    for part in "${PARTS[@]}"; do
        read -r name scene width height spp key <<<"$part"
        width=$((width / scale)); height=$((height / scale))
        [[ -f $scene ]] || continue
        records=()
        for ((k = 1; k <= REPEATS; ++k)); do
            if out_of_time; then SKIPPED=$((SKIPPED + 1)); break; fi
            image=$WORK/bench/$name.$path.$k.png
            run_whitted "$WORK/bench/$name.$path.$k.log" "$scene" -o "$image" --width "$width" --height "$height" \
                --aa uniform --spp "$spp" --max-depth 6 --aov none --trace "$path"
            if [[ $STATUS != 0 ]]; then
                failure "$name ($path): whitted exited with $STATUS: $(tail -1 "$WORK/bench/$name.$path.$k.log")"
                break
            fi
            records+=("${image%.png}.json")
        done
        [[ ${#records[@]} -gt 0 ]] || continue
        measure=$("$TOOL" measure "${records[@]}") || { failure "$name ($path): records unread"; continue; }
        [[ ${#records[@]} == 1 ]] && measure="{\"runs\":[$measure],\"median\":$measure}"
        median=${measure##*\"median\":}
        BENCH_JSON+=("{\"part\": \"$name\", \"trace\": \"$path\", \"width\": $width, \"height\": $height, \"spp\": $spp, \"max_depth\": 6, \"measure\": \"$key\", \"result\": $measure}")
        printf '%-16s %-9s %11s %4s %12s %s\n' "$name" "$path" "${width}x$height" "$spp" \
            "$(number %.4f "$(json_field "$median" render_s)")" \
            "$(number %.2f "$(json_field "$median" "$key")") ($key, ${#records[@]} runs)"
    done
done

# ---- Results ----
join() { local IFS=,; echo "$*"; }
failures_json=()
for f in "${FAILURES[@]}"; do failures_json+=("$(json_string "$f")"); done
paths_json=()
for path in "${PATHS[@]}"; do paths_json+=("\"$path\""); done
ok=true
[[ ${#FAILURES[@]} == 0 && $SKIPPED == 0 ]] || ok=false
[[ $SKIPPED == 0 ]] || failures_json+=("$(json_string "$SKIPPED steps skipped: past the deadline of $DEADLINE s")")
cat > "$OUTDIR/check.json" <<EOF
{
  "ok": $ok,
  "failures": [$(join "${failures_json[@]}")],
  "elapsed_s": $(( $(elapsed_ms) / 1000 )),
  "finished": "$(date -u +%Y-%m-%dT%H:%M:%SZ)",
  "machine": $(json_string "$(uname -srm)"),
  "gpu": $(json_string "$(command -v nvidia-smi >/dev/null && nvidia-smi --query-gpu=name,driver_version --format=csv,noheader)"),
  "devices": $(json_string "$(cat "$OUTDIR/devices.txt")"),
  "trace_paths": [$(join "${paths_json[@]}")],
  "ray_queries": $(json_string "$rayquery_note"),
  "quick": $([[ $QUICK == 1 ]] && echo true || echo false),
  "repeats": $REPEATS,
  "min_psnr_db": $MIN_PSNR,
  "mesh": $(json_string "$mesh_note"),
  "kit": $(cat "$KIT/KIT.json"),
  "scenes": [$(join "${SCENES_JSON[@]}")],
  "bench": [$(join "${BENCH_JSON[@]}")]
}
EOF
if command -v tar >/dev/null; then
    tar -C "$WORK" -cf "$OUTDIR/images.tar" images
else
    rm -rf "$OUTDIR/images" && cp -r "$WORK/images" "$OUTDIR/images"
fi
echo "== $OUTDIR/check.json: ok $ok, ${#FAILURES[@]} failures, $SKIPPED skipped, $(( $(elapsed_ms) / 1000 )) s"
[[ $ok == true ]]
