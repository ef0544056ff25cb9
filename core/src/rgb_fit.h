/* Inside the sigmoid fit of RGB colours (rgb_spectrum.c), shared with the
 * lookup table built from it (rgb_table.c). */
#ifndef VR_CORE_RGB_FIT_H
#define VR_CORE_RGB_FIT_H

#include "vr/error.h"

#define VR_RGBFIT_LO_NM 360.0
#define VR_RGBFIT_HI_NM 830.0
#define VR_RGBFIT_NS 95 /* 5 nm samples over 360-830 nm */

/* D65 times the CMFs at the 5 nm samples, scaled so that R = 1 has Y = 1,
 * and the white's XYZ. */
typedef struct vr_rgbfit_w {
  double w[VR_RGBFIT_NS][3], white[3];
} vr_rgbfit_w;

vr_status vr_rgbfit_weights(vr_rgbfit_w *W, vr_error *err);
/* The CIELAB colour under D65 of the sigmoid with coefficients c. */
void vr_rgbfit_lab(const vr_rgbfit_w *W, const double c[3], double lab[3]);
/* The CIELAB goal of a linear sRGB colour; returns L*. */
double vr_rgbfit_goal(const vr_rgbfit_w *W, const double rgb[3], double lab[3]);
/* Levenberg-Marquardt from c towards goal, at most iters steps; c is
 * updated in place; returns the Delta E*ab reached. */
double vr_rgbfit_step(const vr_rgbfit_w *W, const double goal[3], double c[3], int iters);

#endif
