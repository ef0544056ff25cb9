/* Scene analysis (DESIGN §6.2): what the resolved scene's materials call
 * for, so that each pass is run only when needed, and said why. */
#ifndef VR_WORLD_ANALYSIS_H
#define VR_WORLD_ANALYSIS_H

#include <stdbool.h>

#include "world/rscene.h"

typedef struct vr_scene_needs {
  bool diffuse, specular, photochromic, dispersive, chromogenic;
  const char *specular_example, *dispersive_example; /* a material's name, for messages */
} vr_scene_needs;

vr_scene_needs vr_rscene_needs(const vr_rscene *rs);

#endif
