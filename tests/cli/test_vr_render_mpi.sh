#!/usr/bin/env bash
# Command-line test of vr-render on several MPI ranks (real mpirun,
# --oversubscribe on this machine): the image and the sensor readings of
# 2, 3 and 4 ranks are those of one process (1e-6 relative per value), for
# the decomposed flow, image space and a memory budget; rays created equal
# rays finished over the ranks; a message carries whole ray records; a
# photon-mapped sensor reads the same; ranks given different scenes or
# options are refused; a rank that dies fails the job and leaves no output.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

if [ "$VR_HAVE_MPI" != "ON" ]; then
  # Built without MPI: it runs alone, and refuses to be one of several ranks.
  printf 'material g lambert reflectance=0.5\nrect center=0,0,0 normal=0,0,1 size=2,2 material=g\nlight point position=0,0,1 intensity=10cd\nsensor s point position=0,0,0 normal=0,0,1\nrender integrator=path sensor_samples=64\n' > "$tmp/s.scn"
  (cd "$tmp" && "$bin" s.scn --quiet); check "without MPI: renders alone" test $? -eq 0
  # The one-process configuration (-DVR_MPI=OFF, scripts/test.sh's no-MPI
  # stage); mpirun is installed by the set-up, so its absence is a failure.
  check "without MPI: mpirun is there to try it (scripts/install-deps.sh)" command -v mpirun
  extra=(); [ "$(id -u)" -eq 0 ] && extra=(--allow-run-as-root)
  (cd "$tmp" && timeout 60 mpirun --oversubscribe "${extra[@]}" -np 2 "$bin" s.scn -o two) > /dev/null 2> "$tmp/nompi.err"
  check "without MPI: under mpirun it refuses" test $? -ne 0
  check "without MPI: and says why" grep -q "built without MPI" "$tmp/nompi.err"
  finish
  exit $?
fi
if ! command -v mpirun > /dev/null; then
  echo "not ok - mpirun is missing (apt-get install openmpi-bin)"
  exit 1
fi
mpi=(mpirun --oversubscribe -x VR_MATDB)
# Under the sanitizer build the ranks keep AddressSanitizer's checks but not
# its leak report: Open MPI unloads the components whose set-up it keeps
# until exit, so those blocks cannot be told from ours by name (the code
# of this project is leak-checked by the single-process tests).
if [ -n "${ASAN_OPTIONS:-}" ]; then
  export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
  mpi+=(-x ASAN_OPTIONS)
fi
[ -n "${UBSAN_OPTIONS:-}" ] && mpi+=(-x UBSAN_OPTIONS)
[ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)

source "$(dirname "$0")/mpi_room.sh"  # $tmp/room.scn
S=8
run1() { (cd "$tmp" && "$bin" room.scn --subdomains $S --threads 1 "$@" --quiet); }
runN() { local n=$1; shift; (cd "$tmp" && timeout 300 "${mpi[@]}" -np "$n" "$bin" room.scn --subdomains $S --threads 1 "$@" --quiet); }

