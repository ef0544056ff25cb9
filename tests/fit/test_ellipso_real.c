/* Real ellipsometry files as instruments and peers' projects hold them
 * (tests/data/ellipsometry/real/README.md names each source): the readers
 * against the peers' own test vectors, and refellips' EP4 demo fitted with
 * refellips' tables against its published thickness. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#define REAL VR_TEST_DATA "/ellipsometry/real/"

static void read_ok(const char *file, const vr_ellipso_read_options *o, vr_ellipso_data *d) {
  vr_error err = {0};
  if (vr_ellipso_read_with(file, o, d, &err)) fail_msg("%s", err.message);
}

static size_t skipped(const vr_ellipso_data *d, const char *tag) {
  for (size_t i = 0; i < d->nskipped; i++)
    if (!strcmp(d->skipped[i].tag, tag)) return d->skipped[i].rows;
  return 0;
}

/* Accurion EP4 data exported in WVASE format: a title, then the unit line
 * "nm<TAB><TAB>Psi<TAB>Delta", then "λ AOI Ψ Δ". */
static void ep4_wvase_format(void **state) {
  (void)state;
  vr_ellipso_data d;
  read_ok(REAL "testData1_16nm_PNIPAM_on_Si_EP4.dat", NULL, &d);
  assert_int_equal(d.n, 4);
  assert_false(d.has_sigma);
  /* the file's rows: 658.0 55.0 27.700 170.200 ... 658.0 70.0 11.700 143.900 */
  assert_near(d.p[0].nm, 658.0, 0);
  assert_near(d.p[0].aoi_deg, 55.0, 0);
  assert_near(d.p[0].psi_deg, 27.700, 0);
  assert_near(d.p[0].delta_deg, 170.200, 0);
  assert_near(d.p[3].aoi_deg, 70.0, 0);
  assert_near(d.p[3].delta_deg, 143.900, 0);
  assert_int_equal(d.p[0].line, 3);
  vr_ellipso_data_free(&d);
  read_ok(REAL "W475-P(M-s-O)-8020-.75BB-water-rpt-3-20C-spectro_WVASEformat.dat", NULL, &d);
  assert_int_equal(d.n, 12);
  assert_near(d.p[1].nm, 446.4, 0);
  assert_near(d.p[1].psi_deg, 21.125, 0);
  vr_ellipso_data_free(&d);
  /* the same layout without a title line (refellips' spectroscopic demo):
   * 600 and 700 nm at 50-70 deg */
  read_ok(REAL "WVASE_example_2nmSiO2_20nmPNIPAM_MultiWavelength.txt", NULL, &d);
  assert_int_equal(d.n, 10);
  assert_near(d.p[9].nm, 700, 0);
  assert_near(d.p[9].aoi_deg, 70, 0);
  vr_ellipso_data_free(&d);
}

/* CompleteEASE (M-2000) export: untagged Ψ/Δ rows with a trailing tab, each
 * followed by "dPolE λ 0 depol σ" and "uR λ 0 value σ". */
static void completeease_dpole_ur(void **state) {
  (void)state;
  vr_ellipso_data d;
  read_ok(REAL "Woolam_staticTest.dat", NULL, &d);
  /* 398 wavelengths, 370.324 to 999.935 nm at 70 deg (refellips'
   * tests/test_loaders.py reads the same rows) */
  assert_int_equal(d.n, 398);
  assert_true(d.has_sigma);
  assert_near(d.p[0].nm, 370.324, 0);
  assert_near(d.p[d.n - 1].nm, 999.935, 0);
  /* 370.324 70.000 21.4553 145.7525 0.0140 0.0318, then dPolE ... -5.2834 1.0000 */
  assert_near(d.p[0].psi_deg, 21.4553, 0);
  assert_near(d.p[0].sigma_delta, 0.0318, 0);
  assert_near(d.p[0].depolarisation, -5.2834, 0);
  assert_near(d.p[0].sigma_depolarisation, 1.0, 0);
  /* the last: 999.935 70.000 1.8282 24.4792 ..., dPolE ... -2.1498 */
  assert_near(d.p[d.n - 1].delta_deg, 24.4792, 0);
  assert_near(d.p[d.n - 1].depolarisation, -2.1498, 0);
  /* uR rows carry another quantity: skipped and counted */
  assert_int_equal(d.nskipped, 1);
  assert_int_equal(skipped(&d, "uR"), 398);
  vr_ellipso_data_free(&d);
}

/* Accurion EP4 native tables: named columns in any order, a units line,
 * zones.  refellips' tests/test_loaders.py (open_EP4file on 15-1-1.dat):
 * 11 angles, the mean Ψ over the zones at the last angle 12.72666667. */
