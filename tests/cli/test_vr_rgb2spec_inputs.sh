#!/usr/bin/env bash
# Command-line tests of what vr-rgb2spec takes in besides good PNGs: a
# manifest from a pipe (relative photo paths then taken from the working
# directory), photos with an alpha channel (transparent pixels refused, an
# opaque alpha noted), JPEG photos (simulated and from a real camera,
# tests/data/images/README.md) and 16-bit photos decoded as sRGB by default
# (warnings naming what to do).
set -u
bin="$VR_BIN/vr-rgb2spec"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
brick="$src/samples/photos/materials/brick_red.csv"
wood="$src/samples/photos/materials/wood_pine.csv"

# A small capture: two lights, two flat regions on a grey background.
mkdir -p "$tmp/cap"
cat > "$tmp/cap/manifest.txt" <<EOF
camera cie1931-srgb
photo d65.png light=D65 scale=0.9
photo a.png light=A scale=0.5
region brick rect=8,8,20,16 reference=file:$brick
region wood rect=36,24,20,16 reference=file:$wood
EOF
( cd "$tmp/cap" && "$bin" simulate --manifest manifest.txt --size 64x48 --seed 2 2> /dev/null )
check "simulate writes the photos" test -s "$tmp/cap/a.png"
( cd "$tmp/cap" && "$bin" --manifest manifest.txt --json > "$tmp/file.json" ); rc=$?
check "the capture recovers from its manifest file" test $rc -eq 0

# Manifest from a pipe, photos relative to the working directory.
( cd "$tmp/cap" && cat manifest.txt | "$bin" --manifest - --json > "$tmp/dash.json" 2> "$tmp/err" ); rc=$?
check "--manifest - reads standard input" test $rc -eq 0
check "--manifest - gives the same result as the file" cmp -s "$tmp/file.json" "$tmp/dash.json"
( cd "$tmp/cap" && cat manifest.txt | "$bin" --manifest /dev/stdin --json > "$tmp/stdin.json" 2> "$tmp/err" ); rc=$?
check "--manifest /dev/stdin from a pipe" test $rc -eq 0 -a -z "$(grep "no 'photo' lines" "$tmp/err")"
check "--manifest /dev/stdin gives the same result as the file" cmp -s "$tmp/file.json" "$tmp/stdin.json"
( cd "$tmp/cap" && "$bin" --manifest <(cat manifest.txt) --json > "$tmp/procsub.json" 2> "$tmp/err" ); rc=$?
check "--manifest <(...) (a /dev/fd pipe)" test $rc -eq 0 -a -z "$(grep "no 'photo' lines" "$tmp/err")"
# From elsewhere the same relative names are looked for there, and named.
mkdir -p "$tmp/elsewhere"
( cd "$tmp/elsewhere" && cat "$tmp/cap/manifest.txt" | "$bin" --manifest - > /dev/null 2> "$tmp/err" ); rc=$?
check "a piped manifest's photos are looked for in the working directory" \
  test $rc -eq 1 -a -n "$(grep 'd65.png' "$tmp/err")"
sed 's/light=A /light=Q /' "$tmp/cap/manifest.txt" > "$tmp/bad.txt"
( cd "$tmp/cap" && "$bin" --manifest - < "$tmp/bad.txt" > /dev/null 2> "$tmp/err" ); rc=$?
check "errors in a manifest from - name <stdin>:line:col" \
  test $rc -eq 1 -a -n "$(grep '<stdin>:3:13: unknown light' "$tmp/err")"
( cd "$tmp/cap" && cat "$tmp/bad.txt" | "$bin" --manifest /dev/stdin > /dev/null 2> "$tmp/err" ); rc=$?
check "errors in a piped /dev/stdin name /dev/stdin:line:col" \
  test $rc -eq 1 -a -n "$(grep '/dev/stdin:3:13: unknown light' "$tmp/err")"

