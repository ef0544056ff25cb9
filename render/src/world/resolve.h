/* Inside world/: what resolve.c and state_maps.c share. */
#ifndef VR_WORLD_RESOLVE_H
#define VR_WORLD_RESOLVE_H

#include "world/rscene.h"

/* Each cell's state maps, at the materials' own states. */
vr_status vr_rscene_cell_maps(vr_rscene *rs, vr_error *err);

#endif
