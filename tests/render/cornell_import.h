/* Shared by the render tests that use the measured Cornell box: its
 * spectra (samples/cornell) imported into a test database.  Include after
 * cmocka.h and the vr headers it names. */
#ifndef VR_CORNELL_IMPORT_H
#define VR_CORNELL_IMPORT_H

#include <stdio.h>

#include "vr/material_io.h"
#include "vr/matdb.h"

/* 0 on success; -1 after printing why. */
static inline int cornell_import(vr_matdb *db, const char *file, const char *name,
                                 const char *kind) {
  char path[1024];
  snprintf(path, sizeof path, "%s/samples/cornell/%s", VR_SOURCE_DIR, file);
  vr_error err = {0};
  vr_material *m = NULL;
  if (vr_import_file(path, name, kind, "test", &m, &err) || vr_matdb_save(db, m, &err)) {
    fprintf(stderr, "%s: %s\n", path, err.message);
    vr_material_destroy(m);
    return -1;
  }
  vr_material_destroy(m);
  return 0;
}

/* The box's four spectra under the names samples/cornell/cornell.scn uses. */
static inline int cornell_import_all(vr_matdb *db) {
  return cornell_import(db, "cornell_white.csv", "cornell-white", "reflectance") ||
         cornell_import(db, "cornell_red.csv", "cornell-red", "reflectance") ||
         cornell_import(db, "cornell_green.csv", "cornell-green", "reflectance") ||
         cornell_import(db, "cornell_light.csv", "cornell-light", "illuminant");
}

#endif
