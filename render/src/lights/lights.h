/* Everything that emits light in a resolved scene, as the integrators see
 * it: the scene's light lines (each behind its kind's interface, light.h),
 * the emissive surfaces, the sky above the horizon and the ground glow
 * below it, the sky portals, and the photon sources with their shares.
 *
 * Next-event estimation at a point takes one sample of every light line
 * (vr_lights_sample_light), one emitter chosen by power over squared
 * distance (vr_lights_sample_emitter) and one sky direction
 * (vr_lights_sample_sky); escaping rays meet the sky and the ground glow
 * (vr_lights_environment).  Every sample gives incident radiance times
 * solid angle over its pdf, so the caller multiplies by BSDF and cosine. */
#ifndef VR_LIGHTS_LIGHTS_H
#define VR_LIGHTS_LIGHTS_H

#include <stdbool.h>
#include <stdint.h>

#include "lights/light.h"
#include "vr/scene_tables.h"
#include "vr/sky.h"

/* An emissive surface: an object with emission=. */
typedef struct vr_emitter {
  uint32_t object;
  vr_rspd emission;  /* radiance W/(m² sr nm) of its front side */
  double power;      /* W over the sampled range */
  double sphere[4];  /* bounding sphere: centre, radius */
} vr_emitter;

/* A sky portal (portals.c), from the scene's corner, u, v. */
typedef struct vr_portal {
  double corner[3], u[3], v[3], n[3]; /* n unit, u x v / |u x v| */
  double area, uu, vv;                /* |u x v|, u.u, v.v */
} vr_portal;

/* At most this many portals (the scene parser refuses more). */
#define VR_MAX_PORTALS VR_SCENE_MAX_PORTALS
/* The share of sky samples aimed through the portals when there are any. */
#define VR_PORTAL_SHARE 0.9
/* The share of photons the portal sources get when there are any. */
#define VR_PORTAL_PHOTON_SHARE 0.75
/* The far sources that also emit through the portals. */
enum { VR_PORTAL_SRC_SUN, VR_PORTAL_SRC_SKY, VR_PORTAL_SRC_GROUND };

typedef struct vr_lights {
  vr_light_setup setup;
  const vr_scene_tables *t; /* the emitters' geometry (owned by the domains) */
  size_t n;                 /* the scene's light lines */
  vr_light *light;
  size_t sun;               /* the light that is the sun (VR_LF_SUN), or n */
  size_t nemitters;
  vr_emitter *emitter;
  double *emitter_cdf;      /* by power alone, normalised */
  /* The sky. */
  bool has_sky;
  vr_sky *sky;
  vr_rspd sky_spd;          /* radiance per unit relative luminance: W/(m² sr nm) per (cd/m²) */
  double ground_radiance_scale; /* ground glow: rho / pi */
  vr_rspd ground_spd;       /* the irradiance the ground receives, W/(m² nm) */
  size_t nportals;
  vr_portal *portals;
  double *portal_area_cdf, portal_area; /* running sums of the portals' areas, their total */
  /* Photon sources: the lights, the emitters, the sky and the ground glow,
   * then those through the portals (portal_source[]: VR_PORTAL_SRC_*). */
  size_t nportal_sources;
  int portal_source[3];
  size_t nsources;
  double *source_cdf;
  double total_power;
  /* The power each portal photon starts with (their sources' power over
   * their share of the photons), 0 without them: what a photon scattered
   * outside towards a portal is split to match (photon_trace.c). */
  double portal_photon_power;
} vr_lights;

/* The scene's light lines (emitters, the sky and the sources are added by
 * the calls below, in this order). */
vr_status vr_lights_create(vr_lights *L, const vr_scene *s, const vr_light_setup *u,
                           const vr_scene_tables *t, vr_error *err);
/* Object `object` of the scene is an emissive surface of the given area;
 * *index gets its emitter index, or -1 when its area is zero (it emits
 * nothing). */
vr_status vr_lights_add_emitter(vr_lights *L, const vr_scene_object *so, uint32_t object,
                                double area, int *index, vr_error *err);
/* After the emitters: their choice by power. */
void vr_lights_emitters_done(vr_lights *L);
vr_status vr_lights_sky_create(vr_lights *L, const vr_scene *s, vr_error *err);
vr_status vr_lights_portals_create(vr_lights *L, const vr_scene *s, vr_error *err);
/* Last: the photon sources (with the portals' when photon_portals). */
vr_status vr_lights_sources_create(vr_lights *L, bool photon_portals, vr_error *err);
void vr_lights_destroy(vr_lights *L);

/* ---- next-event estimation (nee.c, emitters.c, sky_light.c) ---- */

/* Light line i's sample at x (its random numbers keyed by key). */
bool vr_lights_sample_light(const vr_lights *L, size_t i, const double x[3],
                            const vr_rng_key *key, int nwl, const double *wl,
                            vr_light_sample *out);
