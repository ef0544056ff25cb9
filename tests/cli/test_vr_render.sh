#!/usr/bin/env bash
# Command-line test of vr-render: --help, usage and file errors, and one
# small analytic scene rendered end to end (outputs, sensor table, stats).
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

"$bin" --help > "$tmp/help" 2>&1; rc=$?
check "--help exits 0" test $rc -eq 0
check "--help shows usage" grep -q "^Usage: vr-render" "$tmp/help"
for o in --output --db --subdomains --threads --image-space --spp --photons --stats --tonemap \
         --sensors-only --quiet --help --version; do
  check "--help lists $o" grep -q -- "$o" "$tmp/help"
done
"$bin" --version > "$tmp/ver"; check "--version" grep -q "vr-render (Virtuelium-C) " "$tmp/ver"

# Usage errors exit 2; errors on files exit 1 and name the file.
"$bin" --bogus "$tmp/x.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "unknown option is a usage error (2)" test $rc -eq 2
"$bin" > /dev/null 2>&1; rc=$?
check "no scene is a usage error (2)" test $rc -eq 2
"$bin" --threads zero "$tmp/x.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "bad --threads is a usage error (2)" test $rc -eq 2
check "bad --threads is named" grep -q -- "--threads 'zero'" "$tmp/err"
"$bin" --tonemap filmic "$tmp/x.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "bad --tonemap is a usage error (2)" test $rc -eq 2
"$bin" "$tmp/none.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "missing scene exits 1" test $rc -eq 1
check "missing scene is named" grep -q "^vr-render: .*none.scn" "$tmp/err"
printf 'camera pinhole from=0,-1,1 to=0,0,0\nrect center=0,0,0 normal=0,0,1 size=1,1 material=nowhere\n' > "$tmp/bad.scn"
"$bin" "$tmp/bad.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "unknown material exits 1" test $rc -eq 1
check "scene error is file:line:col" grep -q "^vr-render: .*bad.scn:2:[0-9]*: .*nowhere" "$tmp/err"
check "no output after an error" test ! -e "$tmp/bad.png"

# CIE 171:2006 test case 5.2 geometry: a 1000 cd isotropic point 3 m above a
# point on the floor, facing it: E = I / r^2 = 1000 / 9 = 111.1 lx.  The
# floor is the only surface and lies below the sensor, so nothing is
# reflected onto it.
cat > "$tmp/point.scn" <<'EOF'
# One lamp over a grey floor.
camera pinhole from=0,-6,4 to=0,0,0 up=0,0,1 fov=60 resolution=32x24
material grey lambert reflectance=0.5
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
light point position=0,0,3 intensity=1000cd
sensor floor point position=0,0,0 normal=0,0,1
render integrator=path spp=4
EOF
(cd "$tmp" && "$bin" point.scn --stats point.json --threads 2 > out.txt 2> log.txt); rc=$?
check "renders the point-light scene" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/log.txt"
for f in point.exr point.spectral.exr point.png point.sensors.csv point.json; do
  check "wrote $f" test -s "$tmp/$f"
done
check "no database file made for a scene that needs none" test ! -e "$VR_MATDB"
check "no staging file left" test -z "$(ls "$tmp" | grep -e '\.stage-' -e '\.tmp-')"
python3 - "$tmp" <<'PY'
import csv, json, sys
d = sys.argv[1]
rows = list(csv.DictReader(open(d + "/point.sensors.csv")))
assert len(rows) == 1 and rows[0]["sensor"] == "floor", rows
E = float(rows[0]["illuminance_lx"])
assert abs(E - 1000 / 9) <= 0.01 * 1000 / 9, E
head = open(d + "/point.sensors.csv").readline().strip().split(",")
assert head[:8] == ["sensor", "i", "j", "x", "y", "z", "illuminance_lx", "stderr_lx"], head
parts = ["sky_component_lx", "sun_direct_lx", "externally_reflected_sky_lx",
         "externally_reflected_sun_lx", "internally_reflected_sky_lx",
         "internally_reflected_sun_lx", "electric_lx", "daylight_factor_pct",
         "df_sky_component_pct", "df_externally_reflected_pct", "df_internally_reflected_pct"]
assert head[-len(parts):] == parts, head
spec = head[8:-len(parts)]
assert len(spec) > 0 and all(h.startswith("E_") for h in spec), head
# A point lamp and no sky: all of it electric light, no daylight factor.
assert abs(float(rows[0]["electric_lx"]) - E) <= 1e-6 * E, rows[0]
assert rows[0]["daylight_factor_pct"] == "", rows[0]
s = json.load(open(d + "/point.json"))
for k in ("passes", "rays", "peak_rss_bytes", "photons", "sensors", "seconds_total", "photochromic"):
    assert k in s, k
