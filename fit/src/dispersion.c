/* Dispersion models: the parameter vector with its names, the simple
 * closed-form kinds (constant, Cauchy, Sellmeier, tabulated), the dispatch
 * to the oscillator sum (oscillators.c) and the B-spline model
 * (bspline_kk.c), and the effective-medium mixing rules.  Evaluation only
 * reads the model, so one model may be evaluated from many threads. */
#include "dispersion_internal.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *kind_name(vr_disp_kind kind) {
  switch (kind) {
  case VR_DISP_CONSTANT: return "constant";
  case VR_DISP_CAUCHY: return "cauchy";
  case VR_DISP_SELLMEIER: return "sellmeier";
  case VR_DISP_SELLMEIER2: return "sellmeier2";
  case VR_DISP_GENOSC: return "genosc";
  case VR_DISP_BSPLINE: return "bspline";
  case VR_DISP_TABULATED: return "tabulated";
  }
  return "?";
}

/* ---- the parameter vector -------------------------------------------------- */

static vr_status append_param(vr_dispersion *d, const char *name, double value, vr_error *err) {
  double *p = realloc(d->p, (d->nparams + 1) * sizeof *p);
  if (!p) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", kind_name(d->kind));
  d->p = p;
  char(*names)[VR_PARAM_NAME_MAX] = realloc(d->names, (d->nparams + 1) * sizeof *names);
  if (!names) return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", kind_name(d->kind));
  d->names = names;
  d->p[d->nparams] = value;
  snprintf(d->names[d->nparams], VR_PARAM_NAME_MAX, "%s", name);
  d->nparams++;
  return VR_OK;
}

static vr_status append_params(vr_dispersion *d, size_t n, const char *const *names,
                               const double *values, vr_error *err) {
  for (size_t i = 0; i < n; i++) {
    vr_status st = append_param(d, names[i], values[i], err);
    if (st != VR_OK) return st;
  }
  return VR_OK;
}

vr_dispersion *vr_dispersion_create(vr_disp_kind kind, vr_error *err) {
  if (kind == VR_DISP_TABULATED) {
    vr_error_set(err, VR_E_ARG, "tabulated: create it with vr_dispersion_tabulated");
    return NULL;
  }
  if ((int)kind < 0 || kind > VR_DISP_TABULATED) {
    vr_error_set(err, VR_E_ARG, "dispersion: unknown kind %d", kind);
    return NULL;
  }
  vr_dispersion *d = calloc(1, sizeof *d);
  if (!d) {
    vr_error_set(err, VR_E_NOMEM, "dispersion: out of memory");
    return NULL;
  }
  d->kind = kind;
  vr_status st = VR_OK;
  switch (kind) {
  case VR_DISP_CONSTANT: {
    static const char *const names[] = {"n", "k"};
    static const double values[] = {1, 0};
    st = append_params(d, 2, names, values, err);
    break;
  }
  case VR_DISP_CAUCHY: {
    static const char *const names[] = {"A", "B", "C", "k_amp", "k_exp", "band_edge"};
    static const double values[] = {1.5, 0, 0, 0, 0, 0};
    st = append_params(d, 6, names, values, err);
    break;
  }
  case VR_DISP_SELLMEIER:
  case VR_DISP_SELLMEIER2: st = append_param(d, "A", 1, err); break;
  case VR_DISP_GENOSC:
  case VR_DISP_BSPLINE: st = append_param(d, "eps_inf", 1, err); break;
  case VR_DISP_TABULATED: break;
  }
  if (st != VR_OK) {
    vr_dispersion_destroy(d);
    return NULL;
  }
  return d;
}

