#!/usr/bin/env bash
# Command-line test of the display denoiser (--denoise): the EXR keeps the
# film and gains the feature layers albedo (R, G, B), normal (X, Y, Z) and
# nearness (V), read back with OpenEXR's own reader
# (tests/support/exr_attrs.c); the statistics record the denoise pass; the
# image and the features are the same for any sub-domains, threads and
# image space; adaptive sampling and denoising go together; and each
# refused use has its row in docs/bad-input.md.  The filter's numbers
# (error against the truth, edges kept) are checked against analytic
# images in tests/render/test_denoise.c.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
attrs="$VR_TEST_BIN/vr-test-exr-attrs"
cmp="$VR_TEST_BIN/vr-test-exr-compare"
source "$(dirname "$0")/harness.sh"

# Two halves of a floor, reflectances 0.2 and 0.8, under the CIE uniform
# sky (CIE S 011/E:2003 type 5): the albedo layer must read 0.2 and 0.8
# (a Lambertian surface's), the normal (0, 0, 1).
cat > "$tmp/floor.scn" <<'EOF'
material dark lambert reflectance=0.2
material light lambert reflectance=0.8
rect center=-500,0,0 normal=0,0,1 size=1000,2000 material=dark
rect center=500,0,0 normal=0,0,1 size=1000,2000 material=light
sky cie type=5 illuminance=1000 ground=0
camera pinhole from=0,0,1 to=0,0.5,0 up=0,0,1 fov=60 resolution=32x24 filter=box
sensor s point position=0,-50,0.01 normal=0,0,1
render integrator=path depth=3 spp=4 seed=5 sensor_samples=64
EOF

"$bin" "$tmp/floor.scn" -o "$tmp/a" --outputs exr,png --denoise --stats "$tmp/a.json" \
  --threads 2 > "$tmp/a.out" 2> "$tmp/a.err"
check "denoised render exits 0" test $? -eq 0
check "the PNG is written" test -s "$tmp/a.png"
check "the denoise pass is said" grep -q '^pass *denoise .*feature-guided non-local means' "$tmp/a.out"
python3 - "$tmp/a.json" > "$tmp/a.py" 2>&1 <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
d = [p for p in s["passes"] if p["name"] == "denoise"]
assert len(d) == 1 and d[0]["ran"] and d[0]["seconds"] >= 0, s["passes"]
print("ok")
EOF
check "statistics list the denoise pass: $(tail -1 "$tmp/a.py")" grep -qx ok "$tmp/a.py"
"$attrs" --channels "$tmp/a.exr" --values albedo.R > "$tmp/ch.txt" 2>&1
for c in R G B albedo.R albedo.G albedo.B normal.X normal.Y normal.Z nearness.V; do
  check "EXR has float channel $c" grep -q "^$c float\$" "$tmp/ch.txt"
done
python3 - "$tmp/ch.txt" > "$tmp/alb.py" 2>&1 <<'EOF'
import sys
row = [l.split() for l in open(sys.argv[1]) if l.startswith("albedo.R ") and len(l.split()) == 4][0]
lo, hi = float(row[1]), float(row[2])
# 0.2 and 0.8: the reflectances (float in the file).
assert abs(lo - 0.2) < 1e-6 and abs(hi - 0.8) < 1e-6, row
print("ok", lo, hi)
EOF
check "albedo.R spans the reflectances 0.2 and 0.8: $(tail -1 "$tmp/alb.py")" grep -q '^ok' "$tmp/alb.py"
"$attrs" --channels "$tmp/a.exr" --values normal.Z > "$tmp/nz.txt" 2>&1
check "normal.Z is 1 everywhere (a floor)" grep -q '^normal.Z 1 1 1$' "$tmp/nz.txt"

