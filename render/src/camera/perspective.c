/* Perspective cameras: the pinhole and the thin lens.
 *
 * The image plane at distance 1 along w spans 2 tan(fov/2) horizontally and
 * that times H/W vertically, so its area is A = (2 tan(fov/2))^2 H/W.  A
 * camera sample is uniform over the image, so its direction has the density
 * 1 / (A cos^3 theta) (dA = d omega / cos^3 theta at distance 1 / cos theta):
 * pbrt's PerspectiveCamera::PDF_We.  A thin lens keeps the point of the plane
 * of focus that the pinhole's ray meets and moves the origin over the lens
 * disc, uniform by area; its direction density from any lens point is the
 * same, so light tracing keeps its form with the lens point for the pinhole. */
#include <math.h>
#include <string.h>

#include "camera/camera.h"
#include "vr/vec3.h"

static void lens_point(const vr_camera *c, const vr_rng_key *key, double p[3]) {
  if (!(c->lens_radius > 0)) {
    memcpy(p, c->o, 3 * sizeof *p);
    return;
  }
  double r = c->lens_radius * sqrt(vr_rng(key, VR_DIM_LENS_U));
  double ph = 2 * M_PI * vr_rng(key, VR_DIM_LENS_V);
  for (int a = 0; a < 3; a++) p[a] = c->o[a] + r * (cos(ph) * c->u[a] + sin(ph) * c->v[a]);
}

static bool generate(const vr_camera *c, double px, double py, const vr_rng_key *key,
                     double org[3], double dir[3]) {
  double sx = (2 * px / c->W - 1) * c->tan_half;
  double sy = (1 - 2 * py / c->H) * c->tan_half * c->aspect;
  for (int a = 0; a < 3; a++) dir[a] = c->w[a] + sx * c->u[a] + sy * c->v[a];
  memcpy(org, c->o, 3 * sizeof *org);
  if (c->lens_radius > 0) {
    double focus[3];
    for (int a = 0; a < 3; a++) focus[a] = org[a] + c->focus * dir[a];
    lens_point(c, key, org);
    for (int a = 0; a < 3; a++) dir[a] = focus[a] - org[a];
  }
  double l = sqrt(vr_dot3(dir, dir));
  for (int a = 0; a < 3; a++) dir[a] /= l;
  return true;
}

static bool raster(const vr_camera *c, const double lens[3], const double y[3], double *px,
                   double *py, double *cos_theta) {
  double d[3], l2 = 0;
  for (int a = 0; a < 3; a++) {
    d[a] = y[a] - lens[a];
    l2 += d[a] * d[a];
  }
  double ct = vr_dot3(d, c->w);
  if (!(ct > 0) || !(l2 > 0)) return false;
  /* The point of the plane of focus on the ray (any plane for a pinhole),
   * read in the image's coordinates about the lens centre. */
  double f = c->lens_radius > 0 ? c->focus : 1.0, s = f / ct, q[3];
  for (int a = 0; a < 3; a++) q[a] = lens[a] + s * d[a] - c->o[a];
  double sx = vr_dot3(q, c->u) / f, sy = vr_dot3(q, c->v) / f;
  double x = (sx / c->tan_half + 1) * 0.5 * c->W;
  double yy = (1 - sy / (c->tan_half * c->aspect)) * 0.5 * c->H;
  double m = c->margin;
  if (!(x >= -m && x < c->W + m && yy >= -m && yy < c->H + m)) return false;
  *px = x, *py = yy;
  *cos_theta = ct / sqrt(l2);
  return true;
}

static double pdf_dir(const vr_camera *c, const double lens[3], const double y[3]) {
  double px, py, ct;
  if (!raster(c, lens, y, &px, &py, &ct)) return 0;
  return 1.0 / (c->area * ct * ct * ct);
}

const vr_camera_ops vr_camera_pinhole = {"pinhole", generate, lens_point, raster, pdf_dir};
const vr_camera_ops vr_camera_thinlens = {"thinlens", generate, lens_point, raster, pdf_dir};