vr_status vr_dispersion_add_term(vr_dispersion *d, vr_osc_kind osc, vr_error *err) {
  if (!d) return vr_error_set(err, VR_E_ARG, "dispersion: NULL model");
  char name[VR_PARAM_NAME_MAX];
  size_t term = d->nterms + 1;
  if (d->kind == VR_DISP_SELLMEIER || d->kind == VR_DISP_SELLMEIER2) {
    snprintf(name, sizeof name, "B%zu", term);
    vr_status st = append_param(d, name, 0, err);
    if (st != VR_OK) return st;
    snprintf(name, sizeof name, "C%zu", term);
    st = append_param(d, name, 0, err);
    if (st != VR_OK) return st;
    d->nterms = term;
    return VR_OK;
  }
  if (d->kind != VR_DISP_GENOSC)
    return vr_error_set(err, VR_E_ARG, "%s: terms are added to sellmeier and genosc models only",
                        kind_name(d->kind));
  size_t np = vr_osc_nparams(osc);
  if (np == 0) return vr_error_set(err, VR_E_ARG, "genosc: unknown oscillator kind %d", osc);
  vr_osc_kind *kinds = realloc(d->osc, term * sizeof *kinds);
  if (!kinds) return vr_error_set(err, VR_E_NOMEM, "genosc: out of memory");
  d->osc = kinds;
  size_t *off = realloc(d->off, term * sizeof *off);
  if (!off) return vr_error_set(err, VR_E_NOMEM, "genosc: out of memory");
  d->off = off;
  size_t first = d->nparams;
  double defaults[8];
  vr_osc_defaults(osc, defaults);
  for (size_t i = 0; i < np; i++) {
    snprintf(name, sizeof name, "%s%zu", vr_osc_param_base(osc, i), term);
    vr_status st = append_param(d, name, defaults[i], err);
    if (st != VR_OK) {
      d->nparams = first; /* drop a half-added term */
      return st;
    }
  }
  d->osc[term - 1] = osc;
  d->off[term - 1] = first;
  d->nterms = term;
  return VR_OK;
}

vr_status vr_dispersion_set_knots(vr_dispersion *d, size_t n, const double *energies_ev,
                                  vr_error *err) {
  if (!d || d->kind != VR_DISP_BSPLINE)
    return vr_error_set(err, VR_E_ARG, "%s: knots belong to bspline models",
                        d ? kind_name(d->kind) : "dispersion");
  if (n < 4 || !energies_ev)
    return vr_error_set(err, VR_E_ARG, "bspline: %zu knots given, a cubic needs >= 4", n);
  for (size_t i = 0; i < n; i++) {
    if (!isfinite(energies_ev[i]) || energies_ev[i] <= 0)
      return vr_error_set(err, VR_E_RANGE, "bspline: knot %zu = %g eV must be finite and > 0", i,
                          energies_ev[i]);
    if (i > 0 && !(energies_ev[i] > energies_ev[i - 1]))
      return vr_error_set(err, VR_E_ARG,
                          "bspline: knot %zu = %g eV does not increase from knot %zu = %g eV", i,
                          energies_ev[i], i - 1, energies_ev[i - 1]);
  }
  double *knots = malloc(n * sizeof *knots);
  if (!knots) return vr_error_set(err, VR_E_NOMEM, "bspline: out of memory");
  memcpy(knots, energies_ev, n * sizeof *knots);
  free(d->knots);
  d->knots = knots;
  d->nknots = n;
  d->nparams = 1; /* keep eps_inf, replace the knot values with zeros */
  char name[VR_PARAM_NAME_MAX];
  for (size_t i = 0; i < n; i++) {
    snprintf(name, sizeof name, "eps2_%zu", i + 1);
    vr_status st = append_param(d, name, 0, err);
    if (st != VR_OK) {
      d->nknots = 0;
      d->nparams = 1;
      return st;
    }
  }
  return VR_OK;
}

vr_dispersion *vr_dispersion_tabulated(const vr_spectrum *n, const vr_spectrum *k, vr_error *err) {
  if (!n) {
    vr_error_set(err, VR_E_ARG, "tabulated: the n spectrum is required");
    return NULL;
  }
  const vr_spectrum *tables[2] = {n, k};
  for (int t = 0; t < 2; t++) {
    const vr_spectrum *s = tables[t];
    for (size_t i = 0; s && i < s->n; i++)
      if (!(s->value[i] >= 0)) {
        vr_error_set(err, VR_E_RANGE, "tabulated: %s = %g at %g nm (sample %zu) must be >= 0",
                     t ? "k" : "n", s->value[i], s->nm[i], i);
        return NULL;
      }
  }
  vr_dispersion *d = calloc(1, sizeof *d);
  if (!d) {
    vr_error_set(err, VR_E_NOMEM, "tabulated: out of memory");
    return NULL;
  }
  d->kind = VR_DISP_TABULATED;
  d->tab_n = vr_spectrum_copy(n, err);
  if (d->tab_n && k) d->tab_k = vr_spectrum_copy(k, err);
  if (!d->tab_n || (k && !d->tab_k)) {
    vr_dispersion_destroy(d);
    return NULL;
  }
  return d;
}

