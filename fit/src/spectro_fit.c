/* n, k of an uncoated pane from T and R: point inversion, dispersion
 * smoothing, k from T (vr/spectro_fit.h). */
#include "vr/spectro_fit.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <gsl/gsl_cdf.h>

#include "vr/lsq.h"
#include "vr/slab_invert.h"

vr_spectro_fit_options vr_spectro_fit_default_options(void) {
  return (vr_spectro_fit_options){.model = VR_NK_SELLMEIER, .sigma_T = 1e-3, .sigma_R = 1e-3};
}

vr_status vr_nk_model_parse(const char *text, vr_nk_model *out, vr_error *err) {
  static const char *const NAMES[] = {"sellmeier", "sellmeier2", "cauchy"};
  for (int i = 0; i < 3; i++)
    if (strcasecmp(text, NAMES[i]) == 0) {
      *out = (vr_nk_model)i;
      return VR_OK;
    }
  return vr_error_set(err, VR_E_ARG, "unknown n model \"%s\" (sellmeier, sellmeier2, cauchy)", text);
}

void vr_spectro_fit_free(vr_spectro_fit_result *r) {
  if (r) free(r->pt);
  if (r) memset(r, 0, sizeof *r);
}

static size_t model_params(vr_nk_model m) { return m == VR_NK_SELLMEIER2 ? 5 : 3; }

/* n of the model at nm; NAN outside its domain (n² <= 0, a pole). */
static double model_n(vr_nk_model m, const double *p, double nm) {
  double L = nm * 1e-3, L2 = L * L;
  if (m == VR_NK_CAUCHY) return p[0] + p[1] / L2 + p[2] / (L2 * L2);
  double n2 = 1.0;
  size_t terms = m == VR_NK_SELLMEIER2 ? 2 : 1;
  for (size_t t = 0; t < terms; t++) {
    double den = L2 - p[2 * t + 1] * p[2 * t + 1];
    if (fabs(den) < 1e-12) return NAN;
    n2 += p[2 * t] * L2 / den;
  }
  n2 -= p[2 * terms] * L2;
  return n2 > 0 ? sqrt(n2) : NAN;
}

typedef struct smooth_ctx {
  vr_nk_model model;
  const vr_spectro_point_fit *pt;
  const size_t *use;
  size_t nuse;
} smooth_ctx;

static int smooth_residual(const double *p, double *res, double *jac, void *user) {
  (void)jac;
  const smooth_ctx *c = user;
  for (size_t i = 0; i < c->nuse; i++) {
    const vr_spectro_point_fit *q = &c->pt[c->use[i]];
    double n = model_n(c->model, p, q->nm);
    if (!isfinite(n)) return 1;
    res[i] = (n - q->n) / q->n_err;
  }
  return 0;
}

/* k at one wavelength from T alone for a pane of index n: T fixes the
 * internal transmittance a through T r² a² + (1 - r)² a - T = 0, and r
 * depends (weakly) on k, so two passes settle it. */
static double k_from_T(double T, double n, double d_nm, double nm) {
  /* T = 0 (opaque within the data's resolution): the k that leaves 1e-30. */
  if (!(T > 0)) return -nm * log(1e-30) / (4 * M_PI * d_nm);
  double k = 0;
  for (int pass = 0; pass < 3; pass++) {
    double r = ((n - 1) * (n - 1) + k * k) / ((n + 1) * (n + 1) + k * k);
    double b = (1 - r) * (1 - r);
    double a = (-b + sqrt(b * b + 4 * T * T * r * r)) / (2 * T * r * r);
    if (!(a > 0)) a = 1e-30;
    k = a >= 1 ? 0.0 : -nm * log(a) / (4 * M_PI * d_nm);
  }
  return k;
}

