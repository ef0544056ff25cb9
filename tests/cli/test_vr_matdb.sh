#!/usr/bin/env bash
# Command-line tests of vr-matdb on real files: the built-in library, import
# and export round trips, bad input, a writer killed in the middle of a large
# import, and readers working while a writer imports.
set -u
bin="$VR_BIN/vr-matdb"
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"

# --- the built-in library with its sources ---------------------------------
"$bin" list > "$tmp/list" 2> "$tmp/list.err"; rc=$?
check "list on a new database succeeds" test $rc -eq 0
check "list shows N-BK7 with its SCHOTT source" grep -q "^N-BK7 .*dielectric .*SCHOTT" "$tmp/list"
check "list shows Si from Green 2008" grep -qi "^Si .*Green" "$tmp/list"
check "list shows gold (Johnson and Christy)" grep -qi "^Au .*conductor.*Johnson" "$tmp/list"
check "list shows CIE D65" grep -q "^CIE-D65 .*illuminant" "$tmp/list"
check "list shows ASTM G173" grep -q "^ASTM-G173-AM1.5G .*ASTM G173" "$tmp/list"
check "list shows the ColorChecker" grep -q "^ColorChecker-dark_skin .*reflectance" "$tmp/list"
check "list counts 78 materials (24 optical, 30 illuminants, 24 ColorChecker)" grep -q "^78 materials" "$tmp/list.err"
"$bin" list --kind conductor > "$tmp/cond"
check "list --kind conductor gives the 4 metals" test "$(wc -l < "$tmp/cond")" -eq 4

# Published values through the command line: N-BK7 n(587.56) = 1.516800 and
# n(486.13) = 1.522376 (SCHOTT); fused silica n(587.56) = 1.458464 (Malitson
# 1965); Si at 630 nm n = 3.879, k = 0.016444 (Green 2008).
"$bin" eval N-BK7 587.56 486.13 --json > "$tmp/bk7.json"
"$bin" eval fused-silica 587.56 --json > "$tmp/fs.json"
"$bin" eval Si 630 --json > "$tmp/si.json"
python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
bk7 = json.load(open(t + "/bk7.json"))["values"]
assert abs(bk7[0]["n"] - 1.516800) < 1e-6 and abs(bk7[1]["n"] - 1.522376) < 1e-6, bk7
fs = json.load(open(t + "/fs.json"))["values"][0]
assert abs(fs["n"] - 1.458464) < 1e-6, fs
si = json.load(open(t + "/si.json"))["values"][0]
assert abs(si["n"] - 3.879) < 1e-9 and abs(si["k"] - 0.016444) < 1e-9, si
PY
check "published n, k through eval" test $? -eq 0
"$bin" eval N-BK7 250 > /dev/null 2> "$tmp/err"; rc=$?
check "eval outside the range fails" test $rc -eq 1
check "... and says so" grep -q "250 nm is outside its data range 300-2500 nm" "$tmp/err"
"$bin" eval N-BK7 250 --extrapolate > /dev/null 2> "$tmp/err"; rc=$?
check "--extrapolate holds the end value with a warning" test $rc -eq 0 -a -s "$tmp/err"
"$bin" show Nope > /dev/null 2> "$tmp/err"; rc=$?
check "unknown material is an error naming it" grep -q "unknown material 'Nope'" "$tmp/err"
"$bin" show N-BK7 --json | python3 -c 'import json,sys; d=json.load(sys.stdin); assert d["formula"]["type"]==2 and len(d["provenance"]["source_sha256"])==64'
check "show --json has the formula and the provenance" test $? -eq 0

# --- import, export, import -------------------------------------------------
"$bin" import "$src/tests/data/CLEAR_3.DAT" > "$tmp/out"; rc=$?
check "IGDB import" test $rc -eq 0
"$bin" show CLEAR_3 > "$tmp/clear"
check "IGDB fields are kept" grep -q "thickness *3.048 mm" "$tmp/clear"
check "IGDB emissivity kept" grep -q "emissivity_back *0.84" "$tmp/clear"
"$bin" export CLEAR_3 --csv -o "$tmp/clear.csv" && "$bin" import "$tmp/clear.csv" --name CLEAR_3_again > /dev/null
"$bin" show CLEAR_3 --json | python3 -c 'import json,sys; print(json.dumps(json.load(sys.stdin)["spectra"]))' > "$tmp/a"
"$bin" show CLEAR_3_again --json | python3 -c 'import json,sys; print(json.dumps(json.load(sys.stdin)["spectra"]))' > "$tmp/b"
check "DAT -> CSV export -> import gives identical spectra" cmp -s "$tmp/a" "$tmp/b"
for m in N-BK7 Si Al; do
  "$bin" export $m --yaml -o "$tmp/$m.yml" && "$bin" import "$tmp/$m.yml" --name "$m-again" > /dev/null
  "$bin" show $m --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(json.dumps([d["formula"], d["spectra"]]))' > "$tmp/a"
  "$bin" show "$m-again" --json | python3 -c 'import json,sys; d=json.load(sys.stdin); print(json.dumps([d["formula"], d["spectra"]]))' > "$tmp/b"
  check "$m: YAML export -> import gives identical data" cmp -s "$tmp/a" "$tmp/b"
