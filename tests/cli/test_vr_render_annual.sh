#!/usr/bin/env bash
# Command-line test of the annual study's schedules and EN 17037
# (annual occupancy=FILE en17037=yes edmed=LX): what vr-render prints and
# writes, and each refused input with its row in docs/bad-input.md.  The
# numbers (daylight hours, E_v,d,med, daylight factors against the CIE
# overcast sky's analytic 39.62 %, Table A.1's levels, the occupancy
# files' hours) are checked in tests/render/test_annual_metrics.c.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
source "$(dirname "$0")/room_shell.sh"

daysim="$src/tests/data/occupancy/8to6withDST.60min.occ.csv"
# An open ground, a horizontal work-plane grid and an eye-level view
# sensor, the Chicago year, Daysim's 8-to-6 schedule with daylight saving.
year_scene() { # FILE ANNUAL-OPTIONS
  cat > "$1" <<EOS
material ground lambert reflectance=0.2
rect center=0,0,0 normal=0,0,1 size=10,10 material=ground
light sun spectrum=D65
sky perez weather=$src/tests/data/weather/chicago.wea
sensor plane grid origin=-1,-1,0.8 u=2,0,0 v=0,2,0 n=2,2 normal=0,0,1
sensor eye point position=0,0,1.2 normal=0,1,0
annual $2
render sensor_samples=64
EOS
}
year_scene "$tmp/en.scn" "occupancy=$daysim en17037=yes"
"$bin" "$tmp/en.scn" -o "$tmp/en" > "$tmp/en.out" 2> "$tmp/en.err"; rc=$?
check "an EN 17037 study exits 0" test $rc -eq 0
check "it names the daylight hours and E_v,d,med" grep -q "^EN 17037 4380 daylight hours .*E_v,d,med [0-9]* lx (their median in the weather file)" "$tmp/en.out"
check "it prints method 2 with its three levels" grep -q "^EN 17037 method 2 (illuminance over 50 % of the daylight hours): .*minimum 300 lx on .*medium 500 lx on .*high 750 lx on" "$tmp/en.out"
check "it prints method 1 with its D targets" grep -q "^EN 17037 method 1 (daylight factor, CIE overcast sky): .*minimum D>=" "$tmp/en.out"
check "UDI over the work plane" grep -q "^annual   UDI over the work plane (its points' mean): below 100 lx [0-9.]* %, 100-3000 lx [0-9.]* %, above 3000 lx [0-9.]* %" "$tmp/en.out"
check "each point's daylight hours and DF" grep -q "^point    eye (0, 0)  EN 17037: daylight hours at 100/300/500/750 lx .* DF [0-9.]* %" "$tmp/en.out"
check "the point table has the EN 17037 columns" grep -q ",workplane,en17037_100_lx_pct,en17037_300_lx_pct,en17037_500_lx_pct,en17037_750_lx_pct,df_cie_overcast_pct$" "$tmp/en.annual.csv"
check "the hourly table has the schedule's 3650 hours" test "$(wc -l < "$tmp/en.annual-hourly.csv")" -eq 3651
check "the set verifies" "$bin" --verify "$tmp/en"

year_scene "$tmp/ed.scn" "en17037=yes edmed=15000"
"$bin" "$tmp/ed.scn" -o "$tmp/ed" > "$tmp/ed.out" 2> /dev/null; rc=$?
check "edmed= exits 0" test $rc -eq 0
check "edmed= sets E_v,d,med and D_T = 300/15000" grep -q "E_v,d,med 15000 lx (edmed=)" "$tmp/ed.out"
check "D_T of the minimum level is 2 %" grep -q "minimum D>=2.00% on" "$tmp/ed.out"
year_scene "$tmp/plain.scn" "hours=9,15"
"$bin" "$tmp/plain.scn" -o "$tmp/plain" > "$tmp/plain.out" 2> /dev/null
check "without en17037=yes no EN 17037 lines" bash -c '! grep -q "EN 17037" "$1"' _ "$tmp/plain.out"
check "nor columns" bash -c '! grep -q "en17037" "$1"' _ "$tmp/plain.annual.csv"

