#!/usr/bin/env bash
# Command-line tests of vr-spectro and BSDF XML: the figures of real files
# (genBSDF, IGSDB) against LBNL WinCalc's published results for the same
# files; a clear pane written as a Klems BSDF XML file against WinCalc's
# BSDF of the same pane (NFRC 102); double glazing and a chromogenic state;
# and bad input.
set -u
bin="$VR_BIN/vr-spectro"
src="$VR_SOURCE_DIR"
g="$src/samples/glazing"
x="$src/tests/data/bsdf"
source "$(dirname "$0")/harness.sh"

# genBSDF's louvred shutter (WinCalc test/products/SquareSlat_genBSDF.xml):
# WinCalc's test/expected_results/1_layer/louvered_shade_bsdf_xml/full_basis/
# condensed_spectrum/theta=0_phi=0/photopic.json gives front transmittance
# direct-hemispherical 0.31047899463815931, back reflectance direct-direct
# 0.0030237980335798059; theta=15_phi=270: back reflectance direct-
# hemispherical 0.59811512825572288.  Same numbers summed: 1e-12.
"$bin" metrics "$x/SquareSlat_genBSDF.xml.gz" --json > "$tmp/s0.json"; rc=$?
check "metrics reads a gzip-compressed genBSDF file" test $rc -eq 0
"$bin" metrics "$x/SquareSlat_genBSDF.xml.gz" --angle 15 --phi 270 --json > "$tmp/s15.json"
python3 - "$tmp/s0.json" "$tmp/s15.json" <<'PY'
import json, sys
a = json.load(open(sys.argv[1])); b = json.load(open(sys.argv[2]))
va = [x for x in a["bands"] if x["band"] == "Visible"][0]
vb = [x for x in b["bands"] if x["band"] == "Visible"][0]
assert a["patches"] == 145 and a["patch"] == 1 and b["patch"] == 8, (a["patch"], b["patch"])
assert abs(va["Transmission Front"]["direct_hemispherical"] - 0.31047899463815931) < 1e-12
assert abs(va["Reflection Back"]["direct_direct"] - 0.0030237980335798059) < 1e-12
assert abs(vb["Reflection Back"]["direct_hemispherical"] - 0.59811512825572288) < 1e-12
PY
check "louvred shutter's figures equal WinCalc's" test $? -eq 0
"$bin" metrics "$x/cgdb_14060_urban_loft_river_stone.xml.gz" > "$tmp/r.txt"
# WinCalc roller_shade_bsdf_xml_cgdb_14060, theta=0, solar: front T direct-
# hemispherical 0.34156801257842329 (printed to 6 decimals).
check "IGSDB roller shade, text output" grep -Eq "^Solar +Transmission Front +0.005358 +0.336210 +0.341568 +0.268315" "$tmp/r.txt"
check "text names the product" grep -q "Urban Loft River Stone, Hunter Douglas" "$tmp/r.txt"

# A clear pane as BSDF XML: NFRC 102 (CLEAR_3.DAT) against WinCalc's own
# BSDF of the same pane (test 1_layer_nfrc_102_as_bsdf: expected_results/
# 1_layer/nfrc_102/full_basis/full_spectrum/theta=0_phi=0/{photopic,solar}
# .json, the diagonal of each matrix times the patch's projected solid
# angle, one patch per ring).  Our NFRC 300 weighting of the same data
# agrees to 2e-6 (WinCalc's photopic table is interpolated differently);
# 1e-5 relative.
"$bin" bsdf-xml "$g/clear_float/CLEAR_3.DAT" --out "$tmp/clear.xml" 2> "$tmp/w.err"; rc=$?
check "bsdf-xml writes a clear pane" test $rc -eq 0
check "bsdf-xml says what it wrote" grep -q "wrote .*clear.xml (Klems full basis" "$tmp/w.err"
for a in 0 10 20 30 40 50 60 70 82.5; do
  "$bin" metrics "$tmp/clear.xml" --angle $a --json > "$tmp/c$a.json" || echo "metrics --angle $a failed"
