/* Annual climate-based daylight metrics by daylight coefficients
 * (vr/annual.h): the hours of the weather file, the coefficient renders
 * (annual_coef.c), the glass's state hour by hour, the year's sums. */
#include "vr/annual.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "annual/annual_internal.h"
#include "lights/light.h"
#include "vr/chromogenic.h"
#include "vr/fisheye.h"
#include "vr/matdb.h"
#include "vr/perez.h"
#include "vr/sky.h"
#include "vr/sun.h"
#include "vr/weather.h"

#define PI 3.14159265358979323846
/* IES LM-83-12's operable-shading rule for sDA. */
#define LM83_SUN_LX 1000.0
#define LM83_SHARE 0.02

void vr_annual_result_destroy(vr_annual_result *r) {
  if (!r) return;
  free(r->points);
  free(r->hourly_lx);
  free(r->hourly_line);
  free(r->hourly_state);
  free(r->hourly_uv);
  free(r->hourly_dgp);
  free(r->views);
  free(r->names);
  free(r->glass_names);
  free(r);
}

static double now_s(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return t.tv_sec + 1e-9 * t.tv_nsec;
}

/* A line for the options' log, if any. */
static void say(const vr_render_options *o, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(const vr_render_options *o, const char *fmt, ...) {
  if (!o->log) return;
  char line[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(line, sizeof line, fmt, ap);
  va_end(ap);
  o->log(o->user, line);
}

/* The hour's Perez sky as patch luminances (cd/m2) and the ground's. */
static void hour_sky(const vr_perez_sky *m, const double sun[3], double ground_rho, double sin_alt,
                     double *L) {
  double norm = 0;
  for (int k = 0; k < VR_SKY_PATCHES; k++) {
    double a0, a1, z0, z1;
    vr_sky_patch_bounds(k, &a0, &a1, &z0, &z1);
    /* Mean relative luminance over a 3 x 3 grid of the patch (equal areas
     * in sin(altitude) and azimuth). */
    double mean = 0;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        double sa = sin(a0 * PI / 180) + (i + 0.5) / 3 * (sin(a1 * PI / 180) - sin(a0 * PI / 180));
        double az = (z0 + (j + 0.5) / 3 * (z1 - z0)) * PI / 180, ca = sqrt(fmax(0, 1 - sa * sa));
        double d[3] = {ca * sin(az), ca * cos(az), sa};
        mean += vr_perez_relative(&m->lum, sun, d) / 9;
      }
    /* Integral of cos(zenith) over the patch: (z1 - z0) (sin^2 a1 - sin^2 a0) / 2. */
    double s0 = sin(a0 * PI / 180), s1 = sin(a1 * PI / 180);
    norm += mean * (z1 - z0) * PI / 180 * (s1 * s1 - s0 * s0) / 2;
    L[k] = mean;
  }
  double scale = norm > 0 ? m->diffuse_horizontal_lx / norm : 0;
  for (int k = 0; k < VR_SKY_PATCHES; k++) L[k] *= scale;
  L[VR_SKY_GROUND_PATCH] =
      ground_rho * (m->diffuse_horizontal_lx + m->direct_normal_lx * fmax(0, sin_alt)) / PI;
}

/* The sun's direction at the centre of a record's interval (a .wea has no
 * year: 2021, as the single-record sky takes it). */
static bool sun_at(const vr_weather *w, const vr_weather_record *r, double dir[3], double *alt) {
  int y = r->year >= 1800 && r->year <= 2200 ? r->year : 2021;
  vr_sun_site site;
  vr_sun_site_default(&site, w->latitude_deg, w->longitude_deg);
  vr_sun_position pos;
  if (vr_sun_position_local(&site, y, r->month, r->day, 30.0 * (r->start_h + r->end_h),
                            w->timezone_h, &pos, NULL, NULL) != VR_OK)
    return false;
  memcpy(dir, pos.direction, 3 * sizeof *dir);
  *alt = pos.altitude_deg;
  return true;
}

static bool occupied(const vr_weather_record *r, const vr_scene_annual *a) {
  double c = 0.5 * (r->start_h + r->end_h);
  return c >= a->from_h && c < a->to_h;
}

/* The glass of the study: its kind from the database, the states to
 * render and the control, with the defaults of vr/annual.h filled in.  A
 * photochromic glass's material is kept in *pc for its kinetics. */
static vr_status glass_setup(const vr_scene *s, struct vr_matdb *db, vr_annual_result *res,
                             vr_material **pc, vr_error *err) {
  vr_scene_annual *a = &res->spec;
  *a = s->annual;
  *pc = NULL;
  if (a->shade >= 0) {
    /* The LM-83 rule's two states: open (0) and drawn (1). */
    res->glass = VR_ANNUAL_SHADE;
    const char *sn = s->materials[a->shade].name, *wn = s->materials[a->shade_window].name;
    size_t ls = strlen(sn) + 1;
    if (!(res->glass_names = malloc(ls + strlen(wn) + 1)))
      return vr_error_set(err, VR_E_NOMEM, "out of memory");
    memcpy(res->glass_names, sn, ls);
    strcpy(res->glass_names + ls, wn);
    res->glass_name = res->glass_names, res->window_name = res->glass_names + ls;
    a->nstates = 2, a->states[0] = 0, a->states[1] = 1, a->control = VR_CONTROL_LM83;
    return VR_OK;
  }
  if (a->glass < 0) {
    a->nstates = 1, a->states[0] = NAN, a->control = VR_CONTROL_FIXED;
    return VR_OK;
  }
  const vr_scene_material *sm = &s->materials[a->glass];
  if (!(res->glass_names = strdup(sm->name))) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  res->glass_name = res->glass_names;
  long line = a->loc.line, col = a->loc.col;
  if (!db)
    return vr_error_at(err, VR_E_NOT_FOUND, s->path, line, col,
                       "glass=%s needs a material database", sm->name);
  vr_material *m = NULL;
  vr_status st = vr_matdb_load(db, sm->db_name, 0, &m, err);
  if (st) {
    vr_error_prefix(err, "%s:%ld:%ld: glass=%s: ", s->path, line, col, sm->name);
    return st;
  }
  vr_chromo_type type;
  if (m->kind != VR_KIND_CHROMOGENIC || vr_chromo_type_of(m, &type, NULL) != VR_OK) {
    st = vr_error_at(err, VR_E_ARG, s->path, line, col,
                     "glass=%s: %s is a %s material, not a chromogenic (switchable) glass",
                     sm->name, sm->db_name, vr_kind_name(m->kind));
    vr_material_destroy(m);
    return st;
  }
  bool given_states = a->nstates > 0;
  if (type == VR_CHROMO_PHOTO) {
    res->glass = VR_ANNUAL_PHOTOCHROMIC;
    if (a->control != VR_CONTROL_FIXED) {
      vr_material_destroy(m);
      return vr_error_at(err, VR_E_ARG, s->path, line, col,
                         "glass=%s is photochromic: its state follows its own UV exposure, "
                         "no control= applies",
                         sm->name);
    }
    a->control = VR_CONTROL_UV;
    if (!given_states) {
      a->nstates = 5;
      for (int i = 0; i < 5; i++) a->states[i] = 0.25 * i;
    }
    if (a->nstates < 2 || a->states[0] != 0 || a->states[a->nstates - 1] != 1) {
      vr_material_destroy(m);
      return vr_error_at(err, VR_E_ARG, s->path, line, col,
                         "glass=%s is photochromic: its states= must run from 0 to 1 (the "
                         "state each hour is interpolated between them)",
                         sm->name);
    }
    *pc = m;
    return VR_OK;
  }
  res->glass = VR_ANNUAL_ELECTROCHROMIC;
  if (a->control == VR_CONTROL_FIXED) {
    if (given_states) {
      vr_material_destroy(m);
      return vr_error_at(err, VR_E_ARG, s->path, line, col,
                         "states= needs control=illuminance or control=sun: a fixed glass "
                         "keeps its material's state=");
    }
    double state = 0;
    if (!isnan(sm->state)) state = sm->state;
    else if (!isnan(sm->charge_mC_cm2) &&
             (st = vr_chromo_state_of_charge(m, sm->charge_mC_cm2, &state, err))) {
      vr_material_destroy(m);
      return st;
    }
    a->nstates = 1, a->states[0] = state;
  } else {
    if (!given_states) {
      a->nstates = 4;
      for (int i = 0; i < 4; i++) a->states[i] = i / 3.0;
    }
    if (isnan(a->max))
      a->max = a->control == VR_CONTROL_SUN ? 1000 : a->control == VR_CONTROL_GLARE ? 0.35 : 3000;
  }
  vr_material_destroy(m);
  return VR_OK;
}


/* The ratio of the cosines of the hour's true sun and its patch centre on
 * a surface of normal n (absolute values when either face counts), held in
 * [0, 4]; 1 where the centre grazes the surface. */
static double sun_ratio(const vr_annual_hour *h, const double n[3], bool either_face) {
  double ct = n[0] * h->sun[0] + n[1] * h->sun[1] + n[2] * h->sun[2];
  double cc = n[0] * h->centre[0] + n[1] * h->centre[1] + n[2] * h->centre[2];
  if (either_face) ct = fabs(ct), cc = fabs(cc);
  return cc > 1e-3 ? fmin(fmax(ct, 0) / cc, 4.0) : 1.0;
}

/* The hour's illuminance at every point with the coefficients d: total
 * and direct sun, the direct part scaled by the cosine ratio. */
static void hour_lx(const vr_annual_hour *h, const vr_dc_set *d, const vr_annual_point *pts, size_t np,
                    double *E, double *D) {
  for (size_t p = 0; p < np; p++) {
    E[p] = D[p] = 0;
    if (!h->daylit) continue;
    const double *dc = d->sky + p * NPATCH;
    double e = 0;
    for (int k = 0; k < NPATCH; k++) e += dc[k] * h->L[k];
    if (h->ks >= 0) {
      size_t i = p * VR_SKY_PATCHES + (size_t)h->ks;
      double direct = h->Edn * d->sun_direct[i] * sun_ratio(h, pts[p].normal, false);
      e += h->Edn * (d->sun_total[i] - d->sun_direct[i]) + direct;
      D[p] = direct;
    }
    E[p] = e;
  }
}

double annual_between(double a, double b, double f) {
  return a > 0 && b > 0 ? a * pow(b / a, f) : a + f * (b - a);
}

/* The photochromic glass's mean state this hour: every texel's UV, its
 * state from the last one's (prev, NAN: none) or the steady state. */
static vr_status pc_state(const vr_annual_hour *h, const vr_uv_set *u, const vr_material *m, double T_K,
                          unsigned flags, double *texel_state, bool have_prev, double *state, double *uv,
                          bool *outside, vr_error *err) {
  double sum_s = 0, sum_uv = 0;
  *outside = false;
  for (size_t t = 0; t < u->ntexels; t++) {
    double E = 0;
    if (h->daylit) {
      for (int k = 0; k < NPATCH; k++) E += u->sky[t * NPATCH + (size_t)k] * h->L[k];
      if (h->ks >= 0) {
        /* The sun reaches one face of the pane or the other. */
        E += h->Edn * u->sun[t * VR_SKY_PATCHES + (size_t)h->ks] *
             sun_ratio(h, u->normal + 3 * t, true);
      }
    }
    double s;
    vr_status st = VR_E_NOT_FOUND;
    if (have_prev) {
      vr_error e = {0};
      st = vr_chromo_state_after(m, E, T_K, flags, texel_state[t],
                                 3600 * (h->r->end_h - h->r->start_h), &s, &e);
      if (st && st != VR_E_NOT_FOUND) return *err = e, st;
    }
    if (st && (st = vr_chromo_steady_state(m, E, T_K, flags, &s, err))) return st;
    if ((flags & VR_CHROMO_EXTRAPOLATE) && vr_chromo_check_domain(m, E, T_K, flags, NULL))
      *outside = true;
    texel_state[t] = s;
    sum_s += s, sum_uv += E;
  }
  double n = u->ntexels ? (double)u->ntexels : 1;
  *state = sum_s / n, *uv = sum_uv / n;
  return VR_OK;
}

/* Every record: occupied or not (the schedule occ, else the hours=
 * window), and for those the study needs (occupied; with EN 17037 every
 * one with the sun up, to rank the daylight hours) the sun, its patch and
 * the Perez sky.  A needed daylit record with a missing irradiance is an
 * error naming its line. */
static vr_status read_hours(const vr_scene *s, const vr_weather *w, const bool *occ,
                            vr_annual_result *res, vr_annual_hour *hours, vr_annual_job *j,
                            vr_error *err) {
  bool en = res->spec.en17037;
  size_t nocc = 0;
  for (size_t i = 0; i < w->nrecords; i++) {
    const vr_weather_record *r = &w->records[i];
    vr_annual_hour *h = &hours[i];
    memset(h, 0, sizeof *h);
    h->r = r;
    h->ks = -1;
    h->occ = occ ? occ[i] : occupied(r, &res->spec);
    nocc += h->occ;
    if (!h->occ && !en) continue;
    double alt;
    if (!sun_at(w, r, h->sun, &alt) || alt <= 0) continue;
    if (isnan(r->direct_normal_w_m2) || isnan(r->diffuse_horizontal_w_m2))
      return vr_error_set(err, VR_E_PARSE,
                          "%s:%ld: the sun is up in this %s hour but its %s irradiance is "
                          "missing (an annual study needs every daylit hour%s)",
                          w->path, r->line, h->occ ? "occupied" : "unoccupied",
                          isnan(r->direct_normal_w_m2) ? "direct normal" : "diffuse horizontal",
                          h->occ ? "" : "; EN 17037 ranks every hour of the year");
    if (!(r->diffuse_horizontal_w_m2 > 0)) continue; /* Perez needs diffuse light: night, or none */
    vr_perez_input in = {90 - alt, r->direct_normal_w_m2, r->diffuse_horizontal_w_m2,
                         r->dew_point_c, vr_weather_day_of_year(r)};
    vr_perez_sky m;
    vr_error e = {0};
    if (vr_perez_sky_from(&in, &m, &e) != VR_OK)
      return vr_error_set(err, VR_E_PARSE, "%s:%ld: %s", w->path, r->line, e.message);
    h->daylit = true;
    res->daylit_hours += h->occ;
    hour_sky(&m, h->sun, s->sky.ground_reflectance, sin(alt * PI / 180), h->L);
    h->Edh = m.diffuse_horizontal_lx;
    h->Egh = m.diffuse_horizontal_lx + m.direct_normal_lx * sin(alt * PI / 180);
    if (m.direct_normal_lx > 0) {
      h->Edn = m.direct_normal_lx;
      h->ks = vr_sky_patch_of(h->sun);
      vr_sky_patch_centre(h->ks, h->centre);
    }
  }
  res->occupied_hours = nocc;
  if (en) {
    size_t n = w->nrecords;
    double *egh = malloc((n + 1) * sizeof *egh), *edh = malloc((n + 1) * sizeof *edh);
    bool *dlh = malloc(n + 1);
    vr_status st = VR_OK;
    if (!egh || !edh || !dlh)
      st = vr_error_set(err, VR_E_NOMEM, "out of memory for EN 17037's daylight hours");
    for (size_t i = 0; !st && i < n; i++) egh[i] = hours[i].Egh, edh[i] = hours[i].Edh;
    double edmed = 0;
    if (!st) st = annual_daylight_hours(egh, edh, n, dlh, &edmed, err);
    for (size_t i = 0; !st && i < n; i++) hours[i].dlh = dlh[i];
    vr_en17037 *e = &res->en17037;
    e->run = true;
    e->daylight_hours = n / 2;
    e->edmed_given = !isnan(res->spec.edmed_lx);
    e->edmed_lx = e->edmed_given ? res->spec.edmed_lx : edmed;
    free(egh), free(edh), free(dlh);
    if (st) return st;
    if (!(e->edmed_lx > 0))
      return vr_error_set(err, VR_E_ARG,
                          "%s: the median diffuse horizontal illuminance over the daylight hours "
                          "is 0 lx: EN 17037's method 1 has no target (give edmed=)",
                          w->path);
  }
  for (size_t i = 0; i < w->nrecords; i++)
    if (hours[i].ks >= 0 && (hours[i].occ || hours[i].dlh)) j->need[hours[i].ks] = true;
  return VR_OK;
}

/* The year's sums: each needed hour's state, illuminance and the metrics
 * (over the occupied hours; EN 17037's over its daylight hours). */
static vr_status year(const vr_annual_hour *hours, size_t nrec, const vr_dc_set *dcs,
                      const vr_uv_set *uv, const vr_glare_set *g, const vr_material *pc, double T_K,
                      unsigned pc_flags, const char *control, vr_annual_result *res, vr_error *err) {
  const vr_scene_annual *a = &res->spec;
  size_t np = res->npoints, nh = res->occupied_hours;
  int ns = a->nstates;
  double *E = calloc((size_t)ns * np + 1, sizeof *E), *D = calloc((size_t)ns * np + 1, sizeof *D);
  double *cur = calloc(np + 1, sizeof *cur);
  double *texel_state = calloc((uv ? uv->ntexels : 0) + 1, sizeof *texel_state);
  res->hourly_lx = calloc(nh * np + 1, sizeof *res->hourly_lx);
  res->hourly_line = calloc(nh + 1, sizeof *res->hourly_line);
  res->hourly_state = calloc(nh + 1, sizeof *res->hourly_state);
  res->hourly_uv = calloc(nh + 1, sizeof *res->hourly_uv);
  size_t nv = res->nviews;
  res->hourly_dgp = calloc(nh * nv + 1, sizeof *res->hourly_dgp);
  double *view_dgp = calloc(nv + 1, sizeof *view_dgp);
  vr_status st = VR_OK;
  if (!E || !D || !cur || !texel_state || !res->hourly_lx || !res->hourly_line ||
      !res->hourly_state || !res->hourly_uv || !res->hourly_dgp || !view_dgp) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory for the year");
    goto done;
  }
  double state_sum = 0;
  size_t oi = 0;           /* the occupied hour's row */
  bool prev_done = false;  /* the record just before was evaluated */
  for (size_t hi = 0; hi < nrec; hi++) {
    const vr_annual_hour *h = &hours[hi];
    if (!h->occ && !h->dlh) {
      prev_done = false;
      continue;
    }
    double *dir = D, state = res->glass ? a->states[0] : NAN, uv_mean = NAN;
    int pick = 0;
    int glo = 0, ghi = 0; /* the states whose images the glare views blend, by gf */
    double gf = 0;
    if (a->control == VR_CONTROL_UV) {
      /* The state carries over from the record before when that one was
       * evaluated too. */
      double s, e;
      bool outside;
      if ((st = pc_state(h, uv, pc, T_K, pc_flags, texel_state, prev_done, &s, &e, &outside, err))) {
        vr_error_prefix(err, "annual, weather record at line %ld: ", h->r->line);
        goto done;
      }
      state = s, uv_mean = e;
      if (h->occ) res->extrapolated_hours += outside;
      int lo = 0;
      while (lo < ns - 2 && s > a->states[lo + 1]) lo++;
      double f = (s - a->states[lo]) / (a->states[lo + 1] - a->states[lo]);
      hour_lx(h, &dcs[lo], res->points, np, E, D);
      hour_lx(h, &dcs[lo + 1], res->points, np, E + np, D + np);
      for (size_t p = 0; p < np; p++) {
        cur[p] = annual_between(E[p], E[np + p], f);
        D[p] = annual_between(D[p], D[np + p], f);
      }
      pick = f < 0.5 ? lo : lo + 1;
      glo = lo, ghi = lo + 1, gf = f;
    } else {
      for (int k = 0; k < ns; k++) hour_lx(h, &dcs[k], res->points, np, E + (size_t)k * np, D + (size_t)k * np);
      if (a->control == VR_CONTROL_LM83) {
        /* IES LM-83-12: the shade is drawn when more than 2 % of the work
         * plane sees 1000 lx of direct sun through the open window. */
        size_t lit = 0, nw = 0;
        for (size_t p = 0; p < np; p++)
          if (res->points[p].workplane) nw++, lit += D[p] >= LM83_SUN_LX;
        pick = (double)lit > LM83_SHARE * (double)nw ? 1 : 0;
        state = pick;
      } else if (a->control == VR_CONTROL_GLARE && nv) {
        /* With glare views, the lightest state whose DGP (contrast term
         * included) stays within max at every view the control watches
         * (control_sensor=, else every view); the darkest when none does. */
        for (pick = 0; pick < ns - 1; pick++) {
          annual_glare_hour(g, h, pick, pick, 0, dcs, E + (size_t)pick * np, view_dgp);
          bool ok = true;
          for (size_t v = 0; v < nv && ok; v++)
            if (!control || !strcmp(res->views[v].sensor, control)) ok = view_dgp[v] <= a->max;
          if (ok) break;
        }
        state = a->states[pick];
      } else if (a->control != VR_CONTROL_FIXED) {
        /* The lightest state that keeps every control point within the
         * threshold; the darkest when none does. */
        /* DGPs = 6.22e-5 E_v + 0.184 (Wienold 2009) at most max is E_v at
         * most (max - 0.184) / 6.22e-5. */
        double limit = a->control == VR_CONTROL_GLARE ? vr_dgps_limit_lx(a->max) : a->max;
        for (pick = 0; pick < ns - 1; pick++) {
          const double *v = (a->control == VR_CONTROL_SUN ? D : E) + (size_t)pick * np;
          bool ok = true;
          for (size_t p = 0; p < np && ok; p++) {
            if (control && (!res->points[p].sensor || strcmp(res->points[p].sensor, control)))
              continue;
            ok = v[p] <= limit;
          }
          if (ok) break;
        }
        state = a->states[pick];
      }
      memcpy(cur, E + (size_t)pick * np, np * sizeof *cur);
      glo = ghi = pick;
      /* ASE through the glass as controlled; with a shade, through the
       * open window (LM-83 defines ASE without operable shading). */
      dir = D + (a->control == VR_CONTROL_LM83 ? 0 : (size_t)pick * np);
    }
    prev_done = true;
    if (h->dlh)
      for (size_t p = 0; p < np; p++)
        for (int k = 0; k < 4; k++) res->points[p].en17037_share[k] += cur[p] >= VR_EN17037_LX[k];
    if (!h->occ) continue;
    res->hourly_line[oi] = h->r->line;
    res->hourly_state[oi] = state;
    res->hourly_uv[oi] = uv_mean;
    memcpy(res->hourly_lx + oi * np, cur, np * sizeof *cur);
    if (nv) {
      double *dgp = res->hourly_dgp + oi * nv;
      annual_glare_hour(g, h, glo, ghi, gf, dcs, cur, dgp);
      for (size_t v = 0; v < nv; v++)
        for (int k = 0; k < VR_GLARE_CLASSES; k++) res->views[v].hours[k] += dgp[v] >= VR_GLARE_DGP[k];
    }
    oi++;
    if (h->daylit && res->glass) {
      res->state_hours[pick] += 1;
      state_sum += state;
    }
    for (size_t p = 0; p < np; p++) {
      vr_annual_point *pt = &res->points[p];
      double e = cur[p];
      pt->mean_lx += e;
      pt->da += e >= a->da_lx;
      pt->udi_below += e < a->udi_lo;
      pt->udi_useful += e >= a->udi_lo && e <= a->udi_hi;
      pt->udi_above += e > a->udi_hi;
      pt->direct_hours += dir[p] >= a->ase_lx;
      pt->glare_hours += vr_dgps(e) >= 0.35;
    }
  }
  res->mean_state = res->glass && res->daylit_hours ? state_sum / (double)res->daylit_hours : NAN;
  /* Shares over the occupied hours; sDA and ASE over the points. */
  double occ = nh ? (double)nh : 1;
  size_t sda = 0, ase = 0, nw = 0;
  for (size_t p = 0; p < np; p++) {
    vr_annual_point *pt = &res->points[p];
    pt->mean_lx /= occ;
    pt->da /= occ, pt->udi_below /= occ, pt->udi_useful /= occ, pt->udi_above /= occ;
    if (!pt->workplane) continue;
    nw++;
    res->udi_plane[0] += pt->udi_below, res->udi_plane[1] += pt->udi_useful;
    res->udi_plane[2] += pt->udi_above;
    sda += pt->da >= a->sda_share;
    ase += pt->direct_hours > a->ase_hours;
  }
  res->workplane_points = nw;
  for (size_t v = 0; v < nv; v++) {
    vr_annual_view *vw = &res->views[v];
    /* EN 17037's glare protection: the highest level whose DGP_e is
     * reached in at most 5 % of the occupied hours. */
    vw->en17037_level = -1;
    for (int k = VR_GLARE_CLASSES - 1; k >= 0; k--)
      if (vw->hours[k] <= 0.05 * (double)nh) vw->en17037_level = VR_GLARE_CLASSES - 1 - k;
  }
  for (int k = 0; k < 3; k++) res->udi_plane[k] /= nw ? (double)nw : 1;
  res->sda = nw ? (double)sda / (double)nw : 0;
  res->ase = nw ? (double)ase / (double)nw : 0;
done:
  free(E), free(D), free(cur), free(texel_state), free(view_dgp);
  return st;
}

