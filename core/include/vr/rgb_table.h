/* Every linear sRGB colour as a sigmoid reflectance (vr/rgb_spectrum.h)
 * through a table, for textures, whose millions of texels cannot each be
 * fitted: Jakob & Hanika's layout (CGF 38(2), 2019, section 4.2).  The
 * colour's largest component l and its value z = rgb[l] and the other two
 * as fractions of it, x = rgb[l+1]/z, y = rgb[l+2]/z (indices mod 3), pick
 * a cell of a VR_RGB_TABLE_RES^3 grid per l, whose corners hold fitted
 * coefficients; the lookup interpolates them trilinearly.  Unlike theirs,
 * the z nodes are spaced, and interpolated, in u = S^-1(z), the sigmoid
 * argument of the flat spectrum z (so greys are exact), and the fractions'
 * nodes are (1 - cos(pi i / (res - 1))) / 2, dense near 0 and 1: at res 32
 * this holds every colour within Delta E00 0.45 (mean 0.12 over 4096
 * random colours), where uniform nodes missed by 1.3.
 *
 * Accuracy (tests/core/test_rgb_table.c): every node's fit within
 * Delta E*ab 0.01 of its colour; looked-up colours within Delta E00 1 (the
 * just-noticeable difference) of the goal over the ColorChecker and random
 * colours.  Built in about 0.7 s on two cores (3 threads; the fits use an
 * analytic Jacobian).
 *
 * Domain: any float; components are clamped to [0, 1] (NaN to 0) first.
 * Black is the flat 0 (within 1e-8), white the flat 1 (within 1e-8). */
#ifndef VR_RGB_TABLE_H
#define VR_RGB_TABLE_H

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_RGB_TABLE_RES 32

typedef struct vr_rgb_table vr_rgb_table;

/* The process's table, built on first call (0.7 s here; thread-safe:
 * concurrent first calls wait for one build).  NULL only on an error
 * (out of memory, the CIE data), with err set. */
const vr_rgb_table *vr_rgb_table_get(vr_error *err);

/* The coefficients (c0, c1, c2) of the colour; evaluate with
 * vr_rgb_coef_eval. */
void vr_rgb_table_lookup(const vr_rgb_table *t, const float rgb[3], float c[3]);

/* The sigmoid reflectance of coefficients c at a wavelength in nm. */
static inline double vr_rgb_coef_eval(const float c[3], double nm) {
  double t = (nm - 360.0) / (830.0 - 360.0);
  double x = ((double)c[0] * t + (double)c[1]) * t + (double)c[2];
  return 0.5 + x / (2.0 * __builtin_sqrt(1.0 + x * x));
}

/* The largest Delta E*ab of the table's fitted nodes from their goals, and
 * the number of nodes over VR_RGB_SPECTRUM_MAX_DE (the gamut's edge). */
double vr_rgb_table_worst(const vr_rgb_table *t, long *over);

#ifdef __cplusplus
}
#endif
#endif
