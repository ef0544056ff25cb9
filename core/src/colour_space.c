/* Colour spaces: xyY, CIELAB (CIE 015:2018 section 8.2.1), sRGB
 * (IEC 61966-2-1:1999) and Bradford chromatic adaptation. */
#include "vr/colour.h"

#include <math.h>

static void mat3(const double m[9], const double v[3], double out[3]) {
  double a = m[0] * v[0] + m[1] * v[1] + m[2] * v[2];
  double b = m[3] * v[0] + m[4] * v[1] + m[5] * v[2];
  double c = m[6] * v[0] + m[7] * v[1] + m[8] * v[2];
  out[0] = a;
  out[1] = b;
  out[2] = c;
}

void vr_xyz_to_xyy(const double xyz[3], const double white[3], double xyy[3]) {
  double s = xyz[0] + xyz[1] + xyz[2];
  double Y = xyz[1];
  if (s == 0.0) {
    double w = white[0] + white[1] + white[2];
    xyy[0] = white[0] / w;
    xyy[1] = white[1] / w;
  } else {
    xyy[0] = xyz[0] / s;
    xyy[1] = xyz[1] / s;
  }
  xyy[2] = Y;
}

void vr_xyy_to_xyz(const double xyy[3], double xyz[3]) {
  double x = xyy[0], y = xyy[1], Y = xyy[2];
  if (y == 0.0) {
    xyz[0] = xyz[1] = xyz[2] = 0.0;
    return;
  }
  xyz[0] = x * Y / y;
  xyz[1] = Y;
  xyz[2] = (1.0 - x - y) * Y / y;
}

/* CIE 015:2018 eq. 8.6: f(t) with the exact rational thresholds. */
static const double EPS = 216.0 / 24389.0; /* (6/29)^3 */
static const double KAPPA = 24389.0 / 27.0; /* (29/3)^3 */

static double lab_f(double t) { return t > EPS ? cbrt(t) : (KAPPA * t + 16.0) / 116.0; }
static double lab_finv(double f) {
  double f3 = f * f * f;
  return f3 > EPS ? f3 : (116.0 * f - 16.0) / KAPPA;
}

void vr_xyz_to_lab(const double xyz[3], const double w[3], double lab[3]) {
  double fx = lab_f(xyz[0] / w[0]), fy = lab_f(xyz[1] / w[1]), fz = lab_f(xyz[2] / w[2]);
  lab[0] = 116.0 * fy - 16.0;
  lab[1] = 500.0 * (fx - fy);
  lab[2] = 200.0 * (fy - fz);
}

void vr_lab_to_xyz(const double lab[3], const double w[3], double xyz[3]) {
  double fy = (lab[0] + 16.0) / 116.0;
  double fx = fy + lab[1] / 500.0, fz = fy - lab[2] / 200.0;
  xyz[0] = w[0] * lab_finv(fx);
  xyz[1] = w[1] * lab_finv(fy);
  xyz[2] = w[2] * lab_finv(fz);
}

void vr_lab_to_lch(const double lab[3], double lch[3]) {
  lch[0] = lab[0];
  lch[1] = hypot(lab[1], lab[2]);
  double h = atan2(lab[2], lab[1]) * 180.0 / M_PI;
  lch[2] = h < 0.0 ? h + 360.0 : h;
}

/* IEC 61966-2-1:1999 section 5.2 (XYZ -> RGB) and 5.3 / Annex (RGB -> XYZ). */
static const double XYZ_TO_SRGB[9] = {3.2406, -1.5372, -0.4986, -0.9689, 1.8758,
                                      0.0415, 0.0557,  -0.2040, 1.0570};
static const double SRGB_TO_XYZ[9] = {0.4124, 0.3576, 0.1805, 0.2126, 0.7152,
                                      0.0722, 0.0193, 0.1192, 0.9505};

void vr_xyz_to_srgb_linear(const double xyz[3], double rgb[3]) { mat3(XYZ_TO_SRGB, xyz, rgb); }
void vr_srgb_linear_to_xyz(const double rgb[3], double xyz[3]) { mat3(SRGB_TO_XYZ, rgb, xyz); }

double vr_srgb_encode(double v) {
  double a = fabs(v), e = a <= 0.0031308 ? 12.92 * a : 1.055 * pow(a, 1.0 / 2.4) - 0.055;
  return v < 0.0 ? -e : e;
}

double vr_srgb_decode(double v) {
  double a = fabs(v), l = a <= 0.04045 ? a / 12.92 : pow((a + 0.055) / 1.055, 2.4);
  return v < 0.0 ? -l : l;
}

bool vr_xyz_to_srgb8(const double xyz[3], int rgb8[3]) {
  double lin[3];
  bool clipped = false;
  vr_xyz_to_srgb_linear(xyz, lin);
  for (int i = 0; i < 3; i++) {
    double v = lin[i];
    /* The standard's 4-digit matrices put D65 white at 1.0001; count a
     * channel as clipped only beyond that precision. */
    if (v < -1e-3 || v > 1.0 + 1e-3) clipped = true;
    v = v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v);
    rgb8[i] = (int)lround(255.0 * vr_srgb_encode(v));
  }
  return clipped;
}

void vr_srgb_white(double xyz[3]) {
  const double xyy[3] = {0.3127, 0.3290, 1.0};
  vr_xyy_to_xyz(xyy, xyz);
}

/* Bradford cone-response matrix (Lam 1985, as used in ICC and CIE 159). */
static const double BFD[9] = {0.8951, 0.2664, -0.1614, -0.7502, 1.7135,
                              0.0367, 0.0389, -0.0685, 1.0296};

void vr_mat3_inverse(const double m[9], double inv[9]) {
  double a = m[0], b = m[1], c = m[2], d = m[3], e = m[4], f = m[5], g = m[6], h = m[7], i = m[8];
  double A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
  double det = a * A + b * B + c * C;
  inv[0] = A / det;
  inv[1] = -(b * i - c * h) / det;
  inv[2] = (b * f - c * e) / det;
  inv[3] = B / det;
  inv[4] = (a * i - c * g) / det;
  inv[5] = -(a * f - c * d) / det;
  inv[6] = C / det;
  inv[7] = -(a * h - b * g) / det;
  inv[8] = (a * e - b * d) / det;
}

void vr_bradford(const double xyz[3], const double src[3], const double dst[3], double out[3]) {
  double s[3], d[3], c[3], inv[9];
  mat3(BFD, src, s);
  mat3(BFD, dst, d);
  mat3(BFD, xyz, c);
  for (int k = 0; k < 3; k++) c[k] *= d[k] / s[k];
  vr_mat3_inverse(BFD, inv);
  mat3(inv, c, out);
}
