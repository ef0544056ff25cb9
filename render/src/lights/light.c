/* The registry of light kinds (lights/kinds.def, one line each; the index
 * is the kind of a scene's light line, vr_scene_light.kind), and what every
 * kind shares: making a
 * light from its scene line and the disc far lights' photons start from.
 * The scene grammar finds the kinds here too (vr_scn_light_kind). */
#include <math.h>
#include <string.h>

#include "lights/kinds.h"
#include "lights/light.h"
#include "vr/vec3.h"

#define VR_LIGHT_KIND(ops) extern const vr_light_ops ops;
#include "lights/kinds.def"
#undef VR_LIGHT_KIND

static const vr_light_ops *const KINDS[] = {
#define VR_LIGHT_KIND(ops) &ops,
#include "lights/kinds.def"
#undef VR_LIGHT_KIND
};
enum { NKINDS = sizeof KINDS / sizeof *KINDS };

const vr_light_ops *vr_light_kind_ops(size_t kind) { return kind < NKINDS ? KINDS[kind] : NULL; }

int vr_light_kind_find(const char *name) {
  for (int k = 0; k < NKINDS; k++)
    if (!strcmp(KINDS[k]->name, name)) return k;
  return -1;
}

/* The grammar's view of the registry (scene/scene_parse.h). */
bool vr_scn_light_kind(size_t kind, vr_scn_light_syntax *out) {
  if (kind >= NKINDS) return false;
  out->name = KINDS[kind]->name;
  out->parse = KINDS[kind]->parse;
  out->unique = (KINDS[kind]->flags & VR_LF_UNIQUE) != 0;
  out->sun = (KINDS[kind]->flags & VR_LF_SUN) != 0;
  return true;
}

const char *vr_scene_light_spectrum(const vr_scene_light *l) {
  const vr_light_ops *o = vr_light_kind_ops((size_t)l->kind);
  return l->spectrum ? l->spectrum : o ? o->spectrum : NULL;
}

vr_status vr_light_init(vr_light *l, const vr_scene_light *sl, const vr_light_setup *u,
                        vr_error *err) {
  memset(l, 0, sizeof *l);
  l->ops = vr_light_kind_ops((size_t)sl->kind);
  memcpy(l->pos, sl->position, sizeof l->pos);
  vr_status st = vr_spd_resolve(&u->spd, sl->spectrum, l->ops->spectrum, &sl->loc, &l->spd, err);
  return st ? st : l->ops->resolve(l, sl, u, err);
}

void vr_light_fini(vr_light *l) {
  if (l->ops && l->ops->destroy) l->ops->destroy(l);
  vr_rspd_free(&l->spd);
}

void vr_light_disc_origin(const vr_light_setup *u, const double d[3], double u1, double u2,
                          double o[3]) {
  double t[3], b[3];
  vr_frame3(d, t, b);
  double R = u->radius, r = R * sqrt(u1), ph = 2 * M_PI * u2;
  for (int a = 0; a < 3; a++)
    o[a] = u->centre[a] - 2 * R * d[a] + r * (cos(ph) * t[a] + sin(ph) * b[a]);
}