/* Step 1 at every wavelength of the first curve (others interpolated). */
static vr_status invert_points(const vr_spectro_data *d, double d_nm,
                               const vr_spectro_fit_options *o, vr_spectro_fit_result *r,
                               vr_error *err) {
  const vr_spectro_curve *c0 = &d->curves[0];
  vr_slab_obs *obs = malloc(d->ncurves * sizeof *obs);
  if (!obs) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_status st = VR_OK;
  for (size_t i = 0; i < c0->n && !st; i++) {
    vr_spectro_point_fit *q = &r->pt[i];
    q->nm = c0->p[i].nm;
    size_t nobs = 0;
    for (size_t j = 0; j < d->ncurves; j++) {
      const vr_spectro_curve *c = &d->curves[j];
      size_t at = 0;
      while (at < c->n && c->p[at].nm < q->nm - 1e-9) at++;
      if (at == c->n || fabs(c->p[at].nm - q->nm) > 1e-9) continue; /* not measured there */
      obs[nobs++] = (vr_slab_obs){c->angle_deg, c->p[at].T, c->p[at].Rf};
    }
    vr_slab_nk nk;
    double cond = 1;
    if (nobs == 1 && obs[0].angle_deg == 0) {
      st = vr_slab_invert_normal(obs[0].T, obs[0].R, d_nm, q->nm, &nk, err);
      q->n_err = hypot(nk.dn_dT * o->sigma_T, nk.dn_dR * o->sigma_R);
      q->k_err = hypot(nk.dk_dT * o->sigma_T, nk.dk_dR * o->sigma_R);
    } else {
      vr_error local;
      vr_status s2 = vr_slab_invert_angles(obs, nobs, d_nm, q->nm, o->sigma_T, o->sigma_R, &nk,
                                           &q->n_err, &q->k_err, &cond, &local);
      if (s2 == VR_E_NOMEM || s2 == VR_E_ARG) st = vr_error_set(err, s2, "%s", local.message);
      else if (s2) nk.flags = VR_SLAB_NO_ROOT;
    }
    if (st) break;
    q->n = nk.n;
    q->k = nk.k;
    q->flags = nk.flags;
    if ((q->flags & (VR_SLAB_NO_ROOT | VR_SLAB_NO_INDEX)) || !isfinite(q->n) ||
        !(q->n_err > 0) || q->n_err > VR_SPECTRO_MAX_SIGMA_N || cond > 1e6) {
      q->flags |= VR_SPECTRO_ILL;
      r->nill++;
    }
  }
  free(obs);
  return st;
}

static void model_names(vr_spectro_fit_result *r) {
  static const char *const S1[] = {"B1", "C1", "D"}, *const U1[] = {"", "um", "1/um2"};
  static const char *const S2[] = {"B1", "C1", "B2", "C2", "D"},
                           *const U2[] = {"", "um", "", "um", "1/um2"};
  static const char *const CA[] = {"A", "B", "C"}, *const UC[] = {"", "um2", "um4"};
  const char *const *n = r->model == VR_NK_CAUCHY ? CA : r->model == VR_NK_SELLMEIER2 ? S2 : S1;
  const char *const *u = r->model == VR_NK_CAUCHY ? UC : r->model == VR_NK_SELLMEIER2 ? U2 : U1;
  for (size_t i = 0; i < r->nparams; i++) {
    snprintf(r->names[i], sizeof r->names[i], "%s", n[i]);
    snprintf(r->units[i], sizeof r->units[i], "%s", u[i]);
  }
}

