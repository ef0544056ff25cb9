#!/usr/bin/env bash
# Command-line test: --memory-budget bounds the resident memory a process
# (and each MPI rank) adds while it renders, not only the bytes it counts
# (docs/ddm.md, "The memory budget").  A small hotel floor from vr-hotel
# (4 rooms, 65 MiB of cells at S = 8) is rendered without a budget and
# under a third of its cells; the peak resident memory read by the kernel
# (getrusage, in --stats) may pass the resident memory at the start of the
# render by at most the budget plus the stated allowance of 16 MiB
# (VR_FLOW_RSS_ALLOWANCE), and the image is the unbudgeted one.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
source "$(dirname "$0")/harness.sh"
# Under AddressSanitizer the process's resident memory is not the
# program's: shadow memory (an eighth of every mapping), red zones around
# each block and the quarantine of freed blocks.  A bound on the kernel's
# figure means nothing there (the CI's sanitizer machine held 12 MiB more
# than the allowance with the quarantine off), so the test is skipped (77);
# the budget's correctness under the sanitizer is test_render_ddm's.
if [ -n "${ASAN_OPTIONS:-}" ]; then
  echo "skipped: resident memory under AddressSanitizer is not the program's"
  exit 77
fi

"$VR_HOTEL" --rooms 4 --detail 40 "$tmp/hotel" > /dev/null
check "vr-hotel writes a small floor" test -f "$tmp/hotel/hotel.scn"
# Its materials come from the main job's database; plain grey here.
sed -E -i 's/^(material [^ ]+) .*/\1 lambert reflectance=0.5/' "$tmp/hotel/hotel.scn"
run() { (cd "$tmp/hotel" && "$@" hotel.scn --subdomains 8 --threads 2 --resolution 64x48 --spp 2 --quiet); }

run "$bin" -o free --stats free.json
check "renders without a budget" test $? -eq 0
budget=$(python3 -c "
import json; s = json.load(open('$tmp/hotel/free.json'))
print(s['memory']['peak_cells_bytes'] // 3)")
run "$bin" --memory-budget "$budget" -o tight --stats tight.json
check "renders under a third of its cells ($budget bytes)" test $? -eq 0
"$cmp" "$tmp/hotel/free.exr" "$tmp/hotel/tight.exr" > "$tmp/cmp.txt"; rc=$?
check "under the budget: the same image" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/cmp.txt"
python3 - "$tmp/hotel" <<'PY'
import json, sys
d = sys.argv[1]
free, tight = json.load(open(d + "/free.json")), json.load(open(d + "/tight.json"))
m = tight["memory"]
b, start, allow = m["budget_bytes"], m["rss_start_bytes"], 16 << 20
added = tight["peak_rss_bytes"] - start
print("# budget %.1f MiB: resident memory grew by %.1f MiB (%.1f MiB uncounted at most); "
      "without a budget by %.1f MiB" % (b / 2**20, added / 2**20, m["peak_uncounted_bytes"] / 2**20,
      (free["peak_rss_bytes"] - start) / 2**20), file=sys.stderr)
assert start > 0 and tight["subdomains"]["unloads"] > 0, (m, tight["subdomains"])
assert added <= b + allow, (added, b)
# the bound is not slack: without the budget the process grows past it
assert free["peak_rss_bytes"] - start > b + allow, (free["peak_rss_bytes"], start, b)
PY
check "resident memory grew by at most the budget + 16 MiB (and by more without it)" test $? -eq 0

# Built with MPI, the ranks' case must run (a missing mpirun fails it).
if [ "$VR_HAVE_MPI" = "ON" ]; then
  check "mpirun is there (scripts/install-deps.sh)" command -v mpirun
  mpi=(mpirun --oversubscribe -np 2)
  [ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
  if [ -n "${ASAN_OPTIONS:-}" ]; then
    export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
    mpi+=(-x ASAN_OPTIONS)
  fi
  run timeout 300 "${mpi[@]}" "$bin" --memory-budget "$budget" -o ranks --stats ranks.json
  check "2 ranks under the budget render" test $? -eq 0
  "$cmp" "$tmp/hotel/free.exr" "$tmp/hotel/ranks.exr" > /dev/null
  check "2 ranks under the budget: the same image" test $? -eq 0
  python3 - "$tmp/hotel/ranks.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
b, allow = s["memory"]["budget_bytes"], 16 << 20
for r in s["ranks"]:
    added = r["peak_rss_bytes"] - r["rss_start_bytes"]
    print("# rank %d: grew by %.1f MiB" % (r["rank"], added / 2**20), file=sys.stderr)
    assert r["rss_start_bytes"] > 0 and added <= b + allow, (r, b)
PY
  check "each rank's resident memory grew by at most the budget + 16 MiB" test $? -eq 0
fi
finish
