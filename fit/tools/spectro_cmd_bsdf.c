/* vr-spectro and BSDF XML: metrics of a WINDOW / IGSDB / genBSDF file, and
 * bsdf-xml, a pane (or several) written as a Klems BSDF XML file. */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/bsdf_xml.h"
#include "vr/btdf_table.h"
#include "vr/json.h"

bool spectro_is_bsdf_xml(const char *path) {
  size_t n = strlen(path);
  return (n > 4 && !strcasecmp(path + n - 4, ".xml")) ||
         (n > 7 && !strcasecmp(path + n - 7, ".xml.gz"));
}

/* Options metrics takes for a pane but not for a BSDF XML file. */
static vr_status refuse_pane_options(const vr_args *a, vr_error *err) {
  static const char *PANE_ONLY[] = {"standard", "panes",  "route",       "thickness",  "state",
                                    "charge",   "uv",     "temperature", "extrapolate"};
  for (size_t i = 0; i < sizeof PANE_ONLY / sizeof PANE_ONLY[0]; i++)
    if (vr_args_get(a, PANE_ONLY[i]))
      return vr_error_set(err, VR_E_RANGE,
                          "--%s: not for a BSDF XML file (its bands are integrated already: "
                          "the file's Visible and Solar matrices are used as they are)",
                          PANE_ONLY[i]);
  return VR_OK;
}

static void print_figures_json(const vr_klems_figures *f) {
  printf("{\"direct_direct\": ");
  vr_json_number(stdout, f->direct_direct);
  printf(", \"direct_diffuse\": ");
  vr_json_number(stdout, f->direct_diffuse);
  printf(", \"direct_hemispherical\": ");
  vr_json_number(stdout, f->direct_hemispherical);
  printf(", \"diffuse_diffuse\": ");
  vr_json_number(stdout, f->diffuse_diffuse);
  printf("}");
}

int spectro_metrics_bsdf_xml(vr_args *a, const char *path) {
  vr_error err = {0};
  vr_bsdf_xml *x = NULL;
  double theta, phi;
  int rc = 1;
  if (refuse_pane_options(a, &err) || vr_args_double(a, "angle", 0, &theta, &err) ||
      vr_args_double(a, "phi", 0, &phi, &err))
    goto out;
  if (!(theta >= 0 && theta <= 90)) {
    vr_error_set(&err, VR_E_ARG, "--angle %g: expected 0 to 90 degrees", theta);
    goto out;
  }
  if (!isfinite(phi)) {
    vr_error_set(&err, VR_E_ARG, "--phi %g: expected an azimuth in degrees", phi);
    goto out;
  }
  if (vr_bsdf_xml_read(path, &x, &err)) goto out;
  int in = vr_klems_patch(&x->basis, theta, phi);
  double tc, pc;
  vr_klems_direction(&x->basis, in, &tc, &pc);
  bool json = vr_args_flag(a, "json");
  if (json) {
    printf("{\"file\": ");
    vr_json_string(stdout, path);
    printf(", \"name\": ");
    vr_json_string(stdout, x->name);
    printf(", \"manufacturer\": ");
    vr_json_string(stdout, x->manufacturer);
    printf(", \"device_type\": ");
    vr_json_string(stdout, x->device_type);
    printf(", \"basis\": ");
    vr_json_string(stdout, x->basis.name);
    printf(", \"patches\": %d, \"theta_deg\": ", x->basis.n);
    vr_json_number(stdout, theta);
    printf(", \"phi_deg\": ");
    vr_json_number(stdout, phi);
    printf(", \"patch\": %d, \"patch_theta_deg\": ", in + 1);
    vr_json_number(stdout, tc);
    printf(", \"patch_phi_deg\": ");
    vr_json_number(stdout, pc);
    printf(", \"bands\": [");
  } else {
    printf("# BSDF XML %s: %s%s%s%s%s\n", path, x->name[0] ? x->name : "(no name)",
           x->manufacturer[0] ? ", " : "", x->manufacturer, x->device_type[0] ? "; " : "",
           x->device_type);
    printf("# basis %s, %d patches%s; incident theta %g, phi %g deg: patch %d (theta %g, phi %g)\n",
           x->basis.name, x->basis.n,
           x->tensor_tree == 3   ? " (resampled from the file's TensorTree3)"
           : x->tensor_tree == 4 ? " (resampled from the file's TensorTree4)"
                                 : "",
           theta, phi, in + 1, tc, pc);
    printf("# WINDOW's figures: direct-direct (the incident patch's own), direct-diffuse, "
           "direct-hemispherical, diffuse-diffuse (uniform incidence)\n");
    printf("%-10s %-20s %14s %14s %14s %14s\n", "band", "side", "direct-direct", "direct-diffuse",
           "direct-hemi", "diffuse-diffuse");
  }
  for (size_t b = 0; b < x->nbands; b++) {
    const vr_bsdf_band *band = &x->bands[b];
    if (json) {
      printf("%s{\"band\": ", b ? ", " : "");
      vr_json_string(stdout, band->name);
      printf(", \"nm\": ");
      vr_json_number(stdout, band->nm);
      printf(", \"detector\": ");
      vr_json_string(stdout, band->detector);
    }
    for (int s = 0; s < VR_BSDF_SIDES; s++) {
      if (!band->m[s]) continue;
      vr_klems_figures f;
      vr_klems_figures_of(&x->basis, band->m[s], in, &f);
      if (json) {
        printf(", ");
        vr_json_string(stdout, vr_bsdf_side_name((vr_bsdf_side)s));
        printf(": ");
        print_figures_json(&f);
      } else {
        printf("%-10s %-20s %14.6f %14.6f %14.6f %14.6f\n", band->name,
               vr_bsdf_side_name((vr_bsdf_side)s), f.direct_direct, f.direct_diffuse,
               f.direct_hemispherical, f.diffuse_diffuse);
      }
    }
    if (json) printf("}");
  }
  if (json) printf("]}\n");
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  vr_bsdf_xml_destroy(x);
  return rc;
}