assert s["peak_rss_bytes"] > 0 and s["rays"]["camera"] > 0, s
assert abs(s["sensors"][0]["illuminance_lx"] - E) < 1e-7 * E  # the CSV keeps 9 digits
PY
check "sensor reads 111.1 lx within 1 %, stats parse" test $? -eq 0
check "summary names the sensor" grep -q "^sensor .*floor" "$tmp/out.txt"
check "decision lines are prefixed" grep -q "^vr-render: " "$tmp/log.txt"

# -o, --sensors-only and --quiet: only the table, nothing printed.
mkdir -p "$tmp/o"
"$bin" "$tmp/point.scn" -o "$tmp/o/s" --sensors-only --quiet > "$tmp/out2.txt" 2>&1; rc=$?
check "--sensors-only runs" test $rc -eq 0
check "--sensors-only writes the table" test -s "$tmp/o/s.sensors.csv"
check "--sensors-only writes no image" test ! -e "$tmp/o/s.png" -a ! -e "$tmp/o/s.exr"
check "--quiet prints nothing" test ! -s "$tmp/out2.txt"

# --sensors-only keeps the spectral columns (the film's bins are known
# without a camera).
head -1 "$tmp/o/s.sensors.csv" | grep -q ",E_405,"; check "--sensors-only table has spectral columns" test $? -eq 0

# Only the effects a scene calls for, read from --stats: a diffuse room with
# photon mapping runs the global photon map but no caustic and no UV pass; a
# mirror added makes the caustic pass run, naming the material.
cat > "$tmp/diffuse.scn" <<'EOF'
camera pinhole from=0,-1.5,1 to=0,0,1 fov=70 resolution=16x12
material grey lambert reflectance=0.5
box min=-2,-2,0 max=2,2,2.5 material=grey
light point position=0,0,2 intensity=500lm
render integrator=photon spp=1 photons=20000 caustic_photons=20000 knn=20
EOF
sed 's/^render/material mirror db:Ag\nsphere center=0.5,0.5,0.4 radius=0.3 material=mirror\nrender/' "$tmp/diffuse.scn" > "$tmp/mirror.scn"
(cd "$tmp" && VR_MATDB="$tmp/m.db" "$bin" diffuse.scn --stats diffuse.json --quiet && \
   VR_MATDB="$tmp/m.db" "$bin" mirror.scn --stats mirror.json --quiet) > /dev/null 2>&1
check "diffuse and mirror scenes render" test $? -eq 0
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
def passes(f):
    return {p["name"]: p for p in json.load(open(d + "/" + f))["passes"]}
a, b = passes("diffuse.json"), passes("mirror.json")
assert a["global photons"]["ran"] and not a["caustic photons"]["ran"], a
assert "no specular" in a["caustic photons"]["reason"], a["caustic photons"]
assert not a["uv"]["ran"] and "photochromic" in a["uv"]["reason"], a["uv"]
assert b["caustic photons"]["ran"] and "mirror" in b["caustic photons"]["reason"], b["caustic photons"]
assert not a["dispersion"]["ran"] and not b["dispersion"]["ran"]
PY
check "--stats: caustic pass only with a mirror, no UV pass without photochromic glass" test $? -eq 0

# A light mesh made only of degenerate triangles is refused with the file
# named; one with a good triangle renders and the dropped ones are counted.
printf 'v 0 0 2\nv 1 0 2\nv 2 0 2\nf 1 2 3\n' > "$tmp/flat.obj"
printf 'v 0 0 2\nv 1 0 2\nv 2 0 2\nv 0 1 2\nf 1 2 3\nf 1 4 2\n' > "$tmp/half.obj"
for m in flat half; do
  cat > "$tmp/$m.scn" <<EOF
material grey lambert reflectance=0.5
material lamp black
rect center=0,0,0 normal=0,0,1 size=4,4 material=grey
mesh $m.obj material=lamp emission=1000cd/m2
sensor floor point position=0.3,0.3,0 normal=0,0,1
render integrator=path sensor_samples=64
EOF
done
(cd "$tmp" && "$bin" flat.scn --sensors-only > /dev/null 2> flat.err); rc=$?
check "an all-degenerate light mesh exits 1" test $rc -eq 1
check "an all-degenerate light mesh names its file" grep -q "flat.obj.*degenerate" "$tmp/flat.err"
(cd "$tmp" && "$bin" half.scn --sensors-only > half.out 2> half.err); rc=$?
check "a light mesh with one degenerate triangle renders" test $rc -eq 0
check "the dropped triangle is reported" grep -q "1 degenerate triangle" "$tmp/half.err"

# A light of zero area (a sphere of radius 1e-200 m: its area underflows to
# 0) carries no power: the render runs and reads 0 lx, in photon mapping
# and in path tracing.
for integ in photon path; do
  cat > "$tmp/zero_$integ.scn" <<EOF
