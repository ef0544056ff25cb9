/* Whether a fit describes its data: the data's own noise, the misfit in
 * units of it, and the exact bulk inversion with propagated uncertainties
 * (vr/ellipso_fit.h). */
#include "vr/ellipso_fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* Σ of squared third differences of one quantity over the sweeps of the
 * file: runs of points at one angle whose wavelength keeps rising (or keeps
 * falling); *count the terms. */
static void third_differences(const vr_ellipso_data *d, bool delta, double *sum, size_t *count) {
  size_t start = 0;
  while (start < d->n) {
    size_t end = start + 1;
    double dir = end < d->n ? d->p[end].nm - d->p[start].nm : 0;
    while (end < d->n && fabs(d->p[end].aoi_deg - d->p[start].aoi_deg) < 0.01 && dir != 0 &&
           (d->p[end].nm - d->p[end - 1].nm) * dir > 0)
      end++;
    if (end - start >= 8)
      for (size_t i = start; i + 3 < end; i++) {
        double v[4];
        for (int j = 0; j < 4; j++) v[j] = delta ? d->p[i + j].delta_deg : d->p[i + j].psi_deg;
        /* Δ is compared as differences wrapped into (-180, 180]. */
        double d1 = vr_delta_difference(v[1] - v[0]), d2 = vr_delta_difference(v[2] - v[1]), d3 = vr_delta_difference(v[3] - v[2]);
        double t = d3 - 2 * d2 + d1;
        *sum += t * t;
        (*count)++;
      }
    start = end;
  }
}

void vr_ellipso_noise(const vr_ellipso_data *d, double *psi_deg, double *delta_deg) {
  double out[2];
  for (int q = 0; q < 2; q++) {
    double sum = 0;
    size_t count = 0;
    third_differences(d, q == 1, &sum, &count);
    if (count >= 4) {
      out[q] = sqrt(sum / (double)count / 20.0);
    } else if (d->has_sigma && d->n) {
      double *s = malloc(d->n * sizeof *s);
      if (!s) {
        out[q] = 0.05;
        continue;
      }
      for (size_t i = 0; i < d->n; i++) s[i] = q ? d->p[i].sigma_delta : d->p[i].sigma_psi;
      qsort(s, d->n, sizeof *s, cmp_double);
      out[q] = s[d->n / 2];
      free(s);
    } else {
      out[q] = 0.05;
    }
    out[q] = fmax(out[q], 0.001);
  }
  *psi_deg = out[0];
  *delta_deg = out[1];
}

void vr_fit_judge(vr_fit_result *r, const vr_ellipso_data *d, double limit) {
  vr_ellipso_noise(d, &r->noise_psi, &r->noise_delta);
  double s = 0;
  for (size_t i = 0; i < d->n; i++) {
    double a = (r->psi_model[i] - d->p[i].psi_deg) / r->noise_psi;
    double b = vr_delta_difference(r->delta_model[i] - d->p[i].delta_deg) / r->noise_delta;
    s += a * a + b * b;
  }
  r->misfit_ratio = d->n ? sqrt(s / (2.0 * (double)d->n)) : 0;
  r->describes = r->misfit_ratio <= limit;
  snprintf(r->verdict, sizeof r->verdict,
           "%s: rms residual %.3g times the noise the data show (Psi %.3g deg, Delta %.3g deg; "
           "limit %.3g)",
           r->describes ? "describes the data" : "does NOT describe the data", r->misfit_ratio,
           r->noise_psi, r->noise_delta, limit);
}

vr_status vr_ellipso_evaluate(const vr_sample_model *m, const vr_ellipso_data *d, vr_fit_result *out,
                              vr_error *err) {
  memset(out, 0, sizeof *out);
  out->npoints = d->n;
  out->dof = (int)(2 * d->n);
  out->covariance_ok = true;
  out->psi_model = calloc(d->n ? d->n : 1, sizeof(double));
  out->delta_model = calloc(d->n ? d->n : 1, sizeof(double));
  if (!out->psi_model || !out->delta_model) {
    vr_fit_result_free(out);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  for (size_t k = 0; k < d->n; k++) {
    vr_status st = vr_model_psi_delta(m, d->p[k].nm, d->p[k].aoi_deg, &out->psi_model[k],
                                      &out->delta_model[k], NULL, err);
    if (st) {
      vr_fit_result_free(out);
      return st;
    }
    double a = (out->psi_model[k] - d->p[k].psi_deg) / d->p[k].sigma_psi;
    double b = vr_delta_difference(out->delta_model[k] - d->p[k].delta_deg) / d->p[k].sigma_delta;
    out->chi2 += a * a + b * b;
  }
  out->mse = out->dof ? sqrt(out->chi2 / out->dof) : 0;
  out->summary.termination = VR_LSQ_CONVERGED;
  return VR_OK;
}

void vr_pseudo_index(const vr_ellipso_point *p, double *n, double *k, double *sigma_n, double *sigma_k) {
  vr_complex N = vr_eps_to_index(vr_pseudo_epsilon(p->psi_deg, p->delta_deg, p->aoi_deg));
  *n = creal(N);
  *k = cimag(N);
  /* dN/dΨ and dN/dΔ by central differences (one-sided at Ψ's ends). */
  const double h = 1e-4;
  double lo = fmax(p->psi_deg - h, 0.0), hi = fmin(p->psi_deg + h, 90.0);
  vr_complex a = vr_eps_to_index(vr_pseudo_epsilon(hi, p->delta_deg, p->aoi_deg));
  vr_complex b = vr_eps_to_index(vr_pseudo_epsilon(lo, p->delta_deg, p->aoi_deg));
  vr_complex dpsi = (a - b) / (hi - lo);
  vr_complex c = vr_eps_to_index(vr_pseudo_epsilon(p->psi_deg, p->delta_deg + h, p->aoi_deg));
  vr_complex e = vr_eps_to_index(vr_pseudo_epsilon(p->psi_deg, p->delta_deg - h, p->aoi_deg));
  vr_complex ddel = (c - e) / (2 * h);
  *sigma_n = hypot(creal(dpsi) * p->sigma_psi, creal(ddel) * p->sigma_delta);
  *sigma_k = hypot(cimag(dpsi) * p->sigma_psi, cimag(ddel) * p->sigma_delta);
}
