/* The two ends of a bidirectional path: the lights a light subpath starts
 * from (their choice, emission and densities) and the camera's importance.
 *
 * Lights.  Point and spot lights and emissive objects are chosen in
 * proportion to their power (the same choice for a light subpath's first
 * vertex and for next-event estimation, so strategy s = 1 samples its
 * vertex with the density the weights assume).  A point or spot light
 * emits uniformly over the sphere (the spot's outer cone), weighted by its
 * distribution; an emitter's point is uniform over its area and its
 * direction cosine-weighted about its front normal (pbrt-v4's SampleLe).
 *
 * Camera.  For a pinhole the image plane at distance 1 has area
 * A = (2 tan(fov/2))² H/W, and a camera sample is uniform over it, so its
 * direction has the density 1 / (A cos³θ) (dA = dω / cos³θ at distance
 * 1 / cos θ): pbrt's PerspectiveCamera::PDF_We.  The importance is
 * We = 1 / (A cos⁴θ) (one cosine goes to the geometry term), so a light
 * vertex y seen at distance d contributes
 *   beta_y f_y |cos_y| / (d² A cos³θ)
 * to the pixel it projects to, which with every pixel's spp samples and
 * one light subpath per sample adds weight 1/spp (pbrt's splat scale).  A
 * thin lens samples its point uniformly on the lens and sees the plane of
 * focus at the same film point; its direction density from any lens point
 * is the same 1 / (A cos³θ), so the contribution keeps its form with the
 * lens point in place of the pinhole. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bdpt_internal.h"

vr_status bdpt_lights_init(bdpt_lights *L, const rscene *rs, vr_error *err) {
  memset(L, 0, sizeof *L);
  size_t cap = rs->nlights + rs->nemitters + 1;
  L->light = calloc(cap, sizeof *L->light);
  L->object = calloc(cap, sizeof *L->object);
  L->pmf = calloc(cap, sizeof *L->pmf);
  L->cdf = calloc(cap, sizeof *L->cdf);
  L->of_object = malloc((rs->s->nobjects + 1) * sizeof *L->of_object);
  if (!L->light || !L->object || !L->pmf || !L->cdf || !L->of_object) {
    bdpt_lights_free(L);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  for (size_t i = 0; i <= rs->s->nobjects; i++) L->of_object[i] = -1;
  double total = 0;
  for (size_t i = 0; i < rs->nlights; i++) {
    const rlight *l = &rs->lights[i];
    if (l->kind == VR_LIGHT_SUN || !(l->power > 0)) continue;
    L->light[L->n] = (int)i;
    L->pmf[L->n++] = l->power;
    total += l->power;
  }
  for (size_t e = 0; e < rs->nemitters; e++) {
    uint32_t o = rs->emitters[e];
    double p = rs->obj[o].emitted_power;
    if (!(p > 0)) continue;
    L->light[L->n] = -1;
    L->object[L->n] = o;
    L->of_object[o] = (int)L->n;
    L->pmf[L->n++] = p;
    total += p;
  }
  double acc = 0;
  for (size_t i = 0; i < L->n; i++) {
    L->pmf[i] /= total;
    L->cdf[i] = (acc += L->pmf[i]);
  }
  if (L->n) L->cdf[L->n - 1] = 1.0;
  return VR_OK;
}

void bdpt_lights_free(bdpt_lights *L) {
  free(L->light);
  free(L->object);
  free(L->pmf);
  free(L->cdf);
  free(L->of_object);
  memset(L, 0, sizeof *L);
}

/* The light u picks, by bisection of the cdf; -1 if there is none. */
static int pick(const bdpt_lights *L, double u) {
  if (!L->n) return -1;
  size_t lo = 0, hi = L->n - 1;
  while (lo < hi) {
    size_t mid = (lo + hi) / 2;
    if (u < L->cdf[mid]) hi = mid;
    else lo = mid + 1;
  }
  while (lo > 0 && !(L->pmf[lo] > 0)) lo--;
  return L->pmf[lo] > 0 ? (int)lo : -1;
}

