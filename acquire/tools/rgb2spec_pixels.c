/* vr-rgb2spec --per-pixel: a spectral texture from the photos, one
 * reflectance spectrum per pixel, written as a spectral OpenEXR in the
 * layout of Fichet, Pacanowski and Wilkie (JCGT 2021; reflective channels
 * "T.<nm>nm") with an sRGB-linear preview under D65 and a "flags" channel
 * (VR_PIXEL_* bits: clipped, bounded, misfit, ...), and, with --texture
 * NAME, referenced from the material database.
 *
 * Every pixel gets the regions' prior and bounds (vr/recover_pixel.h): the
 * regularised estimate through a precomputed operator, the bounded
 * correction only where it leaves [0, 1].  Its weights are the per-pixel
 * noise measured in the regions (median over the regions of each channel's
 * pixel scatter and code step), its lambda the median over the regions of
 * the one that minimises a single pixel's expected predictive risk
 * (vr_recover_pixel_lambda).
 *
 * The pixels are recovered chunk by chunk inside the EXR writer's workers
 * (vr_spectral_exr_write_rows), so recovery and compression share the
 * threads and the texture is never held whole in memory.
 *
 * Decoding: integer photos go through tables of their decoded values and
 * clip marks (manifest encoding or the camera's stored tone curve,
 * vr_capture_decode), float photos through vr_capture_decode directly. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "rgb2spec.h"
#include "vr/camera.h"
#include "vr/colour.h"
#include "vr/file.h"
#include "vr/recover_pixel.h"
#include "vr/sha256.h"
#include "vr/version.h"

typedef float v4f __attribute__((vector_size(16)));

typedef struct tstats {
  vr_pixel_workspace *ws;
  float *crow;           /* one row's decoded responses, pixel-major (width x m) */
  int32_t *code;         /* one row of one photo's codes (width x 3) */
  unsigned char *clrow;  /* one row: 1 where a pixel has a clipped channel */
  unsigned char *mrow;   /* one row's clip marks, pixel-major (width x m) */
  long pixels, bounded, clipped, misfit, no_data, fallback;
  double chi2_per_channel;
  double *sum;        /* n */
  long *rpix;         /* nregions */
  double *rse_patch, *rse_ref; /* nregions: sums of squared differences */
} tstats;

typedef struct ctx {
  const rg_run *run;
  const vr_image *img;
  size_t L, m, n;
  int width;
  float *lut[RGB2SPEC_MAX_LIGHTS][3];         /* integer photos: decoded value per code */
  unsigned char *clip[RGB2SPEC_MAX_LIGHTS];   /* integer photos: clip mark per code */
  int levels[RGB2SPEC_MAX_LIGHTS];
  double **ref;                               /* nregions: reference on the grid or NULL */
  double **patch;                             /* nregions: the region's spectrum, in [0, 1] */
  tstats *ts;
} ctx;

static float decode_float(const ctx *x, size_t l, int ch, float v, unsigned char *mark) {
  const vr_capture_photo *p = x->run->photo[l];
  *mark = v >= p->clip ? VR_CLIP_HIGH : VR_CLIP_NONE;
  return (float)vr_capture_decode(x->run->cap, p, ch, v, false);
}

/* The table lookups of one row of an integer photo held as its codes
 * (vr_image_read_codes): decoded response and clip mark per code. */
#define LOOKUP_ROW(T)                                                             \
  do {                                                                            \
    const T *k = (const T *)x->img[l].codes + (size_t)y * W * 3;                  \
    for (size_t px = 0; px < W; px++, k += 3) {                                   \
      float *c = t->crow + px * m + 3 * l;                                        \
      unsigned char *mk = t->mrow + px * m + 3 * l;                               \
      c[0] = lut[0][k[0]], c[1] = lut[1][k[1]], c[2] = lut[2][k[2]];              \
      mk[0] = clip[k[0]], mk[1] = clip[k[1]], mk[2] = clip[k[2]];                 \
      t->clrow[px] |= (mk[0] | mk[1] | mk[2]) != VR_CLIP_NONE;                    \
    }                                                                             \
  } while (0)

/* Row y of every photo into t->crow (decoded responses), t->mrow (clip
 * marks) and t->clrow (any channel clipped), pixel by pixel.  Integer
 * photos kept as codes go straight through the tables; integer photos
 * read as floats in two simple passes per photo: their values (code /
 * (levels - 1), as read) back to codes, a loop the compiler vectorises,
 * then the table lookups. */
