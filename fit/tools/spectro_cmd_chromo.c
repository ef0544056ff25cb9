/* vr-spectro chromogenic (state-model fits) and state (evaluation). */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/chromogenic.h"
#include "vr/chromogenic_fit.h"
#include "vr/json.h"

/* Spectra and their state tokens, from one file with a state column or
 * from one file per state. */
typedef struct inputs {
  size_t n;
  vr_spectro_data **files;
  size_t nfiles;
  const vr_spectro_curve **curve;
  char *tokens;  /* comma-joined state tokens */
  double thickness_nm;
} inputs;

static void inputs_free(inputs *in) {
  for (size_t i = 0; i < in->nfiles; i++) vr_spectro_destroy(in->files[i]);
  free(in->files);
  free(in->curve);
  free(in->tokens);
}

static vr_status gather(const vr_args *a, inputs *in, vr_error *err) {
  memset(in, 0, sizeof *in);
  in->thickness_nm = NAN;
  size_t nf = a->noperands - 1;
  const char *states = vr_args_get(a, "states");
  in->files = calloc(nf, sizeof *in->files);
  if (!in->files) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t total = 0;
  for (size_t i = 0; i < nf; i++) {
    vr_status st = vr_spectro_read(a->operands[1 + i], &in->files[i], err);
    if (st) return st;
    in->nfiles++;
    for (size_t c = 0; c < in->files[i]->ncurves; c++) total += in->files[i]->curves[c].angle_deg == 0;
    if (isnan(in->thickness_nm)) in->thickness_nm = in->files[i]->thickness_nm;
  }
  in->curve = calloc(total, sizeof *in->curve);
  if (!in->curve) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t labels_len = 1;
  for (size_t i = 0; i < nf; i++)
    for (size_t c = 0; c < in->files[i]->ncurves; c++) {
      const vr_spectro_curve *cv = &in->files[i]->curves[c];
      if (cv->angle_deg != 0) continue;
      if (nf > 1 && in->files[i]->has_state && in->files[i]->ncurves > 1)
        return vr_error_set(err, VR_E_ARG, "%s holds several states; give either one file with a "
                                           "state column or one file per state", a->operands[1 + i]);
      in->curve[in->n++] = cv;
      labels_len += (cv->state ? strlen(cv->state) : 0) + 1;
    }
  if (states) {
    size_t count = 1;
    for (const char *p = states; *p; p++) count += *p == ',';
    if (count != in->n) {
      if (nf > 1)
        return vr_error_set(err, VR_E_ARG, "--states lists %zu state(s) but %zu file(s) were given "
                                           "(one state per file, in the same order)", count, in->n);
      return vr_error_set(err, VR_E_ARG, "--states lists %zu state(s) but %s holds %zu spectra",
                          count, a->operands[1], in->n);
    }
    in->tokens = strdup(states);
  } else {
    if (nf > 1 || !in->files[0]->has_state)
      return vr_error_set(err, VR_E_ARG, "give the state of each spectrum with --states LIST "
                                         "(or a state column in a single file)");
    in->tokens = malloc(labels_len);
    if (in->tokens) {
      in->tokens[0] = '\0';
      for (size_t i = 0; i < in->n; i++) {
        if (i) strcat(in->tokens, ",");
        strcat(in->tokens, in->curve[i]->state);
      }
    }
  }
  return in->tokens ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
}

