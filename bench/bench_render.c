/* Prints how fast the renderer moves rays, and how long the sample room takes.
 *
 * (a) Rays per second on the geometry of samples/room.scn (the shell, the
 *     two panes, the mirror, the four furniture meshes: 974 triangles):
 *     2 million rays with origins uniform in the room's bounds and
 *     directions uniform on the sphere, all made by a counter-based hash,
 *     traced to their closest hit by
 *       - raw Embree: one scene holding every triangle, built here with the
 *         Embree API and the flags the sub-domains use (robust, high
 *         quality), rtcIntersect1 per ray;
 *       - the sub-domains: vr_domains_locate + vr_domains_intersect walking
 *         the cells along the ray, S = 1 and S = 8, which is the inner loop
 *         of the flow plus the hit record the integrators need (point,
 *         normals, surface coordinates);
 *       - the whole ray flow (vr_flow_run): the same rays pushed through the
 *         per-cell queues, S = 1 and S = 8, on 1 and 2 threads;
 *       - the image-space scheduler (vr_flow_run_image_space) on the same
 *         callbacks: each worker traces its units' rays itself, S = 1 (what
 *         vr-render --image-space does) and S = 8 (cells walked in place).
 *     All single-threaded except the 2-thread lines.  Each figure is the
 *     best of three runs; the closest hits are checked to agree.  The
 *     callbacks count hits per worker, so the figures are the flow's own.
 * (b) The wall-clock time of vr_render_scene on samples/room.scn at its own
 *     settings: the domain-decomposed flow with S = 1 and S = 8 and image
 *     space, each on 1 and 2 threads, with the largest difference of the
 *     film (XYZ, relative) from the first line.  It needs the material
 *     database the main job fills: the path given as the first argument,
 *     else $VR_MATDB; without one, (b) is skipped with a message.
 *
 *     build/bench/bench_render [out/materials.db] [--quick]
 *
 * --quick leaves out (b) but for the 2-thread decomposed S = 1 line.
 * Figures go to docs/benchmarks.md. */
#include "vr/domains.h"
#include "vr/flow.h"
#include "vr/geometry.h"
#include "vr/matdb.h"
#include "vr/models.h"
#include "vr/render.h"
#include "vr/scene.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define NRAYS 2000000L
#define RUNS 3
#define UNIT 4096 /* rays per work unit of the flow */

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void die(const char *what, const vr_error *err) {
  fprintf(stderr, "bench_render: %s: %s\n", what, err ? err->message : "failed");
  exit(1);
}

static uint64_t mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}
static double u01(uint64_t stream, uint64_t i) {
  return (double)(mix64(mix64(i) ^ (stream * 0xD1B54A32D192ED03ull)) >> 11) * 0x1.0p-53;
}

/* Ray i: origin uniform in the box [lo, hi], direction uniform on the sphere. */
static void make_ray(const double lo[3], const double hi[3], uint64_t i, double o[3],
                     double d[3]) {
  for (int a = 0; a < 3; a++) o[a] = lo[a] + (hi[a] - lo[a]) * u01(1 + (uint64_t)a, i);
  double z = 1 - 2 * u01(4, i), phi = 2 * M_PI * u01(5, i), s = sqrt(fmax(0, 1 - z * z));
  d[0] = s * cos(phi);
  d[1] = s * sin(phi);
  d[2] = z;
}

static void machine(void) {
  char model[256] = "unknown";
  FILE *f = fopen("/proc/cpuinfo", "r");
  if (f) {
    char line[512];
    while (fgets(line, sizeof line, f))
      if (!strncmp(line, "model name", 10)) {
        const char *c = strchr(line, ':');
        if (c) {
          c++;
          while (*c == ' ' || *c == '\t') c++;
          snprintf(model, sizeof model, "%s", c);
          model[strcspn(model, "\n")] = 0;
        }
        break;
      }
    fclose(f);
  }
  char load[128] = "?";
  f = fopen("/proc/loadavg", "r");
  if (f) {
    if (fgets(load, sizeof load, f)) load[strcspn(load, "\n")] = 0;
    fclose(f);
  }
  printf("machine: %ld online CPUs (nproc), \"%s\"; load average at start: %s\n",
         sysconf(_SC_NPROCESSORS_ONLN), model, load);
  printf("embree %d.%d.%d\n", RTC_VERSION_MAJOR, RTC_VERSION_MINOR, RTC_VERSION_PATCH);
}

/* --- (a) traversal ------------------------------------------------------- */

typedef struct bounds {
  double lo[3], hi[3];
} bounds;

