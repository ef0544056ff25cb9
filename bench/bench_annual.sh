#!/usr/bin/env bash
# The annual study's cost, timed end to end as vr-render runs it: a 4 x 4 x
# 3 m room with a 2 x 1.2 m soda-lime pane facing south, a 3 x 3 work-plane
# grid and an eye-level view sensor, the Chicago year (tests/data/weather),
# for the plain study (8-18 h), with EN 17037 (daylight hours and one
# overcast render more), with Daysim's occupancy file, and with an IGSDB
# roller shade drawn by the LM-83 rule (twice the coefficient renders).
# Prints per case the renders, the seconds vr-render reports for the study
# and the wall-clock seconds of the whole run, for docs/benchmarks.md
# ("Annual studies").
#
# Usage: bench/bench_annual.sh [BUILD-DIR] [SENSOR-SAMPLES]   (default: build, 1024)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
samples=${2:-1024}
bin=$build/render/vr-render
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export VR_MATDB=$work/materials.db
source "$root/tests/cli/room_shell.sh"
scene() { # FILE ANNUAL-OPTIONS
  cat > "$1" <<EOS
material pane db:soda-lime-glass thickness=6mm
material roller bsdf file=$root/tests/data/bsdf/cgdb_14060_urban_loft_river_stone.xml.gz
$(room_shell)
rect center=2,0,1.5 normal=0,1,0 size=2,1.2 material=pane
light sun spectrum=D65
sky perez weather=$root/tests/data/weather/chicago.wea
sensor plane grid origin=0.5,0.5,0.8 u=3,0,0 v=0,3,0 n=3,3 normal=0,0,1
sensor eye point position=2,2.5,1.2 normal=0,-1,0
annual $2 workplane=plane
render sensor_samples=$samples seed=1
EOS
}
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')"
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-34s %8s %10s %10s\n' case renders study_s wall_s
run_case() { # NAME ANNUAL-OPTIONS
  scene "$work/s.scn" "$2"
  local t0 t1 out
  t0=$(date +%s.%N)
  out=$("$bin" "$work/s.scn" -o "$work/out" --threads 2 2> /dev/null)
  t1=$(date +%s.%N)
  local line renders secs
  line=$(printf '%s\n' "$out" | grep '^annual   [0-9]* records')
  renders=$(printf '%s\n' "$line" | sed 's/.* \([0-9]*\) renders.*/\1/')
  secs=$(printf '%s\n' "$line" | sed 's/.* renders, \([0-9.]*\) s.*/\1/')
  printf '%-34s %8s %10s %10.1f\n' "$1" "$renders" "$secs" "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')"
}
run_case "hours=8,18" "hours=8,18"
run_case "hours=8,18 en17037=yes" "hours=8,18 en17037=yes"
run_case "occupancy=Daysim 8to6withDST" "occupancy=$root/tests/data/occupancy/8to6withDST.60min.occ.csv"
run_case "shade=roller window=pane" "shade=roller window=pane"
run_case "shade + en17037" "shade=roller window=pane en17037=yes"
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)"
