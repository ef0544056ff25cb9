/* vr-spectro thermal: U-factor and SHGC of a glazing by ISO 15099 under the
 * NFRC 100/200 environments (vr/glazing_thermal.h), from measured panes;
 * with --method en673, EN 673's U and EN 410's g (spectro_cmd_en673.c). */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/gas.h"
#include "vr/glazing_layers.h"
#include "vr/glazing_thermal.h"
#include "vr/json.h"

/* Normal emissivity below which an unlabelled face is taken as coated:
 * uncoated soda-lime float glass has 0.89 (EN 12898 annex), so a face well
 * under it carries a low-emissivity coating. */
#define COATED_BELOW 0.84

typedef struct pane_info {
  const char *emis_from[2];
  bool from_ir[2], coated[2]; /* an emissivity from the pane's IR data, and of a coated face */
  bool given[2];              /* an emissivity given by --emissivity */
  bool conductivity_assumed;
} pane_info;

/* "12.7:air,16:argon:0.9+air:0.1": one gap (thickness in mm, gas) between
 * each pair of panes. */
static vr_status parse_gaps(const char *s, vr_thermal_system *sys, size_t npanes, vr_error *err) {
  size_t k = 0;
  const char *p = s ? s : "";
  while (*p) {
    if (k + 1 >= npanes)
      return vr_error_set(err, VR_E_ARG, "--gaps '%s': more gaps than the %zu pane(s) leave room "
                                         "for (%zu)", s, npanes, npanes - 1);
    char *end;
    double mm = strtod(p, &end);
    if (end == p || *end != ':' || !(mm > 0 && mm <= 200))
      return vr_error_set(err, VR_E_ARG, "--gaps '%s': gap %zu: expected THICKNESS_MM:GAS with a "
                                         "thickness in (0, 200] mm", s, k + 1);
    const char *g = end + 1, *comma = strchr(g, ',');
    size_t len = comma ? (size_t)(comma - g) : strlen(g);
    char gas[128];
    if (len >= sizeof gas) len = sizeof gas - 1;
    memcpy(gas, g, len);
    gas[len] = '\0';
    vr_status st = vr_gas_parse(gas, &sys->gap[k].gas, err);
    if (st) {
      vr_error_prefix(err, "--gaps: gap %zu: ", k + 1);
      return st;
    }
    sys->gap[k].thickness_m = mm * 1e-3;
    sys->gap[k].pressure_pa = 101325;
    k++;
    p = comma ? comma + 1 : g + len;
  }
  if (k + 1 != npanes)
    return vr_error_set(err, VR_E_ARG, "%zu panes need %zu gap(s) (--gaps MM:GAS,...); %zu given",
                        npanes, npanes - 1, k);
  return VR_OK;
}

/* --emissivity "0.84,0.84:0.15,-": each pane's hemispherical emissivity,
 * F (both faces) or F:B; "-" or an empty item keeps the pane's own.  NAN
 * where none is given. */
static vr_status parse_emissivity(const char *s, size_t npanes, double (*e)[2], vr_error *err) {
  for (size_t i = 0; i < npanes; i++) e[i][0] = e[i][1] = NAN;
  if (!s) return VR_OK;
  const char *p = s;
  for (size_t i = 0;; i++) {
    if (i == npanes)
      return vr_error_set(err, VR_E_RANGE, "--emissivity '%s': more items than the %zu pane(s)", s,
                          npanes);
    while (*p == ' ') p++;
    if (*p == '-' && (p[1] == ',' || !p[1])) {
      p++;
    } else if (*p != ',' && *p) {
      for (int f = 0; f < 2; f++) {
        char *end;
        double v = strtod(p, &end);
        if (end == p || !(v >= 0 && v <= 1))
          return vr_error_set(err, VR_E_RANGE, "--emissivity '%s': pane %zu: expected F or F:B, "
                                               "each in [0, 1]", s, i + 1);
        e[i][f] = v;
        p = end;
        if (f == 0 && *p != ':') {
          e[i][1] = v;
          break;
        }
        if (f == 0) p++;
      }
    }
    if (!*p) return VR_OK;
    if (*p != ',')
      return vr_error_set(err, VR_E_RANGE, "--emissivity '%s': pane %zu: expected ',' after it", s,
                          i + 1);
    p++;
  }
}

/* A pane's thermal data: thickness, conductivity, hemispherical emissivity
 * of each face (from its thermal-infrared data when they reach the
 * standard's THERMAL IR range, else as its file states). */
