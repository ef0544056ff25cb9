#!/usr/bin/env bash
# Command-line tests of vr-rgb2spec: a simulated capture of the ColorChecker
# under four lights recovered by the three methods, the JSON shape, report,
# saving, and bad captures (a photo missing from the manifest, an unknown
# light, photos of different sizes, an unreadable photo); camera calibration
# from a simulated chart photo, saved and reused as "camera db:", and bad
# calibrations.
set -u
bin="$VR_BIN/vr-rgb2spec"
matdb="$VR_BIN/../matdb/vr-matdb"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

"$bin" --help | grep -q "^Usage: vr-rgb2spec PHOTOS"; check "--help" test $? -eq 0

# A capture made here: the chart and a brick under D65, A, a white LED and
# F11, 8-bit sRGB photos with the default noise (sigma 0.002 on linear values).
mkdir -p "$tmp/cap"
cat > "$tmp/cap/manifest.txt" <<EOF
camera cie1931-srgb
photo d65.png light=D65 scale=0.9
photo a.png light=A scale=0.5
photo led.png light=LED-B3 scale=0.75
photo f11.png light=F11 scale=0.75
chart grid=20,20,410,278
region brick rect=440,30,80,60 reference=file:$src/samples/photos/materials/brick_red.csv
EOF
"$bin" simulate --manifest "$tmp/cap/manifest.txt" --seed 3 2> "$tmp/sim.err"; rc=$?
check "simulate writes four photos" test $rc -eq 0 -a -f "$tmp/cap/f11.png"

