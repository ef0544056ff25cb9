/* vr-ellipso's outputs: the text and JSON summaries of a fit, the HTML
 * report with measured and model Ψ, Δ per angle and the fitted n, k, and the
 * material saved to the database with its provenance. */
#include "ellipso_output.h"
#include "vr/atomic_file.h"
#include "vr/json.h"
#include "vr/plot.h"
#include "vr/sha256.h"
#include "vr/version.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

vr_status vr_fit_view_init(vr_fit_view *v, const vr_sample_model *m, const vr_ellipso_data *d, size_t nd,
                           const vr_fit_result *r, const char *layer, vr_error *err) {
  memset(v, 0, sizeof *v);
  v->model = m;
  v->data = d;
  v->ndata = nd;
  v->fit = r;
  v->layer = VR_OWNER_SUBSTRATE;
  v->layer_name = "substrate";
  if (layer) {
    size_t i = 0;
    while (i < m->nlayers && strcmp(m->layers[i].name, layer)) i++;
    if (i < m->nlayers) {
      v->layer = (long)i;
      v->layer_name = m->layers[i].name;
    } else if (strcmp(layer, "substrate")) {
      return vr_error_set(err, VR_E_NOT_FOUND, "no layer '%s' in the model", layer);
    }
  } else {
    /* The first layer whose optical constants were fitted, else the first
     * layer, else the substrate. */
    long pick = m->nlayers ? 0 : VR_OWNER_SUBSTRATE;
    for (size_t j = 0; j < m->nparams; j++)
      if (m->params[j].free && m->params[j].slot >= 0 && m->params[j].owner != VR_OWNER_AMBIENT) {
        pick = m->params[j].owner;
        break;
      }
    v->layer = pick;
    v->layer_name = pick >= 0 ? m->layers[pick].name : "substrate";
  }
  for (size_t j = 0; nd > 1 && j < m->nparams; j++) {
    const vr_model_param *q = &m->params[j];
    if (q->free && q->per_sample && q->owner == v->layer && q->slot != VR_SLOT_THICKNESS) v->nk_per_sample = true;
  }
  size_t total = 0;
  for (size_t s = 0; s < nd; s++) total += d[s].n;
  v->wl = malloc((total ? total : 1) * sizeof *v->wl);
  if (!v->wl) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t at = 0;
  for (size_t s = 0; s < nd; s++)
    for (size_t i = 0; i < d[s].n; i++) v->wl[at++] = d[s].p[i].nm;
  qsort(v->wl, total, sizeof *v->wl, cmp_double);
  for (size_t i = 0; i < total; i++)
    if (!v->nwl || v->wl[i] != v->wl[v->nwl - 1]) v->wl[v->nwl++] = v->wl[i];
  v->n = malloc(v->nwl * sizeof *v->n);
  v->k = malloc(v->nwl * sizeof *v->k);
  if (!v->n || !v->k) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < v->nwl; i++) {
    vr_complex N;
    vr_status st = vr_model_layer_index(m, v->layer, v->wl[i], &N, err);
    if (st) return st;
    v->n[i] = creal(N);
    v->k[i] = cimag(N);
  }
  return VR_OK;
}

void vr_fit_view_free(vr_fit_view *v) {
  free(v->wl);
  free(v->n);
  free(v->k);
  memset(v, 0, sizeof *v);
}

static int high_correlations(const vr_fit_result *r, FILE *f, bool print) {
  int count = 0;
  for (size_t i = 0; i < r->nfree; i++)
    for (size_t j = i + 1; j < r->nfree; j++) {
      double c = r->correlation[i * r->nfree + j];
      if (fabs(c) > 0.95) {
        count++;
        if (print)
          fprintf(f, "warning: %s and %s are correlated (r = %+.4f): the data barely tell them apart\n",
                  r->names[i], r->names[j], c);
      }
    }
  return count;
}

static const char *termination(const vr_fit_result *r) {
  return r->summary.termination == VR_LSQ_CONVERGED ? "converged"
         : r->summary.termination == VR_LSQ_NO_CONVERGENCE ? "iteration limit" : "failure";
}

