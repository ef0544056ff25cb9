/* Several ranks rendering one scene (run.h, docs/ddm.md "Ranks"):
 * agreeing on failures, refusing mismatched scenes, giving cells owners,
 * and putting the ranks' shares together.
 *
 * Failures.  A collective call blocks until every rank makes it, so a rank
 * that fails must tell the others at the very point where they wait.
 * Every collective block below starts with vr_ranks_sync; a rank that
 * fails elsewhere calls vr_ranks_sync once on its way out (render.c), which
 * meets the others' next sync; a failure agreed there is not agreed again.
 * The flow's own termination waves carry failures the same way. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "run/run.h"
#include "vr/comm.h"
#include "vr/film.h"

vr_status vr_ranks_sync(vr_run *r, vr_status st, vr_error *err) {
  if (r->nranks == 1 || r->failure_agreed) return st;
  vr_status all = vr_comm_agree(r->comm, st, err);
  if (all) r->failure_agreed = true;
  return all;
}

vr_status vr_ranks_check_scene(vr_run *r, const vr_rscene *rs, vr_error *err) {
  if (r->nranks == 1) return VR_OK;
  /* The caller's digest of the scene and options, the geometry's key, S. */
  unsigned char mine[68] = {0};
  if (r->opt->has_digest) memcpy(mine, r->opt->scene_digest, 32);
  vr_domains_key(rs->d, mine + 32);
  int32_t S = vr_domains_count(rs->d);
  memcpy(mine + 64, &S, 4);
  unsigned char *all = NULL;
  vr_status st = vr_comm_gather_bytes(r->comm, mine, sizeof mine, &all, NULL, err);
  for (int k = 1; !st && k < r->nranks; k++) {
    const unsigned char *a = all, *b = all + (size_t)k * sizeof mine;
    if (memcmp(a, b, 32))
      st = vr_error_set(err, VR_E_ARG,
                        "rank %d renders another scene file or other options than rank 0 "
                        "(their checksums differ): every rank must be given the same scene "
                        "and options",
                        k);
    else if (memcmp(a + 32, b + 32, 32))
      st = vr_error_set(err, VR_E_ARG,
                        "rank %d reads other geometry than rank 0 (the mesh files or the "
                        "scene's objects differ): every rank must see the same mesh files",
                        k);
    else if (memcmp(a + 64, b + 64, 4))
      st = vr_error_set(err, VR_E_ARG, "rank %d cuts the scene into another number of sub-domains",
                        k);
  }
  free(all);
  /* Every rank compared the same bytes: the verdict is the same. */
  if (st) r->failure_agreed = true;
  return st;
}

/* Sums n accumulator values (doubles kept as bits) over the ranks, in
 * pieces of at most SUM_PIECE values through one buffer: a film is summed
 * without a second copy of it in memory (a 4K film of 33 values a pixel
 * is 2.2 GB; the buffer is 8 MiB). */
#define SUM_PIECE ((size_t)1 << 20)
static vr_status sum_cells(vr_run *r, _Atomic uint64_t *cells, size_t n, vr_error *err) {
  if (!n) return VR_OK;
  size_t cap = n < SUM_PIECE ? n : SUM_PIECE;
  double *v = malloc(cap * sizeof *v);
  vr_status st = v ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  st = vr_ranks_sync(r, st, err);
  for (size_t at = 0; !st && at < n; at += cap) {
    size_t k = n - at < cap ? n - at : cap;
    for (size_t i = 0; i < k; i++) v[i] = vr_atomic_get(&cells[at + i]);
    st = vr_comm_sum_doubles(r->comm, v, k, err);
    for (size_t i = 0; !st && i < k; i++) {
      uint64_t bits;
      memcpy(&bits, &v[i], sizeof bits);
      atomic_store(&cells[at + i], bits);
    }
  }
  free(v);
  return st;
}

