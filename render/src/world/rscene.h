/* The scene resolved for rendering: one vr_bsdf per material, the objects
 * with their emitters and photochromic state maps, every light (lights/),
 * the camera (camera/), the sub-domains opened through the geometry cache
 * (ddm/, none loaded yet), the spectral sampling and the film's bins. */
#ifndef VR_WORLD_RSCENE_H
#define VR_WORLD_RSCENE_H

#include <stdbool.h>
#include <stdint.h>

#include "camera/camera.h"
#include "lights/lights.h"
#include "vr/bsdf.h"
#include "vr/domains.h"
#include "vr/geometry.h"
#include "vr/render.h"
#include "vr/rng.h"
#include "vr/scene.h"
#include "vr/scene_tables.h"

typedef struct vr_robject {
  int material;
  int emitter;             /* its index in the lights' emitters, -1 if it emits nothing */
  /* Photochromic glass (a rect): its state map of nu x nv texels, held by
   * each cell the rect reaches (vr_rcell); nu = 0: the material's own state. */
  int nu, nv;
  size_t texel0;           /* its first texel in the UV pass's numbering */
  double corner[3], eu[3], ev[3], normal[3]; /* rect: point = corner + u eu + v ev */
  bool outside;            /* an exterior surface (outside=yes) */
} vr_robject;

/* What the renderer keeps per cell besides its geometry (which vr_domains
 * loads and unloads): the state maps of the photochromic objects in it. */
typedef struct vr_rcell {
  size_t nmaps;
  uint32_t *map_object;    /* increasing */
  double **map;            /* nu*nv states of that object */
} vr_rcell;

typedef struct vr_rmaterial {
  vr_bsdf *bsdf;
  /* A texture multiplying the reflectance per point (owned by the scene's
   * texture list, shared between materials of the same file), or NULL;
   * its alpha mode and (u, v) repeats. */
  const struct vr_texture *tex;
  vr_alpha_mode alpha;
  double alpha_cutoff, tile[2];
  const struct vr_texture *nmap; /* a tangent-space normal map, or NULL */
  double nscale;
  const struct vr_texture *mrmap; /* a pbr material's metallic-roughness texture, or NULL */
  bool vcol;               /* the hit's vertex colours multiply the reflectance */
  const struct vr_texture *amap; /* an opacity map cutting it out (MTL map_d), or NULL */
  double state;            /* chromogenic state from the scene (or 0) */
  bool photochromic;
  struct vr_material *db;  /* the database material, if any */
  double temperature_K;
  unsigned chromo_flags; /* VR_CHROMO_EXTRAPOLATE when the scene asks for it */
} vr_rmaterial;

typedef struct vr_rscene {
  const vr_scene *s;
  vr_domains *d;
  const vr_scene_tables *t; /* the replicated tables, owned by d */
  vr_rcell *cells;          /* one per sub-domain */
  uint64_t *cell_ns;        /* this rank's tracing time per cell in the last run */
  uint64_t *cell_total_ns;  /* and in all runs */
  size_t ntexels;           /* photochromic texels of all objects */
  double lmin, lmax;        /* sampled range */
  int nwl;                  /* wavelengths per path */
  bool bins_mode;           /* fixed bins instead of hero sampling */
  size_t nmat;
  vr_rmaterial *mat;
  vr_robject *obj;
  vr_lights L;              /* the lights, emitters, sky and photon sources */
  bool sun_disc;            /* camera paths see the sun's disc (not in the annual study's
                               image coefficients, which add it at the true sun) */
  double scene_lo[3], scene_hi[3], scene_radius, scene_centre[3];
  vr_camera cam;
  double film_lo, film_step;
  size_t nbins;
  vr_rng_seed seed; /* the scene's seed and sampler: keys every vr_rng (vr/rng.h) */
  size_t ntex;
  struct vr_texture **tex;  /* every texture the materials use, loaded once each */
  size_t tex_bytes;         /* their memory */
  const struct vr_rgb_table *rgb_table; /* colours to spectra, when vertex colours are used */
  double tex_seconds;       /* and their loading time */
} vr_rscene;

/* Resolution of the scene (resolve.c): materials, lights, the sky, and the
 * sub-domains opened through the geometry cache (none loaded yet). */
vr_status vr_rscene_create(const vr_scene *s, vr_matdb *db, const vr_render_options *opt,
                           int subdomains, vr_rscene **out, vr_error *err);
/* The textures of the materials (world/textures.c): files and embedded
 * images, and the spectral textures of database materials (checked by
 * their recorded SHA-256), on up to `threads` threads; errors name the
 * material's scene line. */
vr_status vr_rscene_textures(vr_rscene *rs, int threads, vr_error *err);
/* The texture factor at a hit for the path's wavelengths (1 where the
 * material has none): false, with f untouched, when it has none.  width:
 * the ray footprint there (world units, 0 for the finest level). */
bool vr_hit_texture(const vr_rscene *rs, const vr_hit *hit, double width, int nwl,
                    const double *nm, double *f);
/* The shading normal a normal map gives at the hit (glTF's convention:
 * tangent-space x along +u, y along +v, z the interpolated normal; scaled
 * x and y, then normalised), into ns: false, ns untouched, when the
 * material has none or the hit no tangent frame.  It stays on the side of
 * the geometric normal the interpolated normal is on. */
bool vr_hit_normal_map(const vr_rscene *rs, const vr_hit *hit, double width, double ns[3]);
/* What a pbr material's textures make of it at the hit (base colour,
 * metallic, roughness), for the path's wavelengths: false, pt untouched,
 * for any other material.  width as for vr_hit_texture. */
bool vr_hit_pbr(const vr_rscene *rs, const vr_hit *hit, double width, int nwl, const double *nm,
                vr_bsdf_point *pt);
/* Whether the material can be cut out (an alpha mode and a texture or an
 * opacity map to read it from). */
static inline bool vr_rmaterial_cuts(const vr_rmaterial *m) {
  return (m->tex || m->amap) && m->alpha != VR_ALPHA_OFF;
}
/* Whether the surface is cut out at the hit (alpha); u: a uniform number
 * for VR_ALPHA_BLEND. */
bool vr_hit_cut_out(const vr_rscene *rs, const vr_hit *hit, double u);

/* Bytes of the photochromic state maps held by the cells. */
size_t vr_rscene_map_bytes(const vr_rscene *rs);
void vr_rscene_destroy(vr_rscene *rs);

/* The chromogenic state at a hit: the texel of the hit cell's own state
 * map of the object, or the material's state. */
double vr_hit_state(const vr_rscene *rs, const vr_hit *hit);
/* The state map of object o held by cell c, or NULL. */
double *vr_cell_state_map(const vr_rscene *rs, int c, uint32_t o);
/* The emission spectrum of object o, or NULL when it emits nothing. */
static inline const vr_rspd *vr_rscene_emission(const vr_rscene *rs, uint32_t o) {
  int e = rs->obj[o].emitter;
  return e >= 0 ? &rs->L.emitter[e].emission : NULL;
}

/* Wavelengths of a path (wavelengths.c): a hero wavelength, stratified
 * over `strata` samples, and equally spaced rotations of it; or the fixed
 * bins' centres. */
void vr_wavelengths(const vr_rscene *rs, const vr_rng_key *key, uint32_t strata, double *wl);
/* The i-th wavelength of a path whose first is wl0, as vr_wavelengths
 * makes it (every one then follows from the first: a ray's wire form
 * carries the first alone). */
double vr_wavelength_at(const vr_rscene *rs, double wl0, int i);

#endif
