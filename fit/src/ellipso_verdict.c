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

/* The third differences of one quantity over the sweeps of the file: runs
 * of points at one angle whose wavelength keeps rising (or keeps falling)
 * and that have at least 8 points.  Writes at most d->n values into t;
 * returns their number. */
static size_t third_differences(const vr_ellipso_data *d, bool delta, double *t) {
  size_t start = 0, count = 0;
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
        t[count++] = fabs(d3 - 2 * d2 + d1);
      }
    start = end;
  }
  return count;
}

void vr_ellipso_noise(const vr_ellipso_data *d, double *psi_deg, double *delta_deg) {
  double out[2];
  double *t = malloc((d->n ? d->n : 1) * sizeof *t);
  for (int q = 0; q < 2; q++) {
    size_t count = t ? third_differences(d, q == 1, t) : 0;
    if (count >= 4) {
      /* Median |third difference| / (0.6745 sqrt(20)): the standard
       * deviation of white noise, robust to the few large differences
       * that a sharp feature or a table's kinks give. */
      qsort(t, count, sizeof *t, cmp_double);
      double med = count % 2 ? t[count / 2] : 0.5 * (t[count / 2 - 1] + t[count / 2]);
      out[q] = med / (0.6745 * sqrt(20.0));
    } else if (d->has_sigma && d->n && t) {
      for (size_t i = 0; i < d->n; i++) t[i] = q ? d->p[i].sigma_delta : d->p[i].sigma_psi;
      qsort(t, d->n, sizeof *t, cmp_double);
      out[q] = t[d->n / 2];
    } else {
      out[q] = 0.05;
    }
    out[q] = fmax(out[q], 0.001);
  }
  free(t);
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
  if (r->nsamples == 1 && r->samples) {
    r->samples[0].misfit_ratio = r->misfit_ratio;
    r->samples[0].noise_psi = r->noise_psi;
    r->samples[0].noise_delta = r->noise_delta;
    r->samples[0].describes = r->describes;
  }
}

void vr_fit_judge_bounds(vr_fit_result *r) {
  if (!r->at_bound) return;
  char names[320] = "";
  size_t used = 0, count = 0;
  for (size_t i = 0; i < r->nfree; i++) {
    if (!r->at_bound[i]) continue;
    count++;
    if (used < sizeof names)
      used += (size_t)snprintf(names + used, sizeof names - used, "%s%s at its %s bound %.6g",
                               count > 1 ? ", " : "", r->names && r->names[i] ? r->names[i] : "a parameter",
                               r->at_bound[i] < 0 ? "lower" : "upper", r->value[i]);
  }
  if (!count) return;
  r->describes = false;
  /* The misfit part of the verdict follows, without its own opening. */
  const char *rest = r->verdict;
  static const char *const OPENING[] = {"describes the data: ", "does NOT describe the data: "};
  for (int k = 0; k < 2; k++)
    if (!strncmp(rest, OPENING[k], strlen(OPENING[k]))) rest += strlen(OPENING[k]);
  char v[sizeof r->verdict];
  snprintf(v, sizeof v, "does NOT describe the data: %.240s (pinned there, not fitted: the data want %s "
           "beyond; widen the bound or change the model); %.230s",
           names, count > 1 ? "them" : "it", rest);
  memcpy(r->verdict, v, sizeof v);
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
