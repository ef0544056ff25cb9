/* Spectrophotometer tables of glazing (vr/spectro_data.h has the format). */
#include "vr/spectro_data.h"
#include "vr/material_io.h"

#include <stdbool.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/csv.h"
#include "vr/file.h"
#include "vr/spectrum.h"

void vr_spectro_destroy(vr_spectro_data *d) {
  if (!d) return;
  for (size_t i = 0; i < d->ncurves; i++) {
    free(d->curves[i].state);
    free(d->curves[i].p);
  }
  free(d->curves);
  free(d->source);
  free(d);
}

static bool word_is(const char *h, const char *const *names) {
  /* The header up to a unit in brackets or a '%': "T (%)" -> "T"; a
   * leading '%' (Cary and Lambda write "%T", "%R") is skipped. */
  char buf[64];
  size_t n = 0;
  while (*h == '%' || isspace((unsigned char)*h)) h++;
  for (; h[n] && h[n] != '(' && h[n] != '[' && h[n] != '%' && n + 1 < sizeof buf; n++)
    buf[n] = h[n];
  while (n > 0 && (isspace((unsigned char)buf[n - 1]) || buf[n - 1] == '_')) n--;
  buf[n] = '\0';
  for (; *names; names++)
    if (strcasecmp(buf, *names) == 0) return true;
  return false;
}

static bool contains_ci(const char *h, const char *w) {
  for (size_t n = strlen(w); *h; h++)
    if (!strncasecmp(h, w, n)) return true;
  return false;
}

static const char *const T_NAMES[] = {"T", "Tnorm", "Tsol", "transmittance", "trans", NULL};
static const char *const RF_NAMES[] = {"Rf", "R", "R_front", "Rfront", "Rfsol", "reflectance",
                                       "refl", NULL};
static const char *const RB_NAMES[] = {"Rb", "R_back", "Rback", "Rbsol", NULL};
/* Absorbance (decadic, as spectrophotometers report it): T = 10^-A. */
static const char *const ABS_NAMES[] = {"Abs", "absorbance", "OD", NULL};
static const char *const ANGLE_NAMES[] = {"angle", "aoi", "theta", "incidence", "angle_deg", NULL};
static const char *const STATE_NAMES[] = {"state", "tint", "charge", "voltage", "irradiance",
                                          "time", "label", NULL};

static bool is_wavelength_header(const char *h) {
  return contains_ci(h, "wave") || contains_ci(h, "lambda") ||
         vr_wavelength_unit_of(h) != VR_UNIT_UNKNOWN;
}

/* A thickness written "thickness: 3.048 mm" or "thickness = 3 mm" (in a
 * CSV comment) -> nm.  Prose that merely mentions a thickness (no ':' or
 * '=' after the word) is not a thickness line.  A value that is not a
 * positive finite number is refused, naming the line: a sign dropped
 * here would make a different pane. */
vr_status vr_spectro_pane_plausible(double nm, const char *file, long line, vr_error *err) {
  if (nm >= 1e4 && nm <= 2e8) return VR_OK;
  return vr_error_at(err, VR_E_RANGE, file, line, 0,
                     "a pane of %g mm is outside 0.01-200 mm: a unit slip (nm or um where mm is "
                     "meant)? A film on glass is a layer of a stack, not a pane",
                     nm * 1e-6);
}

