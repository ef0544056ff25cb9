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

/* One record of the weather file, ready for the sums. */
typedef struct vr_annual_hour {
  const vr_weather_record *r;
  bool occ;                 /* an occupied hour */
  bool dlh;                 /* one of EN 17037's daylight hours (en17037=yes) */
  bool daylit;
  int ks;                   /* the sun's patch, -1 without direct sun */
  double sun[3], centre[3]; /* the true sun and its patch centre */
  double Edn;               /* direct normal illuminance, lx */
  double Edh, Egh;          /* diffuse and global horizontal illuminance, lx */
  double L[NPATCH];         /* patch and ground luminances, cd/m2 */
} vr_annual_hour;

/* One glare view (annual glare_views=): a fisheye at a point sensor, its
 * pixels in the image circle with their solid angle and Guth position
 * index, and per rendered state the pixels' luminance coefficients. */
typedef struct vr_glare_view {
  vr_scene_camera cam;       /* 180-degree equisolid, N x N, up +z */
  double frame[3][3];        /* right, up, forward (the camera's u, v, w) */
  size_t point;              /* the view sensor's point in the result */
  size_t npx;                /* pixels with some solid angle in front */
  size_t *pixel;             /* each one's index in the N x N image */
  double *w, *P;             /* its solid angle (sr) and position index (0: its centre lies
                                outside the circle, so it is no glare source) */
  double *sky[VR_ANNUAL_MAX_STATES]; /* npx x NPATCH: cd/m2 per cd/m2 of each patch and the ground */
  double *sun[VR_ANNUAL_MAX_STATES]; /* npx x VR_SKY_PATCHES: cd/m2 per lx of direct normal sun */
} vr_glare_view;

typedef struct vr_glare_set {
  int n;
  vr_glare_view v[VR_ANNUAL_MAX_VIEWS];
  double sun_omega_sr;       /* the solar disc's solid angle */
  double *scratch;           /* two images of the largest view */
} vr_glare_set;

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

/* Glare views (annual_glare.c): their cameras and pixels, once the
 * result's points are filled. */
vr_status annual_glare_setup(const vr_annual_job *j, vr_glare_set *g, vr_error *err);
/* Renders every view's image coefficients with the glass in `state`, the
 * study's state number si (annual_coef.c). */
vr_status annual_view_dc(vr_annual_job *j, double state, int si, vr_glare_set *g, vr_error *err);
/* The hour's DGP at every view into dgp[view]: the images of state lo,
 * blended geometrically towards state hi by f (photochromic; f = 0
 * otherwise), E the hour's illuminance at every point (the views' E_v) and
 * sun_direct the direct-sun coefficients of states lo and hi. */
void annual_glare_hour(const vr_glare_set *g, const vr_annual_hour *h, int lo, int hi, double f,
                       const vr_dc_set *dcs, const double *E, double *dgp);
void annual_glare_free(vr_glare_set *g);

/* Between two states' readings: geometric where both are positive (the
 * transmittance is exponential in the state), linear otherwise. */
double annual_between(double a, double b, double f);

#endif
