/* The domain-decomposed ray flow: the same image for any number of
 * sub-domains S and threads P (DESIGN §6.5: counter-based randomness keyed
 * by pixel, sample, depth and purpose), rays created equal to rays
 * finished, and the awkward rays: lying in an interface plane, starting on
 * one, bouncing between mirrors that sit in different sub-domains.  Also
 * the scene analysis: passes a scene does not call for are not run. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/domains.h"
#include "vr/geometry.h"
#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"

static vr_matdb *db;
static char dbpath[256];

static int setup(void **state) {
  (void)state;
  snprintf(dbpath, sizeof dbpath, "/tmp/vr_test_flow_%d.db", (int)getpid());
  unlink(dbpath);
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) {
    fprintf(stderr, "%s\n", err.message);
    return -1;
  }
  return 0;
}

static int teardown(void **state) {
  (void)state;
  vr_matdb_close(db);
  unlink(dbpath);
  return 0;
}

static vr_scene *parse(const char *text) {
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), "flow.scn", &s, &err);
  if (st) fprintf(stderr, "parse: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  return s;
}

static vr_render_result *render(vr_scene *s, int S, int P) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = S;
  o.threads = P;
  vr_render_result *r = NULL;
  vr_error err = {0};
  vr_status st = vr_render_scene(s, db, &o, &r, &err);
  if (st) fprintf(stderr, "render: %s\n", err.message);
  assert_int_equal(st, VR_OK);
  assert_true(r->rays_created == r->rays_finished);
  return r;
}

/* A small room with a sphere, a box, two facing silver mirrors and a
 * point light, path traced. */
static const char *ROOM =
    "camera pinhole from=0,-1.8,1.2 to=0,0,1 fov=80 resolution=24x16\n"
    "material wall lambert reflectance=0.6\n"
    "material red lambert reflectance=0.3\n"
    "material mirror db:Ag\n"
    "box min=-2,-2,0 max=2,2,2.5 material=wall\n"
    "sphere center=0.6,0.5,0.5 radius=0.5 material=red\n"
    "box min=-1,0.2,0 max=-0.4,0.8,0.9 material=red\n"
    "rect center=-1.95,0,1.2 normal=1,0,0 size=2,1.5 material=mirror\n"
    "rect center=1.95,0,1.2 normal=-1,0,0 size=2,1.5 material=mirror\n"
    "light point position=0,0,2.2 intensity=300cd\n"
    "render integrator=path spp=4 depth=12 seed=7\n";

static void test_same_image_any_S_P(void **state) {
  (void)state;
  vr_scene *s = parse(ROOM);
  vr_render_result *ref = render(s, 1, 1);
  size_t n = (size_t)ref->width * ref->height * 3;
  double total = 0;
  for (size_t i = 0; i < n; i++) total += ref->xyz[i];
  assert_true(total > 0);
  const int Ss[] = {1, 2, 4, 8}, Ps[] = {1, 2};
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 2; b++) {
      if (Ss[a] == 1 && Ps[b] == 1) continue;
      vr_render_result *r = render(s, Ss[a], Ps[b]);
      for (size_t i = 0; i < n; i++) {
        double x = ref->xyz[i], y = r->xyz[i];
        if (fabs(x - y) > 1e-6 * fmax(fabs(x), fabs(y)) + 1e-12)
          fail_msg("S=%d P=%d: value %zu differs: %.17g vs %.17g", Ss[a], Ps[b], i, x, y);
      }
      if (Ss[a] > 1) assert_true(r->crossings > 0);
      vr_render_result_destroy(r);
    }
  vr_render_result_destroy(ref);
  vr_scene_destroy(s);
}

/* Hits found through the cells equal hits in one cell, for rays in the
 * split planes, starting on them, and random ones. */
