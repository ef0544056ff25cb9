/* What vr-rgb2spec prints, reports and saves. */
#include "rgb2spec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/atomic_file.h"
#include "vr/colour.h"
#include "vr/json.h"
#include "vr/plot.h"
#include "vr/sha256.h"
#include "vr/version.h"

static void flags_text(unsigned f, char *out, size_t size) {
  static const struct {
    unsigned bit;
    const char *name;
  } F[] = {{VR_RECOVER_FLAG_RANK_DEFICIENT, "rank-deficient"},
           {VR_RECOVER_FLAG_OUT_OF_GAMUT, "out-of-gamut"},
           {VR_RECOVER_FLAG_CLIPPED, "clipped"},
           {VR_RECOVER_FLAG_CLIP_VIOLATED, "clip-violated"},
           {VR_RECOVER_FLAG_OUTSIDE_UNIT, "outside-[0,1]"},
           {VR_RECOVER_FLAG_MAX_ITER, "max-iterations"},
           {VR_RECOVER_FLAG_NO_DATA, "no-data"},
           {VR_RECOVER_FLAG_GCV_FLAT, "gcv-flat"},
           {VR_RECOVER_FLAG_MISFIT, "misfit"}};
  size_t used = 0;
  out[0] = '\0';
  for (size_t i = 0; i < sizeof F / sizeof F[0]; i++)
    if (f & F[i].bit) used += (size_t)snprintf(out + used, size - used, "%s%s", used ? "," : "", F[i].name);
}

void rg_print_text(const rg_run *run) {
  printf("# vr-rgb2spec: %zu photo(s), %zu region(s), method %s, %zu wavelengths %g-%g nm\n",
         run->nphotos, run->nregions, run->method_name, run->n, run->grid[0], run->grid[run->n - 1]);
  printf("# condition number of the stacked system: %.4g\n", run->condition);
  printf("# lights:");
  for (size_t l = 0; l < run->nphotos; l++) printf(" %s", run->photo[l]->light_name);
  printf("\n# held-out lights:");
  for (size_t h = 0; h < run->nheldout; h++) printf(" %s", run->heldout_name[h]);
  if (!isnan(run->loo_de[0])) {
    printf("\n# light check (median dE00 of each photo predicted from the others, limit %.0f):",
           RG_LOO_LIMIT);
    for (size_t l = 0; l < run->nphotos; l++)
      printf(" %s %.2f%s", run->photo[l]->light_name, run->loo_de[l],
             run->light_suspect[l] ? " (SUSPECT)" : "");
  }
  printf("\n# dE00 against the photos over lights without clipped channels; [k] = k lights left "
         "out for clipping\n");
  printf("region           dE00 mean  dE00 max  spectral RMSE  held-out dE00 max  flags\n");
  for (size_t i = 0; i < run->nregions; i++) {
    const rg_region *g = &run->regions[i];
    char f[160];
    flags_text(g->info.flags, f, sizeof f);
    double hmax = 0;
    for (size_t h = 0; h < g->nheldout; h++) hmax = fmax(hmax, g->heldout_de[h]);
    char clipnote[32] = "";
    if (g->nclipped_lights) snprintf(clipnote, sizeof clipnote, " [%zu]", g->nclipped_lights);
    printf("%-16s %9.4f %9.4f ", g->def->name, g->de_mean, g->de_max);
    if (isnan(g->rmse)) printf("%14s %18s", "-", "-");
    else printf("%14.4f %18.3f", g->rmse, hmax);
    printf("  %s%s\n", f, clipnote);
  }
}

static void json_array(const double *v, size_t n) {
  printf("[");
  for (size_t i = 0; i < n; i++) {
    if (i) printf(", ");
    vr_json_number(stdout, v[i]);
  }
  printf("]");
}

