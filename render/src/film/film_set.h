/* The set of files one render writes, staged together and moved into place
 * together, with a manifest written last (film_set.c; vr/film.h says what
 * a user sees of it).  Internal to film_output.c and annual_write.c. */
#ifndef VR_FILM_SET_H
#define VR_FILM_SET_H

#include <stdbool.h>
#include "vr/error.h"

#define FILM_SET_MAX 8

typedef struct vr_film_staged {
  char *target; /* where the file ends up */
  char *stage;  /* where it is written first */
  bool renamed;
} vr_film_staged;

typedef struct vr_film_set {
  char *prefix;
  char *dir;      /* PREFIX.partial.PID: the staging folder beside the outputs */
  bool made_dir;
  vr_film_staged f[FILM_SET_MAX];
  int n;
} vr_film_set;

/* Makes the staging folder PREFIX.partial.<pid> beside the outputs. */
vr_status film_set_begin(vr_film_set *s, const char *prefix, vr_error *err);

/* Reserves PREFIX+suffix; *out->stage is the name to write it under. */
vr_status film_set_add(vr_film_set *s, const char *suffix, vr_film_staged **out, vr_error *err);

/* Reserves a file of the set outside PREFIX's names (the statistics): staged
 * in the staging folder when it lies beside the outputs, else beside its
 * target as TARGET.partial.<pid>. */
vr_status film_set_add_path(vr_film_set *s, const char *target, vr_film_staged **out, vr_error *err);

/* Hashes the staged files, moves each into place, then writes
 * PREFIX.manifest.json (run_id, each file's name, bytes and SHA-256)
 * atomically, last, and removes the staging folder.  On failure: as
 * film_set_abort. */
vr_status film_set_commit(vr_film_set *s, const char *run_id, vr_error *err);

/* Gives up: no staged file stays, outputs of this set already moved into
 * place are removed, the staging folder goes. */
void film_set_abort(vr_film_set *s);

#endif
