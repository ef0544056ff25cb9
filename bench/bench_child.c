/* Child processes and their statistics for the end-to-end benchmarks
 * (bench_child.h). */
#define _GNU_SOURCE
#include "bench_child.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>

#include "vr/file.h"
#include "vr/image.h"

extern char **environ;

double bench_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void bench_die(const char *what) {
  fprintf(stderr, "bench: %s\n", what);
  exit(1);
}

int bench_run(char *const argv[], const char *log) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&fa, 1, 2);
  pid_t pid;
  if (posix_spawnp(&pid, argv[0], &fa, NULL, argv, environ)) bench_die("cannot start a child");
  posix_spawn_file_actions_destroy(&fa);
  int status;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) bench_die("waitpid");
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

double bench_json_num(const char *text, const char *key) {
  char pat[128];
  snprintf(pat, sizeof pat, "\"%s\": ", key);
  const char *p = text ? strstr(text, pat) : NULL;
  return p ? strtod(p + strlen(pat), NULL) : NAN;
}

double bench_pass_seconds(const char *text, const char *name) {
  char pat[128];
  snprintf(pat, sizeof pat, "{\"name\": \"%s\"", name);
  const char *p = text ? strstr(text, pat) : NULL;
  return p ? bench_json_num(p, "seconds") : NAN;
}

void bench_log_reason(const char *log, char *out, size_t n) {
  char *lg = NULL;
  size_t len;
  out[0] = '\0';
  if (vr_read_file(log, 0, &lg, &len, NULL)) return;
  const char *why = strstr(lg, "out of memory");
  if (!why) why = lg;
  const char *e = strchr(why, '\n');
  snprintf(out, n, "%.*s", (int)(e ? e - why : (long)strlen(why)), why);
  free(lg);
}

double bench_image_diff(const char *a, const char *b) {
  vr_image x = {0}, y = {0};
  vr_error err = {0};
  if (vr_image_read(a, &x, &err) || vr_image_read(b, &y, &err)) {
    vr_image_free(&x);
    return NAN;
  }
  double worst = 0;
  size_t n = (size_t)x.width * x.height * x.channels;
  if (x.width != y.width || x.height != y.height) worst = INFINITY;
  for (size_t i = 0; worst < INFINITY && i < n; i++) {
    double u = x.data[i], v = y.data[i], m = fmax(fabs(u), fabs(v));
    if (m > 1e-12) worst = fmax(worst, fabs(u - v) / m);
  }
  vr_image_free(&x);
  vr_image_free(&y);
  return worst;
}

int bench_render_args(char **argv, int n, bench_render_opts *o) {
  snprintf(o->num[0], sizeof o->num[0], "%d", o->subdomains);
  snprintf(o->num[1], sizeof o->num[1], "%d", o->threads);
  snprintf(o->num[2], sizeof o->num[2], "%lld", o->budget);
  argv[n++] = (char *)o->vr_render, argv[n++] = (char *)o->scene;
  argv[n++] = "--db", argv[n++] = (char *)o->db, argv[n++] = "-o", argv[n++] = (char *)o->prefix;
  argv[n++] = "--stats", argv[n++] = (char *)o->stats;
  if (o->subdomains > 0) argv[n++] = "--subdomains", argv[n++] = o->num[0];
  if (o->threads > 0) argv[n++] = "--threads", argv[n++] = o->num[1];
  if (o->cache) argv[n++] = "--cache", argv[n++] = (char *)o->cache;
  if (o->budget > 0) argv[n++] = "--memory-budget", argv[n++] = o->num[2];
  if (o->spp) argv[n++] = "--spp", argv[n++] = (char *)o->spp;
  return n;
}

int bench_run_timed(char *const argv[], const char *log, double *wall) {
  double t0 = bench_now();
  int status = bench_run(argv, log);
  *wall = bench_now() - t0;
  return status;
}
