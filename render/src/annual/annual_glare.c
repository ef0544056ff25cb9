/* Annual glare at chosen view points (annual glare_views=, vr/annual.h):
 * the daylight glare probability of Wienold & Christoffersen (2006) hour
 * by hour, contrast term included, from fisheye image daylight
 * coefficients.
 *
 * Each view's image is rendered like the sensors' coefficients: once under
 * the uniform unit sky with every pixel's luminance binned by the Tregenza
 * patch (or the ground glow) it came from, and once per sun patch the year
 * visits with the sun at the patch centre.  An hour's image is then
 *   L(px) = sum_k C_k(px) L_k + E_dn S_ks(px),
 * and its DGP (vr/fisheye.h, evalglare's default threshold: 5 times the
 * mean luminance of the front hemisphere) takes
 *   - E_v from the view sensor's own coefficients (path sensors: many more
 *     samples than a pixel, and the direct sun's cosine ratio applied), as
 *     Wienold's enhanced simplified DGP takes E_v from daylight
 *     coefficients and only the sources from an image;
 *   - the glare sources from the image, pixel by pixel;
 *   - the solar disc as one more source where the view sees the sun
 *     straight (the coefficient images leave the disc out: it would sit at
 *     the patch centre): its luminance E_n / w_sun from the sensor's direct
 *     sun E_n normal to the beam (transmission on the way included), at the
 *     hour's true sun position.  A parallel-beam sun (radius=0) is taken as
 *     the real sun's disc, 0.2665 degrees.
 * The sunlit patches in the image keep the patch centre's sun (up to
 * about 6 degrees off), as the sensors' reflected sun does. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "annual/annual_internal.h"
#include "camera/fisheye.h"
#include "vr/fisheye.h"
#include "vr/vec3.h"

#define PI 3.14159265358979323846
#define REAL_SUN_RADIUS_DEG 0.2665

const double VR_GLARE_DGP[VR_GLARE_CLASSES] = {0.35, 0.40, 0.45};

static vr_status view_setup(const vr_annual_job *j, int vi, vr_glare_view *gv, vr_error *err) {
  const vr_scene *s = j->s;
  const vr_scene_sensor *sn = &s->sensors[s->annual.views[vi]];
  const vr_annual_result *res = j->res;
  bool found = false;
  for (size_t p = 0; p < res->npoints && !found; p++)
    if (res->points[p].sensor && !strcmp(res->points[p].sensor, sn->name)) gv->point = p, found = true;
  if (!found) return vr_error_set(err, VR_E_NUMERIC, "annual: glare view %s has no point", sn->name);
  vr_scene_camera *c = &gv->cam;
  memset(c, 0, sizeof *c);
  c->model = VR_CAM_FISHEYE;
  c->projection = VR_FISHEYE_EQUISOLID;
  c->fov_deg = 180;
  c->width = c->height = s->annual.view_resolution;
  for (int a = 0; a < 3; a++) {
    c->from[a] = sn->position[a];
    c->to[a] = sn->position[a] + sn->normal[a];
  }
  c->up[2] = 1;
  /* The camera's frame (camera.c): w forward, u = w x up, v = u x w. */
  double *u = gv->frame[0], *v = gv->frame[1], *w = gv->frame[2];
  memcpy(w, sn->normal, 3 * sizeof *w);
  vr_cross3(w, c->up, u);
  double lu = sqrt(vr_dot3(u, u));
  for (int a = 0; a < 3; a++) u[a] /= lu;
  vr_cross3(u, w, v);
  size_t N = (size_t)c->width * (size_t)c->height;
  gv->pixel = calloc(N, sizeof *gv->pixel);
  gv->w = calloc(N, sizeof *gv->w);
  gv->P = calloc(N, sizeof *gv->P);
  if (!gv->pixel || !gv->w || !gv->P) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  gv->npx = 0;
  for (int y = 0; y < c->height; y++)
    for (int x = 0; x < c->width; x++) {
      double om, oc, d[3];
      vr_fisheye_pixel_omega(c, x, y, &om, &oc);
      if (!(om > 0)) continue;
      size_t i = gv->npx++;
      gv->pixel[i] = (size_t)y * (size_t)c->width + (size_t)x;
      gv->w[i] = om;
      gv->P[i] = vr_fisheye_direction(c, x + 0.5, y + 0.5, d) && d[2] > 0 ? vr_guth_position_index(d) : 0;
    }
  return VR_OK;
}