void vr_fit_print_text(FILE *f, const vr_fit_view *v) {
  const vr_fit_result *r = v->fit;
  fprintf(f, "MSE (J.A. Woollam's, on Psi and Delta%s) %.4f   (chi2 %.6g over %zu (Psi, Delta) pairs%s, %zu free parameters; %s after %d iterations, %d grid evaluations)\n",
          r->ndepol ? " and depolarisation" : "", r->mse, r->chi2, r->npoints, r->ndepol ? " and their depolarisation" : "",
          r->nfree, termination(r), r->summary.iterations, r->grid_evaluations);
  if (isfinite(r->mse_ncs))
    fprintf(f, "MSE (CompleteEASE's, on N, C, S x 1000, %s) %.4f\n",
            r->ncs_from_file ? "the file's own N, C, S" : "N, C, S computed from the file's Psi, Delta", r->mse_ncs);
  if (r->nsamples > 1) {
    fprintf(f, "\n%-8s %-40s %8s %10s %10s\n", "sample", "data", "points", "MSE", "misfit");
    for (size_t s = 0; s < r->nsamples; s++)
      fprintf(f, "%-8zu %-40.40s %8zu %10.4f %10.3g%s\n", s + 1, r->samples[s].source, r->samples[s].npoints,
              r->samples[s].mse, r->samples[s].misfit_ratio, r->samples[s].describes ? "" : "  DOES NOT DESCRIBE");
  }
  fprintf(f, "\n%-24s %14s %12s %28s\n", "parameter", "value", "std error", "90% confidence limits");
  for (size_t i = 0; i < r->nfree; i++) {
    if (r->at_bound && r->at_bound[i])
      fprintf(f, "%-24s %14.8g   AT ITS %s BOUND: not a free estimate, no uncertainty\n", r->names[i],
              r->value[i], r->at_bound[i] < 0 ? "LOWER" : "UPPER");
    else
      fprintf(f, "%-24s %14.8g %12.4g   [%12.8g, %12.8g]\n", r->names[i], r->value[i], r->stderr_[i],
              r->ci_lo[i], r->ci_hi[i]);
  }
  for (size_t i = 0; r->at_bound && i < r->nfree; i++)
    if (r->at_bound[i]) {
      fprintf(f, "warning: a parameter ended at a bound: the data want it beyond; widen the bound or "
                 "change the model (the other uncertainties hold with it pinned there)\n");
      break;
    }
  if (!r->covariance_ok) fprintf(f, "warning: uncertainties unavailable: %s\n", r->covariance_message);
  if (r->nfree > 1 && r->covariance_ok) {
    fprintf(f, "\ncorrelation matrix\n");
    for (size_t i = 0; i < r->nfree; i++) {
      fprintf(f, "%-24s", r->names[i]);
      for (size_t j = 0; j < r->nfree; j++) fprintf(f, " %+7.4f", r->correlation[i * r->nfree + j]);
      fputc('\n', f);
    }
  }
  high_correlations(r, f, true);
  fprintf(f, "\nverdict: %s\n", r->verdict);
  if (v->nk_per_sample) fprintf(f, "note: the optical constants of %s are fitted per sample; those of sample 1 follow\n", v->layer_name);
  if (r->exact_inversion) {
    /* Point by point: the exact inversion and its propagated deviations. */
    const vr_ellipso_data *d = v->data;
    fprintf(f, "\nexact pseudo-dielectric inversion, point by point\n%10s %8s %12s %12s %12s %12s\n",
            "nm", "AOI", "n", "sigma_n", "k", "sigma_k");
    size_t pstep = d->n > 20 ? (d->n + 19) / 20 : 1;
    for (size_t i = 0; i < d->n; i += pstep) {
      double n, k, sn, sk;
      vr_pseudo_index(&d->p[i], &n, &k, &sn, &sk);
      fprintf(f, "%10.2f %8.3f %12.6f %12.3g %12.6g %12.3g\n", d->p[i].nm, d->p[i].aoi_deg, n, sn, k, sk);
    }
    if (pstep > 1) fprintf(f, "(every %zu-th of %zu points; --json gives all)\n", pstep, d->n);
  }
  fprintf(f, "\nn, k of %s\n%10s %12s %12s\n", v->layer_name, "nm", "n", "k");
  size_t step = v->nwl > 20 ? (v->nwl + 19) / 20 : 1;
  for (size_t i = 0; i < v->nwl; i += step) fprintf(f, "%10.2f %12.6f %12.6g\n", v->wl[i], v->n[i], v->k[i]);
  if (step > 1) fprintf(f, "(every %zu-th of %zu wavelengths; --json gives all)\n", step, v->nwl);
}

