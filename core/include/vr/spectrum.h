/* Tabulated spectra: values on a strictly increasing wavelength grid in nm.
 *
 * A spectrum carries its own grid.  Nothing resamples behind the caller's
 * back: arithmetic between two spectra demands the same grid, and
 * vr_spectrum_resample() is the explicit way to get there.  Evaluation
 * between samples interpolates (linear, or monotone cubic after Fritsch and
 * Carlson 1980, which never overshoots the data: a reflectance stays within
 * the range of its samples).  Outside the grid the end values are held,
 * as CIE 015:2018 section 7.2.2 recommends for colorimetric integration;
 * callers that must refuse extrapolation test vr_spectrum_covers() first. */
#ifndef VR_SPECTRUM_H
#define VR_SPECTRUM_H

#include <stdbool.h>
#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct vr_spectrum {
  size_t n;       /* number of samples, >= 1 */
  double *nm;     /* strictly increasing wavelengths, nm */
  double *value;  /* the samples */
} vr_spectrum;

typedef enum vr_interp { VR_INTERP_LINEAR = 0, VR_INTERP_CUBIC = 1 } vr_interp;
/* The one rule for tabulated optical constants n(λ), k(λ) in the whole
 * toolchain (vr-matdb eval, every fit, the renderer): linear in
 * wavelength, as refellips and pyElli interpolate their tables, so the same
 * table gives the same index everywhere (docs/conventions.md). */
#define VR_NK_INTERP VR_INTERP_LINEAR
typedef enum vr_quadrature { VR_TRAPEZOID = 0, VR_SIMPSON = 1 } vr_quadrature;

/* Copies the samples; refuses n == 0, non-finite numbers and a grid that is
 * not strictly increasing (the message names the offending index). */
vr_spectrum *vr_spectrum_create(size_t n, const double *nm, const double *value, vr_error *err);
/* A uniform grid start, start+step, ... (count samples) holding `fill`. */
vr_spectrum *vr_spectrum_create_uniform(double start, double step, size_t count, double fill,
                                        vr_error *err);
vr_spectrum *vr_spectrum_copy(const vr_spectrum *s, vr_error *err);
void vr_spectrum_destroy(vr_spectrum *s);

double vr_spectrum_eval(const vr_spectrum *s, double nm, vr_interp interp);
bool vr_spectrum_covers(const vr_spectrum *s, double lo_nm, double hi_nm);

/* New spectrum on the given grid (strictly increasing). */
vr_spectrum *vr_spectrum_resample(const vr_spectrum *s, size_t n, const double *grid_nm,
                                  vr_interp interp, vr_error *err);

/* Integral over the spectrum's own grid.  Simpson works on any grid: pairs of
 * uneven intervals use the three-point rule for unequal spacing, and an odd
 * last interval gets the matching end correction, so the rule is exact for
 * quadratics on every grid and for cubics on uniform grids with an even
 * number of intervals.  A single sample integrates to 0. */
double vr_spectrum_integrate(const vr_spectrum *s, vr_quadrature q);

/* Element-wise arithmetic; the two grids must be identical (VR_E_ARG if not). */
vr_status vr_spectrum_add(vr_spectrum *a, const vr_spectrum *b, vr_error *err);
vr_status vr_spectrum_mul(vr_spectrum *a, const vr_spectrum *b, vr_error *err);
void vr_spectrum_scale(vr_spectrum *a, double factor);
bool vr_spectrum_same_grid(const vr_spectrum *a, const vr_spectrum *b);

/* Units of a wavelength axis, as named in file headers. */
typedef enum vr_wl_unit { VR_UNIT_NM = 0, VR_UNIT_UM, VR_UNIT_ANGSTROM, VR_UNIT_EV, VR_UNIT_UNKNOWN } vr_wl_unit;
/* The unit named by a header or a unit word: "nm", "um"/"µm"/"micron(s)",
 * "A"/"Å"/"angstrom(s)", "eV"/"energy", alone or as a token of a longer
 * header ("wavelength (nm)", "lambda_um", "energy_eV"); VR_UNIT_UNKNOWN if
 * none. */
vr_wl_unit vr_wavelength_unit_of(const char *text);
/* x in unit u as nm (hc = 1239.84198 eV nm for energies; x <= 0 in eV gives
 * a negative result, which callers reject). */
double vr_wavelength_to_nm(double x, vr_wl_unit u);

/* A table of spectra read from or written to delimited text: the first column
 * is the wavelength, each further column one spectrum named by its header. */
typedef struct vr_spectrum_table {
  size_t count;
  char **names;
  vr_spectrum **spectra;
} vr_spectrum_table;

/* Reads a table.  The first column header states the unit: "nm", "um"/"µm"
 * (micrometres), "A"/"angstrom", "eV" (converted with hc = 1239.84198 eV nm,
 * CODATA 2018), or a name containing one of those in parentheses or after an
 * underscore, e.g. "wavelength (nm)", "lambda_um".  Rows may come in
 * increasing or decreasing order (eV files run backwards); duplicates and
 * non-monotonic rows are errors naming the line. */
vr_status vr_spectrum_table_read(const char *path, vr_spectrum_table *out, vr_error *err);
/* The wavelengths a table may hold, in nm: 100 nm (vacuum UV) to 100 um
 * (far infrared).  A value outside, once converted by the header's unit,
 * is refused naming its line and field (values in um under an "nm" header
 * would otherwise make a material of 0.4-0.7 nm). */
#define VR_WL_MIN_NM 100.0
#define VR_WL_MAX_NM 1e5
/* The same from text in memory; name is used in messages. */
vr_status vr_spectrum_table_parse(const char *text, size_t len, const char *name,
                                  vr_spectrum_table *out, vr_error *err);
/* Writes all spectra, which must share one grid, with a header line.  The
 * file is written to a temporary name and renamed, so a failure never leaves
 * a half-written file behind. */
vr_status vr_spectrum_table_write(const char *path, const vr_spectrum_table *t, vr_error *err);
void vr_spectrum_table_free(vr_spectrum_table *t);
/* The spectrum named `name` (case-insensitive), or NULL. */
const vr_spectrum *vr_spectrum_table_get(const vr_spectrum_table *t, const char *name);

#ifdef __cplusplus
}
#endif
#endif
