#!/usr/bin/env bash
# Set-up and the main job: installs dependencies, builds, and runs every
# tool that exists on samples/, writing results under out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh
scripts/build.sh build
mkdir -p out
export VR_MATDB="$root/out/materials.db"
rm -f "$VR_MATDB" "$VR_MATDB-wal" "$VR_MATDB-shm"   # a fresh database each run

echo "== material database: create with the built-in library, import the samples (vr-matdb)"
build/matdb/vr-matdb init
build/matdb/vr-matdb import samples/glazing/clear_float/CLEAR_3.DAT --name NFRC-102-clear
build/matdb/vr-matdb import samples/materials/hikari_e-bk7.yml --name E-BK7
build/matdb/vr-matdb list --kind glazing
build/matdb/vr-matdb show NFRC-102-clear
build/matdb/vr-matdb eval E-BK7 486.13 587.56 656.27
build/matdb/vr-matdb eval N-BK7 486.13 587.56 656.27
build/matdb/vr-matdb export NFRC-102-clear --csv -o out/NFRC-102-clear.csv

echo "== ellipsometry: fit the samples, save the fitted layers (vr-ellipso)"
e=samples/ellipsometry
build/fit/vr-ellipso fit $e/thermal_oxide.csv --model $e/thermal_oxide.model --save SiO2-thermal-fit --report out/thermal_oxide.html
build/fit/vr-ellipso fit $e/coated_glass.csv --model $e/coated_glass.model --save coating-fit --report out/coated_glass.html
build/fit/vr-ellipso fit $e/bare_glass.csv --save soda-lime-ellipso --report out/bare_glass.html
build/matdb/vr-matdb history coating-fit

echo "== glazing: figures, n and k, pane tables and tint-state models (vr-spectro)"
g=samples/glazing
build/fit/vr-spectro metrics $g/clear_float/CLEAR_3.DAT | tee out/clear_float_nfrc.txt
build/fit/vr-spectro metrics --panes $g/clear_float/CLEAR_3.DAT,$g/clear_float/CLEAR_3.DAT --json > out/double_clear_nfrc.json
build/fit/vr-spectro thermal --panes $g/clear_float/CLEAR_3.DAT,$g/clear_float/CLEAR_3.DAT --gaps 12.7:air | tee out/double_clear_thermal.txt
build/fit/vr-spectro thermal --method en673 --panes $g/clear_float/CLEAR_3.DAT,$g/clear_float/CLEAR_3.DAT --gaps 16:air | tee out/double_clear_en673.txt
build/fit/vr-spectro metrics $g/lowe/lowe.csv --standard en410 | tee out/lowe_en410.txt
build/fit/vr-spectro fit $g/clear_float/CLEAR_3.DAT --save clear-float-nk --table out/clear_float_nk.csv
build/fit/vr-spectro btdf clear-float-nk --save clear-float-btdf --wavelengths 300:2500:10 --table out/clear_float_btdf.csv
build/fit/vr-spectro btdf --stack $g/lowe/lowe.model --wavelengths 310:2500:10 --save lowe-btdf --table out/lowe_btdf.csv
build/fit/vr-spectro chromogenic $g/electrochromic/ec_states.csv --save electrochromic-glass
build/fit/vr-spectro chromogenic $g/photochromic/pc_states.csv --save photochromic-glass
build/fit/vr-spectro metrics electrochromic-glass --state 1 | tee out/electrochromic_dark.txt
build/fit/vr-spectro state photochromic-glass --uv 40 --temperature 25C > out/photochromic_40Wm2.csv
# The clear pane and the tinted electrochromic state as BSDF XML (for WINDOW,
# Radiance, EnergyPlus), read back for their figures.
build/fit/vr-spectro bsdf-xml $g/clear_float/CLEAR_3.DAT --out out/clear_float.xml
build/fit/vr-spectro bsdf-xml electrochromic-glass --state 1 --out out/electrochromic_dark.xml
build/fit/vr-spectro metrics out/electrochromic_dark.xml --angle 30 | tee out/electrochromic_dark_bsdf.txt

echo "== reflectance spectra from photos under four lights (vr-rgb2spec)"
build/acquire/vr-rgb2spec samples/photos/*.png --save-prefix photo- --report out/photos.html \
  --per-pixel out/photo_texture.exr --texture photo-texture | tee out/photos.txt

echo "== colour of the ColorChecker under D65 and under A (vr-colour)"
build/core/vr-colour samples/spectra/colorchecker_babelcolor.csv | tee out/colorchecker_D65.txt
build/core/vr-colour --illuminant A --json samples/spectra/colorchecker_babelcolor.csv > out/colorchecker_A.json

echo "== a year of Chicago daylight through the fitted electrochromic (glare control) and photochromic (its own UV) glass: DA, sDA, UDI, ASE (vr-render, annual study)"
for g in ec pc; do
  build/render/vr-render samples/annual/office_$g.scn -o out/office_$g --threads 2 > out/office_$g.txt
  head -3 out/office_$g.txt
done
echo "== the measured Cornell box: photon-mapped illuminance on five patches (vr-matdb, vr-render)"
for c in white red green; do
  build/matdb/vr-matdb import "samples/cornell/cornell_$c.csv" --name "cornell-$c" --kind reflectance
done
build/matdb/vr-matdb import samples/cornell/cornell_light.csv --name cornell-light --kind illuminant
build/render/vr-render samples/cornell/cornell.scn -o out/cornell --threads 2 --sensors-only --quiet
echo "== the hotel room through clear and electrochromic windows, from the database filled above, at 640 x 480 by progressive photon mapping (16 iterations of 200 000 photons) with the PNG denoised (vr-render --render --denoise)"
build/render/vr-render samples/room.scn -o out/room --threads 2 --resolution 640x480 \
  --render "integrator=progressive photons=200000 spp=16" --denoise --stats out/room_stats.json
echo "== the same room's sensors with 8 sub-domains under a 28 MiB memory budget that holds the rug's 24 MiB texture (vr-render --memory-budget)"
build/render/vr-render samples/room.scn -o out/room_budget --threads 2 --subdomains 8 --memory-budget 28M --sensors-only --stats out/room_budget_stats.json
echo "== the same room's sensors on 2 MPI ranks that share its 8 sub-domains (mpirun vr-render)"
mpi=(mpirun --oversubscribe -np 2)
[ "$(id -u)" -eq 0 ] && mpi=(mpirun --oversubscribe --allow-run-as-root -np 2)
"${mpi[@]}" build/render/vr-render samples/room.scn -o out/room_ranks --threads 1 --subdomains 8 --sensors-only --stats out/room_ranks_stats.json
echo "main job done: out/materials.db, out/NFRC-102-clear.csv, out/*.html (ellipsometry reports), out/*nfrc* and out/*btdf.csv (glazing), out/double_clear_thermal.txt (its U-factor and SHGC), out/double_clear_en673.txt (its EN 673 U and EN 410 g), out/clear_float.xml and out/electrochromic_dark.xml (BSDF XML), out/photos.html (spectral recovery), out/colorchecker_D65.txt, out/colorchecker_A.json, out/photo_texture.exr (the photos' spectral texture, the room's rug), out/room.png, out/room.exr, out/room.spectral.exr, out/room.sensors.csv and out/room_stats.json (the rendered room), out/room_budget.sensors.csv and out/room_budget_stats.json (its sensors under a memory budget), out/room_ranks.sensors.csv and out/room_ranks_stats.json (on 2 MPI ranks), out/office_ec.annual*.csv and out/office_pc.annual*.csv (a year of daylight through switchable glazing, with the desk view's annual DGP)"