/* Step 2: the weighted dispersion fit and its covariance. */
static vr_status smooth(vr_spectro_fit_result *r, double *cov, vr_error *err) {
  size_t *use = malloc(r->n * sizeof *use), nuse = 0;
  if (!use) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double lo = INFINITY, hi = 0;
  for (size_t i = 0; i < r->n; i++)
    if (!(r->pt[i].flags & VR_SPECTRO_ILL)) {
      use[nuse++] = i;
      lo = fmin(lo, r->pt[i].nm);
      hi = fmax(hi, r->pt[i].nm);
    }
  size_t np = r->nparams;
  if (nuse <= np) {
    free(use);
    return vr_error_set(err, VR_E_NUMERIC,
                        "only %zu of %zu wavelengths invert cleanly, too few for a %zu-parameter "
                        "dispersion model (check the thickness and that T and R belong to an "
                        "uncoated pane)", nuse, r->n, np);
  }
  r->min_nm = lo;
  r->max_nm = hi;
  double *p = r->value;
  double shortest_um = lo * 1e-3;
  if (r->model == VR_NK_CAUCHY) {
    p[0] = 1.5, p[1] = 0.004, p[2] = 0;
  } else if (r->model == VR_NK_SELLMEIER) {
    p[0] = 1.2, p[1] = 0.1, p[2] = 0.01;
  } else {
    p[0] = 1.0, p[1] = 0.07, p[2] = 0.2, p[3] = 0.15, p[4] = 0.01;
  }
  smooth_ctx c = {r->model, r->pt, use, nuse};
  vr_lsq *lsq = vr_lsq_create(np, nuse, smooth_residual, &c, false, err);
  vr_status st = lsq ? VR_OK : (err ? err->status : VR_E_NOMEM);
  if (!st && r->model != VR_NK_CAUCHY) {
    /* Keep the ultraviolet poles below the data: C < 0.9 of the shortest
     * wavelength, B >= 0. */
    for (size_t t = 0; t < (r->model == VR_NK_SELLMEIER2 ? 2u : 1u) && !st; t++) {
      st = vr_lsq_set_bounds(lsq, 2 * t, 0.0, 20.0, err);
      if (!st) st = vr_lsq_set_bounds(lsq, 2 * t + 1, 1e-3, 0.9 * shortest_um, err);
      if (p[2 * t + 1] >= 0.9 * shortest_um) p[2 * t + 1] = 0.5 * shortest_um * (1 + 0.2 * t);
    }
  }
  vr_lsq_summary sum;
  if (!st) st = vr_lsq_solve(lsq, p, NULL, &sum, err);
  if (!st) {
    r->dof = (long)(nuse - np);
    r->chi2_reduced = sum.chi2 / (double)(nuse - np);
    st = vr_lsq_covariance(lsq, p, r->chi2_reduced > 1.0, cov, err);
    if (st) vr_error_prefix(err, "n model: ");
  }
  vr_lsq_destroy(lsq);
  free(use);
  if (st) return st;
  for (size_t i = 0; i < np; i++) r->stderr_[i] = sqrt(cov[i * np + i]);
  return VR_OK;
}

/* Standard error of the model's n at nm by the delta method. */
static double model_n_err(const vr_spectro_fit_result *r, const double *cov, double nm) {
  size_t np = r->nparams;
  double g[6], p[6];
  memcpy(p, r->value, np * sizeof *p);
  for (size_t i = 0; i < np; i++) {
    double h = 1e-6 * fmax(fabs(p[i]), 1e-4);
    double keep = p[i];
    p[i] = keep + h;
    double up = model_n(r->model, p, nm);
    p[i] = keep - h;
    double dn = model_n(r->model, p, nm);
    p[i] = keep;
    g[i] = (up - dn) / (2 * h);
  }
  double v = 0;
  for (size_t i = 0; i < np; i++)
    for (size_t j = 0; j < np; j++) v += g[i] * cov[i * np + j] * g[j];
  return sqrt(fmax(v, 0));
}

static void judge(vr_spectro_fit_result *r, const vr_spectro_data *d, double sigma);

