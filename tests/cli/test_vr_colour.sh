#!/usr/bin/env bash
# Command-line test of vr-colour: the real executable on a real file, its
# --help/--version, and its errors on bad input.
set -u
bin="$VR_BIN/vr-colour"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

"$bin" --help > "$tmp/help" 2>&1; rc=$?
check "--help exits 0" test $rc -eq 0
check "--help shows usage" grep -q "^Usage: vr-colour" "$tmp/help"
"$bin" --version > "$tmp/ver"; check "--version" grep -q "vr-colour (Virtuelium-C) " "$tmp/ver"

# The white patch of the ColorChecker under D65: L* about 96.5 (BabelColor
# average, white 9.5), sRGB near (243, 243, 242) (Pascale 2006).
"$bin" --json "$src/samples/spectra/colorchecker_babelcolor.csv" > "$tmp/out.json"; rc=$?
check "runs on the sample" test $rc -eq 0
check "JSON names the white patch" grep -q '"name": "white_9.5"' "$tmp/out.json"
python3 - "$tmp/out.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
w = [s for s in d["spectra"] if s["name"] == "white_9.5"][0]
assert abs(w["Lab"][0] - 96.5) < 0.6, w
assert all(abs(a - b) <= 2 for a, b in zip(w["sRGB8"], [243, 243, 242])), w
assert len(d["spectra"]) == 24
PY
check "white patch colour" test $? -eq 0

# Bad input: a NaN, an unknown illuminant, a missing file, no operand.
printf 'nm,T\n400,0.5\n410,nan\n' > "$tmp/bad.csv"
"$bin" "$tmp/bad.csv" > /dev/null 2> "$tmp/err"; rc=$?
check "NaN exits non-zero" test $rc -ne 0
check "NaN error names file:line:col and field" grep -q "bad.csv:3:5: field 'T'" "$tmp/err"
"$bin" -i F99 "$src/samples/spectra/colorchecker_babelcolor.csv" > /dev/null 2> "$tmp/err"; rc=$?
check "unknown illuminant exits 1" test $rc -eq 1
check "unknown illuminant is named" grep -q "unknown illuminant 'F99'" "$tmp/err"
"$bin" "$tmp/none.csv" > /dev/null 2> "$tmp/err"; rc=$?
check "missing file exits 1" test $rc -eq 1
check "missing file is named" grep -q "none.csv: cannot open" "$tmp/err"
"$bin" > /dev/null 2>&1; rc=$?
check "no operand is a usage error (2)" test $rc -eq 2
"$bin" --bogus x > /dev/null 2> "$tmp/err"; rc=$?
check "unknown option is a usage error (2)" test $rc -eq 2

# The colorimetry's domain (issue 35, class 4): refused before any output.
printf 'nm,uv\n100,0.5\n200,0.5\n300,0.5\n' > "$tmp/uv.csv"
refuse colour-outside-visible "$bin" "$tmp/uv.csv"
refuse colour-outside-visible "$bin" --extend "$tmp/uv.csv"
printf 'nm,thin\n400,0.5\n401,0.5\n' > "$tmp/thin.csv"
refuse colour-short-range "$bin" "$tmp/thin.csv"
"$bin" --extend "$tmp/thin.csv" > "$tmp/thin.out" 2> "$tmp/thin.err"
check "--extend holds the ends and says so" bash -c "test $? -eq 0 && grep -q 'end values are held' '$tmp/thin.err'"
printf 'nm,one\n550,0.5\n' > "$tmp/one.csv"
refuse colour-one-row "$bin" "$tmp/one.csv"
printf 'nm,neg,ok\n380,-0.2,0.5\n780,0.5,0.5\n' > "$tmp/neg.csv"
refuse colour-reflectance-range "$bin" "$tmp/neg.csv"
check "... nothing printed for the good column either" test ! -s "$tmp/refused.out"
printf 'nm,pct\n380,45\n780,50\n' > "$tmp/pct.csv"
refuse colour-reflectance-percent "$bin" "$tmp/pct.csv"
printf 'nm,big\n380,1e308\n780,1e308\n' > "$tmp/big.csv"
refuse colour-overflow "$bin" --emitter "$tmp/big.csv"
"$bin" "$src/samples/spectra/colorchecker_babelcolor.csv" > /dev/null 2> "$tmp/cc.err"
check "the ColorChecker (380-730 nm) is extended above 730 nm, and said once" \
  grep -q "24 of 24 spectra stop inside 380-780 nm" "$tmp/cc.err"
printf 'nm,led\n400,0.001\n450,0.01\n500,0.002\n700,-0.00005\n' > "$tmp/led.csv"
"$bin" --emitter "$tmp/led.csv" > /dev/null 2> "$tmp/led.err"
check "an emission spectrum dipping 0.5 % of its peak below 0 is read, zero beyond its data" \
  bash -c "test $? -eq 0 && grep -q 'emission is taken as zero' '$tmp/led.err'"
printf 'nm,bad\n400,0.001\n450,0.01\n700,-0.001\n' > "$tmp/badled.csv"
refuse colour-radiance-negative "$bin" --emitter "$tmp/badled.csv"

# Lamps (--emitter): CCT, Duv and CIE 13.3 colour rendering of the sample
# lamps (CIE F2, F7, F11 from the CIE's 5 nm table); CIE 015:2004 lists F2
# at 4230 K with Ra 64, F7 at 6500 K with 90 and F11 at 4000 K with 83.  A
# green LED (far from the Planckian locus) gets no CCT and no Ra.
cp "$src/samples/spectra/lamps_cie_f.csv" "$tmp/lamps.csv"
printf 'nm,green\n380,0\n500,0\n520,0.5\n530,1\n540,0.5\n560,0\n780,0\n' > "$tmp/green.csv"
"$bin" --emitter --json "$tmp/lamps.csv" > "$tmp/lamps.json"; rc=$?
check "lamps: runs" test $rc -eq 0
python3 - "$tmp/lamps.json" <<'PY'
import json, sys
d = {s["name"]: s for s in json.load(open(sys.argv[1]))["spectra"]}
for name, cct, ra in (("F2", 4230, 64), ("F7", 6500, 90), ("F11", 4000, 83)):
    s = d[name]
    assert abs(s["CCT_K"] - cct) <= 0.005 * cct, s
    assert abs(s["Ra"] - ra) <= 0.5, s
    assert len(s["R"]) == 14 and abs(sum(s["R"][:8]) / 8 - s["Ra"]) < 1e-9, s
    assert s["cri_dc_ok"] is True
PY
check "lamps: CCT and Ra of F2, F7 and F11 as CIE 015 lists them" test $? -eq 0
"$bin" --emitter "$tmp/green.csv" > "$tmp/green.out" 2>&1; rc=$?
check "green LED: runs" test $rc -eq 0
check "green LED: no CCT or Ra (far from the locus)" \
  bash -c "grep '^green' '$tmp/green.out' | grep -q ' -  *-  *-  *-$'"
finish
