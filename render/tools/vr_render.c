/* vr-render: renders a scene file into spectral and RGB OpenEXR, an sRGB
 * PNG, a sensor table and statistics (docs/vr-render.md).  This file is the
 * command line around vr_render_scene (the engine) and vr_film_write_with
 * (the files): options, the material database, decision lines and a
 * progress bar on stderr.  The scene's overrides, the checks of the outputs
 * and the results on stdout are in render_overrides.c, render_outputs.c and
 * render_report.c (render_cli.h). */
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <errno.h>
#include <sys/stat.h>
#include <unistd.h>

#include "render_cli.h"
#include "vr/annual.h"
#include "vr/args.h"
#include "vr/comm.h"
#include "vr/domains.h"
#include "vr/file.h"
#include "vr/sha256.h"
#include "vr/film.h"
#include "vr/image.h"
#include "vr/matdb.h"
#include "vr/progress.h"
#include "vr/models.h"
#include "vr/render.h"
#include "vr/scene.h"
#include "vr/sky.h"

static const vr_option OPTIONS[] = {
    {"output", 'o', "PREFIX", "write PREFIX.exr, .spectral.exr, .png, .sensors.csv (those that apply, or those of --outputs) and .manifest.json (default PREFIX: the scene's name without .scn, here); checked before any work"},
    {"outputs", 0, "LIST", "which files to write: a comma-separated subset of exr, spectral, png, hdr, sensors (default: all that apply but hdr, the Radiance picture, written only when named); the manifest is always written and lists them. Without png (and --falsecolour), OpenCV is never loaded; without spectral the film keeps XYZ only (24 bytes a pixel instead of 8 x (3 + bins): 190 MiB at 4K instead of 2.0 GiB with the default 30 bins)"},
    {"db", 'd', "FILE", "material database, read-only; must exist (default: $VR_MATDB, else ./materials.db, made if missing and needed)"},
    {"subdomains", 0, "S", "split the geometry into S sub-domains (default 1)"},
    {"memory-budget", 0, "SIZE", "add at most SIZE (e.g. 512M, 2G) to the process's memory: sub-domains, ray queues, maps and the film, with the resident memory watched (16 MiB allowed beyond); sub-domains are loaded and unloaded as rays need them (default: no budget, all loaded)"},
    {"cache", 0, "DIR", "geometry cache folder (default: SCENE.vrcache beside the scene; a temporary one if that folder cannot be written)"},
    {"threads", 0, "P", "worker threads (default: the number of online CPUs; under mpirun, per rank)"},
    {"send-batch", 0, "N", "under mpirun: rays a message between ranks carries at most (default 256; refused when running alone)"},
    {"send-credit", 0, "N", "under mpirun: rays a rank may send another before that rank credits them back as they leave its memory (default 4096; refused when running alone)"},
    {"image-space", 0, NULL, "image-space mode for comparison: threads trace whole 16x16 tiles over the whole scene, no ray queues (--subdomains ignored)"},
    {"resolution", 0, "WxH", "image size in pixels, overriding the camera line's resolution="},
    {"render", 0, "OPTIONS", "a render line's options replacing the scene's render line, e.g. \"integrator=progressive photons=200000 spp=16\" (those left out take their defaults, not the file's; the file's line is still checked); --spp, --photons and --seed apply over it"},
    {"spp", 0, "N", "samples per pixel, overriding the scene's render line"},
    {"target-error", 0, "E", "adaptive sampling (integrators path, photon, whitted; and path sensors, by point): rounds that double a pixel's samples until its estimated relative standard error (from two independent halves of its samples, over its 3x3 neighbourhood) is at most E, e.g. 0.02 or 2%; the first round is two halves of the smallest multiple of spp that is at least 4; the EXR gains layers samples.N and variance.Y"},
    {"time-limit", 0, "SECONDS", "adaptive sampling: start no round that would end past SECONDS from the start of the render (predicted from the last round); alone, every pixel takes samples until then"},
    {"max-spp", 0, "N", "adaptive sampling: at most N samples a pixel (default 65536)"},
    {"denoise", 0, NULL, "denoise the PNG (integrators path, photon, progressive, whitted): a feature-guided non-local-means filter on the albedo, normal and nearness the camera pass records, weighted by each pixel's noise from two independent halves of its samples (with a fixed spp, which must be even, two passes of spp/2; progressive: two independent chains of spp/2 iterations); the EXRs and sensors stay the raw estimates, and the EXR gains layers albedo (R,G,B), normal (X,Y,Z), nearness (V) and each pixel's variance (variance.Y, from its halves)"},
    {"seed", 0, "N", "random seed in [0, 2^64-1], overriding the scene's render seed= (same seed, same image)"},
    {"exposure", 0, "EV|auto", "PNG exposure in EV, overriding the camera line's exposure=; auto: the image's log-average luminance Ylog = exp(mean ln Y) over its lit pixels to mid grey 0.18 before the tone curve (PNG 141 with filmic, 118 with clip), EV = log2(18 cd/m2 / Ylog)"},
    {"set", 0, "NAME.state=S", "a material's tint state S in [0, 1], overriding the scene (repeat for several materials)"},
    {"photons", 0, "N", "photons per pass, overriding the scene's render line"},
    {"stats", 0, "FILE.json", "write statistics (passes, rays, photons, sensors, memory, time) as JSON, one of the set of outputs"},
    {"flow-profile", 0, NULL, "with --stats, alone, not in image space: record each pass's rays cell by cell (their time by kind, the moves between cells, the units' generation; every ray timed, rays wait in queues even between loaded cells) as the statistics' flow_profile, for the model of the decomposition (bench/bench_ddm_sim.c)"},
    {"tonemap", 0, "NAME", "PNG tone mapping: filmic (default: Narkowicz's fit of the ACES film curve), clip or reinhard"},
    {"falsecolour", 0, "LO,HI", "also write PREFIX.falsecolour.png: the luminance map on a log scale from LO to HI cd/m2, with a labelled legend (needs a camera)"},
    {"sensors-only", 0, NULL, "evaluate the sensors only: no camera pass, no images"},
    {"json", 0, NULL, "print the results (sensors, grids, glare, timings, output files) as one JSON object on stdout instead of the text summary"},
    {"verify", 0, "PREFIX", "check the files PREFIX.manifest.json lists (size, SHA-256) and exit: 0 if the set is whole, 1 if any differs or is missing"},
    {"quiet", 'q', NULL, "print errors only: no decisions, progress bar or summary"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "SCENE.scn [-o PREFIX] [--outputs LIST] [--db FILE] [--subdomains S] [--memory-budget SIZE]\n"
    "                 [--cache DIR] [--threads P] [--image-space] [--send-batch N] [--send-credit N]\n"
    "                 [--render OPTIONS] [--resolution WxH] [--spp N] [--seed N] [--photons N] [--exposure EV|auto]\n"
    "                 [--target-error E] [--time-limit SECONDS] [--max-spp N] [--denoise]\n"
    "                 [--set NAME.state=S]... [--stats FILE.json [--flow-profile]] [--tonemap filmic|clip|reinhard]\n"
    "                 [--falsecolour LO,HI] [--sensors-only] [--json] [--quiet]\n"
    "       vr-render --verify PREFIX";
static const char ABOUT[] =
    "Renders a scene file (docs/scene-format.md) with the materials of the material database.\n"
    "Each analysis decision (which passes the scene needs, and why) is printed to stderr.\n"
    "In the scene, as in pbrt-v4: camera ... filter=box|tent|gaussian|mitchell [filter_radius=R]\n"
    "(pixels) [filter_sigma=S]; render sampler=independent|stratified|sobol; a spectrum or a\n"
    "lambert reflectance inline as [400:0.12,500:0.35,700:0.7] or [400 0.12 500 0.35 700 0.7].\n"
    "A lambert material may take a colour (color=#RRGGBB, rgb=R,G,B) or an image texture\n"
    "(texture=FILE [colorspace=srgb|linear] [alpha=off|mask|blend] [tile=N]) and a normal map\n"
    "(normal_map=FILE [normal_scale=S]); a mesh without\n"
    "material= takes its file's materials, colours and base colour textures; db:NAME of a\n"
    "spectral texture saved by vr-rgb2spec --texture renders per texel (texture=none: its mean).\n"
    "A mesh may be a Radiance scene (mesh office.rad): polygons, spheres, cones, cylinders,\n"
    "rings, a distant source as the sun, !xform lines parsed (never run), plastic, metal,\n"
    "mirror, glass, dielectric, trans, light, glow, illum and BSDF materials; the rest is refused.\n"
    "Outputs: PREFIX.exr (linear sRGB, Y in cd/m2), PREFIX.spectral.exr (spectral radiance\n"
    "in W/(m2 sr nm), Fichet-Pacanowski-Wilkie layout), PREFIX.png (8-bit sRGB of Y x\n"
    "2^exposure / 100 cd/m2 through the tone curve: with filmic 100 cd/m2 is 0.80 at EV 0\n"
    "and white 724 cd/m2), and PREFIX.sensors.csv\n"
    "(illuminance in lx and spectral irradiance in W/(m2 nm)) when the scene has sensors;\n"
    "--outputs chooses among them (e.g. --outputs exr,sensors).\n"
    "The outputs appear together or not at all, with PREFIX.manifest.json (the run's id, each\n"
    "file's size and SHA-256) written last; 'vr-render --verify PREFIX' checks a set against it.\n"
    "Every output is checked before any work: none may replace an input of the run (the scene,\n"
    "its meshes, IES, weather and occupancy files, the database), and its folder must exist.\n"
    "A scene whose sky is a whole weather file (sky perez weather=FILE, no date) is an annual\n"
    "study instead: PREFIX.annual.csv (DA, UDI, direct-sun hours per point; with\n"
    "'annual en17037=yes' EN 17037's daylight hours and daylight factor) and\n"
    "PREFIX.annual-hourly.csv (every occupied hour: 'annual hours=' or 'occupancy=FILE'),\n"
    "with 'annual glare_views=' PREFIX.annual-glare.csv (each view's hours of DGP, contrast term\n"
    "included), with their manifest; sDA, ASE and the EN 17037 levels on stdout.\n"
    "Under mpirun (mpirun -np N vr-render ...) the ranks share the sub-domains and pass rays\n"
    "to each other; rank 0 prints and writes the outputs.";

/* ---- stderr: decision lines and the progress bar ---- */

/* The engine may call back from its worker threads: one lock keeps the
 * lines and the bar whole. */
typedef struct ui {
  pthread_mutex_t lock;
  bool quiet;
  vr_progress *bar;
  char pass[64];
  long total;
  /* stderr not a terminal (a batch job, a log): a line at each tenth of a
   * pass instead of a bar, so a long run shows it is alive. */
  bool lines;
  int tenth;        /* the last tenth printed for this pass, -1 none */
  long last_done;   /* the pass's last count of work done */
  double started;   /* when this pass began (monotonic seconds) */
} ui;

static double now_s(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A progress line for a log, once a pass has run 2 s (a quick pass, or
 * each of progressive photon mapping's many iterations, says nothing):
 * "vr-render: camera 30 % (12 s, about 28 s left)" at each tenth, and
 * "vr-render: camera done (40 s)" at its end. */
static void ui_line(ui *u, const char *pass, long done, long total) {
  int tenth = (int)(10 * (double)done / (double)total);
  if (tenth > 10) tenth = 10;
  if (tenth <= u->tenth || tenth == 0) return;
  double t = now_s() - u->started;
  if (t < 2.0) return;
  u->tenth = tenth;
  if (tenth >= 10)
    fprintf(stderr, "vr-render: %s done (%.0f s)\n", pass, t);
  else if (done > 0)
    fprintf(stderr, "vr-render: %s %d %% (%.0f s, about %.0f s left)\n", pass, 10 * tenth, t,
            t * (double)(total - done) / (double)done);
  fflush(stderr);
}

static void ui_log(void *user, const char *line) {
  ui *u = user;
  if (u->quiet) return;
  pthread_mutex_lock(&u->lock);
  /* Over the bar's line; the bar draws itself again at its next update. */
  if (u->bar) fputs("\r\033[K", stderr);
  fprintf(stderr, "vr-render: %s\n", line);
  fflush(stderr);
  pthread_mutex_unlock(&u->lock);
}

static void ui_progress(void *user, const char *pass, long done, long total) {
  ui *u = user;
  if (u->quiet || total <= 0) return;
  pthread_mutex_lock(&u->lock);
  if (u->lines) {
    /* A new pass: another name or size, or the same again after its end
     * (progressive photon mapping's camera passes). */
    if (strcmp(u->pass, pass ? pass : "") || total != u->total ||
        (u->tenth == 10 && done < total) || done < u->last_done) {
      snprintf(u->pass, sizeof u->pass, "%s", pass ? pass : "");
      u->total = total;
      u->tenth = -1;
      u->started = now_s();
    }
    u->last_done = done;
    ui_line(u, u->pass, done < 0 ? 0 : done, total);
    pthread_mutex_unlock(&u->lock);
    return;
  }
  if (u->bar && (strcmp(u->pass, pass ? pass : "") || total != u->total)) {
    vr_progress_finish(u->bar);
    u->bar = NULL;
  }
  if (!u->bar && done < total) {
    snprintf(u->pass, sizeof u->pass, "%s", pass ? pass : "");
    u->total = total;
    u->bar = vr_progress_create(u->pass, (size_t)total);
  }
  if (u->bar) {
    if (done >= total) {
      vr_progress_finish(u->bar);
      u->bar = NULL;
    } else {
      vr_progress_update(u->bar, done < 0 ? 0 : (size_t)done);
    }
  }
  pthread_mutex_unlock(&u->lock);
}

static void ui_end(ui *u) {
  if (u->bar) vr_progress_finish(u->bar);
  u->bar = NULL;
}

/* ---- options ---- */

int render_usage_error(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fputs("vr-render: ", stderr);
  vfprintf(stderr, fmt, ap);
  va_end(ap);
  fputs("\nTry 'vr-render --help'.\n", stderr);
  return 2;
}

/* An integer option in [lo, hi]; absent leaves *out.  false on a bad value. */
static bool int_option(const vr_args *a, const char *name, long lo, long hi, long *out) {
  const char *v = vr_args_get(a, name);
  if (!v) return true;
  char *end;
  double x = strtod(v, &end);
  if (end == v || *end || !(x >= (double)lo && x <= (double)hi) || x != floor(x)) {
    render_usage_error("--%s '%s': expected an integer in [%ld, %ld]", name, v, lo, hi);
    return false;
  }
  *out = (long)x;
  return true;
}

/* A real option in [lo, hi]; with percent, "2%" is 0.02. */
static bool real_option(const vr_args *a, const char *name, double lo, double hi, bool percent,
                        const char *what, double *out) {
  const char *v = vr_args_get(a, name);
  if (!v) return true;
  char *end;
  double x = strtod(v, &end);
  if (percent && end != v && *end == '%' && !end[1]) x /= 100, end++;
  if (end == v || *end || !(x >= lo && x <= hi)) {
    render_usage_error("--%s '%s': expected %s", name, v, what);
    return false;
  }
  *out = x;
  return true;
}

/* The scene's name without its folder and .scn: "rooms/office.scn" -> "office". */
static char *default_prefix(const char *scene) {
  const char *slash = strrchr(scene, '/');
  const char *base = slash ? slash + 1 : scene;
  size_t n = strlen(base);
  if (n > 4 && !strcmp(base + n - 4, ".scn")) n -= 4;
  if (n == 0) base = "render", n = 6;
  char *s = malloc(n + 1);
  if (s) memcpy(s, base, n), s[n] = '\0';
  return s;
}

/* The default cache folder: the scene's path with .vrcache for .scn
 * ("rooms/office.scn" -> "rooms/office.vrcache"), if it can be made and
 * written; else NULL (a temporary cache), with the reason in why. */
static char *default_cache(const char *scene, char *why, size_t nwhy) {
  size_t n = strlen(scene);
  if (n > 4 && !strcmp(scene + n - 4, ".scn")) n -= 4;
  char *dir = malloc(n + 9);
  if (!dir) return NULL;
  memcpy(dir, scene, n);
  memcpy(dir + n, ".vrcache", 9);
  if ((mkdir(dir, 0755) != 0 && errno != EEXIST) || access(dir, W_OK | X_OK) != 0) {
    snprintf(why, nwhy, "cannot write the geometry cache %s (%s): using a temporary one for "
             "this run (give one with --cache)", dir, strerror(errno));
    free(dir);
    return NULL;
  }
  return dir;
}

/* ---- the material database ---- */

static bool from_db(const char *ref) { return ref && !strncmp(ref, "db:", 3); }

/* Does the scene take anything from the database?  A sun without a
 * spectrum= does: its default, ASTM G173 direct, is a database row (each
 * kind of light names its default). */
static bool scene_needs_db(const vr_scene *s) {
  for (size_t i = 0; i < s->nmaterials; i++)
    if (s->materials[i].source == VR_MATSRC_DB || s->materials[i].coating_db) return true;
  for (size_t i = 0; i < s->nobjects; i++)
    if (from_db(s->objects[i].emission_spectrum)) return true;
  for (size_t i = 0; i < s->nlights; i++)
    if (from_db(vr_scene_light_spectrum(&s->lights[i]))) return true;
  return s->sky.present && from_db(s->sky.spectrum);
}

/* A database this run created: its path and what it held then. */
typedef struct created_db {
  bool created;
  long long rows, max_id;
} created_db;

/* Read-only when the file exists.  When it does not: a scene that takes
 * nothing from the database renders without one; else a --db FILE that is
 * not there is refused (a mistyped path must not become a new database);
 * the default one ($VR_MATDB, else ./materials.db) is created and seeded
 * with the built-in library if the scene needs it (as on any tool's first
 * use; c says so, and a run that then fails removes it if nobody wrote to
 * it meanwhile), else there is no database at all, so that a run leaves no
 * stray file.  Under mpirun only rank 0 may remove it. */
static vr_status open_db(const char *given, const vr_scene *s, ui *u, vr_matdb **db, created_db *c,
                         vr_error *err) {
  *db = NULL;
  memset(c, 0, sizeof *c);
  const char *p = given ? given : vr_matdb_default_path();
  if (access(p, F_OK) == 0) return vr_matdb_open(p, VR_MATDB_READONLY, db, err);
  if (!scene_needs_db(s)) return VR_OK;
  if (given && errno == ENOENT)
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "--db %s: no such material database (a mistyped path? 'vr-matdb --db %s "
                        "init' creates one with the built-in library)", p, p);
  vr_status st = vr_matdb_open(p, 0, db, err);
  if (!st) {
    c->created = !vr_matdb_revision(*db, &c->rows, &c->max_id, NULL);
    char line[4200];
    snprintf(line, sizeof line, "created the material database %s with the built-in library", p);
    ui_log(u, line);
  }
  return st;
}

/* The database this failed run created, removed when it still holds only
 * what the run put there (no other tool saved to it meanwhile). */
static void remove_created_db(const char *p, const created_db *c, ui *u) {
  vr_matdb *db = NULL;
  long long rows = -1, max_id = -1;
  if (vr_matdb_open(p, VR_MATDB_READONLY, &db, NULL) ||
      vr_matdb_revision(db, &rows, &max_id, NULL) || rows != c->rows || max_id != c->max_id) {
    vr_matdb_close(db);
    return; /* written to since: it is someone's database now */
  }
  vr_matdb_close(db);
  static const char *const SUFFIX[] = {"", "-wal", "-shm", "-journal"};
  char buf[4200];
  bool removed = false;
  for (size_t i = 0; i < sizeof SUFFIX / sizeof SUFFIX[0]; i++) {
    snprintf(buf, sizeof buf, "%s%s", p, SUFFIX[i]);
    if (unlink(buf) == 0 && i == 0) removed = true;
  }
  if (removed) ui_log(u, "removed the material database this failed run had created");
}

/* What a Perez sky made of its irradiances, and any limit of the model's
 * domain that acted (a stderr decision line each). */
static void log_perez(ui *u, const vr_scene *s) {
  const vr_scene_sky *k = &s->sky;
  if (!k->present || k->cie_type != VR_SKY_PEREZ || k->annual) return;
  const vr_perez_sky *m = &k->perez;
  char line[8192], from[4200] = "";
  if (k->weather_path) snprintf(from, sizeof from, " (%s, line %ld)", k->weather_path, k->weather_line);
  snprintf(line, sizeof line,
           "Perez sky%s: direct normal %g W/m2, diffuse horizontal %g W/m2; clearness %.3f (bin "
           "%d), brightness %.3f, water %.2f cm; diffuse horizontal %.0f lx (%.1f lm/W), direct "
           "normal %.0f lx (%.1f lm/W)",
           from, k->direct_normal_w_m2, k->diffuse_horizontal_w_m2, m->epsilon, m->bin, m->delta,
           m->water_cm, m->diffuse_horizontal_lx, m->diffuse_efficacy, m->direct_normal_lx,
           m->direct_efficacy);
  ui_log(u, line);
  if (m->limited) {
    char what[512];
    snprintf(line, sizeof line,
             "warning: the Perez model's inputs are outside the range it was fitted on "
             "(clearness %.3f, brightness %.3f): %s",
             m->epsilon_raw, m->delta_raw, vr_perez_limits_text(m->limited, what, sizeof what));
    ui_log(u, line);
  }
}

/* A scene whose sky is a whole weather file: the annual study
 * (vr/annual.h), its two CSV files and a summary. */
static vr_status annual(const vr_scene *scene, vr_matdb *db, const vr_render_options *opt,
                        const char *prefix, int rank, ui *u, vr_error *err) {
  const vr_scene_annual *sa = &scene->annual;
  char line[8192];
  char occupied[4200];
  if (sa->occupancy_path) snprintf(occupied, sizeof occupied, "occupied hours from %s", sa->occupancy_path);
  else snprintf(occupied, sizeof occupied, "occupied hours %g-%g h local standard time", sa->from_h, sa->to_h);
  snprintf(line, sizeof line,
           "annual study: every record of %s, %s, by daylight coefficients (145 sky patches and "
           "the ground, one render per sun patch%s)%s",
           scene->sky.weather_path, occupied,
           sa->glass >= 0   ? ", for each tint state of the glass"
           : sa->shade >= 0 ? ", open and with the shade drawn"
                            : "",
           sa->en17037 ? "; EN 17037 over the year's daylight hours, one render under the CIE "
                         "overcast sky" : "");
  ui_log(u, line);
  vr_annual_result *res = NULL;
  vr_status st = vr_annual_run(scene, db, opt, &res, err);
  ui_end(u);
  if (!st && rank == 0) st = vr_annual_write(res, prefix, err);
  if (!st && rank == 0 && !u->quiet) render_annual_report(scene, res, prefix);
  vr_annual_result_destroy(res);
  return st;
}

/* ---- main ---- */

/* A checksum of what every rank must render alike: the scene file's bytes
 * and the options that change the result. */
static void digest_of(const char *path, const vr_render_options *o, const render_overrides *ov,
                      unsigned char out[32]) {
  vr_sha256 c;
  vr_sha256_init(&c);
  char *text = NULL;
  size_t len = 0;
  if (!vr_read_file(path, 0, &text, &len, NULL)) vr_sha256_update(&c, text, len);
  free(text);
  char opts[256], more[8192];
  /* What changes the ranks' work or their collective calls (the film's
   * bins are summed over the ranks only when kept). */
  snprintf(opts, sizeof opts,
           "S=%d spp=%d photons=%ld image_space=%d no_camera=%d bins=%d target=%.17g "
           "limit=%.17g max_spp=%d denoise=%d",
           o->subdomains, o->spp, o->photons, o->image_space, o->no_camera,
           !o->film_without_bins, o->target_error, o->time_limit_s, o->max_spp, o->denoise);
  vr_sha256_update(&c, opts, strlen(opts));
  render_overrides_text(ov, more, sizeof more);
  vr_sha256_update(&c, more, strlen(more));
  if (ov->render) vr_sha256_update(&c, ov->render, strlen(ov->render) + 1);
  char hex[65];
  vr_sha256_final(&c, hex);
  for (int i = 0; i < 32; i++) {
    unsigned v = 0;
    sscanf(hex + 2 * i, "%2x", &v);
    out[i] = (unsigned char)v;
  }
}

static int run_tool(const vr_args *a, int argc, char **argv, vr_comm *comm) {
  if (vr_args_get(a, "verify")) {
    if (a->noperands)
      return render_usage_error("--verify PREFIX checks written files: it takes no scene file");
    return render_verify(vr_args_get(a, "verify"), vr_args_flag(a, "quiet"));
  }
  if (a->noperands != 1) return render_usage_error("expected one scene file, got %zu", a->noperands);
  render_overrides ov;
  if (render_overrides_parse(a, argc, argv, OPTIONS, NOPT, &ov)) return 2;
  vr_render_options opt;
  vr_render_options_default(&opt);
  long cpus = sysconf(_SC_NPROCESSORS_ONLN);
  long subdomains = 1, spp = 0, photons = 0, batch = 256, credit = 0, max_spp = 0;
  long threads = cpus > 0 ? (cpus < VR_MAX_THREADS ? cpus : VR_MAX_THREADS) : 1;
  if (!int_option(a, "subdomains", 1, VR_MAX_SUBDOMAINS, &subdomains) ||
      !int_option(a, "send-batch", 1, 1 << 20, &batch) ||
      !int_option(a, "send-credit", 1, 1 << 24, &credit) ||
      !int_option(a, "threads", 1, VR_MAX_THREADS, &threads) || !int_option(a, "spp", 1, 1L << 20, &spp) ||
      !int_option(a, "photons", 1, 1000000000000L, &photons) ||
      !int_option(a, "max-spp", 2, 1L << 30, &max_spp) ||
      !real_option(a, "target-error", 1e-6, 0.5, true,
                   "a relative error in [1e-6, 0.5], e.g. 0.02 or 2%", &opt.target_error) ||
      !real_option(a, "time-limit", 1e-3, 1e9, false, "seconds in [0.001, 1e9]",
                   &opt.time_limit_s))
    return 2;
  if (vr_args_get(a, "max-spp") && !vr_args_get(a, "target-error") && !vr_args_get(a, "time-limit"))
    return render_usage_error("--max-spp bounds adaptive sampling: give --target-error or "
                              "--time-limit (else --spp sets the samples)");
  opt.max_spp = (int)max_spp;
  size_t budget = 0;
  vr_error aerr = {0};
  if (vr_args_size(a, "memory-budget", 0, &budget, &aerr)) return render_usage_error("%s", aerr.message);
  if (budget && vr_args_flag(a, "image-space"))
    return render_usage_error("--image-space keeps the whole scene in every thread: it cannot run under "
                       "--memory-budget");
  /* Options that would change nothing are refused, not ignored. */
  if (vr_args_get(a, "send-batch") && vr_comm_size(comm) == 1)
    return render_usage_error("--send-batch sets the messages between mpirun ranks: this process runs "
                       "alone");
  if (vr_args_get(a, "send-credit") && vr_comm_size(comm) == 1)
    return render_usage_error("--send-credit sets the flow control between mpirun ranks: this process "
                       "runs alone");
  if (vr_args_flag(a, "flow-profile") &&
      (!vr_args_get(a, "stats") || vr_args_flag(a, "image-space") || vr_comm_size(comm) > 1))
    return render_usage_error("--flow-profile records one process's queued flow into the statistics: "
                              "it needs --stats, and neither --image-space nor mpirun");
  /* The PNG's default is the film curve: a daylit interior's walls (100 to
   * 600 cd/m2) and its windows keep their gradation at the camera's EV
   * instead of burning out above 100 cd/m2 (docs/vr-render.md, "Exposure
   * and tone mapping"). */
  const char *tonemap = vr_args_get(a, "tonemap");
  if (!tonemap) tonemap = "filmic";
  vr_tonemap tm = VR_TONEMAP_CLIP;
  if (vr_tonemap_parse(tonemap, &tm, NULL))
    return render_usage_error("--tonemap '%s': expected clip, reinhard or filmic", tonemap);
  vr_film_options fo = {.tonemap = tonemap};
  const char *fc = vr_args_get(a, "falsecolour");
  if (fc) {
    char *end = NULL;
    fo.falsecolour_lo_cd_m2 = strtod(fc, &end);
    if (*end == ',') fo.falsecolour_hi_cd_m2 = strtod(end + 1, &end);
    if (*end || !(fo.falsecolour_lo_cd_m2 > 0) ||
        !(fo.falsecolour_hi_cd_m2 > fo.falsecolour_lo_cd_m2) || !isfinite(fo.falsecolour_hi_cd_m2))
      return render_usage_error("--falsecolour '%s': expected LO,HI in cd/m2 with 0 < LO < HI", fc);
  }
  const char *given = vr_args_get(a, "output");
  unsigned asked = 0, outputs = 0;
  if (render_outputs_parse(a, &asked)) return 2;
  bool json = vr_args_flag(a, "json");
  int rank = vr_comm_rank(comm);
  /* Only rank 0 speaks (and writes). */
  ui u = {.quiet = vr_args_flag(a, "quiet") || rank != 0, .lines = !isatty(fileno(stderr)),
          .tenth = -1};
  pthread_mutex_init(&u.lock, NULL);
  opt.subdomains = (int)subdomains;
  opt.threads = (int)threads;
  opt.image_space = vr_args_flag(a, "image-space");
  opt.denoise = vr_args_flag(a, "denoise");
  opt.flow_profile = vr_args_flag(a, "flow-profile");
  opt.memory_budget = budget;
  opt.spp = (int)spp;
  opt.photons = photons;
  opt.comm = comm;
  opt.send_batch = (int)batch;
  opt.send_credit = (int)credit;
  opt.log = ui_log;
  opt.progress = ui_progress;
  opt.user = &u;

  const char *path = a->operands[0], *stats = vr_args_get(a, "stats");
  const char *db_path = vr_args_get(a, "db") ? vr_args_get(a, "db") : vr_matdb_default_path();
  vr_error err = {0};
  vr_scene *scene = NULL;
  vr_matdb *db = NULL;
  vr_render_result *r = NULL;
  render_outputs outs = {0};
  char *prefix = NULL, *cache_dir = NULL;
  char run_id[VR_FILM_RUN_ID_MAX];
  vr_film_run_id(run_id);
  int rc = 1;
  bool agreed = false;
  created_db db_created = {0};
  const char *cache = vr_args_get(a, "cache");
  if (!(prefix = given ? strdup(given) : default_prefix(path))) {
    vr_error_set(&err, VR_E_NOMEM, "out of memory");
    goto ready;
  }
  if (vr_scene_read_with(path, ov.render, &scene, &err) || vr_scene_load_models(scene, &err))
    goto ready;
  if (render_overrides_apply(&ov, scene, &err) || render_options_check(a, scene, &err)) goto ready;
  /* No camera line: the scene exists for its sensors. */
  opt.no_camera = vr_args_flag(a, "sensors-only") || !scene->camera.given;
  if (opt.no_camera && scene->nsensors == 0) {
    vr_error_set(&err, VR_E_ARG, "%s: --sensors-only, but the scene has no sensor line", path);
    goto ready;
  }
  if (render_outputs_choose(asked, scene, opt.no_camera, &outputs, &err)) goto ready;
  /* Without the spectral EXR the film keeps XYZ only (3 doubles a pixel, not 33). */
  opt.film_without_bins = !(outputs & VR_FILM_SPECTRAL);
  /* Every output before any work: a wrong path costs a second, not a render. */
  if (rank == 0) {
    if (render_outputs_check(scene, prefix, stats, db_path, outputs, fc != NULL, &outs, &err))
      goto ready;
    /* OpenCV, for the PNGs, now rather than after the render (vr/image.h). */
    bool png = !scene->sky.annual && ((outputs & VR_FILM_PNG) || fc);
    if (png && vr_image_codecs_load(&err)) {
      vr_error_prefix(&err, "%s%s: ", prefix, outputs & VR_FILM_PNG ? ".png" : ".falsecolour.png");
      goto ready;
    }
    render_clean_stale(prefix, stats, ui_log, &u);
  }
  if (rank == 0) log_perez(&u, scene);
  if (!cache) {
    char why[4400];
    cache = cache_dir = default_cache(path, why, sizeof why);
    if (!cache) ui_log(&u, why);
  }
  opt.cache_dir = cache;
  if (!open_db(vr_args_get(a, "db"), scene, &u, &db, &db_created, &err))
    render_overrides_check_db(&ov, scene, db, &err);
ready:
  /* Every rank ready, or every rank told why not. */
  if (vr_comm_agree(comm, err.status, &err)) goto fail;
  opt.has_digest = true;
  digest_of(path, &opt, &ov, opt.scene_digest);
  if (scene->sky.annual) {
    rc = annual(scene, db, &opt, prefix, rank, &u, &err) ? 1 : 0;
    agreed = rc != 0;
    goto out;
  }
  if (vr_render_scene(scene, db, &opt, &r, &err)) goto fail;
  ui_end(&u);
  double t0 = now_s();
  if (rank == 0) {
    if (ov.exposure_auto && r->width > 0 && r->height > 0 &&
        !vr_film_auto_exposure(r, &r->exposure_ev))
      ui_log(&u, "--exposure auto: the image has no light; exposure left at the camera's");
    fo.stats_path = stats;
    fo.run_id = run_id;
    fo.outputs = outputs;
    fo.camera = &scene->camera;
    if (vr_film_write_with(r, prefix, &fo, &err)) goto out;
    render_report rep = {.scene = path, .prefix = prefix, .stats = stats, .run_id = run_id,
                         .outputs = &outs, .falsecolour = fc != NULL,
                         .exposure_auto = ov.exposure_auto, .film_seconds = now_s() - t0};
    if (json) render_summary_json(scene, r, &rep);
    else if (!u.quiet) render_summary_text(scene, r, &rep);
  }
  rc = 0;
  goto out;
fail:
  agreed = true;
out:
  ui_end(&u);
  /* A failure of rank 0's own (writing the outputs) is its alone. */
  if (rc && (rank == 0 || !agreed)) fprintf(stderr, "vr-render: %s\n", err.message);
  if (r) vr_render_result_destroy(r);
  render_outputs_free(&outs);
  vr_matdb_close(db);
  if (rc && db_created.created && rank == 0) remove_created_db(db_path, &db_created, &u);
  vr_scene_destroy(scene);
  free(prefix);
  free(cache_dir);
  pthread_mutex_destroy(&u.lock);
  return rc;
}

int main(int argc, char **argv) {
  /* Under mpirun, MPI starts first (it may take its own arguments). */
  vr_comm *comm = NULL;
  vr_error err = {0};
  if (vr_comm_init(&argc, &argv, &comm, &err)) {
    fprintf(stderr, "vr-render: %s\n", err.message);
    return 1;
  }
  vr_args a;
  vr_args_outcome o = vr_args_parse(&a, "vr-render", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  int rc = o == VR_ARGS_EXIT_OK ? 0 : o == VR_ARGS_EXIT_USAGE ? 2 : run_tool(&a, argc, argv, comm);
  if (o == VR_ARGS_RUN) vr_args_free(&a);
  vr_comm_finalize(comm);
  return rc;
}
