/* Colours in the scene: an RGB colour becomes the inline reflectance
 * spectrum of Jakob & Hanika's sigmoid (vr/rgb_spectrum.h), written at
 * 5 nm from 360 to 830 nm, so that everything after the parser sees a
 * lambert reflector with a spectrum, as if the user had typed it.  And a
 * lambert line's texture (scn_texture): the file checked here, read when
 * the scene is resolved. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* A file the scene names: there, a regular file, readable. */
static vr_status texture_file(const vr_scn_parser *p, const char *word, const char *path) {
  struct stat sb;
  if (stat(path, &sb))
    return scn_fail(p, word, "\"%s\": cannot open texture '%s': %s", word, path, strerror(errno));
  if (!S_ISREG(sb.st_mode))
    return scn_fail(p, word, "\"%s\": texture '%s' is not a regular file", word, path);
  if (access(path, R_OK))
    return scn_fail(p, word, "\"%s\": cannot read texture '%s': %s", word, path, strerror(errno));
  return VR_OK;
}

/* normal_map=FILE [normal_scale=S]. */
static vr_status normal_map(vr_scn_stmt *t, vr_scene_material *m) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *nm = scn_get(t, "normal_map"), *o = scn_get(t, "normal_scale");
  if (!nm) {
    if (o) return scn_fail(p, o->word, "\"%s\": normal_scale= goes with normal_map=FILE", o->word);
    return VR_OK;
  }
  if (!nm->val[0]) return scn_fail(p, nm->word, "\"%s\": normal_map= needs an image file", nm->word);
  if (!(m->normal_map = scn_resolve(p->s, nm->val))) return scn_nomem(p);
  vr_status st = texture_file(p, nm->word, m->normal_map);
  if (st) return st;
  if (o) {
    if ((st = scn_number(p, o->word, o->val, &m->normal_scale))) return st;
    if (!(m->normal_scale >= 0 && m->normal_scale <= 10))
      return scn_fail(p, o->word, "\"%s\": the scale of a normal map's x and y lies in [0, 10]", o->word);
  }
  return VR_OK;
}

/* A pbr line's metallic=M roughness=R (both required, glTF's factors in
 * [0, 1]) and metallic_roughness=FILE (glTF's packing: roughness in
 * green, metallic in blue, linear). */
vr_status scn_pbr(vr_scn_stmt *t, vr_scene_material *m) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *o;
  m->pbr = true;
  vr_status st;
  if ((st = scn_need(t, "metallic", &o)) ||
      (st = scn_range(t, "metallic", 0, 1, false, false, &m->metallic)) ||
      (st = scn_need(t, "roughness", &o)) ||
      (st = scn_range(t, "roughness", 0, 1, false, false, &m->pbr_roughness)))
    return st;
  if (!(o = scn_get(t, "metallic_roughness"))) return VR_OK;
  if (!o->val[0])
    return scn_fail(p, o->word, "\"%s\": metallic_roughness= needs an image file", o->word);
  if (!(m->mr_map = scn_resolve(p->s, o->val))) return scn_nomem(p);
  return texture_file(p, o->word, m->mr_map);
}

/* tile=N (both) or tile=NU,NV: for the texture and the normal map. */
static vr_status tile(vr_scn_stmt *t, vr_scene_material *m) {
  vr_scn_parser *p = t->p;
  const vr_scn_opt *o = scn_get(t, "tile");
  if (!o) return VR_OK;
  if (!m->texture && !m->normal_map && !m->mr_map)
    return scn_fail(p, o->word, "\"%s\": tile= goes with texture=, normal_map= or metallic_roughness=", o->word);
  double v[2];
  vr_status st;
  if (strchr(o->val, ',')) st = scn_numbers(p, o->word, o->val, false, 2, v);
  else st = scn_number(p, o->word, o->val, &v[0]), v[1] = v[0];
  if (st) return st;
  if (!(v[0] > 0 && v[1] > 0 && isfinite(v[0]) && isfinite(v[1])))
    return scn_fail(p, o->word, "\"%s\": repeats must be positive and finite", o->word);
  m->tile[0] = v[0], m->tile[1] = v[1];
  return VR_OK;
}

vr_status scn_texture(vr_scn_stmt *t, vr_scene_material *m) {
  vr_scn_parser *p = t->p;
  vr_status st0 = normal_map(t, m);
  if (st0) return st0;
  const vr_scn_opt *tex = scn_get(t, "texture"), *o;
  if (!tex) {
    static const char *const NEEDS[] = {"colorspace", "alpha", "alpha_cutoff", NULL};
    for (int k = 0; NEEDS[k]; k++)
      if ((o = scn_get(t, NEEDS[k])))
        return scn_fail(p, o->word, "\"%s\": %s= goes with texture=FILE", o->word, NEEDS[k]);
    return tile(t, m);
  }
  if (!tex->val[0]) return scn_fail(p, tex->word, "\"%s\": texture= needs an image file", tex->word);
  if (!(m->texture = scn_resolve(p->s, tex->val))) return scn_nomem(p);
  vr_status st = texture_file(p, tex->word, m->texture);
  if (st) return st;
  static const char *const SPACES[] = {"srgb", "linear", NULL};
  static const char *const ALPHAS[] = {"off", "mask", "blend", NULL};
  int space = -1, alpha = -1;
  if ((st = scn_choice(t, "colorspace", SPACES, &space)) || (st = scn_choice(t, "alpha", ALPHAS, &alpha)))
    return st;
  m->texture_linear = space == 1;
  m->alpha = alpha == 1 ? VR_ALPHA_MASK : alpha == 2 ? VR_ALPHA_BLEND : VR_ALPHA_OFF;
  if ((o = scn_get(t, "alpha_cutoff"))) {
    if (m->alpha != VR_ALPHA_MASK)
      return scn_fail(p, o->word, "\"%s\": alpha_cutoff= goes with alpha=mask", o->word);
    if ((st = scn_range(t, "alpha_cutoff", 0, 1, false, false, &m->alpha_cutoff))) return st;
  }
  return tile(t, m);
}