# The simulated D65 photo given an alpha channel (PNG 1.2 spec: colour type
# 6, alpha 255 opaque, 0 transparent), its colour kept: the first N pixels
# get alpha 0.  Python decodes the 8-bit RGB PNG (zlib and the five row
# filters of section 6) and writes the RGBA one.
add_alpha() { # SOURCE.png DEST.png N
  python3 - "$@" <<'PY'
import struct, sys, zlib
src, dst, holes = sys.argv[1], sys.argv[2], int(sys.argv[3])
b = open(src, 'rb').read()
w, h, depth, colour, _, _, interlace = struct.unpack('>IIBBBBB', b[16:29])
assert (depth, colour, interlace) == (8, 2, 0), (depth, colour, interlace)
at, idat = 8, b''
while at < len(b):
    n, = struct.unpack('>I', b[at:at + 4])
    if b[at + 4:at + 8] == b'IDAT':
        idat += b[at + 8:at + 8 + n]
    at += 12 + n
raw, stride, prev, rows = zlib.decompress(idat), 3 * w, bytearray(3 * w), b''
for y in range(h):
    f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
    for x in range(stride):
        a = line[x - 3] if x >= 3 else 0
        c = prev[x - 3] if x >= 3 else 0
        p = a + prev[x] - c
        pred = [0, a, prev[x], (a + prev[x]) // 2,
                a if abs(p - a) <= abs(p - prev[x]) and abs(p - a) <= abs(p - c)
                else prev[x] if abs(p - prev[x]) <= abs(p - c) else c][f]
        line[x] = (line[x] + pred) & 255
    rows += b'\0' + b''.join(bytes(line[3 * x:3 * x + 3]) + bytes([0 if y * w + x < holes else 255])
                             for x in range(w))
    prev = line
def chunk(t, d):
    return struct.pack('>I', len(d)) + t + d + struct.pack('>I', zlib.crc32(t + d))
open(dst, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 6, 0, 0, 0))
                      + chunk(b'IDAT', zlib.compress(rows)) + chunk(b'IEND', b''))
PY
}
mkdir -p "$tmp/alpha"
cp "$tmp/cap/manifest.txt" "$tmp/cap/a.png" "$tmp/alpha/"
add_alpha "$tmp/cap/d65.png" "$tmp/alpha/d65.png" 10
"$bin" --manifest "$tmp/alpha/manifest.txt" > /dev/null 2> "$tmp/err"; rc=$?
check "a photo with transparent pixels is refused, naming it and the count" \
  test $rc -eq 1 -a -n "$(grep 'd65.png: 10 of 3072 pixels are not fully opaque' "$tmp/err")"
check "the refusal says what to do" test -n "$(grep 'flatten the photo onto the scene or remove its alpha channel' "$tmp/err")"
add_alpha "$tmp/cap/d65.png" "$tmp/alpha/d65.png" 0
( cd "$tmp/alpha" && "$bin" --manifest manifest.txt --json > "$tmp/alpha.json" 2> "$tmp/err" ); rc=$?
check "an opaque alpha channel is noted and ignored" \
  test $rc -eq 0 -a -n "$(grep '^vr-rgb2spec: note: d65.png: has an alpha channel, every pixel opaque: it is ignored$' "$tmp/err")"
check "... and the result is that of the photo without it" cmp -s "$tmp/file.json" "$tmp/alpha.json"
# A real icon (gdal-data's, 32 x 32, 567 pixels below opaque) as a photo.
mkdir -p "$tmp/icon"
printf 'photo icon.png light=D65\nphoto a.png light=A\nregion r rect=4,4,8,8 reference=file:%s\n' "$wood" \
  > "$tmp/icon/manifest.txt"
cp "$src/tests/data/images/gdalicon.png" "$tmp/icon/icon.png"
( cd "$tmp/icon" && "$bin" simulate --manifest manifest.txt --size 32x32 2> /dev/null )
cp "$src/tests/data/images/gdalicon.png" "$tmp/icon/icon.png" # simulate rewrote both
"$bin" --manifest "$tmp/icon/manifest.txt" > /dev/null 2> "$tmp/err"; rc=$?
check "a real RGBA icon is refused: 567 of 1024 pixels" \
  test $rc -eq 1 -a -n "$(grep 'icon.png: 567 of 1024 pixels are not fully opaque' "$tmp/err")"

# JPEG photos: simulated ones, then a real camera file (one light: the
# recovery fits any colour, so only reading and the warning are at stake).
mkdir -p "$tmp/jpg"
sed 's/\.png/.jpg/' "$tmp/cap/manifest.txt" > "$tmp/jpg/manifest.txt"
( cd "$tmp/jpg" && "$bin" simulate --manifest manifest.txt --size 64x48 2> /dev/null )
"$bin" --manifest "$tmp/jpg/manifest.txt" > /dev/null 2> "$tmp/err"; rc=$?
check "JPEG photos are recovered, with one warning each" \
  test $rc -eq 0 -a "$(grep -c '^vr-rgb2spec: warning: .*\.jpg: JPEG is lossy' "$tmp/err")" -eq 2
