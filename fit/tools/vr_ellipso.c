/* vr-ellipso: spectroscopic ellipsometry to optical constants and layer
 * thicknesses.  "fit" reads Ψ, Δ data and fits a sample model (or, without
 * one, inverts a bulk sample and fits a dispersion model); "simulate" prints
 * the Ψ, Δ a model predicts, for planning measurements and for tests. */
#include "ellipso_output.h"
#include "vr/args.h"
#include "vr/csv.h"
#include "vr/file.h"
#include "vr/matdb.h"
#include "vr/out_guard.h"
#include "vr/spectrum.h"

#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <ctype.h>

static const vr_option OPTIONS[] = {
    {"model", 'm', "FILE", "sample model file (docs/vr-ellipso.md); without it: bulk inversion"},
    {"save", 's', "NAME", "fit: save the fitted layer's n, k and parameters under NAME"},
    {"layer", 'l', "NAME", "fit: the layer whose n, k are reported and saved (default: the fitted one)"},
    {"db", 'd', "FILE", "material database (default: $VR_MATDB, else ./materials.db)"},
    {"report", 'r', "FILE.html", "fit: write an HTML report with plots"},
    {"units", 'u', "UNIT", "wavelength unit of a CSV without one in its header (nm, um, A, eV)"},
    {"wavelength", 0, "NM", "fit: the wavelength of a single-wavelength file that has no wavelength column"},
    {"no-global", 0, NULL, "fit: skip the global thickness search"},
    {"angles", 'a', "LIST", "simulate: angles of incidence in degrees, e.g. 65,70,75"},
    {"wavelengths", 'w', "FROM:TO:STEP", "simulate: wavelengths in nm"},
    {"noise", 0, "SPSI,SDELTA", "simulate: add Gaussian noise with these standard deviations (deg)"},
    {"seed", 0, "N", "simulate: random seed for --noise (default 1)"},
    {"json", 'j', NULL, "fit: JSON output"},
    {"force", 0, NULL, "fit: accept (exit 0) and --save a fit that does not describe the data (the verdict is saved with it)"},
    {"record", 0, "N", "fit: the record (1-based) of a file of several, e.g. a Film Sense kinetic run"},
    {"no-depolarisation", 0, NULL, "fit: do not fit the depolarisation a file gives"},
};
#define NOPT (sizeof OPTIONS / sizeof OPTIONS[0])

static const char USAGE[] =
    "fit DATA... [--model FILE] [--save NAME [--force]] [--db FILE] [--report FILE.html] [--json]\n"
    "       vr-ellipso simulate --model FILE --angles LIST --wavelengths FROM:TO:STEP [--noise SPSI,SDELTA]";
static const char ABOUT[] =
    "Fits spectroscopic ellipsometry data (Psi, Delta; CSV, J.A. Woollam WVASE/CompleteEASE\n"
    ".dat and WVASE-format exports, Accurion EP4 tables, Film Sense exports, Sentech\n"
    "SpectraRay exports) to optical constants and layer thicknesses.  With a model: a global\n"
    "search over the free thicknesses, then Levenberg-Marquardt (Ceres); each parameter is\n"
    "printed with its standard error and 90% confidence limits, the correlation matrix (warning\n"
    "above 0.95), Woollam's MSE and CompleteEASE's N, C, S MSE.  Several data files are fitted\n"
    "as several samples of one model: parameters marked 'per-sample' take one value per file,\n"
    "the others are shared.  Without a model (one file) the sample is treated as bulk:\n"
    "pseudo-optical constants per wavelength, then a dispersion fit or the exact inversion.\n"
    "A fit that does not describe its data (rms residual above 10 times the noise the data\n"
    "show, or a free parameter pinned at a bound) exits 1 and is not saved unless --force;\n"
    "the verdict is saved with the material.  --report never replaces an input of the run\n"
    "(data, model, the model's tables, the database): checked before anything is read.  Delta\n"
    "follows Woollam's convention (bare Si at 70 deg, 633 nm: Psi 10.6, Delta 179.3).";

static int fail(const vr_error *e) {
  fprintf(stderr, "vr-ellipso: %s\n", e->message);
  return 1;
}

static vr_status open_db(const vr_args *a, int flags, vr_matdb **db, vr_error *err) {
  return vr_matdb_open(vr_args_get(a, "db"), flags, db, err);
}

/* The tabulated materials a model file reads (file:PATH, relative to the
 * model's folder) are inputs of the run too. */
