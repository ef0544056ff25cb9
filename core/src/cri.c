/* Correlated colour temperature (CIE 015:2018 9.5) and the colour rendering
 * index of CIE 13.3-1995; see vr/cri.h for the method and its domain. */
#include "vr/cri.h"
#include "vr/colour.h"
#include "embedded.h"

#include <math.h>

/* CIE 13.3's sums: 5 nm from 380 to 780 nm. */
#define CRI_LO 380.0
#define CRI_STEP 5.0
#define CRI_N 81

#define CCT_MIN 1000.0
#define CCT_MAX 100000.0
#define DUV_MAX 0.05

void vr_xyz_to_uv1960(const double xyz[3], double uv[2]) {
  double den = xyz[0] + 15.0 * xyz[1] + 3.0 * xyz[2];
  uv[0] = 4.0 * xyz[0] / den;
  uv[1] = 6.0 * xyz[1] / den;
}

/* u, v of a Planckian radiator: sums at the observer's 1 nm rows. */
static void planck_uv(double kelvin, double uv[2]) {
  size_t rows;
  const double *t = vr_cmf_table(VR_CIE1931_2DEG, &rows);
  double xyz[3] = {0, 0, 0};
  for (size_t i = 0; i < rows; i++) {
    double p = vr_planck(t[i * 4], kelvin);
    for (int k = 0; k < 3; k++) xyz[k] += p * t[i * 4 + 1 + k];
  }
  vr_xyz_to_uv1960(xyz, uv);
}

static double locus_distance(const double uv[2], double mired) {
  double p[2];
  planck_uv(1e6 / mired, p);
  return hypot(uv[0] - p[0], uv[1] - p[1]);
}

vr_status vr_cct_from_uv(const double uv[2], double *cct, double *duv, vr_error *err) {
  if (!isfinite(uv[0]) || !isfinite(uv[1]))
    return vr_error_set(err, VR_E_RANGE, "chromaticity (%g, %g) is not finite", uv[0], uv[1]);
  /* A scan over reciprocal temperature (the locus is nearly uniform in
   * mired), then golden-section search around the nearest sample: the
   * distance is unimodal within a scan step of its minimum. */
  const double m_lo = 1e6 / CCT_MAX, m_hi = 1e6 / CCT_MIN, step = 2.5;
  double best_m = m_lo, best_d = INFINITY;
  for (double m = m_lo; m <= m_hi + 1e-9; m += step) {
    double d = locus_distance(uv, m);
    if (d < best_d) best_d = d, best_m = m;
  }
  double a = fmax(m_lo, best_m - step), b = fmin(m_hi, best_m + step);
  const double g = 0.5 * (sqrt(5.0) - 1.0);
  double c = b - g * (b - a), d = a + g * (b - a);
  double fc = locus_distance(uv, c), fd = locus_distance(uv, d);
  while (b - a > 1e-9) {
    if (fc < fd) {
      b = d, d = c, fd = fc;
      c = b - g * (b - a);
      fc = locus_distance(uv, c);
    } else {
      a = c, c = d, fc = fd;
      d = a + g * (b - a);
      fd = locus_distance(uv, d);
    }
  }
  double m = 0.5 * (a + b), T = 1e6 / m, p[2];
  planck_uv(T, p);
  double dist = hypot(uv[0] - p[0], uv[1] - p[1]);
  if (dist > DUV_MAX)
    return vr_error_set(err, VR_E_RANGE,
                        "chromaticity (u, v) = (%.4f, %.4f) lies %.4f from the Planckian locus "
                        "(more than %.2f): it has no correlated colour temperature",
                        uv[0], uv[1], dist, DUV_MAX);
  if (m <= m_lo + 1e-6 || m >= m_hi - 1e-6)
    return vr_error_set(err, VR_E_RANGE,
                        "chromaticity (u, v) = (%.4f, %.4f) is nearest the locus at its end "
                        "(%.0f K): outside %.0f-%.0f K",
                        uv[0], uv[1], T, CCT_MIN, CCT_MAX);
  *cct = T;
  if (duv) *duv = uv[1] >= p[1] ? dist : -dist;
  return VR_OK;
}

/* A spectrum at CIE 13.3's 81 wavelengths (linear between its samples). */
static vr_status sample(const vr_spectrum *s, const char *what, double out[CRI_N], vr_error *err) {
  if (!vr_spectrum_covers(s, CRI_LO, CRI_LO + CRI_STEP * (CRI_N - 1)))
    return vr_error_set(err, VR_E_RANGE,
                        "the %s covers %g-%g nm; colour rendering (CIE 13.3) needs 380-780 nm",
                        what, s->nm[0], s->nm[s->n - 1]);
  for (int i = 0; i < CRI_N; i++) {
    out[i] = vr_spectrum_eval(s, CRI_LO + CRI_STEP * i, VR_INTERP_LINEAR);
    if (!isfinite(out[i]))
      return vr_error_set(err, VR_E_RANGE, "the %s is not finite at %g nm", what,
                          CRI_LO + CRI_STEP * i);
  }
  return VR_OK;
}

/* The CIE 1931 observer at CIE 13.3's 81 wavelengths. */
static void cmf_grid(double cmf[CRI_N][3]) {
  for (int i = 0; i < CRI_N; i++) vr_cmf_eval(VR_CIE1931_2DEG, CRI_LO + CRI_STEP * i, cmf[i]);
}

/* XYZ of the test colour sample j (-1: the source itself) under S, the
 * source's Y at 100; returns sum S ybar (0: a source without luminance,
 * xyz then not finite). */
