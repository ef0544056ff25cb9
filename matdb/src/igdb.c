/* LBNL Optics / IGDB ".DAT" glazing files (the format of the International
 * Glazing Database and LBNL Optics exports).  A header of brace lines, then
 * rows of wavelength (micrometres unless the units line says otherwise), T,
 * front R, back R at normal incidence.  Text in Windows-1252 (as IGDB
 * writes it) is converted to UTF-8. */
#include "vr/file.h"
#include "import.h"
#include "utf8.h"
#include "vr/csv.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* "Product Name" -> "product_name". */
static void key_of(const char *s, size_t n, char *out, size_t size) {
  size_t j = 0;
  for (size_t i = 0; i < n && j + 1 < size; i++) {
    unsigned char c = (unsigned char)s[i];
    if (isalnum(c)) out[j++] = (char)tolower(c);
    else if (j && out[j - 1] != '_') out[j++] = '_';
  }
  while (j && out[j - 1] == '_') j--;
  out[j] = '\0';
}

static int contains_ci(const char *hay, const char *needle) {
  size_t n = strlen(needle);
  for (; *hay; hay++)
    if (!strncasecmp(hay, needle, n)) return 1;
  return 0;
}

static char *trim(char *s) {
  while (isspace((unsigned char)*s)) s++;
  char *e = s + strlen(s);
  while (e > s && isspace((unsigned char)e[-1])) *--e = '\0';
  return s;
}

static vr_status number_field(const char *file, long line, const char *field, const char *text,
                              double *out, vr_error *err) {
  if (vr_parse_double(text, out))
    return vr_error_at(err, VR_E_PARSE, file, line, 0, "field '%s': expected a number, got '%s'",
                       field, text);
  return VR_OK;
}

/* One "{ key } value" or "{ key: value }" header line. */
static vr_status header_line(vr_material *m, const char *file, long line, char *s, double *scale,
                             int *have_thickness, vr_error *err) {
  char *close = strchr(s, '}');
  if (!close) return vr_error_at(err, VR_E_PARSE, file, line, 0, "header line without a closing '}'");
  *close = '\0';
  char *inside = trim(s + 1), *after = trim(close + 1);
  char *colon = strchr(inside, ':');
  vr_status st;
  char key[64];
  if (colon && !*after) { /* { Key: value } */
    *colon = '\0';
    key_of(inside, strlen(inside), key, sizeof key);
    char *value = trim(colon + 1);
    if (!*key) return VR_OK;
    double v;
    if (!strcmp(key, "nfrc_id") || !strcmp(key, "igdb_checksum")) {
      if (*value && vr_parse_double(value, &v) == 0)
        return vr_material_add_property(m, key, value, v, NULL, err);
    }
    return vr_material_add_property(m, key, value, NAN, NULL, err);
  }
  key_of(inside, strlen(inside), key, sizeof key);
  if (!*key) return VR_OK; /* "{ }" separator */
  if (!strcmp(key, "units_wavelength_units")) {
    if (contains_ci(after, "micron")) *scale = 1000.0;
    else if (contains_ci(after, "nanomet")) *scale = 1.0;
    else
      return vr_error_at(err, VR_E_PARSE, file, line, 0,
                         "field 'Wavelength Units': unknown unit '%s' (Microns or Nanometers)", after);
    return vr_material_add_property(m, "units", after, NAN, NULL, err);
  }
  if (!strcmp(key, "thickness")) {
    double t;
    if ((st = number_field(file, line, "Thickness", after, &t, err))) return st;
    if (t <= 0)
      return vr_error_at(err, VR_E_RANGE, file, line, 0, "field 'Thickness': %g mm must be positive", t);
    *have_thickness = 1;
    return vr_material_add_property(m, "thickness", NULL, t, "mm", err);
  }
  if (!strcmp(key, "conductivity")) {
    double c;
    if ((st = number_field(file, line, "Conductivity", after, &c, err))) return st;
    return vr_material_add_property(m, "conductivity", NULL, c, "W/(m K)", err);
  }
  if (!strcmp(key, "ir_transmittance")) {
    const char *eq = strchr(after, '=');
    double t;
    if ((st = number_field(file, line, "IR Transmittance", eq ? eq + 1 : after, &t, err))) return st;
    return vr_material_add_property(m, "ir_transmittance", NULL, t, NULL, err);
  }
  if (!strcmp(key, "emissivity_front_back")) {
    const char *eq = strchr(after, '=');
    char buf[128];
    snprintf(buf, sizeof buf, "%s", eq ? eq + 1 : after);
    char *save = NULL, *a = strtok_r(buf, " \t", &save), *b = strtok_r(NULL, " \t", &save);
    double ef, eb;
    /* A blank line ("{ Emissivity, front back }" and nothing, as Optics
     * writes for a coated pane measured into the infrared, e.g. IGDB NFRC
     * 20748) gives none: the spectra give it. */
    if (!a) return VR_OK;
    if (!b)
      return vr_error_at(err, VR_E_PARSE, file, line, 0, "field 'Emissivity': expected front and back values");
    if ((st = number_field(file, line, "Emissivity front", a, &ef, err)) ||
        (st = number_field(file, line, "Emissivity back", b, &eb, err)))
      return st;
    if (ef < 0 || ef > 1 || eb < 0 || eb > 1)
      return vr_error_at(err, VR_E_RANGE, file, line, 0, "field 'Emissivity': values must lie in [0, 1]");
    if ((st = vr_material_add_property(m, "emissivity_front", NULL, ef, NULL, err))) return st;
    return vr_material_add_property(m, "emissivity_back", NULL, eb, NULL, err);
  }
  return vr_material_add_property(m, key, *after ? after : NULL, NAN, NULL, err);
}