static vr_status thickness_line(const char *c, const char *file, long line, double *nm,
                                vr_error *err) {
  const char *t = c;
  while ((t = strstr(t, "thickness")) != NULL) {
    const char *q = t + 9;
    while (*q == ' ' || *q == '\t') q++;
    /* The pane's: "thickness", or "pane/glass/sample/substrate thickness";
     * another word before it ("coating thickness: 12 nm") is not. */
    const char *w = t;
    while (w > c && (w[-1] == ' ' || w[-1] == '\t')) w--;
    const char *w0 = w;
    while (w0 > c && isalpha((unsigned char)w0[-1])) w0--;
    size_t wl = (size_t)(w - w0);
    static const char *const OWNERS[] = {"pane", "glass", "sample", "substrate"};
    bool pane = wl == 0;
    for (size_t k = 0; !pane && k < 4; k++)
      pane = wl == strlen(OWNERS[k]) && !strncasecmp(w0, OWNERS[k], wl);
    if ((*q == ':' || *q == '=') && pane) {
      t = q + 1;
      break;
    }
    t = q;
  }
  if (!t) return VR_OK;
  while (*t == ' ' || *t == '\t') t++;
  char *end;
  double v = strtod(t, &end);
  if (end == t || !isfinite(v) || !(v > 0)) {
    char shown[48];
    size_t k = 0;
    while (t[k] && t[k] != '\r' && t[k] != '\n' && k + 1 < sizeof shown) shown[k] = t[k], k++;
    shown[k] = '\0';
    return vr_error_at(err, VR_E_RANGE, file, line, 0,
                       "thickness '%s': a pane's thickness must be a positive number (mm, or "
                       "give nm or um)", shown);
  }
  /* Blanks, a no-break space (spreadsheets) included. */
  for (;;) {
    if (*end == ' ' || *end == '\t') end++;
    else if ((unsigned char)end[0] == 0xC2 && (unsigned char)end[1] == 0xA0) end += 2;
    else break;
  }
  /* The unit: a word from the list, or none (mm, the unit of glazing
   * thickness); any other word is refused, not read as mm.  A word is
   * letters and the micro signs (U+00B5, U+03BC). */
  const char *u = end;
  size_t ul = 0;
  for (;;) {
    unsigned char b0 = (unsigned char)u[ul], b1 = b0 ? (unsigned char)u[ul + 1] : 0;
    if (isalpha(b0)) ul++;
    else if ((b0 == 0xC2 && b1 == 0xB5) || (b0 == 0xCE && b1 == 0xBC)) ul += 2;
    else break;
  }
  static const struct {
    const char *name;
    double nm;
  } UNITS[] = {{"nm", 1},           {"um", 1e3},          {"\xc2\xb5m", 1e3},
               {"\xce\xbcm", 1e3},  {"micron", 1e3},      {"microns", 1e3},
               {"mm", 1e6},         {"millimetre", 1e6},  {"millimetres", 1e6},
               {"millimeter", 1e6}, {"millimeters", 1e6}, {"cm", 1e7},
               {"m", 1e9}};
  double scale = ul ? 0 : 1e6;
  for (size_t k = 0; ul && k < sizeof UNITS / sizeof *UNITS; k++)
    if (strlen(UNITS[k].name) == ul && !strncasecmp(u, UNITS[k].name, ul)) scale = UNITS[k].nm;
  if (!(scale > 0))
    return vr_error_at(err, VR_E_RANGE, file, line, 0,
                       "thickness: unknown unit '%.*s' (nm, um, mm, cm or m; none is mm)", (int)ul,
                       u);
  *nm = v * scale;
  return vr_spectro_pane_plausible(*nm, file, line, err);
}

static vr_spectro_curve *curve_for(vr_spectro_data *d, const char *state, double angle,
                                   size_t cap, vr_error *err) {
  for (size_t i = 0; i < d->ncurves; i++) {
    vr_spectro_curve *c = &d->curves[i];
    bool same_state = (!state && !c->state) || (state && c->state && !strcmp(state, c->state));
    if (same_state && c->angle_deg == angle) return c;
  }
  vr_spectro_curve *grown = realloc(d->curves, (d->ncurves + 1) * sizeof *grown);
  if (!grown) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  d->curves = grown;
  vr_spectro_curve *c = &d->curves[d->ncurves];
  memset(c, 0, sizeof *c);
  c->angle_deg = angle;
  c->p = malloc(cap * sizeof *c->p);
  c->state = state ? strdup(state) : NULL;
  if (!c->p || (state && !c->state)) {
    free(c->p);
    free(c->state);
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return NULL;
  }
  d->ncurves++;
  return c;
}