static void *dup_array(const void *src, size_t bytes, int *failed) {
  if (!src || bytes == 0) return NULL;
  void *p = malloc(bytes);
  if (!p) *failed = 1;
  else memcpy(p, src, bytes);
  return p;
}

vr_dispersion *vr_dispersion_copy(const vr_dispersion *d, vr_error *err) {
  if (!d) {
    vr_error_set(err, VR_E_ARG, "dispersion: NULL model");
    return NULL;
  }
  vr_dispersion *c = calloc(1, sizeof *c);
  if (!c) {
    vr_error_set(err, VR_E_NOMEM, "dispersion: out of memory");
    return NULL;
  }
  *c = *d;
  int failed = 0;
  c->p = dup_array(d->p, d->nparams * sizeof *d->p, &failed);
  c->names = dup_array(d->names, d->nparams * sizeof *d->names, &failed);
  c->osc = dup_array(d->osc, d->nterms * sizeof *d->osc, &failed);
  c->off = dup_array(d->off, d->nterms * sizeof *d->off, &failed);
  c->knots = dup_array(d->knots, d->nknots * sizeof *d->knots, &failed);
  c->tab_n = c->tab_k = NULL;
  if (!failed && d->tab_n && !(c->tab_n = vr_spectrum_copy(d->tab_n, err))) failed = 2;
  if (!failed && d->tab_k && !(c->tab_k = vr_spectrum_copy(d->tab_k, err))) failed = 2;
  if (failed) {
    if (failed == 1) vr_error_set(err, VR_E_NOMEM, "dispersion: out of memory");
    vr_dispersion_destroy(c);
    return NULL;
  }
  return c;
}

void vr_dispersion_destroy(vr_dispersion *d) {
  if (!d) return;
  free(d->p);
  free(d->names);
  free(d->osc);
  free(d->off);
  free(d->knots);
  vr_spectrum_destroy(d->tab_n);
  vr_spectrum_destroy(d->tab_k);
  free(d);
}

vr_disp_kind vr_dispersion_kind(const vr_dispersion *d) { return d->kind; }
size_t vr_dispersion_nparams(const vr_dispersion *d) { return d ? d->nparams : 0; }

const char *vr_dispersion_param_name(const vr_dispersion *d, size_t i) {
  return d && i < d->nparams ? d->names[i] : NULL;
}

long vr_dispersion_param_index(const vr_dispersion *d, const char *name) {
  if (!d || !name) return -1;
  for (size_t i = 0; i < d->nparams; i++)
    if (strcmp(d->names[i], name) == 0) return (long)i;
  return -1;
}

double *vr_dispersion_params(vr_dispersion *d) { return d ? d->p : NULL; }
const double *vr_dispersion_params_const(const vr_dispersion *d) { return d ? d->p : NULL; }

/* ---- the closed-form kinds --------------------------------------------------- */

static vr_status range_param(const vr_dispersion *d, size_t i, const char *must, vr_error *err) {
  return vr_error_set(err, VR_E_RANGE, "%s: %s = %g must be %s", kind_name(d->kind), d->names[i],
                      d->p[i], must);
}

/* N for the kinds defined through n and k. */
static vr_status index_direct(const vr_dispersion *d, double nm, vr_complex *N, vr_error *err) {
  const double *p = d->p;
  double n = 0, k = 0;
  switch (d->kind) {
  case VR_DISP_CONSTANT:
    if (!(p[0] >= 0)) return range_param(d, 0, ">= 0", err);
    if (!(p[1] >= 0)) return range_param(d, 1, ">= 0", err);
    n = p[0];
    k = p[1];
    break;
  case VR_DISP_CAUCHY: {
    /* n = A + B/λ² + C/λ⁴ (λ in µm), k = k_amp exp(k_exp (E - band_edge)). */
    if (!(p[3] >= 0)) return range_param(d, 3, ">= 0", err);
    double l2 = (nm / 1000) * (nm / 1000);
    n = p[0] + p[1] / l2 + p[2] / (l2 * l2);
    k = p[3] == 0 ? 0 : p[3] * exp(p[4] * (VR_HC_EV_NM / nm - p[5]));
    if (!(n > 0))
      return vr_error_set(err, VR_E_RANGE, "cauchy: n = %g at %g nm is not positive", n, nm);
    break;
  }
  case VR_DISP_TABULATED: {
    const vr_spectrum *tn = d->tab_n, *tk = d->tab_k;
    const vr_spectrum *bad = !vr_spectrum_covers(tn, nm, nm) ? tn
                             : tk && !vr_spectrum_covers(tk, nm, nm) ? tk
                                                                     : NULL;
    if (bad)
      return vr_error_set(err, VR_E_RANGE, "tabulated: %g nm is outside the %s table (%g-%g nm)",
                          nm, bad == tn ? "n" : "k", bad->nm[0], bad->nm[bad->n - 1]);
    /* The toolchain's rule for n, k tables (vr/spectrum.h). */
    n = vr_spectrum_eval(tn, nm, VR_NK_INTERP);
    k = tk ? vr_spectrum_eval(tk, nm, VR_NK_INTERP) : 0;
    break;
  }
  default: return vr_error_set(err, VR_E_ARG, "%s: not an n,k model", kind_name(d->kind));
  }
  *N = CMPLX(n, k);
  return VR_OK;
}

