/* vr-render's results on stdout (render_cli.h): the text summary, or with
 * --json one JSON object, and the sensor grids' uniformity in both. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render_cli.h"
#include "vr/fisheye.h"
#include "vr/json.h"
#include "vr/version.h"

/* ---- the grids ---- */

size_t render_grids(const vr_scene *s, const vr_render_result *r, render_grid *g, size_t cap) {
  size_t n = 0;
  for (size_t k = 0; k < s->nsensors && n < cap; k++) {
    if (!s->sensors[k].grid) continue;
    const char *name = s->sensors[k].name;
    render_grid *q = &g[n];
    *q = (render_grid){.name = name, .min_lx = INFINITY, .max_lx = -INFINITY};
    double sum = 0;
    for (size_t i = 0; i < r->nreadings; i++) {
      const vr_sensor_reading *x = &r->readings[i];
      if (!x->sensor || strcmp(x->sensor, name)) continue;
      double e = x->illuminance_lx;
      q->points++;
      sum += e;
      if (e < q->min_lx) q->min_lx = e;
      if (e > q->max_lx) q->max_lx = e;
    }
    if (!q->points) continue;
    q->mean_lx = sum / (double)q->points;
    q->u0 = q->mean_lx > 0 ? q->min_lx / q->mean_lx : NAN;
    q->min_max = q->max_lx > 0 ? q->min_lx / q->max_lx : NAN;
    n++;
  }
  return n;
}

/* ---- text ---- */

/* Bytes for a person: "812.0 KiB", "1.5 GiB". */
static void human(char out[32], size_t bytes) {
  if (bytes >= ((size_t)1 << 30))
    snprintf(out, 32, "%.2f GiB", (double)bytes / (1 << 30));
  else if (bytes >= ((size_t)1 << 20))
    snprintf(out, 32, "%.1f MiB", (double)bytes / (1 << 20));
  else
    snprintf(out, 32, "%.1f KiB", (double)bytes / 1024);
}

static void ratio(double v) {
  if (isnan(v)) printf("-");
  else printf("%.3f", v);
}

