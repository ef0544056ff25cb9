/* An integrator behind one interface: a table of operations (its name in
 * the scene's render line, its own rules for that line, the renders it
 * refuses, and the camera image it makes) registered in one place,
 * integrators/registry.c.  Adding an integrator is one new file holding its
 * table and one line there.
 *
 * vr_render_scene (render.c) resolves the scene, runs the UV and sensor
 * passes, then hands the camera image to the scene's integrator: render()
 * records its decisions (which photon passes, and why), runs its passes
 * through vr_camera_pass or its own loop, and leaves the image's sums in
 * job->acc; the caller adds them over the ranks, divides by job->passes and
 * lets add_film() add what the integrator kept apart (SPPM's photon
 * radiance). */
#ifndef VR_INTEGRATORS_INTEGRATOR_H
#define VR_INTEGRATORS_INTEGRATOR_H

#include "integrators/pass.h"
#include "scene/scene_parse.h"
#include "world/analysis.h"

/* The camera image an integrator makes. */
typedef struct vr_camera_job {
  vr_run *run;
  vr_rscene *rs;
  vr_accum *acc;              /* the image's sums */
  int W, H, spp;
  long photons, caustic_photons; /* per pass, with the command line's override */
  vr_scene_needs needs;       /* what the scene's materials call for */
  bool lights_exist;          /* a light with power: photons have a source */
  /* Set by render(): */
  int passes;                 /* the sums are over this many passes (divide by it) */
  /* Adaptive sampling (adaptive.c): the job's pixels take their samples in
   * rounds (vr_integrator_camera); the film holds sums, and pixel_samples
   * (which the job then owns) each pixel's count. */
  bool adaptive;
  /* Denoising at a fixed spp: the camera pass in two halves (spp even). */
  bool halves;
  uint32_t *pixel_samples;
  struct vr_adaptive_summary adaptive_summary;
  double seconds;             /* the camera passes' time */
  void *state;                /* what add_film() and free_state() work on */
  void (*add_film)(const void *state, double *xyz, double *spectral);
  /* With halves: adds what the integrator kept apart of the second half
   * alone to that half's mean XYZ (NULL: nothing is kept apart). */
  void (*add_half_film)(const void *state, double *xyz);
  void (*free_state)(void *state);
} vr_camera_job;

typedef struct vr_integrator_ops {
  const char *name;           /* render integrator=NAME */
  const char *what;           /* the camera pass's record: "path tracing" */
  /* Its own rules for the render line (scene/scene_parse.h), or NULL. */
  vr_scn_settings_rule settings;
  /* Refuses, before any work, a render it cannot do (VR_E_ARG naming the
   * reason); NULL: it can do any. */
  vr_status (*check)(const vr_scene *s, const vr_render_options *opt, int nranks,
                     vr_error *err);
  vr_status (*render)(vr_camera_job *job, vr_error *err);
  /* Its pixels' estimates are their own camera samples' means (no light
   * splatted onto other pixels, no estimate shared over iterations), so it
   * can sample adaptively (adaptive.c). */
  bool adaptive;
  /* Its pixels' estimates are not their samples' means, but it renders the
   * denoiser's two halves as two independent estimates of the whole image
   * (SPPM: two chains of spp / 2 iterations each), so it can be denoised. */
  bool chains;
  /* Its camera paths deliver each pixel's light with the source it came
   * from (a sky patch, the ground glow, the sun), so the film can keep
   * its tallies by source (vr_render_options.pixel_patches). */
  bool source_tallies;
} vr_integrator_ops;

/* Integrator i (vr_scene_settings.integrator; the values of vr_integrator in
 * vr/scene.h are the first five), NULL past the last. */
const vr_integrator_ops *vr_integrator_ops_of(size_t i);

/* Records that integrator `name` uses no photon map (the records the
 * photon integrators make with their decisions). */
void vr_integrator_no_photons(vr_run *r, const char *name);
/* Which photon passes the job's scene calls for: a global map (diffuse
 * surfaces interreflect, depth above 1, a light with power) and caustics
 * (specular or glossy surfaces and diffuse ones to land on). */
void vr_integrator_photon_needs(const vr_camera_job *job, bool *global, bool *caustic);
/* A pass for the job: its scene, accumulators, spp and depth. */
vr_pass vr_integrator_pass(const vr_camera_job *job);
/* A pass over the whole camera job's image through ops with c's settings
 * (spp, the integrator's hook), the seconds it took added to job->seconds. */
vr_status vr_integrator_camera(vr_camera_job *job, vr_pass *c, const vr_flow_ops *ops,
                               vr_error *err);
/* The camera pass in rounds of adaptive sampling (adaptive.c): what
 * vr_integrator_camera runs when job->adaptive; sets job->pixel_samples. */
vr_status vr_adaptive_camera(vr_camera_job *job, vr_pass *c, const vr_flow_ops *ops,
                             vr_error *err);
/* The samples of a half of the first round: the smallest multiple of spp
 * (the sampler's block) that is at least 4. */
int vr_adaptive_half(int spp);
/* What adaptive sampling holds per pixel beyond the film (bytes). */
size_t vr_adaptive_bytes_per_pixel(void);

#endif
