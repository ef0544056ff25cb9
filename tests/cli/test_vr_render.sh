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
         --sensors-only --quiet --help --version --resolution --exposure --set --json --verify; do
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
"$bin" --tonemap aces "$tmp/x.scn" > /dev/null 2> "$tmp/err"; rc=$?
check "bad --tonemap is a usage error (2)" test $rc -eq 2
check "bad --tonemap names the choices" grep -q "expected clip, reinhard or filmic" "$tmp/err"
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
# stderr is a file here, not a terminal: progress comes as lines (issue 33:
# a batch run printed nothing until it ended): a quick pass says nothing;
# a pass of more than 2 s a line at each tenth from then on, and done.
progress='^vr-render: camera \([0-9]* %\|done\)'
check "a quick pass prints no progress line" test "$(grep -c "$progress" "$tmp/log.txt")" -eq 0
check "no bar's control characters in a log" test -z "$(grep -l $'\r' "$tmp/log.txt")"
"$bin" "$tmp/point.scn" -o "$tmp/slow" --outputs exr --spp 16384 --threads 2 > /dev/null 2> "$tmp/slow.log"
check "a long pass logs its tenths" grep -q "^vr-render: camera [1-9]0 % ([0-9]* s, about [0-9]* s left)" "$tmp/slow.log"
check "and its end" grep -q "^vr-render: camera done ([0-9]* s)" "$tmp/slow.log"
check "at most 10 lines for it (10 ... 90 %, done)" \
  test "$(grep -c "$progress" "$tmp/slow.log")" -le 10
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
# mirror added makes the caustic pass run, naming the material; a mirror
# in a closed box no light reaches makes it store nothing, and then it is
# reported skipped, with the reason, and its map is not read.
cat > "$tmp/diffuse.scn" <<'EOF'
camera pinhole from=0,-1.5,1 to=0,0,1 fov=70 resolution=16x12
material grey lambert reflectance=0.5
box min=-2,-2,0 max=2,2,2.5 material=grey
light point position=0,0,2 intensity=500lm
render integrator=photon spp=1 photons=20000 caustic_photons=20000 knn=20
EOF
sed 's/^render/material mirror db:Ag\nsphere center=0.5,0.5,0.4 radius=0.3 material=mirror\nrender/' "$tmp/diffuse.scn" > "$tmp/mirror.scn"
sed 's/^render/material mirror db:Ag\nbox min=5,5,0 max=7,7,2 material=grey\nsphere center=6,6,0.5 radius=0.3 material=mirror\nrender/' "$tmp/diffuse.scn" > "$tmp/dark.scn"
(cd "$tmp" && VR_MATDB="$tmp/m.db" "$bin" diffuse.scn --stats diffuse.json --quiet && \
   VR_MATDB="$tmp/m.db" "$bin" mirror.scn --stats mirror.json --quiet && \
   VR_MATDB="$tmp/m.db" "$bin" dark.scn --stats dark.json --quiet) > /dev/null 2>&1
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
assert json.load(open(d + "/mirror.json"))["photons"]["caustic"] > 0
c = passes("dark.json")
assert not c["caustic photons"]["ran"], c["caustic photons"]
assert "none of 20000 photons stored" in c["caustic photons"]["reason"] and "mirror" in c["caustic photons"]["reason"], c
assert json.load(open(d + "/dark.json"))["photons"]["caustic"] == 0
assert c["global photons"]["ran"]
PY
check "--stats: caustic pass only with a lit mirror, no UV pass without photochromic glass" test $? -eq 0

# The film keeps its spectral bins only for the spectral EXR: --outputs
# exr,png gives the same EXR with 3 doubles a pixel in the film's sums
# instead of 3 + 30, and the process's peak memory falls by at least 90 %
# of the difference, 8 x 30 bytes a pixel.  (The run with every output
# also writes the spectral EXR, 4 x 30 bytes a pixel more at its peak;
# a film that kept its bins without the spectral EXR would save nothing.)
# One thread, so that each pixel's sum is added in one order.
cat > "$tmp/big.scn" <<'EOF'
camera pinhole from=0,-1.5,1 to=0,0,1 fov=70 resolution=800x600
material grey lambert reflectance=0.5
box min=-2,-2,0 max=2,2,2.5 material=grey
light point position=0,0,2 intensity=500lm
render integrator=path spp=1 depth=1
EOF
(cd "$tmp" && "$bin" big.scn -o big_all --threads 1 --stats big_all.json --quiet && \
   "$bin" big.scn -o big_rgb --threads 1 --outputs exr,png --stats big_rgb.json --quiet) > /dev/null 2>&1
