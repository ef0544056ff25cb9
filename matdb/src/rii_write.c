/* refractiveindex.info YAML output: writes a vr_material as a database file
 * (REFERENCES, COMMENTS, SPECS, a formula or tabulated n / nk block and a
 * tabulated k block) whose numbers read back exactly with vr_rii_parse. */
#include "rii.h"

#include "vr/csv.h"

#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The shortest of %.15g, %.16g and %.17g that reads back as exactly v. */
static void fmt_double(char *buf, size_t size, double v) {
  for (int p = 15; p <= 17; p++) {
    snprintf(buf, size, "%.*g", p, v);
    if (strtod(buf, NULL) == v) return;
  }
}

/* nm as µm text that token_um reads back as exactly nm: the shortest of
 * 15, 16 or 17 significant digits that does, with the decimal point moved
 * three places (17 digits always do), in plain notation where it is short. */
static void fmt_um(char *out, size_t size, double nm) {
  for (int sig = 15; sig <= 17; sig++) {
    char e[48], digits[24];
    snprintf(e, sizeof e, "%.*e", sig - 1, nm); /* [-]d.ddde±XX */
    const char *p = e;
    bool neg = *p == '-';
    if (neg) p++;
    int nd = 0;
    for (; *p && *p != 'e'; p++)
      if (*p >= '0' && *p <= '9' && nd < (int)sizeof digits - 1) digits[nd++] = *p;
    while (nd > 1 && digits[nd - 1] == '0') nd--;
    digits[nd] = '\0';
    const int ex = (*p ? atoi(p + 1) : 0) - 3; /* value = d.ddd x 10^ex µm */
    if (ex >= -5 && ex < 0) /* 0.000ddd */
      snprintf(out, size, "%s0.%.*s%s", neg ? "-" : "", -ex - 1, "00000", digits);
    else if (ex >= 0 && ex < 15 && nd > ex + 1) /* dd.ddd */
      snprintf(out, size, "%s%.*s.%s", neg ? "-" : "", ex + 1, digits, digits + ex + 1);
    else if (ex >= 0 && ex < 15) /* dd000 */
      snprintf(out, size, "%s%s%.*s", neg ? "-" : "", digits, ex + 1 - nd, "000000000000000");
    else /* d.ddde-7 */
      snprintf(out, size, "%s%c%s%se%d", neg ? "-" : "", digits[0], nd > 1 ? "." : "",
               digits + 1, ex);
    double back;
    if (vr_rii_um_to_nm(out, strlen(out), &back) == 0 && back == nm) return;
  }
}

/* Characters YAML will not take raw in a scalar, or takes as a line break
 * (C1 controls including NEL, LS, PS, U+FFFE/U+FFFF): the escape that
 * reads back as the same UTF-8 bytes, and how many bytes it replaces. */
static const char *unicode_escape(const unsigned char *p, size_t *used, char buf[8]) {
  if (p[0] == 0xC2 && p[1] >= 0x80 && p[1] <= 0x9F) {
    snprintf(buf, 8, "\\x%02X", p[1]);
    *used = 2;
    return buf;
  }
  if (p[0] == 0xE2 && p[1] == 0x80 && (p[2] == 0xA8 || p[2] == 0xA9)) {
    *used = 3;
    return p[2] == 0xA8 ? "\\L" : "\\P";
  }
  if (p[0] == 0xEF && p[1] == 0xBF && (p[2] == 0xBE || p[2] == 0xBF)) {
    *used = 3;
    return p[2] == 0xBE ? "\\uFFFE" : "\\uFFFF";
  }
  return NULL;
}

/* A literal block keeps a text readable; it cannot carry leading blanks on
 * the first line, a leading empty line or control characters, which go in a
 * double-quoted scalar with escapes instead. */
static bool literal_ok(const char *s) {
  if (!*s || *s == ' ' || *s == '\t' || *s == '\n') return false;
  char buf[8];
  size_t used;
  for (const unsigned char *p = (const unsigned char *)s; *p; p++)
    if ((*p < 0x20 && *p != '\n' && *p != '\t') || *p == 0x7f || unicode_escape(p, &used, buf))
      return false;
  return true;
}

static void write_quoted(FILE *f, const char *s) {
  char buf[8];
  size_t used;
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
    const char *esc = unicode_escape(p, &used, buf);
    if (esc) {
      fputs(esc, f);
      p += used - 1;
      continue;
    }
    switch (*p) {
    case '"': fputs("\\\"", f); break;
    case '\\': fputs("\\\\", f); break;
    case '\n': fputs("\\n", f); break;
    case '\t': fputs("\\t", f); break;
    case '\r': fputs("\\r", f); break;
    default:
      if (*p < 0x20 || *p == 0x7f) fprintf(f, "\\x%02X", *p);
      else fputc(*p, f);
    }
  }
  fputc('"', f);
}

static void write_text(FILE *f, const char *key, const char *s) {
  if (!s || !*s) return;
  fprintf(f, "%s: ", key);
  if (!literal_ok(s)) {
    write_quoted(f, s);
    fputc('\n', f);
    return;
  }
  fputs("|\n", f);
  for (const char *line = s;;) {
    const char *eol = strchr(line, '\n');
    size_t n = eol ? (size_t)(eol - line) : strlen(line);
    if (n) fprintf(f, "    %.*s", (int)n, line);
    fputc('\n', f);
    if (!eol) break;
    line = eol + 1;
  }
}

