#!/usr/bin/env bash
# Command-line test: lengths and wavelengths in their units, with the
# physical range of what they measure (issue 35, class 3; docs/bad-input.md,
# "Units and plausibility").  On the sample low-e pane's real data file
# (samples/glazing/lowe/lowe.csv, "# thickness: 4 mm"):
#   - "thickness: 4 nm" (a unit slip) is no pane: refused, naming the line,
#     instead of fitting a 4 nm "pane" that "describes the data";
#   - an unknown unit word is refused, not read as mm;
#   - --thickness 1e9 (mm) is refused as a usage error;
# a table whose wavelength_nm column holds micrometres (0.4-0.7) is
# refused instead of becoming a material of 0.4-0.7 nm; a scene pane's
# thickness needs its unit (a bare 3 was 3 m of glass) and a pane's range.
# A photochromic model fitted on the sample's states (0-40 W/m2 of UV,
# 10-40 C) refuses a state outside them, in vr-spectro and in a render
# under a summer noon sun (100 klx at 80 degrees and a 25 klx clear sky),
# unless told to extrapolate.  A model in centimetres (a real 3ds Max
# export, tests/data/models/assimp_obj_house) on a mesh line without units=
# is warned about; with units=cm it is not.
set -u
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
cd "$tmp"
lowe="$src/samples/glazing/lowe/lowe.csv"
grep -q "^# thickness: 4 mm" "$lowe" || { echo "not ok - $lowe no longer says its thickness"; exit 1; }
sed 's/^# thickness: 4 mm/# thickness: 4 nm/' "$lowe" > lowe_nm.csv
refuse spectro-thickness-implausible "$VR_SPECTRO" metrics lowe_nm.csv
check "... naming the line" grep -q "lowe_nm.csv:3:" "$tmp/refused.err"
sed 's/^# thickness: 4 mm/# thickness: 4 furlongs/' "$lowe" > lowe_fur.csv
refuse spectro-thickness-unit-unknown "$VR_SPECTRO" metrics lowe_fur.csv
refuse spectro-thickness-option-range "$VR_SPECTRO" metrics "$lowe" --thickness 1e9
"$VR_SPECTRO" metrics "$lowe" > ok.txt 2>&1
check "the file as written (4 mm) is read" test $? -eq 0
sed 's/^# thickness: 4 mm/# thickness: 4 mm\n# coating thickness: 12 nm\n# glass thickness: 4mm/' "$lowe" > lowe_coat.csv
"$VR_SPECTRO" metrics lowe_coat.csv > coat.txt 2>&1
check "another layer's thickness in a comment is not the pane's" test $? -eq 0
printf 'wavelength_nm,r\n0.4,0.5\n0.5,0.5\n0.7,0.5\n' > um.csv
refuse matdb-wavelength-implausible "$VR_MATDB_TOOL" import um.csv
check "... and nothing was saved" bash -c '! "$1" list 2> /dev/null | grep -q "^um "' _ "$VR_MATDB_TOOL"
cat > bare.scn <<SCN
material pane db:clear-float-nk thickness=3 model=thin
rect center=0,0,0 normal=0,0,1 size=1,1 material=pane
SCN
refuse render-thickness-no-unit "$VR_RENDER" bare.scn -o bare
sed 's/thickness=3 /thickness=30cm /' bare.scn > nm.scn
refuse render-thickness-implausible "$VR_RENDER" nm.scn -o nm
# Photochromic states outside the fitted UV and temperature range.
"$VR_SPECTRO" chromogenic "$src/samples/glazing/photochromic/pc_states.csv" --save pc > /dev/null 2>&1
check "the sample photochromic glass is fitted" test $? -eq 0
refuse spectro-uv-outside-fit "$VR_SPECTRO" state pc --uv 60
check "... naming the fitted range" grep -q "0 to 40 W/m2" "$tmp/refused.err"
refuse spectro-temperature-outside-fit "$VR_SPECTRO" state pc --uv 20 --temperature 60C
"$VR_SPECTRO" state pc --uv 40 --temperature 40C > in.csv 2> in.err
check "the edges of the fitted range are inside" test $? -eq 0 -a ! -s in.err
"$VR_SPECTRO" state pc --uv 60 --extrapolate > ex.csv 2> ex.err
rc=$?
check "--extrapolate evaluates it, with a warning" \
  bash -c '[ "$1" = 0 ] && grep -q "extrapolated as asked" ex.err' _ "$rc"
cat > pc.scn <<SCN
material pane db:pc
material floor lambert reflectance=0.3
rect center=0,0,0 normal=0,0,1 size=4,4 material=floor
rect center=0,0,1 normal=0,0,1 size=1,1 material=pane
light sun altitude=80 azimuth=180 illuminance=100000lx
sky cie type=12 illuminance=25000
sensor s point position=0,0,0.5 normal=0,0,1
render sensor_samples=16
SCN
refuse render-photochromic-outside-fit "$VR_RENDER" pc.scn -o pc
check "... naming the object's line" grep -q "scene line 4" "$tmp/refused.err"
sed -i 's/db:pc$/db:pc extrapolate=yes/' pc.scn
"$VR_RENDER" pc.scn -o pcx > pcx.out 2> pcx.err
rc=$?
check "extrapolate=yes renders it and counts the texels" \
  bash -c '[ "$1" = 0 ] && grep -q "texels outside the UV" pcx.err' _ "$rc"
sed 's/db:pc extrapolate=yes/db:N-BK7 thickness=3mm extrapolate=yes/' pc.scn > nbk7.scn
refuse render-extrapolate-not-photochromic "$VR_RENDER" nbk7.scn -o nbk7
# A mesh line without units= whose model spans kilometres.
cat > house.scn <<SCN
mesh $src/tests/data/models/assimp_obj_house/regr01.obj
sensor s point position=0,0,1 normal=0,0,1
light point position=0,0,2 intensity=100lm
render sensor_samples=4
SCN
"$VR_RENDER" house.scn -o house > house.out 2> house.err
check "a model in cm read as m renders" test $? -eq 0
check "... with a warning naming the line and units=cm" \
  grep -q "mesh 'regr01.obj' (line 1) spans 1636 m .* add units=mm or units=cm" house.err
sed -i 's/regr01.obj$/regr01.obj units=cm/' house.scn
"$VR_RENDER" house.scn -o house2 > house2.out 2> house2.err
check "with units=cm, no warning and a 16.4 m house" \
  bash -c '! grep -q "spans" house2.err && grep -q "x -1.942 to 14.42" house2.err'
finish