void vr_fit_print_json(FILE *f, const vr_fit_view *v) {
  const vr_fit_result *r = v->fit;
  fputs("{\"mse\": ", f);
  vr_json_number(f, r->mse);
  fputs(r->ndepol ? ", \"mse_definition\": \"J.A. Woollam: sqrt(chi2 / (2N + D - M)) over Psi, Delta and depolarisation\""
                  : ", \"mse_definition\": \"J.A. Woollam: sqrt(chi2 / (2N - M)) over Psi and Delta\"", f);
  fputs(", \"mse_ncs\": ", f);
  vr_json_number(f, r->mse_ncs);
  fprintf(f, ", \"mse_ncs_definition\": \"CompleteEASE: 1000 sqrt(sum((dN)^2 + (dC)^2 + (dS)^2) / (3N - M)) on %s\"",
          r->ncs_from_file ? "the file's N, C, S" : "N, C, S of the file's Psi, Delta");
  fprintf(f, ", \"depolarisation_points\": %zu, \"samples\": [", r->ndepol);
  for (size_t s = 0; s < r->nsamples; s++) {
    fputs(s ? ", {\"data\": " : "{\"data\": ", f);
    vr_json_string(f, r->samples[s].source);
    fprintf(f, ", \"points\": %zu, \"mse\": ", r->samples[s].npoints);
    vr_json_number(f, r->samples[s].mse);
    fputs(", \"misfit_ratio\": ", f);
    vr_json_number(f, r->samples[s].misfit_ratio);
    fprintf(f, ", \"describes\": %s}", r->samples[s].describes ? "true" : "false");
  }
  fputc(']', f);
  fputs(", \"chi2\": ", f);
  vr_json_number(f, r->chi2);
  fprintf(f, ", \"points\": %zu, \"free_parameters\": %zu, \"iterations\": %d, \"termination\": \"%s\", \"parameters\": [",
          r->npoints, r->nfree, r->summary.iterations, termination(r));
  for (size_t i = 0; i < r->nfree; i++) {
    fputs(i ? ", {\"name\": " : "{\"name\": ", f);
    vr_json_string(f, r->names[i]);
    fputs(", \"value\": ", f);
    vr_json_number(f, r->value[i]);
    fputs(", \"stderr\": ", f);
    vr_json_number(f, r->stderr_[i]);
    fputs(", \"ci90\": [", f);
    vr_json_number(f, r->ci_lo[i]);
    fputs(", ", f);
    vr_json_number(f, r->ci_hi[i]);
    int b = r->at_bound ? r->at_bound[i] : 0;
    fprintf(f, "], \"at_bound\": %s}", b < 0 ? "\"lower\"" : b > 0 ? "\"upper\"" : "null");
  }
  fputs("], \"correlation\": [", f);
  for (size_t i = 0; i < r->nfree; i++) {
    fputs(i ? ", [" : "[", f);
    for (size_t j = 0; j < r->nfree; j++) {
      if (j) fputs(", ", f);
      vr_json_number(f, r->correlation[i * r->nfree + j]);
    }
    fputc(']', f);
  }
  fprintf(f, "], \"high_correlations\": %d, \"covariance_ok\": %s, \"layer\": ", high_correlations(r, f, false),
          r->covariance_ok ? "true" : "false");
  vr_json_string(f, v->layer_name);
  fprintf(f, ", \"nk_per_sample\": %s", v->nk_per_sample ? "true" : "false");
  fprintf(f, ", \"verdict\": {\"describes\": %s", r->describes ? "true" : "false");
  const char *vk[3] = {"misfit_ratio", "noise_psi_deg", "noise_delta_deg"};
  const double vv[3] = {r->misfit_ratio, r->noise_psi, r->noise_delta};
  for (int j = 0; j < 3; j++) {
    fprintf(f, ", \"%s\": ", vk[j]);
    vr_json_number(f, vv[j]);
  }
  fputs(", \"text\": ", f);
  vr_json_string(f, r->verdict);
  fprintf(f, "}, \"method\": \"%s\"", r->exact_inversion ? "exact inversion" : "fit");
  if (r->exact_inversion) {
    fputs(", \"pseudo\": [", f);
    for (size_t i = 0; i < v->data->n; i++) {
      double n, k, sn, sk;
      vr_pseudo_index(&v->data->p[i], &n, &k, &sn, &sk);
      const double vals[6] = {v->data->p[i].nm, v->data->p[i].aoi_deg, n, sn, k, sk};
      const char *keys[6] = {"wavelength_nm", "aoi_deg", "n", "sigma_n", "k", "sigma_k"};
      for (int j = 0; j < 6; j++) {
        fprintf(f, "%s\"%s\": ", j ? ", " : i ? ", {" : "{", keys[j]);
        vr_json_number(f, vals[j]);
      }
      fputc('}', f);
    }
    fputc(']', f);
  }
  fputs(", \"nk\": [", f);
  for (size_t i = 0; i < v->nwl; i++) {
    fputs(i ? ", {\"wavelength_nm\": " : "{\"wavelength_nm\": ", f);
    vr_json_number(f, v->wl[i]);
    fputs(", \"n\": ", f);
    vr_json_number(f, v->n[i]);
    fputs(", \"k\": ", f);
    vr_json_number(f, v->k[i]);
    fputc('}', f);
  }
  fputs("]}\n", f);
}

