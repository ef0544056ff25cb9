/* Inline spectra in scene files: a table written where a spectrum
 * reference or a reflectance goes, in either of two forms,
 *   [400:0.12,500:0.35,600:0.61,700:0.7]     wavelength:value, by commas
 *   [400 0.12 500 0.35 600 0.61 700 0.7]     pbrt-v4's pairs, by spaces
 * (commas and spaces may separate the entries of either form).  The
 * wavelengths are in nm, positive and strictly increasing, at least two
 * points; values are finite and not negative.  The table means what the
 * same table means in the material database: linear between points, and
 * outside it a reflectance holds its end values while a light emits
 * nothing (render/src/resolve.c), so an inline table renders as the
 * database row it would be imported as. */
#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_parse.h"
#include "vr/spectrum.h"

static bool fail(vr_scn_inline *out, const char *text, const char *at, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

static bool fail(vr_scn_inline *out, const char *text, const char *at, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(out->msg, sizeof out->msg, fmt, ap);
  va_end(ap);
  out->at = (size_t)(at - text);
  free(out->nm);
  free(out->v);
  out->nm = out->v = NULL;
  out->n = 0;
  return false;
}

/* A decimal number filling s[0..n): digits, one point, an exponent; no
 * nan, inf or hexadecimal. */
static bool number(const char *s, size_t n, double *out) {
  char buf[64];
  if (n == 0 || n >= sizeof buf) return false;
  for (size_t i = 0; i < n; i++)
    if (!isdigit((unsigned char)s[i]) && !strchr("+-.eE", s[i])) return false;
  memcpy(buf, s, n);
  buf[n] = '\0';
  char *end;
  *out = strtod(buf, &end);
  return *end == '\0' && isfinite(*out) && (isdigit((unsigned char)buf[0]) || buf[0] == '.' ||
                                            ((buf[0] == '+' || buf[0] == '-') && buf[1] &&
                                             (isdigit((unsigned char)buf[1]) || buf[1] == '.')));
}

static bool separator(char c) { return c == ',' || isspace((unsigned char)c); }

bool scn_inline_read(const char *text, double vmax, vr_scn_inline *out) {
  memset(out, 0, sizeof *out);
  if (text[0] != '[') return fail(out, text, text, "an inline spectrum starts with '['");
  const char *close = strchr(text, ']');
  if (!close)
    return fail(out, text, text, "missing ']' at the end of the inline spectrum");
  if (close[1]) return fail(out, text, close + 1, "unexpected \"%s\" after ']'", close + 1);
  /* The entries: words between separators. */
  size_t cap = 0, count = 0;
  for (const char *c = text + 1; c < close;) {
    while (c < close && separator(*c)) c++;
    if (c >= close) break;
    while (c < close && !separator(*c)) c++;
    cap++;
  }
  if (cap == 0) return fail(out, text, text, "an empty spectrum: give at least two points");
  out->nm = malloc(cap * sizeof *out->nm);
  out->v = malloc(cap * sizeof *out->v);
  if (!out->nm || !out->v) return fail(out, text, text, "out of memory");
  int form = 0; /* 1 wavelength:value, 2 pairs */
  const char *pending = NULL; /* pairs: the wavelength waiting for its value */
  for (const char *c = text + 1; c < close;) {
    while (c < close && separator(*c)) c++;
    if (c >= close) break;
    const char *w = c;
    while (c < close && !separator(*c)) c++;
    size_t len = (size_t)(c - w);
    const char *colon = memchr(w, ':', len);
    int f = colon ? 1 : 2;
    if (form && f != form)
      return fail(out, text, w, "\"%.*s\": mixes the forms W:V and W V (use one)", (int)len, w);
    form = f;
    double nm, v;
    const char *vs;
    size_t vlen;
    if (colon) {
      if (!number(w, (size_t)(colon - w), &nm))
        return fail(out, text, w, "\"%.*s\": expected WAVELENGTH:VALUE with finite decimal numbers",
                    (int)len, w);
      vs = colon + 1;
      vlen = (size_t)(c - vs);
    } else if (!pending) {
      if (!number(w, len, &nm))
        return fail(out, text, w, "\"%.*s\": expected a finite decimal number", (int)len, w);
      pending = w;
      out->nm[count] = nm;
      continue;
    } else {
      nm = out->nm[count];
      vs = w;
      vlen = len;
    }
    const char *at = colon ? w : pending;
    if (!number(vs, vlen, &v))
      return fail(out, text, vs, "\"%.*s\": the value is not a finite decimal number", (int)vlen, vs);
    if (!(nm > 0)) return fail(out, text, at, "wavelength %g nm: must be positive", nm);
    if (count && !(nm > out->nm[count - 1]))
      return fail(out, text, at,
                  "wavelength %g nm after %g nm: wavelengths must increase strictly", nm,
                  out->nm[count - 1]);
    if (v < 0) return fail(out, text, vs, "value %g at %g nm is negative", v, nm);
    if (v > vmax)
      return fail(out, text, vs, "value %g at %g nm is above %g", v, nm, vmax);
    out->nm[count] = nm;
    out->v[count] = v;
    count++;
    pending = NULL;
  }
  if (pending)
    return fail(out, text, pending,
                "wavelength %g nm has no value (pbrt-style pairs: WAVELENGTH VALUE ...)",
                out->nm[count]);
  if (count < 2)
    return fail(out, text, text, "one point is not a spectrum: give at least two");
  out->n = count;
  return true;
}

void scn_inline_free(vr_scn_inline *s) {
  free(s->nm);
  free(s->v);
  s->nm = s->v = NULL;
  s->n = 0;
}

vr_spectrum *vr_scene_inline_spectrum(const char *text, vr_error *err) {
  vr_scn_inline t;
  if (!scn_inline_read(text ? text : "", HUGE_VAL, &t)) {
    vr_error_set(err, VR_E_PARSE, "inline spectrum, at character %zu: %s", t.at + 1, t.msg);
    return NULL;
  }
  vr_spectrum *s = vr_spectrum_create(t.n, t.nm, t.v, err);
  scn_inline_free(&t);
  return s;
}

vr_status scn_inline_check(const vr_scn_parser *p, const char *word, const char *v, double vmax) {
  vr_scn_inline t;
  if (scn_inline_read(v, vmax, &t)) {
    scn_inline_free(&t);
    return VR_OK;
  }
  return scn_fail(p, v + t.at, "\"%.*s=[...]\": %s", (int)(v - word > 0 ? v - word - 1 : 0), word,
                  t.msg);
}
