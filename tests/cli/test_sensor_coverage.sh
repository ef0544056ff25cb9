#!/usr/bin/env bash
# Command-line test (issue 33, honest uncertainties): the standard error a
# path sensor reports is a confidence bound.  The daylit office of
# docs/scene-format.md (sun and CIE sky through a window, a spot lamp, 37
# sensor points), its sensors only, path sensors of 512 paths, is read with
# 20 seeds and against a reference of 32768 paths (seed 999, 64 times the
# paths: its own error is 1/8 of a run's).  A reading's error comes from 16
# independent batches, so reading +- t * stderr with t = 2.131 (Student's t,
# 15 degrees of freedom, 97.5 % quantile: a 95 % interval) must cover the
# reference in 90-98 % of the 740 cases (the issue's window; the binomial
# spread of 740 cases at 95 % is 0.8 %), the errors in stderr units must
# scatter as a t variable (SD sqrt(15/13) = 1.07; 0.85-1.2 allowed: the SD
# of 740 draws is known within 0.03) about 0 (mean within +-0.15: 3.4 of
# its standard errors, 0.044: 1.07 / sqrt(740) = 0.039 for the runs, and the
# reference's own error, an eighth of a run's, shared by a point's 20
# seeds, adds 0.125 / sqrt(37) = 0.021 in quadrature).  Measured: 95.9 %,
# SD 1.01, mean -0.07.
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
source "$(dirname "$0")/harness.sh"
doc="$VR_SOURCE_DIR/docs/scene-format.md"
awk '/^## A complete example/ { on = 1; next } on && /^```/ { if (inside) exit; inside = 1; next } inside { print }' \
  "$doc" | sed 's/^render .*/render integrator=path sensors=path sensor_samples=SAMPLES/' > "$tmp/office.in"
check "the example is extracted" grep -q "^render integrator=path sensors=path" "$tmp/office.in"
cp -r "$VR_SOURCE_DIR/samples/meshes" "$tmp/meshes"
run() { # samples seed name
  sed "s/SAMPLES/$1/" "$tmp/office.in" > "$tmp/$3.scn"
  (cd "$tmp" && "$bin" "$3.scn" --sensors-only --quiet --seed "$2" -o "$3") > "$tmp/$3.err" 2>&1
}
run 32768 999 ref
check "the reference renders ($(tail -1 "$tmp/ref.err"))" test -s "$tmp/ref.sensors.csv"
bad=0
for s in $(seq 1 20); do run 512 "$s" "s$s" || bad=$((bad + 1)); done
check "20 seeds render" test $bad -eq 0
python3 - "$tmp" <<'PY'
import csv, statistics, sys
d = sys.argv[1]
def read(name):
    return [(float(r["illuminance_lx"]), float(r["stderr_lx"])) for r in csv.DictReader(open(f"{d}/{name}.sensors.csv"))]
ref = read("ref")
assert len(ref) == 37, len(ref)
z = []
for s in range(1, 21):
    run = read(f"s{s}")
    assert len(run) == len(ref)
    for (m, se), (rm, _) in zip(run, ref):
        assert se > 0, (s, m, se)
        z.append((m - rm) / se)
cover = sum(abs(v) <= 2.131 for v in z) / len(z)
sd, mean = statistics.pstdev(z), statistics.fmean(z)
print(f"# coverage {100 * cover:.1f} % of {len(z)}, SD of the errors {sd:.3f} stderr, mean {mean:+.3f}")
ok = 0.90 <= cover <= 0.98 and 0.85 <= sd <= 1.2 and abs(mean) <= 0.15
sys.exit(0 if ok else 1)
PY
check "the 95 % intervals cover the reference in 90-98 % of cases, errors scatter as stated" test $? -eq 0
finish