/* Raw Embree over all triangles; fills t[i] (INFINITY on a miss). */
static double run_embree(RTCScene scene, const bounds *b, float *t, long *hits) {
  double t0 = now();
  long h = 0;
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  for (long i = 0; i < NRAYS; i++) {
    double o[3], d[3];
    make_ray(b->lo, b->hi, (uint64_t)i, o, d);
    struct RTCRayHit rh;
    rh.ray.org_x = (float)o[0];
    rh.ray.org_y = (float)o[1];
    rh.ray.org_z = (float)o[2];
    rh.ray.dir_x = (float)d[0];
    rh.ray.dir_y = (float)d[1];
    rh.ray.dir_z = (float)d[2];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = INFINITY;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xFFFFFFFFu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(scene, &ctx, &rh);
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      h++;
      t[i] = rh.ray.tfar;
    } else {
      t[i] = INFINITY;
    }
  }
  *hits = h;
  return now() - t0;
}

/* The flow's inner loop without its queues: walk the cells by parameter. */
static double run_domains(const vr_domains *dm, const bounds *b, float *t, long *hits,
                          long *cells_visited) {
  double t0 = now();
  long h = 0, visits = 0;
  for (long i = 0; i < NRAYS; i++) {
    double o[3], d[3], tn = 0, te;
    make_ray(b->lo, b->hi, (uint64_t)i, o, d);
    t[i] = INFINITY;
    for (;;) {
      int c = vr_domains_locate(dm, o, d, tn, &te);
      vr_hit hit;
      visits++;
      if (vr_domains_intersect(dm, c, o, d, tn, te, &hit)) {
        h++;
        t[i] = (float)hit.t;
        break;
      }
      if (isinf(te)) break;
      tn = te;
    }
  }
  *hits = h;
  *cells_visited = visits;
  return now() - t0;
}

#define MAXTHREADS 2

typedef struct flow_ctx {
  bounds b;
  float *t;
  struct {
    _Alignas(64) long n; /* a cache line per worker: counting costs nothing shared */
  } hits[MAXTHREADS];
} flow_ctx;

static void fl_closest(void *ctx, vr_flow_worker *w, const vr_ray *r, const vr_hit *hit) {
  flow_ctx *c = ctx;
  long i;
  memcpy(&i, r->payload, sizeof i);
  c->t[i] = hit ? (float)hit->t : INFINITY;
  if (hit) c->hits[vr_flow_worker_index(w)].n++;
}
static bool fl_shadow_hit(void *ctx, vr_flow_worker *w, vr_ray *r, const vr_hit *hit) {
  (void)ctx, (void)w, (void)r, (void)hit;
  return false;
}
static void fl_shadow_done(void *ctx, vr_flow_worker *w, const vr_ray *r, bool reached) {
  (void)ctx, (void)w, (void)r, (void)reached;
}
static void fl_generate(void *ctx, vr_flow_worker *w, long unit) {
  flow_ctx *c = ctx;
  for (long i = unit * UNIT; i < (unit + 1) * UNIT && i < NRAYS; i++) {
    vr_ray r;
    memset(&r, 0, offsetof(vr_ray, payload) + sizeof i);
    make_ray(c->b.lo, c->b.hi, (uint64_t)i, r.org, r.dir);
    r.tnear = 0;
    r.tmax = INFINITY;
    r.kind = VR_RAY_CLOSEST;
    memcpy(r.payload, &i, sizeof i);
    vr_flow_push(w, &r);
  }
}
static const vr_flow_ops flow_ops = {fl_closest, fl_shadow_hit, fl_shadow_done, fl_generate,
                                     NULL, NULL, NULL};

static double run_flow(vr_domains *dm, const bounds *b, int threads, bool image_space,
                       float *t, long *hits, uint64_t *crossings) {
  flow_ctx c = {.b = *b, .t = t};
  vr_flow_stats st = {0};
  vr_error err = {0};
  double t0 = now();
  if ((image_space ? vr_flow_run_image_space : vr_flow_run)(
          dm, &flow_ops, &c, (NRAYS + UNIT - 1) / UNIT, threads, NULL, NULL, &st, &err))
    die("vr_flow_run", &err);
  double dt = now() - t0;
  if (st.created != NRAYS || st.finished != NRAYS) die("rays created != finished", NULL);
  *hits = 0;
  for (int i = 0; i < threads; i++) *hits += c.hits[i].n;
  *crossings = st.crossings;
  return dt;
}

/* Rays whose closest hit differs from the reference by more than 1e-4 m. */
static long disagree(const float *ref, const float *t) {
  long n = 0;
  for (long i = 0; i < NRAYS; i++)
    if (isinf(ref[i]) != isinf(t[i]) || (!isinf(ref[i]) && fabsf(ref[i] - t[i]) > 1e-4f)) n++;
  return n;
}

