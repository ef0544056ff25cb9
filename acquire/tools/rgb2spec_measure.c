/* vr-rgb2spec's photos read and regions measured: each photo decoded (on
 * several threads), each region's mean response, noise and clipping in
 * every photo, the chart found once in the first photo. */
#include "rgb2spec.h"

#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <string.h>

#include "vr/chart.h"

/* A channel counts as clipped high when its mean is within two standard
 * deviations of the clip level (some of its pixels reached it), and clipped
 * low when it is within two standard deviations of 0 and below one 8-bit
 * step (a response the file could not store as negative, as the sRGB-
 * primaries camera gives for saturated colours). */
static void clip_marks(const double rgb[3], const double sd[3], long clipped_pixels, double clip,
                       unsigned char *marks) {
  for (int ch = 0; ch < 3; ch++) {
    marks[ch] = VR_CLIP_NONE;
    if ((clipped_pixels > 0 && rgb[ch] + 2 * sd[ch] >= clip) || rgb[ch] >= clip) marks[ch] = VR_CLIP_HIGH;
    else if (rgb[ch] < 1.0 / 255 && rgb[ch] - 2 * sd[ch] <= 0) marks[ch] = VR_CLIP_LOW;
  }
}

static bool srgb_encoded(const vr_capture_photo *p, const vr_image *img) {
  if (p->encoding) return p->encoding == 1;
  return img->bit_depth != 32; /* integer files are display-referred unless said otherwise */
}

/* Measures every region in photo l. */
static vr_status measure(rg_run *run, size_t l, const vr_image *img, double corners[4][2],
                         bool *have_corners, vr_error *err) {
  const vr_capture_photo *p = run->photo[l];
  vr_chart chart;
  bool chart_read = false;
  vr_label_means labels = {0};
  vr_status st = VR_OK;
  for (size_t i = 0; i < run->nregions && !st; i++) {
    rg_region *g = &run->regions[i];
    const vr_capture_region *d = g->def;
    double rgb[3], sd[3] = {0, 0, 0};
    long clipped = 0, pixels = 1;
    if (d->kind == VR_REGION_RECT) {
      int cl = 0;
      st = vr_image_rect_mean(img, d->x, d->y, d->w, d->h, rgb, sd, &cl, p->clip, err);
      clipped = cl;
      pixels = (long)d->w * d->h;
      if (l == 0) g->box[0] = d->x, g->box[1] = d->y, g->box[2] = d->x + d->w, g->box[3] = d->y + d->h;
    } else if (d->kind == VR_REGION_CHART) {
      if (!chart_read) {
        if (!*have_corners && d->chart_auto) {
          st = vr_chart_detect(img, !srgb_encoded(p, img), &chart, err);
          if (!st) memcpy(corners, chart.corners, sizeof chart.corners), *have_corners = true;
        } else if (!*have_corners) {
          double q[4][2] = {{d->x, d->y}, {d->w, d->y}, {d->w, d->h}, {d->x, d->h}};
          memcpy(corners, q, sizeof q);
          *have_corners = true;
        }
        if (!st) st = vr_chart_from_grid(img, (const double(*)[2])corners, 0, &chart, err);
        chart_read = !st;
      }
      if (st) break;
      int k = d->label;
      memcpy(rgb, chart.rgb[k], sizeof rgb);
      memcpy(sd, chart.sd[k], sizeof sd);
      clipped = chart.max[k] >= p->clip;
      pixels = chart.pixels[k];
      /* A square well inside the sampled one: a fifth of the patch side
       * about its centre (the side from the patch area's top edge). */
      double side = hypot(corners[1][0] - corners[0][0], corners[1][1] - corners[0][1]) / 6.5;
      int half = (int)(0.2 * side);
      if (l == 0) { /* the same in every photo: the corners are photo 0's */
        g->box[0] = (int)lround(chart.center[k][0]) - half;
        g->box[1] = (int)lround(chart.center[k][1]) - half;
        g->box[2] = (int)lround(chart.center[k][0]) + half + 1;
        g->box[3] = (int)lround(chart.center[k][1]) + half + 1;
      }
    } else {
      if (!labels.regions) st = vr_image_label_means_file(img, run->cap->labels_path, p->clip, &labels, err);
      const vr_label_region *lr = NULL;
      for (int k = 0; !st && k < labels.count; k++)
        if (labels.regions[k].label == d->label) lr = &labels.regions[k];
      if (!st && !lr) {
        st = vr_error_at(err, VR_E_NOT_FOUND, run->cap->path, d->line, 0,
                         "region %s: label %d does not occur in %s", d->name, d->label,
                         run->cap->labels_path);
        break;
      }
      if (st) break;
      memcpy(rgb, lr->rgb, sizeof rgb);
      memcpy(sd, lr->sd, sizeof sd);
      clipped = lr->clipped;
      pixels = lr->pixels;
    }
    if (st) {
      vr_error_prefix(err, "%s: region %s: ", p->path, d->name);
      break;
    }
    memcpy(g->encoded[l], rgb, sizeof rgb);
    clip_marks(rgb, sd, clipped, p->clip, &g->clipped[3 * l]);
    g->pixels[l] = pixels;
    bool enc = srgb_encoded(p, img);
    double code = img->bit_depth == 8 ? 1.0 / 255 : img->bit_depth == 16 ? 1.0 / 65535 : 0.0;
    for (int ch = 0; ch < 3; ch++) {
      g->c[3 * l + ch] = vr_capture_decode(run->cap, p, ch, rgb[ch], enc);
      /* Noise in linear units: the pixels' scatter and one code step of the
       * file, through the slope of the decoding at the region's level. */
      double h = 1e-4, v = fmin(fmax(rgb[ch], h), 1.0 - h);
      double slope = fabs(vr_capture_decode(run->cap, p, ch, v + h, enc) -
                          vr_capture_decode(run->cap, p, ch, v - h, enc)) / (2 * h);
      g->sigma[3 * l + ch] = vr_recover_mean_sigma(sd[ch] * slope, pixels, code * slope);
      g->sigma_pixel[3 * l + ch] = vr_recover_pixel_sigma(sd[ch] * slope, code * slope);
    }
  }
  vr_label_means_free(&labels);
  return st;
}