static const unsigned COLOURS[] = {0x1f77b4, 0xd62728, 0x2ca02c, 0x9467bd, 0xff7f0e, 0x8c564b};

static bool plot_quantity(FILE *f, const vr_fit_view *v, bool delta) {
  vr_plot *p = vr_plot_create(delta ? "Delta: measured (dots) and model (lines)" : "Psi: measured (dots) and model (lines)",
                              "wavelength (nm)", delta ? "Delta (deg)" : "Psi (deg)");
  size_t most = 1, first = 0, series = 0;
  for (size_t s = 0; s < v->ndata; s++) most = v->data[s].n > most ? v->data[s].n : most;
  double *x = malloc(most * sizeof *x), *ym = malloc(most * sizeof *ym), *yf = malloc(most * sizeof *yf);
  bool ok = p && x && ym && yf;
  for (size_t s = 0; ok && s < v->ndata; s++) {
    const vr_ellipso_data *d = &v->data[s];
    double angles[16];
    size_t na = vr_ellipso_angles(d, angles, 16);
    for (size_t a = 0; ok && a < na; a++) {
      size_t n = 0;
      for (size_t i = 0; i < d->n; i++)
        if (fabs(d->p[i].aoi_deg - angles[a]) < 0.01) {
          x[n] = d->p[i].nm;
          ym[n] = delta ? d->p[i].delta_deg : d->p[i].psi_deg;
          yf[n] = delta ? v->fit->delta_model[first + i] : v->fit->psi_model[first + i];
          n++;
        }
      char label[48];
      if (v->ndata > 1) snprintf(label, sizeof label, "sample %zu, %.2f deg", s + 1, angles[a]);
      else snprintf(label, sizeof label, "%.2f deg", angles[a]);
      unsigned c = COLOURS[series++ % 6];
      ok = vr_plot_add(p, n, x, ym, c, true, label) && vr_plot_add(p, n, x, yf, c, false, "");
    }
    first += d->n;
  }
  if (ok) ok = vr_plot_write_svg(p, f, 720, 360);
  vr_plot_destroy(p);
  free(x);
  free(ym);
  free(yf);
  return ok;
}

static void html_text(FILE *f, const char *s) {
  for (; s && *s; s++) {
    if (*s == '<') fputs("&lt;", f);
    else if (*s == '>') fputs("&gt;", f);
    else if (*s == '&') fputs("&amp;", f);
    else fputc(*s, f);
  }
}

