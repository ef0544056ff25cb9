/* What the renderer's files share: the scene resolved for rendering (lights
 * and emitters in radiometric units on a 1 nm grid, one vr_bsdf per
 * material, the sky, the photochromic state maps), the ray payloads, and
 * the entry points of each pass. */
#ifndef VR_RENDER_INTERNAL_H
#define VR_RENDER_INTERNAL_H

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "vr/bsdf.h"
#include "vr/domains.h"
#include "vr/flow.h"
#include "vr/geometry.h"
#include "vr/render.h"
#include "vr/skypatch.h"
#include "vr/rng.h"
#include "vr/scene.h"
#include "vr/photon_map.h"
#include "vr/photon_set.h"
#include "vr/scene_tables.h"
#include "vr/sky.h"

#define VR_MAX_WL VR_SCENE_MAX_WAVELENGTHS /* wavelengths carried by one path */

/* A spectrum on the resolved grid: value at lo + i nm, i = 0 .. n-1. */
typedef struct rspd {
  double lo;
  int n;
  double *v;
} rspd;

double rspd_at(const rspd *s, double nm);

typedef struct rlight {
  vr_light_kind kind;
  double pos[3], axis[3];
  vr_distribution dist;
  double cos_inner, cos_outer; /* spot */
  rspd spd;        /* point/spot: on-axis intensity W/(sr nm); sun: normal irradiance W/(m² nm) */
  double power;    /* W over the sampled range, for choosing photon sources */
  double cos_sun;  /* sun: cosine of its apparent radius */
  struct vr_ies *ies; /* vr_ies */
} rlight;

typedef struct robject {
  int material;
  rspd emission;           /* radiance W/(m² sr nm), n = 0 if not emissive */
  double emitted_power;    /* W over the sampled range */
  /* Photochromic glass (a rect): its state map of nu x nv texels, held by
   * each cell the rect reaches (rcell); nu = 0: the material's own state. */
  int nu, nv;
  size_t texel0;           /* its first texel in the UV pass's numbering */
  double corner[3], eu[3], ev[3], normal[3]; /* rect: point = corner + u eu + v ev */
  bool outside;            /* an exterior surface (outside=yes) */
} robject;

/* What the renderer keeps per cell besides its geometry (which vr_domains
 * loads and unloads): the state maps of the photochromic objects in it. */
typedef struct rcell {
  size_t nmaps;
  uint32_t *map_object;    /* increasing */
  double **map;            /* nu*nv states of that object */
} rcell;

typedef struct rmaterial {
  vr_bsdf *bsdf;
  double state;            /* chromogenic state from the scene (or 0) */
  bool photochromic;
  struct vr_material *db;  /* the database material, if any */
  double temperature_K;
} rmaterial;

/* A sky portal (portals.c), from the scene's corner, u, v. */
typedef struct rportal {
  double corner[3], u[3], v[3], n[3]; /* n unit, u x v / |u x v| */
  double area, uu, vv;                /* |u x v|, u.u, v.v */
} rportal;

/* At most this many portals (the scene parser refuses more). */
#define VR_MAX_PORTALS VR_SCENE_MAX_PORTALS
/* The share of sky samples aimed through the portals when there are any. */
#define VR_PORTAL_SHARE 0.9

typedef struct rscene {
  const vr_scene *s;
  vr_domains *d;
  const vr_scene_tables *t; /* the replicated tables, owned by d */
  rcell *cells;             /* one per sub-domain */
  int *owner;               /* several ranks: the rank owning each cell */
  uint64_t *cell_ns;        /* this rank's tracing time per cell in the last run */
  uint64_t *cell_total_ns;  /* and in all runs */
  size_t ntexels;           /* photochromic texels of all objects */
  double lmin, lmax;       /* sampled range */
  int nwl;                 /* wavelengths per path */
  bool bins_mode;          /* fixed bins instead of hero sampling */
  size_t nmat;
  rmaterial *mat;
  robject *obj;
  size_t nlights;
  rlight *lights;
  /* Emitters for next-event estimation: emissive objects, chosen at a
   * point x with probability proportional to power / max(d², R²), d the
   * distance from x to the emitter's bounding sphere's centre and R its
   * radius (lights.c), so a vertex mostly samples the lights near it. */
  size_t nemitters;
  uint32_t *emitters;
  double *emitter_cdf;             /* by power alone, normalised */
  double (*emitter_sphere)[4];     /* centre, radius */
  /* The sky. */
  bool has_sky;
  vr_sky *sky;
  rspd sky_spd;            /* radiance per unit relative luminance: W/(m² sr nm) per (cd/m²) */
  double ground_radiance_scale; /* ground glow: luminance below the horizon, cd/m² */
  rspd ground_spd;
  size_t nportals;         /* sky portals: windows the sky's samples aim through */
  rportal *portals;
  double *portal_area_cdf, portal_area; /* running sums of the portals' areas, their total */
  /* Photon sources through the portals (after the usual ones): the sun,
   * the sky, the ground glow, those present (PORTAL_SRC_*). */
  size_t nportal_sources;
  int portal_source[3];
  size_t sun_light;        /* index of the sun light, or nlights */
  /* Light choice for photons: lights, then emitters, then the sky. */
  size_t nsources;
  double *source_cdf;
  double total_power;
  double scene_lo[3], scene_hi[3], scene_radius, scene_centre[3];
  /* Camera frame. */
  double cam_o[3], cam_u[3], cam_v[3], cam_w[3], tan_half;
  double film_lo, film_step;
  size_t nbins;
  vr_rng_seed seed; /* the scene's seed and sampler: keys every vr_rng (vr/rng.h) */
} rscene;

