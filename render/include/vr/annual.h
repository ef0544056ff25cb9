/* Climate-based daylight metrics over a weather file's year, by daylight
 * coefficients: a year of skies for the price of a few renders, with
 * switchable glazing that follows a control rule or its own UV exposure.
 *
 * The scene's sky is `sky perez weather=FILE` with no date: every record of
 * the file is one sky; the scene's `annual` line (vr/scene.h,
 * docs/scene-format.md) sets the hours, thresholds and glass.  Instead of
 * rendering each hour, the illuminance at every sensor point is written as
 *   E(t) = sum_k DC_k L_k(t) + DC_g L_g(t) + E_dn(t) S_k(sun(t))
 *   - DC_k: the illuminance per cd/m2 of each of the 145 Tregenza patches
 *     (vr/skypatch.h), interreflections included, from one path-traced
 *     sensor render under a uniform sky whose light is binned by the patch
 *     it came from; DC_g the same for the ground glow below the horizon;
 *   - L_k(t): the Perez sky of that hour (vr/perez.h) averaged over each
 *     patch and scaled so that the patches give its diffuse horizontal
 *     illuminance; L_g(t) = rho (E_dh + E_dn sin h) / pi;
 *   - S_k: the illuminance per lx of direct normal sunlight with the sun at
 *     the centre of the Tregenza patch that holds the hour's sun (one
 *     render per patch the sun visits in occupied hours, typically 40-70),
 *     its direct part (the sun seen from the point) kept apart for the
 *     annual sunlight exposure.  The direct part is scaled by the ratio of
 *     the cosines at the point of the true sun and the patch centre, exact
 *     for an unobstructed point; the reflected part keeps the patch centre,
 *     up to about 6 degrees from the true sun.
 *
 * Operable shade (annual shade=SHADE window=WINDOW): the coefficients are
 * rendered twice, open and with every object of the window material taking
 * the shade material (a BSDF XML of the shaded system); each hour the shade
 * is drawn when more than 2 % of the work plane's points see at least
 * 1000 lx of direct sun through the open window (IES LM-83-12's rule for
 * sDA); ASE stays that of the open window, as LM-83 defines it.
 *
 * Switchable glass (annual glass=NAME): the coefficients are rendered once
 * per tint state (states=).
 *   - Electrochromic: each hour takes one of those states: the scene's
 *     (control=fixed), or the lightest that keeps every control point at
 *     or below max lx (control=illuminance, default 3000 lx), keeps the
 *     direct sun there at or below max lx (control=sun, default 1000 lx) or
 *     keeps DGPs of their illuminance at or below max (control=glare,
 *     default 0.35; control points facing a view at eye height), the
 *     darkest when none does.
 *   - Photochromic: the pane's UV irradiance each hour, per texel of its
 *     state map and both faces, from UV daylight coefficients (the
 *     renderer's own UV pass under the same unit sky and sun patches,
 *     binned by patch), sets each texel's state by the glass's kinetics
 *     (vr/chromogenic.h: from the last hour's state over the record's
 *     interval when a and b are known, the steady state otherwise) at the
 *     glass's temperature= (298.15 K by default); the pane's mean state
 *     then picks the coefficients, interpolated between the two nearest
 *     rendered states (geometrically: the transmittance is exponential in
 *     the state).  One state for the whole pane is the approximation.
 *
 * Metrics (IES LM-83-12 for sDA and ASE; Nabil & Mardaljevic 2005 for UDI;
 * Reinhart & Walkenhorst 2001 for DA), over the occupied hours (records
 * whose interval centre lies in [from, to) local standard time, every day,
 * or those an occupancy schedule marks: annual occupancy=FILE, a Daysim
 * occupancy file or one 0/1 per record):
 *   DA       share of occupied hours with E >= da_lx (300 lx);
 *   sDA      share of the work plane's points whose DA >= sda_share (50 %):
 *            the grid named workplane=, else every grid sensor's points,
 *            else (no grid) every point; view sensors are reported, not
 *            counted (IES LM-83 defines sDA and ASE over the analysis grid);
 *   UDI      shares of occupied hours below udi_lo (100 lx), between
 *            udi_lo and udi_hi (3000 lx) and above;
 *   ASE      share of the work plane's points whose direct sunlight reaches ase_lx
 *            (1000 lx) in more than ase_hours (250) occupied hours, through
 *            the glass in the state it has that hour;
 *   glare    occupied hours in which DGPs = 6.22e-5 E + 0.184 (Wienold
 *            2009) of a point's illuminance reaches 0.35, the threshold of
 *            perceptible glare: meaningful where the sensor faces a view
 *            at eye height (E is then the vertical illuminance at the eye);
 *   DGP      at the glare views (glare_views=): hour by hour with its
 *            contrast term, from fisheye image daylight coefficients (see
 *            vr_annual_view below); with control=glare the glass then
 *            keeps the views' DGP within max;
 *   EN 17037 (annual en17037=yes) over the year's daylight hours and by
 *            daylight factor: see vr_en17037 below. */
