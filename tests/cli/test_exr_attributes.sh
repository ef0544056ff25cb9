#!/usr/bin/env bash
# What a viewer finds in the EXR files of a real vr-render run (read with
# the OpenEXR core library by vr-test-exr-attrs, not with ours):
#   PREFIX.exr and PREFIX.spectral.exr: chromaticities of linear sRGB
#     (ITU-R BT.709-6: red 0.640 0.330, green 0.300 0.600, blue 0.150
#     0.060, white D65 0.3127 0.3290), whiteLuminance 1 (the pixels are
#     cd/m²: RGB (1,1,1) has luminance 0.2126 + 0.7152 + 0.0722 = 1), and
#     exposure = camera EV - log2(100) (the PNG's display white is
#     100 cd/m² x 2^-EV, docs/vr-render.md);
#   PREFIX.spectral.exr: emissiveUnits "W.m^-2.sr^-1", the string of the
#     spectral layout's reference writer (and pbrt-v4's).
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
attrs="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-attrs"
source "$(dirname "$0")/harness.sh"

cat > "$tmp/lamp.scn" <<'EOF'
camera pinhole from=0,-6,4 to=0,0,0 up=0,0,1 fov=60 resolution=16x12 exposure=-2
material grey lambert reflectance=0.5
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
light point position=0,0,3 intensity=1000cd
render integrator=path spp=1 film=400,700,50
EOF
(cd "$tmp" && "$bin" lamp.scn --threads 2 --quiet > out.txt 2> log.txt); rc=$?
check "renders the scene" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/log.txt"

# "name v1 v2 ..." of the file's attribute name, each value within tol.
has() {
  local file=$1 name=$2 tol=$3; shift 3
  local line
  line=$("$attrs" "$tmp/$file" | awk -v n="$name" '$1 == n')
  [ -n "$line" ] || { echo "# $file: no $name"; return 1; }
  echo "# $file: $line"
  python3 - "$tol" "$line" "$@" <<'PY'
import sys
tol, got, want = float(sys.argv[1]), sys.argv[2].split()[1:], [float(v) for v in sys.argv[3:]]
sys.exit(0 if len(got) == len(want) and all(abs(float(g) - w) <= tol for g, w in zip(got, want)) else 1)
PY
}

for f in lamp.exr lamp.spectral.exr; do
  check "$f: chromaticities of BT.709 / D65" \
    has $f chromaticities 1e-7 0.640 0.330 0.300 0.600 0.150 0.060 0.3127 0.3290
  check "$f: whiteLuminance 1 cd/m2" has $f whiteLuminance 0 1
  check "$f: exposure EV - log2(100)" has $f exposure 1e-6 -8.64385619
done
check "lamp.spectral.exr: emissiveUnits of the reference" \
  test "$("$attrs" "$tmp/lamp.spectral.exr" | awk '$1 == "emissiveUnits" { print $2 }')" = "W.m^-2.sr^-1"
check "lamp.exr has no emissiveUnits" test -z "$("$attrs" "$tmp/lamp.exr" | awk '$1 == "emissiveUnits"')"

finish
