/* Reading the values of a scene file's options: numbers (decimal only, so
 * that "nan", "inf" and hex floats are refused), lengths with a unit,
 * vectors, integers, light quantities with their unit, spectrum references
 * and the translate/rotate/scale transforms.  Values are slices of the
 * current line; nothing here allocates except spectrum references and
 * resolved paths. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "scene/scene_parse.h"
#include "vr/colour.h"

vr_scene_loc scn_loc(const vr_scn_parser *p, const char *at) {
  vr_scene_loc l = {p->line, (long)(at - p->text) + 1};
  return l;
}

vr_status scn_fail(const vr_scn_parser *p, const char *at, const char *fmt, ...) {
  if (!p->err) return VR_E_PARSE;
  char msg[VR_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return vr_error_at(p->err, VR_E_PARSE, p->file, p->line, scn_loc(p, at).col, "%s", msg);
}

vr_status scn_nomem(const vr_scn_parser *p) { return vr_error_set(p->err, VR_E_NOMEM, "out of memory"); }

/* Length of the decimal number at the start of s[0..n): [+-] digits [. digits]
 * [e [+-] digits], at least one digit before the exponent; 0 if none. */
static size_t lex_number(const char *s, size_t n) {
  size_t i = 0, digits = 0;
  if (i < n && (s[i] == '+' || s[i] == '-')) i++;
  while (i < n && isdigit((unsigned char)s[i])) i++, digits++;
  if (i < n && s[i] == '.') {
    i++;
    while (i < n && isdigit((unsigned char)s[i])) i++, digits++;
  }
  if (!digits) return 0;
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    size_t j = i + 1;
    if (j < n && (s[j] == '+' || s[j] == '-')) j++;
    size_t k = j;
    while (k < n && isdigit((unsigned char)s[k])) k++;
    if (k > j) i = k;
  }
  return i;
}

/* The number at the start of s[0..n); *used receives its length. */
static vr_status lead_number(const vr_scn_parser *p, const char *word, const char *s, size_t n,
                             double *out, size_t *used) {
  size_t i = (n && (s[0] == '+' || s[0] == '-')) ? 1 : 0;
  if (n - i >= 3 && (!strncasecmp(s + i, "nan", 3) || !strncasecmp(s + i, "inf", 3)))
    return scn_fail(p, word, "\"%s\": %.*s is not a finite number", word, (int)n, s);
  size_t len = lex_number(s, n);
  if (!len) return scn_fail(p, word, "\"%s\": expected a number, got \"%.*s\"", word, (int)n, s);
  char buf[128];
  if (len >= sizeof buf) return scn_fail(p, word, "\"%s\": number too long", word);
  memcpy(buf, s, len);
  buf[len] = '\0';
  double v = strtod(buf, NULL);
  if (!isfinite(v)) return scn_fail(p, word, "\"%s\": %s is not a finite number", word, buf);
  *out = v;
  *used = len;
  return VR_OK;
}

static vr_status length_unit(const vr_scn_parser *p, const char *word, const char *u, size_t n,
                             double *scale) {
  if (n == 0 || (n == 1 && u[0] == 'm')) *scale = 1.0;
  else if (n == 2 && !strncmp(u, "cm", 2)) *scale = 0.01;
  else if (n == 2 && !strncmp(u, "mm", 2)) *scale = 0.001;
  else return scn_fail(p, word, "\"%s\": unknown length unit \"%.*s\" (m, cm, mm)", word, (int)n, u);
  return VR_OK;
}

/* One number in s[0..n), a length with its unit when `length`. */
static vr_status one(const vr_scn_parser *p, const char *word, const char *s, size_t n, bool length,
                     double *out) {
  size_t used = 0;
  vr_status st = lead_number(p, word, s, n, out, &used);
  if (st) return st;
  if (length) {
    double scale = 1.0;
    if ((st = length_unit(p, word, s + used, n - used, &scale))) return st;
    *out *= scale;
  } else if (used < n) {
    return scn_fail(p, word, "\"%s\": unexpected \"%.*s\" after the number", word, (int)(n - used),
                    s + used);
  }
  return VR_OK;
}

vr_status scn_number(const vr_scn_parser *p, const char *word, const char *v, double *out) {
  return one(p, word, v, strlen(v), false, out);
}

vr_status scn_length(const vr_scn_parser *p, const char *word, const char *v, double *out) {
  return one(p, word, v, strlen(v), true, out);
}