static void decode_row(const ctx *x, tstats *t, int y) {
  const size_t W = (size_t)x->width, m = x->m;
  memset(t->clrow, 0, W);
  for (size_t l = 0; l < x->L; l++) {
    if (x->img[l].codes) {
      /* The table marks code 0 and the codes from the first clipped one up
       * (rg_per_pixel); loads, no branch. */
      const unsigned char *clip = x->clip[l];
      const float *lut[3] = {x->lut[l][0], x->lut[l][1], x->lut[l][2]};
      if (x->img[l].bit_depth == 8) LOOKUP_ROW(uint8_t);
      else LOOKUP_ROW(uint16_t);
      continue;
    }
    const float *v = x->img[l].data + (size_t)y * W * 3;
    if (!x->lut[l][0]) {
      for (size_t px = 0; px < W; px++)
        for (int ch = 0; ch < 3; ch++) {
          const size_t i = px * m + 3 * l + (size_t)ch;
          t->crow[i] = decode_float(x, l, ch, v[px * 3 + (size_t)ch], &t->mrow[i]);
          t->clrow[px] |= t->mrow[i] != VR_CLIP_NONE;
        }
      continue;
    }
    int32_t *code = t->code;
    const float scale = (float)(x->levels[l] - 1), top = scale;
    size_t i = 0;
#ifdef __SSE2__
    const __m128 vs = _mm_set1_ps(scale), vh = _mm_set1_ps(0.5f), vt = _mm_set1_ps(top),
                 vz = _mm_setzero_ps();
    for (; i + 4 <= 3 * W; i += 4) {
      __m128 f = _mm_add_ps(_mm_mul_ps(_mm_loadu_ps(v + i), vs), vh);
      f = _mm_min_ps(_mm_max_ps(f, vz), vt);
      _mm_storeu_si128((__m128i *)(code + i), _mm_cvttps_epi32(f));
    }
#endif
    for (; i < 3 * W; i++) {
      float f = v[i] * scale + 0.5f; /* integer photos hold exact codes: never NaN */
      f = f < 0.0f ? 0.0f : f;
      f = f > top ? top : f;
      code[i] = (int32_t)f;
    }
    const unsigned char *clip = x->clip[l];
    const float *lut[3] = {x->lut[l][0], x->lut[l][1], x->lut[l][2]};
    for (size_t px = 0; px < W; px++) {
      float *c = t->crow + px * m + 3 * l;
      unsigned char *mk = t->mrow + px * m + 3 * l;
      unsigned char any = 0;
      for (int ch = 0; ch < 3; ch++) {
        const int32_t k = code[3 * px + (size_t)ch];
        c[ch] = lut[ch][k];
        /* The table marks code 0 and the codes from the first clipped one
         * up (rg_per_pixel); a load, no branch. */
        mk[ch] = clip[k];
        any |= mk[ch];
      }
      t->clrow[px] |= any != VR_CLIP_NONE;
    }
  }
}

