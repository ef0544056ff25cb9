/* The X-Rite ColorChecker Classic in a photo: found by OpenCV's mcc module
 * (cv::mcc::CCheckerDetector, chart type MCC24) or placed by hand from its
 * four corners, then read out as the mean image value of each of its 24
 * patches, in chart order (index 0 = patch 1 "dark skin", row-major from the
 * brown patch to index 23 = patch 24 "black", the order of vr/colorchecker.h).
 *
 * Layout (the same as mcc's own chart model): 4 rows of 6 square patches of
 * side s separated by gaps of s/10.  The patch area - from the outer corner
 * of patch 1 to the outer corner of patch 24 - is therefore 6.5 s by 4.3 s.
 * In units of the patch pitch p = 1.1 s, patch (row r, column c) occupies
 * [c p, c p + s] x [r p, r p + s] of that area.  Each patch is sampled over
 * a square of side fraction * s about its centre, mapped through the
 * perspective (homography) that takes the patch area onto the four corners,
 * so a chart photographed at an angle is read correctly.  A pixel belongs to
 * a patch when its centre lies inside the mapped square.
 *
 * mcc on a synthetic chart: it does detect a cleanly drawn chart (24 flat
 * squares in the sRGB colours of the chart, gaps of a tenth of a patch on a
 * black card, grey background; 600 x 400 pixels with 80-pixel patches, also
 * rotated by 180 degrees), orienting it by colour so that index 0 is still the
 * dark-skin patch, with 8-bit display values or with linear values and
 * linear = true.  Its outline is then a few pixels off (patch centres up to
 * 4.4 px, 6 % of a patch, with OpenCV 4.6), which the sampled centre square
 * (fraction 0.5 leaves a quarter of a patch of margin on each side) absorbs:
 * the means come out exactly the drawn colours; see tests/acquire.
 * mcc needs the patches to be flat-ish and separated by a dark gap; on an
 * image without a chart it finds nothing and vr_chart_detect returns
 * VR_E_NOT_FOUND.
 *
 * The photo may hold floats or integer codes (vr_image_read_codes): both
 * give the same numbers (vr/image.h, "Integer codes"). */
#ifndef VR_CHART_H
#define VR_CHART_H

#include <stdbool.h>

#include "vr/error.h"
#include "vr/image.h"

#ifdef __cplusplus
extern "C" {
#endif

#define VR_CHART_PATCHES 24
/* Fraction of the patch side sampled when the caller passes 0. */
#define VR_CHART_DEFAULT_FRACTION 0.5

typedef struct vr_chart {
  double rgb[VR_CHART_PATCHES][3];    /* mean image value per patch, chart order */
  double sd[VR_CHART_PATCHES][3];     /* sample standard deviation per patch */
  double max[VR_CHART_PATCHES];       /* largest channel value in the patch (clipping check) */
  long pixels[VR_CHART_PATCHES];      /* pixels averaged */
  double center[VR_CHART_PATCHES][2]; /* patch centre (x, y) in image coordinates */
  /* Outer corners of the patch area, at patches 1, 6, 24 and 19 (top-left,
   * top-right, bottom-right, bottom-left when dark skin is top-left): can be
   * given to vr_chart_from_grid for another photo from the same camera
   * position, e.g. the same scene under another light. */
  double corners[4][2];
} vr_chart;

/* Finds a ColorChecker Classic with mcc and reads its 24 patches (fraction
 * VR_CHART_DEFAULT_FRACTION).  mcc works on an 8-bit BGR copy: values are
 * clamped to [0,1] and, when linear is true (EXR, raw-developed linear TIFF),
 * sRGB-encoded first (IEC 61966-2-1 curve) so that the chart looks as mcc
 * expects; the means are always taken from img's own values.  Scale an HDR
 * image so that the chart lies roughly within [0,1] before detecting.
 * VR_E_NOT_FOUND when no chart is found. */
vr_status vr_chart_detect(const vr_image *img, bool linear, vr_chart *out, vr_error *err);

/* Reads the 24 patches from the four outer corners of the patch area
 * (corners[k] = {x, y}, in the order of vr_chart.corners), for photos where
 * detection fails and for synthetic images.  fraction in (0, 1] is the
 * sampled part of each patch side (0 means VR_CHART_DEFAULT_FRACTION).
 * VR_E_ARG for a degenerate quadrilateral, VR_E_RANGE when a sampled square
 * leaves the image or holds no pixel centre. */
vr_status vr_chart_from_grid(const vr_image *img, const double corners[4][2], double fraction,
                             vr_chart *out, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
