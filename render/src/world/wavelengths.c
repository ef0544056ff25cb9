/* The wavelengths a path carries (world/rscene.h). */
#include "world/rscene.h"

void vr_wavelengths(const vr_rscene *rs, const vr_rng_key *key, uint32_t strata, double *wl) {
  double span = rs->lmax - rs->lmin, step = span / rs->nwl;
  if (rs->bins_mode) {
    for (int i = 0; i < rs->nwl; i++) wl[i] = rs->lmin + (i + 0.5) * step;
    return;
  }
  /* Hero wavelength sampling (Wilkie et al. 2014): one uniform wavelength,
   * the others spaced evenly from it and wrapped, so each is uniform. */
  /* Stratified over the samples of one pixel or sensor point: sample i of
   * n takes its hero from the i-th n-th of the range. */
  double u = vr_rng(key, VR_DIM_WAVELENGTH);
  if (strata > 1) u = ((key->sample % strata) + u) / strata;
  double h = u * span;
  for (int i = 0; i < rs->nwl; i++) {
    double x = h + i * step;
    if (x >= span) x -= span;
    wl[i] = rs->lmin + x;
  }
}

