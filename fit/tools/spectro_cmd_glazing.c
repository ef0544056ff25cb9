/* vr-spectro metrics (glazing figures) and btdf (pane tables). */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/atomic_file.h"
#include "vr/btdf_table.h"
#include "vr/csv.h"
#include "vr/frosted.h"
#include "vr/glazing.h"
#include "vr/json.h"
#include "vr/optical_standard.h"

vr_status spectro_parse_route(const vr_args *a, vr_angular_route *r, vr_error *err) {
  const char *s = vr_args_get(a, "route");
  *r = VR_ROUTE_AUTO;
  if (!s || !strcasecmp(s, "auto")) return VR_OK;
  if (!strcasecmp(s, "physical")) *r = VR_ROUTE_PHYSICAL;
  else if (!strcasecmp(s, "coated")) *r = VR_ROUTE_COATED;
  else return vr_error_set(err, VR_E_ARG, "--route '%s': expected auto, physical or coated", s);
  return VR_OK;
}

static const char *route_name(vr_angular_route r) {
  return r == VR_ROUTE_COATED ? "coated (Windows-CalcEngine polynomials)"
         : r == VR_ROUTE_PHYSICAL ? "physical (n, k back-solved, Fresnel per polarisation)"
                                  : "normal incidence (measured)";
}

vr_status spectro_normal_curve(const vr_spectro_data *d, const char *item,
                               const vr_spectro_curve **c, vr_error *err) {
  for (size_t i = 0; i < d->ncurves; i++)
    if (d->curves[i].angle_deg == 0) {
      if (d->has_state && d->ncurves > 1 && d->curves[i].state)
        for (size_t j = i + 1; j < d->ncurves; j++)
          if (d->curves[j].state && strcmp(d->curves[j].state, d->curves[i].state))
            return vr_error_set(err, VR_E_ARG, "%s holds several tint states; use vr-spectro "
                                               "chromogenic, then metrics NAME --state S", item);
      *c = &d->curves[i];
      return VR_OK;
    }
  return vr_error_set(err, VR_E_ARG, "%s has no normal-incidence spectrum (angle 0)", item);
}

/* Normal solar transmittance of a curve (chooses the coated polynomial set). */
static double solar_T(const vr_standard *std, const vr_spectro_curve *c) {
  vr_pane *p;
  vr_glazing_metrics m;
  if (vr_pane_from_curve(c, NAN, 0, VR_ROUTE_AUTO, NAN, &p, NULL, NULL)) return NAN;
  double t = vr_glazing_metrics_compute(std, p, &m, NULL) ? NAN : m.Tsol;
  vr_pane_destroy(p);
  return t;
}

