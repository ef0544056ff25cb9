/* The registry of integrators (integrators/kinds.def, one line each; the
 * index is the scene's vr_scene_settings.integrator), and what integrators
 * share.  The scene
 * grammar finds their names here too (vr_scn_integrator). */
#include "integrators/integrator.h"

#define VR_INTEGRATOR(ops) extern const vr_integrator_ops ops;
#include "integrators/kinds.def"
#undef VR_INTEGRATOR

static const vr_integrator_ops *const INTEGRATORS[] = {
#define VR_INTEGRATOR(ops) &ops,
#include "integrators/kinds.def"
#undef VR_INTEGRATOR
};
enum { NINTEGRATORS = sizeof INTEGRATORS / sizeof *INTEGRATORS };

const vr_integrator_ops *vr_integrator_ops_of(size_t i) {
  return i < NINTEGRATORS ? INTEGRATORS[i] : NULL;
}

/* The grammar's view of the registry (scene/scene_parse.h). */
const char *vr_scn_integrator(size_t i, vr_scn_settings_rule *rule) {
  if (i >= NINTEGRATORS) return NULL;
  *rule = INTEGRATORS[i]->settings;
  return INTEGRATORS[i]->name;
}

void vr_integrator_no_photons(vr_run *r, const char *name) {
  vr_run_record(r, "global photons", false, "integrator %s uses no photon map", name);
  vr_run_record(r, "caustic photons", false, "integrator %s uses no photon map", name);
}

void vr_integrator_photon_needs(const vr_camera_job *job, bool *global, bool *caustic) {
  const vr_scene_needs *nd = &job->needs;
  *global = nd->diffuse && job->rs->s->settings.max_depth > 1 && job->lights_exist;
  *caustic = nd->specular && nd->diffuse && job->lights_exist;
}

vr_pass vr_integrator_pass(const vr_camera_job *job) {
  return (vr_pass){.rs = job->rs, .acc = job->acc, .spp = job->spp,
                   .max_depth = job->rs->s->settings.max_depth};
}

vr_status vr_integrator_camera(vr_camera_job *job, vr_pass *c, const vr_flow_ops *ops,
                               vr_error *err) {
  if (job->adaptive) return vr_adaptive_camera(job, c, ops, err);
  double t0 = vr_run_now();
  vr_status st;
  if (job->halves) {
    /* Two passes of spp / 2, each a whole block of the sampler
     * (resolve.c), the second's XYZ kept apart: two independent estimates
     * of the pixel, whose difference the denoiser reads as its noise. */
    int spp = c->spp;
    c->weight_spp = spp;
    c->spp = spp / 2;
    st = vr_camera_pass(job->run, c, ops, job->W, job->H, err);
    c->sample_offset = spp / 2;
    c->second_half = true;
    if (!st) st = vr_camera_pass(job->run, c, ops, job->W, job->H, err);
    c->spp = spp;
    c->weight_spp = 0;
    c->sample_offset = 0;
    c->second_half = false;
  } else {
    st = vr_camera_pass(job->run, c, ops, job->W, job->H, err);
  }
  job->seconds += vr_run_now() - t0;
  return st;
}
