/* Shared by the vr_bsdf tests: scene settings as the parser leaves them,
 * materials built in memory (flat-index dielectrics, chromogenic and
 * glazing panes, btdf tables), a temporary database with the seeded
 * library, and a counter-based uniform sequence. */
#ifndef BSDF_TEST_UTIL_H
#define BSDF_TEST_UTIL_H

#include "vr_test.h"
#include "temp_db.h"

#include <complex.h>

#include "vr/bsdf.h"
#include "vr/matdb.h"
#include "vr/material.h"
#include "vr/optics.h"

#define DEG (M_PI / 180.0)

/* A scene material with nothing given, as written on line 12, column 3. */
static inline vr_scene_material test_sm(const char *db_name) {
  vr_scene_material sm;
  memset(&sm, 0, sizeof sm);
  sm.name = (char *)"obj";
  sm.source = VR_MATSRC_DB;
  sm.db_name = (char *)db_name;
  sm.reflectance = NAN;
  sm.roughness = NAN;
  sm.thickness_m = NAN;
  sm.pane = VR_PANE_DEFAULT;
  sm.state = NAN;
  sm.charge_mC_cm2 = NAN;
  sm.temperature_K = NAN;
  sm.loc.line = 12;
  sm.loc.col = 3;
  return sm;
}

static inline vr_spectrum *flat(double v) {
  double nm[2] = {200.0, 3000.0}, val[2] = {v, v};
  return vr_spectrum_create(2, nm, val, NULL);
}

/* A dielectric (or conductor) of constant n and k. */
static inline vr_material *flat_nk(const char *name, vr_material_kind kind, double n, double k) {
  vr_material *m = vr_material_create(name, kind, NULL);
  assert_non_null(m);
  assert_int_equal(vr_material_add_spectrum(m, "n", flat(n), NULL), VR_OK);
  assert_int_equal(vr_material_add_spectrum(m, "k", flat(k), NULL), VR_OK);
  return m;
}


static inline vr_bsdf *make_bsdf(const vr_scene_material *sm, const vr_material *m,
                                 const vr_material *coating) {
  vr_bsdf *b = NULL;
  vr_error err = {0};
  vr_status st = vr_bsdf_create(sm, m, coating, 360.0, 830.0, &b, &err);
  if (st) fail_msg("vr_bsdf_create: %s", err.message);
  return b;
}


static inline vr_material *db_load(vr_matdb *db, const char *name) {
  vr_material *m = NULL;
  vr_error err = {0};
  if (vr_matdb_load(db, name, 0, &m, &err)) fail_msg("vr_matdb_load %s: %s", name, err.message);
  return m;
}


/* A counter-based uniform number: SplitMix64's finaliser of (seed, index,
 * dimension), so every sample is reproducible and independent of order. */
static inline double u01(uint64_t seed, uint64_t i, uint64_t dim) {
  uint64_t z =
      seed * 0x9E3779B97F4A7C15ull + i * 0xD1B54A32D192ED03ull + dim * 0x8CB92BA72F3D8DD7ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return (double)(z >> 11) * 0x1.0p-53;
}

static inline vr_vec3 dir_at(double theta, double phi) {
  return (vr_vec3){sin(theta) * cos(phi), sin(theta) * sin(phi), cos(theta)};
}

/* Unpolarised slab T and R, straight from core. */
static inline void slab_rt(double n, double k, double d_nm, double theta, double nm, double *T,
                           double *R) {
  vr_slab_result s;
  assert_int_equal(vr_slab(1.0, n + I * k, d_nm, theta, nm, &s, NULL), VR_OK);
  *T = 0.5 * (s.T[0] + s.T[1]);
  *R = 0.5 * (s.R[0] + s.R[1]);
}

#endif
