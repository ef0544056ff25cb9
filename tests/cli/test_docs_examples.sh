#!/usr/bin/env bash
# Command-line test: the documentation's examples run as written (issue 35,
# class 6: vr-render.md's first example had failed, and left a stray
# materials.db behind).  Every ```sh block of docs/*.md is run with bash
# -e, from a root that looks like the repository's after a build (a copy of
# samples/, build/ the build tree under test), each block in a fresh root;
# it must exit 0 and leave no materials.db in the root (the examples name
# their database).
set -u
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
unset VR_MATDB
blocks=0
for doc in "$src"/docs/*.md; do
  # Each block to its own file, named by the document and its first line.
  awk -v out="$tmp/block" -v doc="$(basename "$doc")" '
    /^```sh[ \t]*$/ { inb = 1; n++; f = sprintf("%s.%s.%d", out, doc, NR + 1); next }
    /^```/ && inb { inb = 0; close(f); next }
    inb { print > f }' "$doc"
done
for f in "$tmp"/block.*; do
  [ -e "$f" ] || continue
  blocks=$((blocks + 1))
  name=${f#"$tmp"/block.}
  where="docs/${name%.*}:${name##*.}"
  root="$tmp/root.$blocks"
  mkdir -p "$root"
  cp -r "$src/samples" "$root/samples"
  ln -s "$VR_BUILD_DIR" "$root/build"
  (cd "$root" && bash -e -o pipefail "$f") > "$tmp/out.$blocks" 2> "$tmp/err.$blocks"
  rc=$?
  check "$where: the example runs (exit $rc)" test $rc -eq 0
  [ $rc -eq 0 ] || tail -5 "$tmp/err.$blocks"
  check "$where: it leaves no ./materials.db" test ! -e "$root/materials.db"
done
check "the documents hold runnable examples (found $blocks)" test "$blocks" -ge 2
finish