void render_summary_text(const vr_scene *s, const vr_render_result *r, const render_report *rep) {
  if (r->width > 0 && r->height > 0) {
    printf("image    %d x %d", r->width, r->height);
    if (r->nbins && r->bin_nm)
      printf(", %zu bins %g-%g nm", r->nbins, r->bin_nm[0], r->bin_nm[r->nbins - 1]);
    printf(", exposure %+g EV%s\n", r->exposure_ev,
           rep->exposure_auto ? " (auto: the log-average luminance to mid grey)" : "");
    if (r->pixel_samples) {
      const struct vr_adaptive_summary *a = &r->adaptive;
      printf("adaptive %d rounds, %u to %u samples a pixel (mean %.1f); ", a->rounds, a->spp_min,
             a->spp_max, a->spp_mean);
      if (!isnan(a->converged_share))
        printf("%.1f %% of pixels at the target, ", 100 * a->converged_share);
      printf("95 %% of pixels within %.3g relative error; stopped: %s\n", a->error_p95, a->stop);
    }
  }
  for (size_t i = 0; i < r->npasses && i < VR_MAX_PASSES; i++) {
    const vr_pass_record *p = &r->passes[i];
    if (p->ran) printf("pass     %-16s %9.3f s  %s\n", p->name, p->seconds, p->reason);
    else printf("pass     %-16s   skipped    %s\n", p->name, p->reason);
  }
  printf("rays     camera %llu, shadow %llu, photon %llu, other %llu; %llu sub-domain crossings\n",
         (unsigned long long)r->rays_camera, (unsigned long long)r->rays_shadow,
         (unsigned long long)r->rays_photon, (unsigned long long)r->rays_other,
         (unsigned long long)r->crossings);
  if (r->photons_global || r->photons_caustic || r->photons_direct)
    printf("photons  global %zu, caustic %zu, direct %zu\n", r->photons_global, r->photons_caustic,
           r->photons_direct);
  for (size_t k = 0; k < r->nreadings; k++) {
    const vr_sensor_reading *x = &r->readings[k];
    printf("sensor   %s (%d, %d)  %.6g lx  +- %.2g lx", x->sensor ? x->sensor : "", x->i, x->j,
           x->illuminance_lx, x->stderr_lx);
    if (!isnan(x->df_pct))
      printf("  DF %.3g %% (sky %.3g, externally reflected %.3g, internally reflected %.3g)",
             x->df_pct, x->df_sc_pct, x->df_erc_pct, x->df_irc_pct);
    putchar('\n');
  }
  render_grid g[64];
  size_t ng = render_grids(s, r, g, 64);
  for (size_t k = 0; k < ng; k++) {
    printf("grid     %s  %zu points  Emin %.6g lx  Eavg %.6g lx  Emax %.6g lx  U0 = Emin/Eavg ",
           g[k].name, g[k].points, g[k].min_lx, g[k].mean_lx, g[k].max_lx);
    ratio(g[k].u0);
    printf("  Emin/Emax ");
    ratio(g[k].min_max);
    putchar('\n');
  }
  if (!isnan(r->eye_illuminance_lx)) {
    const vr_dgp_result *q = &r->glare;
    printf("glare    vertical illuminance at the lens %.6g lx, DGP %.3f (Wienold & Christoffersen "
           "2006%s; glare sources: %.4g sr above %.4g cd/m2, mean %.4g cd/m2), DGPs %.3f\n",
           r->eye_illuminance_lx, q->dgp, q->vertical_lx < 1000 ? ", low-light corrected" : "",
           q->source_omega_sr, q->threshold_cd_m2, q->source_cd_m2, vr_dgps(r->eye_illuminance_lx));
  }
  if (r->photochromic_texels)
    printf("photochromic  %zu texels, state %.4g to %.4g\n", r->photochromic_texels,
           r->photochromic_state_min, r->photochromic_state_max);
  printf("wrote   ");
  for (int i = 0; i < rep->outputs->n; i++) printf(" %s", rep->outputs->path[i]);
  printf("  (%.3f s)\n", rep->film_seconds);
  if (r->textures)
    printf("textures %zu, %.1f MiB with their mip-maps, loaded in %.2f s\n", r->textures,
           (double)r->texture_bytes / 1048576.0, r->texture_seconds);
  printf("cache    %s%s (%.2f s, %.1f MiB)\n", r->cache_built ? "built: " : "",
         r->cache_reason, r->cache_seconds, (double)r->cache_bytes / 1048576.0);
  if (r->memory_budget) {
    char b[8][32];
    human(b[0], r->memory_budget), human(b[1], r->peak_cells_bytes);
    human(b[2], r->peak_geometry_bytes), human(b[3], r->peak_embree_bytes);
    human(b[4], r->peak_queue_bytes), human(b[5], r->peak_map_bytes);
    human(b[6], r->cell_bytes_read), human(b[7], r->peak_spill_bytes);
    printf("memory   budget %s: peak %s sub-domains (%s arrays, %s Embree), %s queues, %s maps; "
           "%llu loads, %llu unloads, %s read in %.2f s, %llu rays spilled (peak %s on disk)\n",
           b[0], b[1], b[2], b[3], b[4], b[5], (unsigned long long)r->cell_loads,
           (unsigned long long)r->cell_unloads, b[6], r->cell_load_seconds,
           (unsigned long long)r->rays_spilled, b[7]);
  }
  printf("time     %.3f s, peak memory %.1f MiB\n", r->seconds_total,
         (double)vr_peak_rss_bytes() / (1024.0 * 1024.0));
}

/* ---- JSON ---- */

static void key(const char *indent, const char *k) {
  fputs(indent, stdout);
  vr_json_string(stdout, k);
  fputs(": ", stdout);
}

static void num(double v) { vr_json_number(stdout, v); }

