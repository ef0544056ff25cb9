/* Panes at angles, panes combined, and their standard figures; the method
 * is described in vr/glazing.h. */
#include "vr/glazing.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "glazing_internal.h"
#include "vr/colour.h"
#include "vr/cri.h"
#include "vr/optics.h"
#include "vr/slab_invert.h"

void vr_pane_destroy(vr_pane *p) {
  if (!p) return;
  free(p->nm);
  for (int i = 0; i < 2; i++) {
    free(p->T[i]);
    free(p->Rf[i]);
    free(p->Rb[i]);
  }
  free(p);
}

static vr_pane *pane_alloc(size_t n, vr_error *err) {
  vr_pane *p = calloc(1, sizeof *p);
  if (!p) goto oom;
  p->n = n;
  p->nm = malloc(n * sizeof *p->nm);
  bool ok = p->nm != NULL;
  for (int i = 0; i < 2; i++) {
    p->T[i] = malloc(n * sizeof(double));
    p->Rf[i] = malloc(n * sizeof(double));
    p->Rb[i] = malloc(n * sizeof(double));
    ok = ok && p->T[i] && p->Rf[i] && p->Rb[i];
  }
  if (ok) return p;
oom:
  vr_pane_destroy(p);
  vr_error_set(err, VR_E_NOMEM, "out of memory");
  return NULL;
}

/* n (or NAN) solved from T and R at each wavelength. */
static void solve_side(const vr_spectro_curve *c, bool back, double d_nm, double *n, double *k) {
  for (size_t i = 0; i < c->n; i++) {
    double R = back && !isnan(c->p[i].Rb) ? c->p[i].Rb : c->p[i].Rf;
    vr_slab_nk nk;
    n[i] = k[i] = NAN;
    if (vr_slab_invert_normal(c->p[i].T, R, d_nm, c->p[i].nm, &nk, NULL) == VR_OK &&
        !(nk.flags & (VR_SLAB_NO_ROOT | VR_SLAB_NO_INDEX))) {
      n[i] = nk.n;
      k[i] = nk.k;
    }
  }
}

/* Wavelengths without a root borrow n from the nearest solved one and get
 * the k that makes the slab transmit the measured T (opaque when T = 0). */
static size_t fill_unsolved(const vr_spectro_curve *c, double d_nm, double *n, double *k) {
  size_t missing = 0;
  for (size_t i = 0; i < c->n; i++) {
    if (!isnan(n[i])) continue;
    missing++;
    for (size_t off = 1; off < c->n; off++) {
      if (i >= off && !isnan(n[i - off]) && isfinite(k[i - off])) {
        n[i] = n[i - off];
        break;
      }
      if (i + off < c->n && !isnan(n[i + off]) && isfinite(k[i + off])) {
        n[i] = n[i + off];
        break;
      }
    }
    if (isnan(n[i])) continue;
    double r = (n[i] - 1) * (n[i] - 1) / ((n[i] + 1) * (n[i] + 1));
    double a = c->p[i].T / ((1 - r) * (1 - r));
    a = fmin(fmax(a, 1e-30), 1.0);
    k[i] = -c->p[i].nm * log(a) / (4 * M_PI * d_nm);
  }
  return missing;
}

/* Windows-CalcEngine CCoatingCoefficients: C0..C4 of P(cos theta). */
static const double COATED_T[2][5] = {{-0.0015, 3.355, -3.84, 1.46, 0.0288},
                                      {-0.002, 2.813, -2.341, -0.05725, 0.599}};
static const double COATED_R[2][5] = {{0.999, -0.563, 2.043, -2.532, 1.054},
                                      {0.997, -1.868, 6.513, -7.862, 3.225}};

static double poly4(const double *c, double x) {
  return c[0] + x * (c[1] + x * (c[2] + x * (c[3] + x * c[4])));
}