# Bad schedules: named with their line and field; nothing written.
printf '0\n1\n2\n' > "$tmp/two.csv"
year_scene "$tmp/b1.scn" "occupancy=$tmp/two.csv"
refuse render-annual-occupancy-value "$bin" "$tmp/b1.scn" -o "$tmp/b1"
check "the value's line and field are named" grep -q "two.csv:3:1: field 'occupancy'" "$tmp/refused.err"
check "nothing written" test -z "$(ls -d "$tmp"/b1.annual* "$tmp"/b1.manifest* "$tmp"/b1.partial* 2>/dev/null)"
printf '# Daysim occupancy file\n1,1,0.5,0\n2,30,8.5,1\n' > "$tmp/feb30.csv"
year_scene "$tmp/b2.scn" "occupancy=$tmp/feb30.csv"
refuse render-annual-occupancy-row "$bin" "$tmp/b2.scn" -o "$tmp/b2"
check "the row is named with its line" grep -q "feb30.csv:3:1:" "$tmp/refused.err"
printf '1\n0\n' > "$tmp/short.csv"
year_scene "$tmp/b3.scn" "occupancy=$tmp/short.csv"
refuse render-annual-occupancy-count "$bin" "$tmp/b3.scn" -o "$tmp/b3"
year_scene "$tmp/b4.scn" "occupancy=$tmp/none.csv"
refuse render-annual-occupancy-missing "$bin" "$tmp/b4.scn" -o "$tmp/b4"
year_scene "$tmp/b5.scn" "occupancy=$daysim hours=8,18"
refuse render-annual-occupancy-hours "$bin" "$tmp/b5.scn" -o "$tmp/b5"
year_scene "$tmp/b6.scn" "edmed=15000"
refuse render-annual-edmed "$bin" "$tmp/b6.scn" -o "$tmp/b6"
# An operable shade for sDA (IES LM-83-12): a south window of clear glass
# of a closed room, an IGSDB roller shade (BSDF XML) drawn by the rule.
cat > "$tmp/shade.scn" <<EOS
material pane db:soda-lime-glass thickness=6mm
material roller bsdf file=$src/tests/data/bsdf/cgdb_14060_urban_loft_river_stone.xml.gz
$(room_shell)
rect center=2,0,1.5 normal=0,1,0 size=2,1.2 material=pane
light sun spectrum=D65
sky perez weather=$src/tests/data/weather/chicago.wea
sensor plane grid origin=0.5,0.5,0.8 u=3,0,0 v=0,3,0 n=3,3 normal=0,0,1
annual shade=roller window=pane
render sensor_samples=64
EOS
"$bin" "$tmp/shade.scn" -o "$tmp/shade" > "$tmp/shade.out" 2> "$tmp/shade.err"; rc=$?
check "a study with a shade exits 0" test $rc -eq 0
check "it says when the shade was drawn" grep -q "^shade    roller in place of pane, drawn by IES LM-83-12's rule .*: [0-9]* of the [0-9]* occupied daylit hours; ASE is the open window's" "$tmp/shade.out"
check "the hourly table gives the shade's state" bash -c 'cut -d, -f2 "$1" | sort -u | tr "
" " " | grep -q "^0 1 glass_state $"' _ "$tmp/shade.annual-hourly.csv"
# Annual glare at a view (glare_views=): the views' table, the hourly DGP
# column and the set's manifest; the DGP itself is checked in
# tests/render/test_annual_glare.c.
year_scene "$tmp/gl.scn" "hours=9,15 glare_views=eye glare_resolution=32"
"$bin" "$tmp/gl.scn" -o "$tmp/gl" > "$tmp/gl.out" 2> "$tmp/gl.err"; rc=$?
check "a study with a glare view exits 0" test $rc -eq 0
check "it prints the view's DGP hours and EN 17037 level" grep -q "^view     eye  DGP>=0.35 [0-9]* h ([0-9.]* %), >=0.40 [0-9]* h ([0-9.]* %), >=0.45 [0-9]* h ([0-9.]* %) of the occupied hours; EN 17037 glare protection: " "$tmp/gl.out"
check "it says how the views' coefficients were rendered" grep -q "annual: 1 glare view: 32 x 32 fisheye coefficients, 1 sky and [0-9]* sun renders each" "$tmp/gl.err"
check "the views' table has its header and one view" bash -c 'head -1 "$1" | grep -q "^view,x,y,z,dx,dy,dz,dgp_0.35_hours,dgp_0.40_hours,dgp_0.45_hours,dgp_0.35_pct,dgp_0.40_pct,dgp_0.45_pct,en17037_glare_protection$" && test "$(wc -l < "$1")" -eq 2' _ "$tmp/gl.annual-glare.csv"
check "the hourly table ends with the view's DGP" bash -c 'head -1 "$1" | grep -q ",dgp:eye$"' _ "$tmp/gl.annual-hourly.csv"
check "the view's hours at 0.35 are the hourly DGPs at or above it" bash -c '
  want=$(awk -F, "NR > 1 && \$NF >= 0.35 { n++ } END { print n + 0 }" "$1")
  got=$(awk -F, "NR == 2 { print \$8 }" "$2")
  test "$want" = "$got"' _ "$tmp/gl.annual-hourly.csv" "$tmp/gl.annual-glare.csv"
check "the manifest lists the views' table" grep -q "gl.annual-glare.csv" "$tmp/gl.manifest.json"
check "the set with the views' table verifies" "$bin" --verify "$tmp/gl"
year_scene "$tmp/b9.scn" "glare_views=plane"
refuse render-annual-glare-grid "$bin" "$tmp/b9.scn" -o "$tmp/b9"
year_scene "$tmp/b10.scn" "glare_views=nobody"
refuse render-annual-glare-unknown "$bin" "$tmp/b10.scn" -o "$tmp/b10"
year_scene "$tmp/b7.scn" "shade=ground"
refuse render-annual-shade-window "$bin" "$tmp/b7.scn" -o "$tmp/b7"
year_scene "$tmp/b8.scn" "shade=ground window=nothing"
refuse render-annual-shade-unknown "$bin" "$tmp/b8.scn" -o "$tmp/b8"

# An output that would replace the schedule is refused before any work.
cp "$daysim" "$tmp/occ.annual.csv"
year_scene "$tmp/occ.scn" "occupancy=$tmp/occ.annual.csv"
refuse render-annual-occupancy-output "$bin" "$tmp/occ.scn" -o "$tmp/occ"
check "the schedule is intact" cmp -s "$daysim" "$tmp/occ.annual.csv"
cp "$daysim" "$tmp/og.annual-glare.csv"
year_scene "$tmp/og.scn" "occupancy=$tmp/og.annual-glare.csv glare_views=eye"
refuse render-annual-glare-output "$bin" "$tmp/og.scn" -o "$tmp/og"
check "the schedule named like the views' table is intact" cmp -s "$daysim" "$tmp/og.annual-glare.csv"
finish