/* Range and sum checks of one row. */
static vr_status check_point(const vr_spectro_point *p, const char *name, vr_error *err) {
  const struct {
    const char *field;
    double v;
  } f[] = {{"T", p->T}, {"Rf", p->Rf}, {"Rb", p->Rb}};
  for (int i = 0; i < 3; i++) {
    if (isnan(f[i].v)) continue;
    if (f[i].v < 0 || f[i].v > 1)
      return vr_error_at(err, VR_E_RANGE, name, p->line, 0,
                         "field '%s': %g is outside [0, 1] at %g nm", f[i].field, f[i].v, p->nm);
  }
  if (!isnan(p->Rf) && p->T + p->Rf > 1.0 + VR_SPECTRO_TR_TOLERANCE)
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0,
                       "fields 'T' + 'Rf' = %g exceed 1 (+%g tolerance) at %g nm: a pane cannot "
                       "transmit and reflect more than it receives", p->T + p->Rf,
                       VR_SPECTRO_TR_TOLERANCE, p->nm);
  if (!isnan(p->Rb) && p->T + p->Rb > 1.0 + VR_SPECTRO_TR_TOLERANCE)
    return vr_error_at(err, VR_E_RANGE, name, p->line, 0,
                       "fields 'T' + 'Rb' = %g exceed 1 (+%g tolerance) at %g nm", p->T + p->Rb,
                       VR_SPECTRO_TR_TOLERANCE, p->nm);
  return VR_OK;
}

/* Wavelengths run one way through a spectrum: up, or down throughout (as
 * Cary and Lambda exports write them; such a spectrum is turned round in
 * vr_spectro_finish). */
static vr_status append(vr_spectro_data *d, const char *state, double angle,
                        const vr_spectro_point *p, size_t cap, const char *name, vr_error *err) {
  vr_status st = check_point(p, name, err);
  if (st) return st;
  vr_spectro_curve *c = curve_for(d, state, angle, cap, err);
  if (!c) return err ? err->status : VR_E_NOMEM;
  if (c->n > 0) {
    const vr_spectro_point *last = &c->p[c->n - 1];
    bool down = c->n >= 2 && c->p[1].nm < c->p[0].nm;
    bool ok = c->n == 1 ? p->nm != last->nm : down ? p->nm < last->nm : p->nm > last->nm;
    if (!ok) {
      const char *what = p->nm == last->nm ? "repeats" : down ? "is above" : "is below";
      return vr_error_at(err, VR_E_PARSE, name, p->line, 0,
                         "field 'wavelength': %g nm %s %g nm of line %ld; the wavelengths of each "
                         "spectrum (state %s, angle %g deg) must strictly increase (or strictly "
                         "decrease throughout, as Cary and Lambda exports write them)",
                         p->nm, what, last->nm, last->line, state ? state : "-", angle);
    }
  }
  c->p[c->n++] = *p;
  return VR_OK;
}

/* After reading: descending spectra turned round, and each spectrum at
 * least VR_SPECTRO_MIN_ROWS long (one row would make a flat, grey pane). */
static vr_status finish(vr_spectro_data *d, vr_error *err) {
  if (d->ncurves == 0)
    return vr_error_at(err, VR_E_PARSE, d->source, 0, 0, "no data rows");
  for (size_t i = 0; i < d->ncurves; i++) {
    vr_spectro_curve *c = &d->curves[i];
    if (c->n < VR_SPECTRO_MIN_ROWS) {
      char which[96] = "";
      if (d->ncurves > 1)
        snprintf(which, sizeof which, " (state %s, angle %g deg)", c->state ? c->state : "-",
                 c->angle_deg);
      return vr_error_at(err, VR_E_PARSE, d->source, c->n ? c->p[0].line : 0, 0,
                         "the spectrum%s has %zu row(s); a spectrum needs at least %d "
                         "wavelengths (one row cannot say how the pane varies with wavelength)",
                         which, c->n, VR_SPECTRO_MIN_ROWS);
    }
    if (c->p[1].nm < c->p[0].nm)
      for (size_t a = 0, b = c->n - 1; a < b; a++, b--) {
        vr_spectro_point t = c->p[a];
        c->p[a] = c->p[b];
        c->p[b] = t;
      }
  }
  return VR_OK;
}

/* Spectrophotometer exports (Agilent Cary WinUV, PerkinElmer UV WinLab):
 * title lines (sample names) before the header, and metadata after a blank
 * line once the data end.  Both become comments, line numbers kept, so the
 * CSV reader sees a header and its rows.  Sets *vendor when it did so. */
