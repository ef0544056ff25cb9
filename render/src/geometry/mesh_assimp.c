/* Mesh files through Assimp's C API.  Assimp triangulates polygons, bakes
 * the node transforms into the vertices and joins identical vertices; it is
 * not asked to generate normals (a mesh without normals is shaded flat by
 * the renderer) nor to drop degenerate triangles (geometry.c counts those,
 * so the user hears about them). */
#include "geometry/mesh_assimp.h"
#include "geometry/rad_read.h"
#include "vr/colour.h"
#include "vr/scene.h"

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include <assimp/GltfMaterial.h>
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/importerdesc.h>
#include <assimp/version.h>

void vr_mesh_data_free(vr_mesh_data *m) {
  if (!m) return;
  free(m->pos);
  free(m->nrm);
  free(m->uv);
  free(m->rgb);
  free(m->tris);
  free(m->tri_material);
  memset(m, 0, sizeof *m);
}

static bool file_opens(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return false;
  fclose(f);
  return true;
}

/* Whether path's name ends in ext (".obj"), any case. */
static bool has_ext(const char *path, const char *ext) {
  size_t n = strlen(path), e = strlen(ext);
  return n > e && !strcasecmp(path + n - e, ext);
}

static vr_status copy_scene(const struct aiScene *sc, const char *path, vr_mesh_data *out,
                            vr_error *err) {
  bool linear_colours = has_ext(path, ".gltf") || has_ext(path, ".glb"); /* glTF's are linear */
  size_t nverts = 0, ntris = 0;
  bool any_nrm = false, any_uv = false, any_rgb = false;
  for (unsigned i = 0; i < sc->mNumMeshes; i++) {
    const struct aiMesh *m = sc->mMeshes[i];
    size_t tri = 0;
    for (unsigned f = 0; f < m->mNumFaces; f++) tri += m->mFaces[f].mNumIndices == 3;
    if (tri == 0) continue; /* points or lines only */
    nverts += m->mNumVertices;
    ntris += tri;
    any_nrm |= m->mNormals != NULL;
    any_uv |= m->mTextureCoords[0] != NULL;
    any_rgb |= m->mColors[0] != NULL;
  }
  if (ntris == 0) return vr_error_set(err, VR_E_PARSE, "mesh '%s': no triangles", path);
  if (nverts >= UINT32_MAX || ntris >= UINT32_MAX / 3)
    return vr_error_set(err, VR_E_RANGE, "mesh '%s': %zu vertices, %zu triangles: too large",
                        path, nverts, ntris);
  out->pos = malloc(3 * nverts * sizeof *out->pos);
  out->nrm = any_nrm ? calloc(3 * nverts, sizeof *out->nrm) : NULL;
  out->uv = any_uv ? calloc(2 * nverts, sizeof *out->uv) : NULL;
  out->rgb = any_rgb ? malloc(3 * nverts) : NULL;
  if (out->rgb) memset(out->rgb, 255, 3 * nverts);
  out->tris = malloc(3 * ntris * sizeof *out->tris);
  out->tri_material = malloc(ntris * sizeof *out->tri_material);
  if (!out->pos || !out->tris || !out->tri_material || (any_nrm && !out->nrm) || (any_uv && !out->uv) ||
      (any_rgb && !out->rgb)) {
    vr_mesh_data_free(out);
    return vr_error_set(err, VR_E_NOMEM, "mesh '%s': out of memory", path);
  }
  size_t v = 0, t = 0;
  for (unsigned i = 0; i < sc->mNumMeshes; i++) {
    const struct aiMesh *m = sc->mMeshes[i];
    size_t tri = 0;
    for (unsigned f = 0; f < m->mNumFaces; f++) tri += m->mFaces[f].mNumIndices == 3;
    if (tri == 0) continue;
    for (unsigned k = 0; k < m->mNumVertices; k++) {
      out->pos[3 * (v + k) + 0] = m->mVertices[k].x;
      out->pos[3 * (v + k) + 1] = m->mVertices[k].y;
      out->pos[3 * (v + k) + 2] = m->mVertices[k].z;
      if (m->mNormals) {
        out->nrm[3 * (v + k) + 0] = m->mNormals[k].x;
        out->nrm[3 * (v + k) + 1] = m->mNormals[k].y;
        out->nrm[3 * (v + k) + 2] = m->mNormals[k].z;
      }
      if (m->mTextureCoords[0]) {
        out->uv[2 * (v + k) + 0] = m->mTextureCoords[0][k].x;
        out->uv[2 * (v + k) + 1] = m->mTextureCoords[0][k].y;
      }
      if (m->mColors[0]) {
        /* Assimp gives 8-bit colours as code / 255 (PLY's are sRGB-encoded
         * by convention: MeshLab, Blender); glTF's COLOR_0 is linear by its
         * specification, so encoded here.  Clamped, NaN as 0. */
        const float c[3] = {m->mColors[0][k].r, m->mColors[0][k].g, m->mColors[0][k].b};
        for (int a = 0; a < 3; a++) {
          double x = c[a] > 0 ? (c[a] < 1 ? c[a] : 1) : 0;
          if (linear_colours) x = vr_srgb_encode(x);
          out->rgb[3 * (v + k) + (size_t)a] = (uint8_t)lrint(x * 255);
        }
      }
    }
    for (unsigned f = 0; f < m->mNumFaces; f++) {
      const struct aiFace *face = &m->mFaces[f];
      if (face->mNumIndices != 3) continue;
      for (int c = 0; c < 3; c++) {
        if (face->mIndices[c] >= m->mNumVertices) {
          vr_mesh_data_free(out);
          return vr_error_set(err, VR_E_PARSE, "mesh '%s': a face refers to a missing vertex",
                              path);
        }
        out->tris[3 * t + (size_t)c] = (uint32_t)(v + face->mIndices[c]);
      }
      out->tri_material[t] = m->mMaterialIndex;
      t++;
    }
    v += m->mNumVertices;
  }
  out->nverts = nverts;
  out->ntris = ntris;
  return VR_OK;
}

