/* What the fisheye model shares with the glare code (daylight/glare.c). */
#ifndef VR_CAMERA_FISHEYE_H
#define VR_CAMERA_FISHEYE_H

#include "vr/scene.h"

/* A pixel's solid angle in front of the eye and its cosine-weighted solid
 * angle, over 8 x 8 points of its area. */
void vr_fisheye_pixel_omega(const vr_scene_camera *c, int x, int y, double *omega,
                            double *cos_omega);

#endif
