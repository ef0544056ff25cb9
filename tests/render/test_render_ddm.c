/* Domain decomposition for real (docs/ddm.md): sub-domains that own their
 * data, loaded and unloaded under a memory budget, and the geometry cache
 * they live in.  What must hold (issue 13):
 *   - the image is the same (1e-6 relative per value) with and without a
 *     budget, for S = 1, 8 and 27, with budgets that force loads and
 *     unloads; rays created = rays finished (the flow's counting);
 *   - photon maps stored per cell give the image of one map, and the
 *     photochromic state maps held per cell give the image of one map;
 *   - a budget too small for one cell is refused, naming the cell;
 *   - the cache is built once and reused; a changed mesh invalidates it, a
 *     new spp does not; a damaged, truncated or foreign cell file and a
 *     damaged manifest are detected and the cache rebuilt, and the image
 *     after the rebuild is the image before.
 * The expected values are the renderer's own unbudgeted S = 1 image: the
 * decomposition must change nothing, so any difference is a defect. */
#include "vr_test.h"

#include <sys/stat.h>

#include "vr/domains.h"
#include "vr/matdb.h"
#include "vr/render.h"
#include "vr/scene.h"

static vr_matdb *db;
static char dbpath[300], tmpdir[256];

static vr_spectrum *flat(double v) {
  double nm[2] = {250, 2500}, val[2] = {v, v};
  return vr_spectrum_create(2, nm, val, NULL);
}

static int setup(void **state) {
  (void)state;
  snprintf(tmpdir, sizeof tmpdir, "/tmp/vr_test_ddm_%d", (int)getpid());
  mkdir(tmpdir, 0755);
  snprintf(dbpath, sizeof dbpath, "%s/materials.db", tmpdir);
  vr_error err = {0};
  if (vr_matdb_open(dbpath, 0, &db, &err)) return -1;
  vr_material *m = vr_material_create("glass-152", VR_KIND_DIELECTRIC, &err);
  vr_material_add_spectrum(m, "n", flat(1.52), &err);
  vr_material_add_spectrum(m, "k", flat(0.0), &err);
  if (vr_matdb_save(db, m, &err)) return -1;
  vr_material_destroy(m);
  /* A smooth photochromic glass (the shape of test_render_glass.c's). */
  m = vr_material_create("pc-ddm", VR_KIND_CHROMOGENIC, &err);
  double nm[5] = {280, 400, 550, 700, 2500}, t0[5] = {0.6, 0.8, 0.82, 0.8, 0.8},
         dod[5] = {0.5, 0.3, 0.6, 1.0, 1.0};
  vr_material_add_spectrum(m, "T0", vr_spectrum_create(5, nm, t0, NULL), &err);
  vr_material_add_spectrum(m, "dOD", vr_spectrum_create(5, nm, dod, NULL), &err);
  vr_material_add_property(m, "chromogenic_type", "photochromic", NAN, NULL, &err);
  vr_material_add_parameter(m, "K_ref", 5.0, NAN, "W/m2", &err);
  vr_material_add_parameter(m, "Ea", 40000, NAN, "J/mol", &err);
  vr_material_add_parameter(m, "T_ref", 298.15, NAN, "K", &err);
  if (vr_matdb_save(db, m, &err)) return -1;
  vr_material_destroy(m);
  return 0;
}

static int teardown(void **state) {
  (void)state;
  vr_matdb_close(db);
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  return system(cmd) == 0 ? 0 : -1;
}

/* A room with the sample meshes, a mirror, a glass sphere, a photochromic
 * pane in the sun and a lamp: every kind of data a cell holds. */