check "a film with and without its bins renders" test $? -eq 0
python3 - "$tmp" <<'PY'
import json, sys, os
d = sys.argv[1]
a, b = (json.load(open(d + f)) for f in ("/big_all.json", "/big_rgb.json"))
px = 800 * 600
assert a["memory"]["film_bytes"] == px * 33 * 8, a["memory"]
assert b["memory"]["film_bytes"] == px * 3 * 8, b["memory"]
saved = a["peak_rss_bytes"] - b["peak_rss_bytes"]
assert saved >= 0.9 * px * 30 * 8, (saved, a["peak_rss_bytes"], b["peak_rss_bytes"])
assert not os.path.exists(d + "/big_rgb.spectral.exr") and os.path.exists(d + "/big_all.spectral.exr")
PY
check "without the spectral EXR the film holds 3 doubles a pixel, and the process less memory" test $? -eq 0
cmp -s "$tmp/big_all.exr" "$tmp/big_rgb.exr"; check "the same EXR with or without the film's bins" test $? -eq 0

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
check "--cache '' is refused as a usage error" bash -c '[ "$1" = 2 ] && grep -q "the value is empty" "$2"' _ "$rc" "$tmp/err"

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
check "the two tables are a set with a manifest" "$bin" --verify "$tmp/year"
check "the manifest lists both tables" grep -q '"year.annual-hourly.csv"' "$tmp/year.manifest.json"
check "and leaves no staging folder" test -z "$(ls -d "$tmp"/year.partial.* 2>/dev/null)"
echo "x" >> "$tmp/year.annual.csv"
"$bin" --verify "$tmp/year" > /dev/null 2>&1; rc=$?
check "an altered table fails --verify (1)" test $rc -eq 1
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


# ---- Issue 18: nothing a user owns is lost or silently wrong ----

# 1. Outputs never replace inputs: the scene, the database, a mesh; two
# outputs are not one file; every output is checked, not only --stats.
mkdir -p "$tmp/g18" && cp "$tmp/point.scn" "$tmp/g18/"
cp "$tmp/half.scn" "$tmp/half.obj" "$tmp/g18/"
cd "$tmp/g18"
printf 'a database, as far as the guard can tell\n' > m.db
sum_before=$(sha256sum point.scn m.db half.obj)
refuse render-stats-over-scene "$bin" point.scn --stats point.scn
refuse render-stats-over-db "$bin" point.scn --db m.db --stats m.db
refuse render-stats-over-mesh "$bin" half.scn --sensors-only --stats half.obj
ln -s point.scn link.scn
refuse render-stats-over-scene-link "$bin" link.scn --stats point.scn
cp point.scn p2.scn && ln p2.scn p2.sensors.csv
refuse render-output-over-scene "$bin" p2.scn -o p2
refuse render-stats-same-as-output "$bin" point.scn -o same --stats same.png
mkdir -p adir
refuse render-stats-is-folder "$bin" point.scn --stats adir
check "the scene, the database and the mesh are untouched" test "$(sha256sum point.scn m.db half.obj)" = "$sum_before"
check "no output of the refused runs" test -z "$(ls | grep -e '\.png$' -e '\.exr$' -e '\.manifest' -e '\.partial')"
cd - > /dev/null

# 2. Fail before the work: a missing output folder is refused before the
# scene is even prepared (no decision line, no cache made), not after the
# render.
mkdir -p "$tmp/early" && cp "$tmp/point.scn" "$tmp/early/"
refuse render-output-folder-missing "$bin" "$tmp/early/point.scn" -o "$tmp/early/no/such/x"
check "a missing folder: one line, nothing of the render" test "$(wc -l < "$tmp/refused.err")" -eq 1
check "a missing folder: no decision line" test -z "$(grep -e ' run ' -e 'camera' -e 'cache' "$tmp/refused.err")"
check "a missing folder: no cache made" test ! -e "$tmp/early/point.vrcache"
refuse render-stats-folder-missing "$bin" "$tmp/early/point.scn" -o "$tmp/early/x" --stats "$tmp/early/nope/s.json"
check "a missing --stats folder: no image written" test ! -e "$tmp/early/x.png"

