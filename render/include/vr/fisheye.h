/* Fisheye cameras (camera fisheye): the projection of a pixel to a view
 * direction, and the vertical illuminance at the lens from a fisheye image,
 * the basis of daylight glare metrics.
 *
 * The image circle is inscribed in the picture (radius min(W, H)/2, centred);
 * pixels outside it see nothing.  See vr_fisheye_projection (vr/scene.h)
 * for the two projections. */
#ifndef VR_FISHEYE_H
#define VR_FISHEYE_H

#include <stdbool.h>
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The direction seen at image point (px, py) (pixels, y down), in the
 * camera's frame: d[0] right, d[1] up, d[2] forward (unit).  false outside
 * the image circle. */
bool vr_fisheye_direction(const vr_scene_camera *c, double px, double py, double d[3]);

/* E_v = sum over pixels of L cos(theta) dOmega: the illuminance at the lens
 * on the plane facing the view direction (directions beyond 90 degrees
 * count nothing), from luminance (W x H values, cd/m2, row-major).  Each
 * pixel's solid angle and mean cosine are integrated over 8 x 8 points of
 * its area, so pixels the circle's edge cuts count their inside part. */
double vr_fisheye_vertical_illuminance(const vr_scene_camera *c, const double *luminance);

/* The simplified daylight glare probability of Wienold (2009), from the
 * vertical illuminance at the eye alone: DGPs = 6.22e-5 E_v + 0.184.  It
 * has no contrast term: with the sun or a specular reflection of it in
 * view it reads too low. */
double vr_dgps(double vertical_lx);
/* The vertical illuminance at which DGPs reaches dgps: (dgps - 0.184) / 6.22e-5. */
double vr_dgps_limit_lx(double dgps);

/* The Guth position index (IES Lighting Handbook; Luckiesh & Guth 1949)
 * of a direction d in the camera's frame (d[0] right, d[1] up, d[2]
 * forward, unit), as Wienold's evalglare applies it:
 *   above the line of sight, with sigma the angle from the line of sight
 *   and tau the angle from the vertical of the plane holding both (deg),
 *     ln P = (35.2 - 0.31889 tau - 1.22 e^(-2 tau / 9)) 1e-3 sigma
 *            + (21 + 0.26667 tau - 0.002963 tau^2) 1e-5 sigma^2;
 *   below it, Iwata & Osterhaus's index (CIE 2010) in Kikuchi's form, as
 *     evalglare 3 takes it: beta = atan(tan sigma sqrt(1 + 0.3225 cos^2
 *     tau)), ln P = 6.49e-3 beta + 21e-5 beta^2 (degrees);
 * P at most 16.  Directions behind the eye (d[2] <= 0) have P = 16. */
double vr_guth_position_index(const double d[3]);

/* The daylight glare probability of Wienold & Christoffersen (2006) from a
 * fisheye image of luminance (W x H, cd/m2):
 *   DGP = 5.87e-5 E_v + 9.18e-2 log10(1 + sum L_s^2 w_s / (E_v^1.87 P_s^2))
 *         + 0.16,
 * the sum over the pixels brighter than `threshold` cd/m2 in front of the
 * eye (threshold <= 0: 5 times the mean luminance of the front hemisphere,
 * evalglare's default without a task area), each pixel a source of its own
 * solid angle w_s and position index P_s at its centre (evalglare merges
 * neighbouring pixels into sources with their mean luminance and centroid:
 * the same sum for a source of even luminance); below 1000 lx the low-light
 * correction of Wienold (2009), DGP exp(0.024 E_v - 4) / (1 + exp(0.024
 * E_v - 4)); at most 1. */
typedef struct vr_dgp_result {
  double dgp;
  double vertical_lx;         /* E_v, as vr_fisheye_vertical_illuminance */
  double threshold_cd_m2;     /* the glare-source threshold used */
  double source_omega_sr;     /* solid angle of the glare-source pixels */
  double source_cd_m2;        /* their mean luminance (0 without any) */
  double contrast;            /* the sum under the logarithm */
} vr_dgp_result;

void vr_fisheye_dgp(const vr_scene_camera *c, const double *luminance, double threshold,
                    vr_dgp_result *out);

/* DGP from E_v (lx) and the contrast sum sum L_s^2 w_s / (E_v^1.87 P_s^2)
 * as above: the formula with the low-light correction, at most 1. */
double vr_dgp_formula(double ev, double contrast);

#ifdef __cplusplus
}
#endif
#endif
