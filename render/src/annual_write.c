/* The annual study's two CSV files (vr/annual.h), each written whole or
 * not at all. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "vr/annual.h"
#include "vr/csv.h"
#include "vr/atomic_file.h"

/* A number, or an empty field for NAN. */
static void num(FILE *f, double v) {
  if (!isnan(v)) fprintf(f, "%.6g", v);
}

vr_status vr_annual_write(const vr_annual_result *r, const char *prefix, vr_error *err) {
  const vr_scene_annual *a = &r->spec;
  char path[4200];
  snprintf(path, sizeof path, "%s.annual.csv", prefix);
  vr_atomic_file af;
  vr_status st = vr_atomic_file_open(&af, path, err);
  if (st) return st;
  FILE *f = af.fp;
  fprintf(f,
          "sensor,i,j,x,y,z,mean_lx,da_%g_pct,udi_below_%g_pct,udi_%g_%g_pct,udi_above_%g_pct,"
          "direct_sun_hours_%g_lx,dgps_0.35_hours\n",
          a->da_lx, a->udi_lo, a->udi_lo, a->udi_hi, a->udi_hi, a->ase_lx);
  for (size_t p = 0; p < r->npoints; p++) {
    const vr_annual_point *pt = &r->points[p];
    vr_csv_write_field(f, pt->sensor ? pt->sensor : "");
    fprintf(f, ",%d,%d,%.9g,%.9g,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.9g,%.9g\n", pt->i, pt->j,
            pt->position[0], pt->position[1], pt->position[2], pt->mean_lx, 100 * pt->da,
            100 * pt->udi_below, 100 * pt->udi_useful, 100 * pt->udi_above, pt->direct_hours,
            pt->glare_hours);
  }
  if ((st = vr_atomic_file_commit(&af, err))) return st;
  snprintf(path, sizeof path, "%s.annual-hourly.csv", prefix);
  if ((st = vr_atomic_file_open(&af, path, err))) return st;
  f = af.fp;
  fputs("weather_line,glass_state,glass_uv_w_m2", f);
  for (size_t p = 0; p < r->npoints; p++) {
    fputc(',', f);
    char name[300];
    snprintf(name, sizeof name, "%s(%d;%d)", r->points[p].sensor ? r->points[p].sensor : "",
             r->points[p].i, r->points[p].j);
    vr_csv_write_field(f, name);
  }
  fputc('\n', f);
  for (size_t h = 0; h < r->occupied_hours; h++) {
    fprintf(f, "%ld,", r->hourly_line[h]);
    num(f, r->hourly_state[h]);
    fputc(',', f);
    num(f, r->hourly_uv[h]);
    for (size_t p = 0; p < r->npoints; p++) fprintf(f, ",%.6g", r->hourly_lx[h * r->npoints + p]);
    fputc('\n', f);
  }
  return vr_atomic_file_commit(&af, err);
}