static void print_metrics(const vr_glazing_metrics *m, const vr_standard *std, double angle,
                          char **items, size_t n, const char *route, bool json) {
  if (json) {
    printf("{\"standard\": ");
    vr_json_string(stdout, std->name);
    printf(", \"angle_deg\": ");
    vr_json_number(stdout, angle);
    printf(", \"route\": ");
    vr_json_string(stdout, route);
    printf(", \"panes\": [");
    for (size_t i = 0; i < n; i++) {
      if (i) printf(", ");
      vr_json_string(stdout, items[i]);
    }
    printf("]");
    const struct {
      const char *k;
      double v;
    } f[] = {{"Tvis", m->Tvis}, {"Rvis_front", m->Rvis_front}, {"Rvis_back", m->Rvis_back},
             {"Tsol", m->Tsol}, {"Rsol_front", m->Rsol_front}, {"Rsol_back", m->Rsol_back},
             {"Tuv", m->Tuv}};
    for (size_t i = 0; i < sizeof f / sizeof f[0]; i++) {
      printf(", \"%s\": ", f[i].k);
      vr_json_number(stdout, f[i].v);
    }
    const char *labs[3] = {"T_Lab", "Rf_Lab", "Rb_Lab"};
    const double *lab[3] = {m->T_lab, m->Rf_lab, m->Rb_lab};
    /* EN 410's colour rendering in transmission (D65 against D65). */
    printf(", \"Ra\": ");
    vr_json_number(stdout, m->Ra);
    printf(", \"R_i\": ");
    if (isnan(m->Ra))
      printf("null");
    else
      for (int j = 0; j < 8; j++) {
        printf(j ? ", " : "[");
        vr_json_number(stdout, m->R_i[j]);
      }
    if (!isnan(m->Ra)) printf("]");
    printf(", \"has_reflectance\": %s", m->has_R ? "true" : "false");
    if (!m->has_R)
      printf(", \"note\": \"reflectance was not measured: the R figures and the reflected colour "
             "need R (null); the T figures stand\"");
    /* The transmitted tristimulus values, the perfect transmitter's Y at
     * 100, as the IGSDB lists them (tciex, tciey, tciez). */
    printf(", \"T_XYZ\": ");
    if (m->has_colour)
      for (int j = 0; j < 3; j++) {
        printf(j ? ", " : "[");
        vr_json_number(stdout, 100 * m->T_xyz[j]);
      }
    printf(m->has_colour ? "]" : "null");
    for (int i = 0; i < 3; i++) {
      printf(", \"%s\": ", labs[i]);
      if (!m->has_colour || (i > 0 && !m->has_R)) {
        printf("null");
        continue;
      }
      printf("[");
      for (int j = 0; j < 3; j++) {
        if (j) printf(", ");
        vr_json_number(stdout, lab[i][j]);
      }
      printf("]");
    }
    printf("}\n");
    return;
  }
  printf("# %s, %g deg, %zu pane(s): ", std->description ? std->description : std->name, angle, n);
  for (size_t i = 0; i < n; i++) printf("%s%s", i ? " | " : "", items[i]);
  printf("\n# angular route: %s\n", route);
  if (!m->has_R) {
    printf("# reflectance was not measured: transmittance figures only; Rvis, Rsol and the "
           "reflected colour need R\n");
    printf("Tvis        %.6f\nTsol        %.6f\n", m->Tvis, m->Tsol);
  } else {
    printf("Tvis        %.6f\nRvis_front  %.6f\nRvis_back   %.6f\n", m->Tvis, m->Rvis_front,
           m->Rvis_back);
    printf("Tsol        %.6f\nRsol_front  %.6f\nRsol_back   %.6f\n", m->Tsol, m->Rsol_front,
           m->Rsol_back);
  }
  if (!isnan(m->Tuv)) printf("Tuv         %.6f\n", m->Tuv);
  if (m->has_colour) printf("transmitted L*a*b*  %.2f %.2f %.2f\n", m->T_lab[0], m->T_lab[1], m->T_lab[2]);
  if (m->has_colour && m->has_R)
    printf("reflected (front)   %.2f %.2f %.2f\n", m->Rf_lab[0], m->Rf_lab[1], m->Rf_lab[2]);
  if (!isnan(m->Ra))
    printf("Ra          %.2f   (EN 410: D65 through the glazing against D65, CIE 13.3)\n", m->Ra);
}