#ifndef VR_ANNUAL_H
#define VR_ANNUAL_H

#include <stddef.h>

#include "vr/render.h"
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

struct vr_matdb;

typedef struct vr_annual_point {
  const char *sensor;        /* the sensor's name (the result's storage) */
  int i, j;
  double position[3], normal[3];
  double da;                 /* shares in [0, 1] */
  double udi_below, udi_useful, udi_above;
  double direct_hours;       /* occupied hours with direct sunlight >= ase_lx */
  double glare_hours;        /* occupied hours with DGPs >= 0.35 (Wienold 2009's perceptible
                                glare) of the point's illuminance: for points facing a view */
  double mean_lx;            /* over the occupied hours */
  bool workplane;            /* one of the work plane's points (vr_scene_annual.workplane) */
  /* EN 17037 (en17037=yes; NAN otherwise): the share of the year's
   * daylight hours in which the point reaches each of VR_EN17037_LX, and
   * its daylight factor (%) under the CIE standard overcast sky. */
  double en17037_share[4];
  double df_pct;
} vr_annual_point;

/* EN 17037:2018 daylight provision for vertical and inclined openings
 * (Table A.1): at each level (minimum, medium, high) a target illuminance
 * E_T over 50 % of the reference plane and a minimum target illuminance
 * E_TM over 95 % of it, each for at least 50 % of the daylight hours:
 *   minimum 300 / 100 lx, medium 500 / 300 lx, high 750 / 500 lx.
 * The daylight hours are the half of the year's records with the most
 * daylight, ranked by global horizontal illuminance (as Honeybee's
 * epw-to-daylight-hours ranks them).  Method 2 counts each point's hours;
 * method 1 compares each point's daylight factor D with D_T = 100 E_T /
 * E_v,d,med and D_TM = 100 E_TM / E_v,d,med (%), E_v,d,med the median
 * diffuse horizontal illuminance over the daylight hours. */
#define VR_EN17037_LEVELS 3
extern const double VR_EN17037_LX[4];          /* 100, 300, 500, 750 */
extern const int VR_EN17037_TARGET[VR_EN17037_LEVELS];  /* index into VR_EN17037_LX: 1, 2, 3 */
extern const int VR_EN17037_MINIMUM[VR_EN17037_LEVELS]; /* 0, 1, 2 */
extern const char *const VR_EN17037_LEVEL_NAME[VR_EN17037_LEVELS];

typedef struct vr_en17037 {
  bool run;
  size_t daylight_hours;       /* half the weather file's records */
  double edmed_lx;             /* E_v,d,med used by method 1 */
  bool edmed_given;            /* from edmed= (else the weather file's median) */
  /* Shares of the work plane's points meeting each level's target and
   * minimum target: by illuminance hours (method 2) and by daylight factor
   * (method 1). */
  double m2_target[VR_EN17037_LEVELS], m2_minimum[VR_EN17037_LEVELS];
  double m1_target[VR_EN17037_LEVELS], m1_minimum[VR_EN17037_LEVELS];
  int m2_level, m1_level;      /* the highest level met, 0 minimum .. 2 high; -1 none */
} vr_en17037;

/* The assessment from the points' en17037_share and df_pct, over the points
 * marked workplane; fills every field of *e but run, daylight_hours and
 * edmed_given. */
void vr_en17037_assess(const struct vr_annual_point *pts, size_t npoints, double edmed_lx,
                       vr_en17037 *e);

