/* False-colour luminance maps, as lighting designers read them: each
 * pixel's luminance (cd/m2) on a logarithmic scale between two bounds,
 * painted from dark blue through cyan, green, yellow and red to white, with
 * a legend bar at the right labelled at every decade (and at the bounds).
 * Values at or below the lower bound take its colour, at or above the upper
 * bound the upper one; a pixel of luminance 0 (outside a fisheye's circle,
 * or black) stays black.  The labels are drawn with a small built-in bitmap
 * font (digits, '.', 'e', '+', '-' and "cd/m2"), so the map needs no font
 * library. */
#ifndef VR_FALSECOLOUR_H
#define VR_FALSECOLOUR_H

#include "vr/error.h"
#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The colour (sRGB-encoded, [0, 1]) of scale position t in [0, 1]
 * (clamped): piecewise linear between eight stops. */
void vr_falsecolour_colour(double t, float rgb[3]);

/* The scale position of luminance L between lo and hi (0 < lo < hi), log
 * scale, clamped to [0, 1]. */
double vr_falsecolour_position(double L, double lo, double hi);

/* The map of luminance Y (W x H, cd/m2, row-major) with its legend: an
 * image W + legend wide (legend = max(64, W / 5) pixels) and max(H, 128)
 * high.  VR_E_ARG unless 0 < lo < hi (finite). */
vr_status vr_falsecolour_image(const double *Y, int W, int H, double lo, double hi,
                               vr_image *out, vr_error *err);

/* The legend's width for a map W pixels wide. */
int vr_falsecolour_legend_width(int W);

#ifdef __cplusplus
}
#endif
#endif