typedef struct reader {
  rg_run *run;
  vr_image *img;
  size_t next, count;
  pthread_mutex_t lock;
  vr_status st;
  vr_error err;
  size_t failed; /* the photo whose error st and err hold */
} reader;

static void *read_worker(void *arg) {
  reader *rd = arg;
  for (;;) {
    pthread_mutex_lock(&rd->lock);
    size_t l = rd->st ? rd->count : rd->next++;
    pthread_mutex_unlock(&rd->lock);
    if (l >= rd->count) return NULL;
    vr_error e = {0};
    /* Integer photos stay as their codes: the per-pixel path looks every
     * code up in a table anyway, and four 12-megapixel photos as floats
     * would be 576 MB to convert and fault in. */
    vr_status st = vr_image_read_codes(rd->run->photo[l]->path, &rd->img[l], &e);
    if (st) {
      /* The first photo's error in the manifest's order, whichever thread
       * failed first: photos are handed out in order, so every photo before
       * a failing one was taken and is read to its end. */
      pthread_mutex_lock(&rd->lock);
      if (!rd->st || l < rd->failed) rd->st = st, rd->err = e, rd->failed = l;
      pthread_mutex_unlock(&rd->lock);
    }
  }
}

/* The photos after the first, measured on several threads: the first
 * fixes the chart's corners (found by detection or given), which the others
 * then only read, each through a copy of its own.  Each photo fills only
 * its own entries of the regions (and photo 0 their boxes).  The error
 * reported is that of the first photo that fails, as one thread would. */
typedef struct measurer {
  rg_run *run;
  const vr_image *img;
  double corners[4][2];
  bool have_corners;
  size_t next;
  pthread_mutex_t lock;
  vr_status st[RGB2SPEC_MAX_LIGHTS];
  vr_error err[RGB2SPEC_MAX_LIGHTS];
} measurer;

static void *measure_worker(void *arg) {
  measurer *ms = arg;
  for (;;) {
    pthread_mutex_lock(&ms->lock);
    size_t l = ms->next++;
    pthread_mutex_unlock(&ms->lock);
    if (l >= ms->run->nphotos) return NULL;
    double corners[4][2];
    bool have = ms->have_corners;
    memcpy(corners, ms->corners, sizeof corners);
    ms->st[l] = measure(ms->run, l, &ms->img[l], corners, &have, &ms->err[l]);
  }
}

vr_status rg_measure_photos(rg_run *run, const vr_image *img, int threads, vr_error *err) {
  measurer ms = {.run = run, .img = img, .next = 1};
  vr_status st = measure(run, 0, &img[0], ms.corners, &ms.have_corners, err);
  if (st) return st;
  pthread_mutex_init(&ms.lock, NULL);
  pthread_t tid[RGB2SPEC_MAX_LIGHTS];
  int started = 0;
  for (int t = 1; t < threads && (size_t)t + 1 < run->nphotos; t++) {
    if (pthread_create(&tid[started], NULL, measure_worker, &ms)) break;
    started++;
  }
  measure_worker(&ms);
  for (int t = 0; t < started; t++) pthread_join(tid[t], NULL);
  pthread_mutex_destroy(&ms.lock);
  for (size_t l = 1; l < run->nphotos; l++)
    if (ms.st[l]) {
      if (err) *err = ms.err[l];
      return ms.st[l];
    }
  return VR_OK;
}

/* Decoding a 12-megapixel PNG takes a third of a second: the photos are
 * read on several threads.  An error is the first failing photo's, as one
 * thread would report it (the message must not depend on timing). */
vr_status rg_read_photos(rg_run *run, vr_image *img, int threads, vr_error *err) {
  reader rd = {.run = run, .img = img, .count = run->nphotos};
  pthread_mutex_init(&rd.lock, NULL);
  pthread_t tid[RGB2SPEC_MAX_LIGHTS];
  int started = 0;
  for (int t = 1; t < threads && (size_t)t < run->nphotos; t++) {
    if (pthread_create(&tid[started], NULL, read_worker, &rd)) break;
    started++;
  }
  read_worker(&rd);
  for (int t = 0; t < started; t++) pthread_join(tid[t], NULL);
  pthread_mutex_destroy(&rd.lock);
  if (rd.st && err) *err = rd.err;
  return rd.st;
}
