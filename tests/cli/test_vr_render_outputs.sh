#!/usr/bin/env bash
# Command-line test of vr-render's choice of outputs (--outputs) and of
# OpenCV kept out of it: each choice writes exactly its files and the
# manifest, which lists them and passes --verify; every refused list has
# its row in docs/bad-input.md; vr-render's ELF needs no OpenCV, a run
# without a PNG never loads it, a run with one loads the module vr-image-cv
# (from $VR_IMAGE_CV_MODULE, beside the program, or the build) and writes
# the PNG.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
module="$VR_IMAGE_CV"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

cat > "$tmp/point.scn" <<'EOF'
camera pinhole from=0,-6,4 to=0,0,0 up=0,0,1 fov=60 resolution=32x24
material grey lambert reflectance=0.5
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
light point position=0,0,3 intensity=1000cd
sensor floor point position=0,0,0 normal=0,0,1
render integrator=path spp=2 sensor_samples=64
EOF
grep -v '^sensor' "$tmp/point.scn" > "$tmp/nosensor.scn"
grep -v '^camera' "$tmp/point.scn" > "$tmp/nocamera.scn"
annual_scene "$tmp/year.scn"

# The files of a folder, sorted, space-separated.
files_in() { (cd "$1" && ls | sort | tr '\n' ' '); }
# The names the manifest lists, sorted, space-separated.
manifest_names() {
  python3 -c 'import json, sys; print(" ".join(sorted(f["name"] for f in json.load(open(sys.argv[1]))["files"])) + " ")' "$1"
}

"$bin" --help > "$tmp/help" 2>&1
check "--help lists --outputs and its names" grep -q -- "--outputs LIST.*exr, spectral, png, hdr, sensors" "$tmp/help"

# Each choice: exactly its files and the manifest, which lists them and
# passes --verify.
n=0
for choice in exr spectral png sensors exr,sensors spectral,png png,exr,spectral,sensors hdr exr,hdr; do
  n=$((n + 1))
  d="$tmp/o$n"
  mkdir "$d"
  "$bin" "$tmp/point.scn" -o "$d/p" --outputs "$choice" --cache "$tmp/cache" --threads 1 \
    > "$d.out" 2> "$d.err"; rc=$?
  check "--outputs $choice exits 0" test $rc -eq 0
  want=""
  for name in exr spectral png hdr sensors; do
    case ",$choice," in *",$name,"*)
      case $name in
        exr) want="$want p.exr" ;;
        spectral) want="$want p.spectral.exr" ;;
        png) want="$want p.png" ;;
        hdr) want="$want p.hdr" ;;
        sensors) want="$want p.sensors.csv" ;;
      esac ;;
    esac
  done
  listed=$(echo $want | tr ' ' '\n' | sort | tr '\n' ' ')
  all=$(echo $want p.manifest.json | tr ' ' '\n' | sort | tr '\n' ' ')
  check "--outputs $choice writes exactly $all" test "$(files_in "$d")" = "$all"
  check "--outputs $choice: the manifest lists exactly $listed" \
    test "$(manifest_names "$d/p.manifest.json")" = "$listed"
  check "--outputs $choice: the summary's wrote line lists them" \
    grep -q "^wrote .*p.manifest.json" "$d.out"
  "$bin" --verify "$d/p" > /dev/null 2>&1; rc=$?
  check "--outputs $choice: --verify passes" test $rc -eq 0
done
# The files themselves: an EXR, a PNG of the camera's size, a table.
check "the EXR is an OpenEXR file" test "$(head -c 4 "$tmp/o1/p.exr" | od -An -tx1 | tr -d ' ')" = 762f3101
python3 - "$tmp/o3/p.png" <<'PY'
import struct, sys
b = open(sys.argv[1], "rb").read()
assert b[:8] == b"\x89PNG\r\n\x1a\n" and b[12:16] == b"IHDR", b[:16]
assert struct.unpack(">II", b[16:24]) == (32, 24), struct.unpack(">II", b[16:24])
PY
check "--outputs png writes a 32 x 24 PNG" test $? -eq 0
check "--outputs sensors writes the table" grep -q "^floor,0,0," "$tmp/o4/p.sensors.csv"
# The Radiance picture (docs/vr-render.md, "Radiance pictures"): its
# header as Radiance's tools read it, the camera's view.
check "--outputs hdr writes a Radiance picture" test "$(head -n 1 "$tmp/o8/p.hdr")" = "#?RADIANCE"
check "the picture's format line" grep -aq "^FORMAT=32-bit_rle_rgbe$" "$tmp/o8/p.hdr"
check "the picture's view: the pinhole's, 60 degrees across" \
  grep -aq "^VIEW= -vtv -vp 0 -6 4 .* -vh 60 -vv 46.826" "$tmp/o8/p.hdr"
