#!/usr/bin/env bash
# Mutation check (docs/testing.md): puts each small deliberate error into
# the source, rebuilds the build tree BUILD (default: build), runs the whole
# ctest suite and prints the tests that fail, then reverts the error.  A
# mutation no test catches is a gap in the suite.  Needs a clean work tree
# (the mutations are reverted with git checkout); the tree is restored and
# rebuilt on exit, also when interrupted.
set -u
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"
build=${1:-build}
files=(render/src/lights/spd.c core/src/fresnel.c)
if [ -n "$(git status --porcelain -- "${files[@]}")" ]; then
  echo "mutation-check: ${files[*]} have changes of their own; commit or stash them first" >&2
  exit 2
fi
restore() {
  git checkout -- "${files[@]}"
  cmake --build "$build" -j"$(nproc)" > /dev/null 2>&1 || echo "mutation-check: the restored tree did not build" >&2
}
trap restore EXIT
run() {
  echo "== mutation: $1"
  if cmake --build "$build" -j"$(nproc)" > /dev/null 2>&1; then
    (cd "$build" && ctest -j"$(nproc)" 2>&1 | grep -E '\*\*\*Failed|\*\*\*Timeout|tests passed|tests failed')
  else
    echo "   (the mutated tree does not build: no tests run)"
  fi
  git checkout -- "${files[@]}"
}
# 1. Every light's emitted radiance 0.5 % too high.
sed -i 's/  for (int i = 0; i < s->n; i++) s->v\[i\] \*= f;/  for (int i = 0; i < s->n; i++) s->v[i] *= f * 1.005;/' \
  render/src/lights/spd.c
git diff --quiet -- render/src/lights/spd.c && { echo "mutation 1 no longer applies" >&2; exit 1; }
run "emitted radiance scaled by 1.005 (render/src/lights/spd.c, scale_spd)"
# 2. s and p reflection swapped at an interface.
python3 - <<'PY'
p = 'core/src/fresnel.c'
s = open(p).read()
for old in ("  o->Rs = abs2(ns) / abs2(ds);\n  o->Rp = abs2(np) / abs2(dp);", "  o->rs = ns / ds;",
            "  o->rp = np / dp;"):
    assert old in s, old
s = s.replace("  o->Rs = abs2(ns) / abs2(ds);\n  o->Rp = abs2(np) / abs2(dp);",
              "  o->Rs = abs2(np) / abs2(dp);\n  o->Rp = abs2(ns) / abs2(ds);")
s = s.replace("  o->rs = ns / ds;", "  o->rs = np / dp;").replace("  o->rp = np / dp;", "  o->rp = ns / ds;")
open(p, 'w').write(s)
PY
git diff --quiet -- core/src/fresnel.c && { echo "mutation 2 no longer applies" >&2; exit 1; }
run "s and p reflection swapped (core/src/fresnel.c, vr_fresnel_interface)"
