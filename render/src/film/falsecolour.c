/* False-colour luminance maps with a labelled legend (vr/falsecolour.h). */
#include "vr/falsecolour.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

/* The scale's stops: dark blue, blue, cyan, green, yellow, orange, red,
 * white, at equal steps of t. */
static const float STOPS[8][3] = {{0.00f, 0.00f, 0.35f}, {0.00f, 0.25f, 0.95f},
                                  {0.00f, 0.75f, 0.95f}, {0.10f, 0.80f, 0.30f},
                                  {0.95f, 0.90f, 0.10f}, {1.00f, 0.55f, 0.00f},
                                  {0.90f, 0.10f, 0.10f}, {1.00f, 1.00f, 1.00f}};

void vr_falsecolour_colour(double t, float rgb[3]) {
  t = t < 0 ? 0 : t > 1 ? 1 : t;
  double x = t * 7.0;
  int i = (int)x;
  if (i > 6) i = 6;
  double f = x - i;
  for (int c = 0; c < 3; c++) rgb[c] = (float)((1 - f) * STOPS[i][c] + f * STOPS[i + 1][c]);
}

double vr_falsecolour_position(double L, double lo, double hi) {
  if (!(L > lo)) return 0.0;
  if (!(L < hi)) return 1.0;
  return log(L / lo) / log(hi / lo);
}

int vr_falsecolour_legend_width(int W) { return W / 5 > 64 ? W / 5 : 64; }

/* ---- a 5 x 7 bitmap font: each glyph 7 rows of 5 bits, the top row first,
 * the leftmost column the highest bit ---- */

typedef struct vr_glyph {
  char c;
  unsigned char rows[7];
} vr_glyph;

static const vr_glyph FONT[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {'e', {0x00, 0x00, 0x0E, 0x11, 0x1F, 0x10, 0x0E}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}}, {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'c', {0x00, 0x00, 0x0E, 0x10, 0x10, 0x11, 0x0E}}, {'d', {0x01, 0x01, 0x0D, 0x13, 0x11, 0x11, 0x0F}},
    {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}}, {'m', {0x00, 0x00, 0x1A, 0x15, 0x15, 0x11, 0x11}},
};

static const vr_glyph *glyph_of(char c) {
  for (size_t i = 0; i < sizeof FONT / sizeof *FONT; i++)
    if (FONT[i].c == c) return &FONT[i];
  return NULL; /* a space, or a character the font lacks: left blank */
}

static void set_px(vr_image *img, int x, int y, const float rgb[3]) {
  if (x < 0 || y < 0 || x >= img->width || y >= img->height) return;
  memcpy(img->data + 3 * ((size_t)y * (size_t)img->width + (size_t)x), rgb, 3 * sizeof *rgb);
}

/* Text with its top-left corner at (x, y), each font pixel s x s. */
static void draw_text(vr_image *img, int x, int y, int s, const char *text, const float rgb[3]) {
  for (; *text; text++, x += 6 * s) {
    const vr_glyph *g = glyph_of(*text);
    if (!g) continue;
    for (int r = 0; r < 7; r++)
      for (int c = 0; c < 5; c++)
        if (g->rows[r] & (0x10 >> c))
          for (int dy = 0; dy < s; dy++)
            for (int dx = 0; dx < s; dx++) set_px(img, x + c * s + dx, y + r * s + dy, rgb);
  }
}

vr_status vr_falsecolour_image(const double *Y, int W, int H, double lo, double hi,
                               vr_image *out, vr_error *err) {
  if (!(lo > 0 && hi > lo && isfinite(hi)))
    return vr_error_set(err, VR_E_ARG,
                        "false colour: the scale needs 0 < low < high cd/m2 (got %g, %g)", lo, hi);
  int legend = vr_falsecolour_legend_width(W), OH = H > 128 ? H : 128;
  vr_status st = vr_image_alloc(out, W + legend, OH, err);
  if (st) return st;
  for (int y = 0; y < H; y++)
    for (int x = 0; x < W; x++) {
      double L = Y[(size_t)y * (size_t)W + (size_t)x];
      float rgb[3] = {0, 0, 0};
      if (L > 0) vr_falsecolour_colour(vr_falsecolour_position(L, lo, hi), rgb);
      set_px(out, x, y, rgb);
    }
  /* The legend: a bar of the scale, high values at the top, under the
   * unit, and labels at the bounds and the decades between them (a decade
   * too close to the label above it is left out).  The font's pixel is as
   * large as lets six characters sit beside the bar. */
  int barw = legend / 5, s = OH / 160;
  if (s > (legend - barw - 8) / 36) s = (legend - barw - 8) / 36;
  if (s < 1) s = 1;
  int top = 10 * s + 6, bottom = OH - 6 * s, bar0 = W + 4, bar1 = bar0 + barw;
  const float white[3] = {1, 1, 1};
  draw_text(out, bar0, 4, s, "cd/m2", white);
  for (int y = top; y <= bottom; y++) {
    float rgb[3];
    vr_falsecolour_colour((double)(bottom - y) / (bottom - top), rgb);
    for (int x = bar0; x < bar1; x++) set_px(out, x, y, rgb);
  }
  double marks[64];
  int n = 0;
  marks[n++] = hi;
  for (double d = floor(log10(hi)); d >= ceil(log10(lo)) && n < 62; d--) {
    double v = pow(10.0, d);
    if (v < hi * (1 - 1e-9) && v > lo * (1 + 1e-9)) marks[n++] = v;
  }
  marks[n++] = lo;
  int last_y = -1000;
  for (int i = 0; i < n; i++) {
    int y = bottom - (int)lround(vr_falsecolour_position(marks[i], lo, hi) * (bottom - top));
    if (i < n - 1 && y - last_y < 8 * s + 2) continue;
    for (int x = bar1; x < bar1 + 3 * s; x++) set_px(out, x, y, white);
    char buf[32];
    snprintf(buf, sizeof buf, "%.6g", marks[i]);
    draw_text(out, bar1 + 4 * s, y - 3 * s, s, buf, white);
    last_y = y;
  }
  return VR_OK;
}
