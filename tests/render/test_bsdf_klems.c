/* A BSDF XML file as a material (bsdf file=F.xml): sampling consistent
 * with evaluation (weight = f |cos| / pdf, pdf integrating to 1, the
 * weight equal to the matrix row's or column's sum), a clear pane written
 * as XML transmitting straight through within its patch, and the patch
 * conventions against Radiance's own evaluation of genBSDF's louvred
 * shutter (tests/data/bsdf/, README.md there for the Radiance run). */
#include "bsdf_test_util.h"

#include "vr/bsdf_xml.h"

static vr_bsdf *klems_bsdf(const char *path, const double up[3]) {
  vr_scene_material sm = test_sm("x");
  sm.source = VR_MATSRC_BSDF_XML;
  sm.bsdf_file = (char *)path;
  for (int i = 0; i < 3; i++) sm.bsdf_up[i] = up ? up[i] : NAN;
  return make_bsdf(&sm, NULL, NULL);
}

/* x written to a temporary file and made a material (up +z); x freed. */
static vr_bsdf *bsdf_of(vr_bsdf_xml *x) {
  char path[] = "/tmp/vr_klems_XXXXXX.xml";
  int fd = mkstemps(path, 4);
  assert_true(fd >= 0);
  close(fd);
  assert_int_equal(vr_bsdf_xml_write(path, x, NULL), VR_OK);
  vr_bsdf_xml_destroy(x);
  double up[3] = {0, 0, 1};
  vr_bsdf *b = klems_bsdf(path, up);
  unlink(path);
  return b;
}

static const char *data_file(const char *name) {
  static char path[512];
  snprintf(path, sizeof path, "%s/bsdf/%s", VR_TEST_DATA, name);
  return path;
}

/* Sampling and evaluation agree, for radiance and importance, from either
 * side: the sampled weight equals f |cos| / pdf at the sampled direction,
 * and is the same for every sample (the row's or column's sum of the
 * matrix times the projected solid angles); the pdf integrates to 1 over
 * the sphere (checked by uniform sphere sampling). */
static void sampling_matches_eval(void **state) {
  (void)state;
  vr_bsdf *b = klems_bsdf(data_file("SquareSlat_genBSDF.xml.gz"), NULL);
  assert_true(vr_bsdf_is_klems(b));
  assert_int_equal(vr_bsdf_lobes(b), VR_LOBE_GLOSSY_R | VR_LOBE_GLOSSY_T);
  assert_false(vr_bsdf_is_thin(b));
  vr_vec3 n = {0, -1, 0};
  double nm[1] = {550};
  for (int mode = 0; mode < 2; mode++)
    for (int side = 0; side < 2; side++) {
      vr_vec3 wo = dir_at(35 * DEG, 70 * DEG); /* about +z */
      /* put wo on the front (-y) or the back (+y) of n */
      wo = (vr_vec3){wo.x, side ? wo.z : -wo.z, wo.y};
      double w0 = NAN;
      int trans = 0, total = 20000;
      for (int i = 0; i < total; i++) {
        vr_bsdf_sample s;
        if (!vr_bsdf_sample_dir(b, NAN, n, wo, 1, nm, (vr_transport)mode, u01(3, i, 0),
                                u01(3, i, 1), u01(3, i, 2), &s))
          fail_msg("sample %d refused", i);
        if (isnan(w0)) w0 = s.weight[0];
        assert_near(s.weight[0], w0, 1e-12 * w0);
        double f, pdf;
        vr_bsdf_eval(b, NAN, n, wo, s.wi, 1, nm, (vr_transport)mode, &f, &pdf);
        double c = fabs(vr_vec3_dot(n, s.wi));
        assert_near(pdf, s.pdf, 1e-6 * s.pdf);
        assert_near(f * c / pdf, s.weight[0], 1e-6 * w0);
        trans += vr_vec3_dot(n, s.wi) * vr_vec3_dot(n, wo) < 0;
        assert_int_equal(s.lobe, vr_vec3_dot(n, s.wi) * vr_vec3_dot(n, wo) < 0 ? VR_LOBE_GLOSSY_T
                                                                              : VR_LOBE_GLOSSY_R);
      }
      /* The louvres let through about a third and reflect about a half. */
      assert_true(trans > total / 10 && trans < total * 9 / 10);
      /* Integral of the pdf over the sphere, uniform sphere samples: 1
       * within 5 standard errors of the estimate (about 1 %). */
      double sum = 0, sum2 = 0;
      int m = 200000;
      for (int i = 0; i < m; i++) {
        double z = 1 - 2 * u01(5, i, 0), r = sqrt(fmax(0, 1 - z * z)), ph = 2 * M_PI * u01(5, i, 1);
        vr_vec3 wi = {r * cos(ph), r * sin(ph), z};
        double f, pdf;
        vr_bsdf_eval(b, NAN, n, wo, wi, 1, nm, (vr_transport)mode, &f, &pdf);
        double v = pdf * 4 * M_PI;
        sum += v, sum2 += v * v;
      }
      double mean = sum / m, se = sqrt((sum2 / m - mean * mean) / m);
      print_message("mode %d side %d: weight %.4f, pdf integral %.4f +- %.4f\n", mode, side, w0,
                    mean, se);
      assert_near(mean, 1.0, 5 * se);
    }
  vr_bsdf_destroy(b);
}

