/* Colours in the scene: an RGB colour becomes the inline reflectance
 * spectrum of Jakob & Hanika's sigmoid (vr/rgb_spectrum.h), written at
 * 5 nm from 360 to 830 nm, so that everything after the parser sees a
 * lambert reflector with a spectrum, as if the user had typed it. */
#include <stdio.h>
#include <stdlib.h>

#include "scene/scene_parse.h"
#include "vr/colour.h"
#include "vr/rgb_spectrum.h"

char *vr_scene_colour_spectrum(const double rgb_linear[3], vr_error *err) {
  vr_rgb_spectrum s;
  if (vr_rgb_spectrum_fit(rgb_linear, &s, err)) return NULL;
  /* 95 points of "nnn:0.xxxxxxxxx," at most 17 characters each. */
  size_t cap = 95 * 24 + 4, n = 0;
  char *text = malloc(cap);
  if (!text) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  text[n++] = '[';
  for (int i = 0; i < 95; i++) {
    double nm = 360 + 5 * i;
    n += (size_t)snprintf(text + n, cap - n, "%s%.0f:%.9g", i ? "," : "", nm, vr_rgb_spectrum_eval(&s, nm));
  }
  snprintf(text + n, cap - n, "]");
  return text;
}

vr_status scn_colour(vr_scn_stmt *t, char **spectrum) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *hex = scn_get(t, "color"), *rgb = scn_get(t, "rgb");
  if (hex && rgb) return scn_fail(p, scn_later(hex, rgb), "give color= or rgb=, not both");
  static const char *const SPACES[] = {"srgb", "linear", NULL};
  int space = -1;
  vr_status st = scn_choice(t, "space", SPACES, &space);
  if (st) return st;
  const vr_scn_opt *sp = scn_get(t, "space");
  double c[3];
  if (hex) {
    if (sp) return scn_fail(p, sp->word, "\"%s\": color=#RRGGBB is sRGB-encoded; space= is for rgb=", sp->word);
    if (!vr_rgb_parse_hex(hex->val, c))
      return scn_fail(p, hex->word, "\"%s\": a colour is #RRGGBB (six hexadecimal digits, sRGB)", hex->word);
  } else {
    if ((st = scn_numbers(p, rgb->word, rgb->val, false, 3, c))) return st;
    for (int k = 0; k < 3; k++) {
      if (!(c[k] >= 0 && c[k] <= 1))
        return scn_fail(p, rgb->word, "\"%s\": each component must lie in [0, 1]", rgb->word);
      if (space != 1) c[k] = vr_srgb_decode(c[k]);
    }
  }
  vr_error e = {0};
  if (!(*spectrum = vr_scene_colour_spectrum(c, &e))) {
    if (e.status == VR_E_NOMEM) return scn_nomem(p);
    return scn_fail(p, (hex ? hex : rgb)->word, "\"%s\": %s", (hex ? hex : rgb)->word, e.message);
  }
  return VR_OK;
}
