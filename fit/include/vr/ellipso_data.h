/* Spectroscopic ellipsometry measurements: (wavelength, angle of incidence,
 * Ψ, Δ) with their standard deviations, read from the instrument files
 * users have.  Every point remembers the file line it came from.
 *
 * Conventions after reading (docs/conventions.md): wavelength in nm, angles
 * in degrees, Δ in [0, 360) in the exp(+iωt) ellipsometric convention. */
#ifndef VR_ELLIPSO_DATA_H
#define VR_ELLIPSO_DATA_H

#include <stddef.h>
#include "vr/error.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Assumed when a file gives no standard deviations: the MSE is then the rms
 * misfit in degrees, and the reported uncertainties (always scaled by the
 * reduced chi-square) do not depend on this choice. */
#define VR_ELLIPSO_DEFAULT_SIGMA_DEG 1.0

typedef struct vr_ellipso_point {
  double nm;
  double aoi_deg;
  double psi_deg, delta_deg;
  double sigma_psi, sigma_delta; /* degrees, > 0 */
  /* As the file gives it (Woollam dpolE / dPolE rows: percent), NAN if
   * not measured; its standard deviation, NAN if not given. */
  double depolarisation, sigma_depolarisation;
  double bandwidth_nm;           /* spectral bandwidth if the file gives it, else NAN */
  /* The normalised Stokes-like values N, C, S when the instrument gives
   * them (Film Sense), has_ncs false otherwise. */
  double N, C, S;
  int has_ncs;
  long line;                     /* 1-based line in the source file */
} vr_ellipso_point;

/* Rows a reader skipped because they carry other quantities than Ψ, Δ and
 * depolarisation (e.g. CompleteEASE "uR" rows, Mueller-matrix rows). */
#define VR_ELLIPSO_MAX_SKIPPED 8
typedef struct vr_ellipso_skipped {
  char tag[32];
  size_t rows;
} vr_ellipso_skipped;

typedef struct vr_ellipso_data {
  size_t n;
  vr_ellipso_point *p;
  char *source;                  /* file name */
  int has_sigma;                 /* the file gave standard deviations */
  const char *format;            /* the reader that read it (static text) */
  size_t nskipped;               /* kinds of rows skipped, at most VR_ELLIPSO_MAX_SKIPPED */
  vr_ellipso_skipped skipped[VR_ELLIPSO_MAX_SKIPPED];
  /* Files of several records (a Film Sense kinetic run): how many, which
   * one was read (1-based) and its time in s; 0, 0, NAN otherwise. */
  size_t nrecords;
  size_t record;
  double record_time_s;
} vr_ellipso_data;

/* How to read a file; zeroed fields take the defaults. */
typedef struct vr_ellipso_read_options {
  const char *unit;              /* overrides the file's wavelength unit ("nm", "um", "A", "eV") */
  double wavelength_nm;          /* > 0: the wavelength of a file that has no wavelength column */
  size_t record;                 /* > 0: the record (1-based) of a file of several (Film Sense kinetic) */
} vr_ellipso_read_options;

/* Reads a file: Woollam WVASE / CompleteEASE .dat and the WVASE-format
 * exports of other instruments (recognised by content), Accurion EP4
 * tables ("#Lambda\tAOI\t..." with a units line), J.A. Woollam Film Sense
 * static and kinetic exports (N, C, S, P per LED), Sentech SpectraRay
 * exports, or CSV with a header naming the columns (wavelength or energy with its
 * unit; aoi/angle; psi; delta; optional sigma_psi/sigma_delta).  unit, when
 * not NULL, overrides the wavelength unit ("nm", "um", "A", "eV"). */
vr_status vr_ellipso_read(const char *path, const char *unit, vr_ellipso_data *out, vr_error *err);
/* The same from memory (name is used in messages). */
vr_status vr_ellipso_parse(const char *text, size_t len, const char *name, const char *unit,
                           vr_ellipso_data *out, vr_error *err);
/* Both with options (o may be NULL). */
vr_status vr_ellipso_read_with(const char *path, const vr_ellipso_read_options *o,
                               vr_ellipso_data *out, vr_error *err);
vr_status vr_ellipso_parse_with(const char *text, size_t len, const char *name,
                                const vr_ellipso_read_options *o, vr_ellipso_data *out,
                                vr_error *err);
void vr_ellipso_data_free(vr_ellipso_data *d);

/* Keeps the points with lo_nm <= wavelength <= hi_nm; returns how many. */
size_t vr_ellipso_crop(vr_ellipso_data *d, double lo_nm, double hi_nm);

/* Δ folded into [0, 360). */
double vr_delta_normalise(double delta_deg);
/* A difference of two Δ folded into (-180, 180]. */
double vr_delta_difference(double d_deg);
/* The distinct angles of incidence (sorted, merged within 0.01°). */
size_t vr_ellipso_angles(const vr_ellipso_data *d, double *angles, size_t max);

#ifdef __cplusplus
}
#endif
#endif
