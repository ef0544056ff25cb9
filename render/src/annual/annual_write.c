/* The annual study's CSV files (vr/annual.h), written as one set: the two
 * tables and, with glare views, the views' table,
 * staged, moved into place together, then PREFIX.manifest.json (the run's
 * id, each file's size and SHA-256) written last, as a render's images are
 * (film_set.c), so `vr-render --verify PREFIX` checks a year's tables too
 * and a failed run leaves neither table. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "film/film_set.h"
#include "vr/annual.h"
#include "vr/csv.h"
#include "vr/film.h"

/* A number, or an empty field for NAN. */
static void num(FILE *f, double v) {
  if (!isnan(v)) fprintf(f, "%.6g", v);
}

static vr_status open_staged(const vr_film_staged *g, FILE **f, vr_error *err) {
  *f = fopen(g->stage, "w");
  if (!*f)
    return vr_error_set(err, VR_E_IO, "%s: cannot write: %s", g->target, strerror(errno));
  return VR_OK;
}

static vr_status close_staged(const vr_film_staged *g, FILE *f, vr_error *err) {
  bool bad = ferror(f) != 0;
  if (fclose(f) || bad)
    return vr_error_set(err, VR_E_IO, "%s: write failed: %s", g->target, strerror(errno));
  return VR_OK;
}

static void write_points(const vr_annual_result *r, FILE *f) {
  const vr_scene_annual *a = &r->spec;
  fprintf(f,
          "sensor,i,j,x,y,z,mean_lx,da_%g_pct,udi_below_%g_pct,udi_%g_%g_pct,udi_above_%g_pct,"
          "direct_sun_hours_%g_lx,dgps_0.35_hours,workplane",
          a->da_lx, a->udi_lo, a->udi_lo, a->udi_hi, a->udi_hi, a->ase_lx);
  /* EN 17037: each point's share of the daylight hours at each threshold
   * of Table A.1, and its daylight factor. */
  if (r->en17037.run)
    for (int k = 0; k < 4; k++) fprintf(f, ",en17037_%g_lx_pct", VR_EN17037_LX[k]);
  if (r->en17037.run) fputs(",df_cie_overcast_pct", f);
  fputc('\n', f);
  for (size_t p = 0; p < r->npoints; p++) {
    const vr_annual_point *pt = &r->points[p];
    vr_csv_write_field(f, pt->sensor ? pt->sensor : "");
    fprintf(f, ",%d,%d,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.9g,%.9g,%d", pt->i, pt->j,
            pt->position[0], pt->position[1], pt->position[2], pt->mean_lx, 100 * pt->da,
            100 * pt->udi_below, 100 * pt->udi_useful, 100 * pt->udi_above, pt->direct_hours,
            pt->glare_hours, pt->workplane ? 1 : 0);
    if (r->en17037.run) {
      for (int k = 0; k < 4; k++) fprintf(f, ",%.6g", 100 * pt->en17037_share[k]);
      fprintf(f, ",%.6g", pt->df_pct);
    }
    fputc('\n', f);
  }
}

static void write_hourly(const vr_annual_result *r, FILE *f) {
  fputs("weather_line,glass_state,glass_uv_w_m2", f);
  for (size_t p = 0; p < r->npoints; p++) {
    fputc(',', f);
    char name[300];
    snprintf(name, sizeof name, "%s(%d;%d)", r->points[p].sensor ? r->points[p].sensor : "",
             r->points[p].i, r->points[p].j);
    vr_csv_write_field(f, name);
  }
  for (size_t v = 0; v < r->nviews; v++) {
    fputc(',', f);
    char name[300];
    snprintf(name, sizeof name, "dgp:%s", r->views[v].sensor);
    vr_csv_write_field(f, name);
  }
  fputc('\n', f);
  for (size_t h = 0; h < r->occupied_hours; h++) {
    fprintf(f, "%ld,", r->hourly_line[h]);
    num(f, r->hourly_state[h]);
    fputc(',', f);
    num(f, r->hourly_uv[h]);
    for (size_t p = 0; p < r->npoints; p++) fprintf(f, ",%.6g", r->hourly_lx[h * r->npoints + p]);
    for (size_t v = 0; v < r->nviews; v++) fprintf(f, ",%.4f", r->hourly_dgp[h * r->nviews + v]);
    fputc('\n', f);
  }
}

/* One line per glare view: where it looks from and to, its hours of DGP
 * at each class bound, their shares and EN 17037's glare protection. */
static void write_views(const vr_annual_result *r, FILE *f) {
  fputs("view,x,y,z,dx,dy,dz,dgp_0.35_hours,dgp_0.40_hours,dgp_0.45_hours,dgp_0.35_pct,"
        "dgp_0.40_pct,dgp_0.45_pct,en17037_glare_protection\n", f);
  double nh = r->occupied_hours ? (double)r->occupied_hours : 1;
  for (size_t v = 0; v < r->nviews; v++) {
    const vr_annual_view *w = &r->views[v];
    vr_csv_write_field(f, w->sensor);
    fprintf(f, ",%.9g,%.9g,%.9g,%.6g,%.6g,%.6g", w->position[0], w->position[1], w->position[2],
            w->direction[0], w->direction[1], w->direction[2]);
    for (int k = 0; k < VR_GLARE_CLASSES; k++) fprintf(f, ",%.9g", w->hours[k]);
    for (int k = 0; k < VR_GLARE_CLASSES; k++) fprintf(f, ",%.6g", 100 * w->hours[k] / nh);
    fprintf(f, ",%s\n", w->en17037_level >= 0 ? VR_EN17037_LEVEL_NAME[w->en17037_level] : "none");
  }
}

vr_status vr_annual_write(const vr_annual_result *r, const char *prefix, vr_error *err) {
  vr_film_set set = {0};
  vr_film_staged *g = NULL;
  FILE *f = NULL;
  char run_id[VR_FILM_RUN_ID_MAX];
  vr_film_run_id(run_id);
  vr_status st = film_set_begin(&set, prefix, err);
  if (!st) st = film_set_add(&set, ".annual.csv", &g, err);
  if (!st) st = open_staged(g, &f, err);
  if (!st) {
    write_points(r, f);
    st = close_staged(g, f, err);
  }
  if (!st) st = film_set_add(&set, ".annual-hourly.csv", &g, err);
  if (!st) st = open_staged(g, &f, err);
  if (!st) {
    write_hourly(r, f);
    st = close_staged(g, f, err);
  }
  if (!st && r->nviews) {
    st = film_set_add(&set, ".annual-glare.csv", &g, err);
    if (!st) st = open_staged(g, &f, err);
    if (!st) {
      write_views(r, f);
      st = close_staged(g, f, err);
    }
  }
  if (!st) st = film_set_commit(&set, run_id, err);
  if (st && set.dir) film_set_abort(&set);
  return st;
}
