#!/usr/bin/env bash
# Command-line test of BSDF XML windows in vr-render (material NAME bsdf
# file=F.xml, docs/scene-format.md):
#   - a round trip: NFRC 102 (CLEAR_3.DAT) imported as a glazing material
#     and rendered as a pane, against the same pane written as a Klems BSDF
#     XML file by vr-spectro bsdf-xml and rendered through that file, in a
#     black room under a skylight and a sky of uniform radiance (CIE general
#     sky type 5), three sensors: the same illuminance within the Klems
#     basis' resolution plus 4 standard errors of the difference;
#   - an IGSDB roller shade (cgdb 14060, as the IGSDB serves it) in the same
#     skylight: the sensor under it reads the uniform sky through the
#     shade's matrices, so its illuminance over the clear pane's is the
#     shade's diffuse-diffuse back transmittance over the pane's Tvis
#     (WinCalc's figures, test_bsdf_xml.c), within 1 % and 4 standard
#     errors;
#   - genBSDF's tensor tree b00kT (resampled onto the Klems basis as it is
#     read) against the Klems file Radiance's bsdf2klems wrote from it;
#   - the same image on 1 and 8 sub-domains through genBSDF's louvres;
#   - refusals (docs/bad-input.md).
set -u
bin="$(cd "$VR_BIN" && pwd)/vr-render"
spectro="$(cd "$VR_SPECTRO_BIN" && pwd)/vr-spectro"
cmp="$(cd "$VR_TEST_BIN" && pwd)/vr-test-exr-compare"
matdb="$(cd "$VR_MATDB_BIN" && pwd)/vr-matdb"
source "$(dirname "$0")/harness.sh"
data="$VR_SOURCE_DIR/tests/data"
cd "$tmp"

"$matdb" init > /dev/null 2>&1
"$matdb" import "$VR_SOURCE_DIR/samples/glazing/clear_float/CLEAR_3.DAT" --name clear3 > /dev/null 2>&1
"$spectro" bsdf-xml clear3 --out clear3.xml 2> /dev/null
check "the pane written as BSDF XML" test -s clear3.xml
zcat "$data/bsdf/cgdb_14060_urban_loft_river_stone.xml.gz" > shade.xml

scene() { # $1: the window's material line
  cat <<SCN
$1
material black black
rect center=2,2,0 normal=0,0,1 size=4,4 material=black
rect center=0,2,1.5 normal=1,0,0 size=4,3 material=black
rect center=4,2,1.5 normal=-1,0,0 size=4,3 material=black
rect center=2,0,1.5 normal=0,1,0 size=4,3 material=black
rect center=2,4,1.5 normal=0,-1,0 size=4,3 material=black
rect center=2,0.7,3 normal=0,0,-1 size=4,1.4 material=black
rect center=2,3.3,3 normal=0,0,-1 size=4,1.4 material=black
rect center=0.55,2,3 normal=0,0,-1 size=1.1,1.2 material=black
rect center=3.45,2,3 normal=0,0,-1 size=1.1,1.2 material=black
rect center=2,2,3 normal=0,0,-1 size=1.8,1.2 material=window
sky cie type=5 illuminance=10000
sensor centre point position=2,2,0.8 normal=0,0,1
sensor off    point position=2.8,2.4,0.8 normal=0,0,1
sensor tilted point position=1.5,1.8,1.2 normal=0.3,0,0.954
render integrator=path spp=1 sensor_samples=524288
SCN
}
scene "material window db:clear3" > pane.scn
scene "material window bsdf file=clear3.xml" > xml.scn
scene "material window bsdf file=shade.xml up=0,1,0" > shade.scn
"$bin" pane.scn -o pane --sensors-only --quiet; rc1=$?
"$bin" xml.scn -o xml --sensors-only --quiet; rc2=$?
"$bin" shade.scn -o shade --sensors-only --quiet; rc3=$?
check "the three renders run" test $rc1 -eq 0 -a $rc2 -eq 0 -a $rc3 -eq 0
python3 - pane.sensors.csv xml.sensors.csv shade.sensors.csv <<'PY'
import csv, math, sys
rd = [{r["sensor"]: (float(r["illuminance_lx"]), float(r["stderr_lx"])) for r in csv.DictReader(open(f))}
      for f in sys.argv[1:4]]
pane, xml, shade = rd
# The Klems basis' resolution for these sensors: a BSDF XML pane transmits
# its figure at each ring's nominal angle (0, 10, ..., 40 deg) over the
# whole ring; the sensors see the skylight within 42 deg of its normal, and
# NFRC 102's Tvis changes by at most 0.8 % within those rings (T(40 deg)
# 0.88882 against T(45 deg) 0.88158, vr-spectro metrics --angle).  The sky
# is uniform, so the patches' blur of directions changes nothing else.
for name in pane:
    (a, sa), (b, sb) = pane[name], xml[name]
    tol = 0.008 * a + 4 * math.hypot(sa, sb)
    print("# %s: pane %.1f +- %.1f lx, BSDF XML %.1f +- %.1f lx (%+.2f %%, allowed %.2f %%)"
          % (name, a, sa, b, sb, 100 * (b / a - 1), 100 * tol / a))
    assert abs(b - a) <= tol, name