bool vr_lights_sample_emitter(const vr_lights *L, const double x[3], int nwl, const double *wl,
                              const vr_rng_key *key, vr_light_sample *out);
/* A sky direction from x (above the surface of normal n when n is not
 * NULL), through the portals' mixture when there are portals. */
bool vr_lights_sample_sky(const vr_lights *L, const double x[3], const double n[3], int nwl,
                          const double *wl, const vr_rng_key *key, vr_light_sample *out);
/* Radiance arriving from the environment along dir (sky above, ground glow below). */
/* The sun's disc seen along dir (unit): its radiance, the normal
 * irradiance over the disc's solid angle 2 pi (1 - cos r), into L; false
 * (L untouched) without a sun, for a parallel beam (radius 0) or outside
 * the disc.  The sun is a delta light for next-event estimation, so only
 * a path whose every vertex was delta may count it (the eye's). */
bool vr_lights_sun_disc(const vr_lights *L, const double dir[3], int nwl, const double *wl,
                        double *Lsun);
void vr_lights_environment(const vr_lights *L, const double dir[3], bool include_sky, int nwl,
                           const double *wl, double *L_out);
/* The share of the ground glow's radiance at nm that the sun lit (the rest
 * is the sky's), and the unobstructed sky's horizontal illuminance (lx,
 * without the sun): the daylight factor's denominator. */
double vr_lights_ground_sun_share(const vr_lights *L, double nm);
double vr_lights_sky_horizontal_lx(const vr_lights *L);
/* The sky's radiance along dir (towards the sky), per wavelength, and the
 * sky's and the ground glow's rough powers through the scene's disc (only
 * for sharing the photons among sources). */
void vr_lights_sky_radiance(const vr_lights *L, const double dir[3], int nwl, const double *wl,
                            double *out);
double vr_lights_sky_power(const vr_lights *L);
double vr_lights_ground_power(const vr_lights *L);

/* ---- portals (portals.c) ---- */

/* How much each portal is worth sampling from x, once per shading point:
 * a solid-angle estimate, for the sky (sky) times the share of the portal
 * above x's horizontal plane (the sky gives nothing below the horizon), and
 * that share.  sum 0: no portal is usable from x. */
typedef struct vr_portal_weights {
  bool sky;
  double sum, w[VR_MAX_PORTALS], share[VR_MAX_PORTALS];
} vr_portal_weights;
void vr_portal_weights_at(const vr_lights *L, const double x[3], bool sky, vr_portal_weights *pw);
/* A direction through one of the portals from x (u0 picks the portal, u1
 * and u2 the point; false if none is usable from x), and the portal
 * strategy's density in solid angle at x for a direction, both with x's
 * weights.  For the sky only the part of each portal above x is sampled,
 * and the density is that of the directions that rise (0 for the others). */
bool vr_portal_sample(const vr_lights *L, const double x[3], const vr_portal_weights *pw,
                      double u0, double u1, double u2, double dir[3]);
double vr_portal_pdf(const vr_lights *L, const double x[3], const vr_portal_weights *pw,
                     const double dir[3]);
/* A point uniform over the portals' total area (u0 picks the portal by
 * area, u1 and u2 the point), and which portal. */
void vr_portal_point(const vr_lights *L, double u0, double u1, double u2, double y[3],
                     size_t *which);
/* Whether org + t dir, t in (0, tmax], crosses a portal inwards (along its
 * normal). */
bool vr_portal_crossed_inward(const vr_lights *L, const double org[3], const double dir[3],
                              double tmax);
/* The share of what a diffuse surface at x (normal n) reflects that goes
 * through the portals: the point-to-rectangle form factor, each portal
 * taken at its centre, A cos cos' / (pi d^2), summed and capped at 1.  An
 * estimate for choosing how many photons to split into (never a weight). */
double vr_portal_form_factor(const vr_lights *L, const double x[3], const double n[3]);

/* ---- photon sources (sources.c) ---- */

/* A photon's start: where, which way, and its power per wavelength sample
 * (W, before dividing by the photon count). */
typedef struct vr_photon_emit {
  double org[3], dir[3];
  double power[VR_MAX_WL];
} vr_photon_emit;

/* Photon emission from source `source` (< nsources - nportal_sources) in
 * source_cdf order. */
bool vr_lights_emit_photon(const vr_lights *L, size_t source, int nwl, const double *wl,
                           const vr_rng_key *key, vr_photon_emit *out);
/* A photon of a far source (VR_PORTAL_SRC_*) through the portals;
 * *to_portal is the distance from its origin to the portal it enters by. */
bool vr_lights_emit_portal_photon(const vr_lights *L, int kind, int nwl, const double *wl,
                                  const vr_rng_key *key, vr_photon_emit *out, double *to_portal);
/* Whether source s is a far one (the sun, the sky, the ground glow), and
 * whether it is the ground glow. */
bool vr_lights_source_is_far(const vr_lights *L, size_t s);
bool vr_lights_source_is_ground(const vr_lights *L, size_t s);

#endif