void vr_coated_angular(double T0, double R0, double angle_deg, double solar_T0, double *T,
                       double *R) {
  int set = solar_T0 > 0.645 ? 0 : 1; /* clear : bronze */
  double c = cos(angle_deg * M_PI / 180.0);
  if (angle_deg >= 90) c = 0;
  double tau = poly4(COATED_T[set], c), rho = poly4(COATED_R[set], c) - tau;
  *T = fmin(fmax(tau * T0, 0.0), 1.0);
  *R = fmin(fmax(R0 * (1 - rho) + rho, 0.0), 1.0);
}

vr_status vr_pane_from_curve(const vr_spectro_curve *c, double thickness_nm, double angle_deg,
                             vr_angular_route route, double solar_T0, vr_pane **out,
                             size_t *unsolved, vr_error *err) {
  *out = NULL;
  if (unsolved) *unsolved = 0;
  if (!(angle_deg >= 0 && angle_deg <= 90))
    return vr_error_set(err, VR_E_ARG, "angle of incidence %g deg outside [0, 90]", angle_deg);
  if (c->n == 0) return vr_error_set(err, VR_E_ARG, "empty spectrum");
  bool has_R = !isnan(c->p[0].Rf);
  if (!has_R && angle_deg > 0)
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "the pane's reflectance R was not measured: reaching %g deg needs it "
                        "(both angular routes start from T and R at normal incidence)", angle_deg);
  vr_pane *p = pane_alloc(c->n, err);
  if (!p) return VR_E_NOMEM;
  p->has_R = has_R;
  for (size_t i = 0; i < c->n; i++) {
    p->nm[i] = c->p[i].nm;
    double Rb = isnan(c->p[i].Rb) ? c->p[i].Rf : c->p[i].Rb;
    if (has_R && fabs(Rb - c->p[i].Rf) > VR_COATED_ASYMMETRY && p->nm[i] >= 380 && p->nm[i] <= 780)
      p->coated = true;
    for (int s = 0; s < 2; s++) {
      p->T[s][i] = c->p[i].T;
      p->Rf[s][i] = c->p[i].Rf;
      p->Rb[s][i] = Rb;
    }
  }
  if (angle_deg == 0) {
    *out = p;
    return VR_OK;
  }
  if (route == VR_ROUTE_AUTO) route = p->coated ? VR_ROUTE_COATED : VR_ROUTE_PHYSICAL;
  p->route = route;
  if (route == VR_ROUTE_COATED) {
    if (!(solar_T0 >= 0 && solar_T0 <= 1)) {
      vr_pane_destroy(p);
      return vr_error_set(err, VR_E_ARG, "the coated route needs the pane's normal solar "
                                         "transmittance in [0, 1] (got %g)", solar_T0);
    }
    for (size_t i = 0; i < c->n; i++)
      for (int s = 0; s < 2; s++) {
        double t, r;
        vr_coated_angular(c->p[i].T, p->Rf[s][i], angle_deg, solar_T0, &t, &r);
        p->T[s][i] = t;
        p->Rf[s][i] = r;
        vr_coated_angular(c->p[i].T, p->Rb[s][i], angle_deg, solar_T0, &t, &r);
        p->Rb[s][i] = r;
      }
    *out = p;
    return VR_OK;
  }
  if (!(thickness_nm > 0)) {
    vr_pane_destroy(p);
    return vr_error_set(err, VR_E_ARG,
                        "%g deg needs the pane's thickness (the physical route back-solves n and "
                        "k from T, R and d); give --thickness", angle_deg);
  }
  double *n = malloc(c->n * sizeof *n), *k = malloc(c->n * sizeof *k);
  vr_status st = n && k ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  const double theta = angle_deg * M_PI / 180.0;
  for (int side = 0; side < 2 && !st; side++) {
    solve_side(c, side == 1, thickness_nm, n, k);
    size_t miss = fill_unsolved(c, thickness_nm, n, k);
    if (unsolved && miss > *unsolved) *unsolved = miss;
    for (size_t i = 0; i < c->n && !st; i++) {
      if (isnan(n[i])) {
        st = vr_error_set(err, VR_E_NUMERIC,
                          "no wavelength of the spectrum gives an index: the data fit no "
                          "uncoated pane of %g mm", thickness_nm * 1e-6);
        break;
      }
      vr_slab_result s;
      st = vr_slab(1.0, n[i] + I * k[i], thickness_nm, theta, c->p[i].nm, &s, err);
      for (int pol = 0; pol < 2 && !st; pol++) {
        if (side == 0) {
          p->T[pol][i] = s.T[pol];
          p->Rf[pol][i] = s.R[pol];
        } else {
          p->Rb[pol][i] = s.R[pol];
        }
      }
    }
  }
  free(n);
  free(k);
  if (st) {
    vr_pane_destroy(p);
    return st;
  }
  *out = p;
  return VR_OK;
}

