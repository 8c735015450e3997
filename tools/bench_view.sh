#!/usr/bin/env bash
# Frame times of the live window: opens SCENE under Xvfb, traces until every
# pixel has SPP samples, closes, and prints the window's own summary (frames
# that traced, mean frame and tracing milliseconds, the longest frame),
# then `whitted render` of the same work for the tracing throughput.
#   tools/bench_view.sh [SCENE] [SPP] [FRAME_MS]
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/room.xml}
spp=${2:-4}
frame_ms=${3:-40}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
printf 'spp %s\nquit\n' "$spp" > "$work/script.txt"
start=$(date +%s%N)
xvfb-run -a -s '-screen 0 1024x768x24' build/whitted view "$scene" --spp "$spp" --frame-ms "$frame_ms" \
  --script "$work/script.txt" | tail -1
echo "view: $(( ($(date +%s%N) - start) / 1000000 )) ms in all (window start included)"
build/whitted render "$scene" --aa uniform --spp "$spp" -o "$work/render.png" 2>&1 | tail -1
