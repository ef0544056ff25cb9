/* A model's own materials (vr/models.h).  A mesh line with
 * material.PATTERN=NAME options, or without material=, becomes one object
 * per material of its file that has triangles: the first PATTERN (shell
 * wildcards) that matches the file's material name gives the scene
 * material; else material= when the line has one; else a lambert reflector
 * made from the file's own colour (glTF base colour, MTL Kd) as a sigmoid
 * spectrum (vr/rgb_spectrum.h), with its glTF metallic-roughness when
 * the file gives one, which the user hears about once through
 * s->notes.  The geometry then takes each object's triangles of its file
 * material only (vr_scene_object.mesh_material). */
#include <errno.h>
#include <fnmatch.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "geometry/mesh_assimp.h"
#include "geometry/rad_read.h"
#include "vr/models.h"

static vr_status nomem(vr_error *err) { return vr_error_set(err, VR_E_NOMEM, "out of memory"); }

static vr_status add_note(vr_scene *s, const char *text, vr_error *err) {
  char **n = realloc(s->notes, (s->nnotes + 1) * sizeof *n);
  if (!n) return nomem(err);
  s->notes = n;
  if (!(n[s->nnotes] = strdup(text))) return nomem(err);
  s->nnotes++;
  return VR_OK;
}

static int material_index(const vr_scene *s, const char *name) {
  for (size_t j = 0; j < s->nmaterials; j++)
    if (!strcmp(s->materials[j].name, name)) return (int)j;
  return -1;
}

/* The file's name without its folder. */
static const char *base(const char *path) {
  const char *b = strrchr(path, '/');
  return b ? b + 1 : path;
}

static bool is_obj(const char *path) {
  size_t n = strlen(path);
  return n > 4 && !strcasecmp(path + n - 4, ".obj");
}

/* Where a file material's image is: its bytes when the model embeds it
 * (*path then names it MODEL#NAME for messages), else the file beside the
 * model (a Windows path's backslashes read as slashes), which must open. */
static vr_status locate(const vr_scene *s, const vr_scene_object *ob, const vr_mesh_material *mm,
                        const char *what, const char *name, const unsigned char *bytes,
                        size_t len, char **path, unsigned char **out_bytes, size_t *out_len,
                        vr_error *err) {
  char buf[1400];
  if (bytes) {
    if (!(*out_bytes = malloc(len))) return nomem(err);
    memcpy(*out_bytes, bytes, len);
    *out_len = len;
    snprintf(buf, sizeof buf, "%s#%s", ob->mesh_path, name);
    return (*path = strdup(buf)) ? VR_OK : nomem(err);
  }
  if (name[0] == '*')
    return vr_error_at(err, VR_E_PARSE, s->path, ob->loc.line, ob->loc.col,
                       "mesh '%s': material '%s': its %s '%s' is an embedded image the file does "
                       "not hold as a compressed image (no such index, or raw texels)",
                       base(ob->mesh_path), mm->name, what, name);
  const char *slash = strrchr(ob->mesh_path, '/');
  int dir = name[0] == '/' ? 0 : slash ? (int)(slash - ob->mesh_path + 1) : 0; /* absolute as is */
  snprintf(buf, sizeof buf, "%.*s%s", dir, ob->mesh_path, name);
  for (char *c = buf + dir; *c; c++)
    if (*c == '\\') *c = '/';
  if (!(*path = strdup(buf))) return nomem(err);
  FILE *f = fopen(*path, "rb");
  if (!f)
    return vr_error_at(err, VR_E_IO, s->path, ob->loc.line, ob->loc.col,
                       "mesh '%s': material '%s': cannot open its %s '%s': %s",
                       base(ob->mesh_path), mm->name, what, *path, strerror(errno));
  fclose(f);
  return VR_OK;
}