static vr_status fill_rows(void *user, int thread, int y0, int y1, float *spectra, float *rgb,
                           uint32_t *flags, vr_error *err) {
  (void)err;
  ctx *x = user;
  tstats *t = &x->ts[thread];
  size_t n = x->n, m = x->m, W = (size_t)x->width;
  float rowsum[1024];
  struct {
    long bounded, clipped, misfit, no_data, fallback;
  } cnt = {0, 0, 0, 0, 0};
  for (int y = y0; y < y1; y++) {
    float chi2sum = 0.0f; /* one row: a few thousand values of order 1 */
    /* A row's spectra summed in float (at most a few thousand values in
     * [0, 1]: 1e-4 relative at worst), then into the double totals. */
    memset(rowsum, 0, n * sizeof *rowsum);
    decode_row(x, t, y);
    for (size_t px = 0; px < W; px++) {
      size_t out = (size_t)(y - y0) * W + px;
      const bool any_clip = t->clrow[px] != 0;
      const float *c = t->crow + px * m;
      const unsigned char *marks = t->mrow + px * m;
      float chi2;
      float *r = spectra + out * n;
      unsigned f = vr_pixel_recover(t->ws, c, any_clip ? marks : NULL, r, rgb + out * 3, &chi2);
      flags[out] = f;
      if (f) {
        cnt.bounded += (f & VR_PIXEL_BOUNDED) != 0;
        cnt.clipped += (f & (VR_PIXEL_CLIPPED_HIGH | VR_PIXEL_CLIPPED_LOW)) != 0;
        cnt.misfit += (f & VR_PIXEL_MISFIT) != 0;
        cnt.no_data += (f & VR_PIXEL_NO_DATA) != 0;
        cnt.fallback += (f & VR_PIXEL_FALLBACK) != 0;
      }
      size_t used = m;
      for (size_t i = 0; any_clip && i < m; i++) used -= marks[i] != VR_CLIP_NONE;
      if (used) chi2sum += chi2 / (float)used;
      for (size_t j = 0; j + 4 <= n; j += 4) {
        v4f a, b;
        memcpy(&a, rowsum + j, sizeof a);
        memcpy(&b, r + j, sizeof b);
        a += b;
        memcpy(rowsum + j, &a, sizeof a);
      }
      for (size_t j = n & ~(size_t)3; j < n; j++) rowsum[j] += r[j];
    }
    for (size_t j = 0; j < n; j++) t->sum[j] += rowsum[j];
    t->chi2_per_channel += chi2sum;
  }
  t->pixels += (long)(y1 - y0) * (long)W;
  t->bounded += cnt.bounded;
  t->clipped += cnt.clipped;
  t->misfit += cnt.misfit;
  t->no_data += cnt.no_data;
  t->fallback += cnt.fallback;
  /* The pixels of rect and chart regions against the regions' spectra. */
  const rg_run *run = x->run;
  for (size_t g = 0; g < run->nregions; g++) {
    const rg_region *rg = &run->regions[g];
    if (rg->box[2] <= rg->box[0]) continue;
    int ya = rg->box[1] > y0 ? rg->box[1] : y0, yb = rg->box[3] < y1 ? rg->box[3] : y1;
    int xa = rg->box[0] > 0 ? rg->box[0] : 0, xb = rg->box[2] < x->width ? rg->box[2] : x->width;
    for (int y = ya; y < yb; y++)
      for (int px = xa; px < xb; px++) {
        const float *r = spectra + ((size_t)(y - y0) * W + (size_t)px) * n;
        double e2 = 0.0, f2 = 0.0;
        for (size_t j = 0; j < n; j++) {
          double d = r[j] - x->patch[g][j];
          e2 += d * d;
          if (x->ref[g]) f2 += (r[j] - x->ref[g][j]) * (r[j] - x->ref[g][j]);
        }
        t->rpix[g]++;
        t->rse_patch[g] += e2 / (double)n;
        t->rse_ref[g] += f2 / (double)n;
      }
  }
  return VR_OK;
}

/* Per-pixel noise and lambda from the regions (see the file comment). */
static vr_status choose_noise(const rg_run *run, rg_pixels *res, vr_error *err) {
  size_t m = 3 * run->nphotos, R = run->nregions, k = 0;
  double *v = malloc(R * sizeof *v);
  if (!v) return vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
  for (size_t i = 0; i < m; i++) {
    k = 0;
    for (size_t g = 0; g < R; g++)
      if (run->regions[g].clipped[i] == VR_CLIP_NONE) v[k++] = run->regions[g].sigma_pixel[i];
    res->sigma[i] = k ? rg_median(v, k) : 1e-3;
  }
  k = 0;
  for (size_t g = 0; g < R; g++) {
    double lam;
    vr_error e = {0};
    if (vr_recover_pixel_lambda(run->sys, run->regions[g].c, res->sigma, run->regions[g].clipped,
                                &lam, &e) == VR_OK)
      v[k++] = lam;
  }
  if (!k) {
    free(v);
    return vr_error_set(err, VR_E_ARG, "--per-pixel: no region has two unclipped channels to "
                                       "choose the smoothing from");
  }
  res->lambda = rg_median(v, k);
  free(v);
  return VR_OK;
}

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