check "the picture's resolution line" grep -aq "^-Y 24 +X 32$" "$tmp/o8/p.hdr"
# The files do not depend on which others are written: a full run's are
# the same, byte for byte (one thread, so that the film's sums are added in
# one order).
mkdir "$tmp/all"
"$bin" "$tmp/point.scn" -o "$tmp/all/p" --cache "$tmp/cache" --threads 1 > /dev/null 2>&1
check "no --outputs writes all five files and the manifest" \
  test "$(files_in "$tmp/all")" = "p.exr p.manifest.json p.png p.sensors.csv p.spectral.exr "
check "--outputs exr writes the EXR of a full run" cmp -s "$tmp/all/p.exr" "$tmp/o1/p.exr"
check "--outputs png writes the PNG of a full run" cmp -s "$tmp/all/p.png" "$tmp/o3/p.png"
check "--outputs spectral writes the spectral EXR of a full run" \
  cmp -s "$tmp/all/p.spectral.exr" "$tmp/o2/p.spectral.exr"
# --sensors-only with the table; a scene without sensors with an image.
mkdir "$tmp/so" "$tmp/ns"
"$bin" "$tmp/point.scn" -o "$tmp/so/p" --sensors-only --outputs sensors --cache "$tmp/cache" \
  > /dev/null 2>&1; rc=$?
check "--sensors-only --outputs sensors exits 0" test $rc -eq 0
check "--sensors-only --outputs sensors writes the table and the manifest" \
  test "$(files_in "$tmp/so")" = "p.manifest.json p.sensors.csv "
"$bin" "$tmp/nosensor.scn" -o "$tmp/ns/p" --outputs exr --cache "$tmp/cache" > /dev/null 2>&1; rc=$?
check "a scene without sensors, --outputs exr" test $rc -eq 0 -a -s "$tmp/ns/p.exr"

# Refused before any work, each a row of docs/bad-input.md; nothing written.
mkdir "$tmp/r"
cd "$tmp/r"
refuse render-outputs-empty "$bin" "$tmp/point.scn" --outputs ''
refuse render-outputs-empty-name "$bin" "$tmp/point.scn" --outputs 'exr,,png'
refuse render-outputs-unknown "$bin" "$tmp/point.scn" --outputs exr,jpg
refuse render-outputs-twice "$bin" "$tmp/point.scn" --outputs png,exr,png
refuse render-outputs-sensors-only "$bin" "$tmp/point.scn" --sensors-only --outputs sensors,png
refuse render-outputs-tonemap-no-png "$bin" "$tmp/point.scn" --outputs exr --tonemap reinhard
refuse render-outputs-exposure-no-image "$bin" "$tmp/point.scn" --outputs sensors --exposure 1
refuse render-outputs-no-camera "$bin" "$tmp/nocamera.scn" --outputs png
refuse render-outputs-no-sensors "$bin" "$tmp/nosensor.scn" --outputs exr,sensors
refuse render-outputs-annual "$bin" "$tmp/year.scn" --outputs sensors
check "a refused list writes nothing" test -z "$(ls "$tmp/r")"

# OpenCV: not in vr-render's ELF, nor among the libraries it loads at start.
readelf -d "$bin" > "$tmp/dynamic" 2>&1
check "readelf reads vr-render's dynamic section" grep -q "(NEEDED)" "$tmp/dynamic"
check "vr-render's ELF needs no OpenCV library" test -z "$(grep NEEDED "$tmp/dynamic" | grep -i opencv)"
ldd "$bin" > "$tmp/ldd" 2>&1
check "ldd lists vr-render's libraries" grep -q "libc.so" "$tmp/ldd"
check "no OpenCV among the libraries vr-render loads at start" test -z "$(grep -i opencv "$tmp/ldd")"
check "the module vr-image-cv.so was built" test -s "$module"
# A run without PNG never loads OpenCV: the dynamic loader's own record,
# and with the module's path pointing nowhere it still succeeds.
mkdir "$tmp/lazy"
LD_DEBUG=files "$bin" "$tmp/point.scn" -o "$tmp/lazy/e" --outputs exr,spectral,sensors \
  --cache "$tmp/cache" --quiet 2> "$tmp/lazy/exr.ld"; rc=$?
