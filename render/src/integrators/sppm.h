/* Stochastic progressive photon mapping (Hachisuka & Jensen 2009, with the
 * per-pixel radius and flux statistics of Hachisuka, Ogaki & Jensen 2008),
 * spectral: the
 * renderer's `integrator=progressive` (alias `sppm`).
 *
 * Each iteration i:
 *  1. picks one set of hero wavelengths for the whole iteration (the hero
 *     stratified over the iterations), shared by every camera path and
 *     every photon, so each photon counts at every wavelength a visible
 *     point carries (no wavelength bins);
 *  2. traces one camera path per pixel through specular vertices to its
 *     first vertex with a diffuse lobe: emission and next-event estimates
 *     on the way go to the film as in the path tracer, and the vertex
 *     becomes the pixel's visible point (position, shading normal, wo, the
 *     material and its state, the path's throughput);
 *  3. traces photons in passes through the ray flow (no photon map is
 *     stored): each photon that has scattered off something other than a
 *     straight pane (light that next-event estimation cannot reach) adds
 *     f(wo, wi) Φ at its wavelengths to every visible point within that
 *     point's radius, found through a hash grid of the visible points;
 *  4. updates each pixel that received M photons (Hachisuka, Ogaki &
 *     Jensen 2008, as pbrt-v4's SPPM does): N' = N + γ M, R' = R sqrt(N' / (N + M)),
 *     τ' = (τ + β Φ) R'^2 / R^2, with γ = alpha (2/3 by default).
 * The pixel's photon radiance after I iterations of Np photons each is
 * τ / (I Np π R^2), held as CIE XYZ and film bins (each iteration's
 * wavelengths converted as the film converts them).
 *
 * Memory: a fixed amount per pixel (the visible point, R, N, τ), whatever
 * the number of iterations or photons.  Several ranks: each rank's visible
 * points and photon sums are added over the ranks after each step (a pixel's
 * visible point is made by one rank), so every rank holds the same state. */
#ifndef VR_SPPM_H
#define VR_SPPM_H

#include <stdatomic.h>
#include <stdint.h>

#include "integrators/pass.h"

/* One visible point as doubles, so ranks can add them (a pixel's point
 * is non-zero on one rank only). */
enum {
  VP_VALID = 0, VP_P = 1, VP_N = 4, VP_WO = 7, VP_STATE = 10, VP_MATERIAL = 11,
  VP_LAMBERT = 12, /* 1: a Lambertian surface, whose f is the same for every wi on wo's side */
  VP_TERM = 13,    /* 1: the camera path refracted dispersively (only the hero is left) */
  VP_OBJECT = 14,  /* the object hit, plus one */
  VP_NG = 15,      /* its geometric normal */
  VP_BETA = 18,    /* the camera path's throughput, or for a Lambertian one beta f */
  VP_DOUBLES = VP_BETA + VR_MAX_WL
};

/* What photons add to one visible point in an iteration, and what they
 * need of it, in one place (a little over two cache lines): the photon pass's memory
 * traffic is these records. */
typedef struct vr_sppm_acc {
  _Atomic uint32_t lock;     /* held while a photon adds */
  uint32_t m;                /* photons that reached the point */
  uint32_t term;             /* VP_TERM's value */
  double w[VR_MAX_WL];       /* VP_BETA's values */
  double phi[VR_MAX_WL];     /* sum of w f Φ (f folded into w for a Lambertian point) */
} vr_sppm_acc;

/* Points are stored by slot, the image cut in 8 x 8-pixel tiles, so the
 * points a photon reaches, neighbours in the image, are neighbours in
 * memory. */
#define SPPM_TILE 8