static void guard_model_files(vr_out_guard *g, const char *model_path) {
  char *text = NULL;
  size_t len = 0;
  vr_error e = {0};
  if (vr_read_file(model_path, 1 << 20, &text, &len, &e)) return; /* the model reader says why */
  const char *slash = strrchr(model_path, '/');
  int dirlen = slash ? (int)(slash - model_path) : 0;
  bool comment = false;
  for (size_t i = 0; i < len; i++) {
    if (text[i] == '\n') comment = false;
    else if (text[i] == '#') comment = true;
    if (comment || (i && !isspace((unsigned char)text[i - 1])) || strncasecmp(text + i, "file:", 5)) continue;
    size_t j = i + 5;
    while (j < len && !isspace((unsigned char)text[j]) && text[j] != '#') j++;
    char path[4200];
    if (text[i + 5] == '/' || !slash) snprintf(path, sizeof path, "%.*s", (int)(j - i - 5), text + i + 5);
    else snprintf(path, sizeof path, "%.*s/%.*s", dirlen, model_path, (int)(j - i - 5), text + i + 5);
    vr_out_guard_input(g, path, "a material table of the model");
    i = j - 1;
  }
  free(text);
}

static int cmd_fit(vr_args *a) {
  vr_error err = {0};
  size_t nd = a->noperands - 1;
  const char *const *paths = &a->operands[1];
  vr_ellipso_data *d = calloc(nd, sizeof *d);
  vr_sample_model **m = calloc(nd, sizeof *m);
  vr_matdb *db = NULL;
  vr_fit_result r = {0};
  vr_fit_view v = {0};
  int rc = 1;
  const char *model_path = vr_args_get(a, "model");
  const char *save = vr_args_get(a, "save");
  vr_ellipso_read_options ro = {.unit = vr_args_get(a, "units")};
  const char *wl = vr_args_get(a, "wavelength"), *rec = vr_args_get(a, "record");
  double recd = 0;
  if (!d || !m) {
    fprintf(stderr, "vr-ellipso: out of memory\n");
    goto out;
  }
  if (nd > 1 && !model_path) {
    fprintf(stderr, "vr-ellipso: %zu data files and no --model: several files are fitted as several samples "
                    "of one model (mark per-sample parameters in it); without a model, fit each file on its own\n",
            nd);
    rc = 2;
    goto out;
  }
  if (wl && (vr_parse_double(wl, &ro.wavelength_nm) || !(ro.wavelength_nm > 0))) {
    fprintf(stderr, "vr-ellipso: --wavelength '%s': expected a wavelength in nm > 0\n", wl);
    rc = 2;
    goto out;
  }
  if (rec && (vr_parse_double(rec, &recd) || !(recd >= 1) || recd != floor(recd) || recd > 1e9)) {
    fprintf(stderr, "vr-ellipso: --record '%s': expected a record number from 1\n", rec);
    rc = 2;
    goto out;
  }
  ro.record = (size_t)recd;
  const char *layer = vr_args_get(a, "layer");
  if (!model_path && layer && strcmp(layer, "substrate")) {
    fprintf(stderr, "vr-ellipso: --layer %s: without --model the sample is bulk and has no layers (only 'substrate')\n",
            layer);
    rc = 2;
    goto out;
  }
  /* Outputs are checked before any work: the report must not replace a
   * file this run reads (its data, model, the model's tables, the
   * database). */
  const char *report = vr_args_get(a, "report");
  if (report) {
    vr_out_guard g;
    vr_out_guard_init(&g);
    for (size_t s = 0; s < nd; s++) vr_out_guard_input(&g, paths[s], "the measurement");
    if (model_path) {
      vr_out_guard_input(&g, model_path, "the model");
      guard_model_files(&g, model_path);
    }
    const char *dbp = vr_args_get(a, "db");
    vr_out_guard_database(&g, dbp ? dbp : vr_matdb_default_path());
    if (vr_out_guard_check(&g, report, "--report", &err)) goto out;
  }
  for (size_t s = 0; s < nd; s++) {
    if (vr_ellipso_read_with(paths[s], &ro, &d[s], &err)) goto out;
    fprintf(stderr, "vr-ellipso: %s: %zu points (%s)", paths[s], d[s].n, d[s].format);
    if (d[s].nrecords > 1) fprintf(stderr, ", record %zu of %zu at %g s", d[s].record, d[s].nrecords, d[s].record_time_s);
    fputc('\n', stderr);
    for (size_t i = 0; i < d[s].nskipped; i++)
      fprintf(stderr, "vr-ellipso: note: %s: skipped %zu row%s of type '%s' (not Psi/Delta measurements)\n", paths[s],
              d[s].skipped[i].rows, d[s].skipped[i].rows == 1 ? "" : "s", d[s].skipped[i].tag);
  }
  vr_fit_options opt = vr_fit_default_options();
  opt.global_search = !vr_args_flag(a, "no-global");
  opt.fit_depolarisation = !vr_args_flag(a, "no-depolarisation");
  /* Only a run that saves may create the --db it names. */
  if ((save || (model_path && vr_matdb_named_in(model_path))) &&
      open_db(a, save ? 0 : VR_MATDB_MUST_EXIST, &db, &err))
    goto out;
  /* A save that cannot happen is said now, not after the fit. */
  if (save && vr_matdb_require_writable(db, &err)) goto out;
  if (model_path) {
    if (vr_model_read(model_path, db, &m[0], &err)) goto out;
    for (size_t s = 1; s < nd; s++)
      if (!(m[s] = vr_model_copy(m[0], &err))) goto out;
    /* The reported layer (--layer) and whether its n, k can be saved are
     * known from the model alone. */
    vr_fit_result none = {0};
    vr_fit_view pre;
    vr_status pst = vr_fit_view_init(&pre, m[0], d, nd, &none, layer, &err);
    bool per_sample = pre.nk_per_sample;
    const char *pname = pre.layer_name;
    vr_fit_view_free(&pre);
    if (pst) goto out;
    if (save && per_sample) {
      vr_error_set(&err, VR_E_ARG, "--save %s: the optical constants of %s are fitted per sample: there is no "
                                   "one n, k to save (share them, or save another layer with --layer)",
                   save, pname);
      goto out;
    }
    if (vr_ellipso_fit_samples(m, d, nd, &opt, &r, &err)) goto out;
  } else {
    if (vr_ellipso_fit_bulk(&d[0], &opt, &m[0], &r, &err)) goto out;
  }
  if (r.ndepol) fprintf(stderr, "vr-ellipso: fitting %zu depolarisation values as well (--no-depolarisation: Psi, Delta only)\n", r.ndepol);
  if (vr_fit_view_init(&v, m[0], d, nd, &r, layer, &err)) goto out;
  if (vr_args_flag(a, "json")) vr_fit_print_json(stdout, &v);
  else vr_fit_print_text(stdout, &v);
  if (report && vr_fit_write_report(report, &v, &err)) goto out;
  const char *what = nd > 1 ? "the data files" : paths[0];
  if (!r.describes && !vr_args_flag(a, "force")) {
    fprintf(stderr, "vr-ellipso: %s: the fit %s%s\n", what, r.verdict, save ? "; not saved (--force saves it anyway)" : "");
    rc = 1;
    err.message[0] = '\0';
    goto out;
  }
  if (!r.describes) fprintf(stderr, "vr-ellipso: warning: %s: the fit %s (accepted with --force)\n", what, r.verdict);
  if (save) {
    if (vr_fit_save(db, save, &v, paths, nd, model_path, vr_args_flag(a, "force") && !r.describes, &err)) goto out;
    fprintf(stderr, "vr-ellipso: saved '%s' to %s\n", save, vr_matdb_path(db));
  }
  fprintf(stderr, "vr-ellipso: fit took %.3f s\n", r.seconds);
  rc = 0;
out:
  if (rc && err.message[0]) fail(&err);
  vr_fit_view_free(&v);
  vr_fit_result_free(&r);
  for (size_t s = 0; m && s < nd; s++) vr_model_destroy(m[s]);
  vr_matdb_close(db);
  for (size_t s = 0; d && s < nd; s++) vr_ellipso_data_free(&d[s]);
  free(m);
  free(d);
  return rc;
}

