/* The sample model: its parameters, their storage, bounds and couplings,
 * and the optical constants of its layers (Ψ, Δ are in
 * ellipso_response.c). */
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
  if (p->owner == VR_OWNER_SAMPLE) switch (p->slot) {
      case VR_SLOT_AOI_OFFSET: return &m->aoi_offset_deg;
      case VR_SLOT_NONUNIFORMITY: return &m->nonuniformity_pct;
      case VR_SLOT_BANDWIDTH: return &m->bandwidth_nm;
      default: return &m->delta_offset_deg;
    }
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
  c->nonuniformity_pct = m->nonuniformity_pct;
  c->bandwidth_nm = m->bandwidth_nm;
  c->bandwidth_set = m->bandwidth_set;
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
  vr_status st = vr_model_apply_couplings((vr_sample_model *)m, err);
  return st ? st : vr_model_layer_index_coupled(m, i, nm, N, err);
}

vr_status vr_model_layer_index_coupled(const vr_sample_model *m, long i, double nm, vr_complex *N,
                                       vr_error *err) {
  vr_sample_model *mm = (vr_sample_model *)m;
  vr_complex eps;
  vr_status st;
  if (i == VR_OWNER_SUBSTRATE) st = memo_eps(m->substrate, &mm->substrate_memo, nm, &eps, err);
  else if (i == VR_OWNER_AMBIENT) st = memo_eps(m->ambient, &mm->ambient_memo, nm, &eps, err);
  else st = layer_eps(m, i, nm, &eps, err);
  if (!st) *N = vr_eps_to_index(eps);
  return st;
}

vr_status vr_model_apply_couplings(vr_sample_model *m, vr_error *err) {
  for (size_t i = 0; i < m->nparams; i++) {
    const vr_model_param *q = &m->params[i];
    if (!q->coupled_to) continue;
    double v = q->coef * vr_model_param_get(m, (size_t)(q->coupled_to - 1)) + q->offset;
    if ((q->slot == VR_SLOT_THICKNESS && q->owner != VR_OWNER_SAMPLE && v < 0) ||
        ((q->slot == VR_SLOT_NONUNIFORMITY || q->slot == VR_SLOT_BANDWIDTH) && v < 0) ||
        (q->slot == VR_SLOT_FRACTION && (v < 0 || v > 1)))
      return vr_error_set(err, VR_E_RANGE, "coupled parameter %s = %g is outside its domain (it follows %s)",
                          q->name, v, m->params[q->coupled_to - 1].name);
    *vr_model_param_value(m, i) = v;
  }
  return VR_OK;
}

