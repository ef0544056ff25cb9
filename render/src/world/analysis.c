/* What the scene's materials call for (world/analysis.h). */
#include "world/analysis.h"

vr_scene_needs vr_rscene_needs(const vr_rscene *rs) {
  vr_scene_needs n = {0};
  const vr_scene *s = rs->s;
  for (size_t i = 0; i < s->nobjects; i++) {
    const vr_rmaterial *m = &rs->mat[s->objects[i].material];
    unsigned l = vr_bsdf_lobes(m->bsdf);
    const char *name = s->materials[s->objects[i].material].name;
    if (l & VR_LOBE_DIFFUSE) n.diffuse = true;
    if (l & (VR_LOBE_SPECULAR_R | VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T)) {
      if (!n.specular) n.specular_example = name;
      n.specular = true;
    }
    if (m->photochromic) n.photochromic = true;
    if (vr_bsdf_is_chromogenic(m->bsdf)) n.chromogenic = true;
    if (vr_bsdf_dispersive(m->bsdf) && (l & (VR_LOBE_SPECULAR_T | VR_LOBE_GLOSSY_T))) {
      if (!n.dispersive) n.dispersive_example = name;
      n.dispersive = true;
    }
  }
  return n;
}