static void accurion_tables(void **state) {
  (void)state;
  vr_ellipso_data d;
  read_ok(REAL "15-1-1.dat", NULL, &d);
  double a[16];
  assert_int_equal(vr_ellipso_angles(&d, a, 16), 11);
  assert_near(a[0], 50, 0);
  assert_near(a[10], 70, 0);
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < d.n; i++)
    if (d.p[i].aoi_deg == 70.0) sum += d.p[i].psi_deg, n++;
  assert_int_equal(n, 3); /* zone 4 at 70 deg could not be nulled (NaN) */
  assert_near(sum / n, 12.72666667, 5e-9);
  assert_int_equal(skipped(&d, "Zone 0 (average)"), 11);
  assert_int_equal(skipped(&d, "Zone 5 (spread)"), 11);
  assert_int_equal(skipped(&d, "NaN (not nulled)"), 3);
  assert_near(d.p[0].bandwidth_nm, 2.0, 0);
  vr_ellipso_data_free(&d);
  /* pyElli's tests/test_accurion.py: 114 points (57 wavelengths at 40 and
   * 50 deg), columns in another order, CRLF line ends */
  read_ok(REAL "Si3N4_on_4inBF33_W02_20240903-150451.ds.dat", NULL, &d);
  assert_int_equal(d.n, 114);
  /* first row: 0 40.000 365.0 6.1 115908 417.6 409.8 179.785156 32.535931 */
  assert_near(d.p[0].aoi_deg, 40.0, 0);
  assert_near(d.p[0].nm, 365.0, 0);
  assert_near(d.p[0].delta_deg, 179.785156, 0);
  assert_near(d.p[0].psi_deg, 32.535931, 0);
  assert_near(d.p[0].bandwidth_nm, 6.1, 0);
  assert_int_equal(d.nskipped, 0);
  vr_ellipso_data_free(&d);
}

/* A single-wavelength table without a wavelength column: refused with a
 * hint, read with the wavelength given; a wavelength given for a file that
 * has its own is refused. */
static void single_wavelength(void **state) {
  (void)state;
  vr_ellipso_data d;
  vr_error err = {0};
  assert_int_not_equal(vr_ellipso_read(REAL "WVASE_example_2nmSiO2_11nmPNIPAM_658nm.txt", NULL, &d, &err), VR_OK);
  assert_contains(err.message, "--wavelength");
  vr_ellipso_read_options o = {.wavelength_nm = 658};
  read_ok(REAL "WVASE_example_2nmSiO2_11nmPNIPAM_658nm.txt", &o, &d);
  assert_int_equal(d.n, 4);
  assert_near(d.p[0].nm, 658, 0);
  assert_near(d.p[0].aoi_deg, 55, 0);
  assert_near(d.p[3].delta_deg, 136.59, 0);
  vr_ellipso_data_free(&d);
  err = (vr_error){0};
  assert_int_not_equal(vr_ellipso_read_with(REAL "15-1-1.dat", &o, &d, &err), VR_OK);
  assert_contains(err.message, "has its own wavelengths");
}

/* refellips' demo stack: air | PNIPAM Cauchy (A = 1.47, B = 0.00495 um^2)
 * | 20 Å silica | silicon, with refellips' own silica.csv and silicon.csv,
 * the PNIPAM thickness free.  The ambient is air.csv's index at 658 nm
 * (our CSV reader refuses air.csv itself: its rows omit the k its header
 * names).  Fits file with it; returns the thickness (nm) and chi2. */
static double fit_refellips_stack(const char *file, double *chi2) {
  vr_ellipso_data d;
  read_ok(file, NULL, &d);
  const char *model = "ambient constant n=1.00027623\n"
                      "layer pnipam cauchy thickness=15 A=1.47 B=0.00495 fit min=10 max=50\n"
                      "layer oxide file:refellips_materials/silica.csv thickness=2\n"
                      "substrate file:refellips_materials/silicon.csv\n";
  vr_sample_model *m = NULL;
  vr_error err = {0};
  if (vr_model_parse(model, strlen(model), "refellips.model", REAL, NULL, &m, &err)) fail_msg("%s", err.message);
  vr_fit_options opt = vr_fit_default_options();
  vr_fit_result r = {0};
  if (vr_ellipso_fit(m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  assert_int_equal(r.nfree, 1);
  double t = r.value[0];
  *chi2 = r.chi2;
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_ellipso_data_free(&d);
  return t;
}

/* refellips demos/refellipsDemo.ipynb @ 0136a6b0: published 113.501 ±
 * 0.544 Å, chi2 0.1820020806589319.  The same tables interpolated by the
 * same rule (linear, vr/spectrum.h) and the same unweighted objective give
 * refellips' answer to its printed digits. */
static void refellips_ep4_demo(void **state) {
  (void)state;
  double chi2, t = fit_refellips_stack(REAL "testData1_16nm_PNIPAM_on_Si_EP4.dat", &chi2);
  print_message("refellips EP4 demo: %.6f nm (refellips 11.3501 +- 0.0544), chi2 %.8f (0.18200208)\n", t, chi2);
  assert_near(t, 11.3501, 0.00005);
  assert_near(chi2, 0.1820020806589319, 1e-5 * 0.182);
}

/* refellips' spectroscopic demo data (WVASE-generated, 600 and 700 nm at
 * 50-70 deg) with the same stack: refellips' own check,
 * tests/test_refellips.py test_smoke_test_a_fit @ 504eb3d5, is chi2 < 0.055
 * (with its pnipam.csv, not published; PNIPAM here is the demo's Cauchy). */
static void refellips_spectroscopic_demo(void **state) {
  (void)state;
  double chi2, t = fit_refellips_stack(REAL "WVASE_example_2nmSiO2_20nmPNIPAM_MultiWavelength.txt", &chi2);
  print_message("refellips spectroscopic demo: %.4f nm, chi2 %.5f (refellips' bound 0.055)\n", t, chi2);
  assert_true(chi2 < 0.055);
  /* the data were generated for about 20 nm of PNIPAM */
  assert_true(fabs(t - 20) < 1);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(ep4_wvase_format),      cmocka_unit_test(completeease_dpole_ur),
      cmocka_unit_test(accurion_tables),       cmocka_unit_test(single_wavelength),
      cmocka_unit_test(refellips_ep4_demo),    cmocka_unit_test(refellips_spectroscopic_demo),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
