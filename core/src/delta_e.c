/* Colour differences: CIE 1976 and CIEDE2000.  The CIEDE2000 steps and their
 * numbering follow Sharma, Wu and Dalal, "The CIEDE2000 color-difference
 * formula: implementation notes, supplementary test data, and mathematical
 * observations", Color Res. Appl. 30(1), 2005, eqs. (1)-(17), including
 * their conventions for hue angles when a chroma is zero. */
#include "vr/colour.h"

#include <math.h>

static double deg(double rad) { return rad * 180.0 / M_PI; }
static double rad(double d) { return d * M_PI / 180.0; }

double vr_delta_e76(const double a[3], const double b[3]) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
              (a[2] - b[2]) * (a[2] - b[2]));
}

double vr_delta_e2000(const double lab1[3], const double lab2[3]) {
  double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2];
  double L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
  /* (2)-(7) */
  double C1 = hypot(a1, b1), C2 = hypot(a2, b2);
  double Cbar = 0.5 * (C1 + C2);
  double Cbar7 = pow(Cbar, 7.0);
  double G = 0.5 * (1.0 - sqrt(Cbar7 / (Cbar7 + pow(25.0, 7.0))));
  double a1p = (1.0 + G) * a1, a2p = (1.0 + G) * a2;
  double C1p = hypot(a1p, b1), C2p = hypot(a2p, b2);
  double h1p = (a1p == 0.0 && b1 == 0.0) ? 0.0 : deg(atan2(b1, a1p));
  double h2p = (a2p == 0.0 && b2 == 0.0) ? 0.0 : deg(atan2(b2, a2p));
  if (h1p < 0.0) h1p += 360.0;
  if (h2p < 0.0) h2p += 360.0;
  /* (8)-(12) */
  double dLp = L2 - L1, dCp = C2p - C1p, dhp;
  if (C1p * C2p == 0.0) dhp = 0.0;
  else if (fabs(h2p - h1p) <= 180.0) dhp = h2p - h1p;
  else if (h2p - h1p > 180.0) dhp = h2p - h1p - 360.0;
  else dhp = h2p - h1p + 360.0;
  double dHp = 2.0 * sqrt(C1p * C2p) * sin(rad(dhp) / 2.0);
  /* (13)-(17) */
  double Lbarp = 0.5 * (L1 + L2), Cbarp = 0.5 * (C1p + C2p), hbarp;
  if (C1p * C2p == 0.0) hbarp = h1p + h2p;
  else if (fabs(h1p - h2p) <= 180.0) hbarp = 0.5 * (h1p + h2p);
  else if (h1p + h2p < 360.0) hbarp = 0.5 * (h1p + h2p + 360.0);
  else hbarp = 0.5 * (h1p + h2p - 360.0);
  double T = 1.0 - 0.17 * cos(rad(hbarp - 30.0)) + 0.24 * cos(rad(2.0 * hbarp)) +
             0.32 * cos(rad(3.0 * hbarp + 6.0)) - 0.20 * cos(rad(4.0 * hbarp - 63.0));
  double dtheta = 30.0 * exp(-((hbarp - 275.0) / 25.0) * ((hbarp - 275.0) / 25.0));
  double Cbarp7 = pow(Cbarp, 7.0);
  double RC = 2.0 * sqrt(Cbarp7 / (Cbarp7 + pow(25.0, 7.0)));
  double l50 = (Lbarp - 50.0) * (Lbarp - 50.0);
  double SL = 1.0 + 0.015 * l50 / sqrt(20.0 + l50);
  double SC = 1.0 + 0.045 * Cbarp;
  double SH = 1.0 + 0.015 * Cbarp * T;
  double RT = -sin(rad(2.0 * dtheta)) * RC;
  double tL = dLp / SL, tC = dCp / SC, tH = dHp / SH;
  return sqrt(tL * tL + tC * tC + tH * tH + RT * tC * tH);
}