/* A clear pane as BSDF XML (diagonal matrices): light sampled through it
 * leaves in the incident direction's own patch, with the pane's T + R at
 * that patch as the weight; vr_bsdf_rta gives the patch's T and R. */
static void clear_pane_goes_straight(void **state) {
  (void)state;
  vr_klems_basis kb;
  vr_klems_full(&kb);
  vr_bsdf_xml *x;
  assert_int_equal(vr_bsdf_xml_create(&kb, 1, &x, NULL), VR_OK);
  snprintf(x->bands[0].name, sizeof x->bands[0].name, "Visible");
  for (int p = 0; p < kb.n; p++) {
    double t, ph, lam = vr_klems_lambda(&kb, p);
    vr_klems_direction(&kb, p, &t, &ph);
    double T = 0.9 * cos(t * DEG), R = 0.08 + 0.5 * pow(1 - cos(t * DEG), 5);
    x->bands[0].m[VR_BSDF_TF][p * kb.n + p] = x->bands[0].m[VR_BSDF_TB][p * kb.n + p] = T / lam;
    x->bands[0].m[VR_BSDF_RF][p * kb.n + p] = x->bands[0].m[VR_BSDF_RB][p * kb.n + p] = R / lam;
  }
  vr_bsdf *b = bsdf_of(x); /* frees x */
  vr_vec3 n = {0, -1, 0};
  double nm[1] = {500};
  /* Light from the front at 40 deg (ring 5, 35-45 deg). */
  vr_vec3 from = {sin(40 * DEG) * cos(30 * DEG), -cos(40 * DEG), sin(40 * DEG) * sin(30 * DEG)};
  double R, T, A;
  vr_bsdf_rta(b, NAN, vr_vec3_dot(n, from), 500, &R, &T, &A);
  /* The file holds 9 significant digits. */
  assert_near(T, 0.9 * cos(40 * DEG), 1e-8);
  assert_near(R, 0.08 + 0.5 * pow(1 - cos(40 * DEG), 5), 1e-8);
  for (int i = 0; i < 2000; i++) {
    vr_bsdf_sample s;
    assert_true(vr_bsdf_sample_dir(b, NAN, n, from, 1, nm, VR_TRANSPORT_IMPORTANCE, u01(7, i, 0),
                                   u01(7, i, 1), u01(7, i, 2), &s));
    /* The column's sum: the pane's T + R at 40 deg, as written (9 digits). */
    assert_near(s.weight[0], 0.9 * cos(40 * DEG) + 0.08 + 0.5 * pow(1 - cos(40 * DEG), 5), 2e-8);
    if (s.lobe != VR_LOBE_GLOSSY_T) continue;
    /* Within the patch: theta in 35-45 deg, azimuth within 7.5 deg of the
     * straight line's (24 patches in the ring). */
    vr_vec3 straight = {-from.x, -from.y, -from.z};
    double th = acos(fabs(vr_vec3_dot(n, s.wi))) / DEG;
    assert_true(th >= 35 - 1e-9 && th <= 45 + 1e-9);
    double a1 = atan2(s.wi.z, s.wi.x), a2 = atan2(straight.z, straight.x);
    double d = fabs(remainder(a1 - a2, 2 * M_PI)) / DEG;
    assert_true(d <= 7.5 + 1e-9);
  }
  vr_bsdf_destroy(b);
}