/* The colour factor of a textured file material as a spectrum (none: 1).
 * glTF: the base colour factor multiplies the texture (glTF 2.0 §3.9.2).
 * OBJ: the texture alone: the MTL specification multiplies map_Kd by Kd,
 * but exporters write Kd 0 or 0.8 beside a map and the renderers people
 * compare with (Blender's importer, pbrt-v4, Mitsuba) use the map alone. */
static vr_status factor(vr_scene *s, const vr_scene_object *ob, const vr_mesh_material *mm,
                        vr_scene_material *m, vr_error *err) {
  m->reflectance = 1;
  if (!mm->has_colour || is_obj(ob->mesh_path) ||
      (mm->rgb[0] == 1 && mm->rgb[1] == 1 && mm->rgb[2] == 1))
    return VR_OK;
  double rgb[3];
  for (int k = 0; k < 3; k++) rgb[k] = isfinite(mm->rgb[k]) ? fmin(fmax(mm->rgb[k], 0), 1) : 0;
  vr_error e = {0};
  if (!(m->reflectance_spectrum = vr_scene_colour_spectrum(rgb, &e)))
    return vr_error_at(err, e.status, s->path, ob->loc.line, ob->loc.col,
                       "mesh '%s': material '%s': %s", base(ob->mesh_path), mm->name, e.message);
  return VR_OK;
}

/* A glTF material's metallic-roughness (the file gives a metallic factor):
 * the pbr BRDF with its factors (glTF's defaults, 1 and 1, where one is
 * missing) and its metallic-roughness texture; said in its note (extra). */
static vr_status metal_rough(vr_scene *s, const vr_scene_object *ob, const vr_mesh_material *mm,
                             vr_scene_material *m, char *extra, size_t cap, vr_error *err) {
  extra[0] = '\0';
  if (!isfinite(mm->metallic)) return VR_OK;
  m->pbr = true;
  m->metallic = fmin(fmax(mm->metallic, 0), 1);
  m->pbr_roughness = isfinite(mm->roughness) ? fmin(fmax(mm->roughness, 0), 1) : 1;
  if (mm->mr[0]) {
    vr_status st = locate(s, ob, mm, "metallic-roughness texture", mm->mr, mm->mr_bytes,
                          mm->mr_len, &m->mr_map, &m->mr_bytes, &m->mr_len, err);
    if (st) return st;
  }
  int n = snprintf(extra, cap, ", glTF metallic-roughness (metallic %g, roughness %g%s)",
                   m->metallic, m->pbr_roughness,
                   mm->mr[0] ? ", times its metallic-roughness texture" : "");
  size_t k = n > 0 && (size_t)n < cap ? (size_t)n : cap - 1;
  if (mm->clearcoat > 0 || mm->transmission > 0)
    snprintf(extra + k, cap - k, "; its %s%s%s is not rendered (map it to a database %s with material.%s=)",
             mm->clearcoat > 0 ? "KHR_materials_clearcoat" : "",
             mm->clearcoat > 0 && mm->transmission > 0 ? " and " : "",
             mm->transmission > 0 ? "KHR_materials_transmission" : "",
             mm->transmission > 0 ? "glass" : "material", mm->name);
  return VR_OK;
}

/* A file material with a base-colour texture: the texture (times its
 * colour factor in glTF, see factor()).  The texture's file is looked for
 * beside the model (a Windows path's backslashes read as slashes), or is
 * the bytes embedded in it. */
