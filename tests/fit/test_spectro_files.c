/* Real spectrophotometer files and the fit verdict: LBNL Optics 5 .LOF files
 * of Pilkington glass from LBNL's pyWinCalc, an Agilent Cary 50 export from
 * WrightTools (sources in tests/data/spectro/README.md), vendor layouts
 * (title line, %T/%R, descending wavelengths, trailing metadata), and the
 * refusals of thickness, row count and sample count.  Expected values are the
 * files' own numbers, read off the files, or the IGDB/WINDOW facts about the
 * products (NFRC 9803 uncoated, NFRC 9923 coated on its front). */
#include "vr_test.h"
#include "vr/glazing.h"
#include "vr/optical_standard.h"
#include "vr/spectro_data.h"
#include "vr/spectro_fit.h"

#define SPECTRO VR_TEST_DATA "/spectro"

static vr_spectro_data *read_ok(const char *path) {
  vr_spectro_data *d = NULL;
  vr_error err = {0};
  if (vr_spectro_read(path, &d, &err)) fail_msg("%s", err.message);
  return d;
}

static vr_status parse(const char *text, vr_spectro_data **d, vr_error *err) {
  return vr_spectro_parse_csv(text, strlen(text), "x.csv", d, err);
}

/* CLEAR5.LOF, NFRC 9803 "Optifloat Clear": header "{ Thickness } 4.699",
 * rows 0.300-2.500 um (361 at 5 nm to 2.1 um, 8 at 50 nm): 369 rows. */
static void lof_clear(void **state) {
  (void)state;
  vr_spectro_data *d = read_ok(SPECTRO "/CLEAR5.LOF");
  assert_near(d->thickness_nm, 4.699e6, 1e-3);
  assert_int_equal(d->ncurves, 1);
  const vr_spectro_curve *c = &d->curves[0];
  assert_int_equal(c->n, 369);
  assert_true(d->has_Rf && d->has_Rb);
  /* first row "0.300    0.0000    0.0440    0.0440" (file line 23) */
  assert_near(c->p[0].nm, 300, 1e-9);
  assert_near(c->p[0].T, 0.0, 1e-12);
  assert_near(c->p[0].Rf, 0.044, 1e-12);
  assert_int_equal(c->p[0].line, 23);
  /* "0.550    0.8940    0.0830    0.0830" */
  assert_near(c->p[50].nm, 550, 1e-9);
  assert_near(c->p[50].T, 0.894, 1e-12);
  assert_near(c->p[50].Rb, 0.083, 1e-12);
  assert_near(c->p[368].nm, 2500, 1e-9);
  vr_spectro_destroy(d);
}

/* LOW-E_5.LOF, NFRC 9923 "Energy Advantage Low-E", coated front: 392 rows
 * to 25 um, last "25.000    0.0000    0.8960    0.1690". */
static void lof_lowe(void **state) {
  (void)state;
  vr_spectro_data *d = read_ok(SPECTRO "/LOW-E_5.LOF");
  assert_near(d->thickness_nm, 4.7244e6, 1e-3);
  const vr_spectro_curve *c = &d->curves[0];
  assert_int_equal(c->n, 392);
  assert_near(c->p[391].nm, 25000, 1e-6);
  assert_near(c->p[391].Rf, 0.896, 1e-12);
  assert_near(c->p[391].Rb, 0.169, 1e-12);
  /* "0.550    0.8340    0.1120    0.1060": front and back differ */
  assert_near(c->p[50].Rf, 0.112, 1e-12);
  assert_near(c->p[50].Rb, 0.106, 1e-12);
  vr_spectro_destroy(d);
}

/* The Optics layout is known by content, whatever the name; its errors name
 * the line. */
static void optics_by_content(void **state) {
  (void)state;
  vr_spectro_data *d = NULL;
  vr_error err = {0};
  const char *ok = "{ Units, Wavelength Units } SI Nanometers\n{ Thickness } 3\n"
                   "400 0.8 0.08 0.08\n500 0.85 0.08 0.08\n600 0.86 0.08 0.08\n";
  assert_int_equal(vr_spectro_parse_optics(ok, strlen(ok), "p.txt", &d, &err), VR_OK);
  assert_near(d->curves[0].p[1].nm, 500, 1e-12);
  vr_spectro_destroy(d);
  const char *neg = "{ Thickness } -5.715\n0.4 0.8 0.08 0.08\n";
  assert_int_equal(vr_spectro_parse_optics(neg, strlen(neg), "p.LOF", &d, &err), VR_E_RANGE);
  assert_contains(err.message, "p.LOF:1");
  assert_contains(err.message, "Thickness");
  const char *one = "{ Thickness } 3\n0.4 0.8 0.08 0.08\n";
  assert_int_equal(vr_spectro_parse_optics(one, strlen(one), "p.LOF", &d, &err), VR_E_PARSE);
  assert_contains(err.message, "p.LOF:2");
  assert_contains(err.message, "at least 3");
}