check "the JPEG warning says what to do" \
  test -n "$(grep 'keep regions a few pixels inside the patches, or use PNG, TIFF or a 16-bit TIFF' "$tmp/err")"
mkdir -p "$tmp/camera"
cp "$src/tests/data/images/iphone4s_goexif.jpg" "$tmp/camera/d65.jpg"
printf 'photo d65.jpg light=D65\nregion sky rect=150,10,40,20\n' > "$tmp/camera/manifest.txt"
"$bin" --manifest "$tmp/camera/manifest.txt" > "$tmp/out" 2> "$tmp/err"; rc=$?
check "a real camera JPEG (205 x 102 as stored, EXIF orientation not applied) is recovered, with the warning" \
  test $rc -eq 0 -a "$(grep -c 'JPEG is lossy' "$tmp/err")" -eq 1 -a -n "$(grep '^sky ' "$tmp/out")"

# 16-bit photos: simulated linear (encoding=linear makes 16-bit files, as a
# raw converter does), then read with a manifest that does not say so.
mkdir -p "$tmp/lin"
sed 's/ scale=\([0-9.]*\)$/ scale=\1 encoding=linear/' "$tmp/cap/manifest.txt" > "$tmp/lin/sim.txt"
( cd "$tmp/lin" && "$bin" simulate --manifest sim.txt --size 64x48 2> /dev/null )
"$bin" --manifest "$tmp/lin/sim.txt" > /dev/null 2> "$tmp/err"; rc=$?
check "16-bit photos with encoding=linear: no warning" test $rc -eq 0 -a -z "$(grep 'warning' "$tmp/err")"
cp "$tmp/cap/manifest.txt" "$tmp/lin/manifest.txt"
"$bin" --manifest "$tmp/lin/manifest.txt" > /dev/null 2> "$tmp/err"
check "16-bit photos without encoding=: a warning each, naming manifest:line" \
  test "$(grep -c '^vr-rgb2spec: warning: .*\.png: this 16-bit photo has no encoding= and is decoded as sRGB' "$tmp/err")" -eq 2 \
    -a -n "$(grep "add encoding=linear to its photo line ($tmp/lin/manifest.txt:3)" "$tmp/err")"

# ---- Nothing a user owns is lost or silently wrong (issue 18) -----------
# Outputs never replace inputs: --report (and its swatch image) and
# --per-pixel are checked against the photos, the manifest, every file it
# reads and the database before any photo is read; two outputs must differ.
own="$tmp/own"
mkdir -p "$own"
cp "$tmp/cap/d65.png" "$tmp/cap/a.png" "$brick" "$own/"
python3 -c "
print('wavelength_nm,value')
for w in range(380, 785, 5): print(w, 1.0, sep=',')" > "$own/flat.csv"
printf 'photo d65.png light=D65 scale=0.9\nphoto a.png light=A scale=0.5\nregion brick rect=8,8,20,16 reference=file:brick_red.csv\nregion wood rect=36,24,20,16 reference=file:%s\n' \
  "$wood" > "$own/manifest.txt"
sed 's/light=A /light=file:flat.csv /' "$own/manifest.txt" > "$own/flat.txt"
touch "$own/x.db"
sums() { sha256sum "$own"/d65.png "$own"/a.png "$own"/manifest.txt "$own"/brick_red.csv "$own"/flat.csv "$own"/x.db; }
sums > "$tmp/sums.before"
refuse rgb2spec-per-pixel-over-photo "$bin" "$own/d65.png" "$own/a.png" --per-pixel "$own/d65.png"
check "... refused before anything is recovered (nothing on standard output)" test ! -s "$tmp/refused.out"
refuse rgb2spec-report-over-photo "$bin" --manifest "$own/manifest.txt" --report "$own/a.png"
refuse rgb2spec-report-over-manifest "$bin" --manifest "$own/manifest.txt" --report "$own/manifest.txt"
refuse rgb2spec-output-over-reference "$bin" --manifest "$own/manifest.txt" --per-pixel "$own/brick_red.csv"
refuse rgb2spec-output-over-light "$bin" --manifest "$own/flat.txt" --report "$own/flat.csv"
refuse rgb2spec-output-over-db "$bin" --manifest "$own/manifest.txt" --db "$own/x.db" --report "$own/x.db"
sums > "$tmp/sums.after"
check "... photos, manifest, spectra and database left as they were" cmp -s "$tmp/sums.before" "$tmp/sums.after"
refuse rgb2spec-outputs-same-file "$bin" --manifest "$own/manifest.txt" --report "$own/r.html" --per-pixel "$own/r.html"
refuse rgb2spec-output-missing-folder "$bin" --manifest "$own/manifest.txt" --per-pixel "$own/nosuch/t.exr" \
  --texture t --db "$own/new.db"
