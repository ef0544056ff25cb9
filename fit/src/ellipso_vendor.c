/* Instrument exports: J.A. Woollam WVASE and CompleteEASE ASCII ".dat"
 * files (a comment line, VASEmethod[...] and Original[...] lines, a unit
 * line "nm", "eV" or "Angstroms" optionally followed by TRIG, then rows
 * "[E] λ AOI Ψ Δ σΨ σΔ", "dpolE λ AOI depol σ" (CompleteEASE: "dPolE λ 0
 * depol σ"), or in TRIG files "λ AOI tanΨ cosΔ"; rows of other types,
 * such as CompleteEASE's "uR", are skipped and counted), the same layout
 * as other instruments export it ("nm<TAB><TAB>Psi<TAB>Delta" as the unit
 * line, Accurion EP4), and Sentech SpectraRay exports ("; WAVELENGTH a1 a1
 * a2 a2 ..." then rows "λ Ψ(a1) Δ(a1) Ψ(a2) Δ(a2) ...").  Formats as
 * documented in tests/data/ellipsometry/WOOLLAM_FORMAT.md from real files. */
#include "vr/file.h"
#include "ellipso_read.h"
#include "vr/csv.h"

#include <ctype.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

/* Woollam files start with a comment line and then carry "nm", "eV" or
 * "Angstroms" (optionally "TRIG") on a line, or a VASEmethod line, before
 * the rows; Sentech exports start with "; WAVELENGTH". */
int vr_ellipso_sniff_woollam(const char *text, size_t len) {
  size_t lines = 0;
  if (len > 12 && text[0] == ';') return 1;
  for (size_t i = 0; i < len && lines < 12; lines++) {
    size_t j = i;
    while (j < len && text[j] != '\n') j++;
    size_t l = j - i;
    while (l && (text[i + l - 1] == '\r' || text[i + l - 1] == ' ' || text[i + l - 1] == '\t')) l--;
    if ((l >= 2 && !strncasecmp(text + i, "nm", 2) && (l == 2 || text[i + 2] == ' ' || text[i + 2] == '\t')) ||
        (l == 2 && !strncasecmp(text + i, "eV", 2)) ||
        (l == 9 && !strncasecmp(text + i, "Angstroms", 9)) || (l >= 10 && !strncmp(text + i, "VASEmethod", 10)))
      return 1;
    /* A row tag: "E" or "dpolE" followed by a blank (the line is not
     * NUL-terminated, so lengths are checked before comparing). */
    if (l > 2 && text[i] == 'E' && (text[i + 1] == '\t' || text[i + 1] == ' ')) return 1;
    if (l > 6 && !strncmp(text + i, "dpolE", 5) && (text[i + 5] == '\t' || text[i + 5] == ' ')) return 1;
    i = j + 1;
  }
  return 0;
}

typedef struct lines {
  char *buf, *cur;
  long line;
} lines;

static char *next_line(lines *l) {
  if (!l->cur || !*l->cur) return NULL;
  char *s = l->cur, *nl = strchr(s, '\n');
  if (nl) {
    *nl = '\0';
    l->cur = nl + 1;
  } else {
    l->cur = s + strlen(s);
  }
  size_t n = strlen(s);
  while (n && (s[n - 1] == '\r' || s[n - 1] == ' ' || s[n - 1] == '\t')) s[--n] = '\0';
  l->line++;
  return s;
}

static size_t split(char *s, char **tok, size_t max) {
  size_t n = 0;
  char *save = NULL;
  for (char *t = strtok_r(s, " \t,", &save); t && n < max; t = strtok_r(NULL, " \t,", &save)) tok[n++] = t;
  return n;
}

static vr_status number(const char *name, long line, const char *field, const char *text, double *out,
                        vr_error *err) {
  int rc = vr_parse_double(text, out);
  if (rc == -2) return vr_error_at(err, VR_E_RANGE, name, line, 0, "field '%s': '%s' is not a finite number", field, text);
  if (rc) return vr_error_at(err, VR_E_PARSE, name, line, 0, "field '%s': expected a number, got '%s'", field, text);
  return VR_OK;
}

static vr_status push(vr_ellipso_data *d, size_t *cap, vr_ellipso_point **p, vr_error *err) {
  if (d->n == *cap) {
    size_t c = *cap ? 2 * *cap : 256;
    vr_ellipso_point *q = realloc(d->p, c * sizeof *q);
    if (!q) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    d->p = q;
    *cap = c;
  }
  *p = &d->p[d->n];
  vr_ellipso_point_init(*p);
  return VR_OK;
}

static char *copy_text(const char *text, size_t len, vr_error *err) {
  if (vr_text_check_encoding(text, len, "the file", err)) return NULL;
  if (memchr(text, '\0', len)) {
    vr_error_set(err, VR_E_PARSE, "binary data (NUL byte) in a text file");
    return NULL;
  }
  char *b = malloc(len + 1);
  if (!b) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  memcpy(b, text, len);
  b[len] = '\0';
  return b;
}

