#!/usr/bin/env bash
# Adaptive sampling (--target-error, --time-limit) against a fixed number of
# samples a pixel, on the sample room (samples/room.scn, photon mapping as
# the main job renders it) at 160 x 120 pixels: each run is a whole
# vr-render, timed end to end, its image's luminance error measured against
# a reference of 1024 samples a pixel (vr-test-exr-compare --error: per
# pixel |Y - Y_ref| / max(Y_ref, 1 % of the mean), root mean square and 95th
# percentile).  The reference's own noise (1024 samples) is sqrt(64 / 1024)
# = 25 % of a 64-sample image's (3 % more in quadrature), 12.5 % of a
# 16-sample one's, 50 % of a 256-sample one's; the adaptive runs stop at
# 256 samples a pixel, a quarter of the reference's.  Every run has the
# scene's seed and photon count, so all share the reference's photon maps:
# this measures the camera's noise, not the maps'.  "Equal time" sets the
# limit to the fixed 64-sample run's whole-process seconds, while the limit
# counts from the render's start (after the scene is read).  Prints the
# table of docs/benchmarks.md, "Adaptive sampling".
#
# Usage: bench/bench_adaptive.sh [BUILD-DIR] [DB]   (default: build, out/materials.db)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
db=${2:-$root/out/materials.db}
[ -f "$db" ] || { echo "bench_adaptive: no $db: run scripts/main-job.sh first" >&2; exit 1; }
bin=$build/render/vr-render
cmp=$build/tests/vr-test-exr-compare
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
scene=$root/samples/room.scn
common=(--db "$db" --resolution 160x120 --threads 2 --outputs exr --cache "$work/cache" --quiet)

# run NAME OPTIONS...: one render, its wall-clock seconds and mean spp.
run() {
  local name=$1; shift
  local t0 t1
  t0=$(date +%s.%N)
  "$bin" "$scene" "${common[@]}" -o "$work/$name" --stats "$work/$name.json" "$@"
  t1=$(date +%s.%N)
  local spp
  spp=$(python3 -c 'import json, sys
a = json.load(open(sys.argv[1]))["image"]["adaptive"]
print("%.1f" % a["spp_mean"] if a else "-")' "$work/$name.json")
  local err
  err=$("$cmp" --error "$work/ref.exr" "$work/$name.exr" 2> /dev/null | grep '^rms_rel' ||
        echo "rms_rel - p95_rel -")
  last_seconds=$(echo "$t1 - $t0" | bc)
  printf '| %-28s | %7.1f | %8s | %s |\n' "$name $*" "$last_seconds" "$spp" \
    "$(echo "$err" | awk '{ printf "%.4f | %.4f", $2, $4 }')"
}

echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "reference: 1024 samples a pixel"
t0=$(date +%s.%N)
"$bin" "$scene" "${common[@]}" -o "$work/ref" --spp 1024
echo "  $(echo "$(date +%s.%N) - $t0" | bc) s"
echo
echo "| run | seconds | mean spp | rms relative error | 95th percentile |"
echo "|---|---|---|---|---|"
last_seconds=0
for spp in 16 64 256; do
  run "fixed" --spp "$spp"
  [ "$spp" = 64 ] && t64=$last_seconds
done
for e in 0.1 0.05 0.02; do run "adaptive" --target-error "$e" --max-spp 256; done
# Equal time with the fixed 64 samples: its seconds as the limit.
run "time-limited" --time-limit "$t64" --max-spp 256
run "time-limited" --time-limit "$t64" --spp 4 --max-spp 256
run "time-limited" --time-limit "$t64" --spp 4 --target-error 0.05 --max-spp 256
