/* Photometric <-> radiometric conversion for light sources.  The efficacy
 * integrals walk the merged grid of the spectrum's samples and the CIE
 * table's 1 nm rows, on which both functions are linear, so the rules used
 * (trapezoid for S, Simpson for V S) are exact for the interpolants. */
#include "vr/photometry.h"

#include <math.h>

#include "vr/colour.h"

#define PI 3.14159265358979323846

/* A band no renderer will ask for is refused before the walk, so a stray
 * number cannot make it run for ever. */
#define BAND_MIN_NM 1.0
#define BAND_MAX_NM 100000.0

const char *vr_photometry_unit_name(vr_light_unit u) {
  switch (u) {
  case VR_UNIT_W: return "W";
  case VR_UNIT_LM: return "lm";
  case VR_UNIT_CD: return "cd";
  case VR_UNIT_W_SR: return "W/sr";
  case VR_UNIT_LX: return "lx";
  case VR_UNIT_W_M2: return "W/m2";
  case VR_UNIT_CD_M2: return "cd/m2";
  case VR_UNIT_W_M2_SR: return "W/(m2 sr)";
  default: return "(no unit)";
  }
}

bool vr_photometry_is_photometric(vr_light_unit u) {
  return u == VR_UNIT_LM || u == VR_UNIT_CD || u == VR_UNIT_LX || u == VR_UNIT_CD_M2;
}

vr_light_unit vr_photometry_counterpart(vr_light_unit u) {
  switch (u) {
  case VR_UNIT_W: return VR_UNIT_LM;
  case VR_UNIT_LM: return VR_UNIT_W;
  case VR_UNIT_CD: return VR_UNIT_W_SR;
  case VR_UNIT_W_SR: return VR_UNIT_CD;
  case VR_UNIT_LX: return VR_UNIT_W_M2;
  case VR_UNIT_W_M2: return VR_UNIT_LX;
  case VR_UNIT_CD_M2: return VR_UNIT_W_M2_SR;
  case VR_UNIT_W_M2_SR: return VR_UNIT_CD_M2;
  default: return VR_UNIT_NONE;
  }
}

static double v_of(double nm) {
  double xyz[3];
  vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
  return xyz[1];
}

/* The next knot after x: the next whole nanometre (the CMF rows) or the
 * next sample of the spectrum, whichever comes first, capped at hi.
 * *k tracks the spectrum sample index so the walk stays linear. */
static double next_knot(const vr_spectrum *s, size_t *k, double x, double hi) {
  double n = floor(x) + 1.0;
  while (*k < s->n && s->nm[*k] <= x) (*k)++;
  if (*k < s->n && s->nm[*k] < n) n = s->nm[*k];
  return n < hi ? n : hi;
}

static bool band_ok(double lo, double hi) {
  return lo >= BAND_MIN_NM && hi <= BAND_MAX_NM && lo < hi;
}

/* Both integrals in one walk: what = 0 for S, 1 for V S. */
static double walk(const vr_spectrum *s, double lo, double hi, int what) {
  if (!s || !band_ok(lo, hi)) return 0.0;
  size_t k = 0;
  double x0 = lo, s0 = vr_spectrum_eval(s, lo, VR_INTERP_LINEAR), sum = 0.0;
  double v0 = what ? v_of(lo) : 0.0;
  while (x0 < hi) {
    double x1 = next_knot(s, &k, x0, hi);
    double s1 = vr_spectrum_eval(s, x1, VR_INTERP_LINEAR), h = x1 - x0;
    if (what) {
      /* Simpson: exact for the quadratic V S on an interval where both are
       * linear. */
      double xm = 0.5 * (x0 + x1);
      double v1 = v_of(x1);
      sum += h / 6.0 *
             (v0 * s0 + 4.0 * v_of(xm) * vr_spectrum_eval(s, xm, VR_INTERP_LINEAR) + v1 * s1);
      v0 = v1;
    } else {
      sum += 0.5 * h * (s0 + s1);
    }
    x0 = x1;
    s0 = s1;
  }
  return sum;
}

double vr_photometry_band_integral(const vr_spectrum *spd, double lo, double hi) {
  return walk(spd, lo, hi, 0);
}

double vr_photometry_v_integral(const vr_spectrum *spd, double lo, double hi) {
  return walk(spd, lo, hi, 1);
}

vr_status vr_photometry_efficacy(const vr_spectrum *spd, double lo, double hi, double *K,
                                 vr_error *err) {
  if (!spd) return vr_error_set(err, VR_E_ARG, "luminous efficacy: no spectrum");
  if (!band_ok(lo, hi))
    return vr_error_set(err, VR_E_ARG,
                        "luminous efficacy: band %g..%g nm is empty, inverted or outside "
                        "%g..%g nm",
                        lo, hi, BAND_MIN_NM, BAND_MAX_NM);
  double e = walk(spd, lo, hi, 0);
  if (!(e > 0.0) || !isfinite(e))
    return vr_error_set(err, VR_E_RANGE,
                        "luminous efficacy: the spectrum carries no power in %g..%g nm "
                        "(integral %g)",
                        lo, hi, e);
  /* Km = 683.002 lm/W, CIE 015:2018 (VR_KM in vr/colour.h). */
  *K = VR_KM * walk(spd, lo, hi, 1) / e;
  return VR_OK;
}

