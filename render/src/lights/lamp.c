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
                       const double cone_axis[3], double cos_max, const double un[5],
                       vr_light_emission *out) {
  vr_sample_cone(cone_axis, cos_max, un[0], un[1], out->dir);
  out->pdf_dir = vr_cone_pdf(cos_max);
  out->f = dist(l, out->dir);
  out->weight = out->f / out->pdf_dir;
  memcpy(out->org, l->pos, sizeof out->org);
  memcpy(out->n, l->axis, sizeof out->n);
  out->pdf_pos = 1;
  return out->weight > 0;
}

bool vr_lamp_sample_li(const vr_light *l, double (*dist)(const vr_light *, const double *),
                       const double x[3], int nwl, const double *wl, vr_light_sample *out) {
  out->delta = true;
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = l->pos[a] - x[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) {
    out->dir[a] = d[a] / r;
    out->p[a] = l->pos[a];
    out->n[a] = l->axis[a];
  }
  out->pdf_pos = 1;
  out->dist = r;
  double from_light[3] = {-out->dir[0], -out->dir[1], -out->dir[2]};
  double f = dist(l, from_light) / r2;
  if (!(f > 0)) return false;
  for (int k = 0; k < nwl; k++) out->L[k] = vr_rspd_at(&l->spd, wl[k]) * f;
  return true;
}