vr_status vr_spectro_fit(const vr_spectro_data *d, double thickness_nm,
                         const vr_spectro_fit_options *opt, vr_spectro_fit_result *out,
                         vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_spectro_fit_options o = opt ? *opt : vr_spectro_fit_default_options();
  if (!(thickness_nm > 0) || !isfinite(thickness_nm))
    return vr_error_set(err, VR_E_ARG, "the pane's thickness is required (a positive number; "
                                       "give --thickness MM)");
  if (!(o.sigma_T > 0) || !(o.sigma_R > 0))
    return vr_error_set(err, VR_E_ARG, "photometric noise sigma_T, sigma_R must be positive");
  if (d->ncurves == 0 || d->curves[0].n == 0) return vr_error_set(err, VR_E_ARG, "no data");
  if (!d->has_Rf)
    return vr_error_set(err, VR_E_ARG, "%s: n and k need both T and R (no reflectance column)",
                        d->source);
  for (size_t j = 0; j < d->ncurves; j++)
    if (d->curves[j].state && (j == 0 || !d->curves[0].state ||
                               strcmp(d->curves[j].state, d->curves[0].state)))
      return vr_error_set(err, VR_E_ARG,
                          "%s holds several tint states; fit one state at a time (or use "
                          "vr-spectro chromogenic)", d->source);
  out->n = d->curves[0].n;
  out->model = o.model;
  out->nparams = model_params(o.model);
  out->thickness_nm = thickness_nm;
  model_names(out);
  out->pt = calloc(out->n, sizeof *out->pt);
  if (!out->pt) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  double *cov = out->covariance;
  vr_status st = invert_points(d, thickness_nm, &o, out, err);
  if (!st) st = smooth(out, cov, err);
  if (st) {
    vr_spectro_fit_free(out);
    return st;
  }
  const vr_spectro_curve *c0 = &d->curves[0];
  for (size_t i = 0; i < out->n; i++) {
    vr_spectro_point_fit *q = &out->pt[i];
    q->n_model = model_n(out->model, out->value, q->nm);
    q->n_model_err = model_n_err(out, cov, q->nm);
    /* T at normal incidence when the first curve is; otherwise the point
     * inversion's k already used every angle. */
    q->k_final = c0->angle_deg == 0 ? k_from_T(c0->p[i].T, q->n_model, thickness_nm, q->nm) : q->k;
  }
  judge(out, d, o.sigma_T);
  return VR_OK;
}

/* Step 4 (vr/spectro_fit.h): n_err is linear in sigma (sigma_T = sigma_R
 * here), so the chi-square with another sigma is a rescaling. */
static void judge(vr_spectro_fit_result *r, const vr_spectro_data *d, double sigma) {
  r->sigma_verdict = fmax(sigma, VR_SPECTRO_VERDICT_SIGMA);
  double scale = sigma / r->sigma_verdict;
  r->chi2_verdict = r->chi2_reduced * scale * scale;
  r->chi2_limit = gsl_cdf_chisq_Qinv(VR_SPECTRO_VERDICT_P, (double)r->dof) / (double)r->dof;
  r->describes = r->chi2_verdict <= r->chi2_limit;
  const vr_spectro_curve *c = &d->curves[0];
  for (size_t i = 0; i < c->n && d->has_Rb; i++)
    if (c->p[i].nm >= 380 && c->p[i].nm <= 780 && fabs(c->p[i].Rf - c->p[i].Rb) > 0.01)
      r->coated = true;
  snprintf(r->verdict, sizeof r->verdict,
           "%s: reduced chi-square %.3g with the measurement's sigma %.3g (limit %.3g, the "
           "upper %g%% point of chi-square for %ld degrees of freedom)%s",
           r->describes ? "describes the data" : "does NOT describe the data", r->chi2_verdict,
           r->sigma_verdict, r->chi2_limit, 100 * VR_SPECTRO_VERDICT_P, r->dof,
           r->describes ? ""
           : r->coated ? ": Rf and Rb differ, so the pane is coated, and a coating is no index "
                         "of the glass (fit the glass uncoated, or give its layers to btdf --stack)"
                       : ": the dispersion model cannot follow these T and R (coated pane, wrong "
                         "thickness, or a different --model?)");
}

