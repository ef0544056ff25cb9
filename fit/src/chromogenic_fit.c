/* Tint-state models from spectra at several states (vr/chromogenic_fit.h). */
#include "vr/chromogenic_fit.h"

#include <ctype.h>
#include <gsl/gsl_cdf.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/csv.h"
#include "vr/lsq.h"

#define T_DEFAULT_K 298.15

/* "25C" / "298.15K" / "298.15" -> kelvin. */
static int parse_temperature(const char *v, double *K) {
  char buf[32];
  size_t n = strlen(v);
  if (n == 0 || n >= sizeof buf) return -1;
  memcpy(buf, v, n + 1);
  double add = 0;
  if (buf[n - 1] == 'C' || buf[n - 1] == 'c') add = 273.15, buf[n - 1] = '\0';
  else if (buf[n - 1] == 'K' || buf[n - 1] == 'k') buf[n - 1] = '\0';
  double x;
  if (vr_parse_double(buf, &x)) return -1;
  *K = x + add;
  return *K > 0 ? 0 : -1;
}

vr_status vr_chromo_state_parse(const char *token, vr_chromo_state *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  out->T_K = T_DEFAULT_K;
  out->E = out->t = out->q = NAN;
  snprintf(out->label, sizeof out->label, "%s", token);
  if (!strchr(token, '=')) {
    char buf[64];
    snprintf(buf, sizeof buf, "%s", token);
    size_t n = strlen(buf);
    out->kind = VR_STATE_CHARGE;
    if (n > 6 && strcasecmp(buf + n - 6, "mC/cm2") == 0) buf[n - 6] = '\0';
    else if (n > 1 && (buf[n - 1] == 'V' || buf[n - 1] == 'v')) {
      out->kind = VR_STATE_VOLTAGE;
      buf[n - 1] = '\0';
    }
    if (vr_parse_double(buf, &out->q))
      return vr_error_set(err, VR_E_PARSE,
                          "state \"%s\": expected a charge density (12.5 or 12.5mC/cm2), a "
                          "voltage (-1.2V) or photochromic keys (E=40, t=60:E=40, fade=120:E=40)",
                          token);
    if (out->kind == VR_STATE_CHARGE && out->q < 0)
      return vr_error_set(err, VR_E_RANGE, "state \"%s\": a charge density is >= 0", token);
    return VR_OK;
  }
  char buf[128];
  snprintf(buf, sizeof buf, "%s", token);
  bool have_t = false, have_fade = false;
  for (char *save = NULL, *kv = strtok_r(buf, ":", &save); kv; kv = strtok_r(NULL, ":", &save)) {
    char *eq = strchr(kv, '=');
    if (!eq) return vr_error_set(err, VR_E_PARSE, "state \"%s\": \"%s\" is not key=value", token, kv);
    *eq = '\0';
    const char *v = eq + 1;
    double x;
    if (strcmp(kv, "T") == 0) {
      if (parse_temperature(v, &out->T_K))
        return vr_error_set(err, VR_E_PARSE, "state \"%s\": temperature \"%s\" (use 25C or 298K)",
                            token, v);
      continue;
    }
    if (vr_parse_double(v, &x) || x < 0)
      return vr_error_set(err, VR_E_PARSE, "state \"%s\": %s must be a number >= 0", token, kv);
    if (strcmp(kv, "E") == 0) out->E = x;
    else if (strcmp(kv, "t") == 0) out->t = x, have_t = true;
    else if (strcmp(kv, "fade") == 0) out->t = x, have_fade = true;
    else
      return vr_error_set(err, VR_E_PARSE, "state \"%s\": unknown key \"%s\" (E, t, fade, T)", token,
                          kv);
  }
  if (isnan(out->E))
    return vr_error_set(err, VR_E_PARSE, "state \"%s\": photochromic states need E=<UV W/m2>", token);
  if (have_t && have_fade)
    return vr_error_set(err, VR_E_PARSE, "state \"%s\": t and fade exclude each other", token);
  out->kind = have_t ? VR_STATE_ACTIVATION : have_fade ? VR_STATE_FADE : VR_STATE_STEADY;
  return VR_OK;
}

