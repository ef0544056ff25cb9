/* Stochastic progressive photon mapping: visible points, their hash grid,
 * photon deposits and the per-pixel radius statistics (sppm.h). */
#include "integrators/sppm.h"
#include "integrators/photon_maps.h"
#include "integrators/surface_disc.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "vr/comm.h"
#include "vr/rng.h"

/* A grid entry: a point's position (from the grid's corner, so float
 * keeps it to about 1e-7 of the grid's size), its radius squared (a little larger in
 * float, never smaller), the normal of the side it is seen from (zero for a
 * non-Lambertian point, whose BSDF decides), its slot, its object and its
 * geometric normal: what a photon's search reads, one run of memory per
 * hash slot. */
typedef struct vr_sppm_entry {
  float p[3], r2;
  float side[3];
  uint32_t slot;
  uint32_t object;
  float ng[3];
} vr_sppm_entry;

static size_t slot_of(const vr_sppm *s, uint32_t pixel) {
  size_t x = pixel % (uint32_t)s->width, y = pixel / (uint32_t)s->width;
  size_t tw = ((size_t)s->width + SPPM_TILE - 1) / SPPM_TILE;
  return ((y / SPPM_TILE) * tw + x / SPPM_TILE) * SPPM_TILE * SPPM_TILE +
         (y % SPPM_TILE) * SPPM_TILE + x % SPPM_TILE;
}

/* The pixel of a slot, or -1 for the padding of edge tiles. */
static long pixel_of(const vr_sppm *s, size_t slot) {
  size_t tw = ((size_t)s->width + SPPM_TILE - 1) / SPPM_TILE, t = slot / (SPPM_TILE * SPPM_TILE);
  size_t in = slot % (SPPM_TILE * SPPM_TILE);
  size_t x = (t % tw) * SPPM_TILE + in % SPPM_TILE, y = (t / tw) * SPPM_TILE + in / SPPM_TILE;
  return x < (size_t)s->width && y < (size_t)s->height ? (long)(y * (size_t)s->width + x) : -1;
}

static void put(_Atomic uint64_t *cell, double v) {
  uint64_t b;
  memcpy(&b, &v, sizeof b);
  atomic_store_explicit(cell, b, memory_order_relaxed);
}

vr_status vr_sppm_create(vr_sppm *s, const vr_rscene *rs, int width, int height, size_t film_bins,
                         double radius0, double radius0_px, double gamma, vr_error *err) {
  memset(s, 0, sizeof *s);
  s->width = width;
  s->height = height;
  s->npx = (size_t)width * (size_t)height;
  s->nslots = (((size_t)width + SPPM_TILE - 1) / SPPM_TILE) *
              (((size_t)height + SPPM_TILE - 1) / SPPM_TILE) * SPPM_TILE * SPPM_TILE;
  s->nwl = rs->nwl;
  s->wl_weight = (rs->lmax - rs->lmin) / rs->nwl;
  s->radius0 = radius0;
  s->radius0_px = radius0_px;
  s->gamma = gamma;
  s->footprint = rs->cam.tan_half > 0 ? 2 * rs->cam.tan_half / width : M_PI / width;
  memcpy(s->cam, rs->cam.o, sizeof s->cam);
  s->hsize = s->npx ? s->npx : 1;
  s->vp = calloc(s->nslots * VP_DOUBLES, sizeof *s->vp);
  s->acc = calloc(s->nslots, sizeof *s->acc);
  s->radius = calloc(s->nslots, sizeof *s->radius);
  s->share = calloc(s->nslots, sizeof *s->share);
  s->ends = vr_rect_edges_ending(rs);
  s->n = calloc(s->nslots, sizeof *s->n);
  s->start = calloc(s->hsize + 1, sizeof *s->start);
  if (!s->vp || !s->acc || !s->radius || !s->share || !s->ends || !s->n || !s->start) {
    vr_sppm_destroy(s);
    return vr_error_set(err, VR_E_NOMEM, "out of memory for the visible points of %d x %d pixels",
                        width, height);
  }
  vr_status st = vr_accum_create(&s->tau, width, height, film_bins, rs->film_lo, rs->film_step, 0,
                                 1, 0, err);
  if (!st && rs->bins_mode) st = vr_accum_set_bins(&s->tau, rs->lmin, rs->lmax, rs->nwl, err);
  if (st) vr_sppm_destroy(s);
  return st;
}