double vr_spectro_fit_n(const vr_spectro_fit_result *r, double nm, double *n_err) {
  if (n_err) *n_err = model_n_err(r, r->covariance, nm);
  return model_n(r->model, r->value, nm);
}

vr_status vr_spectro_fit_material(const vr_spectro_fit_result *r, const char *name, bool forced,
                                  vr_material **out, vr_error *err) {
  *out = NULL;
  vr_material *m = vr_material_create(name, VR_KIND_DIELECTRIC, err);
  if (!m) return err ? err->status : VR_E_NOMEM;
  vr_formula *f = &m->n_formula;
  const double *p = r->value;
  if (r->model == VR_NK_CAUCHY) {
    /* refractiveindex.info formula 5: n = C1 + C2 l^C3 + C4 l^C5 */
    double c[] = {p[0], p[1], -2, p[2], -4};
    f->type = 5;
    f->ncoeffs = 5;
    memcpy(f->c, c, sizeof c);
  } else {
    /* formula 4: n² = C1 + C2 l^C3/(l² - C4^C5) + C6 l^C7/(l² - C8^C9) + C10 l^C11 */
    bool two = r->model == VR_NK_SELLMEIER2;
    double c[] = {1, p[0], 2, p[1], 2, two ? p[2] : 0, 2, two ? p[3] : 0, 2, -p[two ? 4 : 2], 2};
    f->type = 4;
    f->ncoeffs = 11;
    memcpy(f->c, c, sizeof c);
  }
  f->min_nm = r->min_nm;
  f->max_nm = r->max_nm;
  double *nm = malloc(r->n * sizeof *nm), *k = malloc(r->n * sizeof *k),
         *ke = malloc(r->n * sizeof *ke);
  vr_status st = nm && k && ke ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < r->n && !st; i++) {
    nm[i] = r->pt[i].nm;
    k[i] = fmax(r->pt[i].k_final, 0);
    ke[i] = isfinite(r->pt[i].k_err) ? r->pt[i].k_err : -1;
  }
  char model[128];
  snprintf(model, sizeof model, "%s n (weighted fit of the point inversion), k from T",
           r->model == VR_NK_CAUCHY ? "Cauchy" : r->model == VR_NK_SELLMEIER2 ? "two-pole Sellmeier" : "Sellmeier");
  vr_spectrum *ks = st ? NULL : vr_spectrum_create(r->n, nm, k, err);
  vr_spectrum *kes = ks ? vr_spectrum_create(r->n, nm, ke, err) : NULL;
  if (!ks || !kes) st = st ? st : (err ? err->status : VR_E_NOMEM);
  if (!st) st = vr_material_add_spectrum(m, "k", ks, err), ks = NULL;
  if (!st) st = vr_material_add_spectrum(m, "k_err", kes, err), kes = NULL;
  if (!st) st = vr_material_add_property(m, "thickness", NULL, r->thickness_nm * 1e-6, "mm", err);
  for (size_t i = 0; i < r->nparams && !st; i++)
    st = vr_material_add_parameter(m, r->names[i], p[i], r->stderr_[i], r->units[i][0] ? r->units[i] : NULL, err);
  if (!st) st = vr_material_set_text(&m->prov.model, model, err);
  if (!st) m->prov.residual = r->chi2_reduced;
  if (!st) st = vr_material_add_property(m, "fit_chi2_reduced", NULL, r->chi2_verdict, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_chi2_limit", NULL, r->chi2_limit, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_describes", NULL, r->describes ? 1 : 0, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_forced", NULL, forced ? 1 : 0, NULL, err);
  if (!st) {
    char note[480];
    snprintf(note, sizeof note, "verdict: %s%s", r->verdict,
             forced ? "; saved with --force" : "");
    st = vr_material_set_text(&m->prov.note, note, err);
  }
  vr_spectrum_destroy(ks);
  vr_spectrum_destroy(kes);
  free(nm);
  free(k);
  free(ke);
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  *out = m;
  return VR_OK;
}
