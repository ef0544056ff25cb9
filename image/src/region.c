/* Turning regions of a photo into numbers: a rectangle, the regions of a
 * label image, and the convex quadrilaterals of chart patches.  Means and
 * deviations are two-pass (mean first, then squared deviations from it), so
 * a patch of nearly equal values keeps its small deviation exactly instead
 * of losing it to the cancellation of sum(x^2) - n mean^2. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "vr/image.h"

/* The value of each 8-bit code, k / 255 rounded to float once by the
 * compiler (IEEE division, the decoder's own at run time). */
#define CODE8(k) ((float)(k) / 255.0f)
#define CODE8_4(k) CODE8(k), CODE8((k) + 1), CODE8((k) + 2), CODE8((k) + 3)
#define CODE8_16(k) CODE8_4(k), CODE8_4((k) + 4), CODE8_4((k) + 8), CODE8_4((k) + 12)
#define CODE8_64(k) CODE8_16(k), CODE8_16((k) + 16), CODE8_16((k) + 32), CODE8_16((k) + 48)
static const float k_code8[256] = {CODE8_64(0), CODE8_64(64), CODE8_64(128), CODE8_64(192)};

/* Pixel (x, y) as floats, from either form of vr/image.h: for codes the
 * same true division as the decoder's, so the values are those of
 * vr_image_read. */
static void pixel(const vr_image *img, long x, long y, float p[3]) {
  const size_t i = ((size_t)y * (size_t)img->width + (size_t)x) * 3;
  if (img->data) {
    p[0] = img->data[i], p[1] = img->data[i + 1], p[2] = img->data[i + 2];
  } else if (img->bit_depth == 8) {
    const uint8_t *c = (const uint8_t *)img->codes + i;
    for (int k = 0; k < 3; k++) p[k] = k_code8[c[k]];
  } else {
    const uint16_t *c = (const uint16_t *)img->codes + i;
    for (int k = 0; k < 3; k++) p[k] = (float)c[k] / 65535.0f;
  }
}

static int is_clipped(const float *p, double clip_level) {
  return p[0] >= clip_level || p[1] >= clip_level || p[2] >= clip_level;
}

vr_status vr_image_rect_mean(const vr_image *img, int x, int y, int w, int h, double rgb[3],
                             double sd[3], int *clipped, double clip_level, vr_error *err) {
  vr_status st = vr_image_check_any(img, "vr_image_rect_mean", err);
  if (st != VR_OK) return st;
  if (!rgb) return vr_error_set(err, VR_E_ARG, "vr_image_rect_mean: rgb is NULL");
  if (w < 1 || h < 1)
    return vr_error_set(err, VR_E_RANGE, "rectangle x=%d y=%d w=%d h=%d is empty", x, y, w, h);
  if (x < 0 || y < 0 || (long)x + w > img->width || (long)y + h > img->height)
    return vr_error_set(err, VR_E_RANGE, "rectangle x=%d y=%d w=%d h=%d is not inside the %d x %d "
                        "image", x, y, w, h, img->width, img->height);
  double sum[3] = {0, 0, 0};
  int nclip = 0;
  for (long j = y; j < (long)y + h; j++)
    for (long i = x; i < (long)x + w; i++) {
      float p[3];
      pixel(img, i, j, p);
      for (int c = 0; c < 3; c++) sum[c] += p[c];
      nclip += is_clipped(p, clip_level);
    }
  const double n = (double)w * (double)h;
  for (int c = 0; c < 3; c++) rgb[c] = sum[c] / n;
  if (sd) {
    double ss[3] = {0, 0, 0};
    for (long j = y; j < (long)y + h; j++)
      for (long i = x; i < (long)x + w; i++) {
        float p[3];
      pixel(img, i, j, p);
        for (int c = 0; c < 3; c++) ss[c] += (p[c] - rgb[c]) * (p[c] - rgb[c]);
      }
    for (int c = 0; c < 3; c++) sd[c] = n > 1 ? sqrt(ss[c] / (n - 1)) : 0.0;
  }
  if (clipped) *clipped = nclip;
  return VR_OK;
}

typedef struct label_acc {
  long n, clipped;
  double sum[3], ss[3];
} label_acc;

