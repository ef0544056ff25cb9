/* ColorChecker reference reflectances: see vr/colorchecker.h. */
#include "vr/colorchecker.h"
#include "embedded.h"

static const char *const NAMES[VR_COLORCHECKER_PATCHES] = {
    "dark_skin", "light_skin",    "blue_sky",     "foliage",    "blue_flower", "bluish_green",
    "orange",    "purplish_blue", "moderate_red", "purple",     "yellow_green", "orange_yellow",
    "blue",      "green",         "red",          "yellow",     "magenta",     "cyan",
    "white_9.5", "neutral_8",     "neutral_6.5",  "neutral_5",  "neutral_3.5", "black_2"};

const char *vr_colorchecker_name(size_t i) { return i < VR_COLORCHECKER_PATCHES ? NAMES[i] : NULL; }

vr_spectrum *vr_colorchecker_patch(size_t i, vr_error *err) {
  if (i >= VR_COLORCHECKER_PATCHES) {
    vr_error_set(err, VR_E_ARG, "ColorChecker patch index %zu out of 0-23", i);
    return NULL;
  }
  unsigned rows = vr_data_colorchecker_babelcolor_rows, cols = vr_data_colorchecker_babelcolor_cols;
  vr_spectrum *s = vr_spectrum_create_uniform(0.0, 1.0, rows, 0.0, err);
  if (!s) return NULL;
  for (unsigned r = 0; r < rows; r++) {
    s->nm[r] = vr_data_colorchecker_babelcolor[r * cols];
    s->value[r] = vr_data_colorchecker_babelcolor[r * cols + 1 + i];
  }
  return s;
}