vr_status vr_ranks_sum_accum(vr_run *r, vr_accum *a, unsigned parts, vr_error *err) {
  if (r->nranks == 1) return VR_OK;
  size_t px = (size_t)a->width * (size_t)a->height;
  vr_status st = VR_OK;
  if (parts & RANKS_FILM) {
    st = sum_cells(r, a->xyz, px * 3, err);
    if (!st) st = sum_cells(r, a->bins, px * a->nbins, err);
    if (!st && a->half_xyz) st = sum_cells(r, a->half_xyz, px * 3, err);
    if (!st && a->feat) st = sum_cells(r, a->feat, px * VR_FEATURES, err);
    if (!st && a->pixel_patches) st = sum_cells(r, a->pixel_patches, px * VR_PIXEL_SOURCES, err);
  }
  if (!st && (parts & RANKS_SENSORS)) {
    st = sum_cells(r, a->sensor_lx, a->npoints * (size_t)a->groups, err);
    if (!st) st = sum_cells(r, a->sensor_bins, a->npoints * a->nbins, err);
    if (!st) st = sum_cells(r, a->sensor_parts, a->npoints * VR_SENSOR_PARTS, err);
    if (!st) st = sum_cells(r, a->sensor_patches, a->npoints * VR_SENSOR_PATCHES, err);
  }
  if (!st && (parts & RANKS_TEXELS)) st = sum_cells(r, a->texel_uv, a->ntexels, err);
  if (!st && (parts & RANKS_TEXELS))
    st = sum_cells(r, a->texel_patches, a->ntexels * VR_SENSOR_PATCHES, err);
  return st;
}


/* Every map's staged records, as (set, map, count, records) runs. */
vr_status vr_ranks_share_photons(vr_run *r, vr_photon_set *const *sets, int nsets, vr_error *err) {
  if (r->nranks == 1) return VR_OK;
  size_t bytes = 0;
  for (int s = 0; s < nsets; s++)
    for (int m = 0; sets[s] && m < vr_photon_set_count_maps(sets[s]); m++) {
      const vr_photon_map *pm = vr_photon_set_map(sets[s], m);
      const unsigned char *rec;
      size_t n = vr_photon_map_staged(pm, &rec);
      if (n) bytes += 16 + n * vr_photon_map_record_size(pm);
    }
  unsigned char *mine = malloc(bytes ? bytes : 1), *p = mine;
  vr_status st = mine ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory for the photons");
  st = vr_ranks_sync(r, st, err);
  if (st) {
    free(mine);
    return st;
  }
  for (int s = 0; s < nsets; s++)
    for (int m = 0; sets[s] && m < vr_photon_set_count_maps(sets[s]); m++) {
      const vr_photon_map *pm = vr_photon_set_map(sets[s], m);
      const unsigned char *rec;
      uint64_t n = vr_photon_map_staged(pm, &rec);
      if (!n) continue;
      uint32_t head[2] = {(uint32_t)s, (uint32_t)m};
      memcpy(p, head, 8);
      memcpy(p + 8, &n, 8);
      memcpy(p + 16, rec, n * vr_photon_map_record_size(pm));
      p += 16 + n * vr_photon_map_record_size(pm);
    }
  unsigned char *all = NULL;
  size_t *counts = NULL;
  st = vr_comm_gather_bytes(r->comm, mine, bytes, &all, &counts, err);
  free(mine);
  /* The others' records join this rank's maps. */
  size_t at = 0;
  for (int k = 0; !st && k < r->nranks; k++) {
    size_t end = at + counts[k];
    while (k != r->rank && !st && at + 16 <= end) {
      uint32_t head[2];
      uint64_t n;
      memcpy(head, all + at, 8);
      memcpy(&n, all + at + 8, 8);
      vr_photon_set *set = head[0] < (uint32_t)nsets ? sets[head[0]] : NULL;
      vr_photon_map *pm = set ? (vr_photon_map *)vr_photon_set_map(set, (int)head[1]) : NULL;
      size_t rs = vr_photon_map_record_size(pm);
      if (!pm || !rs || n > (end - at - 16) / rs) {
        st = vr_error_set(err, VR_E_IO, "photons from rank %d: a malformed message", k);
        break;
      }
      st = vr_photon_map_add_records(pm, all + at + 16, (size_t)n, err);
      at += 16 + (size_t)n * rs;
    }
    at = end;
  }
  free(all);
  free(counts);
  return vr_ranks_sync(r, st, err);
}

