/* The sample model: its parameters, and Ψ, Δ through the core thin-film
 * solver, including an incoherent substrate whose back face reflects.
 *
 * Back side: with film-stack amplitudes r0 (from the ambient), t_down (into
 * the substrate), r_up and t_up (from inside the substrate back out), the
 * back-face coefficient r_b and the single-pass intensity attenuation a,
 * the j-th beam that comes out after j round trips has amplitude
 *   A_j = t_down r_b (r_up r_b)^(j-1) t_up  (times a phase common to s and p).
 * Thick substrates decorrelate the beams, so the detected intensities and the
 * p-s cross term add over j as geometric series:
 *   I_pp = |r0p|^2 + |g_p|^2 a^2 / (1 - |h_p|^2 a^2),
 *   X    = r0p r0s* + g_p g_s* a^2 / (1 - h_p h_s* a^2),
 * with g = t_down r_b t_up and h = r_up r_b.  tan Ψ = sqrt(I_pp / I_ss),
 * Δ = -arg X (Woollam's sign), depolarisation 1 - |X| / sqrt(I_pp I_ss). */
#include "model_internal.h"
#include "vr/ellipso_data.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void vr_model_destroy(vr_sample_model *m) {
  if (!m) return;
  vr_dispersion_destroy(m->ambient);
  vr_dispersion_destroy(m->substrate);
  for (size_t i = 0; i < m->nlayers; i++) {
    free(m->layers[i].name);
    vr_dispersion_destroy(m->layers[i].disp);
  }
  free(m->layers);
  for (size_t i = 0; i < m->nparams; i++) free(m->params[i].name);
  free(m->params);
  free(m->source);
  free(m);
}

static vr_dispersion *owner_disp(const vr_sample_model *m, long owner) {
  if (owner == VR_OWNER_AMBIENT) return m->ambient;
  if (owner == VR_OWNER_SUBSTRATE) return m->substrate;
  return m->layers[owner].disp;
}

double *vr_model_param_value(vr_sample_model *m, size_t i) {
  const vr_model_param *p = &m->params[i];
  if (p->owner == VR_OWNER_SAMPLE)
    return p->slot == VR_SLOT_AOI_OFFSET ? &m->aoi_offset_deg : &m->delta_offset_deg;
  if (p->slot == VR_SLOT_THICKNESS)
    return p->owner == VR_OWNER_SUBSTRATE ? &m->substrate_thickness_nm : &m->layers[p->owner].thickness_nm;
  if (p->slot == VR_SLOT_FRACTION) return &m->layers[p->owner].fraction;
  return vr_dispersion_params(owner_disp(m, p->owner)) + p->slot;
}

double vr_model_param_get(const vr_sample_model *m, size_t i) {
  return *vr_model_param_value((vr_sample_model *)m, i);
}

long vr_model_param_index(const vr_sample_model *m, const char *name) {
  for (size_t i = 0; i < m->nparams; i++)
    if (!strcmp(m->params[i].name, name)) return (long)i;
  return -1;
}

vr_sample_model *vr_model_copy(const vr_sample_model *m, vr_error *err) {
  vr_sample_model *c = calloc(1, sizeof *c);
  if (!c) goto nomem;
  c->substrate_thickness_nm = m->substrate_thickness_nm;
  c->backside = m->backside;
  c->aoi_offset_deg = m->aoi_offset_deg;
  c->delta_offset_deg = m->delta_offset_deg;
  if (m->source && !(c->source = strdup(m->source))) goto nomem;
  if (!(c->ambient = vr_dispersion_copy(m->ambient, err))) goto fail;
  if (!(c->substrate = vr_dispersion_copy(m->substrate, err))) goto fail;
  if (m->nlayers && !(c->layers = calloc(m->nlayers, sizeof *c->layers))) goto nomem;
  for (size_t i = 0; i < m->nlayers; i++) {
    c->layers[i] = m->layers[i];
    c->layers[i].name = NULL;
    c->layers[i].disp = NULL;
    c->nlayers = i + 1;
    if (!(c->layers[i].name = strdup(m->layers[i].name))) goto nomem;
    if (m->layers[i].disp && !(c->layers[i].disp = vr_dispersion_copy(m->layers[i].disp, err))) goto fail;
  }
  if (m->nparams && !(c->params = calloc(m->nparams, sizeof *c->params))) goto nomem;
  for (size_t i = 0; i < m->nparams; i++) {
    c->params[i] = m->params[i];
    c->params[i].name = NULL;
    c->nparams = i + 1;
    if (!(c->params[i].name = strdup(m->params[i].name))) goto nomem;
  }
  return c;
nomem:
  vr_error_set(err, VR_E_NOMEM, "out of memory");
fail:
  vr_model_destroy(c);
  return NULL;
}