static void line(const char *what, double best, long hits, const char *extra) {
  printf("  %-44s %7.3f s  %6.2f Mrays/s  %ld hits%s\n", what, best, NRAYS / best / 1e6, hits,
         extra);
}

static void part_a(const vr_scene *s) {
  vr_error err = {0};
  vr_geometry *g = NULL;
  if (vr_geometry_build(s, &g, &err)) die("geometry", &err);
  bounds b;
  memcpy(b.lo, g->bmin, sizeof b.lo);
  memcpy(b.hi, g->bmax, sizeof b.hi);
  printf("\n(a) closest-hit traversal, %ld random rays in the room's bounds "
         "[%.2f,%.2f] x [%.2f,%.2f] x [%.2f,%.2f] m, %zu triangles, best of %d\n",
         NRAYS, b.lo[0], b.hi[0], b.lo[1], b.hi[1], b.lo[2], b.hi[2], g->ntris, RUNS);

  float *ref = malloc(NRAYS * sizeof *ref), *t = malloc(NRAYS * sizeof *t);
  if (!ref || !t) die("rays", NULL);

  /* Raw Embree: one scene, the same triangles, the sub-domains' flags. */
  RTCDevice dev = rtcNewDevice("threads=1,verbose=0");
  if (!dev) die("rtcNewDevice", NULL);
  RTCScene sc = rtcNewScene(dev);
  rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  /* Embree's own buffers (padded as it needs), filled with the same data. */
  float *v = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                     3 * sizeof(float), g->nverts);
  unsigned *ix = rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                         3 * sizeof(unsigned), g->ntris);
  if (!v || !ix) die("Embree buffers", NULL);
  memcpy(v, g->verts, 3 * g->nverts * sizeof *v);
  memcpy(ix, g->tris, 3 * g->ntris * sizeof *ix);
  rtcCommitGeometry(geom);
  rtcAttachGeometry(sc, geom);
  rtcReleaseGeometry(geom);
  double tb = now();
  rtcCommitScene(sc);
  tb = now() - tb;
  if (rtcGetDeviceError(dev) != RTC_ERROR_NONE) die("Embree scene", NULL);

  double best = INFINITY;
  long hits = 0;
  for (int k = 0; k < RUNS; k++) best = fmin(best, run_embree(sc, &b, ref, &hits));
  char extra[160];
  snprintf(extra, sizeof extra, " (scene build %.2f ms)", 1e3 * tb);
  line("raw Embree, rtcIntersect1, one scene", best, hits, extra);
  double embree_best = best;

  static const int S[2] = {1, 8};
  vr_domains *dm[2] = {NULL, NULL};
  for (int j = 0; j < 2; j++) {
    double t0 = now();
    if (vr_domains_build(g, S[j], &dm[j], &err)) die("vr_domains_build", &err);
    double tbuild = now() - t0;
    long visits = 0;
    best = INFINITY;
    for (int k = 0; k < RUNS; k++) best = fmin(best, run_domains(dm[j], &b, t, &hits, &visits));
    size_t prims = 0;
    for (int c = 0; c < vr_domains_count(dm[j]); c++) prims += vr_domains_cell_primitives(dm[j], c);
    snprintf(extra, sizeof extra,
             "; %.2f cells/ray, %zu triangles stored; x%.2f of raw; %ld disagree (build %.2f ms)",
             (double)visits / NRAYS, prims, best / embree_best, disagree(ref, t), 1e3 * tbuild);
    char what[64];
    snprintf(what, sizeof what, "vr_domains locate+intersect, S = %d", S[j]);
    line(what, best, hits, extra);
  }
  for (int image = 0; image < 2; image++)
    for (int threads = 1; threads <= MAXTHREADS; threads++)
      for (int j = 0; j < 2; j++) {
        uint64_t cross = 0;
        best = INFINITY;
        for (int k = 0; k < RUNS; k++)
          best = fmin(best, run_flow(dm[j], &b, threads, image, t, &hits, &cross));
        snprintf(extra, sizeof extra, "; %.2f crossings/ray; x%.2f of raw; %ld disagree",
                 (double)cross / NRAYS, best / embree_best, disagree(ref, t));
        char what[64];
        snprintf(what, sizeof what, "%s, S = %d, %d thread%s",
                 image ? "vr_flow_run_image_space" : "vr_flow_run (queues)", S[j], threads,
                 threads > 1 ? "s" : "");
        line(what, best, hits, extra);
      }
  for (int j = 0; j < 2; j++) vr_domains_destroy(dm[j]);
  rtcReleaseScene(sc);
  rtcReleaseDevice(dev);
  vr_geometry_destroy(g);
  free(ref);
  free(t);
}

