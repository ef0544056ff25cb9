/* Fitting sample models to ellipsometry data, one sample or several with
 * shared and per-sample parameters: global search over the free
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
  vr_fit_options o = {0, 60, 3, 200, true, VR_RESID_PSI_DELTA, true};
  return o;
}

/* One fitted quantity: a model parameter, shared by every sample
 * (sample < 0) or one sample's own copy of a per-sample parameter. */
typedef struct fit_var {
  size_t param;
  long sample;
} fit_var;

/* A data point of one sample. */
typedef struct fit_point {
  size_t sample, index;
} fit_point;

typedef struct fit_ctx {
  vr_sample_model *const *m; /* one model per sample, same parameter list */
  const vr_ellipso_data *d;  /* one data set per sample */
  size_t ns;
  const fit_var *vars;
  size_t nfree;
  const fit_point *points;
  size_t npoints;
  /* Depolarisation residuals, after the 2 npoints Ψ/Δ ones, for the points
   * whose file gives it (ndep of them), when the model can depolarise. */
  bool depol;
  size_t ndep;
  vr_fit_residual residual;
} fit_ctx;

static void set_params(fit_ctx *c, const double *x) {
  for (size_t j = 0; j < c->nfree; j++)
    for (size_t s = 0; s < c->ns; s++)
      if (c->vars[j].sample < 0 || (size_t)c->vars[j].sample == s)
        *vr_model_param_value(c->m[s], c->vars[j].param) = x[j];
}

static const vr_model_param *var_param(const fit_ctx *c, size_t j) {
  return &c->m[0]->params[c->vars[j].param];
}

/* σ of a depolarisation value (percent): the file's, else 1 %. */
static double sigma_depol(const vr_ellipso_point *p) {
  return isfinite(p->sigma_depolarisation) && p->sigma_depolarisation > 0 ? p->sigma_depolarisation : 1.0;
}

static int residuals(const double *x, double *r, double *jac, void *user) {
  (void)jac;
  fit_ctx *c = user;
  set_params(c, x);
  size_t q = 2 * c->npoints;
  for (size_t k = 0; k < c->npoints; k++) {
    const vr_ellipso_point *p = &c->d[c->points[k].sample].p[c->points[k].index];
    vr_model_response m;
    if (vr_model_measure(c->m[c->points[k].sample], p->nm, p->aoi_deg, p->bandwidth_nm, &m, NULL)) return 1;
    if (c->residual == VR_RESID_RHO) {
      vr_complex d = tan(m.psi * M_PI / 180) * cexp(I * m.delta * M_PI / 180) -
                     tan(p->psi_deg * M_PI / 180) * cexp(I * p->delta_deg * M_PI / 180);
      r[2 * k] = creal(d);
      r[2 * k + 1] = cimag(d);
    } else {
      r[2 * k] = (m.psi - p->psi_deg) / p->sigma_psi;
      r[2 * k + 1] = vr_delta_difference(m.delta - p->delta_deg) / p->sigma_delta;
    }
    if (c->depol && isfinite(p->depolarisation))
      r[q++] = (100.0 * m.depolarisation - p->depolarisation) / sigma_depol(p);
  }
  return 0;
}

static size_t nresiduals(const fit_ctx *c) { return 2 * c->npoints + (c->depol ? c->ndep : 0); }

static double chi2_at(fit_ctx *c, const double *x, double *work) {
  if (residuals(x, work, NULL, c)) return INFINITY;
  double s = 0;
  for (size_t k = 0; k < nresiduals(c); k++) s += work[k] * work[k];
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
  free(r->depol_model);
  free(r->samples);
  memset(r, 0, sizeof *r);
}

/* Grid for one thickness: step a sixth of the shortest interference period
 * (n taken as 2.5, the high end of common films), over its bounds or, when
 * those are open, up to a few times the start value. */
