/* vr-rgb2spec --per-pixel: a spectral texture from the photos, one
 * reflectance spectrum per pixel, written as a spectral OpenEXR in the
 * layout of Fichet, Pacanowski and Wilkie (JCGT 2021; reflective channels
 * "T.<nm>nm") with an sRGB-linear preview under D65, and, with --texture
 * NAME, referenced from the material database.
 *
 * Every pixel goes through the same linear map: the Matrix-R fundamental
 * metamer r = P c of its stacked linear responses c (P = A^+, computed once
 * by vr_recovery_matrix), then clamped into [0, 1] so that the texture is
 * physically possible; the fraction of samples clamped is reported, and so
 * is the RGB round trip after clamping, which is what the clamp costs.
 * The per-region methods (bounded, regularised) solve a problem per
 * region and are not used here: one matrix product per pixel is what makes
 * 12-megapixel photos practical (bench_rgb2spec).
 *
 * Decoding: integer photos go through a table of their decoded values
 * (manifest encoding or the camera's stored tone curve, vr_capture_decode),
 * float photos through vr_capture_decode directly. */
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "rgb2spec.h"
#include "vr/camera.h"
#include "vr/colour.h"
#include "vr/file.h"
#include "vr/sha256.h"
#include "vr/spectral_exr.h"
#include "vr/version.h"

typedef struct job {
  const rg_run *run;
  const vr_image *img;        /* nphotos */
  float *lut[RGB2SPEC_MAX_LIGHTS][3]; /* decoded values of integer photos, or NULL */
  int levels[RGB2SPEC_MAX_LIGHTS];
  const double *P;            /* n x 3L */
  const double *A;            /* 3L x n */
  const double *preview;      /* 3 x n: sRGB-linear responses under D65 */
  vr_spectral_image *out;
  vr_image *rgb;
  int y0, y1;
  /* results of this slice */
  double clamped, samples, rt_se, rt_n;
  double *sum;                /* n */
} job;

static double decode(const job *j, size_t l, int ch, float v) {
  if (j->lut[l][ch]) {
    long k = lrint((double)v * (j->levels[l] - 1));
    if (k < 0) k = 0;
    if (k >= j->levels[l]) k = j->levels[l] - 1;
    return j->lut[l][ch][k];
  }
  const rg_run *run = j->run;
  return vr_capture_decode(run->cap, run->photo[l], ch, v, false);
}

static void *work(void *arg) {
  job *j = arg;
  const rg_run *run = j->run;
  size_t n = run->n, m = 3 * run->nphotos;
  int W = j->img[0].width;
  double c[3 * RGB2SPEC_MAX_LIGHTS], r[1024];
  for (int y = j->y0; y < j->y1; y++)
    for (int x = 0; x < W; x++) {
      size_t px = (size_t)y * (size_t)W + (size_t)x;
      for (size_t l = 0; l < run->nphotos; l++)
        for (int ch = 0; ch < 3; ch++) c[3 * l + ch] = decode(j, l, ch, j->img[l].data[px * 3 + (size_t)ch]);
      for (size_t i = 0; i < n; i++) {
        double v = 0;
        for (size_t k = 0; k < m; k++) v += j->P[i * m + k] * c[k];
        if (v < 0 || v > 1) {
          j->clamped++;
          v = v < 0 ? 0 : 1;
        }
        r[i] = v;
        j->sum[i] += v;
        j->out->data[px * n + i] = (float)v;
      }
      j->samples += (double)n;
      for (size_t k = 0; k < m; k++) {
        double v = 0;
        for (size_t i = 0; i < n; i++) v += j->A[k * n + i] * r[i];
        j->rt_se += (v - c[k]) * (v - c[k]);
      }
      j->rt_n += (double)m;
      for (int ch = 0; ch < 3; ch++) {
        double v = 0;
        for (size_t i = 0; i < n; i++) v += j->preview[(size_t)ch * n + i] * r[i];
        j->rgb->data[px * 3 + (size_t)ch] = (float)v;
      }
    }
  return NULL;
}