/* Assimp 5.2's PLY reader loops forever on a header without end_header and
 * reads past the end of a truncated binary body (both seen with truncated
 * files), so a PLY file's header is checked here first: it must end, its
 * element counts must be numbers, and a binary body must be at least as
 * long as its fixed-size part (every list taken as empty). */
#define PLY_HEADER_MAX 65536

static size_t ply_type_size(const char *t) {
  static const struct {
    const char *name;
    size_t size;
  } types[] = {{"char", 1},   {"uchar", 1},   {"int8", 1},    {"uint8", 1},  {"short", 2},
               {"ushort", 2}, {"int16", 2},   {"uint16", 2},  {"int", 4},    {"uint", 4},
               {"int32", 4},  {"uint32", 4},  {"float", 4},   {"float32", 4}, {"double", 8},
               {"float64", 8}};
  for (size_t i = 0; i < sizeof types / sizeof *types; i++)
    if (strcmp(t, types[i].name) == 0) return types[i].size;
  return 0;
}

static vr_status ply_precheck(const char *path, vr_error *err) {
  FILE *f = fopen(path, "rb");
  if (!f) return VR_OK; /* Assimp reports it */
  char *buf = malloc(PLY_HEADER_MAX + 1);
  if (!buf) {
    fclose(f);
    return vr_error_set(err, VR_E_NOMEM, "mesh '%s': out of memory", path);
  }
  size_t n = fread(buf, 1, PLY_HEADER_MAX, f);
  long long file_size = -1;
  if (fseek(f, 0, SEEK_END) == 0) file_size = ftell(f);
  fclose(f);
  buf[n] = '\0';
  vr_status st = VR_OK;
  if (n < 4 || strncmp(buf, "ply", 3) != 0 || (buf[3] != '\n' && buf[3] != '\r')) goto done;
  char *end = strstr(buf, "\nend_header");
  if (!end) {
    st = vr_error_set(err, VR_E_PARSE, "mesh '%s': PLY header has no end_header line within "
                      "%d bytes (truncated file?)", path, PLY_HEADER_MAX);
    goto done;
  }
  char *body = strchr(end + 1, '\n');
  long long header_len = body ? (long long)(body + 1 - buf) : (long long)n;
  end[1] = '\0';
  bool binary = false;
  unsigned long long min_body = 0, count = 0, row = 0;
  long line = 1;
  for (char *save = NULL, *ln = strtok_r(buf, "\n", &save); ln; ln = strtok_r(NULL, "\n", &save)) {
    line++;
    char w[4][32] = {{0}};
    int k = sscanf(ln, "%31s %31s %31s %31s", w[0], w[1], w[2], w[3]);
    if (k >= 2 && strcmp(w[0], "format") == 0) {
      binary = strncmp(w[1], "binary", 6) == 0;
    } else if (k >= 1 && strcmp(w[0], "element") == 0) {
      min_body += count * row;
      char *e = NULL;
      count = k >= 3 ? strtoull(w[2], &e, 10) : 0;
      if (k < 3 || !e || *e || w[2][0] == '-' || count > (1ULL << 40)) {
        st = vr_error_set(err, VR_E_PARSE, "mesh '%s': PLY header: element '%s' has no valid "
                          "count", path, k >= 2 ? w[1] : "");
        goto done;
      }
      row = 0;
    } else if (k >= 2 && strcmp(w[0], "property") == 0) {
      row += ply_type_size(w[1]) ? ply_type_size(w[1])
                                 : strcmp(w[1], "list") == 0 && k >= 3 ? ply_type_size(w[2]) : 0;
    }
  }
  min_body += count * row;
  if (binary && file_size >= 0 && (unsigned long long)(file_size - header_len) < min_body)
    st = vr_error_set(err, VR_E_PARSE, "mesh '%s': PLY body has %lld bytes, its header needs at "
                      "least %llu (truncated file?)", path, file_size - header_len, min_body);
done:
  free(buf);
  return st;
}