# The shade under a uniform sky of radiance L: the skylight's normal points
# down into the room, so the sky lights the shade's back, and the radiance
# it sends into the room in a direction o is L times the sum over incident
# patches i of TB[o][i] Lambda_i.  A roller shade diffuses: for the
# directions this point sees (within 27 deg of the normal) those sums lie
# within 0.5 % of the shade's diffuse-diffuse back transmittance, 0.2467380
# (WinCalc, cgdb 14060, Visible), so the sensor reads 0.2467380 L times the
# projected solid angle of the opening.  The clear pane passes its Tvis,
# 0.8992600 at normal incidence and at least 0.8979 within 27 deg
# (vr-spectro metrics --angle), of the same light.  Expected ratio
# 0.2467380 / 0.8992600 within 1 % (the two spreads) and 4 standard errors.
(a, sa), (s, ss) = pane["centre"], shade["centre"]
ratio, want = s / a, 0.24673804723626364 / 0.8992599767990066
se = ratio * math.hypot(sa / a, ss / s)
print("# shade over clear pane at the centre: %.4f, expected %.4f (+- %.4f)" % (ratio, want, 0.01 * want + 4 * se))
assert abs(ratio - want) <= 0.01 * want + 4 * se
PY
check "a clear pane through its BSDF XML reads as the pane; the IGSDB shade as its figures say" test $? -eq 0

# A tensor tree (genBSDF's b00kT, TensorTree4) read and resampled onto the
# Klems basis, against the Klems file Radiance's bsdf2klems wrote from it
# (tests/data/bsdf/README.md), in the same skylight: their figures agree
# within 0.6 % in diffuse-diffuse (tests/matdb/test_bsdf_xml_tree.c), so
# the sensors within 1 % and 4 standard errors of the difference.
zcat "$data/bsdf/bsdf2klems_b00kT.xml.gz" > b2k.xml
scene "material window bsdf file=$data/bsdf/tensortree_b00kT.xml" | sed 's/sensor_samples=524288/sensor_samples=131072/' > tt.scn
scene "material window bsdf file=b2k.xml" | sed 's/sensor_samples=524288/sensor_samples=131072/' > b2k.scn
"$bin" tt.scn -o tt --sensors-only --quiet && "$bin" b2k.scn -o b2k --sensors-only --quiet
check "the tensor tree and its bsdf2klems Klems file render" test $? -eq 0
python3 - tt.sensors.csv b2k.sensors.csv <<'PY'
import csv, math, sys
tt, kl = [{r["sensor"]: (float(r["illuminance_lx"]), float(r["stderr_lx"])) for r in csv.DictReader(open(f))}
          for f in sys.argv[1:3]]
for name in tt:
    (a, sa), (b, sb) = tt[name], kl[name]
    tol = 0.01 * b + 4 * math.hypot(sa, sb)
    print("# %s: tensor tree %.1f +- %.1f lx, bsdf2klems %.1f +- %.1f lx (%+.2f %%)" % (name, a, sa, b, sb, 100 * (a / b - 1)))
    assert abs(a - b) <= tol, name
PY
check "the tensor tree reads as Radiance's Klems version of it" test $? -eq 0

# The decomposition: the same image through the louvres on 1 and 8
# sub-domains (rays cross cells between the window's vertices).
zcat "$data/bsdf/SquareSlat_genBSDF.xml.gz" > louvres.xml
{ scene "material window bsdf file=louvres.xml" | sed -e 's/material black black/material black lambert reflectance=0.5/' -e '/^render /d'
  echo "light sun altitude=60 azimuth=0 illuminance=90000lx"
  echo "camera pinhole from=2,0.3,1.5 to=2,2,2.9 fov=70 resolution=32x24"
  echo "render integrator=path spp=4 sensor_samples=1024"; } > img.scn
"$bin" img.scn -o one --quiet --subdomains 1 && "$bin" img.scn -o eight --quiet --subdomains 8
"$cmp" one.exr eight.exr > cmp.txt 2>&1
check "the same image on 1 and 8 sub-domains" grep -q "largest relative difference 0 " cmp.txt
check "and the same sensors" cmp -s one.sensors.csv eight.sensors.csv

# Refusals.
scene "material window bsdf" > nofile.scn
refuse render-bsdf-no-file "$bin" nofile.scn -o x --sensors-only --quiet
scene "material window bsdf file=nosuch.xml" > missing.scn
refuse render-bsdf-missing "$bin" missing.scn -o x --sensors-only --quiet
printf '<WindowElement><Optical><Layer>\n' > cut.xml
scene "material window bsdf file=cut.xml" > cut.scn
refuse render-bsdf-malformed "$bin" cut.scn -o x --sensors-only --quiet
check "the malformed file's message names the scene line and the file" grep -q "cut.scn:1:.*cut.xml" "$tmp/refused.err"
scene "material window bsdf file=clear3.xml up=0,0,0" > up.scn
refuse render-bsdf-up-zero "$bin" up.scn -o x --sensors-only --quiet

finish
