#!/usr/bin/env bash
# Textures at 20 million triangles under a memory budget (issue 32): the
# vr-hotel floor (24 rooms, detail 100) whose furniture carries its wood and
# fabric textures, rendered from the middle room on 16 sub-domains under a
# budget, and again with the two textured materials as plain lambert
# reflectors; prints the camera pass's time, the texture memory, the loads
# and the peak resident memory of each.  Run after the main job (its
# database holds the room materials).
#
# Usage: bench/bench_hotel_textures.sh DB [BUILD_DIR] [HOTEL_DIR] [BUDGET] [SPP]
set -euo pipefail
db=${1:?usage: bench_hotel_textures.sh DB [BUILD_DIR] [HOTEL_DIR] [BUDGET] [SPP]}
build=${2:-build}
dir=${3:-$build/bench-hotel-textures}
budget=${4:-605M}
spp=${5:-4}
bin="$(cd "$build" && pwd)/render/vr-render"
[ -s "$dir/hotel.scn" ] || "$build/samples/hotel/vr-hotel" "$dir" > /dev/null
cd "$dir"
sed -e 's|^material wood .*|material wood     lambert reflectance=0.45|' \
    -e 's|^material fabric .*|material fabric   lambert reflectance=0.55|' hotel.scn > hotel_plain.scn
common=(--db "$db" --threads "$(nproc)" --subdomains 16 --memory-budget "$budget" --spp "$spp"
        --outputs exr --cache cache)
"$bin" hotel_plain.scn -o warm "${common[@]}" --resolution 8x6 > /dev/null 2>&1 # the cache, once
run() {
  "$bin" "$1" -o "$2" "${common[@]}" > "$2.out" 2> "$2.err"
  local cam tex rss loads
  cam=$(awk '$1 == "pass" && $2 == "camera" {print $3}' "$2.out")
  tex=$(awk '$1 == "textures" {print $3}' "$2.out")
  loads=$(sed -n 's/.*; \([0-9]*\) loads, \([0-9]*\) unloads.*/\1\/\2/p' "$2.out")
  rss=$(sed -n 's/.*peak memory \([0-9.]*\) MiB.*/\1/p' "$2.out")
  echo "${cam:-?} ${tex:-0} ${loads:-?} ${rss:-?}"
}
read -r tc tt tl tr <<< "$(run hotel.scn tex)"
read -r pc pt pl pr <<< "$(run hotel_plain.scn plain)"
echo "hotel floor: $(sed -n 's/.*scene: [0-9]* objects, \([0-9]*\) triangles.*/\1/p' tex.err) triangles, 16 sub-domains, budget $budget, $spp spp at 320x240, $(nproc) threads"
printf "%-11s %11s %14s %14s %10s\n" run "camera (s)" "textures MiB" "loads/unloads" "peak MiB"
printf "%-11s %11s %14s %14s %10s\n" textured "$tc" "$tt" "$tl" "$tr"
printf "%-11s %11s %14s %14s %10s\n" plain "$pc" "$pt" "$pl" "$pr"
awk -v a="$tc" -v b="$pc" 'BEGIN { printf "camera pass textured / plain: %.2fx\n", a / b }'