/* EN 17037 once the year is summed: the hours' counts as shares, each
 * point's daylight factor from a render under the CIE overcast sky with
 * the glass in its clearest state rendered, and the assessment. */
static vr_status en17037_finish(vr_annual_job *j, vr_annual_result *res, vr_error *err) {
  vr_en17037 *e = &res->en17037;
  double *df = calloc(res->npoints + 1, sizeof *df);
  if (!df) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_status st = annual_df(j, res->spec.states[0], df, err);
  double n = e->daylight_hours ? (double)e->daylight_hours : 1;
  for (size_t p = 0; !st && p < res->npoints; p++) {
    vr_annual_point *pt = &res->points[p];
    for (int k = 0; k < 4; k++) pt->en17037_share[k] /= n;
    pt->df_pct = df[p];
  }
  free(df);
  if (!st) vr_en17037_assess(res->points, res->npoints, e->edmed_lx, e);
  return st;
}

/* The glare views: their cameras and the result's table of them. */
static vr_status views_setup(vr_annual_job *j, vr_glare_set *g, vr_error *err) {
  vr_annual_result *res = j->res;
  vr_status st = annual_glare_setup(j, g, err);
  if (st) return st;
  res->nviews = (size_t)g->n;
  if (!(res->views = calloc(res->nviews + 1, sizeof *res->views)))
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t v = 0; v < res->nviews; v++) {
    const vr_annual_point *pt = &res->points[g->v[v].point];
    res->views[v].sensor = pt->sensor;
    res->views[v].point = g->v[v].point;
    memcpy(res->views[v].position, pt->position, sizeof pt->position);
    memcpy(res->views[v].direction, g->v[v].frame[2], sizeof res->views[v].direction);
  }
  return VR_OK;
}