static vr_status pane_thermal(const vr_standard *std, const vr_spectro_data *d, const vr_pane *p,
                              const char *item, const double given[2], vr_thermal_pane *tp,
                              pane_info *info, vr_error *err) {
  if (!isfinite(d->thickness_nm))
    return vr_error_set(err, VR_E_NOT_FOUND, "%s: no thickness (a '# thickness: 3 mm' line, the "
                                             "file's header or --thickness)", item);
  tp->thickness_m = d->thickness_nm * 1e-9;
  tp->conductivity = d->thermal.conductivity;
  info->conductivity_assumed = !isfinite(tp->conductivity);
  if (info->conductivity_assumed) tp->conductivity = 1.0; /* soda-lime glass, EN 572-1 */
  tp->tir = isfinite(d->thermal.tir) ? d->thermal.tir : 0.0;
  if (isfinite(given[0])) {
    for (int f = 0; f < 2; f++) {
      tp->emis[f] = given[f];
      info->emis_from[f] = "--emissivity";
      info->given[f] = true;
    }
    return VR_OK;
  }
  double en[2];
  vr_error e2 = {0};
  if (!vr_pane_emissivity(std, p, en, &tp->tir, &e2)) {
    for (int f = 0; f < 2; f++) {
      vr_coated_side cs = d->thermal.coated;
      bool coated = cs == VR_COATED_BOTH || (f == 0 && cs == VR_COATED_FRONT) ||
                    (f == 1 && cs == VR_COATED_BACK);
      if (cs == VR_COATED_UNKNOWN) coated = en[f] < COATED_BELOW;
      tp->emis[f] = vr_emissivity_hemispherical(en[f], coated);
      info->from_ir[f] = true;
      info->coated[f] = coated;
      info->emis_from[f] = cs == VR_COATED_UNKNOWN
                               ? (coated ? "IR data, NFRC 301 coated (normal emissivity < 0.84)"
                                         : "IR data, NFRC 301 uncoated")
                               : (coated ? "IR data, NFRC 301 coated" : "IR data, NFRC 301 uncoated");
    }
    return VR_OK;
  }
  if (e2.status != VR_E_RANGE) {
    *err = e2;
    return e2.status;
  }
  if (!isfinite(d->thermal.emissivity[0]))
    return vr_error_set(err, VR_E_NOT_FOUND,
                        "%s: no emissivity: its data do not reach the thermal infrared (%s) and the "
                        "file gives none (a '# emissivity: 0.84 0.84' line, front and back, an "
                        "Optics '{ Emissivity, front back }' header, or --emissivity)", item,
                        e2.message);
  for (int f = 0; f < 2; f++) {
    tp->emis[f] = d->thermal.emissivity[f];
    info->emis_from[f] = "the file's header";
  }
  return VR_OK;
}

/* EN 673 wants corrected emissivities (EN 12898): an uncoated face (by
 * its IR data, or a header value of uncoated glass, 0.84 or more) takes
 * the standard's 0.837 for soda-lime glass; a coated one from IR data
 * keeps its NFRC 301 hemispherical value, said so; a coated header value
 * or one given by --emissivity is taken as the corrected one. */
static void en673_emissivities(vr_thermal_pane *tp, pane_info *info) {
  for (int f = 0; f < 2; f++) {
    if (!info->from_ir[f]) {
      if (!info->given[f] && tp->emis[f] >= COATED_BELOW) {
        tp->emis[f] = VR_EN673_UNCOATED;
        info->emis_from[f] = "the file's header: uncoated, EN 673's 0.837";
      }
      continue;
    }
    if (!info->coated[f]) {
      tp->emis[f] = VR_EN673_UNCOATED;
      info->emis_from[f] = "IR data: uncoated, EN 673's 0.837";
    } else {
      info->emis_from[f] = "IR data, NFRC 301 hemispherical; EN 12898's corrected value may "
                           "differ (--emissivity)";
    }
  }
}

static void print_state(const char *name, const vr_thermal_state *s, size_t n, bool json) {
  if (json) {
    printf("\"%s\": {\"q_in\": %.10g, \"h_in\": %.10g, \"h_out\": %.10g, \"iterations\": %d, "
           "\"T\": [", name, s->q_in, s->h_in, s->h_out, s->iterations);
    for (size_t i = 0; i < 2 * n; i++) printf("%s%.10g", i ? ", " : "", s->T[i]);
    printf("], \"gap_h\": [");
    for (size_t i = 0; i + 1 < n; i++) printf("%s%.10g", i ? ", " : "", s->gap_h[i]);
    printf("], \"gap_Ra\": [");
    for (size_t i = 0; i + 1 < n; i++) printf("%s%.10g", i ? ", " : "", s->gap_Ra[i]);
    printf("]}");
    return;
  }
  printf("%-7s faces (C):", name);
  for (size_t i = 0; i < 2 * n; i++) printf(" %.2f", s->T[i] - 273.15);
  printf("   h_out %.2f  h_in %.2f W/(m2 K)", s->h_out, s->h_in);
  for (size_t i = 0; i + 1 < n; i++) printf("  gap %zu h %.3f (Ra %.0f)", i + 1, s->gap_h[i], s->gap_Ra[i]);
  printf("\n");
}

