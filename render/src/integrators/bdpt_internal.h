/* Inside the bidirectional path tracer (bdpt.c, bdpt_lights.c,
 * bdpt_walk.c): path vertices, the local light table, the camera's
 * importance, the subpath walks and the visibility of a connection.
 *
 * Conventions follow pbrt's BDPT (Pharr, Jakob & Humphreys, Physically
 * Based Rendering, 3rd ed., §16.3; pbrt-v4's code keeps them): a vertex keeps
 * the throughput beta of the subpath that reached it (before it scatters),
 * and pdf_fwd / pdf_rev, the area densities with which its own subpath and
 * the other side's would have generated it, for multiple importance
 * sampling (Veach 1997, ch. 10).
 *
 * Thin panes (VR_LOBE_STRAIGHT) are not vertices: a walk that goes
 * straight through one carries on in the same direction with the weight
 * T/p_T, and the density of the vertex it reaches is multiplied by p_T, the
 * probability of that choice; a connection passes a pane with T, as shadow
 * rays do, so both ways of making the same path agree.  The product of the
 * reverse choices on a vertex's incoming segment (seg_rev) enters the
 * reverse density of the vertex before it. */
#ifndef VR_BDPT_INTERNAL_H
#define VR_BDPT_INTERNAL_H

#include <stdbool.h>
#include <stdint.h>

#include "vr/vec3.h"
#include "integrators/integrator.h"

enum { BV_CAMERA = 0, BV_LIGHT, BV_SURFACE };

typedef struct vr_bdpt_vertex {
  uint8_t type;
  bool on_surface;   /* a surface point: a scattering vertex or a point of an emitter */
  bool delta;        /* the walk scattered here by a delta lobe */
  bool delta_light;  /* a point or spot light: no other strategy can reach it */
  bool connectible;  /* has a non-delta lobe (surfaces), always for lights and the camera */
  bool term;         /* a dispersive refraction on the subpath so far kept the hero only */
  int32_t medium;    /* object whose inside the incoming segment lies in, -1 outside */
  int source;        /* its light (bdpt_lights index) for a light or an emitter's point, -1 */
  uint32_t object;
  const vr_bsdf *bsdf;
  double state;      /* chromogenic state at the hit */
  bool tinted;       /* a texture multiplies the BSDF by tint */
  bool bent;         /* ns is a normal map's: nothing scatters across ng */
  double tint[VR_MAX_WL];
  vr_bsdf_point pt;  /* a pbr material's textures at the hit (its BRDF's, not a tint) */
  unsigned lobes;
  double p[3], ng[3], ns[3];
  double wo[3];      /* unit, towards the previous vertex of its subpath */
  double beta[VR_MAX_WL];
  double pdf_fwd, pdf_rev;
  double seg_rev;    /* panes on the incoming segment: product of their reverse p_T */
} vr_bdpt_vertex;

/* The lights BDPT starts subpaths from: point and spot lights and
 * emissive objects, chosen in proportion to their power.  The sun, the sky
 * and the ground glow are left to the camera subpath (next-event estimation
 * and escapes, as the path tracer does them). */
typedef struct vr_bdpt_lights {
  size_t n;
  int *light;        /* index into the scene's light lines (rs->L.light), or -1 for an emitter */
  uint32_t *object;  /* the emitter's object */
  double *pmf, *cdf;
  int *of_object;    /* per scene object: its index here, or -1 */
} vr_bdpt_lights;

/* One worker's scratch and counters. */
typedef struct vr_bdpt_tls {
  vr_bdpt_vertex *cam, *light;
  uint64_t rays_camera, rays_light, rays_shadow, dropped;
} vr_bdpt_tls;

typedef struct vr_bdpt {
  vr_rscene *rs;
  vr_accum *acc;
  vr_bdpt_lights L;
  const vr_camera *cam;   /* the scene's, pinhole or thin lens */
  int spp, sample_offset, max_depth, nwl;
  double wl_weight;        /* (lmax - lmin) / nwl, as vr_accum_pixel wants */
  int threads;
  vr_bdpt_tls *tls;
} vr_bdpt;