double vr_glazing_lerp(const double *x, const double *y, size_t n, double at) {
  if (at <= x[0]) return y[0];
  if (at >= x[n - 1]) return y[n - 1];
  size_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    size_t mid = (lo + hi) / 2;
    if (x[mid] <= at) lo = mid;
    else hi = mid;
  }
  double t = (at - x[lo]) / (x[hi] - x[lo]);
  return y[lo] + t * (y[hi] - y[lo]);
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

vr_status vr_glazing_common_grid(vr_pane *const *panes, size_t count, double **grid, size_t *n,
                             vr_error *err) {
  double lo = -INFINITY, hi = INFINITY;
  size_t total = 0;
  for (size_t j = 0; j < count; j++) {
    lo = fmax(lo, panes[j]->nm[0]);
    hi = fmin(hi, panes[j]->nm[panes[j]->n - 1]);
    total += panes[j]->n;
  }
  *grid = NULL, *n = 0;
  if (!(hi > lo)) return VR_OK;
  double *g = malloc(total * sizeof *g);
  if (!g) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t k = 0;
  for (size_t j = 0; j < count; j++)
    for (size_t i = 0; i < panes[j]->n; i++)
      if (panes[j]->nm[i] >= lo - 1e-9 && panes[j]->nm[i] <= hi + 1e-9) g[k++] = panes[j]->nm[i];
  qsort(g, k, sizeof *g, cmp_double);
  size_t m = 0;
  for (size_t i = 0; i < k; i++)
    if (m == 0 || g[i] > g[m - 1] + 1e-9) g[m++] = g[i];
  *grid = g, *n = m;
  return VR_OK;
}

