/* The tube light: 'light tube from=X,Y,Z to=X,Y,Z radius=R flux=Q|luminance=Q'.
 * A cylinder of uniform radiance, as linear fluorescent and LED tubes are
 * modelled (Radiance's `light` material on a `cylinder`, which has no end
 * caps): its lateral surface A = 2 pi r l, each point a Lambertian emitter
 * of radiance L.  A flux (lm or W) is L pi A, so L = flux / (pi A); a
 * luminance (cd/m2 or W/(m2 sr)) is L itself.  Like the other light lines
 * it is not geometry: rays do not hit it, next-event estimation and
 * photons find it.
 *
 * Sampling: a point uniform over the lateral surface (u along the axis,
 * the angle around it), so the next-event weight is L cos_y A / d^2 and
 * the density in solid angle at x of the near side it sees along a
 * direction is d^2 / (A cos_y); emission leaves a point cosine-weighted
 * about its outward normal, Le cos / (p_pos p_dir) = L pi A. */
#include <math.h>
#include <string.h>

#include "lights/kinds.h"
#include "vr/vec3.h"

/* l->k: the radius, the length and the lateral area; l->pos is one end,
 * l->axis the unit direction to the other. */
#define RADIUS(l) ((l)->k[0])
#define LENGTH(l) ((l)->k[1])
#define AREA(l) ((l)->k[2])

static const vr_light_unit FLUX[] = {VR_UNIT_LM, VR_UNIT_W, VR_UNIT_NONE};
static const vr_light_unit LUMINANCE[] = {VR_UNIT_CD_M2, VR_UNIT_W_M2_SR, VR_UNIT_NONE};

static vr_status parse(vr_scn_stmt *t, vr_scene_light *l) {
  vr_scn_parser *p = t->p;
  static const char *const TUBE[] = {"from", "to", "radius", "flux", "luminance", "spectrum", NULL};
  t->what = "a tube light";
  const vr_scn_opt *from, *to, *r;
  vr_status st;
  double end[3];
  if ((st = scn_options(t, 2, TUBE)) || (st = scn_need(t, "from", &from)) ||
      (st = scn_need(t, "to", &to)) || (st = scn_need(t, "radius", &r)) ||
      (st = scn_point(t, from, l->position)) || (st = scn_point(t, to, end)) ||
      (st = scn_positive_length(t, r, &l->shape[3])))
    return st;
  double d[3] = {end[0] - l->position[0], end[1] - l->position[1], end[2] - l->position[2]};
  if (!(vr_dot3(d, d) > 0)) return scn_fail(p, to->word, "\"%s\": the tube has no length", to->word);
  memcpy(l->shape, end, sizeof end);
  const vr_scn_opt *flux = scn_get(t, "flux"), *lum = scn_get(t, "luminance");
  if (!flux == !lum)
    return scn_fail(p, flux && lum ? scn_later(flux, lum) : t->w[0],
                    "a tube light needs flux= (lm or W) or luminance= (cd/m2 or W/m2/sr), one of them");
  return flux ? scn_quantity(p, flux->word, flux->val, FLUX, VR_UNIT_NONE, "a flux", &l->amount)
              : scn_quantity(p, lum->word, lum->val, LUMINANCE, VR_UNIT_NONE, "a luminance",
                             &l->amount);
}

static vr_status resolve(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                         vr_error *err) {
  for (int a = 0; a < 3; a++) l->axis[a] = sl->shape[a] - sl->position[a];
  LENGTH(l) = vr_normalize3(l->axis);
  RADIUS(l) = sl->shape[3];
  AREA(l) = 2 * M_PI * RADIUS(l) * LENGTH(l);
  vr_quantity q = sl->amount;
  if (q.unit == VR_UNIT_LM || q.unit == VR_UNIT_W) q.value /= M_PI * AREA(l);
  vr_status st = vr_spd_normalise(&u->spd, &l->spd, q, vr_unit_is_photometric(q.unit), &sl->loc,
                                  "tube light", err);
  if (st) return st;
  l->power = vr_rspd_integral(&l->spd, u->spd.lmin, u->spd.lmax) * M_PI * AREA(l);
  return VR_OK;
}