vr_status vr_model_check(const vr_sample_model *m, vr_error *err) {
  for (size_t i = 0; i < m->nparams; i++) {
    const vr_model_param *p = &m->params[i];
    double v = vr_model_param_get(m, i);
    if (!isfinite(v)) return vr_error_set(err, VR_E_RANGE, "parameter %s is not finite", p->name);
    if (v < p->lower || v > p->upper)
      return vr_error_set(err, VR_E_RANGE, "parameter %s = %g lies outside its bounds [%g, %g]",
                          p->name, v, p->lower, p->upper);
    if (p->slot == VR_SLOT_THICKNESS && v < 0)
      return vr_error_set(err, VR_E_RANGE, "parameter %s: negative thickness %g nm", p->name, v);
    if (p->slot == VR_SLOT_FRACTION && (v < 0 || v > 1))
      return vr_error_set(err, VR_E_RANGE, "parameter %s: volume fraction %g outside [0, 1]", p->name, v);
  }
  return VR_OK;
}

/* ε of a dispersion, through the memo when it has no parameters. */
static vr_status memo_eps(const vr_dispersion *d, vr_eps_memo *memo, double nm, vr_complex *eps,
                          vr_error *err) {
  if (vr_dispersion_nparams(d) != 0) return vr_dispersion_eps(d, nm, eps, err);
  if (memo->nm == nm) {
    *eps = memo->eps;
    return VR_OK;
  }
  vr_status st = vr_dispersion_eps(d, nm, eps, err);
  if (!st) {
    memo->nm = nm;
    memo->eps = *eps;
  }
  return st;
}

static vr_status layer_eps(const vr_sample_model *m, long i, double nm, vr_complex *eps,
                           vr_error *err) {
  if (i < 0) {
    *eps = 1.0; /* void */
    return VR_OK;
  }
  vr_model_layer *L = &((vr_sample_model *)m)->layers[i];
  if (L->disp) return memo_eps(L->disp, &L->memo, nm, eps, err);
  vr_complex a, b;
  vr_status st = layer_eps(m, L->ema_a, nm, &a, err);
  if (!st) st = layer_eps(m, L->ema_b, nm, &b, err);
  if (st) return st;
  *eps = L->ema == VR_EMA_BRUGGEMAN ? vr_ema_bruggeman(a, b, L->fraction)
                                    : vr_ema_maxwell_garnett(a, b, L->fraction);
  return VR_OK;
}

vr_status vr_model_layer_index(const vr_sample_model *m, long i, double nm, vr_complex *N,
                               vr_error *err) {
  vr_sample_model *mm = (vr_sample_model *)m;
  vr_complex eps;
  vr_status st = vr_model_apply_couplings(mm, err);
  if (st) return st;
  if (i == VR_OWNER_SUBSTRATE) st = memo_eps(m->substrate, &mm->substrate_memo, nm, &eps, err);
  else if (i == VR_OWNER_AMBIENT) st = memo_eps(m->ambient, &mm->ambient_memo, nm, &eps, err);
  else st = layer_eps(m, i, nm, &eps, err);
  if (!st) *N = vr_eps_to_index(eps);
  return st;
}

#define MAX_STACK 64

static double abs2(vr_complex z) { return creal(z) * creal(z) + cimag(z) * cimag(z); }

static vr_status psi_delta(const vr_sample_model *m, double nm, double aoi_deg, double *psi,
                           double *delta, double *depol, vr_error *err);

vr_status vr_model_apply_couplings(vr_sample_model *m, vr_error *err) {
  for (size_t i = 0; i < m->nparams; i++) {
    const vr_model_param *q = &m->params[i];
    if (!q->coupled_to) continue;
    double v = q->coef * vr_model_param_get(m, (size_t)(q->coupled_to - 1)) + q->offset;
    if ((q->slot == VR_SLOT_THICKNESS && q->owner != VR_OWNER_SAMPLE && v < 0) ||
        (q->slot == VR_SLOT_FRACTION && (v < 0 || v > 1)))
      return vr_error_set(err, VR_E_RANGE, "coupled parameter %s = %g is outside its domain (it follows %s)",
                          q->name, v, m->params[q->coupled_to - 1].name);
    *vr_model_param_value(m, i) = v;
  }
  return VR_OK;
}