/* Splits v at sep into exactly n parts; false when the count differs. */
static bool split(const char *v, char sep, int n, const char **part, size_t *len) {
  const char *s = v;
  for (int i = 0; i < n; i++) {
    const char *e = strchr(s, sep);
    if (!e) e = s + strlen(s);
    if (i < n - 1 && !*e) return false;
    if (i == n - 1 && *e) return false;
    part[i] = s;
    len[i] = (size_t)(e - s);
    s = e + 1;
  }
  return true;
}

vr_status scn_numbers(const vr_scn_parser *p, const char *word, const char *v, bool length, int n,
                      double *out) {
  const char *part[4];
  size_t len[4];
  if (n < 1 || n > 4 || !split(v, ',', n, part, len))
    return scn_fail(p, word, "\"%s\": expected %d numbers separated by commas", word, n);
  for (int i = 0; i < n; i++) {
    vr_status st = one(p, word, part[i], len[i], length, &out[i]);
    if (st) return st;
  }
  return VR_OK;
}

/* Normalises v; false for a zero vector.  Scaled by the largest component
 * first, so 1e200,1e200,0 does not overflow. */
static bool unit3(double v[3]) {
  double big = fmax(fabs(v[0]), fmax(fabs(v[1]), fabs(v[2])));
  if (!(big > 0.0)) return false;
  double len = 0.0;
  for (int i = 0; i < 3; i++) v[i] /= big, len += v[i] * v[i];
  len = sqrt(len);
  for (int i = 0; i < 3; i++) v[i] /= len;
  return true;
}

vr_status scn_direction(const vr_scn_parser *p, const char *word, const char *v, double out[3]) {
  vr_status st = scn_numbers(p, word, v, false, 3, out);
  if (st) return st;
  return unit3(out) ? VR_OK : scn_fail(p, word, "\"%s\": a zero-length direction", word);
}

vr_status scn_ints(const vr_scn_parser *p, const char *word, const char *v, char sep, int n, long long lo,
                   long long hi, long long *out) {
  const char *part[4];
  size_t len[4];
  bool ok = n >= 1 && n <= 4 && split(v, sep, n, part, len);
  for (int i = 0; ok && i < n; i++) {
    double x;
    size_t used;
    vr_error quiet;
    vr_scn_parser q = *p;
    q.err = &quiet; /* one message below for every way of being wrong */
    ok = !lead_number(&q, word, part[i], len[i], &x, &used) && used == len[i] && x == floor(x) &&
         x >= (double)lo && x <= (double)hi;
    if (ok) out[i] = (long long)x;
  }
  if (ok) return VR_OK;
  if (n == 1) return scn_fail(p, word, "\"%s\": expected an integer in [%lld, %lld]", word, lo, hi);
  return scn_fail(p, word, "\"%s\": expected %d integers in [%lld, %lld] separated by '%c'", word, n,
                  lo, hi, sep);
}

vr_status scn_u64(const vr_scn_parser *p, const char *word, const char *v, unsigned long long *out) {
  size_t n = strlen(v);
  bool ok = n > 0 && n <= 20;
  for (size_t i = 0; ok && i < n; i++) ok = isdigit((unsigned char)v[i]);
  if (ok) {
    errno = 0;
    *out = strtoull(v, NULL, 10);
    ok = errno == 0;
  }
  return ok ? VR_OK
            : scn_fail(p, word, "\"%s\": expected an integer in [0, 18446744073709551615]", word);
}

static const struct {
  const char *name;
  vr_light_unit unit;
} UNITS[] = {{"W", VR_UNIT_W},       {"lm", VR_UNIT_LM},      {"cd", VR_UNIT_CD},
             {"W/sr", VR_UNIT_W_SR}, {"lx", VR_UNIT_LX},      {"W/m2", VR_UNIT_W_M2},
             {"cd/m2", VR_UNIT_CD_M2}, {"W/m2/sr", VR_UNIT_W_M2_SR}};

/* The largest value a scene may give in each unit: 1000 times the
 * brightest source of its kind, so that a unit slip (1e300 lm, a
 * luminance given as a flux) is refused before any work instead of
 * overflowing the film. */
static const struct {
  vr_light_unit unit;
  double max;
  const char *why;
} LIMITS[] = {
    {VR_UNIT_CD_M2, 1.6e12, "1000 times the sun's disk, 1.6e9 cd/m2"},
    {VR_UNIT_W_M2_SR, 2e10, "1000 times the sun's disk, about 2e7 W/(m2 sr)"},
    {VR_UNIT_LX, 1.3e8, "1000 times direct sunlight, 1.3e5 lx"},
    {VR_UNIT_W_M2, 1.4e6, "1000 times the solar constant, 1361 W/m2"},
    {VR_UNIT_LM, 2e9, "1000 times a 20 kW xenon arc lamp, about 2e6 lm"},
    {VR_UNIT_W, 2e7, "1000 times a 20 kW lamp"},
    {VR_UNIT_CD, 1e12, "1000 times a searchlight, about 1e9 cd"},
    {VR_UNIT_W_SR, 1e10, "1000 times a searchlight's intensity"},
};