# 3. The set of outputs: a manifest written last lists every file with its
# size and SHA-256; --verify checks it; a file of another run put back in
# the set (what a kill between the final renames leaves) is reported;
# staging leftovers of a killed run (dead process) are removed by the next
# run, a live run's are kept.
mkdir -p "$tmp/set/other"
cd "$tmp/set"
cp "$tmp/point.scn" .
sleep 0 & dead=$!; wait $dead
mkdir "point.partial.$dead" && echo half > "point.partial.$dead/point.png"
echo half > "other/s.json.partial.$dead"
mkdir "point.partial.$$"   # this test's own shell: alive
"$bin" point.scn --stats other/s.json > set.out 2> set.err; rc=$?
check "render with a manifest" test $rc -eq 0
check "the dead run's staging folder is removed" test ! -e "point.partial.$dead"
check "the dead run's staged statistics are removed" test ! -e "other/s.json.partial.$dead"
check "the removal is said" grep -q "removed what a killed run left: .*point.partial.$dead" set.err
check "a live run's staging folder is kept" test -d "point.partial.$$"
rmdir "point.partial.$$"
check "no staging folder of this run left" test -z "$(ls -a . other | grep -e '\.partial\.' -e '\.tmp-' -e '\.stage-')"
python3 - "$tmp/set" <<'PY'
import hashlib, json, os, sys
d = sys.argv[1]
m = json.load(open(d + "/point.manifest.json"))
names = [f["name"] for f in m["files"]]
want = ["point.exr", "point.spectral.exr", "point.png", "point.sensors.csv", d + "/other/s.json"]
assert names == want, names
for f in m["files"]:
    p = f["name"] if f["name"].startswith("/") else d + "/" + f["name"]
    b = open(p, "rb").read()
    assert len(b) == f["bytes"] and hashlib.sha256(b).hexdigest() == f["sha256"], f
assert m["run_id"] and json.load(open(d + "/other/s.json"))["sensors"], m
PY
check "the manifest lists each file, its size and SHA-256" test $? -eq 0
"$bin" --verify point > verify.out 2>&1; rc=$?
check "--verify on a whole set exits 0" test $rc -eq 0
check "--verify says so" grep -q "^verified point: the 5 files of run .* match point.manifest.json" verify.out
cp point.png old.png
"$bin" point.scn --exposure -3 --quiet; check "a second run with another exposure" test $? -eq 0
check "the second run's PNG differs" test "$(sha256sum < point.png)" != "$(sha256sum < old.png)"
"$bin" --verify point > /dev/null 2>&1; check "the second set verifies" test $? -eq 0
cp old.png point.png
refuse render-verify-mixed-set "$bin" --verify point
check "--verify names the odd file" grep -q "point.png" "$tmp/refused.out"
refuse render-verify-no-manifest "$bin" --verify nothing
refuse render-verify-with-scene "$bin" --verify point point.scn
cd - > /dev/null

# 4. Designer options.  --resolution and --exposure override the camera
# line, --spp the render line; bad values are usage errors.
"$bin" "$tmp/point.scn" -o "$tmp/res" --resolution 12x7 --spp 2 --json > "$tmp/res.json" 2> /dev/null; rc=$?
check "--resolution 12x7 --json runs" test $rc -eq 0
python3 - "$tmp" <<'PY'
import json, sys
d = sys.argv[1]
j = json.load(open(d + "/res.json"))
assert j["image"]["width"] == 12 and j["image"]["height"] == 7, j["image"]
cam = [p for p in j["passes"] if p["name"] == "camera"][0]
assert "12 x 7 pixels, 2 samples per pixel" in cam["reason"], cam
assert j["sensors"][0]["name"] == "floor" and abs(j["sensors"][0]["illuminance_lx"] - 1000 / 9) < 1.2, j["sensors"]
assert d + "/res.png" in j["outputs"] and d + "/res.manifest.json" in j["outputs"], j["outputs"]
assert j["timings"]["render_seconds"] > 0 and j["glare"] is None and j["run_id"], j
m = json.load(open(d + "/res.manifest.json"))
assert m["run_id"] == j["run_id"], (m["run_id"], j["run_id"])
PY
check "--json: valid JSON with the image, sensors, outputs, timings and the run id" test $? -eq 0
refuse render-resolution-bad "$bin" "$tmp/point.scn" --resolution 0x10
refuse render-exposure-bad "$bin" "$tmp/point.scn" --exposure bright
refuse render-option-twice "$bin" "$tmp/point.scn" --spp 2 --spp 4
refuse render-spp-no-image "$bin" "$tmp/point.scn" --sensors-only --spp 4
refuse render-exposure-no-image "$bin" "$tmp/point.scn" --sensors-only --exposure 2
refuse render-stats-annual "$bin" "$tmp/year.scn" -o "$tmp/year2" --stats "$tmp/year2.json"
refuse render-output-folder-missing "$bin" "$tmp/year.scn" -o "$tmp/no/such/year"
refuse render-send-batch-alone "$bin" "$tmp/point.scn" --send-batch 16