camera pinhole from=0,-3,1 to=0,0,0 resolution=16x12
material grey lambert reflectance=0.5
material lamp black
rect center=0,0,0 normal=0,0,1 size=4,4 material=grey
sphere center=0,0,1 radius=1e-200 material=lamp emission=100cd/m2
sensor s point position=0,0,0 normal=0,0,1
render integrator=$integ spp=2 photons=10000 sensor_samples=256
EOF
  (cd "$tmp" && "$bin" "zero_$integ.scn" --quiet); rc=$?
  check "a zero-area light renders ($integ)" test $rc -eq 0
  check "a zero-area light gives 0 lx ($integ)" \
    test "$(sed -n 2p "$tmp/zero_$integ.sensors.csv" | cut -d, -f7)" = "0"
done

# The geometry cache and the memory budget (docs/ddm.md).  The cache is
# made beside the scene by default, reused on the next run, and a budget
# that forces sub-domains in and out gives the same sensor readings.
check "the point scene's cache was made beside it" test -s "$tmp/point.vrcache/S1/manifest.vrm"
(cd "$tmp" && "$bin" point.scn --stats again.json --threads 2 --quiet); rc=$?
check "second run of the point scene" test $rc -eq 0
python3 - "$tmp" <<'PY'
import json, sys
s = json.load(open(sys.argv[1] + "/again.json"))
assert s["cache"]["built"] is False and s["cache"]["reason"] == "reused", s["cache"]
assert s["subdomains"]["count"] == 1 and s["subdomains"]["loads"] == 1, s["subdomains"]
assert s["memory"]["budget_bytes"] == 0 and s["memory"]["peak_cells_bytes"] > 0, s["memory"]
PY
check "the cache is reused, stats say so" test $? -eq 0
cat > "$tmp/boxes.scn" <<'SCN'
# Eight boxes around a lamp, to cut into sub-domains.
material grey lambert reflectance=0.5
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
box min=-3,-3,0 max=-2,-2,1 material=grey
box min=2,-3,0 max=3,-2,1 material=grey
box min=-3,2,0 max=-2,3,1 material=grey
box min=2,2,0 max=3,3,1 material=grey
box min=-0.5,-3,0 max=0.5,-2,2 material=grey
box min=-0.5,2,0 max=0.5,3,2 material=grey
box min=-3,-0.5,0 max=-2,0.5,2 material=grey
box min=2,-0.5,0 max=3,0.5,2 material=grey
light point position=0,0,3 intensity=1000cd
sensor floor grid origin=-1,-1,0 u=2,0,0 v=0,2,0 n=2,2 normal=0,0,1
render integrator=path sensor_samples=512 depth=3
SCN
(cd "$tmp" && "$bin" boxes.scn --sensors-only --subdomains 8 --cache "$tmp/c" -o free --stats free.json --quiet); rc=$?
check "boxes, 8 sub-domains, no budget" test $rc -eq 0
(cd "$tmp" && "$bin" boxes.scn --sensors-only --subdomains 8 --cache "$tmp/c" -o tight --stats tight.json \
   --memory-budget 80K --threads 2 > tight.out 2> tight.err); rc=$?
check "boxes, 8 sub-domains, an 80 KiB budget" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/tight.err"
check "--cache DIR is used" test -s "$tmp/c/S8/manifest.vrm"
check "the summary reports the budget" grep -q "^memory   budget 80.0 KiB" "$tmp/tight.out"
python3 - "$tmp" <<'PY'
import csv, json, sys
d = sys.argv[1]
f = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/free.sensors.csv"))]
t = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/tight.sensors.csv"))]
assert len(f) == 4 and all(abs(a - b) <= 1e-6 * a for a, b in zip(f, t)), (f, t)
s = json.load(open(d + "/tight.json"))
m, sd = s["memory"], s["subdomains"]
assert m["budget_bytes"] == 80 * 1024, m
assert m["peak_cells_bytes"] + m["peak_queue_bytes"] + m["peak_map_bytes"] <= m["budget_bytes"], m
assert sd["loads"] > 8 and sd["unloads"] > 0, sd
assert s["rays"]["created"] == s["rays"]["finished"], s["rays"]
PY
check "the budget moves sub-domains in and out, same readings, held within it" test $? -eq 0

# Bad budgets are usage errors naming the option; one too small for the
# largest sub-domain is refused naming it; --image-space cannot take one.
for b in abc 0 -5M 12Q 1e40; do
  "$bin" "$tmp/boxes.scn" --memory-budget "$b" > /dev/null 2> "$tmp/err"; rc=$?
  check "--memory-budget $b is a usage error (2)" test $rc -eq 2
  check "--memory-budget $b is named" grep -q -- "--memory-budget: '$b' is not a size" "$tmp/err"