/* Assimp's JoinIdenticalVertices merges a NaN vertex into another one, so
 * non-finite positions are looked for before joining. */
static vr_status check_finite(const struct aiScene *sc, const char *path, vr_error *err) {
  for (unsigned i = 0; i < sc->mNumMeshes; i++) {
    const struct aiMesh *m = sc->mMeshes[i];
    for (unsigned k = 0; k < m->mNumVertices; k++) {
      const struct aiVector3D *p = &m->mVertices[k];
      if (!isfinite(p->x) || !isfinite(p->y) || !isfinite(p->z))
        return vr_error_set(err, VR_E_RANGE, "mesh '%s': a vertex is not finite (%g, %g, %g)",
                            path, (double)p->x, (double)p->y, (double)p->z);
    }
  }
  return VR_OK;
}

/* The file through Assimp, triangulated, node transforms baked in. */
static vr_status import(const char *path, const struct aiScene **out, vr_error *err) {
  *out = NULL;
  if (!path || !*path) return vr_error_set(err, VR_E_ARG, "mesh: no file name");
  vr_status st = ply_precheck(path, err);
  if (st != VR_OK) return st;
  const struct aiScene *sc =
      aiImportFile(path, aiProcess_Triangulate | aiProcess_PreTransformVertices);
  if (!sc) {
    const char *why = aiGetErrorString();
    bool opens = file_opens(path);
    /* A format Assimp does not read: say which it does (a Radiance .rad
     * model is not one of them). */
    if (opens && why && strstr(why, "No suitable reader")) {
      char list[1400];
      size_t n = 0;
      list[0] = '\0';
      for (size_t i = 0; i < aiGetImportFormatCount() && n + 16 < sizeof list; i++) {
        const struct aiImporterDesc *d = aiGetImportFormatDescription(i);
        int w = d && d->mFileExtensions ? snprintf(list + n, sizeof list - n, "%s%s", n ? " " : "",
                                                  d->mFileExtensions)
                                        : 0;
        if (w > 0) n += (size_t)w < sizeof list - n ? (size_t)w : sizeof list - n - 1;
      }
      return vr_error_set(err, VR_E_PARSE,
                          "mesh '%s': Assimp %u.%u has no reader for it; the extensions it reads "
                          "are: %s",
                          path, aiGetVersionMajor(), aiGetVersionMinor(), list);
    }
    return vr_error_set(err, opens ? VR_E_PARSE : VR_E_IO, "mesh '%s': %s", path,
                        why && *why ? why : (opens ? "cannot be read" : "cannot be opened"));
  }
  *out = sc;
  return VR_OK;
}

