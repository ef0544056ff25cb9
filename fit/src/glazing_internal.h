/* Shared between the glazing files: resampling panes onto one grid. */
#ifndef VR_GLAZING_INTERNAL_H
#define VR_GLAZING_INTERNAL_H

#include <stddef.h>
#include "vr/glazing.h"

/* y(at) by linear interpolation on x[0..n-1] (increasing); the end values
 * outside. */
double vr_glazing_lerp(const double *x, const double *y, size_t n, double at);

/* The system's wavelengths (*grid, *n of them, freed by the caller): every
 * pane's samples inside the range all the panes cover, sorted, without
 * repeats (two samples closer than 1e-9 nm are one).  *grid NULL and *n 0
 * when the panes share no range; VR_E_NOMEM only when out of memory. */
vr_status vr_glazing_common_grid(vr_pane *const *panes, size_t count, double **grid, size_t *n,
                                 vr_error *err);

#endif