vr_status annual_glare_setup(const vr_annual_job *j, vr_glare_set *g, vr_error *err) {
  memset(g, 0, sizeof *g);
  double r = j->sun->sun_radius_deg > 0 ? j->sun->sun_radius_deg : REAL_SUN_RADIUS_DEG;
  g->sun_omega_sr = 2 * PI * (1 - cos(r * PI / 180));
  size_t most = 0;
  for (int i = 0; i < j->s->annual.nviews; i++) {
    g->n = i + 1;
    vr_status st = view_setup(j, i, &g->v[i], err);
    if (st) return st;
    if (g->v[i].npx > most) most = g->v[i].npx;
  }
  if (!(g->scratch = calloc(2 * most + 1, sizeof *g->scratch)))
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  return VR_OK;
}

/* One view's luminance this hour, pixel by pixel, in state si. */
static void view_image(const vr_glare_view *gv, const vr_annual_hour *h, int si, double *L) {
  for (size_t i = 0; i < gv->npx; i++) {
    const double *c = gv->sky[si] + i * NPATCH;
    double l = 0;
    for (int k = 0; k < NPATCH; k++) l += c[k] * h->L[k];
    if (h->ks >= 0) l += h->Edn * gv->sun[si][i * VR_SKY_PATCHES + (size_t)h->ks];
    L[i] = l;
  }
}

/* The DGP of an image L of the view, E_v = ev, with the sun seen straight
 * at illuminance En normal to the beam from direction sd (camera frame). */
static double view_dgp(const vr_glare_set *g, const vr_glare_view *gv, const double *L, double ev,
                       double En, const double sd[3]) {
  bool sun = En > 0 && sd[2] > 0;
  double lw = sun ? En : 0, wf = 0;
  for (size_t i = 0; i < gv->npx; i++) lw += L[i] * gv->w[i], wf += gv->w[i];
  double threshold = wf > 0 ? 5 * lw / wf : INFINITY, sum = 0;
  for (size_t i = 0; i < gv->npx; i++)
    if (gv->P[i] > 0 && L[i] > threshold) sum += L[i] * L[i] * gv->w[i] / (gv->P[i] * gv->P[i]);
  if (sun && En / g->sun_omega_sr > threshold) {
    double P = vr_guth_position_index(sd);
    sum += En * En / (g->sun_omega_sr * P * P);
  }
  return vr_dgp_formula(ev, ev > 0 ? sum / pow(ev, 1.87) : 0);
}

void annual_glare_hour(const vr_glare_set *g, const vr_annual_hour *h, int lo, int hi, double f,
                       const vr_dc_set *dcs, const double *E, double *dgp) {
  for (int vi = 0; vi < g->n; vi++) {
    const vr_glare_view *gv = &g->v[vi];
    double *L = g->scratch, *Lh = g->scratch + gv->npx;
    double ev = E[gv->point], En = 0, sd[3] = {0, 0, 0};
    if (!h->daylit) {
      dgp[vi] = vr_dgp_formula(ev, 0);
      continue;
    }
    view_image(gv, h, lo, L);
    if (f > 0) {
      view_image(gv, h, hi, Lh);
      for (size_t i = 0; i < gv->npx; i++) L[i] = annual_between(L[i], Lh[i], f);
    }
    if (h->ks >= 0) {
      /* The sun seen straight: the sensor's direct coefficient is the
       * illuminance on its plane with the sun at the patch centre; over
       * that centre's cosine it is the illuminance normal to the beam. */
      const double *w = gv->frame[2];
      double cc = vr_dot3(w, h->centre);
      size_t i = gv->point * VR_SKY_PATCHES + (size_t)h->ks;
      double s = dcs[lo].sun_direct[i];
      if (f > 0) s = annual_between(s, dcs[hi].sun_direct[i], f);
      if (cc > 1e-3 && s > 0) En = h->Edn * s / cc;
      for (int a = 0; a < 3; a++) sd[a] = vr_dot3(gv->frame[a], h->sun);
    }
    dgp[vi] = view_dgp(g, gv, L, ev, En, sd);
  }
}

void annual_glare_free(vr_glare_set *g) {
  for (int i = 0; i < g->n; i++) {
    vr_glare_view *gv = &g->v[i];
    free(gv->pixel), free(gv->w), free(gv->P);
    for (int k = 0; k < VR_ANNUAL_MAX_STATES; k++) free(gv->sky[k]), free(gv->sun[k]);
  }
  free(g->scratch);
  memset(g, 0, sizeof *g);
}
