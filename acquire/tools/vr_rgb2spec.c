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
    {"save-prefix", 's', "P", "save each region's spectrum as material P<region>"},
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

static int cmd_recover(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_capture *cap = NULL;
  vr_camera *cam = NULL;
  rg_run run = {0};
  vr_image img[RGB2SPEC_MAX_LIGHTS] = {0};
  char *mpath = NULL;
  int rc = 1;
  const char *manifest = vr_args_get(a, "manifest"), *prefix = vr_args_get(a, "save-prefix");
  const char *pixels = vr_args_get(a, "per-pixel"), *texture = vr_args_get(a, "texture");
  rg_pixels px = {0};
  rg_pixel_options popt = {.threads = 2, .compression = VR_EXR_COMPRESSION_NONE, .half = true};
  int threads = 2;
  if (vr_args_get(a, "threads")) {
    char *end;
    long t = strtol(vr_args_get(a, "threads"), &end, 10);
    if (*end || t < 1 || t > 256) {
      vr_error_set(&err, VR_E_ARG, "--threads '%s': expected 1 to 256", vr_args_get(a, "threads"));
      goto out;
    }
    threads = (int)t;
  }
  popt.threads = threads;
  popt.half = !vr_args_flag(a, "exr-float");
  if (vr_args_get(a, "exr-compression") &&
      vr_exr_compression_parse(vr_args_get(a, "exr-compression"), &popt.compression, &err))
    goto out;
  if (texture && !*texture) {
    fprintf(stderr, "vr-rgb2spec: --texture needs a material name\n");
    rc = 2;
    goto out_quiet;
  }
  if (texture && !pixels) {
    vr_error_set(&err, VR_E_ARG, "--texture needs --per-pixel FILE.exr");
    goto out;
  }
  if (parse_method(vr_args_get(a, "method"), &run.method, &err)) goto out;
  if (!manifest && a->noperands == 0) {
    vr_error_set(&err, VR_E_ARG, "give photos or --manifest FILE");
    goto out;
  }
  mpath = manifest ? strdup(manifest) : default_manifest(a->operands[0]);
  if (!mpath) {
    vr_error_set(&err, VR_E_NOMEM, "out of memory");
    goto out;
  }
  if (!rg_db_option_ok(a)) {
    rc = 2;
    goto out_quiet;
  }
  /* Outputs are checked before any work, first against what the command
   * line names (nothing is opened or created yet), then against every file
   * the manifest reads. */
  const char *report = vr_args_get(a, "report");
  vr_out_guard *guard = calloc(1, sizeof *guard);
  if (!guard) {
    vr_error_set(&err, VR_E_NOMEM, "out of memory");
    goto out;
  }
  vr_out_guard_init(guard);
  if (strcmp(mpath, "-")) vr_out_guard_input(guard, mpath, "the capture manifest");
  for (size_t i = 0; i < a->noperands; i++) vr_out_guard_input(guard, a->operands[i], "a photo");
  vr_out_guard_database(guard, vr_args_get(a, "db") ? vr_args_get(a, "db") : vr_matdb_default_path());
  vr_status gst = check_outputs(guard, report, pixels, &err);
  if (gst) {
    free(guard);
    goto out;
  }
  /* Lookups alone (db: lights or references) open the database read-only:
   * a missing one is an error, never created and seeded here. */
  if (vr_capture_read_db(mpath, vr_args_get(a, "db"), prefix || texture ? 0 : VR_MATDB_READONLY,
                         prefix || texture, &db, &cap, &err)) {
    free(guard);
    goto out;
  }
  rg_guard_capture(guard, cap, true);
  gst = check_outputs(guard, report, pixels, &err);
  free(guard);
  if (gst) goto out;
  /* A save that cannot happen is said now, not after the recovery. */
  if ((prefix || texture) && vr_matdb_require_writable(db, &err)) goto out;
  run.cap = cap;
  /* The photos: those given, each of which the manifest must list; or all. */
  if (a->noperands == 0) {
    for (size_t i = 0; i < cap->nphotos && i < RGB2SPEC_MAX_LIGHTS; i++) run.photo[run.nphotos++] = &cap->photos[i];
  } else {
    for (size_t i = 0; i < a->noperands; i++) {
      const vr_capture_photo *p = vr_capture_find_photo(cap, a->operands[i]);
      if (!p) {
        vr_error_set(&err, VR_E_NOT_FOUND, "photo %s is not listed in the manifest %s (add a "
                                           "'photo FILE light=...' line)", a->operands[i], mpath);
        goto out;
      }
      if (run.nphotos == RGB2SPEC_MAX_LIGHTS) {
        vr_error_set(&err, VR_E_ARG, "at most %d photos", RGB2SPEC_MAX_LIGHTS);
        goto out;
      }
      run.photo[run.nphotos++] = p;
    }
  }
  /* The photos themselves, decoded on `threads` threads, all of one size. */
  if (rg_read_photos(&run, img, threads, &err)) goto out;
  for (size_t l = 0; l < run.nphotos; l++) {
    if (rg_check_photo(cap, run.photo[l], &img[l], stderr, &err)) goto out;
    if (l && (img[l].width != img[0].width || img[l].height != img[0].height)) {
      vr_error_set(&err, VR_E_ARG, "%s is %dx%d but %s is %dx%d: the regions are pixel positions, "
                                   "so every photo must have the same size", run.photo[l]->path,
                   img[l].width, img[l].height, run.photo[0]->path, img[0].width, img[0].height);
      goto out;
    }
  }
  /* The regularised method weighs every response by its measured noise and
   * chooses its smoothing from it, so it suits any file: at vanishing
   * noise it tends to the bounded method's smoothest exact fit
   * (bench_rgb2spec_noise, docs/vr-rgb2spec.md). */
  if ((int)run.method == -1) run.method = VR_RECOVER_REGULARISED;
  run.method_name = run.method == VR_RECOVER_MATRIX_R ? "matrix-r"
                    : run.method == VR_RECOVER_BOUNDED ? "bounded" : "regularised";
  /* Camera and recovery system. */
  double grid[1024];
  size_t n;
  if (vr_camera_grid_uniform(cap->grid[0], cap->grid[1], cap->grid[2], grid, 1024, &n, &err)) goto out;
  cam = cap->camera == VR_CAPTURE_CAMERA_SRGB
            ? vr_camera_create_srgb(n, grid, &err)
            : vr_camera_create_measured((const vr_spectrum *const *)cap->sens, n, grid, &err);
  if (!cam) goto out;
  run.cam = cam;
  const vr_spectrum *lights[RGB2SPEC_MAX_LIGHTS];
  double scale[RGB2SPEC_MAX_LIGHTS];
  for (size_t l = 0; l < run.nphotos; l++) lights[l] = run.photo[l]->light, scale[l] = run.photo[l]->scale;
  vr_recovery_options opt;
  vr_recovery_options_default(&opt);
  if (parse_rule(vr_args_get(a, "lambda-rule"), &opt.lambda_rule, &err)) goto out;
  if (!(run.sys = vr_recovery_system_create(cam, run.nphotos, lights, scale, &opt, &err))) goto out;
  run.n = vr_recovery_system_samples(run.sys);
  run.grid = vr_recovery_system_grid(run.sys);
  run.condition = vr_recovery_system_condition(run.sys);
  static const char *const HELD[] = {"A", "D50", "D65", "F2", "F11", "LED-B3"};
  /* A light counts as used whatever it was called (file:d65.csv is D65). */
  for (size_t h = 0; h < 6; h++) {
    vr_spectrum *cand = vr_illuminant(HELD[h], NULL);
    bool used = !cand;
    for (size_t l = 0; l < run.nphotos && !used; l++)
      used = !strcasecmp(run.photo[l]->light_name, HELD[h]) || rg_same_light(cand, run.photo[l]->light);
    if (!used) run.heldout_name[run.nheldout++] = HELD[h];
    vr_spectrum_destroy(cand);
  }
  /* Regions, measured in every photo. */
  run.nregions = cap->nregions;
  if (run.nregions == 0) {
    vr_error_set(&err, VR_E_ARG, "%s names no region (region, chart lines)", mpath);
    goto out;
  }
  run.regions = calloc(run.nregions, sizeof *run.regions);
  if (!run.regions) goto out;
  for (size_t i = 0; i < run.nregions; i++) run.regions[i].def = &cap->regions[i];
  if (rg_measure_photos(&run, img, threads, &err)) goto out;
  /* Recovery and the round trip.  CIEDE2000 against the photo is a colour
   * difference only where the photo holds a colour: a light with a clipped
   * channel is left out of the mean and max and counted apart. */
  for (size_t i = 0; i < run.nregions; i++) {
    rg_region *g = &run.regions[i];
    if (!(g->r = malloc(run.n * sizeof *g->r))) goto out;
    if (vr_recover_noisy(run.sys, run.method, g->c, g->sigma, g->clipped, g->r, &g->info, &err)) {
      vr_error_prefix(&err, "region %s: ", g->def->name);
      goto out;
    }
    vr_render_rgb(run.sys, g->r, g->rendered);
    g->de_mean = 0;
    g->de_max = 0;
    size_t counted = 0;
    for (size_t l = 0; l < run.nphotos; l++) {
      if (g->clipped[3 * l] || g->clipped[3 * l + 1] || g->clipped[3 * l + 2]) {
        g->de[l] = NAN;
        g->nclipped_lights++;
        continue;
      }
      g->de[l] = rg_delta_e(&run, l, &g->c[3 * l], &g->rendered[3 * l]);
      g->de_mean += g->de[l];
      g->de_max = fmax(g->de_max, g->de[l]);
      counted++;
    }
    if (counted) g->de_mean /= (double)counted;
    else g->de_mean = g->de_max = NAN;
    g->misfit = (g->info.flags & VR_RECOVER_FLAG_MISFIT) != 0;
    run.nmisfit += g->misfit;
    compare_reference(&run, g);
  }
  if (rg_check_lights(&run, &err)) goto out;
  if (vr_args_flag(a, "json")) rg_print_json(&run);
  else rg_print_text(&run);
  /* What the recovery cannot stand behind: said on stderr, and the exit
   * status is 1 unless --force (which also lets --save-prefix save). */
  bool doubtful = run.nmisfit > 0;
  size_t told = 0;
  for (size_t i = 0; i < run.nregions; i++)
    if (run.regions[i].misfit && ++told <= 5)
      fprintf(stderr, "vr-rgb2spec: region %s: the recovered spectrum misses its photos by more "
                      "than their noise explains (chi2 %.3g > %.3g for %zu channels)%s\n",
              run.regions[i].def->name, run.regions[i].info.chi2, run.regions[i].info.chi2_limit,
              run.regions[i].info.used,
              run.regions[i].info.flags & VR_RECOVER_FLAG_OUT_OF_GAMUT ? "; out of gamut" : "");
  if (told > 5) fprintf(stderr, "vr-rgb2spec: ... and %zu more regions miss their photos\n", told - 5);
  for (size_t l = 0; told && l < run.nphotos; l++) {
    const char *hint = rg_encoding_hint(cap, run.photo[l], &img[l]);
    if (hint) fprintf(stderr, "vr-rgb2spec: %s: %s\n", run.photo[l]->path, hint);
  }
  for (size_t l = 0; l < run.nphotos; l++)
    if (run.light_suspect[l]) {
      doubtful = true;
      fprintf(stderr, "vr-rgb2spec: %s:%ld: photo %s does not look lit by %s: the regions "
                      "recovered from the other photos, rendered under %s, miss it by a median "
                      "CIEDE2000 of %.1f (limit %.0f); check the light of this photo (two photos' "
                      "lights swapped?)\n", cap->path, run.photo[l]->line, run.photo[l]->path,
              run.photo[l]->light_name, run.photo[l]->light_name, run.loo_de[l], RG_LOO_LIMIT);
    }
  bool force = vr_args_flag(a, "force");
  /* The report is written either way: it shows what went wrong. */
  if (report && rg_write_report(report, &run, &err)) goto out;
  if ((prefix || pixels) && doubtful && !force) {
    bool saves = prefix || texture;
    vr_error_set(&err, VR_E_ARG, "nothing %s: %zu region(s) miss their photos or a light "
                                 "disagrees with its photo (see above); --force %s anyway",
                 saves && pixels ? "saved or written" : saves ? "saved" : "written", run.nmisfit,
                 saves && pixels ? "saves and writes" : saves ? "saves" : "writes");
    goto out;
  }
  if (prefix && rg_save(db, prefix, &run, force && doubtful, &err)) goto out;
  if (pixels) {
    /* With --texture the EXR is written beside its final name and put in
     * place only once its database row is saved: a failed save leaves
     * neither, and an earlier file of that name as it was. */
    char tmpname[4200];
    const char *target = pixels;
    if (texture) {
      snprintf(tmpname, sizeof tmpname, "%s.part-%ld", pixels, (long)getpid());
      target = tmpname;
    }
    if (rg_per_pixel(&run, img, target, &popt, &px, &err)) goto out;
    rg_print_pixels(vr_args_flag(a, "json") ? stderr : stdout, &run, &px, pixels);
    if (texture) {
      if (rg_save_texture(db, texture, target, pixels, &run, &px, force && doubtful, &err)) {
        remove(target);
        goto out;
      }
      if (rename(target, pixels)) {
        vr_error_set(&err, VR_E_IO, "%s: cannot put the texture in place (%s left as written): %s; "
                                    "material '%s' names %s", pixels, target, strerror(errno), texture, pixels);
        goto out;
      }
    }
  }
  if (doubtful && !force) {
    rc = 1;
    goto out_quiet;
  }
  rc = 0;
out:
  if (rc) fail(&err);
out_quiet:
  for (size_t i = 0; i < run.nregions && run.regions; i++) free(run.regions[i].r);
  free(run.regions);
  for (size_t l = 0; l < RGB2SPEC_MAX_LIGHTS; l++) vr_image_free(&img[l]);
  vr_recovery_system_destroy(run.sys);
  vr_camera_destroy(cam);
  vr_capture_destroy(cap);
  vr_matdb_close(db);
  free(mpath);
  rg_pixels_free(&px);
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
