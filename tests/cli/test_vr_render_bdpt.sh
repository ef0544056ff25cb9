#!/usr/bin/env bash
# Command-line test of vr-render with render integrator=bdpt: a scene
# renders end to end (decomposed options left at one cell, and in image
# space), and what BDPT cannot do is refused before any work, as the rows
# render-bdpt-* of docs/bad-input.md say: more than one sub-domain, a
# memory budget, several MPI ranks, a fisheye camera.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
source "$(dirname "$0")/harness.sh"

cat > "$tmp/bdpt.scn" <<'EOF'
# A point lamp and an emitting panel over a grey floor.
camera pinhole from=0,-6,4 to=0,0,0 up=0,0,1 fov=60 resolution=32x24
material grey lambert reflectance=0.5
material lamp black
rect center=0,0,0 normal=0,0,1 size=20,20 material=grey
rect center=0,0,3 normal=0,0,-1 size=0.5,0.5 material=lamp emission=5000cd/m2
light point position=2,0,2 intensity=300cd
render integrator=bdpt spp=4 depth=4
EOF
(cd "$tmp" && "$bin" bdpt.scn --threads 2 --stats bdpt.json > out.txt 2> log.txt); rc=$?
check "renders with integrator=bdpt" test $rc -eq 0
[ $rc -eq 0 ] || sed 's/^/# /' "$tmp/log.txt"
for f in bdpt.exr bdpt.png bdpt.json; do check "wrote $f" test -s "$tmp/$f"; done
check "the camera pass says bidirectional path tracing" \
  grep -q '"name": "camera".*bidirectional path tracing' "$tmp/bdpt.json"
rays_ok() {
  python3 - "$1" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))["rays"]
sys.exit(0 if r["photon"] > 0 and r["shadow"] > 0 and r["created"] == r["finished"] else 1)
PY
}
check "light subpaths count as photon rays, connections as shadow rays" rays_ok "$tmp/bdpt.json"
(cd "$tmp" && "$bin" bdpt.scn --image-space --subdomains 4 -o space --quiet); rc=$?
check "image space (the scene in one cell) is accepted, --subdomains then ignored" test $rc -eq 0

refuse render-bdpt-subdomains "$bin" "$tmp/bdpt.scn" --subdomains 4 -o "$tmp/sub"
check "nothing written after the refusal" test ! -e "$tmp/sub.png"
refuse render-bdpt-budget "$bin" "$tmp/bdpt.scn" --memory-budget 1G -o "$tmp/budget"
sed 's/^camera pinhole/camera fisheye/' "$tmp/bdpt.scn" > "$tmp/fish.scn"
refuse render-bdpt-fisheye "$bin" "$tmp/fish.scn" -o "$tmp/fish"
# Built with MPI, the ranks' case must run (a missing mpirun fails it);
# the one-process configuration (-DVR_MPI=OFF) has no ranks to refuse.
if [ "${VR_HAVE_MPI:-OFF}" = "ON" ]; then
  check "mpirun is there (scripts/install-deps.sh)" command -v mpirun
  mpi=(mpirun --oversubscribe)
  [ "$(id -u)" -eq 0 ] && mpi+=(--allow-run-as-root)
  if [ -n "${ASAN_OPTIONS:-}" ]; then
    export ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0"
    mpi+=(-x ASAN_OPTIONS)
  fi
  refuse render-bdpt-ranks timeout 120 "${mpi[@]}" -np 2 "$bin" "$tmp/bdpt.scn" -o "$tmp/ranks"
fi
finish
