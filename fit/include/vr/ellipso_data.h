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
  double depolarisation;         /* NAN if not measured */
  long line;                     /* 1-based line in the source file */
} vr_ellipso_point;

typedef struct vr_ellipso_data {
  size_t n;
  vr_ellipso_point *p;
  char *source;                  /* file name */
  int has_sigma;                 /* the file gave standard deviations */
} vr_ellipso_data;

/* Reads a file: Woollam WVASE / CompleteEASE .dat (recognised by content),
 * or CSV with a header naming the columns (wavelength or energy with its
 * unit; aoi/angle; psi; delta; optional sigma_psi/sigma_delta).  unit, when
 * not NULL, overrides the wavelength unit ("nm", "um", "A", "eV"). */
vr_status vr_ellipso_read(const char *path, const char *unit, vr_ellipso_data *out, vr_error *err);
/* The same from memory (name is used in messages). */
vr_status vr_ellipso_parse(const char *text, size_t len, const char *name, const char *unit,
                           vr_ellipso_data *out, vr_error *err);
void vr_ellipso_data_free(vr_ellipso_data *d);

/* Keeps the points with lo_nm <= wavelength <= hi_nm; returns how many. */
size_t vr_ellipso_crop(vr_ellipso_data *d, double lo_nm, double hi_nm);

/* Δ folded into [0, 360). */
double vr_delta_normalise(double delta_deg);
/* The distinct angles of incidence (sorted, merged within 0.01°). */
size_t vr_ellipso_angles(const vr_ellipso_data *d, double *angles, size_t max);

#ifdef __cplusplus
}
#endif
#endif
