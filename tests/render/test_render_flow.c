/* The domain-decomposed ray flow: the same image for any number of
 * sub-domains S and threads P (DESIGN §6.5: counter-based randomness keyed
 * by pixel, sample, depth and purpose), and the same again from the
 * image-space tile scheduler; rays created equal to rays finished, also
 * when every ray spawns more in other cells; image tiles that cover every
 * pixel once; and the awkward rays: lying in an interface plane, starting
 * on one, bouncing between mirrors that sit in different sub-domains.  Also
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

#include "render_test_util.h"
#include "vr/domains.h"
#include "vr/flow.h"
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

static vr_scene *parse(const char *text) { return parse_text(text, "flow.scn"); }

static vr_render_result *render_mode(vr_scene *s, int S, int P, bool image_space) {
  vr_render_result *r = render_scene_with(s, db, S, P, false, image_space);
  assert_true(r->rays_created == r->rays_finished);
  return r;
}

static vr_render_result *render(vr_scene *s, int S, int P) { return render_mode(s, S, P, false); }

/* Fails unless the two films agree to 1e-6 relative in every value. */
static void same_film(const vr_render_result *a, const vr_render_result *b, const char *what) {
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  size_t n = (size_t)a->width * a->height * 3;
  for (size_t i = 0; i < n; i++) {
    double x = a->xyz[i], y = b->xyz[i];
    if (fabs(x - y) > 1e-6 * fmax(fabs(x), fabs(y)) + 1e-12)
      fail_msg("%s: value %zu differs: %.17g vs %.17g", what, i, x, y);
  }
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
      char what[32];
      snprintf(what, sizeof what, "S=%d P=%d", Ss[a], Ps[b]);
      same_film(ref, r, what);
      assert_true(r->rays_created == ref->rays_created);
      if (Ss[a] > 1) assert_true(r->crossings > 0);
      vr_render_result_destroy(r);
    }
  vr_render_result_destroy(ref);
  vr_scene_destroy(s);
}

/* Image space (tiles over the whole scene, each worker tracing its tiles'
 * rays depth first on its own stack) gives the decomposed image: the same
 * rays, keyed by pixel and sample, only traced in another order.  Path
 * tracing in the room, then photon mapping with its photon pass. */
static void test_image_space_same_image(void **state) {
  (void)state;
  vr_scene *s = parse(ROOM);
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) {
      s->settings.integrator = VR_INT_PHOTON;
      s->settings.photons = s->settings.caustic_photons = 4000;
    }
    vr_render_result *ref = render(s, 4, 2);
    assert_true(ref->crossings > 0);
    for (int P = 1; P <= 2; P++) {
      vr_render_result *r = render_mode(s, 4, P, true);
      char what[64];
      snprintf(what, sizeof what, "%s, image space P=%d vs S=4 P=2",
               pass ? "photon mapping" : "path tracing", P);
      same_film(ref, r, what);
      /* One cell: nothing to cross, and the same rays as the flow made. */
      assert_int_equal(r->crossings, 0);
      assert_true(r->rays_created == ref->rays_created);
      assert_true(r->rays_camera == ref->rays_camera);
      assert_true(r->rays_shadow == ref->rays_shadow);
      assert_true(r->rays_photon == ref->rays_photon);
      if (pass == 1) assert_true(r->photons_global == ref->photons_global);
      vr_render_result_destroy(r);
    }
    vr_render_result_destroy(ref);
  }
  vr_scene_destroy(s);
}

/* Camera tiles: square, clipped at the edges, every pixel in exactly one;
 * and a render whose size is no multiple of the tile makes exactly one
 * camera ray per pixel and sample (Whitted in a diffuse box: no bounce) and
 * lights every pixel, in both schedulers. */
static void test_tiles_cover_image(void **state) {
  (void)state;
  const int sizes[][2] = {{1, 1}, {16, 16}, {17, 5}, {37, 21}, {320, 240}, {5, 100}};
  for (size_t k = 0; k < sizeof sizes / sizeof sizes[0]; k++) {
    int W = sizes[k][0], H = sizes[k][1];
    long n = vr_flow_tiles(W, H);
    assert_int_equal(n, (long)((W + VR_FLOW_TILE - 1) / VR_FLOW_TILE) *
                            ((H + VR_FLOW_TILE - 1) / VR_FLOW_TILE));
    int *seen = calloc((size_t)W * H, sizeof *seen);
    assert_non_null(seen);
    for (long u = 0; u < n; u++) {
      int x0, y0, x1, y1;
      vr_flow_tile(W, H, u, &x0, &y0, &x1, &y1);
      assert_true(x0 >= 0 && x0 < x1 && x1 <= W && x1 - x0 <= VR_FLOW_TILE);
      assert_true(y0 >= 0 && y0 < y1 && y1 <= H && y1 - y0 <= VR_FLOW_TILE);
      for (int y = y0; y < y1; y++)
        for (int x = x0; x < x1; x++) seen[y * W + x]++;
    }
    for (int i = 0; i < W * H; i++) assert_int_equal(seen[i], 1);
    free(seen);
  }
  assert_int_equal(vr_flow_tiles(0, 10), 0);

  vr_scene *s = parse("camera pinhole from=0,-1.5,1 to=0,0,1 fov=70 resolution=37x21\n"
                      "material wall lambert reflectance=0.5\n"
                      "box min=-2,-2,0 max=2,2,2.5 material=wall\n"
                      "light point position=0,0,2 intensity=100cd\n"
                      "render integrator=whitted spp=2 seed=3\n");
  vr_render_result *ref = NULL;
  for (int image = 0; image < 2; image++) {
    vr_render_result *r = render_mode(s, image ? 1 : 2, 2, image);
    assert_int_equal(r->rays_camera, 37 * 21 * 2);
    for (int i = 0; i < 37 * 21; i++) assert_true(r->xyz[3 * i + 1] > 0);
    if (ref) {
      same_film(ref, r, "whitted, image space vs S=2");
      vr_render_result_destroy(r);
    } else {
      ref = r;
    }
  }
  vr_render_result_destroy(ref);
  vr_scene_destroy(s);
}