/* Label of pixel (x,y), or -1 when its channels disagree or leave 0..scale. */
static long label_at(const vr_image *labels, long x, long y, double scale) {
  float p[3];
      pixel(labels, x, y, p);
  for (int c = 0; c < 3; c++)
    if (!(p[c] >= 0.0f && p[c] <= 1.0f)) return -1;
  long v0 = lround(p[0] * scale), v1 = lround(p[1] * scale), v2 = lround(p[2] * scale);
  return (v0 == v1 && v1 == v2) ? v0 : -1;
}

vr_status vr_image_label_means(const vr_image *img, const vr_image *labels,
                               const char *labels_name, double clip_level,
                               vr_label_means *out, vr_error *err) {
  const char *name = labels_name ? labels_name : "label image";
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_image_label_means: out is NULL");
  memset(out, 0, sizeof *out);
  vr_status st = vr_image_check_any(img, "vr_image_label_means: photo", err);
  if (st == VR_OK) st = vr_image_check_any(labels, name, err);
  if (st != VR_OK) return st;
  if (labels->bit_depth != 8 && labels->bit_depth != 16)
    return vr_error_at(err, VR_E_ARG, name, 0, 0,
                       "a label image must hold 8- or 16-bit integers, this one has bit depth %d",
                       labels->bit_depth);
  if (labels->width != img->width || labels->height != img->height)
    return vr_error_at(err, VR_E_ARG, name, 0, 0,
                       "label image is %d x %d but the photo is %d x %d; they must match",
                       labels->width, labels->height, img->width, img->height);
  const double scale = labels->bit_depth == 8 ? 255.0 : 65535.0;
  const long w = img->width, h = img->height;
  long max_label = 0;
  for (long y = 0; y < h; y++)
    for (long x = 0; x < w; x++) {
      long l = label_at(labels, x, y, scale);
      if (l < 0) {
        float p[3];
      pixel(labels, x, y, p);
        return vr_error_at(err, VR_E_PARSE, name, 0, 0,
                           "pixel (%ld, %ld) is not grey (R, G, B = %g, %g, %g): a label "
                           "image holds one region id per pixel as a grey level",
                           x, y, p[0] * scale, p[1] * scale, p[2] * scale);
      }
      if (l > max_label) max_label = l;
    }
  label_acc *acc = calloc((size_t)max_label + 1, sizeof *acc);
  if (!acc) return vr_error_set(err, VR_E_NOMEM, "out of memory for %ld labels", max_label);
  for (long y = 0; y < h; y++)
    for (long x = 0; x < w; x++) {
      long l = label_at(labels, x, y, scale);
      if (l == 0) continue;
      float p[3];
      pixel(img, x, y, p);
      acc[l].n++;
      acc[l].clipped += is_clipped(p, clip_level);
      for (int c = 0; c < 3; c++) acc[l].sum[c] += p[c];
    }
  for (long y = 0; y < h; y++)
    for (long x = 0; x < w; x++) {
      long l = label_at(labels, x, y, scale);
      if (l == 0) continue;
      float p[3];
      pixel(img, x, y, p);
      for (int c = 0; c < 3; c++) {
        double d = p[c] - acc[l].sum[c] / (double)acc[l].n;
        acc[l].ss[c] += d * d;
      }
    }
  int count = 0;
  for (long l = 1; l <= max_label; l++) count += acc[l].n > 0;
  out->regions = count ? calloc((size_t)count, sizeof *out->regions) : NULL;
  if (count && !out->regions) {
    free(acc);
    return vr_error_set(err, VR_E_NOMEM, "out of memory for %d regions", count);
  }
  for (long l = 1, k = 0; l <= max_label; l++) {
    if (acc[l].n == 0) continue;
    vr_label_region *r = &out->regions[k++];
    r->label = (int)l;
    r->pixels = acc[l].n;
    r->clipped = acc[l].clipped;
    for (int c = 0; c < 3; c++) {
      r->rgb[c] = acc[l].sum[c] / (double)acc[l].n;
      r->sd[c] = acc[l].n > 1 ? sqrt(acc[l].ss[c] / (double)(acc[l].n - 1)) : 0.0;
    }
  }
  out->count = count;
  free(acc);
  return VR_OK;
}

