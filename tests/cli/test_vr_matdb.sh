#!/usr/bin/env bash
# Command-line tests of vr-matdb on real files: the built-in library, import
# and export round trips, bad input, outputs that would overwrite the
# database, foreign and read-only databases (issue 18), a writer killed in
# the middle of a large import, and readers working while a writer imports.
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

# --- issue 18: outputs never overwrite inputs ----------------------------------
db_sum=$(sha256sum < "$VR_MATDB")
refuse matdb-export-over-db "$bin" export N-BK7 --csv -o "$VR_MATDB"
refuse matdb-export-over-db bash -c 'cd "$(dirname "$1")" && exec "$2" export N-BK7 --csv -o "$(basename "$1")"' _ "$VR_MATDB" "$bin"
ln -s "$VR_MATDB" "$tmp/link.db"
refuse matdb-export-over-db-link "$bin" export N-BK7 --csv -o "$tmp/link.db"
refuse matdb-export-over-journal "$bin" export N-BK7 --csv -o "$VR_MATDB-wal"
refuse matdb-export-over-journal "$bin" export N-BK7 --csv -o "$VR_MATDB-journal"
check "the database is byte for byte as before" test "$(sha256sum < "$VR_MATDB")" = "$db_sum"
check "... and no -journal file was made" test ! -e "$VR_MATDB-journal"
"$bin" check > /dev/null; check "... and sound" test $? -eq 0
refuse matdb-export-empty-output "$bin" export N-BK7 --csv -o ''
refuse matdb-export-missing-folder "$bin" export N-BK7 --csv -o "$tmp/nosuch/n.csv"
check "... no folder made" test ! -e "$tmp/nosuch"
"$bin" export N-BK7 --csv -o - > "$tmp/stdout.csv"; rc=$?
check "-o - is standard output" test $rc -eq 0 -a "$(head -1 "$tmp/stdout.csv")" = "nm,n,k" -a ! -e ./-
refuse matdb-db-empty "$bin" --db '' list
mkdir "$tmp/emptyenv"
(cd "$tmp/emptyenv" && VR_MATDB= "$bin" list > /dev/null 2> list.err); rc=$?
check "an empty \$VR_MATDB counts as unset: ./materials.db" test $rc -eq 0 -a -s "$tmp/emptyenv/materials.db"
check "... and list names it" grep -q "78 materials in materials.db" "$tmp/emptyenv/list.err"

# --- a foreign SQLite file or a CSV as the database: refused, untouched ------
python3 - "$tmp" <<'PY'
import sqlite3, sys
for name, mode in (("foreign.db", "DELETE"), ("foreign_wal.db", "WAL")):
    c = sqlite3.connect(sys.argv[1] + "/" + name)
    c.execute("PRAGMA journal_mode = " + mode)
    c.execute("CREATE TABLE invoices (id INTEGER, amount REAL)")
    c.execute("INSERT INTO invoices VALUES (1, 2.5)")
    c.commit()
    c.close()
PY
for f in foreign.db foreign_wal.db; do
  sum=$(sha256sum < "$tmp/$f")
  refuse matdb-foreign-sqlite "$bin" --db "$tmp/$f" list
  refuse matdb-foreign-sqlite-import "$bin" --db "$tmp/$f" import "$src/tests/data/CLEAR_3.DAT"
  refuse matdb-foreign-sqlite-import "$bin" --db "$tmp/$f" init
  check "$f: the message names the file" grep -q "$tmp/$f" "$tmp/refused.err"
  check "$f: byte for byte as before (journal mode too)" test "$(sha256sum < "$tmp/$f")" = "$sum"
  check "$f: no -wal, -shm or -journal made beside it" \
    test ! -e "$tmp/$f-wal" -a ! -e "$tmp/$f-shm" -a ! -e "$tmp/$f-journal"
