/* RGB colours as sigmoid reflectance spectra (vr/rgb_spectrum.h).
 *
 * The fit: the colour of R(lambda) = S(c0 t^2 + c1 t + c2) under D65 is
 * summed at 5 nm over 360-830 nm (the CMFs' range; 5 nm is finer than the
 * sigmoid's curvature and than the renderer's bins), and its CIELAB
 * coordinates are brought to the goal's by damped Gauss-Newton
 * (Levenberg-Marquardt) on the three coefficients.  Saturated colours need
 * large coefficients that a start at grey does not reach in one go, so the
 * goal moves from mid grey to the colour in steps, each fit starting from
 * the last (the continuation Jakob and Hanika use to fill their tables). */
#include "vr/rgb_spectrum.h"

#include <ctype.h>
#include <math.h>
#include <string.h>

#include "rgb_fit.h"
#include "vr/colour.h"

#define STEPS 24
#define ITERS 40

double vr_rgbfit_goal(const vr_rgbfit_w *W, const double rgb[3], double lab[3]) {
  double xyz[3];
  vr_srgb_linear_to_xyz(rgb, xyz);
  vr_xyz_to_lab(xyz, W->white, lab);
  return lab[0];
}

static double sigmoid(double x) {
  if (isinf(x)) return x > 0 ? 1 : 0;
  return 0.5 + x / (2 * sqrt(1 + x * x));
}

double vr_rgb_spectrum_eval(const vr_rgb_spectrum *s, double nm) {
  double t = (nm - VR_RGBFIT_LO_NM) / (VR_RGBFIT_HI_NM - VR_RGBFIT_LO_NM);
  if (isinf(s->c[2])) return s->c[2] > 0 ? 1 : 0;
  return sigmoid((s->c[0] * t + s->c[1]) * t + s->c[2]);
}

vr_status vr_rgbfit_weights(vr_rgbfit_w *W, vr_error *err) {
  vr_spectrum *d65 = vr_illuminant("D65", err);
  if (!d65) return err ? err->status : VR_E_NOMEM;
  double ysum = 0;
  for (int i = 0; i < VR_RGBFIT_NS; i++) {
    double nm = VR_RGBFIT_LO_NM + 5.0 * i, cmf[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, cmf);
    double e = vr_spectrum_eval(d65, nm, VR_INTERP_LINEAR);
    for (int k = 0; k < 3; k++) W->w[i][k] = e * cmf[k];
    ysum += W->w[i][1];
  }
  vr_spectrum_destroy(d65);
  memset(W->white, 0, sizeof W->white);
  for (int i = 0; i < VR_RGBFIT_NS; i++)
    for (int k = 0; k < 3; k++) W->white[k] += (W->w[i][k] /= ysum);
  return VR_OK;
}

void vr_rgbfit_lab(const vr_rgbfit_w *W, const double c[3], double lab[3]) {
  double xyz[3] = {0, 0, 0};
  for (int i = 0; i < VR_RGBFIT_NS; i++) {
    double t = (double)i / (VR_RGBFIT_NS - 1);
    double r = sigmoid((c[0] * t + c[1]) * t + c[2]);
    for (int k = 0; k < 3; k++) xyz[k] += W->w[i][k] * r;
  }
  vr_xyz_to_lab(xyz, W->white, lab);
}

/* The derivative of CIELAB's f (CIE 15:2004, 8.2.1: cbrt above
 * (6/29)^3, the line of slope 1 / (3 (6/29)^2) below). */
static double lab_df(double t) {
  const double d = 6.0 / 29.0;
  return t > d * d * d ? 1.0 / (3 * cbrt(t) * cbrt(t)) : 1.0 / (3 * d * d);
}

/* The Jacobian of Lab in the coefficients, analytic: XYZ and its
 * derivatives in one pass over the samples (S'(x) = 1 / (2 (1 + x^2)^1.5),
 * dx/dc = t^2, t, 1), then the chain rule through f. */
static void jacobian(const vr_rgbfit_w *W, const double c[3], double J[3][3]) {
  double xyz[3] = {0, 0, 0}, d[3][3] = {{0}};
  for (int i = 0; i < VR_RGBFIT_NS; i++) {
    double t = (double)i / (VR_RGBFIT_NS - 1), x = (c[0] * t + c[1]) * t + c[2];
    double q = 1 + x * x, r = 0.5 + x / (2 * sqrt(q)), s = 1 / (2 * q * sqrt(q));
    double dx[3] = {t * t, t, 1};
    for (int k = 0; k < 3; k++) {
      xyz[k] += W->w[i][k] * r;
      for (int j = 0; j < 3; j++) d[k][j] += W->w[i][k] * s * dx[j];
    }
  }
  double g[3];
  for (int k = 0; k < 3; k++) g[k] = lab_df(xyz[k] / W->white[k]) / W->white[k];
  for (int j = 0; j < 3; j++) {
    double fx = g[0] * d[0][j], fy = g[1] * d[1][j], fz = g[2] * d[2][j];
    J[0][j] = 116 * fy;
    J[1][j] = 500 * (fx - fy);
    J[2][j] = 200 * (fy - fz);
  }
}