static char *vendor_layout(const char *text, size_t len, size_t *out_len, bool *vendor,
                           char ***titles, size_t *ntitles) {
  *vendor = false;
  *titles = NULL;
  *ntitles = 0;
  /* Lines, found once. */
  size_t nl = 0;
  for (size_t i = 0; i < len; i++) nl += text[i] == '\n';
  size_t *start = malloc((nl + 2) * sizeof *start), nlines = 0;
  if (!start) return NULL;
  start[nlines++] = 0;
  for (size_t i = 0; i < len; i++)
    if (text[i] == '\n') start[nlines++] = i + 1;
  if (start[nlines - 1] >= len) nlines--;
  long header = -1;
  for (size_t l = 0; l < nlines && header < 0 && l < 12; l++) {
    size_t e = l + 1 < nlines ? start[l + 1] : len;
    char buf[512];
    size_t k = e - start[l] < sizeof buf - 1 ? e - start[l] : sizeof buf - 1;
    memcpy(buf, text + start[l], k);
    buf[k] = '\0';
    if (buf[0] == '#') continue;
    /* "Wavelength (nm)" (Cary), "nm" as the first field (UV WinLab). */
    bool wl = contains_ci(buf, "wavelength") || contains_ci(buf, "lambda") ||
              (!strncasecmp(buf, "nm", 2) && (buf[2] == ',' || buf[2] == '\t' || buf[2] == ';'));
    bool pct = strstr(buf, "%T") || strstr(buf, "%R") || contains_ci(buf, "%trans") ||
               contains_ci(buf, "%refl");
    if (wl && (pct || l > 0)) {
      /* A header with a value column; title lines are the content before. */
      bool has_content_before = false;
      for (size_t j = 0; j < l; j++) {
        size_t ee = start[j + 1];
        for (size_t q = start[j]; q < ee; q++)
          if (!isspace((unsigned char)text[q])) {
            has_content_before = text[q] != '#';
            break;
          }
        if (has_content_before) break;
      }
      if (has_content_before || pct) header = (long)l;
      else break; /* a plain header on the first line: no export layout */
    } else if (wl) {
      break;
    }
  }
  if (header < 0) {
    free(start);
    return NULL;
  }
  /* The copy: '#' before each title line and each line of the trailing
   * block, which starts at the first blank line after a data row. */
  char *out = malloc(len + nlines + 1);
  if (!out) {
    free(start);
    return NULL;
  }
  size_t o = 0;
  bool seen_data = false, trailer = false;
  for (size_t l = 0; l < nlines; l++) {
    size_t b = start[l], e = l + 1 < nlines ? start[l + 1] : len;
    bool blank = true;
    for (size_t q = b; q < e; q++)
      if (!isspace((unsigned char)text[q])) blank = false;
    if ((long)l > header && !blank && !trailer) seen_data = true;
    if ((long)l > header && blank && seen_data) trailer = true;
    bool comment = !blank && ((long)l < header || trailer) && text[b] != '#';
    if (comment && (long)l < header) {
      /* Sample names of the title line, for messages. */
      size_t q = b;
      while (q < e) {
        size_t f = q;
        while (q < e && text[q] != ',' && text[q] != '\t' && text[q] != ';' && text[q] != '\r' &&
               text[q] != '\n')
          q++;
        if (q > f) {
          char **g = realloc(*titles, (*ntitles + 1) * sizeof *g);
          if (g) {
            *titles = g;
            g[*ntitles] = malloc(q - f + 1);
            if (g[*ntitles]) {
              memcpy(g[*ntitles], text + f, q - f);
              g[*ntitles][q - f] = '\0';
              (*ntitles)++;
            }
          }
        }
        q++;
      }
    }
    if (comment) out[o++] = '#';
    memcpy(out + o, text + b, e - b);
    o += e - b;
  }
  out[o] = '\0';
  *out_len = o;
  free(start);
  *vendor = true;
  return out;
}

static void free_titles(char **t, size_t n) {
  for (size_t i = 0; i < n; i++) free(t[i]);
  free(t);
}

