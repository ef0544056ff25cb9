/* Figures of each layer of a system of panes: the share of incident solar
 * power each pane absorbs, and a pane's thermal-infrared emissivity; the
 * methods are described in vr/glazing_layers.h. */
#include "vr/glazing_layers.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "glazing_internal.h"

/* Spectral absorptance of each layer at one wavelength, light arriving on
 * the front of layer 0.  t, f, b: the layers' T, Rf, Rb; A: out.  The
 * suffix systems (layers j..n-1) are built backwards, the prefix systems
 * (0..j) forwards, and the fluxes in each gap follow from the geometric
 * series of the reflections between the two. */
static void absorb_one(size_t n, const double *t, const double *f, const double *b, double *A,
                       double *sT, double *sRf) {
  /* sT[j], sRf[j]: the suffix system of layers j..n-1; sRf[n] = 0. */
  sT[n] = 1.0, sRf[n] = 0.0;
  for (size_t j = n; j-- > 0;) {
    double den = 1.0 - b[j] * sRf[j + 1];
    if (!(den > 0)) den = 1e-300; /* two perfect mirrors facing: no light passes anyway */
    sT[j] = t[j] * sT[j + 1] / den;
    sRf[j] = f[j] + t[j] * t[j] * sRf[j + 1] / den;
  }
  double pT = 1.0, pRb = 0.0; /* the prefix system of layers 0..j-1 */
  for (size_t j = 0; j < n; j++) {
    double den = 1.0 - pRb * sRf[j];
    if (!(den > 0)) den = 1e-300;
    double in_front = pT / den; /* forward flux in the gap before layer j */
    /* Prefix 0..j, then the forward and backward flux in the gap after j. */
    double d1 = 1.0 - pRb * f[j];
    if (!(d1 > 0)) d1 = 1e-300;
    double qT = pT * t[j] / d1;
    double qRb = b[j] + t[j] * t[j] * pRb / d1;
    double d2 = 1.0 - qRb * sRf[j + 1];
    if (!(d2 > 0)) d2 = 1e-300;
    double in_back = qT / d2 * sRf[j + 1];
    A[j] = in_front * (1.0 - t[j] - f[j]) + in_back * (1.0 - t[j] - b[j]);
    pT = qT, pRb = qRb;
  }
}

vr_status vr_glazing_layer_absorptance(const vr_standard *std, const char *method,
                                       vr_pane *const *panes, size_t count, bool from_back,
                                       double *A, vr_error *err) {
  if (count == 0) return vr_error_set(err, VR_E_ARG, "no panes");
  const vr_std_method *m = vr_standard_method(std, method);
  if (!m) return vr_error_set(err, VR_E_NOT_FOUND, "standard %s has no %s method", std->name, method);
  for (size_t j = 0; j < count; j++)
    if (!panes[j]->has_R)
      return vr_error_set(err, VR_E_NOT_FOUND,
                          "pane %zu has no reflectance: its absorptance is 1 - T - R", j + 1);
  double *grid = NULL;
  size_t n = 0;
  vr_status st = vr_glazing_common_grid(panes, count, &grid, &n, err);
  if (st) return st;
  if (n < 2) {
    free(grid);
    return vr_error_set(err, VR_E_RANGE, "the panes share no wavelength range");
  }
  /* Work arrays: per layer t, f, b, A, then the suffix (count + 1 each),
   * and the spectral absorptance of every layer on the grid. */
  double *w = malloc((4 * count + 2 * (count + 1) + count * n) * sizeof *w);
  if (!w) {
    free(grid);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  double *t = w, *f = t + count, *b = f + count, *a = b + count, *sT = a + count;
  double *sRf = sT + count + 1, *spec = sRf + count + 1;
  for (size_t i = 0; i < n; i++) {
    for (size_t j = 0; j < count; j++) spec[j * n + i] = 0.0;
    for (int pol = 0; pol < 2; pol++) {
      for (size_t j = 0; j < count; j++) {
        /* From the back the system is seen in reverse, each pane turned. */
        const vr_pane *p = panes[from_back ? count - 1 - j : j];
        t[j] = vr_glazing_lerp(p->nm, p->T[pol], p->n, grid[i]);
        double rf = vr_glazing_lerp(p->nm, p->Rf[pol], p->n, grid[i]);
        double rb = vr_glazing_lerp(p->nm, p->Rb[pol], p->n, grid[i]);
        f[j] = from_back ? rb : rf;
        b[j] = from_back ? rf : rb;
      }
      absorb_one(count, t, f, b, a, sT, sRf);
      for (size_t j = 0; j < count; j++) {
        size_t layer = from_back ? count - 1 - j : j;
        spec[layer * n + i] += 0.5 * a[j]; /* unpolarised: the mean of s and p */
      }
    }
  }
  for (size_t j = 0; j < count && !st; j++) {
    vr_spectrum *s = vr_spectrum_create(n, grid, spec + j * n, err);
    st = s ? vr_std_average(m, s, &A[j], err) : (err ? err->status : VR_E_NOMEM);
    vr_spectrum_destroy(s);
  }
  free(w);
  free(grid);
  return st;
}

double vr_emissivity_hemispherical(double normal, bool coated) {
  /* NFRC 301 (as Windows-CalcEngine applies it, SingleLayerOptics/src/
   * ScatteringLayer.cpp): eps_h = sum_i c_i eps_n^(i+1). */
  static const double COATED[5] = {1.3217, -1.8766, 4.6586, -5.8349, 2.7406};
  static const double UNCOATED[4] = {0.1569, 3.7669, -5.4398, 2.4733};
  const double *c = coated ? COATED : UNCOATED;
  size_t k = coated ? 5 : 4;
  double e = 0.0, pw = normal;
  for (size_t i = 0; i < k; i++, pw *= normal) e += c[i] * pw;
  return e;
}

vr_status vr_pane_emissivity(const vr_standard *std, const vr_pane *pane, double normal[2],
                             double *tir, vr_error *err) {
  const vr_std_method *m = vr_standard_method(std, "THERMAL IR");
  if (!m)
    return vr_error_set(err, VR_E_NOT_FOUND, "standard %s has no THERMAL IR method", std->name);
  if (!pane->has_R)
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "the pane has no reflectance: its emissivity is 1 - T - R");
  double *v = malloc(pane->n * sizeof *v);
  if (!v) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_status st = VR_OK;
  for (int side = 0; side < 2 && !st; side++) {
    double *const *R = side ? pane->Rb : pane->Rf;
    for (size_t i = 0; i < pane->n; i++)
      v[i] = 1.0 - 0.5 * (pane->T[0][i] + pane->T[1][i]) - 0.5 * (R[0][i] + R[1][i]);
    vr_spectrum *s = vr_spectrum_create(pane->n, pane->nm, v, err);
    st = s ? vr_std_average(m, s, &normal[side], err) : (err ? err->status : VR_E_NOMEM);
    vr_spectrum_destroy(s);
  }
  if (!st && tir) {
    for (size_t i = 0; i < pane->n; i++) v[i] = 0.5 * (pane->T[0][i] + pane->T[1][i]);
    vr_spectrum *s = vr_spectrum_create(pane->n, pane->nm, v, err);
    st = s ? vr_std_average(m, s, tir, err) : (err ? err->status : VR_E_NOMEM);
    vr_spectrum_destroy(s);
  }
  free(v);
  return st;
}
