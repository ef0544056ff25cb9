/* The materials' textures (world/rscene.h): loaded once per file (models
 * share a file material's texture between the objects of every mesh line
 * that names the file), with their memory and loading time kept for the
 * report, and read at hits. */
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "textures/texture.h"
#include "vr/matdb.h"
#include "world/resolve.h"

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* What material i's texture is read from: a file or embedded image of the
 * scene, or the database material's spectral texture; NULL if none. */
static const char *source_of(const vr_rscene *rs, size_t i, const char **sha, bool *spectral,
                             const vr_scene_material **sm_out) {
  const vr_scene_material *sm = &rs->s->materials[i];
  *sm_out = sm, *sha = NULL, *spectral = false;
  if (sm->texture) return sm->texture;
  if (sm->source != VR_MATSRC_DB || sm->texture_off || !rs->mat[i].db) return NULL;
  const vr_property *tp = vr_material_property(rs->mat[i].db, "texture");
  if (!tp) return NULL;
  const vr_property *hp = vr_material_property(rs->mat[i].db, "texture_sha256");
  *sha = hp && hp->text ? hp->text : "";
  *spectral = true;
  return tp->text ? tp->text : "";
}

vr_status vr_rscene_textures(vr_rscene *rs, vr_error *err) {
  double t0 = now();
  const char **keys = calloc(rs->nmat + 1, sizeof *keys);
  rs->tex = calloc(rs->nmat + 1, sizeof *rs->tex);
  if (!keys || !rs->tex) {
    free(keys);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  vr_status st = VR_OK;
  for (size_t i = 0; i < rs->nmat && !st; i++) {
    const vr_scene_material *sm;
    const char *sha;
    bool spectral;
    const char *path = source_of(rs, i, &sha, &spectral, &sm);
    if (!path) continue;
    vr_rmaterial *rm = &rs->mat[i];
    rm->alpha = sm->alpha;
    rm->alpha_cutoff = sm->alpha_cutoff;
    rm->tile[0] = sm->tile[0], rm->tile[1] = sm->tile[1];
    for (size_t k = 0; k < rs->ntex && !rm->tex; k++)
      if (!strcmp(keys[k], path)) rm->tex = rs->tex[k];
    if (rm->tex) continue;
    vr_texture *t = NULL;
    if (spectral && !path[0])
      st = vr_error_set(err, VR_E_PARSE, "database material '%s' has a texture property without a file",
                        sm->db_name);
    else if (spectral && !sha[0])
      st = vr_error_set(err, VR_E_PARSE,
                        "database material '%s' records its texture '%s' without its SHA-256 "
                        "(texture_sha256): the file cannot be checked (save it again with "
                        "vr-rgb2spec --texture, or give texture=none)",
                        sm->db_name, path);
    else if (spectral)
      st = vr_texture_load_spectral(path, sha, &t, err);
    else if (sm->texture_bytes)
      st = vr_texture_load_rgb_memory(sm->texture_bytes, sm->texture_len, path,
                                      !sm->texture_linear, &t, err);
    else
      st = vr_texture_load_rgb(path, !sm->texture_linear, &t, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld:%ld: material '%s': ", rs->s->path, sm->loc.line, sm->loc.col,
                      sm->name);
      break;
    }
    keys[rs->ntex] = path;
    rs->tex[rs->ntex++] = t;
    rs->tex_bytes += vr_texture_bytes(t);
    rm->tex = t;
  }
  free(keys);
  rs->tex_seconds = now() - t0;
  return st;
}

static void tex_uv(const vr_rmaterial *m, const vr_hit *hit, double *u, double *v) {
  *u = hit->uv[0] * m->tile[0];
  *v = hit->uv[1] * m->tile[1];
}

bool vr_hit_texture(const vr_rscene *rs, const vr_hit *hit, double width, int nwl,
                    const double *nm, double *f) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!m->tex) return false;
  double u, v;
  tex_uv(m, hit, &u, &v);
  double tile = m->tile[0] > m->tile[1] ? m->tile[0] : m->tile[1];
  vr_texture_eval(m->tex, u, v, width * hit->uv_rate * tile, nwl, nm, f);
  return true;
}

bool vr_hit_cut_out(const vr_rscene *rs, const vr_hit *hit, double r) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!m->tex || m->alpha == VR_ALPHA_OFF) return false;
  double u, v;
  tex_uv(m, hit, &u, &v);
  double a = vr_texture_alpha(m->tex, u, v);
  return m->alpha == VR_ALPHA_MASK ? a < m->alpha_cutoff : r >= a;
}