vr_status vr_spectro_parse_csv(const char *text, size_t len, const char *name,
                               vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  bool vendor;
  char **titles;
  size_t ntitles;
  size_t recast_len = 0;
  char *recast = vendor_layout(text, len, &recast_len, &vendor, &titles, &ntitles);
  if (recast) text = recast, len = recast_len;
  vr_csv *csv;
  vr_status st = vr_csv_parse(text, len, name, &csv, err);
  if (st) {
    free(recast);
    free_titles(titles, ntitles);
    return st;
  }
  vr_spectro_data *d = calloc(1, sizeof *d);
  if (!d || !(d->source = strdup(name))) {
    free(d);
    vr_csv_destroy(csv);
    free(recast);
    free_titles(titles, ntitles);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  d->thickness_nm = NAN;
  vr_spectro_thermal_init(&d->thermal);
  /* Thickness and thermal comments, with their line numbers from the text. */
  {
    long line = 1;
    for (const char *p = text, *e = text + len; p < e && !st; line++) {
      const char *nl = memchr(p, '\n', (size_t)(e - p));
      size_t n = nl ? (size_t)(nl - p) : (size_t)(e - p);
      const char *q = p;
      while (q < p + n && (*q == ' ' || *q == '\t')) q++;
      if (q < p + n && *q == '#' && n < 512) {
        char buf[512];
        memcpy(buf, q, n - (size_t)(q - p));
        buf[n - (size_t)(q - p)] = '\0';
        st = thickness_line(buf, name, line, &d->thickness_nm, err);
        if (!st) st = vr_spectro_thermal_line(buf, name, line, &d->thermal, err);
      }
      p = nl ? nl + 1 : e;
    }
    if (st) goto done;
  }
  if (vr_csv_rows(csv) < 2) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_rows(csv) ? vr_csv_line(csv, 0) : 0, 0,
                     "expected a header line and at least %d data rows", VR_SPECTRO_MIN_ROWS);
    goto done;
  }
  long cw = -1, cT = -1, cf = -1, cb = -1, ca = -1, cs = -1;
  long wT = -1, wf = -1, wb = -1; /* the wavelength column of each value column */
  size_t nT = 0;
  bool absorbance = false;
  vr_wl_unit unit = VR_UNIT_NM;
  bool pct[3] = {false, false, false};
  long last_w = -1;
  for (size_t c = 0; c < vr_csv_cols(csv, 0); c++) {
    const char *h = vr_csv_field(csv, 0, c);
    if (!*h) continue;
    if (word_is(h, T_NAMES) || word_is(h, ABS_NAMES)) {
      nT++;
      if (cT < 0) {
        cT = (long)c, wT = last_w, pct[0] = strchr(h, '%') != NULL;
        absorbance = word_is(h, ABS_NAMES);
      }
    } else if (word_is(h, RF_NAMES) && cf < 0) {
      cf = (long)c, wf = last_w, pct[1] = strchr(h, '%') != NULL;
    } else if (word_is(h, RB_NAMES) && cb < 0) {
      cb = (long)c, wb = last_w, pct[2] = strchr(h, '%') != NULL;
    } else if (word_is(h, ANGLE_NAMES) && ca < 0) {
      ca = (long)c;
    } else if (word_is(h, STATE_NAMES) && cs < 0) {
      cs = (long)c;
    } else if (is_wavelength_header(h)) {
      last_w = (long)c;
      if (cw < 0) {
        cw = (long)c;
        vr_wl_unit u = vr_wavelength_unit_of(h);
        if (u != VR_UNIT_UNKNOWN) unit = u;
      }
    }
  }
  if (cw < 0 || cT < 0) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "no '%s' column in the header (expected columns such as wavelength_nm, T, "
                     "Rf, Rb, angle, state, or a Cary/Lambda export's \"Wavelength (nm),%%T\")",
                     cw < 0 ? "wavelength" : "T");
    goto done;
  }
  if (nT > 1) {
    char list[256] = "";
    for (size_t i = 0; i < ntitles && strlen(list) + strlen(titles[i]) + 3 < sizeof list; i++) {
      if (i) strcat(list, ", ");
      strcat(list, titles[i]);
    }
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "%zu transmittance columns (samples %s): one pane per file; export each "
                     "sample alone (its %%T and, if measured, its %%R)", nT,
                     *list ? list : "unnamed");
    goto done;
  }
  if (wT < 0) wT = cw;
  if (wf < 0) wf = cw;
  if (wb < 0) wb = cw;
  d->has_Rf = cf >= 0;
  d->has_Rb = cb >= 0;
  d->has_angle = ca >= 0;
  d->has_state = cs >= 0;
  size_t rows = vr_csv_rows(csv), inside = 0;
  long outside_line = 0;
  double outside_w = 0, outside_nm = 0;
  for (size_t r = 1; r < rows && !st; r++) {
    vr_spectro_point p = {.Rf = NAN, .Rb = NAN, .line = vr_csv_line(csv, r)};
    double w, angle = 0;
    if ((st = vr_csv_number(csv, r, (size_t)wT, "wavelength", &w, err))) break;
    p.nm = vr_wavelength_to_nm(w, unit);
    if (!(p.nm > 0)) {
      st = vr_error_at(err, VR_E_RANGE, name, p.line, vr_csv_col_pos(csv, r, (size_t)wT),
                       "field 'wavelength': %g is not a positive wavelength", w);
      break;
    }
    if (p.nm >= VR_WL_MIN_NM && p.nm <= VR_WL_MAX_NM) inside++;
    else if (!outside_line) outside_line = p.line, outside_w = w, outside_nm = p.nm;
    /* In an export of column pairs, R must sit on T's wavelengths. */
    const long wcol[2] = {wf, wb}, vcol[2] = {cf, cb};
    for (int q = 0; q < 2 && !st; q++) {
      double w2;
      if (vcol[q] < 0 || wcol[q] == wT) continue;
      if ((st = vr_csv_number(csv, r, (size_t)wcol[q], "wavelength", &w2, err))) break;
      if (fabs(w2 - w) > 1e-9 * fmax(1, fabs(w)))
        st = vr_error_at(err, VR_E_PARSE, name, p.line, vr_csv_col_pos(csv, r, (size_t)wcol[q]),
                         "field '%s': measured at %g, not at T's wavelength %g (export T and R "
                         "on the same wavelengths)", q ? "Rb" : "Rf", w2, w);
    }
    if (st) break;
    if ((st = vr_csv_number(csv, r, (size_t)cT, absorbance ? "Abs" : "T", &p.T, err))) break;
    if (absorbance) p.T = pow(10.0, -p.T);
    if (cf >= 0 && (st = vr_csv_number(csv, r, (size_t)cf, "Rf", &p.Rf, err))) break;
    if (cb >= 0 && (st = vr_csv_number(csv, r, (size_t)cb, "Rb", &p.Rb, err))) break;
    if (ca >= 0) {
      if ((st = vr_csv_number(csv, r, (size_t)ca, "angle", &angle, err))) break;
      if (!(angle >= 0 && angle < 90)) {
        st = vr_error_at(err, VR_E_RANGE, name, p.line, vr_csv_col_pos(csv, r, (size_t)ca),
                         "field 'angle': %g deg is outside [0, 90)", angle);
        break;
      }
    }
    if (pct[0]) p.T /= 100;
    if (pct[1]) p.Rf /= 100;
    if (pct[2]) p.Rb /= 100;
    const char *state = NULL;
    if (cs >= 0) {
      state = vr_csv_field(csv, r, (size_t)cs);
      if (!state || !*state) {
        st = vr_error_at(err, VR_E_PARSE, name, p.line, 0, "field 'state' is empty");
        break;
      }
    }
    st = append(d, state, angle, &p, rows, name, err);
  }
  /* A measurement may run past 100 nm - 100 um, but one with no wavelength
   * inside is in another unit than its header says. */
  if (!st && !inside && outside_line)
    st = vr_error_at(err, VR_E_RANGE, name, outside_line, 0,
                     "field 'wavelength': %g is %g nm, and no wavelength of the file lies in 100 "
                     "nm - 100 um: is the column in another unit (say it in the header: "
                     "wavelength_um, wavelength (nm))?",
                     outside_w, outside_nm);
  if (!st) st = finish(d, err);
