/* Ellipsometry without a model: each (Ψ, Δ) pair inverted as a bulk
 * two-phase sample (pseudo-optical constants), then a dispersion model
 * fitted to all data so that n, k come out smooth and Kramers-Kronig
 * consistent: Cauchy with an Urbach tail for a transparent material, a
 * B-spline ε2 otherwise.  When that smooth model misses the data by more
 * than three times their noise (a Drude metal, whose ε2 diverges below the
 * measured range, cannot be a B-spline ε2 over it), the answer is the exact
 * inversion itself: at each wavelength the mean over its angles, weighted
 * by the propagated variances, tabulated. */
#include "vr/ellipso_fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Least-squares n = A + B/λ² + C/λ⁴ (λ in µm) through the pseudo n. */
static void cauchy_start(const vr_ellipso_data *d, const double *n, double abc[3]) {
  double M[3][3] = {{0}}, v[3] = {0};
  for (size_t i = 0; i < d->n; i++) {
    double l2 = pow(d->p[i].nm / 1000.0, -2.0), f[3] = {1.0, l2, l2 * l2};
    for (int a = 0; a < 3; a++) {
      v[a] += f[a] * n[i];
      for (int b = 0; b < 3; b++) M[a][b] += f[a] * f[b];
    }
  }
  /* Cramer's rule; a degenerate set (one wavelength) falls back to A only. */
  double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
               M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
               M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  if (fabs(det) < 1e-12 * fabs(M[0][0] * M[1][1] * M[2][2]) || !isfinite(det)) {
    abc[0] = v[0] / M[0][0];
    abc[1] = abc[2] = 0.0;
    return;
  }
  for (int c = 0; c < 3; c++) {
    double T[3][3];
    memcpy(T, M, sizeof T);
    for (int r = 0; r < 3; r++) T[r][c] = v[r];
    abc[c] = (T[0][0] * (T[1][1] * T[2][2] - T[1][2] * T[2][1]) -
              T[0][1] * (T[1][0] * T[2][2] - T[1][2] * T[2][0]) +
              T[0][2] * (T[1][0] * T[2][1] - T[1][1] * T[2][0])) / det;
  }
}

static vr_status free_param(vr_sample_model *m, const char *name, double value, double lo, double hi,
                            vr_error *err) {
  long k = vr_model_param_index(m, name);
  if (k < 0) return vr_error_set(err, VR_E_ARG, "no parameter %s", name);
  *vr_model_param_value(m, (size_t)k) = value;
  m->params[k].free = true;
  m->params[k].lower = lo;
  m->params[k].upper = hi;
  return VR_OK;
}

/* The smooth fit is kept when its rms residual is within this many times
 * the data's noise. */
#define BULK_SMOOTH_LIMIT 3.0

static int by_nm(const void *a, const void *b) {
  double x = ((const vr_ellipso_point *)a)->nm, y = ((const vr_ellipso_point *)b)->nm;
  return (x > y) - (x < y);
}

