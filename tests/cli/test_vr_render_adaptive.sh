#!/usr/bin/env bash
# Command-line test of adaptive sampling (--target-error, --time-limit,
# --max-spp): the summary's adaptive line and the statistics' image.adaptive
# agree, the RGB EXR gains the layers samples.N and variance.Y (read back
# with OpenEXR's own reader, tests/support/exr_attrs.c), a time limit stops
# after the first round, and each refused use has its row in
# docs/bad-input.md.  The numbers themselves (unbiased means, honest
# variances) are checked against analytic scenes in
# tests/render/test_adaptive.c.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
attrs="$VR_TEST_BIN/vr-test-exr-attrs"
source "$(dirname "$0")/harness.sh"

# A floor under the CIE uniform sky (luminance 0.5 x 1000 / pi cd/m2) and,
# in the left half, a black emitter of 50 cd/m2 (only the wavelengths'
# noise there: its pixels stop after the first round); the sensor lies 50 m
# from the emitter, which then takes 1e-3 lx of its 1000 lx of sky.
cat > "$tmp/floor.scn" <<'EOF'
material floor lambert reflectance=0.5
material black lambert reflectance=0
rect center=0,0,0 normal=0,0,1 size=2000,2000 material=floor
rect center=-0.5,2,0.5 normal=0,-1,0 size=1,1 material=black emission=50cd/m2
sky cie type=5 illuminance=1000 ground=0
camera pinhole from=0,0,0.5 to=0,2,0.3 up=0,0,1 fov=60 resolution=32x24
sensor s point position=0,-50,0.01 normal=0,0,1
render integrator=path depth=3 spp=4 seed=5 sensor_samples=64
EOF
sed 's/integrator=path/integrator=bdpt/' "$tmp/floor.scn" > "$tmp/box.scn"
sed 's/sensor_samples=64/sensor_samples=64 sensors=photon photons=1000/' "$tmp/floor.scn" > "$tmp/photon.scn"

"$bin" "$tmp/floor.scn" -o "$tmp/a" --outputs exr --target-error 2% --max-spp 256 \
  --stats "$tmp/a.json" --threads 2 > "$tmp/a.out" 2> "$tmp/a.err"
check "adaptive render exits 0" test $? -eq 0
check "summary has the adaptive line" grep -q '^adaptive .* rounds, 8 to [0-9]* samples a pixel' "$tmp/a.out"
check "camera pass says its rounds" grep -q 'camera .* samples per pixel (mean .*rounds' "$tmp/a.out"
python3 - "$tmp/a.json" > "$tmp/a.py" 2>&1 <<'EOF'
import json, sys
a = json.load(open(sys.argv[1]))["image"]["adaptive"]
assert a["spp_first"] == 8, a            # two halves of spp=4
assert a["spp_min"] == 8 and a["spp_max"] <= 256, a
assert a["rounds"] >= 2 and 0 < a["converged_share"] <= 1, a
print("ok")
EOF
check "statistics hold image.adaptive: $(tail -1 "$tmp/a.py")" grep -qx ok "$tmp/a.py"
"$attrs" --channels "$tmp/a.exr" --values samples.N > "$tmp/ch.txt" 2>&1
check "EXR has samples.N (uint) and variance.Y (float)" \
  grep -q '^samples.N uint$' "$tmp/ch.txt"
check "EXR variance.Y is float" grep -q '^variance.Y float$' "$tmp/ch.txt"
check "EXR keeps R G B" grep -q '^R float$' "$tmp/ch.txt"
# The layer's counts are the statistics' (min, max, mean over the pixels).
python3 - "$tmp/a.json" "$tmp/ch.txt" > "$tmp/n.py" 2>&1 <<'EOF'
import json, sys
a = json.load(open(sys.argv[1]))["image"]["adaptive"]
row = [l.split() for l in open(sys.argv[2]) if l.startswith("samples.N ")]
name, lo, hi, mean = [r for r in row if len(r) == 4][0]
assert float(lo) == a["spp_min"] and float(hi) == a["spp_max"], (lo, hi, a)
assert abs(float(mean) - a["spp_mean"]) <= 1e-6 * a["spp_mean"], (mean, a)
print("ok", lo, hi, mean)
EOF
check "samples.N agrees with the statistics: $(tail -1 "$tmp/n.py")" grep -q '^ok' "$tmp/n.py"