done:
  vr_csv_destroy(csv);
  free(recast);
  free_titles(titles, ntitles);
  if (st) {
    vr_spectro_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

/* LBNL Optics files (IGDB ".DAT", Optics 5 ".LOF"): read by the database's
 * importer (one reader of the layout), then taken as a measurement. */
vr_status vr_spectro_parse_optics(const char *text, size_t len, const char *name,
                                  vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  vr_material *m = vr_material_create("optics", VR_KIND_GLAZING, err);
  if (!m) return err ? err->status : VR_E_NOMEM;
  vr_status st = vr_igdb_parse(text, len, name, m, err);
  if (!st) st = vr_spectro_from_material(m, out, err);
  vr_material_destroy(m);
  if (!st) {
    char *src = strdup(name);
    if (!src) {
      vr_spectro_destroy(*out);
      *out = NULL;
      return vr_error_set(err, VR_E_NOMEM, "out of memory");
    }
    free((*out)->source);
    (*out)->source = src;
    /* Each point keeps its file line for later messages: the data rows are
     * the lines that are neither blank nor a brace header, in order. */
    vr_spectro_curve *c = &(*out)->curves[0];
    size_t i = 0;
    long line = 1;
    for (size_t at = 0; at < len && i < c->n; line++) {
      size_t end = at;
      while (end < len && text[end] != '\n') end++;
      size_t k = at;
      if (line == 1 && len >= 3 && !memcmp(text, "\xEF\xBB\xBF", 3)) k = 3;
      while (k < end && isspace((unsigned char)text[k])) k++;
      if (k < end && text[k] != '{') c->p[i++].line = line;
      at = end + 1;
    }
  }
  return st;
}

vr_status vr_spectro_from_material(const vr_material *m, vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  const vr_spectrum *T = vr_material_spectrum(m, "T");
  if (!T)
    return vr_error_set(err, VR_E_NOT_FOUND, "material %s has no transmittance (role T)", m->name);
  const vr_spectrum *Rf = vr_material_spectrum(m, "Rf"), *Rb = vr_material_spectrum(m, "Rb");
  vr_spectro_data *d = calloc(1, sizeof *d);
  if (!d) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  d->source = strdup(m->prov.source_path ? m->prov.source_path : m->name);
  const vr_property *th = vr_material_property(m, "thickness");
  d->thickness_nm = th && isfinite(th->value) ? th->value * 1e6 : NAN;
  vr_spectro_thermal_from_material(m, &d->thermal);
  d->has_Rf = Rf != NULL;
  d->has_Rb = Rb != NULL;
  vr_status st = d->source ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < T->n && !st; i++) {
    vr_spectro_point p = {.nm = T->nm[i], .T = T->value[i], .Rf = NAN, .Rb = NAN};
    if (Rf) p.Rf = vr_spectrum_eval(Rf, p.nm, VR_INTERP_LINEAR);
    if (Rb) p.Rb = vr_spectrum_eval(Rb, p.nm, VR_INTERP_LINEAR);
    st = append(d, NULL, 0, &p, T->n, d->source, err);
  }
  if (!st) st = finish(d, err);
  if (st) {
    vr_spectro_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

/* The LBNL Optics layout is known by its content (a first line in braces),
 * whatever the extension: IGDB ".DAT", Optics 5 ".LOF", or a renamed copy. */
static bool looks_like_optics(const char *text, size_t n) {
  size_t i = 0;
  if (n >= 3 && !memcmp(text, "\xef\xbb\xbf", 3)) i = 3;
  while (i < n && isspace((unsigned char)text[i])) i++;
  return i < n && text[i] == '{';
}

vr_status vr_spectro_read(const char *path, vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  char *buf;
  size_t n;
  vr_status st = vr_read_file(path, 0, &buf, &n, err);
  if (st) return st;
  st = looks_like_optics(buf, n) ? vr_spectro_parse_optics(buf, n, path, out, err)
                                 : vr_spectro_parse_csv(buf, n, path, out, err);
  free(buf);
  return st;
}

vr_spectrum *vr_spectro_spectrum(const vr_spectro_curve *c, char which, vr_error *err) {
  double *nm = malloc(c->n * sizeof *nm), *v = malloc(c->n * sizeof *v);
  vr_spectrum *s = NULL;
  if (!nm || !v) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    goto out;
  }
  for (size_t i = 0; i < c->n; i++) {
    nm[i] = c->p[i].nm;
    v[i] = which == 'T' ? c->p[i].T : which == 'f' ? c->p[i].Rf : c->p[i].Rb;
    if (isnan(v[i])) {
      vr_error_set(err, VR_E_NOT_FOUND, "%s was not measured",
                   which == 'f' ? "front reflectance Rf" : "back reflectance Rb");
      goto out;
    }
  }
  s = vr_spectrum_create(c->n, nm, v, err);
out:
  free(nm);
  free(v);
  return s;
}
