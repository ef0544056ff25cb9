/* GGX roughness of frosted glass from scattered transmittance
 * (vr/frosted.h). */
#include "vr/frosted.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vr/csv.h"
#include "vr/lsq.h"
#include "vr/microfacet.h"
#include "vr/optics.h"

double vr_frosted_btdf(double alpha, double n, double scale, double theta_i, double theta_o,
                       double phi_o) {
  const double d = M_PI / 180;
  double st = sin(theta_o * d) / n;
  if (!(st < 1)) return 0;
  double ct = sqrt(1 - st * st);
  vr_vec3 wi = {sin(theta_i * d), 0, cos(theta_i * d)};
  /* Inside the glass, heading down (z < 0), with the outgoing azimuth. */
  vr_vec3 wt = {st * cos(phi_o * d), st * sin(phi_o * d), -ct};
  double f = vr_ggx_dielectric_btdf(alpha, n, wi, wt, VR_TRANSPORT_RADIANCE);
  vr_fresnel fr;
  vr_fresnel_interface(n, 1.0, acos(ct), &fr);
  return scale * f * 0.5 * (fr.Ts + fr.Tp) / (n * n);
}

vr_status vr_btdf_samples_read(const char *path, vr_btdf_sample **out, size_t *count,
                               vr_error *err) {
  *out = NULL;
  *count = 0;
  vr_csv *csv;
  vr_status st = vr_csv_read(path, &csv, err);
  if (st) return st;
  long ci = vr_csv_find_column(csv, 0, "theta_i"), co = vr_csv_find_column(csv, 0, "theta_o"),
       cp = vr_csv_find_column(csv, 0, "phi_o"), cf = vr_csv_find_column(csv, 0, "btdf");
  size_t rows = vr_csv_rows(csv);
  if (ci < 0 || co < 0 || cf < 0 || rows < 2) {
    st = vr_error_at(err, VR_E_PARSE, path, rows ? vr_csv_line(csv, 0) : 0, 0,
                     "expected a header with theta_i, theta_o, [phi_o,] btdf and data rows");
    vr_csv_destroy(csv);
    return st;
  }
  vr_btdf_sample *s = calloc(rows, sizeof *s);
  if (!s) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t n = 0;
  for (size_t r = 1; r < rows && !st; r++) {
    vr_btdf_sample *p = &s[n];
    p->line = vr_csv_line(csv, r);
    if ((st = vr_csv_number(csv, r, (size_t)ci, "theta_i", &p->theta_i, err)) ||
        (st = vr_csv_number(csv, r, (size_t)co, "theta_o", &p->theta_o, err)) ||
        (cp >= 0 && (st = vr_csv_number(csv, r, (size_t)cp, "phi_o", &p->phi_o, err))) ||
        (st = vr_csv_number(csv, r, (size_t)cf, "btdf", &p->f, err)))
      break;
    if (!(p->theta_i >= 0 && p->theta_i < 90) || !(p->theta_o >= 0 && p->theta_o < 90))
      st = vr_error_at(err, VR_E_RANGE, path, p->line, 0, "angles must lie in [0, 90) degrees");
    else if (!(p->f > 0))
      st = vr_error_at(err, VR_E_RANGE, path, p->line, 0, "field 'btdf': %g is not positive", p->f);
    n++;
  }
  vr_csv_destroy(csv);
  if (st) {
    free(s);
    return st;
  }
  *out = s;
  *count = n;
  return VR_OK;
}

typedef struct fctx {
  const vr_btdf_sample *s;
  size_t n;
  double index, sigma;
} fctx;

static int residual(const double *p, double *r, double *jac, void *user) {
  (void)jac;
  const fctx *c = user;
  if (!(p[0] > 0) || !(p[1] > 0)) return 1;
  for (size_t i = 0; i < c->n; i++) {
    double f = vr_frosted_btdf(p[0], c->index, p[1], c->s[i].theta_i, c->s[i].theta_o, c->s[i].phi_o);
    r[i] = (f - c->s[i].f) / (c->sigma * c->s[i].f);
  }
  return 0;
}

vr_status vr_frosted_fit_alpha(const vr_btdf_sample *s, size_t count, double n, double sigma_rel,
                               vr_frosted_fit *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  if (count < 3) return vr_error_set(err, VR_E_ARG, "a roughness fit needs 3 or more samples");
  if (!(n > 1) || !(sigma_rel > 0))
    return vr_error_set(err, VR_E_ARG, "need n > 1 and a positive relative noise");
  fctx c = {s, count, n, sigma_rel};
  /* Start from the best of a coarse scan in alpha (the scale then follows
   * from the mean ratio), so a narrow lobe is not missed. */
  double best = INFINITY, p[2] = {0.1, 1};
  for (double a = 0.02; a <= 1.5; a *= 1.25) {
    double lr = 0;
    size_t used = 0;
    for (size_t i = 0; i < count; i++) {
      double f = vr_frosted_btdf(a, n, 1, s[i].theta_i, s[i].theta_o, s[i].phi_o);
      if (f > 0) lr += log(s[i].f / f), used++;
    }
    if (!used) continue;
    double scale = exp(lr / (double)used), cost = 0;
    for (size_t i = 0; i < count; i++) {
      double f = scale * vr_frosted_btdf(a, n, 1, s[i].theta_i, s[i].theta_o, s[i].phi_o);
      cost += pow((f - s[i].f) / s[i].f, 2);
    }
    if (cost < best) best = cost, p[0] = a, p[1] = scale;
  }
  vr_lsq *lsq = vr_lsq_create(2, count, residual, &c, false, err);
  if (!lsq) return err ? err->status : VR_E_NOMEM;
  double cov[4];
  vr_lsq_summary sum;
  vr_status st = vr_lsq_set_bounds(lsq, 0, 1e-3, 3.0, err);
  if (!st) st = vr_lsq_set_bounds(lsq, 1, 1e-6, 1e6, err);
  if (!st) st = vr_lsq_solve(lsq, p, NULL, &sum, err);
  if (!st) st = vr_lsq_covariance(lsq, p, sum.chi2 / (double)(count - 2) > 1, cov, err);
  vr_lsq_destroy(lsq);
  if (st) return st;
  out->alpha = p[0];
  out->scale = p[1];
  out->alpha_err = sqrt(cov[0]);
  out->scale_err = sqrt(cov[3]);
  out->rms_rel = sigma_rel * sqrt(sum.chi2 / (double)count);
  return VR_OK;
}