check "... and no database created for the texture" test ! -e "$own/new.db"
refuse rgb2spec-db-empty "$bin" --manifest "$own/manifest.txt" --save-prefix x- --db ''
refuse rgb2spec-db-empty "$bin" simulate --manifest "$own/manifest.txt" --db ''
refuse rgb2spec-calibrate-db-empty "$bin" calibrate "$own/d65.png" --light D65 --save cam --db ''
refuse rgb2spec-texture-empty "$bin" --manifest "$own/manifest.txt" --per-pixel "$own/t.exr" --texture ''
# simulate writes the photos: none may be the manifest or a file it reads,
# and every one must be writable before the first is rendered.
printf 'photo m.txt light=D65\nregion r rect=1,1,4,4\n' > "$own/m.txt"
refuse rgb2spec-simulate-over-manifest "$bin" simulate --manifest "$own/m.txt" --size 16x16
mkdir -p "$own/sim"
printf 'photo one.png light=D65\nphoto nosuch/two.png light=A\nregion r rect=1,1,4,4\n' > "$own/sim/m.txt"
refuse rgb2spec-simulate-missing-folder "$bin" simulate --manifest "$own/sim/m.txt" --size 16x16
check "... and no photo of the set written" test ! -e "$own/sim/one.png"

# A recovery the tool does not stand behind (two lights swapped: every
# region misses its photos) writes no texture and saves no row without
# --force; with it, the rows say so.
sed -e 's/light=D65/light=XX/; s/light=A /light=D65 /; s/light=XX/light=A/' "$own/manifest.txt" > "$own/swapped.txt"
refuse rgb2spec-misfit-nothing-written "$bin" --manifest "$own/swapped.txt" --per-pixel "$own/sw.exr" --texture sw-tex \
  --save-prefix sw- --db "$own/sw.db"
check "... no EXR written" test ! -e "$own/sw.exr"
"$bin" --manifest "$own/swapped.txt" --per-pixel "$own/sw.exr" --texture sw-tex --save-prefix sw- --db "$own/sw.db" \
  --force > /dev/null 2>&1; rc=$?
"$VR_BIN/../matdb/vr-matdb" show sw-brick --db "$own/sw.db" --json > "$tmp/sw.json"
python3 - "$tmp/sw.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
note = d["provenance"]["note"]
assert "misses its photos" in note and "saved with --force" in note, note
p = {x["key"]: x["value"] for x in d["properties"]}
assert p["fit_misfit"] == 1 and p["fit_forced"] == 1, p
PY
check "--force writes and saves, the rows saying they were forced" test $? -eq 0 -a $rc -eq 0 -a -s "$own/sw.exr"

# A texture whose database row cannot be saved leaves an earlier file of
# that name as it was (the EXR is put in place only after its row).
echo "an earlier texture" > "$own/keep.exr"
refuse rgb2spec-texture-row-refused "$bin" --manifest "$own/manifest.txt" --per-pixel "$own/keep.exr" \
  --texture $'bad\xff' --db "$own/k.db"
check "... the earlier file is kept, no part file left" \
  test "$(cat "$own/keep.exr")" = "an earlier texture" -a -z "$(ls "$own" | grep part)"

# A UTF-8 byte-order mark (as Windows editors write) at the start of a
# manifest is not a statement.
( cd "$tmp/cap" && { printf '\xef\xbb\xbf'; cat manifest.txt; } > bom.txt && "$bin" --manifest bom.txt --json > "$tmp/bom.json" 2> "$tmp/err" ); rc=$?
check "a manifest with a UTF-8 byte-order mark gives the same result as without" \
  test $rc -eq 0 -a -n "$(cmp -s "$tmp/file.json" "$tmp/bom.json" && echo same)"

finish
