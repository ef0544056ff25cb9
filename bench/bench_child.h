/* What the end-to-end benchmarks share: running the real tools as child
 * processes, timing them, and reading numbers back from their --stats
 * JSON. */
#ifndef BENCH_CHILD_H
#define BENCH_CHILD_H

#include <stddef.h>

double bench_now(void);
void bench_die(const char *what) __attribute__((noreturn));
/* Runs argv (argv[0] looked up in PATH) with stdout and stderr to log;
 * returns the exit status (128 + signal if it was killed). */
int bench_run(char *const argv[], const char *log);
/* bench_run, and its wall time in *wall (seconds). */
int bench_run_timed(char *const argv[], const char *log, double *wall);
/* The first number after "key": in a JSON text (NAN if absent). */
double bench_json_num(const char *text, const char *key);
/* The seconds of a pass by name in the stats' pass list (NAN if absent). */
double bench_pass_seconds(const char *text, const char *name);
/* The first line of log that says "out of memory", else its first line. */
void bench_log_reason(const char *log, char *out, size_t n);
/* Largest relative difference between two RGB EXR images (NAN if one
 * cannot be read, INFINITY if their sizes differ). */
double bench_image_diff(const char *a, const char *b);

/* One vr-render run's common options; zero or NULL fields are left out. */
typedef struct bench_render_opts {
  const char *vr_render, *scene, *db, *prefix, *stats, *cache, *spp;
  int subdomains, threads;
  long long budget;
  char num[3][32]; /* room for the numbers as text */
} bench_render_opts;
/* Appends vr-render and its options to argv from index n (argv must have
 * room for 24 more); returns the new count.  The caller ends argv with
 * NULL. */
int bench_render_args(char **argv, int n, bench_render_opts *o);

#endif
