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