static vr_status textured(vr_scene *s, const vr_scene_object *ob, const vr_mesh_material *mm,
                          vr_scene_material *m, vr_error *err) {
  vr_status st = factor(s, ob, mm, m, err);
  if (st) return st;
  m->alpha = m->alpha_map ? VR_ALPHA_MASK : mm->alpha;
  m->alpha_cutoff = mm->alpha_cutoff;
  if ((st = locate(s, ob, mm, "texture", mm->texture, mm->texture_bytes, mm->texture_len,
                    &m->texture, &m->texture_bytes, &m->texture_len, err)))
    return st;
  char note[1400];
  char extra[300];
  if ((st = metal_rough(s, ob, mm, m, extra, sizeof extra, err))) return st;
  snprintf(note, sizeof note,
           "mesh '%s': material '%s' (%zu triangles) is mapped to nothing: its texture '%s'%s%s "
           "as spectra%s, material '%s'%s",
           base(ob->mesh_path), mm->name, mm->triangles, mm->texture,
           m->reflectance_spectrum ? " times its colour" : "",
           m->alpha_map ? ", cut out where its map_d is below 0.5" : mm->alpha == VR_ALPHA_MASK ? ", cut out by its alpha" : mm->alpha == VR_ALPHA_BLEND ? ", see-through by its alpha" : "",
           m->normal_map ? ", with its normal map" : "", m->name, extra);
  return add_note(s, note, err);
}

/* The scene material for the file's material mm of object i; made from
 * its colour when nothing maps it. */
static vr_status material_for(vr_scene *s, size_t i, const vr_scene_object *ob,
                              const vr_mesh_material *mm, int *out, bool *from_file,
                              vr_error *err) {
  *from_file = false;
  for (size_t k = 0; k < s->nmesh_maps; k++) {
    const vr_scene_mesh_map *map = &s->mesh_maps[k];
    if (map->object != i || fnmatch(map->pattern, mm->name, 0)) continue;
    *out = map->material;
    return VR_OK;
  }
  if (ob->material >= 0) {
    *out = ob->material;
    return VR_OK;
  }
  /* From the file: one scene material per file material, shared by every
   * line that names the file. */
  char name[512];
  snprintf(name, sizeof name, "%s:%s", base(ob->mesh_path), mm->name);
  *from_file = true;
  if ((*out = material_index(s, name)) >= 0) return VR_OK;
  vr_scene_material *g = realloc(s->materials, (s->nmaterials + 1) * sizeof *g);
  if (!g) return nomem(err);
  s->materials = g;
  vr_scene_material *m = &g[s->nmaterials++];
  memset(m, 0, sizeof *m);
  if (!(m->name = strdup(name))) return nomem(err);
  m->loc = ob->loc;
  m->source = VR_MATSRC_LAMBERT_CONST;
  m->roughness = m->thickness_m = m->state = m->charge_mC_cm2 = m->temperature_K = NAN;
  m->alpha_cutoff = 0.5, m->tile[0] = m->tile[1] = 1, m->normal_scale = 1;
  *out = (int)(s->nmaterials - 1);
  if (mm->rad_kind >= 0) {
    /* A Radiance material: its kind decides (rad_materials.c); the
     * emission goes to the objects (expand). */
    char what[600], note[4000];
    vr_error e = {0};
    vr_status st = vr_rad_scene_material(mm, ob, m, what, sizeof what, &e);
    if (st)
      return vr_error_at(err, st, s->path, ob->loc.line, ob->loc.col, "mesh '%s': %s",
                         base(ob->mesh_path), e.message);
    snprintf(note, sizeof note, "mesh '%s': Radiance material '%s' (%zu triangles, %s): %s",
             base(ob->mesh_path), mm->name, mm->triangles, mm->rad_where, what);
    return add_note(s, note, err);
  }
  if (mm->normal[0]) {
    vr_status st = locate(s, ob, mm, "normal map", mm->normal, mm->normal_bytes, mm->normal_len,
                          &m->normal_map, &m->normal_bytes, &m->normal_len, err);
    if (st) return st;
    m->normal_scale = mm->normal_scale;
  }
  if (mm->opacity[0]) {
    vr_status st = locate(s, ob, mm, "opacity map (map_d)", mm->opacity, mm->opacity_bytes,
                          mm->opacity_len, &m->alpha_map, &m->alpha_map_bytes, &m->alpha_map_len,
                          err);
    if (st) return st;
    m->alpha = VR_ALPHA_MASK;
  }
  char note[1600];
  if (mm->texture[0]) return textured(s, ob, mm, m, err);
  /* Vertex colours multiply the material's colour (glTF's COLOR_0 its
   * base colour; a PLY file's stand alone: Assimp's stand-in is white). */
  m->vertex_colours = mm->vertex_colours;
  const char *vc = mm->vertex_colours ? " times its vertex colours" : "";
  if (mm->invented && mm->vertex_colours) {
    m->reflectance = 1;
    snprintf(note, sizeof note,
             "mesh '%s' has no materials of its own: its vertex colours as spectra, material '%s' "
             "(%zu triangles)",
             base(ob->mesh_path), name, mm->triangles);
    return add_note(s, note, err);
  }
  if (!mm->has_colour) {
    m->reflectance = 0.5;
    snprintf(note, sizeof note,
             "mesh '%s': material '%s' (%zu triangles) is mapped to nothing and has no colour%s: "
             "grey 0.5%s (map it with material.%s=NAME)",
             base(ob->mesh_path), mm->name, mm->triangles,
             mm->undefined ? " (no newmtl of the .mtl files its mtllib lines name defines it)" : "",
             vc, mm->name);
    return add_note(s, note, err);
  }
  double rgb[3];
  bool clipped = false;
  for (int k = 0; k < 3; k++) {
    rgb[k] = isfinite(mm->rgb[k]) ? fmin(fmax(mm->rgb[k], 0), 1) : 0;
    clipped |= rgb[k] != mm->rgb[k];
  }
  vr_error e = {0};
  if (!(m->reflectance_spectrum = vr_scene_colour_spectrum(rgb, &e)))
    return vr_error_at(err, e.status, s->path, ob->loc.line, ob->loc.col,
                       "mesh '%s': material '%s': %s", base(ob->mesh_path), mm->name, e.message);
  char extra[300];
  vr_status st = metal_rough(s, ob, mm, m, extra, sizeof extra, err);
  if (st) return st;
  snprintf(note, sizeof note,
           "mesh '%s': material '%s' (%zu triangles) is mapped to nothing: its colour "
           "(linear %.3g, %.3g, %.3g%s)%s as a spectrum%s, material '%s'%s",
           base(ob->mesh_path), mm->name, mm->triangles, rgb[0], rgb[1], rgb[2],
           clipped ? ", clipped to [0, 1]" : "", vc,
           m->alpha_map ? ", cut out where its map_d is below 0.5" : "", name, extra);
  return add_note(s, note, err);
}