vr_status vr_model_psi_delta(const vr_sample_model *m, double nm, double aoi_deg, double *psi,
                             double *delta, double *depol, vr_error *err) {
  vr_status cs = vr_model_apply_couplings((vr_sample_model *)m, err);
  if (cs) return cs;
  double a = aoi_deg + m->aoi_offset_deg;
  if (!(a > 0 && a < 90))
    return vr_error_set(err, VR_E_RANGE, "at %g nm: angle %g deg + offset %g deg is outside (0, 90)", nm,
                        aoi_deg, m->aoi_offset_deg);
  vr_status st = psi_delta(m, nm, a, psi, delta, depol, err);
  if (!st && m->delta_offset_deg != 0) *delta = vr_delta_normalise(*delta + m->delta_offset_deg);
  return st;
}

static vr_status psi_delta(const vr_sample_model *m, double nm, double aoi_deg, double *psi,
                           double *delta, double *depol, vr_error *err) {
  size_t count = m->nlayers + 2;
  if (count > MAX_STACK) return vr_error_set(err, VR_E_ARG, "more than %d layers", MAX_STACK - 2);
  vr_layer L[MAX_STACK];
  vr_status st = vr_model_layer_index(m, VR_OWNER_AMBIENT, nm, &L[0].n, err);
  for (size_t i = 0; !st && i < m->nlayers; i++) {
    st = vr_model_layer_index(m, (long)i, nm, &L[i + 1].n, err);
    L[i + 1].thickness_nm = m->layers[i].thickness_nm;
    L[i + 1].incoherent = 0;
  }
  if (!st) st = vr_model_layer_index(m, VR_OWNER_SUBSTRATE, nm, &L[count - 1].n, err);
  if (st) return st;
  L[0].thickness_nm = L[count - 1].thickness_nm = 0;
  L[0].incoherent = L[count - 1].incoherent = 0;
  double theta = aoi_deg * M_PI / 180.0;
  if (depol) *depol = 0.0;
  if (!m->backside || !(m->substrate_thickness_nm > 0)) {
    st = vr_tmm_ellipsometry(L, count, theta, nm, psi, delta, NULL, err);
    if (st) vr_error_prefix(err, "at %g nm, %g deg: ", nm, aoi_deg);
    return st;
  }
  /* Film stack from above and from inside the substrate, then the back face. */
  vr_complex beta = L[0].n * sin(theta);
  vr_tmm_result down[2], up[2], back[2];
  vr_layer rev[MAX_STACK], bf[2] = {{L[count - 1].n, 0, 0}, {L[0].n, 0, 0}};
  for (size_t i = 0; i < count; i++) rev[i] = L[count - 1 - i];
  for (int p = 0; p < 2; p++) {
    if ((st = vr_tmm_coherent_beta(L, count, beta, nm, (vr_pol)p, &down[p], NULL, err)) ||
        (st = vr_tmm_coherent_beta(rev, count, beta, nm, (vr_pol)p, &up[p], NULL, err)) ||
        (st = vr_tmm_coherent_beta(bf, 2, beta, nm, (vr_pol)p, &back[p], NULL, err)))
      return st;
  }
  double im_q = cimag(vr_optics_q(L[count - 1].n, beta));
  double a = exp(-4.0 * M_PI * im_q * m->substrate_thickness_nm / nm); /* single pass */
  vr_complex g[2], h[2];
  for (int p = 0; p < 2; p++) {
    g[p] = down[p].t * back[p].r * up[p].t;
    h[p] = up[p].r * back[p].r;
  }
  double a2 = a * a;
  double Ipp = abs2(down[1].r) + abs2(g[1]) * a2 / (1.0 - abs2(h[1]) * a2);
  double Iss = abs2(down[0].r) + abs2(g[0]) * a2 / (1.0 - abs2(h[0]) * a2);
  vr_complex X = down[1].r * conj(down[0].r) + g[1] * conj(g[0]) * a2 / (1.0 - h[1] * conj(h[0]) * a2);
  if (!(Iss > 0)) return vr_error_set(err, VR_E_NUMERIC, "at %g nm: no s-polarised reflection", nm);
  *psi = atan(sqrt(Ipp / Iss)) * 180.0 / M_PI;
  double d = -carg(X) * 180.0 / M_PI;
  *delta = d < 0 ? d + 360.0 : d;
  if (depol) *depol = 1.0 - cabs(X) / sqrt(Ipp * Iss);
  return VR_OK;
}