done
printf 'nm,value\n400,0.5\n410,0.6\n' > "$tmp/spectrum.csv"
cp "$tmp/spectrum.csv" "$tmp/spectrum.orig"
refuse matdb-not-sqlite "$bin" --db "$tmp/spectrum.csv" import "$src/tests/data/CLEAR_3.DAT"
refuse matdb-not-sqlite "$bin" --db "$tmp/spectrum.csv" list
check "the CSV given as --db is untouched" cmp -s "$tmp/spectrum.csv" "$tmp/spectrum.orig"
refuse matdb-db-folder "$bin" --db "$tmp" list
: > "$tmp/zero.db"
"$bin" --db "$tmp/zero.db" list > /dev/null 2>&1; rc=$?
check "a 0-byte file is a new database (created and seeded)" test $rc -eq 0 -a -s "$tmp/zero.db"
# A writer killed in a rollback-journal database leaves a hot journal; the
# first reader has SQLite roll it back (the identity check must not stop it).
"$bin" --db "$tmp/hot.db" init > /dev/null
python3 - "$tmp/hot.db" <<'PY'
import os, sqlite3, sys
c = sqlite3.connect(sys.argv[1], isolation_level=None)
c.execute("PRAGMA journal_mode = DELETE").fetchall()
c.execute("PRAGMA cache_size = 1")
c.execute("BEGIN")
c.execute("UPDATE sample SET value = value + 1")
os._exit(0)
PY
check "a killed writer left a hot journal" test -s "$tmp/hot.db-journal"
out=$("$bin" --db "$tmp/hot.db" eval N-BK7 587.56 2>&1)
check "a reader recovers it: N-BK7 nd = 1.51680 (SCHOTT)" test -n "$(echo "$out" | grep '^587.56 *1.5168')"
check "... in rollback mode still" test "$(od -An -tu1 -j18 -N1 "$tmp/hot.db" | tr -d ' ')" = 1

# --- a read-only shared database ----------------------------------------------
# Root ignores file modes, so the reader runs in an unprivileged user
# namespace (unshare -U: mapped to nobody, no capability over the files).
# Two copies: WAL mode (as vr-matdb leaves it) and rollback-journal mode.
ro="$tmp/shared"
mkdir -p "$ro/wal" "$ro/rollback" "$tmp/ro_out"
"$bin" --db "$ro/wal/m.db" import "$src/tests/data/CLEAR_3.DAT" > /dev/null
cp "$ro/wal/m.db" "$ro/rollback/m.db"
python3 -c 'import sqlite3, sys; c = sqlite3.connect(sys.argv[1]); c.execute("PRAGMA journal_mode = DELETE"); c.close()' "$ro/rollback/m.db"
check "the copies are in WAL and rollback mode (SQLite header byte 18: 2 and 1)" \
  test "$(od -An -tu1 -j18 -N1 "$ro/wal/m.db" | tr -d ' ')" = 2 -a \
       "$(od -An -tu1 -j18 -N1 "$ro/rollback/m.db" | tr -d ' ')" = 1
