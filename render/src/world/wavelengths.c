/* The wavelengths a path carries (world/rscene.h). */
#include <float.h>
#include <math.h>

#include "world/rscene.h"

double vr_wavelength_at(const vr_rscene *rs, double wl0, int i) {
  double span = rs->lmax - rs->lmin, step = span / rs->nwl;
  if (rs->bins_mode) return rs->lmin + (i + 0.5) * step;
  if (i == 0) return wl0;
  double x = (wl0 - rs->lmin) + i * step;
  if (x >= span) x -= span;
  return rs->lmin + x;
}

void vr_wavelengths(const vr_rscene *rs, const vr_rng_key *key, uint32_t strata, double *wl) {
  if (rs->bins_mode) {
    for (int i = 0; i < rs->nwl; i++) wl[i] = vr_wavelength_at(rs, 0.0, i);
    return;
  }
  /* Hero wavelength sampling (Wilkie et al. 2014): one uniform wavelength,
   * the others spaced evenly from it and wrapped, so each is uniform. */
  /* Stratified over the samples of one pixel or sensor point: sample i of
   * n takes its hero from the i-th n-th of the range. */
  double u = vr_rng(key, VR_DIM_WAVELENGTH);
  if (strata > 1) u = ((key->sample % strata) + u) / strata;
  /* The hero is a float (the wire carries it in 4 bytes); rounding moves
   * it by at most 3e-5 nm, and never onto lmax. */
  float h = (float)(rs->lmin + u * (rs->lmax - rs->lmin));
  if (!((double)h < rs->lmax)) h = nextafterf((float)rs->lmax, 0.0f);
  if ((double)h < rs->lmin) h = nextafterf((float)rs->lmin, FLT_MAX);
  for (int i = 0; i < rs->nwl; i++) wl[i] = vr_wavelength_at(rs, (double)h, i);
}