/* CuPCtS_H2O_vis.csv, an Agilent Cary 50 export: title "sample1,,",
 * header "Wavelength (nm),Abs,", 141 rows from 899.9957886 down to
 * 200.0188751 nm, a blank line, then 36 lines of instrument metadata; CRLF.
 * The row "614.9726563,0.5448060036," is T = 10^-0.5448060036. */
static void cary_export(void **state) {
  (void)state;
  vr_spectro_data *d = read_ok(SPECTRO "/CuPCtS_H2O_vis.csv");
  const vr_spectro_curve *c = &d->curves[0];
  assert_int_equal(d->ncurves, 1);
  assert_int_equal(c->n, 141);
  assert_false(d->has_Rf);
  assert_true(isnan(d->thickness_nm));
  assert_near(c->p[0].nm, 200.0188751, 1e-9);
  assert_near(c->p[140].nm, 899.9957886, 1e-9);
  size_t at = 0;
  while (at < c->n && fabs(c->p[at].nm - 614.9726563) > 1e-6) at++;
  assert_true(at < c->n);
  assert_near(c->p[at].T, pow(10.0, -0.5448060036), 1e-12);
  assert_int_equal(c->p[at].line, 60);
  vr_spectro_destroy(d);
}

/* A Lambda/Cary-style T and R pair: title line, %T and %R columns each after
 * its wavelength column, descending, trailing metadata after a blank line. */
static void vendor_pairs(void **state) {
  (void)state;
  vr_spectro_data *d = NULL;
  vr_error err = {0};
  const char *pair = "glassT,,glassR,\r\n"
                     "Wavelength (nm),%T,Wavelength (nm),%R,\r\n"
                     "700.0,90.1,700.0,8.1,\r\n600.0,90.5,600.0,8.2,\r\n500.0,90.9,500.0,8.3,\r\n"
                     "\r\nglassT\r\nCollection Time: 1/15/2014 4:59:54 PM\r\nInstrument  Cary 5000\r\n";
  assert_int_equal(parse(pair, &d, &err), VR_OK);
  const vr_spectro_curve *c = &d->curves[0];
  assert_int_equal(c->n, 3);
  assert_near(c->p[0].nm, 500, 1e-12);
  assert_near(c->p[0].T, 0.909, 1e-12);
  assert_near(c->p[0].Rf, 0.083, 1e-12);
  assert_int_equal(c->p[0].line, 5);
  vr_spectro_destroy(d);
  /* R on other wavelengths than T. */
  const char *skew = "s,,s,\nWavelength (nm),%T,Wavelength (nm),%R,\n700,90,701,8,\n600,90,600,8,\n"
                     "500,90,500,8,\n";
  assert_int_equal(parse(skew, &d, &err), VR_E_PARSE);
  assert_contains(err.message, "x.csv:3");
  assert_contains(err.message, "not at T's wavelength");
  /* Several samples: one pane per file, the samples named. */
  const char *many = "A,,B,\nWavelength (nm),%T,Wavelength (nm),%T,\n700,90,700,80,\n600,90,600,80,\n"
                     "500,90,500,80,\n";
  assert_int_equal(parse(many, &d, &err), VR_E_PARSE);
  assert_contains(err.message, "2 transmittance columns (samples A, B)");
}

static void refusals(void **state) {
  (void)state;
  vr_spectro_data *d = NULL;
  vr_error err = {0};
  /* A negative thickness is refused on its line, not read as positive. */
  assert_int_equal(parse("wavelength_nm,T,Rf\n# thickness: -5.715 mm\n400,0.8,0.08\n500,0.8,0.08\n"
                         "600,0.8,0.08\n", &d, &err), VR_E_RANGE);
  assert_contains(err.message, "x.csv:2");
  assert_contains(err.message, "-5.715");
  assert_int_equal(parse("# thickness: nan mm\nwavelength_nm,T\n400,0.8\n500,0.8\n600,0.8\n", &d, &err),
                   VR_E_RANGE);
  /* Prose that mentions a thickness is no thickness line. */
  assert_int_equal(parse("# the thickness was measured twice\nwavelength_nm,T\n400,0.8\n500,0.8\n"
                         "600,0.8\n", &d, &err), VR_OK);
  assert_true(isnan(d->thickness_nm));
  vr_spectro_destroy(d);
  /* One row is not a spectrum. */
  assert_int_equal(parse("wavelength_nm,T,Rf\n500,0.9,0.08\n", &d, &err), VR_E_PARSE);
  assert_contains(err.message, "x.csv:2");
  assert_contains(err.message, "1 row(s)");
}

/* The verdict: real uncoated glass is described by the dispersion model,
 * the coated low-e pane is not (and the verdict says why). */
static vr_spectro_fit_result fit(const char *path) {
  vr_spectro_data *d = read_ok(path);
  vr_spectro_fit_result r;
  vr_error err = {0};
  if (vr_spectro_fit(d, d->thickness_nm, NULL, &r, &err)) fail_msg("%s", err.message);
  vr_spectro_destroy(d);
  return r;
}

