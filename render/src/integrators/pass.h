/* A pass of paths through the ray flow (camera, sensor and UV paths), and
 * the path tracing every camera-side integrator shares (paths.c):
 *   - emission is counted where no next-event estimate could have found it:
 *     at the first vertex and after a delta lobe (mirror, refraction, pane);
 *   - at a vertex with a non-delta lobe, next-event estimation sends one
 *     shadow ray to each light line, one to an emissive surface and one to
 *     the sky (lights/lights.h); shadow rays cross thin elements (panes,
 *     chromogenic glass, measured glazing) with their straight
 *     transmittance, so sunlight through a window is direct light;
 *   - the sky is reached only by next-event estimation after a non-delta
 *     lobe (no double counting); the ground glow below the horizon only by
 *     escaping rays;
 *   - at a vertex with a diffuse lobe the pass's integrator has its say
 *     (vr_pass.at_diffuse): the Whitted integrator stops there (the paper's
 *     local illumination: direct light plus specular chains), the photon
 *     integrators read their maps or leave a visible point, photon sensors
 *     read the maps; without a say, or when it lets the path go on, the
 *     path samples the BSDF and continues.
 * Glossy (GGX) vertices always continue by sampling, with next-event
 * estimation at each. */
#ifndef VR_INTEGRATORS_PASS_H
#define VR_INTEGRATORS_PASS_H

#include <stdbool.h>

#include "film/accum.h"
#include "integrators/payload.h"
#include "run/run.h"
#include "world/rscene.h"

/* A surface vertex as the path code evaluates it. */
typedef struct vr_surface {
  const vr_bsdf *b;
  double state;
  vr_vec3 n, wo;
  int nwl;
  const double *wl;
  vr_vec3 ns;
  bool tinted;              /* a texture multiplies the BSDF by tint (per wavelength) */
  double tint[VR_MAX_WL];
  vr_bsdf_point pt;         /* a pbr material's textures at the point (not a tint: its
                               base colour is inside the BRDF), and the lobes asked for */
  bool bent;                /* n and ns are a normal map's: a direction on the other side
                               of the geometric normal ng from wo scatters nothing (the
                               textured materials are opaque Lambertian reflectors) */
  vr_vec3 ng;
} vr_surface;

/* The spread a ray cone takes on after a diffuse or glossy vertex
 * (radians): such a vertex scatters over the hemisphere, and the texture
 * it meets next is averaged over many paths anyway, so a wide footprint
 * (a coarse mip level) only removes aliasing noise. */
#define VR_CONE_SPREAD_SCATTER 0.1
/* The ray cone after a vertex at distance t along the ray: its width there
 * becomes the new origin width; a deflecting non-delta lobe widens the
 * spread. */
void vr_cone_advance(vr_payload *p, double t, unsigned lobe);

typedef struct vr_pass vr_pass;

struct vr_pass {
  vr_rscene *rs;
  vr_accum *acc;
  int spp, sample_offset, max_depth;
  int wave_spp;             /* camera units: samples per pixel of one unit (0: all spp) */
  /* Adaptive sampling (adaptive.c): the pixels that take this pass's
   * samples (NULL: all), whether a sample weighs 1 (the film then holds
   * sums, divided by each pixel's count at the end) rather than 1/spp, and
   * whether the pass is the second half of a round (its XYZ also kept
   * apart). */
  const uint8_t *active;
  /* A sample weighs 1 / weight_spp where it is not 0, else 1 / spp (a
   * denoised render's halves: passes of spp / 2 making an image of spp). */
  int weight_spp;
  bool sum_samples;
  bool second_half;
  /* Wavelengths every path of the pass shares (an SPPM iteration's), or NULL. */
  const double *fixed_wl;
  /* The integrator's say at a path's vertex with a diffuse lobe, after
   * next-event estimation: true when the path ends there (it delivered
   * what it estimates).  NULL: paths go on. */
  bool (*at_diffuse)(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                     const vr_surface *se, const double wo[3]);
  /* Photon passes (photon_trace.c): where a photon lands on a surface with
   * a diffuse lobe (before any portal it must still cross is excluded). */
  void (*land)(vr_pass *c, const vr_payload *p, const vr_hit *hit, const double dir[3]);
  long photons_per_unit;
  /* Sensor paths: a sample's slot in the point's batches is sample %
   * sensor_slots (0: the sample itself). */
  uint32_t sensor_slots;
  void *state;              /* the integrator's own */
};

