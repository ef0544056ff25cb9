/* One interpolation rule for tabulated n, k in the whole toolchain
 * (VR_NK_INTERP in vr/spectrum.h: linear in wavelength): the material
 * database (what vr-matdb eval and the renderer read) and a fit's db: and
 * file: materials give the same index from the same table, equal to the
 * linear interpolation computed by hand. */
#include "vr_test.h"
#include "vr/ellipso_model.h"
#include "vr/matdb.h"
#include "vr/material.h"

#include <unistd.h>

static void one_rule(void **state) {
  (void)state;
  char dir[] = "/tmp/vr-nk-XXXXXX";
  assert_non_null(mkdtemp(dir));
  char dbp[64], csv[64];
  snprintf(dbp, sizeof dbp, "%s/m.db", dir);
  snprintf(csv, sizeof csv, "%s/t.csv", dir);
  /* A coarse table: n 3.9 -> 3.8 and k 0.02 -> 0.008 between 600 and 700 nm. */
  FILE *f = fopen(csv, "w");
  assert_non_null(f);
  fputs("wavelength_nm,n,k\n500,4.2,0.1\n600,3.9,0.02\n700,3.8,0.008\n800,3.7,0.001\n", f);
  fclose(f);
  const double nm = 633.3, t = (633.3 - 600) / 100;
  const double n_lin = 3.9 + t * (3.8 - 3.9), k_lin = 0.02 + t * (0.008 - 0.02);

  vr_error err = {0};
  vr_matdb *db = NULL;
  if (vr_matdb_open(dbp, 0, &db, &err)) fail_msg("%s", err.message);
  vr_material *m = vr_material_create("T", VR_KIND_DIELECTRIC, &err);
  const double w[4] = {500, 600, 700, 800}, n[4] = {4.2, 3.9, 3.8, 3.7}, k[4] = {0.1, 0.02, 0.008, 0.001};
  vr_spectrum *sn = vr_spectrum_create(4, w, n, &err), *sk = vr_spectrum_create(4, w, k, &err);
  assert_non_null(m);
  assert_non_null(sn);
  assert_non_null(sk);
  if (vr_material_add_spectrum(m, "n", sn, &err) || vr_material_add_spectrum(m, "k", sk, &err) ||
      vr_matdb_save(db, m, &err))
    fail_msg("%s", err.message);
  double n1, k1;
  if (vr_material_nk(m, nm, false, &n1, &k1, NULL, &err)) fail_msg("%s", err.message);
  vr_material_destroy(m);

  const char *texts[2] = {"substrate db:T\n", "substrate file:t.csv\n"};
  for (int i = 0; i < 2; i++) {
    vr_sample_model *sm = NULL;
    if (vr_model_parse(texts[i], strlen(texts[i]), "nk.model", dir, db, &sm, &err)) fail_msg("%s", err.message);
    vr_complex N;
    if (vr_model_layer_index(sm, VR_OWNER_SUBSTRATE, nm, &N, &err)) fail_msg("%s", err.message);
    assert_near(creal(N), n_lin, 1e-12);
    assert_near(cimag(N), k_lin, 1e-12);
    vr_model_destroy(sm);
  }
  assert_near(n1, n_lin, 1e-12);
  assert_near(k1, k_lin, 1e-12);
  vr_matdb_close(db);
  unlink(csv);
  unlink(dbp);
  char wal[80];
  snprintf(wal, sizeof wal, "%s-wal", dbp);
  unlink(wal);
  snprintf(wal, sizeof wal, "%s-shm", dbp);
  unlink(wal);
  rmdir(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(one_rule)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