vr_status vr_pane_combine(vr_pane *const *panes, size_t count, vr_pane **out, vr_error *err) {
  *out = NULL;
  if (count == 0) return vr_error_set(err, VR_E_ARG, "no panes");
  for (size_t j = 0; j < count && count > 1; j++)
    if (!panes[j]->has_R)
      return vr_error_set(err, VR_E_NOT_FOUND,
                          "pane %zu has no reflectance: panes combine through their "
                          "inter-reflections, which need Rf and Rb", j + 1);
  size_t n = 0;
  double *grid = NULL;
  vr_status st = vr_glazing_common_grid(panes, count, &grid, &n, err);
  if (st) return st;
  if (n < 2) {
    free(grid);
    char spans[512];
    size_t k = 0;
    for (size_t j = 0; j < count && k < sizeof spans; j++)
      k += (size_t)snprintf(spans + k, sizeof spans - k, "%spane %zu %g-%g nm", j ? ", " : "",
                            j + 1, panes[j]->nm[0], panes[j]->nm[panes[j]->n - 1]);
    return vr_error_set(err, VR_E_RANGE, "the panes share no wavelength range (%s)", spans);
  }
  vr_pane *s = pane_alloc(n, err);
  if (!s) {
    free(grid);
    return VR_E_NOMEM;
  }
  memcpy(s->nm, grid, n * sizeof *s->nm);
  free(grid);
  const vr_pane *first = panes[0];
  for (int pol = 0; pol < 2; pol++)
    for (size_t i = 0; i < n; i++) {
      s->T[pol][i] = vr_glazing_lerp(first->nm, first->T[pol], first->n, s->nm[i]);
      s->Rf[pol][i] = vr_glazing_lerp(first->nm, first->Rf[pol], first->n, s->nm[i]);
      s->Rb[pol][i] = vr_glazing_lerp(first->nm, first->Rb[pol], first->n, s->nm[i]);
    }
  s->coated = first->coated;
  s->has_R = first->has_R;
  for (size_t j = 1; j < count; j++) {
    const vr_pane *q = panes[j];
    s->coated = s->coated || q->coated;
    for (int pol = 0; pol < 2; pol++)
      for (size_t i = 0; i < s->n; i++) {
        double T2 = vr_glazing_lerp(q->nm, q->T[pol], q->n, s->nm[i]);
        double Rf2 = vr_glazing_lerp(q->nm, q->Rf[pol], q->n, s->nm[i]);
        double Rb2 = vr_glazing_lerp(q->nm, q->Rb[pol], q->n, s->nm[i]);
        double T1 = s->T[pol][i], Rf1 = s->Rf[pol][i], Rb1 = s->Rb[pol][i];
        double den = 1.0 - Rb1 * Rf2; /* > 0 unless both faces are perfect mirrors */
        if (!(den > 0)) den = 1e-300;
        s->T[pol][i] = T1 * T2 / den;
        s->Rf[pol][i] = Rf1 + T1 * T1 * Rf2 / den;
        s->Rb[pol][i] = Rb2 + T2 * T2 * Rb1 / den;
      }
  }
  *out = s;
  return VR_OK;
}

/* Unpolarised spectrum of one quantity. */
static vr_spectrum *unpolarised(const vr_pane *p, double *const q[2], vr_error *err) {
  double *v = malloc(p->n * sizeof *v);
  if (!v) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  for (size_t i = 0; i < p->n; i++) v[i] = 0.5 * (q[0][i] + q[1][i]);
  vr_spectrum *s = vr_spectrum_create(p->n, p->nm, v, err);
  free(v);
  return s;
}

static vr_status average(const vr_standard *std, const char *method, const vr_spectrum *s,
                         double *out, bool required, vr_error *err) {
  const vr_std_method *m = vr_standard_method(std, method);
  *out = NAN;
  if (!m)
    return required ? vr_error_set(err, VR_E_NOT_FOUND, "standard %s has no %s method", std->name,
                                   method)
                    : VR_OK;
  return vr_std_average(m, s, out, err);
}

/* X, Y, Z of a spectrum under the COLOR_TRISTIM methods, scaled so that the
 * perfect transmitter has Y = 1; white receives that transmitter's XYZ. */
static vr_status tristimulus(const vr_standard *std, const vr_spectrum *s, double xyz[3],
                             double white[3], bool *ok, vr_error *err) {
  /* LBNL's names: COLOR_TRISTIM* (NFRC files), CRI_* (EN 410 files). */
  static const char *const NAMES[2][3] = {{"COLOR_TRISTIMX", "COLOR_TRISTIMY", "COLOR_TRISTIMZ"},
                                          {"CRI_X", "CRI_Y", "CRI_Z"}};
  const vr_std_method *m[3];
  *ok = false;
  int set = vr_standard_method(std, NAMES[0][0]) ? 0 : 1;
  for (int i = 0; i < 3; i++)
    if (!(m[i] = vr_standard_method(std, NAMES[set][i]))) return VR_OK;
  /* num = sum data S cmf and den = sum S cmf: the white is den itself, and
   * everything is normalised by den_Y (the "k" of the colour methods). */
  double num[3], den[3];
  for (int i = 0; i < 3; i++) {
    vr_status st = vr_std_sums(m[i], s, &num[i], &den[i], err);
    if (st) return st;
  }
  for (int i = 0; i < 3; i++) {
    xyz[i] = num[i] / den[1];
    white[i] = den[i] / den[1];
  }
  *ok = true;
  return VR_OK;
}