int spectro_cmd_thermal(vr_args *a) {
  vr_error err = {0};
  vr_matdb *db = NULL;
  vr_standard *std = NULL;
  char *list = NULL, *items[SPECTRO_MAX_PANES];
  size_t n = 0;
  vr_spectro_data *data[SPECTRO_MAX_PANES] = {0};
  vr_pane *panes[SPECTRO_MAX_PANES] = {0}, *sys_optics = NULL;
  pane_info info[SPECTRO_MAX_PANES] = {0};
  vr_thermal_system sys = {0};
  int rc = 1;
  const char *stdname = vr_args_get(a, "standard"), *method = vr_args_get(a, "method");
  bool json = vr_args_flag(a, "json");
  vr_standard *emis_std = NULL; /* EN 673: the emissivities from IR data by NFRC's THERMAL IR */
  vr_en673_edition edition = VR_EN673_2011;
  bool en673 = method && !strcmp(method, "en673");
  if (method && !en673 && strcmp(method, "iso15099")) {
    vr_error_set(&err, VR_E_RANGE, "--method '%s': expected iso15099 (the heat balance under NFRC "
                                   "100/200, the default) or en673 (EN 673's U, EN 410's g)",
                 method);
    goto out;
  }
  if (vr_args_get(a, "edition") && !en673) {
    vr_error_set(&err, VR_E_RANGE, "--edition: only with --method en673");
    goto out;
  }
  if (en673 && (spectro_en673_parse_edition(vr_args_get(a, "edition"), &edition, &err))) goto out;
  if (en673 && vr_args_get(a, "height")) {
    vr_error_set(&err, VR_E_RANGE, "--height: EN 673's declared U has no height (its Nusselt "
                                   "correlation is the gap's alone); drop it or use --method "
                                   "iso15099");
    goto out;
  }
  if (vr_args_double(a, "height", 1.0, &sys.height_m, &err) ||
      vr_args_double(a, "tilt", 90.0, &sys.tilt_deg, &err))
    goto out;
  if (!(sys.height_m > 0 && sys.height_m <= 100)) {
    vr_error_set(&err, VR_E_RANGE, "--height %g: expected a glazing height in (0, 100] m",
                 sys.height_m);
    goto out;
  }
  if (en673 && sys.tilt_deg != 90.0) {
    vr_error_set(&err, VR_E_RANGE, "--tilt %g: EN 673's declared U is for vertical glazing (90)",
                 sys.tilt_deg);
    goto out;
  }
  if (!(sys.tilt_deg >= 0 && sys.tilt_deg <= 180)) {
    vr_error_set(&err, VR_E_RANGE, "--tilt %g: expected 0 to 180 degrees (90: vertical)",
                 sys.tilt_deg);
    goto out;
  }
  if (vr_standard_open(stdname ? stdname : en673 ? "en410" : "nfrc", &std, &err)) goto out;
  if (en673 && vr_standard_open("nfrc", &emis_std, &err)) goto out;
  if (spectro_pane_items(a, &list, items, &n, &err)) goto out;
  if (n > VR_THERMAL_MAX_PANES) {
    vr_error_set(&err, VR_E_ARG, "%zu panes: the heat balance takes at most %d", n,
                 VR_THERMAL_MAX_PANES);
    goto out;
  }
  sys.n = n;
  double given[SPECTRO_MAX_PANES][2];
  if (parse_gaps(vr_args_get(a, "gaps"), &sys, n, &err) ||
      parse_emissivity(vr_args_get(a, "emissivity"), n, given, &err))
    goto out;
  for (size_t i = 0; i < n; i++) {
    if (spectro_pane_source(a, items[i], &db, &data[i], &err)) goto out;
    const vr_spectro_curve *c = NULL;
    if (spectro_normal_curve(data[i], items[i], &c, &err)) goto out;
    if (vr_pane_from_curve(c, data[i]->thickness_nm, 0, VR_ROUTE_AUTO, NAN, &panes[i], NULL, &err)) {
      vr_error_prefix(&err, "%s: ", items[i]);
      goto out;
    }
    if (pane_thermal(en673 ? emis_std : std, data[i], panes[i], items[i], given[i], &sys.pane[i],
                     &info[i], &err))
      goto out;
    if (en673) en673_emissivities(&sys.pane[i], &info[i]);
  }
  double A[SPECTRO_MAX_PANES];
  vr_glazing_metrics m;
  if (vr_pane_combine(panes, n, &sys_optics, &err) ||
      vr_glazing_metrics_compute(std, sys_optics, &m, &err) ||
      vr_glazing_layer_absorptance(std, "SOLAR", panes, n, false, A, &err))
    goto out;
  for (size_t i = 0; i < n; i++) sys.pane[i].absorptance = A[i];
  if (en673) {
    const char *from[SPECTRO_MAX_PANES][2];
    for (size_t i = 0; i < n; i++) from[i][0] = info[i].emis_from[0], from[i][1] = info[i].emis_from[1];
    if (spectro_en673_report(&sys, items, (const char *const(*)[2])from, std->name, m.Tsol, edition,
                             json, &err))
      goto out;
    rc = 0;
    goto out;
  }
  vr_thermal_figures f;
  if (vr_thermal_nfrc(&sys, m.Tsol, &f, &err)) goto out;
  if (json) {
    printf("{\"method\": \"ISO 15099 centre of glass, NFRC 100/200\", \"standard\": ");
    vr_json_string(stdout, std->name);
    printf(", \"U\": %.12g, \"SHGC\": %.12g, \"Tsol\": %.12g, \"height_m\": %g, \"tilt_deg\": %g, "
           "\"panes\": [", f.U, f.SHGC, m.Tsol, sys.height_m, sys.tilt_deg);
    for (size_t i = 0; i < n; i++) {
      printf("%s{\"source\": ", i ? ", " : "");
      vr_json_string(stdout, items[i]);
      printf(", \"thickness_mm\": %.10g, \"conductivity\": %.10g, "
             "\"emissivity\": [%.12g, %.12g], \"emissivity_from\": [\"%s\", \"%s\"], "
             "\"ir_transmittance\": %.12g, \"solar_absorptance\": %.12g}",
             sys.pane[i].thickness_m * 1e3, sys.pane[i].conductivity, sys.pane[i].emis[0],
             sys.pane[i].emis[1], info[i].emis_from[0], info[i].emis_from[1], sys.pane[i].tir, A[i]);
    }
    printf("], \"gaps\": [");
    for (size_t i = 0; i + 1 < n; i++) {
      printf("%s{\"thickness_mm\": %.10g, \"gas\": \"", i ? ", " : "", sys.gap[i].thickness_m * 1e3);
      for (size_t g = 0; g < sys.gap[i].gas.n; g++)
        printf("%s%s:%g", g ? "+" : "", vr_gas_name(sys.gap[i].gas.id[g]), sys.gap[i].gas.frac[g]);
      printf("\"}");
    }
    printf("], ");
    print_state("winter", &f.winter, n, true);
    printf(", ");
    print_state("summer", &f.summer, n, true);
    printf("}\n");
  } else {
    printf("ISO 15099 centre of glass, NFRC 100 (U) / 200 (SHGC); optics under %s; height %g m, "
           "tilt %g deg\n", std->name, sys.height_m, sys.tilt_deg);
    static const char *const TINT[] = {"state", "charge", "uv"};
    for (int t = 0; t < 3; t++)
      if (vr_args_get(a, TINT[t]))
        printf("chromogenic panes at --%s %s\n", TINT[t], vr_args_get(a, TINT[t]));
    for (size_t i = 0; i < n; i++) {
      printf("pane %zu  %s: %.3f mm, k %.3g W/(m K)%s, emissivity %.4f (%s) / %.4f (%s), solar "
             "absorptance %.4f\n", i + 1, items[i], sys.pane[i].thickness_m * 1e3,
             sys.pane[i].conductivity, info[i].conductivity_assumed ? " (assumed: glass)" : "",
             sys.pane[i].emis[0], info[i].emis_from[0], sys.pane[i].emis[1], info[i].emis_from[1],
             A[i]);
      if (i + 1 < n) {
        printf("gap  %zu  %.2f mm ", i + 1, sys.gap[i].thickness_m * 1e3);
        for (size_t g = 0; g < sys.gap[i].gas.n; g++)
          printf("%s%s %.0f%%", g ? " + " : "", vr_gas_name(sys.gap[i].gas.id[g]),
                 100 * sys.gap[i].gas.frac[g]);
        printf("\n");
      }
    }
    printf("U-factor  %.4f W/(m2 K)\nSHGC      %.4f   (Tsol %.4f)\n", f.U, f.SHGC, m.Tsol);
    print_state("winter", &f.winter, n, false);
    print_state("summer", &f.summer, n, false);
  }
  rc = 0;
out:
  if (rc) rc = spectro_fail(&err);
  for (size_t i = 0; i < n; i++) {
    vr_spectro_destroy(data[i]);
    vr_pane_destroy(panes[i]);
  }
  vr_pane_destroy(sys_optics);
  vr_standard_destroy(std);
  vr_standard_destroy(emis_std);
  vr_matdb_close(db);
  free(list);
  return rc;
}
