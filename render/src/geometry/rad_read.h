/* Reading a Radiance scene description (.rad) into triangles, materials
 * and distant sources, for models.c and the mesh reader.  Private to
 * render/.
 *
 * What is read (Radiance's "The RADIANCE 5.x Synthetic Imaging System",
 * primitives and materials; argument layouts as there):
 *   surfaces   polygon, sphere, bubble, cone, cup, cylinder, tube, ring,
 *              tessellated (rad_shapes.c); source (a distant source);
 *   materials  plastic, metal, mirror, glass, dielectric, light, glow,
 *              illum, BSDF, trans, and alias chains to any of them;
 *   commands   !xform with -t -rx -ry -rz -s -mx -my -mz -n -m and one or
 *              more files: parsed here and the files read, never run
 *              through a shell.
 * Everything else is refused with the file, the line and the primitive:
 * patterns, textures and mixtures (brightfunc, colorpict, mixfunc, ...),
 * materials this renderer does not model (plasfunc, BRTDfunc, ...), octree
 * instances and Radiance meshes, any other !command. */
#ifndef VR_RAD_READ_H
#define VR_RAD_READ_H

#include <stdbool.h>
#include <stddef.h>

#include "geometry/mesh_assimp.h"
#include "vr/error.h"
#include "vr/scene.h"

typedef enum vr_rad_kind {
  VR_RAD_PLASTIC = 0, /* R G B spec rough */
  VR_RAD_METAL,       /* R G B spec rough */
  VR_RAD_MIRROR,      /* R G B */
  VR_RAD_GLASS,       /* rtn gtn btn [n]: transmissivities, index (default 1.52) */
  VR_RAD_DIELECTRIC,  /* rtn gtn btn n hc: transmission per unit length, index, Hartmann */
  VR_RAD_LIGHT,       /* R G B radiance, W/(sr m2) in Radiance's convention */
  VR_RAD_GLOW,        /* R G B maxrad */
  VR_RAD_BSDF,        /* thickness, BSDF XML file, up vector; no extra reals */
  VR_RAD_TRANS        /* R G B spec rough trans tspec */
} vr_rad_kind;

typedef struct vr_rad_material {
  char name[128];     /* its identifier; a redefinition is NAME@LINE */
  vr_rad_kind kind;
  double arg[7];      /* its real arguments as written (glass: n filled with 1.52) */
  char file[1024];    /* BSDF: the XML file, resolved against the .rad file's folder */
  double up[3];       /* BSDF: the up vector (after the !xform that placed it) */
  char where[1100];   /* "FILE:LINE", for messages */
  size_t triangles;   /* triangles that use it */
} vr_rad_material;

/* A distant source (the sun gensky writes): direction towards it, full
 * angle in degrees and its light material. */
typedef struct vr_rad_source {
  double dir[3];
  double angle_deg;
  int material;
  char where[1100];
} vr_rad_source;

/* A polygon as read: its name, where, material and its triangles
 * [first, first + count) of the model's mesh. */
typedef struct vr_rad_poly {
  char id[128];
  char where[1100];
  size_t first, count;
} vr_rad_poly;

/* Two polygons that lie in one plane and overlap (rad_overlap.c). */
typedef struct vr_rad_overlap {
  size_t a, b;       /* indices into the model's polys, a < b */
  double area;       /* the area they share, m2 in the file's units */
} vr_rad_overlap;

typedef struct vr_rad_model {
  vr_mesh_data mesh;        /* tri_material indexes mats */
  vr_rad_material *mats;
  size_t nmats;
  vr_rad_source *src;
  size_t nsrc;
  size_t illum_dropped;     /* illum surfaces with no alternate material (invisible) */
  size_t degenerate;        /* polygons of no area, skipped as oconv skips them */
  size_t files;             /* files read, the top one and its !xform includes */
  vr_rad_poly *polys;       /* every polygon with triangles, in reading order */
  size_t npolys;
} vr_rad_model;

/* Reads path and the files its !xform lines name.  Errors are VR_E_IO or
 * VR_E_PARSE "FILE:LINE: message" naming the primitive at fault. */
vr_status vr_rad_read(const char *path, vr_rad_model *out, vr_error *err);
void vr_rad_free(vr_rad_model *m);

/* Whether a path names a Radiance scene (.rad). */
bool vr_rad_is(const char *path);

/* The SHA-256 (64 hex digits) of path and of every file its !xform lines
 * include, in reading order: the geometry cache's key of a .rad model. */
vr_status vr_rad_digest(const char *path, char hex[65], vr_error *err);

/* What the scene makes of the model (rad_materials.c). */

/* The model's materials as a mesh file's (rad_kind and its arguments set),
 * in its order, with their triangle counts. */
vr_status vr_rad_mesh_materials(const vr_rad_model *rm, vr_mesh_material **out, size_t *n,
                                vr_error *err);

/* Scene material m (initialised by the caller: name, loc, defaults) from
 * Radiance material mm of object ob.  note: what was decided, for the
 * user.  Errors name mm's file and line. */
vr_status vr_rad_scene_material(const vr_mesh_material *mm, const vr_scene_object *ob,
                                vr_scene_material *m, char *note, size_t cap, vr_error *err);
/* The emission a light or glow gives its objects (*spectrum owned by the
 * caller); value 0 and NULL for the other kinds. */
vr_status vr_rad_emission(const vr_mesh_material *mm, vr_quantity *emission, char **spectrum,
                          vr_error *err);

/* The model's distant source, if any, as the scene's sun (light sun): its
 * direction through ob's transform, its radius half the source's angle,
 * its illuminance normal to the beam L * 2 pi (1 - cos(angle / 2)) with
 * L = 179 (0.265 R + 0.670 G + 0.065 B) cd/m2, Radiance's luminance of its
 * light material.  Refused when the scene has a sky or a sun already, or
 * the model more than one source. */
vr_status vr_rad_add_sources(vr_scene *s, const vr_scene_object *ob, const vr_rad_model *rm,
                             vr_error *err);

/* Polygons of the model that coincide: in the same plane (within 0.1 mm
 * and 1e-4 in the normal, either facing) and sharing more than 1 cm2 of
 * area, as a floor drawn over a ground.  A renderer then sees either
 * surface there (Radiance and this one need not pick the same), so the
 * reader says so.  *out (free()) holds the pairs, largest shared area
 * first; *n their count. */
vr_status vr_rad_overlaps(const vr_rad_model *m, vr_rad_overlap **out, size_t *n, vr_error *err);

/* Tessellation (rad_shapes.c): appends the triangles of one primitive,
 * in world coordinates, to m with material mat.  outward false flips
 * the surface (bubble, cup, tube). */
vr_status vr_rad_polygon(vr_mesh_data *m, const double *v, size_t n, uint32_t mat, bool *degenerate,
                         vr_error *err);
vr_status vr_rad_sphere(vr_mesh_data *m, const double c[3], double r, bool outward, uint32_t mat,
                        vr_error *err);
vr_status vr_rad_cone(vr_mesh_data *m, const double p0[3], const double p1[3], double r0, double r1,
                      bool outward, uint32_t mat, vr_error *err);
vr_status vr_rad_ring(vr_mesh_data *m, const double c[3], const double n[3], double r0, double r1,
                      uint32_t mat, vr_error *err);

#endif