vr_status spectro_pane_items(const vr_args *a, char **list, char **items, size_t *n, vr_error *err) {
  *n = 0;
  *list = NULL;
  const char *panes_opt = vr_args_get(a, "panes");
  if (panes_opt) {
    if (!(*list = strdup(panes_opt))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
    char *save = NULL;
    for (char *t = strtok_r(*list, ",", &save); t; t = strtok_r(NULL, ",", &save)) {
      if (*n == SPECTRO_MAX_PANES)
        return vr_error_set(err, VR_E_ARG, "--panes: at most %d panes", SPECTRO_MAX_PANES);
      items[(*n)++] = t;
    }
  } else if (a->noperands >= 2) {
    items[(*n)++] = (char *)a->operands[1];
  }
  if (*n == 0)
    return vr_error_set(err, VR_E_ARG, "%s needs a pane: FILE, NAME or --panes A,B", a->operands[0]);
  return VR_OK;
}

vr_status spectro_panes_metrics(const vr_standard *std, vr_spectro_data *const *data, char **items,
                                size_t n, double angle, vr_angular_route route,
                                vr_glazing_metrics *m, const char **used_route, size_t *unsolved,
                                vr_error *err) {
  vr_pane *panes[SPECTRO_MAX_PANES] = {0}, *sys = NULL;
  vr_status st = VR_OK;
  *used_route = route_name(VR_ROUTE_AUTO);
  for (size_t i = 0; i < n && !st; i++) {
    const vr_spectro_curve *c;
    if ((st = spectro_normal_curve(data[i], items[i], &c, err))) break;
    double sol = angle > 0 ? solar_T(std, c) : NAN;
    size_t u = 0;
    if ((st = vr_pane_from_curve(c, data[i]->thickness_nm, angle, route, sol, &panes[i], &u, err))) {
      vr_error_prefix(err, "%s: ", items[i]);
      break;
    }
    if (angle > 0) *used_route = route_name(panes[i]->route);
    unsolved[i] += u;
  }
  if (!st) st = vr_pane_combine(panes, n, &sys, err);
  if (!st && (st = vr_glazing_metrics_compute(std, sys, m, err)) && n == 1)
    vr_error_prefix(err, "%s: ", items[0]);
  for (size_t i = 0; i < n; i++) vr_pane_destroy(panes[i]);
  vr_pane_destroy(sys);
  return st;
}

int spectro_cmd_metrics(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_standard *std = NULL;
  char *list = NULL, *items[SPECTRO_MAX_PANES];
  size_t n = 0, unsolved[SPECTRO_MAX_PANES] = {0};
  vr_spectro_data *data[SPECTRO_MAX_PANES] = {0};
  int rc = 1;
  double angle;
  vr_angular_route route;
  const char *stdname = vr_args_get(a, "standard");
  const char *used_route;
  if (!vr_args_get(a, "panes") && a->noperands >= 2 && spectro_is_bsdf_xml(a->operands[1]))
    return spectro_metrics_bsdf_xml(a, a->operands[1]);
  if (vr_args_get(a, "phi")) {
    vr_error_set(&err, VR_E_RANGE, "--phi: only for a BSDF XML file (a pane's figures do not depend "
                                 "on the azimuth)");
    goto out;
  }
  if (vr_args_double(a, "angle", 0, &angle, &err) || spectro_parse_route(a, &route, &err)) goto out;
  if (!(angle >= 0 && angle <= 90)) {
    vr_error_set(&err, VR_E_ARG, "--angle %g: expected 0 to 90 degrees", angle);
    goto out;
  }
  if (vr_standard_open(stdname ? stdname : "nfrc", &std, &err)) goto out;
  if (spectro_pane_items(a, &list, items, &n, &err)) goto out;
  for (size_t i = 0; i < n; i++)
    if (spectro_pane_source(a, items[i], &db, &data[i], &err)) goto out;
  vr_glazing_metrics m;
  if (spectro_panes_metrics(std, data, items, n, angle, route, &m, &used_route, unsolved, &err))
    goto out;
  for (size_t i = 0; i < n; i++)
    if (unsolved[i])
      fprintf(stderr, "vr-spectro: %s: %zu wavelength(s) fit no slab; their index was borrowed "
                      "from neighbours\n", items[i], unsolved[i]);
  print_metrics(&m, std, angle, items, n, used_route, vr_args_flag(a, "json"));
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  for (size_t i = 0; i < n; i++) vr_spectro_destroy(data[i]);
  vr_standard_destroy(std);
  vr_matdb_close(db);
  free(list);
  return rc;
}

/* --wavelengths FROM:TO:STEP (default 300:2500:10). */
vr_status spectro_wavelengths(const vr_args *a, double **nm, size_t *n, vr_error *err) {
  const char *w = vr_args_get(a, "wavelengths");
  double v[3] = {300, 2500, 10};
  char tail;
  if (w && (sscanf(w, "%lf:%lf:%lf%c", &v[0], &v[1], &v[2], &tail) != 3 || !(v[0] > 0) ||
            !(v[1] >= v[0]) || !(v[2] > 0) || !isfinite(v[1]) || (v[1] - v[0]) / v[2] > 1e6))
    return vr_error_set(err, VR_E_RANGE, "--wavelengths '%s': expected FROM:TO:STEP in nm", w);
  *n = (size_t)floor((v[1] - v[0]) / v[2] + 1e-9) + 1;
  *nm = malloc(*n * sizeof **nm);
  if (!*nm) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < *n; i++) (*nm)[i] = v[0] + v[2] * (double)i;
  return VR_OK;
}

static vr_status write_btdf_table(const char *path, const vr_btdf_table *t, vr_error *err) {
  vr_atomic_file f;
  vr_status st = vr_atomic_file_open(&f, path, err);
  if (st) return st;
  fprintf(f.fp, "angle_deg,wavelength_nm,Ts,Tp,Rfs,Rfp,Rbs,Rbp\n");
  for (size_t i = 0; i < t->na; i++)
    for (size_t j = 0; j < t->nl; j++) {
      fprintf(f.fp, "%g,%g", t->angles[i], t->nm[j]);
      for (int q = 0; q < VR_BT_COUNT; q++) fprintf(f.fp, ",%.8f", t->q[q][i * t->nl + j]);
      fprintf(f.fp, "\n");
    }
  return vr_atomic_file_commit(&f, err);
}

/* A measured curve on the --wavelengths grid, linear between its rows; the
 * grid must lie inside the measurement (no extrapolation). */