static size_t thickness_grid(const vr_model_param *p, double start, const fit_ctx *c, int requested,
                             double *grid, size_t max) {
  double lmin = INFINITY;
  for (size_t s = 0; s < c->ns; s++)
    for (size_t i = 0; i < c->d[s].n; i++) lmin = fmin(lmin, c->d[s].p[i].nm);
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
  size_t n = thickness_grid(var_param(c, j), x[j], c, opt->grid_points, grid, GRID_MAX);
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
  vr_lsq *lsq = vr_lsq_create(c->nfree, nresiduals(c), residuals, c, false, err);
  if (!lsq) return err ? err->status : VR_E_NOMEM;
  /* Forward differences halve the cost of each Jacobian; the model is
   * smooth in double precision, so a 1e-8 relative step keeps them accurate
   * to ~1e-8, far below the noise (the covariance uses central ones). */
  vr_status st = vr_lsq_set_forward_differences(lsq, true, err);
  for (size_t j = 0; j < c->nfree && !st; j++) {
    const vr_model_param *p = var_param(c, j);
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

/* Whether the model predicts any depolarisation (a back side, a
 * non-uniformity or bandwidth set or fitted, or the data's bandwidth). */
static bool can_depolarise(const fit_ctx *c) {
  const vr_sample_model *m = c->m[0];
  if (m->backside || m->nonuniformity_pct > 0 || (m->bandwidth_set && m->bandwidth_nm > 0)) return true;
  for (size_t i = 0; i < m->nparams; i++)
    if (m->params[i].free && m->params[i].owner == VR_OWNER_SAMPLE &&
        (m->params[i].slot == VR_SLOT_NONUNIFORMITY || m->params[i].slot == VR_SLOT_BANDWIDTH))
      return true;
  for (size_t s = 0; !m->bandwidth_set && s < c->ns; s++)
    for (size_t i = 0; i < c->d[s].n; i++)
      if (c->d[s].p[i].bandwidth_nm > 0) return true;
  return false;
}

/* The models' values at the solution, the MSEs and the verdicts. */
static vr_status finish(fit_ctx *c, vr_fit_result *out, double limit, vr_error *err) {
  size_t ntot = c->npoints;
  out->psi_model = calloc(ntot ? ntot : 1, sizeof(double));
  out->delta_model = calloc(ntot ? ntot : 1, sizeof(double));
  out->depol_model = calloc(ntot ? ntot : 1, sizeof(double));
  out->samples = calloc(c->ns, sizeof *out->samples);
  if (!out->psi_model || !out->delta_model || !out->depol_model || !out->samples)
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  out->nsamples = c->ns;
  double ncs = 0;
  size_t ncs_file = 0;
  for (size_t k = 0; k < ntot; k++) {
    const fit_point *fp = &c->points[k];
    const vr_ellipso_point *p = &c->d[fp->sample].p[fp->index];
    vr_model_response m;
    vr_status st = vr_model_measure(c->m[fp->sample], p->nm, p->aoi_deg, p->bandwidth_nm, &m, err);
    if (st) return st;
    out->psi_model[k] = m.psi;
    out->delta_model[k] = m.delta;
    out->depol_model[k] = m.depolarisation;
    /* CompleteEASE's MSE compares N, C, S: the file's when it gives them,
     * else those of its Ψ, Δ (and depolarisation when given). */
    double N = p->N, C = p->C, S = p->S;
    if (p->has_ncs) {
      ncs_file++;
    } else {
      double dep = isfinite(p->depolarisation) ? p->depolarisation / 100.0 : 0.0;
      double t = 2 * p->psi_deg * M_PI / 180, dl = p->delta_deg * M_PI / 180;
      N = cos(t);
      double rr = sqrt(fmax(0.0, (1 - dep) * (1 - dep) - N * N));
      C = rr * cos(dl);
      S = rr * sin(dl);
    }
    ncs += (m.N - N) * (m.N - N) + (m.C - C) * (m.C - C) + (m.S - S) * (m.S - S);
  }
  int ncs_dof = (int)(3 * ntot) - (int)c->nfree;
  out->mse_ncs = ncs_dof > 0 ? 1000.0 * sqrt(ncs / ncs_dof) : NAN;
  out->ncs_from_file = ncs_file == ntot && ntot > 0;
  /* Verdicts per sample, the worst one reported for the whole fit. */
  size_t first = 0;
  out->describes = true;
  for (size_t s = 0; s < c->ns; s++) {
    vr_fit_result view = *out;
    view.psi_model += first;
    view.delta_model += first;
    vr_fit_judge(&view, &c->d[s], limit);
    vr_fit_sample *fs = &out->samples[s];
    fs->source = c->d[s].source;
    fs->first = first;
    fs->npoints = c->d[s].n;
    fs->misfit_ratio = view.misfit_ratio;
    fs->noise_psi = view.noise_psi;
    fs->noise_delta = view.noise_delta;
    fs->describes = view.describes;
    double chi = 0;
    for (size_t i = 0; i < c->d[s].n; i++) {
      const vr_ellipso_point *p = &c->d[s].p[i];
      double a = (out->psi_model[first + i] - p->psi_deg) / p->sigma_psi;
      double b = vr_delta_difference(out->delta_model[first + i] - p->delta_deg) / p->sigma_delta;
      chi += a * a + b * b;
    }
    fs->chi2 = chi;
    fs->mse = sqrt(chi / (double)(2 * c->d[s].n));
    if (s == 0 || view.misfit_ratio > out->misfit_ratio) {
      out->misfit_ratio = view.misfit_ratio;
      out->noise_psi = view.noise_psi;
      out->noise_delta = view.noise_delta;
      if (c->ns == 1) memcpy(out->verdict, view.verdict, sizeof out->verdict);
      else snprintf(out->verdict, sizeof out->verdict, "sample %zu (%.120s) %.480s", s + 1,
                    fs->source ? fs->source : "data", view.verdict);
    }
    out->describes = out->describes && view.describes;
    first += c->d[s].n;
  }
  vr_fit_judge_bounds(out);
  return VR_OK;
}

/* The samples must share one parameter list (names, free and per-sample
 * flags) for a shared parameter to mean one thing in all of them; ntot
 * receives the points in all. */
static vr_status check_samples(vr_sample_model *const *models, const vr_ellipso_data *data, size_t ns,
                               size_t *ntot, vr_error *err) {
  const vr_sample_model *m = models[0];
  vr_status st;
  *ntot = 0;
  for (size_t s = 0; s < ns; s++) {
    if ((st = vr_model_check(models[s], err))) return st;
    bool same = models[s]->nparams == m->nparams;
    for (size_t i = 0; same && i < m->nparams; i++)
      same = !strcmp(models[s]->params[i].name, m->params[i].name) &&
             models[s]->params[i].free == m->params[i].free && models[s]->params[i].per_sample == m->params[i].per_sample;
    if (!same) return vr_error_set(err, VR_E_ARG, "the samples' models differ (sample %zu)", s + 1);
    if (data[s].n == 0) return vr_error_set(err, VR_E_ARG, "%s: no data points", data[s].source ? data[s].source : "data");
    *ntot += data[s].n;
  }
  return VR_OK;
}

/* The fitted variables: one per free parameter, or one per sample for a
 * per-sample one when there are several samples; x receives their start
 * values from the models. */
static void list_vars(vr_sample_model *const *models, size_t ns, fit_var *vars, double *x) {
  const vr_sample_model *m = models[0];
  size_t nfree = 0;
  for (size_t i = 0; i < m->nparams; i++) {
    if (!m->params[i].free) continue;
    if (m->params[i].per_sample && ns > 1)
      for (size_t s = 0; s < ns; s++) vars[nfree++] = (fit_var){i, (long)s};
    else vars[nfree++] = (fit_var){i, -1};
  }
  for (size_t j = 0; j < nfree; j++)
    x[j] = vr_model_param_get(models[vars[j].sample < 0 ? 0 : (size_t)vars[j].sample], vars[j].param);
}

/* Every point of every sample, in order; returns how many of them give a
 * depolarisation (its residuals are counted apart). */
static size_t list_points(const vr_ellipso_data *data, size_t ns, fit_point *pts) {
  size_t k = 0, ndep = 0;
  for (size_t s = 0; s < ns; s++)
    for (size_t i = 0; i < data[s].n; i++) {
      pts[k++] = (fit_point){s, i};
      ndep += isfinite(data[s].p[i].depolarisation);
    }
  return ndep;
}

/* Every model evaluation must work at the start: a point the model cannot
 * compute is named by its file and line here, where the solver could only
 * say that a residual failed. */
static vr_status check_start(const fit_ctx *c, vr_error *err) {
  for (size_t q = 0; q < c->npoints; q++) {
    const fit_point *fp = &c->points[q];
    const vr_ellipso_point *p = &c->d[fp->sample].p[fp->index];
    vr_model_response resp;
    vr_status st = vr_model_measure(c->m[fp->sample], p->nm, p->aoi_deg, p->bandwidth_nm, &resp, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld: ", c->d[fp->sample].source ? c->d[fp->sample].source : "data", p->line);
      return st;
    }
  }
  return VR_OK;
}

/* The global search's points: each sample's wavelengths thinned to about
 * opt->grid_wavelengths (all angles kept), so that scanning the
 * thicknesses stays cheap on long spectra. */
static fit_ctx search_subset(const fit_ctx *all, const vr_fit_options *opt, fit_point *subset) {
  size_t ns_pts = 0, sub_dep = 0;
  for (size_t s = 0; s < all->ns; s++) {
    const vr_ellipso_data *d = &all->d[s];
    size_t stride = 1, distinct = 0, w = 0;
    double last = -1;
    for (size_t q = 0; q < d->n; q++)
      if (d->p[q].nm != last) {
        distinct++;
        last = d->p[q].nm;
      }
    if (opt->grid_wavelengths > 0 && distinct > (size_t)opt->grid_wavelengths)
      stride = (distinct + (size_t)opt->grid_wavelengths - 1) / (size_t)opt->grid_wavelengths;
    last = -1;
    for (size_t q = 0; q < d->n; q++) {
      if (d->p[q].nm != last) {
        w++;
        last = d->p[q].nm;
      }
      if ((w - 1) % stride == 0) {
        subset[ns_pts++] = (fit_point){s, q};
        sub_dep += isfinite(d->p[q].depolarisation);
      }
    }
  }
  fit_ctx sub = *all;
  sub.points = subset;
  sub.npoints = ns_pts;
  sub.ndep = sub_dep;
  return sub;
}

/* What the global search found: the best candidate's chi2 (INFINITY when
 * none converged) and the solver's work, reported with the final fit's. */
typedef struct search_result {
  double chi2;
  int iterations, evaluations;
} search_result;

/* Global search over the free thicknesses on a subset of the data: the
 * first thickness scanned on a grid, each of its best minima completed by
 * one coordinate scan of the other thicknesses and a quick local fit; best
 * receives the best candidate.  Interference makes chi2 in a thickness a
 * row of minima, which a local fit from the model's start would not leave. */
static vr_status global_search(const fit_ctx *all, double *x, const vr_fit_options *opt, fit_point *subset,
                               double *work, double *best, search_result *res, vr_fit_result *out,
                               vr_error *err) {
  size_t nfree = all->nfree;
  fit_ctx sub = search_subset(all, opt, subset);
  size_t firstj = 0;
  for (size_t j = 0; j < nfree; j++)
    if (var_param(all, j)->slot == VR_SLOT_THICKNESS) {
      firstj = j;
      break;
    }
  double starts[16];
  size_t nstart = scan(&sub, x, firstj, opt, starts, opt->candidates > 16 ? 16 : (size_t)opt->candidates, work,
                       &out->grid_evaluations);
  for (size_t s = 0; s < nstart; s++) {
    double *y = calloc(nfree, sizeof *y);
    if (!y) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    memcpy(y, x, nfree * sizeof *x);
    y[firstj] = starts[s];
    /* Other thicknesses: one coordinate scan each. */
    for (size_t j = 0; j < nfree; j++) {
      if (j == firstj || var_param(all, j)->slot != VR_SLOT_THICKNESS) continue;
      double b;
      if (scan(&sub, y, j, opt, &b, 1, work, &out->grid_evaluations)) y[j] = b;
    }
    vr_lsq_summary sum;
    vr_error lerr = {0};
    /* Candidates are refined on the subset; only the winner sees all data. */
    vr_status lst = local_fit(&sub, y, opt, true, &sum, NULL, &lerr);
    if (lst == VR_OK) {
      res->iterations += sum.iterations;
      res->evaluations += sum.residual_evaluations;
    }
    if (lst == VR_OK && sum.chi2 < res->chi2) {
      res->chi2 = sum.chi2;
      memcpy(best, y, nfree * sizeof *y);
    }
    free(y);
  }
  return VR_OK;
}

/* The result's per-parameter arrays, allocated together so that one check
 * covers them. */
static bool alloc_parameters(vr_fit_result *out, size_t nfree) {
  out->names = calloc(nfree, sizeof *out->names);
  out->value = calloc(nfree, sizeof(double));
  out->stderr_ = calloc(nfree, sizeof(double));
  out->ci_lo = calloc(nfree, sizeof(double));
  out->ci_hi = calloc(nfree, sizeof(double));
  out->correlation = calloc(nfree * nfree, sizeof(double));
  out->at_bound = calloc(nfree, sizeof(int));
  return out->names && out->value && out->stderr_ && out->ci_lo && out->ci_hi && out->correlation &&
         out->at_bound;
}

/* The covariance at the solution, or why there is none (a failure leaves
 * the fit itself valid).  Its differences move the models' parameters, so
 * they are set back to the solution; lsq is destroyed. */
static void compute_covariance(fit_ctx *all, vr_lsq *lsq, const double *best, double *cov, vr_fit_result *out) {
  vr_error cerr = {0};
  out->covariance_ok = vr_lsq_covariance(lsq, best, true, cov, &cerr) == VR_OK;
  vr_lsq_destroy(lsq);
  set_params(all, best);
  if (!out->covariance_ok) {
    /* Keep the start of the solver's explanation. */
    memcpy(out->covariance_message, cerr.message, sizeof out->covariance_message - 1);
    out->covariance_message[sizeof out->covariance_message - 1] = '\0';
  }
}

/* Each fitted parameter's name ("name[sample]" for a per-sample one),
 * value, bound flag, standard error, 90 % limits and correlations. */
static vr_status fill_parameters(const fit_ctx *all, const double *best, const double *cov, vr_fit_result *out,
                                 vr_error *err) {
  size_t nfree = all->nfree;
  double t = gsl_cdf_tdist_Pinv(0.95, (double)out->dof);
  for (size_t j = 0; j < nfree; j++) {
    const vr_model_param *mp = var_param(all, j);
    char name[192];
    if (all->vars[j].sample >= 0) snprintf(name, sizeof name, "%s[%ld]", mp->name, all->vars[j].sample + 1);
    else snprintf(name, sizeof name, "%s", mp->name);
    if (!(out->names[j] = strdup(name))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    out->value[j] = best[j];
    double tol = fmax(1e-12, 1e-9 * (isfinite(mp->upper - mp->lower) ? mp->upper - mp->lower : fabs(best[j])));
    out->at_bound[j] = best[j] <= mp->lower + tol ? -1 : best[j] >= mp->upper - tol ? 1 : 0;
    double se = out->covariance_ok && !out->at_bound[j] ? sqrt(cov[j * nfree + j]) : NAN;
    out->stderr_[j] = se;
    out->ci_lo[j] = best[j] - t * se;
    out->ci_hi[j] = best[j] + t * se;
    for (size_t q = 0; q < nfree; q++) {
      double den = sqrt(cov[j * nfree + j] * cov[q * nfree + q]);
      out->correlation[j * nfree + q] = out->covariance_ok && den > 0 ? cov[j * nfree + q] / den : NAN;
    }
  }
  return VR_OK;
}

vr_status vr_ellipso_fit_samples(vr_sample_model *const *models, const vr_ellipso_data *data, size_t ns,
                                 const vr_fit_options *opt_in, vr_fit_result *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  double t_start = now();
  vr_fit_options opt = opt_in ? *opt_in : vr_fit_default_options();
  if (ns == 0) return vr_error_set(err, VR_E_ARG, "no data set");
  vr_sample_model *m = models[0];
  size_t ntot;
  vr_status st = check_samples(models, data, ns, &ntot, err);
  if (st) return st;
  size_t nfree = 0;
  for (size_t i = 0; i < m->nparams; i++)
    if (m->params[i].free) nfree += m->params[i].per_sample ? ns : 1;
  if (nfree == 0) return vr_error_set(err, VR_E_ARG, "the model has no free parameter (mark some with 'fit')");
  fit_var *vars = calloc(nfree, sizeof *vars);
  fit_point *all_pts = calloc(ntot, sizeof *all_pts), *subset = calloc(ntot, sizeof *subset);
  double *x = calloc(nfree, sizeof *x), *best = calloc(nfree, sizeof *best),
         *work = calloc(3 * ntot, sizeof *work), *cov = calloc(nfree * nfree, sizeof *cov);
  if (!vars || !all_pts || !subset || !x || !best || !work || !cov) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  list_vars(models, ns, vars, x);
  size_t ndep = list_points(data, ns, all_pts);
  fit_ctx all = {models, data, ns, vars, nfree, all_pts, ntot, false, ndep, opt.residual};
  all.depol = opt.fit_depolarisation && ndep > 0 && can_depolarise(&all) && opt.residual == VR_RESID_PSI_DELTA;
  if (nresiduals(&all) <= nfree) {
    st = vr_error_set(err, VR_E_ARG, "%zu data values cannot determine %zu free parameters (need more than %zu)",
                      nresiduals(&all), nfree, nfree);
    goto done;
  }
  if ((st = check_start(&all, err))) goto done;

  size_t nthick = 0;
  for (size_t j = 0; j < nfree; j++) nthick += var_param(&all, j)->slot == VR_SLOT_THICKNESS;
  search_result search = {INFINITY, 0, 0};
  memcpy(best, x, nfree * sizeof *x);
  if (opt.global_search && nthick > 0 &&
      (st = global_search(&all, x, &opt, subset, work, best, &search, out, err)))
    goto done;
  /* Final local fit from the best start (or the model's own start). */
  if (!isfinite(search.chi2)) memcpy(best, x, nfree * sizeof *x);
  vr_lsq *lsq = NULL;
  if ((st = local_fit(&all, best, &opt, false, &out->summary, &lsq, err))) goto done;
  /* Report the work of the whole search, not only of the last polish. */
  out->summary.iterations += search.iterations;
  out->summary.residual_evaluations += search.evaluations;
  set_params(&all, best);
  out->npoints = ntot;
  out->ndepol = all.depol ? ndep : 0;
  out->nfree = nfree;
  out->dof = (int)(nresiduals(&all) - nfree);
  out->chi2 = out->summary.chi2;
  out->mse = sqrt(out->chi2 / out->dof);
  if (!alloc_parameters(out, nfree)) {
    vr_lsq_destroy(lsq);
    st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto done;
  }
  compute_covariance(&all, lsq, best, cov, out);
  if ((st = fill_parameters(&all, best, cov, out, err))) goto done;
  if ((st = finish(&all, out, VR_FIT_MAX_MISFIT, err))) goto done;
  out->seconds = now() - t_start;
done:
  free(vars);
  free(all_pts);
  free(subset);
  free(x);
  free(best);
  free(work);
  free(cov);
  if (st) vr_fit_result_free(out);
  return st;
}

vr_status vr_ellipso_evaluate(const vr_sample_model *m, const vr_ellipso_data *d, vr_fit_result *out,
                              vr_error *err) {
  memset(out, 0, sizeof *out);
  fit_point *pts = calloc(d->n ? d->n : 1, sizeof *pts);
  vr_sample_model *mm = (vr_sample_model *)m;
  fit_ctx c = {&mm, d, 1, NULL, 0, pts, d->n, false, 0, VR_RESID_PSI_DELTA};
  vr_status st = pts ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t k = 0; k < d->n && !st; k++) pts[k] = (fit_point){0, k};
  if (!st) st = finish(&c, out, VR_FIT_MAX_MISFIT, err);
  free(pts);
  if (st) {
    vr_fit_result_free(out);
    return st;
  }
  out->npoints = d->n;
  out->chi2 = out->samples[0].chi2;
  out->dof = (int)(2 * d->n);
  out->covariance_ok = true;
  out->mse = out->dof ? sqrt(out->chi2 / out->dof) : 0;
  out->summary.termination = VR_LSQ_CONVERGED;
  return VR_OK;
}

vr_status vr_ellipso_fit(vr_sample_model *m, const vr_ellipso_data *d, const vr_fit_options *opt,
                         vr_fit_result *out, vr_error *err) {
  return vr_ellipso_fit_samples(&m, d, 1, opt, out, err);
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