static void print_result(const vr_chromo_fit_result *r, const vr_chromo_state *st, bool json) {
  bool ec = r->type == VR_CHROMO_ELECTRO;
  size_t j550 = 0, j633 = 0;
  for (size_t j = 1; j < r->nl; j++) {
    if (fabs(r->nm[j] - 550) < fabs(r->nm[j550] - 550)) j550 = j;
    if (fabs(r->nm[j] - 632.8) < fabs(r->nm[j633] - 632.8)) j633 = j;
  }
  if (json) {
    printf("{\"type\": \"%s\", \"chi2_reduced\": ", ec ? "electrochromic" : "photochromic");
    vr_json_number(stdout, r->chi2_reduced);
    printf(", \"dof\": %ld, \"states\": [", r->dof);
    for (size_t i = 0; i < r->ns; i++) {
      printf("%s{\"label\": ", i ? ", " : "");
      vr_json_string(stdout, st[i].label);
      printf(", \"s\": ");
      vr_json_number(stdout, r->s[i]);
      printf("}");
    }
    printf("], \"Q_full_mC_cm2\": ");
    vr_json_number(stdout, r->q_full);
    printf(", \"parameters\": [");
    for (size_t i = 0; i < r->nparams; i++) {
      const vr_chromo_param *p = &r->params[i];
      printf("%s{\"name\": \"%s\", \"unit\": \"%s\", \"fitted\": %s, \"value\": ", i ? ", " : "",
             p->name, p->unit, p->fitted ? "true" : "false");
      vr_json_number(stdout, p->value);
      printf(", \"stderr\": ");
      vr_json_number(stdout, p->stderr_);
      printf(", \"ci90\": ");
      vr_json_number(stdout, p->ci90);
      printf("}");
    }
    printf("], \"dOD\": [");
    for (size_t j = 0; j < r->nl; j++) {
      printf("%s[", j ? ", " : "");
      vr_json_number(stdout, r->nm[j]);
      printf(", ");
      vr_json_number(stdout, r->dOD[j]);
      printf(", ");
      vr_json_number(stdout, r->dOD_ci90[j]);
      printf("]");
    }
    printf("]}\n");
    return;
  }
  printf("# %s state model, %zu spectra x %zu wavelengths, reduced chi-square %.3g (%ld dof)\n",
         ec ? "electrochromic" : "photochromic", r->ns, r->nl, r->chi2_reduced, r->dof);
  printf("state                 s       T(%g nm) model\n", r->nm[j550]);
  for (size_t i = 0; i < r->ns; i++)
    printf("%-20s  %.4f  %.4f\n", st[i].label, r->s[i], r->T0[j550] * pow(10, -r->s[i] * r->dOD[j550]));
  printf("dOD at s = 1: %.4f +- %.4f (%g nm), %.4f +- %.4f (%g nm) (90%% limits)\n", r->dOD[j550],
         r->dOD_ci90[j550], r->nm[j550], r->dOD[j633], r->dOD_ci90[j633], r->nm[j633]);
  if (ec && isfinite(r->q_full))
    printf("coloration efficiency at %g nm: %.1f +- %.1f cm2/C (Q_full = %g mC/cm2)\n", r->nm[j633],
           r->dOD[j633] / (r->q_full * 1e-3), r->dOD_ci90[j633] / (r->q_full * 1e-3), r->q_full);
  for (size_t i = 0; i < r->nparams; i++) {
    const vr_chromo_param *p = &r->params[i];
    if (!p->fitted) {
      printf("%-6s not determined by these data (%s)\n", p->name,
             p->name[0] == 'E' ? "one temperature" : "steady states only: see K_ref");
      continue;
    }
    printf("%-6s = %.6g +- %.3g %s (90%% limits)\n", p->name, p->value, p->ci90, p->unit);
  }
}