done
"$bin" "$tmp/boxes.scn" --memory-budget 1G --image-space > /dev/null 2> "$tmp/err"; rc=$?
check "--memory-budget with --image-space is a usage error (2)" test $rc -eq 2
(cd "$tmp" && "$bin" boxes.scn --sensors-only --subdomains 8 --cache "$tmp/c" -o small --memory-budget 30K \
   > /dev/null 2> small.err); rc=$?
check "a budget too small exits 1" test $rc -eq 1
check "a budget too small names a sub-domain" grep -q "memory budget 30.0 KiB is too small: sub-domain [0-9]* needs" "$tmp/small.err"
check "a budget too small writes nothing" test ! -e "$tmp/small.sensors.csv"

# A cache folder that cannot be written: --cache names it; by default the
# render falls back to a temporary cache and says so.  (As root every
# folder is writable, and the check would mean nothing: it is skipped.)
mkdir -p "$tmp/ro" && cp "$tmp/point.scn" "$tmp/ro/" && chmod 555 "$tmp/ro"
if [ ! -w "$tmp/ro" ]; then
  (cd "$tmp" && "$bin" ro/point.scn -o ro_out --sensors-only 2> ro.err > /dev/null); rc=$?
  check "a read-only scene folder still renders" test $rc -eq 0
  check "the temporary cache is announced" grep -q "using a temporary one" "$tmp/ro.err"
  "$bin" "$tmp/point.scn" --cache "$tmp/ro/c" --sensors-only -o "$tmp/x" > /dev/null 2> "$tmp/err"; rc=$?
  check "an unwritable --cache exits 1" test $rc -eq 1
  check "an unwritable --cache is named" grep -q "ro/c" "$tmp/err"
fi
chmod 755 "$tmp/ro"
"$bin" "$tmp/point.scn" --cache '' > /dev/null 2> "$tmp/err"; rc=$?
check "--cache '' is refused" test $rc -eq 1

# A year of weather: the annual study writes its two tables and prints sDA
# and ASE (the metrics themselves are tested in tests/render/test_annual.c).
cat > "$tmp/year.scn" <<EOF
material ground lambert reflectance=0.2
rect center=0,0,0 normal=0,0,1 size=10,10 material=ground
light sun spectrum=D65
sky perez weather=$src/tests/data/weather/chicago.wea
sensor top point position=0,0,0.001 normal=0,0,1
annual hours=9,15 ase=1000,250
render sensor_samples=256
EOF
"$bin" "$tmp/year.scn" -o "$tmp/year" > "$tmp/year.out" 2> "$tmp/year.err"; rc=$?
check "an annual study exits 0" test $rc -eq 0
check "it prints sDA and ASE" grep -q "^annual   sDA300/50% 100.0 % of points, ASE1000,250h 100.0 % of points" "$tmp/year.out"
check "it writes the point table" grep -q "^top,0,0," "$tmp/year.annual.csv"
check "the hourly table has a line per occupied hour" test "$(wc -l < "$tmp/year.annual-hourly.csv")" -eq $((365 * 6 + 1))
check "no images for a year" test ! -e "$tmp/year.png"
printf 'light sun\nsky perez weather=%s/tests/data/weather/chicago.wea\nsensor s point position=0,0,1 normal=0,0,1\nannual glass=g\n' "$src" > "$tmp/noglass.scn"
"$bin" "$tmp/noglass.scn" -o "$tmp/ng" > /dev/null 2> "$tmp/err"; rc=$?
check "an unknown glass exits 1" test $rc -eq 1
check "an unknown glass is named with its line" grep -q "noglass.scn:4:.*glass=g: no material of that name" "$tmp/err"

# A false-colour luminance map beside the images; a bad scale is a usage
# error, a map without an image an error before any work.
"$bin" "$tmp/point.scn" -o "$tmp/fc" --falsecolour 1,1000 > "$tmp/fc.out" 2> /dev/null; rc=$?
check "--falsecolour exits 0" test $rc -eq 0
check "--falsecolour writes the map" test -s "$tmp/fc.falsecolour.png"
check "the summary lists the map" grep -q "fc.falsecolour.png" "$tmp/fc.out"
"$bin" "$tmp/point.scn" -o "$tmp/fc2" --falsecolour 100,10 > /dev/null 2> "$tmp/err"; rc=$?
check "--falsecolour 100,10 is a usage error (2)" test $rc -eq 2
check "the bad scale is named" grep -q "0 < LO < HI" "$tmp/err"
"$bin" "$tmp/point.scn" -o "$tmp/fc3" --falsecolour 1,1000 --sensors-only > /dev/null 2> "$tmp/err"; rc=$?
check "--falsecolour with --sensors-only exits 1" test $rc -eq 1
check "it says why" grep -q "sensors-only renders none" "$tmp/err"
check "and writes nothing" test ! -e "$tmp/fc3.sensors.csv"

finish