/* Turns the panes round (the back faces the light): their order reversed
 * and each one's Rf and Rb exchanged where Rb was measured.  Twice is the
 * identity. */
static void turn_round(vr_spectro_data **data, char **items, size_t n) {
  for (size_t i = 0; i < n / 2; i++) {
    vr_spectro_data *d = data[i];
    data[i] = data[n - 1 - i], data[n - 1 - i] = d;
    char *t = items[i];
    items[i] = items[n - 1 - i], items[n - 1 - i] = t;
  }
  for (size_t i = 0; i < n; i++) {
    if (!data[i]->has_Rb) continue;
    for (size_t c = 0; c < data[i]->ncurves; c++)
      for (size_t k = 0; k < data[i]->curves[c].n; k++) {
        vr_spectro_point *p = &data[i]->curves[c].p[k];
        double r = p->Rf;
        p->Rf = p->Rb, p->Rb = r;
      }
  }
}

/* Ring r of the basis on the diagonal: entry (i, i) = figure / Lambda_i for
 * each patch i of the ring, fig[band][side]. */
static void set_ring(vr_bsdf_xml *x, const vr_klems_basis *basis, int r,
                     const double fig[2][VR_BSDF_SIDES]) {
  for (int k = 0; k < basis->nphi[r]; k++) {
    int p = basis->first[r] + k;
    double lam = vr_klems_lambda(basis, p);
    for (int b = 0; b < 2; b++)
      for (int s = 0; s < VR_BSDF_SIDES; s++)
        x->bands[b].m[s][(size_t)p * basis->n + p] = fig[b][s] / lam;
  }
}

/* bsdf-xml --stack: a coated pane given as its layer stack, by thin-film
 * optics at each ring's angle (vr_btdf_from_model, s and p), weighted by
 * the standard.  A stack's transmittance is the same from both sides
 * (reciprocity), its reflectances are not. */
