/* vr-spectro fit: n, k of an uncoated pane from T and R. */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/atomic_file.h"
#include "vr/json.h"
#include "vr/slab_invert.h"
#include "vr/spectro_fit.h"

static const char *flag_text(int f) {
  if (f & VR_SLAB_NO_ROOT) return "no slab gives these T, R";
  if (f & VR_SLAB_NO_INDEX) return "k too large for the face reflectance";
  if (f & VR_SPECTRO_ILL) return "ill-conditioned";
  if (f & VR_SLAB_CLAMPED_A) return "lossless within noise (k = 0)";
  return "";
}

static void print_text(const vr_spectro_fit_result *r, const char *src) {
  printf("# vr-spectro fit of %s: pane %.4g mm, %zu wavelengths %.1f-%.1f nm\n", src,
         r->thickness_nm * 1e-6, r->n, r->pt[0].nm, r->pt[r->n - 1].nm);
  printf("n model: %s, reduced chi-square %.3g\n",
         r->model == VR_NK_CAUCHY ? "Cauchy A + B/l^2 + C/l^4"
         : r->model == VR_NK_SELLMEIER2 ? "n^2 = 1 + sum_2 B l^2/(l^2 - C^2) - D l^2"
                                        : "n^2 = 1 + B1 l^2/(l^2 - C1^2) - D l^2",
         r->chi2_reduced);
  for (size_t i = 0; i < r->nparams; i++)
    printf("  %-3s = %.8g +- %.2g %s\n", r->names[i], r->value[i], r->stderr_[i], r->units[i]);
  double e;
  const double lines[][2] = {{486.1327, 0}, {587.5618, 0}, {656.2725, 0}};
  const char *names[] = {"F", "d", "C"};
  for (int i = 0; i < 3; i++) {
    if (lines[i][0] < r->min_nm || lines[i][0] > r->max_nm) continue;
    double n = vr_spectro_fit_n(r, lines[i][0], &e);
    printf("n_%s (%.4f nm) = %.6f +- %.6f\n", names[i], lines[i][0], n, e);
  }
  printf("ill-conditioned wavelengths (left out of the smoothing): %zu\n", r->nill);
  size_t shown = 0;
  for (size_t i = 0; i < r->n; i++)
    if ((r->pt[i].flags & VR_SPECTRO_ILL) && shown++ < 10)
      printf("  %.1f nm: %s\n", r->pt[i].nm, flag_text(r->pt[i].flags));
  if (shown > 10) printf("  ... and %zu more (see --table)\n", shown - 10);
  printf("verdict: the n model %s\n", r->verdict);
}

static void print_json(const vr_spectro_fit_result *r, const char *src) {
  printf("{\"source\": ");
  vr_json_string(stdout, src);
  printf(", \"thickness_mm\": ");
  vr_json_number(stdout, r->thickness_nm * 1e-6);
  printf(", \"model\": \"%s\", \"chi2_reduced\": ",
         r->model == VR_NK_CAUCHY ? "cauchy" : r->model == VR_NK_SELLMEIER2 ? "sellmeier2" : "sellmeier");
  vr_json_number(stdout, r->chi2_reduced);
  printf(", \"parameters\": [");
  for (size_t i = 0; i < r->nparams; i++) {
    printf("%s{\"name\": \"%s\", \"value\": ", i ? ", " : "", r->names[i]);
    vr_json_number(stdout, r->value[i]);
    printf(", \"stderr\": ");
    vr_json_number(stdout, r->stderr_[i]);
    printf(", \"unit\": \"%s\"}", r->units[i]);
  }
  printf("], \"verdict\": {\"describes\": %s, \"chi2_reduced\": ", r->describes ? "true" : "false");
  vr_json_number(stdout, r->chi2_verdict);
  printf(", \"chi2_limit\": ");
  vr_json_number(stdout, r->chi2_limit);
  printf(", \"sigma\": ");
  vr_json_number(stdout, r->sigma_verdict);
  printf(", \"dof\": %ld, \"text\": ", r->dof);
  vr_json_string(stdout, r->verdict);
  printf("}, \"ill_conditioned\": %zu, \"points\": [", r->nill);
  for (size_t i = 0; i < r->n; i++) {
    const vr_spectro_point_fit *p = &r->pt[i];
    printf("%s[", i ? ", " : "");
    double v[] = {p->nm, p->n, p->n_err, p->n_model, p->n_model_err, p->k_final, p->k_err};
    for (int j = 0; j < 7; j++) {
      if (j) printf(", ");
      vr_json_number(stdout, v[j]);
    }
    printf(", %d]", p->flags);
  }
  printf("], \"point_columns\": [\"nm\", \"n_point\", \"n_point_err\", \"n\", \"n_err\", \"k\", "
         "\"k_err\", \"flags\"]}\n");
}