vr_status vr_chromo_states_parse(const char *list, vr_chromo_state **out, size_t *count,
                                 vr_error *err) {
  *out = NULL;
  *count = 0;
  size_t cap = 1;
  for (const char *p = list; *p; p++) cap += *p == ',';
  vr_chromo_state *s = calloc(cap, sizeof *s);
  char *copy = strdup(list);
  if (!s || !copy) {
    free(s);
    free(copy);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  vr_status st = VR_OK;
  size_t n = 0;
  for (char *save = NULL, *tok = strtok_r(copy, ",", &save); tok && !st;
       tok = strtok_r(NULL, ",", &save)) {
    while (isspace((unsigned char)*tok)) tok++;
    st = vr_chromo_state_parse(tok, &s[n++], err);
  }
  free(copy);
  if (!st && n == 0) st = vr_error_set(err, VR_E_ARG, "no states in \"%s\"", list);
  if (st) {
    free(s);
    return st;
  }
  *out = s;
  *count = n;
  return VR_OK;
}

void vr_chromo_fit_free(vr_chromo_fit_result *r) {
  if (!r) return;
  double *arrays[] = {r->nm, r->T0, r->dOD, r->dOD_err, r->dOD_ci90, r->Rf0, r->dRf, r->Rb0, r->dRb, r->s};
  for (size_t i = 0; i < sizeof arrays / sizeof arrays[0]; i++) free(arrays[i]);
  memset(r, 0, sizeof *r);
}

/* The fit's working data: OD and weights on one grid. */
typedef struct work {
  size_t ns, nl;
  const vr_chromo_state *st;
  double *od, *w;    /* ns x nl, row per spectrum; w = 1 / sigma_OD^2 */
  double *s;         /* ns */
  bool fit_a, fit_ea;
} work;

/* Per wavelength j, the weighted line od = c + s d through the spectra:
 * returns chi2 and fills c, d and var(d) (unscaled). */
static double line_fit(const work *w, const double *s, size_t j, double *c, double *d,
                       double *var_d) {
  double S = 0, Sx = 0, Sy = 0, Sxx = 0, Sxy = 0;
  for (size_t i = 0; i < w->ns; i++) {
    double wi = w->w[i * w->nl + j], y = w->od[i * w->nl + j];
    S += wi, Sx += wi * s[i], Sy += wi * y, Sxx += wi * s[i] * s[i], Sxy += wi * s[i] * y;
  }
  double det = S * Sxx - Sx * Sx;
  if (!(det > 0)) {
    *c = Sy / S;
    *d = 0;
    *var_d = INFINITY;
  } else {
    *d = (S * Sxy - Sx * Sy) / det;
    *c = (Sy - *d * Sx) / S;
    *var_d = S / det;
  }
  double chi2 = 0;
  for (size_t i = 0; i < w->ns; i++) {
    double r = w->od[i * w->nl + j] - (*c + *d * s[i]);
    chi2 += w->w[i * w->nl + j] * r * r;
  }
  return chi2;
}

/* States of the photochromic spectra for rates p = (ln a, ln b_ref, Ea J/mol). */
static void photo_states(const work *w, const double *p, double *s) {
  double a = exp(p[0]), bref = exp(p[1]), ea = p[2];
  for (size_t i = 0; i < w->ns; i++) {
    const vr_chromo_state *q = &w->st[i];
    double b = bref * exp(-(ea / VR_GAS_CONSTANT) * (1.0 / q->T_K - 1.0 / T_DEFAULT_K));
    double ss = a * q->E / (a * q->E + b);
    if (q->kind == VR_STATE_STEADY) s[i] = ss;
    else if (q->kind == VR_STATE_ACTIVATION) s[i] = ss * (1 - exp(-(a * q->E + b) * q->t));
    else s[i] = ss * exp(-b * q->t);
    if (!(q->E > 0) && q->kind != VR_STATE_FADE) s[i] = 0;
  }
}

static int photo_residual(const double *p, double *res, double *jac, void *user) {
  (void)jac;
  const work *w = user;
  if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) return 1;
  photo_states(w, p, w->s);
  for (size_t j = 0; j < w->nl; j++) {
    double c, d, v;
    line_fit(w, w->s, j, &c, &d, &v);
    for (size_t i = 0; i < w->ns; i++)
      res[i * w->nl + j] =
          (w->od[i * w->nl + j] - (c + d * w->s[i])) * sqrt(w->w[i * w->nl + j]);
  }
  return 0;
}