static vr_status stack_rings(const vr_args *a, const char *stack, const vr_standard *std,
                             const vr_klems_basis *basis, vr_bsdf_xml *x, vr_error *err) {
  vr_matdb *db = NULL;
  vr_sample_model *model = NULL;
  vr_btdf_table t = {0};
  double *nm = NULL, angles[VR_KLEMS_MAX_RINGS];
  size_t nl = 0;
  for (int r = 0; r < basis->nrings; r++) angles[r] = basis->theta_c[r];
  vr_status st = spectro_db(a, &db, err);
  if (!st) st = vr_model_read(stack, db, &model, err);
  if (!st) st = spectro_wavelengths(a, &nm, &nl, err);
  if (!st) {
    st = vr_btdf_from_model(model, angles, (size_t)basis->nrings, nm, nl, &t, err);
    if (st == VR_E_RANGE && !vr_args_get(a, "wavelengths"))
      vr_error_prefix(err, "%s at the default --wavelengths 300:2500:10 (give them inside every "
                      "layer's data): ", stack);
  }
  for (int r = 0; !st && r < basis->nrings; r++) {
    const size_t o = (size_t)r * t.nl;
    vr_pane p = {.n = t.nl, .nm = t.nm, .coated = true, .has_R = true,
                 .T = {t.q[VR_BT_TS] + o, t.q[VR_BT_TP] + o},
                 .Rf = {t.q[VR_BT_RFS] + o, t.q[VR_BT_RFP] + o},
                 .Rb = {t.q[VR_BT_RBS] + o, t.q[VR_BT_RBP] + o}};
    vr_glazing_metrics m;
    st = vr_glazing_metrics_compute(std, &p, &m, err);
    if (st) {
      vr_error_prefix(err, "%s at --wavelengths %g:%g: ", stack, t.nm[0], t.nm[t.nl - 1]);
      break;
    }
    const double fig[2][VR_BSDF_SIDES] = {{m.Tvis, m.Tvis, m.Rvis_front, m.Rvis_back},
                                          {m.Tsol, m.Tsol, m.Rsol_front, m.Rsol_back}};
    set_ring(x, basis, r, fig);
  }
  if (!st && t.thickness_nm > 0) x->thickness_mm = t.thickness_nm * 1e-6;
  vr_btdf_table_free(&t);
  free(nm);
  vr_model_destroy(model);
  vr_matdb_close(db);
  return st;
}

/* bsdf-xml: the panes' figures at each ring's nominal angle of the Klems
 * full basis, on the diagonal (specular glazing scatters nothing): entry
 * (i, i) = figure / Lambda_i, as WINDOW writes a specular layer. */
