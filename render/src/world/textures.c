/* The materials' textures (world/rscene.h): loaded once per file (models
 * share a file material's texture between the objects of every mesh line
 * that names the file), in parallel, with their memory and loading time
 * kept for the report, and read at hits. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "textures/texture.h"
#include "vr/matdb.h"
#include "vr/rgb_table.h"
#include "vr/vec3.h"
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

/* One texture to load: the first material that names its source. */
typedef struct load_job {
  const vr_scene_material *sm;
  const char *path, *sha;
  bool spectral;
  int kind;              /* 0: base colour, 1: normal map, 2: metallic-roughness, 3: opacity
                            (the last three linear) */
  bool linear;           /* integer samples read as linear (colorspace=linear, normal maps) */
  vr_texture *t;
  vr_status st;
  vr_error err;
} load_job;

static void load_one(load_job *j) {
  const vr_scene_material *sm = j->sm;
  if (j->spectral && !j->path[0])
    j->st = vr_error_set(&j->err, VR_E_PARSE,
                         "database material '%s' has a texture property without a file",
                         sm->db_name);
  else if (j->spectral && !j->sha[0])
    j->st = vr_error_set(&j->err, VR_E_PARSE,
                         "database material '%s' records its texture '%s' without its SHA-256 "
                         "(texture_sha256): the file cannot be checked (save it again with "
                         "vr-rgb2spec --texture, or give texture=none)",
                         sm->db_name, j->path);
  else if (j->spectral)
    j->st = vr_texture_load_spectral(j->path, j->sha, &j->t, &j->err);
  else if (j->kind == 1 && sm->normal_bytes)
    j->st = vr_texture_load_rgb_memory(sm->normal_bytes, sm->normal_len, j->path, false, &j->t,
                                       &j->err);
  else if (j->kind == 2 && sm->mr_bytes)
    j->st = vr_texture_load_rgb_memory(sm->mr_bytes, sm->mr_len, j->path, false, &j->t, &j->err);
  else if (j->kind == 3 && sm->alpha_map_bytes)
    j->st = vr_texture_load_rgb_memory(sm->alpha_map_bytes, sm->alpha_map_len, j->path, false,
                                       &j->t, &j->err);
  else if (j->kind)
    j->st = vr_texture_load_rgb(j->path, false, &j->t, &j->err);
  else if (sm->texture_bytes)
    j->st = vr_texture_load_rgb_memory(sm->texture_bytes, sm->texture_len, j->path,
                                       !sm->texture_linear, &j->t, &j->err);
  else
    j->st = vr_texture_load_rgb(j->path, !sm->texture_linear, &j->t, &j->err);
}

typedef struct loader {
  load_job *jobs;
  size_t n;
  atomic_size_t next;
} loader;

static void *load_worker(void *arg) {
  loader *l = arg;
  for (size_t k; (k = atomic_fetch_add(&l->next, 1)) < l->n;) load_one(&l->jobs[k]);
  return NULL;
}

