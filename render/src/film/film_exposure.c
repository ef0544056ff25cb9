/* Automatic exposure for the PNG (vr/film.h): the image's log-average
 * luminance mapped to mid grey.
 *
 * The log average exp(mean ln Y) over the pixels that see something is the
 * "key" of Reinhard et al. (2002, eq. 1): unlike the arithmetic mean it is
 * not pulled up by a few very bright pixels (the sun, a lamp, a window
 * seen from inside).  Mid grey is display value 0.18 (PNG 118 after the
 * sRGB curve), Reinhard's key a = 0.18; since display = Y 2^EV / 100,
 * EV = log2(18 / Y_log). */
#include <math.h>

#include "vr/film.h"

bool vr_film_auto_exposure(const vr_render_result *r, double *ev) {
  double sum = 0;
  size_t n = 0, npix = r && r->xyz ? (size_t)r->width * (size_t)r->height : 0;
  for (size_t p = 0; p < npix; p++) {
    double Y = r->xyz[3 * p + 1];
    /* Black pixels (outside a fisheye's circle, a view into nothing) and
     * infinite ones say nothing about the scene's level. */
    if (Y > 0 && isfinite(Y)) sum += log(Y), n++;
  }
  if (!n) return false;
  *ev = log2(18.0 / exp(sum / (double)n));
  return true;
}
