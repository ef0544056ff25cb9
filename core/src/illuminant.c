/* CIE illuminants: A and blackbodies from Planck's law, the daylight series
 * from S0, S1, S2, and the tabulated D65, D50, F and LED series (CIE 015:2018,
 * ISO/CIE 11664-2),
 * embedded from core/data with their sources named there. */
#include "vr/colour.h"
#include "embedded.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* CODATA 2018: h, c, k exact in the 2019 SI. */
#define PLANCK_H 6.62607015e-34
#define LIGHT_C 299792458.0
#define BOLTZMANN_K 1.380649e-23

double vr_planck(double nm, double kelvin) {
  double lam = nm * 1e-9;
  double c1 = 2.0 * PLANCK_H * LIGHT_C * LIGHT_C;      /* W m^2 sr^-1 */
  double c2 = PLANCK_H * LIGHT_C / BOLTZMANN_K;         /* m K */
  double x = c2 / (lam * kelvin);
  /* expm1 keeps precision in the Rayleigh-Jeans limit (x small). */
  return c1 / (pow(lam, 5.0) * expm1(x)) * 1e-9;        /* per nm */
}

static vr_spectrum *from_table(const double *t, unsigned rows, unsigned cols, unsigned col,
                               vr_error *err) {
  vr_spectrum *s = vr_spectrum_create_uniform(0.0, 1.0, rows, 0.0, err);
  if (!s) return NULL;
  for (unsigned i = 0; i < rows; i++) {
    s->nm[i] = t[i * cols];
    s->value[i] = t[i * cols + col];
  }
  return s;
}

vr_spectrum *vr_illuminant_a(vr_error *err) {
  vr_spectrum *s = vr_spectrum_create_uniform(300.0, 1.0, 531, 0.0, err);
  if (!s) return NULL;
  /* CIE 015:2018 eq. 2.1, with c2 = 1.435e7 nm K as the definition fixes. */
  const double c2 = 1.435e7, T = 2848.0;
  for (size_t i = 0; i < s->n; i++) {
    double l = s->nm[i];
    s->value[i] = 100.0 * pow(560.0 / l, 5.0) * expm1(c2 / (T * 560.0)) / expm1(c2 / (T * l));
  }
  return s;
}

vr_spectrum *vr_illuminant_blackbody(double kelvin, vr_error *err) {
  if (!(kelvin > 0.0) || !isfinite(kelvin)) {
    vr_error_set(err, VR_E_RANGE, "blackbody temperature must be positive (got %g K)", kelvin);
    return NULL;
  }
  vr_spectrum *s = vr_spectrum_create_uniform(300.0, 1.0, 531, 0.0, err);
  if (!s) return NULL;
  double ref = vr_planck(560.0, kelvin);
  for (size_t i = 0; i < s->n; i++) s->value[i] = 100.0 * vr_planck(s->nm[i], kelvin) / ref;
  return s;
}

static double round3(double x) { return round(x * 1000.0) / 1000.0; }

vr_spectrum *vr_illuminant_d(double T, vr_error *err) {
  if (!(T >= 4000.0 && T <= 25000.0)) {
    vr_error_set(err, VR_E_RANGE,
                 "CIE daylight is defined for 4000-25000 K (got %g K)", T);
    return NULL;
  }
  /* CIE 015:2018 eqs. 4.7-4.11. */
  double xd = T <= 7000.0
                  ? -4.6070e9 / (T * T * T) + 2.9678e6 / (T * T) + 0.09911e3 / T + 0.244063
                  : -2.0064e9 / (T * T * T) + 1.9018e6 / (T * T) + 0.24748e3 / T + 0.237040;
  double yd = -3.000 * xd * xd + 2.870 * xd - 0.275;
  double M = 0.0241 + 0.2562 * xd - 0.7341 * yd;
  double M1 = round3((-1.3515 - 1.7703 * xd + 5.9114 * yd) / M);
  double M2 = round3((0.0300 - 31.4424 * xd + 30.0717 * yd) / M);
  const double *t = vr_data_cie_d_vectors;
  unsigned rows = vr_data_cie_d_vectors_rows, cols = vr_data_cie_d_vectors_cols;
  /* The S vectors are published at 10 nm; the CIE obtains 5 nm values by
   * linear interpolation, and so do we. */
  double first = t[0], last = t[(rows - 1) * cols];
  size_t n = (size_t)llround((last - first) / 5.0) + 1;
  vr_spectrum *s = vr_spectrum_create_uniform(first, 5.0, n, 0.0, err);
  if (!s) return NULL;
  vr_spectrum *S[3];
  for (unsigned k = 0; k < 3; k++) {
    S[k] = from_table(t, rows, cols, k + 1, err);
    if (!S[k]) {
      for (unsigned j = 0; j < k; j++) vr_spectrum_destroy(S[j]);
      vr_spectrum_destroy(s);
      return NULL;
    }
  }
  for (size_t i = 0; i < n; i++) {
    double l = s->nm[i];
    s->value[i] = vr_spectrum_eval(S[0], l, VR_INTERP_LINEAR) +
                  M1 * vr_spectrum_eval(S[1], l, VR_INTERP_LINEAR) +
                  M2 * vr_spectrum_eval(S[2], l, VR_INTERP_LINEAR);
  }
  for (unsigned k = 0; k < 3; k++) vr_spectrum_destroy(S[k]);
  return s;
}