vr_status rg_per_pixel(const rg_run *run, const vr_image *img, const char *path, int threads,
                       rg_pixels *res, vr_error *err) {
  size_t n = run->n, m = 3 * run->nphotos;
  memset(res, 0, sizeof *res);
  if (n > 1024) return vr_error_set(err, VR_E_ARG, "--per-pixel: at most 1024 grid samples");
  if (threads < 1) threads = 1;
  int H = img[0].height, W = img[0].width;
  double *P = malloc(n * m * sizeof *P), *preview = malloc(3 * n * sizeof *preview);
  job *jobs = calloc((size_t)threads, sizeof *jobs);
  pthread_t *tid = calloc((size_t)threads, sizeof *tid);
  vr_spectral_image out = {0};
  vr_image rgb = {0};
  vr_camera *srgb = NULL;
  vr_spectrum *d65 = NULL;
  float *luts[RGB2SPEC_MAX_LIGHTS][3] = {{0}};
  vr_status st = VR_OK;
  if (!P || !preview || !jobs || !tid) {
    st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
    goto done;
  }
  if ((st = vr_recovery_matrix(run->sys, P))) goto done;
  if (!(srgb = vr_camera_create_srgb(n, run->grid, err)) || !(d65 = vr_illuminant("D65", err))) {
    st = err ? err->status : VR_E_ARG;
    goto done;
  }
  if ((st = vr_camera_response(srgb, d65, preview, err))) goto done;
  if ((st = vr_spectral_image_alloc(&out, W, H, n, run->grid, VR_SPECTRAL_REFLECTIVE, err))) goto done;
  if ((st = vr_image_alloc(&rgb, W, H, err))) goto done;
  /* Decoding tables for integer photos (8 or 16 bit). */
  int levels[RGB2SPEC_MAX_LIGHTS] = {0};
  for (size_t l = 0; l < run->nphotos; l++) {
    if (img[l].bit_depth != 8 && img[l].bit_depth != 16) continue;
    levels[l] = img[l].bit_depth == 8 ? 256 : 65536;
    bool srgb_enc = run->photo[l]->encoding ? run->photo[l]->encoding == 1 : true;
    for (int ch = 0; ch < 3; ch++) {
      if (!(luts[l][ch] = malloc((size_t)levels[l] * sizeof(float)))) {
        st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
        goto done;
      }
      for (int k = 0; k < levels[l]; k++)
        luts[l][ch][k] = (float)vr_capture_decode(run->cap, run->photo[l], ch,
                                                  (double)k / (levels[l] - 1), srgb_enc);
    }
  }
  for (int t = 0; t < threads; t++) {
    job *j = &jobs[t];
    j->run = run;
    j->img = img;
    memcpy(j->lut, luts, sizeof luts);
    memcpy(j->levels, levels, sizeof levels);
    j->P = P;
    j->A = vr_recovery_system_matrix(run->sys);
    j->preview = preview;
    j->out = &out;
    j->rgb = &rgb;
    j->y0 = (int)((long)H * t / threads);
    j->y1 = (int)((long)H * (t + 1) / threads);
    if (!(j->sum = calloc(n, sizeof *j->sum))) {
      st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
      goto done;
    }
  }
  int started = 0;
  for (int t = 1; t < threads; t++) {
    if (pthread_create(&tid[t], NULL, work, &jobs[t])) break;
    started = t;
  }
  work(&jobs[0]);
  for (int t = 1; t <= started; t++) pthread_join(tid[t], NULL);
  for (int t = started + 1; t < threads; t++) work(&jobs[t]);
  res->mean = calloc(n, sizeof *res->mean);
  if (!res->mean) {
    st = vr_error_set(err, VR_E_NOMEM, "--per-pixel: out of memory");
    goto done;
  }
  double clamped = 0, samples = 0, se = 0, cnt = 0;
  for (int t = 0; t < threads; t++) {
    clamped += jobs[t].clamped;
    samples += jobs[t].samples;
    se += jobs[t].rt_se;
    cnt += jobs[t].rt_n;
    for (size_t i = 0; i < n; i++) res->mean[i] += jobs[t].sum[i];
  }
  for (size_t i = 0; i < n; i++) res->mean[i] /= (double)W * H;
  res->pixels = (long)W * H;
  res->clamped_fraction = samples > 0 ? clamped / samples : 0;
  res->rgb_rms = cnt > 0 ? sqrt(se / cnt) : 0;
  st = vr_spectral_exr_write(path, &out, &rgb, NULL, err);
done:
  for (int t = 0; jobs && t < threads; t++) free(jobs[t].sum);
  for (size_t l = 0; l < RGB2SPEC_MAX_LIGHTS; l++)
    for (int ch = 0; ch < 3; ch++) free(luts[l][ch]);
  free(jobs);
  free(tid);
  free(P);
  free(preview);
  vr_spectral_image_free(&out);
  vr_image_free(&rgb);
  vr_camera_destroy(srgb);
  vr_spectrum_destroy(d65);
  if (st) free(res->mean), res->mean = NULL;
  return st;
}

vr_status rg_save_texture(vr_matdb *db, const char *name, const char *path, const rg_run *run,
                          const rg_pixels *px, vr_error *err) {
  unsigned char *bytes = NULL;
  size_t len = 0;
  vr_status st = vr_read_file(path, 0, (char **)&bytes, &len, err);
  if (st) return st;
  vr_sha256 h;
  char hex[65];
  vr_sha256_init(&h);
  vr_sha256_update(&h, bytes, len);
  vr_sha256_final(&h, hex);
  free(bytes);
  char *abs = realpath(path, NULL);
  vr_material *m = vr_material_create(name, VR_KIND_REFLECTANCE, err);
  if (!m || !abs) {
    free(abs);
    vr_material_destroy(m);
    return m ? vr_error_set(err, VR_E_IO, "%s: cannot resolve the path", path) : err->status;
  }
  vr_spectrum *mean = vr_spectrum_create(run->n, run->grid, px->mean, err);
  char model[160];
  snprintf(model, sizeof model, "Matrix R per pixel, clamped to [0,1] (%.3g %% of samples), %zu lights",
           100 * px->clamped_fraction, run->nphotos);
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
  if (!st) {
    m->prov.residual = px->rgb_rms;
    st = vr_matdb_save(db, m, err);
  }
  free(abs);
  vr_material_destroy(m);
  return st;
}
