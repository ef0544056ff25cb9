#!/usr/bin/env bash
# docs/bad-input.md is kept true by the command-line tests: each row is run
# by a "refuse ROW-ID ..." line of some test (which checks the exit status
# and the message the row gives).  Here: every row is used by a test, every
# ID a test uses has a row, and no ID appears twice.
set -u
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
doc="$src/docs/bad-input.md"
awk -F'|' '/^\| *`?[a-z][a-z0-9-]*`? *\|/ { g=$2; gsub(/[ `]/, "", g); if (g != "id") print g }' "$doc" | sort > "$tmp/rows"
grep -ho 'refuse [a-z0-9-]*' "$src"/tests/cli/*.sh | awk '$2 != "" && $2 != "ID" { print $2 }' | sort -u > "$tmp/used"
check "the table has rows" test -s "$tmp/rows"
check "no row ID appears twice" test -z "$(uniq -d "$tmp/rows")"
unused=$(comm -23 "$tmp/rows" "$tmp/used")
check "every row is run by a test (unused: ${unused:-none})" test -z "$unused"
missing=$(comm -13 "$tmp/rows" "$tmp/used")
check "every refused case a test runs has a row (missing: ${missing:-none})" test -z "$missing"
while IFS='|' read -r _ id tool input code msg _; do
  id=$(echo "$id" | tr -d ' `')
  case "$id" in ''|id|-*) continue ;; esac
  code=$(echo "$code" | tr -d ' `')
  check "row $id has an exit status of 1 or 2" test "$code" = 1 -o "$code" = 2
  check "row $id names its tool" grep -q "vr-" <<< "$tool"
done < <(grep '^|' "$doc")
finish