/* Rates by variable projection; fills r->params. */
static vr_status fit_photo(work *w, vr_chromo_fit_result *r, vr_error *err) {
  bool any_time = false, two_temps = false;
  for (size_t i = 0; i < w->ns; i++) {
    any_time |= w->st[i].kind != VR_STATE_STEADY;
    /* The same test as the stored domain's (vr/chromogenic.h): closer
     * temperatures are one, and cannot tell an activation energy. */
    two_temps |= fabs(w->st[i].T_K - w->st[0].T_K) > 2 * VR_CHROMO_T_SLACK_K;
  }
  /* Start: K = b/a near the middle of the irradiances, a = 1e-3 m2/(W s). */
  double emax = 0, tmin = INFINITY, tmax = -INFINITY;
  for (size_t i = 0; i < w->ns; i++) {
    emax = fmax(emax, w->st[i].E);
    tmin = fmin(tmin, w->st[i].T_K), tmax = fmax(tmax, w->st[i].T_K);
  }
  r->E_fit_max = emax, r->T_fit_min = tmin, r->T_fit_max = tmax;
  if (!(emax > 0))
    return vr_error_set(err, VR_E_ARG, "photochromic spectra need at least one state with E > 0");
  double a0 = any_time ? 1e-3 : 1.0;
  double p[3] = {log(a0), log(a0 * emax / 4), 0};
  size_t m = w->ns * w->nl;
  vr_lsq *lsq = vr_lsq_create(3, m, photo_residual, w, false, err);
  if (!lsq) return err ? err->status : VR_E_NOMEM;
  vr_status st = VR_OK;
  if (!any_time) st = vr_lsq_set_fixed(lsq, 0, true, err);
  if (!st && !two_temps) st = vr_lsq_set_fixed(lsq, 2, true, err);
  /* Ea in J/mol: steps relative to 1e4 J/mol, not to the start 0. */
  if (!st && two_temps) p[2] = 4e4;
  if (!st) st = vr_lsq_set_bounds(lsq, 0, log(1e-12), log(1e6), err);
  if (!st) st = vr_lsq_set_bounds(lsq, 1, log(1e-12), log(1e9), err);
  vr_lsq_summary sum;
  if (!st) st = vr_lsq_solve(lsq, p, NULL, &sum, err);
  size_t nfree = 1 + (any_time ? 1 : 0) + (two_temps ? 1 : 0);
  long dof = (long)m - 2 * (long)w->nl - (long)nfree;
  double cov[9];
  if (!st && dof <= 0)
    st = vr_error_set(err, VR_E_ARG, "%zu spectra are too few for the rates and a line per "
                                     "wavelength", w->ns);
  if (!st) {
    r->chi2_reduced = sum.chi2 / (double)dof;
    r->dof = dof;
    st = vr_lsq_covariance(lsq, p, false, cov, err);
    if (st) vr_error_prefix(err, "photochromic rates: ");
  }
  vr_lsq_destroy(lsq);
  if (st) return st;
  double scale = r->chi2_reduced, t = gsl_cdf_tdist_Pinv(0.95, (double)dof);
  double a = exp(p[0]), b = exp(p[1]);
  double sa = a * sqrt(cov[0] * scale), sb = b * sqrt(cov[4] * scale),
         se = sqrt(cov[8] * scale);
  /* K = b/a: var(ln K) = var(ln b) + var(ln a) - 2 cov. */
  double sk = (b / a) * sqrt(fmax((cov[4] + cov[0] - 2 * cov[1]) * scale, 0));
  r->nparams = 4;
  const struct {
    const char *n, *u;
    double v, e;
    bool fitted;
  } P[4] = {{"a", "m2/(W s)", any_time ? a : NAN, any_time ? sa : NAN, any_time},
            {"b_ref", "1/s", any_time ? b : NAN, any_time ? sb : NAN, any_time},
            {"Ea", "J/mol", p[2], two_temps ? se : NAN, two_temps},
            {"K_ref", "W/m2", b / a, sk, true}};
  for (int i = 0; i < 4; i++) {
    snprintf(r->params[i].name, sizeof r->params[i].name, "%s", P[i].n);
    snprintf(r->params[i].unit, sizeof r->params[i].unit, "%s", P[i].u);
    r->params[i].value = P[i].v;
    r->params[i].stderr_ = P[i].e;
    r->params[i].ci90 = t * P[i].e;
    r->params[i].fitted = P[i].fitted;
  }
  photo_states(w, p, w->s);
  return VR_OK;
}

