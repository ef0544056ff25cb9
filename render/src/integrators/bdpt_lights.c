/* The lights a light subpath starts from, for the bidirectional path
 * tracer: their choice, their vertices and their densities, through each
 * light's own sampling (lights/light.h) so that BDPT, the path tracer and
 * the photons sample a light the same way.
 *
 * Light lines (point, spot, ...) and emissive objects are chosen in
 * proportion to their power (the same choice for a light subpath's first
 * vertex and for next-event estimation, so strategy s = 1 samples its
 * vertex with the density the weights assume).  A light line's vertex and
 * direction are its sample_le(), its next-event sample its sample_li();
 * an emitter's point is uniform over its area and its direction
 * cosine-weighted about its front normal (pbrt-v4's SampleLe).  The
 * camera's end is the camera model's (camera/camera.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vr/vec3.h"
#include "integrators/bdpt_internal.h"

vr_status bdpt_lights_init(vr_bdpt_lights *L, const vr_rscene *rs, vr_error *err) {
  memset(L, 0, sizeof *L);
  size_t cap = rs->L.n + rs->L.nemitters + 1;
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
  for (size_t i = 0; i < rs->L.n; i++) {
    const vr_light *l = &rs->L.light[i];
    if ((l->ops->flags & VR_LF_FAR) || !(l->power > 0)) continue;
    L->light[L->n] = (int)i;
    L->pmf[L->n++] = l->power;
    total += l->power;
  }
  for (size_t e = 0; e < rs->L.nemitters; e++) {
    uint32_t o = rs->L.emitter[e].object;
    double p = rs->L.emitter[e].power;
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

void bdpt_lights_free(vr_bdpt_lights *L) {
  free(L->light);
  free(L->object);
  free(L->pmf);
  free(L->cdf);
  free(L->of_object);
  memset(L, 0, sizeof *L);
}

/* The light u picks, by bisection of the cdf; -1 if there is none. */
static int pick(const vr_bdpt_lights *L, double u) {
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

double bdpt_light_pdf_dir(const vr_bdpt *b, const vr_bdpt_vertex *y, const double dir[3]) {
  const vr_bdpt_lights *L = &b->L;
  if (y->source < 0) return 0;
  int li = L->light[y->source];
  if (li < 0) {
    double c = vr_dot3(y->ng, dir);
    return c > 0 ? c / M_PI : 0;
  }
  const vr_light *l = &b->rs->L.light[li];
  return l->ops->pdf_le_dir(l, y->p, y->ng, dir);
}

double bdpt_light_pdf_origin(const vr_bdpt *b, const vr_bdpt_vertex *v) {
  if (v->source < 0 || b->L.light[v->source] >= 0) return 0;
  return b->L.pmf[v->source] / b->rs->t->object_area[v->object];
}

void bdpt_emitted(const vr_bdpt *b, const vr_bdpt_vertex *v, const double to[3], int nwl, const double *wl,
                  double *Le) {
  const vr_rspd *e = vr_rscene_emission(b->rs, v->object);
  bool front = e && vr_dot3(v->ng, to) > 0;
  for (int k = 0; k < nwl; k++) Le[k] = front ? vr_rspd_at(e, wl[k]) : 0.0;
}

/* The vertex of light line j at point p with normal n, its density the
 * choice's times the point's.  No camera path can hit a light line, so
 * every strategy that would need it hit is out (delta_light). */
static void vertex_of(int j, vr_bdpt_vertex *y) {
  memset(y, 0, sizeof *y);
  y->type = BV_LIGHT;
  y->source = j;
  y->medium = -1;
  y->connectible = true;
  y->seg_rev = 1;
}

static void light_vertex(const vr_bdpt *b, int j, const double p[3], const double n[3],
                         double pdf_pos, vr_bdpt_vertex *y) {
  vertex_of(j, y);
  memcpy(y->p, p, sizeof y->p);
  memcpy(y->ng, n, sizeof y->ng);
  memcpy(y->ns, n, sizeof y->ns);
  y->delta_light = true;
  y->pdf_fwd = b->L.pmf[j] * pdf_pos;
}

/* An emitter's point from three numbers, uniform by area. */
static void emitter_vertex(const vr_bdpt *b, int j, double u1, double u2, double u3,
                           vr_bdpt_vertex *y) {
  const vr_rscene *rs = b->rs;
  vertex_of(j, y);
  uint32_t o = b->L.object[j];
  vr_scene_tables_sample_object(rs->t, o, u1, u2, u3, y->p, y->ng);
  memcpy(y->ns, y->ng, sizeof y->ns);
  y->object = o;
  y->on_surface = true;
  y->pdf_fwd = b->L.pmf[j] / rs->t->object_area[o];
}

bool bdpt_light_start(const vr_bdpt *b, const vr_bdpt_sample *sm, vr_bdpt_vertex *y0,
                      double dir[3], double *pdf_dir, double *beta) {
  const vr_rscene *rs = b->rs;
  vr_rng_key key = {rs->seed, sm->stream, sm->sample, BK_LIGHT_START};
  int j = pick(&b->L, vr_rng(&key, VR_DIM_LIGHT_PICK));
  if (j < 0) return false;
  int li = b->L.light[j];
  bool any = false;
  if (li >= 0) {
    /* The light's own emission sample: Le cos / (p_light p_pos p_dir). */
    const vr_light *l = &rs->L.light[li];
    vr_light_emission e;
    if (!l->ops->sample_le(l, &rs->L.setup, &key, &e)) return false;
    light_vertex(b, j, e.org, e.n, e.pdf_pos, y0);
    memcpy(dir, e.dir, 3 * sizeof *dir);
    *pdf_dir = bdpt_light_pdf_dir(b, y0, dir);
    if (!(e.f > 0) || !(*pdf_dir > 0)) return false;
    for (int k = 0; k < sm->nwl; k++)
      any |= (beta[k] = vr_rspd_at(&l->spd, sm->wl[k]) * e.f / (y0->pdf_fwd * *pdf_dir)) > 0;
    return any;
  }
  emitter_vertex(b, j, vr_rng(&key, VR_DIM_LIGHT_U), vr_rng(&key, VR_DIM_LIGHT_V),
                 vr_rng(&key, VR_DIM_LIGHT_W), y0);
  double u1 = vr_rng(&key, VR_DIM_EMIT_U), u2 = vr_rng(&key, VR_DIM_EMIT_V);
  /* Cosine-weighted about the front normal: Le cos / (p_pos cos / pi). */
  vr_sample_cosine(y0->ng, u1, u2, dir);
  double z = sqrt(fmax(0, 1 - u1));
  *pdf_dir = z / M_PI;
  if (!(z > 0)) return false;
  const vr_rspd *e = vr_rscene_emission(rs, y0->object);
  for (int k = 0; k < sm->nwl; k++)
    any |= (beta[k] = vr_rspd_at(e, sm->wl[k]) * M_PI / y0->pdf_fwd) > 0;
  return any;
}

bool bdpt_light_sample(const vr_bdpt *b, const vr_bdpt_sample *sm, uint32_t key_depth,
                       const double x[3], vr_bdpt_vertex *y, double *contrib) {
  const vr_rscene *rs = b->rs;
  vr_rng_key key = {rs->seed, sm->stream, sm->sample, key_depth};
  int j = pick(&b->L, vr_rng(&key, VR_DIM_LIGHT_PICK));
  if (j < 0) return false;
  int li = b->L.light[j];
  bool any = false;
  if (li >= 0) {
    /* The light's next-event sample (Le G_light / p_pos, for a point
     * light Le / d^2) over the choice's probability. */
    vr_light_sample ls;
    if (!vr_lights_sample_light(&rs->L, (size_t)li, x, &key, sm->nwl, sm->wl, &ls)) return false;
    light_vertex(b, j, ls.p, ls.n, ls.pdf_pos, y);
    for (int k = 0; k < sm->nwl; k++) any |= (contrib[k] = ls.L[k] / b->L.pmf[j]) > 0;
    return any;
  }
  emitter_vertex(b, j, vr_rng(&key, VR_DIM_LIGHT_U), vr_rng(&key, VR_DIM_LIGHT_V),
                 vr_rng(&key, VR_DIM_LIGHT_W), y);
  double d[3], r2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = x[a] - y->p[a];
    r2 += d[a] * d[a];
  }
  if (!(r2 > 0)) return false;
  double r = sqrt(r2);
  for (int a = 0; a < 3; a++) d[a] /= r;
  double g = vr_dot3(y->ng, d) / r2;
  if (!(g > 0)) return false;
  const vr_rspd *e = vr_rscene_emission(rs, y->object);
  for (int k = 0; k < sm->nwl; k++) any |= (contrib[k] = vr_rspd_at(e, sm->wl[k]) * g / y->pdf_fwd) > 0;
  return any;
}
