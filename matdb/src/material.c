/* The in-memory material: construction, ownership, and evaluation of n, k
 * and tabulated values with the range rules of vr/material.h. */
#include "vr/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static const char *const KIND_NAMES[VR_KIND_COUNT] = {
    "dielectric", "conductor", "layered", "reflectance", "btdf",
    "chromogenic", "illuminant", "camera", "glazing"};

const char *vr_kind_name(vr_material_kind kind) {
  return (unsigned)kind < VR_KIND_COUNT ? KIND_NAMES[kind] : "unknown";
}

vr_status vr_kind_parse(const char *text, vr_material_kind *kind, vr_error *err) {
  for (int i = 0; i < VR_KIND_COUNT; i++)
    if (!strcasecmp(text, KIND_NAMES[i])) {
      *kind = (vr_material_kind)i;
      return VR_OK;
    }
  return vr_error_set(err, VR_E_NOT_FOUND,
                      "unknown material kind '%s' (dielectric, conductor, layered, reflectance, "
                      "btdf, chromogenic, illuminant, camera, glazing)",
                      text);
}

static char *dup_or_null(const char *s) { return s ? strdup(s) : NULL; }

vr_material *vr_material_create(const char *name, vr_material_kind kind, vr_error *err) {
  vr_material *m = calloc(1, sizeof *m);
  if (!m || !(m->name = strdup(name))) {
    free(m);
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  m->kind = kind;
  m->prov.residual = NAN;
  return m;
}

void vr_material_destroy(vr_material *m) {
  if (!m) return;
  free(m->name);
  free(m->description);
  for (size_t i = 0; i < m->nspectra; i++) {
    free(m->spectra[i].role);
    vr_spectrum_destroy(m->spectra[i].s);
  }
  free(m->spectra);
  for (size_t i = 0; i < m->nprops; i++) {
    free(m->props[i].key);
    free(m->props[i].text);
    free(m->props[i].unit);
  }
  free(m->props);
  for (size_t i = 0; i < m->nparams; i++) {
    free(m->params[i].name);
    free(m->params[i].unit);
  }
  free(m->params);
  free(m->prov.source_path);
  free(m->prov.tool);
  free(m->prov.tool_version);
  free(m->prov.model);
  free(m->prov.reference);
  free(m->prov.note);
  free(m);
}

vr_status vr_material_set_text(char **field, const char *text, vr_error *err) {
  char *copy = dup_or_null(text);
  if (text && !copy) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  free(*field);
  *field = copy;
  return VR_OK;
}

vr_status vr_material_add_spectrum(vr_material *m, const char *role, vr_spectrum *s, vr_error *err) {
  for (size_t i = 0; i < m->nspectra; i++)
    if (!strcmp(m->spectra[i].role, role)) {
      vr_spectrum_destroy(s);
      return vr_error_set(err, VR_E_ARG, "material '%s' already has a '%s' spectrum", m->name, role);
    }
  vr_role_spectrum *p = realloc(m->spectra, (m->nspectra + 1) * sizeof *p);
  char *r = strdup(role);
  if (!p || !r) {
    if (p) m->spectra = p;
    free(r);
    vr_spectrum_destroy(s);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  m->spectra = p;
  m->spectra[m->nspectra++] = (vr_role_spectrum){r, s};
  return VR_OK;
}

vr_status vr_material_add_property(vr_material *m, const char *key, const char *text, double value,
                                   const char *unit, vr_error *err) {
  vr_property *p = realloc(m->props, (m->nprops + 1) * sizeof *p);
  if (!p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  m->props = p;
  vr_property q = {strdup(key), dup_or_null(text), value, dup_or_null(unit)};
  if (!q.key || (text && !q.text) || (unit && !q.unit)) {
    free(q.key);
    free(q.text);
    free(q.unit);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  m->props[m->nprops++] = q;
  return VR_OK;
}

vr_status vr_material_add_parameter(vr_material *m, const char *name, double value, double se,
                                    const char *unit, vr_error *err) {
  vr_parameter *p = realloc(m->params, (m->nparams + 1) * sizeof *p);
  if (!p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  m->params = p;
  vr_parameter q = {strdup(name), value, se, dup_or_null(unit)};
  if (!q.name || (unit && !q.unit)) {
    free(q.name);
    free(q.unit);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  m->params[m->nparams++] = q;
  return VR_OK;
}

const vr_spectrum *vr_material_spectrum(const vr_material *m, const char *role) {
  for (size_t i = 0; i < m->nspectra; i++)
    if (!strcmp(m->spectra[i].role, role)) return m->spectra[i].s;
  return NULL;
}

const vr_property *vr_material_property(const vr_material *m, const char *key) {
  for (size_t i = 0; i < m->nprops; i++)
    if (!strcasecmp(m->props[i].key, key)) return &m->props[i];
  return NULL;
}

static void span(const vr_spectrum *s, double *lo, double *hi) {
  *lo = s->nm[0];
  *hi = s->nm[s->n - 1];
}

vr_status vr_material_nk_range(const vr_material *m, double *lo, double *hi, vr_error *err) {
  const vr_spectrum *n = vr_material_spectrum(m, "n"), *k = vr_material_spectrum(m, "k");
  if (m->n_formula.type) {
    *lo = m->n_formula.min_nm;
    *hi = m->n_formula.max_nm;
  } else if (n) {
    span(n, lo, hi);
  } else {
    return vr_error_set(err, VR_E_NOT_FOUND, "material '%s' (%s) has no refractive index", m->name,
                        vr_kind_name(m->kind));
  }
  if (k) {
    double a, b;
    span(k, &a, &b);
    if (a > *lo) *lo = a;
    if (b < *hi) *hi = b;
    if (*lo > *hi)
      return vr_error_set(err, VR_E_RANGE, "material '%s': the n and k ranges do not overlap",
                          m->name);
  }
  return VR_OK;
}

vr_status vr_material_nk(const vr_material *m, double nm, bool allow, double *n, double *k,
                         bool *extrapolated, vr_error *err) {
  double lo, hi;
  vr_status st = vr_material_nk_range(m, &lo, &hi, err);
  if (st) return st;
  if (!isfinite(nm)) return vr_error_set(err, VR_E_ARG, "wavelength is not finite");
  bool out = nm < lo || nm > hi;
  if (extrapolated) *extrapolated = out;
  if (out && !allow)
    return vr_error_set(err, VR_E_RANGE,
                        "material '%s': %g nm is outside its data range %g-%g nm (allow "
                        "extrapolation explicitly to hold the end values)",
                        m->name, nm, lo, hi);
  double x = nm < lo ? lo : (nm > hi ? hi : nm);
  if (m->n_formula.type) {
    if ((st = vr_formula_eval(&m->n_formula, x, n, err))) return st;
  } else {
    *n = vr_spectrum_eval(vr_material_spectrum(m, "n"), x, VR_NK_INTERP);
  }
  const vr_spectrum *ks = vr_material_spectrum(m, "k");
  *k = ks ? vr_spectrum_eval(ks, x, VR_NK_INTERP) : 0.0;
  return VR_OK;
}

vr_status vr_material_eval(const vr_material *m, const char *role, double nm, bool allow,
                           double *value, bool *extrapolated, vr_error *err) {
  const vr_spectrum *s = vr_material_spectrum(m, role);
  if (!s)
    return vr_error_set(err, VR_E_NOT_FOUND, "material '%s' (%s) has no '%s' data", m->name,
                        vr_kind_name(m->kind), role);
  if (!isfinite(nm)) return vr_error_set(err, VR_E_ARG, "wavelength is not finite");
  bool out = !vr_spectrum_covers(s, nm, nm);
  if (extrapolated) *extrapolated = out;
  if (out && !allow)
    return vr_error_set(err, VR_E_RANGE,
                        "material '%s': %g nm is outside its '%s' data range %g-%g nm", m->name, nm,
                        role, s->nm[0], s->nm[s->n - 1]);
  *value = vr_spectrum_eval(s, nm, VR_INTERP_LINEAR);
  return VR_OK;
}
