#!/usr/bin/env python3
"""Builds the synthetic measurement files of samples/glazing/ from published
values (README.md names every source).  Standard library only; the noise is
seeded, so the files are reproducible:

    python3 samples/glazing/make_samples.py BUILD_DIR

BUILD_DIR holds a built vr-spectro (for the low-e stack's thin-film optics).
The clear-glass base of the chromogenic samples is NFRC 102 (CLEAR_3.DAT)."""
import math
import os
import random
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
HC = 1239.84198  # eV nm


def read_igdb(path):
    rows = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("{"):
                continue
            um, t, rf, rb = (float(x) for x in line.split())
            rows.append((um * 1000.0, t, rf, rb))
    return rows


def eta_wo3(nm):
    """Coloration efficiency of WO3 (cm2/C): 78 at 632.8 nm and 125 at 950 nm
    (README), a Gaussian polaron band in photon energy centred at 1.2 eV
    through both points."""
    c, e1, e2 = 1.2, HC / 632.8, HC / 950.0
    two_w2 = ((e1 - c) ** 2 - (e2 - c) ** 2) / math.log(125.0 / 78.0)
    e = HC / nm
    return 125.0 * math.exp(-((e - c) ** 2 - (e2 - c) ** 2) / two_w2)


def clip(x):
    return min(max(x, 0.0), 1.0)


def electrochromic(base, rng):
    """View-like device: bleached = clear glass x 0.77 (device layers; Tvis
    0.69 as View's clear state), states 0-32 mC/cm2."""
    out = ["# Synthetic electrochromic glazing (WO3-based) at five tint states;",
           "# see README.md for the sources and the model. Noise sigma = 1e-3.",
           "# thickness: 6 mm",
           "wavelength_nm,T,Rf,Rb,state"]
    for q in (0, 8, 16, 24, 32):
        for nm, t, rf, rb in base:
            tq = 0.77 * t * 10 ** (-eta_wo3(nm) * q * 1e-3)
            out.append("%.1f,%.5f,%.5f,%.5f,%dmC/cm2" % (
                nm, clip(tq + rng.gauss(0, 1e-3)), clip(rf + rng.gauss(0, 1e-3)),
                clip(rb + rng.gauss(0, 1e-3)), q))
    return out


# Photochromic kinetics: b_ref = ln 2 / 56 s and Ea = 0.44 eV (Caurant et al.,
# README); a = 2e-3 m2/(W s) is an assumption (README).
A, B_REF, EA = 2e-3, math.log(2) / 56.0, 0.44 * 96485.33212


def pc_state(E, T, kind, t):
    b = B_REF * math.exp(-(EA / 8.314462618) * (1 / T - 1 / 298.15))
    ss = A * E / (A * E + b) if E > 0 else 0.0
    if kind == "steady":
        return ss
    if kind == "activation":
        return ss * (1 - math.exp(-(A * E + b) * t))
    return ss * math.exp(-b * t)


def photochromic(base, rng):
    states = [("E=0", 0, 298.15, "steady", 0), ("E=5", 5, 298.15, "steady", 0),
              ("E=10", 10, 298.15, "steady", 0), ("E=20", 20, 298.15, "steady", 0),
              ("E=40", 40, 298.15, "steady", 0), ("E=40:T=10C", 40, 283.15, "steady", 0),
              ("E=40:T=40C", 40, 313.15, "steady", 0),
              ("t=30:E=40", 40, 298.15, "activation", 30),
              ("t=120:E=40", 40, 298.15, "activation", 120),
              ("fade=60:E=40", 40, 298.15, "fade", 60)]
    out = ["# Synthetic silver-halide photochromic glass: steady states under UV,",
           "# activation and fading, three temperatures; see README.md. Noise 1e-3.",
           "# thickness: 4 mm",
           "wavelength_nm,T,Rf,Rb,state"]
    for label, E, T, kind, t in states:
        s = pc_state(E, T, kind, t)
        for nm, tc, rf, rb in base:
            dod = 0.6 * math.exp(-((nm - 550.0) / 150.0) ** 2)
            ts = tc * 10 ** (-s * dod)
            out.append("%.1f,%.5f,%.5f,%.5f,%s" % (
                nm, clip(ts + rng.gauss(0, 1e-3)), clip(rf + rng.gauss(0, 1e-3)),
                clip(rb + rng.gauss(0, 1e-3)), label))
    return out


def lowe(build):
    tool = os.path.join(build, "fit", "vr-spectro")
    table = os.path.join(HERE, "lowe", ".table.csv")
    subprocess.run([tool, "btdf", "--stack", os.path.join(HERE, "lowe", "lowe.model"),
                    "--angles", "0", "--wavelengths", "310:2500:10", "--table", table],
                   check=True, stdout=subprocess.DEVNULL)
    out = ["# Computed, not measured: T, Rf, Rb of lowe.model (ZnO 35 / Ag 10 / ZnO 35 nm",
           "# on 4 mm soda-lime) by thin-film optics; see README.md.",
           "# thickness: 4 mm",
           "wavelength_nm,T,Rf,Rb"]
    with open(table) as f:
        next(f)
        for line in f:
            a, nm, ts, tp, rfs, rfp, rbs, rbp = line.strip().split(",")
            out.append("%s,%.6f,%.6f,%.6f" % (nm, float(ts), float(rfs), float(rbs)))
    os.remove(table)
    return out


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else "build"
    base = read_igdb(os.path.join(HERE, "clear_float", "CLEAR_3.DAT"))
    rng = random.Random(2014)
    files = {"electrochromic/ec_states.csv": electrochromic(base, rng),
             "photochromic/pc_states.csv": photochromic(base, rng),
             "lowe/lowe.csv": lowe(build)}
    for name, lines in files.items():
        with open(os.path.join(HERE, name), "w") as f:
            f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