/* Electrochromic states: charges scaled by the largest, or voltages by a
 * rank-one projection between the palest and the darkest spectrum. */
static vr_status electro_states(work *w, vr_chromo_fit_result *r, vr_error *err) {
  bool volt = w->st[0].kind == VR_STATE_VOLTAGE;
  if (!volt) {
    double qmax = 0;
    for (size_t i = 0; i < w->ns; i++) qmax = fmax(qmax, w->st[i].q);
    if (!(qmax > 0)) return vr_error_set(err, VR_E_ARG, "every charge density is 0: no colouring");
    for (size_t i = 0; i < w->ns; i++) w->s[i] = w->st[i].q / qmax;
    r->q_full = qmax;
    return VR_OK;
  }
  size_t lo = 0, hi = 0;
  double mlo = INFINITY, mhi = -INFINITY;
  for (size_t i = 0; i < w->ns; i++) {
    double mean = 0;
    for (size_t j = 0; j < w->nl; j++) mean += w->od[i * w->nl + j] / (double)w->nl;
    if (mean < mlo) mlo = mean, lo = i;
    if (mean > mhi) mhi = mean, hi = i;
  }
  if (lo == hi) return vr_error_set(err, VR_E_ARG, "the spectra do not differ: no colouring");
  for (size_t i = 0; i < w->ns; i++) {
    double num = 0, den = 0;
    for (size_t j = 0; j < w->nl; j++) {
      double diff = w->od[hi * w->nl + j] - w->od[lo * w->nl + j];
      num += w->w[i * w->nl + j] * (w->od[i * w->nl + j] - w->od[lo * w->nl + j]) * diff;
      den += w->w[i * w->nl + j] * diff * diff;
    }
    w->s[i] = fmin(fmax(num / den, 0.0), 1.0);
  }
  r->q_full = NAN;
  return VR_OK;
}

static vr_status grid_values(const vr_spectrum *s, const double *nm, size_t nl, size_t which,
                             const char *what, double *out, vr_error *err) {
  if (s->nm[0] > nm[0] + 1e-9 || s->nm[s->n - 1] < nm[nl - 1] - 1e-9)
    return vr_error_set(err, VR_E_RANGE,
                        "%s of spectrum %zu spans %g-%g nm and does not cover the first "
                        "spectrum's %g-%g nm", what, which + 1, s->nm[0], s->nm[s->n - 1], nm[0],
                        nm[nl - 1]);
  for (size_t j = 0; j < nl; j++) out[j] = vr_spectrum_eval(s, nm[j], VR_INTERP_LINEAR);
  return VR_OK;
}

/* Plain least-squares lines of a reflectance against s. */
static void r_lines(const double *R, const double *s, size_t ns, size_t nl, double *r0, double *dr) {
  double sm = 0, ss = 0;
  for (size_t i = 0; i < ns; i++) sm += s[i] / (double)ns;
  for (size_t i = 0; i < ns; i++) ss += (s[i] - sm) * (s[i] - sm);
  for (size_t j = 0; j < nl; j++) {
    double ym = 0, sy = 0;
    for (size_t i = 0; i < ns; i++) ym += R[i * nl + j] / (double)ns;
    for (size_t i = 0; i < ns; i++) sy += (s[i] - sm) * (R[i * nl + j] - ym);
    dr[j] = ss > 0 ? sy / ss : 0;
    r0[j] = ym - dr[j] * sm;
  }
}

