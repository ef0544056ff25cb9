/* Emissive surfaces (objects with emission=) as lights: their spectra in
 * radiometric units, and next-event estimation of one of them chosen by
 * power over squared distance.
 *
 * An emitter emits from its front side (along its normal) with uniform
 * radiance; its point for a sample is uniform by area. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lights/lights.h"
#include "vr/vec3.h"

/* The bounding sphere (centre of the bounding box, half its diagonal) of
 * an emissive object, from the replicated tables. */
static void bounds(const vr_scene_tables *t, size_t o, double out[4]) {
  if (t->sphere[o][3] > 0) {
    memcpy(out, t->sphere[o], 4 * sizeof *out);
    return;
  }
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  for (uint64_t e = t->emit_begin[o]; e < t->emit_end[o]; e++)
    for (int k = 0; k < 9; k++) {
      double v = t->emit_verts[9 * e + k];
      if (v < lo[k % 3]) lo[k % 3] = v;
      if (v > hi[k % 3]) hi[k % 3] = v;
    }
  double r2 = 0;
  for (int a = 0; a < 3; a++) {
    out[a] = 0.5 * (lo[a] + hi[a]);
    r2 += 0.25 * (hi[a] - lo[a]) * (hi[a] - lo[a]);
  }
  out[3] = sqrt(r2);
}

vr_status vr_lights_add_emitter(vr_lights *L, const vr_scene_object *so, uint32_t object,
                                double area, int *index, vr_error *err) {
  *index = -1;
  vr_emitter *e = &L->emitter[L->nemitters];
  memset(e, 0, sizeof *e);
  vr_status st = vr_spd_resolve(&L->setup.spd, so->emission_spectrum, "D65", &so->loc,
                                &e->emission, err);
  if (!st)
    st = vr_spd_normalise(&L->setup.spd, &e->emission, so->emission,
                          vr_unit_is_photometric(so->emission.unit), &so->loc, "emission", err);
  if (st || !(area > 0)) {
    /* A zero-area emitter emits nothing; it is not an error. */
    vr_rspd_free(&e->emission);
    return st;
  }
  e->object = object;
  e->power = vr_rspd_integral(&e->emission, L->setup.spd.lmin, L->setup.spd.lmax) * M_PI * area;
  bounds(L->t, object, e->sphere);
  double before = L->nemitters ? L->emitter_cdf[L->nemitters - 1] : 0.0;
  L->emitter_cdf[L->nemitters] = before + e->power;
  *index = (int)L->nemitters++;
  return VR_OK;
}

void vr_lights_emitters_done(vr_lights *L) {
  double acc = L->nemitters ? L->emitter_cdf[L->nemitters - 1] : 0.0;
  for (size_t e = 0; e < L->nemitters; e++) L->emitter_cdf[e] /= acc > 0 ? acc : 1;
}

/* Emitter i's share at x before normalising: its power over the squared
 * distance to its bounding sphere's centre, at least its radius. */
static double weight(const vr_lights *L, size_t i, const double x[3]) {
  const double *s = L->emitter[i].sphere;
  double d2 = 0;
  for (int a = 0; a < 3; a++) d2 += (x[a] - s[a]) * (x[a] - s[a]);
  double r2 = s[3] * s[3];
  double p = L->emitter_cdf[i] - (i ? L->emitter_cdf[i - 1] : 0.0);
  return p / (d2 > r2 ? d2 : (r2 > 0 ? r2 : 1e-30));
}

bool vr_lights_sample_emitter(const vr_lights *L, const double x[3], int nwl, const double *wl,
                             const vr_rng_key *key, vr_light_sample *out) {
  if (!L->nemitters) return false;
  /* Choose an emitter by power over squared distance (never closer than
   * its bounding radius): a lamp across the building is rarely chosen
   * from inside a room, and its shadow ray rarely leaves the room.  Any
   * choice with p > 0 wherever light can arrive is unbiased; this one
   * tracks the unoccluded 1/d² falloff.  Two passes, no storage. */
  double sum = 0;
  for (size_t i = 0; i < L->nemitters; i++) sum += weight(L, i, x);
  if (!(sum > 0)) return false;
  double u = vr_rng(key, VR_DIM_LIGHT_PICK) * sum, acc = 0, w = 0;
  size_t e = 0;
  for (; e < L->nemitters; e++) {
    w = weight(L, e, x);
    acc += w;
    if (u < acc) break;
  }
  if (e == L->nemitters) { /* rounding at the top end */
    e = L->nemitters - 1;
    while (e > 0 && !(weight(L, e, x) > 0)) e--;
    w = weight(L, e, x);
  }
  double p_pick = w / sum;
  if (!(p_pick > 0)) return false;
  uint32_t obj = L->emitter[e].object;
  double y[3], ny[3];
  vr_scene_tables_sample_object(L->t, obj, vr_rng(key, VR_DIM_LIGHT_U), vr_rng(key, VR_DIM_LIGHT_V),
                            vr_rng(key, VR_DIM_LIGHT_W), y, ny);
  if (key->seed.sampler != VR_SAMPLER_INDEPENDENT && L->t->is_rect && L->t->is_rect[obj]) {
    /* A low-discrepancy sampler's 2D point (LIGHT_V, LIGHT_W) placed on
     * the whole rect (uniform by area, as its two triangles are), so its
     * stratification covers the light instead of a triangle picked apart
     * by LIGHT_U.  Independent numbers keep the triangles' way, bit for
     * bit as before samplers existed. */
    const double *f = L->t->rect_frame[obj];
    double s = vr_rng(key, VR_DIM_LIGHT_V), t = vr_rng(key, VR_DIM_LIGHT_W);
    for (int a = 0; a < 3; a++) y[a] = f[a] + s * f[3 + a] + t * f[6 + a];
  }
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = y[a] - x[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) out->dir[a] = d[a] / r;
  double cos_y = -vr_dot3(out->dir, ny);
  if (!(cos_y > 0)) return false; /* emitters emit from their front side */
  double area = L->t->object_area[obj];
  double g = cos_y * area / (r2 * p_pick);
  for (int k = 0; k < nwl; k++) out->L[k] = vr_rspd_at(&L->emitter[e].emission, wl[k]) * g;
  out->dist = r;
  out->delta = false;
  memcpy(out->p, y, sizeof out->p);
  memcpy(out->n, ny, sizeof out->n);
  out->pdf_pos = 1 / area;
  return true;
}