/* Termination under heavy spawning: every closest-hit ray pushes two more
 * from its hit point, in whatever cell that is, down to depth 9, and every
 * unit starts 16 rays, so the run must trace exactly 16 (2^10 - 1) rays per
 * unit before it ends, with rays handed between the workers all along. */
typedef struct tree_ctx {
  struct {
    _Alignas(64) long rays; /* per worker */
  } seen[2];
  double lo[3], hi[3];
} tree_ctx;

static double hash01(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return (double)((z ^ (z >> 31)) >> 11) * 0x1.0p-53;
}

static void tree_ray(const tree_ctx *c, const double *from, uint64_t id, int depth,
                     vr_flow_worker *w) {
  vr_ray r;
  memset(&r, 0, sizeof r);
  for (int a = 0; a < 3; a++)
    r.org[a] = from ? from[a] : c->lo[a] + (c->hi[a] - c->lo[a]) * (0.1 + 0.8 * hash01(id * 8 + a));
  double z = 1 - 2 * hash01(id * 8 + 3), ph = 2 * M_PI * hash01(id * 8 + 4);
  r.dir[0] = sqrt(1 - z * z) * cos(ph);
  r.dir[1] = sqrt(1 - z * z) * sin(ph);
  r.dir[2] = z;
  if (from)
    for (int a = 0; a < 3; a++) r.org[a] += 1e-4 * r.dir[a];
  r.tmax = INFINITY;
  r.kind = VR_RAY_CLOSEST;
  memcpy(r.payload, &id, sizeof id);
  memcpy(r.payload + 8, &depth, sizeof depth);
  vr_flow_push(w, &r);
}

static void tree_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  tree_ctx *c = ctx;
  c->seen[vr_flow_worker_index(w)].rays++;
  uint64_t id;
  int depth;
  memcpy(&id, r->payload, sizeof id);
  memcpy(&depth, r->payload + 8, sizeof depth);
  if (depth == 9) return;
  double at[3];
  for (int a = 0; a < 3; a++) at[a] = hit ? hit->p[a] : r->org[a];
  for (int k = 0; k < 2; k++) tree_ray(c, at, id * 2 + (uint64_t)k + 1, depth + 1, w);
}

static bool tree_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
  return false;
}

static void tree_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)ctx, (void)w, (void)r, (void)reached;
}

static void tree_generate(void *ctx, vr_flow_worker *w, long unit) {
  for (int i = 0; i < 16; i++) tree_ray(ctx, NULL, (uint64_t)unit * 1000003u + (uint64_t)i, 0, w);
}

static void test_termination_many_spawned(void **state) {
  (void)state;
  vr_scene *s = parse(ROOM);
  vr_geometry *g = NULL;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(s, &g, &err), VR_OK);
  const vr_flow_ops ops = {tree_closest, tree_shadow_hit, tree_shadow_done, tree_generate,
                           NULL, NULL, NULL};
  const long units = 40, per_unit = 16 * 1023;
  for (int S = 1; S <= 8; S *= 8) {
    vr_domains *d = NULL;
    assert_int_equal(vr_domains_build(g, S, &d, &err), VR_OK);
    for (int image = 0; image < 2; image++)
      for (int P = 1; P <= 2; P++) {
        tree_ctx c;
        memset(&c, 0, sizeof c);
        memcpy(c.lo, g->bmin, sizeof c.lo);
        memcpy(c.hi, g->bmax, sizeof c.hi);
        vr_flow_stats st;
        vr_status rc = (image ? vr_flow_run_image_space : vr_flow_run)(d, &ops, &c, units, P, NULL,
                                                                      NULL, &st, &err);
        assert_int_equal(rc, VR_OK);
        assert_true(st.created == (uint64_t)(units * per_unit));
        assert_true(st.finished == st.created);
        assert_true(st.closest == st.created && st.shadow == 0);
        assert_true(st.by_purpose[0] == st.created);
        assert_int_equal(c.seen[0].rays + c.seen[1].rays, units * per_unit);
        if (S > 1) assert_true(st.crossings > 0);
        if (P == 1) assert_int_equal(c.seen[1].rays, 0);
      }
    vr_domains_destroy(d);
  }
  vr_geometry_destroy(g);
  vr_scene_destroy(s);
}

