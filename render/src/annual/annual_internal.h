/* Shared by the annual study's files: the daylight coefficients one tint
 * state gives (annual_coef.c) and the year's sums over them (annual.c). */
#ifndef VR_ANNUAL_INTERNAL_H
#define VR_ANNUAL_INTERNAL_H

#include <stdbool.h>

#include "vr/annual.h"
#include "vr/skypatch.h"
#include "vr/weather.h"

#define NPATCH (VR_SKY_PATCHES + 1)
#define SUN_LX 100000.0 /* the sun renders' normal illuminance */

/* The illuminance coefficients of every point in one state of the glass. */
typedef struct vr_dc_set {
  double *sky;        /* npoints x NPATCH: lx per cd/m2 of each patch and of the ground */
  double *sun_total;  /* npoints x VR_SKY_PATCHES: lx per lx of direct normal sun */
  double *sun_direct; /* the same, the sun seen straight from the point only */
} vr_dc_set;

/* The UV coefficients of a photochromic glass's texels (both faces). */
typedef struct vr_uv_set {
  size_t ntexels;
  double *sky;        /* ntexels x NPATCH: W/m2 per cd/m2 */
  double *sun;        /* ntexels x VR_SKY_PATCHES: W/m2 per lx of direct normal sun */
  double *normal;     /* ntexels x 3: the pane's unit normal (the sun's cosine ratio) */
} vr_uv_set;

typedef struct vr_annual_job {
  const vr_scene *s;
  struct vr_matdb *db;
  const vr_render_options *o;
  const vr_scene_light *sun;
  size_t npoints;
  bool need[VR_SKY_PATCHES]; /* sun patches the occupied daylit hours visit */
  vr_annual_result *res;
} vr_annual_job;

/* Renders the coefficients with the glass (if any) in state `state`; the
 * first call also fills the result's points (names, places, normals). */
vr_status annual_dc(vr_annual_job *j, double state, vr_dc_set *out, vr_error *err);
/* Renders the UV coefficients of the glass's texels (its state left to its
 * UV exposure). */
vr_status annual_uv(vr_annual_job *j, vr_uv_set *out, vr_error *err);
void annual_dc_free(vr_dc_set *d);

/* The occupied records of the weather file w from the schedule at path
 * (annual_occupancy.c): occ[i] for record i. */
vr_status annual_occupancy_read(const char *path, const vr_weather *w, bool *occ, vr_error *err);

/* EN 17037 (annual_en17037.c).  The daylight hours: dlh[i] for the n/2
 * records of most global horizontal illuminance egh (lx; ties in file
 * order), and the median of their diffuse horizontal illuminance edh. */
vr_status annual_daylight_hours(const double *egh, const double *edh, size_t n, bool *dlh,
                                double *edmed_lx, vr_error *err);
/* Every point's daylight factor (%) from one render under the CIE standard
 * overcast sky with the glass (if any) in `state` (annual_coef.c). */
vr_status annual_df(vr_annual_job *j, double state, double *df_pct, vr_error *err);
void annual_uv_free(vr_uv_set *u);

#endif
