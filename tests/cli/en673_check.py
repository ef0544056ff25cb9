#!/usr/bin/env python3
"""EN 673 U and EN 410 g recomputed from a `vr-spectro thermal --method
en673 --json` report, independently of the C code (fit/src/glazing_en673.c):
the panes' thicknesses, conductivities, corrected emissivities and solar
absorptances and the gaps as the report states them, EN 673's equations and
gas table at 10 C, EN 410's closed forms for 1, 2 and 3 panes (5.4.3-5.4.6).

usage: en673_check.py REPORT.json GAS [GAS...] (one gas per gap: air, argon,
krypton, xenon, or a mixture argon:0.9+air:0.1).  Exits non-zero naming the
figure that differs by more than 1e-9."""
import json
import sys

# EN 673, gas properties at 10 C: density, viscosity, conductivity, specific heat.
TABLE = {
    'air': (1.232, 1.761e-5, 2.496e-2, 1008.0),
    'argon': (1.699, 2.164e-5, 1.684e-2, 519.0),
    'krypton': (3.560, 2.400e-5, 0.900e-2, 245.0),
    'xenon': (5.689, 2.226e-5, 0.529e-2, 161.0),
}


def gas(spec):
    parts = spec.split('+')
    out = [0.0] * 4
    for p in parts:
        name, _, frac = p.partition(':')
        f = float(frac) if frac else 1.0
        for i in range(4):
            out[i] += f * TABLE[name][i]
    return out


def main():
    rep = json.load(open(sys.argv[1]))
    gases = [gas(g) for g in sys.argv[2:]]
    panes, gaps = rep['panes'], rep['gaps']
    n = len(panes)
    assert len(gaps) == n - 1 == len(gases), 'one gas per gap'
    edition_1997 = '1997' in rep['method']
    he = 23.0 if edition_1997 else 25.0
    ei = panes[-1]['emissivity'][1]
    hi = 3.6 + (4.4 if edition_1997 else 4.1) * ei / 0.837
    sigma, Tm = 5.67e-8, 283.0
    R_glass = [p['thickness_mm'] * 1e-3 / p['conductivity'] for p in panes]

    def hs_of(k, dT):
        rho, mu, lam, c = gases[k]
        s = gaps[k]['thickness_mm'] * 1e-3
        e1, e2 = panes[k]['emissivity'][1], panes[k + 1]['emissivity'][0]
        hr = 4 * sigma * Tm ** 3 / (1 / e1 + 1 / e2 - 1)
        gr = 9.81 * s ** 3 * dT * rho ** 2 / (Tm * mu ** 2)
        nu = max(1.0, 0.035 * (gr * mu * c / lam) ** 0.38)
        return hr + nu * lam / s

    dT = [15.0 / max(1, n - 1)] * (n - 1)
    for _ in range(200):
        hs = [hs_of(k, dT[k]) for k in range(n - 1)]
        tot = sum(1 / h for h in hs)
        new = [15.0 * (1 / h) / tot for h in hs]
        if all(abs(a - b) < 1e-14 for a, b in zip(new, dT)):
            break
        dT = new
    hs = [hs_of(k, dT[k]) for k in range(n - 1)]
    U = 1 / (1 / he + sum(R_glass) + sum(1 / h for h in hs) + 1 / hi)

    a = [p['solar_absorptance'] for p in panes]
    if n == 1:
        qi = a[0] * hi / (he + hi)
    elif n == 2:
        lam = 1 / (R_glass[0] + 1 / hs[0] + R_glass[1])
        qi = ((a[0] + a[1]) / he + a[1] / lam) / (1 / hi + 1 / he + 1 / lam)
    elif n == 3:
        l12 = 1 / (R_glass[0] + 1 / hs[0] + R_glass[1] / 2)
        l23 = 1 / (R_glass[1] / 2 + 1 / hs[1] + R_glass[2])
        qi = ((a[0] + a[1] + a[2]) / he + (a[1] + a[2]) / l12 + a[2] / l23) / (
            1 / hi + 1 / he + 1 / l12 + 1 / l23)
    else:
        sys.exit('EN 410 writes q_i for 1 to 3 panes')
    g = rep['tau_e'] + qi
    bad = []
    for name, ours, want in (('U', rep['U'], U), ('g', rep['g'], g), ('q_i', rep['q_i'], qi),
                             ('hi', rep['hi'], hi)):
        if abs(ours - want) > 1e-9:
            bad.append('%s %.12g, recomputed %.12g' % (name, ours, want))
    if round(U * 10) / 10 != rep['U_declared']:
        bad.append('declared U %.1f, recomputed %.1f' % (rep['U_declared'], round(U * 10) / 10))
    print('U %.9f (recomputed %.9f), g %.9f (recomputed %.9f)' % (rep['U'], U, rep['g'], g))
    if bad:
        sys.exit('; '.join(bad))


main()