vr_status rg_per_pixel(const rg_run *run, const vr_image *img, const char *path,
                       const rg_pixel_options *opt, rg_pixels *res, vr_error *err) {
  size_t n = run->n, m = 3 * run->nphotos, R = run->nregions;
  int threads = opt->threads < 1 ? 1 : opt->threads;
  memset(res, 0, sizeof *res);
  double t0 = now();
  ctx x = {.run = run, .img = img, .L = run->nphotos, .m = m, .n = n, .width = img[0].width};
  vr_pixel_recovery *pr = NULL;
  vr_camera *srgb = NULL;
  vr_spectrum *d65 = NULL;
  double *preview = malloc(3 * n * sizeof *preview);
  x.ts = calloc((size_t)threads, sizeof *x.ts);
  x.ref = calloc(R, sizeof *x.ref);
  x.patch = calloc(R, sizeof *x.patch);
  vr_status st = VR_OK;
  if (!preview || !x.ts || !x.ref || !x.patch) {
    st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
    goto done;
  }
  if ((st = choose_noise(run, res, err))) goto done;
  if (!(srgb = vr_camera_create_srgb(n, run->grid, err)) || !(d65 = vr_illuminant("D65", err))) {
    st = err ? err->status : VR_E_ARG;
    goto done;
  }
  if ((st = vr_camera_response(srgb, d65, preview, err))) goto done;
  if (!(pr = vr_pixel_recovery_create(run->sys, res->sigma, res->lambda, preview, err))) {
    st = err ? err->status : VR_E_NOMEM;
    goto done;
  }
  for (size_t l = 0; l < run->nphotos; l++) {
    if (img[l].bit_depth != 8 && img[l].bit_depth != 16) continue;
    const vr_capture_photo *p = run->photo[l];
    int levels = x.levels[l] = img[l].bit_depth == 8 ? 256 : 65536;
    bool srgb_enc = p->encoding ? p->encoding == 1 : true;
    if (!(x.clip[l] = malloc((size_t)levels))) goto nomem;
    for (int k = levels - 1; k >= 0; k--) {
      double v = (double)k / (levels - 1);
      x.clip[l][k] = v >= p->clip ? VR_CLIP_HIGH : k == 0 ? VR_CLIP_LOW : VR_CLIP_NONE;
    }
    for (int ch = 0; ch < 3; ch++) {
      if (!(x.lut[l][ch] = malloc((size_t)levels * sizeof(float)))) goto nomem;
      for (int k = 0; k < levels; k++)
        x.lut[l][ch][k] = (float)vr_capture_decode(run->cap, p, ch, (double)k / (levels - 1), srgb_enc);
    }
  }
  for (size_t g = 0; g < R; g++) {
    if (!(x.patch[g] = malloc(n * sizeof(double)))) goto nomem;
    for (size_t j = 0; j < n; j++) x.patch[g][j] = fmin(fmax(run->regions[g].r[j], 0.0), 1.0);
    const vr_spectrum *ref = run->regions[g].def->reference;
    if (!ref) continue;
    if (!(x.ref[g] = malloc(n * sizeof(double)))) goto nomem;
    for (size_t j = 0; j < n; j++) x.ref[g][j] = vr_spectrum_eval(ref, run->grid[j], VR_INTERP_LINEAR);
  }
  for (int t = 0; t < threads; t++) {
    tstats *ts = &x.ts[t];
    if (!(ts->ws = vr_pixel_workspace_create(pr, err))) {
      st = err ? err->status : VR_E_NOMEM;
      goto done;
    }
    ts->sum = calloc(n, sizeof *ts->sum);
    ts->crow = malloc((size_t)x.width * m * sizeof *ts->crow);
    ts->mrow = malloc((size_t)x.width * m);
    ts->clrow = malloc((size_t)x.width);
    ts->code = malloc((size_t)x.width * 3 * sizeof *ts->code);
    if (!ts->crow || !ts->mrow || !ts->clrow || !ts->code) goto nomem;
    ts->rpix = calloc(R, sizeof *ts->rpix);
    ts->rse_patch = calloc(R, sizeof *ts->rse_patch);
    ts->rse_ref = calloc(R, sizeof *ts->rse_ref);
    if (!ts->sum || !ts->rpix || !ts->rse_patch || !ts->rse_ref) goto nomem;
  }
  static const char *const attr_names[] = {"flagsMeaning", "recoveryMethod"};
  char method[256];
  snprintf(method, sizeof method, "vr-rgb2spec per pixel: regularised (second differences, "
           "lambda %.4g on 1/sigma-weighted responses), bounded to [0,1], %zu lights", res->lambda,
           run->nphotos);
  const char *attr_values[] = {"bit 0: a channel clipped high; 1: a channel at code 0; 2: the "
                               "linear estimate left [0,1] (bounded correction); 3: misfit beyond "
                               "the noise (chi2 > 99.9 % point); 4: no data; 5: general solver",
                               method};
  vr_spectral_exr_layout lay = {.width = img[0].width, .height = img[0].height, .nbands = n,
                                .wavelengths_nm = run->grid, .kind = VR_SPECTRAL_REFLECTIVE,
                                .half = opt->half, .rgb = 1, .flags_channel = "flags",
                                .nattrs = 2, .attr_names = attr_names, .attr_values = attr_values,
                                .compression = opt->compression, .threads = threads};
  if ((st = vr_spectral_exr_write_rows(path, &lay, fill_rows, &x, err))) goto done;
  if (!(res->mean = calloc(n, sizeof *res->mean)) || !(res->region_pixels = calloc(R, sizeof(long))) ||
      !(res->region_rmse_patch = calloc(R, sizeof(double))) ||
      !(res->region_rmse_ref = calloc(R, sizeof(double))))
    goto nomem;
  double sp = 0.0, sr = 0.0;
  long cp = 0, cr = 0;
  for (int t = 0; t < threads; t++) {
    tstats *ts = &x.ts[t];
    res->pixels += ts->pixels;
    res->bounded += ts->bounded;
    res->clipped += ts->clipped;
    res->misfit += ts->misfit;
    res->no_data += ts->no_data;
    res->fallback += ts->fallback;
    res->chi2_per_channel += ts->chi2_per_channel;
    for (size_t j = 0; j < n; j++) res->mean[j] += ts->sum[j];
    for (size_t g = 0; g < R; g++) {
      res->region_pixels[g] += ts->rpix[g];
      res->region_rmse_patch[g] += ts->rse_patch[g];
      res->region_rmse_ref[g] += ts->rse_ref[g];
    }
  }
  for (size_t j = 0; j < n; j++) res->mean[j] /= (double)res->pixels;
  res->chi2_per_channel /= (double)res->pixels;
  for (size_t g = 0; g < R; g++) {
    long k = res->region_pixels[g];
    sp += res->region_rmse_patch[g];
    cp += k;
    if (x.ref[g]) sr += res->region_rmse_ref[g], cr += k;
    res->region_rmse_patch[g] = k ? sqrt(res->region_rmse_patch[g] / (double)k) : NAN;
    res->region_rmse_ref[g] = k && x.ref[g] ? sqrt(res->region_rmse_ref[g] / (double)k) : NAN;
  }
  res->rmse_patch = cp ? sqrt(sp / (double)cp) : NAN;
  res->rmse_ref = cr ? sqrt(sr / (double)cr) : NAN;
  res->seconds = now() - t0;
  goto done;
nomem:
  st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
done:
  for (int t = 0; x.ts && t < threads; t++) {
    vr_pixel_workspace_destroy(x.ts[t].ws);
    free(x.ts[t].sum);
    free(x.ts[t].crow);
    free(x.ts[t].mrow);
    free(x.ts[t].clrow);
    free(x.ts[t].code);
    free(x.ts[t].rpix);
    free(x.ts[t].rse_patch);
    free(x.ts[t].rse_ref);
  }
  free(x.ts);
  for (size_t g = 0; x.ref && g < R; g++) free(x.ref[g]);
  for (size_t g = 0; x.patch && g < R; g++) free(x.patch[g]);
  free(x.ref);
  free(x.patch);
  for (size_t l = 0; l < RGB2SPEC_MAX_LIGHTS; l++) {
    free(x.clip[l]);
    for (int ch = 0; ch < 3; ch++) free(x.lut[l][ch]);
  }
  vr_pixel_recovery_destroy(pr);
  vr_camera_destroy(srgb);
  vr_spectrum_destroy(d65);
  free(preview);
  if (st) rg_pixels_free(res);
  return st;
}