static const char *unit_name(vr_light_unit u) {
  for (size_t i = 0; i < sizeof UNITS / sizeof UNITS[0]; i++)
    if (UNITS[i].unit == u) return UNITS[i].name;
  return "?";
}

static void unit_list(const vr_light_unit *allowed, char *buf, size_t cap) {
  size_t used = 0;
  buf[0] = '\0';
  for (size_t i = 0; allowed[i] != VR_UNIT_NONE && used < cap; i++) {
    int k = snprintf(buf + used, cap - used, "%s%s", i ? (allowed[i + 1] ? ", " : " or ") : "",
                     unit_name(allowed[i]));
    if (k < 0) break;
    used += (size_t)k;
  }
}

vr_status scn_quantity(const vr_scn_parser *p, const char *word, const char *v,
                       const vr_light_unit *allowed, vr_light_unit dflt, const char *what,
                       vr_quantity *out) {
  size_t n = strlen(v), used;
  double x;
  vr_status st = lead_number(p, word, v, n, &x, &used);
  if (st) return st;
  const char *u = v + used;
  char list[128];
  unit_list(allowed, list, sizeof list);
  vr_light_unit unit = VR_UNIT_NONE;
  if (!*u) {
    if (dflt == VR_UNIT_NONE) return scn_fail(p, word, "\"%s\": %s needs a unit (%s)", word, what, list);
    unit = dflt;
  } else {
    for (size_t i = 0; i < sizeof UNITS / sizeof UNITS[0]; i++)
      if (!strcmp(u, UNITS[i].name)) unit = UNITS[i].unit;
    if (unit == VR_UNIT_NONE) return scn_fail(p, word, "\"%s\": unknown unit \"%s\" (%s)", word, u, list);
    bool fits = false;
    for (size_t i = 0; allowed[i] != VR_UNIT_NONE; i++) fits |= allowed[i] == unit;
    if (!fits) return scn_fail(p, word, "\"%s\": %s is in %s, not %s", word, what, list, u);
  }
  if (x < 0) return scn_fail(p, word, "\"%s\": %s must not be negative", word, what);
  for (size_t i = 0; i < sizeof LIMITS / sizeof LIMITS[0]; i++)
    if (LIMITS[i].unit == unit && x > LIMITS[i].max)
      return scn_fail(p, word, "\"%s\": %g %s is beyond any light source (at most %g %s, %s): "
                      "a unit slip?", word, x, unit_name(unit), LIMITS[i].max, unit_name(unit),
                      LIMITS[i].why);
  out->value = x;
  out->unit = unit;
  return VR_OK;
}

/* A whole number made of digits and one optional point, as the core's
 * D<CCT> and BB<T> names are written. */
static bool plain_number(const char *s, double *out) {
  size_t n = strlen(s);
  if (!n || lex_number(s, n) != n) return false;
  for (size_t i = 0; i < n; i++)
    if (!isdigit((unsigned char)s[i]) && s[i] != '.') return false;
  *out = strtod(s, NULL);
  return isfinite(*out);
}

/* The names the core's vr_illuminant accepts, checked without building the
 * spectrum: the fixed list, D<CCT> within the daylight range, BB<T>. */
static bool cie_name(const char *v) {
  size_t count;
  const char *const *names = vr_illuminant_names(&count);
  for (size_t i = 0; i < count; i++)
    if (!strcasecmp(v, names[i])) return true;
  double x;
  if ((v[0] == 'D' || v[0] == 'd') && plain_number(v + 1, &x)) return x >= 4000.0 && x <= 25000.0;
  if (!strncasecmp(v, "BB", 2) && plain_number(v + 2, &x)) return x > 0.0;
  return false;
}