vr_status vr_annual_run(const vr_scene *s, struct vr_matdb *db, const vr_render_options *o,
                        vr_annual_result **out, vr_error *err) {
  *out = NULL;
  if (!s->sky.present || !s->sky.annual || !s->sky.weather_path)
    return vr_error_set(err, VR_E_ARG,
                        "%s: an annual study needs 'sky perez weather=FILE' with no date and time",
                        s->path);
  if (!s->nsensors) return vr_error_set(err, VR_E_ARG, "%s: an annual study needs sensors", s->path);
  vr_annual_job j = {.s = s, .db = db, .o = o};
  for (size_t i = 0; i < s->nlights; i++)
    if (vr_light_kind_ops((size_t)s->lights[i].kind)->flags & VR_LF_SUN) j.sun = &s->lights[i];
  if (!j.sun) return vr_error_set(err, VR_E_ARG, "%s: an annual study needs a 'light sun' line", s->path);
  double t0 = now_s();
  vr_annual_result *res = calloc(1, sizeof *res);
  if (!res) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  vr_material *pc = NULL;
  vr_weather *w = NULL;
  vr_annual_hour *hours = NULL;
  bool *occ = NULL;
  vr_dc_set dcs[VR_ANNUAL_MAX_STATES] = {{0}};
  vr_uv_set uv = {0};
  vr_glare_set glare = {0};
  vr_status st = glass_setup(s, db, res, &pc, err);
  if (!st) st = vr_weather_read(s->sky.weather_path, &w, err);
  if (st) goto done;
  for (size_t i = 0; i < s->nsensors; i++) j.npoints += (size_t)s->sensors[i].nu * (size_t)s->sensors[i].nv;
  res->npoints = j.npoints;
  res->records = w->nrecords;
  res->points = calloc(j.npoints + 1, sizeof *res->points);
  hours = calloc(w->nrecords + 1, sizeof *hours);
  if (res->spec.occupancy_path && !(occ = calloc(w->nrecords + 1, sizeof *occ))) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory for the occupancy schedule");
    goto done;
  }
  if (!res->points || !hours) {
    st = vr_error_set(err, VR_E_NOMEM, "out of memory for the annual study");
    goto done;
  }
  j.res = res;
  if (occ && (st = annual_occupancy_read(res->spec.occupancy_path, w, occ, err))) goto done;
  if ((st = read_hours(s, w, occ, res, hours, &j, err))) goto done;
  for (int k = 0; k < VR_SKY_PATCHES; k++) res->sun_patches += j.need[k];
  for (int k = 0; k < res->spec.nstates && !st; k++) {
    st = annual_dc(&j, res->spec.states[k], &dcs[k], err);
    if (!st) say(o, "annual: %s: 1 sky and %zu sun renders (%zu in all, %.1f s)",
                 res->glass ? "a tint state rendered" : "the coefficients rendered", res->sun_patches,
                 res->renders, now_s() - t0);
    if (!st && k == 0 && s->annual.nviews) st = views_setup(&j, &glare, err);
    if (!st && glare.n) {
      st = annual_view_dc(&j, res->spec.states[k], k, &glare, err);
      if (!st) say(o, "annual: %d glare view%s: %d x %d fisheye coefficients, 1 sky and %zu sun "
                      "renders each (%zu renders in all, %.1f s)",
                   glare.n, glare.n > 1 ? "s" : "", s->annual.view_resolution,
                   s->annual.view_resolution, res->sun_patches, res->renders, now_s() - t0);
    }
  }
  if (!st && res->spec.control == VR_CONTROL_UV) {
    st = annual_uv(&j, &uv, err);
    if (!st) say(o, "annual: the glass's UV coefficients rendered (%zu renders in all, %.1f s)",
                 res->renders, now_s() - t0);
  }
  if (st) goto done;
  const char *control =
      res->spec.control_sensor >= 0 ? s->sensors[res->spec.control_sensor].name : NULL;
  double T_K = NAN;
  unsigned pc_flags = VR_CHROMO_ESTIMATE; /* the hour's UV is from sampled coefficients */
  if (res->spec.glass >= 0) {
    T_K = s->materials[res->spec.glass].temperature_K;
    if (s->materials[res->spec.glass].extrapolate) pc_flags |= VR_CHROMO_EXTRAPOLATE;
  }
  if (isnan(T_K)) T_K = 298.15;
  /* The glass's temperature is the year's: outside the fitted range it is
   * the material line's fault, not an hour's. */
  if (pc && !(pc_flags & VR_CHROMO_EXTRAPOLATE) && (st = vr_chromo_check_domain(pc, 0, T_K, 0, err))) {
    vr_error_prefix(err, "%s:%ld: material '%s': ", s->path ? s->path : "scene",
                    s->materials[res->spec.glass].loc.line, s->materials[res->spec.glass].name);
    goto done;
  }
  st = year(hours, w->nrecords, dcs, &uv, &glare, pc, T_K, pc_flags, control, res, err);
  if (!st && res->en17037.run) st = en17037_finish(&j, res, err);
  for (size_t p = 0; !st && !res->en17037.run && p < res->npoints; p++) {
    for (int k = 0; k < 4; k++) res->points[p].en17037_share[k] = NAN;
    res->points[p].df_pct = NAN;
  }
  if (!st && res->extrapolated_hours)
    say(o, "annual: warning: in %zu hours the glass's UV or temperature lay outside the range "
           "it was fitted on; its state was extrapolated as extrapolate=yes asked",
        res->extrapolated_hours);
  res->seconds = now_s() - t0;
done:
  for (int k = 0; k < VR_ANNUAL_MAX_STATES; k++) annual_dc_free(&dcs[k]);
  annual_uv_free(&uv);
  annual_glare_free(&glare);
  free(hours);
  free(occ);
  vr_material_destroy(pc);
  vr_weather_free(w);
  if (st) {
    vr_annual_result_destroy(res);
    return st;
  }
  *out = res;
  return VR_OK;
}