/* Resolution of the scene (resolve.c): materials, lights, the sky, and the
 * sub-domains opened through the geometry cache (none loaded yet). */
vr_status vr_rscene_create(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                           int subdomains, rscene **out, vr_error *err);
/* Bytes of the photochromic state maps held by the cells. */
size_t vr_rscene_map_bytes(const rscene *rs);
void vr_rscene_destroy(rscene *rs);

/* A relative spectrum by reference (db:NAME, a CIE name, bb:T; NULL: dflt)
 * on the resolved grid, and its scaling to an amount in given units. */
vr_status vr_rscene_spectrum(const rscene *rs, struct vr_matdb *db, const char *ref,
                             const char *dflt, const vr_scene_loc *loc, rspd *out, vr_error *err);
vr_status vr_rscene_normalise(const rscene *rs, rspd *s, vr_quantity q, bool photometric,
                              const vr_scene_loc *loc, const char *what, vr_error *err);

/* Lights (lights.c). */
typedef struct light_sample {
  double dir[3];       /* from the point to the light, unit */
  double dist;         /* INFINITY for the sun and the sky */
  double L[VR_MAX_WL]; /* radiance-like contribution divided by pdf: f-less, cos-less */
  bool delta;
} light_sample;

/* One sample of every delta light (point, spot, sun) and one emitter and
 * one sky direction, each adding a shadow ray through add(); the values
 * given are incident radiance times solid angle over pdf at x. */
int vr_light_sample_delta(const rscene *rs, size_t i, const double x[3], int nwl,
                          const double *wl, const vr_rng_key *key, light_sample *out);
bool vr_light_sample_emitter(const rscene *rs, const double x[3], int nwl, const double *wl,
                             const vr_rng_key *key, light_sample *out);
bool vr_light_sample_sky(const rscene *rs, const double x[3], const double n[3], int nwl,
                         const double *wl, const vr_rng_key *key, light_sample *out);
/* Radiance arriving from the environment along dir (sky above, ground glow below). */
void vr_light_environment(const rscene *rs, const double dir[3], bool include_sky, int nwl,
                          const double *wl, double *L);

/* Sky portals (portals.c): the rscene's copy of the scene's portals; a
 * direction through one of them from x (u0 picks the portal, u1 and u2 the
 * point; false if none is usable from x); and the portal strategy's
 * density in solid angle at x for a direction. */
vr_status vr_portals_create(rscene *rs, vr_error *err);
bool vr_portal_sample(const rscene *rs, const double x[3], double u0, double u1, double u2,
                      double dir[3]);
double vr_portal_pdf(const rscene *rs, const double x[3], const double dir[3]);
/* A point uniform over the portals' total area (u0 picks the portal by
 * area, u1 and u2 the point), and which portal. */
void vr_portal_point(const rscene *rs, double u0, double u1, double u2, double y[3], size_t *which);
/* Whether org + t dir, t in (0, tmax], crosses a portal inwards (along its
 * normal). */
bool vr_portal_crossed_inward(const rscene *rs, const double org[3], const double dir[3],
                              double tmax);
enum { PORTAL_SRC_SUN, PORTAL_SRC_SKY, PORTAL_SRC_GROUND };
/* The share of photons the portal sources get when there are any. */
#define VR_PORTAL_PHOTON_SHARE 0.75

/* Wavelengths of a path: hero plus equally spaced rotations, or bins. */
void vr_wavelengths(const rscene *rs, const vr_rng_key *key, uint32_t strata, double *wl);

/* The sky (lights.c). */
vr_status vr_light_sky_create(rscene *rs, struct vr_matdb *db, vr_error *err);
void vr_light_sky_destroy(rscene *rs);
double vr_light_sky_power(const rscene *rs);
double vr_light_ground_power(const rscene *rs);
/* The share of the ground glow's radiance at nm that the sun lit (the rest
 * is the sky's), and the unobstructed sky's horizontal illuminance (lx,
 * without the sun): the daylight factor's denominator. */
