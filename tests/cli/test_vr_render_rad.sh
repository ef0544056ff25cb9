#!/usr/bin/env bash
# Command-line test of Radiance scenes (.rad) in vr-render:
#   - honeybee-radiance's sample office (tests/data/radiance/sample_office,
#     as Honeybee writes it: materials and surfaces in separate files,
#     gathered by a .rad of !xform lines) under a CIE overcast sky, its
#     work-plane grid given as a .pts file: every point's illuminance
#     against Radiance 6.1's (rtrace, Monte Carlo, radiance_overcast.txt,
#     README.md there) within 4 of our standard errors plus 1 % for
#     Radiance's own noise, and the mean over the 32 points within 4
#     standard errors of that mean plus 0.5 %;
#   - the decisions printed: each Radiance material and what it became,
#     and the model's floor and context ground found coinciding (21.6 and
#     7.2 m2) as Honeybee wrote it;
#   - refusals (docs/bad-input.md), each naming the .rad file and line,
#     and no output written for them.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
source "$(dirname "$0")/harness.sh"
not_grep() { ! grep -q "$@"; }
office="$VR_SOURCE_DIR/tests/data/radiance/sample_office"
cd "$tmp"

awk -f "$office/lower_context.awk" "$office/scene/sample_office_envelope.rad" > envelope.rad
cat > office.rad <<EOF
!xform $office/scene/sample_office_envelope.mat
!xform envelope.rad
!xform $office/aperture/sample_office.mat
!xform $office/aperture/sample_office.rad
EOF
cat > office.scn <<EOF
mesh office.rad
sky overcast illuminance=10000 ground=0.2
sensor wp points file=$office/grid.pts
render integrator=path sensor_samples=32768 depth=30 seed=7
EOF
"$bin" office.scn --sensors-only -o office 2> office.err
check "the office renders" test $? -eq 0
check "its wall material is read as Radiance wrote it" \
  grep -q "Radiance material 'generic_wall_0.50' (.* triangles, .*sample_office_envelope.mat:1): plastic 0.5 0.5 0.5 0: Lambertian" office.err
check "its glass as a thin pane" \
  grep -q "Radiance material 'skylight_45_59c8c160' (2 triangles, .*sample_office.mat:1): glass 0.490702 0.490702 0.490702, n 1.52: a thin pane" office.err
check "32 points" test "$(tail -n +2 office.sensors.csv | wc -l)" -eq 32
check "no coinciding polygons once the ground is lowered" not_grep coincide office.err
# As Honeybee wrote it, the floor (21.6 + 7.2 m2) lies in the ground's plane.
sed "s#^mesh office.rad#mesh $office/office.rad#; s/sensor_samples=32768/sensor_samples=64/" office.scn > asis.scn
"$bin" asis.scn --sensors-only -o asis 2> asis.err
check "the model as written: its coinciding floor and ground said" \
  grep -q "2 pairs of polygons coincide .*'context_e3bb11d6_0' (.*sample_office_envelope.rad:1) and 'room_geometry_cd906227_8' (.*sample_office_envelope.rad:51) over 21.6 m2; .* over 7.2 m2" asis.err
# Radiance's reading beside ours (illuminance, standard error).
paste -d, "$office/radiance_overcast.txt" <(tail -n +2 office.sensors.csv | cut -d, -f7,8) > both.csv
check "Radiance's 32 readings beside ours" test "$(awk -F, 'NF == 3 && $1 > 0' both.csv | wc -l)" -eq 32
bad=$(awk -F, '{ d = $2 - $1; if (d < 0) d = -d; if (d > 4 * $3 + 0.01 * $1) print NR - 1 ": " $2 " vs " $1 " (se " $3 ")" }' both.csv)
check "every point within 4 standard errors + 1 % of Radiance's (off: ${bad:-none})" test -z "$bad"
mean=$(awk -F, '{ s += ($2 - $1) / $1; v += ($3 / $1) ^ 2 } END {
  m = s / NR; se = sqrt(v) / NR; print (m < 0 ? -m : m) <= 4 * se + 0.005 ? "ok" : "off: " m " (se " se ")" }' both.csv)