static char *room_text(const char *integrator, int spp) {
  char *t = malloc(8192);
  const char *m = VR_SOURCE_DIR "/samples/meshes";
  snprintf(t, 8192,
           "camera pinhole from=2.5,1.6,1.5 to=2.5,-2,1.0 fov=80 resolution=40x30\n"
           "material wall lambert reflectance=0.6\n"
           "material red lambert reflectance=0.3\n"
           "material mirror db:Ag\n"
           "material glass db:glass-152\n"
           "material pc db:pc-ddm\n"
           "box min=0,-2,0 max=5,2,2.7 material=wall\n"
           "mesh %s/bed.obj material=red rotate=0,0,1,90 translate=1.05,-0.45,0\n"
           "mesh %s/lamp.obj material=mirror translate=4.3,-1.3,0.75\n"
           "mesh %s/table.ply material=red rotate=0,0,1,90 translate=4.3,-0.9,0\n"
           "sphere center=3,0.5,0.4 radius=0.35 material=glass\n"
           "rect center=0.02,0,1.3 normal=1,0,0 size=1.5,1 material=mirror\n"
           "rect center=2.5,-1.98,1.5 normal=0,1,0 size=3.6,1.2 material=pc texels=6,3\n"
           "light point position=2.5,0,2.4 intensity=200cd\n"
           "light point position=2.5,-1.5,1.5 intensity=100cd\n"
           "render integrator=%s spp=%d depth=6 seed=3 photons=60000 knn=30\n",
           m, m, m, integrator, spp);
  return t;
}

static vr_scene *parse(const char *text) {
  vr_scene *s = NULL;
  vr_error err = {0};
  vr_status st = vr_scene_parse(text, strlen(text), "ddm.scn", &s, &err);
  if (st) fail_msg("parse: %s", err.message);
  return s;
}

static vr_render_result *render(const vr_scene *s, int S, size_t budget, const char *cache,
                                vr_status want, vr_error *err_out) {
  vr_render_options o;
  vr_render_options_default(&o);
  o.subdomains = S;
  o.threads = 2;
  o.memory_budget = budget;
  o.cache_dir = cache;
  vr_render_result *r = NULL;
  vr_error err = {0};
  vr_status st = vr_render_scene(s, db, &o, &r, &err);
  if (err_out) *err_out = err;
  if (st != want) fail_msg("render S=%d budget=%zu: status %d (%s), expected %d", S, budget, st,
                           err.message, want);
  if (r) assert_true(r->rays_created == r->rays_finished);
  return r;
}

static void same_film(const vr_render_result *a, const vr_render_result *b, const char *what) {
  assert_int_equal(a->width, b->width);
  size_t n = (size_t)a->width * a->height * 3;
  double total = 0;
  for (size_t i = 0; i < n; i++) {
    double x = a->xyz[i], y = b->xyz[i];
    total += x;
    if (!(fabs(x - y) <= 1e-6 * fmax(fabs(x), fabs(y)) + 1e-12))
      fail_msg("%s: value %zu differs: %.17g vs %.17g", what, i, x, y);
  }
  assert_true(total > 0);
}

/* The camera's film, which counts in the budget: 3 XYZ and the bins per
 * pixel, in doubles. */
static size_t film_bytes(const vr_render_result *r) {
  return (size_t)r->width * (size_t)r->height * (3 + r->nbins) * sizeof(double);
}

/* What cells cost, from a render's cache: sizes of loading cell c. */
static size_t budget_for(const vr_scene *s, int S, int cells) {
  vr_domains_options o;
  vr_domains_options_default(&o);
  o.subdomains = S;
  vr_domains *d = NULL;
  vr_error err = {0};
  if (vr_domains_open(s, &o, &d, &err)) fail_msg("open: %s", err.message);
  /* The `cells` largest load peaks... */
  size_t *p = calloc((size_t)S, sizeof *p), sum = 0;
  for (int c = 0; c < S; c++) p[c] = vr_domains_cell_load_peak(d, c);
  for (int k = 0; k < cells && k < S; k++) {
    int best = 0;
    for (int c = 1; c < S; c++)
      if (p[c] > p[best]) best = c;
    sum += p[best];
    p[best] = 0;
  }
  free(p);
  vr_domains_destroy(d);
  /* ... plus the queues' least share (8-ray batches, two threads) and the
   * state maps, over 7/8 (the queues take an eighth of a larger budget). */
  size_t queues = (size_t)(2 * S * 8 + S * 8) * 304 + 64 * 1024;
  return (sum + queues) * 8 / 7;
}

