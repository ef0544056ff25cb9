/* What several light kinds share.  Only the kinds' own files include this;
 * their tables are registered in lights/kinds.def. */
#ifndef VR_LIGHTS_KINDS_H
#define VR_LIGHTS_KINDS_H

#include <math.h>

#include "lights/light.h"

/* Lamps (point and spot lights): intensity= in cd, lm, W or W/sr; required
 * unless a goniometric file gives the candelas. */
vr_status vr_lamp_parse_amount(const vr_scn_stmt *t, vr_scene_light *l, bool required);
/* Converts a lamp's amount to its on-axis spectral intensity, omega being
 * the solid-angle integral of its distribution over the on-axis value
 * (flux to intensity), and sets its power. */
vr_status vr_lamp_resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                          double omega, vr_error *err);
/* Next-event sample of a lamp whose relative intensity towards a unit
 * direction (from the lamp) is dist(l, d); inline so that each kind's
 * distribution is called directly (next-event estimation calls it for
 * every lamp at every vertex). */
static inline bool vr_lamp_sample_li(const vr_light *l, double (*dist)(const vr_light *, const double *),
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

/* A lamp's emission: a direction uniform in the cone of cos_max about
 * cone_axis (cos_max = -1: the sphere), weighted by dist; and its
 * next-event density, 0 (a point: no BSDF sample finds it). */
bool vr_lamp_sample_le(const vr_light *l, double (*dist)(const vr_light *, const double *),
                       const double cone_axis[3], double cos_max, const vr_rng_key *key,
                       vr_light_emission *out);
double vr_lamp_pdf_li(const vr_light *l, const double x[3], const double dir[3]);

#endif
