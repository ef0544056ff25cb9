/* Terminal progress bar with ETA: see vr/progress.h. */
#include "vr/progress.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

struct vr_progress {
  char label[64];
  size_t total;
  double start, last_draw;
};

static double now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void clock_text(char *buf, size_t size, double s) {
  long t = (long)(s + 0.5);
  if (t >= 3600) snprintf(buf, size, "%ld:%02ld:%02ld", t / 3600, (t / 60) % 60, t % 60);
  else snprintf(buf, size, "%ld:%02ld", t / 60, t % 60);
}

void vr_progress_format(char *buf, size_t size, const char *label, size_t done, size_t total,
                        double elapsed, int width) {
  if (total == 0) total = 1;
  if (done > total) done = total;
  double frac = (double)done / (double)total;
  char bar[128];
  if (width > (int)sizeof bar - 1) width = (int)sizeof bar - 1;
  int fill = (int)(frac * width);
  for (int i = 0; i < width; i++) bar[i] = i < fill ? '#' : ' ';
  bar[width] = '\0';
  char eta[32];
  if (done == total) {
    clock_text(eta, sizeof eta, elapsed);
    snprintf(buf, size, "%s [%s] 100%%  took %s", label, bar, eta);
  } else if (done == 0) {
    snprintf(buf, size, "%s [%s]   0%%  ETA --:--", label, bar);
  } else {
    clock_text(eta, sizeof eta, elapsed * (1.0 - frac) / frac);
    snprintf(buf, size, "%s [%s] %3d%%  ETA %s", label, bar, (int)(100.0 * frac), eta);
  }
}

vr_progress *vr_progress_create(const char *label, size_t total) {
  if (!isatty(fileno(stderr))) return NULL;
  vr_progress *p = calloc(1, sizeof *p);
  if (!p) return NULL;
  snprintf(p->label, sizeof p->label, "%s", label ? label : "");
  p->total = total ? total : 1;
  p->start = now();
  p->last_draw = -1.0;
  return p;
}

static void draw(vr_progress *p, size_t done) {
  char line[256];
  vr_progress_format(line, sizeof line, p->label, done, p->total, now() - p->start, 30);
  fprintf(stderr, "\r%s\033[K", line);
  fflush(stderr);
}

void vr_progress_update(vr_progress *p, size_t done) {
  if (!p) return;
  double t = now();
  if (t - p->last_draw < 0.1 && done < p->total) return;
  p->last_draw = t;
  draw(p, done);
}

void vr_progress_finish(vr_progress *p) {
  if (!p) return;
  draw(p, p->total);
  fputc('\n', stderr);
  free(p);
}
