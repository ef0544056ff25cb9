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
finish
