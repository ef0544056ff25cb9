/* Shared by the calibration tests: a real camera (the Nikon D5100 of
 * Darrodi et al. 2015, tests/data/camera_nikon_d5100_darrodi2015.csv),
 * photographing the ColorChecker (BabelColor averages) under a light,
 * rendered at 1 nm over 360-830 nm exactly as CIE 015 sums run, then
 * exposed, given noise on the linear values, encoded and quantised. */
#ifndef CALIB_TEST_UTIL_H
#define CALIB_TEST_UTIL_H

#include "vr_test.h"
#include "vr/calibrate.h"
#include "vr/colorchecker.h"
#include "vr/colour.h"

#define CT_PATCHES VR_COLORCHECKER_PATCHES

/* Loads the three curves r, g, b of a camera CSV. */
static inline void ct_load_camera(const char *path, vr_spectrum *sens[3]) {
  vr_error err = {0};
  vr_spectrum_table t = {0};
  if (vr_spectrum_table_read(path, &t, &err) != VR_OK) fail_msg("%s", err.message);
  static const char *const roles[3] = {"r", "g", "b"};
  for (int c = 0; c < 3; c++) {
    const vr_spectrum *s = vr_spectrum_table_get(&t, roles[c]);
    if (!s) fail_msg("%s has no column %s", path, roles[c]);
    sens[c] = vr_spectrum_copy(s, &err);
  }
  vr_spectrum_table_free(&t);
}

/* A sensitivity at nm: linear between samples, zero outside the table. */
static inline double ct_sens(const vr_spectrum *s, double nm) {
  if (nm < s->nm[0] || nm > s->nm[s->n - 1]) return 0.0;
  return vr_spectrum_eval(s, nm, VR_INTERP_LINEAR);
}

/* Linear responses of a reflectance (NULL: a perfect white), normalised
 * so that a perfect white gives green 1 (the measured-camera convention of
 * vr/camera.h). */
static inline void ct_render(const vr_spectrum *const sens[3], const vr_spectrum *light,
                             const vr_spectrum *refl, double out[3]) {
  double sum[3] = {0, 0, 0}, white = 0.0;
  for (int i = 0; i <= 470; i++) {
    double nm = 360.0 + i, S = vr_spectrum_eval(light, nm, VR_INTERP_LINEAR);
    double r = refl ? vr_spectrum_eval(refl, nm, VR_INTERP_LINEAR) : 1.0;
    for (int c = 0; c < 3; c++) sum[c] += S * ct_sens(sens[c], nm) * r;
    white += S * ct_sens(sens[1], nm);
  }
  for (int c = 0; c < 3; c++) out[c] = sum[c] / white;
}

/* A deterministic normal deviate (xorshift64 and Box-Muller). */
static inline double ct_gauss(unsigned long long *state) {
  double u[2];
  for (int k = 0; k < 2; k++) {
    unsigned long long x = *state;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    *state = x;
    u[k] = ((double)(x >> 11) + 0.5) / 9007199254740992.0;
  }
  return sqrt(-2.0 * log(u[0])) * cos(6.283185307179586 * u[1]);
}

typedef struct ct_capture {
  vr_tone tone;
  double gamma;
  double exposure_max; /* the brightest linear patch value after exposure */
  double sigma;        /* Gaussian noise on linear values */
  int bits;            /* 8: quantised to 8-bit codes; 0: not quantised */
  unsigned long long seed;
  int pixels;          /* each patch the mean of this many pixels (0 or 1: one) */
} ct_capture;

/* The 24 encoded patch values of the chart under light; lin receives the
 * exposed linear values before noise (may be NULL). */
static inline void ct_photograph(const vr_spectrum *const sens[3], const vr_spectrum *light,
                                 const ct_capture *cap, double rgb[][3], double lin[][3]) {
  vr_error err = {0};
  double y[CT_PATCHES][3], top = 0.0;
  for (size_t p = 0; p < CT_PATCHES; p++) {
    vr_spectrum *r = vr_colorchecker_patch(p, &err);
    ct_render(sens, light, r, y[p]);
    vr_spectrum_destroy(r);
    for (int c = 0; c < 3; c++) top = fmax(top, y[p][c]);
  }
  unsigned long long state = cap->seed ? cap->seed : 88172645463325252ull;
  double k = cap->exposure_max / top;
  int np = cap->pixels > 1 ? cap->pixels : 1;
  for (size_t p = 0; p < CT_PATCHES; p++)
    for (int c = 0; c < 3; c++) {
      double sum = 0.0;
      if (lin) lin[p][c] = k * y[p][c];
      for (int i = 0; i < np; i++) {
        double v = k * y[p][c];
        if (cap->sigma > 0) v += cap->sigma * ct_gauss(&state);
        v = fmin(fmax(v, 0.0), 1.0);
        v = vr_tone_encode(cap->tone, cap->gamma, v);
        if (cap->bits == 8) v = round(v * 255.0) / 255.0;
        sum += v;
      }
      rgb[p][c] = sum / np;
    }
}

/* Wavelength of the largest value of a curve on its samples. */
static inline double ct_peak_nm(size_t n, const double *nm, const double *v) {
  size_t at = 0;
  for (size_t j = 1; j < n; j++)
    if (v[j] > v[at]) at = j;
  return nm[at];
}

#endif