/* A key that reads back as the same text without quotes. */
static bool plain_key_ok(const char *s) {
  if (!*s || *s == '-' || *s == '.') return false;
  for (; *s; s++)
    if (!((*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9') ||
          *s == '_' || *s == '.' || *s == '-' || *s == '(' || *s == ')'))
      return false;
  return true;
}

static void write_rows(FILE *f, const vr_spectrum *a, const vr_spectrum *b) {
  char x[40], y[40], z[40];
  fputs("    data: |\n", f);
  for (size_t i = 0; i < a->n; i++) {
    fmt_um(x, sizeof x, a->nm[i]);
    fmt_double(y, sizeof y, a->value[i]);
    if (b) {
      fmt_double(z, sizeof z, b->value[i]);
      fprintf(f, "        %s %s %s\n", x, y, z);
    } else {
      fprintf(f, "        %s %s\n", x, y);
    }
  }
}

vr_status vr_rii_write(FILE *f, const vr_material *m, vr_error *err) {
  if (!f || !m) return vr_error_set(err, VR_E_ARG, "vr_rii_write: NULL argument");
  const vr_formula *fo = &m->n_formula;
  const vr_spectrum *n = vr_material_spectrum(m, "n"), *k = vr_material_spectrum(m, "k");
  /* Refuse what the format cannot hold rather than drop it silently. */
  for (size_t i = 0; i < m->nspectra; i++)
    if (strcmp(m->spectra[i].role, "n") && strcmp(m->spectra[i].role, "k"))
      return vr_error_set(err, VR_E_ARG,
                          "material '%s' has '%s' data, which a refractiveindex.info file cannot "
                          "hold (only n and k)",
                          m->name, m->spectra[i].role);
  if (fo->type && n)
    return vr_error_set(err, VR_E_ARG,
                        "material '%s' has both a formula and tabulated n; a refractiveindex.info "
                        "file holds one",
                        m->name);
  if (!fo->type && !n && !k)
    return vr_error_set(err, VR_E_ARG, "material '%s' has no n or k to write", m->name);
  if (fo->type) {
    if (fo->type < 1 || fo->type > 9 || fo->ncoeffs == 0 || fo->ncoeffs > VR_FORMULA_MAX_COEFFS)
      return vr_error_set(err, VR_E_ARG,
                          "material '%s': formula type %d with %zu coefficients cannot be written",
                          m->name, fo->type, fo->ncoeffs);
    bool finite = isfinite(fo->min_nm) && isfinite(fo->max_nm) && fo->min_nm > 0;
    for (size_t i = 0; i < fo->ncoeffs; i++) finite = finite && isfinite(fo->c[i]);
    if (!finite)
      return vr_error_set(err, VR_E_ARG,
                          "material '%s': the formula has a non-finite coefficient or range",
                          m->name);
  }

  fputs("# refractiveindex.info database format, written by Virtuelium-C (vr_rii_write);\n"
        "# wavelengths in micrometres\n",
        f);
  write_text(f, "REFERENCES", m->prov.reference);
  write_text(f, "COMMENTS", m->description);
  fputs("DATA:\n", f);
  char x[40], y[40];
  if (fo->type) {
    fmt_um(x, sizeof x, fo->min_nm);
    fmt_um(y, sizeof y, fo->max_nm);
    fprintf(f, "  - type: formula %d\n    wavelength_range: %s %s\n    coefficients:", fo->type,
            x, y);
    for (size_t i = 0; i < fo->ncoeffs; i++) {
      fmt_double(x, sizeof x, fo->c[i]);
      fprintf(f, " %s", x);
    }
    fputc('\n', f);
  }
  if (n && k && vr_spectrum_same_grid(n, k)) {
    fputs("  - type: tabulated nk\n", f);
    write_rows(f, n, k);
  } else {
    if (n) {
      fputs("  - type: tabulated n\n", f);
      write_rows(f, n, NULL);
    }
    if (k) {
      fputs("  - type: tabulated k\n", f);
      write_rows(f, k, NULL);
    }
  }

  /* Properties go back as one flat SPECS mapping: a key "a.b" reads back
   * as "a.b", numbers stay plain and text is quoted so it stays text. */
  bool header = false;
  for (size_t i = 0; i < m->nprops; i++) {
    const vr_property *p = &m->props[i];
    if (!p->text && !isfinite(p->value)) continue;
    if (!header) {
      fputs("SPECS:\n", f);
      header = true;
    }
    fputs("    ", f);
    if (plain_key_ok(p->key)) fputs(p->key, f);
    else write_quoted(f, p->key);
    fputs(": ", f);
    if (p->text) {
      write_quoted(f, p->text);
    } else {
      fmt_double(x, sizeof x, p->value);
      if (p->unit) {
        /* "20 °C" is how the database itself writes a quantity with a unit. */
        char *both = malloc(strlen(x) + strlen(p->unit) + 2);
        if (!both) return vr_error_set(err, VR_E_NOMEM, "out of memory");
        sprintf(both, "%s %s", x, p->unit);
        write_quoted(f, both);
        free(both);
      } else {
        fputs(x, f);
      }
    }
    fputc('\n', f);
  }
  if (fflush(f) != 0 || ferror(f))
    return vr_error_set(err, VR_E_IO, "material '%s': writing the refractiveindex.info file failed",
                        m->name);
  return VR_OK;
}
