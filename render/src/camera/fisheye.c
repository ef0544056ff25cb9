/* The fisheye camera model: the projection of an image point to a view
 * direction (equisolid or angular, vr/fisheye.h), a pixel's solid angle,
 * and the vertical illuminance at the lens from a fisheye image.  Light
 * tracing is not written for it (no raster(), no pdf_dir()). */
#include "vr/fisheye.h"

#include <math.h>
#include <string.h>

#include "camera/camera.h"
#include "camera/fisheye.h"
#include "vr/vec3.h"

/* Image point to normalised circle coordinates (u right, v up), r in [0, 1]
 * inside the circle. */
static void circle_coords(const vr_scene_camera *c, double px, double py, double *u, double *v) {
  double R = 0.5 * (c->width < c->height ? c->width : c->height);
  *u = (px - 0.5 * c->width) / R;
  *v = (0.5 * c->height - py) / R;
}

/* theta for a radius r in [0, 1]. */
static double theta_of(const vr_scene_camera *c, double r) {
  double tmax = 0.5 * c->fov_deg * M_PI / 180.0;
  if (c->projection == VR_FISHEYE_ANGULAR) return r * tmax;
  double s = r * sin(0.5 * tmax);
  return 2.0 * asin(s > 1 ? 1 : s);
}

/* dOmega / dA at radius r (A in normalised circle units): equisolid
 * 4 sin^2(theta_max / 2), constant; angular theta_max sin(theta) / r. */
static double omega_density(const vr_scene_camera *c, double r) {
  double tmax = 0.5 * c->fov_deg * M_PI / 180.0;
  if (c->projection == VR_FISHEYE_EQUISOLID) return 4.0 * sin(0.5 * tmax) * sin(0.5 * tmax);
  return r > 1e-12 ? tmax * sin(r * tmax) / r : tmax * tmax;
}

bool vr_fisheye_direction(const vr_scene_camera *c, double px, double py, double d[3]) {
  double u, v;
  circle_coords(c, px, py, &u, &v);
  double r = sqrt(u * u + v * v);
  if (!(r <= 1.0)) return false;
  double th = theta_of(c, r), s = sin(th);
  d[0] = r > 0 ? s * u / r : 0.0;
  d[1] = r > 0 ? s * v / r : 0.0;
  d[2] = cos(th);
  return true;
}

void vr_fisheye_pixel_omega(const vr_scene_camera *c, int x, int y, double *omega, double *cos_omega) {
  enum { SUB = 8 };
  double R = 0.5 * (c->width < c->height ? c->width : c->height), da = 1.0 / (R * R * SUB * SUB);
  double w = 0, wc = 0;
  for (int j = 0; j < SUB; j++)
    for (int i = 0; i < SUB; i++) {
      double u, v;
      circle_coords(c, x + (i + 0.5) / SUB, y + (j + 0.5) / SUB, &u, &v);
      double r = sqrt(u * u + v * v);
      if (r > 1.0) continue;
      double ct = cos(theta_of(c, r));
      if (ct > 0) w += omega_density(c, r) * da, wc += ct * omega_density(c, r) * da;
    }
  *omega = w, *cos_omega = wc;
}

double vr_fisheye_vertical_illuminance(const vr_scene_camera *c, const double *luminance) {
  int W = c->width, H = c->height;
  double e = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = luminance[(size_t)y * (size_t)W + (size_t)x], w, wc;
      if (L == 0.0) continue;
      vr_fisheye_pixel_omega(c, x, y, &w, &wc);
      e += L * wc;
    }
  return e;
}


static bool generate(const vr_camera *c, double px, double py, const vr_rng_key *key,
                     double org[3], double dir[3]) {
  (void)key;
  double d[3];
  if (!vr_fisheye_direction(c->sc, px, py, d)) return false; /* outside the image circle */
  for (int a = 0; a < 3; a++) dir[a] = d[2] * c->w[a] + d[0] * c->u[a] + d[1] * c->v[a];
  memcpy(org, c->o, 3 * sizeof *org);
  double l = sqrt(vr_dot3(dir, dir));
  for (int a = 0; a < 3; a++) dir[a] /= l;
  return true;
}

static void centre(const vr_camera *c, const vr_rng_key *key, double p[3]) {
  (void)key;
  memcpy(p, c->o, 3 * sizeof *p);
}

const vr_camera_ops vr_camera_fisheye = {"fisheye", generate, centre, NULL, NULL};