/* n² = A + Σ B_i λ² / (λ² - C_i²) (sellmeier, C in µm) or
 * Σ B_i λ² / (λ² - C_i) (sellmeier2, C in µm², the SCHOTT catalogue form). */
static vr_status sellmeier_eps(const vr_dispersion *d, double nm, vr_complex *eps, vr_error *err) {
  double l2 = (nm / 1000) * (nm / 1000);
  double n2 = d->p[0];
  for (size_t t = 0; t < d->nterms; t++) {
    double B = d->p[1 + 2 * t], C = d->p[2 + 2 * t];
    double pole = d->kind == VR_DISP_SELLMEIER ? C * C : C;
    double den = l2 - pole;
    if (fabs(den) <= 64 * DBL_EPSILON * l2)
      return vr_error_set(err, VR_E_NUMERIC,
                          "%s: %g nm is on the pole of term %zu (C%zu = %g %s)", kind_name(d->kind),
                          nm, t + 1, t + 1, C, d->kind == VR_DISP_SELLMEIER ? "um" : "um^2");
    n2 += B * l2 / den;
  }
  if (!(n2 > 0))
    return vr_error_set(err, VR_E_RANGE, "%s: n^2 = %g at %g nm is not positive",
                        kind_name(d->kind), n2, nm);
  *eps = n2;
  return VR_OK;
}

static vr_status genosc_eps(const vr_dispersion *d, double nm, vr_complex *eps, vr_error *err) {
  double E = VR_HC_EV_NM / nm;
  vr_complex sum = d->p[0];
  for (size_t t = 0; t < d->nterms; t++) {
    const double *p = d->p + d->off[t];
    vr_status st = vr_osc_check(d->osc[t], p, t + 1, err);
    if (st != VR_OK) return st;
    vr_complex term;
    st = vr_osc_eps(d->osc[t], p, E, &term, err);
    if (st != VR_OK) {
      vr_error_prefix(err, "genosc term %zu at %g nm: ", t + 1, nm);
      return st;
    }
    sum += term;
  }
  *eps = sum;
  return VR_OK;
}

static vr_status check_nm(const vr_dispersion *d, double nm, vr_error *err) {
  if (!d) return vr_error_set(err, VR_E_ARG, "dispersion: NULL model");
  if (!(nm > 0) || !isfinite(nm))
    return vr_error_set(err, VR_E_ARG, "%s: wavelength %g nm must be finite and > 0",
                        kind_name(d->kind), nm);
  return VR_OK;
}

static vr_status finite_or_error(const vr_dispersion *d, double nm, vr_complex v, vr_error *err) {
  if (isfinite(creal(v)) && isfinite(cimag(v))) return VR_OK;
  return vr_error_set(err, VR_E_NUMERIC, "%s: the result at %g nm is not finite",
                      kind_name(d->kind), nm);
}

vr_status vr_dispersion_eps(const vr_dispersion *d, double nm, vr_complex *eps, vr_error *err) {
  vr_status st = check_nm(d, nm, err);
  if (st != VR_OK) return st;
  vr_complex e = 0;
  switch (d->kind) {
  case VR_DISP_CONSTANT:
  case VR_DISP_CAUCHY:
  case VR_DISP_TABULATED: {
    vr_complex N;
    st = index_direct(d, nm, &N, err);
    e = N * N;
    break;
  }
  case VR_DISP_SELLMEIER:
  case VR_DISP_SELLMEIER2: st = sellmeier_eps(d, nm, &e, err); break;
  case VR_DISP_GENOSC: st = genosc_eps(d, nm, &e, err); break;
  case VR_DISP_BSPLINE: st = vr_bspline_eps(d, VR_HC_EV_NM / nm, &e, err); break;
  }
  if (st == VR_OK) st = finite_or_error(d, nm, e, err);
  if (st == VR_OK) *eps = e;
  return st;
}