# A grid's summary (Emin, Eavg, Emax, U0 = Emin/Eavg, Emin/Emax) in the text
# results and the JSON, recomputed here from the sensor table.
(cd "$tmp" && "$bin" boxes.scn --sensors-only -o grid > grid.txt 2> /dev/null && \
   "$bin" boxes.scn --sensors-only -o grid2 --json > grid.json 2> /dev/null); rc=$?
check "the grid scene renders (text and JSON)" test $rc -eq 0
python3 - "$tmp" <<'PY'
import csv, json, sys
d = sys.argv[1]
E = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/grid.sensors.csv")) if r["sensor"] == "floor"]
assert len(E) == 4
lo, avg, hi = min(E), sum(E) / len(E), max(E)
line = [l for l in open(d + "/grid.txt") if l.startswith("grid ")]
assert len(line) == 1, line
w = line[0].split()
val = lambda key: float(w[w.index(key) + 1])
for key, want in (("Emin", lo), ("Eavg", avg), ("Emax", hi)):
    assert abs(val(key) - want) <= 1e-5 * want, (key, val(key), want)
assert w[1] == "floor" and w[2] == "4" and w[3] == "points", w
assert abs(float(w[w.index("Emin/Eavg") + 1]) - lo / avg) <= 1e-3, w
assert abs(float(w[w.index("Emin/Emax") + 1]) - lo / hi) <= 1e-3, w
g = json.load(open(d + "/grid.json"))["grids"]
assert len(g) == 1 and g[0]["name"] == "floor" and g[0]["points"] == 4, g
E2 = [float(r["illuminance_lx"]) for r in csv.DictReader(open(d + "/grid2.sensors.csv"))]
lo, avg, hi = min(E2), sum(E2) / 4, max(E2)
for k, want in (("min_lx", lo), ("mean_lx", avg), ("max_lx", hi), ("u0", lo / avg), ("min_over_max", lo / hi)):
    assert abs(g[0][k] - want) <= 1e-7 * abs(want), (k, g[0][k], want)
PY
check "grid summary: Emin, Eavg, Emax, U0, Emin/Emax as the sensor table gives them" test $? -eq 0