void rg_print_json(const rg_run *run) {
  printf("{\"method\": \"%s\", \"condition_number\": ", run->method_name);
  vr_json_number(stdout, run->condition);
  printf(", \"lights\": [");
  for (size_t l = 0; l < run->nphotos; l++) {
    printf("%s{\"photo\": ", l ? ", " : "");
    vr_json_string(stdout, run->photo[l]->path);
    printf(", \"light\": ");
    vr_json_string(stdout, run->photo[l]->light_name);
    printf("}");
  }
  printf("], \"heldout_lights\": [");
  for (size_t h = 0; h < run->nheldout; h++) {
    if (h) printf(", ");
    vr_json_string(stdout, run->heldout_name[h]);
  }
  printf("], \"light_check_deltaE00\": ");
  json_array(run->loo_de, run->nphotos);
  printf(", \"light_suspect\": [");
  for (size_t l = 0; l < run->nphotos; l++) printf("%s%s", l ? ", " : "", run->light_suspect[l] ? "true" : "false");
  printf("], \"regions\": [");
  for (size_t i = 0; i < run->nregions; i++) {
    const rg_region *g = &run->regions[i];
    char f[160];
    flags_text(g->info.flags, f, sizeof f);
    printf("%s\n {\"name\": ", i ? "," : "");
    vr_json_string(stdout, g->def->name);
    printf(", \"deltaE00_mean\": ");
    vr_json_number(stdout, g->de_mean);
    printf(", \"deltaE00_max\": ");
    vr_json_number(stdout, g->de_max);
    printf(", \"spectral_rmse\": ");
    vr_json_number(stdout, g->rmse);
    printf(", \"heldout_deltaE00\": ");
    json_array(g->heldout_de, g->nheldout);
    printf(", \"flags\": ");
    vr_json_string(stdout, f);
    printf(", \"residual\": ");
    vr_json_number(stdout, g->info.residual);
    printf(", \"chi2\": ");
    vr_json_number(stdout, g->info.chi2);
    printf(", \"chi2_limit\": ");
    vr_json_number(stdout, g->info.chi2_limit);
    printf(", \"lambda\": ");
    vr_json_number(stdout, g->info.lambda);
    printf(", \"misfit\": %s, \"lights_left_out_for_clipping\": %zu", g->misfit ? "true" : "false",
           g->nclipped_lights);
    printf(", \"per_light\": [");
    for (size_t l = 0; l < run->nphotos; l++) {
      printf("%s{\"photo_rgb\": ", l ? ", " : "");
      json_array(&g->c[3 * l], 3);
      printf(", \"noise_rgb\": ");
      json_array(&g->sigma[3 * l], 3);
      printf(", \"rendered_rgb\": ");
      json_array(&g->rendered[3 * l], 3);
      printf(", \"clipped\": [%d, %d, %d], \"deltaE00\": ", g->clipped[3 * l], g->clipped[3 * l + 1],
             g->clipped[3 * l + 2]);
      vr_json_number(stdout, g->de[l]);
      printf("}");
    }
    printf("], \"spectrum\": [");
    for (size_t j = 0; j < run->n; j++) {
      printf("%s[", j ? ", " : "");
      vr_json_number(stdout, run->grid[j]);
      printf(", ");
      vr_json_number(stdout, g->r[j]);
      printf("]");
    }
    printf("]}");
  }
  printf("\n]}\n");
}

/* An sRGB colour for display: linear responses, white-balanced to the
 * light's white, encoded. */
static void display_rgb(const rg_run *run, size_t l, const double lin[3], int out[3]) {
  const double *A = vr_recovery_system_matrix(run->sys);
  for (int ch = 0; ch < 3; ch++) {
    double w = 0;
    for (size_t j = 0; j < run->n; j++) w += A[(3 * l + ch) * run->n + j];
    double v = w > 0 ? lin[ch] / w : 0;
    out[ch] = (int)lround(255 * vr_srgb_encode(fmin(fmax(v, 0), 1)));
  }
}

/* The swatch image: one row per region, per light a square of the photo's
 * colour beside one of the re-rendered colour. */
static vr_status write_swatch(const char *path, const rg_run *run, vr_error *err) {
  const int cell = 32, gap = 6;
  int w = (int)run->nphotos * (2 * cell + gap) + gap, h = (int)run->nregions * (cell + gap) + gap;
  vr_image img;
  vr_status st = vr_image_alloc(&img, w, h, err);
  if (st) return st;
  for (size_t i = 0; i < (size_t)w * (size_t)h * 3; i++) img.data[i] = 1.0f;
  for (size_t i = 0; i < run->nregions; i++)
    for (size_t l = 0; l < run->nphotos; l++)
      for (int k = 0; k < 2; k++) {
        int rgb[3];
        display_rgb(run, l, k ? &run->regions[i].rendered[3 * l] : &run->regions[i].c[3 * l], rgb);
        int x0 = gap + (int)l * (2 * cell + gap) + k * cell, y0 = gap + (int)i * (cell + gap);
        for (int y = y0; y < y0 + cell; y++)
          for (int x = x0; x < x0 + cell; x++)
            for (int ch = 0; ch < 3; ch++) img.data[((size_t)y * w + x) * 3 + ch] = (float)rgb[ch] / 255.0f;
      }
  st = vr_image_write_png(path, &img, 8, err);
  vr_image_free(&img);
  return st;
}