"$bin" --db "$ro/wal/m.db" export CLEAR_3 --csv -o "$tmp/clear_ref.csv"
# An older schema (a material database's application id, user_version 0
# and no tables yet): it must be migrated, which writes it.
python3 -c 'import sqlite3, sys; c = sqlite3.connect(sys.argv[1]); c.execute("PRAGMA application_id = 1448232013"); c.close()' "$ro/wal/old.db"
chmod 755 "$tmp"; chmod 777 "$tmp/ro_out"
chmod 444 "$ro"/*/m.db; chmod 555 "$ro/wal" "$ro/rollback"
chmod 444 "$ro/wal/old.db"
# Without user namespaces (a container's seccomp profile blocks them),
# root keeps its uid but drops the capabilities that override file modes
# (setpriv, util-linux), so the 444/555 modes bind it as they bind anyone
# and it can still read the binaries and the test data; a user who is not
# root is already bound by the modes.
asuser=()
if unshare -U true 2> /dev/null; then asuser=(unshare -U)
elif [ "$(id -u)" -eq 0 ]; then asuser=(setpriv --bounding-set -dac_override,-dac_read_search,-fowner)
fi
{
  "${asuser[@]}" touch "$ro/wal/probe" 2> /dev/null
  check "the test user really cannot write the shared folder" test ! -e "$ro/wal/probe"
  for mode in wal rollback; do
    d="$ro/$mode"
    before=$(sha256sum "$d/m.db"; ls -a "$d")
    "${asuser[@]}" "$bin" --db "$d/m.db" list > "$tmp/ro_list" 2> "$tmp/ro_err"; rc=$?
    check "$mode, read-only: list works" test $rc -eq 0
    check "$mode, read-only: the 78 built-in materials and CLEAR_3" grep -q "^79 materials" "$tmp/ro_err"
    "${asuser[@]}" "$bin" --db "$d/m.db" show CLEAR_3 > "$tmp/ro_show"; rc=$?
    check "$mode, read-only: show works" test $rc -eq 0 -a -n "$(grep 'thickness *3.048 mm' "$tmp/ro_show")"
    # SCHOTT: N-BK7 nd = 1.51680 at 587.56 nm
    out=$("${asuser[@]}" "$bin" --db "$d/m.db" eval N-BK7 587.56)
    check "$mode, read-only: eval gives N-BK7 nd = 1.51680" test -n "$(echo "$out" | grep '^587.56 *1.5168')"
    "${asuser[@]}" "$bin" --db "$d/m.db" export CLEAR_3 --csv -o "$tmp/ro_out/$mode.csv"; rc=$?
    check "$mode, read-only: export to a writable folder works" test $rc -eq 0
    check "$mode, read-only: ... the same CSV as from the writable database" cmp -s "$tmp/ro_out/$mode.csv" "$tmp/clear_ref.csv"
    "${asuser[@]}" "$bin" --db "$d/m.db" history CLEAR_3 > /dev/null 2>&1; rc=$?
    check "$mode, read-only: history works" test $rc -eq 0
    "${asuser[@]}" "$bin" --db "$d/m.db" check > /dev/null; rc=$?
    check "$mode, read-only: check works" test $rc -eq 0
    "${asuser[@]}" "$bin" --db "$d/m.db" init > "$tmp/ro_init"; rc=$?
    check "$mode, read-only: init says it is ready and read-only" test $rc -eq 0 -a -n "$(grep 'read-only' "$tmp/ro_init")"
    refuse matdb-readonly-import "${asuser[@]}" "$bin" --db "$d/m.db" import "$src/tests/data/CLEAR_3.DAT"
    check "$mode, read-only: the message names the database" grep -q "$d/m.db: the material database is read-only (the file is not writable)" "$tmp/refused.err"
    refuse matdb-readonly-rm "${asuser[@]}" "$bin" --db "$d/m.db" rm CLEAR_3 --yes
    check "$mode, read-only: nothing changed, nothing made beside it" test "$(sha256sum "$d/m.db"; ls -a "$d")" = "$before"
    # The other tools read it too: vr-spectro without --save, vr-render.
    spectro="$VR_BIN/../fit/vr-spectro"
    if [ -x "$spectro" ]; then
      "${asuser[@]}" "$spectro" --db "$d/m.db" metrics CLEAR_3 --json > "$tmp/ro_metrics.json" 2> "$tmp/ro_err"; rc=$?
      check "$mode, read-only: vr-spectro metrics of a database material" test $rc -eq 0 -a -s "$tmp/ro_metrics.json"
      [ $rc -eq 0 ] || sed 's/^/# /' "$tmp/ro_err"
    fi
    render="$VR_BIN/../render/vr-render"
    if [ -x "$render" ]; then
      cat > "$tmp/ro_out/ag.scn" <<'EOF'
camera pinhole from=0,-6,4 to=0,0,0 up=0,0,1 fov=60 resolution=8x6
material grey lambert reflectance=0.5
material mirror db:Ag
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
sphere center=0,0,0.5 radius=0.3 material=mirror
light point position=0,0,3 intensity=1000cd
sensor floor point position=1,0,0 normal=0,0,1
render integrator=path spp=1
EOF
      "${asuser[@]}" "$render" --db "$d/m.db" "$tmp/ro_out/ag.scn" --sensors-only -o "$tmp/ro_out/ag_$mode" --quiet > /dev/null 2> "$tmp/ro_err"; rc=$?
      check "$mode, read-only: vr-render loads a material from it" test $rc -eq 0
      [ $rc -eq 0 ] || sed 's/^/# /' "$tmp/ro_err"
    fi
    check "$mode, read-only: still nothing changed after the other tools" test "$(sha256sum "$d/m.db"; ls -a "$d")" = "$before"
  done
  refuse matdb-create-readonly-folder "${asuser[@]}" "$bin" --db "$ro/wal/new.db" init
  refuse matdb-migrate-readonly "${asuser[@]}" "$bin" --db "$ro/wal/old.db" list
  # The advice works: a copy in a writable folder, migrated by init.
  cp "$ro/wal/old.db" "$tmp/ro_out/old.db"; chmod 666 "$tmp/ro_out/old.db"
  "${asuser[@]}" "$bin" --db "$tmp/ro_out/old.db" init > /dev/null 2>&1; rc=$?
  "${asuser[@]}" "$bin" --db "$tmp/ro_out/old.db" list > /dev/null 2> "$tmp/old_err"
  check "... and its advice works: a writable copy is migrated by init" \
    bash -c '[ "$1" = 0 ] && grep -q "^78 materials" "$2"' _ "$rc" "$tmp/old_err"
}
chmod 755 "$ro/wal" "$ro/rollback"

# --- a material's --version, the program's --version --------------------------
"$bin" show N-BK7 --version 1 > "$tmp/v1"; rc=$?
check "show NAME --version 1 shows version 1" test $rc -eq 0 -a "$(head -1 "$tmp/v1")" = "N-BK7 (version 1, dielectric)"
"$bin" show N-BK7 -v 1 > "$tmp/v1s"
check "... as -v 1" cmp -s "$tmp/v1" "$tmp/v1s"
"$bin" eval N-BK7 587.56 --version 1 --json > "$tmp/v1e"; rc=$?
check "eval NAME --version 1" test $rc -eq 0 -a -n "$(grep '"version": 1' "$tmp/v1e")"
"$bin" export N-BK7 --csv --version 1 > "$tmp/v1x"; rc=$?
check "export NAME --version 1" test $rc -eq 0 -a "$(head -1 "$tmp/v1x")" = "nm,n,k"
"$bin" --version > "$tmp/ver"; rc=$?
check "--version alone is the program's" test $rc -eq 0 -a -n "$(grep '^vr-matdb (Virtuelium-C) ' "$tmp/ver")"
"$bin" --help > "$tmp/help"
check "--help tells both apart" grep -q -- "--version  *alone: show the program version" "$tmp/help"
refuse matdb-version-unknown "$bin" show N-BK7 --version 2
refuse matdb-version-not-number "$bin" show N-BK7 --version 1.5
refuse matdb-version-zero "$bin" eval N-BK7 587.56 --version 0
refuse matdb-version-no-value "$bin" show N-BK7 --version

# --- options that do not apply, extra operands --------------------------------
refuse matdb-option-not-applicable "$bin" list -o "$tmp/list.csv"
check "... and wrote nothing" test ! -e "$tmp/list.csv"
refuse matdb-option-not-applicable "$bin" show N-BK7 --yaml
refuse matdb-extra-operand "$bin" show N-BK7 Si
refuse matdb-export-format "$bin" export N-BK7 --csv --yaml

# --- IGDB names in Windows-1252, JSON always valid UTF-8 ----------------------
# 0xE9 is é, 0xAE ®, 0x93/0x94 the curly quotes in Windows-1252 (Unicode's
# CP1252.TXT mapping table).
python3 - "$src/tests/data/CLEAR_3.DAT" "$tmp/CP1252.DAT" <<'PY'
import sys
t = open(sys.argv[1], "rb").read()
open(sys.argv[2], "wb").write(t.replace(b"Generic Clear Glass", b"Cr\xe9ation Glass\xae \x93Pro\x94"))
PY
"$bin" import "$tmp/CP1252.DAT" > /dev/null; rc=$?
check "a Windows-1252 IGDB file imports" test $rc -eq 0
"$bin" show CP1252 --json > "$tmp/cp.json"
python3 - "$tmp/cp.json" <<'PY'
import json, sys
d = json.loads(open(sys.argv[1], "rb").read().decode("utf-8"))
want = "Cr\u00e9ation Glass\u00ae \u201cPro\u201d"
assert d["description"] == want, d["description"]
assert [p["text"] for p in d["properties"] if p["key"] == "product_name"] == [want]
PY
check "... its product name is UTF-8 in show --json" test $? -eq 0
"$bin" list --json > "$tmp/all.json"
python3 -c 'import json, sys; json.loads(open(sys.argv[1], "rb").read().decode("utf-8"))' "$tmp/all.json"
check "list --json is valid UTF-8 JSON" test $? -eq 0
badname="$tmp/$(printf 'grey\xe9card').csv"
printf 'nm,value\n400,0.5\n410,0.6\n' > "$badname"
refuse matdb-name-not-utf8 "$bin" import "$badname"
"$bin" import "$badname" --name grey-card > /dev/null; rc=$?
check "... with --name it imports" test $rc -eq 0
"$bin" show grey-card --json > "$tmp/gc.json"
python3 -c '
import json, sys
d = json.loads(open(sys.argv[1], "rb").read().decode("utf-8"))
assert d["provenance"]["source_path"].endswith("grey\ufffdcard.csv"), d["provenance"]["source_path"]' "$tmp/gc.json"
check "... a non-UTF-8 file name shows as U+FFFD in JSON" test $? -eq 0
# A row written by an older build with a Windows-1252 byte in it.
python3 -c '
import sqlite3, sys
c = sqlite3.connect(sys.argv[1])
sqlite3.connect(sys.argv[2]).backup(c)
c.execute("UPDATE material SET description = CAST(x%s AS TEXT) WHERE name = %s" % ("\x274372e96174696f6e\x27", "\x27N-BK7\x27"))
c.commit()' "$tmp/old.db" "$VR_MATDB"
"$bin" --db "$tmp/old.db" show N-BK7 --json > "$tmp/old.json"
python3 -c '
import json, sys
d = json.loads(open(sys.argv[1], "rb").read().decode("utf-8"))
assert d["description"] == "Cr\ufffdation", d["description"]' "$tmp/old.json"
check "an old row with a Windows-1252 byte gives valid JSON (U+FFFD)" test $? -eq 0

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
