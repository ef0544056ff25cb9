/* vr-rgb2spec: reflectance spectra from RGB photos of the same scene under
 * several known lights (Cohen-Kappauf Matrix R), with round-trip accuracy
 * reports.  This file runs the command and recovers the regions' spectra;
 * rgb2spec_measure.c reads the photos and measures the regions,
 * rgb2spec_output.c prints and saves, rgb2spec_simulate.c makes synthetic
 * captures. */
#include "rgb2spec.h"
#include "rgb2spec_inputs.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <errno.h>
#include <unistd.h>

#include "vr/colour.h"

static const vr_option OPTIONS[] = {
    {"manifest", 'm', "FILE", "capture manifest (default: manifest.txt beside the first photo)"},
    {"method", 0, "NAME", "matrix-r, bounded, regularised or auto (default: regularised, weighted by the measured noise)"},
    {"lambda-rule", 0, "NAME", "regularised smoothing from the noise: upre (default), discrepancy or gcv"},
    {"force", 0, NULL, "save and write even when a region misses its photos or a light disagrees with its photo"},
    {"save-prefix", 's', "P|''", "save each region's spectrum as material P<region> ('' saves it as <region>)"},
    {"db", 'd', "FILE", "material database (default: $VR_MATDB, else ./materials.db)"},
    {"report", 'r', "FILE.html", "HTML report with plots and a swatch image"},
    {"json", 'j', NULL, "JSON output"},
    {"per-pixel", 0, "FILE.exr", "also recover every pixel (regularised, bounded to [0, 1]) into a spectral EXR"},
    {"exr-compression", 0, "NAME", "with --per-pixel: none (default, fastest), rle, zips, zip or piz (smallest)"},
    {"exr-float", 0, NULL, "with --per-pixel: 32-bit float bands instead of 16-bit half"},
    {"texture", 0, "NAME", "with --per-pixel: save material NAME referencing the EXR (mean spectrum as 'value')"},
    {"threads", 0, "N", "threads for reading photos and --per-pixel (default 2)"},
    {"noise", 0, "SIGMA", "simulate: Gaussian noise on linear values (default 0.002)"},
    {"seed", 0, "N", "simulate: random seed (default 1)"},
    {"size", 0, "WxH", "simulate: photo size (default 640x480)"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "PHOTOS... [--manifest FILE] [--method matrix-r|bounded|regularised] [--lambda-rule R]\n"
    "                  [--save-prefix P] [--force] [--db FILE] [--report FILE.html] [--json]\n"
    "                  [--per-pixel FILE.exr [--texture NAME] [--exr-compression C] [--exr-float]]\n"
    "       vr-rgb2spec simulate --manifest FILE [--noise SIGMA] [--seed N] [--size WxH]\n"
    "       vr-rgb2spec calibrate PHOTO --light NAME|FILE [options] (see calibrate --help)";
static const char ABOUT[] =
    "Recovers reflectance spectra of the regions named in a capture manifest from photos\n"
    "taken under several known lights (docs/vr-rgb2spec.md).  matrix-r: the fundamental\n"
    "metamer of the stacked system (exact round trip, may leave [0, 1]); bounded: the\n"
    "smoothest spectrum in [0, 1] with the recorded responses; regularised (the default):\n"
    "smooth least squares weighted by the noise measured in each region, its smoothing\n"
    "chosen from that noise (unbiased predictive risk), then bounded to [0, 1].\n"
    "Reports per region and light the photo's and the re-rendered RGB and CIEDE2000 (lights\n"
    "with a clipped channel apart), the spectral RMSE and held-out-light CIEDE2000 where a\n"
    "reference is known, and the condition number of the system.  Exit status 1 when a\n"
    "region misses its photos by more than their noise explains or a photo disagrees with\n"
    "its light; --save-prefix, --per-pixel and --texture then save and write nothing unless\n"
    "--force (the report is written).  Outputs never replace an input of the run (photos,\n"
    "manifest, the files it reads, the database): checked before any photo is read.\n"
    "--per-pixel writes a spectral EXR texture with the same prior and bounds and a flags\n"
    "channel.  simulate renders the manifest's regions from their reference spectra into\n"
    "photos (noise, then 8-bit sRGB, or 16-bit for encoding=linear).";

static int fail(const vr_error *e) {
  fprintf(stderr, "vr-rgb2spec: %s\n", e->message);
  return 1;
}

double rg_delta_e(const rg_run *run, size_t l, const double a[3], const double b[3]) {
  /* White: the responses to a perfect reflector under that light. */
  const double *A = vr_recovery_system_matrix(run->sys);
  double w[3] = {0, 0, 0}, xa[3], xb[3], xw[3], la[3], lb[3];
  for (int ch = 0; ch < 3; ch++)
    for (size_t j = 0; j < run->n; j++) w[ch] += A[(3 * l + ch) * run->n + j];
  vr_srgb_linear_to_xyz(a, xa);
  vr_srgb_linear_to_xyz(b, xb);
  vr_srgb_linear_to_xyz(w, xw);
  vr_xyz_to_lab(xa, xw, la);
  vr_xyz_to_lab(xb, xw, lb);
  return vr_delta_e2000(la, lb);
}

/* Reference spectrum on the grid: RMSE, and CIEDE2000 under held-out lights. */
static void compare_reference(rg_run *run, rg_region *g) {
  const vr_spectrum *ref = g->def->reference;
  g->rmse = NAN;
  g->nheldout = 0;
  if (!ref) return;
  double se = 0;
  for (size_t j = 0; j < run->n; j++) {
    double d = g->r[j] - vr_spectrum_eval(ref, run->grid[j], VR_INTERP_LINEAR);
    se += d * d;
  }
  g->rmse = sqrt(se / (double)run->n);
  vr_spectrum *rec = vr_spectrum_create(run->n, run->grid, g->r, NULL);
  for (size_t h = 0; rec && h < run->nheldout; h++) {
    vr_spectrum *L = vr_illuminant(run->heldout_name[h], NULL);
    if (!L) continue;
    double x1[3], x2[3], w[3], l1[3], l2[3];
    vr_xyz_reflectance(ref, L, VR_CIE1931_2DEG, x1);
    vr_xyz_reflectance(rec, L, VR_CIE1931_2DEG, x2);
    vr_xyz_white(L, VR_CIE1931_2DEG, w);
    vr_xyz_to_lab(x1, w, l1);
    vr_xyz_to_lab(x2, w, l2);
    g->heldout_de[g->nheldout++] = vr_delta_e2000(l1, l2);
    vr_spectrum_destroy(L);
  }
  vr_spectrum_destroy(rec);
}

/* auto: decided once the photos are read (m = -1 until then). */
static vr_status parse_method(const char *s, vr_recover_method *m, vr_error *err) {
  if (!s || !strcasecmp(s, "auto")) *m = (vr_recover_method)-1;
  else if (!strcasecmp(s, "bounded")) *m = VR_RECOVER_BOUNDED;
  else if (!strcasecmp(s, "matrix-r")) *m = VR_RECOVER_MATRIX_R;
  else if (!strcasecmp(s, "regularised") || !strcasecmp(s, "regularized")) *m = VR_RECOVER_REGULARISED;
  else return vr_error_set(err, VR_E_ARG, "--method '%s': expected matrix-r, bounded or regularised", s);
  return VR_OK;
}

static vr_status parse_rule(const char *s, vr_lambda_rule *rule, vr_error *err) {
  if (!s || !strcasecmp(s, "auto") || !strcasecmp(s, "upre")) *rule = s && !strcasecmp(s, "upre") ? VR_LAMBDA_UPRE : VR_LAMBDA_AUTO;
  else if (!strcasecmp(s, "discrepancy")) *rule = VR_LAMBDA_DISCREPANCY;
  else if (!strcasecmp(s, "gcv")) *rule = VR_LAMBDA_GCV;
  else return vr_error_set(err, VR_E_ARG, "--lambda-rule '%s': expected upre, discrepancy or gcv", s);
  return VR_OK;
}

static char *default_manifest(const char *photo) {
  const char *slash = strrchr(photo, '/');
  size_t n = slash ? (size_t)(slash - photo) + 1 : 0;
  char *s = malloc(n + 16);
  if (s) {
    memcpy(s, photo, n);
    strcpy(s + n, "manifest.txt");
  }
  return s;
}

/* The run's outputs against the inputs in g and against each other:
 * --report (and the swatch image beside it) and --per-pixel. */
static vr_status check_outputs(const vr_out_guard *g, const char *report, const char *pixels,
                               vr_error *err) {
  char swatch[4200];
  vr_status st = VR_OK;
  if (report) {
    snprintf(swatch, sizeof swatch, "%s.swatch.png", report);
    if ((st = vr_out_guard_check(g, report, "--report", err)) ||
        (st = vr_out_guard_check(g, swatch, "--report's swatch image", err)))
      return st;
  }
  if (pixels && (st = vr_out_guard_check(g, pixels, "--per-pixel", err))) return st;
  if (report && pixels &&
      ((st = vr_out_guard_distinct(report, "--report", pixels, "--per-pixel", err)) ||
       (st = vr_out_guard_distinct(swatch, "--report's swatch image", pixels, "--per-pixel", err))))
    return st;
  return VR_OK;
}

/* What one recovery run holds between its steps, so that each step can
 * fail with a plain return and free_recover_cmd releases it all once. */
typedef struct recover_cmd {
  vr_args *a;
  const char *prefix, *pixels, *texture, *report;
  int threads;
  rg_pixel_options popt;
  char *mpath;
  vr_matdb *db;
  vr_capture *cap;
  vr_camera *cam;
  rg_run run;
  vr_image img[RGB2SPEC_MAX_LIGHTS];
  rg_pixels px;
} recover_cmd;

/* The options checked before any file is opened, in the order the user
 * hears of them.  Returns 0, 1 (err filled) or 2 (usage already told on
 * stderr: exit status 2). */
/* A wrong option value: told on stderr now, exit status 2. */
static int usage(const vr_error *err) {
  fprintf(stderr, "vr-rgb2spec: %s\nTry 'vr-rgb2spec --help' for more information.\n", err->message);
  return 2;
}

static int read_options(recover_cmd *c, vr_error *err) {
  vr_args *a = c->a;
  const char *manifest = vr_args_get(a, "manifest");
  c->prefix = vr_args_get(a, "save-prefix");
  c->pixels = vr_args_get(a, "per-pixel");
  c->texture = vr_args_get(a, "texture");
  c->popt = (rg_pixel_options){.threads = 2, .compression = VR_EXR_COMPRESSION_NONE, .half = true};
  c->threads = 2;
  if (vr_args_get(a, "threads")) {
    char *end;
    long t = strtol(vr_args_get(a, "threads"), &end, 10);
    if (*end || t < 1 || t > 256) {
      vr_error_set(err, VR_E_ARG, "--threads '%s': expected 1 to 256", vr_args_get(a, "threads"));
      return usage(err);
    }
    c->threads = (int)t;
  }
  c->popt.threads = c->threads;
  c->popt.half = !vr_args_flag(a, "exr-float");
  if (vr_args_get(a, "exr-compression") &&
      vr_exr_compression_parse(vr_args_get(a, "exr-compression"), &c->popt.compression, err))
    return usage(err);
  if (c->texture && !c->pixels) {
    vr_error_set(err, VR_E_ARG, "--texture needs --per-pixel FILE.exr");
    return usage(err);
  }
  if (parse_method(vr_args_get(a, "method"), &c->run.method, err)) return usage(err);
  if (!manifest && a->noperands == 0) {
    vr_error_set(err, VR_E_ARG, "give photos or --manifest FILE");
    return usage(err);
  }
  c->mpath = manifest ? strdup(manifest) : default_manifest(a->operands[0]);
  if (!c->mpath) {
    vr_error_set(err, VR_E_NOMEM, "out of memory");
    return 1;
  }
  c->report = vr_args_get(a, "report");
  return 0;
}

/* Reads the manifest and opens the database, with the outputs checked
 * before any work: first against what the command line names (nothing is
 * opened or created yet), then against every file the manifest reads. */
static vr_status open_capture(recover_cmd *c, vr_error *err) {
  vr_args *a = c->a;
  vr_out_guard *guard = calloc(1, sizeof *guard);
  if (!guard) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_out_guard_init(guard);
  if (strcmp(c->mpath, "-")) vr_out_guard_input(guard, c->mpath, "the capture manifest");
  for (size_t i = 0; i < a->noperands; i++) vr_out_guard_input(guard, a->operands[i], "a photo");
  vr_out_guard_database(guard, vr_args_get(a, "db") ? vr_args_get(a, "db") : vr_matdb_default_path());
  vr_status st = check_outputs(guard, c->report, c->pixels, err);
  /* Lookups alone (db: lights or references) open the database read-only:
   * a missing one is an error, never created and seeded here. */
  bool saves = c->prefix || c->texture;
  if (!st)
    st = vr_capture_read_db(c->mpath, vr_args_get(a, "db"), saves ? 0 : VR_MATDB_READONLY, saves,
                            &c->db, &c->cap, err);
  if (!st) {
    rg_guard_capture(guard, c->cap, true);
    st = check_outputs(guard, c->report, c->pixels, err);
  }
  free(guard);
  /* A save that cannot happen is said now, not after the recovery. */
  if (!st && saves) st = vr_matdb_require_writable(c->db, err);
  c->run.cap = c->cap;
  return st;
}

/* The photos: those given, each of which the manifest must list; or all. */
static vr_status choose_photos(recover_cmd *c, vr_error *err) {
  rg_run *run = &c->run;
  if (c->a->noperands == 0) {
    for (size_t i = 0; i < c->cap->nphotos && i < RGB2SPEC_MAX_LIGHTS; i++)
      run->photo[run->nphotos++] = &c->cap->photos[i];
    return VR_OK;
  }
  for (size_t i = 0; i < c->a->noperands; i++) {
    const vr_capture_photo *p = vr_capture_find_photo(c->cap, c->a->operands[i]);
    if (!p)
      return vr_error_set(err, VR_E_NOT_FOUND, "photo %s is not listed in the manifest %s (add a "
                                               "'photo FILE light=...' line)", c->a->operands[i], c->mpath);
    if (run->nphotos == RGB2SPEC_MAX_LIGHTS)
      return vr_error_set(err, VR_E_ARG, "at most %d photos", RGB2SPEC_MAX_LIGHTS);
    run->photo[run->nphotos++] = p;
  }
  return VR_OK;
}

/* The photos themselves, decoded on `threads` threads, all of one size
 * because the regions are pixel positions. */
static vr_status load_photos(recover_cmd *c, vr_error *err) {
  rg_run *run = &c->run;
  vr_image *img = c->img;
  vr_status st = rg_read_photos(run, img, c->threads, err);
  for (size_t l = 0; !st && l < run->nphotos; l++) {
    if ((st = rg_check_photo(c->cap, run->photo[l], &img[l], stderr, err))) break;
    if (l && (img[l].width != img[0].width || img[l].height != img[0].height))
      st = vr_error_set(err, VR_E_ARG, "%s is %dx%d but %s is %dx%d: the regions are pixel positions, "
                                       "so every photo must have the same size", run->photo[l]->path,
                        img[l].width, img[l].height, run->photo[0]->path, img[0].width, img[0].height);
  }
  return st;
}

/* The method, the camera and the recovery system of the chosen photos'
 * lights: what every region's recovery shares. */
static vr_status build_system(recover_cmd *c, vr_error *err) {
  rg_run *run = &c->run;
  const vr_capture *cap = c->cap;
  /* The regularised method weighs every response by its measured noise and
   * chooses its smoothing from it, so it suits any file: at vanishing
   * noise it tends to the bounded method's smoothest exact fit
   * (bench_rgb2spec_noise, docs/vr-rgb2spec.md). */
  if ((int)run->method == -1) run->method = VR_RECOVER_REGULARISED;
  run->method_name = run->method == VR_RECOVER_MATRIX_R ? "matrix-r"
                     : run->method == VR_RECOVER_BOUNDED ? "bounded" : "regularised";
  double grid[1024];
  size_t n;
  vr_status st = vr_camera_grid_uniform(cap->grid[0], cap->grid[1], cap->grid[2], grid, 1024, &n, err);
  if (st) return st;
  c->cam = cap->camera == VR_CAPTURE_CAMERA_SRGB
               ? vr_camera_create_srgb(n, grid, err)
               : vr_camera_create_measured((const vr_spectrum *const *)cap->sens, n, grid, err);
  if (!c->cam) return err->status ? err->status : VR_E_NOMEM;
  run->cam = c->cam;
  const vr_spectrum *lights[RGB2SPEC_MAX_LIGHTS];
  double scale[RGB2SPEC_MAX_LIGHTS];
  for (size_t l = 0; l < run->nphotos; l++) lights[l] = run->photo[l]->light, scale[l] = run->photo[l]->scale;
  vr_recovery_options opt;
  vr_recovery_options_default(&opt);
  if ((st = parse_rule(vr_args_get(c->a, "lambda-rule"), &opt.lambda_rule, err))) return st;
  if (!(run->sys = vr_recovery_system_create(c->cam, run->nphotos, lights, scale, &opt, err)))
    return err->status ? err->status : VR_E_NOMEM;
  run->n = vr_recovery_system_samples(run->sys);
  run->grid = vr_recovery_system_grid(run->sys);
  run->condition = vr_recovery_system_condition(run->sys);
  return VR_OK;
}

/* The lights of a fixed list that no photo used, under which a region with
 * a reference is then compared: colour outside the fit.  A light counts as
 * used whatever it was called (file:d65.csv is D65). */
static void choose_heldout(rg_run *run) {
  static const char *const HELD[] = {"A", "D50", "D65", "F2", "F11", "LED-B3"};
  for (size_t h = 0; h < 6; h++) {
    vr_spectrum *cand = vr_illuminant(HELD[h], NULL);
    bool used = !cand;
    for (size_t l = 0; l < run->nphotos && !used; l++)
      used = !strcasecmp(run->photo[l]->light_name, HELD[h]) || rg_same_light(cand, run->photo[l]->light);
    if (!used) run->heldout_name[run->nheldout++] = HELD[h];
    vr_spectrum_destroy(cand);
  }
}

/* Regions, measured in every photo. */
static vr_status measure_regions(recover_cmd *c, vr_error *err) {
  rg_run *run = &c->run;
  run->nregions = c->cap->nregions;
  if (run->nregions == 0)
    return vr_error_set(err, VR_E_ARG, "%s names no region (region, chart lines)", c->mpath);
  run->regions = calloc(run->nregions, sizeof *run->regions);
  if (!run->regions) return VR_E_NOMEM;
  for (size_t i = 0; i < run->nregions; i++) run->regions[i].def = &c->cap->regions[i];
  return rg_measure_photos(run, c->img, c->threads, err);
}

/* Recovery of one region and its round trip.  CIEDE2000 against the photo
 * is a colour difference only where the photo holds a colour: a light with
 * a clipped channel is left out of the mean and max and counted apart. */
static vr_status recover_region(rg_run *run, rg_region *g, vr_error *err) {
  if (!(g->r = malloc(run->n * sizeof *g->r))) return VR_E_NOMEM;
  vr_status st = vr_recover_noisy(run->sys, run->method, g->c, g->sigma, g->clipped, g->r, &g->info, err);
  if (st) {
    vr_error_prefix(err, "region %s: ", g->def->name);
    return st;
  }
  vr_render_rgb(run->sys, g->r, g->rendered);
  g->de_mean = 0;
  g->de_max = 0;
  size_t counted = 0;
  for (size_t l = 0; l < run->nphotos; l++) {
    if (g->clipped[3 * l] || g->clipped[3 * l + 1] || g->clipped[3 * l + 2]) {
      g->de[l] = NAN;
      g->nclipped_lights++;
      continue;
    }
    g->de[l] = rg_delta_e(run, l, &g->c[3 * l], &g->rendered[3 * l]);
    g->de_mean += g->de[l];
    g->de_max = fmax(g->de_max, g->de[l]);
    counted++;
  }
  if (counted) g->de_mean /= (double)counted;
  else g->de_mean = g->de_max = NAN;
  g->misfit = (g->info.flags & VR_RECOVER_FLAG_MISFIT) != 0;
  run->nmisfit += g->misfit;
  compare_reference(run, g);
  return VR_OK;
}

/* What the recovery cannot stand behind, said on stderr: regions that miss
 * their photos (with a hint on the photos' encoding) and photos that do not
 * look lit by their light.  Returns whether there was any. */
static bool tell_doubts(const recover_cmd *c) {
  const rg_run *run = &c->run;
  bool doubtful = run->nmisfit > 0;
  size_t told = 0;
  for (size_t i = 0; i < run->nregions; i++)
    if (run->regions[i].misfit && ++told <= 5)
      fprintf(stderr, "vr-rgb2spec: region %s: the recovered spectrum misses its photos by more "
                      "than their noise explains (chi2 %.3g > %.3g for %zu channels)%s\n",
              run->regions[i].def->name, run->regions[i].info.chi2, run->regions[i].info.chi2_limit,
              run->regions[i].info.used,
              run->regions[i].info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT ? "; out of gamut" : "");
  if (told > 5) fprintf(stderr, "vr-rgb2spec: ... and %zu more regions miss their photos\n", told - 5);
  for (size_t l = 0; told && l < run->nphotos; l++) {
    const char *hint = rg_encoding_hint(c->cap, run->photo[l], &c->img[l]);
    if (hint) fprintf(stderr, "vr-rgb2spec: %s: %s\n", run->photo[l]->path, hint);
  }
  for (size_t l = 0; l < run->nphotos; l++)
    if (run->light_suspect[l]) {
      doubtful = true;
      fprintf(stderr, "vr-rgb2spec: %s:%ld: photo %s does not look lit by %s: the regions "
                      "recovered from the other photos, rendered under %s, miss it by a median "
                      "CIEDE2000 of %.1f (limit %.0f); check the light of this photo (two photos' "
                      "lights swapped?)\n", c->cap->path, run->photo[l]->line, run->photo[l]->path,
              run->photo[l]->light_name, run->photo[l]->light_name, run->loo_de[l], RG_LOO_LIMIT);
    }
  return doubtful;
}

/* --per-pixel (and --texture).  With --texture the EXR is written beside
 * its final name and put in place only once its database row is saved: a
 * failed save leaves neither, and an earlier file of that name as it was. */
static vr_status write_pixels(recover_cmd *c, bool forced, vr_error *err) {
  char tmpname[4200];
  const char *target = c->pixels;
  if (c->texture) {
    snprintf(tmpname, sizeof tmpname, "%s.part-%ld", c->pixels, (long)getpid());
    target = tmpname;
  }
  vr_status st = rg_per_pixel(&c->run, c->img, target, &c->popt, &c->px, err);
  if (st) return st;
  rg_print_pixels(vr_args_flag(c->a, "json") ? stderr : stdout, &c->run, &c->px, c->pixels);
  if (!c->texture) return VR_OK;
  if ((st = rg_save_texture(c->db, c->texture, target, c->pixels, &c->run, &c->px, forced, err))) {
    remove(target);
    return st;
  }
  if (rename(target, c->pixels))
    return vr_error_set(err, VR_E_IO, "%s: cannot put the texture in place (%s left as written): %s; "
                                      "material '%s' names %s", c->pixels, target, strerror(errno),
                        c->texture, c->pixels);
  return VR_OK;
}

/* The report, written either way since it shows what went wrong; the
 * saves and the per-pixel texture only when the recovery can stand behind
 * them, or with --force. */
static vr_status write_outputs(recover_cmd *c, bool doubtful, bool force, vr_error *err) {
  vr_status st;
  if (c->report && (st = rg_write_report(c->report, &c->run, err))) return st;
  if ((c->prefix || c->pixels) && doubtful && !force) {
    bool saves = c->prefix || c->texture, both = saves && c->pixels;
    return vr_error_set(err, VR_E_ARG, "nothing %s: %zu region(s) miss their photos or a light "
                                       "disagrees with its photo (see above); --force %s anyway",
                        both ? "saved or written" : saves ? "saved" : "written", c->run.nmisfit,
                        both ? "saves and writes" : saves ? "saves" : "writes");
  }
  if (c->prefix && (st = rg_save(c->db, c->prefix, &c->run, force && doubtful, err))) return st;
  if (c->pixels) return write_pixels(c, force && doubtful, err);
  return VR_OK;
}

/* One place releases what the steps made, whichever of them failed. */
static void free_recover_cmd(recover_cmd *c) {
  rg_run *run = &c->run;
  for (size_t i = 0; i < run->nregions && run->regions; i++) free(run->regions[i].r);
  free(run->regions);
  for (size_t l = 0; l < RGB2SPEC_MAX_LIGHTS; l++) vr_image_free(&c->img[l]);
  vr_recovery_system_destroy(run->sys);
  vr_camera_destroy(c->cam);
  vr_capture_destroy(c->cap);
  vr_matdb_close(c->db);
  free(c->mpath);
  rg_pixels_free(&c->px);
}

static int cmd_recover(vr_args *a) {
  recover_cmd c = {.a = a};
  vr_error err = {0};
  int rc = read_options(&c, &err);
  if (rc == 2) goto out_quiet;
  if (rc) goto out;
  rc = 1;
  if (open_capture(&c, &err) || choose_photos(&c, &err) || load_photos(&c, &err) ||
      build_system(&c, &err))
    goto out;
  choose_heldout(&c.run);
  if (measure_regions(&c, &err)) goto out;
  for (size_t i = 0; i < c.run.nregions; i++)
    if (recover_region(&c.run, &c.run.regions[i], &err)) goto out;
  if (rg_check_lights(&c.run, &err)) goto out;
  if (vr_args_flag(a, "json")) rg_print_json(&c.run);
  else rg_print_text(&c.run);
  bool doubtful = tell_doubts(&c), force = vr_args_flag(a, "force");
  if (write_outputs(&c, doubtful, force, &err)) goto out;
  /* The exit status is 1 unless --force when the recovery has doubts. */
  if (doubtful && !force) goto out_quiet;
  rc = 0;
out:
  if (rc) fail(&err);
out_quiet:
  free_recover_cmd(&c);
  return rc;
}

int main(int argc, char **argv) {
  if (argc > 1 && !strcmp(argv[1], "calibrate")) return rg_cmd_calibrate(argc - 1, argv + 1);
  vr_args a;
  vr_args_outcome o = vr_args_parse(&a, "vr-rgb2spec", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  int rc;
  if (a.noperands >= 1 && !strcmp(a.operands[0], "simulate")) {
    rc = rg_cmd_simulate(&a);
  } else {
    rc = cmd_recover(&a);
  }
  vr_args_free(&a);
  return rc;
}