double vr_light_ground_sun_share(const rscene *rs, double nm);
double vr_light_sky_horizontal_lx(const rscene *rs); /* the ground glow's, likewise */
/* Photon emission from source i of rs->source_cdf order. */
typedef struct photon_emit {
  double org[3], dir[3];
  double power[VR_MAX_WL]; /* W per wavelength sample, before dividing by the photon count */
} photon_emit;
bool vr_light_emit_photon(const rscene *rs, size_t source, int nwl, const double *wl,
                          const vr_rng_key *key, photon_emit *out);
/* A photon of a far source (PORTAL_SRC_*) through the portals; *to_portal
 * is the distance from its origin to the portal it enters by. */
bool vr_light_emit_portal_photon(const rscene *rs, int kind, int nwl, const double *wl,
                                 const vr_rng_key *key, photon_emit *out, double *to_portal);
/* Rough powers of the portal sources, only to share the photons. */
double vr_light_portal_power(const rscene *rs, int kind);

/* Ray payloads (integrate.c). */
enum { TARGET_PIXEL = 0, TARGET_SENSOR, TARGET_TEXEL, TARGET_PHOTON, TARGET_GATHER };
enum { PURPOSE_CAMERA = 0, PURPOSE_SHADOW, PURPOSE_PHOTON, PURPOSE_SENSOR, PURPOSE_UV,
       PURPOSE_GATHER };
enum { FLAG_SPECULAR_LAST = 1, FLAG_HAS_DIFFUSE = 2, FLAG_HAS_SPECULAR = 4,
       FLAG_TERMINATED = 8, FLAG_PHOTON_GATHER = 16 /* a photon sensor's gather path */,
       FLAG_REFLECTED = 32 /* a sensor path met a non-delta vertex */,
       FLAG_OUTSIDE_LAST = 64 /* ... and the last one was an exterior surface */ };
#define NO_PATCH 0xFF
#define VR_SENSOR_PATCHES (VR_SKY_PATCHES + 1)
/* Photon payloads reuse two of the sensor paths' bits: */
enum { FLAG_FAR_DIRECT = 32 /* a far source's usual photon, not yet scattered (portals) */,
       FLAG_PORTAL_PATH = 64 /* a portal photon that has not yet reached its portal */ };
/* Where a sensor path's light came from, and the daylight components
 * (render_sensors.c): the part of a reading each delivery adds to. */
enum { SRC_OTHER = 0, SRC_SUN, SRC_SKY, SRC_LAMP, SRC_GROUND };
/* The parts of a reading they add to: VR_PART_* (vr/render.h). */

typedef struct payload {
  uint64_t stream;
  uint32_t sample;
  uint32_t index;          /* pixel, sensor point, texel */
  uint8_t depth, target, flags, nwl;
  uint8_t source;          /* sensor paths: SRC_* of the light a shadow ray carries */
  uint8_t patch;           /* sky light: its Tregenza patch (vr/skypatch.h), the ground
                              VR_SKY_GROUND_PATCH; NO_PATCH otherwise */
  int32_t medium;          /* object whose inside the path is in, -1 outside */
  double weight;           /* sample weight (1/spp, ...), applied on delivery */
  double wl[VR_MAX_WL];
  double beta[VR_MAX_WL];  /* throughput, photon power, or a shadow ray's contribution */
  double portal_t;         /* portal photons: distance left to the portal */
} payload;
_Static_assert(sizeof(payload) <= VR_RAY_PAYLOAD, "a payload must fit in a ray");

/* Accumulators shared by the passes (film.c). */
typedef struct accum {
  int width, height, spp;
  size_t nbins;
  double bin_lo, bin_step;
  _Atomic uint64_t *xyz;      /* doubles stored as bits, width*height*3 */
  _Atomic uint64_t *bins;     /* width*height*nbins */
  size_t npoints;             /* sensor points */
  int groups;                 /* batches for the standard error */
  _Atomic uint64_t *sensor_lx;  /* npoints*groups */
  _Atomic uint64_t *sensor_bins;/* npoints*nbins */
  _Atomic uint64_t *sensor_parts;/* npoints*VR_SENSOR_PARTS: illuminance by component (lx, summed
                                    over the groups' samples) */
  _Atomic uint64_t *sensor_patches;/* npoints*VR_SENSOR_PATCHES: the sky's and the ground glow's
                                    illuminance by the patch it came from (lx, summed) */
  size_t ntexels;
  _Atomic uint64_t *texel_uv;   /* W/m2 in the UV band, summed */
  _Atomic uint64_t *texel_patches;/* ntexels*VR_SENSOR_PATCHES: the sky's and the ground glow's
                                    share of texel_uv by the patch it came from */
  /* Fixed-bins mode: the CMFs averaged over each of the cmf_n bins of
   * [cmf_lo, cmf_lo + cmf_n cmf_step], used for a wavelength in that bin
   * instead of their value at it (NULL in hero mode). */
  double (*cmf_avg)[3];
  double cmf_lo, cmf_step;
  int cmf_n;
} accum;