/* One camera sample: its random-number stream and wavelengths. */
typedef struct vr_bdpt_sample {
  uint64_t stream;
  uint32_t sample;
  int nwl;
  double wl[VR_MAX_WL];
} vr_bdpt_sample;

/* Random-number keys (vr_rng_key.depth) of the uses within a sample. */
#define BK_CAMERA_WALK 0x100u    /* + vertex index */
#define BK_LIGHT_START 0xF000u
#define BK_LIGHT_WALK 0x10000u   /* + vertex index */
#define BK_NEE 0x20000u          /* + camera vertex index */
#define BK_LENS 0x30000u         /* + light vertex index */
#define BK_FAR 0x40000u          /* + camera vertex index */
#define BK_PANE_DIM 64u          /* + crossing: a pane's choice on a segment */

/* bdpt_lights.c */
vr_status bdpt_lights_init(vr_bdpt_lights *L, const vr_rscene *rs, vr_error *err);
void bdpt_lights_free(vr_bdpt_lights *L);
/* The first vertex of a light subpath, the direction it leaves in, that
 * direction's density (solid angle) and the subpath's throughput after it
 * (Le cos / (p_light p_pos p_dir)); false if there is no light or it sends
 * nothing that way. */
bool bdpt_light_start(const vr_bdpt *b, const vr_bdpt_sample *sm, vr_bdpt_vertex *y0, double dir[3],
                      double *pdf_dir, double *beta);
/* A light vertex for next-event estimation from x (strategy s = 1), chosen
 * as light subpaths choose their first vertex, and Le G_light / (p_light
 * p_pos) towards x per wavelength (G_light: cos at an emitter over d²,
 * 1 / d² for a point); false if none or it sends nothing towards x. */
bool bdpt_light_sample(const vr_bdpt *b, const vr_bdpt_sample *sm, uint32_t key_depth, const double x[3],
                       vr_bdpt_vertex *y, double *contrib);
/* Density (solid angle) with which light vertex y emits towards unit dir. */
double bdpt_light_pdf_dir(const vr_bdpt *b, const vr_bdpt_vertex *y, const double dir[3]);
/* Density (area) with which a light subpath starts at v, a point of an
 * emitter (0 elsewhere). */
double bdpt_light_pdf_origin(const vr_bdpt *b, const vr_bdpt_vertex *v);
/* Radiance an emitter's point v sends towards the unit direction to. */
void bdpt_emitted(const vr_bdpt *b, const vr_bdpt_vertex *v, const double to[3], int nwl, const double *wl,
                  double *Le);
/* bdpt_walk.c */
/* Extends path[0 .. n) by a random walk leaving path[n-1] along dir
 * (density pdf_dir) with throughput beta, to at most maxv vertices;
 * radiance mode for the camera (far, not NULL: the sun's, the sky's and the
 * ground glow's light found on the way is added to far), importance for
 * light subpaths.  Returns the number of vertices. */
int bdpt_walk(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_sample *sm, vr_bdpt_vertex *path, int n, int maxv,
              const double dir[3], double pdf_dir, const double *beta, bool importance,
              uint32_t key_base, double *far);
/* Whether a and b see each other through thin panes: their transmittance
 * and the medium's absorption T per wavelength, and the products of the
 * panes' transmission-choice probabilities for travel from a to b (*p_ab)
 * and from b to a (*p_ba). */
bool bdpt_visible(const vr_bdpt *b, vr_bdpt_tls *tl, const vr_bdpt_vertex *a, const vr_bdpt_vertex *c, int nwl,
                  const double *wl, double *T, double *p_ab, double *p_ba);
/* f (BSDF, no cosine) at surface vertex v from v->wo towards unit wi; in
 * importance mode with the shading-normal correction of Veach 1997 §5.3.
 * *pdf (may be NULL): the density (solid angle) of sampling wi there. */
void bdpt_f(const vr_bdpt_vertex *v, const double wi[3], int nwl, const double *wl, bool importance,
            double *f, double *pdf);
/* Area density at `to` of a direction density pdf at v (the cosine at `to`
 * when it is a surface point). */
double bdpt_to_area(const vr_bdpt_vertex *v, const vr_bdpt_vertex *to, double pdf);

#endif