"$bin" "$tmp"/cap/*.png --method matrix-r --json > "$tmp/mr.json"; rc=$?
check "matrix-r runs" test $rc -eq 0
python3 - "$tmp/mr.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["condition_number"] > 1
r = d["regions"]
assert len(r) == 25 and r[0]["name"] == "patch-01"
for x in r:
    assert set(["name", "deltaE00_mean", "deltaE00_max", "spectral_rmse", "spectrum"]) <= set(x)
    assert len(x["spectrum"]) == 31 and x["spectrum"][0][0] == 400
# Matrix R is an exact round trip (Cohen and Kappauf): every unclipped patch
# reproduces its photo within CIEDE2000 0.01.
exact = [x for x in r if "clipped" not in x["flags"]]
assert len(exact) >= 18, len(exact)
assert max(x["deltaE00_max"] for x in exact) < 0.01, [(x["name"], x["deltaE00_max"]) for x in exact]
PY
check "JSON shape; Matrix R round trip below 0.01 for unclipped patches" test $? -eq 0

"$bin" "$tmp"/cap/*.png --method bounded --json --report "$tmp/r.html" --save-prefix photo- > "$tmp/b.json"; rc=$?
check "bounded runs with a report and saving" test $rc -eq 0
python3 - "$tmp/b.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
for x in d["regions"]:
    assert all(-1e-9 <= v <= 1 + 1e-9 for _, v in x["spectrum"]), x["name"]
PY
check "bounded spectra lie in [0, 1]" test $? -eq 0
"$bin" "$tmp"/cap/*.png --json > "$tmp/auto.json"
python3 - "$tmp/auto.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["method"] == "regularised", d["method"]
rm = [x["spectral_rmse"] for x in d["regions"]]
assert len(rm) == 25 and None not in rm
# 8-bit photos, four lights: bench_rgb2spec gives a mean RMSE of 0.026 over
# the 24 patches for the regularised method (docs/benchmarks.md); allow 0.04.
assert sum(rm) / len(rm) < 0.04, sum(rm) / len(rm)
PY
check "auto picks the regularised method for 8-bit photos; spectra match the references" test $? -eq 0
check "report has plots" test "$(grep -o '<svg' "$tmp/r.html" | wc -l)" -eq 25
check "swatch image written" test -s "$tmp/r.html.swatch.png"
"$matdb" show photo-brick > "$tmp/show"
check "saved with provenance" grep -q "vr-rgb2spec" "$tmp/show"

# Bad captures.
cp "$tmp/cap/d65.png" "$tmp/cap/extra.png"
"$bin" "$tmp/cap/d65.png" "$tmp/cap/extra.png" 2> "$tmp/err" > /dev/null; rc=$?
check "a photo missing from the manifest" test $rc -eq 1 -a -n "$(grep 'extra.png is not listed' "$tmp/err")"
sed 's/light=F11/light=F99/' "$tmp/cap/manifest.txt" > "$tmp/cap/bad.txt"
"$bin" --manifest "$tmp/cap/bad.txt" 2> "$tmp/err" > /dev/null; rc=$?
check "an unknown light names manifest:line" test $rc -eq 1 -a -n "$(grep 'bad.txt:5:' "$tmp/err" | grep 'unknown light')"
mkdir -p "$tmp/small"
sed 's/^photo f11.png.*$//' "$tmp/cap/manifest.txt" > "$tmp/small/manifest.txt"
echo "photo f11.png light=F11 scale=0.75" >> "$tmp/small/manifest.txt"
( cd "$tmp/small" && "$bin" simulate --manifest manifest.txt --size 500x300 --noise 0 2>/dev/null )
cp "$tmp/cap/d65.png" "$tmp/cap/a.png" "$tmp/cap/led.png" "$tmp/small/"
"$bin" --manifest "$tmp/small/manifest.txt" 2> "$tmp/err" > /dev/null; rc=$?
check "photos of different sizes" test $rc -eq 1 -a -n "$(grep 'same size' "$tmp/err")"
echo "not a png" > "$tmp/cap/led.png"
"$bin" --manifest "$tmp/cap/manifest.txt" 2> "$tmp/err" > /dev/null; rc=$?
check "an unreadable photo names the file" test $rc -eq 1 -a -n "$(grep 'led.png' "$tmp/err")"
"$bin" "$tmp/cap/d65.png" --method best 2> /dev/null > /dev/null; rc=$?
check "unknown method (a usage error)" test $rc -eq 2

# Camera calibration.  A real camera (the Nikon D5100 measured by Darrodi et
# al., JOSA A 2015) photographs the chart under D65 and A; calibrate from the
# D65 photo, save, and recover with "camera db:" as well as with the true
# curves.
mkdir -p "$tmp/cal"
cat > "$tmp/cal/manifest.txt" <<MANIFEST
camera file:$src/tests/data/camera_nikon_d5100_darrodi2015.csv
photo d65.png light=D65 scale=0.9
photo a.png light=A scale=0.5
chart grid=20,20,410,278
region brick rect=440,30,80,60 reference=file:$src/samples/photos/materials/brick_red.csv
MANIFEST
"$bin" simulate --manifest "$tmp/cal/manifest.txt" --seed 5 2> /dev/null
"$bin" calibrate "$tmp/cal/d65.png" --light D65 --save nikon-cal --json > "$tmp/cal.json" 2> "$tmp/cal.err"; rc=$?
check "calibrate finds the chart, fits and saves" test $rc -eq 0 -a -n "$(grep 'saved camera nikon-cal' "$tmp/cal.err")"
python3 - "$tmp/cal.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert d["saved"] == "nikon-cal" and d["used_patches"] == 24 and d["clipped_patches"] == 0
ch = d["channels"]
assert [c["tone"] for c in ch] == ["srgb"] * 3, [c["tone"] for c in ch]
# Darrodi et al.: peaks at 595, 530 and 460 nm; the 10 nm estimate within 20 nm.
for c, peak in zip(ch, (595, 530, 460)):
    assert abs(c["peak_nm"] - peak) <= 20, (c["channel"], c["peak_nm"])
    assert c["lambda"] > 0 and 2 < c["dof"] < 24 and c["rms"] < 0.003
s = d["sensitivities"]
assert len(s) == 31 and s[0][0] == 400 and s[-1][0] == 700
assert max(x[2] for x in s) == 1.0 and min(min(x[1:]) for x in s) >= 0
PY
check "calibration: sRGB curves, peaks within 20 nm, green peak 1" test $? -eq 0
"$matdb" show nikon-cal > "$tmp/show"
check "saved camera carries its linearisation and provenance" \
  test -n "$(grep 'linearisation_g *srgb' "$tmp/show")" -a -n "$(grep 'vr-rgb2spec calibrate' "$tmp/show")"
"$bin" calibrate "$tmp/cal/d65.png" --light "$src/core/data/cie_d65.csv" --chart grid=20,20,410,278 > "$tmp/cal.txt"; rc=$?
check "calibrate with an SPD file and a placed chart; text table" \
  test $rc -eq 0 -a -n "$(grep '^green  *srgb' "$tmp/cal.txt")" -a "$(grep -c '^ *[4-7][0-9]0 ' "$tmp/cal.txt")" -eq 31
sed 's#^camera .*#camera db:nikon-cal#' "$tmp/cal/manifest.txt" > "$tmp/cal/db.txt"
"$bin" --manifest "$tmp/cal/manifest.txt" --json > "$tmp/true.json" && "$bin" --manifest "$tmp/cal/db.txt" --json > "$tmp/db.json"; rc=$?
python3 - "$tmp/true.json" "$tmp/db.json" <<'PY'
import json, sys
rm = [json.load(open(f))["regions"] for f in sys.argv[1:]]
m = [sum(x["spectral_rmse"] for x in r) / len(r) for r in rm]
# The calibrated camera recovers the spectra as well as the true one.
assert abs(m[1] - m[0]) < 0.005, m
PY
check "recovery with camera db:NAME matches the true camera" test $rc -eq 0 -a $? -eq 0

# A stored power-law curve is used both ways: simulate encodes with it, the
# recovery decodes with it, and calibrate finds it again.
"$bin" calibrate "$tmp/cal/d65.png" --light D65 --chart grid=20,20,410,278 --tone gamma=2.2 \
  --save gamma-cam > /dev/null 2>&1
mkdir -p "$tmp/gam"
sed 's#^camera .*#camera db:gamma-cam#' "$tmp/cal/manifest.txt" > "$tmp/gam/manifest.txt"
"$bin" simulate --manifest "$tmp/gam/manifest.txt" --seed 6 2> /dev/null
"$bin" calibrate "$tmp/gam/d65.png" --light D65 --chart grid=20,20,410,278 --json > "$tmp/gam.json"; rc=$?
python3 - "$tmp/gam.json" <<'PY'
import json, sys
for c in json.load(open(sys.argv[1]))["channels"]:
    assert c["tone"].startswith("gamma "), c["tone"]
    assert abs(float(c["tone"].split()[1]) - 2.2) < 0.05, c["tone"]
PY
check "a gamma-2.2 camera's photos: calibrate finds gamma 2.2 within 0.05" test $rc -eq 0 -a $? -eq 0
"$bin" --manifest "$tmp/gam/manifest.txt" --json > "$tmp/gamrec.json"
python3 - "$tmp/true.json" "$tmp/gamrec.json" <<'PY'
import json, sys
rm = [json.load(open(f))["regions"] for f in sys.argv[1:]]
m = [sum(x["spectral_rmse"] for x in r) / len(r) for r in rm]
de = [sum(x["deltaE00_mean"] for x in r) / len(r) for r in rm]
assert abs(m[1] - m[0]) < 0.01, m
# Round-trip CIEDE2000 is what the decoding shows in: measured 0.74 for the
# sRGB photos, 0.78 for the gamma photos decoded with the stored curve, and
# 1.30 when they are (wrongly) decoded as sRGB.
assert abs(de[1] - de[0]) < 0.2, de
PY
check "the recovery decodes with the stored gamma" test $? -eq 0

# Bad calibrations: a clear error naming the file, exit 1, no database row.
echo "not a png" > "$tmp/cal/broken.png"
"$bin" calibrate "$tmp/cal/broken.png" --light D65 --save bad-1 2> "$tmp/err" > /dev/null; rc=$?
check "calibrate: an unreadable photo is named" test $rc -eq 1 -a -n "$(grep 'broken.png' "$tmp/err")"
"$bin" calibrate "$tmp/cal/d65.png" --light D99X --save bad-2 2> "$tmp/err" > /dev/null; rc=$?
check "calibrate: an unknown light is named" test $rc -eq 1 -a -n "$(grep 'light D99X' "$tmp/err")"
mkdir -p "$tmp/nochart"
printf 'photo blank.png light=D65\nregion brick rect=40,30,80,60 reference=file:%s\n' \
  "$src/samples/photos/materials/brick_red.csv" > "$tmp/nochart/manifest.txt"
"$bin" simulate --manifest "$tmp/nochart/manifest.txt" 2> /dev/null
"$bin" calibrate "$tmp/nochart/blank.png" --light D65 --save bad-3 2> "$tmp/err" > /dev/null; rc=$?
check "calibrate: no chart in the photo" test $rc -eq 1 -a -n "$(grep 'blank.png: no ColorChecker' "$tmp/err")"
"$bin" calibrate "$tmp/cal/d65.png" --light D65 --chart grid=5,5 --save bad-4 2> "$tmp/err" > /dev/null; rc=$?
check "calibrate: a malformed chart grid" test $rc -eq 1 -a -n "$(grep -- '--chart' "$tmp/err")"
for n in 1 2 3 4; do "$matdb" show "bad-$n" > /dev/null 2>&1 && echo "bad-$n was saved"; done > "$tmp/rows"
check "calibrate: no database row after a failure" test ! -s "$tmp/rows"
"$bin" calibrate "$tmp/cal/d65.png" 2> /dev/null; rc=$?
check "calibrate: --light is required" test $rc -eq 2
"$bin" --help | grep -q "vr-rgb2spec calibrate PHOTO"; check "--help names calibrate" test $? -eq 0

# Per-pixel mode: a spectral EXR in the Fichet et al. 2021 layout (reflective
# channels T.<nm>nm, JCGT 10(3) and afichet/spectral-exr), referenced from the
# database by a material whose 'texture' property is its absolute path.
photos="$src/samples/photos"
"$bin" "$photos"/d65.png "$photos"/a.png --per-pixel "$tmp/tex.exr" --texture photo-tex > "$tmp/pp" 2> "$tmp/err"; rc=$?
check "per-pixel: exit 0" test $rc -eq 0
check "per-pixel: the EXR exists" test -s "$tmp/tex.exr"
check "per-pixel: reflective channel names of the 400-700 nm grid" \
  test -n "$(grep -a -o 'T.400,000000nm' "$tmp/tex.exr" | head -1)" -a -n "$(grep -a -o 'T.700,000000nm' "$tmp/tex.exr" | head -1)"
check "per-pixel: the summary counts 640 x 480 pixels" test -n "$(grep 'per-pixel: 307200 pixels' "$tmp/pp")"
"$matdb" show photo-tex --json > "$tmp/tex.json" 2>&1
python3 - "$tmp/tex.json" "$tmp/tex.exr" <<'PY'
import json, os, sys
m = json.load(open(sys.argv[1]))
props = {p["key"]: p for p in m["properties"]}
assert os.path.samefile(props["texture"]["text"], sys.argv[2]), props["texture"]
assert len(props["texture_sha256"]["text"]) == 64
PY
check "per-pixel: the database row references the EXR" test $? -eq 0
"$bin" "$photos"/d65.png --texture x 2> "$tmp/err" > /dev/null; rc=$?
check "per-pixel: --texture alone is refused (a usage error)" test $rc -eq 2 -a -n "$(grep -- '--per-pixel' "$tmp/err")"
"$bin" "$photos"/d65.png --per-pixel "$tmp/no/such/dir/t.exr" --texture bad-tex 2> "$tmp/err" > /dev/null; rc=$?
check "per-pixel: an unwritable output is an error" test $rc -eq 1 -a -n "$(grep 'no/such/dir' "$tmp/err")"
"$matdb" show bad-tex > /dev/null 2>&1; rc=$?
check "per-pixel: no database row after a failed write" test $rc -ne 0

# ---- Noise-aware recovery, honest reports, light checks, textures -----
# (a fresh copy of the capture: the bad-capture tests above broke led.png)
mkdir -p "$tmp/c2"
cp "$tmp/cap/manifest.txt" "$tmp/c2/manifest.txt"
"$bin" simulate --manifest "$tmp/c2/manifest.txt" --seed 3 2> /dev/null

# 16-bit linear photos (a raw converter's output; simulate writes 16-bit PNG
# for encoding=linear), sigma 0.002 per pixel, four lights: the issue's
# target for the patch recovery is a mean RMSE <= 0.02 over the chart (the
# BabelColor spectra); measured 0.0186 with the measured-noise regularised
# method, against 0.0331 for the bounded method's exact fit.
mkdir -p "$tmp/lin"
sed -e 's/^\(photo .*\)$/\1 encoding=linear/' "$tmp/cap/manifest.txt" > "$tmp/lin/manifest.txt"
"$bin" simulate --manifest "$tmp/lin/manifest.txt" --seed 3 2> /dev/null
"$bin" --manifest "$tmp/lin/manifest.txt" --json > "$tmp/lin.json" 2> "$tmp/err"; rc=$?
python3 - "$tmp/lin.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
r = [x["spectral_rmse"] for x in d["regions"] if x["name"].startswith("patch")]
assert len(r) == 24 and sum(r) / 24 <= 0.02, sum(r) / 24
PY
check "16-bit linear photos: chart RMSE <= 0.02, exit 0" test $? -eq 0 -a $rc -eq 0

# Lights given by file are still used lights: the CIE D65 table as a CSV
# (core/data/cie_d65.csv, CIE 015:2018) leaves D65 out of the held-out list.
mkdir -p "$tmp/fl"
cp "$tmp/c2/d65.png" "$tmp/c2/a.png" "$tmp/fl/"
cat > "$tmp/fl/manifest.txt" <<MANIFEST
photo d65.png light=file:$src/core/data/cie_d65.csv scale=0.9
photo a.png light=A scale=0.5
chart grid=20,20,410,278
MANIFEST
"$bin" --manifest "$tmp/fl/manifest.txt" --json > "$tmp/fl.json" 2> "$tmp/err"
python3 - "$tmp/fl.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
assert "D65" not in d["heldout_lights"] and "A" not in d["heldout_lights"], d["heldout_lights"]
assert "D50" in d["heldout_lights"], d["heldout_lights"]
PY
check "held-out lights leave out a light given as file: (same spectrum as D65)" test $? -eq 0

# CIEDE2000 against the photo only where the photo holds a colour: a light
# with a clipped channel is null per light and left out of mean and max.
python3 - "$tmp/auto.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
seen = 0
for x in d["regions"]:
    per = x["per_light"]
    ok = [p["deltaE00"] for p in per if not any(p["clipped"])]
    for p in per:
        if any(p["clipped"]):
            assert p["deltaE00"] is None, (x["name"], p)
            seen += 1
    if ok:
        assert abs(max(ok) - x["deltaE00_max"]) < 1e-12, x["name"]
        assert abs(sum(ok) / len(ok) - x["deltaE00_mean"]) < 1e-12, x["name"]
    assert x["lights_left_out_for_clipping"] == len(per) - len(ok)
    # the noise of each mean response is reported and positive
    assert all(s > 0 for p in per for s in p["noise_rgb"])
assert seen > 0, "the capture has clipped patches (blue, cyan, white)"
PY
check "dE00 on unclipped lights only; clipped light-region pairs reported apart" test $? -eq 0

# Two photos' lights swapped (D65 <-> A, exposures kept): each is predicted
# from the others and misses by far more than metamerism allows; warned,
# exit 1, nothing saved without --force.
mkdir -p "$tmp/sw"
cp "$tmp/c2/"*.png "$tmp/sw/"
sed -e 's/light=D65/light=XX/; s/light=A /light=D65 /; s/light=XX/light=A/' "$tmp/c2/manifest.txt" > "$tmp/sw/manifest.txt"
"$bin" --manifest "$tmp/sw/manifest.txt" --json --save-prefix swapped- > "$tmp/sw.json" 2> "$tmp/err"; rc=$?
check "swapped lights: exit 1" test $rc -eq 1
check "swapped lights: the photo and its light are named" \
  test -n "$(grep 'manifest.txt:2: photo .*d65.png does not look lit by A' "$tmp/err")"
python3 - "$tmp/sw.json" "$tmp/auto.json" <<'PY'
import json, sys
sw, good = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
assert sw["light_suspect"][0] and sw["light_suspect"][1], sw["light_check_deltaE00"]
# the right lights pass with a wide margin (median dE00 below 1, limit 6)
assert not any(good["light_suspect"]) and max(good["light_check_deltaE00"]) < 2, good["light_check_deltaE00"]
PY
check "swapped lights: both photos suspect; the true lights are not" test $? -eq 0
"$matdb" show swapped-brick > /dev/null 2>&1; rc=$?
check "swapped lights: nothing saved without --force" test $rc -ne 0
"$bin" --manifest "$tmp/sw/manifest.txt" --save-prefix swapped- --force > /dev/null 2>&1; rc=$?
"$matdb" show swapped-brick > /dev/null 2>&1; rc2=$?
check "swapped lights: --force saves and exits 0" test $rc -eq 0 -a $rc2 -eq 0

# A surface no reflectance can explain (flat 1.3: fluorescent, or a
# specular highlight): flagged misfit, exit 1; its neighbours are not.
mkdir -p "$tmp/glow"
printf 'nm,value\n380,1.3\n780,1.3\n' > "$tmp/glow/glow.csv"
cat > "$tmp/glow/manifest.txt" <<MANIFEST
photo d65.png light=D65 scale=0.6
photo a.png light=A scale=0.33
photo led.png light=LED-B3 scale=0.5
photo f11.png light=F11 scale=0.5
region glow rect=20,20,60,60 reference=file:glow.csv
region brick rect=100,20,60,60 reference=file:$src/samples/photos/materials/brick_red.csv
region pine rect=180,20,60,60 reference=file:$src/samples/photos/materials/wood_pine.csv
MANIFEST
"$bin" simulate --manifest "$tmp/glow/manifest.txt" --size 260x100 2> /dev/null
"$bin" --manifest "$tmp/glow/manifest.txt" --json > "$tmp/glow.json" 2> "$tmp/err"; rc=$?
check "misfit: exit 1 and the region named" test $rc -eq 1 -a -n "$(grep 'region glow: the recovered spectrum misses' "$tmp/err")"
python3 - "$tmp/glow.json" <<'PY'
import json, sys
r = {x["name"]: x for x in json.load(open(sys.argv[1]))["regions"]}
assert r["glow"]["misfit"] and "misfit" in r["glow"]["flags"]
assert not r["brick"]["misfit"] and not r["pine"]["misfit"]
assert r["glow"]["chi2"] > r["glow"]["chi2_limit"]
PY
check "misfit: only the impossible region is flagged" test $? -eq 0

# Per-pixel texture of the simulated chart: the regularised operator with
# the bounds; RMSE against the true reflectance <= 0.06 (the issue's target)
# and a flags channel.
"$bin" --manifest "$tmp/c2/manifest.txt" --per-pixel "$tmp/cap.exr" > "$tmp/pp2" 2> "$tmp/err"; rc=$?
check "per-pixel: regularised texture written" test $rc -eq 0 -a -s "$tmp/cap.exr"
rmse=$(sed -n 's/.*against the references RMSE \([0-9.]*\).*/\1/p' "$tmp/pp2")
check "per-pixel: RMSE against the references <= 0.06 (got $rmse)" python3 -c "import sys; sys.exit(0 if float('$rmse') <= 0.06 else 1)"
check "per-pixel: the EXR carries the flags channel and its meaning" \
  test "$(grep -a -c 'flagsMeaning' "$tmp/cap.exr")" -ge 1
