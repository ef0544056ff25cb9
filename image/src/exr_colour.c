/* The colour attributes both EXR writers put beside R, G, B (vr/image.h,
 * vr_exr_colour): OpenEXR's standard `chromaticities` and `whiteLuminance`
 * (openexr.com, "Standard Optional Attributes": the CIE x, y of the
 * primaries and white, and the luminance in cd/m² of RGB (1, 1, 1)), and
 * an `exposure` float for display.  Without them a viewer takes the
 * numbers as relative to an unknown white and shows a render in absolute
 * cd/m² (a wall at 500) as flat white. */
#include <math.h>
#include <string.h>

#include "exr_stream.h"
#include "image_internal.h"

vr_exr_colour vr_exr_colour_srgb(double white_luminance, double exposure) {
  /* ITU-R BT.709-6, table items 1.3 (primaries) and 1.4 (white, D65);
   * IEC 61966-2-1:1999 takes the same. */
  vr_exr_colour c = {.has_chromaticities = 1,
                     .chromaticities = {0.640f, 0.330f, 0.300f, 0.600f, 0.150f, 0.060f, 0.3127f,
                                        0.3290f},
                     .white_luminance = white_luminance,
                     .has_exposure = 1,
                     .exposure = exposure};
  return c;
}

static const char *const NAMES[8] = {"red x",  "red y",  "green x", "green y",
                                     "blue x", "blue y", "white x", "white y"};

vr_status vr_exr_colour_check(const char *path, const vr_exr_colour *c, vr_error *err) {
  if (!c) return VR_OK;
  const char *p = path ? path : "OpenEXR";
  if (c->has_chromaticities) {
    for (int i = 0; i < 8; i++) {
      float v = c->chromaticities[i];
      if (!isfinite(v) || v < 0.0f || v > 1.0f)
        return vr_error_at(err, VR_E_ARG, p, 0, 0,
                           "chromaticities: %s = %g is not a CIE 1931 chromaticity in [0, 1]",
                           NAMES[i], (double)v);
    }
    if (!(c->chromaticities[7] > 0.0f))
      return vr_error_at(err, VR_E_ARG, p, 0, 0,
                         "chromaticities: white y = 0 gives no white (x/y is undefined)");
  }
  if (!isfinite(c->white_luminance) || c->white_luminance < 0)
    return vr_error_at(err, VR_E_ARG, p, 0, 0,
                       "whiteLuminance %g cd/m2: must be finite and >= 0 (0 writes none)",
                       c->white_luminance);
  if (c->has_exposure && !isfinite(c->exposure))
    return vr_error_at(err, VR_E_ARG, p, 0, 0, "exposure %g stops is not finite", c->exposure);
  return VR_OK;
}

exr_result_t vr_exr_colour_set(exr_context_t ctxt, int part, const vr_exr_colour *c) {
  if (!c) return EXR_ERR_SUCCESS;
  exr_result_t rv = EXR_ERR_SUCCESS;
  if (c->has_chromaticities) {
    const float *x = c->chromaticities;
    exr_attr_chromaticities_t ch = {x[0], x[1], x[2], x[3], x[4], x[5], x[6], x[7]};
    rv = exr_attr_set_chromaticities(ctxt, part, "chromaticities", &ch);
  }
  if (rv == EXR_ERR_SUCCESS && c->white_luminance > 0)
    rv = exr_attr_set_float(ctxt, part, "whiteLuminance", (float)c->white_luminance);
  if (rv == EXR_ERR_SUCCESS && c->has_exposure)
    rv = exr_attr_set_float(ctxt, part, "exposure", (float)c->exposure);
  return rv;
}

int vr_exr_colour_attr(const char *name) {
  static const char *const ATTRS[3] = {"chromaticities", "whiteLuminance", "exposure"};
  for (int i = 0; i < 3; i++)
    if (name && strcmp(ATTRS[i], name) == 0) return 1;
  return 0;
}
