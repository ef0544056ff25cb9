/* Light spectra on the 1 nm grid: resolving references and scaling to the
 * scene's amounts (lights/spd.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lights/spd.h"
#include "vr/colour.h"
#include "vr/matdb.h"

#define UV_LO 300.0 /* the photochromic UV band, nm */

double vr_rspd_at(const vr_rspd *s, double nm) {
  if (!s->n) return 0.0;
  double x = nm - s->lo;
  if (x <= 0) return s->v[0];
  int i = (int)x;
  if (i >= s->n - 1) return s->v[s->n - 1];
  double f = x - i;
  return s->v[i] * (1 - f) + s->v[i + 1] * f;
}

void vr_rspd_free(vr_rspd *s) {
  free(s->v);
  s->v = NULL;
  s->n = 0;
}

double vr_rspd_integral(const vr_rspd *s, double lo, double hi) {
  double sum = 0;
  for (double nm = lo; nm <= hi + 1e-9; nm += 1.0)
    sum += vr_rspd_at(s, nm) * ((nm == lo || nm > hi - 0.5) ? 0.5 : 1.0);
  return sum;
}

/* K_m ∫ V S dλ over 360-830 nm, 1 nm steps: lumens per unit of S. */
static double luminous(const vr_rspd *s) {
  double sum = 0;
  for (int nm = 360; nm <= 830; nm++) {
    double xyz[3];
    vr_cmf_eval(VR_CIE1931_2DEG, nm, xyz);
    sum += xyz[1] * vr_rspd_at(s, nm) * ((nm == 360 || nm == 830) ? 0.5 : 1.0);
  }
  return VR_KM * sum;
}

vr_status vr_spd_resolve(const vr_spd_setup *u, const char *ref, const char *dflt,
                         const vr_scene_loc *loc, vr_rspd *out, vr_error *err) {
  vr_matdb *db = u->db;
  const char *name = ref ? ref : dflt;
  vr_spectrum *sp = NULL;
  vr_material *m = NULL;
  vr_status st = VR_OK;
  if (!strncmp(name, "db:", 3)) {
    if (!db)
      return vr_error_at(err, VR_E_NOT_FOUND, u->path, loc->line, loc->col,
                         "spectrum '%s' needs a material database", name);
    st = vr_matdb_load(db, name + 3, 0, &m, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld:%ld: spectrum '%s': ", u->path, loc->line, loc->col, name);
      return st;
    }
    const vr_spectrum *v = vr_material_spectrum(m, "value");
    if (!v) {
      vr_material_destroy(m);
      return vr_error_at(err, VR_E_ARG, u->path, loc->line, loc->col,
                         "spectrum '%s' is a %s material without a 'value' spectrum", name,
                         vr_kind_name(m->kind));
    }
    sp = vr_spectrum_copy(v, err);
    vr_material_destroy(m);
  } else if (!strncmp(name, "bb:", 3)) {
    sp = vr_illuminant_blackbody(strtod(name + 3, NULL), err);
  } else if (name[0] == '[') {
    sp = vr_scene_inline_spectrum(name, err); /* checked when the scene was read */
  } else {
    sp = vr_illuminant(name, err);
  }
  if (!sp) {
    vr_error_prefix(err, "%s:%ld:%ld: spectrum '%s': ", u->path, loc->line, loc->col, name);
    return err ? err->status : VR_E_ARG;
  }
  double lo = fmin(UV_LO, u->lmin), hi = fmax(830.0, u->lmax);
  out->lo = lo;
  out->n = (int)(hi - lo) + 1;
  out->v = malloc((size_t)out->n * sizeof *out->v);
  if (!out->v) {
    vr_spectrum_destroy(sp);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  for (int i = 0; i < out->n; i++) {
    double nm = lo + i;
    /* Zero outside the data: a light is not assumed to emit where its
     * spectrum was not measured. */
    out->v[i] = (nm < sp->nm[0] || nm > sp->nm[sp->n - 1])
                    ? 0.0
                    : fmax(0.0, vr_spectrum_eval(sp, nm, VR_INTERP_LINEAR));
  }
  vr_spectrum_destroy(sp);
  return VR_OK;
}

static void scale_spd(vr_rspd *s, double f) {
  for (int i = 0; i < s->n; i++) s->v[i] *= f;
}

vr_status vr_spd_normalise(const vr_spd_setup *u, vr_rspd *s, vr_quantity q, bool photometric,
                           const vr_scene_loc *loc, const char *what, vr_error *err) {
  double denom = photometric ? luminous(s) : vr_rspd_integral(s, u->lmin, u->lmax);
  if (!(denom > 0))
    return vr_error_at(err, VR_E_RANGE, u->path, loc->line, loc->col,
                       "%s: its spectrum has no %s power", what,
                       photometric ? "visible" : "in-range");
  scale_spd(s, q.value / denom);
  return VR_OK;
}

bool vr_unit_is_photometric(vr_light_unit u) {
  return u == VR_UNIT_LM || u == VR_UNIT_CD || u == VR_UNIT_LX || u == VR_UNIT_CD_M2;
}