static vr_status resample_curve(const vr_spectro_curve *c, const double *nm, size_t n,
                                const char *item, vr_spectro_curve *out, vr_error *err) {
  double lo = c->p[0].nm, hi = c->p[c->n - 1].nm;
  if (nm[0] < lo - 1e-9 || nm[n - 1] > hi + 1e-9)
    return vr_error_set(err, VR_E_RANGE,
                        "--wavelengths %g-%g nm: outside the measurement of %s, %g-%g nm (a "
                        "measured pane is resampled within its data, never extrapolated)",
                        nm[0], nm[n - 1], item, lo, hi);
  *out = *c;
  out->n = n;
  out->p = malloc(n * sizeof *out->p);
  if (!out->p) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  size_t k = 0;
  for (size_t i = 0; i < n; i++) {
    double x = fmin(fmax(nm[i], lo), hi);
    while (k + 2 < c->n && c->p[k + 1].nm < x) k++;
    const vr_spectro_point *a = &c->p[k], *b = &c->p[k + 1];
    double t = (x - a->nm) / (b->nm - a->nm);
    out->p[i] = (vr_spectro_point){.nm = nm[i],
                                   .T = a->T + t * (b->T - a->T),
                                   .Rf = a->Rf + t * (b->Rf - a->Rf),
                                   .Rb = a->Rb + t * (b->Rb - a->Rb)};
  }
  return VR_OK;
}

static void json_array(const double *v, size_t n, size_t stride) {
  printf("[");
  for (size_t i = 0; i < n; i++) {
    if (i) printf(", ");
    vr_json_number(stdout, v[i * stride]);
  }
  printf("]");
}

static void print_btdf_json(const vr_btdf_table *t, const char *item, const vr_frosted_fit *ff,
                            size_t ns) {
  static const char *const Q[VR_BT_COUNT] = {"Ts", "Tp", "Rfs", "Rfp", "Rbs", "Rbp"};
  printf("{\"source\": ");
  vr_json_string(stdout, item);
  printf(", \"method\": ");
  vr_json_string(stdout, t->method);
  printf(", \"thickness_mm\": ");
  vr_json_number(stdout, t->thickness_nm > 0 ? t->thickness_nm * 1e-6 : NAN);
  printf(", \"angles_deg\": ");
  json_array(t->angles, t->na, 1);
  printf(", \"wavelengths_nm\": ");
  json_array(t->nm, t->nl, 1);
  for (int q = 0; q < VR_BT_COUNT; q++) {
    printf(", \"%s\": [", Q[q]);
    for (size_t i = 0; i < t->na; i++) {
      if (i) printf(", ");
      json_array(t->q[q] + i * t->nl, t->nl, 1);
    }
    printf("]");
  }
  if (ff) {
    printf(", \"frosted\": {\"samples\": %zu, \"alpha\": ", ns);
    vr_json_number(stdout, ff->alpha);
    printf(", \"alpha_err\": ");
    vr_json_number(stdout, ff->alpha_err);
    printf(", \"scale\": ");
    vr_json_number(stdout, ff->scale);
    printf(", \"rms_rel\": ");
    vr_json_number(stdout, ff->rms_rel);
    printf("}");
  }
  printf(", \"table_columns\": \"each quantity is [angle][wavelength]\"}\n");
}

static void print_btdf(const vr_btdf_table *t) {
  size_t j = 0;
  for (size_t k = 1; k < t->nl; k++)
    if (fabs(t->nm[k] - 550) < fabs(t->nm[j] - 550)) j = k;
  printf("# %s\n# at %g nm:\nangle  Ts       Tp       T        Rf       Rb\n", t->method, t->nm[j]);
  for (size_t i = 0; i < t->na; i++) {
    const size_t at = i * t->nl + j;
    printf("%5g  %.6f %.6f %.6f %.6f %.6f\n", t->angles[i], t->q[VR_BT_TS][at], t->q[VR_BT_TP][at],
           0.5 * (t->q[VR_BT_TS][at] + t->q[VR_BT_TP][at]),
           0.5 * (t->q[VR_BT_RFS][at] + t->q[VR_BT_RFP][at]),
           0.5 * (t->q[VR_BT_RBS][at] + t->q[VR_BT_RBP][at]));
  }
}

