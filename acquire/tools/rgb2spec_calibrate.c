/* vr-rgb2spec calibrate: a camera's tone curves and spectral sensitivities
 * from one photo of a ColorChecker under a known light (vr/calibrate.h),
 * printed as a table or JSON and optionally saved as a camera material that
 * capture manifests then use as "camera db:NAME".  The photo, chart and
 * light are read with the same library calls as the recovery (vr_image,
 * vr_chart, vr_capture_spectrum); nothing is written unless everything
 * before the save succeeded. */
#include "rgb2spec.h"
#include "rgb2spec_inputs.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "vr/calibrate.h"
#include "vr/chart.h"
#include "vr/colour.h"
#include "vr/csv.h"
#include "vr/json.h"
#include "vr/sha256.h"

static const vr_option OPTIONS[] = {
    {"light", 'l', "NAME|FILE", "the light: a CIE illuminant (D65, A, F11, LED-B3, ...), db:NAME or a CSV spectrum file"},
    {"chart", 'c', "auto|grid=...", "find the ColorChecker (auto, the default) or place it: grid=X0,Y0,X1,Y1 (outer corners of the patch area, as in a manifest) or 8 numbers, the corners x,y clockwise from patch 1"},
    {"grid", 'g', "START,STOP,STEP", "wavelengths of the sensitivities, nm (default 400,700,10)"},
    {"tone", 0, "CURVE", "auto (default), linear, srgb or gamma=G: impose the tone curve"},
    {"clip", 0, "C", "encoded values at or above C are saturated (default 0.999)"},
    {"save", 's', "NAME", "save the camera as material NAME"},
    {"db", 'd', "FILE", "material database (default: $VR_MATDB, else ./materials.db)"},
    {"json", 'j', NULL, "JSON output"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "PHOTO --light NAME|FILE [--chart auto|grid=X0,Y0,X1,Y1] [--grid START,STOP,STEP]\n"
    "                              [--tone auto|linear|srgb|gamma=G] [--save NAME] [--db FILE] [--json]";
static const char ABOUT[] =
    "Estimates a camera's tone curve (linear, sRGB or a fitted power law, per channel, from\n"
    "the six neutral patches) and its spectral sensitivities (smooth non-negative least\n"
    "squares, weight by generalised cross-validation) from one photo of an X-Rite\n"
    "ColorChecker Classic under a known light (docs/vr-rgb2spec.md).  Prints the fit and\n"
    "the sensitivities (green peak 1); --save stores them as a camera material for\n"
    "'camera db:NAME' in a capture manifest, with the tone curves.";

static const char *const CHANNEL[3] = {"red", "green", "blue"};
static const char *const TONE_NAME[3] = {"linear", "srgb", "gamma"};

static void flags_text(unsigned f, char *out, size_t size) {
  static const struct {
    unsigned bit;
    const char *name;
  } F[] = {{VR_CALIBRATION_FLAG_CLIPPED, "clipped"},
           {VR_CALIBRATION_FLAG_GCV_FLAT, "gcv-flat"},
           {VR_CALIBRATION_FLAG_MAX_ITER, "max-iterations"},
           {VR_CALIBRATION_FLAG_PARTIAL_LIGHT, "partial-light"}};
  size_t used = 0;
  out[0] = '\0';
  for (size_t i = 0; i < sizeof F / sizeof F[0]; i++)
    if (f & F[i].bit && used < size)
      used += (size_t)snprintf(out + used, size - used, "%s%s", used ? " " : "", F[i].name);
}

/* A light given as db:NAME, file:PATH, a CIE name, or a bare file path. */
static vr_status resolve_light(const char *arg, vr_matdb *db, vr_spectrum **out, vr_error *err) {
  if (strncmp(arg, "db:", 3) && strncmp(arg, "file:", 5)) {
    if ((*out = vr_illuminant(arg, NULL))) return VR_OK;
    if (access(arg, F_OK) == 0) {
      size_t n = strlen(arg) + 6;
      char *ref = malloc(n);
      if (!ref) return vr_error_set(err, VR_E_NOMEM, "out of memory");
      snprintf(ref, n, "file:%s", arg);
      vr_status st = vr_capture_spectrum(ref, NULL, db, "value", true, out, err);
      free(ref);
      return st;
    }
  }
  vr_status st = vr_capture_spectrum(arg, NULL, db, "value", true, out, err);
  if (st == VR_E_NOT_FOUND && strncmp(arg, "db:", 3))
    vr_error_set(err, st, "--light %s: not a CIE illuminant (D65, A, F1-F12, LED-B1..., D<CCT>, "
                          "BB<T>), db:NAME or a readable spectrum file", arg);
  return st;
}

static vr_status read_chart(const char *photo, const vr_image *img, const char *spec, vr_chart *chart,
                            vr_error *err) {
  vr_status st;
  if (!spec || !strcmp(spec, "auto")) {
    st = vr_chart_detect(img, img->bit_depth == 32, chart, err);
    if (st == VR_E_NOT_FOUND)
      vr_error_set(err, st, "no ColorChecker found (give its corners with --chart grid=X0,Y0,X1,Y1)");
  } else {
    double v[8];
    size_t k = 0;
    double q[4][2];
    if (strncmp(spec, "grid=", 5) || vr_parse_doubles(spec + 5, v, 8, &k) || (k != 4 && k != 8))
      return vr_error_set(err, VR_E_ARG, "--chart '%s': expected auto, grid=X0,Y0,X1,Y1 or grid= "
                                         "with the four corners' 8 coordinates", spec);
    if (k == 4) {
      if (!(v[2] > v[0] && v[3] > v[1]))
        return vr_error_set(err, VR_E_ARG, "--chart '%s': need X1 > X0 and Y1 > Y0", spec);
      double r[4][2] = {{v[0], v[1]}, {v[2], v[1]}, {v[2], v[3]}, {v[0], v[3]}};
      memcpy(q, r, sizeof q);
    } else {
      for (int i = 0; i < 4; i++) q[i][0] = v[2 * i], q[i][1] = v[2 * i + 1];
    }
    st = vr_chart_from_grid(img, (const double(*)[2])q, 0, chart, err);
  }
  if (st) vr_error_prefix(err, "%s: ", photo);
  return st;
}

static void print_text(const char *photo, const char *light, const vr_calibration *cal) {
  char f[128];
  flags_text(cal->flags, f, sizeof f);
  printf("camera calibration: %s under %s\n", photo, light);
  printf("patches: %d used in every channel, %d left out of some channel", cal->used_patches,
         cal->clipped_patches);
  for (int p = 0, first = 1; p < VR_CALIBRATION_PATCHES; p++)
    if (cal->clipped[p]) printf("%s%d", first ? " (patches " : ", ", p + 1), first = 0;
  printf("%s\n", cal->clipped_patches ? ")" : "");
  printf("condition number of A: %.3g; the light covers %.0f%% of the grid%s%s\n", cal->cond,
         100.0 * cal->coverage, f[0] ? "; flags: " : "", f);
  printf("\n%-6s %-12s %9s %9s %9s %9s %7s  %10s %6s %9s %6s %5s\n", "", "tone", "tone rms",
         "linear", "srgb", "gamma", "(fit)", "lambda", "dof", "rms", "used", "peak");
  for (int c = 0; c < 3; c++) {
    char t[32];
    vr_tone_format(cal->tone[c], cal->gamma[c], t, sizeof t);
    size_t at = 0;
    for (size_t j = 1; j < cal->n; j++)
      if (cal->sens[c][j] > cal->sens[c][at]) at = j;
    printf("%-6s %-12s %9.5f %9.5f %9.5f %9.5f %7.3f  %10.3g %6.2f %9.6f %6d %5.0f\n", CHANNEL[c], t,
           cal->tone_rms[c], cal->tone_fit_rms[c][0], cal->tone_fit_rms[c][1],
           cal->tone_fit_rms[c][2], cal->gamma[c], cal->lambda[c], cal->dof[c], cal->rms[c],
           cal->used[c], cal->grid_nm[at]);
  }
  printf("\n%8s %9s %9s %9s\n", "nm", "red", "green", "blue");
  for (size_t j = 0; j < cal->n; j++)
    printf("%8g %9.5f %9.5f %9.5f\n", cal->grid_nm[j], cal->sens[0][j], cal->sens[1][j],
           cal->sens[2][j]);
}

static void print_json(const char *photo, const char *light, const vr_calibration *cal,
                       const char *saved) {
  char f[128];
  flags_text(cal->flags, f, sizeof f);
  printf("{\"photo\": ");
  vr_json_string(stdout, photo);
  printf(", \"light\": ");
  vr_json_string(stdout, light);
  printf(", \"condition_number\": ");
  vr_json_number(stdout, cal->cond);
  printf(", \"light_coverage\": ");
  vr_json_number(stdout, cal->coverage);
  printf(", \"used_patches\": %d, \"clipped_patches\": %d, \"clipped\": [", cal->used_patches,
         cal->clipped_patches);
  for (int p = 0, first = 1; p < VR_CALIBRATION_PATCHES; p++)
    if (cal->clipped[p]) printf("%s%d", first ? "" : ", ", p + 1), first = 0;
  printf("], \"flags\": ");
  vr_json_string(stdout, f);
  printf(",\n \"channels\": [");
  for (int c = 0; c < 3; c++) {
    char t[32];
    vr_tone_format(cal->tone[c], cal->gamma[c], t, sizeof t);
    size_t at = 0;
    for (size_t j = 1; j < cal->n; j++)
      if (cal->sens[c][j] > cal->sens[c][at]) at = j;
    printf("%s\n  {\"channel\": \"%s\", \"tone\": ", c ? "," : "", CHANNEL[c]);
    vr_json_string(stdout, t);
    printf(", \"tone_rms\": ");
    vr_json_number(stdout, cal->tone_rms[c]);
    printf(", \"tone_fits\": {");
    for (int k = 0; k < 3; k++) {
      printf("%s\"%s\": ", k ? ", " : "", TONE_NAME[k]);
      vr_json_number(stdout, cal->tone_fit_rms[c][k]);
    }
    printf("}, \"gamma_fit\": ");
    vr_json_number(stdout, cal->gamma[c]);
    printf(", \"neutrals\": %d, \"neutral_correction\": ", cal->neutrals[c]);
    vr_json_number(stdout, cal->neutral_correction[c]);
    printf(", \"lambda\": ");
    vr_json_number(stdout, cal->lambda[c]);
    printf(", \"gcv\": ");
    vr_json_number(stdout, cal->gcv[c]);
    printf(", \"dof\": ");
    vr_json_number(stdout, cal->dof[c]);
    printf(", \"rms\": ");
    vr_json_number(stdout, cal->rms[c]);
    printf(", \"used\": %d, \"at_zero\": %d, \"peak_nm\": ", cal->used[c], cal->at_zero[c]);
    vr_json_number(stdout, cal->grid_nm[at]);
    printf("}");
  }
  printf("],\n \"sensitivities\": [");
  for (size_t j = 0; j < cal->n; j++) {
    printf("%s[", j ? ", " : "");
    vr_json_number(stdout, cal->grid_nm[j]);
    for (int c = 0; c < 3; c++) {
      printf(", ");
      vr_json_number(stdout, cal->sens[c][j]);
    }
    printf("]");
  }
  printf("],\n \"saved\": ");
  vr_json_string(stdout, saved);
  printf("}\n");
}

static vr_status save(vr_matdb *db, const char *name, const char *photo, const char *light,
                      const char *chart, const vr_calibration *cal, vr_error *err) {
  vr_material *m;
  vr_status st = vr_calibration_to_material(cal, name, &m, err);
  if (st) return st;
  char note[512];
  snprintf(note, sizeof note, "light: %s; chart: %s; grid %g-%g nm, %zu samples", light,
           chart ? chart : "auto", cal->grid_nm[0], cal->grid_nm[cal->n - 1], cal->n);
  st = vr_material_set_text(&m->prov.source_path, photo, err);
  if (!st) st = vr_sha256_file(photo, m->prov.sha256, err);
  if (!st) st = vr_material_set_text(&m->prov.tool, "vr-rgb2spec calibrate", err);
  if (!st) st = vr_material_set_text(&m->prov.tool_version, vr_version(), err);
  if (!st) st = vr_material_set_text(&m->prov.note, note, err);
  if (!st) st = vr_matdb_save(db, m, err);
  if (!st)
    fprintf(stderr, "vr-rgb2spec: saved camera %s (version %d) to %s\n", name, m->version,
            vr_matdb_path(db));
  vr_material_destroy(m);
  return st;
}

int rg_cmd_calibrate(int argc, char **argv) {
  vr_args a;
  vr_args_outcome o =
      vr_args_parse(&a, "vr-rgb2spec calibrate", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_spectrum *light = NULL;
  vr_image img = {0};
  vr_calibration cal = {0};
  int rc = 1;
  const char *light_arg = vr_args_get(&a, "light"), *chart_arg = vr_args_get(&a, "chart"),
             *grid_arg = vr_args_get(&a, "grid"), *tone_arg = vr_args_get(&a, "tone"),
             *name = vr_args_get(&a, "save");
  if (a.noperands != 1 || !light_arg) {
    fprintf(stderr, "vr-rgb2spec calibrate: give one PHOTO and --light\n"
                    "Try 'vr-rgb2spec calibrate --help' for more information.\n");
    vr_args_free(&a);
    return 2;
  }
  const char *photo = a.operands[0];
  vr_calibration_options opt;
  vr_calibration_options_default(&opt);
  double grid[1024];
  size_t n = 0;
  /* Wrong option values are usage errors (exit 2), found before any file. */
  rc = 2;
  if (vr_args_double(&a, "clip", opt.clip, &opt.clip, &err)) goto out;
  if (tone_arg && vr_tone_parse(tone_arg, true, &opt.tone, &opt.gamma, &err)) goto out;
  if (grid_arg) {
    double g[3];
    size_t k = 0;
    if (vr_parse_doubles(grid_arg, g, 3, &k) || k != 3) {
      vr_error_set(&err, VR_E_ARG, "--grid '%s': expected START,STOP,STEP in nm", grid_arg);
      goto out;
    }
    if (vr_camera_grid_uniform(g[0], g[1], g[2], grid, 1024, &n, &err)) goto out;
  }
  rc = 1;
  /* The database now only if the light is in it; otherwise not before the
   * save, so that a failed run leaves no file behind. */
  if (!strncmp(light_arg, "db:", 3) &&
      vr_matdb_open(vr_args_get(&a, "db"), name ? 0 : VR_MATDB_READONLY | VR_MATDB_MUST_EXIST, &db,
                    &err))
    goto out;
  if (resolve_light(light_arg, db, &light, &err)) goto out;
  if (vr_image_read(photo, &img, &err)) goto out;
  vr_chart chart;
  if (read_chart(photo, &img, chart_arg, &chart, &err)) goto out;
  bool clipped[VR_CALIBRATION_PATCHES];
  for (int p = 0; p < VR_CALIBRATION_PATCHES; p++) clipped[p] = chart.max[p] >= opt.clip;
  if (vr_calibrate_camera((const double(*)[3])chart.rgb, clipped, light, NULL, n,
                          grid_arg ? grid : NULL, &opt, &cal, &err)) {
    vr_error_prefix(&err, "%s: ", photo);
    goto out;
  }
  if (name) {
    if (!db && vr_matdb_open(vr_args_get(&a, "db"), 0, &db, &err)) goto out;
    if (save(db, name, photo, light_arg, chart_arg, &cal, &err)) goto out;
  }
  if (vr_args_flag(&a, "json")) print_json(photo, light_arg, &cal, name);
  else print_text(photo, light_arg, &cal);
  rc = 0;
out:
  if (rc) fprintf(stderr, "vr-rgb2spec: %s\n", err.message);
  vr_calibration_free(&cal);
  vr_image_free(&img);
  vr_spectrum_destroy(light);
  vr_matdb_close(db);
  vr_args_free(&a);
  return rc;
}