void vr_sppm_destroy(vr_sppm *s) {
  free(s->vp);
  free(s->acc);
  free(s->radius);
  free(s->share);
  free(s->ends);
  free(s->n);
  free(s->start);
  free(s->idx);
  vr_accum_destroy(&s->tau);
  memset(s, 0, sizeof *s);
}

void vr_sppm_begin(vr_sppm *s, const vr_rscene *rs, int iteration, int iterations) {
  /* The hero is stratified over the iterations (vr_wavelengths takes the
   * stratum from the key's sample index). */
  vr_rng_key key = {rs->seed, 0x5e5e5e5e5eull, (uint32_t)iteration, 0};
  vr_wavelengths(rs, &key, (uint32_t)(iterations > 0 ? iterations : 1), s->wl);
  memset(s->vp, 0, s->nslots * VP_DOUBLES * sizeof *s->vp);
  memset(s->acc, 0, s->nslots * sizeof *s->acc);
}

void vr_sppm_set_point(vr_sppm *s, const vr_rscene *rs, uint32_t pixel, const double p[3],
                       const double ns[3], const double ng[3], int object, const double wo[3],
                       int material, double state, const vr_bsdf_point *pt, int nwl,
                       const double *beta, bool terminated) {
  if (pixel >= s->npx) return;
  double *v = s->vp + slot_of(s, pixel) * VP_DOUBLES;
  const vr_bsdf *b = rs->mat[material].bsdf;
  /* A Lambertian surface's f is one value for every wi on wo's side:
   * evaluated here once, for the mirror direction, not per photon.  So is
   * a pbr surface's diffuse part (its specular part is followed by the
   * camera path): at the mirror direction, where its (1 - F) factor is
   * that of wo's incidence. */
  bool pbr = vr_bsdf_is_pbr(b);
  bool lambert = (vr_bsdf_lobes(b) == VR_LOBE_DIFFUSE && !vr_bsdf_is_thin(b)) || pbr;
  double f[VR_BSDF_MAX_WAVELENGTHS];
  if (lambert) {
    double c = ns[0] * wo[0] + ns[1] * wo[1] + ns[2] * wo[2], wi[3], pdf;
    for (int a = 0; a < 3; a++) wi[a] = 2 * c * ns[a] - wo[a];
    vr_bsdf_point d = pt ? *pt : vr_bsdf_point_plain();
    d.only = VR_LOBE_DIFFUSE;
    vr_bsdf_eval_at(b, &d, state, (vr_vec3){ns[0], ns[1], ns[2]}, (vr_vec3){wo[0], wo[1], wo[2]},
                    (vr_vec3){wi[0], wi[1], wi[2]}, nwl, s->wl, VR_TRANSPORT_RADIANCE, f, &pdf);
  }
  bool any = false;
  for (int k = 0; k < nwl && k < VR_MAX_WL; k++)
    any |= (v[VP_BETA + k] = lambert ? beta[k] * f[k] : beta[k]) > 0;
  if (!any) return;
  v[VP_VALID] = 1;
  v[VP_LAMBERT] = lambert;
  v[VP_TERM] = terminated;
  memcpy(v + VP_P, p, 3 * sizeof *p);
  memcpy(v + VP_N, ns, 3 * sizeof *ns);
  memcpy(v + VP_NG, ng, 3 * sizeof *ng);
  v[VP_OBJECT] = object + 1;
  memcpy(v + VP_WO, wo, 3 * sizeof *wo);
  v[VP_STATE] = state;
  v[VP_MATERIAL] = material;
}

static size_t hash3(int x, int y, int z, size_t n) {
  uint64_t h = (uint64_t)(uint32_t)x * 73856093u ^ (uint64_t)(uint32_t)y * 19349663u ^
               (uint64_t)(uint32_t)z * 83492791u;
  return (size_t)(h % n);
}

static int cell_of(const vr_sppm *s, double x, int a) {
  double c = floor((x - s->lo[a]) / s->cell);
  return c < 0 ? 0 : c >= s->res[a] ? s->res[a] - 1 : (int)c;
}

