/* Line and marker plots rendered with cairo's SVG surface: axes with
 * rounded tick steps, series, a legend.  See vr/plot.h. */
#include "vr/plot.h"

#include <cairo-svg.h>
#include <cairo.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct series {
  size_t n;
  double *x, *y;
  unsigned colour;
  bool markers;
  char label[64];
} series;

struct vr_plot {
  char title[128], xlabel[64], ylabel[64];
  size_t count;
  series *s;
};

vr_plot *vr_plot_create(const char *title, const char *xlabel, const char *ylabel) {
  vr_plot *p = calloc(1, sizeof *p);
  if (!p) return NULL;
  snprintf(p->title, sizeof p->title, "%s", title ? title : "");
  snprintf(p->xlabel, sizeof p->xlabel, "%s", xlabel ? xlabel : "");
  snprintf(p->ylabel, sizeof p->ylabel, "%s", ylabel ? ylabel : "");
  return p;
}

void vr_plot_destroy(vr_plot *p) {
  if (!p) return;
  for (size_t i = 0; i < p->count; i++) {
    free(p->s[i].x);
    free(p->s[i].y);
  }
  free(p->s);
  free(p);
}

bool vr_plot_add(vr_plot *p, size_t n, const double *x, const double *y, unsigned colour,
                 bool markers, const char *label) {
  series *s = realloc(p->s, (p->count + 1) * sizeof *s);
  if (!s) return false;
  p->s = s;
  series *t = &p->s[p->count];
  memset(t, 0, sizeof *t);
  t->x = malloc((n ? n : 1) * sizeof(double));
  t->y = malloc((n ? n : 1) * sizeof(double));
  if (!t->x || !t->y) {
    free(t->x);
    free(t->y);
    return false;
  }
  memcpy(t->x, x, n * sizeof(double));
  memcpy(t->y, y, n * sizeof(double));
  t->n = n;
  t->colour = colour;
  t->markers = markers;
  snprintf(t->label, sizeof t->label, "%s", label ? label : "");
  p->count++;
  return true;
}

static cairo_status_t to_file(void *closure, const unsigned char *data, unsigned int length) {
  return fwrite(data, 1, length, closure) == length ? CAIRO_STATUS_SUCCESS : CAIRO_STATUS_WRITE_ERROR;
}

/* A "nice" tick step (1, 2 or 5 times a power of ten) for about 6 ticks. */
static double nice_step(double range) {
  double raw = range / 6.0, mag = pow(10.0, floor(log10(raw))), f = raw / mag;
  return (f < 1.5 ? 1.0 : f < 3.5 ? 2.0 : f < 7.5 ? 5.0 : 10.0) * mag;
}

static void rgb(cairo_t *cr, unsigned c) {
  cairo_set_source_rgb(cr, ((c >> 16) & 255) / 255.0, ((c >> 8) & 255) / 255.0, (c & 255) / 255.0);
}