static double tristimulus(const double S[CRI_N], const double cmf[CRI_N][3], int j, double xyz[3]) {
  const double *t = vr_data_cie_tcs;
  unsigned cols = vr_data_cie_tcs_cols;
  double sum[3] = {0, 0, 0}, norm = 0;
  for (int i = 0; i < CRI_N; i++) {
    /* The samples' table starts at 360 nm, 5 nm apart. */
    unsigned row = (unsigned)lround((CRI_LO + CRI_STEP * i - t[0]) / CRI_STEP);
    double rho = j < 0 ? 1.0 : t[row * cols + 1 + (unsigned)j];
    for (int k = 0; k < 3; k++) sum[k] += S[i] * rho * cmf[i][k];
    norm += S[i] * cmf[i][1];
  }
  for (int k = 0; k < 3; k++) xyz[k] = 100.0 * sum[k] / norm;
  return norm;
}

static double cd_c(const double uv[2]) { return (4.0 - uv[0] - 10.0 * uv[1]) / uv[1]; }
static double cd_d(const double uv[2]) { return (1.708 * uv[1] + 0.404 - 1.481 * uv[0]) / uv[1]; }

static vr_status rendering(const double St[CRI_N], const double Sr[CRI_N], vr_cri *out,
                           vr_error *err) {
  double cmf[CRI_N][3], xyz[3], uv_t[2], uv_r[2];
  cmf_grid(cmf);
  double lum_t = tristimulus(St, cmf, -1, xyz);
  vr_xyz_to_uv1960(xyz, uv_t);
  double lum_r = tristimulus(Sr, cmf, -1, xyz);
  vr_xyz_to_uv1960(xyz, uv_r);
  if (!(lum_t > 0) || !(lum_r > 0))
    return vr_error_set(err, VR_E_RANGE,
                        "the %s has no luminance between 380 and 780 nm: no colour rendering",
                        lum_t > 0 ? "reference" : "source");
  out->dc = hypot(uv_t[0] - uv_r[0], uv_t[1] - uv_r[1]);
  out->dc_ok = out->dc < VR_CRI_DC_LIMIT;
  double ct = cd_c(uv_t), dt = cd_d(uv_t), cr = cd_c(uv_r), dr = cd_d(uv_r);
  double sum8 = 0;
  for (int j = 0; j < VR_CRI_SAMPLES; j++) {
    double xt[3], xr[3], ut[2], ur[2];
    tristimulus(St, cmf, j, xt);
    tristimulus(Sr, cmf, j, xr);
    vr_xyz_to_uv1960(xt, ut);
    vr_xyz_to_uv1960(xr, ur);
    /* CIE 13.3 eq. (6): the test sample's chromaticity adapted to the
     * reference white. */
    double ci = cd_c(ut), di = cd_d(ut);
    double den = 16.518 + 1.481 * (cr / ct) * ci - (dr / dt) * di;
    double ua = (10.872 + 0.404 * (cr / ct) * ci - 4.0 * (dr / dt) * di) / den;
    double va = 5.520 / den;
    double Wt = 25.0 * cbrt(xt[1]) - 17.0, Wr = 25.0 * cbrt(xr[1]) - 17.0;
    double dU = 13.0 * Wt * (ua - uv_r[0]) - 13.0 * Wr * (ur[0] - uv_r[0]);
    double dV = 13.0 * Wt * (va - uv_r[1]) - 13.0 * Wr * (ur[1] - uv_r[1]);
    double dE = sqrt(dU * dU + dV * dV + (Wt - Wr) * (Wt - Wr));
    out->R[j] = 100.0 - 4.6 * dE;
    if (j < 8) sum8 += out->R[j];
  }
  out->Ra = sum8 / 8.0;
  return VR_OK;
}

vr_status vr_cri_against(const vr_spectrum *source, const vr_spectrum *reference, vr_cri *out,
                         vr_error *err) {
  double St[CRI_N], Sr[CRI_N];
  vr_status st = sample(source, "source", St, err);
  if (!st) st = sample(reference, "reference", Sr, err);
  if (st) return st;
  out->cct = NAN;
  out->planckian = false;
  return rendering(St, Sr, out, err);
}

vr_status vr_cri_compute(const vr_spectrum *source, vr_cri *out, vr_error *err) {
  double St[CRI_N], Sr[CRI_N], xyz[3], uv[2], T;
  vr_status st = sample(source, "source", St, err);
  if (st) return st;
  double cmf[CRI_N][3];
  cmf_grid(cmf);
  if (!(tristimulus(St, cmf, -1, xyz) > 0))
    return vr_error_set(err, VR_E_RANGE,
                        "the source has no luminance between 380 and 780 nm: no colour rendering");
  vr_xyz_to_uv1960(xyz, uv);
  if ((st = vr_cct_from_uv(uv, &T, NULL, err))) return st;
  /* CIE 13.3 section 5.2: Planckian below 5000 K, daylight from 5000 K. */
  bool planck = T < 5000.0;
  vr_spectrum *ref = planck ? vr_illuminant_blackbody(T, err) : vr_illuminant_d(T, err);
  if (!ref) return err ? err->status : VR_E_RANGE;
  st = sample(ref, "reference", Sr, err);
  vr_spectrum_destroy(ref);
  if (st) return st;
  if ((st = rendering(St, Sr, out, err))) return st;
  out->cct = T;
  out->planckian = planck;
  return VR_OK;
}
