/* The point light: 'light point position= [intensity=] [distribution=
 * isotropic|lambertian|goniometric] [normal=] [ies=FILE]'.  Its intensity
 * towards a direction is the on-axis intensity times the distribution:
 * 1 (isotropic), max(cos, 0) about the normal (lambertian), or the IES
 * LM-63 file's candelas over their peak (goniometric).  Photons and light
 * subpaths leave it uniformly over the sphere, weighted by the
 * distribution. */
#include <math.h>
#include <string.h>

#include "lights/kinds.h"
#include "vr/ies.h"
#include "vr/vec3.h"

#define DIST(l) ((vr_distribution)(l)->k[0])

static vr_status parse(vr_scn_stmt *t, vr_scene_light *l) {
  vr_scn_parser *p = t->p;
  static const char *const POINT[] = {"position", "intensity", "distribution", "normal", "ies", "spectrum", NULL};
  static const char *const DISTS[] = {"isotropic", "lambertian", "goniometric", NULL};
  t->what = "a point light";
  const vr_scn_opt *o, *ies, *dist;
  vr_status st;
  if ((st = scn_options(t, 2, POINT)) || (st = scn_need(t, "position", &o)) || (st = scn_point(t, o, l->position)))
    return st;
  int d = -1;
  if ((st = scn_choice(t, "distribution", DISTS, &d))) return st;
  ies = scn_get(t, "ies"), dist = scn_get(t, "distribution");
  if (ies && d >= 0 && d != VR_DIST_GONIOMETRIC)
    return scn_fail(p, ies->word, "ies= needs distribution=goniometric (or no distribution=)");
  if (ies) d = VR_DIST_GONIOMETRIC;
  if (d == VR_DIST_GONIOMETRIC && !ies)
    return scn_fail(p, dist->word, "distribution=goniometric needs ies=FILE");
  l->distribution = d < 0 ? VR_DIST_ISOTROPIC : (vr_distribution)d;
  if (ies && !(l->ies_path = scn_resolve(p->s, ies->val))) return scn_nomem(p);
  if ((o = scn_get(t, "normal")) && (st = scn_direction(p, o->word, o->val, l->normal))) return st;
  return vr_lamp_parse_amount(t, l, l->distribution != VR_DIST_GONIOMETRIC);
}

static vr_status resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                         vr_error *err) {
  l->k[0] = sl->distribution;
  memcpy(l->axis, sl->normal, sizeof l->axis);
  vr_normalize3(l->axis);
  struct vr_ies *ies = NULL;
  if (sl->distribution == VR_DIST_GONIOMETRIC) {
    vr_status st = vr_ies_read(sl->ies_path, &ies, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld:%ld: ", u->spd.path, sl->loc.line, sl->loc.col);
      return st;
    }
    l->data = ies;
  }
  /* The distribution's solid-angle integral over its on-axis (peak) value. */
  double omega = sl->distribution == VR_DIST_LAMBERTIAN ? M_PI
                 : ies ? vr_ies_lumens(ies) / fmax(vr_ies_max_candela(ies), 1e-300)
                       : 4 * M_PI;
  if (ies && sl->amount.unit == VR_UNIT_NONE) {
    /* The file's own candela values: the peak is the amount. */
    vr_scene_light own = *sl;
    own.amount = (vr_quantity){vr_ies_max_candela(ies), VR_UNIT_CD};
    return vr_lamp_resolve(l, &own, u, omega, err);
  }
  return vr_lamp_resolve(l, sl, u, omega, err);
}

static void destroy(vr_light *l) {
  vr_ies_destroy(l->data);
  l->data = NULL;
}

/* Intensity towards unit d (from the light) over the on-axis value. */
static double distribution(const vr_light *l, const double d[3]) {
  double c = vr_dot3(d, l->axis);
  switch (DIST(l)) {
  case VR_DIST_LAMBERTIAN: return c > 0 ? c : 0.0;
  case VR_DIST_GONIOMETRIC: return vr_ies_candela_dir(l->data, d) / vr_ies_max_candela(l->data);
  default: return 1.0;
  }
}

static bool sample_li(const vr_light *l, const double x[3], const vr_rng_key *key,
                      vr_light_dims dims, int nwl, const double *wl, vr_light_sample *out) {
  (void)key, (void)dims;
  return vr_lamp_sample_li(l, distribution, x, nwl, wl, out);
}

static const double UP[3] = {0, 0, 1};

static bool sample_le(const vr_light *l, const vr_light_setup *u, const vr_rng_key *key,
                      vr_light_emission *out) {
  (void)u;
  return vr_lamp_sample_le(l, distribution, UP, -1.0, key, out);
}

static double pdf_le_dir(const vr_light *l, const double p[3], const double n[3],
                         const double dir[3]) {
  (void)l, (void)p, (void)n, (void)dir;
  return 1.0 / (4 * M_PI);
}

const vr_light_ops vr_light_point = {
    .name = "point", .flags = VR_LF_DELTA_POSITION, .source = VR_SRC_LAMP, .spectrum = "D65",
    .parse = parse, .resolve = resolve, .destroy = destroy, .sample_li = sample_li,
    .pdf_li = vr_lamp_pdf_li, .sample_le = sample_le, .pdf_le_dir = pdf_le_dir};
