/* Camera models behind one interface: a model turns an image point into a
 * primary ray and, for light tracing (BDPT), a point of the scene back into
 * an image point with the density of the direction that joins them.  The
 * models are registered in camera.c, one line each, in the order of
 * vr_camera_model (vr/scene.h); adding one is a new file and a line there.
 *
 * Image points are in pixels from the top-left corner of the image; the
 * camera frame is u (right), v (up), w (forward), unit and orthogonal. */
#ifndef VR_CAMERA_H
#define VR_CAMERA_H

#include <stdbool.h>

#include "vr/error.h"
#include "vr/rng.h"
#include "vr/scene.h"

typedef struct vr_camera vr_camera;

typedef struct vr_camera_ops {
  const char *name; /* as in the scene's camera line */
  /* The primary ray through image point (px, py): its origin and unit
   * direction, the lens numbers drawn from key; false where the model sees
   * nothing (outside a fisheye's image circle). */
  bool (*generate)(const vr_camera *c, double px, double py, const vr_rng_key *key, double org[3],
                   double dir[3]);
  /* A point on the lens, uniform by area (the centre for a pinhole). */
  void (*sample_lens)(const vr_camera *c, const vr_rng_key *key, double p[3]);
  /* The image point seen from lens point `lens` towards y and cos(theta)
   * to the view axis; false behind the camera or outside the image widened
   * by the filter's margin.  NULL where light tracing is not written for
   * the model (fisheye). */
  bool (*raster)(const vr_camera *c, const double lens[3], const double y[3], double *px,
                 double *py, double *cos_theta);
  /* The density (solid angle) of the direction from `lens` towards y with
   * which generate() makes it. */
  double (*pdf_dir)(const vr_camera *c, const double lens[3], const double y[3]);
} vr_camera_ops;

struct vr_camera {
  const vr_camera_ops *ops;
  const vr_scene_camera *sc;
  double o[3], u[3], v[3], w[3];
  double tan_half;    /* tan(fov / 2), horizontal */
  double aspect;      /* H / W */
  double area;        /* the image plane's area at distance 1 along w */
  double lens_radius; /* thin lens: the aperture's radius (0: a pinhole) */
  double focus;       /* thin lens: distance to the plane of focus */
  double margin;      /* pixels beyond the image a wide pixel filter reaches from it */
  int W, H;
};

/* The camera of the scene's camera line (its resolution as it stands). */
void vr_camera_init(vr_camera *c, const vr_scene_camera *sc);

/* The model of a scene's camera line. */
const vr_camera_ops *vr_camera_model_ops(vr_camera_model model);

/* The models, one per vr_camera_model. */
extern const vr_camera_ops vr_camera_pinhole, vr_camera_thinlens, vr_camera_fisheye;

#endif