vr_status vr_rscene_textures(vr_rscene *rs, int threads, vr_error *err) {
  double t0 = now();
  load_job *jobs = calloc(4 * rs->nmat + 1, sizeof *jobs);
  /* [4i]: texture, [4i+1]: normal map, [4i+2]: metallic-roughness, [4i+3]: opacity */
  size_t *job_of = calloc(4 * rs->nmat + 1, sizeof *job_of);
  rs->tex = calloc(4 * rs->nmat + 1, sizeof *rs->tex);
  if (!jobs || !job_of || !rs->tex) {
    free(jobs), free(job_of);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  /* The distinct sources, each loaded once. */
  size_t n = 0;
  for (size_t i = 0; i < rs->nmat; i++) {
    const vr_scene_material *sm;
    const char *sha;
    bool spectral;
    const char *path = source_of(rs, i, &sha, &spectral, &sm);
    job_of[4 * i] = job_of[4 * i + 1] = job_of[4 * i + 2] = job_of[4 * i + 3] = (size_t)-1;
    vr_rmaterial *rm = &rs->mat[i];
    rm->alpha = sm->alpha;
    rm->alpha_cutoff = sm->alpha_cutoff;
    rm->tile[0] = sm->tile[0], rm->tile[1] = sm->tile[1];
    rm->nscale = sm->normal_scale;
    rm->vcol = sm->vertex_colours;
    if (rm->vcol && !rs->rgb_table) {
      vr_error e = {0};
      if (!(rs->rgb_table = vr_rgb_table_get(&e))) {
        free(jobs), free(job_of);
        if (err) *err = e;
        return e.status ? e.status : VR_E_NOMEM;
      }
    }
    for (int kind = 0; kind < 4; kind++) {
      const char *p = kind == 3 ? sm->alpha_map : kind == 2 ? sm->mr_map : kind ? sm->normal_map : path;
      if (!p) continue;
      size_t k = 0;
      bool spec = !kind && spectral, linear = kind || sm->texture_linear;
      /* The same file decoded the same way (kind, colour space) is shared. */
      while (k < n && (strcmp(jobs[k].path, p) || jobs[k].kind != kind ||
                       jobs[k].spectral != spec || jobs[k].linear != linear))
        k++;
      if (k == n)
        jobs[n++] = (load_job){.sm = sm, .path = p, .sha = kind ? NULL : sha, .spectral = spec,
                               .kind = kind, .linear = linear};
      job_of[4 * i + (size_t)kind] = k;
    }
  }
  /* Decoded in parallel (the RGB-to-spectrum table is built once, by
   * whichever gets there first). */
  loader l = {jobs, n, 0};
  int nt = threads > 1 ? threads : 1;
  if ((size_t)nt > n) nt = (int)n;
  pthread_t th[64];
  int started = 0;
  for (; started < nt - 1 && started < 64; started++)
    if (pthread_create(&th[started], NULL, load_worker, &l)) break;
  load_worker(&l);
  for (int k = 0; k < started; k++) pthread_join(th[k], NULL);
  vr_status st = VR_OK;
  for (size_t k = 0; k < n; k++) {
    if (jobs[k].st && !st) {
      st = jobs[k].st;
      if (err) *err = jobs[k].err;
      const vr_scene_material *sm = jobs[k].sm;
      vr_error_prefix(err, "%s:%ld:%ld: material '%s': ", rs->s->path, sm->loc.line, sm->loc.col,
                      sm->name);
    }
    if (jobs[k].t) {
      rs->tex[rs->ntex++] = jobs[k].t;
      rs->tex_bytes += vr_texture_bytes(jobs[k].t);
    }
  }
  if (!st)
    for (size_t i = 0; i < rs->nmat; i++) {
      if (job_of[4 * i] != (size_t)-1) rs->mat[i].tex = jobs[job_of[4 * i]].t;
      if (job_of[4 * i + 1] != (size_t)-1) rs->mat[i].nmap = jobs[job_of[4 * i + 1]].t;
      if (job_of[4 * i + 2] != (size_t)-1) rs->mat[i].mrmap = jobs[job_of[4 * i + 2]].t;
      if (job_of[4 * i + 3] != (size_t)-1) rs->mat[i].amap = jobs[job_of[4 * i + 3]].t;
    }
  free(jobs);
  free(job_of);
  rs->tex_seconds = now() - t0;
  return st;
}

/* A sphere's v runs from its +z pole down (the state maps' convention);
 * textures have v up, so the image's top is at the +z pole. */
static void tex_uv(const vr_rmaterial *m, const vr_hit *hit, double *u, double *v) {
  *u = hit->uv[0] * m->tile[0];
  *v = (hit->sphere ? 1 - hit->uv[1] : hit->uv[1]) * m->tile[1];
}

/* The hit's vertex colours as a reflectance factor (1 without them). */
static bool vertex_colour(const vr_rscene *rs, const vr_rmaterial *m, const vr_hit *hit, int nwl,
                          const double *nm, double *f) {
  if (!m->vcol || !hit->has_rgb) return false;
  float in[3] = {(float)hit->rgb[0], (float)hit->rgb[1], (float)hit->rgb[2]}, c[3];
  vr_rgb_table_lookup(rs->rgb_table, in, c);
  for (int k = 0; k < nwl; k++) f[k] = vr_rgb_coef_eval(c, nm[k]);
  return true;
}

bool vr_hit_texture(const vr_rscene *rs, const vr_hit *hit, double width, int nwl,
                    const double *nm, double *f) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!m->tex) return vertex_colour(rs, m, hit, nwl, nm, f);
  double u, v;
  tex_uv(m, hit, &u, &v);
  double tile = m->tile[0] > m->tile[1] ? m->tile[0] : m->tile[1];
  vr_texture_eval(m->tex, u, v, width * hit->uv_rate * tile, nwl, nm, f);
  return true;
}

