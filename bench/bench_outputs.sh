#!/usr/bin/env bash
# vr-render's start-up and outputs: the Cornell box (bench/cornell_path.scn)
# path-traced at 64 x 64 pixels, 1 sample a pixel, whole runs timed by
# hyperfine for --outputs exr, spectral, png and all the files, and the
# number of shared libraries vr-render loads at start (ldd).  Prints the
# figures of docs/benchmarks.md, "vr-render: start-up and outputs".
#
# Usage: bench/bench_outputs.sh [BUILD-DIR] [RUNS]   (default: build, 20)
# Needs hyperfine (scripts/install-deps.sh installs it).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
runs=${2:-20}
command -v hyperfine > /dev/null || { echo "bench_outputs: needs hyperfine (apt-get install hyperfine)" >&2; exit 1; }
bin=$build/render/vr-render
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export VR_MATDB=$work/materials.db
for c in white red green; do
  "$build/matdb/vr-matdb" import "$root/samples/cornell/cornell_$c.csv" --name "cornell-$c" \
    --kind reflectance > /dev/null
done
"$build/matdb/vr-matdb" import "$root/samples/cornell/cornell_light.csv" --name cornell-light \
  --kind illuminant > /dev/null

echo "vr-render loads $(ldd "$bin" | wc -l) shared libraries at start ($(ldd "$bin" | grep -c opencv) of OpenCV)"
echo "load average before the runs: $(cut -d' ' -f1-3 /proc/loadavg)"
run="$bin $root/bench/cornell_path.scn --resolution 64x64 --spp 1 --threads 2 --cache $work/cache --quiet"
$run -o "$work/warm" # builds the geometry cache, fills the page cache
hyperfine -N --warmup 3 --runs "$runs" --style basic --export-markdown "$work/table.md" \
  -n "outputs exr" "$run -o $work/e --outputs exr" \
  -n "outputs spectral" "$run -o $work/s --outputs spectral" \
  -n "outputs png" "$run -o $work/p --outputs png" \
  -n "all four (the default)" "$run -o $work/a"
cat "$work/table.md"
echo "load average after the runs: $(cut -d' ' -f1-3 /proc/loadavg)"
