/* Textures (textures/texture.h): loading, mip-maps and filtered lookups. */
#include "textures/texture.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/colour.h"
#include "vr/file.h"
#include "vr/image.h"
#include "vr/rgb_table.h"
#include "vr/sha256.h"
#include "vr/spectral_exr.h"

#define MAX_LEVELS 32

struct vr_texture {
  bool spectral, alpha;
  int levels, w[MAX_LEVELS], h[MAX_LEVELS];
  /* Per level, nc codes a texel over 65535: RGB and alpha (nc = 4), or
   * the nb bands of a spectral texture (nc = nb), values in [0, 1]. */
  uint16_t *px[MAX_LEVELS];
  size_t nc, nb;
  double *wl;
  const vr_rgb_table *tab;
  size_t bytes;
  double mean[3];
};

void vr_texture_destroy(vr_texture *t) {
  if (!t) return;
  for (int k = 0; k < t->levels; k++) free(t->px[k]);
  free(t->wl);
  free(t);
}

/* Level k + 1's extent of source texels for destination texel x: the box
 * [x n / m, (x + 1) n / m) of the n source texels for m = max(1, n / 2). */
static void box(int x, int n, int m, int *a, int *b) {
  *a = (int)((long)x * n / m);
  *b = (int)((long)(x + 1) * n / m);
  if (*b <= *a) *b = *a + 1;
}

/* Halves level k into k + 1. */
static vr_status next_level(vr_texture *t, int k, vr_error *err) {
  int w = t->w[k], h = t->h[k], W = w > 1 ? w / 2 : 1, H = h > 1 ? h / 2 : 1;
  size_t nc = t->nc, n = (size_t)W * (size_t)H * nc;
  double *acc = calloc(nc, sizeof *acc);
  t->px[k + 1] = malloc(n * sizeof(uint16_t));
  if (!acc || !t->px[k + 1]) {
    free(acc);
    free(t->px[k + 1]);
    t->px[k + 1] = NULL;
    return vr_error_set(err, VR_E_NOMEM, "out of memory for a texture's mip-maps");
  }
  for (int y = 0; y < H; y++) {
    int y0, y1;
    box(y, h, H, &y0, &y1);
    for (int x = 0; x < W; x++) {
      int x0, x1;
      box(x, w, W, &x0, &x1);
      memset(acc, 0, nc * sizeof *acc);
      for (int j = y0; j < y1; j++)
        for (int i = x0; i < x1; i++) {
          size_t at = ((size_t)j * (size_t)w + (size_t)i) * nc;
          for (size_t c = 0; c < nc; c++)
            acc[c] += t->px[k][at + c];
        }
      double inv = 1.0 / ((double)(y1 - y0) * (x1 - x0));
      size_t to = ((size_t)y * (size_t)W + (size_t)x) * nc;
      for (size_t c = 0; c < nc; c++) t->px[k + 1][to + c] = (uint16_t)(acc[c] * inv + 0.5);
    }
  }
  free(acc);
  t->w[k + 1] = W, t->h[k + 1] = H;
  t->bytes += n * sizeof(uint16_t);
  return VR_OK;
}

static vr_status build_mips(vr_texture *t, vr_error *err) {
  while (t->levels < MAX_LEVELS && (t->w[t->levels - 1] > 1 || t->h[t->levels - 1] > 1)) {
    vr_status st = next_level(t, t->levels - 1, err);
    if (st) return st;
    t->levels++;
  }
  return VR_OK;
}

static vr_status from_image(vr_image *img, const char *name, bool srgb, vr_texture **out,
                            vr_error *err) {
  *out = NULL;
  vr_error e = {0};
  const vr_rgb_table *tab = vr_rgb_table_get(&e);
  if (!tab) return vr_error_set(err, e.status, "texture '%s': %s", name, e.message);
  vr_texture *t = calloc(1, sizeof *t);
  size_t n = (size_t)img->width * (size_t)img->height;
  if (!t || !(t->px[0] = malloc(n * 4 * sizeof(uint16_t)))) {
    free(t);
    return vr_error_set(err, VR_E_NOMEM, "texture '%s': out of memory (%d x %d)", name, img->width,
                        img->height);
  }
  t->tab = tab;
  t->nc = 4;
  t->levels = 1, t->w[0] = img->width, t->h[0] = img->height;
  t->bytes = n * 4 * sizeof(uint16_t);
  t->alpha = img->alpha_data && img->transparent > 0;
  bool decode = srgb && img->bit_depth <= 16; /* integer samples only: float TIFF and EXR are linear */
  float lut[256];
  for (int i = 0; i < 256; i++) lut[i] = (float)vr_srgb_decode(i / 255.0);
  for (size_t i = 0; i < n; i++) {
    for (int c = 0; c < 3; c++) {
      double v = img->data[3 * i + (size_t)c];
      if (!(v > 0)) v = 0; /* NaN too */
      if (v > 1) v = 1;
      if (decode) v = img->bit_depth == 8 ? lut[(int)(v * 255 + 0.5)] : vr_srgb_decode(v);
      t->px[0][4 * i + (size_t)c] = (uint16_t)(v * 65535 + 0.5); /* v in [0, 1] */
      t->mean[c] += v / (double)n;
    }
    double a = img->alpha_data ? img->alpha_data[i] : 1;
    a = a > 0 ? (a < 1 ? a : 1) : 0;
    t->px[0][4 * i + 3] = (uint16_t)(a * 65535 + 0.5);
  }
  vr_status st = build_mips(t, err);
  if (st) {
    vr_error_prefix(err, "texture '%s': ", name);
    vr_texture_destroy(t);
    return st;
  }
  *out = t;
  return VR_OK;
}