vr_status vr_fit_write_report(const char *path, const vr_fit_view *v, vr_error *err) {
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.fp;
  const vr_fit_result *r = v->fit;
  fputs("<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>vr-ellipso fit</title>\n"
        "<style>body{font-family:sans-serif;max-width:980px;margin:2em auto}table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}.warn{color:#b00}</style></head><body>\n", f);
  fputs("<h1>Ellipsometry fit</h1>\n<p>Data: ", f);
  for (size_t s = 0; s < v->ndata; s++) {
    if (s) fputs("; ", f);
    html_text(f, v->data[s].source);
  }
  fputs("<br>Model: ", f);
  html_text(f, v->model->source);
  fprintf(f, "<br>MSE = %.4f (Woollam's definition, sqrt(chi2 / (2N%s - M))), chi2 = %.6g, N = %zu, M = %zu; %s after %d iterations.",
          r->mse, r->ndepol ? " + D" : "", r->chi2, r->npoints, r->nfree, termination(r), r->summary.iterations);
  if (isfinite(r->mse_ncs))
    fprintf(f, "<br>MSE = %.4f (CompleteEASE's definition on N, C, S x 1000, %s).", r->mse_ncs,
            r->ncs_from_file ? "the file's own N, C, S" : "from the file's Psi, Delta");
  fputs("</p>\n<p>Verdict: ", f);
  html_text(f, r->verdict);
  fputs("</p>\n", f);
  fputs("<h2>Parameters</h2>\n<table><tr><th>parameter</th><th>value</th><th>std error</th><th>90% limits</th></tr>\n", f);
  for (size_t i = 0; i < r->nfree; i++) {
    fputs("<tr><td style=\"text-align:left\">", f);
    html_text(f, r->names[i]);
    fprintf(f, "</td><td>%.8g</td><td>%.4g</td><td>[%.8g, %.8g]</td></tr>\n", r->value[i], r->stderr_[i], r->ci_lo[i], r->ci_hi[i]);
  }
  fputs("</table>\n", f);
  if (!r->covariance_ok) {
    fputs("<p class=\"warn\">Uncertainties unavailable: ", f);
    html_text(f, r->covariance_message);
    fputs("</p>\n", f);
  }
  if (r->covariance_ok && r->nfree > 1) {
    fputs("<h2>Correlation</h2>\n<table><tr><th></th>", f);
    for (size_t j = 0; j < r->nfree; j++) {
      fputs("<th>", f);
      html_text(f, r->names[j]);
      fputs("</th>", f);
    }
    fputs("</tr>\n", f);
    for (size_t i = 0; i < r->nfree; i++) {
      fputs("<tr><th>", f);
      html_text(f, r->names[i]);
      fputs("</th>", f);
      for (size_t j = 0; j < r->nfree; j++) {
        double c = r->correlation[i * r->nfree + j];
        fprintf(f, i != j && fabs(c) > 0.95 ? "<td class=\"warn\">%+.4f</td>" : "<td>%+.4f</td>", c);
      }
      fputs("</tr>\n", f);
    }
    fputs("</table>\n", f);
    if (high_correlations(r, f, false))
      fputs("<p class=\"warn\">Correlations above 0.95 in magnitude: those parameters are not separately determined by these data.</p>\n", f);
  }
  fputs("<h2>Psi and Delta</h2>\n", f);
  bool ok = plot_quantity(f, v, false) && plot_quantity(f, v, true);
  fputs("\n<h2>Optical constants of ", f);
  html_text(f, v->layer_name);
  fputs("</h2>\n", f);
  vr_plot *p = vr_plot_create("n (blue) and k (red)", "wavelength (nm)", "n, k");
  ok = ok && p && vr_plot_add(p, v->nwl, v->wl, v->n, 0x1f77b4, false, "n") &&
       vr_plot_add(p, v->nwl, v->wl, v->k, 0xd62728, false, "k") && vr_plot_write_svg(p, f, 720, 320);
  vr_plot_destroy(p);
  fputs("\n</body></html>\n", f);
  /* A plot that failed to be written (a full disk) is the write's error,
   * which the commit reports with its reason; else the plot itself failed. */
  if (!ok && !ferror(f) && fflush(f) == 0) {
    vr_atomic_file_abort(&af);
    return vr_error_set(err, VR_E_IO, "%s: could not draw the plots (out of memory)", path);
  }
  return vr_atomic_file_commit(&af, err);
}