vr_status rg_write_report(const char *path, const rg_run *run, vr_error *err) {
  char swatch[4200];
  snprintf(swatch, sizeof swatch, "%s.swatch.png", path);
  vr_status st = write_swatch(swatch, run, err);
  if (st) return st;
  vr_atomic_file f;
  if ((st = vr_atomic_file_open(&f, path, err))) return st;
  FILE *o = f.fp;
  const char *sw = strrchr(swatch, '/');
  fprintf(o, "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>vr-rgb2spec report</title>"
             "<style>body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}"
             "td,th{border:1px solid #ccc;padding:2px 6px;text-align:right}"
             ".sw{display:inline-block;width:18px;height:18px;border:1px solid #888}</style></head><body>\n");
  fprintf(o, "<h1>Spectral recovery: %zu regions, %zu lights</h1>\n", run->nregions, run->nphotos);
  fprintf(o, "<p>vr-rgb2spec %s, method <b>%s</b>, %zu wavelengths %g&ndash;%g nm, condition number "
             "of the stacked system <b>%.4g</b>. Lights:", vr_version(), run->method_name, run->n,
          run->grid[0], run->grid[run->n - 1], run->condition);
  for (size_t l = 0; l < run->nphotos; l++) fprintf(o, " %s (%s)", run->photo[l]->light_name, run->photo[l]->path);
  fprintf(o, ".</p>\n<p>Swatch: for each light, the photo's colour (left) beside the re-rendered one "
             "(right):<br><img src=\"%s\"></p>\n", sw ? sw + 1 : swatch);
  fprintf(o, "<table><tr><th>region</th><th>light</th><th>photo RGB (linear)</th><th>re-rendered RGB</th>"
             "<th>colour</th><th>&Delta;E00</th><th>clipped</th></tr>\n");
  for (size_t i = 0; i < run->nregions; i++) {
    const rg_region *g = &run->regions[i];
    for (size_t l = 0; l < run->nphotos; l++) {
      int a[3], b[3];
      char de_text[32];
      if (isnan(g->de[l])) snprintf(de_text, sizeof de_text, "(clipped)");
      else snprintf(de_text, sizeof de_text, "%.4f", g->de[l]);
      display_rgb(run, l, &g->c[3 * l], a);
      display_rgb(run, l, &g->rendered[3 * l], b);
      fprintf(o, "<tr><td>%s</td><td>%s</td><td>%.4f %.4f %.4f</td><td>%.4f %.4f %.4f</td>"
                 "<td><span class=sw style=\"background:rgb(%d,%d,%d)\"></span><span class=sw "
                 "style=\"background:rgb(%d,%d,%d)\"></span></td><td>%s</td><td>%s</td></tr>\n",
              g->def->name, run->photo[l]->light_name, g->c[3 * l], g->c[3 * l + 1], g->c[3 * l + 2],
              g->rendered[3 * l], g->rendered[3 * l + 1], g->rendered[3 * l + 2], a[0], a[1], a[2],
              b[0], b[1], b[2], de_text,
              g->clipped[3 * l] || g->clipped[3 * l + 1] || g->clipped[3 * l + 2] ? "yes" : "");
    }
  }
  fprintf(o, "</table>\n<h2>Against known reflectances</h2><table><tr><th>region</th>"
             "<th>spectral RMSE</th>");
  for (size_t h = 0; h < run->nheldout; h++) fprintf(o, "<th>&Delta;E00 under %s</th>", run->heldout_name[h]);
  fprintf(o, "</tr>\n");
  for (size_t i = 0; i < run->nregions; i++) {
    const rg_region *g = &run->regions[i];
    if (isnan(g->rmse)) continue;
    fprintf(o, "<tr><td>%s</td><td>%.4f</td>", g->def->name, g->rmse);
    for (size_t h = 0; h < g->nheldout; h++) fprintf(o, "<td>%.3f</td>", g->heldout_de[h]);
    fprintf(o, "</tr>\n");
  }
  fprintf(o, "</table><p>Held-out lights are CIE illuminants not used in the fit; colours with the "
             "CIE 1931 observer.</p>\n<h2>Spectra</h2>\n");
  bool ok = true;
  for (size_t i = 0; i < run->nregions && ok; i++) {
    const rg_region *g = &run->regions[i];
    char title[128];
    snprintf(title, sizeof title, "%s: recovered (blue)%s", g->def->name,
             g->def->reference ? ", reference (black)" : "");
    vr_plot *p = vr_plot_create(title, "wavelength (nm)", "reflectance");
    ok = p && vr_plot_add(p, run->n, run->grid, g->r, 0x1f77b4, false, "recovered");
    if (ok && g->def->reference) {
      double ref[1024];
      for (size_t j = 0; j < run->n && j < 1024; j++)
        ref[j] = vr_spectrum_eval(g->def->reference, run->grid[j], VR_INTERP_LINEAR);
      ok = vr_plot_add(p, run->n, run->grid, ref, 0x000000, true, "reference");
    }
    ok = ok && vr_plot_write_svg(p, o, 480, 260);
    vr_plot_destroy(p);
  }
  fprintf(o, "</body></html>\n");
  /* A plot that failed to be written (a full disk) is the write's error,
   * which the commit reports with its reason; else the plot itself failed. */
  if (!ok && !ferror(o) && fflush(o) == 0) {
    vr_atomic_file_abort(&f);
    return vr_error_set(err, VR_E_IO, "%s: could not draw the plots (out of memory)", path);
  }
  return vr_atomic_file_commit(&f, err);
}

