/* A light of the scene's 'light' lines behind one interface: a kind is a
 * table of operations (its syntax, the conversion of the amount the user
 * gave to radiometric units, incident light at a point, emission for
 * photons and light subpaths, their densities) registered in one place,
 * lights/registry.c.  Adding a kind of light is one new file holding its
 * table and one line there; the path tracer, BDPT, the photon passes and
 * the annual study reach every kind through this interface.
 *
 * Emissive surfaces (objects with emission=) and the sky are not 'light'
 * lines: they are in lights/emitters.c and lights/sky_light.c, and
 * lights/lights.h gathers all of them for the integrators.
 *
 * Units: spd is the kind's spectral amount in W per nm (per sr, per m², as
 * the kind says); every sample gives incident radiance times solid angle
 * over its pdf (a delta light: the spectral irradiance at normal
 * incidence), so the caller multiplies by BSDF and cosine only. */
#ifndef VR_LIGHTS_LIGHT_H
#define VR_LIGHTS_LIGHT_H

#include <stdbool.h>
#include <stdint.h>

#include "lights/spd.h"
#include "scene/scene_parse.h"
#include "vr/rng.h"
#include "vr/scene.h"

#define VR_MAX_WL VR_SCENE_MAX_WAVELENGTHS /* wavelengths carried by one path */

/* Where light that reaches a sensor came from: the daylight components
 * (render_sensors.c) and the sky-patch tallies are kept by source. */
typedef enum vr_source_class {
  VR_SRC_OTHER = 0, /* photon-map radiance: no single source */
  VR_SRC_SUN,
  VR_SRC_SKY,
  VR_SRC_LAMP,
  VR_SRC_GROUND
} vr_source_class;

/* What a light may know of the scene: where spectra are resolved, and the
 * bounding sphere far lights send their photons across. */
typedef struct vr_light_setup {
  vr_spd_setup spd;
  double centre[3], radius;
} vr_light_setup;

typedef struct vr_light vr_light;

/* One sample of the light incident at a point x. */
typedef struct vr_light_sample {
  double dir[3];       /* from x to the light, unit */
  double dist;         /* to the light's point; INFINITY for far lights */
  double p[3], n[3];   /* the light's point and its normal (a point light's axis) */
  double pdf_pos;      /* the density of p over the light's area; 1 for a point */
  double L[VR_MAX_WL]; /* incident radiance times solid angle over pdf: f-less, cos-less */
  bool delta;          /* a direction no BSDF sample can find */
} vr_light_sample;

/* One sample of what a light emits: a photon, or a light subpath's start. */
typedef struct vr_light_emission {
  double org[3], n[3]; /* where it leaves, and the light's normal there (axis) */
  double pdf_pos;      /* the density of org over the light's area; 1 for a point */
  double dir[3];       /* unit, away from the light */
  double f;            /* Le(dir) cos(theta_org) = spd(λ) f: a point light's distribution
                          (its spd is the on-axis intensity), cos for a uniform area light
                          (its spd is the radiance) */
  double pdf_dir;      /* the density of dir (solid angle); 1 for a far light's beam */
  double weight;       /* f / (pdf_pos pdf_dir): the photon's power is spd(λ) weight */
} vr_light_emission;

/* The random dimensions a 2D sample draws from (vr/rng.h), a pair of the
 * sampler (vr_rng_pair): next-event estimation uses VR_DIM_LIGHT_V/W,
 * photons through portals VR_DIM_EMIT_W/X. */
typedef struct vr_light_dims {
  uint32_t u, v;
} vr_light_dims;

typedef struct vr_light_ops {
  const char *name;     /* the word after 'light' */
  unsigned flags;       /* VR_LF_* */
  vr_source_class source; /* the daylight component its light belongs to */
  const char *spectrum; /* the default spectrum reference */
  /* Reads the options of the scene line into l (kind and loc set). */
  vr_status (*parse)(vr_scn_stmt *t, vr_scene_light *l);
  /* Converts the amount written to l->spd (W per nm, per the kind's
   * reference) and l->power (W over the sampled range, the photons' share);
   * l->spd holds the relative spectrum when it is called. */
  vr_status (*resolve)(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                       vr_error *err);
  void (*destroy)(vr_light *l); /* NULL: nothing of its own */
  /* Light incident at x: one sample (false when it sends nothing to x). */
  bool (*sample_li)(const vr_light *l, const double x[3], const vr_rng_key *key,
                    vr_light_dims dims, int nwl, const double *wl, vr_light_sample *out);
  /* The density (solid angle at x) of sample_li's direction dir; 0 for a
   * delta light. */
  double (*pdf_li)(const vr_light *l, const double x[3], const double dir[3]);
  /* Emission, its numbers drawn from key's VR_DIM_EMIT_U, _V (a pair),
   * _W, _X (a pair) and _Y as it needs them: false when it sends nothing
   * that way. */
  bool (*sample_le)(const vr_light *l, const vr_light_setup *u, const vr_rng_key *key,
                    vr_light_emission *out);
  /* The density (solid angle) with which sample_le leaves point p (normal
   * n) along dir; not used for far lights. */
  double (*pdf_le_dir)(const vr_light *l, const double p[3], const double n[3],
                       const double dir[3]);
} vr_light_ops;

enum {
  VR_LF_DELTA_POSITION = 1,   /* a point: no ray can hit it, no area density */
  VR_LF_FAR = 2,           /* at infinity (the sun): photons come from a disc across
                                  the scene; no light subpath starts there */
  VR_LF_UNIQUE = 4,        /* at most one in a scene */
  VR_LF_SUN = 8            /* the sun a weather sky places and the ground reflects */
};

struct vr_light {
  const vr_light_ops *ops;
  double pos[3], axis[3]; /* where it is, which way it faces (unit) */
  vr_rspd spd;            /* after resolve: the spectral amount (the kind says per what) */
  double power;           /* W over the sampled range, for choosing photon sources */
  double k[8];            /* the kind's own numbers, laid out by its file */
  void *data;             /* the kind's own data, freed by ops->destroy */
};

/* The kinds (lights/registry.c): the ops of kind k (vr_scene_light.kind),
 * NULL past the last; the kind named `name`, or -1. */
const vr_light_ops *vr_light_kind_ops(size_t kind);
int vr_light_kind_find(const char *name);

/* A point on the disc of radius R (the scene's bounding sphere's) normal to
 * d, centred on the scene's centre moved 2R back along d: photons of far
 * sources start there and cross the whole scene. */
void vr_light_disc_origin(const vr_light_setup *u, const double d[3], double u1, double u2,
                          double o[3]);

/* A light of scene line sl: its spectrum resolved and its amount converted
 * (the kind's resolve); vr_light_fini frees what it holds. */
vr_status vr_light_init(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                        vr_error *err);
void vr_light_fini(vr_light *l);

#endif
