/* Shared by the render tests that need a database: a temporary one with
 * the seeded library, and spectra made from a function of wavelength.
 * Include after cmocka.h. */
#ifndef VR_TEMP_DB_H
#define VR_TEMP_DB_H

#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "vr/matdb.h"
#include "vr/spectrum.h"

/* Spectrum from a function of wavelength on 300..900 nm, 5 nm steps. */
static inline vr_spectrum *spectrum_of(double (*f)(double nm)) {
  double nm[121], v[121];
  for (int i = 0; i < 121; i++) {
    nm[i] = 300.0 + 5.0 * i;
    v[i] = f(nm[i]);
  }
  return vr_spectrum_create(121, nm, v, NULL);
}

/* A temporary seeded database (the caller closes it and removes path). */
static inline vr_matdb *temp_db(char *path, size_t size) {
  snprintf(path, size, "/tmp/vr_bsdf_test_XXXXXX");
  int fd = mkstemp(path);
  assert_true(fd >= 0);
  close(fd);
  unlink(path);
  vr_matdb *db = NULL;
  vr_error err = {0};
  if (vr_matdb_open(path, 0, &db, &err)) fail_msg("vr_matdb_open: %s", err.message);
  return db;
}

static inline void temp_db_close(vr_matdb *db, const char *path) {
  vr_matdb_close(db);
  char side[300];
  unlink(path);
  snprintf(side, sizeof side, "%s-wal", path);
  unlink(side);
  snprintf(side, sizeof side, "%s-shm", path);
  unlink(side);
}

#endif