vr_status rg_save(vr_matdb *db, const char *prefix, const rg_run *run, bool forced, vr_error *err) {
  vr_status st = VR_OK;
  char note[512];
  size_t used = (size_t)snprintf(note, sizeof note, "lights:");
  for (size_t l = 0; l < run->nphotos && used < sizeof note; l++)
    used += (size_t)snprintf(note + used, sizeof note - used, " %s", run->photo[l]->light_name);
  for (size_t i = 0; i < run->nregions && !st; i++) {
    const rg_region *g = &run->regions[i];
    char name[256];
    snprintf(name, sizeof name, "%s%s", prefix, g->def->name);
    vr_material *m = vr_material_create(name, VR_KIND_REFLECTANCE, err);
    if (!m) return err ? err->status : VR_E_NOMEM;
    double *v = malloc(run->n * sizeof *v);
    if (!v) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
    /* A reflectance is stored within [0, 1]; Matrix R's excursions are in
     * the report, not in the database. */
    for (size_t j = 0; j < run->n && !st; j++) v[j] = fmin(fmax(g->r[j], 0), 1);
    vr_spectrum *s = st ? NULL : vr_spectrum_create(run->n, run->grid, v, err);
    free(v);
    char model[96];
    snprintf(model, sizeof model, "Cohen-Kappauf %s, %zu lights", run->method_name, run->nphotos);
    if (!st) st = s ? vr_material_add_spectrum(m, "value", s, err) : VR_E_NOMEM;
    if (!st) st = vr_material_add_property(m, "condition_number", NULL, run->condition, NULL, err);
    if (!st) st = vr_material_add_property(m, "deltaE00_mean", NULL, g->de_mean, NULL, err);
    if (!st) st = vr_material_set_text(&m->prov.source_path, run->cap->path, err);
    /* The hash of the manifest bytes as read: also right for a pipe. */
    if (!st) memcpy(m->prov.sha256, run->cap->sha256, sizeof m->prov.sha256);
    if (!st) st = vr_material_set_text(&m->prov.tool, "vr-rgb2spec", err);
    if (!st) st = vr_material_set_text(&m->prov.tool_version, vr_version(), err);
    if (!st) st = vr_material_set_text(&m->prov.model, model, err);
    if (!st) {
      /* What the recovery said of this region travels with it. */
      char full[1024];
      snprintf(full, sizeof full, "%s; %s (chi2 %.4g, limit %.4g)%s", note,
               g->misfit ? "misses its photos by more than their noise explains" : "fits its photos within their noise",
               g->info.chi2, g->info.chi2_limit,
               forced ? "; saved with --force although some regions miss their photos or a light disagrees with its photo" : "");
      st = vr_material_set_text(&m->prov.note, full, err);
    }
    if (!st) st = vr_material_add_property(m, "fit_misfit", NULL, g->misfit ? 1 : 0, NULL, err);
    if (!st) st = vr_material_add_property(m, "fit_forced", NULL, forced ? 1 : 0, NULL, err);
    if (!st) m->prov.residual = g->de_mean;
    if (!st) st = vr_matdb_save(db, m, err);
    vr_material_destroy(m);
  }
  if (!st) fprintf(stderr, "vr-rgb2spec: saved %zu spectra as %s* to %s\n", run->nregions, prefix, vr_matdb_path(db));
  return st;
}
