/* Ellipsometry data from CSV tables with a header line.  Columns are found
 * by name: the wavelength (or photon energy) with its unit, the angle of
 * incidence, Ψ, Δ, and optionally their standard deviations. */
#include "ellipso_read.h"
#include "vr/csv.h"
#include "vr/spectrum.h"

#include <ctype.h>
#include <stdbool.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

static int has(const char *h, const char *word) {
  size_t n = strlen(word);
  for (; *h; h++)
    if (!strncasecmp(h, word, n)) return 1;
  return 0;
}

static int is_sigma(const char *h) {
  return has(h, "sigma") || has(h, "err") || has(h, "std") || has(h, "unc") ||
         !strncasecmp(h, "dpsi", 4) || !strncasecmp(h, "ddelta", 6) || !strncasecmp(h, "s_", 2);
}

/* The wavelength unit a header names, or NULL. */
static const char *unit_of(const char *h) {
  static const char *const NAMES[] = {"nm", "um", "A", "eV"};
  vr_wl_unit u = vr_wavelength_unit_of(h);
  return u == VR_UNIT_UNKNOWN ? NULL : NAMES[u];
}

vr_status vr_ellipso_parse_csv(const char *text, size_t len, const char *name,
                               const vr_ellipso_read_options *o, vr_ellipso_data *out,
                               vr_error *err) {
  const char *unit = o->unit;
  out->format = "CSV with named columns";
  vr_csv *csv;
  vr_status st = vr_csv_parse(text, len, name, &csv, err);
  if (st) return st;
  long cw = -1, ca = -1, cp = -1, cd = -1, csp = -1, csd = -1;
  const char *wunit = NULL;
  if (vr_csv_rows(csv) == 0) {
    vr_csv_destroy(csv);
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "empty file");
  }
  for (size_t c = 0; c < vr_csv_cols(csv, 0); c++) {
    const char *h = vr_csv_field(csv, 0, c);
    long *slot = NULL;
    if (is_sigma(h)) {
      if (has(h, "psi")) slot = &csp;
      else if (has(h, "delta")) slot = &csd;
    } else if (has(h, "psi")) slot = &cp;
    else if (has(h, "delta")) slot = &cd;
    else if (has(h, "aoi") || has(h, "angle") || has(h, "theta")) slot = &ca;
    else if (cw < 0 && (has(h, "wave") || has(h, "lambda") || has(h, "wl") || unit_of(h))) {
      cw = (long)c;
      wunit = unit_of(h);
    }
    /* Two columns read as one quantity: which one the file means cannot
     * be guessed, and the other would be ignored in silence. */
    if (slot && *slot >= 0) {
      st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                       "columns '%s' and '%s' are both read as the same quantity: rename or remove one",
                       vr_csv_field(csv, 0, (size_t)*slot), h);
      vr_csv_destroy(csv);
      return st;
    }
    if (slot) *slot = (long)c;
  }
  /* A standard deviation for one of Psi, Delta only: weighting one by the
   * file and the other by the default 1 deg would misweigh the fit, and
   * dropping it would ignore the file in silence. */
  if ((csp >= 0) != (csd >= 0)) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "column '%s' gives the standard deviation of %s but no column gives that of %s: "
                     "give both (sigma_psi, sigma_delta) or neither",
                     vr_csv_field(csv, 0, (size_t)(csp >= 0 ? csp : csd)), csp >= 0 ? "Psi" : "Delta",
                     csp >= 0 ? "Delta (sigma_delta)" : "Psi (sigma_psi)");
    vr_csv_destroy(csv);
    return st;
  }
  /* A single-wavelength instrument's table may have no wavelength column:
   * the caller gives it. */
  bool fixed_w = cw < 0 && o->wavelength_nm > 0;
  if (fixed_w) {
    cw = ca;
    out->format = "CSV with named columns, at the wavelength given";
  }
  if (cw < 0 && ca >= 0 && cp >= 0 && cd >= 0) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "no wavelength column: a single-wavelength file needs its wavelength "
                     "given (vr-ellipso --wavelength NM)");
    vr_csv_destroy(csv);
    return st;
  }
  const char *missing = cw < 0 ? "wavelength (or energy)" : ca < 0 ? "angle of incidence (aoi)"
                        : cp < 0 ? "psi" : cd < 0 ? "delta" : NULL;
  if (missing) {
    st = vr_error_at(err, VR_E_PARSE, name, vr_csv_line(csv, 0), 0,
                     "no '%s' column in the header (expected columns such as wavelength_nm, aoi, "
                     "psi, delta, sigma_psi, sigma_delta)", missing);
    vr_csv_destroy(csv);
    return st;
  }
  if (unit) wunit = unit;
  if (!wunit || fixed_w) wunit = "nm";
  size_t rows = vr_csv_rows(csv) - 1;
  out->p = calloc(rows ? rows : 1, sizeof *out->p);
  if (!out->p) {
    vr_csv_destroy(csv);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  out->has_sigma = csp >= 0 && csd >= 0;
  for (size_t r = 1; r <= rows && !st; r++) {
    vr_ellipso_point *p = &out->p[out->n];
    double w;
    const char *wname = vr_csv_field(csv, 0, (size_t)cw);
    if ((st = vr_csv_number(csv, r, (size_t)cw, wname, &w, err)) ||
        (st = vr_csv_number(csv, r, (size_t)ca, vr_csv_field(csv, 0, (size_t)ca), &p->aoi_deg, err)) ||
        (st = vr_csv_number(csv, r, (size_t)cp, vr_csv_field(csv, 0, (size_t)cp), &p->psi_deg, err)) ||
        (st = vr_csv_number(csv, r, (size_t)cd, vr_csv_field(csv, 0, (size_t)cd), &p->delta_deg, err)))
      break;
    p->sigma_psi = p->sigma_delta = VR_ELLIPSO_DEFAULT_SIGMA_DEG;
    if (out->has_sigma &&
        ((st = vr_csv_number(csv, r, (size_t)csp, vr_csv_field(csv, 0, (size_t)csp), &p->sigma_psi, err)) ||
         (st = vr_csv_number(csv, r, (size_t)csd, vr_csv_field(csv, 0, (size_t)csd), &p->sigma_delta, err))))
      break;
    p->line = vr_csv_line(csv, r);
    p->depolarisation = p->sigma_depolarisation = p->bandwidth_nm = NAN;
    if (fixed_w) w = o->wavelength_nm;
    if ((st = vr_ellipso_point_finish(p, w, wunit, name, err))) break;
    out->n++;
  }
  vr_csv_destroy(csv);
  if (!st && out->n == 0) st = vr_error_at(err, VR_E_PARSE, name, 0, 0, "no data rows");
  return st;
}
