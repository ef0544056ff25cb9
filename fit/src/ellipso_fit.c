/* Fitting sample models to ellipsometry data: global search over the free
 * thicknesses on a subset of wavelengths, Levenberg-Marquardt from the best
 * grid minima on all data, then standard errors, 90 % limits and the
 * correlation matrix (conventions in vr/ellipso_fit.h). */
#include "vr/ellipso_fit.h"

#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

vr_fit_options vr_fit_default_options(void) {
  vr_fit_options o = {0, 60, 3, 200, true, VR_RESID_PSI_DELTA};
  return o;
}

typedef struct fit_ctx {
  vr_sample_model *m;
  const vr_ellipso_data *d;
  const size_t *free_idx;
  size_t nfree;
  const size_t *points;  /* data points used, NULL = all */
  size_t npoints;
  vr_fit_residual residual;
} fit_ctx;

static void set_params(fit_ctx *c, const double *x) {
  for (size_t j = 0; j < c->nfree; j++) *vr_model_param_value(c->m, c->free_idx[j]) = x[j];
}

static int residuals(const double *x, double *r, double *jac, void *user) {
  (void)jac;
  fit_ctx *c = user;
  set_params(c, x);
  for (size_t k = 0; k < c->npoints; k++) {
    const vr_ellipso_point *p = &c->d->p[c->points ? c->points[k] : k];
    double psi, delta;
    if (vr_model_psi_delta(c->m, p->nm, p->aoi_deg, &psi, &delta, NULL, NULL)) return 1;
    if (c->residual == VR_RESID_RHO) {
      vr_complex d = tan(psi * M_PI / 180) * cexp(I * delta * M_PI / 180) -
                     tan(p->psi_deg * M_PI / 180) * cexp(I * p->delta_deg * M_PI / 180);
      r[2 * k] = creal(d);
      r[2 * k + 1] = cimag(d);
    } else {
      r[2 * k] = (psi - p->psi_deg) / p->sigma_psi;
      r[2 * k + 1] = vr_delta_difference(delta - p->delta_deg) / p->sigma_delta;
    }
  }
  return 0;
}

static double chi2_at(fit_ctx *c, const double *x, double *work) {
  if (residuals(x, work, NULL, c)) return INFINITY;
  double s = 0;
  for (size_t k = 0; k < 2 * c->npoints; k++) s += work[k] * work[k];
  return s;
}

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void vr_fit_result_free(vr_fit_result *r) {
  if (!r) return;
  for (size_t i = 0; r->names && i < r->nfree; i++) free(r->names[i]);
  free(r->names);
  free(r->value);
  free(r->stderr_);
  free(r->ci_lo);
  free(r->ci_hi);
  free(r->correlation);
  free(r->at_bound);
  free(r->psi_model);
  free(r->delta_model);
  memset(r, 0, sizeof *r);
}

/* Grid for one thickness: step a sixth of the shortest interference period
 * (n taken as 2.5, the high end of common films), over its bounds or, when
 * those are open, up to a few times the start value. */
static size_t thickness_grid(const vr_model_param *p, double start, const vr_ellipso_data *d,
                             int requested, double *grid, size_t max) {
  double lmin = INFINITY;
  for (size_t i = 0; i < d->n; i++) lmin = fmin(lmin, d->p[i].nm);
  double period = lmin / (2.0 * 2.5);
  double lo = fmax(p->lower, 0.0);
  double hi = p->upper;
  double open_hi = fmax(3.0 * start, start + 1000.0);
  if (!(hi < open_hi)) hi = open_hi;
  size_t n = requested > 0 ? (size_t)requested : (size_t)ceil((hi - lo) / (period / 6.0)) + 1;
  if (n < 2) n = 2;
  if (n > max) n = max;
  for (size_t i = 0; i < n; i++) grid[i] = lo + (hi - lo) * (double)i / (double)(n - 1);
  return n;
}

#define GRID_MAX 400