void rg_pixels_free(rg_pixels *px) {
  free(px->mean);
  free(px->region_pixels);
  free(px->region_rmse_patch);
  free(px->region_rmse_ref);
  px->mean = NULL;
  px->region_pixels = NULL;
  px->region_rmse_patch = px->region_rmse_ref = NULL;
}

void rg_print_pixels(FILE *out, const rg_run *run, const rg_pixels *px, const char *path) {
  double P = (double)px->pixels;
  fprintf(out, "per-pixel: %ld pixels into %s (%zu bands, regularised, lambda %.3g) in %.2f s "
               "(%.2f Mpixel/s)\n", px->pixels, path, run->n, px->lambda, px->seconds,
          1e-6 * P / px->seconds);
  fprintf(out, "per-pixel: %.2f %% bounded to [0, 1], %.2f %% with clipped channels, %.2f %% misfit "
               "beyond the noise, %.2f %% no data, %ld through the general solver; mean chi2 per "
               "channel %.3g\n", 100 * px->bounded / P, 100 * px->clipped / P, 100 * px->misfit / P,
          100 * px->no_data / P, px->fallback, px->chi2_per_channel);
  if (!isnan(px->rmse_patch))
    fprintf(out, "per-pixel: region pixels against the patch recovery RMSE %.4f%s", px->rmse_patch,
            isnan(px->rmse_ref) ? "\n" : "");
  if (!isnan(px->rmse_patch) && !isnan(px->rmse_ref))
    fprintf(out, ", against the references RMSE %.4f\n", px->rmse_ref);
}