static void fill_entry(const vr_sppm *s, size_t i, vr_sppm_entry *e) {
  const double *v = s->vp + i * VP_DOUBLES;
  for (int a = 0; a < 3; a++) e->p[a] = (float)(v[VP_P + a] - s->lo[a]);
  e->r2 = (float)(s->radius[i] * s->radius[i]) * (1 + 1e-5f);
  double co = v[VP_N] * v[VP_WO] + v[VP_N + 1] * v[VP_WO + 1] + v[VP_N + 2] * v[VP_WO + 2];
  double sg = v[VP_LAMBERT] > 0.5 ? (co < 0 ? -1.0 : 1.0) : 0.0;
  for (int a = 0; a < 3; a++) e->side[a] = (float)(sg * v[VP_N + a]);
  e->slot = (uint32_t)i;
  e->object = (uint32_t)(v[VP_OBJECT] - 1);
  for (int a = 0; a < 3; a++) e->ng[a] = (float)v[VP_NG + a];
}

/* Point i's share of its disc on its sheet: below 1 on a rect near an edge
 * where the sheet ends (surface_disc.h). */
static double disc_share(const vr_sppm *s, const vr_rscene *rs, size_t i) {
  const double *v = s->vp + i * VP_DOUBLES;
  size_t o = (size_t)(v[VP_OBJECT] - 1);
  if (o >= rs->t->nobjects || !s->ends[o]) return 1.0;
  if (s->ends[o] & VR_SHEET_BOX) {
    double f[9];
    vr_box_face_frame(&rs->s->objects[o], v + VP_P, f);
    return vr_rect_disc_share(f, VR_EDGE_ALL, v + VP_P, s->radius[i], 0);
  }
  if (!rs->t->is_rect[o]) return 1.0;
  return vr_rect_disc_share(rs->t->rect_frame[o], s->ends[o], v + VP_P, s->radius[i], 0);
}

void vr_sppm_set_pilot(vr_sppm *s, const struct vr_photon_maps *maps, int k, double rmax) {
  s->pilot = maps, s->pilot_k = k, s->pilot_rmax = rmax;
}

/* Photons a unit area of the point's surface receives from one iteration,
 * on the side it is seen from, by the pilot maps: the k nearest of each map
 * (on the point's object) over their disc, k / (pi r^2) summed over the
 * maps; 0 where none lies within pilot_rmax. */
static double pilot_density(const vr_sppm *s, const double *v) {
  const vr_photon_set *sets[2] = {s->pilot->global, s->pilot->caustic};
  double n[3] = {v[VP_NG], v[VP_NG + 1], v[VP_NG + 2]};
  if (n[0] * v[VP_WO] + n[1] * v[VP_WO + 1] + n[2] * v[VP_WO + 2] < 0)
    for (int a = 0; a < 3; a++) n[a] = -n[a];
  double rho = 0, bins[512];
  for (int m = 0; m < 2; m++) {
    if (!sets[m] || !vr_photon_set_count(sets[m])) continue;
    if (vr_photon_map_nbins(vr_photon_set_map(sets[m], 0)) > 512) continue;
    double r = 0;
    int got = vr_photon_set_irradiance_on(sets[m], v + VP_P, n, (uint32_t)(v[VP_OBJECT] - 1),
                                          s->pilot_k, s->pilot_rmax, 0, bins, &r);
    if (got > 0 && r > 0) rho += got / (M_PI * r * r);
  }
  return rho;
}