/* Scans free thickness j (others held), returns the best values in order. */
static size_t scan(fit_ctx *c, double *x, size_t j, const vr_fit_options *opt, double *best,
                   size_t nbest, double *work, int *evals) {
  double grid[GRID_MAX], chi[GRID_MAX];
  const vr_model_param *p = &c->m->params[c->free_idx[j]];
  size_t n = thickness_grid(p, x[j], c->d, opt->grid_points, grid, GRID_MAX);
  double keep = x[j];
  for (size_t i = 0; i < n; i++) {
    x[j] = grid[i];
    chi[i] = chi2_at(c, x, work);
    (*evals)++;
  }
  x[j] = keep;
  /* Local minima of the scan, best first. */
  size_t found = 0;
  double bestchi[16];
  for (size_t i = 0; i < n; i++) {
    bool is_min = (i == 0 || chi[i] <= chi[i - 1]) && (i + 1 == n || chi[i] <= chi[i + 1]);
    if (!is_min || !isfinite(chi[i])) continue;
    size_t pos = found < nbest ? found : nbest;
    while (pos > 0 && bestchi[pos - 1] > chi[i]) pos--;
    if (pos >= nbest) continue;
    for (size_t q = (found < nbest ? found : nbest - 1); q > pos; q--) {
      bestchi[q] = bestchi[q - 1];
      best[q] = best[q - 1];
    }
    bestchi[pos] = chi[i];
    best[pos] = grid[i];
    if (found < nbest) found++;
  }
  return found;
}

/* quick: a loose, short solve, enough to rank the grid candidates. */
static vr_status local_fit(fit_ctx *c, double *x, const vr_fit_options *opt, bool quick,
                           vr_lsq_summary *sum, vr_lsq **keep, vr_error *err) {
  vr_lsq *lsq = vr_lsq_create(c->nfree, 2 * c->npoints, residuals, c, false, err);
  if (!lsq) return err ? err->status : VR_E_NOMEM;
  /* Forward differences halve the cost of each Jacobian; the model is
   * smooth in double precision, so a 1e-8 relative step keeps them accurate
   * to ~1e-8, far below the noise (the covariance uses central ones). */
  vr_status st = vr_lsq_set_forward_differences(lsq, true, err);
  for (size_t j = 0; j < c->nfree && !st; j++) {
    const vr_model_param *p = &c->m->params[c->free_idx[j]];
    if (!st) st = vr_lsq_set_step(lsq, j, 1e-8, err);
    double lo = p->lower, hi = p->upper;
    if (x[j] < lo) x[j] = lo;
    if (x[j] > hi) x[j] = hi;
    st = vr_lsq_set_bounds(lsq, j, lo, hi, err);
  }
  vr_lsq_options o = vr_lsq_default_options();
  o.max_iterations = quick ? 12 : opt->max_iterations;
  o.function_tolerance = quick ? 1e-6 : 1e-10;
  o.parameter_tolerance = quick ? 1e-6 : 1e-10;
  if (!st) st = vr_lsq_solve(lsq, x, &o, sum, err);
  if (st || !keep) vr_lsq_destroy(lsq);
  else *keep = lsq;
  return st;
}

