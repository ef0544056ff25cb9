#!/usr/bin/env bash
# Command-line test: a write to standard output that fails is a failure
# (issue 35, class 1; docs/bad-input.md, rows stdout-full-*).  Each of the
# six tools prints its usual result to /dev/full, a device every write to
# which fails with ENOSPC as a full disk does: the tool must exit 1 and say
# "cannot write standard output" on stderr, not exit 0 with nothing
# written.  The same commands to a regular file succeed (the guard only
# fires on a failed write).
set -u
src="$VR_SOURCE_DIR"
source "$(dirname "$0")/harness.sh"
s="$src/samples"
test -c /dev/full || { echo "not ok - /dev/full is missing on this machine"; exit 1; }

full() { "$@" > /dev/full; }   # the command, its standard output on /dev/full
to_file() { # NAME, then the command: to a regular file it succeeds and writes
  local name=$1; shift
  "$@" > "$tmp/$name.out" 2> "$tmp/$name.err"
  check "$name: the same command to a file succeeds and writes" test $? -eq 0 -a -s "$tmp/$name.out"
}
export -f full

cc=("$VR_COLOUR" "$s/spectra/colorchecker_babelcolor.csv")
refuse stdout-full-colour bash -c 'full "$@"' _ "${cc[@]}"
to_file colour "${cc[@]}"
md=("$VR_MATDB_TOOL" list)
refuse stdout-full-matdb bash -c 'full "$@"' _ "${md[@]}"
to_file matdb "${md[@]}"
el=("$VR_ELLIPSO" simulate --model "$s/ellipsometry/thermal_oxide.model" --angles 70 --wavelengths 500:600:10)
refuse stdout-full-ellipso bash -c 'full "$@"' _ "${el[@]}"
to_file ellipso "${el[@]}"
sp=("$VR_SPECTRO" metrics "$s/glazing/clear_float/CLEAR_3.DAT")
refuse stdout-full-spectro bash -c 'full "$@"' _ "${sp[@]}"
to_file spectro "${sp[@]}"
refuse stdout-full-rgb2spec bash -c 'full "$@"' _ "$VR_RGB2SPEC" --help
to_file rgb2spec "$VR_RGB2SPEC" --help
refuse stdout-full-render bash -c 'full "$@"' _ "$VR_RENDER" --help
to_file render "$VR_RENDER" --help
# A render's report goes to standard output too: refused, after the image.
cat > "$tmp/r.scn" <<SCN
material grey lambert reflectance=0.5
rect center=0,0,0 normal=0,0,1 size=1,1 material=grey
camera pinhole from=0,-2,1 to=0,0,0 up=0,0,1 resolution=8x8
light point position=0,0,2 intensity=10cd
render integrator=path spp=1
SCN
refuse stdout-full-render-report bash -c '"$1" "$2" -o "$3" > /dev/full' _ "$VR_RENDER" "$tmp/r.scn" "$tmp/r"
finish