vr_status vr_sppm_build(vr_sppm *s, const vr_rscene *rs, vr_error *err) {
  double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  double rmax = 0;
  size_t nvalid = 0;
  for (size_t i = 0; i < s->nslots; i++) {
    const double *v = s->vp + i * VP_DOUBLES;
    if (!(v[VP_VALID] > 0.5)) continue;
    if (!(s->radius[i] > 0)) {
      /* The first radius: as given, or a few pixel footprints at the point. */
      double d[3] = {v[VP_P] - s->cam[0], v[VP_P + 1] - s->cam[1], v[VP_P + 2] - s->cam[2]};
      s->radius[i] = s->radius0 > 0
                         ? s->radius0
                         : s->radius0_px * s->footprint * sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
      /* Where one iteration's photons are sparse, the radius that would
       * hold pilot_k of them (no larger than pilot_rmax): a disc of a few
       * pixels would see one photon in several iterations, and its
       * pixel's estimate would be a blotch of a few photons. */
      if (s->radius0 <= 0 && s->pilot) {
        double rho = pilot_density(s, v);
        double rk = rho > 0 ? sqrt(s->pilot_k / (M_PI * rho)) : s->pilot_rmax;
        if (rk > s->pilot_rmax) rk = s->pilot_rmax;
        if (rk > s->radius[i]) s->radius[i] = rk;
      }
      if (!(s->radius[i] > 0)) s->radius[i] = 1e-6;
    }
    s->share[i] = disc_share(s, rs, i);
    for (int k = 0; k < VR_MAX_WL; k++) s->acc[i].w[k] = v[VP_BETA + k];
    s->acc[i].term = v[VP_TERM] > 0.5;
    for (int a = 0; a < 3; a++) {
      lo[a] = fmin(lo[a], v[VP_P + a] - s->radius[i]);
      hi[a] = fmax(hi[a], v[VP_P + a] + s->radius[i]);
    }
    if (s->radius[i] > rmax) rmax = s->radius[i];
    nvalid++;
  }
  free(s->idx);
  s->idx = NULL;
  memset(s->start, 0, (s->hsize + 1) * sizeof *s->start);
  if (!nvalid) return VR_OK;
  /* Cells of twice the largest radius: a point's disc reaches at most two
   * cells along each axis. */
  s->cell = 2 * rmax;
  for (int a = 0; a < 3; a++) {
    s->lo[a] = lo[a];
    double r = ceil((hi[a] - lo[a]) / s->cell);
    s->res[a] = r < 1 ? 1 : r > (1 << 20) ? (1 << 20) : (int)r;
  }
  /* Counting, then filling (compressed rows by hash slot). */
  size_t total = 0;
  for (int pass = 0; pass < 2; pass++) {
    for (size_t i = 0; i < s->nslots; i++) {
      const double *v = s->vp + i * VP_DOUBLES;
      if (!(v[VP_VALID] > 0.5)) continue;
      int c0[3], c1[3];
      for (int a = 0; a < 3; a++) {
        c0[a] = cell_of(s, v[VP_P + a] - s->radius[i], a);
        c1[a] = cell_of(s, v[VP_P + a] + s->radius[i], a);
      }
      /* The point goes once into each hash slot its cells fall in: two of
       * its cells that share a slot must not list it twice, or a photon
       * in either would be counted twice there (with as many slots as
       * pixels, a few per cent of the points had such a pair: SPPM read
       * 0.6-0.8 % bright in a room at radii of 5-10 cm). */
      size_t hs[8];
      int nh = 0;
      for (int z = c0[2]; z <= c1[2]; z++)
        for (int y = c0[1]; y <= c1[1]; y++)
          for (int x = c0[0]; x <= c1[0]; x++) {
            size_t h = hash3(x, y, z, s->hsize);
            bool seen = false;
            for (int k = 0; k < nh && !seen; k++) seen = hs[k] == h;
            if (seen) continue;
            if (nh < 8) hs[nh++] = h; /* at most 2 x 2 x 2 cells: cells are 2 rmax wide */
            if (pass == 0) {
              s->start[h + 1]++;
              total++;
            } else {
              fill_entry(s, i, &s->idx[s->start[h]++]);
            }
          }
    }
    if (pass == 0) {
      if (total > UINT32_MAX) return vr_error_set(err, VR_E_NOMEM, "too many visible points");
      for (size_t h = 0; h < s->hsize; h++) s->start[h + 1] += s->start[h];
      s->idx = malloc((total ? total : 1) * sizeof *s->idx);
      if (!s->idx) return vr_error_set(err, VR_E_NOMEM, "out of memory for the visible points' grid");
    }
  }
  /* The fill advanced each start to its row's end: shift back. */
  for (size_t h = s->hsize; h > 0; h--) s->start[h] = s->start[h - 1];
  s->start[0] = 0;
  return VR_OK;
}