/* A Radiance model's coinciding polygons, said once (the three that
 * share the most, and how many pairs in all). */
static vr_status overlap_note(vr_scene *s, const vr_scene_object *ob, const vr_rad_model *rm,
                              vr_error *err) {
  vr_rad_overlap *o;
  size_t n;
  vr_status st = vr_rad_overlaps(rm, &o, &n, err);
  if (st || !n) return st;
  char note[4000];
  int len = snprintf(note, sizeof note,
                     "mesh '%s': %zu pair%s of polygons coincide (one plane, shared area): a "
                     "renderer sees either surface there, and Radiance need not pick the same:",
                     base(ob->mesh_path), n, n == 1 ? "" : "s");
  for (size_t k = 0; k < n && k < 3 && len > 0 && (size_t)len < sizeof note; k++) {
    const vr_rad_poly *a = &rm->polys[o[k].a], *b = &rm->polys[o[k].b];
    len += snprintf(note + len, sizeof note - (size_t)len, "%s '%s' (%s) and '%s' (%s) over %.4g m2",
                    k ? ";" : "", a->id, a->where, b->id, b->where, o[k].area);
  }
  if (n > 3 && len > 0 && (size_t)len < sizeof note)
    snprintf(note + len, sizeof note - (size_t)len, "; ...");
  free(o);
  return add_note(s, note, err);
}