# The reference is one process with the whole scene in one cell.
S=1 run1 -o one --stats one.json; check "one process renders" test $? -eq 0
# Ranks x sub-domains, including more ranks than cells.  Without a budget
# a rank loads the cells that take much of its work or cost little to load
# (the camera's cell, where every rank's paths start, is held by several)
# and sends the rays of the others to a rank that holds them (docs/ddm.md,
# "Ranks").
for case in 2x8 3x8 4x8 2x1 4x2 3x27; do
  n=${case%x*} S=${case#*x}
  runN $n -o ranks$case --stats ranks$case.json; rc=$?
  check "$n ranks, S = $S: renders" test $rc -eq 0
  "$cmp" "$tmp/one.exr" "$tmp/ranks$case.exr" > "$tmp/cmp$case.txt"; rc=$?
  check "$n ranks, S = $S: the image of one process" test $rc -eq 0
  [ $rc -eq 0 ] || sed 's/^/# /' "$tmp/cmp$case.txt"
  python3 - "$tmp" $n $S <<'PY'
import csv, json, sys
d, n, S = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
a = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/one.sensors.csv"))]
b = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/ranks%dx%d.sensors.csv" % (n, S)))]
assert len(a) == 4 and all(abs(x - y) <= 1e-6 * x for x, y in zip(a, b)), (a, b)
s = json.load(open(d + "/ranks%dx%d.json" % (n, S)))
# every ray created on any rank was finished on some rank: a ray lost in a
# message (or never received) leaves created > finished
assert s["rays"]["created"] == s["rays"]["finished"], s["rays"]
assert len(s["ranks"]) == n, s["ranks"]
sent = sum(r["rays_sent"] for r in s["ranks"])
recv = sum(r["rays_received"] for r in s["ranks"])
assert sent == recv, (sent, recv)
held = [c["ranks"] for c in s["cells"] if c["ranks"] > 0]
# a hot cell (the camera's, where every rank's paths start) is loaded by
# several ranks: no cell has a single owner
assert max(held) >= 2, s["cells"]
print("# cells held by", held, "rays sent", sent, file=sys.stderr)
PY
  check "$n ranks, S = $S: the same readings, rays created = finished, rays sent = received, a hot cell on several ranks" test $? -eq 0
done
S=8
check "only rank 0 wrote outputs" test -z "$(ls "$tmp" | grep -v -e '^one' -e '^ranks' -e '^cmp' -e '^batch' -e '^room' -e '\.db' -e 'vrcache')"

# Progressive photon mapping (SPPM): each rank's visible points and photon
# sums are added over the ranks after each step, so 2 ranks on 8
# sub-domains give the image of one process.
sed 's/^render .*/render integrator=progressive spp=3 photons=20000 depth=6 seed=3 sensor_samples=64/' "$tmp/room.scn" > "$tmp/sppm.scn"
(cd "$tmp" && "$bin" sppm.scn --threads 1 -o sppm1 --quiet); check "SPPM: one process renders" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" sppm.scn --subdomains 8 --threads 1 -o sppm2 --quiet)
check "SPPM: 2 ranks on 8 sub-domains render" test $? -eq 0
"$cmp" "$tmp/sppm1.exr" "$tmp/sppm2.exr" > "$tmp/cmpsppm.txt"; rc=$?
check "SPPM: 2 ranks give the image of one process" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/cmpsppm.txt"

# A film of over 2^20 sums (400 x 300 pixels x 33) is added over the
# ranks in pieces through one buffer (run/ranks.c): the image and every
# band of the spectral image are those of one process; without the spectral
# EXR (3 sums a pixel) the image is the same.
sed 's/^render .*/render integrator=path spp=1 depth=3 seed=5/' "$tmp/room.scn" > "$tmp/film.scn"
(cd "$tmp" && "$bin" film.scn --threads 1 --resolution 400x300 -o film1 --quiet)
check "a 400 x 300 film: one process renders" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" film.scn --subdomains 8 --threads 1 \
   --resolution 400x300 -o film2 --quiet)
check "a 400 x 300 film: 2 ranks render" test $? -eq 0
"$cmp" "$tmp/film1.exr" "$tmp/film2.exr" > /dev/null
check "a 400 x 300 film: 2 ranks give the image of one process" test $? -eq 0
"$cmp" --spectral "$tmp/film1.spectral.exr" "$tmp/film2.spectral.exr" > /dev/null
check "a 400 x 300 film: and every band of its spectral image" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" film.scn --subdomains 8 --threads 1 \
   --resolution 400x300 --outputs exr -o film3 --quiet)
"$cmp" "$tmp/film1.exr" "$tmp/film3.exr" > /dev/null
check "a 400 x 300 film without its bins: the same image on 2 ranks" test $? -eq 0

# Adaptive sampling: the rounds' decisions come from the film summed over
# the ranks, so 2 ranks on 8 sub-domains take the same samples at every
# pixel and give the image of one process.
sed 's/^render .*/render integrator=path spp=2 depth=3 seed=5/' "$tmp/room.scn" > "$tmp/adapt.scn"
(cd "$tmp" && "$bin" adapt.scn --threads 1 --target-error 0.1 --max-spp 32 --outputs exr \
   -o adapt1 --stats adapt1.json --quiet)
check "adaptive: one process renders" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" adapt.scn --subdomains 8 --threads 1 \
   --target-error 0.1 --max-spp 32 --outputs exr -o adapt2 --stats adapt2.json --quiet)
check "adaptive: 2 ranks render" test $? -eq 0
"$cmp" "$tmp/adapt1.exr" "$tmp/adapt2.exr" > /dev/null
check "adaptive: 2 ranks give the image of one process" test $? -eq 0
python3 -c 'import json, sys
a, b = [json.load(open(f))["image"]["adaptive"] for f in sys.argv[1:]]
assert a["rounds"] >= 2 and a["spp_min"] < a["spp_max"], a
assert all(a[k] == b[k] for k in ("rounds", "spp_min", "spp_max", "spp_mean")), (a, b)' \
  "$tmp/adapt1.json" "$tmp/adapt2.json"
check "adaptive: the same rounds and samples on 2 ranks" test $? -eq 0
# Denoising: the features are sums over the samples, summed over the ranks
# as the film: 2 ranks on 8 sub-domains give the film and the feature
# layers of one process.
sed 's/^render .*/render integrator=path spp=4 depth=3 seed=5/' "$tmp/room.scn" > "$tmp/dn.scn"
(cd "$tmp" && "$bin" dn.scn --threads 1 --denoise --resolution 64x48 --outputs exr,png -o dn1 --quiet)
check "denoise: one process renders" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" dn.scn --subdomains 8 --threads 1 --denoise \
   --resolution 64x48 --outputs exr,png -o dn2 --quiet)
check "denoise: 2 ranks render" test $? -eq 0
"$cmp" "$tmp/dn1.exr" "$tmp/dn2.exr" > /dev/null
check "denoise: 2 ranks give the film of one process" test $? -eq 0
for layer in albedo.R normal.X nearness.V; do
  a=$("$(dirname "$cmp")/vr-test-exr-attrs" --channels "$tmp/dn1.exr" --values $layer | grep "^$layer [-0-9]")
  b=$("$(dirname "$cmp")/vr-test-exr-attrs" --channels "$tmp/dn2.exr" --values $layer | grep "^$layer [-0-9]")
  check "denoise: $layer the same on 2 ranks ($a)" test -n "$a" -a "$a" = "$b"
done
check "denoise: rank 0 writes the PNG" test -s "$tmp/dn2.png"
# SPPM denoised (two chains, each iteration's sums added over the ranks):
# the film and the variance layer of one process on 2 ranks.
sed 's/^render .*/render integrator=progressive spp=4 photons=20000 seed=5/' "$tmp/room.scn" > "$tmp/dp.scn"
(cd "$tmp" && "$bin" dp.scn --threads 1 --denoise --resolution 40x30 --outputs exr -o dp1 --quiet)
check "SPPM denoised: one process renders" test $? -eq 0
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" dp.scn --subdomains 8 --threads 1 --denoise \
   --resolution 40x30 --outputs exr -o dp2 --quiet)
check "SPPM denoised: 2 ranks render" test $? -eq 0
"$cmp" "$tmp/dp1.exr" "$tmp/dp2.exr" > /dev/null
check "SPPM denoised: 2 ranks give the film of one process" test $? -eq 0
a=$("$(dirname "$cmp")/vr-test-exr-attrs" --channels "$tmp/dp1.exr" --values variance.Y | grep "^variance.Y [-0-9]")
b=$("$(dirname "$cmp")/vr-test-exr-attrs" --channels "$tmp/dp2.exr" --values variance.Y | grep "^variance.Y [-0-9]")
check "SPPM denoised: variance.Y the same on 2 ranks ($a)" test -n "$a" -a "$a" = "$b"
# The ranks must agree on keeping the bins (their sums are collective):
# different --outputs are refused like different options.
(cd "$tmp" && timeout 120 "${mpi[@]}" -np 2 sh -c 'if [ "$OMPI_COMM_WORLD_RANK" = 0 ]; then exec "$0" "$@" --outputs exr; else exec "$0" "$@"; fi' \
   "$bin" film.scn --subdomains 8 --threads 1 --resolution 40x30 -o film4 --quiet) > /dev/null 2> "$tmp/film4.err"
rc=$?
check "ranks asked for different outputs are refused" test $rc -ne 0 -a $rc -ne 124
grep -q "other options than rank 0" "$tmp/film4.err"; check "the refusal says the ranks' options differ" test $? -eq 0

# Under a budget that holds the film and a few cells a rank, rays go to a rank that
# holds their cell: --send-batch bounds the rays of a message, a message
# is a header and whole rays, and --send-credit bounds what a rank holds
# of another's rays before it credits them back (flow control: the sender
# waits, docs/ddm.md).
runN 2 --memory-budget 700K --send-batch 16 --send-credit 4 -o batch --stats batch.json
check "2 ranks under a budget, 16 rays a message, 4 of credit: renders" test $? -eq 0
"$cmp" "$tmp/one.exr" "$tmp/batch.exr" > /dev/null; check "2 ranks, 16 rays a message, 4 of credit: the same image" test $? -eq 0
python3 - "$tmp/batch.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
sent = sum(r["rays_sent"] for r in s["ranks"])
assert sent > 0 and sent == sum(r["rays_received"] for r in s["ranks"]), s["ranks"]
assert s["rays"]["created"] == s["rays"]["finished"], s["rays"]
for r in s["ranks"]:
    w = r["ray_wire_bytes"]
    # every message of rays: an 8-byte header and whole rays (the receiver
    # fails the run on any other), at most 16; a ray in its wire form
    # (render/src/ddm/ray_wire.c) takes at most 96 bytes on average
    # (issue 31's bound; about 76 measured, docs/ddm.md)
    assert abs(r["ray_bytes_sent"] - 8 * r["ray_messages"] - w * r["rays_sent"]) < 1e-6 * r["ray_bytes_sent"], r
    assert 40 < w <= 96, r
    assert r["rays_sent"] <= 16 * r["ray_messages"], r
    # what a rank holds of the other's rays never passes the credit
    assert r["peak_uncredited"] <= 4, r
assert sum(r["credit_waits"] for r in s["ranks"]) > 0, s["ranks"]
PY
check "2 ranks, 16 rays a message, 4 of credit: whole rays, the credit held to, senders waited" test $? -eq 0

# Image space (each rank its share of the tiles, every cell everywhere)
# and a memory budget (each rank holding few of its cells).
runN 2 --image-space -o imsp; check "2 ranks in image space" test $? -eq 0
"$cmp" "$tmp/one.exr" "$tmp/imsp.exr" > /dev/null; check "image space on 2 ranks: the same image" test $? -eq 0
runN 2 --memory-budget 700K -o budget --stats budget.json; check "2 ranks under a budget" test $? -eq 0
"$cmp" "$tmp/one.exr" "$tmp/budget.exr" > /dev/null; check "2 ranks under a budget: the same image" test $? -eq 0
# What the budget guarantees (flow_sched.c): each rank's cells and queues
# (with the rays waiting to go to another rank) stay within it, the queues
# spill what they cannot hold, every ray is traced.
python3 -c "
import json, sys; s = json.load(open('$tmp/budget.json'))
b, m = s['memory']['budget_bytes'], s['memory']
assert b == 700 * 1024, b
for r in s['ranks']:
    assert r['peak_cells_bytes'] + r['peak_queue_bytes'] <= b, (r, m)
assert s['subdomains']['rays_spilled'] > 0, s['subdomains']
assert s['rays']['created'] == s['rays']['finished'], s['rays']"
check "2 ranks under a budget: cells and queues within it, queues spilled, rays accounted for" test $? -eq 0

# Photon-mapped sensors read the same over ranks (each rank stores the
# photons landing in its cells; every rank gets them all).
sed 's/^render .*/render integrator=photon sensors=photon photons=40000 knn=40 spp=1/' "$tmp/room.scn" > "$tmp/photon.scn"
(cd "$tmp" && "$bin" photon.scn --subdomains 8 --threads 1 --sensors-only -o p1 --quiet) && \
  (cd "$tmp" && timeout 300 "${mpi[@]}" -np 3 "$bin" photon.scn --subdomains 8 --threads 1 --sensors-only -o p3 --quiet)
check "photon-mapped sensors on 1 and 3 ranks" test $? -eq 0
python3 - "$tmp" <<'PY'
import csv, sys
d = sys.argv[1]
a = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/p1.sensors.csv"))]
b = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/p3.sensors.csv"))]
assert all(x > 0 for x in a) and all(abs(x - y) <= 1e-6 * x for x, y in zip(a, b)), (a, b)
PY
check "photon-mapped sensors: the same readings" test $? -eq 0

# An annual study with a glare view on two ranks: the image coefficients'
# tallies by sky patch are summed over the ranks like the film, so every
# hour's DGP is one process's (an eye looking at the window of the closed
# room, whose DGP the window's pixels decide: without the ranks' sum of
# those tallies, hours differ by up to 4e-4 here).
source "$(dirname "$0")/room_shell.sh"
{
  room_shell
  cat <<EOS
light sun spectrum=D65
sky perez weather=$VR_SOURCE_DIR/tests/data/weather/chicago.wea
sensor eye point position=2,3,1.2 normal=0,-1,0
annual hours=11,13 glare_views=eye glare_resolution=32
render sensor_samples=64 spp=4
EOS
} > "$tmp/year.scn"
(cd "$tmp" && "$bin" year.scn -o year1 --threads 1 --quiet) > /dev/null 2>&1
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" year.scn -o year2 --threads 1 --quiet) > /dev/null 2> "$tmp/year2.err"; rc=$?
check "an annual study with a glare view on 2 ranks runs" test $rc -eq 0
python3 - "$tmp" <<'PY'
import csv, sys
d = sys.argv[1]
a = [float(r["dgp:eye"]) for r in csv.DictReader(open(d + "/year1.annual-hourly.csv"))]
b = [float(r["dgp:eye"]) for r in csv.DictReader(open(d + "/year2.annual-hourly.csv"))]
assert len(a) == len(b) == 730 and all(abs(x - y) <= 1.5e-4 for x, y in zip(a, b)), (len(a), len(b))  # printed to 4 places
PY
check "its hourly DGP is one process's" test $? -eq 0

# Ranks given different scenes or options are refused, naming the rank.
sed 's/reflectance=0.6/reflectance=0.5/' "$tmp/room.scn" > "$tmp/other.scn"
(cd "$tmp" && timeout 120 "${mpi[@]}" -np 1 "$bin" room.scn --subdomains 8 -o mix : -np 1 "$bin" other.scn --subdomains 8 -o mix) > /dev/null 2> "$tmp/mix.err"; rc=$?
check "different scenes on two ranks exit non-zero" test $rc -ne 0
check "different scenes are named as such" grep -q "rank 1 renders another scene file or other options than rank 0" "$tmp/mix.err"
check "different scenes write nothing" test ! -e "$tmp/mix.png"
(cd "$tmp" && timeout 120 "${mpi[@]}" -np 1 "$bin" room.scn --subdomains 8 --spp 2 -o mix : -np 1 "$bin" room.scn --subdomains 8 --spp 3 -o mix) > /dev/null 2> "$tmp/mix2.err"; rc=$?
check "different options on two ranks are refused" test $rc -ne 0 -a ! -e "$tmp/mix.png"

# A rank that dies: the job fails and no output is written.
sed 's/^render .*/render integrator=path spp=400 depth=6 seed=3/' "$tmp/room.scn" > "$tmp/long.scn"
(cd "$tmp" && timeout 300 "${mpi[@]}" -np 2 "$bin" long.scn --subdomains 8 --threads 1 -o dead > dead.out 2> dead.err) &
job=$!
victim=""
for i in $(seq 1 100); do
  for p in $(pgrep -f "$bin long.scn"); do
    if tr '\0' '\n' < /proc/$p/environ 2>/dev/null | grep -q '^OMPI_COMM_WORLD_RANK=1$'; then victim=$p; fi
  done
  [ -n "$victim" ] && break
  sleep 0.1
done
sleep 1
[ -n "$victim" ] && kill -9 "$victim"
wait $job; rc=$?
check "a killed rank was found" test -n "$victim"
check "a killed rank fails the job" test $rc -ne 0
check "a killed rank leaves no output" test ! -e "$tmp/dead.png" -a ! -e "$tmp/dead.exr"
# Open MPI's own report of the rank this test killed (its text in 4.1:
# "mpirun noticed that process rank 1 with PID ... exited on signal 9
# (Killed)."), not any failure.
check "mpirun reports that rank 1 died of signal 9" \
  grep -q "process rank 1 with PID .* exited on signal 9" "$tmp/dead.err"

finish