/* The path-tracing callbacks of the ray flow (paths.c): closest hits and
 * escapes, shadow rays' crossings and deliveries. */
void vr_path_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit);
bool vr_path_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit);
void vr_path_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached);
/* A closest hit on a cut-out (alpha) point of a textured surface: the ray
 * goes on through it (pushed again beyond the hit, its footprint and
 * medium's absorption carried on) and true is returned; else false. */
bool vr_path_pass_through(vr_pass *c, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit);
/* A vr_payload's wire form between ranks (payload_wire.c): the ops' round,
 * pack and unpack of every pass whose rays carry one (ctx: its vr_pass). */
void vr_payload_round(const void *ctx, unsigned char *payload);
size_t vr_payload_pack(const void *ctx, const unsigned char *payload, unsigned char *out);
size_t vr_payload_unpack(const void *ctx, const unsigned char *in, size_t avail,
                         unsigned char *payload);
#define VR_PAYLOAD_WIRE vr_payload_round, vr_payload_pack, vr_payload_unpack
/* Camera unit: one tile of the image, one wave of its samples. */
void vr_camera_generate(void *ctx, vr_flow_worker *w, long unit);
/* The camera pass's flow: camera paths, shadow rays. */
extern const vr_flow_ops vr_camera_path_ops;

/* The camera pass: c->spp samples a pixel of a W x H image through ops, in
 * waves of bounded rays. */
vr_status vr_camera_pass(vr_run *r, vr_pass *c, const vr_flow_ops *ops, int W, int H,
                         vr_error *err);

/* Pieces for integrators' own callbacks. */
/* Delivers a finished contribution (times the sample weight) to what the
 * path serves. */
void vr_path_deliver(vr_pass *c, const vr_payload *p, const double *v);
/* BSDF times |cos| at a vertex, per wavelength (fu: a vr_surface), and a
 * sensor's cosine receiver on the front of normal fu. */
typedef void (*vr_bsdf_cos_fn)(const void *u, const double wi[3], double *fc);
void vr_surface_f(const void *u, const double wi[3], double *fc);
void vr_receiver_f(const void *u, const double wi[3], double *fc);
/* Next-event estimation at x: one shadow ray per light line, one to an
 * emitter, one to the sky (above n_for_sky when not NULL), each carrying
 * beta f(wi) L; depth_key keys their random numbers.  lines_only: the
 * light lines alone (a vertex whose sampled directions count the sky and
 * the emitters they hit, VR_PF_SPECULAR_LAST). */
void vr_path_next_event(vr_pass *c, vr_flow_worker *w, const vr_payload *p, const double x[3],
                        const double ng[3], const double *n_for_sky, vr_bsdf_cos_fn f,
                        const void *fu, uint32_t depth_key, bool lines_only);
/* The surface at a hit seen from wo, and the absorption of the medium the
 * path crossed to reach it (applied to p->beta). */
vr_surface vr_path_surface(const vr_rscene *rs, const vr_payload *p, const vr_hit *hit,
                           const double wo[3]);
void vr_path_absorb(const vr_rscene *rs, vr_payload *p, const vr_hit *hit);
/* An origin just off the surface on the side of dir. */
void vr_spawn_origin(const double p[3], const double ng[3], const double dir[3], double o[3]);
/* (lmax - lmin) / nwl: a wavelength sample's weight in spectral integrals. */
double vr_wl_weight(const vr_rscene *rs, int nwl);

#endif