static double dist(const double a[3], const double b[3]) {
  return sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
              (a[2] - b[2]) * (a[2] - b[2]));
}

/* Solves the 3 x 3 system A x = b by Cramer's rule; false if singular. */
static bool solve3(const double A[3][3], const double b[3], double x[3]) {
  double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
               A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
               A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  if (!(fabs(det) > 1e-300)) return false;
  for (int j = 0; j < 3; j++) {
    double M[3][3];
    memcpy(M, A, sizeof M);
    for (int i = 0; i < 3; i++) M[i][j] = b[i];
    x[j] = (M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
            M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
            M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0])) /
           det;
  }
  return true;
}

/* Levenberg-Marquardt from c towards the goal's Lab; returns Delta E. */
double vr_rgbfit_step(const vr_rgbfit_w *W, const double goal[3], double c[3], int iters) {
  double lab[3], mu = 1e-3;
  vr_rgbfit_lab(W, c, lab);
  double de = dist(lab, goal);
  for (int it = 0; it < iters && de > 1e-9; it++) {
    double J[3][3];
    jacobian(W, c, J);
    double A[3][3], g[3];
    for (int a = 0; a < 3; a++) {
      g[a] = 0;
      for (int i = 0; i < 3; i++) g[a] -= J[i][a] * (lab[i] - goal[i]);
      for (int b = 0; b < 3; b++) {
        A[a][b] = 0;
        for (int i = 0; i < 3; i++) A[a][b] += J[i][a] * J[i][b];
      }
    }
    bool better = false;
    for (int tries = 0; tries < 12 && !better; tries++) {
      double D[3][3], step[3];
      memcpy(D, A, sizeof D);
      for (int a = 0; a < 3; a++) D[a][a] += mu * (A[a][a] > 0 ? A[a][a] : 1);
      if (!solve3(D, g, step)) {
        mu *= 10;
        continue;
      }
      double cn[3] = {c[0] + step[0], c[1] + step[1], c[2] + step[2]}, ln[3];
      vr_rgbfit_lab(W, cn, ln);
      double dn = dist(ln, goal);
      if (dn < de) {
        memcpy(c, cn, sizeof cn), memcpy(lab, ln, sizeof ln);
        de = dn, better = true;
        mu = fmax(mu / 10, 1e-12);
      } else {
        mu *= 10;
      }
    }
    if (!better) break;
  }
  return de;
}

vr_status vr_rgb_spectrum_fit(const double rgb[3], vr_rgb_spectrum *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  for (int k = 0; k < 3; k++)
    if (!(rgb[k] >= 0 && rgb[k] <= 1))
      return vr_error_set(err, VR_E_RANGE,
                          "colour (%g, %g, %g): linear sRGB components must lie in [0, 1]", rgb[0],
                          rgb[1], rgb[2]);
  vr_rgbfit_w W;
  vr_status st = vr_rgbfit_weights(&W, err);
  if (st) return st;
  /* Greys: the flat spectrum S(c2) = g exactly (y = 2g - 1, c2 = y / sqrt(1 - y^2)). */
  if (rgb[0] == rgb[1] && rgb[1] == rgb[2]) {
    double y = 2 * rgb[0] - 1;
    out->c[2] = y >= 1 ? INFINITY : y <= -1 ? -INFINITY : y / sqrt(1 - y * y);
    return VR_OK;
  }
  double goal[3];
  vr_rgbfit_goal(&W, rgb, goal);
  /* From mid grey (c = 0) to the goal in steps of its Lab. */
  double start[3], c[3] = {0, 0, 0};
  vr_rgbfit_lab(&W, c, start);
  double de = 0;
  for (int s = 1; s <= STEPS; s++) {
    double f = (double)s / STEPS, g[3];
    for (int k = 0; k < 3; k++) g[k] = start[k] + f * (goal[k] - start[k]);
    de = vr_rgbfit_step(&W, g, c, ITERS);
  }
  out->c[0] = c[0], out->c[1] = c[1], out->c[2] = c[2];
  out->delta_e = de;
  if (!(de <= VR_RGB_SPECTRUM_MAX_DE))
    return vr_error_set(err, VR_E_NUMERIC,
                        "colour (%g, %g, %g): no reflectance reaches it (the closest is Delta E*ab "
                        "%.3g away; a reflectance must lie in [0, 1] at every wavelength, and the "
                        "colours at the very edge of the sRGB gamut need one that is 0 or 1 over "
                        "whole bands)",
                        rgb[0], rgb[1], rgb[2], de);
  return VR_OK;
}

static int hexval(int ch) {
  if (ch >= '0' && ch <= '9') return ch - '0';
  ch = tolower(ch);
  return ch >= 'a' && ch <= 'f' ? ch - 'a' + 10 : -1;
}

bool vr_rgb_parse_hex(const char *text, double rgb[3]) {
  if (!text || text[0] != '#' || strlen(text) != 7) return false;
  for (int k = 0; k < 3; k++) {
    int hi = hexval((unsigned char)text[1 + 2 * k]), lo = hexval((unsigned char)text[2 + 2 * k]);
    if (hi < 0 || lo < 0) return false;
    rgb[k] = vr_srgb_decode((16 * hi + lo) / 255.0);
  }
  return true;
}
