/* EN 17037:2018 daylight provision in the annual study (vr/annual.h): the
 * year's daylight hours, the median diffuse illuminance over them, and the
 * assessment of the work plane. */
#include <math.h>
#include <stdlib.h>

#include "annual/annual_internal.h"

/* EN 17037:2018 Table A.1 (vertical and inclined openings). */
const double VR_EN17037_LX[4] = {100, 300, 500, 750};
const int VR_EN17037_TARGET[VR_EN17037_LEVELS] = {1, 2, 3};  /* E_T: 300, 500, 750 lx */
const int VR_EN17037_MINIMUM[VR_EN17037_LEVELS] = {0, 1, 2}; /* E_TM: 100, 300, 500 lx */
const char *const VR_EN17037_LEVEL_NAME[VR_EN17037_LEVELS] = {"minimum", "medium", "high"};

/* The shares of the reference plane and of the daylight hours (Table A.1:
 * F_plane 50 % for E_T, 95 % for E_TM; F_time 50 %). */
#define F_PLANE_TARGET 0.50
#define F_PLANE_MINIMUM 0.95
#define F_TIME 0.50

void vr_en17037_assess(const vr_annual_point *pts, size_t np, double edmed_lx, vr_en17037 *e) {
  size_t nw = 0, m2[4] = {0}, m1[4] = {0};
  for (size_t p = 0; p < np; p++) {
    if (!pts[p].workplane) continue;
    nw++;
    for (int k = 0; k < 4; k++) {
      m2[k] += pts[p].en17037_share[k] >= F_TIME;
      /* D >= 100 E / E_v,d,med, in %. */
      m1[k] += pts[p].df_pct >= 100 * VR_EN17037_LX[k] / edmed_lx;
    }
  }
  double n = nw ? (double)nw : 1;
  e->edmed_lx = edmed_lx;
  e->m2_level = e->m1_level = -1;
  for (int l = 0; l < VR_EN17037_LEVELS; l++) {
    int t = VR_EN17037_TARGET[l], m = VR_EN17037_MINIMUM[l];
    e->m2_target[l] = (double)m2[t] / n, e->m2_minimum[l] = (double)m2[m] / n;
    e->m1_target[l] = (double)m1[t] / n, e->m1_minimum[l] = (double)m1[m] / n;
    /* A level is met when both its criteria are (the levels nest: a
     * higher level's thresholds are higher). */
    if (nw && e->m2_target[l] >= F_PLANE_TARGET && e->m2_minimum[l] >= F_PLANE_MINIMUM)
      e->m2_level = l;
    if (nw && e->m1_target[l] >= F_PLANE_TARGET && e->m1_minimum[l] >= F_PLANE_MINIMUM)
      e->m1_level = l;
  }
}

typedef struct ranked {
  double egh;
  size_t i;
} ranked;

/* Most light first; equal light in the file's order. */
static int by_light(const void *a, const void *b) {
  const ranked *x = a, *y = b;
  if (x->egh != y->egh) return x->egh > y->egh ? -1 : 1;
  return x->i < y->i ? -1 : x->i > y->i;
}

static int by_value(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

vr_status annual_daylight_hours(const double *egh, const double *edh, size_t n, bool *dlh,
                                double *edmed_lx, vr_error *err) {
  size_t half = n / 2;
  ranked *r = malloc((n + 1) * sizeof *r);
  double *d = malloc((half + 1) * sizeof *d);
  if (!r || !d) {
    free(r), free(d);
    return vr_error_set(err, VR_E_NOMEM, "out of memory for EN 17037's daylight hours");
  }
  for (size_t i = 0; i < n; i++) r[i] = (ranked){egh[i], i}, dlh[i] = false;
  qsort(r, n, sizeof *r, by_light);
  for (size_t k = 0; k < half; k++) dlh[r[k].i] = true, d[k] = edh[r[k].i];
  qsort(d, half, sizeof *d, by_value);
  *edmed_lx = half == 0 ? 0 : half % 2 ? d[half / 2] : 0.5 * (d[half / 2 - 1] + d[half / 2]);
  free(r), free(d);
  return VR_OK;
}