vr_status vr_ranks_finish(vr_run *r, vr_rscene *rs, vr_render_result *res, vr_error *err) {
  int R = r->nranks, S = vr_domains_count(rs->d);
  res->ncells = (size_t)S;
  res->cell_seconds = calloc((size_t)S, sizeof *res->cell_seconds);
  res->cell_ranks = calloc((size_t)S, sizeof *res->cell_ranks);
  if (!res->cell_seconds || !res->cell_ranks) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  r->mine.cells_loaded = 0;
  for (int c = 0; c < S; c++) {
    res->cell_seconds[c] = 1e-9 * (double)rs->cell_total_ns[c];
    res->cell_ranks[c] = vr_domains_loaded(rs->d, c);
    r->mine.cells_loaded += res->cell_ranks[c];
  }
  res->ranks = R;
  res->rank_stats = calloc((size_t)R, sizeof *res->rank_stats);
  vr_status st = res->rank_stats ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  r->mine.peak_rss_bytes = vr_peak_rss_bytes();
  r->mine.cell_loads = res->cell_loads;
  r->mine.load_seconds = res->cell_load_seconds;
  r->mine.peak_cells_bytes = res->peak_cells_bytes;
  if (R == 1) {
    if (!st) res->rank_stats[0] = r->mine;
    return st;
  }
  st = vr_ranks_sync(r, st, err);
  if (st) return st;
  /* Counts add up; peaks are the largest of any rank. */
  uint64_t sum[12] = {res->rays_camera, res->rays_shadow, res->rays_photon, res->rays_other,
                      res->crossings, res->rays_created, res->rays_finished, res->rays_spilled,
                      res->cell_loads, res->cell_unloads, res->cell_bytes_read, 0};
  double secs[1] = {res->cell_load_seconds};
  uint64_t mx[7] = {res->peak_cells_bytes, res->peak_geometry_bytes, res->peak_embree_bytes,
                    res->peak_queue_bytes, res->peak_map_bytes, res->peak_spill_bytes,
                    res->peak_uncounted_bytes};
  st = vr_comm_sum_u64(r->comm, sum, 12, err);
  if (!st) st = vr_comm_sum_doubles(r->comm, secs, 1, err);
  if (!st) st = vr_comm_sum_doubles(r->comm, res->cell_seconds, (size_t)S, err);
  uint64_t *held = st ? NULL : calloc((size_t)S, sizeof *held);
  if (!st && !held) st = vr_error_set(err, VR_E_NOMEM, "out of memory");
  for (int c = 0; !st && c < S; c++) held[c] = (uint64_t)res->cell_ranks[c];
  if (!st) st = vr_comm_sum_u64(r->comm, held, (size_t)S, err);
  for (int c = 0; !st && c < S; c++) res->cell_ranks[c] = (int)held[c];
  free(held);
  if (!st) st = vr_comm_max_u64(r->comm, mx, 7, err);
  unsigned char *all = NULL;
  if (!st) st = vr_comm_gather_bytes(r->comm, &r->mine, sizeof r->mine, &all, NULL, err);
  if (st) return st;
  res->rays_camera = sum[0], res->rays_shadow = sum[1], res->rays_photon = sum[2];
  res->rays_other = sum[3], res->crossings = sum[4], res->rays_created = sum[5];
  res->rays_finished = sum[6], res->rays_spilled = sum[7], res->cell_loads = sum[8];
  res->cell_unloads = sum[9], res->cell_bytes_read = sum[10];
  res->cell_load_seconds = secs[0];
  res->peak_cells_bytes = (size_t)mx[0], res->peak_geometry_bytes = (size_t)mx[1];
  res->peak_embree_bytes = (size_t)mx[2], res->peak_queue_bytes = (size_t)mx[3];
  res->peak_map_bytes = (size_t)mx[4], res->peak_spill_bytes = (size_t)mx[5];
  res->peak_uncounted_bytes = (size_t)mx[6];
  memcpy(res->rank_stats, all, (size_t)R * sizeof *res->rank_stats);
  free(all);
  return VR_OK;
}
