/* Spectrophotometer tables of glazing (vr/spectro_data.h has the format). */
#include "vr/spectro_data.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/csv.h"
#include "vr/file.h"
#include "vr/material_io.h"
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
  /* The header up to a unit in brackets or a '%': "T (%)" -> "T". */
  char buf[64];
  size_t n = 0;
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
static const char *const ANGLE_NAMES[] = {"angle", "aoi", "theta", "incidence", "angle_deg", NULL};
static const char *const STATE_NAMES[] = {"state", "tint", "charge", "voltage", "irradiance",
                                          "time", "label", NULL};

/* "# thickness: 3.048 mm" -> nm. */
static void thickness_comment(const char *c, double *nm) {
  const char *t = strstr(c, "thickness");
  if (!t) return;
  t += 9;
  while (*t && !isdigit((unsigned char)*t) && *t != '.') t++;
  char *end;
  double v = strtod(t, &end);
  if (end == t || !(v > 0)) return;
  while (isspace((unsigned char)*end)) end++;
  if (!strncasecmp(end, "nm", 2)) *nm = v;
  else if (!strncasecmp(end, "um", 2) || !strncmp(end, "\xc2\xb5m", 3)) *nm = v * 1e3;
  else *nm = v * 1e6; /* mm, the unit of glazing thickness */
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

static vr_status append(vr_spectro_data *d, const char *state, double angle,
                        const vr_spectro_point *p, size_t cap, const char *name, vr_error *err) {
  vr_status st = check_point(p, name, err);
  if (st) return st;
  vr_spectro_curve *c = curve_for(d, state, angle, cap, err);
  if (!c) return err ? err->status : VR_E_NOMEM;
  if (c->n > 0 && !(p->nm > c->p[c->n - 1].nm)) {
    const char *what = p->nm == c->p[c->n - 1].nm ? "repeats" : "is below";
    return vr_error_at(err, VR_E_PARSE, name, p->line, 0,
                       "field 'wavelength': %g nm %s %g nm of line %ld; the wavelengths of each "
                       "spectrum (state %s, angle %g deg) must strictly increase",
                       p->nm, what, c->p[c->n - 1].nm, c->p[c->n - 1].line, state ? state : "-",
                       angle);
  }
  c->p[c->n++] = *p;
  return VR_OK;
}

vr_status vr_spectro_parse_csv(const char *text, size_t len, const char *name,
                               vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  vr_csv *csv;
  vr_status st = vr_csv_parse(text, len, name, &csv, err);
  if (st) return st;
  vr_spectro_data *d = calloc(1, sizeof *d);
  if (!d || !(d->source = strdup(name))) {
    free(d);
    vr_csv_destroy(csv);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  d->thickness_nm = NAN;
  for (size_t i = 0; i < vr_csv_comment_count(csv); i++)
    thickness_comment(vr_csv_comment(csv, i), &d->thickness_nm);
  if (vr_csv_rows(csv) < 2) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_rows(csv) ? vr_csv_line(csv, 0) : 0, 0,
                     "expected a header line and at least one data row");
    goto done;
  }
  long cw = -1, cT = -1, cf = -1, cb = -1, ca = -1, cs = -1;
  vr_wl_unit unit = VR_UNIT_NM;
  bool pct[3] = {false, false, false};
  for (size_t c = 0; c < vr_csv_cols(csv, 0); c++) {
    const char *h = vr_csv_field(csv, 0, c);
    if (word_is(h, T_NAMES) && cT < 0) cT = (long)c, pct[0] = strchr(h, '%') != NULL;
    else if (word_is(h, RF_NAMES) && cf < 0) cf = (long)c, pct[1] = strchr(h, '%') != NULL;
    else if (word_is(h, RB_NAMES) && cb < 0) cb = (long)c, pct[2] = strchr(h, '%') != NULL;
    else if (word_is(h, ANGLE_NAMES) && ca < 0) ca = (long)c;
    else if (word_is(h, STATE_NAMES) && cs < 0) cs = (long)c;
    else if (cw < 0 && (contains_ci(h, "wave") || contains_ci(h, "lambda") ||
                        vr_wavelength_unit_of(h) != VR_UNIT_UNKNOWN)) {
      cw = (long)c;
      vr_wl_unit u = vr_wavelength_unit_of(h);
      if (u != VR_UNIT_UNKNOWN) unit = u;
    }
  }
  if (cw < 0 || cT < 0) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "no '%s' column in the header (expected columns such as wavelength_nm, T, "
                     "Rf, Rb, angle, state)", cw < 0 ? "wavelength" : "T");
    goto done;
  }
  d->has_Rf = cf >= 0;
  d->has_Rb = cb >= 0;
  d->has_angle = ca >= 0;
  d->has_state = cs >= 0;
  size_t rows = vr_csv_rows(csv);
  for (size_t r = 1; r < rows && !st; r++) {
    vr_spectro_point p = {.Rf = NAN, .Rb = NAN, .line = vr_csv_line(csv, r)};
    double w, angle = 0;
    if ((st = vr_csv_number(csv, r, (size_t)cw, "wavelength", &w, err))) break;
    p.nm = vr_wavelength_to_nm(w, unit);
    if (!(p.nm > 0)) {
      st = vr_error_at(err, VR_E_RANGE, name, p.line, vr_csv_col_pos(csv, r, (size_t)cw),
                       "field 'wavelength': %g is not a positive wavelength", w);
      break;
    }
    if ((st = vr_csv_number(csv, r, (size_t)cT, "T", &p.T, err))) break;
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
done:
  vr_csv_destroy(csv);
  if (st) {
    vr_spectro_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
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
  d->has_Rf = Rf != NULL;
  d->has_Rb = Rb != NULL;
  vr_status st = d->source ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < T->n && !st; i++) {
    vr_spectro_point p = {.nm = T->nm[i], .T = T->value[i], .Rf = NAN, .Rb = NAN};
    if (Rf) p.Rf = vr_spectrum_eval(Rf, p.nm, VR_INTERP_LINEAR);
    if (Rb) p.Rb = vr_spectrum_eval(Rb, p.nm, VR_INTERP_LINEAR);
    st = append(d, NULL, 0, &p, T->n, d->source, err);
  }
  if (st) {
    vr_spectro_destroy(d);
    return st;
  }
  *out = d;
  return VR_OK;
}

static bool looks_like_igdb(const char *path) {
  const char *dot = strrchr(path, '.');
  return dot && strcasecmp(dot, ".dat") == 0;
}

vr_status vr_spectro_read(const char *path, vr_spectro_data **out, vr_error *err) {
  *out = NULL;
  if (looks_like_igdb(path)) {
    vr_material *m = NULL;
    vr_status st = vr_import_file(path, NULL, NULL, "vr-spectro", &m, err);
    if (st) return st;
    st = vr_spectro_from_material(m, out, err);
    vr_material_destroy(m);
    if (!st) {
      free((*out)->source);
      (*out)->source = strdup(path);
    }
    return st;
  }
  char *buf;
  size_t n;
  vr_status st = vr_read_file(path, 0, &buf, &n, err);
  if (st) return st;
  st = vr_spectro_parse_csv(buf, n, path, out, err);
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