vr_status vr_image_label_means_file(const vr_image *img, const char *labels_path,
                                    double clip_level, vr_label_means *out, vr_error *err) {
  if (!out) return vr_error_set(err, VR_E_ARG, "vr_image_label_means_file: out is NULL");
  memset(out, 0, sizeof *out);
  vr_image labels;
  vr_status st = vr_image_read(labels_path, &labels, err);
  if (st != VR_OK) return st;
  st = vr_image_label_means(img, &labels, labels_path, clip_level, out, err);
  vr_image_free(&labels);
  return st;
}

void vr_label_means_free(vr_label_means *m) {
  if (!m) return;
  free(m->regions);
  memset(m, 0, sizeof *m);
}

/* Twice the signed area of (a, b, p): > 0 when p lies left of a -> b. */
static double cross(const double a[2], const double b[2], double px, double py) {
  return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
}

static int inside(const double q[4][2], double sign, double px, double py) {
  for (int k = 0; k < 4; k++)
    if (sign * cross(q[k], q[(k + 1) % 4], px, py) < 0) return 0;
  return 1;
}

vr_status vr_region_quad_stats(const vr_image *img, const double quad[4][2],
                               vr_region_stats *out, vr_error *err) {
  memset(out, 0, sizeof *out);
  out->max = -HUGE_VAL;
  vr_status st = vr_image_check_any(img, "patch sampling", err);
  if (st != VR_OK) return st;
  double area2 = 0, lo[2] = {HUGE_VAL, HUGE_VAL}, hi[2] = {-HUGE_VAL, -HUGE_VAL};
  for (int k = 0; k < 4; k++) {
    area2 += quad[k][0] * quad[(k + 1) % 4][1] - quad[(k + 1) % 4][0] * quad[k][1];
    for (int d = 0; d < 2; d++) {
      if (!isfinite(quad[k][d]))
        return vr_error_set(err, VR_E_ARG, "patch corner %d is not a finite number", k);
      lo[d] = fmin(lo[d], quad[k][d]);
      hi[d] = fmax(hi[d], quad[k][d]);
    }
  }
  const double sign = area2 >= 0 ? 1.0 : -1.0;
  /* Pixel i has its centre at i + 0.5: the range of i whose centre can lie
   * inside [lo, hi], clamped to the image. */
  const double wmax = img->width - 1.0, hmax = img->height - 1.0;
  long x0 = (long)fmin(fmax(0.0, ceil(lo[0] - 0.5)), wmax + 1);
  long y0 = (long)fmin(fmax(0.0, ceil(lo[1] - 0.5)), hmax + 1);
  long x1 = (long)fmax(fmin(wmax, floor(hi[0] - 0.5)), -1.0);
  long y1 = (long)fmax(fmin(hmax, floor(hi[1] - 0.5)), -1.0);
  double sum[3] = {0, 0, 0};
  for (long y = y0; y <= y1; y++)
    for (long x = x0; x <= x1; x++) {
      if (!inside(quad, sign, x + 0.5, y + 0.5)) continue;
      float p[3];
      pixel(img, x, y, p);
      out->pixels++;
      for (int c = 0; c < 3; c++) {
        sum[c] += p[c];
        if (p[c] > out->max) out->max = p[c];
      }
    }
  if (out->pixels == 0) return VR_OK;
  const double n = (double)out->pixels;
  for (int c = 0; c < 3; c++) out->mean[c] = sum[c] / n;
  double ss[3] = {0, 0, 0};
  for (long y = y0; y <= y1; y++)
    for (long x = x0; x <= x1; x++) {
      if (!inside(quad, sign, x + 0.5, y + 0.5)) continue;
      float p[3];
      pixel(img, x, y, p);
      for (int c = 0; c < 3; c++) ss[c] += (p[c] - out->mean[c]) * (p[c] - out->mean[c]);
    }
  for (int c = 0; c < 3; c++) out->sd[c] = n > 1 ? sqrt(ss[c] / (n - 1)) : 0.0;
  return VR_OK;
}
