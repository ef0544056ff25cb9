/* The denoiser's features (film/denoise.c): what a camera sample sees at
 * its first vertex with a non-delta lobe, after the mirrors and panes
 * before it (a view through a window records the room or the sky behind
 * the glass, not the glass, as OIDN's and pbrt-v4's feature buffers do):
 *   - the albedo: the BSDF's directional albedo towards wo times the
 *     surface's tint (textures), at eight fixed wavelengths, estimated by
 *     four BSDF samples of their own random numbers (exact for a
 *     Lambertian surface, whose sample weight is its reflectance);
 *   - the shading normal (a normal map's where there is one);
 *   - the nearness 1 / (1 + t / 1 m), t the distance from the camera to
 *     the vertex: in (0, 1], 1/2 at a metre, 0 for a sample that escaped,
 *     so that it can be averaged over a pixel's samples and compared
 *     across the image.  The metre (the scene's unit) is the scale of a
 *     room: a step of 0.45 m at 5 m changes it by 0.0126, the denoiser's
 *     smallest feature tolerance (k_f sqrt(tau)).  (A scale from the
 *     scene's bounds would make it useless in a daylight scene with a
 *     kilometre of ground: 0.999 everywhere in the room.)
 * A sample that escapes records albedo 1, normal 0, nearness 0.  Each
 * sample records once (VR_PF_FEATURED), wherever its ray is traced, into
 * the film's feature sums, which are summed over the ranks as the image. */
#include <math.h>

#include "integrators/features.h"

enum { ALBEDO_SAMPLES = 4, FEATURE_KEY = 0x7E000000 };

bool vr_features_wanted(const vr_pass *c, const vr_payload *p) {
  return c->acc->feat && p->target == VR_TARGET_PIXEL && !(p->flags & VR_PF_FEATURED);
}

void vr_features_escape(vr_pass *c, vr_payload *p) {
  double one[VR_MAX_WL], n[3] = {0, 0, 0};
  for (int k = 0; k < VR_MAX_WL; k++) one[k] = 1.0;
  vr_accum_features(c->acc, p->index, p->weight, p->nwl, p->wl, one, n, 0.0);
  p->flags |= VR_PF_FEATURED;
}

void vr_features_hit(vr_pass *c, vr_payload *p, const vr_hit *hit, const vr_surface *path_se) {
  const vr_rscene *rs = c->rs;
  /* The albedo at fixed wavelengths, the midpoints of VR_MAX_WL equal
   * bins of the range, whatever the path's: the path's own (a few, random)
   * would give a surface of coloured paint another XYZ in every pixel, and
   * the denoiser would take that noise for texture.  The surface (its
   * texture's tint, a pbr surface's point) is looked up again at them. */
  vr_payload q = *p;
  q.nwl = VR_MAX_WL;
  for (int k = 0; k < VR_MAX_WL; k++)
    q.wl[k] = rs->lmin + (k + 0.5) * (rs->lmax - rs->lmin) / VR_MAX_WL;
  double wo[3] = {path_se->wo.x, path_se->wo.y, path_se->wo.z};
  vr_surface fixed = vr_path_surface(rs, &q, hit, wo);
  const vr_surface *se = &fixed;
  double albedo[VR_MAX_WL] = {0};
  for (int i = 0; i < ALBEDO_SAMPLES; i++) {
    vr_rng_key key = {rs->seed, p->stream, p->sample, FEATURE_KEY + (uint32_t)i};
    vr_bsdf_sample bs;
    if (!vr_bsdf_sample_at(se->b, &se->pt, se->state, se->n, se->wo, q.nwl, q.wl,
                           VR_TRANSPORT_RADIANCE, vr_rng_independent(&key, VR_DIM_LOBE),
                           vr_rng_independent(&key, VR_DIM_DIR_U),
                           vr_rng_independent(&key, VR_DIM_DIR_V), &bs))
      continue;
    for (int k = 0; k < q.nwl; k++)
      if (isfinite(bs.weight[k])) albedo[k] += bs.weight[k] / ALBEDO_SAMPLES;
  }
  for (int k = 0; k < q.nwl; k++) {
    if (se->tinted) albedo[k] *= se->tint[k];
    /* A dispersive lobe's weight stands for the other wavelengths too
     * (nwl): an albedo is at most 1 whatever the sample. */
    if (albedo[k] > 1.0) albedo[k] = 1.0;
  }
  double n[3] = {se->ns.x, se->ns.y, se->ns.z};
  /* The path's length so far: the distance the camera's cone has
   * travelled is not kept, so the hit's distance from the camera. */
  double d[3], t = 0;
  for (int a = 0; a < 3; a++) d[a] = hit->p[a] - rs->cam.o[a], t += d[a] * d[a];
  t = sqrt(t);
  vr_accum_features(c->acc, p->index, p->weight, q.nwl, q.wl, albedo, n, 1.0 / (1.0 + t));
  p->flags |= VR_PF_FEATURED;
}
