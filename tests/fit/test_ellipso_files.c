/* Real instrument files: pyElli's Sentech measurement of TiO2 on SiO2 on Si
 * fitted as pyElli's own test does, J.A. Woollam WVASE and CompleteEASE
 * files, and the readers' errors. */
#include "vr_test.h"
#include "vr/ellipso_fit.h"

#define DATA VR_TEST_DATA "/ellipsometry/"

static double chi2_rho(const vr_sample_model *m, const vr_ellipso_data *d) {
  double s = 0;
  for (size_t i = 0; i < d->n; i++) {
    double psi, delta;
    if (vr_model_psi_delta(m, d->p[i].nm, d->p[i].aoi_deg, &psi, &delta, NULL, NULL)) return INFINITY;
    vr_complex a = tan(psi * M_PI / 180) * cexp(I * delta * M_PI / 180);
    vr_complex b = tan(d->p[i].psi_deg * M_PI / 180) * cexp(I * d->p[i].delta_deg * M_PI / 180);
    s += pow(cabs(a - b), 2);
  }
  return s;
}

/* pyElli's Cauchy is n = n0 + 100 n1 / lambda^2 + 1e7 n2 / lambda^4 with
 * lambda in nm, i.e. B = 1e-4 n1 um^2 and C = 1e-5 n2 um^4 here. */
static const char *SENTECH_MODEL =
    "layer TiO2 cauchy thickness=24.8772291\n"
    "param TiO2.A = 2.23183200\nparam TiO2.B = 0.0449066847\nparam TiO2.C = 0.0019977445\n"
    "layer SiO2 cauchy thickness=276.36\n"
    "param SiO2.A = 1.452\nparam SiO2.B = 0.0036\nparam SiO2.C = 0\n"
    "substrate file:samples/ellipsometry/Si_Aspnes.yml\n";

static void read_sentech(vr_ellipso_data *d) {
  vr_error err = {0};
  if (vr_ellipso_read(DATA "TiO2_400cycles.txt", NULL, d, &err)) fail_msg("%s", err.message);
  assert_int_equal(d->n, 1227);
  assert_near(d->p[0].aoi_deg, 70.06, 1e-12);
  /* pyElli's test (tests/test_TiO2.py) keeps 400-800 nm: 926 rows, and
   * models the angle as 70 deg. */
  assert_int_equal(vr_ellipso_crop(d, 400, 800), 926);
  for (size_t i = 0; i < d->n; i++) d->p[i].aoi_deg = 70.0;
}

static void pyelli_sentech_forward(void **state) {
  (void)state;
  /* pyElli asserts sum |rho_meas - rho_model|^2 < 0.0456 at its fitted
   * values (TiO2 24.8772291 nm, Cauchy 2.231832 / 449.066847 / 199.774450). */
  vr_ellipso_data d;
  read_sentech(&d);
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(SENTECH_MODEL, strlen(SENTECH_MODEL), "sentech.model", VR_SOURCE_DIR, NULL, &m, &err))
    fail_msg("%s", err.message);
  double c2 = chi2_rho(m, &d);
  print_message("sum |drho|^2 at pyElli's values: %.6f\n", c2);
  assert_true(c2 < 0.0456);
  vr_model_destroy(m);
  vr_ellipso_data_free(&d);
}

static void pyelli_sentech_fit(void **state) {
  (void)state;
  /* The same fit from pyElli's start values (TiO2 20 nm, Cauchy 2.236, 451,
   * 251): the thickness comes out at 24.88 nm and the residual below 0.0456
   * (pyElli example's lmfit: 24.8772 +- 0.0106 nm, chi-square 0.04560). */
  vr_ellipso_data d;
  read_sentech(&d);
  char text[1024];
  snprintf(text, sizeof text, "%s%s", SENTECH_MODEL,
           "param TiO2.thickness = 20 fit min=0 max=100\n"
           "param TiO2.A = 2.236 fit\nparam TiO2.B = 0.0451 fit\nparam TiO2.C = 0.00251 fit\n");
  vr_sample_model *m;
  vr_error err = {0};
  if (vr_model_parse(text, strlen(text), "sentech.model", VR_SOURCE_DIR, NULL, &m, &err)) fail_msg("%s", err.message);
  vr_fit_options opt = vr_fit_default_options();
  opt.residual = VR_RESID_RHO;
  vr_fit_result r;
  if (vr_ellipso_fit(m, &d, &opt, &r, &err)) fail_msg("%s", err.message);
  print_message("TiO2 %.4f +- %.4f nm, sum |drho|^2 %.6f\n", r.value[0], r.stderr_[0], r.chi2);
  assert_string_equal(r.names[0], "TiO2.thickness");
  assert_near(r.value[0], 24.88, 0.05);
  assert_true(r.chi2 < 0.0456);
  assert_near(chi2_rho(m, &d), r.chi2, 1e-9);
  vr_fit_result_free(&r);
  vr_model_destroy(m);
  vr_ellipso_data_free(&d);
}