void vr_sppm_deposit(vr_sppm *s, const vr_rscene *rs, const double x[3], const double ng[3],
                     int object, const double wi[3], const double *beta, bool terminated) {
  if (!s->idx) return;
  int c[3];
  for (int a = 0; a < 3; a++) {
    double f = floor((x[a] - s->lo[a]) / s->cell);
    if (f < 0 || f >= s->res[a]) return; /* outside every point's disc */
    c[a] = (int)f;
  }
  size_t h = hash3(c[0], c[1], c[2], s->hsize);
  float xf[3] = {(float)(x[0] - s->lo[0]), (float)(x[1] - s->lo[1]), (float)(x[2] - s->lo[2])};
  float wf[3] = {(float)wi[0], (float)wi[1], (float)wi[2]};
  for (uint32_t j = s->start[h]; j < s->start[h + 1]; j++) {
    const vr_sppm_entry *e = &s->idx[j];
    float d[3] = {xf[0] - e->p[0], xf[1] - e->p[1], xf[2] - e->p[2]};
    if (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] > e->r2) continue;
    /* Only the point's own sheet of surface (surface_disc.h): the
     * point's own object's photons are taken (a rect's are on it; a box's
     * on the point's face only); another object's must face the same way
     * on the same plane, and at a rect's or a box's point lie inside the
     * edges that end. */
    uint8_t ends = e->object < rs->t->nobjects ? s->ends[e->object] : 0;
    if (e->object != (uint32_t)object) {
      bool rect = e->object < rs->t->nobjects && rs->t->is_rect[e->object];
      double pe[3] = {e->p[0], e->p[1], e->p[2]}, ne[3] = {e->ng[0], e->ng[1], e->ng[2]};
      double xr[3] = {xf[0], xf[1], xf[2]};
      if (!vr_same_sheet(pe, ne, xr, ng, sqrt((double)e->r2))) continue;
      if (rect && ends && !vr_rect_sheet_holds(rs->t->rect_frame[e->object], ends, x)) continue;
      if (ends & VR_SHEET_BOX) {
        double f[9], pw[3];
        for (int a = 0; a < 3; a++) pw[a] = (double)e->p[a] + s->lo[a];
        vr_box_face_frame(&rs->s->objects[e->object], pw, f);
        if (!vr_rect_sheet_holds(f, VR_EDGE_ALL, x)) continue;
      }
    } else if (ends & VR_SHEET_BOX) {
      double ne[3] = {e->ng[0], e->ng[1], e->ng[2]};
      if (!vr_box_same_face(ne, ng)) continue;
    }
    vr_sppm_acc *q = &s->acc[e->slot];
    double add[VR_MAX_WL];
    if (e->side[0] != 0 || e->side[1] != 0 || e->side[2] != 0) {
      /* Lambertian: f is in w already; nothing from the other side. */
      if (!(e->side[0] * wf[0] + e->side[1] * wf[1] + e->side[2] * wf[2] > 0)) continue;
      for (int k = 0; k < s->nwl; k++) add[k] = q->w[k] * beta[k];
    } else {
      const double *v = s->vp + (size_t)e->slot * VP_DOUBLES;
      const vr_bsdf *b = rs->mat[(int)v[VP_MATERIAL]].bsdf;
      double f[VR_BSDF_MAX_WAVELENGTHS], pdf;
      vr_bsdf_eval(b, v[VP_STATE], (vr_vec3){v[VP_N], v[VP_N + 1], v[VP_N + 2]},
                   (vr_vec3){v[VP_WO], v[VP_WO + 1], v[VP_WO + 2]},
                   (vr_vec3){wi[0], wi[1], wi[2]}, s->nwl, s->wl, VR_TRANSPORT_RADIANCE, f, &pdf);
      for (int k = 0; k < s->nwl; k++) add[k] = q->w[k] * f[k] * beta[k];
    }
    if (terminated && q->term)
      for (int k = 0; k < s->nwl; k++) add[k] /= s->nwl;
    for (int k = 0; k < s->nwl; k++)
      if (!(add[k] > 0) || !isfinite(add[k])) add[k] = 0.0;
    /* One lock a point for its nwl sums and its count: two atomic
     * operations instead of nwl + 1 compare-and-swap loops. */
    while (atomic_exchange_explicit(&q->lock, 1, memory_order_acquire))
      ;
    for (int k = 0; k < s->nwl; k++) q->phi[k] += add[k];
    /* M counts the photons that reached the disc, whatever f gave them
     * (the statistics count photons, not their weight). */
    q->m++;
    atomic_store_explicit(&q->lock, 0, memory_order_release);
  }
}