vr_status vr_ellipso_fit(vr_sample_model *m, const vr_ellipso_data *d, const vr_fit_options *opt_in,
                         vr_fit_result *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  double t_start = now();
  vr_fit_options opt = opt_in ? *opt_in : vr_fit_default_options();
  vr_status st = vr_model_check(m, err);
  if (st) return st;
  if (d->n == 0) return vr_error_set(err, VR_E_ARG, "no data points");
  size_t nfree = 0;
  for (size_t i = 0; i < m->nparams; i++) nfree += m->params[i].free;
  if (nfree == 0) return vr_error_set(err, VR_E_ARG, "the model has no free parameter (mark some with 'fit')");
  if (2 * d->n <= nfree)
    return vr_error_set(err, VR_E_ARG,
                        "%zu data values cannot determine %zu free parameters (need more than %zu)",
                        2 * d->n, nfree, nfree);
  size_t *free_idx = calloc(nfree, sizeof *free_idx), *subset = calloc(d->n, sizeof *subset);
  double *x = calloc(nfree, sizeof *x), *best = calloc(nfree, sizeof *best),
         *work = calloc(2 * d->n, sizeof *work), *cov = calloc(nfree * nfree, sizeof *cov);
  if (!free_idx || !subset || !x || !best || !work || !cov) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  nfree = 0;
  for (size_t i = 0; i < m->nparams; i++)
    if (m->params[i].free) free_idx[nfree++] = i;
  for (size_t j = 0; j < nfree; j++) x[j] = vr_model_param_get(m, free_idx[j]);

  /* Every model evaluation must work at the start. */
  fit_ctx all = {m, d, free_idx, nfree, NULL, d->n, opt.residual};
  for (size_t k = 0; k < d->n; k++) {
    double psi, delta;
    if ((st = vr_model_psi_delta(m, d->p[k].nm, d->p[k].aoi_deg, &psi, &delta, NULL, err))) {
      vr_error_prefix(err, "%s:%ld: ", d->source ? d->source : "data", d->p[k].line);
      goto done;
    }
  }

  /* Global search on a subset of wavelengths (all angles kept). */
  size_t nthick = 0;
  for (size_t j = 0; j < nfree; j++) nthick += m->params[free_idx[j]].slot == VR_SLOT_THICKNESS;
  double bestchi = INFINITY;
  int search_iterations = 0, search_evaluations = 0;
  memcpy(best, x, nfree * sizeof *x);
  if (opt.global_search && nthick > 0) {
    size_t stride = 1, distinct = 0;
    double last = -1;
    for (size_t k = 0; k < d->n; k++)
      if (d->p[k].nm != last) {
        distinct++;
        last = d->p[k].nm;
      }
    if (opt.grid_wavelengths > 0 && distinct > (size_t)opt.grid_wavelengths)
      stride = (distinct + (size_t)opt.grid_wavelengths - 1) / (size_t)opt.grid_wavelengths;
    size_t ns = 0, w = 0;
    last = -1;
    for (size_t k = 0; k < d->n; k++) {
      if (d->p[k].nm != last) {
        w++;
        last = d->p[k].nm;
      }
      if ((w - 1) % stride == 0) subset[ns++] = k;
    }
    fit_ctx sub = {m, d, free_idx, nfree, subset, ns, opt.residual};
    size_t first = 0;
    for (size_t j = 0; j < nfree; j++)
      if (m->params[free_idx[j]].slot == VR_SLOT_THICKNESS) {
        first = j;
        break;
      }
    double starts[16];
    size_t nstart = scan(&sub, x, first, &opt, starts, opt.candidates > 16 ? 16 : (size_t)opt.candidates,
                         work, &out->grid_evaluations);
    for (size_t s = 0; s < nstart; s++) {
      double *y = calloc(nfree, sizeof *y);
      if (!y) {
        st = vr_error_set(err, VR_E_NOMEM, "out of memory");
        goto done;
      }
      memcpy(y, x, nfree * sizeof *x);
      y[first] = starts[s];
      /* Other thicknesses: one coordinate scan each. */
      for (size_t j = 0; j < nfree; j++) {
        if (j == first || m->params[free_idx[j]].slot != VR_SLOT_THICKNESS) continue;
        double b;
        if (scan(&sub, y, j, &opt, &b, 1, work, &out->grid_evaluations)) y[j] = b;
      }
      vr_lsq_summary sum;
      vr_error lerr = {0};
      /* Candidates are refined on the subset; only the winner sees all data. */
      vr_status lst = local_fit(&sub, y, &opt, true, &sum, NULL, &lerr);
      if (lst == VR_OK) {
        search_iterations += sum.iterations;
        search_evaluations += sum.residual_evaluations;
      }
      if (lst == VR_OK && sum.chi2 < bestchi) {
        bestchi = sum.chi2;
        memcpy(best, y, nfree * sizeof *y);
      }
      free(y);
    }
  }
  /* Final local fit from the best start (or the model's own start). */
  if (!isfinite(bestchi)) memcpy(best, x, nfree * sizeof *x);
  vr_lsq *lsq = NULL;
  if ((st = local_fit(&all, best, &opt, false, &out->summary, &lsq, err))) goto done;
  /* Report the work of the whole search, not only of the last polish. */
  out->summary.iterations += search_iterations;
  out->summary.residual_evaluations += search_evaluations;
  set_params(&all, best);
  out->npoints = d->n;
  out->nfree = nfree;
  out->dof = (int)(2 * d->n - nfree);
  out->chi2 = out->summary.chi2;
  out->mse = sqrt(out->chi2 / out->dof);
  out->names = calloc(nfree, sizeof *out->names);
  out->value = calloc(nfree, sizeof(double));
  out->stderr_ = calloc(nfree, sizeof(double));
  out->ci_lo = calloc(nfree, sizeof(double));
  out->ci_hi = calloc(nfree, sizeof(double));
  out->correlation = calloc(nfree * nfree, sizeof(double));
  out->at_bound = calloc(nfree, sizeof(int));
  out->psi_model = calloc(d->n, sizeof(double));
  out->delta_model = calloc(d->n, sizeof(double));
  if (!out->names || !out->value || !out->stderr_ || !out->ci_lo || !out->ci_hi || !out->correlation ||
      !out->at_bound || !out->psi_model || !out->delta_model) {
    vr_lsq_destroy(lsq);
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  vr_error cerr = {0};
  out->covariance_ok = vr_lsq_covariance(lsq, best, true, cov, &cerr) == VR_OK;
  vr_lsq_destroy(lsq);
  set_params(&all, best);
  if (!out->covariance_ok) {
    /* Keep the start of the solver's explanation. */
    memcpy(out->covariance_message, cerr.message, sizeof out->covariance_message - 1);
    out->covariance_message[sizeof out->covariance_message - 1] = '\0';
  }
  double t = gsl_cdf_tdist_Pinv(0.95, (double)out->dof);
  for (size_t j = 0; j < nfree; j++) {
    if (!(out->names[j] = strdup(m->params[free_idx[j]].name))) {
      st = vr_error_set(err, VR_E_NOMEM, "out of memory");
      goto done;
    }
    out->value[j] = best[j];
    const vr_model_param *mp = &m->params[free_idx[j]];
    double tol = fmax(1e-12, 1e-9 * (isfinite(mp->upper - mp->lower) ? mp->upper - mp->lower : fabs(best[j])));
    out->at_bound[j] = best[j] <= mp->lower + tol ? -1 : best[j] >= mp->upper - tol ? 1 : 0;
    double se = out->covariance_ok && !out->at_bound[j] ? sqrt(cov[j * nfree + j]) : NAN;
    out->stderr_[j] = se;
    out->ci_lo[j] = best[j] - t * se;
    out->ci_hi[j] = best[j] + t * se;
    for (size_t k = 0; k < nfree; k++) {
      double den = sqrt(cov[j * nfree + j] * cov[k * nfree + k]);
      out->correlation[j * nfree + k] = out->covariance_ok && den > 0 ? cov[j * nfree + k] / den : NAN;
    }
  }
  for (size_t k = 0; k < d->n; k++)
    vr_model_psi_delta(m, d->p[k].nm, d->p[k].aoi_deg, &out->psi_model[k], &out->delta_model[k], NULL, NULL);
  vr_fit_judge(out, d, VR_FIT_MAX_MISFIT);
  out->seconds = now() - t_start;
done:
  free(free_idx);
  free(subset);
  free(x);
  free(best);
  free(work);
  free(cov);
  if (st) vr_fit_result_free(out);
  return st;
}

vr_complex vr_pseudo_epsilon(double psi_deg, double delta_deg, double aoi_deg) {
  /* The inversion is written for rho = r_p / r_s of the exp(-i w t)
   * amplitudes, the conjugate of the reported tan(Psi) e^{i Delta}. */
  double th = aoi_deg * M_PI / 180.0;
  vr_complex rho = tan(psi_deg * M_PI / 180.0) * cexp(-I * delta_deg * M_PI / 180.0);
  vr_complex f = (1.0 - rho) / (1.0 + rho);
  double s = sin(th), tn = tan(th);
  return s * s * (1.0 + tn * tn * f * f);
}