static vr_status parse_sentech(lines *L, char *header, const char *name, const char *unit,
                               vr_ellipso_data *d, vr_error *err) {
  d->format = "Sentech SpectraRay export";
  char *tok[64];
  size_t nt = split(header + 1, tok, 64);
  if (nt < 3 || strcasecmp(tok[0], "WAVELENGTH") || (nt - 1) % 2)
    return vr_error_at(err, VR_E_PARSE, name, L->line, 0,
                       "expected '; WAVELENGTH a1 a1 a2 a2 ...' (one Psi and one Delta column per angle)");
  size_t na = (nt - 1) / 2;
  double aoi[32];
  if (na > 32) return vr_error_at(err, VR_E_PARSE, name, L->line, 0, "more than 32 angles");
  for (size_t j = 0; j < na; j++) {
    vr_status st = number(name, L->line, "angle", tok[1 + 2 * j], &aoi[j], err);
    if (st) return st;
  }
  size_t cap = 0;
  char *s;
  while ((s = next_line(L))) {
    if (!*s || *s == ';') continue;
    size_t n = split(s, tok, 64);
    if (n != 1 + 2 * na)
      return vr_error_at(err, VR_E_PARSE, name, L->line, 0, "expected %zu fields (wavelength, then Psi and Delta for %zu angle%s), found %zu",
                         1 + 2 * na, na, na == 1 ? "" : "s", n);
    double w;
    vr_status st = number(name, L->line, "wavelength", tok[0], &w, err);
    for (size_t j = 0; !st && j < na; j++) {
      vr_ellipso_point *p = NULL;
      if ((st = push(d, &cap, &p, err))) break;
      p->line = L->line;
      p->aoi_deg = aoi[j];
      p->sigma_psi = p->sigma_delta = VR_ELLIPSO_DEFAULT_SIGMA_DEG;
      if ((st = number(name, L->line, "psi", tok[1 + 2 * j], &p->psi_deg, err)) ||
          (st = number(name, L->line, "delta", tok[2 + 2 * j], &p->delta_deg, err)) ||
          (st = vr_ellipso_point_finish(p, w, unit ? unit : "nm", name, err)))
        break;
      d->n++;
    }
    if (st) return st;
  }
  return d->n ? VR_OK : vr_error_at(err, VR_E_PARSE, name, 0, 0, "no data rows");
}

