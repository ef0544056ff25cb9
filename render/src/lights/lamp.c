/* What point and spot lights share: their intensity= option, the
 * conversion of flux or intensity to an on-axis spectral intensity, and
 * next-event estimation towards a point source. */
#include <math.h>
#include <string.h>

#include "lights/kinds.h"
#include "vr/vec3.h"

static const vr_light_unit LAMP_UNITS[] = {VR_UNIT_CD, VR_UNIT_LM, VR_UNIT_W, VR_UNIT_W_SR,
                                           VR_UNIT_NONE};

vr_status vr_lamp_parse_amount(const vr_scn_stmt *t, vr_scene_light *l, bool required) {
  const vr_scn_opt *o = scn_get(t, "intensity");
  if (!o) return required ? scn_fail(t->p, t->w[0], "%s needs intensity=", t->what) : VR_OK;
  return scn_quantity(t->p, o->word, o->val, LAMP_UNITS, VR_UNIT_NONE, "an intensity", &l->amount);
}

vr_status vr_lamp_resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                          double omega, vr_error *err) {
  vr_quantity q = sl->amount;
  bool photo = vr_unit_is_photometric(q.unit);
  if (q.unit == VR_UNIT_LM || q.unit == VR_UNIT_W) q.value /= omega;
  vr_status st = vr_spd_normalise(&u->spd, &l->spd, q, photo, &sl->loc, "light", err);
  if (st) return st;
  l->power = vr_rspd_integral(&l->spd, u->spd.lmin, u->spd.lmax) * omega;
  return VR_OK;
}

double vr_lamp_pdf_li(const vr_light *l, const double x[3], const double dir[3]) {
  (void)l, (void)x, (void)dir;
  return 0;
}

bool vr_lamp_sample_le(const vr_light *l, double (*dist)(const vr_light *, const double *),
                       const double cone_axis[3], double cos_max, const vr_rng_key *key,
                       vr_light_emission *out) {
  vr_sample_cone(cone_axis, cos_max, vr_rng(key, VR_DIM_EMIT_U), vr_rng(key, VR_DIM_EMIT_V),
                 out->dir);
  out->pdf_dir = vr_cone_pdf(cos_max);
  out->f = dist(l, out->dir);
  out->weight = out->f / out->pdf_dir;
  memcpy(out->org, l->pos, sizeof out->org);
  memcpy(out->n, l->axis, sizeof out->n);
  out->pdf_pos = 1;
  return out->weight > 0;
}