vr_status vr_texture_load_rgb(const char *path, bool srgb, vr_texture **out, vr_error *err) {
  vr_image img;
  vr_status st = vr_image_read_alpha(path, &img, err);
  if (st) return st;
  st = from_image(&img, path, srgb, out, err);
  vr_image_free(&img);
  return st;
}

vr_status vr_texture_load_rgb_memory(const void *bytes, size_t len, const char *name, bool srgb,
                                     vr_texture **out, vr_error *err) {
  vr_image img;
  vr_status st = vr_image_decode_alpha(bytes, len, name, &img, err);
  if (st) return st;
  st = from_image(&img, name, srgb, out, err);
  vr_image_free(&img);
  return st;
}

vr_status vr_texture_load_spectral(const char *path, const char *sha256_hex, vr_texture **out,
                                   vr_error *err) {
  *out = NULL;
  char *buf;
  size_t len;
  vr_status st = vr_read_file(path, 0, &buf, &len, err);
  if (st) return vr_error_prefix(err, "spectral texture: "), st;
  if (sha256_hex) {
    vr_sha256 h;
    char hex[65];
    vr_sha256_init(&h);
    vr_sha256_update(&h, buf, len);
    vr_sha256_final(&h, hex);
    if (strcasecmp(hex, sha256_hex)) {
      free(buf);
      return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                         "spectral texture: its SHA-256 is %s, the database recorded %s (the file "
                         "changed since it was saved: save it again with vr-rgb2spec --texture)",
                         hex, sha256_hex);
    }
  }
  vr_spectral_image img;
  st = vr_spectral_exr_read_memory(buf, len, path, &img, NULL, err);
  free(buf);
  if (st) return st;
  if (img.kind != VR_SPECTRAL_REFLECTIVE) {
    vr_spectral_image_free(&img);
    return vr_error_at(err, VR_E_PARSE, path, 0, 0,
                       "spectral texture: its channels are emissive (S0.*), a reflectance "
                       "texture has reflective T.* channels");
  }
  size_t n = (size_t)img.width * (size_t)img.height * img.nbands;
  for (size_t i = 0; i < n; i++)
    if (!(img.data[i] >= 0 && img.data[i] <= 1.5f)) {
      size_t px = i / img.nbands;
      vr_error_at(err, VR_E_RANGE, path, 0, 0,
                  "spectral texture: pixel (%zu, %zu) band %.1f nm holds %g (a reflectance "
                  "in [0, 1] is expected)",
                  px % (size_t)img.width, px / (size_t)img.width,
                  img.wavelengths_nm[i % img.nbands], (double)img.data[i]);
      vr_spectral_image_free(&img);
      return VR_E_RANGE;
    }
  vr_texture *t = calloc(1, sizeof *t);
  if (!t || !(t->wl = malloc(img.nbands * sizeof *t->wl))) {
    free(t);
    vr_spectral_image_free(&img);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  t->spectral = true;
  t->nb = t->nc = img.nbands;
  memcpy(t->wl, img.wavelengths_nm, img.nbands * sizeof *t->wl);
  t->levels = 1, t->w[0] = img.width, t->h[0] = img.height;
  /* 16-bit codes: a step of 1.5e-5 in reflectance, half the floats'
   * memory; values over 1 (up to the 1.5 accepted) are held at 1. */
  if (!(t->px[0] = malloc(n * sizeof(uint16_t)))) {
    vr_texture_destroy(t);
    vr_spectral_image_free(&img);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  for (size_t i = 0; i < n; i++) {
    float v = img.data[i] < 1 ? img.data[i] : 1;
    t->px[0][i] = (uint16_t)(v * 65535 + 0.5f);
  }
  t->bytes = n * sizeof(uint16_t);
  vr_spectral_image_free(&img);
  if ((st = build_mips(t, err))) {
    vr_error_prefix(err, "%s: ", path);
    vr_texture_destroy(t);
    return st;
  }
  *out = t;
  return VR_OK;
}

size_t vr_texture_bytes(const vr_texture *t) { return t->bytes; }
void vr_texture_size(const vr_texture *t, int *w, int *h, int *levels) {
  *w = t->w[0], *h = t->h[0], *levels = t->levels;
}
bool vr_texture_is_spectral(const vr_texture *t) { return t->spectral; }
bool vr_texture_has_alpha(const vr_texture *t) { return t->alpha; }
void vr_texture_mean_rgb(const vr_texture *t, double rgb[3]) { memcpy(rgb, t->mean, sizeof t->mean); }

/* Bilinear weights and wrapped texel indices at (u, v) on a w x h level. */
typedef struct taps {
  size_t at[4];
  double wt[4];
} taps;

static int wrap(long i, int n) {
  long m = i % n;
  return (int)(m < 0 ? m + n : m);
}

static taps taps_at(int w, int h, double u, double v) {
  if (!isfinite(u)) u = 0;
  if (!isfinite(v)) v = 0;
  /* Keep the coordinates small before scaling (repeat). */
  u -= floor(u), v -= floor(v);
  double x = u * w - 0.5, y = (1.0 - v) * h - 0.5;
  double fx = floor(x), fy = floor(y), ax = x - fx, ay = y - fy;
  int x0 = wrap((long)fx, w), x1 = wrap((long)fx + 1, w), y0 = wrap((long)fy, h),
      y1 = wrap((long)fy + 1, h);
  taps t;
  t.at[0] = (size_t)y0 * (size_t)w + (size_t)x0, t.wt[0] = (1 - ax) * (1 - ay);
  t.at[1] = (size_t)y0 * (size_t)w + (size_t)x1, t.wt[1] = ax * (1 - ay);
  t.at[2] = (size_t)y1 * (size_t)w + (size_t)x0, t.wt[2] = (1 - ax) * ay;
  t.at[3] = (size_t)y1 * (size_t)w + (size_t)x1, t.wt[3] = ax * ay;
  return t;
}

/* The two levels a footprint reads and the weight of the second. */
static void levels_for(const vr_texture *t, double width, int *k0, int *k1, double *f) {
  int big = t->w[0] > t->h[0] ? t->w[0] : t->h[0];
  double lod = width > 0 && isfinite(width) ? log2(width * big) : 0;
  if (!(lod > 0)) lod = 0;
  if (lod >= t->levels - 1) {
    *k0 = *k1 = t->levels - 1, *f = 0;
    return;
  }
  *k0 = (int)lod, *k1 = *k0 + 1, *f = lod - *k0;
}

void vr_texture_rgb(const vr_texture *t, double u, double v, double width, double rgb[3]) {
  int k0, k1;
  double f;
  levels_for(t, width, &k0, &k1, &f);
  rgb[0] = rgb[1] = rgb[2] = 0;
  if (t->spectral) return;
  for (int l = 0; l < 2; l++) {
    int k = l ? k1 : k0;
    double lw = l ? f : 1 - f;
    if (!(lw > 0)) continue;
    taps tp = taps_at(t->w[k], t->h[k], u, v);
    for (int q = 0; q < 4; q++)
      for (int c = 0; c < 3; c++) rgb[c] += lw * tp.wt[q] * t->px[k][4 * tp.at[q] + (size_t)c];
  }
  for (int c = 0; c < 3; c++) rgb[c] /= 65535;
}

void vr_texture_eval(const vr_texture *t, double u, double v, double width, int nwl,
                     const double *nm, double *out) {
  if (!t->spectral) {
    double rgb[3];
    vr_texture_rgb(t, u, v, width, rgb);
    float in[3] = {(float)rgb[0], (float)rgb[1], (float)rgb[2]}, c[3];
    vr_rgb_table_lookup(t->tab, in, c);
    for (int i = 0; i < nwl; i++) out[i] = vr_rgb_coef_eval(c, nm[i]);
    return;
  }
  /* Spectral: each wavelength between its two bands, filtered. */
  int k0, k1;
  double f;
  levels_for(t, width, &k0, &k1, &f);
  for (int i = 0; i < nwl; i++) {
    size_t b = 0;
    double fb = 0;
    if (nm[i] >= t->wl[t->nb - 1])
      b = t->nb - 1;
    else if (nm[i] > t->wl[0]) {
      size_t lo = 0, hi = t->nb - 1;
      while (hi - lo > 1) {
        size_t m = (lo + hi) / 2;
        if (t->wl[m] <= nm[i]) lo = m;
        else hi = m;
      }
      b = lo, fb = (nm[i] - t->wl[lo]) / (t->wl[lo + 1] - t->wl[lo]);
    }
    double r = 0;
    for (int l = 0; l < 2; l++) {
      int k = l ? k1 : k0;
      double lw = l ? f : 1 - f;
      if (!(lw > 0)) continue;
      taps tp = taps_at(t->w[k], t->h[k], u, v);
      for (int q = 0; q < 4; q++) {
        const uint16_t *s = t->px[k] + tp.at[q] * t->nb;
        double val = fb > 0 ? s[b] + fb * ((double)s[b + 1] - s[b]) : s[b];
        r += lw * tp.wt[q] * val;
      }
    }
    out[i] = r / 65535;
  }
}

double vr_texture_alpha(const vr_texture *t, double u, double v) {
  if (!t->alpha) return 1;
  taps tp = taps_at(t->w[0], t->h[0], u, v);
  double a = 0;
  for (int q = 0; q < 4; q++) a += tp.wt[q] * t->px[0][4 * tp.at[q] + 3];
  return a / 65535;
}