vr_status vr_fit_save(vr_matdb *db, const char *name, const vr_fit_view *v, const char *const *data_paths,
                      size_t npaths, const char *model_path, bool forced, vr_error *err) {
  if (v->nk_per_sample)
    return vr_error_set(err, VR_E_ARG, "the optical constants of %s differ per sample: there is no one n, k to save",
                        v->layer_name);
  char joined[4096] = "";
  for (size_t i = 0; i < npaths; i++) {
    size_t l = strlen(joined);
    snprintf(joined + l, sizeof joined - l, "%s%s", i ? "; " : "", data_paths[i]);
  }
  vr_complex N;
  vr_status st = vr_model_layer_index(v->model, v->layer, 550.0, &N, NULL);
  vr_material *m = vr_material_create(name, st == VR_OK && cimag(N) > creal(N) ? VR_KIND_CONDUCTOR : VR_KIND_DIELECTRIC, err);
  if (!m) return VR_E_NOMEM;
  vr_spectrum *n = vr_spectrum_create(v->nwl, v->wl, v->n, err), *k = n ? vr_spectrum_create(v->nwl, v->wl, v->k, err) : NULL;
  if (!n || !k) {
    vr_spectrum_destroy(n);
    vr_material_destroy(m);
    return err ? err->status : VR_E_NOMEM;
  }
  char model[256];
  snprintf(model, sizeof model, "ellipsometry fit of layer '%s' in %s", v->layer_name, model_path ? model_path : "an automatic bulk model");
  if ((st = vr_material_add_spectrum(m, "n", n, err)) || (st = vr_material_add_spectrum(m, "k", k, err)) ||
      (st = vr_material_set_text(&m->prov.source_path, joined, err)) ||
      (st = vr_material_set_text(&m->prov.tool, "vr-ellipso fit", err)) ||
      (st = vr_material_set_text(&m->prov.tool_version, vr_version(), err)) ||
      (st = vr_material_set_text(&m->prov.model, model, err)))
    goto done;
  if (npaths == 1) {
    if ((st = vr_sha256_file(data_paths[0], m->prov.sha256, err))) goto done;
  } else {
    vr_sha256 all;
    vr_sha256_init(&all);
    for (size_t i = 0; i < npaths; i++) {
      char one[65];
      if ((st = vr_sha256_file(data_paths[i], one, err))) goto done;
      vr_sha256_update(&all, one, 64);
    }
    vr_sha256_final(&all, m->prov.sha256);
  }
  m->prov.residual = v->fit->mse;
  for (size_t i = 0; i < v->fit->nfree && !st; i++)
    st = vr_material_add_parameter(m, v->fit->names[i], v->fit->value[i], v->fit->stderr_[i], NULL, err);
  if (!st && v->layer >= 0)
    st = vr_material_add_property(m, "thickness", NULL, v->model->layers[v->layer].thickness_nm, "nm", err);
  /* The verdict travels with the material: whoever uses it later sees
   * whether the fit described its data, and whether it was forced. */
  const vr_fit_result *r = v->fit;
  size_t pinned = 0;
  for (size_t i = 0; r->at_bound && i < r->nfree; i++) pinned += r->at_bound[i] != 0;
  if (!st) st = vr_material_add_property(m, "fit_mse", NULL, r->mse, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_misfit_ratio", NULL, r->misfit_ratio, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_parameters_at_bound", NULL, (double)pinned, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_describes", NULL, r->describes ? 1 : 0, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_forced", NULL, forced ? 1 : 0, NULL, err);
  if (!st) {
    char note[1024];
    snprintf(note, sizeof note, "verdict: %s; MSE %.6g%s", r->verdict, r->mse,
             forced ? "; saved with --force although the fit does not describe the data" : "");
    st = vr_material_set_text(&m->prov.note, note, err);
  }
  if (!st) st = vr_matdb_save(db, m, err);
done:
  vr_material_destroy(m);
  return st;
}