done
python3 - "$tmp" <<'PY'
import json, math, sys
# WinCalc's matrix diagonal at each ring's first patch (1/sr), full spectrum.
W = {
 ("Visible", "Transmission Front"): [37.68281822886991, 38.55137389605194, 40.99320039782792, 37.92880872390735, 39.705936743801786, 38.86255245071142, 41.76729177050876, 32.16603970974832, 19.541775350274822],
 ("Visible", "Reflection Front"): [3.459748110863899, 3.5406400563642837, 3.7842193513116222, 3.5905386675596325, 4.072774778243935, 4.873848380439658, 7.916641558868864, 12.419643081529873, 36.16366838033368],
 ("Visible", "Reflection Back"): [3.4597627120377448, 3.5406550003913284, 3.7842352803496766, 3.590553524739145, 4.072790645162665, 4.873864552517261, 7.916660258826538, 12.419659690914937, 36.16368569225913],
 ("Solar", "Transmission Front"): [34.94183147369309, 35.7292440141165, 37.935063503015115, 35.01129386511855, 36.52375719314184, 35.58835388902791, 38.03546612044238, 29.062185836428977, 16.978345629076628],
 ("Solar", "Reflection Front"): [3.1329553462626882, 3.2050083025124785, 3.422279787665854, 3.244486104702439, 3.6835107085043215, 4.429659103724421, 7.264562959323716, 11.52914355285978, 34.321069041379786],
 ("Solar", "Reflection Back"): [3.1367579869454314, 3.2088993813754354, 3.426425494320022, 3.2483532167050897, 3.6876503379992998, 4.43391093008745, 7.269562884204305, 11.533693228361845, 34.32574100265626],
}
# WinCalc's back transmittance (solved from the back's reflectance, so it
# differs from the front's at an angle), same files, back/transmittance.
W_TB = {
 "Visible": [37.68281822886991, 38.55137401950377, 40.99320091300742, 37.92880976152122, 39.705938589062555, 38.862555149274975, 41.76729592693095, 32.166044550512694, 19.541782781702437],
 "Solar": [34.94183147369309, 35.72928456407793, 37.935233376529766, 35.01163776932674, 36.524370476346654, 35.589242609789, 38.03678256617027, 29.06359644424912, 16.980156658542985],
}
rings = [(0, 5, 1), (5, 15, 8), (15, 25, 16), (25, 35, 20), (35, 45, 24), (45, 55, 24), (55, 65, 24), (65, 75, 16), (75, 90, 12)]
angles = ["0", "10", "20", "30", "40", "50", "60", "70", "82.5"]
worst = 0
for k, (lo, hi, n) in enumerate(rings):
    lam = math.pi * (math.sin(math.radians(hi)) ** 2 - math.sin(math.radians(lo)) ** 2) / n
    d = json.load(open(f"{sys.argv[1]}/c{angles[k]}.json"))
    bands = {b["band"]: b for b in d["bands"]}
    for (band, side), v in W.items():
        f = bands[band][side]
        e = abs(f["direct_direct"] / (v[k] * lam) - 1)
        worst = max(worst, e)
        assert e < 1e-5, (band, side, angles[k], f["direct_direct"], v[k] * lam)
        assert f["direct_diffuse"] == 0, (band, side)  # a clear pane scatters nothing
    for band, v in W_TB.items():
        e = abs(bands[band]["Transmission Back"]["direct_direct"] / (v[k] * lam) - 1)
        worst = max(worst, e)
        assert e < 1e-5, (band, "Transmission Back", angles[k], e)
# Hemispherical (diffuse-diffuse) transmittance, WinCalc: photopic
# 0.8213063590923718, solar 0.7526877806045663.
d = json.load(open(f"{sys.argv[1]}/c0.json"))
bands = {b["band"]: b for b in d["bands"]}
assert abs(bands["Visible"]["Transmission Front"]["diffuse_diffuse"] / 0.8213063590923718 - 1) < 1e-5
assert abs(bands["Solar"]["Transmission Front"]["diffuse_diffuse"] / 0.7526877806045663 - 1) < 1e-5
print("# worst relative difference from WinCalc: %.2g" % worst)
PY
check "clear pane's BSDF equals WinCalc's (NFRC 102)" test $? -eq 0

# Double glazing: the file's normal Tvis is the pair's (WinCalc, two NFRC
# 102 panes: 0.8142742, as test_vr_spectro.sh checks for metrics --panes).
"$bin" bsdf-xml --panes "$g/clear_float/CLEAR_3.DAT,$g/clear_float/CLEAR_3.DAT" --out "$tmp/dg.xml" 2> /dev/null
"$bin" metrics "$tmp/dg.xml" --json > "$tmp/dg.json"
python3 -c "
import json; d=json.load(open('$tmp/dg.json')); b={x['band']: x for x in d['bands']}
t=b['Visible']['Transmission Front']['direct_direct']; assert abs(t-0.8142742)<2e-5, t"
check "double glazing as BSDF XML keeps WinCalc's Tvis" test $? -eq 0