void vr_sppm_update(vr_sppm *s, uint64_t photons) {
  s->photons_total += photons;
  size_t nb = s->tau.nbins;
  for (size_t i = 0; i < s->nslots; i++) {
    uint64_t M = s->acc[i].m;
    long px = pixel_of(s, i);
    if (!M || px < 0) continue;
    double N = s->n[i], R = s->radius[i];
    /* A disc partly off its sheet holds the sheet's photons over only
     * share s of its area: its count and flux stand for M / s and Φ / s
     * over the whole disc. */
    double sh = s->share[i] > 0 ? s->share[i] : 1.0, Me = (double)M / sh;
    double Nn = N + s->gamma * Me;
    double Rn = R * sqrt(Nn / (N + Me));
    /* τ + β Φ: this iteration's radiance samples at its wavelengths, in
     * the film's units before the 1 / (photons π R^2). */
    double L[VR_MAX_WL];
    for (int k = 0; k < s->nwl; k++) L[k] = s->acc[i].phi[k] / s->wl_weight / sh;
    vr_accum_pixel(&s->tau, (uint32_t)px, s->nwl, s->wl, L, s->wl_weight);
    double shrink = (Rn * Rn) / (R * R);
    size_t p = (size_t)px;
    for (int a = 0; a < 3; a++)
      put(&s->tau.xyz[p * 3 + (size_t)a], vr_atomic_get(&s->tau.xyz[p * 3 + (size_t)a]) * shrink);
    for (size_t b = 0; b < nb; b++)
      put(&s->tau.bins[p * nb + b], vr_atomic_get(&s->tau.bins[p * nb + b]) * shrink);
    s->n[i] = Nn;
    s->radius[i] = Rn;
  }
}

void vr_sppm_film(const vr_sppm *s, double w, double *xyz, double *bins) {
  size_t nb = bins ? s->tau.nbins : 0;
  if (!s->photons_total) return;
  for (size_t i = 0; i < s->nslots; i++) {
    double R = s->radius[i];
    long px = pixel_of(s, i);
    if (!(R > 0) || px < 0) continue;
    size_t p = (size_t)px;
    double k = w / ((double)s->photons_total * M_PI * R * R);
    for (int a = 0; a < 3; a++) xyz[p * 3 + (size_t)a] += vr_atomic_get(&s->tau.xyz[p * 3 + (size_t)a]) * k;
    for (size_t b = 0; b < nb; b++) bins[p * nb + b] += vr_atomic_get(&s->tau.bins[p * nb + b]) * k;
  }
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

void vr_sppm_radii(const vr_sppm *s, double *lo, double *median, double *hi) {
  *lo = *median = *hi = 0;
  double *r = malloc((s->nslots ? s->nslots : 1) * sizeof *r);
  if (!r) return;
  size_t n = 0;
  for (size_t i = 0; i < s->nslots; i++)
    if (s->radius[i] > 0) r[n++] = s->radius[i];
  if (n) {
    qsort(r, n, sizeof *r, cmp_double);
    *lo = r[0], *median = r[n / 2], *hi = r[n - 1];
  }
  free(r);
}

vr_status vr_sppm_sum_points(vr_sppm *s, struct vr_comm *comm, vr_error *err) {
  return vr_comm_sum_doubles(comm, s->vp, s->nslots * VP_DOUBLES, err);
}

vr_status vr_sppm_sum_photons(vr_sppm *s, struct vr_comm *comm, vr_error *err) {
  size_t per = (size_t)s->nwl + 1, n = s->nslots * per;
  double *t = malloc(n * sizeof *t);
  if (!t) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (size_t i = 0; i < s->nslots; i++) {
    memcpy(t + i * per, s->acc[i].phi, (size_t)s->nwl * sizeof *t);
    t[i * per + (size_t)s->nwl] = s->acc[i].m;
  }
  vr_status st = vr_comm_sum_doubles(comm, t, n, err);
  if (!st)
    for (size_t i = 0; i < s->nslots; i++) {
      memcpy(s->acc[i].phi, t + i * per, (size_t)s->nwl * sizeof *t);
      s->acc[i].m = (uint32_t)llround(t[i * per + (size_t)s->nwl]);
    }
  free(t);
  return st;
}
