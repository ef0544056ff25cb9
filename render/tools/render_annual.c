/* vr-render's summary of an annual study on stdout (render_cli.h): the
 * run, the glass or shade, sDA, ASE and UDI over the work plane, EN 17037's
 * levels and every point's figures. */
#include <stdio.h>

#include "render_cli.h"
#include "vr/annual.h"

void render_annual_report(const vr_scene *scene, const vr_annual_result *res, const char *prefix) {
  const vr_scene_annual *a = &res->spec;
  printf("annual   %zu records, %zu occupied hours (%zu with daylight), %zu sun patches, %zu "
         "renders, %.1f s\n",
         res->records, res->occupied_hours, res->daylit_hours, res->sun_patches, res->renders,
         res->seconds);
  if (res->glass == VR_ANNUAL_SHADE) {
    printf("shade    %s in place of %s, drawn by IES LM-83-12's rule (more than 2 %% of the work "
           "plane at 1000 lx of direct sun): %.0f of the %zu occupied daylit hours; ASE is the "
           "open window's\n",
           res->glass_name, res->window_name, res->state_hours[1], res->daylit_hours);
  } else if (res->glass) {
    static const char *const RULE[] = {"fixed", "illuminance", "sun", "glare (DGPs)",
                                       "its own UV exposure"};
    printf("glass    %s, %s, control: %s", res->glass_name,
           res->glass == VR_ANNUAL_PHOTOCHROMIC ? "photochromic" : "electrochromic",
           a->control == VR_CONTROL_GLARE && res->nviews ? "glare (DGP at the glare views)"
                                                         : RULE[a->control]);
    if (a->control == VR_CONTROL_ILLUMINANCE || a->control == VR_CONTROL_SUN ||
        a->control == VR_CONTROL_GLARE)
      printf(" (max %g%s%s%s)", a->max, a->control == VR_CONTROL_GLARE ? "" : " lx", a->control_sensor >= 0 ? " at " : "",
             a->control_sensor >= 0 ? scene->sensors[a->control_sensor].name : "");
    printf(", mean state %.3f; daylit hours by state:", res->mean_state);
    for (int k = 0; k < a->nstates; k++) printf(" %g: %.0f", a->states[k], res->state_hours[k]);
    if (res->extrapolated_hours)
      printf("; extrapolated beyond its fitted UV or temperature: %zu h", res->extrapolated_hours);
    printf("\n");
  }
  printf("annual   sDA%g/%g%% %.1f %% of points, ASE%g,%gh %.1f %% of points (the work plane: %s, "
         "%zu point%s)\n",
         a->da_lx, 100 * a->sda_share, 100 * res->sda, a->ase_lx, a->ase_hours, 100 * res->ase,
         a->workplane >= 0 ? scene->sensors[a->workplane].name
                           : vr_scene_has_grid(scene) ? "every grid" : "every sensor (no grid)",
         res->workplane_points, res->workplane_points == 1 ? "" : "s");
  printf("annual   UDI over the work plane (its points' mean): below %g lx %.1f %%, %g-%g lx "
         "%.1f %%, above %g lx %.1f %%\n",
         a->udi_lo, 100 * res->udi_plane[0], a->udi_lo, a->udi_hi, 100 * res->udi_plane[1],
         a->udi_hi, 100 * res->udi_plane[2]);
  if (res->en17037.run) {
    const vr_en17037 *e = &res->en17037;
    printf("EN 17037 %zu daylight hours (the half of the year with the most global horizontal "
           "light); E_v,d,med %.0f lx (%s)\n",
           e->daylight_hours, e->edmed_lx, e->edmed_given ? "edmed=" : "their median in the weather file");
    for (int m = 0; m < 2; m++) {
      const double *tg = m ? e->m1_target : e->m2_target, *mn = m ? e->m1_minimum : e->m2_minimum;
      int level = m ? e->m1_level : e->m2_level;
      printf("EN 17037 method %d (%s): %s;", m ? 1 : 2,
             m ? "daylight factor, CIE overcast sky" : "illuminance over 50 % of the daylight hours",
             level < 0 ? "no level met" : VR_EN17037_LEVEL_NAME[level]);
      for (int l = 0; l < VR_EN17037_LEVELS; l++) {
        double ET = VR_EN17037_LX[VR_EN17037_TARGET[l]], ETM = VR_EN17037_LX[VR_EN17037_MINIMUM[l]];
        if (m)
          printf(" %s D>=%.2f%% on %.1f %% (50 %% needed), D>=%.2f%% on %.1f %% (95 %%)%s",
                 VR_EN17037_LEVEL_NAME[l], 100 * ET / e->edmed_lx, 100 * tg[l],
                 100 * ETM / e->edmed_lx, 100 * mn[l], l + 1 < VR_EN17037_LEVELS ? ";" : "");
        else
          printf(" %s %g lx on %.1f %% (50 %% needed), %g lx on %.1f %% (95 %%)%s",
                 VR_EN17037_LEVEL_NAME[l], ET, 100 * tg[l], ETM, 100 * mn[l],
                 l + 1 < VR_EN17037_LEVELS ? ";" : "");
      }
      printf("\n");
    }
  }
  for (size_t p = 0; p < res->npoints; p++) {
    const vr_annual_point *pt = &res->points[p];
    printf("point    %s (%d, %d)  DA %.1f %%  UDI %.1f / %.1f / %.1f %%  direct sun %.0f h  "
           "DGPs>=0.35 %.0f h  mean %.0f lx%s\n",
           pt->sensor ? pt->sensor : "", pt->i, pt->j, 100 * pt->da, 100 * pt->udi_below,
           100 * pt->udi_useful, 100 * pt->udi_above, pt->direct_hours, pt->glare_hours,
           pt->mean_lx, pt->workplane ? "" : "  (not on the work plane)");
    if (res->en17037.run)
      printf("point    %s (%d, %d)  EN 17037: daylight hours at 100/300/500/750 lx %.1f / %.1f / "
             "%.1f / %.1f %%  DF %.2f %%\n",
             pt->sensor ? pt->sensor : "", pt->i, pt->j, 100 * pt->en17037_share[0],
             100 * pt->en17037_share[1], 100 * pt->en17037_share[2], 100 * pt->en17037_share[3],
             pt->df_pct);
  }
  double nh = res->occupied_hours ? (double)res->occupied_hours : 1;
  for (size_t v = 0; v < res->nviews; v++) {
    const vr_annual_view *w = &res->views[v];
    printf("view     %s  DGP>=0.35 %.0f h (%.1f %%), >=0.40 %.0f h (%.1f %%), >=0.45 %.0f h "
           "(%.1f %%) of the occupied hours; EN 17037 glare protection: %s\n",
           w->sensor, w->hours[0], 100 * w->hours[0] / nh, w->hours[1], 100 * w->hours[1] / nh,
           w->hours[2], 100 * w->hours[2] / nh,
           w->en17037_level >= 0 ? VR_EN17037_LEVEL_NAME[w->en17037_level] : "none (DGP >= 0.45 in more than 5 % of the hours)");
  }
  printf("wrote    %s.annual.csv %s.annual-hourly.csv ", prefix, prefix);
  if (res->nviews) printf("%s.annual-glare.csv ", prefix);
  printf("%s.manifest.json\n", prefix);
}