check "--outputs exr,spectral,sensors runs (under LD_DEBUG)" test $rc -eq 0
check "the loader's record of that run is there" grep -q "file=" "$tmp/lazy/exr.ld"
check "a run without PNG loads no OpenCV library" test -z "$(grep -i opencv "$tmp/lazy/exr.ld")"
check "a run without PNG does not load vr-image-cv.so" test -z "$(grep vr-image-cv "$tmp/lazy/exr.ld")"
VR_IMAGE_CV_MODULE="$tmp/no/such.so" "$bin" "$tmp/point.scn" -o "$tmp/lazy/e2" --outputs exr \
  --cache "$tmp/cache" --quiet > /dev/null 2>&1; rc=$?
check "--outputs exr runs without the module" test $rc -eq 0 -a -s "$tmp/lazy/e2.exr"
# A run with the PNG loads the module and OpenCV, and writes it.
LD_DEBUG=files "$bin" "$tmp/point.scn" -o "$tmp/lazy/p" --outputs png --cache "$tmp/cache" \
  --quiet 2> "$tmp/lazy/png.ld"; rc=$?
check "--outputs png runs (under LD_DEBUG)" test $rc -eq 0 -a -s "$tmp/lazy/p.png"
check "a run with a PNG loads OpenCV's imgcodecs" grep -q "libopencv_imgcodecs" "$tmp/lazy/png.ld"
check "a run with a PNG loads the built module" grep -qF "file=$module " "$tmp/lazy/png.ld"
# Without the module: refused before any work, naming the path tried.
refuse render-png-module-missing env VR_IMAGE_CV_MODULE="$tmp/no/such.so" "$bin" \
  "$tmp/point.scn" -o "$tmp/r/m" --outputs exr,png --cache "$tmp/cache"
check "the missing module's path is named" grep -qF "$tmp/no/such.so" "$tmp/refused.err"
check "a missing module is found before the render" test -z "$(grep 'camera  *run' "$tmp/refused.err")"
check "a missing module leaves no file" test -z "$(ls "$tmp/r")"
libm=$(awk '/libm\.so/ { print $3 }' "$tmp/ldd")
VR_IMAGE_CV_MODULE="$libm" "$bin" "$tmp/point.scn" -o "$tmp/r/m" --outputs png \
  --cache "$tmp/cache" > /dev/null 2> "$tmp/err"; rc=$?
check "another library as the module exits 1" test $rc -eq 1
check "another library as the module is named as such" grep -qF "$libm: not a vr-image-cv module" "$tmp/err"
# Copied or installed programs find the module beside them.
mkdir -p "$tmp/copy" "$tmp/inst/bin" "$tmp/inst/lib/virtuelium-c"
cp "$bin" "$module" "$tmp/copy/"
cp "$bin" "$tmp/inst/bin/"
cp "$module" "$tmp/inst/lib/virtuelium-c/"
LD_DEBUG=files "$tmp/copy/vr-render" "$tmp/point.scn" -o "$tmp/copy/p" --outputs png \
  --cache "$tmp/cache" --quiet 2> "$tmp/copy.ld"; rc=$?
check "a copied vr-render writes a PNG" test $rc -eq 0 -a -s "$tmp/copy/p.png"
check "with the module beside it" grep -qF "file=$tmp/copy/vr-image-cv.so " "$tmp/copy.ld"
LD_DEBUG=files "$tmp/inst/bin/vr-render" "$tmp/point.scn" -o "$tmp/inst/p" --outputs png \
  --cache "$tmp/cache" --quiet 2> "$tmp/inst.ld"; rc=$?
check "an installed vr-render writes a PNG" test $rc -eq 0 -a -s "$tmp/inst/p.png"
check "with the module in ../lib/virtuelium-c" \
  grep -qF "file=$tmp/inst/bin/../lib/virtuelium-c/vr-image-cv.so " "$tmp/inst.ld"
LD_DEBUG=files VR_IMAGE_CV_MODULE="$tmp/copy/vr-image-cv.so" "$bin" "$tmp/point.scn" \
  -o "$tmp/inst/q" --outputs png --cache "$tmp/cache" --quiet 2> "$tmp/env.ld"; rc=$?
check "VR_IMAGE_CV_MODULE chooses the module" \
  test $rc -eq 0 -a -n "$(grep -F "file=$tmp/copy/vr-image-cv.so " "$tmp/env.ld")"
finish