static vr_status write_table(const char *path, const vr_spectro_fit_result *r, vr_error *err) {
  vr_atomic_file f;
  vr_status st = vr_atomic_file_open(&f, path, err);
  if (st) return st;
  fprintf(f.fp, "wavelength_nm,n_point,n_point_err,n,n_err,k,k_err,flags,note\n");
  for (size_t i = 0; i < r->n; i++) {
    const vr_spectro_point_fit *p = &r->pt[i];
    fprintf(f.fp, "%.4f,%.8g,%.3g,%.8g,%.3g,%.6g,%.3g,%d,%s\n", p->nm, p->n, p->n_err, p->n_model,
            p->n_model_err, p->k_final, p->k_err, p->flags, flag_text(p->flags));
  }
  return vr_atomic_file_commit(&f, err);
}

int spectro_cmd_fit(vr_args *a) {
  vr_error err = {0};
  const char *path = a->operands[1];
  vr_spectro_data *d = NULL;
  vr_matdb *db = NULL;
  vr_spectro_fit_result r = {0};
  vr_material *m = NULL;
  int rc = 1;
  vr_spectro_fit_options o = vr_spectro_fit_default_options();
  const char *model = vr_args_get(a, "model"), *save = vr_args_get(a, "save"),
             *table = vr_args_get(a, "table");
  if (model && vr_nk_model_parse(model, &o.model, &err)) goto out;
  if (vr_args_double(a, "sigma", 1e-3, &o.sigma_T, &err)) goto out;
  o.sigma_R = o.sigma_T;
  if (spectro_pane_source(a, path, &db, &d, &err)) goto out;
  if (isnan(d->thickness_nm)) {
    vr_error_set(&err, VR_E_ARG, "%s: the pane's thickness is unknown: give --thickness MM", path);
    goto out;
  }
  if (vr_spectro_fit(d, d->thickness_nm, &o, &r, &err)) {
    vr_error_prefix(&err, "%s: ", path);
    goto out;
  }
  if (vr_args_flag(a, "json")) print_json(&r, path);
  else print_text(&r, path);
  bool force = vr_args_flag(a, "force");
  if (!r.describes && !force) {
    /* Nothing is written for a fit that does not describe its data. */
    vr_error_set(&err, VR_E_NUMERIC, "%s: the fit %s%s", path, r.verdict,
                 save || table ? "; nothing saved or written (--force accepts it)"
                               : " (--force accepts it)");
    goto out;
  }
  if (!r.describes)
    fprintf(stderr, "vr-spectro: warning: %s: the fit %s (accepted with --force)\n", path,
            r.verdict);
  if (table && write_table(table, &r, &err)) goto out;
  if (save) {
    if (spectro_db(a, &db, &err) ||
        vr_spectro_fit_material(&r, save, !r.describes && force, &m, &err) ||
        spectro_save(db, m, "fit", path, &err))
      goto out;
  }
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  vr_material_destroy(m);
  vr_spectro_fit_free(&r);
  vr_spectro_destroy(d);
  vr_matdb_close(db);
  return rc;
}