/* The material names an OBJ file's mtllib files define (their newmtl
 * lines), each as "\nNAME\n" in one string (NULL if none or out of
 * memory): Assimp gives a usemtl name its own default colour when no .mtl
 * defines it, which must not pass for the file's.  The files are read
 * once, whatever the number of materials. */
static char *mtl_names(const char *obj) {
  FILE *f = fopen(obj, "r");
  if (!f) return NULL;
  const char *slash = strrchr(obj, '/');
  int dirlen = slash ? (int)(slash - obj + 1) : 0;
  char line[1024], *names = NULL;
  size_t len = 0;
  while (fgets(line, sizeof line, f)) {
    char *p = line;
    while (*p == ' ' || *p == '\t') p++;
    if (strncmp(p, "mtllib", 6) || (p[6] != ' ' && p[6] != '\t')) continue;
    for (char *save = NULL, *lib = strtok_r(p + 6, " \t\r\n", &save); lib;
         lib = strtok_r(NULL, " \t\r\n", &save)) {
      char mtl[4096];
      snprintf(mtl, sizeof mtl, "%.*s%s", dirlen, obj, lib);
      FILE *m = fopen(mtl, "r");
      if (!m) continue;
      char ml[1024];
      while (fgets(ml, sizeof ml, m)) {
        char *q = ml;
        while (*q == ' ' || *q == '\t') q++;
        if (strncmp(q, "newmtl", 6) || (q[6] != ' ' && q[6] != '\t')) continue;
        q += 6;
        while (*q == ' ' || *q == '\t') q++;
        size_t n = strcspn(q, "\r\n");
        while (n && (q[n - 1] == ' ' || q[n - 1] == '\t')) n--;
        char *g = realloc(names, len + n + 3);
        if (!g) break;
        names = g;
        names[len++] = '\n';
        memcpy(names + len, q, n), len += n;
        names[len++] = '\n';
        names[len] = '\0';
      }
      fclose(m);
    }
  }
  fclose(f);
  return names;
}

static bool names_have(const char *names, const char *name) {
  if (!names) return false;
  char key[132];
  snprintf(key, sizeof key, "\n%s\n", name);
  return strstr(names, key) != NULL;
}

/* An embedded texture ("*N", or a name that matches an embedded texture's
 * file name): its compressed bytes (mHeight 0) copied into m.  Raw texel
 * arrays (mHeight > 0) are not a file: left to the caller's error (no
 * file of that name).  false when out of memory. */
static bool embedded(const struct aiScene *sc, const char *name, unsigned char **bytes,
                     size_t *len) {
  const struct aiTexture *t = NULL;
  if (name[0] == '*') {
    char *end;
    long k = strtol(name + 1, &end, 10);
    if (end != name + 1 && !*end && k >= 0 && (unsigned long)k < sc->mNumTextures)
      t = sc->mTextures[k];
  } else {
    for (unsigned k = 0; k < sc->mNumTextures && !t; k++)
      if (sc->mTextures[k]->mFilename.length && !strcmp(sc->mTextures[k]->mFilename.data, name))
        t = sc->mTextures[k];
  }
  if (!t || t->mHeight != 0 || !t->mWidth) return true;
  if (!(*bytes = malloc(t->mWidth))) return false;
  memcpy(*bytes, t->pcData, t->mWidth);
  *len = t->mWidth;
  return true;
}

/* A texture's file name without its surrounding blanks (an MTL line's
 * trailing space: tinyobjloader's issue 92); inner ones are kept. */
static void trimmed(const char *name, char out[256]) {
  while (*name == ' ' || *name == '\t') name++;
  int len = (int)strlen(name);
  while (len > 0 && (name[len - 1] == ' ' || name[len - 1] == '\t' || name[len - 1] == '\r')) len--;
  snprintf(out, 256, "%.*s", len < 255 ? len : 255, name);
}

/* The material's texture of the first of types[0..n) it has: its file
 * name, trimmed, into name ("" when none) and an embedded one's bytes.
 * false when out of memory. */
