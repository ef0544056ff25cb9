#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) and runs each for a
# bounded time from its seed corpus.  Usage: fuzz.sh [SECONDS per target]
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
secs=${1:-30}
if [ ! -f build-fuzz/CMakeCache.txt ]; then
  CC=clang CXX=clang++ cmake -S . -B build-fuzz -DVR_FUZZ=ON -DVR_SANITIZE=ON -DVR_WERROR=ON \
    -DCMAKE_BUILD_TYPE=Debug > /dev/null
fi
# Only the fuzzers and the libraries they link: the tests are built and run
# by scripts/test.sh's other two builds.
cmake --build build-fuzz -j "$(nproc)" --target vr_fuzzers
for t in build-fuzz/tests/fuzz_*; do
  name=$(basename "$t")
  corpus=tests/fuzz/corpus/${name#fuzz_}
  work=$(mktemp -d)
  cp -r "$corpus"/. "$work"/ 2>/dev/null || true
  echo "fuzzing $name for ${secs}s"
  # Crash artefacts go into the build folder, never into the work tree.
  mkdir -p build-fuzz/artifacts
  "$t" -artifact_prefix=build-fuzz/artifacts/"$name"- -max_total_time="$secs" -max_len=65536 -timeout=10 -print_final_stats=1 "$work" 2>&1 | tail -4
  rm -rf "$work"
done
echo "fuzz targets ran without a crash"