vr_status vr_chromo_fit(size_t ns, const vr_chromo_state *states, const vr_spectrum *const *T,
                        const vr_spectrum *const *Rf, const vr_spectrum *const *Rb,
                        double sigma_T, vr_chromo_fit_result *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  out->E_fit_max = out->T_fit_min = out->T_fit_max = NAN;
  if (ns < 3)
    return vr_error_set(err, VR_E_ARG, "a state model needs spectra at 3 or more states (got %zu)", ns);
  if (!(sigma_T > 0)) return vr_error_set(err, VR_E_ARG, "sigma_T must be positive");
  bool photo = states[0].kind >= VR_STATE_STEADY;
  for (size_t i = 1; i < ns; i++) {
    bool p = states[i].kind >= VR_STATE_STEADY;
    if (p != photo || (!photo && states[i].kind != states[0].kind))
      return vr_error_set(err, VR_E_ARG,
                          "state \"%s\" and state \"%s\" are of different kinds (charges, voltages "
                          "and photochromic states cannot be mixed)", states[0].label, states[i].label);
  }
  out->type = photo ? VR_CHROMO_PHOTO : VR_CHROMO_ELECTRO;
  size_t nl = T[0]->n;
  out->nl = nl;
  out->ns = ns;
  work w = {.ns = ns, .nl = nl, .st = states};
  w.od = malloc(ns * nl * sizeof *w.od);
  w.w = malloc(ns * nl * sizeof *w.w);
  out->nm = malloc(nl * sizeof *out->nm);
  out->s = malloc(ns * sizeof *out->s);
  out->T0 = malloc(nl * sizeof(double));
  out->dOD = malloc(nl * sizeof(double));
  out->dOD_err = malloc(nl * sizeof(double));
  out->dOD_ci90 = malloc(nl * sizeof(double));
  double *tmp = malloc(nl * sizeof *tmp);
  vr_status st = (w.od && w.w && out->nm && out->s && out->T0 && out->dOD && out->dOD_err &&
                  out->dOD_ci90 && tmp) ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  if (!st) memcpy(out->nm, T[0]->nm, nl * sizeof *out->nm);
  w.s = out->s;
  for (size_t i = 0; i < ns && !st; i++) {
    st = grid_values(T[i], out->nm, nl, i, "T", tmp, err);
    for (size_t j = 0; j < nl && !st; j++) {
      /* T = 0 would be infinite OD: floor at the noise level. */
      double t = fmax(tmp[j], sigma_T);
      w.od[i * nl + j] = -log10(t);
      double s_od = sigma_T / (t * M_LN10);
      w.w[i * nl + j] = 1.0 / (s_od * s_od);
    }
  }
  if (!st) st = photo ? fit_photo(&w, out, err) : electro_states(&w, out, err);
  double chi2 = 0;
  for (size_t j = 0; j < nl && !st; j++) {
    double c, d, v;
    chi2 += line_fit(&w, out->s, j, &c, &d, &v);
    out->T0[j] = pow(10.0, -c);
    out->dOD[j] = d;
    out->dOD_err[j] = sqrt(v);
  }
  if (!st) {
    if (!photo) {
      out->dof = (long)(ns * nl) - 2 * (long)nl;
      out->chi2_reduced = chi2 / (double)out->dof;
      out->nparams = 0;
    }
    double t = gsl_cdf_tdist_Pinv(0.95, (double)out->dof);
    for (size_t j = 0; j < nl; j++) {
      out->dOD_err[j] *= sqrt(out->chi2_reduced);
      out->dOD_ci90[j] = t * out->dOD_err[j];
    }
  }
  /* Reflectances, when every spectrum has them. */
  const vr_spectrum *const *Rs[2] = {Rf, Rb};
  double **r0[2] = {&out->Rf0, &out->Rb0}, **dr[2] = {&out->dRf, &out->dRb};
  for (int side = 0; side < 2 && !st; side++) {
    bool all = Rs[side] != NULL;
    for (size_t i = 0; all && i < ns; i++) all = Rs[side][i] != NULL;
    if (!all) continue;
    double *R = malloc(ns * nl * sizeof *R);
    *r0[side] = malloc(nl * sizeof(double));
    *dr[side] = malloc(nl * sizeof(double));
    if (!R || !*r0[side] || !*dr[side]) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    for (size_t i = 0; i < ns && !st; i++)
      st = grid_values(Rs[side][i], out->nm, nl, i, side ? "Rb" : "Rf", R + i * nl, err);
    if (!st) r_lines(R, out->s, ns, nl, *r0[side], *dr[side]);
    free(R);
  }
  free(tmp);
  free(w.od);
  free(w.w);
  if (st) vr_chromo_fit_free(out);
  return st;
}