static bool texture_of(const struct aiScene *sc, const struct aiMaterial *am,
                       const enum aiTextureType *types, int n, char name[256],
                       unsigned char **bytes, size_t *len) {
  struct aiString tex;
  for (int k = 0; k < n; k++)
    if (aiGetMaterialTexture(am, types[k], 0, &tex, NULL, NULL, NULL, NULL, NULL, NULL) ==
        AI_SUCCESS) {
      trimmed(tex.data, name);
      return embedded(sc, name, bytes, len);
    }
  return true;
}

void vr_mesh_materials_free(vr_mesh_material *m, size_t n) {
  for (size_t i = 0; m && i < n; i++) free(m[i].texture_bytes), free(m[i].normal_bytes), free(m[i].mr_bytes), free(m[i].opacity_bytes);
  free(m);
}

vr_status vr_mesh_materials(const char *path, vr_mesh_material **out, size_t *n, vr_error *err) {
  *out = NULL, *n = 0;
  if (vr_rad_is(path)) {
    vr_rad_model rm;
    vr_status st = vr_rad_read(path, &rm, err);
    if (!st) st = vr_rad_mesh_materials(&rm, out, n, err);
    vr_rad_free(&rm);
    return st;
  }
  const struct aiScene *sc;
  vr_status st = import(path, &sc, err);
  if (st) return st;
  vr_mesh_material *m = calloc(sc->mNumMaterials ? sc->mNumMaterials : 1, sizeof *m);
  if (!m) {
    aiReleaseImport(sc);
    return vr_error_set(err, VR_E_NOMEM, "mesh '%s': out of memory", path);
  }
  bool obj = has_ext(path, ".obj"), ply = has_ext(path, ".ply");
  char *defined = obj ? mtl_names(path) : NULL;
  for (unsigned i = 0; i < sc->mNumMaterials; i++) {
    const struct aiMaterial *am = sc->mMaterials[i];
    struct aiString name;
    bool named = aiGetMaterialString(am, AI_MATKEY_NAME, &name) == AI_SUCCESS;
    if (named)
      snprintf(m[i].name, sizeof m[i].name, "%.127s", name.data);
    else
      snprintf(m[i].name, sizeof m[i].name, "material%u", i);
    /* Assimp's stand-ins: its DefaultMaterial, and the unnamed white one
     * its PLY reader makes for a file without a material element. */
    m[i].invented = !strcmp(m[i].name, AI_DEFAULT_MATERIAL_NAME) || (ply && !named);
    m[i].undefined = !m[i].invented && obj && !names_have(defined, m[i].name);
    m[i].rad_kind = -1;
    struct aiColor4D c;
    /* glTF's base colour first (Assimp gives it as the diffuse colour too,
     * but not every version), then the diffuse colour. */
    if (!m[i].invented && !m[i].undefined && (aiGetMaterialColor(am, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
                           aiGetMaterialColor(am, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS)) {
      m[i].has_colour = true;
      m[i].rgb[0] = c.r, m[i].rgb[1] = c.g, m[i].rgb[2] = c.b;
    }
    ai_real mf, rf, xf;
    m[i].clearcoat = aiGetMaterialFloatArray(am, AI_MATKEY_CLEARCOAT_FACTOR, &xf, NULL) == AI_SUCCESS ? xf : 0;
    m[i].transmission = aiGetMaterialFloatArray(am, AI_MATKEY_TRANSMISSION_FACTOR, &xf, NULL) == AI_SUCCESS ? xf : 0;
    m[i].metallic = aiGetMaterialFloatArray(am, AI_MATKEY_METALLIC_FACTOR, &mf, NULL) == AI_SUCCESS ? mf : NAN;
    m[i].roughness = aiGetMaterialFloatArray(am, AI_MATKEY_ROUGHNESS_FACTOR, &rf, NULL) == AI_SUCCESS ? rf : NAN;
    /* Assimp 5.2 keeps glTF's metallicRoughnessTexture as the first
     * "unknown" texture (AI_MATKEY_GLTF_PBRMETALLICROUGHNESS_METALLICROUGHNESS_TEXTURE),
     * later versions as the metalness and roughness textures; only glTF
     * files (which give a metallic factor) are asked, an unknown texture
     * of another format being anything. */
    static const enum aiTextureType BASE[] = {aiTextureType_BASE_COLOR, aiTextureType_DIFFUSE},
                                    MR[] = {aiTextureType_UNKNOWN, aiTextureType_METALNESS,
                                            aiTextureType_DIFFUSE_ROUGHNESS},
                                    NORMAL[] = {aiTextureType_NORMALS},
                                    OPACITY[] = {aiTextureType_OPACITY};
    if (!texture_of(sc, am, BASE, 2, m[i].texture, &m[i].texture_bytes, &m[i].texture_len) ||
        (isfinite(m[i].metallic) &&
         !texture_of(sc, am, MR, 3, m[i].mr, &m[i].mr_bytes, &m[i].mr_len)) ||
        !texture_of(sc, am, NORMAL, 1, m[i].normal, &m[i].normal_bytes, &m[i].normal_len) ||
        !texture_of(sc, am, OPACITY, 1, m[i].opacity, &m[i].opacity_bytes, &m[i].opacity_len)) {
      vr_mesh_materials_free(m, sc->mNumMaterials);
      aiReleaseImport(sc);
      return vr_error_set(err, VR_E_NOMEM, "mesh '%s': out of memory", path);
    }
    m[i].normal_scale = 1;
    ai_real sc_n;
    if (m[i].normal[0] &&
        aiGetMaterialFloatArray(am, "$tex.scale", aiTextureType_NORMALS, 0, &sc_n, NULL) ==
            AI_SUCCESS && sc_n >= 0 && sc_n <= 10)
      m[i].normal_scale = sc_n;
    struct aiString mode;
    m[i].alpha_cutoff = 0.5;
    if (aiGetMaterialString(am, AI_MATKEY_GLTF_ALPHAMODE, &mode) == AI_SUCCESS)
      m[i].alpha = !strcmp(mode.data, "MASK") ? VR_ALPHA_MASK : !strcmp(mode.data, "BLEND") ? VR_ALPHA_BLEND : VR_ALPHA_OFF;
    ai_real cut;
    if (aiGetMaterialFloatArray(am, AI_MATKEY_GLTF_ALPHACUTOFF, &cut, NULL) == AI_SUCCESS && cut >= 0 && cut <= 1)
      m[i].alpha_cutoff = cut;
  }
  for (unsigned i = 0; i < sc->mNumMeshes; i++) {
    const struct aiMesh *me = sc->mMeshes[i];
    size_t tri = 0;
    for (unsigned f = 0; f < me->mNumFaces; f++) tri += me->mFaces[f].mNumIndices == 3;
    if (me->mMaterialIndex < sc->mNumMaterials) {
      m[me->mMaterialIndex].triangles += tri;
      if (tri && me->mColors[0]) m[me->mMaterialIndex].vertex_colours = true;
    }
  }
  free(defined);
  *n = sc->mNumMaterials;
  *out = m;
  aiReleaseImport(sc);
  return VR_OK;
}

vr_status vr_mesh_read(const char *path, vr_mesh_data *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  if (vr_rad_is(path)) {
    /* A Radiance scene: its own reader (rad_read.c), not Assimp. */
    vr_rad_model rm;
    vr_status st = vr_rad_read(path, &rm, err);
    if (st) return st;
    *out = rm.mesh;
    memset(&rm.mesh, 0, sizeof rm.mesh);
    vr_rad_free(&rm);
    return VR_OK;
  }
  const struct aiScene *sc;
  vr_status st = import(path, &sc, err);
  if (st) return st;
  if ((st = check_finite(sc, path, err)) != VR_OK) {
    aiReleaseImport(sc);
    return st;
  }
  /* On failure Assimp has released the scene itself. */
  sc = aiApplyPostProcessing(sc, aiProcess_JoinIdenticalVertices);
  if (!sc) return vr_error_set(err, VR_E_PARSE, "mesh '%s': %s", path, aiGetErrorString());
  st = copy_scene(sc, path, out, err);
  aiReleaseImport(sc);
  return st;
}