typedef struct vr_sppm {
  int width, height;
  size_t npx, nslots;
  int nwl;
  double wl[VR_MAX_WL];      /* this iteration's wavelengths */
  double wl_weight;          /* (lmax - lmin) / nwl */
  double *vp;                /* nslots * VP_DOUBLES */
  vr_sppm_acc *acc;             /* nslots */
  double *radius;            /* per slot, m; 0 until its first visible point */
  double *share;             /* per slot: this iteration's share of the disc on its sheet */
  uint8_t *ends;             /* per object: a rect's edges where its sheet ends (surface_disc.h) */
  double *n;                 /* per slot: the photon count N of the statistics */
  vr_accum tau;                 /* τ as XYZ and film bins per pixel */
  double radius0;            /* the first radius: metres, or */
  double radius0_px;         /* ... this many pixel footprints at the point (radius0 = 0) */
  double footprint;          /* a pixel's width at unit distance (pinhole) */
  /* The first radius from the photon density (vr_sppm_set_pilot): at
   * least the radius whose disc holds pilot_k photons of one iteration,
   * found among the pilot maps' photons, at most pilot_rmax. */
  const struct vr_photon_maps *pilot;
  int pilot_k;
  double pilot_rmax;
  double cam[3];             /* camera position, for the footprint */
  double gamma;              /* the share of new photons kept (alpha) */
  /* The grid of this iteration's visible points. */
  double lo[3], cell;
  int res[3];
  size_t hsize;
  uint32_t *start;           /* hsize + 1 offsets into idx */
  struct vr_sppm_entry *idx;    /* each hash slot's points side by side */
  uint64_t photons_total;    /* emitted over the iterations so far */
} vr_sppm;

/* film_bins: the spectral bins its film keeps (the camera film's: 0 when
 * no output needs them). */
vr_status vr_sppm_create(vr_sppm *s, const vr_rscene *rs, int width, int height, size_t film_bins,
                         double radius0, double radius0_px, double gamma, vr_error *err);
void vr_sppm_destroy(vr_sppm *s);

/* The photon maps of one iteration's photons (global and caustic: the
 * light SPPM's photons carry), traced apart, from which new visible
 * points take their first radius (NULL: pixel footprints only); the maps
 * stay the caller's and must outlive every vr_sppm_build that places a
 * pixel's first point. */
void vr_sppm_set_pilot(vr_sppm *s, const struct vr_photon_maps *maps, int k, double rmax);
/* Iteration `iteration` of `iterations`: picks its wavelengths and clears
 * the visible points and this iteration's sums. */
void vr_sppm_begin(vr_sppm *s, const vr_rscene *rs, int iteration, int iterations);

/* The pixel's visible point (a camera path's first diffuse vertex);
 * terminated: the path refracted dispersively on the way, so beta holds
 * only the hero, times nwl (bsdf_dielectric.c). */
void vr_sppm_set_point(vr_sppm *s, const vr_rscene *rs, uint32_t pixel, const double p[3],
                       const double ns[3], const double ng[3], int object, const double wo[3],
                       int material, double state, const vr_bsdf_point *pt, int nwl,
                       const double *beta, bool terminated);

/* After the camera pass (and the ranks' sum of the points): the grid, and
 * each point's share of its disc on its sheet of surface. */
vr_status vr_sppm_build(vr_sppm *s, const vr_rscene *rs, vr_error *err);

/* A photon of power beta (at the iteration's wavelengths, before the 1/N of
 * the photon count) arriving at x on object `object` (geometric normal ng)
 * from direction wi (towards where it came from): adds f Φ to every
 * visible point whose disc holds x on the point's own sheet of surface
 * (surface_disc.h: not a wall's photons at a floor's point).
 * terminated: the photon refracted dispersively (its hero alone, times
 * nwl); where the point's camera path did too, the factor nwl counts
 * once, since both stand for the same dropped wavelengths (the iteration
 * shares one hero between them). */
void vr_sppm_deposit(vr_sppm *s, const vr_rscene *rs, const double x[3], const double ng[3],
                     int object, const double wi[3], const double *beta, bool terminated);

/* Several ranks: adds the visible points (after the camera pass) or this
 * iteration's photon sums (after the photon pass) over the ranks. */
struct vr_comm;
vr_status vr_sppm_sum_points(vr_sppm *s, struct vr_comm *comm, vr_error *err);
vr_status vr_sppm_sum_photons(vr_sppm *s, struct vr_comm *comm, vr_error *err);

/* After the photon pass (and the ranks' sums): the radius and τ update. */
void vr_sppm_update(vr_sppm *s, uint64_t photons);

/* The radii of the pixels that have one: the least, the median and the
 * greatest (0 when none has). */
void vr_sppm_radii(const vr_sppm *s, double *lo, double *median, double *hi);

/* Adds w times the photon radiance τ / (I Np π R^2) of every pixel to xyz
 * (npx * 3) and, unless NULL, bins (npx * nbins). */
void vr_sppm_film(const vr_sppm *s, double w, double *xyz, double *bins);

#endif