static void woollam_wvase(void **state) {
  (void)state;
  /* pyElli's tests/test_wollam.py: 543 rows, 300 to 1200 nm, 3 angles. */
  vr_ellipso_data d;
  vr_error err = {0};
  if (vr_ellipso_read(DATA "wvase_example.dat", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_int_equal(d.n, 543);
  assert_true(d.has_sigma);
  assert_near(d.p[0].nm, 300, 0);
  assert_near(d.p[d.n - 1].nm, 1200, 0);
  double a[8];
  assert_int_equal(vr_ellipso_angles(&d, a, 8), 3);
  assert_near(a[0], 65, 0);
  assert_near(a[2], 75, 0);
  /* First row: 300 65 12.140821 1.5609661 0.37071 3.46024. */
  assert_near(d.p[0].psi_deg, 12.140821, 0);
  assert_near(d.p[0].delta_deg, 1.5609661, 0);
  assert_near(d.p[0].sigma_delta, 3.46024, 0);
  assert_int_equal(d.p[0].line, 5);
  vr_ellipso_data_free(&d);
}

static void woollam_trig_and_completeease(void **state) {
  (void)state;
  vr_ellipso_data d;
  vr_error err = {0};
  /* tan(Psi) / cos(Delta) file: "300 70 .245 .123". */
  if (vr_ellipso_read(DATA "wvase_trig.dat", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_int_equal(d.n, 2);
  assert_near(d.p[0].psi_deg, atan(0.245) * 180 / M_PI, 1e-12);
  assert_near(d.p[0].delta_deg, acos(0.123) * 180 / M_PI, 1e-12);
  assert_near(d.p[1].delta_deg, acos(-0.034) * 180 / M_PI, 1e-12);
  vr_ellipso_data_free(&d);
  /* CompleteEASE: "E" rows, Angstroms, a dpolE row, Delta given as -89.9. */
  const char *ce = "InS on a-sapphir \nVASEmethod[EllipsometerType=4 , CompleteEASE=6.37]\nAngstroms\n"
                   "E\t1930.000000\t50.000000\t31.709644\t144.353119\t0.016751\t0.060483\n"
                   "E\t6000.0\t50.0\t20.0\t-89.91\t0.02\t0.07\n"
                   "dpolE\t6000.0\t50.0\t1.5\t0.2\n";
  if (vr_ellipso_parse(ce, strlen(ce), "ce.dat", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_int_equal(d.n, 2);
  assert_near(d.p[0].nm, 193.0, 1e-12);
  assert_near(d.p[1].delta_deg, 270.09, 1e-9);
  assert_near(d.p[1].depolarisation, 1.5, 0);
  assert_true(isnan(d.p[0].depolarisation));
  vr_ellipso_data_free(&d);
  /* eV unit line: 2 eV is 619.92 nm. */
  const char *ev = "sample\neV\n2.0 70 20 100 0.01 0.02\n";
  if (vr_ellipso_parse(ev, strlen(ev), "ev.dat", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_near(d.p[0].nm, 1239.84198 / 2.0, 1e-9);
  vr_ellipso_data_free(&d);
}

static void csv_units_and_conventions(void **state) {
  (void)state;
  vr_ellipso_data d;
  vr_error err = {0};
  const char *csv = "wavelength (um),aoi,psi,delta,sigma_psi,sigma_delta\n0.6328,70,10.6,-179.5,0.01,0.05\n";
  if (vr_ellipso_parse(csv, strlen(csv), "a.csv", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_near(d.p[0].nm, 632.8, 1e-9);
  assert_near(d.p[0].delta_deg, 180.5, 1e-12); /* -179.5 folded into [0, 360) */
  assert_true(d.has_sigma);
  vr_ellipso_data_free(&d);
  const char *nosig = "energy_eV,angle,Psi,Delta\n2.5,65,30,120\n";
  if (vr_ellipso_parse(nosig, strlen(nosig), "b.csv", NULL, &d, &err)) fail_msg("%s", err.message);
  assert_false(d.has_sigma);
  assert_near(d.p[0].sigma_psi, VR_ELLIPSO_DEFAULT_SIGMA_DEG, 0);
  assert_near(d.p[0].nm, 1239.84198 / 2.5, 1e-9);
  vr_ellipso_data_free(&d);
}

static void reader_errors(void **state) {
  (void)state;
  struct { const char *name, *text, *expect; } cases[] = {
      {"nan.csv", "wavelength_nm,aoi,psi,delta\n500,70,NaN,100\n", "nan.csv:2:8: field 'psi': 'NaN' is not a finite number"},
      {"cols.csv", "wavelength_nm,aoi,delta\n500,70,100\n", "cols.csv:1: no 'psi' column"},
      {"short.csv", "wavelength_nm,aoi,psi,delta\n500,70,10\n", "short.csv:2:"},
      {"aoi.csv", "wavelength_nm,aoi,psi,delta\n500,95,10,100\n", "aoi.csv:2: field 'aoi': 95 degrees is outside (0, 90)"},
      {"mm.dat", "x\nVASEmethod[]\nnm\nmm12\t245.7\t70\t-0.18\t-0.18\t0.006\t0.006\n", "mm.dat: no Psi/Delta rows (only rows of type 'mm12'"},
      {"bad.dat", "x\nnm\n300 65 12.1 abc 0.3 3.4\n", "bad.dat:3: field 'delta': expected a number, got 'abc'"},
      {"five.dat", "x\nnm\n300 65 12.1 4 0.3\n", "bad"},
      {"empty.csv", "wavelength_nm,aoi,psi,delta\n", "empty.csv: no data rows"},
      {"sent.txt", "; WAVELENGTH 70 70\n400 10 20\n401 10\n", "sent.txt:3: expected 3 fields"},
      {"cols.dat", "x\nnm\t\tPsi\tFoo\n658 50 1 2\n", "cols.dat:2: after the unit 'nm': expected TRIG, or the column names Psi and Delta"},
      {"dpol.dat", "x\nnm\ndPolE\t500\t0\t1.5\t1\n", "dpol.dat:3: dPolE row at 500, 0 deg has no Psi/Delta row before it"},
      {"ep4u.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\trad\tdeg\tdeg\n658\t50\t170\t30\n", "ep4u.dat:2: field 'AOI': unit 'rad', expected deg"},
      {"ep4n.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\tdeg\tdeg\tdeg\n658\t50\tx\t30\n", "ep4n.dat:3: field 'Delta': expected a number, got 'x'"},
      {"ep4s.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\tdeg\tdeg\tdeg\n658\t50\t170\n", "ep4s.dat:3: expected 4 tab-separated fields, found 3"},
      {"ep4w.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\tdeg\tdeg\tdeg\nNaN\t50\t170\t30\n", "ep4w.dat:3: field 'Lambda': not a finite number: 'NaN'"},
      {"ep4a.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\tdeg\tdeg\tdeg\n658\t95\t170\t30\n", "ep4a.dat:3: field 'aoi': 95 degrees is outside (0, 90)"},
      {"ep4e.dat", "#Lambda\tAOI\tDelta\tPsi\n#nm\tdeg\tdeg\tdeg\n", "ep4e.dat: no data rows"},
      /* A lone standard-deviation column is refused, not ignored. */
      {"lone.csv", "wavelength_nm,aoi,psi,delta,sigma_psi\n500,70,10,100,0.01\n",
       "lone.csv:1: column 'sigma_psi' gives the standard deviation of Psi but no column gives that of Delta"},
      {"loned.csv", "wavelength_nm,aoi,psi,delta,sigma_delta\n500,70,10,100,0.01\n",
       "loned.csv:1: column 'sigma_delta' gives the standard deviation of Delta but no column gives that of Psi"},
      {"dup.csv", "wavelength_nm,aoi,psi,delta,psi_model\n500,70,10,100,11\n",
       "dup.csv:1: columns 'psi' and 'psi_model' are both read as the same quantity"},
  };
  for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
    vr_ellipso_data d;
    vr_error err = {0};
    vr_status st = vr_ellipso_parse(cases[i].text, strlen(cases[i].text), cases[i].name, NULL, &d, &err);
    if (st == VR_OK) fail_msg("%s parsed", cases[i].name);
    if (strcmp(cases[i].expect, "bad")) assert_contains(err.message, cases[i].expect);
    else assert_contains(err.message, "4 or 6 numbers");
  }
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(pyelli_sentech_forward),
      cmocka_unit_test(pyelli_sentech_fit),
      cmocka_unit_test(woollam_wvase),
      cmocka_unit_test(woollam_trig_and_completeease),
      cmocka_unit_test(csv_units_and_conventions),
      cmocka_unit_test(reader_errors),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