/* Replaces *m and *out by the tabulated exact inversion of d. */
static vr_status exact_inversion(const vr_ellipso_data *d, vr_sample_model **m, vr_fit_result *out,
                                 vr_error *err) {
  double smooth = out->misfit_ratio;
  char why[208];
  snprintf(why, sizeof why, "%.200s", out->verdict);
  vr_ellipso_point *p = malloc(d->n * sizeof *p);
  double *wl = malloc(d->n * sizeof *wl), *nv = malloc(d->n * sizeof *nv),
         *kv = malloc(d->n * sizeof *kv);
  vr_status st = p && wl && nv && kv ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t nw = 0;
  bool one_angle = true; /* one point per wavelength */
  if (!st) {
    memcpy(p, d->p, d->n * sizeof *p);
    qsort(p, d->n, sizeof *p, by_nm);
    for (size_t i = 0; i < d->n;) {
      double sn = 0, sk = 0, wn = 0, wk = 0;
      size_t j = i;
      for (; j < d->n && p[j].nm == p[i].nm; j++) {
        double n, k, en, ek;
        vr_pseudo_index(&p[j], &n, &k, &en, &ek);
        double a = 1.0 / fmax(en * en, 1e-30), b = 1.0 / fmax(ek * ek, 1e-30);
        sn += a * n, wn += a, sk += b * k, wk += b;
      }
      one_angle = one_angle && j == i + 1;
      wl[nw] = p[i].nm, nv[nw] = sn / wn, kv[nw] = fmax(sk / wk, 0.0);
      nw++;
      i = j;
    }
  }
  vr_spectrum *ns = NULL, *ks = NULL;
  vr_dispersion *disp = NULL;
  vr_sample_model *table = NULL;
  vr_fit_result r = {0};
  if (!st && nw < 2)
    st = vr_error_set(err, VR_E_ARG,
                      "the smooth dispersion fit does not describe the data (%s) and one "
                      "wavelength cannot make a table: give a model",
                      out->verdict);
  if (!st && (!(ns = vr_spectrum_create(nw, wl, nv, err)) || !(ks = vr_spectrum_create(nw, wl, kv, err)) ||
              !(disp = vr_dispersion_tabulated(ns, ks, err))))
    st = err ? err->status : VR_E_NOMEM;
  if (!st) {
    table = vr_model_bulk(disp, err); /* takes disp */
    disp = NULL;
    if (!table) st = err ? err->status : VR_E_NOMEM;
  }
  if (!st) st = vr_ellipso_evaluate(table, d, &r, err);
  if (!st) {
    vr_fit_judge(&r, d, VR_FIT_MAX_MISFIT);
    r.exact_inversion = true;
    r.summary.iterations = out->summary.iterations;
    char v[sizeof r.verdict];
    /* One angle per wavelength: the inversion reproduces any data, and
     * nothing in them shows whether the sample is bare. */
    char how[240];
    if (isfinite(smooth)) snprintf(how, sizeof how, "missed by %.3g times the noise", smooth);
    else snprintf(how, sizeof how, "failed: %.200s", why);
    snprintf(v, sizeof v, "exact inversion (the smooth dispersion fit %s); %.120s%s", how, r.verdict,
             one_angle ? "; n, k are those of a bare substrate: with one angle per wavelength the "
                         "data cannot show layers"
                       : "");
    memcpy(r.verdict, v, sizeof v);
    vr_fit_result_free(out);
    *out = r;
    vr_model_destroy(*m);
    *m = table;
    table = NULL;
  }
  vr_model_destroy(table);
  vr_dispersion_destroy(disp);
  vr_spectrum_destroy(ns);
  vr_spectrum_destroy(ks);
  free(p);
  free(wl);
  free(nv);
  free(kv);
  return st;
}