done
"$bin" import "$src/tests/data/CLEAR_3.DAT" > /dev/null
"$bin" history CLEAR_3 > "$tmp/hist"
check "a second import adds version 2" test "$(wc -l < "$tmp/hist")" -eq 2
"$bin" rm CLEAR_3 > /dev/null 2>&1; rc=$?
check "rm without --yes refuses" test $rc -eq 2
"$bin" rm CLEAR_3 --yes > /dev/null; rc=$?
check "rm --yes removes" test $rc -eq 0

# --- bad input ----------------------------------------------------------------
printf 'nm,value\n400,0.5\n410,abc\n' > "$tmp/bad.csv"
"$bin" import "$tmp/bad.csv" > /dev/null 2> "$tmp/err"; rc=$?
check "malformed CSV exits 1" test $rc -eq 1
check "... naming file, line, column and field" grep -q "bad.csv:3:5: field 'value': expected a number, got 'abc'" "$tmp/err"
printf 'DATA:\n  - type: formula 2\n    wavelength_range: 0.3 2.5\n   coefficients: 1 2\n' > "$tmp/bad.yml"
"$bin" import "$tmp/bad.yml" > /dev/null 2> "$tmp/err"; rc=$?
check "malformed YAML exits 1 naming the file and line" test $rc -eq 1 -a -n "$(grep 'bad.yml:[0-9]' "$tmp/err")"
printf '{ Thickness } 3\n0.3 0.5 0.1 0.1\n0.31 0.5 0.1\n' > "$tmp/bad.dat"
"$bin" import "$tmp/bad.dat" > /dev/null 2> "$tmp/err"; rc=$?
check "malformed DAT names line and field" grep -q "bad.dat:3: field 'Rb' is missing" "$tmp/err"
"$bin" list > "$tmp/list2" 2>/dev/null
check "failed imports left nothing behind" test "$(wc -l < "$tmp/list2")" -eq "$(($(wc -l < "$tmp/list") + 4))"
printf 'not a database at all, just text\n%.0s' {1..200} > "$tmp/junk.db"
"$bin" --db "$tmp/junk.db" list > /dev/null 2> "$tmp/err"; rc=$?
check "a junk file is refused" grep -q "not a SQLite database" "$tmp/err"
"$bin" frobnicate > /dev/null 2>&1; rc=$?
check "unknown command is a usage error" test $rc -eq 2

# --- a writer killed in the middle of a large import --------------------------
python3 -c '
import random
random.seed(1)
with open("'"$tmp"'/big.csv", "w") as f:
    f.write("nm,value\n")
    for i in range(1500000):
        f.write("%.6f,%.6f\n" % (300 + i * 0.0005, random.random()))
'
before=$("$bin" list 2>/dev/null | md5sum)
"$bin" import "$tmp/big.csv" --name big > /dev/null 2>&1 &
writer=$!
killed=no
for i in $(seq 1 600); do
  size=$(stat -c %s "$VR_MATDB-wal" 2>/dev/null || echo 0)
  if [ "$size" -gt 8000000 ]; then kill -9 $writer; killed=yes; break; fi
  kill -0 $writer 2>/dev/null || break
  sleep 0.05
done
wait $writer 2>/dev/null
check "the writer was killed inside its transaction (WAL > 8 MB)" test $killed = yes
"$bin" check > /dev/null; rc=$?
check "integrity check passes after kill -9" test $rc -eq 0
after=$("$bin" list 2>/dev/null | md5sum)
check "the database is exactly as before" test "$before" = "$after"
"$bin" show big > /dev/null 2>&1; rc=$?
check "no half material" test $rc -eq 1

# --- two readers and one writer at once --------------------------------------
"$bin" import "$tmp/big.csv" --name big > "$tmp/writer.out" 2>&1 &
writer=$!
reader() {
  local bad=0
  for i in $(seq 1 25); do
    out=$("$bin" eval N-BK7 587.56 2>&1) || bad=$((bad+1))
    case "$out" in *1.5168*) ;; *) bad=$((bad+1));; esac
  done
  echo $bad > "$tmp/reader$1"
}
reader 1 & r1=$!
reader 2 & r2=$!
wait $r1 $r2
wait $writer; wrc=$?
check "reader 1 never failed while the writer wrote" test "$(cat "$tmp/reader1")" -eq 0
check "reader 2 never failed while the writer wrote" test "$(cat "$tmp/reader2")" -eq 0
check "the writer committed" test $wrc -eq 0
"$bin" eval big 300.0005 --role value > /dev/null; rc=$?
check "the large material is readable" test $rc -eq 0

finish