/* Duff et al. 2017, "Building an orthonormal basis, revisited". */
static void frame(const double n[3], double t[3], double b[3]) {
  double s = copysign(1.0, n[2]);
  double a = -1.0 / (s + n[2]), c = n[0] * n[1] * a;
  t[0] = 1 + s * n[0] * n[0] * a, t[1] = s * c, t[2] = -s * n[0];
  b[0] = c, b[1] = s + n[1] * n[1] * a, b[2] = -n[1];
}

/* A direction uniform in the cone of cos_max about axis. */
static void cone(const double axis[3], double cos_max, double u1, double u2, double out[3]) {
  double t[3], b[3];
  frame(axis, t, b);
  double c = 1 - u1 * (1 - cos_max), s = sqrt(fmax(0, 1 - c * c)), ph = 2 * M_PI * u2;
  for (int a = 0; a < 3; a++) out[a] = c * axis[a] + s * (cos(ph) * t[a] + sin(ph) * b[a]);
}

static const double UP[3] = {0, 0, 1};

double bdpt_light_pdf_dir(const bdpt *b, const bvert *y, const double dir[3]) {
  const bdpt_lights *L = &b->L;
  if (y->source < 0) return 0;
  int li = L->light[y->source];
  if (li < 0) {
    double c = bdpt_dot(y->ng, dir);
    return c > 0 ? c / M_PI : 0;
  }
  const rlight *l = &b->rs->lights[li];
  if (l->kind == VR_LIGHT_SPOT)
    return bdpt_dot(l->axis, dir) >= l->cos_outer ? 1.0 / (2 * M_PI * (1 - l->cos_outer)) : 0;
  return 1.0 / (4 * M_PI);
}

double bdpt_light_pdf_origin(const bdpt *b, const bvert *v) {
  if (v->source < 0 || b->L.light[v->source] >= 0) return 0;
  return b->L.pmf[v->source] / b->rs->t->object_area[v->object];
}

void bdpt_emitted(const bdpt *b, const bvert *v, const double to[3], int nwl, const double *wl,
                  double *Le) {
  const robject *o = &b->rs->obj[v->object];
  bool front = o->emission.n && bdpt_dot(v->ng, to) > 0;
  for (int k = 0; k < nwl; k++) Le[k] = front ? rspd_at(&o->emission, wl[k]) : 0.0;
}

/* Fills the light vertex of light j; for an emitter, its point from three
 * numbers. */
static void light_vertex(const bdpt *b, int j, double u1, double u2, double u3, bvert *y) {
  const rscene *rs = b->rs;
  memset(y, 0, sizeof *y);
  y->type = BV_LIGHT;
  y->source = j;
  y->medium = -1;
  y->connectible = true;
  y->seg_rev = 1;
  int li = b->L.light[j];
  if (li >= 0) {
    memcpy(y->p, rs->lights[li].pos, sizeof y->p);
    memcpy(y->ng, rs->lights[li].axis, sizeof y->ng);
    memcpy(y->ns, y->ng, sizeof y->ns);
    y->delta_light = true;
    y->pdf_fwd = b->L.pmf[j]; /* position density 1 (a delta) */
    return;
  }
  uint32_t o = b->L.object[j];
  vr_scene_tables_sample_object(rs->t, o, u1, u2, u3, y->p, y->ng);
  memcpy(y->ns, y->ng, sizeof y->ns);
  y->object = o;
  y->on_surface = true;
  y->pdf_fwd = b->L.pmf[j] / rs->t->object_area[o];
}

