/* Reading a mesh file (OBJ, PLY, glTF, ... whatever Assimp knows) into
 * plain arrays, for geometry.c.  Private to render/. */
#ifndef VR_MESH_ASSIMP_H
#define VR_MESH_ASSIMP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "vr/error.h"

/* One file's triangles, all its meshes joined in file order, node
 * transforms applied, in the file's own units and axes. */
typedef struct vr_mesh_data {
  size_t nverts;
  double *pos;     /* 3 per vertex */
  double *nrm;     /* 3 per vertex, NULL if no mesh of the file has normals;
                      (0,0,0) on the vertices of a mesh without them */
  double *uv;      /* 2 per vertex (first UV set), NULL if no mesh has one; 0 where absent */
  uint8_t *rgb;    /* 3 per vertex: the first colour set as 8-bit codes (a PLY file's
                      red, green, blue), NULL if no mesh has one; 255 where absent */
  size_t ntris;
  uint32_t *tris;  /* 3 per triangle, indices into the vertices */
  uint32_t *tri_material; /* per triangle: the index of its material in the file
                             (vr_mesh_materials' order) */
} vr_mesh_data;

/* A material of a model file, as the file gives it (OBJ/MTL newmtl,
 * glTF materials, ...). */
typedef struct vr_mesh_material {
  char name[128];      /* the file's name for it (Assimp's AI_MATKEY_NAME) */
  bool invented;       /* Assimp's DefaultMaterial for a file without materials:
                          not the file's (its colour is Assimp's, not the file's) */
  bool undefined;      /* OBJ: named by usemtl but defined by no newmtl of the .mtl
                          files its mtllib lines name (missing or incomplete):
                          Assimp's defaults stand in, so it has no colour here */
  bool has_colour;     /* the file gives a base colour (glTF baseColorFactor) or a
                          diffuse colour (MTL Kd) */
  double rgb[3];       /* that colour, linear (glTF's base colour is linear by
                          its specification; MTL's Kd is read as linear, as
                          Blender's and Assimp's importers do) */
  char texture[256];   /* its base-colour or diffuse texture's file as the file
                          names it (relative to the model's folder), or "" */
  unsigned char *texture_bytes; /* an embedded texture's file bytes (glTF data: URIs,
                          GLB buffers; "*N" names), else NULL; vr_mesh_materials_free */
  size_t texture_len;
  char normal[256];    /* its tangent-space normal map (glTF normalTexture, MTL norm), or "" */
  unsigned char *normal_bytes; /* an embedded normal map's bytes, else NULL */
  size_t normal_len;
  double normal_scale; /* glTF normalTexture.scale (default 1) */
  /* glTF metallic-roughness factors, NAN when the file gives none (OBJ,
   * PLY), and its metallicRoughnessTexture (roughness in green, metallic
   * in blue, linear), "" when none, with an embedded one's bytes. */
  double metallic, roughness;
  char mr[256];
  /* glTF extensions the renderer does not model, kept to say so:
   * KHR_materials_clearcoat's and KHR_materials_transmission's factors
   * (0 when absent). */
  double clearcoat, transmission;
  unsigned char *mr_bytes;
  size_t mr_len;
  char opacity[256];   /* its opacity map (MTL map_d), or "" */
  unsigned char *opacity_bytes; /* an embedded one's bytes, else NULL */
  size_t opacity_len;
  int alpha;           /* vr_alpha_mode: glTF alphaMode (OPAQUE, MASK, BLEND) */
  double alpha_cutoff; /* glTF alphaCutoff (default 0.5) */
  size_t triangles;    /* triangles that use it */
  bool vertex_colours; /* some mesh of it has a colour per vertex (a PLY file's) */
  /* A Radiance material (a .rad file, rad_read.h): its kind and arguments
   * (rad_kind is a vr_rad_kind, -1 for every other file). */
  int rad_kind;
  double rad_arg[7], rad_up[3];
  char rad_file[1024], rad_where[1100];
} vr_mesh_material;

/* Fills *out (zeroed first).  Errors carry no location, the caller adds it:
 * VR_E_IO "mesh 'PATH': <Assimp's message>" when the file cannot be opened,
 * VR_E_PARSE with Assimp's message when it can but Assimp cannot read it, or
 * "mesh 'PATH': no triangles" when it holds none; VR_E_RANGE when it is too
 * large for 32-bit indices. */
vr_status vr_mesh_read(const char *path, vr_mesh_data *out, vr_error *err);
void vr_mesh_data_free(vr_mesh_data *m);

/* The materials of a model file in the file's order (*out, *n; free(*out)),
 * with the triangles each has; errors as vr_mesh_read's. */
vr_status vr_mesh_materials(const char *path, vr_mesh_material **out, size_t *n, vr_error *err);
/* Frees what vr_mesh_materials returned. */
void vr_mesh_materials_free(vr_mesh_material *m, size_t n);

#endif