vr_status vr_ellipso_fit_bulk(const vr_ellipso_data *d, const vr_fit_options *opt_in,
                              vr_sample_model **model_out, vr_fit_result *out, vr_error *err) {
  *model_out = NULL;
  memset(out, 0, sizeof *out);
  if (d->n == 0) return vr_error_set(err, VR_E_ARG, "no data points");
  double *n = calloc(d->n, sizeof *n), *k = calloc(d->n, sizeof *k);
  if (!n || !k) {
    free(n);
    free(k);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  double kmax = 0, emin = INFINITY, emax = 0;
  for (size_t i = 0; i < d->n; i++) {
    vr_complex N = vr_eps_to_index(vr_pseudo_epsilon(d->p[i].psi_deg, d->p[i].delta_deg, d->p[i].aoi_deg));
    n[i] = creal(N);
    k[i] = cimag(N);
    kmax = fmax(kmax, k[i]);
    double e = VR_HC_EV_NM / d->p[i].nm;
    emin = fmin(emin, e);
    emax = fmax(emax, e);
  }
  vr_status st = VR_OK;
  vr_dispersion *disp = NULL;
  vr_sample_model *m = NULL;
  vr_fit_options opt = opt_in ? *opt_in : vr_fit_default_options();
  opt.global_search = false;
  if (kmax < 0.05) {
    double abc[3];
    cauchy_start(d, n, abc);
    if (!(disp = vr_dispersion_create(VR_DISP_CAUCHY, err))) {
      st = err ? err->status : VR_E_NOMEM;
      goto done;
    }
    m = vr_model_bulk(disp, err); /* takes disp, also on failure */
    disp = NULL;
    if (!m) {
      st = err ? err->status : VR_E_NOMEM;
      goto done;
    }
    if ((st = free_param(m, "substrate.A", abc[0], 1.0, 5.0, err)) ||
        (st = free_param(m, "substrate.B", abc[1], -1.0, 1.0, err)))
      goto done;
    /* C only with enough distinct wavelengths to see curvature. */
    if (d->n >= 6 && (st = free_param(m, "substrate.C", abc[2], -1.0, 1.0, err))) goto done;
    if (kmax > 0.005) {
      /* Urbach tail anchored at the highest measured energy. */
      if ((st = free_param(m, "substrate.k_amp", kmax, 0.0, 1.0, err)) ||
          (st = free_param(m, "substrate.k_exp", 1.5, 0.0, 50.0, err)))
        goto done;
      *vr_model_param_value(m, (size_t)vr_model_param_index(m, "substrate.band_edge")) = emax;
    }
  } else {
    /* Knots every 0.25 eV across the measured energies (a margin of one knot
     * on each side), ε2 started from the pseudo ε2. */
    double e[64];
    size_t nk = 0;
    double step = 0.25, lo = emin - step, hi = emax + step;
    if ((hi - lo) / step > 60) step = (hi - lo) / 60;
    for (double x = lo; x <= hi + 1e-9 && nk < 64; x += step) e[nk++] = x;
    while (nk < 4) e[nk] = e[nk - 1] + step, nk++;
    if (!(disp = vr_dispersion_create(VR_DISP_BSPLINE, err))) {
      st = err ? err->status : VR_E_NOMEM;
      goto done;
    }
    if ((st = vr_dispersion_set_knots(disp, nk, e, err))) goto done;
    m = vr_model_bulk(disp, err); /* takes disp, also on failure */
    disp = NULL;
    if (!m) {
      st = err ? err->status : VR_E_NOMEM;
      goto done;
    }
    double *p = vr_dispersion_params(m->substrate);
    size_t np = vr_dispersion_nparams(m->substrate);
    p[0] = 1.0;
    for (size_t j = 1; j < np; j++) {
      /* pseudo ε2 = 2 n k at the data point nearest the knot energy */
      double best = INFINITY, val = 0;
      for (size_t i = 0; i < d->n; i++) {
        double dist = fabs(VR_HC_EV_NM / d->p[i].nm - e[j - 1]);
        if (dist < best) {
          best = dist;
          val = 2.0 * n[i] * k[i];
        }
      }
      p[j] = val;
    }
    for (size_t j = 0; j < m->nparams; j++)
      if (m->params[j].owner == VR_OWNER_SUBSTRATE && m->params[j].slot >= 0) m->params[j].free = true;
  }
  st = vr_ellipso_fit(m, d, &opt, out, err);
  if (!st) {
    vr_fit_judge(out, d, BULK_SMOOTH_LIMIT);
    vr_fit_judge_bounds(out);
    if (!out->describes) st = exact_inversion(d, &m, out, err);
  } else if (st != VR_E_NOMEM) {
    /* The smooth model cannot even be evaluated over these data (a
     * negative k, say): the exact inversion answers, and says why. */
    memset(out, 0, sizeof *out);
    out->misfit_ratio = INFINITY;
    snprintf(out->verdict, sizeof out->verdict, "%.200s", err ? err->message : "failed");
    st = exact_inversion(d, &m, out, err);
  }
done:
  vr_dispersion_destroy(disp);
  free(n);
  free(k);
  if (st) vr_model_destroy(m);
  else *model_out = m;
  return st;
}
