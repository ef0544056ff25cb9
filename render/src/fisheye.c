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

/* A pixel's solid angle in front of the eye and its cosine-weighted
 * solid angle, over 8 x 8 points of its area. */
static void pixel_omega(const vr_scene_camera *c, int x, int y, double *omega, double *cos_omega) {
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
      pixel_omega(c, x, y, &w, &wc);
      e += L * wc;
    }
  return e;
}

double vr_guth_position_index(const double d[3]) {
  if (!(d[2] > 0)) return 16.0;
  double P;
  if (d[1] >= 0) {
    double sigma = acos(fmin(1.0, d[2])) * 180.0 / M_PI;
    double tau = atan2(fabs(d[0]), d[1]) * 180.0 / M_PI;
    P = exp((35.2 - 0.31889 * tau - 1.22 * exp(-2.0 * tau / 9.0)) * 1e-3 * sigma +
            (21.0 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma);
  } else {
    double R = sqrt(d[0] * d[0] + d[1] * d[1]) / d[2]; /* sqrt(tan^2 phi + tan^2 theta) */
    double f = R > 0.6 ? 1.2 : 0.8;
    P = 1.0 + f * fmin(R, 3.0);
  }
  return fmin(P, 16.0);
}

void vr_fisheye_dgp(const vr_scene_camera *c, const double *luminance, double threshold,
                    vr_dgp_result *out) {
  int W = c->width, H = c->height;
  double ev = 0, lw = 0, w_front = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = luminance[(size_t)y * (size_t)W + (size_t)x], w, wc;
      pixel_omega(c, x, y, &w, &wc);
      ev += L * wc, lw += L * w, w_front += w;
    }
  if (!(threshold > 0)) threshold = w_front > 0 ? 5.0 * lw / w_front : INFINITY;
  double sum = 0, ws = 0, ls = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = luminance[(size_t)y * (size_t)W + (size_t)x], w, wc, d[3];
      if (!(L > threshold) || !vr_fisheye_direction(c, x + 0.5, y + 0.5, d) || !(d[2] > 0)) continue;
      pixel_omega(c, x, y, &w, &wc);
      double P = vr_guth_position_index(d);
      sum += L * L * w / (P * P);
      ws += w, ls += L * w;
    }
  double contrast = ev > 0 ? sum / pow(ev, 1.87) : 0;
  double dgp = 5.87e-5 * ev + 9.18e-2 * log10(1.0 + contrast) + 0.16;
  if (ev < 1000) {
    double q = exp(0.024 * ev - 4.0);
    dgp *= q / (1.0 + q);
  }
  out->dgp = fmin(dgp, 1.0);
  out->vertical_lx = ev;
  out->threshold_cd_m2 = threshold;
  out->source_omega_sr = ws;
  out->source_cd_m2 = ws > 0 ? ls / ws : 0;
  out->contrast = contrast;
}

double vr_dgps(double vertical_lx) { return 6.22e-5 * vertical_lx + 0.184; }

double vr_dgps_limit_lx(double dgps) { return (dgps - 0.184) / 6.22e-5; }