void render_summary_json(const vr_scene *s, const vr_render_result *r, const render_report *rep) {
  FILE *f = stdout;
  fputs("{\n", f);
  key("  ", "version"), vr_json_string(f, vr_version()), fputs(",\n", f);
  key("  ", "run_id"), vr_json_string(f, rep->run_id), fputs(",\n", f);
  key("  ", "scene"), vr_json_string(f, rep->scene), fputs(",\n", f);
  key("  ", "image");
  if (r->width > 0 && r->height > 0) {
    fprintf(f, "{\"width\": %d, \"height\": %d, \"bins\": %zu, \"exposure_ev\": ", r->width,
            r->height, r->nbins);
    num(r->exposure_ev);
    fprintf(f, ", \"exposure_auto\": %s, \"adaptive\": ", rep->exposure_auto ? "true" : "false");
    vr_adaptive_write_json(f, r);
    fputs("},\n", f);
  } else {
    fputs("null,\n", f);
  }
  key("  ", "passes"), vr_passes_write_json(f, r), fputs(",\n", f);
  key("  ", "sensors"), fputc('[', f);
  for (size_t k = 0; k < r->nreadings; k++) {
    const vr_sensor_reading *x = &r->readings[k];
    fprintf(f, "%s\n    {\"name\": ", k ? "," : "");
    vr_json_string(f, x->sensor ? x->sensor : "");
    fprintf(f, ", \"i\": %d, \"j\": %d, \"position\": [", x->i, x->j);
    for (int c = 0; c < 3; c++) fputs(c ? ", " : "", f), num(x->position[c]);
    fputs("], \"illuminance_lx\": ", f), num(x->illuminance_lx);
    fputs(", \"stderr_lx\": ", f), num(x->stderr_lx);
    fprintf(f, ", \"paths\": %llu", (unsigned long long)x->paths);
    fputs(", \"daylight_factor_pct\": ", f), num(x->df_pct);
    fputc('}', f);
  }
  fputs(r->nreadings ? "\n  ],\n" : "],\n", f);
  render_grid g[64];
  size_t ng = render_grids(s, r, g, 64);
  key("  ", "grids"), fputc('[', f);
  for (size_t k = 0; k < ng; k++) {
    fprintf(f, "%s\n    {\"name\": ", k ? "," : "");
    vr_json_string(f, g[k].name);
    fprintf(f, ", \"points\": %zu, \"min_lx\": ", g[k].points);
    num(g[k].min_lx);
    fputs(", \"mean_lx\": ", f), num(g[k].mean_lx);
    fputs(", \"max_lx\": ", f), num(g[k].max_lx);
    fputs(", \"u0\": ", f), num(g[k].u0);
    fputs(", \"min_over_max\": ", f), num(g[k].min_max);
    fputc('}', f);
  }
  fputs(ng ? "\n  ],\n" : "],\n", f);
  key("  ", "glare");
  if (!isnan(r->eye_illuminance_lx)) {
    fputs("{\"vertical_illuminance_lx\": ", f), num(r->eye_illuminance_lx);
    fputs(", \"dgp\": ", f), num(r->glare.dgp);
    fputs(", \"dgps\": ", f), num(vr_dgps(r->eye_illuminance_lx));
    fputs(", \"source_sr\": ", f), num(r->glare.source_omega_sr);
    fputs(", \"threshold_cd_m2\": ", f), num(r->glare.threshold_cd_m2);
    fputs(", \"source_cd_m2\": ", f), num(r->glare.source_cd_m2);
    fputs("},\n", f);
  } else {
    fputs("null,\n", f);
  }
  key("  ", "rays");
  fprintf(f, "{\"camera\": %" PRIu64 ", \"shadow\": %" PRIu64 ", \"photon\": %" PRIu64
          ", \"other\": %" PRIu64 ", \"crossings\": %" PRIu64 "},\n",
          r->rays_camera, r->rays_shadow, r->rays_photon, r->rays_other, r->crossings);
  key("  ", "outputs"), fputc('[', f);
  for (int i = 0; i < rep->outputs->n; i++)
    fputs(i ? ", " : "", f), vr_json_string(f, rep->outputs->path[i]);
  fputs("],\n", f);
  key("  ", "timings");
  fputs("{\"render_seconds\": ", f), num(r->seconds_total);
  fputs(", \"outputs_seconds\": ", f), num(rep->film_seconds);
  fputs(", \"peak_rss_bytes\": ", f);
  fprintf(f, "%lld}\n}\n", vr_peak_rss_bytes());
}