# The same image and features for other sub-domains, threads and image
# space (the features are sums, as the film).
"$bin" "$tmp/floor.scn" -o "$tmp/b" --outputs exr --denoise --subdomains 4 --threads 1 > /dev/null 2>&1
check "4 sub-domains, 1 thread: exits 0" test $? -eq 0
"$cmp" "$tmp/a.exr" "$tmp/b.exr" > /dev/null
check "4 sub-domains: the same film" test $? -eq 0
"$bin" "$tmp/floor.scn" -o "$tmp/c" --outputs exr --denoise --image-space --threads 2 > /dev/null 2>&1
"$cmp" "$tmp/a.exr" "$tmp/c.exr" > /dev/null
check "image space: the same film" test $? -eq 0
for layer in albedo.G normal.Y nearness.V; do
  a=$("$attrs" --channels "$tmp/a.exr" --values $layer | grep "^$layer [-0-9]")
  b=$("$attrs" --channels "$tmp/b.exr" --values $layer | grep "^$layer [-0-9]")
  c=$("$attrs" --channels "$tmp/c.exr" --values $layer | grep "^$layer [-0-9]")
  check "$layer the same for any sub-domains and image space ($a)" test "$a" = "$b" -a "$a" = "$c"
done

# With adaptive sampling: both the samples and the feature layers.
"$bin" "$tmp/floor.scn" -o "$tmp/d" --outputs exr,png --denoise --target-error 5% --max-spp 64 \
  --threads 2 > /dev/null 2>&1
check "adaptive and denoised: exits 0" test $? -eq 0
"$attrs" --channels "$tmp/d.exr" > "$tmp/dch.txt" 2>&1
check "adaptive and denoised: samples.N and albedo.R" \
  sh -c "grep -q '^samples.N uint\$' '$tmp/dch.txt' && grep -q '^albedo.R float\$' '$tmp/dch.txt'"

# SPPM denoised: two chains of spp/2 iterations; the variance layer too,
# and the same film for any sub-domains (as every integrator's).
cat > "$tmp/furnace.scn" <<'EOF'
material wall lambert reflectance=0.5
rect center=0,0,-1 normal=0,0,1 size=2,2 material=wall emission=100cd/m2
rect center=0,0,1 normal=0,0,-1 size=2,2 material=wall emission=100cd/m2
rect center=-1,0,0 normal=1,0,0 size=2,2 material=wall emission=100cd/m2
rect center=1,0,0 normal=-1,0,0 size=2,2 material=wall emission=100cd/m2
rect center=0,-1,0 normal=0,1,0 size=2,2 material=wall emission=100cd/m2
rect center=0,1,0 normal=0,-1,0 size=2,2 material=wall emission=100cd/m2
camera pinhole from=0,0,0 to=0,1,0 fov=60 resolution=16x12 filter=box
render integrator=progressive spp=4 photons=5000 depth=16 seed=3
EOF
"$bin" "$tmp/furnace.scn" -o "$tmp/p" --outputs exr,png --denoise --threads 2 > "$tmp/p.out" 2>&1
check "progressive, denoised: exits 0" test $? -eq 0
check "progressive, denoised: two chains said" grep -q '2 independent chains (the denoiser.s halves) of 2 iterations' "$tmp/p.out"
"$attrs" --channels "$tmp/p.exr" > "$tmp/pch.txt" 2>&1
check "progressive, denoised: variance.Y and albedo.R, no samples.N" \
  sh -c "grep -q '^variance.Y float\$' '$tmp/pch.txt' && grep -q '^albedo.R float\$' '$tmp/pch.txt' && ! grep -q '^samples.N' '$tmp/pch.txt'"
"$bin" "$tmp/furnace.scn" -o "$tmp/q" --outputs exr --denoise --threads 1 --subdomains 4 > /dev/null 2>&1
"$cmp" "$tmp/p.exr" "$tmp/q.exr" > /dev/null
check "progressive, denoised, 4 sub-domains: the same film" test $? -eq 0

sed 's/integrator=path/integrator=bdpt/' "$tmp/floor.scn" > "$tmp/box.scn"
refuse render-denoise-integrator "$bin" "$tmp/box.scn" -o "$tmp/x" --denoise
refuse render-denoise-odd-spp "$bin" "$tmp/floor.scn" -o "$tmp/x" --denoise --spp 5
refuse render-denoise-no-image "$bin" "$tmp/floor.scn" -o "$tmp/x" --denoise --sensors-only
refuse render-denoise-flow-profile "$bin" "$tmp/floor.scn" -o "$tmp/x" --denoise --stats "$tmp/x.json" \
  --flow-profile --threads 1
annual_scene "$tmp/year.scn"
refuse render-denoise-annual "$bin" "$tmp/year.scn" -o "$tmp/x" --denoise
check "nothing written by the refused runs" sh -c "! ls '$tmp'/x.* 2>/dev/null | grep -q ."
finish
