/* The spot light: 'light spot position= direction= cone=DEG [falloff=DEG]
 * intensity='.  Full intensity within `cone` of its axis, falling to zero
 * by a smoothstep over the next `falloff` degrees.  Photons and light
 * subpaths leave it uniformly within the outer cone, weighted by the
 * falloff. */
#include <math.h>
#include <string.h>

#include "lights/kinds.h"
#include "vr/vec3.h"

#define COS_INNER(l) ((l)->k[0])
#define COS_OUTER(l) ((l)->k[1])

static vr_status parse(vr_scn_stmt *t, vr_scene_light *l) {
  vr_scn_parser *p = t->p;
  static const char *const SPOT[] = {"position", "direction", "cone", "falloff", "intensity", "spectrum", NULL};
  t->what = "a spot light";
  const vr_scn_opt *o, *dir, *cone;
  vr_status st;
  if ((st = scn_options(t, 2, SPOT)) || (st = scn_need(t, "position", &o)) || (st = scn_need(t, "direction", &dir)) ||
      (st = scn_need(t, "cone", &cone)) || (st = scn_point(t, o, l->position)) ||
      (st = scn_direction(p, dir->word, dir->val, l->direction)) ||
      (st = scn_range(t, "cone", 0, 180, true, true, &l->cone_deg)) ||
      (st = scn_range(t, "falloff", 0, 180, false, false, &l->falloff_deg)))
    return st;
  if (l->cone_deg + l->falloff_deg > 180)
    return scn_fail(p, scn_get(t, "falloff") ? scn_get(t, "falloff")->word : t->w[0], "cone + falloff exceeds 180 degrees");
  return vr_lamp_parse_amount(t, l, true);
}

static vr_status resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                         vr_error *err) {
  memcpy(l->axis, sl->direction, sizeof l->axis);
  vr_normalize3(l->axis);
  COS_INNER(l) = cos(sl->cone_deg * M_PI / 180.0);
  COS_OUTER(l) = cos((sl->cone_deg + sl->falloff_deg) * M_PI / 180.0);
  double omega = 2 * M_PI * (1 - 0.5 * (COS_INNER(l) + COS_OUTER(l)));
  return vr_lamp_resolve(l, sl, u, omega, err);
}

/* Intensity towards unit d (from the light) over the on-axis value. */
static double distribution(const vr_light *l, const double d[3]) {
  double c = vr_dot3(d, l->axis);
  if (c >= COS_INNER(l)) return 1.0;
  if (c <= COS_OUTER(l)) return 0.0;
  double x = (c - COS_OUTER(l)) / (COS_INNER(l) - COS_OUTER(l));
  return x * x * (3 - 2 * x); /* smoothstep falloff */
}

static bool sample_li(const vr_light *l, const double x[3], const vr_rng_key *key,
                      vr_light_dims dims, int nwl, const double *wl, vr_light_sample *out) {
  (void)key, (void)dims;
  return vr_lamp_sample_li(l, distribution, x, nwl, wl, out);
}

static bool sample_le(const vr_light *l, const vr_light_setup *u, const vr_rng_key *key,
                      vr_light_emission *out) {
  (void)u;
  return vr_lamp_sample_le(l, distribution, l->axis, COS_OUTER(l), key, out);
}

static double pdf_le_dir(const vr_light *l, const double p[3], const double n[3],
                         const double dir[3]) {
  (void)p, (void)n;
  return vr_dot3(l->axis, dir) >= COS_OUTER(l) ? vr_cone_pdf(COS_OUTER(l)) : 0;
}

const vr_light_ops vr_light_spot = {
    .name = "spot", .flags = VR_LF_DELTA_POSITION, .source = VR_SRC_LAMP, .spectrum = "D65",
    .parse = parse, .resolve = resolve, .sample_li = sample_li, .pdf_li = vr_lamp_pdf_li,
    .sample_le = sample_le, .pdf_le_dir = pdf_le_dir};
