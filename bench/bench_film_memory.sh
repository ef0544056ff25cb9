#!/usr/bin/env bash
# The film's memory at 4K: the sample room (samples/room.scn) rendered at
# 3840 x 2160, 1 sample a pixel, 20 000 photons, by one process and by two
# ranks (mpirun --oversubscribe), with all outputs (the spectral EXR among
# them) and with --outputs exr,png; two ranks also under a memory budget.
# Prints, per run, the film's sums per process (stats memory.film_bytes),
# each rank's peak resident memory when its render ended (stats
# ranks[].peak_rss_bytes: before the outputs), and rank 0's peak over the
# whole run, outputs written (stats peak_rss_bytes, taken as the last file
# of the set is written), for docs/ddm.md "The film".
#
# Usage: bench/bench_film_memory.sh DB [BUILD-DIR] [BUDGET]
#   DB: the main job's database (out/materials.db); BUILD-DIR default build;
#   BUDGET default 400M.  Run it on an older build to compare.
set -uo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
db=$(realpath "$1")
build=$(cd "${2:-$root/build}" && pwd)
budget=${3:-400M}
bin=$build/render/vr-render
# Open MPI refuses root unless told (a container's only user is root).
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
common=(--db "$db" --resolution 3840x2160 --spp 1 --photons 20000 --threads 1 --quiet)
echo "build: $build ($(git -C "$build" rev-parse --short HEAD 2>/dev/null || echo '?')), $(nproc) cores, load $(cut -d' ' -f1-3 /proc/loadavg)"
# The geometry caches the runs use (one folder per sub-domain count), built
# before any run is measured.
for warm in "--cache $work/cache" "--cache $work/cache --subdomains 8" "--cache $work/cache8 --subdomains 8"; do
  # shellcheck disable=SC2086
  "$bin" "$root/samples/room.scn" --db "$db" --resolution 16x16 --spp 1 --photons 1000 --quiet \
    $warm -o "$work/warm" --outputs exr || { echo "bench_film_memory: the warm-up render failed" >&2; exit 1; }
done
printf '| run | outputs | film sums a process | peak at the end of the render, each rank | peak of rank 0 with its outputs | wall |\n|---|---|---|---|---|---|\n'
run() { # label, outputs label, command...
  local label=$1 outs=$2
  shift 2
  local t0=$(date +%s.%N) rc
  "$@" > "$work/log" 2>&1; rc=$?
  local t=$(echo "$(date +%s.%N) - $t0" | bc)
  if [ $rc -ne 0 ]; then
    printf '| %s | %s | refused or failed (exit %d): %s | | | %.1f s |\n' "$label" "$outs" "$rc" \
      "$(grep -m1 -o 'memory budget[^:]*is too small\|[^:]*out of memory' "$work/log" | head -c 120)" "$t"
    return
  fi
  python3 - "$work/s.json" "$label" "$outs" "$t" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
m = d["memory"]
film = m.get("film_bytes")
film = "%.0f MiB" % (film / 2**20) if film is not None else "(not reported)"
ranks = d.get("ranks") or []
rss = " / ".join("%.0f" % (r["peak_rss_bytes"] / 2**20) for r in ranks) if ranks else "(not reported)"
print("| %s | %s | %s | %s MiB | %.0f MiB | %.1f s |" % (sys.argv[2], sys.argv[3], film, rss,
      d["peak_rss_bytes"] / 2**20, float(sys.argv[4])))
PY
}
scn=$root/samples/room.scn
for outs in all exr,png; do
  o=(); [ "$outs" = all ] || o=(--outputs "$outs")
  run "1 process" "$outs" "$bin" "$scn" "${common[@]}" --cache "$work/cache" -o "$work/a" "${o[@]}" --stats "$work/s.json"
  run "2 ranks" "$outs" mpirun --oversubscribe -np 2 "$bin" "$scn" "${common[@]}" --cache "$work/cache" \
    --subdomains 8 -o "$work/b" "${o[@]}" --stats "$work/s.json"
  run "2 ranks, budget $budget" "$outs" mpirun --oversubscribe -np 2 "$bin" "$scn" "${common[@]}" \
    --cache "$work/cache8" --subdomains 8 --memory-budget "$budget" -o "$work/c" "${o[@]}" --stats "$work/s.json"
done
