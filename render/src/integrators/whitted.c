/* Ray tracing with shadow rays (render integrator=whitted): the paper's
 * local illumination.  A camera path follows mirrors and refractions and
 * ends at its first vertex with a diffuse lobe, where it takes the direct
 * light of every light, emitter and the sky (paths.c); no interreflection. */
#include "integrators/integrator.h"

static bool at_diffuse(vr_pass *c, vr_flow_worker *w, vr_payload *p, const vr_hit *hit,
                       const vr_surface *se, const double wo[3]) {
  (void)c, (void)w, (void)hit, (void)se, (void)wo;
  return p->target == VR_TARGET_PIXEL;
}

static vr_status render(vr_camera_job *job, vr_error *err) {
  vr_integrator_no_photons(job->run, "whitted");
  vr_pass c = vr_integrator_pass(job);
  c.at_diffuse = at_diffuse;
  job->passes = 1;
  return vr_integrator_camera(job, &c, &vr_camera_path_ops, err);
}

const vr_integrator_ops vr_integrator_whitted = {
    .name = "whitted", .what = "ray tracing with shadow rays", .render = render, .adaptive = true};