int spectro_cmd_bsdf_xml(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_standard *std = NULL;
  vr_bsdf_xml *x = NULL;
  char *list = NULL, *items[SPECTRO_MAX_PANES];
  size_t n = 0, unsolved[SPECTRO_MAX_PANES] = {0};
  vr_spectro_data *data[SPECTRO_MAX_PANES] = {0};
  vr_angular_route route;
  const char *stdname = vr_args_get(a, "standard"), *outp = vr_args_get(a, "out"), *used;
  const char *stack = vr_args_get(a, "stack");
  int rc = 1;
  if (!outp) {
    vr_error_set(&err, VR_E_RANGE, "--out FILE.xml: bsdf-xml needs it");
    goto out;
  }
  if (!spectro_is_bsdf_xml(outp) || strlen(outp) < 5 || strcasecmp(outp + strlen(outp) - 4, ".xml")) {
    vr_error_set(&err, VR_E_RANGE, "--out '%s': expected a name ending in .xml", outp);
    goto out;
  }
  if (stack && (a->noperands > 1 || vr_args_get(a, "panes") || vr_args_get(a, "route") ||
                vr_args_get(a, "thickness") || vr_args_get(a, "state") || vr_args_get(a, "charge") ||
                vr_args_get(a, "uv"))) {
    vr_error_set(&err, VR_E_RANGE, "--stack %s is the pane: give no FILE, NAME, --panes, --route, "
                 "--thickness or state with it (the model holds the layers and the substrate; "
                 "thin-film optics needs no angular route)", stack);
    goto out;
  }
  if (!stack && vr_args_get(a, "wavelengths")) {
    vr_error_set(&err, VR_E_RANGE, "--wavelengths: only with --stack (a measured pane keeps its own "
                 "wavelengths)");
    goto out;
  }
  if (spectro_parse_route(a, &route, &err) || vr_standard_open(stdname ? stdname : "nfrc", &std, &err))
    goto out;
  if (!stack && spectro_pane_items(a, &list, items, &n, &err)) goto out;
  for (size_t i = 0; i < n; i++)
    if (spectro_pane_source(a, items[i], &db, &data[i], &err)) goto out;
  vr_klems_basis basis;
  vr_klems_full(&basis);
  if (vr_bsdf_xml_create(&basis, 2, &x, &err)) goto out;
  snprintf(x->bands[0].name, sizeof x->bands[0].name, "Visible");
  snprintf(x->bands[0].detector, sizeof x->bands[0].detector, "ASTM E308 1931 Y.dsp");
  snprintf(x->bands[1].name, sizeof x->bands[1].name, "Solar");
  snprintf(x->bands[1].detector, sizeof x->bands[1].detector, "None");
  if (stack) {
    const char *slash = strrchr(stack, '/');
    snprintf(x->name, sizeof x->name, "%s", slash ? slash + 1 : stack);
    snprintf(x->manufacturer, sizeof x->manufacturer, "vr-spectro (%s, thin-film stack)", std->name);
    snprintf(x->device_type, sizeof x->device_type, "Other");
    if (stack_rings(a, stack, std, &basis, x, &err)) goto out;
  } else {
    size_t len = 0;
    for (size_t i = 0; i < n; i++) {
      const char *slash = strrchr(items[i], '/');
      if (len >= sizeof x->name - 1) break; /* the name is full */
      len += (size_t)snprintf(x->name + len, sizeof x->name - len, "%s%s", i ? " | " : "",
                              slash ? slash + 1 : items[i]);
    }
    snprintf(x->manufacturer, sizeof x->manufacturer, "vr-spectro (%s)", std->name);
    snprintf(x->device_type, sizeof x->device_type, "Other");
    double th = 0;
    for (size_t i = 0; i < n; i++) th += data[i]->thickness_nm;
    if (n == 1 && th > 0) x->thickness_mm = th * 1e-6;
  }
  for (int r = 0; !stack && r < basis.nrings; r++) {
    /* Front figures, then the back's transmittance with the panes turned
     * round: at an angle the physical route solves each side from its own
     * reflectance, so T seen from the back differs slightly (as in WINDOW). */
    vr_glazing_metrics m, back;
    if (spectro_panes_metrics(std, data, items, n, basis.theta_c[r], route, &m, &used, unsolved, &err))
      goto out;
    size_t turned[SPECTRO_MAX_PANES] = {0};
    turn_round(data, items, n);
    vr_status st = spectro_panes_metrics(std, data, items, n, basis.theta_c[r], route, &back, &used,
                                         turned, &err);
    turn_round(data, items, n);
    if (st) goto out;
    for (size_t i = 0; i < n; i++) unsolved[n - 1 - i] += turned[i];
    if (!m.has_R) {
      vr_error_set(&err, VR_E_ARG, "%s: a BSDF needs reflectance; the pane has T only",
                   n == 1 ? items[0] : "the panes");
      goto out;
    }
    const double fig[2][VR_BSDF_SIDES] = {{m.Tvis, back.Tvis, m.Rvis_front, m.Rvis_back},
                                          {m.Tsol, back.Tsol, m.Rsol_front, m.Rsol_back}};
    set_ring(x, &basis, r, fig);
  }
  for (size_t i = 0; i < n; i++)
    if (unsolved[i])
      fprintf(stderr, "vr-spectro: %s: %zu wavelength(s) over the %d angles and two sides fit no "
                      "slab; their index was borrowed from neighbours\n", items[i], unsolved[i],
              basis.nrings);
  if (vr_bsdf_xml_write(outp, x, &err)) goto out;
  fprintf(stderr, "vr-spectro: wrote %s (Klems full basis, Visible and Solar, %s)\n", outp, std->name);
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  for (size_t i = 0; i < n; i++) vr_spectro_destroy(data[i]);
  vr_bsdf_xml_destroy(x);
  vr_standard_destroy(std);
  vr_matdb_close(db);
  free(list);
  return rc;
}