vr_status vr_dispersion_index(const vr_dispersion *d, double nm, vr_complex *N, vr_error *err) {
  vr_status st = check_nm(d, nm, err);
  if (st != VR_OK) return st;
  vr_complex n;
  if (d->kind == VR_DISP_CONSTANT || d->kind == VR_DISP_CAUCHY || d->kind == VR_DISP_TABULATED) {
    st = index_direct(d, nm, &n, err);
  } else {
    vr_complex e;
    st = vr_dispersion_eps(d, nm, &e, err);
    n = st == VR_OK ? vr_eps_to_index(e) : 0;
  }
  if (st == VR_OK) st = finite_or_error(d, nm, n, err);
  if (st == VR_OK) *N = n;
  return st;
}

vr_complex vr_eps_to_index(vr_complex eps) {
  /* csqrt honours the sign of a zero imaginary part: csqrt(-4 - 0i) = -2i.
   * A lossless ε is taken with +0 so that a metal-like ε < 0 gives k > 0. */
  if (cimag(eps) == 0) eps = CMPLX(creal(eps), 0.0);
  return csqrt(eps);
}

/* ---- effective-medium approximations --------------------------------------- */

/* The two roots of 2e² - b e - ea eb = 0, b = (3f - 1) eb + (2 - 3f) ea, which
 * is the Bruggeman condition f (eb - e)/(eb + 2e) + (1 - f)(ea - e)/(ea + 2e) = 0
 * multiplied out (Bruggeman, Ann. Phys. 416, 636 (1935); Aspnes, Thin Solid
 * Films 89, 249 (1982)).  The larger root comes from the sum that does not
 * cancel and the other from the product of the roots, -ea eb / 2. */
static void bruggeman_roots(vr_complex ea, vr_complex eb, double f, vr_complex r[2]) {
  vr_complex b = (3 * f - 1) * eb + (2 - 3 * f) * ea;
  vr_complex s = csqrt(b * b + 8 * ea * eb);
  if (creal(conj(b) * s) < 0) s = -s;
  r[0] = (b + s) / 4;
  r[1] = r[0] != 0 ? -ea * eb / (2 * r[0]) : 0;
}

static vr_complex nearest(const vr_complex r[2], vr_complex to) {
  return cabs(r[0] - to) <= cabs(r[1] - to) ? r[0] : r[1];
}

vr_complex vr_ema_bruggeman(vr_complex eps_a, vr_complex eps_b, double f) {
  if (!(f >= 0 && f <= 1)) return CMPLX(NAN, NAN);
  if (f == 0) return eps_a;
  if (f == 1) return eps_b;
  vr_complex r[2];
  bruggeman_roots(eps_a, eps_b, f, r);
  /* A passive mixture has Im e >= 0; when only one root is passive it is
   * the answer. */
  double tol = 1e-12 * (cabs(r[0]) + cabs(r[1]));
  int ok0 = cimag(r[0]) >= -tol, ok1 = cimag(r[1]) >= -tol;
  if (ok0 != ok1) return ok0 ? r[0] : r[1];
  /* Both (lossless components) or neither: follow the root that starts at
   * ea for f = 0 as f grows, which is the physical branch. */
  enum { STEPS = 64 };
  vr_complex e = eps_a;
  for (int i = 1; i <= STEPS; i++) {
    bruggeman_roots(eps_a, eps_b, f * i / STEPS, r);
    e = nearest(r, e);
  }
  return e;
}

/* Maxwell Garnett, Phil. Trans. R. Soc. A 203, 385 (1904): spherical
 * inclusions of eps_incl at volume fraction f in eps_host. */
vr_complex vr_ema_maxwell_garnett(vr_complex eps_host, vr_complex eps_incl, double f) {
  if (!(f >= 0 && f <= 1)) return CMPLX(NAN, NAN);
  vr_complex dh = eps_incl - eps_host;
  return eps_host * (eps_incl + 2 * eps_host + 2 * f * dh) / (eps_incl + 2 * eps_host - f * dh);
}