vr_status vr_igdb_parse(const char *text, size_t len, const char *file, vr_material *m,
                        vr_error *err) {
  vr_status enc = vr_text_check_encoding(text, len, file, err);
  if (enc) return enc;
  if (memchr(text, '\0', len))
    return vr_error_at(err, VR_E_PARSE, file, 0, 0, "binary data (NUL byte) in a text file");
  /* IGDB and LBNL Optics write Windows-1252 ("Glass(R)" as 0xAE, accents
   * as 0xE9 ...): text that is not UTF-8 is taken as that code page, so
   * product names reach the database, and JSON, as valid UTF-8.  A UTF-8
   * file (with or without a byte-order mark) is kept as it is. */
  if (len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) text += 3, len -= 3;
  char *buf;
  if (vr_utf8_valid(text, len, NULL)) {
    if ((buf = malloc(len + 1))) {
      memcpy(buf, text, len);
      buf[len] = '\0';
    }
  } else {
    buf = vr_cp1252_to_utf8(text, len, NULL);
  }
  if (!buf) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_status st = VR_OK;
  double scale = 1000.0; /* micrometres unless the file says otherwise */
  int have_thickness = 0;
  size_t n = 0, cap = 0;
  double *rows = NULL; /* n x 4 */
  long line = 0, first_row = 0;
  for (char *p = buf, *next; p && *p; p = next) {
    line++;
    next = strchr(p, '\n');
    if (next) *next++ = '\0';
    char *s = trim(p);
    if (!*s) continue;
    if (*s == '{') {
      if (n) {
        st = vr_error_at(err, VR_E_PARSE, file, line, 1, "header line after the data rows");
        goto done;
      }
      if ((st = header_line(m, file, line, s, &scale, &have_thickness, err))) goto done;
      continue;
    }
    double v[4];
    const char *names[4] = {"wavelength", "T", "Rf", "Rb"};
    char *save = NULL, *tok = strtok_r(s, " \t,", &save);
    for (int c = 0; c < 4; c++, tok = strtok_r(NULL, " \t,", &save)) {
      if (!tok) {
        st = vr_error_at(err, VR_E_PARSE, file, line, 0, "field '%s' is missing (a row needs wavelength, T, Rf, Rb)", names[c]);
        goto done;
      }
      int rc = vr_parse_double(tok, &v[c]);
      if (rc) {
        st = vr_error_at(err, rc == -2 ? VR_E_RANGE : VR_E_PARSE, file, line, 0,
                         rc == -2 ? "field '%s': '%s' is not a finite number"
                                  : "field '%s': expected a number, got '%s'", names[c], tok);
        goto done;
      }
      if (c > 0 && (v[c] < 0.0 || v[c] > 1.0)) {
        st = vr_error_at(err, VR_E_RANGE, file, line, 0, "field '%s': %g lies outside [0, 1]", names[c], v[c]);
        goto done;
      }
    }
    if (tok) {
      st = vr_error_at(err, VR_E_PARSE, file, line, 0, "unexpected extra field '%s'", tok);
      goto done;
    }
    /* A measured pane cannot reflect and transmit more than it receives;
     * 0.005 leaves room for the instruments' stated uncertainty. */
    if (v[1] + v[2] > 1.005 || v[1] + v[3] > 1.005) {
      st = vr_error_at(err, VR_E_RANGE, file, line, 0, "T + R = %g exceeds 1 at %g",
                       v[1] + fmax(v[2], v[3]), v[0]);
      goto done;
    }
    double nm = v[0] * scale;
    if (!(nm > 0)) {
      st = vr_error_at(err, VR_E_RANGE, file, line, 0, "field 'wavelength': %g must be positive", v[0]);
      goto done;
    }
    if (n && !(nm > rows[(n - 1) * 4])) {
      st = vr_error_at(err, VR_E_PARSE, file, line, 0,
                       "field 'wavelength': %g does not increase on the previous row", v[0]);
      goto done;
    }
    if (n == cap) {
      cap = cap ? cap * 2 : 128;
      double *r = realloc(rows, cap * 4 * sizeof *r);
      if (!r) {
        st = vr_error_set(err, VR_E_NOMEM, "out of memory");
        goto done;
      }
      rows = r;
    }
    if (!n) first_row = line;
    rows[n * 4] = nm;
    for (int c = 1; c < 4; c++) rows[n * 4 + c] = v[c];
    n++;
  }
  if (!n) {
    st = vr_error_at(err, VR_E_PARSE, file, 0, 0, "no data rows (wavelength T Rf Rb)");
    goto done;
  }
  if (!have_thickness) {
    st = vr_error_at(err, VR_E_PARSE, file, 0, 0, "no '{ Thickness }' header line");
    goto done;
  }
  if (n < 3) { /* one row would make a flat, grey pane */
    st = vr_error_at(err, VR_E_PARSE, file, first_row, 0,
                     "the spectrum has %zu row(s); a spectrum needs at least 3 wavelengths "
                     "(one row cannot say how the pane varies with wavelength)", n);
    goto done;
  }
  {
    const char *roles[3] = {"T", "Rf", "Rb"};
    double *grid = malloc(n * sizeof *grid), *col = malloc(n * sizeof *col);
    if (!grid || !col) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    for (size_t i = 0; !st && i < n; i++) grid[i] = rows[i * 4];
    for (int c = 0; !st && c < 3; c++) {
      for (size_t i = 0; i < n; i++) col[i] = rows[i * 4 + 1 + c];
      vr_spectrum *s = vr_spectrum_create(n, grid, col, err);
      st = s ? vr_material_add_spectrum(m, roles[c], s, err) : VR_E_RANGE;
    }
    free(grid);
    free(col);
  }
  if (!st) st = vr_material_set_text(&m->prov.model, "IGDB optics file (T, Rf, Rb at normal incidence)", err);
  if (!st) {
    const vr_property *pn = vr_material_property(m, "product_name");
    if (pn && pn->text) st = vr_material_set_text(&m->description, pn->text, err);
  }
done:
  free(buf);
  free(rows);
  return st;
}
