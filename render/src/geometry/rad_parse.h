/* The Radiance reader's own parts (rad_read.c reads the words and the
 * files, rad_prims.c the materials and surfaces).  Private to the .rad
 * reader. */
#ifndef VR_RAD_PARSE_H
#define VR_RAD_PARSE_H

#include <stdbool.h>

#include "geometry/rad_read.h"
#include "vr/scene.h"

/* An identifier's meaning: a material (mat >= 0), or an illum with no
 * alternate (mat = -1: invisible, its surfaces dropped). */
typedef struct def {
  char name[128];
  int mat;
} def;

typedef struct reader {
  vr_rad_model *m;
  vr_error *err;
  def *defs;
  size_t ndefs;
  char **files; /* every file read, in order */
  size_t nfiles;
  bool walk_only; /* vr_rad_digest: follow !xform, build nothing */
} reader;

/* One file being read. */
typedef struct src {
  const char *path;
  char *text;
  size_t len, pos;
  long line;
  vr_xform x;          /* file coordinates -> the model's */
  bool flip;           /* x mirrors: reverse the triangles' order */
  char mod[128];       /* !xform -m: every surface takes this modifier, "" none */
  int depth;
} src;

/* A primitive's arguments. */
typedef struct prim {
  char mod[128], type[64], id[128];
  long line;
  long nstr;
  char **str;
  long nreal;
  double *real;
} prim;

vr_status rad_nomem(vr_error *err);
/* err set to "FILE:LINE: message" for file f. */
vr_status rad_fail(reader *r, const src *f, long line, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* A whole word as a finite number. */
bool rad_to_real(const char *w, double *out);
/* The latest definition of an identifier: its material (-1: an invisible
 * illum), *found false when none. */
int rad_lookup(const reader *r, const char *name, bool *found);
vr_status rad_define(reader *r, const char *name, int mat);

/* A material definition; a surface (polygon, sphere, ..., source). */
vr_status rad_material(reader *r, src *f, prim *p, vr_rad_kind kind);
vr_status rad_surface(reader *r, src *f, prim *p);

#endif