static void test_same_image_with_budget(void **state) {
  (void)state;
  char *text = room_text("path", 2);
  vr_scene *s = parse(text);
  vr_render_result *ref = render(s, 1, 0, NULL, VR_OK, NULL);
  assert_true(ref->photochromic_texels == 18);
  const int Ss[] = {1, 8, 27};
  for (int i = 0; i < 3; i++) {
    int S = Ss[i];
    char what[64];
    vr_render_result *r = render(s, S, 0, NULL, VR_OK, NULL);
    snprintf(what, sizeof what, "S=%d, no budget", S);
    same_film(ref, r, what);
    assert_int_equal(r->cell_loads, (uint64_t)S); /* all loaded once */
    assert_int_equal(r->cell_unloads, 0);
    vr_render_result_destroy(r);
    size_t b = budget_for(s, S, S == 1 ? 1 : 2) + film_bytes(ref);
    r = render(s, S, b, NULL, VR_OK, NULL);
    snprintf(what, sizeof what, "S=%d, budget %zu", S, b);
    same_film(ref, r, what);
    print_message("  S = %2d, budget %7zu B: %3llu loads, %3llu unloads, %llu rays spilled, peak "
                  "%zu B of cells\n",
                  S, b, (unsigned long long)r->cell_loads, (unsigned long long)r->cell_unloads,
                  (unsigned long long)r->rays_spilled, r->peak_cells_bytes);
    if (S > 1) {
      /* The budget held about two cells: cells came and went. */
      assert_true(r->cell_loads > (uint64_t)S);
      assert_true(r->cell_unloads > 0);
    }
    assert_true(r->peak_cells_bytes + r->peak_queue_bytes + r->peak_map_bytes <= b);
    /* The photochromic states, held per cell, are the single map's. */
    for (size_t t = 0; t < ref->photochromic_texels; t++)
      assert_near(r->photochromic_state[t], ref->photochromic_state[t], 1e-9);
    vr_render_result_destroy(r);
  }
  vr_render_result_destroy(ref);
  vr_scene_destroy(s);
  free(text);
}

static void test_photon_maps_per_cell(void **state) {
  (void)state;
  char *text = room_text("photon", 1);
  vr_scene *s = parse(text);
  vr_render_result *ref = render(s, 1, 0, NULL, VR_OK, NULL);
  assert_true(ref->photons_global > 1000);
  vr_render_result *r8 = render(s, 8, 0, NULL, VR_OK, NULL);
  same_film(ref, r8, "photon mapping, S=8");
  assert_int_equal(r8->photons_global, ref->photons_global);
  /* Under a budget the maps count: give them room, and cells little. */
  size_t b = budget_for(s, 8, 2) + film_bytes(ref) + 3 * (ref->peak_map_bytes + (1 << 20));
  vr_render_result *rb = render(s, 8, b, NULL, VR_OK, NULL);
  same_film(ref, rb, "photon mapping, S=8 with a budget");
  assert_true(rb->peak_map_bytes > 0);
  vr_render_result_destroy(ref);
  vr_render_result_destroy(r8);
  vr_render_result_destroy(rb);
  vr_scene_destroy(s);
  free(text);
}

static void test_budget_too_small(void **state) {
  (void)state;
  char *text = room_text("path", 1);
  vr_scene *s = parse(text);
  vr_error err;
  render(s, 8, 20000, NULL, VR_E_ARG, &err);
  assert_contains(err.message, "memory budget");
  assert_contains(err.message, "too small: sub-domain ");
  assert_contains(err.message, "needs at least");
  vr_scene_destroy(s);
  free(text);
}

/* ---- the cache ---- */

static void write_text(const char *path, const char *text) {
  FILE *f = fopen(path, "w");
  assert_non_null(f);
  fputs(text, f);
  fclose(f);
}

/* A box room with a two-triangle mesh of our own, so that the test can
 * change it. */
static char *cache_scene(const char *obj, int spp) {
  char *t = malloc(2048);
  snprintf(t, 2048,
           "camera pinhole from=2,0,1 to=0,0,1 fov=70 resolution=24x16\n"
           "material wall lambert reflectance=0.5\n"
           "box min=-1,-1,0 max=3,1,2 material=wall\n"
           "mesh %s material=wall\n"
           "light point position=1,0,1.8 intensity=50cd\n"
           "render integrator=path spp=%d depth=4 seed=5\n",
           obj, spp);
  return t;
}

static const char *OBJ_A = "v 0 -0.5 0.2\nv 0 0.5 0.2\nv 0 0 1.2\nf 1 2 3\n";
static const char *OBJ_B = "v 0 -0.5 0.2\nv 0 0.5 0.2\nv 0 0 1.5\nf 1 2 3\n";

