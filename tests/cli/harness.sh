# Shared by the command-line tests (sourced): a temporary folder removed on
# exit, a fresh material database in it, and "check NAME CONDITION..." that
# prints TAP-style lines; "finish" prints the totals and sets the status.
tmp=$(mktemp -d)
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$tmp"' EXIT
export VR_MATDB="$tmp/materials.db"
pass=0 fails=0
check() {
  local name=$1; shift
  if "$@"; then echo "ok - $name"; pass=$((pass+1)); else echo "not ok - $name"; fails=$((fails+1)); fi
}
finish() {
  echo "$pass passed, $fails failed"
  test $fails -eq 0
}

# "refuse ID command..." runs a command that must be refused as the row ID
# of docs/bad-input.md says: the exit status of the row's "exit" column and
# a message containing the row's "message" text (backticks stripped).  The
# table in the docs is thus the expected behaviour, kept true here; a row
# whose ID no test uses is caught by tests/cli/test_bad_input_table.sh.
# The command's standard error is left in $tmp/refused.err.
refuse() {
  local id=$1; shift
  local doc="$VR_SOURCE_DIR/docs/bad-input.md"
  local row
  row=$(awk -F'|' -v id="$id" '{ g=$2; gsub(/[ `]/, "", g); if (g == id) { print; exit } }' "$doc")
  if [ -z "$row" ]; then
    echo "not ok - $id: no row '$id' in docs/bad-input.md"; fails=$((fails+1)); return
  fi
  local want_rc want_msg
  want_rc=$(printf '%s' "$row" | awk -F'|' '{ gsub(/[ `]/, "", $5); print $5 }')
  want_msg=$(printf '%s' "$row" | awk -F'|' '{ m=$6; gsub(/`/, "", m); sub(/^ +/, "", m); sub(/ +$/, "", m); print m }')
  "$@" > "$tmp/refused.out" 2> "$tmp/refused.err"
  local rc=$?
  if [ "$rc" = "$want_rc" ] && grep -qF -- "$want_msg" "$tmp/refused.err"; then
    echo "ok - $id (exit $rc)"; pass=$((pass+1))
  else
    echo "not ok - $id: exit $rc (want $want_rc), message: $(head -c 400 "$tmp/refused.err") (want: $want_msg)"
    fails=$((fails+1))
  fi
}

# "annual_scene FILE" writes a small annual study: a ground plane, the
# sun and the Perez sky of the Chicago weather file, one sensor, hours 9
# to 15 (for tests of what an annual study refuses or writes).
annual_scene() {
  cat > "$1" <<EOF
material ground lambert reflectance=0.2
rect center=0,0,0 normal=0,0,1 size=10,10 material=ground
light sun spectrum=D65
sky perez weather=$VR_SOURCE_DIR/tests/data/weather/chicago.wea
sensor top point position=0,0,0.001 normal=0,0,1
annual hours=9,15
render sensor_samples=64
EOF
}
