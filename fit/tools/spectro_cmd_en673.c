/* vr-spectro thermal --method en673: EN 673's U and EN 410's g of a
 * glazing (vr/glazing_en673.h), from the panes the thermal command read. */
#include "spectro_cli.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vr/glazing_en673.h"
#include "vr/json.h"

vr_status spectro_en673_parse_edition(const char *s, vr_en673_edition *e, vr_error *err) {
  if (!s || !strcmp(s, "2011")) *e = VR_EN673_2011;
  else if (!strcmp(s, "1997")) *e = VR_EN673_1997;
  else
    return vr_error_set(err, VR_E_RANGE, "--edition '%s': expected 2011 (EN 673:2011, EN "
                                         "410:2011) or 1997 (EN 673:1997, EN 410:1998)", s);
  return VR_OK;
}

vr_status spectro_en673_report(const vr_thermal_system *sys, char **items, const char *const (*from)[2],
                         const char *std_name, double tau_e, vr_en673_edition edition, bool json,
                         vr_error *err) {
  size_t n = sys->n;
  vr_en673_system s = {.n = n, .edition = edition};
  for (size_t i = 0; i < n; i++) {
    const vr_thermal_pane *p = &sys->pane[i];
    if (p->tir > 0)
      return vr_error_set(err, VR_E_ARG, "%s: thermal-infrared transmittance %g: EN 673 holds "
                                         "for panes opaque in the far infrared only", items[i],
                          p->tir);
    s.pane[i] = (vr_en673_pane){p->thickness_m, p->conductivity, {p->emis[0], p->emis[1]},
                                p->absorptance};
    if (i + 1 < n) {
      s.gap_m[i] = sys->gap[i].thickness_m;
      s.gas[i] = sys->gap[i].gas;
    }
  }
  vr_en673_result r;
  vr_status st = vr_en673_u(&s, &r, err);
  if (st) return st;
  double a[VR_EN673_MAX_PANES];
  for (size_t i = 0; i < n; i++) a[i] = s.pane[i].absorptance;
  double qi = vr_en410_qi(n, a, r.he, r.hi, r.Lambda), g = tau_e + qi;
  const char *ed = edition == VR_EN673_1997 ? "EN 673:1997 / EN 410:1998" : "EN 673:2011 / EN 410:2011";
  if (json) {
    printf("{\"method\": \"%s\", \"standard\": ", ed);
    vr_json_string(stdout, std_name);
    printf(", \"U\": %.12g, \"U_declared\": %.1f, \"g\": %.12g, \"tau_e\": %.12g, \"q_i\": %.12g, "
           "\"he\": %.12g, \"hi\": %.12g, \"panes\": [",
           r.U, r.U_declared, g, tau_e, qi, r.he, r.hi);
    for (size_t i = 0; i < n; i++) {
      printf("%s{\"source\": ", i ? ", " : "");
      vr_json_string(stdout, items[i]);
      printf(", \"thickness_mm\": %.10g, \"conductivity\": %.10g, \"emissivity\": [%.12g, %.12g], "
             "\"emissivity_from\": [\"%s\", \"%s\"], \"solar_absorptance\": %.12g}",
             s.pane[i].thickness_m * 1e3, s.pane[i].conductivity, s.pane[i].emis[0],
             s.pane[i].emis[1], from[i][0], from[i][1], a[i]);
    }
    printf("], \"gaps\": [");
    for (size_t k = 0; k + 1 < n; k++)
      printf("%s{\"thickness_mm\": %.10g, \"hs\": %.12g, \"hr\": %.12g, \"hg\": %.12g, "
             "\"Nu\": %.12g, \"dT\": %.12g, \"Lambda\": %.12g}",
             k ? ", " : "", s.gap_m[k] * 1e3, r.hs[k], r.hr[k], r.hg[k], r.Nu[k], r.dT[k],
             r.Lambda[k]);
    printf("]}\n");
    return VR_OK;
  }
  printf("%s centre of glass, vertical; optics under %s\n", ed, std_name);
  for (size_t i = 0; i < n; i++) {
    printf("pane %zu  %s: %.3f mm, k %.3g W/(m K), corrected emissivity %.4f (%s) / %.4f (%s), "
           "solar absorptance %.4f\n", i + 1, items[i], s.pane[i].thickness_m * 1e3,
           s.pane[i].conductivity, s.pane[i].emis[0], from[i][0], s.pane[i].emis[1], from[i][1],
           a[i]);
    if (i + 1 < n) {
      printf("gap  %zu  %.2f mm ", i + 1, s.gap_m[i] * 1e3);
      for (size_t k = 0; k < s.gas[i].n; k++)
        printf("%s%s %.0f%%", k ? " + " : "", vr_gas_name(s.gas[i].id[k]), 100 * s.gas[i].frac[k]);
      printf(": hs %.4f = hr %.4f + hg %.4f W/(m2 K) (Nu %.4f, dT %.2f K)\n", r.hs[i], r.hr[i],
             r.hg[i], r.Nu[i], r.dT[i]);
    }
  }
  printf("U  %.4f W/(m2 K), declared %.1f   (he %.1f, hi %.2f)\n", r.U, r.U_declared, r.he, r.hi);
  printf("g  %.4f = tau_e %.4f + q_i %.4f\n", g, tau_e, qi);
  return VR_OK;
}
