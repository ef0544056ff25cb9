#!/usr/bin/env python3
# tests/cli/test_vr_spectro.sh: the coated-stack BTDF table against an
# independent thin-film computation (characteristic matrices, Macleod,
# Thin-Film Optical Filters, 4th ed., ch. 2; an incoherent substrate by
# summing intensities) of
# the sample low-e stack, at every angle of the table, s and p apart.
import cmath, math, re, sys
d = sys.argv[1]
def rii(path):
    txt = open(path).read()
    tab = []
    m = re.search(r"type: tabulated nk\s+data: \|\n((?:\s+[-+0-9.eE]+\s+[-+0-9.eE]+\s+[-+0-9.eE]+\n)+)", txt)
    if m:
        for line in m.group(1).split("\n"):
            if line.strip():
                w, n, k = map(float, line.split()); tab.append((w * 1000, n, k))
        def nk(nm):
            for (w0, n0, k0), (w1, n1, k1) in zip(tab, tab[1:]):
                if w0 <= nm <= w1:
                    f = (nm - w0) / (w1 - w0)
                    return complex(n0 + f * (n1 - n0), k0 + f * (k1 - k0))
            raise ValueError(nm)
        return nk
    c = list(map(float, re.search(r"coefficients: ([-0-9. eE]+)", txt).group(1).split()))
    ktab = []
    m = re.search(r"type: tabulated k\s+data: \|\n((?:\s+[-+0-9.eE]+\s+[-+0-9.eE]+\n)+)", txt)
    for line in m.group(1).split("\n"):
        if line.strip():
            w, k = map(float, line.split()); ktab.append((w * 1000, k))
    def nk(nm):
        um = nm / 1000
        n = c[0] + c[1] * um ** c[2] + c[3] * um ** c[4]
        for (w0, k0), (w1, k1) in zip(ktab, ktab[1:]):
            if w0 <= nm <= w1:
                return complex(n, k0 + (nm - w0) / (w1 - w0) * (k1 - k0))
        raise ValueError(nm)
    return nk
zno, ag, glass = rii(d + "/ZnO_Aguilar.yml"), rii(d + "/Ag_Ciesielski.yml"), rii(d + "/SodaLime_Rubin.yml")
def stack(nm, layers, n_in, n_out, beta=0.0, pol="s"):
    # R, T of films between media n_in and n_out for light whose invariant
    # n sin(theta) is beta (0: normal incidence), by the tilted admittances
    # eta_s = N cos(theta), eta_p = N / cos(theta) (Macleod, ch. 2.5); N cos
    # is sqrt(N^2 - beta^2) on the branch that decays in an absorbing film.
    def eta(N):
        nc = cmath.sqrt(N * N - beta * beta)
        return (nc if pol == "s" else N * N / nc), nc
    M = [[1, 0], [0, 1]]
    for N, dd in layers:
        e, nc = eta(N)
        delta = 2 * math.pi * nc * dd / nm
        A = [[cmath.cos(delta), 1j * cmath.sin(delta) / e], [1j * e * cmath.sin(delta), cmath.cos(delta)]]
        M = [[M[0][0] * A[0][0] + M[0][1] * A[1][0], M[0][0] * A[0][1] + M[0][1] * A[1][1]],
             [M[1][0] * A[0][0] + M[1][1] * A[1][0], M[1][0] * A[0][1] + M[1][1] * A[1][1]]]
    e_in, e_out = eta(n_in)[0], eta(n_out)[0]
    B = M[0][0] + M[0][1] * e_out
    C = M[1][0] + M[1][1] * e_out
    r = (e_in * B - C) / (e_in * B + C)
    t = 2 * e_in / (e_in * B + C)
    return abs(r) ** 2, (e_out.real / e_in.real) * abs(t) ** 2
worst = 0
bad = 0
rows = {}
for line in list(open(sys.argv[2]))[1:]:
    a, nm, ts, tp, rfs, rfp, rbs, rbp = map(float, line.split(","))
    rows[a] = rows.get(a, 0) + 1
    if a >= 90:
        # Grazing: nothing enters, everything is reflected (the admittances
        # are singular there).
        for name, want, got in (("T", 0.0, ts), ("T", 0.0, tp), ("Rf", 1.0, rfs), ("Rf", 1.0, rfp),
                                ("Rb", 1.0, rbs), ("Rb", 1.0, rbp)):
            if not (abs(want - got) <= float(sys.argv[3])):
                bad += 1
            print("%4.0f deg %6.0f %-2s table %.6f expected %.6f" % (a, nm, name, got, want))
        continue
    ns = glass(nm)
    beta = math.sin(math.radians(a))
    cos_g = math.sqrt(1 - (beta / ns.real) ** 2)
    # Macleod's convention: N = n - ik with this matrix.
    films = [(zno(nm).conjugate(), 35), (ag(nm).conjugate(), 10), (zno(nm).conjugate(), 35)]
    tau = math.exp(-4 * math.pi * ns.imag * 4e6 / (nm * cos_g))
    for pol, got in (("s", (ts, rfs, rbs)), ("p", (tp, rfp, rbp))):
        Rf1, Tf1 = stack(nm, films, complex(1), complex(ns.real, 0), beta, pol)
        Rb1, _ = stack(nm, films[::-1], complex(ns.real, 0), complex(1), beta, pol)
        Rg = stack(nm, [], complex(ns.real, 0), complex(1), beta, pol)[0]
        T = Tf1 * tau * (1 - Rg) / (1 - Rb1 * tau * tau * Rg)
        Rf = Rf1 + Tf1 * Tf1 * tau * tau * Rg / (1 - Rb1 * tau * tau * Rg)
        Rb = Rg + (1 - Rg) ** 2 * tau * tau * Rb1 / (1 - Rg * tau * tau * Rb1)
        for name, want, g in (("T", T, got[0]), ("Rf", Rf, got[1]), ("Rb", Rb, got[2])):
            diff = abs(want - g)
            worst = max(worst, diff)
            if not (diff <= float(sys.argv[3])):  # false for NaN too
                bad += 1
            print("%4.0f deg %6.0f %-2s %s table %.6f independent %.6f" % (a, nm, name, pol, g, want))
print("worst", worst, "rows by angle", rows, "outside the limit", bad)
# Usage: thin_film_check.py SAMPLE_FOLDER TABLE.csv LIMIT NROWS: exit 1 when
# a value (any angle, s or p) differs from the table by more than LIMIT (or
# is NaN), or when the table does not hold NROWS rows at each of its angles
# (among them 0 degrees).
ok = bad == 0 and 0.0 in rows and all(n == int(sys.argv[4]) for n in rows.values())
sys.exit(0 if ok else 1)