#define SIM_MAX_WAVELENGTHS 100000

static int cmd_simulate(vr_args *a) {
  vr_error err = {0};
  const char *model_path = vr_args_get(a, "model"), *angles = vr_args_get(a, "angles"),
             *wls = vr_args_get(a, "wavelengths"), *noise = vr_args_get(a, "noise");
  if (!model_path || !angles || !wls) {
    fprintf(stderr, "vr-ellipso: simulate needs --model, --angles and --wavelengths\n");
    return 2;
  }
  double ang[32], w[3], sig[2] = {0, 0}, seed = 1;
  size_t na, nw, ns = 0;
  char wbuf[128];
  snprintf(wbuf, sizeof wbuf, "%s", wls);
  for (char *c = wbuf; *c; c++)
    if (*c == ':') *c = ',';
  if (vr_parse_doubles(angles, ang, 32, &na)) {
    fprintf(stderr, "vr-ellipso: --angles '%s': expected numbers separated by commas\n", angles);
    return 2;
  }
  for (size_t j = 0; j < na; j++)
    if (!(ang[j] > 0 && ang[j] < 90)) {
      fprintf(stderr, "vr-ellipso: --angles '%s': %g deg is not an angle of incidence in (0, 90)\n",
              angles, ang[j]);
      return 2;
    }
  if (vr_parse_doubles(wbuf, w, 3, &nw) || nw != 3 || !(w[2] > 0) || !(w[1] >= w[0]) || !(w[0] > 0)) {
    fprintf(stderr, "vr-ellipso: --wavelengths '%s': expected FROM:TO:STEP in nm with STEP > 0\n", wls);
    return 2;
  }
  /* An instrument's range and count: what a spectroscopic ellipsometer
   * measures (190 nm - 25 um, a few thousand wavelengths), with room. */
  if (w[0] < VR_WL_MIN_NM || w[1] > VR_WL_MAX_NM || (w[1] - w[0]) / w[2] + 1 > SIM_MAX_WAVELENGTHS) {
    fprintf(stderr, "vr-ellipso: --wavelengths '%s': %.0f wavelengths from %g to %g nm; simulate "
                    "takes at most %d in %g nm - %g um\n", wls, floor((w[1] - w[0]) / w[2]) + 1,
            w[0], w[1], SIM_MAX_WAVELENGTHS, VR_WL_MIN_NM, VR_WL_MAX_NM / 1000);
    return 2;
  }
  if (noise && (vr_parse_doubles(noise, sig, 2, &ns) || ns != 2 || sig[0] < 0 || sig[1] < 0)) {
    fprintf(stderr, "vr-ellipso: --noise '%s': expected SPSI,SDELTA in degrees\n", noise);
    return 2;
  }
  if (vr_args_double(a, "seed", 1, &seed, &err)) {
    fprintf(stderr, "vr-ellipso: %s\n", err.message);
    return 2;
  }
  if (!(seed >= 0 && seed <= 4294967295.0 && seed == floor(seed))) {
    fprintf(stderr, "vr-ellipso: --seed %g: expected a whole number in [0, 4294967295]\n", seed);
    return 2;
  }
  vr_matdb *db = NULL;
  vr_sample_model *m = NULL;
  if (vr_matdb_named_in(model_path) && open_db(a, VR_MATDB_MUST_EXIST, &db, &err)) return fail(&err);
  int rc = 1;
  if (vr_model_read(model_path, db, &m, &err)) goto out;
  gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
  if (!rng) goto out;
  gsl_rng_set(rng, (unsigned long)seed);
  printf(noise ? "wavelength_nm,aoi,psi,delta,sigma_psi,sigma_delta\n" : "wavelength_nm,aoi,psi,delta\n");
  size_t steps = (size_t)floor((w[1] - w[0]) / w[2] + 1e-9) + 1;
  for (size_t i = 0; i < steps && rc; i++) {
    double nm = w[0] + w[2] * (double)i;
    for (size_t j = 0; j < na; j++) {
      double psi, delta;
      if (vr_model_psi_delta(m, nm, ang[j], &psi, &delta, NULL, &err)) {
        gsl_rng_free(rng);
        goto out;
      }
      if (noise) {
        psi += gsl_ran_gaussian(rng, sig[0]);
        delta += gsl_ran_gaussian(rng, sig[1]);
        if (delta < 0) delta += 360;
        if (delta >= 360) delta -= 360;
        printf("%.4f,%.4f,%.6f,%.6f,%g,%g\n", nm, ang[j], psi, delta, sig[0], sig[1]);
      } else {
        printf("%.4f,%.4f,%.10f,%.10f\n", nm, ang[j], psi, delta);
      }
    }
  }
  gsl_rng_free(rng);
  rc = 0;
out:
  if (rc && err.message[0]) fail(&err);
  vr_model_destroy(m);
  vr_matdb_close(db);
  return rc;
}

int main(int argc, char **argv) {
  vr_args a;
  vr_args_outcome o = vr_args_parse(&a, "vr-ellipso", USAGE, ABOUT, OPTIONS, NOPT, argc, argv);
  if (o == VR_ARGS_EXIT_OK) return 0;
  if (o == VR_ARGS_EXIT_USAGE) return 2;
  int rc;
  if (a.noperands >= 2 && !strcmp(a.operands[0], "fit")) rc = cmd_fit(&a);
  else if (a.noperands >= 1 && !strcmp(a.operands[0], "simulate")) rc = cmd_simulate(&a);
  else {
    fprintf(stderr, "vr-ellipso: expected 'fit DATA' or 'simulate'\nTry 'vr-ellipso --help'.\n");
    rc = 2;
  }
  vr_args_free(&a);
  return rc;
}
