/* Tabulated dispersion from a stored material: what a model file's db:NAME
 * and file:PATH entries become.  A formula is sampled at 1 nm over its
 * range, so the fit sees the same n the database gives. */
#include "model_internal.h"

#include <math.h>
#include <stdlib.h>

vr_dispersion *vr_dispersion_from_material(const vr_material *m, vr_error *err) {
  const vr_spectrum *n = vr_material_spectrum(m, "n"), *k = vr_material_spectrum(m, "k");
  if (!m->n_formula.type) {
    if (!n) {
      vr_error_set(err, VR_E_ARG, "material '%s' (%s) has no refractive index", m->name,
                   vr_kind_name(m->kind));
      return NULL;
    }
    return vr_dispersion_tabulated(n, k, err);
  }
  double lo = m->n_formula.min_nm, hi = m->n_formula.max_nm;
  size_t count = (size_t)floor(hi - lo) + 1;
  if (count < 2) count = 2;
  vr_spectrum *ns = vr_spectrum_create_uniform(lo, (hi - lo) / (double)(count - 1), count, 0, err);
  if (!ns) return NULL;
  for (size_t i = 0; i < count; i++)
    if (vr_formula_eval(&m->n_formula, ns->nm[i], &ns->value[i], err)) {
      vr_spectrum_destroy(ns);
      return NULL;
    }
  vr_dispersion *d = vr_dispersion_tabulated(ns, k, err);
  vr_spectrum_destroy(ns);
  return d;
}