/* The point at (u along the axis, angle 2 pi v) and its outward normal. */
static void surface_point(const vr_light *l, double u, double v, double p[3], double n[3]) {
  double t[3], b[3];
  vr_frame3(l->axis, t, b);
  double ph = 2 * M_PI * v, c = cos(ph), s = sin(ph);
  for (int a = 0; a < 3; a++) {
    n[a] = c * t[a] + s * b[a];
    p[a] = l->pos[a] + u * LENGTH(l) * l->axis[a] + RADIUS(l) * n[a];
  }
}

static bool sample_li(const vr_light *l, const double x[3], const vr_rng_key *key,
                      vr_light_dims dims, int nwl, const double *wl, vr_light_sample *out) {
  double y[3], ny[3];
  surface_point(l, vr_rng(key, dims.u), vr_rng(key, dims.v), y, ny);
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = y[a] - x[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) out->dir[a] = d[a] / r;
  double cos_y = -vr_dot3(out->dir, ny);
  if (!(cos_y > 0)) return false; /* the far side of the tube, facing away */
  double g = cos_y * AREA(l) / r2;
  for (int k = 0; k < nwl; k++) out->L[k] = vr_rspd_at(&l->spd, wl[k]) * g;
  out->dist = r;
  out->delta = false;
  memcpy(out->p, y, sizeof out->p);
  memcpy(out->n, ny, sizeof out->n);
  out->pdf_pos = 1 / AREA(l);
  return true;
}

/* Where the ray x + t dir first meets the lateral surface from outside
 * (t > 0, within the tube's length): its t and normal; false if nowhere. */
static bool hit(const vr_light *l, const double x[3], const double dir[3], double *t_out,
                double n[3]) {
  double o[3];
  for (int a = 0; a < 3; a++) o[a] = x[a] - l->pos[a];
  double oa = vr_dot3(o, l->axis), da = vr_dot3(dir, l->axis), op[3], dp[3];
  for (int a = 0; a < 3; a++) op[a] = o[a] - oa * l->axis[a], dp[a] = dir[a] - da * l->axis[a];
  double A = vr_dot3(dp, dp), B = 2 * vr_dot3(op, dp), C = vr_dot3(op, op) - RADIUS(l) * RADIUS(l);
  double disc = B * B - 4 * A * C;
  if (!(A > 0) || !(disc >= 0) || !(C > 0)) return false; /* parallel, missing, or x inside */
  double t = (-B - sqrt(disc)) / (2 * A);
  double along = oa + t * da;
  if (!(t > 0) || along < 0 || along > LENGTH(l)) return false;
  for (int a = 0; a < 3; a++) n[a] = (op[a] + t * dp[a]) / RADIUS(l);
  *t_out = t;
  return true;
}

static double pdf_li(const vr_light *l, const double x[3], const double dir[3]) {
  double t, n[3];
  if (!hit(l, x, dir, &t, n)) return 0;
  double cos_y = -vr_dot3(dir, n);
  return cos_y > 0 ? t * t / (AREA(l) * cos_y) : 0;
}

static bool sample_le(const vr_light *l, const vr_light_setup *u, const vr_rng_key *key,
                      vr_light_emission *out) {
  (void)u;
  surface_point(l, vr_rng(key, VR_DIM_EMIT_U), vr_rng(key, VR_DIM_EMIT_V), out->org, out->n);
  vr_sample_cosine(out->n, vr_rng(key, VR_DIM_EMIT_W), vr_rng(key, VR_DIM_EMIT_X), out->dir);
  double c = vr_dot3(out->dir, out->n);
  out->pdf_pos = 1 / AREA(l);
  out->pdf_dir = c / M_PI;
  out->f = c;
  out->weight = M_PI * AREA(l);
  /* Off the surface, so that the tube's own point does not stop it. */
  double off = 1e-5 * (1 + fmax(fabs(out->org[0]), fmax(fabs(out->org[1]), fabs(out->org[2]))));
  for (int a = 0; a < 3; a++) out->org[a] += off * out->n[a];
  return c > 0;
}

static double pdf_le_dir(const vr_light *l, const double p[3], const double n[3],
                         const double dir[3]) {
  (void)l, (void)p;
  double c = vr_dot3(n, dir);
  return c > 0 ? c / M_PI : 0;
}

const vr_light_ops vr_light_tube = {
    .name = "tube", .source = VR_SRC_LAMP, .spectrum = "D65", .parse = parse,
    .resolve = resolve, .sample_li = sample_li, .pdf_li = pdf_li, .sample_le = sample_le,
    .pdf_le_dir = pdf_le_dir};