vr_status vr_ellipso_parse_woollam(const char *text, size_t len, const char *name,
                                   const vr_ellipso_read_options *o, vr_ellipso_data *d,
                                   vr_error *err) {
  const char *unit_override = o->unit;
  char *buf = copy_text(text, len, err);
  if (!buf) {
    vr_error_prefix(err, "%s: ", name);
    return err ? err->status : VR_E_PARSE;
  }
  lines L = {buf, buf, 0};
  vr_status st = VR_OK;
  char *s, unit[16] = "";
  bool trig = false, swapped = false;
  size_t cap = 0;
  d->has_sigma = 1;
  d->format = "J.A. Woollam WVASE / CompleteEASE .dat";
  /* Header: everything up to and including the unit line. */
  while ((s = next_line(&L))) {
    if (L.line == 1 && s[0] == ';') {
      st = parse_sentech(&L, s, name, unit_override, d, err);
      d->has_sigma = 0;
      free(buf);
      return st;
    }
    char *tok[8];
    char copy[128];
    snprintf(copy, sizeof copy, "%s", s);
    size_t n = split(copy, tok, 8);
    if (n >= 1 && n <= 4 && (!strcasecmp(tok[0], "nm") || !strcasecmp(tok[0], "eV") ||
                             !strcasecmp(tok[0], "Angstroms") || !strcasecmp(tok[0], "A"))) {
      snprintf(unit, sizeof unit, "%s", tok[0]);
      trig = n == 2 && !strcasecmp(tok[1], "TRIG");
      /* WVASE-format exports of other instruments (Accurion EP4) name
       * the last two columns after the unit: "nm<TAB><TAB>Psi<TAB>Delta". */
      if (n == 3 && !strcasecmp(tok[1], "Psi") && !strcasecmp(tok[2], "Delta")) {
        d->format = "WVASE-format export (unit line with column names)";
      } else if (n == 3 && !strcasecmp(tok[1], "Delta") && !strcasecmp(tok[2], "Psi")) {
        swapped = true;
        d->format = "WVASE-format export (unit line with column names)";
      } else if (n >= 2 && !trig) {
        st = vr_error_at(err, VR_E_PARSE, name, L.line, 0,
                         "after the unit '%s': expected TRIG, or the column names Psi and Delta",
                         tok[0]);
        goto done;
      }
      break;
    }
    if (L.line > 8) {
      st = vr_error_at(err, VR_E_PARSE, name, 0, 0, "no unit line (nm, eV or Angstroms) in the header");
      goto done;
    }
  }
  if (!unit[0]) {
    st = vr_error_at(err, VR_E_PARSE, name, 0, 0, "no unit line (nm, eV or Angstroms) in the header");
    goto done;
  }
  if (!strcasecmp(unit, "Angstroms")) snprintf(unit, sizeof unit, "A");
  const char *u = unit_override ? unit_override : unit;
  while ((s = next_line(&L))) {
    char *tok[16];
    size_t n = split(s, tok, 16);
    if (!n) continue;
    size_t k = 0;
    const char *tag = "";
    if (isalpha((unsigned char)tok[0][0])) {
      tag = tok[0];
      k = 1;
    }
    if (!strcasecmp(tag, "dpolE")) {
      /* "dpolE λ AOI depolarisation σ" (WVASE) or "dPolE λ 0 depolarisation
       * σ" (CompleteEASE, no angle): it belongs to the latest Ψ, Δ row at
       * that wavelength (and angle, when one is given). */
      double w, a, dp, sdp = NAN;
      if (n - k < 3) {
        st = vr_error_at(err, VR_E_PARSE, name, L.line, 0,
                         "%s row needs wavelength, angle and depolarisation", tag);
        goto done;
      }
      if ((st = number(name, L.line, "wavelength", tok[k], &w, err)) ||
          (st = number(name, L.line, "aoi", tok[k + 1], &a, err)) ||
          (st = number(name, L.line, "depolarisation", tok[k + 2], &dp, err)) ||
          (n - k > 3 && (st = number(name, L.line, "sigma_depolarisation", tok[k + 3], &sdp, err))))
        goto done;
      double nm = vr_ellipso_to_nm(w, u);
      size_t i = d->n;
      while (i-- > 0 && !((a == 0 || fabs(d->p[i].aoi_deg - a) < 1e-6) &&
                          fabs(d->p[i].nm - nm) <= 1e-9 * nm)) {
      }
      if (i == (size_t)-1) {
        st = vr_error_at(err, VR_E_PARSE, name, L.line, 0,
                         "%s row at %g, %g deg has no Psi/Delta row before it", tag, w, a);
        goto done;
      }
      d->p[i].depolarisation = dp;
      d->p[i].sigma_depolarisation = sdp;
      continue;
    }
    if (*tag && strcmp(tag, "E")) {
      /* Other quantities (CompleteEASE "uR", Mueller-matrix "mm12", ...):
       * skipped, and said. */
      vr_ellipso_note_skipped(d, tag);
      continue;
    }
    size_t fields = n - k;
    if (fields != 4 && fields != 6) {
      st = vr_error_at(err, VR_E_PARSE, name, L.line, 0,
                       "expected wavelength, angle, %s and optionally their standard deviations (4 or 6 numbers), found %zu",
                       trig ? "tan(Psi), cos(Delta)" : "Psi, Delta", fields);
      goto done;
    }
    vr_ellipso_point *p = NULL;
    if ((st = push(d, &cap, &p, err))) goto done;
    double w, v[4] = {0, 0, VR_ELLIPSO_DEFAULT_SIGMA_DEG, VR_ELLIPSO_DEFAULT_SIGMA_DEG};
    const char *names[4] = {trig ? "tan(psi)" : "psi", trig ? "cos(delta)" : "delta", "sigma_psi", "sigma_delta"};
    p->line = L.line;
    if ((st = number(name, L.line, "wavelength", tok[k], &w, err)) ||
        (st = number(name, L.line, "aoi", tok[k + 1], &p->aoi_deg, err)))
      goto done;
    for (size_t j = 0; j + 2 < fields; j++)
      if ((st = number(name, L.line, names[j], tok[k + 2 + j], &v[j], err))) goto done;
    if (fields == 4) d->has_sigma = 0;
    if (trig) {
      if (v[0] < 0 || fabs(v[1]) > 1) {
        st = vr_error_at(err, VR_E_RANGE, name, L.line, 0, "tan(Psi) must be >= 0 and |cos(Delta)| <= 1");
        goto done;
      }
      double psi = atan(v[0]), delta = acos(v[1]);
      p->psi_deg = psi * 180 / M_PI;
      /* cos(Delta) leaves the sign of Delta open: Delta in [0, 180]. */
      p->delta_deg = delta * 180 / M_PI;
      p->sigma_psi = fields == 6 ? v[2] * cos(psi) * cos(psi) * 180 / M_PI : v[2];
      p->sigma_delta = fields == 6 ? v[3] / fmax(fabs(sin(delta)), 1e-3) * 180 / M_PI : v[3];
    } else {
      p->psi_deg = v[swapped];
      p->delta_deg = v[!swapped];
      p->sigma_psi = v[2 + swapped];
      p->sigma_delta = v[3 - swapped];
    }
    if ((st = vr_ellipso_point_finish(p, w, u, name, err))) goto done;
    d->n++;
  }
  if (!d->n)
    st = d->nskipped ? vr_error_at(err, VR_E_PARSE, name, 0, 0,
                                   "no Psi/Delta rows (only rows of type '%s'%s, which carry "
                                   "other quantities)", d->skipped[0].tag,
                                   d->nskipped > 1 ? " and others" : "")
                     : vr_error_at(err, VR_E_PARSE, name, 0, 0, "no data rows");
done:
  free(buf);
  return st;
}