/* Object i as one object per used material of its file, appended to *out. */
static vr_status expand(vr_scene *s, size_t i, vr_scene_object **out, size_t *nout, vr_error *err) {
  vr_scene_object *ob = &s->objects[i];
  vr_mesh_material *mm = NULL;
  size_t nm = 0;
  vr_error e = {0};
  vr_status st;
  if (vr_rad_is(ob->mesh_path)) {
    /* A Radiance scene: its materials, its sun and what was left out. */
    vr_rad_model rm;
    if ((st = vr_rad_read(ob->mesh_path, &rm, &e)))
      return vr_error_at(err, st, s->path, ob->loc.line, ob->loc.col, "%s", e.message);
    st = vr_rad_mesh_materials(&rm, &mm, &nm, &e);
    if (!st) st = vr_rad_add_sources(s, ob, &rm, &e);
    char note[1400];
    if (!st && (rm.illum_dropped || rm.degenerate || rm.nsrc)) {
      snprintf(note, sizeof note,
               "mesh '%s' (%zu file%s): %zu illum surface%s without an alternate material left out "
               "(invisible in Radiance), %zu polygon%s of no area skipped, %zu distant source%s "
               "as the sun",
               base(ob->mesh_path), rm.files, rm.files == 1 ? "" : "s", rm.illum_dropped,
               rm.illum_dropped == 1 ? "" : "s", rm.degenerate, rm.degenerate == 1 ? "" : "s",
               rm.nsrc, rm.nsrc == 1 ? "" : "s");
      st = add_note(s, note, &e);
    }
    if (!st) st = overlap_note(s, ob, &rm, &e);
    vr_rad_free(&rm);
    if (st) {
      vr_mesh_materials_free(mm, nm);
      return vr_error_at(err, st, s->path, ob->loc.line, ob->loc.col, "%s", e.message);
    }
  } else if ((st = vr_mesh_materials(ob->mesh_path, &mm, &nm, &e))) {
    return vr_error_at(err, st, s->path, ob->loc.line, ob->loc.col, "%s", e.message);
  }
  size_t used = 0;
  for (size_t k = 0; k < nm; k++)
    used += mm[k].triangles > 0 && (!mm[k].invented || mm[k].vertex_colours);
  if (!used && ob->material < 0) {
    vr_mesh_materials_free(mm, nm);
    return vr_error_at(err, VR_E_PARSE, s->path, ob->loc.line, ob->loc.col,
                       "mesh '%s' has no materials of its own: give material=NAME",
                       base(ob->mesh_path));
  }
  /* Every pattern must name some material of the file. */
  for (size_t k = 0; k < s->nmesh_maps; k++) {
    const vr_scene_mesh_map *map = &s->mesh_maps[k];
    if (map->object != i) continue;
    bool any = false;
    for (size_t j = 0; j < nm && !any; j++) any = mm[j].triangles && !fnmatch(map->pattern, mm[j].name, 0);
    if (any) continue;
    char list[512] = "";
    size_t len = 0;
    for (size_t j = 0; j < nm && len + 4 < sizeof list; j++)
      if (mm[j].triangles) {
        int w = snprintf(list + len, sizeof list - len, "%s%s", len ? ", " : "", mm[j].name);
        if (w < 0 || (size_t)w >= sizeof list - len) break;
        len += (size_t)w;
      }
    vr_mesh_materials_free(mm, nm);
    if (map->file)
      return vr_error_at(err, VR_E_PARSE, map->file, map->loc.line, map->loc.col,
                         "'%s' matches no material of '%s' (its materials: %s)", map->pattern,
                         base(ob->mesh_path), len ? list : "none");
    return vr_error_at(err, VR_E_PARSE, s->path, map->loc.line, map->loc.col,
                       "material.%s= matches no material of '%s' (its materials: %s)", map->pattern,
                       base(ob->mesh_path), len ? list : "none");
  }
  for (size_t k = 0; k < nm && !st; k++) {
    if (!mm[k].triangles) continue;
    int mat;
    bool from_file;
    if ((st = material_for(s, i, ob, &mm[k], &mat, &from_file, err))) break;
    vr_scene_object *n = realloc(*out, (*nout + 1) * sizeof *n);
    if (!n) {
      st = nomem(err);
      break;
    }
    *out = n;
    vr_scene_object *c = &n[(*nout)++];
    *c = *ob;
    c->mesh_material = (int)k;
    c->material = mat;
    c->vertex_colours = s->materials[mat].vertex_colours;
    c->name = c->emission_spectrum = NULL;
    c->mesh_path = strdup(ob->mesh_path);
    char label[512];
    snprintf(label, sizeof label, "%s:%s", ob->name ? ob->name : base(ob->mesh_path), mm[k].name);
    c->name = strdup(label);
    if (ob->emission_spectrum) c->emission_spectrum = strdup(ob->emission_spectrum);
    if (!c->mesh_path || !c->name || (ob->emission_spectrum && !c->emission_spectrum)) st = nomem(err);
    if (!st && from_file && (mm[k].rad_kind == VR_RAD_LIGHT || mm[k].rad_kind == VR_RAD_GLOW)) {
      /* A Radiance light or glow emits (the mesh line's own emission=
       * gives way to it). */
      char *es = NULL;
      vr_error e2 = {0};
      if ((st = vr_rad_emission(&mm[k], &c->emission, &es, &e2)))
        st = vr_error_at(err, st, s->path, ob->loc.line, ob->loc.col, "%s", e2.message);
      free(c->emission_spectrum);
      c->emission_spectrum = es;
    }
  }
  vr_mesh_materials_free(mm, nm);
  return st;
}