int spectro_cmd_btdf(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_sample_model *model = NULL;
  vr_spectro_data *d = NULL;
  vr_material *src = NULL, *out = NULL;
  vr_btdf_table t = {0};
  vr_btdf_sample *samples = NULL;
  vr_spectro_curve grid = {0};
  double *nm = NULL, angles[64], d_nm;
  size_t na = 0, nl = 0, ns = 0;
  vr_angular_route route;
  int rc = 1;
  const char *stack = vr_args_get(a, "stack"), *ang = vr_args_get(a, "angles"),
             *save = vr_args_get(a, "save"), *scatter = vr_args_get(a, "scatter");
  const char *item = a->noperands >= 2 ? a->operands[1] : NULL;
  if (spectro_parse_route(a, &route, &err) || spectro_thickness(a, &d_nm, &err)) goto out;
  if (ang) {
    if (vr_parse_doubles(ang, angles, 64, &na)) {
      vr_error_set(&err, VR_E_ARG, "--angles '%s': expected up to 64 numbers, e.g. 0,30,60", ang);
      goto out;
    }
  } else {
    for (int i = 0; i <= 80; i += 10) angles[na++] = i;
    angles[na++] = 85;
    angles[na++] = 90;
  }
  if (stack) {
    if (spectro_db(a, &db, &err) || vr_model_read(stack, db, &model, &err) ||
        spectro_wavelengths(a, &nm, &nl, &err) || vr_btdf_from_model(model, angles, na, nm, nl, &t, &err))
      goto out;
    item = stack;
  } else if (!item) {
    vr_error_set(&err, VR_E_ARG, "btdf needs a pane: FILE, NAME or --stack FILE.model");
    goto out;
  } else {
    FILE *f = fopen(item, "rb");
    if (f) {
      fclose(f);
      const vr_spectro_curve *c;
      vr_standard *std = NULL;
      if (spectro_pane_source(a, item, &db, &d, &err) || spectro_normal_curve(d, item, &c, &err) ||
          vr_standard_open("nfrc", &std, &err))
        goto out;
      double sol = solar_T(std, c);
      vr_standard_destroy(std);
      if (vr_args_get(a, "wavelengths")) {
        if (spectro_wavelengths(a, &nm, &nl, &err) || resample_curve(c, nm, nl, item, &grid, &err)) goto out;
        c = &grid;
      }
      if (vr_btdf_from_curve(c, d->thickness_nm, route, sol, angles, na, &t, &err)) goto out;
    } else {
      if (spectro_db(a, &db, &err) || vr_matdb_load(db, item, 0, &src, &err)) goto out;
      if (src->kind == VR_KIND_GLAZING) {
        const vr_spectro_curve *c;
        vr_standard *std = NULL;
        if (vr_spectro_from_material(src, &d, &err) || vr_standard_open("nfrc", &std, &err)) goto out;
        if (!isnan(d_nm)) d->thickness_nm = d_nm;
        c = &d->curves[0];
        double sol = solar_T(std, c);
        vr_standard_destroy(std);
        if (vr_args_get(a, "wavelengths")) {
          if (spectro_wavelengths(a, &nm, &nl, &err) || resample_curve(c, nm, nl, item, &grid, &err))
            goto out;
          c = &grid;
        }
        if (vr_btdf_from_curve(c, d->thickness_nm, route, sol, angles, na, &t, &err)) goto out;
      } else {
        const vr_property *th = vr_material_property(src, "thickness");
        if (isnan(d_nm) && th && th->value > 0) d_nm = th->value * 1e6;
        if (spectro_wavelengths(a, &nm, &nl, &err) ||
            vr_btdf_from_material(src, d_nm, angles, na, nm, nl, &t, &err))
          goto out;
      }
    }
  }
  bool json = vr_args_flag(a, "json");
  if (!json) print_btdf(&t);
  vr_frosted_fit ff = {0};
  if (scatter) {
    double index;
    if (vr_args_double(a, "index", 1.52, &index, &err) ||
        vr_btdf_samples_read(scatter, &samples, &ns, &err) ||
        vr_frosted_fit_alpha(samples, ns, index, 0.02, &ff, &err))
      goto out;
    if (!json)
      printf("frosted face (GGX, %zu samples, n = %g): alpha = %.4f +- %.4f, scale %.3f +- %.3f, "
             "relative RMS %.3f\n", ns, index, ff.alpha, ff.alpha_err, ff.scale, ff.scale_err,
             ff.rms_rel);
  }
  if (json) print_btdf_json(&t, item, scatter ? &ff : NULL, ns);
  if (vr_args_get(a, "table") && write_btdf_table(vr_args_get(a, "table"), &t, &err)) goto out;
  if (save) {
    if (spectro_db(a, &db, &err) || vr_btdf_table_material(&t, save, &out, &err)) goto out;
    if (scatter && vr_material_add_parameter(out, "roughness_alpha", ff.alpha, ff.alpha_err, NULL, &err))
      goto out;
    if (spectro_save(db, out, "btdf", item, &err)) goto out;
  }
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  free(samples);
  free(nm);
  free(grid.p);
  vr_btdf_table_free(&t);
  vr_material_destroy(src);
  vr_material_destroy(out);
  vr_spectro_destroy(d);
  vr_model_destroy(model);
  vr_matdb_close(db);
  return rc;
}
