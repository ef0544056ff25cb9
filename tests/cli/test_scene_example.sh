#!/usr/bin/env bash
# Command-line test: the complete example of docs/scene-format.md runs as
# written (its first code block, beside a copy of samples/meshes), on a
# fresh material database (the built-in library only), with a smaller
# image, fewer samples and photons so that it is quick; its sensors read
# light.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
source "$(dirname "$0")/harness.sh"
doc="$VR_SOURCE_DIR/docs/scene-format.md"
awk '/^## A complete example/ { on = 1; next } on && /^```/ { if (inside) exit; inside = 1; next } inside { print }' \
  "$doc" > "$tmp/office.scn"
check "the example is extracted" grep -q "^render integrator=photon" "$tmp/office.scn"
cp -r "$VR_SOURCE_DIR/samples/meshes" "$tmp/meshes"
(cd "$tmp" && "$bin" office.scn -o office --resolution 64x48 --spp 1 --photons 20000 --stats office.json \
   > office.out 2> office.err)
rc=$?
check "renders as written (exit $rc: $(tail -1 "$tmp/office.err"))" test $rc -eq 0
check "writes its image" test -s "$tmp/office.exr"
check "its desk sensor reads light" python3 -c "
import json, sys; s = json.load(open('$tmp/office.json'))
d = [r for r in s['sensors'] if r['name'] == 'desk'][0]
sys.exit(0 if d['illuminance_lx'] > 0 else 1)"
finish
