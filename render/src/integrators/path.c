/* The path tracer (render integrator=path): the reference.  Every vertex
 * with a non-delta lobe estimates direct light and the path goes on by
 * sampling the BSDF (paths.c), with Russian roulette from the fourth
 * vertex. */
#include "integrators/integrator.h"

static vr_status render(vr_camera_job *job, vr_error *err) {
  vr_integrator_no_photons(job->run, "path");
  vr_pass c = vr_integrator_pass(job);
  job->passes = 1;
  return vr_integrator_camera(job, &c, &vr_camera_path_ops, err);
}

const vr_integrator_ops vr_integrator_path = {.name = "path", .what = "path tracing",
                                              .render = render, .adaptive = true,
                                              .source_tallies = true};
