/* Daylight glare from a fisheye image (vr/fisheye.h): Guth's position
 * index, the daylight glare probability DGP of Wienold & Christoffersen 2006
 * with Wienold 2009's low-light correction, and the simplified DGPs from the
 * vertical illuminance alone. */
#include <math.h>

#include "camera/fisheye.h"
#include "vr/fisheye.h"

double vr_guth_position_index(const double d[3]) {
  if (!(d[2] > 0)) return 16.0;
  double P;
  if (d[1] >= 0) {
    double sigma = acos(fmin(1.0, d[2])) * 180.0 / M_PI;
    double tau = atan2(fabs(d[0]), d[1]) * 180.0 / M_PI;
    P = exp((35.2 - 0.31889 * tau - 1.22 * exp(-2.0 * tau / 9.0)) * 1e-3 * sigma +
            (21.0 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma);
  } else {
    /* Below the line of sight: Iwata & Osterhaus's index (CIE 2010) in
     * Kikuchi's conversion to sigma and tau, as evalglare 3 (Radiance 6.1)
     * takes it: beta = atan(tan(sigma) sqrt(1 + 0.3225 cos^2 tau)),
     * ln P = 6.49e-3 beta + 21e-5 beta^2 (degrees); tau is measured from
     * the vertical, so cos^2 tau is the same from below. */
    double s2 = d[0] * d[0] + d[1] * d[1], cos2tau = s2 > 0 ? d[1] * d[1] / s2 : 1.0;
    double beta = atan(sqrt(s2) / d[2] * sqrt(1.0 + 0.3225 * cos2tau)) * 180.0 / M_PI;
    P = exp(6.49e-3 * beta + 21e-5 * beta * beta);
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
      vr_fisheye_pixel_omega(c, x, y, &w, &wc);
      ev += L * wc, lw += L * w, w_front += w;
    }
  if (!(threshold > 0)) threshold = w_front > 0 ? 5.0 * lw / w_front : INFINITY;
  double sum = 0, ws = 0, ls = 0;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = luminance[(size_t)y * (size_t)W + (size_t)x], w, wc, d[3];
      if (!(L > threshold) || !vr_fisheye_direction(c, x + 0.5, y + 0.5, d) || !(d[2] > 0)) continue;
      vr_fisheye_pixel_omega(c, x, y, &w, &wc);
      double P = vr_guth_position_index(d);
      sum += L * L * w / (P * P);
      ws += w, ls += L * w;
    }
  double contrast = ev > 0 ? sum / pow(ev, 1.87) : 0;
  out->dgp = vr_dgp_formula(ev, contrast);
  out->vertical_lx = ev;
  out->threshold_cd_m2 = threshold;
  out->source_omega_sr = ws;
  out->source_cd_m2 = ws > 0 ? ls / ws : 0;
  out->contrast = contrast;
}

double vr_dgp_formula(double ev, double contrast) {
  double dgp = 5.87e-5 * ev + 9.18e-2 * log10(1.0 + contrast) + 0.16;
  if (ev < 1000) {
    double q = exp(0.024 * ev - 4.0);
    dgp *= q / (1.0 + q);
  }
  return fmin(dgp, 1.0);
}

double vr_dgps(double vertical_lx) { return 6.22e-5 * vertical_lx + 0.184; }

double vr_dgps_limit_lx(double dgps) { return (dgps - 0.184) / 6.22e-5; }