# A time limit far below one round's time: the first round only.
"$bin" "$tmp/floor.scn" -o "$tmp/t" --outputs exr --time-limit 0.001 --stats "$tmp/t.json" \
  --threads 2 > "$tmp/t.out" 2> "$tmp/t.err"
check "time-limited render exits 0" test $? -eq 0
check "time limit: one round of 8 samples" grep -q '^adaptive 1 rounds, 8 to 8 samples a pixel.*stopped: time limit' "$tmp/t.out"
# Without adaptive sampling the EXR has R, G, B only.
"$bin" "$tmp/floor.scn" -o "$tmp/p" --outputs exr --threads 2 > /dev/null 2>&1
"$attrs" --channels "$tmp/p.exr" > "$tmp/pch.txt" 2>&1
check "plain EXR has no samples layer" test "$(grep -c . "$tmp/pch.txt")" = 3

refuse render-target-error-bad "$bin" "$tmp/floor.scn" -o "$tmp/x" --target-error 0
refuse render-target-error-bad "$bin" "$tmp/floor.scn" -o "$tmp/x" --target-error -1
refuse render-target-error-bad "$bin" "$tmp/floor.scn" -o "$tmp/x" --target-error nan
refuse render-target-error-bad "$bin" "$tmp/floor.scn" -o "$tmp/x" --target-error 60%
refuse render-time-limit-bad "$bin" "$tmp/floor.scn" -o "$tmp/x" --time-limit -5
refuse render-max-spp-below-first "$bin" "$tmp/floor.scn" -o "$tmp/x" --target-error 0.02 --max-spp 6
refuse render-max-spp-alone "$bin" "$tmp/floor.scn" -o "$tmp/x" --max-spp 64
refuse render-target-error-no-image "$bin" "$tmp/photon.scn" -o "$tmp/x" --sensors-only --target-error 0.02
refuse render-time-limit-no-image "$bin" "$tmp/floor.scn" -o "$tmp/x" --sensors-only --time-limit 60
annual_scene "$tmp/year.scn"
refuse render-target-error-annual "$bin" "$tmp/year.scn" -o "$tmp/x" --target-error 0.02

# Path sensors take rounds too: with --sensors-only, the sensor's rounds
# are said on stderr and its reading is the sky's 1000 lx within its error.
"$bin" "$tmp/floor.scn" -o "$tmp/s" --sensors-only --target-error 0.05 --json --threads 2 \
  > "$tmp/s.json" 2> "$tmp/s.err"
check "adaptive sensors exit 0" test $? -eq 0
check "sensor rounds said on stderr" grep -q 'sensors round 2: .* paths a point so far' "$tmp/s.err"
python3 - "$tmp/s.json" > "$tmp/s.py" 2>&1 <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))["sensors"][0]
# 1000 lx: the CIE uniform sky's horizontal illuminance (the sky line)
assert abs(s["illuminance_lx"] - 1000) <= 6 * s["stderr_lx"], s
assert s["stderr_lx"] <= 0.05 * s["illuminance_lx"], s
print("ok", s["illuminance_lx"], s["stderr_lx"])
EOF
check "adaptive sensor reads 1000 lx within its error: $(tail -1 "$tmp/s.py")" grep -q '^ok' "$tmp/s.py"
refuse render-target-error-integrator "$bin" "$tmp/box.scn" -o "$tmp/x" --target-error 0.02
check "refusals wrote nothing" test -z "$(ls "$tmp" | grep '^x\.')"
finish
