#!/usr/bin/env bash
# Annual glare at a view (annual glare_views=) against direct renders of
# single hours: the 4 x 4 x 3 m office of samples/annual with its 2 x 1.2 m
# south window left open, an eye at (2, 3, 1.2) looking at the window, the
# Chicago year (tests/data/weather/chicago.wea), 8-18 h.
#   1. the annual study with the view (64 x 64 fisheye coefficients, 16
#      paths a pixel; 2048 sensor paths), timed;
#   2. eight of its hours, chosen across the range of its DGP, each rendered
#      directly (sky perez weather= date= time=) through a 256 x 256 angular
#      fisheye at the eye, 64 paths a pixel, the path integrator: vr-render's
#      own DGP of that image and, when EVALGLARE is given, evalglare's DGP
#      of its Radiance picture (-d, default source detection).
# Prints one line per hour (the weather file's line, date and time, E_v and
# DGP by the coefficients, by the direct render, by evalglare) and the
# seconds, for docs/vr-render.md.
#
# Usage: bench/bench_annual_glare.sh [BUILD-DIR] [EVALGLARE]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
evalglare=${2:-}
bin="$build/render/vr-render"
wea="$root/tests/data/weather/chicago.wea"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

shell() {
  grep -v '^#' "$root/samples/annual/office_ec.scn" |
    grep -v -e '^material window' -e 'material=window' -e '^sky ' -e '^annual' -e '^sensor' -e '^render' -e '^light'
}
{
  shell
  echo "light sun spectrum=D65"
  echo "sky perez weather=$wea ground=0.2"
  echo "sensor eye point position=2,3,1.2 normal=0,-1,0"
  echo "annual glare_views=eye glare_resolution=64"
  echo "render sensor_samples=2048 spp=16"
} > "$tmp/year.scn"
t0=$(date +%s.%N)
"$bin" "$tmp/year.scn" -o "$tmp/year" --threads 2 -q
t1=$(date +%s.%N)
year_s=$(echo "$t1 - $t0" | bc -l)
hours=$(($(wc -l < "$tmp/year.annual-hourly.csv") - 1))
printf 'annual study: %d occupied hours, %.1f s (coefficients and the year)\n' "$hours" "$year_s"

# Eight hours with daylight, at evenly spaced ranks of their DGP.
python3 - "$tmp/year.annual-hourly.csv" > "$tmp/picked" <<'EOF'
import csv, sys
rows = list(csv.reader(open(sys.argv[1])))
h = rows[0]
ie, idg = h.index('eye(0;0)'), h.index('dgp:eye')
data = sorted((float(r[idg]), int(r[0]), float(r[ie])) for r in rows[1:] if float(r[ie]) > 50)
n = len(data)
for q in (0.05, 0.2, 0.4, 0.6, 0.75, 0.9, 0.97, 1.0):
    d = data[min(n - 1, int(q * n))]
    print(d[1], d[0], d[2])
EOF

printf '%-6s %-11s %10s %8s %10s %8s %10s %9s\n' line "date time" "E_v coef" "DGP coef" "E_v render" "DGP" "evalglare" "render s"
total=0
while read -r line dgp ev; do
  read -r m d h _ < <(sed -n "${line}p" "$wea")
  hh=$(python3 -c "h=$h; print('%02d:%02d' % (int(h), round((h - int(h)) * 60)))")
  date=$(printf '%02d-%02d' "$m" "$d")
  {
    shell
    echo "light sun spectrum=D65"
    echo "sky perez weather=$wea date=$date time=$hh ground=0.2"
    echo "camera fisheye from=2,3,1.2 to=2,2,1.2 resolution=256x256 projection=angular"
    echo "render integrator=path spp=64"
  } > "$tmp/hour.scn"
  t0=$(date +%s.%N)
  "$bin" "$tmp/hour.scn" -o "$tmp/hour" --threads 2 --outputs hdr -q --json > "$tmp/hour.json"
  t1=$(date +%s.%N)
  s=$(echo "$t1 - $t0" | bc -l)
  total=$(echo "$total + $s" | bc -l)
  read -r rev rdgp < <(python3 -c "
import json; g = json.load(open('$tmp/hour.json'))['glare']
print(g['vertical_illuminance_lx'], g['dgp'])")
  eg="-"
  if [ -n "$evalglare" ]; then
    eg=$("$evalglare" -d "$tmp/hour.hdr" 2> /dev/null | awk '/^dgp/ || /^DGP/ {print $2; exit}')
    [ -n "$eg" ] || eg=$("$evalglare" "$tmp/hour.hdr" 2> /dev/null | awk '{print $2; exit}')
  fi
  printf '%-6s %-11s %10.0f %8.4f %10.0f %8.4f %10s %9.1f\n' "$line" "$date $hh" "$ev" "$dgp" "$rev" "$rdgp" "$eg" "$s"
done < "$tmp/picked"
printf 'direct renders: %.1f s for 8 hours, %.2f s an hour (%.0f s for the %d hours)\n' \
  "$total" "$(echo "$total / 8" | bc -l)" "$(echo "$total / 8 * $hours" | bc -l)" "$hours"