vr_status scn_spectrum(const vr_scn_parser *p, const char *word, const char *v, vr_spectrum_ref *out) {
  if (v[0] == '[') {
    vr_status st = scn_inline_check(p, word, v, HUGE_VAL);
    if (st) return st;
  } else if (!strncmp(v, "db:", 3)) {
    if (!v[3]) return scn_fail(p, word, "\"%s\": db: needs a name", word);
  } else if (!strncmp(v, "bb:", 3)) {
    double k;
    size_t n = strlen(v + 3), used;
    vr_status st = lead_number(p, word, v + 3, n, &k, &used);
    if (st) return st;
    if (used < n && strcmp(v + 3 + used, "K"))
      return scn_fail(p, word, "\"%s\": a blackbody is bb:KELVIN", word);
    if (!(k > 0)) return scn_fail(p, word, "\"%s\": a blackbody temperature must be positive", word);
  } else if (!cie_name(v)) {
    return scn_fail(p, word,
                    "\"%s\": unknown spectrum \"%s\" (db:NAME, bb:KELVIN, [W:V,...], or a CIE illuminant: A, "
                    "D50, D55, D65, D75, E, F1-F12, LED-B1-B5, LED-BH1, LED-RGB1, LED-V1, LED-V2, "
                    "D<CCT> for 4000-25000 K, BB<T>)",
                    word, v);
  }
  char *copy = strdup(v);
  if (!copy) return scn_nomem(p);
  free(*out);
  *out = copy;
  return VR_OK;
}

/* sin and cos of an angle in degrees, exact at multiples of 90 so that
 * axis-aligned rotations stay axis-aligned. */
static void sincos_deg(double deg, double *s, double *c) {
  double r = fmod(deg, 360.0);
  if (r < 0) r += 360.0;
  if (r == 0.0) *s = 0, *c = 1;
  else if (r == 90.0) *s = 1, *c = 0;
  else if (r == 180.0) *s = 0, *c = -1;
  else if (r == 270.0) *s = -1, *c = 0;
  else *s = sin(r * M_PI / 180.0), *c = cos(r * M_PI / 180.0);
}

static double det3(const vr_xform *x) {
  const double(*m)[4] = x->m;
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

vr_status scn_transform(const vr_scn_parser *p, const char *word, const char *key, const char *v,
                        vr_xform *x) {
  vr_xform op;
  vr_xform_identity(&op);
  vr_status st = VR_OK;
  if (!strcmp(key, "translate")) {
    double t[3];
    if ((st = scn_numbers(p, word, v, true, 3, t))) return st;
    for (int i = 0; i < 3; i++) op.m[i][3] = t[i];
  } else if (!strcmp(key, "rotate")) {
    double a[4];
    if ((st = scn_numbers(p, word, v, false, 4, a))) return st;
    double k[3] = {a[0], a[1], a[2]}, s, c;
    if (!unit3(k))
      return scn_fail(p, word, "\"%s\": the rotation axis is a zero vector", word);
    sincos_deg(a[3], &s, &c);
    /* Rodrigues: R = c I + s [k]x + (1 - c) k k^T, counterclockwise about
     * the axis seen from its tip (right-hand rule). */
    double K[3][3] = {{0, -k[2], k[1]}, {k[2], 0, -k[0]}, {-k[1], k[0], 0}};
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) op.m[i][j] = (i == j ? c : 0.0) + s * K[i][j] + (1 - c) * k[i] * k[j];
  } else { /* scale */
    double f[3];
    if (strchr(v, ',')) {
      if ((st = scn_numbers(p, word, v, false, 3, f))) return st;
    } else {
      if ((st = scn_number(p, word, v, &f[0]))) return st;
      f[1] = f[2] = f[0];
    }
    if (f[0] == 0 || f[1] == 0 || f[2] == 0)
      return scn_fail(p, word, "\"%s\": a singular transform (a scale of 0)", word);
    for (int i = 0; i < 3; i++) op.m[i][i] = f[i];
  }
  vr_xform_then(x, &op, x);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 4; j++)
      if (!isfinite(x->m[i][j])) return scn_fail(p, word, "\"%s\": the transform overflows", word);
  /* vr_xform_normal needs a finite, non-zero determinant. */
  double d = det3(x);
  if (!isfinite(d)) return scn_fail(p, word, "\"%s\": the transform overflows", word);
  if (d == 0.0) return scn_fail(p, word, "\"%s\": the transform becomes singular", word);
  return VR_OK;
}

char *scn_resolve(const vr_scene *s, const char *rel) {
  if (rel[0] == '/' || !strcmp(s->dir, ".")) return strdup(rel);
  size_t nd = strlen(s->dir), n = nd + strlen(rel) + 2;
  char *out = malloc(n);
  if (out) snprintf(out, n, "%s%s%s", s->dir, nd && s->dir[nd - 1] == '/' ? "" : "/", rel);
  return out;
}