static const char *const F_NAMES[] = {"F1", "F2", "F3", "F4",  "F5",  "F6",
                                      "F7", "F8", "F9", "F10", "F11", "F12"};
static const char *const LED_NAMES[] = {"LED-B1", "LED-B2",   "LED-B3", "LED-B4", "LED-B5",
                                        "LED-BH1", "LED-RGB1", "LED-V1", "LED-V2"};
static const char *const ALL_NAMES[] = {
    "A",   "D50", "D55", "D65", "D75", "E",      "F1",     "F2",     "F3",     "F4",
    "F5",  "F6",  "F7",  "F8",  "F9",  "F10",    "F11",    "F12",    "LED-B1", "LED-B2",
    "LED-B3", "LED-B4", "LED-B5", "LED-BH1", "LED-RGB1", "LED-V1", "LED-V2"};

const char *const *vr_illuminant_names(size_t *count) {
  *count = sizeof ALL_NAMES / sizeof ALL_NAMES[0];
  return ALL_NAMES;
}

/* Parses a whole decimal number after a prefix ("D6500" -> 6500). */
static int number_after(const char *name, size_t skip, double *out) {
  const char *p = name + skip;
  if (!*p) return 0;
  for (const char *q = p; *q; q++)
    if (!isdigit((unsigned char)*q) && *q != '.') return 0;
  *out = atof(p);
  return 1;
}

vr_spectrum *vr_illuminant(const char *name, vr_error *err) {
  if (!strcasecmp(name, "A")) return vr_illuminant_a(err);
  if (!strcasecmp(name, "D65"))
    return from_table(vr_data_cie_d65, vr_data_cie_d65_rows, vr_data_cie_d65_cols, 1, err);
  if (!strcasecmp(name, "D50"))
    return from_table(vr_data_cie_d50, vr_data_cie_d50_rows, vr_data_cie_d50_cols, 1, err);
  /* The other named daylights are the D series at the nominal temperature
   * times 1.4388/1.4380 (the 1968 revision of c2), CIE 015:2018 note 4.1. */
  if (!strcasecmp(name, "D55")) return vr_illuminant_d(5500.0 * 1.4388 / 1.4380, err);
  if (!strcasecmp(name, "D75")) return vr_illuminant_d(7500.0 * 1.4388 / 1.4380, err);
  if (!strcasecmp(name, "E")) return vr_spectrum_create_uniform(300.0, 1.0, 531, 100.0, err);
  for (unsigned i = 0; i < 12; i++)
    if (!strcasecmp(name, F_NAMES[i]))
      return from_table(vr_data_cie_f_series, vr_data_cie_f_series_rows, vr_data_cie_f_series_cols,
                        i + 1, err);
  for (unsigned i = 0; i < 9; i++)
    if (!strcasecmp(name, LED_NAMES[i]))
      return from_table(vr_data_cie_led_series, vr_data_cie_led_series_rows,
                        vr_data_cie_led_series_cols, i + 1, err);
  double v;
  if ((name[0] == 'D' || name[0] == 'd') && number_after(name, 1, &v)) return vr_illuminant_d(v, err);
  if (!strncasecmp(name, "BB", 2) && number_after(name, 2, &v)) return vr_illuminant_blackbody(v, err);
  vr_error_set(err, VR_E_NOT_FOUND,
               "unknown illuminant '%s' (known: A, D50, D55, D65, D75, E, F1-F12, LED-B1-B5, "
               "LED-BH1, LED-RGB1, LED-V1, LED-V2, D<CCT>, BB<T>)",
               name);
  return NULL;
}