check "per-pixel: clipped and bounded pixels counted" test -n "$(grep -E 'bounded to \[0, 1\], [0-9.]+ % with clipped channels' "$tmp/pp2")"
"$bin" --manifest "$tmp/c2/manifest.txt" --per-pixel "$tmp/cap2.exr" --exr-compression lzma 2> "$tmp/err" > /dev/null; rc=$?
check "per-pixel: an unknown compression is refused (a usage error)" test $rc -eq 2 -a -n "$(grep -i 'lzma' "$tmp/err")"
"$bin" --manifest "$tmp/c2/manifest.txt" --lambda-rule magic 2> "$tmp/err" > /dev/null; rc=$?
check "an unknown lambda rule is refused" test $rc -eq 1 -a -n "$(grep 'magic' "$tmp/err")"

# A db: lookup without a database must not create one in the working
# directory.
mkdir -p "$tmp/nodb"
cp "$tmp/c2/d65.png" "$tmp/nodb/"
printf 'photo d65.png light=D65\nregion x rect=1,1,4,4 reference=db:nothing\n' > "$tmp/nodb/manifest.txt"
( cd "$tmp/nodb" && env -u VR_MATDB "$bin" --manifest manifest.txt > /dev/null 2> "$tmp/err" ); rc=$?
check "db: lookup without a database: error, no ./materials.db created" test $rc -eq 1 -a ! -e "$tmp/nodb/materials.db"

finish
