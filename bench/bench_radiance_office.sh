#!/usr/bin/env bash
# Side by side with Radiance on a public .rad model: honeybee-radiance's
# sample office (tests/data/radiance/sample_office), read by oconv and
# rtrace and by vr-render's .rad reader, under the same CIE overcast sky
# (gensky -c, 10 000 lx horizontal, ground 0.2), illuminance at the same
# .pts points (a 4 x 8 work-plane grid at 0.8 m).  Prints each point's
# two readings and their difference, the mean and worst, and the seconds
# each tool took, for docs/radiance.md.
#
# The model's context ground (context_e3bb11d6_0, reflectance 0.5) lies
# in the plane of the room's floor (0.2, z = 0): the two coincide under
# the room and each renderer sees one of them there.  It is lowered by
# 1 cm for the comparison (in both); run with KEEP_OVERLAP=1 to compare
# the file as it is.
#
# BLIND=1 puts an IGSDB roller shade (tests/data/bsdf/cgdb_14060, a BSDF
# XML file) in the lower south window in place of its glass, as a Radiance
# BSDF material read by both; SHADE=NAME another file of tests/data/bsdf,
# SHADE_FILE=F.xml.gz any (bench/bsdf_make_reciprocal.py writes one whose
# transmission is reciprocal, gzip it).
#
# Usage: bench/bench_radiance_office.sh RADIANCE-BIN-DIR [BUILD-DIR] [AD] [SAMPLES]
#   RADIANCE-BIN-DIR: oconv, rtrace, gensky, rcalc (../shared/peers/radiance
#   builds them); RAYPATH must reach rayinit.cal and skybright.cal, e.g.
#   RAYPATH=.:SRC/src/rt:SRC/src/gen.  AD: rtrace's -ad (default 65536, with
#   -aa 0 -ab 12 -lw 1e-7: Monte Carlo, no ambient cache); SAMPLES:
#   vr-render's sensor_samples (default 131072, path, depth 30).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rbin=$(cd "${1:?usage: $0 RADIANCE-BIN-DIR [BUILD-DIR] [AD] [SAMPLES]}" && pwd)
build=$(cd "${2:-$root/build}" && pwd)
ad=${3:-65536}
samples=${4:-131072}
: "${RAYPATH:?set RAYPATH to reach rayinit.cal and skybright.cal}"
model=$root/tests/data/radiance/sample_office
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The grid: cell centres of a 4 x 8 grid over x -1.5..1.5, y -2.7..3.5.
cp "$model/grid.pts" "$work/grid.pts"

envelope=$model/scene/sample_office_envelope.rad
if [ "${KEEP_OVERLAP:-0}" != 1 ]; then
  awk -f "$model/lower_context.awk" "$envelope" > "$work/envelope.rad"
  envelope=$work/envelope.rad
fi
blind=
if [ "${BLIND:-0}" = 1 ]; then
  gzip -dc "${SHADE_FILE:-$root/tests/data/bsdf/${SHADE:-cgdb_14060_urban_loft_river_stone}.xml.gz}" > "$work/shade.xml"
  # The window's material redefined after the aperture materials: the
  # surfaces after it take it, in both readers.
  printf 'void BSDF south_glass_top_45_08dc6264\n6 0 shade.xml 0 0 1 .\n0\n0\n' > "$work/blind.mat"
  blind=$work/blind.mat
fi
cat > "$work/office.rad" <<EOF
!xform $model/scene/sample_office_envelope.mat
!xform $envelope
!xform $model/aperture/sample_office.mat
${blind:+!xform $blind}
!xform $model/aperture/sample_office.rad
EOF

# Radiance.
"$rbin/gensky" -ang 45 0 -c -B 55.866 -g 0.2 > "$work/sky.rad"
cat >> "$work/sky.rad" <<'EOF'
skyfunc glow sky_mat 0 0 4 1 1 1 0
sky_mat source sky 0 0 4 0 0 1 180
skyfunc glow ground_glow 0 0 4 1 1 1 0
ground_glow source ground 0 0 4 0 0 -1 180
EOF
(cd "$work" && "$rbin/oconv" "$work/sky.rad" "$model/scene/sample_office_envelope.mat" "$envelope" \
  "$model/aperture/sample_office.mat" $blind "$model/aperture/sample_office.rad" > "$work/office.oct")
t0=$(date +%s.%N)
cd "$work"
"$rbin/rtrace" -h -I -ab 12 -ad "$ad" -aa 0 -lw 1e-7 -n 2 "$work/office.oct" < "$work/grid.pts" |
  "$rbin/rcalc" -e '$1=179*(.265*$1+.670*$2+.065*$3)' > "$work/radiance.txt"
[ -n "${RADIANCE_OUT:-}" ] && cp "$work/radiance.txt" "$RADIANCE_OUT"
t1=$(date +%s.%N)

# vr-render.
cat > "$work/office.scn" <<EOF
mesh $work/office.rad
sky overcast illuminance=10000 ground=0.2
sensor wp points file=$work/grid.pts
render integrator=path sensor_samples=$samples depth=30
EOF
t2=$(date +%s.%N)
"$build/render/vr-render" "$work/office.scn" --sensors-only --quiet -o "$work/vr"
t3=$(date +%s.%N)
tail -n +2 "$work/vr.sensors.csv" | cut -d, -f7,8 > "$work/vr.txt"

echo "point  radiance_lx  vr_lx  vr_stderr_lx  diff_pct"
paste -d, "$work/radiance.txt" "$work/vr.txt" | awk -F, -v t0="$t0" -v t1="$t1" -v t2="$t2" \
  -v t3="$t3" -v ad="$ad" -v ns="$samples" '
  { d = ($2 - $1) / $1 * 100; s += d; a = d < 0 ? -d : d; if (a > m) m = a; if (a <= 2) ok++;
    printf "%2d  %9.2f  %9.2f  %6.2f  %+6.2f\n", NR - 1, $1, $2, $3, d }
  END { tr = t1 - t0; tv = t3 - t2;
        printf "mean difference %+.2f %%, worst |difference| %.2f %%, %d of %d points within 2 %%\n", s / NR, m, ok, NR;
        printf "rtrace -ab 12 -ad %d -aa 0 -lw 1e-7 -n 2: %.1f s; vr-render path, %d samples a point, 2 threads: %.1f s\n", ad, tr, ns, tv }'
