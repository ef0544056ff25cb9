/* vr-rgb2spec's checks of the capture against itself: whether each photo
 * agrees with the light the manifest gives it, and whether two lights are
 * the same spectrum under different names. */
#include "rgb2spec.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

bool rg_same_light(const vr_spectrum *a, const vr_spectrum *b) {
  /* Shapes compared on 400-700 nm every 5 nm after scaling each to a mean
   * of 1: 1 % RMS tells a CIE table from a CSV copy of it (rounding to 4
   * digits) yet separates D65 from D50 (7 %) or F2 from F11 (40 %). */
  enum { K = 61 };
  double va[K], vb[K], ma = 0.0, mb = 0.0;
  for (int k = 0; k < K; k++) {
    double nm = 400.0 + 5.0 * k;
    va[k] = vr_spectrum_eval(a, nm, VR_INTERP_LINEAR);
    vb[k] = vr_spectrum_eval(b, nm, VR_INTERP_LINEAR);
    ma += va[k] / K;
    mb += vb[k] / K;
  }
  if (!(ma > 0.0) || !(mb > 0.0)) return false;
  double e2 = 0.0;
  for (int k = 0; k < K; k++) {
    double d = va[k] / ma - vb[k] / mb;
    e2 += d * d / K;
  }
  return sqrt(e2) < 0.01;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

double rg_median(double *v, size_t k) {
  qsort(v, k, sizeof *v, cmp_double);
  return k % 2 ? v[k / 2] : 0.5 * (v[k / 2 - 1] + v[k / 2]);
}

/* Leave one photo out: recover every region from the other photos (the
 * regularised method with the measured noise), render it under the light
 * of the photo left out, and compare with that photo.  With the right
 * lights the prediction misses by what metamerism leaves open (medians of
 * 0.17-0.52 CIEDE2000 on samples/photos); a photo whose light is wrong -
 * two lights swapped, a warm light named D65 - misses every region by far
 * more (33 and 40 on samples/photos with the D65 and A photos' lights and
 * exposures swapped; tests/cli swaps the names only). */
vr_status rg_check_lights(rg_run *run, vr_error *err) {
  size_t L = run->nphotos, n = run->n;
  for (size_t l = 0; l < L; l++) {
    run->loo_de[l] = NAN;
    run->light_suspect[l] = false;
  }
  if (L < 3 || run->nregions < 3) return VR_OK;
  const double *A = vr_recovery_system_matrix(run->sys);
  double *de = malloc(run->nregions * sizeof *de), *r = malloc(n * sizeof *r);
  if (!de || !r) {
    free(de);
    free(r);
    return vr_error_set(err, VR_E_NOMEM, "light check: out of memory");
  }
  vr_status st = VR_OK;
  for (size_t out = 0; out < L && !st; out++) {
    const vr_spectrum *lights[RGB2SPEC_MAX_LIGHTS];
    double scale[RGB2SPEC_MAX_LIGHTS];
    size_t k = 0;
    for (size_t l = 0; l < L; l++)
      if (l != out) lights[k] = run->photo[l]->light, scale[k++] = run->photo[l]->scale;
    vr_recovery_system *s = vr_recovery_system_create(run->cam, L - 1, lights, scale, NULL, err);
    if (!s) {
      st = err ? err->status : VR_E_NOMEM;
      break;
    }
    size_t count = 0;
    for (size_t i = 0; i < run->nregions && !st; i++) {
      const rg_region *g = &run->regions[i];
      double c[3 * RGB2SPEC_MAX_LIGHTS], sig[3 * RGB2SPEC_MAX_LIGHTS];
      unsigned char clip[3 * RGB2SPEC_MAX_LIGHTS];
      bool out_clipped = false;
      size_t row = 0;
      for (size_t l = 0; l < L; l++)
        for (int ch = 0; ch < 3; ch++) {
          size_t from = 3 * l + (size_t)ch;
          if (l == out) {
            out_clipped |= g->clipped[from] != VR_CLIP_NONE;
            continue;
          }
          c[row] = g->c[from];
          sig[row] = g->sigma[from];
          clip[row++] = g->clipped[from];
        }
      if (out_clipped) continue;
      vr_recover_info info;
      st = vr_recover_noisy(s, VR_RECOVER_REGULARISED, c, sig, clip, r, &info, err);
      if (st) break;
      double pred[3];
      for (int ch = 0; ch < 3; ch++) {
        double v = 0.0;
        for (size_t j = 0; j < n; j++) v += A[(3 * out + (size_t)ch) * n + j] * r[j];
        pred[ch] = v;
      }
      de[count++] = rg_delta_e(run, out, &g->c[3 * out], pred);
    }
    vr_recovery_system_destroy(s);
    if (st || count < 3) continue;
    run->loo_de[out] = rg_median(de, count);
    run->light_suspect[out] = run->loo_de[out] > RG_LOO_LIMIT;
  }
  free(de);
  free(r);
  return st;
}