check "the mean relative difference within 4 standard errors + 0.5 % ($mean)" test "$mean" = ok

# Refusals: the .rad file and its line in the message, nothing written.
rad() { printf '%b' "$2" > "$1"; }
cat > bad.scn <<'EOF'
mesh bad.rad
sensor s point position=0,0,1 normal=0,0,1
EOF
rad bad.rad 'void plastic w 0 0 5 .5 .5 .5 0 0\nvoid brightfunc skyfunc 2 skybr skybright.cal 0 0\n'
refuse render-rad-pattern "$bin" bad.scn -o bad1
check "it names bad.rad line 2" grep -q "bad.scn:1:1: .*bad.rad:2: brightfunc 'skyfunc'" "$tmp/refused.err"
rad bad.rad '!gensky 3 21 12 -a 45\n'
refuse render-rad-command "$bin" bad.scn -o bad2
rad bad.rad 'void plastic w 0 0 5 .5 .5 .5 0 0\n\nwall polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n'
refuse render-rad-undefined "$bin" bad.scn -o bad3
check "it names line 3" grep -q "bad.rad:3: polygon 'p'" "$tmp/refused.err"
rad bad.rad 'void plastic w 0 0 5 .5 .5 .5 0 0\nw polygon p 0 0 8 0 0 0 1 0 0 0 1\n'
refuse render-rad-polygon-args "$bin" bad.scn -o bad4
rad bad.rad 'void plastic w 0 0 5 .5 .5 nan 0 0\n'
refuse render-rad-not-finite "$bin" bad.scn -o bad5
rad bad.rad 'void plasfunc p 2 refl f.cal 0 4 .5 .5 .5 0\n'
refuse render-rad-material-unread "$bin" bad.scn -o bad6
rad bad.rad '!xform -t 1 0 0 missing.rad\n'
refuse render-rad-xform-missing "$bin" bad.scn -o bad7
rad bad.rad 'void plastic w 0 0 5 1.2 .5 .5 0 0\nw polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n'
refuse render-rad-reflectance "$bin" bad.scn -o bad8
check "it names the material's line" grep -q "bad.rad:1: plastic 'w'" "$tmp/refused.err"
rad bad.rad 'void light sm 0 0 3 1e6 1e6 1e6\nsm source sun 0 0 4 0 0 1 0.5\nvoid plastic w 0 0 5 .5 .5 .5 0 0\nw polygon p 0 0 9 0 0 0 1 0 0 0 1 0\n'
printf 'sky overcast illuminance=10000\n' >> bad.scn
refuse render-rad-sun-and-sky "$bin" bad.scn -o bad9
rad tr.rad 'void trans d 0 0 7 .8 .8 .8 0 0 .6 0\nd polygon s 0 0 12 -5 -5 1 5 -5 1 5 5 1 -5 5 1\n'
printf 'mesh tr.rad\ncamera pinhole from=0,0,0.5 to=0,0,1 up=0,1,0 resolution=8x8\nrender integrator=bdpt spp=1\n' > tr.scn
refuse render-bdpt-translucent "$bin" tr.scn -o bad10
check "no output of any refused run" test -z "$(ls bad[0-9]* 2>/dev/null)"

# The sun from the file without the sky: E normal to it = L * solid angle.
sed -i '$d' bad.scn
"$bin" bad.scn --sensors-only -o sun 2> sun.err
check "a distant source becomes the sun" test $? -eq 0
want=$(awk 'BEGIN { pi = atan2(0, -1); printf "%.1f", 179e6 * 2 * pi * (1 - cos(0.25 * pi / 180)) }')
got=$(tail -n 1 sun.sensors.csv | cut -d, -f7)
check "its illuminance 179 x 1e6 x 2 pi (1 - cos 0.25 deg) = $want lx (got $got)" \
  awk -v g="$got" -v w="$want" 'BEGIN { exit !(g / w > 0.999 && g / w < 1.001) }'
finish