# A chromogenic state: the file of the tinted state carries the state's
# normal Tvis (metrics at the same state), below the bleached one.
"$bin" chromogenic "$g/electrochromic/ec_states.csv" --save ec > /dev/null 2>&1
"$bin" bsdf-xml ec --state 1 --out "$tmp/ec1.xml" 2> /dev/null
"$bin" bsdf-xml ec --state 0 --out "$tmp/ec0.xml" 2> /dev/null
"$bin" metrics ec --state 1 --json > "$tmp/ecm.json"
python3 - "$tmp" <<'PY'
import json, subprocess, sys, os
t = sys.argv[1]
def tvis(f):
    d = json.loads(subprocess.run([os.environ["VR_BIN"] + "/vr-spectro", "metrics", f, "--json"], capture_output=True, text=True).stdout)
    return {x["band"]: x for x in d["bands"]}["Visible"]["Transmission Front"]["direct_direct"]
m = json.load(open(t + "/ecm.json"))["Tvis"]
t1, t0 = tvis(t + "/ec1.xml"), tvis(t + "/ec0.xml")
assert abs(t1 - m) < 1e-8, (t1, m)
assert t1 < 0.5 * t0, (t1, t0)
PY
check "electrochromic tinted state as BSDF XML" test $? -eq 0

# A coated pane from its layer stack (the sample low-e: ZnO/Ag/ZnO on 4 mm
# soda-lime): thin-film optics at each ring's angle, s and p, whose
# spectra test_vr_spectro.sh checks against an independent computation
# (tests/cli/thin_film_check.py, within 1e-5 at 0, 45 and 80 degrees).
# Each ring of the file must carry the standard's figures of those spectra
# at the ring's angle: at each of the 9 ring centres (0, 10, ..., 70, 82.5
# degrees), the figures of the btdf table at that angle (unpolarised: the
# mean of s and p) read as a measured pane by metrics, to the table's 8
# digits (1e-7).  (Back T is front T by reciprocity, written so, not
# checked here.)  And the stack at 60 degrees
# against WINDOW's coated-glazing polynomials from the same normal spectra
# (bsdf-xml lowe.csv): they differ, which is why the stack is worth giving.
"$bin" bsdf-xml --stack "$g/lowe/lowe.model" --wavelengths 310:2500:10 --out "$tmp/lowe.xml" 2> /dev/null
check "bsdf-xml --stack writes a coated pane" test $? -eq 0
"$bin" btdf --stack "$g/lowe/lowe.model" --angles 0,10,20,30,40,50,60,70,82.5 --wavelengths 310:2500:10 --table "$tmp/lowe_bt.csv" > /dev/null
"$bin" bsdf-xml "$g/lowe/lowe.csv" --out "$tmp/lowe_poly.xml" 2> /dev/null
python3 - "$tmp" <<'PY'
import json, subprocess, sys, os
t, b = sys.argv[1], os.environ["VR_BIN"] + "/vr-spectro"
def run(*args):
    return json.loads(subprocess.run([b, *args, "--json"], capture_output=True, text=True, check=True).stdout)
rows = [list(map(float, l.split(","))) for l in open(t + "/lowe_bt.csv").readlines()[1:]]
for angle in (0, 10, 20, 30, 40, 50, 60, 70, 82.5):
    with open(f"{t}/at{angle:g}.csv", "w") as f:
        f.write("# thickness: 4 mm\nwavelength_nm,T,Rf,Rb\n")
        for a, nm, ts, tp, rfs, rfp, rbs, rbp in rows:
            if a == angle:
                f.write(f"{nm:g},{(ts + tp) / 2:.9f},{(rfs + rfp) / 2:.9f},{(rbs + rbp) / 2:.9f}\n")
    want = run("metrics", f"{t}/at{angle:g}.csv")
    got = {x["band"]: x for x in run("metrics", t + "/lowe.xml", "--angle", f"{angle:g}")["bands"]}
    for band, key, side in (("Visible", "Tvis", "Transmission Front"), ("Visible", "Rvis_front", "Reflection Front"), ("Visible", "Rvis_back", "Reflection Back"),
                            ("Solar", "Tsol", "Transmission Front"), ("Solar", "Rsol_front", "Reflection Front"),
                            ("Solar", "Rsol_back", "Reflection Back")):
        g = got[band][side]["direct_direct"]
        assert abs(g - want[key]) < 1e-7, (angle, band, side, g, want[key])
    if angle == 60:
        poly = {x["band"]: x for x in run("metrics", t + "/lowe_poly.xml", "--angle", "60")["bands"]}
        tv, tp = got["Visible"]["Transmission Front"]["direct_direct"], poly["Visible"]["Transmission Front"]["direct_direct"]
        print(f"# 60 deg: Tvis {tv:.6f} by the stack, {tp:.6f} by WINDOW's coated polynomials")
        assert abs(tv - tp) > 1e-3, (tv, tp)