bool vr_plot_write_svg(const vr_plot *p, FILE *f, int W, int H) {
  double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
  for (size_t i = 0; i < p->count; i++)
    for (size_t j = 0; j < p->s[i].n; j++) {
      double x = p->s[i].x[j], y = p->s[i].y[j];
      if (!isfinite(x) || !isfinite(y)) continue;
      x0 = fmin(x0, x), x1 = fmax(x1, x), y0 = fmin(y0, y), y1 = fmax(y1, y);
    }
  if (!(x0 <= x1)) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  if (x1 == x0) x0 -= 1, x1 += 1;
  if (y1 == y0) y0 -= 1, y1 += 1;
  double dy = (y1 - y0) * 0.05;
  y0 -= dy, y1 += dy;
  cairo_surface_t *surf = cairo_svg_surface_create_for_stream(to_file, f, W, H);
  cairo_t *cr = cairo_create(surf);
  const double L = 78, R = 20, T = 36, B = 50;
  double pw = W - L - R, ph = H - T - B;
#define PX(x) (L + ((x) - x0) / (x1 - x0) * pw)
#define PY(y) (T + ph - ((y) - y0) / (y1 - y0) * ph)
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, 11);
  cairo_set_line_width(cr, 1);
  cairo_set_source_rgb(cr, 0.85, 0.85, 0.85);
  double sx = nice_step(x1 - x0), sy = nice_step(y1 - y0);
  char buf[32];
  for (double v = ceil(x0 / sx) * sx; v <= x1 + 1e-9 * sx; v += sx) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, PX(v), T);
    cairo_line_to(cr, PX(v), T + ph);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    snprintf(buf, sizeof buf, "%g", fabs(v) < 1e-12 * sx ? 0.0 : v);
    cairo_move_to(cr, PX(v) - 10, T + ph + 16);
    cairo_show_text(cr, buf);
  }
  for (double v = ceil(y0 / sy) * sy; v <= y1 + 1e-9 * sy; v += sy) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, L, PY(v));
    cairo_line_to(cr, L + pw, PY(v));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    snprintf(buf, sizeof buf, "%g", fabs(v) < 1e-12 * sy ? 0.0 : v);
    cairo_text_extents_t ext;
    cairo_text_extents(cr, buf, &ext);
    cairo_move_to(cr, L - 6 - ext.x_advance, PY(v) + 4); /* right-aligned on the axis */
    cairo_show_text(cr, buf);
  }
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_rectangle(cr, L, T, pw, ph);
  cairo_stroke(cr);
  cairo_move_to(cr, L + pw / 2 - 40, H - 12);
  cairo_show_text(cr, p->xlabel);
  cairo_save(cr);
  cairo_move_to(cr, 14, T + ph / 2 + 30);
  cairo_rotate(cr, -M_PI / 2);
  cairo_show_text(cr, p->ylabel);
  cairo_restore(cr);
  cairo_set_font_size(cr, 13);
  cairo_move_to(cr, L, 22);
  cairo_show_text(cr, p->title);
  cairo_set_font_size(cr, 11);
  cairo_rectangle(cr, L, T, pw, ph);
  cairo_clip(cr);
  for (size_t i = 0; i < p->count; i++) {
    const series *s = &p->s[i];
    rgb(cr, s->colour);
    bool pen = false;
    for (size_t j = 0; j < s->n; j++) {
      if (!isfinite(s->x[j]) || !isfinite(s->y[j])) {
        pen = false;
        continue;
      }
      if (s->markers) {
        cairo_arc(cr, PX(s->x[j]), PY(s->y[j]), 2.0, 0, 2 * M_PI);
        cairo_fill(cr);
      } else if (pen) {
        cairo_line_to(cr, PX(s->x[j]), PY(s->y[j]));
      } else {
        cairo_move_to(cr, PX(s->x[j]), PY(s->y[j]));
        pen = true;
      }
    }
    if (!s->markers) {
      cairo_set_line_width(cr, 1.5);
      cairo_stroke(cr);
    }
  }
  cairo_reset_clip(cr);
  size_t labelled = 0, shown = 0;
  for (size_t i = 0; i < p->count; i++) labelled += p->s[i].label[0] != 0;
  if (labelled) { /* a white box so the legend stays readable over data */
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, L + pw - 156, T + 2, 150, 14.0 * (double)labelled + 6);
    cairo_fill(cr);
  }
  for (size_t i = 0; i < p->count; i++) {
    if (!p->s[i].label[0]) continue; /* unlabelled companions (model lines) */
    rgb(cr, p->s[i].colour);
    double ly = T + 14 + 14.0 * (double)shown++;
    cairo_rectangle(cr, L + pw - 150, ly - 8, 10, 8);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_move_to(cr, L + pw - 135, ly);
    cairo_show_text(cr, p->s[i].label);
  }
#undef PX
#undef PY
  cairo_destroy(cr);
  cairo_surface_finish(surf);
  bool ok = cairo_surface_status(surf) == CAIRO_STATUS_SUCCESS;
  cairo_surface_destroy(surf);
  return ok;
}