/* A glare view (annual glare_views=): the daylight glare probability DGP
 * of Wienold & Christoffersen (2006), contrast term included, hour by hour
 * from fisheye image daylight coefficients (render/src/annual/annual_glare.c),
 * its E_v the view sensor's illuminance.  Counted: the occupied hours with
 * DGP at or above each of VR_GLARE_DGP, Wienold's (2009) bounds of
 * perceptible, disturbing and intolerable glare, which are also EN
 * 17037:2018's DGP_e of high, medium and minimum glare protection: a view
 * meets a level when DGP reaches its DGP_e in at most 5 % of the occupied
 * hours. */
#define VR_GLARE_CLASSES 3
extern const double VR_GLARE_DGP[VR_GLARE_CLASSES]; /* 0.35, 0.40, 0.45 */

typedef struct vr_annual_view {
  const char *sensor;        /* the view sensor's name (the result's storage) */
  size_t point;              /* its point */
  double position[3], direction[3];
  double hours[VR_GLARE_CLASSES]; /* occupied hours with DGP >= VR_GLARE_DGP[k] */
  int en17037_level;         /* 2 high (0.35), 1 medium (0.40), 0 minimum (0.45), -1 none */
} vr_annual_view;

typedef enum vr_annual_glass {
  VR_ANNUAL_NO_GLASS = 0, VR_ANNUAL_ELECTROCHROMIC, VR_ANNUAL_PHOTOCHROMIC,
  VR_ANNUAL_SHADE            /* an operable shade: state 0 open, 1 drawn (LM-83 rule) */
} vr_annual_glass;

typedef struct vr_annual_result {
  vr_scene_annual spec;      /* the study as run: the scene's line, defaults filled */
  vr_annual_glass glass;
  const char *glass_name;    /* the scene's alias (with a shade: the shade's), or NULL */
  const char *window_name;   /* with a shade: the window material it replaces */
  size_t npoints;
  vr_annual_point *points;
  double sda, ase;           /* shares of the work plane's points in [0, 1] */
  double udi_plane[3];       /* UDI below, useful, above: the work plane's points' mean shares */
  size_t workplane_points;   /* how many (the other points are reported apart) */
  size_t records, occupied_hours, daylit_hours; /* of the file; occupied; of those with daylight */
  size_t sun_patches;        /* sun positions rendered */
  size_t renders;            /* every render made */
  double state_hours[VR_ANNUAL_MAX_STATES]; /* occupied daylit hours in each rendered state
                                               (electrochromic), or nearest to it (photochromic) */
  double mean_state;         /* over the occupied daylit hours */
  size_t extrapolated_hours; /* photochromic hours whose UV (at some texel) or
                                temperature lay outside the glass's fitted
                                range: evaluated as extrapolate=yes asked */
  vr_en17037 en17037;        /* en17037=yes */
  double seconds;            /* all renders and the year's sums */
  /* Hour by hour (occupied hours, in file order): the illuminance of every
   * point, occupied_hours x npoints, lx; the weather file's line; the
   * glass's state (NAN without one); its mean UV irradiance (W/m2,
   * photochromic glass, NAN otherwise). */
  double *hourly_lx;
  /* The glare views and their DGP hour by hour (occupied hours x nviews). */
  size_t nviews;
  vr_annual_view *views;
  double *hourly_dgp;
  long *hourly_line;
  double *hourly_state, *hourly_uv;
  char *names;               /* storage */
  char *glass_names;         /* storage of glass_name and window_name */
} vr_annual_result;

/* Runs the study of a scene whose sky is a whole weather file (see above),
 * with the render options o (sensors only).  A scene without such a sky,
 * without sensors or without a sun line, a glass that is not chromogenic,
 * or a control that does not suit its glass, is VR_E_ARG naming the line. */
vr_status vr_annual_run(const vr_scene *s, struct vr_matdb *db, const vr_render_options *o,
                        vr_annual_result **out, vr_error *err);
void vr_annual_result_destroy(vr_annual_result *r);
/* PREFIX.annual.csv (one line per point: its metrics) and
 * PREFIX.annual-hourly.csv (one line per occupied hour: the weather file's
 * line, the glass's state and UV, every point's lx), each written whole or
 * not at all. */
vr_status vr_annual_write(const vr_annual_result *r, const char *prefix, vr_error *err);

#ifdef __cplusplus
}
#endif
#endif
