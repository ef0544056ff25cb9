/* RGB colours as reflectance spectra: Jakob & Hanika's sigmoid model
 * ("A Low-Dimensional Function Space for Efficient Spectral Upsampling",
 * Computer Graphics Forum 38(2), 2019).  A reflectance is
 *
 *   R(lambda) = S(c0 t^2 + c1 t + c2),  S(x) = 1/2 + x / (2 sqrt(1 + x^2)),
 *   t = (lambda - 360 nm) / (830 nm - 360 nm),
 *
 * smooth, in (0, 1) everywhere, with three coefficients found so that its
 * colour under CIE D65 for the CIE 1931 2-degree observer is the given
 * linear sRGB colour (IEC 61966-2-1, whose white is D65).  Jakob and
 * Hanika show (section 5) that this space holds every sRGB colour; the fit
 * here is checked against its goal and refused when it misses (only
 * colours at the gamut's very edge, where a component is 0 or 1 and the
 * coefficients run off to infinity, come near).
 *
 * Domain: linear sRGB components in [0, 1].  Greys (equal components) are
 * exact flat spectra (c0 = c1 = 0), 0 and 1 included. */
#ifndef VR_RGB_SPECTRUM_H
#define VR_RGB_SPECTRUM_H

#include <stdbool.h>

#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The colour difference (CIE 1976 Delta E*ab under D65) a fit must reach
 * to be accepted. */
#define VR_RGB_SPECTRUM_MAX_DE 0.01

typedef struct vr_rgb_spectrum {
  double c[3];     /* c0, c1, c2; c2 = +/-INFINITY for the greys 1 and 0 */
  double delta_e;  /* CIE 1976 Delta E*ab of the fit's colour from the goal */
} vr_rgb_spectrum;

/* Fits a linear sRGB colour (components in [0, 1]).  Refused: a component
 * outside [0, 1] or not finite (VR_E_RANGE), a colour the fit cannot reach
 * within VR_RGB_SPECTRUM_MAX_DE (VR_E_NUMERIC, with the Delta E reached). */
vr_status vr_rgb_spectrum_fit(const double rgb_linear[3], vr_rgb_spectrum *out, vr_error *err);

/* The reflectance at a wavelength in nm (the formula holds at any nm; the
 * fit is made over 360-830 nm). */
double vr_rgb_spectrum_eval(const vr_rgb_spectrum *s, double nm);

/* "#RRGGBB" (sRGB-encoded, 8 bits each) to linear sRGB; false if the text
 * is not exactly that. */
bool vr_rgb_parse_hex(const char *text, double rgb_linear[3]);

#ifdef __cplusplus
}
#endif
#endif