vr_status vr_accum_create(accum *a, int width, int height, size_t nbins, double bin_lo,
                          double bin_step, size_t npoints, int groups, size_t ntexels,
                          vr_error *err);
void vr_accum_destroy(accum *a);
/* Fixed-bins mode: weight each of the n bins of [lo, hi] by the CMFs'
 * mean over the bin, so a spectrum flat within each bin integrates
 * exactly (the midpoint rule with 4 bins of 117 nm is 17 % off for D65). */
vr_status vr_accum_set_bins(accum *a, double lo, double hi, int n, vr_error *err);
void vr_atomic_add(_Atomic uint64_t *cell, double v);
double vr_atomic_get(_Atomic uint64_t *cell);
/* Adds radiance samples (already divided by their wavelength pdf) of a pixel. */
void vr_accum_pixel(accum *a, uint32_t pixel, int nwl, const double *wl, const double *L,
                    double wl_weight);
/* Returns the illuminance (lx) it added. */
/* Adds lx to the illuminance point received from sky patch (or the ground). */
void vr_accum_sensor_patch_lx(accum *a, uint32_t point, int patch, double lx);
double vr_accum_sensor(accum *a, uint32_t point, uint32_t sample, int nwl, const double *wl,
                       const double *E, double wl_weight);
/* Adds lx, or the illuminance of E, to part `part` (VR_PART_*) of point. */
void vr_accum_sensor_part_lx(accum *a, uint32_t point, int part, double lx);
void vr_accum_sensor_part(accum *a, uint32_t point, int part, int nwl, const double *wl,
                          const double *E, double wl_weight);
/* Adds the illuminance of E to slot `slot` (< groups) of point only, not
 * to its spectrum: for side sums such as a photon sensor's bias probe. */
void vr_accum_sensor_lx(accum *a, uint32_t point, uint32_t slot, int nwl, const double *wl,
                        const double *E, double wl_weight);

/* The passes (integrate.c, photons.c). */
typedef struct pass_ctx {
  rscene *rs;
  accum *acc;
  vr_integrator integrator;
  int spp, sample_offset, max_depth;
  int wave_spp;                /* camera units: samples per pixel of one unit (0: all spp) */
  /* Stochastic progressive photon mapping (sppm.h): the visible points
   * the camera pass makes and the photon pass adds to; NULL otherwise. */
  struct vr_sppm *sppm;
  int sensor_samples;
  /* Sensor points, flattened. */
  size_t npoints;
  double (*points)[6];         /* position, normal */
  /* Photon maps (photon integrators): one per cell in each set. */
  vr_photon_set *direct, *caustic, *global;
  long photons_per_unit, photon_units;
  double photon_scale;         /* 1 / total photons emitted */
  int knn;
  double radius;
  bool fixed_radius, final_gather;
  int gather_rays;
  /* Photon sensors (render_sensors.c): sensor paths end at their first
   * diffuse hit in the photon maps' radiance; the accumulator has
   * 2 sensor_groups slots a point, the second half for the bias probe. */
  bool sensor_photons;
  int sensor_groups;
  _Atomic uint64_t fg_photon, fg_path; /* diffuse vertices ended by the maps / continued */
  /* UV pass. */
  size_t ntexels;
  uint32_t *texel_object;
  uint32_t *texel_index;
  int uv_sky_samples;
  uint64_t seed;
} pass_ctx;

extern const vr_flow_ops vr_camera_ops;  /* camera and sensor paths, gather rays */
extern const vr_flow_ops vr_photon_ops;  /* photon tracing into the maps */
extern const vr_flow_ops vr_uv_ops;      /* UV irradiance of photochromic texels */
extern const vr_flow_ops vr_sensor_ops;  /* sensor points */
void vr_camera_generate(void *ctx, vr_flow_worker *w, long unit);
void vr_sensor_generate(void *ctx, vr_flow_worker *w, long unit);

/* The chromogenic state at a hit: the texel of the hit cell's own state
 * map of the object, or the material's state. */
double vr_hit_state(const rscene *rs, const vr_hit *hit);
/* The state map of object o held by cell c, or NULL. */
double *vr_cell_state_map(const rscene *rs, int c, uint32_t o);

#endif