# --exposure auto maps the log-average luminance to mid grey (PNG 118 with
# --tonemap clip): a dim lamp's render, near black at the camera's EV 0,
# comes near it; the default film curve lifts the mid-tones (0.18 becomes
# 0.267, PNG 141).
sed 's/intensity=1000cd/intensity=10cd/' "$tmp/point.scn" > "$tmp/dim.scn"
"$bin" "$tmp/dim.scn" -o "$tmp/dim0" --quiet && "$bin" "$tmp/dim.scn" -o "$tmp/dima" --exposure auto > "$tmp/dima.out" 2> /dev/null
check "--exposure auto runs" test $? -eq 0
check "--exposure auto is reported" grep -q "^image .*exposure +[0-9.]* EV (auto" "$tmp/dima.out"
"$bin" "$tmp/dim.scn" -o "$tmp/dimc" --exposure auto --tonemap clip --quiet
check "--tonemap clip runs" test $? -eq 0
python3 - "$tmp" <<'PY'
import struct, sys, zlib
def png_mean(path):
    b = open(path, "rb").read()
    assert b[:8] == b"\x89PNG\r\n\x1a\n"
    i, idat, w = 8, b"", 0
    while i < len(b):
        n, t = struct.unpack(">I4s", b[i:i + 8])
        c = b[i + 8:i + 8 + n]
        if t == b"IHDR":
            w, h, depth, ctype = struct.unpack(">IIBB", c[:10])
            ch = {0: 1, 2: 3, 6: 4}[ctype]
            assert depth == 8
        elif t == b"IDAT":
            idat += c
        i += 12 + n
    raw, stride, prev, vals = zlib.decompress(idat), w * ch, bytearray(w * ch), []
    for y in range(h):
        f, row = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for x in range(stride):
            a = row[x - ch] if x >= ch else 0
            up, c = prev[x], prev[x - ch] if x >= ch else 0
            if f == 1: row[x] = (row[x] + a) & 255
            elif f == 2: row[x] = (row[x] + up) & 255
            elif f == 3: row[x] = (row[x] + (a + up) // 2) & 255
            elif f == 4:
                p = a + up - c; pa, pb, pc = abs(p - a), abs(p - up), abs(p - c)
                row[x] = (row[x] + (a if pa <= pb and pa <= pc else up if pb <= pc else c)) & 255
        vals += [row[x] for x in range(stride) if ch < 4 or x % 4 != 3]
        prev = row
    return sum(vals) / len(vals)
d = sys.argv[1]
m0, ma, mc = png_mean(d + "/dim0.png"), png_mean(d + "/dima.png"), png_mean(d + "/dimc.png")
print(f"# PNG means: EV 0 {m0:.1f}, auto clip {mc:.1f}, auto filmic {ma:.1f}")
assert m0 < 20, m0
assert 90 <= mc <= 150, mc
assert mc + 10 <= ma <= mc + 40, (mc, ma)
PY
check "--exposure auto brings a dark render's PNG mean near mid grey (118 clipped); the film curve lifts it" test $? -eq 0

# --set NAME.state=S: one scene file for a tint study.  Errors name the
# material or the parameter.
refuse render-set-unknown-material "$bin" "$tmp/point.scn" --set glass.state=0.5
refuse render-set-unknown-parameter "$bin" "$tmp/point.scn" --set grey.tint=0.5
refuse render-set-state-range "$bin" "$tmp/point.scn" --set grey.state=1.5
refuse render-set-no-state "$bin" "$tmp/point.scn" --set grey.state=0.5
refuse render-set-twice "$bin" "$tmp/point.scn" --set grey.state=0.5 --set grey.state=0.6
sed 's/^render/material silver db:Ag\nsphere center=3,3,1 radius=0.2 material=silver\nrender/' "$tmp/point.scn" > "$tmp/ag.scn"
refuse render-set-not-chromogenic "$bin" "$tmp/ag.scn" --set silver.state=0.5
spectro="$VR_BIN/../fit/vr-spectro"
# vr-spectro is built in every configuration that runs this test
# (scripts/test.sh builds it in the one-process stage too).
check "vr-spectro is built beside vr-render" test -x "$spectro"
if [ -x "$spectro" ]; then
  "$spectro" chromogenic "$src/samples/glazing/electrochromic/ec_states.csv" --save ec > /dev/null 2>&1
  check "an electrochromic glass for the tint study" test $? -eq 0
  cat > "$tmp/tint.scn" <<'EOF'
material grey lambert reflectance=0.5
material ec db:ec state=0.2
rect center=0,0,0 normal=0,0,1 size=4,4 material=grey
rect center=0,0,1.5 normal=0,0,1 size=3,3 material=ec
light point position=0,0,3 intensity=1000cd
sensor under point position=0,0,0.01 normal=0,0,1
render integrator=path sensor_samples=256
EOF
  for st in 0 1; do
    "$bin" "$tmp/tint.scn" -o "$tmp/tint$st" --set "ec.state=$st" --quiet
  done
  sed 's/state=0.2/state=1/' "$tmp/tint.scn" > "$tmp/tint_one.scn"
  "$bin" "$tmp/tint_one.scn" -o "$tmp/tint_one" --quiet
  python3 - "$tmp" <<'PY'
import csv, sys
d = sys.argv[1]
E = lambda f: float(next(csv.DictReader(open(d + "/" + f + ".sensors.csv")))["illuminance_lx"])
e0, e1, one = E("tint0"), E("tint1"), E("tint_one")
assert e1 < 0.5 * e0, (e0, e1)
assert abs(e1 - one) <= 1e-9 * one, (e1, one)
PY
  check "--set ec.state: the coloured glass lets less light through, as state=1 in the file" test $? -eq 0
  # A charge beyond the fitted ones (Q_full of ec_states.csv is its most
  # coloured state's charge) has no state: refused, not clamped to state 1.
  sed 's/state=0.2/charge=500mC\/cm2/' "$tmp/tint.scn" > "$tmp/tint_charge.scn"
  refuse render-charge-above "$bin" "$tmp/tint_charge.scn" -o "$tmp/tint_charge" --quiet
else
  echo "# vr-spectro not built: the tint study with a fitted glass is skipped"
fi

# A UTF-8 byte order mark at the start of a scene file is not text.
printf '\357\273\277' | cat - "$tmp/point.scn" > "$tmp/bom.scn"
"$bin" "$tmp/bom.scn" -o "$tmp/bom" --sensors-only --quiet; rc=$?
check "a scene file starting with a UTF-8 BOM renders" test $rc -eq 0

finish