PY
check "bsdf-xml --stack: each of the 9 rings holds the standard's figures of the stack at its angle" test $? -eq 0

# Bad input: docs/bad-input.md's rows.
printf '<?xml version="1.0"?>\n<WindowElement>\n<Optical>\n<Layer>\n' > "$tmp/cut.xml"
refuse spectro-bsdf-xml-malformed "$bin" metrics "$tmp/cut.xml"
check "the malformed file's message names its line" grep -q "cut.xml:5:" "$tmp/refused.err"
zcat "$x/cgdb_46016_seatex_midnight.xml.gz" | python3 -c "
import sys; s=sys.stdin.read(); i=s.index('<ScatteringData>')+len('<ScatteringData>'); j=s.index('</ScatteringData>')
sys.stdout.write(s[:i] + ' 0.1 0.2 0.3 ' + s[j:])" > "$tmp/short.xml"
refuse spectro-bsdf-xml-count "$bin" metrics "$tmp/short.xml"
sed 's/<IncidentDataStructure>Columns/<IncidentDataStructure>TensorTree3/' < <(zcat "$x/cgdb_46016_seatex_midnight.xml.gz") > "$tmp/tt.xml"
refuse spectro-bsdf-xml-tensor-tree "$bin" metrics "$tmp/tt.xml"
# A real tensor tree (genBSDF's b00kT): read and resampled onto the Klems
# full basis; its figures are checked against Radiance's bsdf2klems in
# tests/matdb/test_bsdf_xml_tree.c.
"$bin" metrics "$VR_SOURCE_DIR/tests/data/bsdf/tensortree_b00kT.xml" > "$tmp/ttm.txt" 2> "$tmp/ttm.err"
check "metrics reads a TensorTree4 file" test $? -eq 0
check "and says it was resampled" grep -q "basis LBNL/Klems Full, 145 patches (resampled from the file's TensorTree4)" "$tmp/ttm.txt"
check "its normal-incidence Tvis (Transmission Back, direct-hemispherical 0.869)" \
  grep -Eq "^Visible +Transmission Back +[0-9.]+ +[0-9.]+ +0\.86[89]" "$tmp/ttm.txt"
refuse spectro-bsdf-xml-pane-option "$bin" metrics "$x/SquareSlat_genBSDF.xml.gz" --standard en410
refuse spectro-phi-for-pane "$bin" metrics "$g/clear_float/CLEAR_3.DAT" --phi 90
refuse spectro-bsdf-xml-no-out "$bin" bsdf-xml "$g/clear_float/CLEAR_3.DAT"
refuse spectro-bsdf-xml-stack-and-pane "$bin" bsdf-xml "$g/clear_float/CLEAR_3.DAT" --stack "$g/lowe/lowe.model" --out "$tmp/o.xml"
refuse spectro-bsdf-xml-wavelengths "$bin" bsdf-xml "$g/clear_float/CLEAR_3.DAT" --wavelengths 400:800:10 --out "$tmp/o.xml"
check "refused bsdf-xml runs wrote nothing" test ! -e "$tmp/o.xml"
refuse spectro-bsdf-xml-out-name "$bin" bsdf-xml "$g/clear_float/CLEAR_3.DAT" --out "$tmp/pane.txt"
printf 'wavelength_nm,T\n' > "$tmp/t_only.csv"
for w in $(seq 300 5 2500); do echo "$w,0.85"; done >> "$tmp/t_only.csv"
refuse spectro-bsdf-xml-no-reflectance "$bin" bsdf-xml "$tmp/t_only.csv" --thickness 4 --out "$tmp/t.xml"
check "nothing written for a refused pane" test ! -e "$tmp/t.xml"
cp "$tmp/clear.xml" "$tmp/keep.xml"
refuse spectro-bsdf-xml-over-input "$bin" bsdf-xml "$tmp/keep.xml" --out "$tmp/keep.xml"
check "the input is left as it was" cmp -s "$tmp/clear.xml" "$tmp/keep.xml"

finish