static void verdict(void **state) {
  (void)state;
  const char *uncoated[] = {VR_TEST_DATA "/CLEAR_3.DAT", SPECTRO "/CLEAR5.LOF"};
  for (int i = 0; i < 2; i++) {
    vr_spectro_fit_result r = fit(uncoated[i]);
    assert_true(r.describes);
    assert_true(r.chi2_verdict <= r.chi2_limit);
    assert_near(r.sigma_verdict, VR_SPECTRO_VERDICT_SIGMA, 0);
    assert_contains(r.verdict, "describes the data");
    /* The limit is chi-square's upper 0.1 % point per degree of freedom:
     * 1.24 at 364 (Wilson-Hilferty: (1 - 2/9v + 3.090 sqrt(2/9v))^3). */
    double v = (double)r.dof, z = 3.0902;
    assert_near(r.chi2_limit, pow(1 - 2 / (9 * v) + z * sqrt(2 / (9 * v)), 3), 2e-3);
    vr_spectro_fit_free(&r);
  }
  vr_spectro_fit_result r = fit(SPECTRO "/LOW-E_5.LOF");
  assert_false(r.describes);
  assert_true(r.coated);
  assert_true(r.chi2_verdict > 10 * r.chi2_limit);
  assert_contains(r.verdict, "does NOT describe the data");
  assert_contains(r.verdict, "coated");
  /* Saved only when forced, and then the verdict goes with it. */
  vr_material *m = NULL;
  vr_error err = {0};
  assert_int_equal(vr_spectro_fit_material(&r, "lowe-forced", true, &m, &err), VR_OK);
  assert_near(vr_material_property(m, "fit_describes")->value, 0, 0);
  assert_near(vr_material_property(m, "fit_forced")->value, 1, 0);
  assert_near(vr_material_property(m, "fit_chi2_reduced")->value, r.chi2_verdict, 0);
  assert_contains(m->prov.note, "does NOT describe");
  assert_contains(m->prov.note, "--force");
  vr_material_destroy(m);
  vr_spectro_fit_free(&r);
}

/* A transmittance-only pane: the T figures, no R figures; NFRC 102's T
 * alone gives Windows-CalcEngine's Tvis 0.899260 and Tsol 0.833849. */
static void transmittance_only(void **state) {
  (void)state;
  vr_spectro_data *d = read_ok(VR_TEST_DATA "/CLEAR_3.DAT");
  vr_spectro_curve *c = &d->curves[0];
  for (size_t i = 0; i < c->n; i++) c->p[i].Rf = c->p[i].Rb = NAN;
  vr_standard *std = NULL;
  vr_pane *p = NULL;
  vr_glazing_metrics m;
  vr_error err = {0};
  assert_int_equal(vr_standard_open("nfrc", &std, &err), VR_OK);
  assert_int_equal(vr_pane_from_curve(c, d->thickness_nm, 0, VR_ROUTE_AUTO, NAN, &p, NULL, &err), VR_OK);
  assert_int_equal(vr_glazing_metrics_compute(std, p, &m, &err), VR_OK);
  assert_false(m.has_R);
  assert_near(m.Tvis, 0.899260, 5e-7);
  assert_near(m.Tsol, 0.833849, 5e-7);
  assert_true(isnan(m.Rvis_front) && isnan(m.Rsol_back));
  /* Several panes need R (the inter-reflections), and so does an angle. */
  vr_pane *two[2] = {p, p}, *sys = NULL;
  assert_int_equal(vr_pane_combine(two, 2, &sys, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "no reflectance");
  vr_pane *at = NULL;
  assert_int_equal(vr_pane_from_curve(c, d->thickness_nm, 30, VR_ROUTE_AUTO, NAN, &at, NULL, &err),
                   VR_E_NOT_FOUND);
  vr_pane_destroy(p);
  vr_standard_destroy(std);
  vr_spectro_destroy(d);
}

/* A standard's weight left unmeasured: the Cary file stops at 900 nm, so
 * the solar figure (300-2500 nm) is refused, not integrated over a part. */
static void coverage(void **state) {
  (void)state;
  vr_spectro_data *d = read_ok(SPECTRO "/CuPCtS_H2O_vis.csv");
  vr_standard *std = NULL;
  vr_error err = {0};
  assert_int_equal(vr_standard_open("nfrc", &std, &err), VR_OK);
  vr_spectrum *T = vr_spectro_spectrum(&d->curves[0], 'T', &err);
  double v;
  assert_int_equal(vr_std_average(vr_standard_method(std, "PHOTOPIC"), T, &v, &err), VR_OK);
  assert_int_equal(vr_std_average(vr_standard_method(std, "SOLAR"), T, &v, &err), VR_E_RANGE);
  assert_contains(err.message, "unmeasured");
  vr_spectrum_destroy(T);
  vr_standard_destroy(std);
  vr_spectro_destroy(d);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(lof_clear),    cmocka_unit_test(lof_lowe),
      cmocka_unit_test(optics_by_content), cmocka_unit_test(cary_export),
      cmocka_unit_test(vendor_pairs), cmocka_unit_test(refusals),
      cmocka_unit_test(verdict),      cmocka_unit_test(transmittance_only),
      cmocka_unit_test(coverage),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
