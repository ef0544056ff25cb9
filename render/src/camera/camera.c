/* The camera frame from the scene's camera line, and the registry of camera
 * models: one line per model, in the order of vr_camera_model. */
#include "camera/camera.h"

#include <math.h>
#include <string.h>

#include "vr/vec3.h"

static const vr_camera_ops *const MODELS[] = {
    [VR_CAM_PINHOLE] = &vr_camera_pinhole,
    [VR_CAM_THINLENS] = &vr_camera_thinlens,
    [VR_CAM_FISHEYE] = &vr_camera_fisheye,
};

const vr_camera_ops *vr_camera_model_ops(vr_camera_model model) { return MODELS[model]; }

void vr_camera_init(vr_camera *c, const vr_scene_camera *sc) {
  memset(c, 0, sizeof *c);
  c->sc = sc;
  c->ops = vr_camera_model_ops(sc->model);
  for (int a = 0; a < 3; a++) c->w[a] = sc->to[a] - sc->from[a];
  vr_normalize3(c->w);
  vr_cross3(c->w, sc->up, c->u);
  vr_normalize3(c->u);
  vr_cross3(c->u, c->w, c->v);
  memcpy(c->o, sc->from, sizeof c->o);
  c->tan_half = tan(0.5 * sc->fov_deg * M_PI / 180.0);
  c->W = sc->width, c->H = sc->height;
  c->aspect = (double)c->H / c->W;
  c->area = 4 * c->tan_half * c->tan_half * c->aspect;
  double R = sc->filter.radius > 0 ? sc->filter.radius : 0.5;
  c->margin = R > 0.5 ? R - 0.5 : 0;
  if (sc->model == VR_CAM_THINLENS && sc->aperture_m > 0) {
    c->lens_radius = sc->aperture_m;
    c->focus = sc->focus_m;
  }
}
