/* Fisheye projection and the vertical illuminance of a fisheye image (see
 * vr/fisheye.h). */
#include "vr/fisheye.h"

#include <math.h>

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

double vr_fisheye_vertical_illuminance(const vr_scene_camera *c, const double *luminance) {
  enum { SUB = 8 };
  int W = c->width, H = c->height;
  double R = 0.5 * (W < H ? W : H), da = 1.0 / (R * R * SUB * SUB), e = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = luminance[(size_t)y * (size_t)W + (size_t)x];
      if (L == 0.0) continue;
      double w = 0;
      for (int j = 0; j < SUB; j++)
        for (int i = 0; i < SUB; i++) {
          double u, v;
          circle_coords(c, x + (i + 0.5) / SUB, y + (j + 0.5) / SUB, &u, &v);
          double r = sqrt(u * u + v * v);
          if (r > 1.0) continue;
          double ct = cos(theta_of(c, r));
          if (ct > 0) w += ct * omega_density(c, r) * da;
        }
      e += L * w;
    }
  return e;
}

double vr_dgps(double vertical_lx) { return 6.22e-5 * vertical_lx + 0.184; }