static vr_render_result *cached(const char *obj, int spp, const char *cache) {
  char *text = cache_scene(obj, spp);
  vr_scene *s = parse(text);
  vr_render_result *r = render(s, 4, 0, cache, VR_OK, NULL);
  vr_scene_destroy(s);
  free(text);
  return r;
}

static void flip_byte(const char *path, long at) {
  FILE *f = fopen(path, "r+b");
  assert_non_null(f);
  fseek(f, at, at < 0 ? SEEK_END : SEEK_SET);
  int c = fgetc(f);
  fseek(f, -1, SEEK_CUR);
  fputc(c ^ 0x20, f);
  fclose(f);
}

static void test_cache_lifecycle(void **state) {
  (void)state;
  char obj[512], cache[512], cell[600], manifest[600];
  snprintf(obj, sizeof obj, "%s/tri.obj", tmpdir);
  snprintf(cache, sizeof cache, "%s/cache", tmpdir);
  snprintf(cell, sizeof cell, "%s/S4/cell-00002.vrc", cache);
  snprintf(manifest, sizeof manifest, "%s/S4/manifest.vrm", cache);
  write_text(obj, OBJ_A);

  vr_render_result *first = cached(obj, 2, cache);
  assert_true(first->cache_built);
  assert_string_equal(first->cache_reason, "no cache yet");
  vr_render_result *again = cached(obj, 2, cache);
  assert_false(again->cache_built);
  assert_string_equal(again->cache_reason, "reused");
  same_film(first, again, "reused cache");
  vr_render_result_destroy(again);
  /* Another spp is not another geometry. */
  vr_render_result *spp = cached(obj, 3, cache);
  assert_false(spp->cache_built);
  vr_render_result_destroy(spp);

  /* A damaged byte in a cell's contents, in its header, a cut file, a
   * damaged manifest: each is found and the cache rebuilt, same image. */
  struct {
    const char *path;
    long at;
    const char *reason;
  } damage[] = {{cell, -3, "damaged (checksum of its contents)"},
                {cell, 30, "damaged header"},
                {manifest, -5, "damaged (checksum)"}};
  /* What an interrupted build left beside the cache goes with the next
   * build. */
  char stale[700];
  snprintf(stale, sizeof stale, "%s/S4.tmp-1", cache);
  mkdir(stale, 0755);
  snprintf(stale, sizeof stale, "%s/S4.tmp-1/part-00000", cache);
  write_text(stale, "x");
  for (size_t i = 0; i < 3; i++) {
    flip_byte(damage[i].path, damage[i].at);
    vr_render_result *r = cached(obj, 2, cache);
    assert_true(r->cache_built);
    assert_contains(r->cache_reason, damage[i].reason);
    same_film(first, r, damage[i].reason);
    vr_render_result_destroy(r);
    assert_true(access(stale, F_OK) != 0);
  }
  assert_int_equal(truncate(cell, 200), 0);
  vr_render_result *cut = cached(obj, 2, cache);
  assert_true(cut->cache_built);
  assert_contains(cut->cache_reason, "truncated");
  same_film(first, cut, "truncated cell");
  vr_render_result_destroy(cut);
  /* A cell file of another cell in its place is another file. */
  char other[600];
  snprintf(other, sizeof other, "%s/S4/cell-00001.vrc", cache);
  char cmd[1400];
  snprintf(cmd, sizeof cmd, "cp '%s' '%s'", other, cell);
  assert_int_equal(system(cmd), 0);
  vr_render_result *foreign = cached(obj, 2, cache);
  assert_true(foreign->cache_built);
  same_film(first, foreign, "foreign cell");
  vr_render_result_destroy(foreign);

  /* The mesh moves: a new geometry, a new cache, another image. */
  write_text(obj, OBJ_B);
  vr_render_result *moved = cached(obj, 2, cache);
  assert_true(moved->cache_built);
  assert_contains(moved->cache_reason, "geometry changed");
  size_t n = (size_t)first->width * first->height * 3, differ = 0;
  for (size_t i = 0; i < n; i++) differ += first->xyz[i] != moved->xyz[i];
  assert_true(differ > 0);
  vr_render_result_destroy(moved);
  vr_render_result_destroy(first);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_same_image_with_budget),
      cmocka_unit_test(test_photon_maps_per_cell),
      cmocka_unit_test(test_budget_too_small),
      cmocka_unit_test(test_cache_lifecycle),
  };
  return cmocka_run_group_tests(tests, setup, teardown);
}