static int kind_of(vr_light_unit u) {
  switch (u) {
  case VR_UNIT_W: case VR_UNIT_LM: return 1;       /* power */
  case VR_UNIT_CD: case VR_UNIT_W_SR: return 2;    /* intensity */
  case VR_UNIT_LX: case VR_UNIT_W_M2: return 3;    /* illuminance */
  case VR_UNIT_CD_M2: case VR_UNIT_W_M2_SR: return 4; /* luminance */
  default: return 0;
  }
}

static vr_status check_value(vr_quantity q, vr_error *err) {
  if (!(q.value >= 0.0) || !isfinite(q.value))
    return vr_error_set(err, VR_E_ARG, "light amount %g %s: must be finite and >= 0", q.value,
                        vr_photometry_unit_name(q.unit));
  return VR_OK;
}

vr_status vr_photometry_convert(vr_quantity q, vr_light_unit to, const vr_spectrum *spd,
                                double lo, double hi, double *out, vr_error *err) {
  vr_status st = check_value(q, err);
  if (st != VR_OK) return st;
  int kq = kind_of(q.unit), kt = kind_of(to);
  if (!kq || kq != kt)
    return vr_error_set(err, VR_E_ARG, "cannot express %g %s in %s: not the same kind of amount",
                        q.value, vr_photometry_unit_name(q.unit), vr_photometry_unit_name(to));
  if (q.unit == to) {
    *out = q.value;
    return VR_OK;
  }
  double K;
  st = vr_photometry_efficacy(spd, lo, hi, &K, err);
  if (st != VR_OK) {
    vr_error_prefix(err, "converting %g %s to %s: ", q.value, vr_photometry_unit_name(q.unit),
                    vr_photometry_unit_name(to));
    return st;
  }
  /* Photometric = K x radiometric, for every kind alike (the geometry is
   * the same on both sides). */
  if (!(K > 0.0) && vr_photometry_is_photometric(q.unit))
    return vr_error_set(err, VR_E_RANGE,
                        "cannot express %g %s in %s: the spectrum has no luminous efficacy in "
                        "%g..%g nm",
                        q.value, vr_photometry_unit_name(q.unit), vr_photometry_unit_name(to), lo,
                        hi);
  *out = vr_photometry_is_photometric(q.unit) ? q.value / K : q.value * K;
  return VR_OK;
}

double vr_photometry_solid_angle(vr_distribution d) {
  switch (d) {
  case VR_DIST_ISOTROPIC: return 4.0 * PI;
  case VR_DIST_LAMBERTIAN: return PI;
  default: return NAN;
  }
}

vr_status vr_photometry_point_light(vr_quantity amount, double omega, const vr_spectrum *spd,
                                    double lo, double hi, vr_point_radiometry *out,
                                    vr_error *err) {
  int k = kind_of(amount.unit);
  if (k != 1 && k != 2)
    return vr_error_set(err, VR_E_ARG,
                        "point light amount %g %s: expected a power (W, lm) or an intensity "
                        "(cd, W/sr)",
                        amount.value, vr_photometry_unit_name(amount.unit));
  if (!(omega > 0.0) || !isfinite(omega))
    return vr_error_set(err, VR_E_ARG,
                        "point light: the ratio of flux to intensity %g sr must be > 0", omega);
  vr_status st = check_value(amount, err);
  if (st != VR_OK) return st;
  double K;
  st = vr_photometry_efficacy(spd, lo, hi, &K, err);
  if (st != VR_OK) return st;
  double radiometric;
  st = vr_photometry_convert(amount, k == 1 ? VR_UNIT_W : VR_UNIT_W_SR, spd, lo, hi,
                             &radiometric, err);
  if (st != VR_OK) return st;
  out->efficacy_lm_per_w = K;
  if (k == 1) {
    out->power_w = radiometric;
    out->intensity_w_sr = radiometric / omega;
  } else {
    out->intensity_w_sr = radiometric;
    out->power_w = radiometric * omega;
  }
  out->intensity_scale = out->intensity_w_sr / vr_photometry_band_integral(spd, lo, hi);
  return VR_OK;
}

vr_status vr_photometry_radiometric(vr_quantity q, vr_light_unit expect, const vr_spectrum *spd,
                                    double lo, double hi, double *amount, double *scale,
                                    vr_error *err) {
  if (vr_photometry_is_photometric(expect) || !kind_of(expect))
    return vr_error_set(err, VR_E_ARG, "radiometric amount: %s is not a radiometric unit",
                        vr_photometry_unit_name(expect));
  if (kind_of(q.unit) != kind_of(expect))
    return vr_error_set(err, VR_E_ARG, "light amount %g %s: expected %s or %s", q.value,
                        vr_photometry_unit_name(q.unit), vr_photometry_unit_name(expect),
                        vr_photometry_unit_name(vr_photometry_counterpart(expect)));
  double a;
  vr_status st = vr_photometry_convert(q, expect, spd, lo, hi, &a, err);
  if (st != VR_OK) return st;
  *amount = a;
  if (scale) {
    double e = vr_photometry_band_integral(spd, lo, hi);
    if (!(e > 0.0))
      return vr_error_set(err, VR_E_RANGE,
                          "light amount %g %s: the spectrum carries no power in %g..%g nm",
                          q.value, vr_photometry_unit_name(q.unit), lo, hi);
    *scale = a / e;
  }
  return VR_OK;
}