int spectro_cmd_chromogenic(vr_args *a) {
  vr_error err = {0};
  inputs in;
  vr_chromo_state *st = NULL;
  size_t ns = 0;
  vr_chromo_fit_result r = {0};
  vr_spectrum **T = NULL, **Rf = NULL, **Rb = NULL;
  vr_material *m = NULL;
  vr_matdb *db = NULL;
  int rc = 1;
  double sigma, d_nm;
  if (vr_args_double(a, "sigma", 1e-3, &sigma, &err) || spectro_thickness(a, &d_nm, &err)) goto fail0;
  if (gather(a, &in, &err)) goto out;
  if (!isnan(d_nm)) in.thickness_nm = d_nm;
  if (vr_chromo_states_parse(in.tokens, &st, &ns, &err)) goto out;
  T = calloc(ns, sizeof *T);
  Rf = calloc(ns, sizeof *Rf);
  Rb = calloc(ns, sizeof *Rb);
  if (!T || !Rf || !Rb) {
    vr_error_set(&err, VR_E_NOMEM, "out of memory");
    goto out;
  }
  for (size_t i = 0; i < ns; i++) {
    if (!(T[i] = vr_spectro_spectrum(in.curve[i], 'T', &err))) goto out;
    Rf[i] = vr_spectro_spectrum(in.curve[i], 'f', NULL);
    Rb[i] = vr_spectro_spectrum(in.curve[i], 'b', NULL);
  }
  if (vr_chromo_fit(ns, st, (const vr_spectrum *const *)T, (const vr_spectrum *const *)Rf,
                    (const vr_spectrum *const *)Rb, sigma, &r, &err))
    goto out;
  print_result(&r, st, vr_args_flag(a, "json"));
  const char *save = vr_args_get(a, "save");
  if (save) {
    if (spectro_db(a, &db, &err) ||
        vr_chromo_fit_material(&r, save, in.thickness_nm * 1e-6, &m, &err) ||
        vr_material_set_text(&m->prov.note, in.tokens, &err) ||
        spectro_save(db, m, "chromogenic", a->operands[1], &err))
      goto out;
  }
  rc = 0;
out:
  inputs_free(&in);
fail0:
  if (rc) rc = spectro_fail(&err);
  for (size_t i = 0; i < ns; i++) {
    if (T) vr_spectrum_destroy(T[i]);
    if (Rf) vr_spectrum_destroy(Rf[i]);
    if (Rb) vr_spectrum_destroy(Rb[i]);
  }
  free(T);
  free(Rf);
  free(Rb);
  free(st);
  vr_chromo_fit_free(&r);
  vr_material_destroy(m);
  vr_matdb_close(db);
  return rc;
}

int spectro_cmd_state(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_material *m = NULL;
  int rc = 1;
  double s;
  if (spectro_db(a, &db, &err) || vr_matdb_load(db, a->operands[1], 0, &m, &err) ||
      spectro_state_of(a, m, &s, &err))
    goto out;
  const vr_spectrum *grid = vr_material_spectrum(m, "T0");
  if (!grid) {
    vr_error_set(&err, VR_E_ARG, "material %s is not a chromogenic glass", m->name);
    goto out;
  }
  size_t n = grid->n;
  double *v = malloc(3 * n * sizeof *v);
  if (!v) {
    vr_error_set(&err, VR_E_NOMEM, "out of memory");
    goto out;
  }
  for (size_t i = 0; i < n; i++)
    if (vr_chromo_eval(m, s, grid->nm[i], &v[i], &v[n + i], &v[2 * n + i], &err)) {
      free(v);
      goto out;
    }
  if (vr_args_flag(a, "json")) {
    static const char *const KEYS[3] = {"T", "Rf", "Rb"};
    printf("{\"material\": ");
    vr_json_string(stdout, m->name);
    printf(", \"state\": ");
    vr_json_number(stdout, s);
    printf(", \"wavelength_nm\": [");
    for (size_t i = 0; i < n; i++) {
      if (i) printf(", ");
      vr_json_number(stdout, grid->nm[i]);
    }
    printf("]");
    for (int q = 0; q < 3; q++) {
      printf(", \"%s\": ", KEYS[q]);
      if (isnan(v[q * n])) { /* not modelled (no reflectance in the fit) */
        printf("null");
        continue;
      }
      printf("[");
      for (size_t i = 0; i < n; i++) {
        if (i) printf(", ");
        vr_json_number(stdout, v[q * n + i]);
      }
      printf("]");
    }
    printf("}\n");
  } else {
    printf("# %s at state s = %.6f\nwavelength_nm,T,Rf,Rb\n", m->name, s);
    for (size_t i = 0; i < n; i++) {
      printf("%g,%.6f,", grid->nm[i], v[i]);
      if (isnan(v[n + i])) printf(",");
      else printf("%.6f,", v[n + i]);
      if (isnan(v[2 * n + i])) printf("\n");
      else printf("%.6f\n", v[2 * n + i]);
    }
  }
  free(v);
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  vr_material_destroy(m);
  vr_matdb_close(db);
  return rc;
}