/* EN 410 (4.9): D65 through the glazing, rendered against D65 (CIE 13.3 on
 * its 5 nm grid, 380-780 nm).  Left NAN where the transmittance does not
 * cover that range or is dark there (an opaque pane has no rendering). */
static vr_status colour_rendering(const vr_spectrum *T, vr_glazing_metrics *out, vr_error *err) {
  out->Ra = NAN;
  for (int i = 0; i < 8; i++) out->R_i[i] = NAN;
  if (!vr_spectrum_covers(T, 380.0, 780.0)) return VR_OK;
  vr_spectrum *d65 = vr_illuminant("D65", err);
  vr_spectrum *lit = d65 ? vr_spectrum_create_uniform(380.0, 5.0, 81, 0.0, err) : NULL;
  if (!lit) {
    vr_spectrum_destroy(d65);
    return err ? err->status : VR_E_NOMEM;
  }
  for (size_t i = 0; i < lit->n; i++)
    lit->value[i] = vr_spectrum_eval(d65, lit->nm[i], VR_INTERP_LINEAR) *
                    vr_spectrum_eval(T, lit->nm[i], VR_INTERP_LINEAR);
  vr_cri c;
  if (!vr_cri_against(lit, d65, &c, NULL)) {
    out->Ra = c.Ra;
    for (int i = 0; i < 8; i++) out->R_i[i] = c.R[i];
  }
  vr_spectrum_destroy(lit);
  vr_spectrum_destroy(d65);
  return VR_OK;
}

vr_status vr_glazing_metrics_compute(const vr_standard *std, const vr_pane *pane,
                                     vr_glazing_metrics *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  out->has_R = pane->has_R;
  out->Rvis_front = out->Rvis_back = out->Rsol_front = out->Rsol_back = NAN;
  for (int i = 0; i < 3; i++) out->Rf_lab[i] = out->Rb_lab[i] = NAN;
  vr_spectrum *T = unpolarised(pane, pane->T, err);
  vr_spectrum *Rf = T && pane->has_R ? unpolarised(pane, pane->Rf, err) : NULL;
  vr_spectrum *Rb = Rf ? unpolarised(pane, pane->Rb, err) : NULL;
  vr_status st = T && (Rb || !pane->has_R) ? VR_OK : (err ? err->status : VR_E_NOMEM);
  if (!st) st = average(std, "PHOTOPIC", T, &out->Tvis, true, err);
  if (!st && Rf) st = average(std, "PHOTOPIC", Rf, &out->Rvis_front, true, err);
  if (!st && Rb) st = average(std, "PHOTOPIC", Rb, &out->Rvis_back, true, err);
  if (!st) st = average(std, "SOLAR", T, &out->Tsol, true, err);
  if (!st && Rf) st = average(std, "SOLAR", Rf, &out->Rsol_front, true, err);
  if (!st && Rb) st = average(std, "SOLAR", Rb, &out->Rsol_back, true, err);
  if (!st) st = average(std, "TUV", T, &out->Tuv, false, err);
  if (!st) st = colour_rendering(T, out, err);
  double white[3], xyz[3];
  bool ok = false;
  if (!st) st = tristimulus(std, T, out->T_xyz, white, &ok, err);
  if (!st && ok) {
    vr_xyz_to_lab(out->T_xyz, white, out->T_lab);
    if (Rf) st = tristimulus(std, Rf, xyz, white, &ok, err);
    if (!st && Rf) vr_xyz_to_lab(xyz, white, out->Rf_lab);
    if (!st && Rb) st = tristimulus(std, Rb, xyz, white, &ok, err);
    if (!st && Rb) vr_xyz_to_lab(xyz, white, out->Rb_lab);
    out->has_colour = !st;
  }
  vr_spectrum_destroy(T);
  vr_spectrum_destroy(Rf);
  vr_spectrum_destroy(Rb);
  return st;
}
