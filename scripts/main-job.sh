#!/usr/bin/env bash
# Set-up and the main job: installs dependencies, builds, and runs every
# tool that exists on samples/, writing results under out/.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh
scripts/build.sh build
mkdir -p out
bin=build/core

echo "== colour of the ColorChecker under D65 and under A (vr-colour)"
"$bin/vr-colour" samples/spectra/colorchecker_babelcolor.csv | tee out/colorchecker_D65.txt
"$bin/vr-colour" --illuminant A --json samples/spectra/colorchecker_babelcolor.csv > out/colorchecker_A.json
echo "wrote out/colorchecker_D65.txt and out/colorchecker_A.json"
