/* Reading a mesh file (OBJ, PLY, glTF, ... whatever Assimp knows) into
 * plain arrays, for geometry.c.  Private to render/. */
#ifndef VR_MESH_ASSIMP_H
#define VR_MESH_ASSIMP_H

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
  size_t ntris;
  uint32_t *tris;  /* 3 per triangle, indices into the vertices */
} vr_mesh_data;

/* Fills *out (zeroed first).  Errors carry no location, the caller adds it:
 * VR_E_IO "mesh 'PATH': <Assimp's message>" when the file cannot be opened,
 * VR_E_PARSE with Assimp's message when it can but Assimp cannot read it, or
 * "mesh 'PATH': no triangles" when it holds none; VR_E_RANGE when it is too
 * large for 32-bit indices. */
vr_status vr_mesh_read(const char *path, vr_mesh_data *out, vr_error *err);
void vr_mesh_data_free(vr_mesh_data *m);

#endif
