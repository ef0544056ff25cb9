/* Reading and writing tables of spectra as delimited text, with errors that
 * name the line and column, and writes that never leave half a file. */
#include "vr/spectrum.h"
#include "vr/csv.h"
#include "vr/atomic_file.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define HC_EV_NM 1239.84198 /* h c in eV nm, CODATA 2018 */

vr_wl_unit vr_wavelength_unit_of(const char *h) {
  char low[128];
  size_t n = 0;
  for (; h[n] && n + 1 < sizeof low; n++) low[n] = (char)tolower((unsigned char)h[n]);
  low[n] = '\0';
  /* Split into alphanumeric tokens ("µ" is kept as its UTF-8 bytes). */
  char *save = NULL;
  for (char *tok = strtok_r(low, " ()[]_,/-", &save); tok; tok = strtok_r(NULL, " ()[]_,/-", &save)) {
    if (!strcmp(tok, "nm") || !strcmp(tok, "nanometer") || !strcmp(tok, "nanometers")) return VR_UNIT_NM;
    if (!strcmp(tok, "um") || !strcmp(tok, "\xc2\xb5m") || !strcmp(tok, "micron") ||
        !strcmp(tok, "microns") || !strcmp(tok, "micrometer") || !strcmp(tok, "micrometers"))
      return VR_UNIT_UM;
    if (!strcmp(tok, "a") || !strcmp(tok, "angstrom") || !strcmp(tok, "angstroms") ||
        !strcmp(tok, "\xc3\x85") || !strcmp(tok, "\xe2\x84\xab"))
      return VR_UNIT_ANGSTROM;
    if (!strcmp(tok, "ev") || !strcmp(tok, "energy")) return VR_UNIT_EV;
  }
  return VR_UNIT_UNKNOWN;
}

double vr_wavelength_to_nm(double x, vr_wl_unit u) {
  switch (u) {
  case VR_UNIT_UM: return x * 1000.0;
  case VR_UNIT_ANGSTROM: return x * 0.1;
  case VR_UNIT_EV: return x > 0 ? HC_EV_NM / x : -1.0;
  default: return x;
  }
}

void vr_spectrum_table_free(vr_spectrum_table *t) {
  if (!t) return;
  for (size_t i = 0; i < t->count; i++) {
    if (t->names) free(t->names[i]);
    if (t->spectra) vr_spectrum_destroy(t->spectra[i]);
  }
  free(t->names);
  free(t->spectra);
  memset(t, 0, sizeof *t);
}

const vr_spectrum *vr_spectrum_table_get(const vr_spectrum_table *t, const char *name) {
  for (size_t i = 0; i < t->count; i++)
    if (strcasecmp(t->names[i], name) == 0) return t->spectra[i];
  return NULL;
}