static void test_rays_on_interfaces(void **state) {
  (void)state;
  vr_scene *s = parse(ROOM);
  vr_geometry *g = NULL;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(s, &g, &err), VR_OK);
  vr_domains *one = NULL, *many = NULL;
  assert_int_equal(vr_domains_build(g, 1, &one, &err), VR_OK);
  assert_int_equal(vr_domains_build(g, 8, &many, &err), VR_OK);
  /* Collect the split planes through the cells' boxes. */
  unsigned long long seed = 12345;
  int checked = 0;
  for (int i = 0; i < 4000; i++) {
    double o[3], d[3];
    for (int a = 0; a < 3; a++) {
      seed = seed * 6364136223846793005ull + 1442695040888963407ull;
      o[a] = -1.9 + 3.8 * ((seed >> 11) * 0x1.0p-53);
      seed = seed * 6364136223846793005ull + 1442695040888963407ull;
      d[a] = -1 + 2 * ((seed >> 11) * 0x1.0p-53);
    }
    o[2] = 0.1 + fabs(o[2]) * 0.6;
    int cell = i % vr_domains_count(many);
    double lo[3], hi[3];
    vr_domains_cell_bounds(many, cell, lo, hi);
    if (i % 3 == 0) {
      /* Start exactly on a cell face. */
      o[0] = lo[0] > g->bmin[0] ? lo[0] : hi[0];
    } else if (i % 3 == 1) {
      /* Lie in a cell face: no motion across it. */
      o[1] = lo[1] > g->bmin[1] ? lo[1] : hi[1];
      d[1] = 0;
    }
    vr_hit h1, h2;
    bool g1 = false, g2 = false;
    double te;
    int c = vr_domains_locate(one, o, d, 0, &te);
    g1 = vr_domains_intersect(one, c, o, d, 0, INFINITY, &h1);
    double t = 0;
    int steps = 0;
    for (;;) {
      c = vr_domains_locate(many, o, d, t, &te);
      if (vr_domains_intersect(many, c, o, d, t, te, &h2)) {
        g2 = true;
        break;
      }
      if (isinf(te)) break;
      assert_true(te > t); /* strictly forward, no epsilon needed */
      t = te;
      assert_true(++steps < 64);
    }
    assert_int_equal(g1, g2);
    if (g1) {
      assert_int_equal(h1.object, h2.object);
      assert_true(h1.t == h2.t);
      checked++;
    }
  }
  assert_true(checked > 3000);
  vr_domains_destroy(one);
  vr_domains_destroy(many);
  vr_geometry_destroy(g);
  vr_scene_destroy(s);
}

static const vr_pass_record *pass(const vr_render_result *r, const char *name) {
  for (size_t i = 0; i < r->npasses; i++)
    if (!strcmp(r->passes[i].name, name)) return &r->passes[i];
  fail_msg("no pass record '%s'", name);
  return NULL;
}

/* Only the effects a scene calls for. */
static void test_only_needed_passes(void **state) {
  (void)state;
  const char *diffuse_only =
      "camera pinhole from=0,-1.5,1 to=0,0,1 resolution=8x6\n"
      "material wall lambert reflectance=0.5\n"
      "box min=-2,-2,0 max=2,2,2.5 material=wall\n"
      "light point position=0,0,2 intensity=100cd\n"
      "render integrator=photon spp=1 photons=2000 caustic_photons=2000\n";
  vr_scene *s = parse(diffuse_only);
  vr_render_result *r = render(s, 2, 1);
  assert_false(pass(r, "caustic photons")->ran);
  assert_true(pass(r, "global photons")->ran);
  assert_false(pass(r, "uv")->ran);
  assert_false(pass(r, "dispersion")->ran);
  assert_true(r->photons_global > 0);
  assert_int_equal(r->photons_caustic, 0);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);

  s = parse(ROOM); /* mirrors: caustics are possible, once photon mapping is asked for */
  s->settings.integrator = VR_INT_PHOTON;
  s->settings.photons = s->settings.caustic_photons = 4000;
  r = render(s, 1, 2);
  assert_true(pass(r, "caustic photons")->ran);
  assert_true(r->photons_caustic > 0);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
}

/* An empty scene and a light without power render without crashing. */
static void test_empty_and_powerless(void **state) {
  (void)state;
  vr_scene *s = parse("camera pinhole from=0,0,0 to=0,1,0 resolution=4x4\n");
  vr_render_result *r = render(s, 4, 2);
  for (size_t i = 0; i < 48; i++) assert_true(r->xyz[i] == 0.0);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
  s = parse("camera pinhole from=0,-0.5,1 to=0,0,1 resolution=4x4\n"
            "material wall lambert reflectance=0.5\n"
            "box min=-1,-1,0 max=1,1,2 material=wall\n"
            "light point position=0,0,1 intensity=0cd\n"
            "render integrator=photon spp=1 photons=1000\n");
  r = render(s, 2, 2);
  for (size_t i = 0; i < 48; i++) assert_true(r->xyz[i] == 0.0);
  vr_render_result_destroy(r);
  vr_scene_destroy(s);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_image_any_S_P),
      cmocka_unit_test(test_rays_on_interfaces),
      cmocka_unit_test(test_only_needed_passes),
      cmocka_unit_test(test_empty_and_powerless),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
