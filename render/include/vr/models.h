/* A scene's model files' own materials (docs/scene-format.md, "Materials
 * from the model file").  The parser (vr/scene.h) reads no model file; a
 * mesh line without material=, or with material.PATTERN=NAME options, is
 * left for this step, which reads the files' material lists and makes such
 * a line one object per material of its file that has faces. */
#ifndef VR_MODELS_H
#define VR_MODELS_H

#include "vr/error.h"
#include "vr/scene.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Expands the mesh lines that need it (a no-op for a scene without any):
 * each file material takes the first matching pattern's material, else the
 * line's material=, else a lambert reflector of the file's own colour as a
 * sigmoid spectrum (named FILE:MATERIAL, said once in s->notes).  Errors
 * name the scene file and the line: a file Assimp cannot read, a pattern
 * matching none of the file's materials (listing them), a file without
 * materials on a line without material=.  vr_render_scene refuses a scene
 * this has not been run on when it needs it. */
vr_status vr_scene_load_models(vr_scene *s, vr_error *err);

/* Whether s still has mesh lines for vr_scene_load_models. */
bool vr_scene_models_pending(const vr_scene *s);

#ifdef __cplusplus
}
#endif
#endif