/* The absolute name of path, which need not exist yet: its folder
 * resolved, then its last component.  malloc'ed; NULL if the folder cannot
 * be resolved. */
static char *absolute_name(const char *path) {
  const char *slash = strrchr(path, '/');
  char *dir = slash ? strndup(path, slash == path ? 1 : (size_t)(slash - path)) : strdup(".");
  char *rdir = dir ? realpath(dir, NULL) : NULL;
  free(dir);
  if (!rdir) return NULL;
  const char *base = slash ? slash + 1 : path;
  size_t n = strlen(rdir) + strlen(base) + 2;
  char *abs = malloc(n);
  if (abs) snprintf(abs, n, "%s%s%s", rdir, strcmp(rdir, "/") ? "/" : "", base);
  free(rdir);
  return abs;
}

vr_status rg_save_texture(vr_matdb *db, const char *name, const char *written, const char *final,
                          const rg_run *run, const rg_pixels *px, bool forced, vr_error *err) {
  unsigned char *bytes = NULL;
  size_t len = 0;
  vr_status st = vr_read_file(written, 0, (char **)&bytes, &len, err);
  if (st) return st;
  vr_sha256 h;
  char hex[65];
  vr_sha256_init(&h);
  vr_sha256_update(&h, bytes, len);
  vr_sha256_final(&h, hex);
  free(bytes);
  char *abs = absolute_name(final);
  vr_material *m = vr_material_create(name, VR_KIND_REFLECTANCE, err);
  if (!m || !abs) {
    free(abs);
    vr_material_destroy(m);
    return m ? vr_error_set(err, VR_E_IO, "%s: cannot resolve the path", final) : err->status;
  }
  vr_spectrum *mean = vr_spectrum_create(run->n, run->grid, px->mean, err);
  char model[160];
  snprintf(model, sizeof model, "regularised per pixel (lambda %.3g), bounded to [0,1] "
           "(%.3g %% of pixels), %zu lights", px->lambda, 100.0 * (double)px->bounded /
           (double)px->pixels, run->nphotos);
  if (!mean) st = err->status;
  if (!st) st = vr_material_add_spectrum(m, "value", mean, err);
  if (!st) st = vr_material_add_property(m, "texture", abs, NAN, NULL, err);
  if (!st) st = vr_material_add_property(m, "texture_sha256", hex, NAN, NULL, err);
  if (!st) st = vr_material_add_property(m, "texture_layout", "spectral OpenEXR, Fichet et al. 2021, reflective", NAN, NULL, err);
  if (!st) st = vr_material_add_property(m, "texture_pixels", NULL, (double)px->pixels, NULL, err);
  if (!st) st = vr_material_set_text(&m->description, "spectral texture recovered from photos; "
                                                      "'value' is its mean reflectance", err);
  if (!st) st = vr_material_set_text(&m->prov.source_path, run->cap->path, err);
  if (!st) st = vr_material_set_text(&m->prov.tool, "vr-rgb2spec --per-pixel", err);
  if (!st) st = vr_material_set_text(&m->prov.tool_version, vr_version(), err);
  if (!st) st = vr_material_set_text(&m->prov.model, model, err);
  if (!st && isfinite(px->rmse_patch))
    st = vr_material_add_property(m, "texture_rmse_vs_patches", NULL, px->rmse_patch, NULL, err);
  if (!st) st = vr_material_add_property(m, "fit_forced", NULL, forced ? 1 : 0, NULL, err);
  if (!st && forced)
    st = vr_material_set_text(&m->prov.note, "saved with --force although some regions miss their photos "
                                             "or a light disagrees with its photo", err);
  if (!st) {
    m->prov.residual = px->chi2_per_channel;
    st = vr_matdb_save(db, m, err);
  }
  free(abs);
  vr_material_destroy(m);
  return st;
}