static vr_status from_csv(vr_csv *csv, vr_spectrum_table *out, vr_error *err) {
  const char *path = vr_csv_name(csv);
  vr_status st = VR_OK;
  size_t rows = vr_csv_rows(csv);
  double probe;
  int has_header = rows > 0 && vr_parse_double(vr_csv_field(csv, 0, 0), &probe) != 0;
  size_t first = has_header ? 1 : 0;
  if (rows <= first) {
    return vr_error_at(err, VR_E_PARSE, path, 0, 0, "no data rows");
  }
  size_t ncols = has_header ? vr_csv_cols(csv, 0) : vr_csv_cols(csv, first);
  if (ncols < 2) {
    return vr_error_at(err, VR_E_PARSE, path, vr_csv_line(csv, 0), 0,
                       "need a wavelength column and at least one value column, found %zu column",
                       ncols);
  }
  vr_wl_unit u = has_header ? vr_wavelength_unit_of(vr_csv_field(csv, 0, 0)) : VR_UNIT_NM;
  if (u == VR_UNIT_UNKNOWN) u = VR_UNIT_NM;
  size_t n = rows - first, m = ncols - 1;
  double *nm = malloc(n * sizeof(double)), *vals = malloc(n * m * sizeof(double));
  out->names = calloc(m, sizeof(char *));
  out->spectra = calloc(m, sizeof(vr_spectrum *));
  if (!nm || !vals || !out->names || !out->spectra) {
    st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
    goto done;
  }
  out->count = m;
  for (size_t c = 0; c < m; c++) {
    char buf[32];
    const char *name = has_header ? vr_csv_field(csv, 0, c + 1) : NULL;
    if (!name || !*name) {
      snprintf(buf, sizeof buf, "value%zu", c + 1);
      name = buf;
    }
    if (!(out->names[c] = strdup(name))) {
      st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
      goto done;
    }
  }
  const char *wl_name = has_header ? vr_csv_field(csv, 0, 0) : "wavelength";
  size_t inside = 0;
  for (size_t r = 0; r < n; r++) {
    size_t row = r + first;
    if (vr_csv_cols(csv, row) != ncols) {
      st = vr_error_at(err, VR_E_PARSE, path, vr_csv_line(csv, row), vr_csv_col_pos(csv, row, ncols),
                       "expected %zu fields, found %zu", ncols, vr_csv_cols(csv, row));
      goto done;
    }
    double w;
    if ((st = vr_csv_number(csv, row, 0, wl_name, &w, err))) goto done;
    if (u == VR_UNIT_EV && w <= 0.0) {
      st = vr_error_at(err, VR_E_RANGE, path, vr_csv_line(csv, row), vr_csv_col_pos(csv, row, 0),
                       "field '%s': photon energy must be positive", wl_name);
      goto done;
    }
    nm[r] = vr_wavelength_to_nm(w, u);
    if (!(nm[r] > 0.0)) {
      st = vr_error_at(err, VR_E_RANGE, path, vr_csv_line(csv, row), vr_csv_col_pos(csv, row, 0),
                       "field '%s': wavelength must be positive, got %g", wl_name, w);
      goto done;
    }
    if (nm[r] >= VR_WL_MIN_NM && nm[r] <= VR_WL_MAX_NM) inside++;
    for (size_t c = 0; c < m; c++)
      if ((st = vr_csv_number(csv, row, c + 1, out->names[c], &vals[r * m + c], err))) goto done;
  }
  /* Tables may run past 100 nm - 100 um (metals' far infrared), but one
   * with no wavelength inside is in another unit than its header says. */
  if (n && !inside) {
    st = vr_error_at(err, VR_E_RANGE, path, vr_csv_line(csv, first), vr_csv_col_pos(csv, first, 0),
                     "field '%s': every wavelength (%g to %g nm as the header's unit reads them) "
                     "is outside 100 nm - 100 um: is the column in another unit (say it in the "
                     "header: wavelength_um, wavelength (nm), eV)?",
                     wl_name, nm[0], nm[n - 1]);
    goto done;
  }
  /* Order: all increasing, or all decreasing (then reversed). */
  int dir = n > 1 ? (nm[1] > nm[0] ? 1 : -1) : 1;
  for (size_t r = 1; r < n; r++) {
    if (nm[r] == nm[r - 1] || (nm[r] > nm[r - 1]) != (dir > 0)) {
      st = vr_error_at(err, VR_E_PARSE, path, vr_csv_line(csv, r + first),
                       vr_csv_col_pos(csv, r + first, 0),
                       "field '%s': wavelengths must be strictly %s; %g nm %s %g nm", wl_name,
                       dir > 0 ? "increasing" : "decreasing", nm[r],
                       nm[r] == nm[r - 1] ? "repeats" : "breaks the order after", nm[r - 1]);
      goto done;
    }
  }
  double *col = malloc(n * sizeof(double)), *grid = malloc(n * sizeof(double));
  if (!col || !grid) {
    free(col);
    free(grid);
    st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
    goto done;
  }
  for (size_t r = 0; r < n; r++) grid[r] = nm[dir > 0 ? r : n - 1 - r];
  for (size_t c = 0; c < m && !st; c++) {
    for (size_t r = 0; r < n; r++) col[r] = vals[(dir > 0 ? r : n - 1 - r) * m + c];
    if (!(out->spectra[c] = vr_spectrum_create(n, grid, col, err))) {
      vr_error_prefix(err, "%s: column '%s': ", path, out->names[c]);
      st = err ? err->status : VR_E_ARG;
    }
  }
  free(col);
  free(grid);
done:
  free(nm);
  free(vals);
  if (st) vr_spectrum_table_free(out);
  return st;
}

vr_status vr_spectrum_table_read(const char *path, vr_spectrum_table *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_csv *csv;
  vr_status st = vr_csv_read(path, &csv, err);
  if (st) return st;
  st = from_csv(csv, out, err);
  vr_csv_destroy(csv);
  return st;
}

vr_status vr_spectrum_table_parse(const char *text, size_t len, const char *name,
                                  vr_spectrum_table *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_csv *csv;
  vr_status st = vr_csv_parse(text, len, name, &csv, err);
  if (st) return st;
  st = from_csv(csv, out, err);
  vr_csv_destroy(csv);
  return st;
}

vr_status vr_spectrum_table_write(const char *path, const vr_spectrum_table *t, vr_error *err) {
  if (t->count == 0) return vr_error_set(err, VR_E_ARG, "%s: nothing to write", path);
  for (size_t i = 1; i < t->count; i++)
    if (!vr_spectrum_same_grid(t->spectra[0], t->spectra[i]))
      return vr_error_set(err, VR_E_ARG, "%s: spectrum '%s' is not on the grid of '%s'", path,
                          t->names[i], t->names[0]);
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st) return st;
  fputs("nm", af.fp);
  for (size_t i = 0; i < t->count; i++) {
    const char *name = t->names[i];
    if (strpbrk(name, ",\"")) {
      fputs(",\"", af.fp);
      for (const char *p = name; *p; p++) {
        if (*p == '"') fputc('"', af.fp);
        fputc(*p, af.fp);
      }
      fputc('"', af.fp);
    } else {
      fprintf(af.fp, ",%s", name);
    }
  }
  fputc('\n', af.fp);
  const vr_spectrum *g = t->spectra[0];
  for (size_t r = 0; r < g->n; r++) {
    fprintf(af.fp, "%.17g", g->nm[r]);
    for (size_t i = 0; i < t->count; i++) fprintf(af.fp, ",%.17g", t->spectra[i]->value[r]);
    fputc('\n', af.fp);
  }
  return vr_atomic_file_commit(&af, err);
}
