/* The lights of a resolved scene (lights.h): making them from the scene's
 * light lines, next-event samples of those lines, and freeing it all. */
#include <stdlib.h>
#include <string.h>

#include "lights/lights.h"

vr_status vr_lights_create(vr_lights *L, const vr_scene *s, const vr_light_setup *u,
                           const vr_scene_tables *t, vr_error *err) {
  memset(L, 0, sizeof *L);
  L->setup = *u;
  L->t = t;
  L->light = calloc(s->nlights + 1, sizeof *L->light);
  L->emitter = calloc(s->nobjects + 1, sizeof *L->emitter);
  L->emitter_cdf = calloc(s->nobjects + 1, sizeof *L->emitter_cdf);
  if (!L->light || !L->emitter || !L->emitter_cdf)
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  L->sun = s->nlights;
  for (size_t i = 0; i < s->nlights; i++) {
    vr_status st = vr_light_init(&L->light[i], &s->lights[i], u, err);
    L->n = i + 1; /* what init allocated is freed even when it failed */
    if (st) return st;
    if (L->light[i].ops->flags & VR_LF_SUN) L->sun = i;
  }
  return VR_OK;
}

void vr_lights_destroy(vr_lights *L) {
  for (size_t i = 0; L->light && i < L->n; i++) vr_light_fini(&L->light[i]);
  for (size_t e = 0; L->emitter && e < L->nemitters; e++) vr_rspd_free(&L->emitter[e].emission);
  vr_sky_destroy(L->sky);
  vr_rspd_free(&L->sky_spd);
  vr_rspd_free(&L->ground_spd);
  free(L->light);
  free(L->emitter);
  free(L->emitter_cdf);
  free(L->portals);
  free(L->portal_area_cdf);
  free(L->source_cdf);
  memset(L, 0, sizeof *L);
}

bool vr_lights_sample_light(const vr_lights *L, size_t i, const double x[3],
                            const vr_rng_key *key, int nwl, const double *wl,
                            vr_light_sample *out) {
  const vr_light *l = &L->light[i];
  /* A 2D sample from the sampler's pair (LIGHT_V, LIGHT_W): two first
   * components of different pairs are not jointly uniform under sobol. */
  return l->ops->sample_li(l, x, key, (vr_light_dims){VR_DIM_LIGHT_V, VR_DIM_LIGHT_W}, nwl, wl,
                           out);
}
