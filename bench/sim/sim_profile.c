/* Reads the "flow_profile" member vr-render writes into its statistics
 * (render/src/film/flow_profile_json.c).  Only that member's shape is
 * parsed: arrays of numbers and a few keys, with every count checked. */
#include "sim_profile.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Reads up to n numbers from a JSON array that starts at *s ('['),
 * flattening nested arrays; leaves *s after the closing bracket.
 * Returns how many were read, or -1 if malformed. */
static long numbers(const char **s, double *out, long n) {
  const char *p = *s;
  if (*p != '[') return -1;
  int depth = 0;
  long k = 0;
  do {
    if (*p == '[') {
      depth++, p++;
    } else if (*p == ']') {
      depth--, p++;
    } else if (*p == ',' || *p == ' ' || *p == '\n') {
      p++;
    } else {
      char *end;
      double v = strtod(p, &end);
      if (end == p) {
        if (!strncmp(p, "null", 4)) v = 0, end = (char *)p + 4;
        else return -1;
      }
      if (k < n) out[k] = v;
      k++;
      p = end;
    }
  } while (depth > 0 && *p);
  if (depth) return -1;
  *s = p;
  return k;
}

static const char *after(const char *s, const char *key) {
  const char *p = strstr(s, key);
  return p ? p + strlen(key) : NULL;
}

bool sim_profile_read(const char *json, sim_profile *p, char *msg, int n) {
  memset(p, 0, sizeof *p);
  const char *s = after(json, "\"flow_profile\": {\"cells\": ");
  if (!s) return snprintf(msg, (size_t)n, "no flow_profile (run vr-render with --flow-profile)"), false;
  /* Cells: count them first (pairs). */
  const char *t = s;
  long k = numbers(&t, NULL, 0);
  if (k <= 0 || k % 2) return snprintf(msg, (size_t)n, "flow_profile: malformed cells"), false;
  int S = (int)(k / 2);
  double *cells = malloc((size_t)k * sizeof *cells);
  p->S = S;
  p->bytes = malloc((size_t)S * sizeof *p->bytes);
  p->load_s = malloc((size_t)S * sizeof *p->load_s);
  if (!cells || !p->bytes || !p->load_s) return free(cells), snprintf(msg, (size_t)n, "out of memory"), false;
  numbers(&s, cells, k);
  for (int c = 0; c < S; c++) p->bytes[c] = cells[2 * c], p->load_s[c] = cells[2 * c + 1];
  free(cells);
  const char *q = after(s, "\"passes\": [");
  while (q && p->npasses < SIM_MAX_PASSES && (q = after(q, "{\"name\": \""))) {
    sim_pass *ps = &p->pass[p->npasses];
    const char *e = strchr(q, '"');
    if (!e || e - q >= (long)sizeof ps->name) break;
    memcpy(ps->name, q, (size_t)(e - q));
    ps->name[e - q] = 0;
    const char *u = after(e, "\"units\": "), *g = after(e, "\"generate_seconds\": ");
    const char *r = after(e, "\"rays\": "), *m = after(e, "\"moves\": ");
    if (!u || !g || !r || !m) return snprintf(msg, (size_t)n, "flow_profile: pass %s incomplete", ps->name), false;
    ps->units = strtol(u, NULL, 10);
    ps->gen_s = strtod(g, NULL);
    double *rk = malloc((size_t)S * 4 * sizeof *rk);
    ps->rays = calloc((size_t)S, sizeof *ps->rays);
    ps->cost = calloc((size_t)S, sizeof *ps->cost);
    ps->out = calloc((size_t)(S + 1) * (size_t)S, sizeof *ps->out);
    if (!rk || !ps->rays || !ps->cost || !ps->out) return free(rk), snprintf(msg, (size_t)n, "out of memory"), false;
    p->npasses++;
    if (numbers(&r, rk, 4L * S) != 4L * S) {
      free(rk);
      return snprintf(msg, (size_t)n, "flow_profile: pass %s: %d cells expected", ps->name, S), false;
    }
    for (int c = 0; c < S; c++) {
      ps->rays[c] = rk[4 * c] + rk[4 * c + 2];
      ps->cost[c] = ps->rays[c] > 0 ? (rk[4 * c + 1] + rk[4 * c + 3]) / ps->rays[c] : 0;
    }
    free(rk);
    const char *mt = m;
    long nm = numbers(&mt, NULL, 0);
    if (nm < 0 || nm % 3) return snprintf(msg, (size_t)n, "flow_profile: pass %s: malformed moves", ps->name), false;
    double *mv = malloc((size_t)(nm ? nm : 1) * sizeof *mv);
    if (!mv) return snprintf(msg, (size_t)n, "out of memory"), false;
    numbers(&m, mv, nm);
    for (long i = 0; i < nm; i += 3) {
      int a = (int)mv[i], b = (int)mv[i + 1];
      if (a < -1 || a >= S || b < 0 || b >= S) {
        free(mv);
        return snprintf(msg, (size_t)n, "flow_profile: pass %s: a move names no cell", ps->name), false;
      }
      int row = a < 0 ? S : a;
      double per = a < 0 ? (ps->units > 0 ? (double)ps->units : 1) : (ps->rays[a] > 0 ? ps->rays[a] : 1);
      ps->out[(size_t)row * (size_t)S + (size_t)b] = mv[i + 2] / per;
    }
    free(mv);
    q = m;
  }
  if (!p->npasses) return snprintf(msg, (size_t)n, "flow_profile: no pass"), false;
  return true;
}

void sim_profile_free(sim_profile *p) {
  free(p->bytes);
  free(p->load_s);
  for (int i = 0; i < p->npasses; i++) free(p->pass[i].rays), free(p->pass[i].cost), free(p->pass[i].out);
  memset(p, 0, sizeof *p);
}

double sim_pass_rays(const sim_profile *p, int pass) {
  double n = 0;
  for (int c = 0; c < p->S; c++) n += p->pass[pass].rays[c];
  return n;
}

double sim_pass_seconds(const sim_profile *p, int pass) {
  double t = p->pass[pass].gen_s;
  for (int c = 0; c < p->S; c++) t += p->pass[pass].rays[c] * p->pass[pass].cost[c];
  return t;
}
