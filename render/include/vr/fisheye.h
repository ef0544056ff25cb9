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

#ifdef __cplusplus
}
#endif
#endif