vr_status vr_chromo_fit_material(const vr_chromo_fit_result *r, const char *name,
                                 double thickness_mm, vr_material **out, vr_error *err) {
  *out = NULL;
  vr_material *m = vr_material_create(name, VR_KIND_CHROMOGENIC, err);
  if (!m) return err ? err->status : VR_E_NOMEM;
  bool ec = r->type == VR_CHROMO_ELECTRO;
  vr_status st = vr_material_add_property(m, "chromogenic_type", ec ? "electrochromic" : "photochromic",
                                          NAN, NULL, err);
  if (!st && thickness_mm > 0)
    st = vr_material_add_property(m, "thickness", NULL, thickness_mm, "mm", err);
  double *eta = malloc(r->nl * sizeof *eta);
  if (!eta && !st) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  const struct {
    const char *role;
    const double *v;
  } roles[] = {{"T0", r->T0}, {"dOD", r->dOD}, {"dOD_err", r->dOD_err}, {"eta", eta},
               {"Rf0", r->Rf0}, {"dRf", r->dRf}, {"Rb0", r->Rb0}, {"dRb", r->dRb}};
  bool have_eta = ec && isfinite(r->q_full);
  for (size_t j = 0; eta && j < r->nl; j++)
    eta[j] = have_eta ? r->dOD[j] / (r->q_full * 1e-3) : 0; /* cm2/C from mC/cm2 */
  for (size_t i = 0; i < sizeof roles / sizeof roles[0] && !st; i++) {
    if (!roles[i].v || (roles[i].v == eta && !have_eta)) continue;
    vr_spectrum *s = vr_spectrum_create(r->nl, r->nm, roles[i].v, err);
    st = s ? vr_material_add_spectrum(m, roles[i].role, s, err) : (err ? err->status : VR_E_NOMEM);
  }
  free(eta);
  if (!st && have_eta) st = vr_material_add_parameter(m, "Q_full", r->q_full, NAN, "mC/cm2", err);
  for (size_t i = 0; i < r->nparams && !st; i++) {
    const vr_chromo_param *p = &r->params[i];
    if (!isfinite(p->value) || (!p->fitted && strcmp(p->name, "K_ref") != 0)) continue;
    if (strcmp(p->name, "K_ref") == 0 && r->params[0].fitted) continue; /* a, b_ref say it */
    st = vr_material_add_parameter(m, p->name, p->value, p->stderr_, p->unit, err);
  }
  if (!st && !ec) st = vr_material_add_parameter(m, "T_ref", T_DEFAULT_K, NAN, "K", err);
  /* The domain the states span: evaluations outside it are refused. */
  if (!st && !ec && isfinite(r->E_fit_max))
    st = vr_material_add_parameter(m, "E_fit_max", r->E_fit_max, NAN, "W/m2", err);
  if (!st && !ec && isfinite(r->T_fit_min))
    st = vr_material_add_parameter(m, "T_fit_min", r->T_fit_min, NAN, "K", err);
  if (!st && !ec && isfinite(r->T_fit_max))
    st = vr_material_add_parameter(m, "T_fit_max", r->T_fit_max, NAN, "K", err);
  if (!st)
    st = vr_material_set_text(&m->prov.model,
                              ec ? "OD linear in state, s = Q/Q_full (coloration efficiency)"
                                 : "OD linear in state, ds/dt = a E (1-s) - b(T) s, Arrhenius b(T)",
                              err);
  if (!st) m->prov.residual = r->chi2_reduced;
  if (st) {
    vr_material_destroy(m);
    return st;
  }
  *out = m;
  return VR_OK;
}
