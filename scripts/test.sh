#!/usr/bin/env bash
# Set-up and the whole test suite: installs dependencies, builds twice (a
# normal build and one with AddressSanitizer + UndefinedBehaviorSanitizer),
# runs ctest on both, then the fuzz targets for a bounded time.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
scripts/install-deps.sh

echo "== normal build"
scripts/build.sh build -DVR_WERROR=ON
(cd build && ctest --output-on-failure -j "$(nproc)")

echo "== vr-render built without MPI (it must build and run alone)"
[ -f build-nompi/CMakeCache.txt ] ||
  cmake -S . -B build-nompi -DVR_MPI=OFF -DVR_WERROR=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
# vr-rgb2spec too: the textures test makes its spectral texture with it;
# vr-spectro: the tint study of cli_vr_render fits its glass with it;
# vr-matdb and vr-spectro: the BSDF XML test imports a pane and writes it.
# vr-test-exr-attrs: the adaptive test reads the EXR layers with OpenEXR.
cmake --build build-nompi -j "$(nproc)" --target vr-render vr-test-exr-compare vr-test-exr-attrs vr-hotel vr-rgb2spec vr-spectro \
  vr-matdb > /dev/null
(cd build-nompi && ctest --output-on-failure -R '^cli_vr_render')

echo "== AddressSanitizer + UndefinedBehaviorSanitizer build"
scripts/build.sh build-asan -DVR_WERROR=ON -DVR_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug
(cd build-asan && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
   LSAN_OPTIONS=suppressions="$root/tests/lsan.supp" \
   ctest --output-on-failure -j "$(nproc)" -E '^(test_annual|test_slab_caustic)$')
# (the two longest Monte Carlo tests run in the normal build only: README,
# "What the tests need", says why)

echo "== fuzz targets (libFuzzer, bounded)"
scripts/fuzz.sh 20