/* The cap on waiting rays holds whatever a unit's size (up to half the
 * cap), on one worker and on two: a unit starts only when the largest unit
 * made so far fits below the cap with the rays waiting and those of the
 * units being generated.  Units of 1500 rays under a cap of 3500 hold no
 * more rays at once than units of one ray (which fill the queues to the
 * cap one at a time).  Before the rule a unit started while fewer than
 * 3500 waited, so the queues could hold up to 5000 rays (measured on one
 * worker: 1.79 MB against 1.32 MB). */
static long g_unit_rays;

static void flat_generate(void *ctx, vr_flow_worker *w, long unit) {
  for (long i = 0; i < g_unit_rays; i++)
    tree_ray(ctx, NULL, (uint64_t)unit * 1000003u + (uint64_t)i, 9, w); /* depth 9: no children */
}

static void test_cap_holds_for_large_units(void **state) {
  (void)state;
  vr_scene *s = parse(ROOM);
  vr_geometry *g = NULL;
  vr_domains *d = NULL;
  vr_error err = {0};
  assert_int_equal(vr_geometry_build(s, &g, &err), VR_OK);
  assert_int_equal(vr_domains_build(g, 2, &d, &err), VR_OK);
  const vr_flow_ops ops = {tree_closest, tree_shadow_hit, tree_shadow_done, flat_generate,
                           NULL, NULL, NULL};
  for (int threads = 1; threads <= 2; threads++) {
    size_t peak[2];
    const long per_unit[2] = {1, 1500}, units[2] = {12000, 8};
    for (int k = 0; k < 2; k++) {
      tree_ctx c;
      memset(&c, 0, sizeof c);
      memcpy(c.lo, g->bmin, sizeof c.lo);
      memcpy(c.hi, g->bmax, sizeof c.hi);
      g_unit_rays = per_unit[k];
      vr_flow_options o;
      vr_flow_options_default(&o);
      o.threads = threads;
      o.max_pending = 3500;
      vr_flow_stats st;
      assert_int_equal(vr_flow_run_with(d, &ops, &c, units[k], &o, &st, &err), VR_OK);
      assert_true(st.created == (uint64_t)(units[k] * per_unit[k]));
      peak[k] = st.peak_queue_bytes;
      print_message("    %d worker(s), units of %ld rays: peak %.2f MB in the queues\n", threads,
                    per_unit[k], peak[k] / 1e6);
    }
    if ((double)peak[1] > 1.1 * (double)peak[0])
      fail_msg("%d worker(s): units of 1500 rays held %zu bytes, units of 1 ray %zu: the cap was "
               "overshot", threads, peak[1], peak[0]);
  }
  vr_domains_destroy(d);
  vr_geometry_destroy(g);
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
  int checked = 0, on_faces = 0;
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
    /* Only faces between cells: a face on the scene's bounds is the plane
     * of the room's outer walls, and a ray lying in a wall's plane meets
     * the next wall exactly on their shared edge, where any BVH may or may
     * not report it (a grazing case, not an interface). */
    if (i % 3 == 0 && (lo[0] > g->bmin[0] || hi[0] < g->bmax[0])) {
      /* Start exactly on a cell face. */
      o[0] = lo[0] > g->bmin[0] ? lo[0] : hi[0];
      on_faces++;
    } else if (i % 3 == 1 && (lo[1] > g->bmin[1] || hi[1] < g->bmax[1])) {
      /* Lie in a cell face: no motion across it. */
      o[1] = lo[1] > g->bmin[1] ? lo[1] : hi[1];
      d[1] = 0;
      on_faces++;
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
    if (g1 != g2)
      fail_msg("ray %d (o %.17g %.17g %.17g, d %.17g %.17g %.17g): %s with one cell, %s with eight (t %.9g, object %u)",
               i, o[0], o[1], o[2], d[0], d[1], d[2], g1 ? "hit" : "miss", g2 ? "hit" : "miss",
               g1 ? h1.t : h2.t, g1 ? h1.object : h2.object);
    if (g1) {
      assert_int_equal(h1.object, h2.object);
      assert_true(h1.t == h2.t);
      checked++;
    }
  }
  assert_true(checked > 3000);
  print_message("  %d of 4000 rays start on or lie in an interface\n", on_faces);
  assert_true(on_faces > 1000);
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
      cmocka_unit_test(test_image_space_same_image),
      cmocka_unit_test(test_tiles_cover_image),
      cmocka_unit_test(test_termination_many_spawned),
      cmocka_unit_test(test_cap_holds_for_large_units),
      cmocka_unit_test(test_rays_on_interfaces),
      cmocka_unit_test(test_only_needed_passes),
      cmocka_unit_test(test_empty_and_powerless),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
