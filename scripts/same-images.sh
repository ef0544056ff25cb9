#!/usr/bin/env bash
# Renders one matrix of scenes with two builds of vr-render and checks that
# they agree bit for bit: every integrator (path, whitted, photon with and
# without final gathering, progressive, bdpt), both sensor estimators, the
# photochromic UV pass, pinhole, thin-lens and fisheye cameras, sub-domains,
# a memory budget, image space, 2 MPI ranks, and an annual study.  For
# refactorings that must not change a pixel (issue 30).
#
# Usage: scripts/same-images.sh OLD_BUILD NEW_BUILD DATABASE [WORKDIR]
#   OLD_BUILD, NEW_BUILD: build trees (their render/vr-render is run);
#   DATABASE: a material database filled by scripts/main-job.sh (out/materials.db);
#   WORKDIR: scratch folder (default: a new temporary one).
# Prints one line per case and exits 1 if any case differs.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
old=$(cd "$1" && pwd); new=$(cd "$2" && pwd); db=$(cd "$(dirname "$3")" && pwd)/$(basename "$3")
work=${4:-$(mktemp -d)}
mkdir -p "$work/scenes"
cmp_exr=$new/tests/vr-test-exr-compare
mpi=(mpirun --oversubscribe -np 2)
[ "$(id -u)" -eq 0 ] && mpi=(mpirun --oversubscribe --allow-run-as-root -np 2)

# Scene variants of samples/room.scn (the meshes beside them) and of the
# Cornell box with an N-BK7 slab.
cp -r "$root/samples/meshes" "$work/scenes/"
room=$work/scenes/room.scn
sed -e 's/^render .*/render integrator=photon photons=20000 knn=50 spp=4/' "$root/samples/room.scn" > "$room"
variant() { # NAME SED-EXPRESSION...
  local name=$1; shift
  sed "$@" "$room" > "$work/scenes/$name.scn"
}
variant room_path -e 's/^render .*/render integrator=path spp=4 sampler=independent/'
variant room_sobol -e 's/^render .*/render integrator=path spp=4/'
variant room_stratified -e 's/^render .*/render integrator=path spp=4 sampler=stratified/'
variant room_whitted -e 's/^render .*/render integrator=whitted spp=4/'
variant room_fg -e 's/^render .*/render integrator=photon photons=20000 knn=50 spp=2 final_gather=on gather_rays=4/'
variant room_sppm -e 's/^render .*/render integrator=progressive photons=20000 spp=4/'
variant room_bdpt -e 's/^render .*/render integrator=bdpt spp=4/'
variant room_psens -e 's/^render .*/render integrator=photon photons=20000 knn=50 spp=4 sensors=photon sensor_samples=256/'
variant room_portal -e 's/^render .*/render integrator=photon photons=20000 knn=50 spp=4 photon_portals=on/' \
  -e "\$a portal center=1.5,-2,1.6 normal=0,1,0 size=1.4,1.4" -e "\$a portal center=3.5,-2,1.6 normal=0,1,0 size=1.4,1.4"
variant room_thinlens -e 's/^camera pinhole/camera thinlens aperture=0.02 focus=2.5/' -e 's/^render .*/render integrator=path spp=4/'
variant room_fisheye -e 's/^camera pinhole \(.*\) fov=80 resolution=320x240/camera fisheye \1 fov=180 resolution=96x96/' \
  -e 's/^render .*/render integrator=path spp=4/'
variant room_bins -e 's/^render .*/render integrator=path spp=4 spectral=bins wavelengths=8/'
variant room_pc -e 's/^material ec .*/material ec db:photochromic-glass/' -e 's/^render .*/render integrator=path spp=4/'
variant room_spot -e 's/^light point .*/light spot position=4.77,-1.28,1.5 direction=0,0,-1 cone=30 falloff=10 intensity=400lm/' \
  -e 's/^render .*/render integrator=photon photons=20000 knn=50 spp=4/'
variant room_lamp -e '/^light sun/d' -e '/^sky /d' -e 's/^render .*/render integrator=bdpt spp=4/' \
  -e '$a rect center=2.5,0,2.69 normal=0,0,-1 size=0.4,0.4 material=paint emission=2000cd/m2'