/* --- (b) the whole render ------------------------------------------------ */

typedef struct config {
  bool image_space;
  int S, P;
} config;

static void part_b(const vr_scene *s, const char *dbpath, bool quick) {
  printf("\n(b) vr_render_scene on %s at its own settings\n", s->path);
  if (!dbpath || access(dbpath, R_OK) != 0) {
    printf("  skipped: no material database (%s); run scripts/main-job.sh, then pass "
           "out/materials.db or set VR_MATDB\n",
           dbpath ? dbpath : "no argument and VR_MATDB unset");
    return;
  }
  vr_error err = {0};
  vr_matdb *db = NULL;
  if (vr_matdb_open(dbpath, VR_MATDB_READONLY, &db, &err)) die(dbpath, &err);
  printf("  database %s\n", dbpath);
  static const config all[] = {{false, 1, 2}, {false, 1, 1}, {false, 8, 1}, {false, 8, 2},
                               {true, 1, 1},  {true, 1, 2}};
  int n = quick ? 1 : (int)(sizeof all / sizeof all[0]);
  double *ref = NULL;
  size_t nref = 0;
  for (int k = 0; k < n; k++) {
    vr_render_options opt;
    vr_render_options_default(&opt);
    opt.threads = all[k].P;
    opt.subdomains = all[k].S;
    opt.image_space = all[k].image_space;
    vr_render_result *r = NULL;
    double t0 = now();
    if (vr_render_scene(s, db, &opt, &r, &err)) die("vr_render_scene", &err);
    double wall = now() - t0;
    if (k == 0) {
      printf("  %d x %d pixels, %d spp, %ld photons per pass, knn %d\n", r->width, r->height,
             s->settings.spp, s->settings.photons, s->settings.knn);
      printf("  rays: camera %llu, shadow %llu, photon %llu, other %llu; photons stored: "
             "global %zu, caustic %zu\n",
             (unsigned long long)r->rays_camera, (unsigned long long)r->rays_shadow,
             (unsigned long long)r->rays_photon, (unsigned long long)r->rays_other,
             r->photons_global, r->photons_caustic);
    }
    double diff = 0;
    size_t npx = (size_t)r->width * (size_t)r->height * 3;
    if (!ref) {
      ref = malloc(npx * sizeof *ref);
      if (!ref) die("film copy", NULL);
      memcpy(ref, r->xyz, npx * sizeof *ref);
      nref = npx;
    } else if (npx == nref) {
      for (size_t i = 0; i < npx; i++) {
        double a = ref[i], b = r->xyz[i], m = fmax(fabs(a), fabs(b));
        if (m > 0) diff = fmax(diff, fabs(a - b) / m);
      }
    }
    char what[64];
    if (all[k].image_space)
      snprintf(what, sizeof what, "image space, %d thread%s", all[k].P, all[k].P > 1 ? "s" : "");
    else
      snprintf(what, sizeof what, "decomposed, S = %d, %d thread%s", all[k].S, all[k].P,
               all[k].P > 1 ? "s" : "");
    uint64_t rays = r->rays_camera + r->rays_shadow + r->rays_photon + r->rays_other;
    printf("  %-30s %7.2f s", what, wall);
    bool photons = false; /* the photon passes share one time: print it once */
    for (size_t i = 0; i < r->npasses; i++) {
      const vr_pass_record *p = &r->passes[i];
      if (!p->ran || !(p->seconds > 0)) continue;
      if (strstr(p->name, "photons")) {
        if (photons) continue;
        photons = true;
        printf("; photons %.2f s", p->seconds);
      } else {
        printf("; %s %.2f s", p->name, p->seconds);
      }
    }
    printf("; %.2f Mrays/s; %llu crossings; created %s finished", rays / wall / 1e6,
           (unsigned long long)r->crossings,
           r->rays_created == r->rays_finished ? "==" : "!=");
    if (k > 0) printf("; film differs by %.1e", diff);
    printf("\n");
    fflush(stdout);
    vr_render_result_destroy(r);
  }
  free(ref);
  vr_matdb_close(db);
}

int main(int argc, char **argv) {
  const char *scene_path = VR_SOURCE_DIR "/samples/room.scn";
  const char *dbpath = getenv("VR_MATDB");
  bool quick = false;
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--quick"))
      quick = true;
    else
      dbpath = argv[i];
  }
  machine();
  vr_error err = {0};
  vr_scene *s = NULL;
  if (vr_scene_read(scene_path, &s, &err) || vr_scene_load_models(s, &err)) die(scene_path, &err);
  part_a(s);
  part_b(s, dbpath, quick);
  vr_scene_destroy(s);
  return 0;
}
