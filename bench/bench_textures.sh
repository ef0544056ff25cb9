#!/usr/bin/env bash
# Textures, end to end (issue 32's target): a public textured interior of
# 262 661 triangles, 24 materials and 9 textures, "The Wooden Staircase" by
# Wig42 (CC BY 3.0; Benedikt Bitterli's Mitsuba version, as kept in the
# GitHub repository jgarciapueyo/mitsuba2-transient-scenes, folder
# staircase/), rendered by vr-render from one mesh line with its own
# materials and textures, and again untextured (one grey material) at the
# same resolution and samples: prints the time to the first pixel (the
# prepare pass: geometry cache, materials, textures), the texture memory,
# the camera pass's time and the ratio textured / untextured.
#
# Usage: bench/bench_textures.sh STAIRCASE_DIR [BUILD_DIR] [SPP] [RESOLUTION]
#   STAIRCASE_DIR holds scene.xml, models/ and textures/; the merged
#   staircase.obj/.mtl are made there on first use (bench/models/mitsuba_obj.py).
set -euo pipefail
dir=${1:?usage: bench_textures.sh STAIRCASE_DIR [BUILD_DIR] [SPP] [RESOLUTION]}
build=${2:-build}
spp=${3:-16}
res=${4:-1280x720}
bin="$(cd "$build" && pwd)/render/vr-render"
here="$(cd "$(dirname "$0")" && pwd)"
cd "$dir"
[ -s staircase.obj ] || python3 "$here/models/mitsuba_obj.py" scene.xml staircase.obj
scene() { # the mesh line's material options, the output scene
  cat > "$2" <<SCN
material grey lambert reflectance=0.5
material lightbody black
mesh staircase.obj up=y $1
rect center=-0.481,1.653,7.13 normal=0,0,-1 size=2.06,2.16 material=lightbody emission=20000cd/m2
camera pinhole from=0.0324,-4.882,1.5267 to=0.0248,-3.883,1.5718 up=0,0,1 fov=60 resolution=$res
render integrator=path spp=$spp depth=5
SCN
}
scene "" bench_tex.scn
scene "material=grey" bench_grey.scn
run() { # scene, prefix
  "$bin" "$1" -o "$2" --threads "$(nproc)" --outputs exr,png --exposure 1 2> "$2.err" > "$2.out"
  local prep cam tex rss
  prep=$(awk '$1 == "pass" && $2 == "prepare" {print $3}' "$2.out")
  cam=$(awk '$1 == "pass" && $2 == "camera" {print $3}' "$2.out")
  tex=$(awk '$1 == "textures" {print $3}' "$2.out")
  rss=$(sed -n 's/.*peak memory \([0-9.]*\) MiB.*/\1/p' "$2.out")
  echo "$prep ${cam} ${tex:-0} $rss"
}
# The geometry cache first (built once, then reused by both runs).
"$bin" bench_grey.scn -o warm --outputs exr --spp 1 --resolution 16x9 > /dev/null 2>&1
read -r tp tc tt tr <<< "$(run bench_tex.scn tex)"
read -r gp gc gt gr <<< "$(run bench_grey.scn grey)"
tris=$(sed -n 's/.*scene: [0-9]* objects, \([0-9]*\) triangles.*/\1/p' tex.err)
objs=$(sed -n 's/.*scene: \([0-9]*\) objects.*/\1/p' tex.err)
echo "model: The Wooden Staircase (Wig42, CC BY 3.0): $tris triangles, $objs objects from one mesh line"
echo "machine: $(nproc) threads, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
printf "%-11s %12s %12s %14s %12s\n" run "prepare (s)" "camera (s)" "textures MiB" "peak MiB"
printf "%-11s %12s %12s %14s %12s\n" textured "$tp" "$tc" "$tt" "$tr"
printf "%-11s %12s %12s %14s %12s\n" untextured "$gp" "$gc" "$gt" "$gr"
awk -v a="$tc" -v b="$gc" -v c="$tp" -v d="$gp" 'BEGIN {
  printf "camera pass textured / untextured: %.2fx (%s spp at %s)\n", a / b, "'"$spp"'", "'"$res"'";
  printf "whole run textured / untextured:   %.2fx\n", (a + c) / (b + d) }'
