/* The five coefficients of a sky luminance distribution: gradation (a, b)
 * and indicatrix (c, d, e), shared by the CIE general skies (vr/sky.h) and
 * the Perez all-weather sky (vr/perez.h). */
#ifndef VR_SKY_PARAMS_H
#define VR_SKY_PARAMS_H

typedef struct vr_sky_params {
  double a, b, c, d, e;
} vr_sky_params;

#endif