/* Radiance 6.1 (rtrace -ab 0 -av 0 0 0, tests/data/bsdf/README.md): the
 * louvred shutter as 'void BSDF shade 6 0 SquareSlat_genBSDF.xml 0 0 1 .'
 * on a 100 x 100 m polygon in the plane y = 0 facing -y, a 0.5 deg source
 * of radiance 1000 W/sr/m2 towards (0.3, -0.8, 0.4), viewed from (0, 1, 0)
 * in four directions d: the radiance of the window.  Radiance evaluates a
 * BSDF backwards, with the view ray as the incident direction, and the
 * 'Transmission Front' matrix for it (it relies on reciprocity, which
 * genBSDF's louvres do not have: checkBSDF reports 47 % mean reciprocity
 * error).  So its figures are our material's for light going the other
 * way, from the viewer's side (the back, incident) to the source's side
 * (the front, exiting), in a file whose 'Transmission Back' holds the
 * 'Transmission Front' data: that checks the incident and exiting patch
 * conventions, theta and azimuth, on both sides.  Radiance jitters its
 * samples over the source's disc, which crosses patch edges: 2.5 %. */
static void patches_as_radiance_reads_them(void **state) {
  (void)state;
  vr_bsdf_xml *x;
  vr_error err = {0};
  if (vr_bsdf_xml_read(data_file("SquareSlat_genBSDF.xml.gz"), &x, &err)) fail_msg("%s", err.message);
  vr_bsdf_band *vis = (vr_bsdf_band *)vr_bsdf_xml_band(x, "Visible");
  size_t nn = (size_t)x->basis.n * x->basis.n;
  memcpy(vis->m[VR_BSDF_TB], vis->m[VR_BSDF_TF], nn * sizeof(double));
  vr_bsdf *b = bsdf_of(x); /* frees x */
  static const double D[4][3] = {{0, -1, 0}, {-0.3, -0.8, -0.4}, {0.2, -0.9, 0.1}, {-0.5, -0.7, 0.2}};
  static const double RADIANCE[4] = {2.191570e-03, 2.164593e-03, 3.207470e-03, 2.625925e-03};
  vr_vec3 n = {0, -1, 0};
  double s[3] = {0.3, -0.8, 0.4};
  vr_normalize3(s);
  vr_vec3 sun = vr_vec3_of(s);
  double omega = 2 * M_PI * (1 - cos(0.25 * DEG)), E = 1000 * omega * fabs(vr_vec3_dot(n, sun));
  double nm[1] = {550};
  for (int k = 0; k < 4; k++) {
    double d[3] = {D[k][0], D[k][1], D[k][2]};
    vr_normalize3(d);
    vr_vec3 toward_viewer = {-d[0], -d[1], -d[2]};
    double f;
    /* Light from the viewer's side (wi) to the source's side (wo). */
    vr_bsdf_eval(b, NAN, n, sun, toward_viewer, 1, nm, VR_TRANSPORT_RADIANCE, &f, NULL);
    print_message("direction %d: ours %.6e, Radiance %.6e\n", k, f * E, RADIANCE[k]);
    assert_near(f * E, RADIANCE[k], 0.025 * RADIANCE[k]);
  }
  vr_bsdf_destroy(b);
}

/* A file the renderer cannot use is refused with its name. */
static void refusals(void **state) {
  (void)state;
  vr_scene_material sm = test_sm("x");
  sm.source = VR_MATSRC_BSDF_XML;
  sm.bsdf_up[0] = sm.bsdf_up[1] = sm.bsdf_up[2] = NAN;
  sm.bsdf_file = "/nonexistent/shade.xml";
  vr_bsdf *b = NULL;
  vr_error err = {0};
  assert_int_equal(vr_bsdf_create(&sm, NULL, NULL, 380, 780, &b, &err), VR_E_IO);
  assert_contains(err.message, "/nonexistent/shade.xml");
  /* Only a Solar band: the renderer needs the Visible one. */
  vr_klems_basis kb;
  vr_klems_full(&kb);
  vr_bsdf_xml *x;
  assert_int_equal(vr_bsdf_xml_create(&kb, 1, &x, NULL), VR_OK);
  snprintf(x->bands[0].name, sizeof x->bands[0].name, "Solar");
  char path[] = "/tmp/vr_klems_XXXXXX.xml";
  int fd = mkstemps(path, 4);
  close(fd);
  assert_int_equal(vr_bsdf_xml_write(path, x, NULL), VR_OK);
  vr_bsdf_xml_destroy(x);
  sm.bsdf_file = path;
  assert_int_equal(vr_bsdf_create(&sm, NULL, NULL, 380, 780, &b, &err), VR_E_NOT_FOUND);
  assert_contains(err.message, "no Visible band");
  unlink(path);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(sampling_matches_eval),
      cmocka_unit_test(clear_pane_goes_straight),
      cmocka_unit_test(patches_as_radiance_reads_them),
      cmocka_unit_test(refusals),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