bool bdpt_light_start(const bdpt *b, const bsample *sm, bvert *y0, double dir[3],
                      double *pdf_dir, double *beta) {
  const rscene *rs = b->rs;
  vr_rng_key key = {rs->seed, sm->stream, sm->sample, BK_LIGHT_START};
  int j = pick(&b->L, vr_rng(&key, VR_DIM_LIGHT_PICK));
  if (j < 0) return false;
  light_vertex(b, j, vr_rng(&key, VR_DIM_LIGHT_U), vr_rng(&key, VR_DIM_LIGHT_V),
               vr_rng(&key, VR_DIM_LIGHT_W), y0);
  double u1 = vr_rng(&key, VR_DIM_EMIT_U), u2 = vr_rng(&key, VR_DIM_EMIT_V);
  int li = b->L.light[j];
  bool any = false;
  if (li >= 0) {
    const rlight *l = &rs->lights[li];
    if (l->kind == VR_LIGHT_SPOT) cone(l->axis, l->cos_outer, u1, u2, dir);
    else cone(UP, -1.0, u1, u2, dir);
    *pdf_dir = bdpt_light_pdf_dir(b, y0, dir);
    double f = vr_light_distribution(rs, (size_t)li, dir);
    if (!(f > 0) || !(*pdf_dir > 0)) return false;
    for (int k = 0; k < sm->nwl; k++)
      any |= (beta[k] = rspd_at(&l->spd, sm->wl[k]) * f / (y0->pdf_fwd * *pdf_dir)) > 0;
    return any;
  }
  /* Cosine-weighted about the front normal: Le cos / (p_pos cos / pi). */
  double t[3], bb[3], r = sqrt(u1), ph = 2 * M_PI * u2, z = sqrt(fmax(0, 1 - u1));
  frame(y0->ng, t, bb);
  for (int a = 0; a < 3; a++) dir[a] = z * y0->ng[a] + r * (cos(ph) * t[a] + sin(ph) * bb[a]);
  *pdf_dir = z / M_PI;
  if (!(z > 0)) return false;
  const robject *o = &rs->obj[y0->object];
  for (int k = 0; k < sm->nwl; k++)
    any |= (beta[k] = rspd_at(&o->emission, sm->wl[k]) * M_PI / y0->pdf_fwd) > 0;
  return any;
}

bool bdpt_light_sample(const bdpt *b, const bsample *sm, uint32_t key_depth, const double x[3],
                       bvert *y, double *contrib) {
  const rscene *rs = b->rs;
  vr_rng_key key = {rs->seed, sm->stream, sm->sample, key_depth};
  int j = pick(&b->L, vr_rng(&key, VR_DIM_LIGHT_PICK));
  if (j < 0) return false;
  light_vertex(b, j, vr_rng(&key, VR_DIM_LIGHT_U), vr_rng(&key, VR_DIM_LIGHT_V),
               vr_rng(&key, VR_DIM_LIGHT_W), y);
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = x[a] - y->p[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) d[a] /= r;
  double g;
  int li = b->L.light[j];
  const rspd *spd;
  if (li >= 0) {
    g = vr_light_distribution(rs, (size_t)li, d) / r2;
    spd = &rs->lights[li].spd;
  } else {
    g = bdpt_dot(y->ng, d) / r2;
    spd = &rs->obj[y->object].emission;
  }
  if (!(g > 0)) return false;
  bool any = false;
  for (int k = 0; k < sm->nwl; k++)
    any |= (contrib[k] = rspd_at(spd, sm->wl[k]) * g / y->pdf_fwd) > 0;
  return any;
}

bool bdpt_cam_raster(const bdpt_cam *cam, const double c[3], const double y[3], double *px,
                     double *py, double *cos_theta) {
  double d[3], l2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = y[a] - c[a];
    l2 += d[a] * d[a];
  }
  double ct = bdpt_dot(d, cam->w);
  if (!(ct > 0) || !(l2 > 0)) return false;
  /* The point of the plane of focus on the ray (any plane for a pinhole),
   * read in the image's coordinates about the lens centre. */
  double f = cam->lens_radius > 0 ? cam->focus : 1.0, s = f / ct, q[3];
  for (int a = 0; a < 3; a++) q[a] = c[a] + s * d[a] - cam->o[a];
  double sx = bdpt_dot(q, cam->u) / f, sy = bdpt_dot(q, cam->v) / f;
  double x = (sx / cam->tan_half + 1) * 0.5 * cam->W;
  double yy = (1 - sy / (cam->tan_half * cam->aspect)) * 0.5 * cam->H;
  double m = cam->margin;
  if (!(x >= -m && x < cam->W + m && yy >= -m && yy < cam->H + m)) return false;
  *px = x, *py = yy;
  *cos_theta = ct / sqrt(l2);
  return true;
}

double bdpt_cam_pdf_dir(const bdpt_cam *cam, const double c[3], const double y[3]) {
  double px, py, ct;
  if (!bdpt_cam_raster(cam, c, y, &px, &py, &ct)) return 0;
  return 1.0 / (cam->area * ct * ct * ct);
}
