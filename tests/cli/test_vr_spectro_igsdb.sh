#!/usr/bin/env bash
# Coated single panes and a coated double glazing under NFRC 300, against
# figures published for the same measured data:
#   - the IGSDB's own summary of each product (integrated_results_summary,
#     NFRC), computed by LBNL's WINDOW: Tvis, Rvis front and back, Tuv and
#     the transmitted colour's X, Y, Z;
#   - Windows-CalcEngine's expected results (WinCalc's test suite): the
#     solar figures of three single panes and every figure of the double
#     glazing of NFRC 2191 (low-e, coated back) outside NFRC 102.
# The products are IGSDB JSON files as WinCalc's tests hold them
# (tests/data/spectro/igsdb/, README.md there).  Three are coated on the
# back, so their front and back reflectances differ: a swapped Rf/Rb
# column or a pane read backwards moves Rvis by 0.01 to 0.03.
set -u
bin="$VR_BIN/vr-spectro"
d="$VR_SOURCE_DIR/tests/data/spectro/igsdb"
clear3="$VR_SOURCE_DIR/samples/glazing/clear_float/CLEAR_3.DAT"
source "$(dirname "$0")/harness.sh"

# The IGSDB JSON's spectral rows as the CSV vr-spectro reads (wavelength in
# micrometres, T, Rf, Rb; its thickness as a comment).
to_csv() { python3 "$(dirname "$0")/igsdb_csv.py" "$@"; }

# 1. Every product against the IGSDB's summary.  The summary's figures are
#    single-precision floats printed to 7 significant digits, so each is
#    held to one unit of its 7th significant digit (the float's spacing,
#    6e-8 near 0.9, plus the half unit of printing).  WINDOW's solar
#    figures are not checked here: its solar integration differs from
#    Windows-CalcEngine's by up to 8e-5 on these panes (WinCalc's own are
#    in section 2).
for id in 6046 21467 6400 2191 11561 9962; do
  to_csv "$d/nfrc_$id.json" "$tmp/$id.csv"
  "$bin" metrics "$tmp/$id.csv" --standard nfrc --json > "$tmp/$id.out"; rc=$?
  check "NFRC $id: metrics runs" test $rc -eq 0
  python3 - "$d/nfrc_$id.json" "$tmp/$id.out" <<'PY'
import json, math, sys
s = [x for x in json.load(open(sys.argv[1]))['integrated_results_summary']
     if x['calculation_standard_name'] == 'NFRC'][0]
m = json.load(open(sys.argv[2]))
pairs = [('tfvis', m['Tvis']), ('rfvis', m['Rvis_front']), ('rbvis', m['Rvis_back']),
         ('tuv', m['Tuv']), ('tciex', m['T_XYZ'][0]), ('tciey', m['T_XYZ'][1]),
         ('tciez', m['T_XYZ'][2])]
bad = []
for k, ours in pairs:
    want = s[k]
    unit = 10 ** (math.floor(math.log10(abs(want))) - 6)
    if abs(ours - want) > unit:
        bad.append('%s: %.9g, IGSDB %.9g (bound %.0e)' % (k, ours, want, unit))
assert not bad, bad
PY
  check "NFRC $id: Tvis, Rvis front/back, Tuv, transmitted XYZ equal the IGSDB's" test $? -eq 0
done

# 2. Windows-CalcEngine's expected results (LBNL-ETA/WinCalc at 65e615a3,
#    test/expected_results/.../no_basis/full_spectrum/theta=0_phi=0/, the
#    direct-hemispherical system figures), within 1e-6 as the CEN case of
#    test_vr_spectro.sh: the same integration of the same data.
python3 - "$tmp" <<'PY'
import json, sys
t = sys.argv[1]
# (Tsol, Rsol front, Rsol back), WinCalc's 1_layer/coated_nfrc_*/solar.json
want = {6046: (0.38320977335302403, 0.2859716745906676, 0.4492397297378513),
        21467: (0.8576201292183416, 0.10884755380372335, 0.11456752185525478),
        6400: (0.2924510119608726, 0.4177759275897887, 0.538454518889331)}
bad = []
for id, w in want.items():
    m = json.load(open('%s/%d.out' % (t, id)))
    for k, v in zip(('Tsol', 'Rsol_front', 'Rsol_back'), w):
        if abs(m[k] - v) > 1e-6:
            bad.append('%d %s: %.9g, WinCalc %.9g' % (id, k, m[k], v))
assert not bad, bad
PY
check "solar figures of NFRC 6046, 21467, 6400 equal WinCalc's" test $? -eq 0

# The double glazing: NFRC 2191 outside (its coating on surface 2), NFRC 102
# inside.  2191 is measured to 25 um, NFRC 102 to 2.5 um: the system is
# formed where both are measured.  WinCalc's
# 2_layers/low_e_nfrc_2191_air_nfrc_102 photopic, solar and tuv.json.
"$bin" metrics --panes "$tmp/2191.csv,$clear3" --standard nfrc --json > "$tmp/dg.out"; rc=$?
check "double glazing 2191 | NFRC 102: metrics runs" test $rc -eq 0
python3 - "$tmp/dg.out" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
want = {'Tvis': 0.7883163119098675, 'Rvis_front': 0.15427560431717915,
        'Rvis_back': 0.14613895561167434, 'Tsol': 0.5867449144609855,
        'Rsol_front': 0.20467097234144105, 'Rsol_back': 0.20665692165336225,
        'Tuv': 0.2837987702992273}
bad = ['%s: %.9g, WinCalc %.9g' % (k, m[k], v) for k, v in want.items() if abs(m[k] - v) > 1e-6]
assert not bad, bad
PY
check "double glazing 2191 | NFRC 102: every figure equals WinCalc's" test $? -eq 0

# 3. Panes that share no measured range are refused.
printf 'wavelength_um,T,Rf,Rb\n0.3,0.5,0.1,0.1\n0.4,0.5,0.1,0.1\n0.5,0.5,0.1,0.1\n' > "$tmp/a.csv"
printf 'wavelength_um,T,Rf,Rb\n0.6,0.5,0.1,0.1\n1.0,0.5,0.1,0.1\n2.5,0.5,0.1,0.1\n' > "$tmp/b.csv"
refuse spectro-panes-disjoint "$bin" metrics --panes "$tmp/a.csv,$tmp/b.csv"

finish
