#!/usr/bin/env bash
# Command-line tests of vr-rgb2spec: a simulated capture of the ColorChecker
# under four lights recovered by the three methods, the JSON shape, report,
# saving, and bad captures (a photo missing from the manifest, an unknown
# light, photos of different sizes, an unreadable photo).
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
check "unknown method" test $rc -eq 1

finish
