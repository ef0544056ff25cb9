#!/usr/bin/env python3
"""Writes a Klems BSDF XML file whose transmission is reciprocal.

Usage: bench/bsdf_make_reciprocal.py IN.xml OUT.xml

Radiance evaluates a BSDF backwards (the view ray as the incident
direction), which is the same as evaluating it forwards only when the data
are reciprocal: T_front[o][i] = T_back[i][o] (rows outgoing, columns
incoming, one Klems basis on both sides).  Measured files often are not
(Radiance's checkBSDF reports the error).  This replaces the two
transmission matrices of every block by T_f' = (T_f + T_b^T) / 2 and
T_b' = T_f'^T, leaving reflection alone, so that a comparison with
Radiance (bench/bench_radiance_office.sh, SHADE_FILE=) isolates that
difference.  Reads plain XML (gunzip a .xml.gz first)."""
import re
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    text = open(sys.argv[1], encoding="utf-8-sig").read()
    pat = re.compile(r"<WavelengthDataDirection>\s*(.*?)\s*</WavelengthDataDirection>"
                     r".*?<ScatteringData>(.*?)</ScatteringData>", re.S)
    found = {}
    for m in pat.finditer(text):
        vals = [float(x) for x in re.split(r"[,\s]+", m.group(2).strip()) if x]
        n = int(round(len(vals) ** 0.5))
        if n * n != len(vals):
            sys.exit(f"{sys.argv[1]}: a {m.group(1)} block of {len(vals)} values is not square")
        found.setdefault(m.group(1), (m, [vals[i * n:(i + 1) * n] for i in range(n)]))
    if "Transmission Front" not in found or "Transmission Back" not in found:
        sys.exit(f"{sys.argv[1]}: no Transmission Front and Back blocks")
    tf = found["Transmission Front"][1]
    tb = found["Transmission Back"][1]
    n = len(tf)
    tfp = [[(tf[i][j] + tb[j][i]) / 2 for j in range(n)] for i in range(n)]
    tbp = [[tfp[j][i] for j in range(n)] for i in range(n)]

    def fmt(mat):
        return "\n" + "\n".join(",".join("%.6g" % v for v in row) + "," for row in mat) + "\n"

    out = text
    for name, mat in sorted((("Transmission Front", tfp), ("Transmission Back", tbp)),
                            key=lambda t: -found[t[0]][0].start(2)):
        m = found[name][0]
        out = out[:m.start(2)] + fmt(mat) + out[m.end(2):]
    open(sys.argv[2], "w", encoding="utf-8").write(out)


main()
