/* A pane's thermal data given beside its spectra (vr/spectro_data.h):
 * hemispherical emissivity of each face, conductivity and the coated face,
 * from CSV comment lines or an LBNL Optics header (read by matdb/igdb.c). */
#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/material.h"
#include "vr/spectro_data.h"

void vr_spectro_thermal_init(vr_spectro_thermal *t) {
  t->emissivity[0] = t->emissivity[1] = NAN;
  t->conductivity = NAN;
  t->tir = NAN;
  t->coated = VR_COATED_UNKNOWN;
  t->line = 0;
}

/* "key:" or "key =" at the start of a comment (after '#'), case-insensitive;
 * the value after it, or NULL. */
static const char *value_of(const char *c, const char *key) {
  while (*c == '#' || *c == ' ' || *c == '\t') c++;
  size_t k = strlen(key);
  if (strncasecmp(c, key, k)) return NULL;
  c += k;
  while (*c == ' ' || *c == '\t') c++;
  if (*c != ':' && *c != '=') return NULL;
  c++;
  while (*c == ' ' || *c == '\t') c++;
  return c;
}

static vr_status number(const char **p, const char *file, long line, const char *field, double lo,
                        double hi, double *v, vr_error *err) {
  char *end;
  *v = strtod(*p, &end);
  if (end == *p || !isfinite(*v) || *v < lo || *v > hi)
    return vr_error_at(err, VR_E_RANGE, file, line, 0, "field '%s': expected a number in [%g, %g]",
                       field, lo, hi);
  *p = end;
  while (**p == ' ' || **p == '\t' || **p == ',') (*p)++;
  return VR_OK;
}

vr_status vr_spectro_coated_parse(const char *s, vr_coated_side *out) {
  static const struct {
    const char *name;
    vr_coated_side side;
  } SIDES[] = {{"front", VR_COATED_FRONT},
               {"back", VR_COATED_BACK},
               {"both", VR_COATED_BOTH},
               {"neither", VR_COATED_NEITHER},
               {"none", VR_COATED_NEITHER}};
  while (*s == ' ' || *s == '\t') s++;
  size_t n = 0;
  while (isalpha((unsigned char)s[n])) n++;
  for (size_t i = 0; i < sizeof SIDES / sizeof *SIDES; i++)
    if (n == strlen(SIDES[i].name) && !strncasecmp(s, SIDES[i].name, n)) {
      *out = SIDES[i].side;
      return VR_OK;
    }
  return VR_E_PARSE;
}

vr_status vr_spectro_thermal_line(const char *c, const char *file, long line,
                                  vr_spectro_thermal *t, vr_error *err) {
  const char *v;
  vr_status st;
  if ((v = value_of(c, "emissivity"))) {
    /* "front back", or one value for both faces. */
    double e[2];
    if ((st = number(&v, file, line, "emissivity", 0, 1, &e[0], err))) return st;
    e[1] = e[0];
    /* A second number is the back's; words after one value are prose. */
    if ((isdigit((unsigned char)*v) || *v == '.' || *v == '-' || *v == '+') &&
        (st = number(&v, file, line, "emissivity back", 0, 1, &e[1], err)))
      return st;
    t->emissivity[0] = e[0], t->emissivity[1] = e[1];
    t->line = line;
  } else if ((v = value_of(c, "conductivity"))) {
    /* W/(m K); glass about 1, polymers 0.1-0.3, metals far above. */
    if ((st = number(&v, file, line, "conductivity", 1e-3, 1e3, &t->conductivity, err))) return st;
  } else if ((v = value_of(c, "ir transmittance"))) {
    if ((st = number(&v, file, line, "ir transmittance", 0, 1, &t->tir, err))) return st;
  } else if ((v = value_of(c, "coated side")) || (v = value_of(c, "coated_side"))) {
    if (vr_spectro_coated_parse(v, &t->coated))
      return vr_error_at(err, VR_E_PARSE, file, line, 0,
                         "field 'coated side': expected front, back, both or neither");
  }
  return VR_OK;
}

void vr_spectro_thermal_from_material(const vr_material *m, vr_spectro_thermal *t) {
  vr_spectro_thermal_init(t);
  const vr_property *ef = vr_material_property(m, "emissivity_front");
  const vr_property *eb = vr_material_property(m, "emissivity_back");
  const vr_property *kc = vr_material_property(m, "conductivity");
  const vr_property *cs = vr_material_property(m, "coated_side");
  const vr_property *ti = vr_material_property(m, "ir_transmittance");
  if (ti && ti->value >= 0 && ti->value <= 1) t->tir = ti->value;
  if (ef && eb && isfinite(ef->value) && isfinite(eb->value))
    t->emissivity[0] = ef->value, t->emissivity[1] = eb->value;
  if (kc && isfinite(kc->value) && kc->value > 0) t->conductivity = kc->value;
  if (cs && cs->text) vr_spectro_coated_parse(cs->text, &t->coated);
}