bool vr_hit_pbr(const vr_rscene *rs, const vr_hit *hit, double width, int nwl, const double *nm,
                vr_bsdf_point *pt) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!vr_bsdf_is_pbr(m->bsdf)) return false;
  *pt = vr_bsdf_point_plain();
  if (!m->tex && !m->mrmap && !(m->vcol && hit->has_rgb)) return true;
  double u, v;
  tex_uv(m, hit, &u, &v);
  double tile = m->tile[0] > m->tile[1] ? m->tile[0] : m->tile[1];
  double w = width * hit->uv_rate * tile;
  if (m->tex) {
    vr_texture_eval(m->tex, u, v, w, nwl, nm, pt->base);
    pt->has_base = true;
  }
  /* glTF's COLOR_0 multiplies the base colour (and its texture). */
  double vc[VR_BSDF_MAX_WAVELENGTHS];
  if (vertex_colour(rs, m, hit, nwl, nm, vc)) {
    for (int k = 0; k < nwl; k++) pt->base[k] = pt->has_base ? pt->base[k] * vc[k] : vc[k];
    pt->has_base = true;
  }
  if (pt->has_base) {
    double sum = 0;
    for (int k = 0; k < nwl; k++) sum += pt->base[k];
    pt->base_mean = nwl > 0 ? sum / nwl : 0;
  }
  if (m->mrmap) {
    /* glTF: roughness in green, metallic in blue, times the factors. */
    double rgb[3];
    vr_texture_rgb(m->mrmap, u, v, w, rgb);
    const vr_scene_material *sm = &rs->s->materials[rs->obj[hit->object].material];
    pt->roughness = rgb[1] * sm->pbr_roughness;
    pt->metallic = rgb[2] * sm->metallic;
  }
  return true;
}

bool vr_hit_normal_map(const vr_rscene *rs, const vr_hit *hit, double width, double ns[3]) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!m->nmap) return false;
  /* The tangent frame: T along dp/du made perpendicular to the shading
   * normal, B = N x T turned towards dp/dv (a mirrored mapping). */
  const double *N = hit->ns;
  double d = vr_dot3(hit->dpdu, N), T[3], B[3];
  for (int a = 0; a < 3; a++) T[a] = hit->dpdu[a] - d * N[a];
  double tl = sqrt(vr_dot3(T, T));
  if (!(tl > 0) || !isfinite(tl)) return false;
  for (int a = 0; a < 3; a++) T[a] /= tl;
  B[0] = N[1] * T[2] - N[2] * T[1], B[1] = N[2] * T[0] - N[0] * T[2], B[2] = N[0] * T[1] - N[1] * T[0];
  if (vr_dot3(B, hit->dpdv) < 0)
    for (int a = 0; a < 3; a++) B[a] = -B[a];
  double u, v, rgb[3];
  tex_uv(m, hit, &u, &v);
  double tile = m->tile[0] > m->tile[1] ? m->tile[0] : m->tile[1];
  vr_texture_rgb(m->nmap, u, v, width * hit->uv_rate * tile, rgb);
  double x = (2 * rgb[0] - 1) * m->nscale, y = (2 * rgb[1] - 1) * m->nscale, z = 2 * rgb[2] - 1;
  double n[3], l = 0;
  for (int a = 0; a < 3; a++) {
    n[a] = x * T[a] + y * B[a] + z * N[a];
    l += n[a] * n[a];
  }
  l = sqrt(l);
  if (!(l > 0)) return false;
  for (int a = 0; a < 3; a++) n[a] /= l;
  /* A normal the map turns through the surface is not used. */
  if (vr_dot3(n, hit->ng) * vr_dot3(N, hit->ng) <= 0) return false;
  memcpy(ns, n, sizeof n);
  return true;
}

bool vr_hit_cut_out(const vr_rscene *rs, const vr_hit *hit, double r) {
  const vr_rmaterial *m = &rs->mat[rs->obj[hit->object].material];
  if (!vr_rmaterial_cuts(m)) return false;
  double u, v;
  tex_uv(m, hit, &u, &v);
  double a;
  if (m->amap && vr_texture_has_alpha(m->amap)) {
    a = vr_texture_alpha(m->amap, u, v);
  } else if (m->amap) {
    /* A grey opacity map: its value (the full-size level, as alpha). */
    double rgb[3];
    vr_texture_rgb(m->amap, u, v, 0, rgb);
    a = rgb[0];
  } else {
    a = vr_texture_alpha(m->tex, u, v);
  }
  return m->alpha == VR_ALPHA_MASK ? a < m->alpha_cutoff : r >= a;
}
