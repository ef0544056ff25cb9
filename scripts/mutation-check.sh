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
# MUTATIONS="3 5" runs only those (default: all).  Exit status: 0 when
# every mutation run was caught, 1 when one was not (or did not build), 2
# for a bad argument.
only=" ${MUTATIONS:-1 2 3 4 5 6} "
for m in $only; do
  case "$m" in [1-6]) ;; *) echo "mutation-check: MUTATIONS='${MUTATIONS:-}': $m is not a mutation (1 to 6, separated by spaces)" >&2; exit 2 ;; esac
done
want() { case "$only" in *" $1 "*) return 0 ;; esac; return 1; }
missed=0
files=(render/src/lights/spd.c core/src/fresnel.c render/src/film/accum.c core/src/cmf.c
       render/src/ddm/flow.c fit/src/gas.c)
if [ -n "$(git status --porcelain -- "${files[@]}")" ]; then
  echo "mutation-check: ${files[*]} have changes of their own; commit or stash them first" >&2
  exit 2
fi
restore() {
  git checkout -- "${files[@]}"
  cmake --build "$build" -j"$(nproc)" > /dev/null 2>&1 || echo "mutation-check: the restored tree did not build" >&2
}
trap restore EXIT
# Stops when mutation $1's edit of file $2 no longer applies.
applied() { git diff --quiet -- "$2" && { echo "mutation $1 no longer applies" >&2; exit 1; }; return 0; }
run() {
  echo "== mutation: $1"
  if cmake --build "$build" -j"$(nproc)" > /dev/null 2>&1; then
    local out
    out=$(cd "$build" && ctest -j"$(nproc)" 2>&1 | grep -E '\*\*\*Failed|\*\*\*Timeout|tests passed|tests failed')
    echo "$out"
    if ! grep -qE '\*\*\*Failed|\*\*\*Timeout' <<< "$out"; then
      echo "   NOT CAUGHT: no test failed"
      missed=1
    fi
  else
    echo "   (the mutated tree does not build: no tests run)"
    missed=1
  fi
  git checkout -- "${files[@]}"
}
# 1. Every light's emitted radiance 0.5 % too high.
if want 1; then
  sed -i 's/  for (int i = 0; i < s->n; i++) s->v\[i\] \*= f;/  for (int i = 0; i < s->n; i++) s->v[i] *= f * 1.005;/' \
    render/src/lights/spd.c
  applied 1 render/src/lights/spd.c
  run "emitted radiance scaled by 1.005 (render/src/lights/spd.c, scale_spd)"
fi
# 2. s and p reflection swapped at an interface.
if want 2; then
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
  applied 2 core/src/fresnel.c
  run "s and p reflection swapped (core/src/fresnel.c, vr_fresnel_interface)"
fi
# 3. A one-bin wavelength shift in the film: every sample lands in the bin
#    above its own (the spectral images, the sensors' spectral columns).
if want 3; then
  sed -i 's|  double x = (nm - a->bin_lo) / a->bin_step;|  double x = (nm - a->bin_lo) / a->bin_step + 1.0;|' render/src/film/accum.c
  applied 3 render/src/film/accum.c
  run "film spectral bins shifted by one (render/src/film/accum.c, bin_of)"
fi
# 4. A one-bin wavelength shift in colorimetry: the spectra weighted at the
#    next 1 nm row of the colour-matching functions (every XYZ, Tvis, colour).
if want 4; then
  sed -i 's|    double nm = t\[i \* 4\];|    double nm = t[i * 4] + 1.0;|' core/src/cmf.c
  applied 4 core/src/cmf.c
  run "colour-matching rows shifted by 1 nm (core/src/cmf.c, weighted_sum)"
fi
# 5. A dropped ray: one in 1000 rays handed from one cell to the next is
#    lost, its count balanced as if it had ended (so the run still ends).
if want 5; then
  sed -i 's|^      w->st.crossings++;$|      w->st.crossings++;\n      if (w->st.crossings % 1000 == 0) { finish(w, 1); return; }|' render/src/ddm/flow.c
  applied 5 render/src/ddm/flow.c
  run "one in 1000 hand-overs between cells drops its ray (render/src/ddm/flow.c, trace)"
fi
# 6. A gas's conductivity 1 % high (every fill: the gaps' conduction and
#    convection, the indoor film's natural convection).
if want 6; then
  sed -i 's|    lam\[i\] = GAS\[id\].lambda\[0\] + GAS\[id\].lambda\[1\] \* T;|    lam[i] = 1.01 * (GAS[id].lambda[0] + GAS[id].lambda[1] * T);|' fit/src/gas.c
  applied 6 fit/src/gas.c
  run "fill gases' conductivity 1 % high (fit/src/gas.c, vr_gas_properties)"
fi
exit $missed