cornell=$work/scenes/cornell_bk7.scn
sed -e "s#\.\./\.\./samples/#$root/samples/#" -e 's/resolution=256x256/resolution=48x48/' \
  -e 's/^render .*/render integrator=progressive range=400,700 spp=4 depth=16 photons=20000/' \
  "$root/bench/scenes/cornell_bk7.scn" > "$cornell"
sed -e 's/^render .*/render integrator=bdpt range=400,700 spp=4 depth=16/' "$cornell" > "$work/scenes/cornell_bdpt.scn"

fail=0
run_case() { # NAME [mpi] SCENE [vr-render options...]; 'mpi' runs it on 2 ranks
  local name=$1 launch=(); shift
  if [ "$1" = mpi ]; then launch=("${mpi[@]}"); shift; fi
  local scene=$1; shift
  for side in old new; do
    local bin=$old; [ $side = new ] && bin=$new
    mkdir -p "$work/$side"
    local outs=(--outputs exr,spectral,sensors) extra=()
    grep -q '^sensor' "$scene" || outs=(--outputs exr,spectral)
    case "$name $*" in office*) outs=() ;; *--sensors-only*) outs=(--outputs sensors) ;; esac
    # The control case: the new side renders another seed, and must differ.
    [ "$name" = control ] && [ $side = new ] && extra=(--seed 2)
    "${launch[@]}" "$bin/render/vr-render" "$scene" --db "$db" -o "$work/$side/$name" --quiet \
      "${outs[@]}" --cache "$work/$side/cache-$name" "$@" "${extra[@]}" > /dev/null
  done
  local same=yes
  for f in "$work/old/$name".*; do
    local ext=${f#"$work/old/$name"}
    case $ext in .manifest.json|.partial*) continue ;; esac
    if ! cmp -s "$f" "$work/new/$name$ext"; then
      if [ "$ext" = .exr ] && "$cmp_exr" "$f" "$work/new/$name$ext" 0 > /dev/null 2>&1; then continue; fi
      same="no ($ext differs)"
    fi
  done
  if [ "$name" = control ]; then
    # The comparison itself must be able to fail.
    if [ "$same" = yes ]; then same="no (a different seed gave the same files)"; else same=yes; fi
  fi
  [ "$same" = yes ] || fail=1
  printf '%-22s %s\n' "$name" "$same"
}
small=(--resolution 64x48 --threads 2)
run_case control "$work/scenes/room_path.scn" "${small[@]}"
run_case room_photon "$room" "${small[@]}"
run_case room_path "$work/scenes/room_path.scn" "${small[@]}"
run_case room_sobol "$work/scenes/room_sobol.scn" "${small[@]}"
run_case room_stratified "$work/scenes/room_stratified.scn" "${small[@]}"
run_case room_whitted "$work/scenes/room_whitted.scn" "${small[@]}"
run_case room_fg "$work/scenes/room_fg.scn" "${small[@]}"
run_case room_sppm "$work/scenes/room_sppm.scn" "${small[@]}"
run_case room_bdpt "$work/scenes/room_bdpt.scn" "${small[@]}"
run_case room_psens "$work/scenes/room_psens.scn" --sensors-only --threads 2
run_case room_portal "$work/scenes/room_portal.scn" "${small[@]}"
run_case room_thinlens "$work/scenes/room_thinlens.scn" "${small[@]}"
run_case room_fisheye "$work/scenes/room_fisheye.scn" --threads 2
run_case room_bins "$work/scenes/room_bins.scn" "${small[@]}"
run_case room_pc "$work/scenes/room_pc.scn" "${small[@]}"
run_case room_spot "$work/scenes/room_spot.scn" "${small[@]}"
run_case room_lamp "$work/scenes/room_lamp.scn" "${small[@]}"
run_case room_s8 "$room" "${small[@]}" --subdomains 8
run_case room_budget "$work/scenes/room_path.scn" "${small[@]}" --subdomains 8 --memory-budget 150K
run_case room_imagespace "$room" "${small[@]}" --image-space
run_case room_mpi mpi "$room" --resolution 64x48 --threads 1 --subdomains 8
run_case room_mpi_sppm mpi "$work/scenes/room_sppm.scn" --resolution 64x48 --threads 1 --subdomains 8
run_case cornell_sppm "$cornell" --threads 2
run_case cornell_bdpt "$work/scenes/cornell_bdpt.scn" --threads 2
run_case office_pc "$root/samples/annual/office_pc.scn" --threads 2
echo "work folder: $work"
exit $fail