static bool needs(const vr_scene *s, size_t i) {
  const vr_scene_object *ob = &s->objects[i];
  if (ob->shape != VR_SHAPE_MESH) return false;
  /* A Radiance scene always: its sources become the sun whatever its
   * materials become. */
  if (ob->material < 0 || (ob->mesh_material < 0 && ob->mesh_path && vr_rad_is(ob->mesh_path)))
    return true;
  for (size_t k = 0; k < s->nmesh_maps; k++)
    if (s->mesh_maps[k].object == i) return true;
  return false;
}

bool vr_scene_models_pending(const vr_scene *s) {
  for (size_t i = 0; i < s->nobjects; i++)
    if (needs(s, i)) return true;
  return false;
}

vr_status vr_scene_load_models(vr_scene *s, vr_error *err) {
  if (!vr_scene_models_pending(s)) return VR_OK;
  vr_scene_object *out = NULL;
  size_t nout = 0;
  vr_status st = VR_OK;
  for (size_t i = 0; i < s->nobjects && !st; i++) {
    vr_scene_object *ob = &s->objects[i];
    if (!needs(s, i)) {
      vr_scene_object *n = realloc(out, (nout + 1) * sizeof *n);
      if (!n) {
        st = nomem(err);
        break;
      }
      out = n;
      out[nout++] = *ob;
      memset(ob, 0, sizeof *ob); /* moved */
      continue;
    }
    st = expand(s, i, &out, &nout, err);
  }
  /* The originals' strings: the moved ones were zeroed. */
  for (size_t i = 0; i < s->nobjects; i++) {
    free(s->objects[i].name);
    free(s->objects[i].mesh_path);
    free(s->objects[i].emission_spectrum);
  }
  free(s->objects);
  s->objects = out;
  s->nobjects = nout;
  /* The patterns are spent: the objects now say which material is theirs. */
  for (size_t k = 0; k < s->nmesh_maps; k++) free(s->mesh_maps[k].pattern), free(s->mesh_maps[k].file);
  free(s->mesh_maps);
  s->mesh_maps = NULL;
  s->nmesh_maps = 0;
  return st;
}
