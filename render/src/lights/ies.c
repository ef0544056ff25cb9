/* IES LM-63 photometric files (type C, TILT=NONE): a reader that reports
 * "file:line: message", bilinear candela lookup with the standard's
 * horizontal symmetries, and the luminous flux in closed form for the
 * bilinear interpolant.  Layout and symmetries: ANSI/IESNA LM-63-2002
 * sections 5.1-5.13 (earlier layouts differ only in the lines before TILT). */
#include "vr/ies.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/file.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)
#define MAX_FILE_BYTES (16u << 20)
/* Real files have at most a few hundred angles per axis; the caps keep a
 * corrupt count from asking for gigabytes. */
#define MAX_ANGLES 10000
#define MAX_VALUES 4000000
#define ANGLE_TOL 1e-6

typedef struct vr_ies_reader {
  const char *begin, *p, *end, *name;
  long line;
  vr_error *err;
} vr_ies_reader;

static vr_status fail(vr_ies_reader *r, long line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static vr_status fail(vr_ies_reader *r, long line, const char *fmt, ...) {
  char msg[VR_ERROR_MESSAGE_MAX];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  return vr_error_at(r->err, VR_E_PARSE, r->name, line, 0, "%s", msg);
}

/* One line [start, eol) and advances past its end. */
static bool next_line(vr_ies_reader *r, const char **start, const char **eol) {
  if (r->p >= r->end) return false;
  *start = r->p;
  const char *q = r->p;
  while (q < r->end && *q != '\n') q++;
  *eol = q;
  if (q > *start && q[-1] == '\r') (*eol)--;
  r->p = q < r->end ? q + 1 : q;
  r->line++;
  return true;
}

static bool is_sep(char c) { return c == ' ' || c == '\t' || c == '\r' || c == ',' || c == '\f' || c == '\v'; }

/* The next number; `what` names it in messages. */
static vr_status number(vr_ies_reader *r, const char *what, double *out) {
  for (;;) {
    while (r->p < r->end && is_sep(*r->p)) r->p++;
    if (r->p < r->end && *r->p == '\n') {
      r->line++;
      r->p++;
      continue;
    }
    break;
  }
  if (r->p >= r->end) {
    /* Name the last line of the file, not the empty one after its final
     * line break. */
    long last = r->line;
    if (r->end > r->begin && r->end[-1] == '\n' && last > 1) last--;
    return fail(r, last, "file ends before the %s", what);
  }
  const char *s = r->p;
  while (r->p < r->end && !is_sep(*r->p) && *r->p != '\n') r->p++;
  size_t n = (size_t)(r->p - s);
  char buf[64];
  if (n >= sizeof buf) return fail(r, r->line, "the %s is not a number", what);
  memcpy(buf, s, n);
  buf[n] = '\0';
  char *e;
  double v = strtod(buf, &e);
  if (e == buf || *e || !isfinite(v)) {
    return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0, "the %s is not a number: '%s'",
                       what, buf);
  }
  *out = v;
  return VR_OK;
}

static vr_status integer(vr_ies_reader *r, const char *what, long lo, long hi, long *out) {
  double v;
  vr_status st = number(r, what, &v);
  if (st != VR_OK) return st;
  if (v != floor(v) || v < lo || v > hi)
    return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0,
                       "the %s must be a whole number in %ld..%ld, not %g", what, lo, hi, v);
  *out = (long)v;
  return VR_OK;
}

static bool near(double a, double b) { return fabs(a - b) <= ANGLE_TOL; }

/* Lines before TILT=: the version line and keywords (or free text in
 * LM-63-1986 files), which carry nothing the renderer needs. */
static vr_status header(vr_ies_reader *r, vr_ies *ies) {
  const char *s, *e;
  bool first = true;
  snprintf(ies->version, sizeof ies->version, "LM-63-1986");
  while (next_line(r, &s, &e)) {
    while (s < e && isspace((unsigned char)*s)) s++;
    size_t n = (size_t)(e - s);
    if (first) {
      first = false;
      if (n >= 16 && !strncmp(s, "IESNA:LM-63-", 12)) {
        snprintf(ies->version, sizeof ies->version, "LM-63-%.4s", s + 12);
        continue;
      }
      if (n >= 7 && !strncmp(s, "IESNA91", 7)) {
        snprintf(ies->version, sizeof ies->version, "LM-63-1991");
        continue;
      }
    }
    if (n >= 4 && !strncasecmp(s, "TILT", 4)) {
      const char *q = s + 4;
      while (q < e && isspace((unsigned char)*q)) q++;
      if (q >= e || *q != '=') return fail(r, r->line, "expected TILT=NONE after TILT");
      q++;
      while (q < e && isspace((unsigned char)*q)) q++;
      const char *v = q;
      while (e > v && isspace((unsigned char)e[-1])) e--;
      size_t vn = (size_t)(e - v);
      if (vn == 4 && !strncasecmp(v, "NONE", 4)) {
        /* From here on r->line is the line r->p is on, counted as the
         * number reader passes line breaks. */
        r->line++;
        return VR_OK;
      }
      if (vn == 7 && !strncasecmp(v, "INCLUDE", 7))
        return fail(r, r->line, "TILT=INCLUDE is not supported (only TILT=NONE)");
      return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0,
                         "TILT=%.*s (a separate tilt file) is not supported (only TILT=NONE)",
                         (int)(vn > 200 ? 200 : vn), v);
    }
  }
  return fail(r, r->line > 0 ? r->line : 1, "no TILT= line: not an IES LM-63 file");
}

static vr_status angles(vr_ies_reader *r, double *a, size_t n, const char *what) {
  char label[64];
  for (size_t i = 0; i < n; i++) {
    snprintf(label, sizeof label, "%s angle %zu", what, i + 1);
    vr_status st = number(r, label, &a[i]);
    if (st != VR_OK) return st;
    if (a[i] < -ANGLE_TOL || a[i] > 360.0 + ANGLE_TOL)
      return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0, "%s is %g, outside 0..360",
                         label, a[i]);
    if (i > 0 && !(a[i] > a[i - 1]))
      return vr_error_at(r->err, VR_E_PARSE, r->name, r->line, 0,
                         "%s angles must increase: %g after %g", what, a[i], a[i - 1]);
  }
  return VR_OK;
}

vr_status vr_ies_parse(const char *text, size_t len, const char *name, vr_ies **out,
                       vr_error *err) {
  *out = NULL;
  vr_ies_reader r = {text, text, text + len, name ? name : "<ies>", 0, err};
  vr_ies *ies = calloc(1, sizeof *ies);
  if (!ies) return vr_error_set(err, VR_E_NOMEM, "out of memory reading %s", r.name);
  vr_status st = header(&r, ies);
  long lamps = 0, nv = 0, nh = 0, type = 0, units = 0;
  double lumens = 0, mult = 0, w = 0, l = 0, h = 0, ballast = 0, blp = 0, watts = 0;
  if (st == VR_OK) st = integer(&r, "number of lamps", 1, 1000000, &lamps);
  if (st == VR_OK) st = number(&r, "lumens per lamp", &lumens);
  if (st == VR_OK && !(lumens > 0.0 || lumens == -1.0))
    st = fail(&r, r.line, "lumens per lamp must be > 0 or -1 (absolute photometry), not %g", lumens);
  if (st == VR_OK) st = number(&r, "candela multiplier", &mult);
  if (st == VR_OK && !(mult > 0.0)) st = fail(&r, r.line, "the candela multiplier must be > 0, not %g", mult);
  if (st == VR_OK) st = integer(&r, "number of vertical angles", 2, MAX_ANGLES, &nv);
  if (st == VR_OK) st = integer(&r, "number of horizontal angles", 1, MAX_ANGLES, &nh);
  if (st == VR_OK && nv * nh > MAX_VALUES)
    st = fail(&r, r.line, "too many candela values (%ld x %ld, over %d)", nv, nh, MAX_VALUES);
  if (st == VR_OK) st = integer(&r, "photometric type", 1, 3, &type);
  if (st == VR_OK && type != 1)
    st = fail(&r, r.line, "photometric type %s is not supported (type C, 1, only)",
              type == 2 ? "B (2)" : "A (3)");
  if (st == VR_OK) st = integer(&r, "units type", 1, 2, &units);
  if (st == VR_OK) st = number(&r, "luminous opening width", &w);
  if (st == VR_OK) st = number(&r, "luminous opening length", &l);
  if (st == VR_OK) st = number(&r, "luminous opening height", &h);
  if (st == VR_OK) st = number(&r, "ballast factor", &ballast);
  if (st == VR_OK && !(ballast > 0.0)) st = fail(&r, r.line, "the ballast factor must be > 0, not %g", ballast);
  if (st == VR_OK) st = number(&r, "ballast-lamp photometric factor", &blp);
  if (st == VR_OK && !(blp > 0.0))
    st = fail(&r, r.line, "the ballast-lamp photometric factor must be > 0, not %g", blp);
  if (st == VR_OK) st = number(&r, "input watts", &watts);
  if (st == VR_OK && !(watts >= 0.0)) st = fail(&r, r.line, "input watts must be >= 0, not %g", watts);
  if (st == VR_OK) {
    ies->nv = (size_t)nv;
    ies->nh = (size_t)nh;
    ies->v_deg = malloc(ies->nv * sizeof(double));
    ies->h_deg = malloc(ies->nh * sizeof(double));
    ies->cd = malloc(ies->nv * ies->nh * sizeof(double));
    if (!ies->v_deg || !ies->h_deg || !ies->cd)
      st = vr_error_set(err, VR_E_NOMEM, "out of memory reading %s", r.name);
  }
  if (st == VR_OK) st = angles(&r, ies->v_deg, ies->nv, "vertical");
  if (st == VR_OK) {
    double v0 = ies->v_deg[0], v1 = ies->v_deg[ies->nv - 1];
    if (!(near(v0, 0.0) || near(v0, 90.0)) || !(near(v1, 90.0) || near(v1, 180.0)))
      st = vr_error_at(err, VR_E_PARSE, r.name, r.line, 0,
                       "vertical angles run %g..%g; type C needs 0 or 90 first and 90 or 180 "
                       "last (LM-63-2002 5.9)",
                       v0, v1);
  }
  if (st == VR_OK) st = angles(&r, ies->h_deg, ies->nh, "horizontal");
  if (st == VR_OK) {
    double h0 = ies->h_deg[0], h1 = ies->h_deg[ies->nh - 1];
    if (ies->nh == 1)
      ies->symmetry = VR_IES_ROTATIONAL;
    else if (near(h0, 0.0) && near(h1, 90.0))
      ies->symmetry = VR_IES_QUADRANT;
    else if (near(h0, 0.0) && near(h1, 180.0))
      ies->symmetry = VR_IES_BILATERAL;
    else if (near(h0, 90.0) && near(h1, 270.0))
      ies->symmetry = VR_IES_BILATERAL_90;
    else if (near(h0, 0.0) && near(h1, 360.0))
      ies->symmetry = VR_IES_NONE;
    else
      st = vr_error_at(err, VR_E_PARSE, r.name, r.line, 0,
                       "horizontal angles run %g..%g; expected 0 alone, 0-90, 0-180, 90-270 or "
                       "0-360 (LM-63-2002 5.10)",
                       h0, h1);
  }
  double scale = mult * ballast * blp;
  for (size_t i = 0; st == VR_OK && i < ies->nh; i++) {
    for (size_t j = 0; st == VR_OK && j < ies->nv; j++) {
      char label[96];
      snprintf(label, sizeof label, "candela value %zu of horizontal angle %g", j + 1,
               ies->h_deg[i]);
      double c;
      st = number(&r, label, &c);
      if (st == VR_OK && c < 0.0)
        st = vr_error_at(err, VR_E_PARSE, r.name, r.line, 0, "%s is negative (%g)", label, c);
      if (st == VR_OK) ies->cd[i * ies->nv + j] = c * scale;
    }
  }
  if (st == VR_OK) {
    /* Trailing blanks, and the DOS end-of-file mark some tools leave, are
     * allowed; anything else means the counts and the data disagree. */
    while (r.p < r.end && (isspace((unsigned char)*r.p) || *r.p == ',' || *r.p == 0x1a ||
                           *r.p == '\0')) {
      if (*r.p == '\n') r.line++;
      r.p++;
    }
    if (r.p < r.end)
      st = fail(&r, r.line,
                "unexpected text after the candela values (more values than the angle counts "
                "announce?)");
  }
  if (st != VR_OK) {
    vr_ies_destroy(ies);
    return st;
  }
  ies->lamps = (int)lamps;
  ies->lumens_per_lamp = lumens;
  ies->multiplier = scale;
  ies->photometric_type = (int)type;
  /* International foot, 0.3048 m exactly. */
  double unit = units == 1 ? 0.3048 : 1.0;
  ies->width_m = w * unit;
  ies->length_m = l * unit;
  ies->height_m = h * unit;
  ies->input_watts = watts;
  *out = ies;
  return VR_OK;
}

vr_status vr_ies_read(const char *path, vr_ies **out, vr_error *err) {
  char *text;
  size_t len;
  *out = NULL;
  vr_status st = vr_read_file(path, MAX_FILE_BYTES, &text, &len, err);
  if (st != VR_OK) return st;
  st = vr_ies_parse(text, len, path, out, err);
  free(text);
  return st;
}

void vr_ies_destroy(vr_ies *ies) {
  if (!ies) return;
  free(ies->v_deg);
  free(ies->h_deg);
  free(ies->cd);
  free(ies);
}

/* ---- evaluation ---------------------------------------------------------- */

/* Index i with a[i] <= x <= a[i+1] (n >= 2, x within the range) and the
 * fraction along that interval. */
static size_t locate(const double *a, size_t n, double x, double *frac) {
  size_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    size_t mid = (lo + hi) / 2;
    if (a[mid] <= x)
      lo = mid;
    else
      hi = mid;
  }
  double t = (x - a[lo]) / (a[lo + 1] - a[lo]);
  *frac = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
  return lo;
}

static double wrap360(double deg) {
  double r = fmod(deg, 360.0);
  return r < 0.0 ? r + 360.0 : r;
}

/* Folds any horizontal angle into the measured range by the symmetry the
 * angle set implies (LM-63-2002 5.10). */
static double fold(const vr_ies *ies, double hdeg) {
  double h = wrap360(hdeg);
  switch (ies->symmetry) {
  case VR_IES_QUADRANT:
    if (h > 180.0) h = 360.0 - h;
    if (h > 90.0) h = 180.0 - h;
    break;
  case VR_IES_BILATERAL:
    if (h > 180.0) h = 360.0 - h;
    break;
  case VR_IES_BILATERAL_90: /* mirror about the 90-270 plane: h -> 180 - h */
    if (h < 90.0) h = 180.0 - h;
    else if (h > 270.0) h = 540.0 - h;
    break;
  default:
    break;
  }
  double h0 = ies->h_deg[0], h1 = ies->h_deg[ies->nh - 1];
  return h < h0 ? h0 : h > h1 ? h1 : h;
}

static double along_v(const vr_ies *ies, size_t row, size_t iv, double fv) {
  const double *c = ies->cd + row * ies->nv;
  return c[iv] + fv * (c[iv + 1] - c[iv]);
}

double vr_ies_candela(const vr_ies *ies, double v, double hdeg) {
  double v0 = ies->v_deg[0], v1 = ies->v_deg[ies->nv - 1];
  if (!(v >= v0 - ANGLE_TOL && v <= v1 + ANGLE_TOL)) return 0.0;
  double fv;
  size_t iv = locate(ies->v_deg, ies->nv, v < v0 ? v0 : v > v1 ? v1 : v, &fv);
  if (ies->nh == 1) return along_v(ies, 0, iv, fv);
  double fh;
  size_t ih = locate(ies->h_deg, ies->nh, fold(ies, hdeg), &fh);
  double a = along_v(ies, ih, iv, fv), b = along_v(ies, ih + 1, iv, fv);
  return a + fh * (b - a);
}

double vr_ies_candela_dir(const vr_ies *ies, const double d[3]) {
  double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  if (!(len > 0.0)) return 0.0;
  double cz = -d[2] / len;
  cz = cz > 1.0 ? 1.0 : cz < -1.0 ? -1.0 : cz;
  double v = acos(cz) / DEG; /* 0 at nadir */
  double h = (d[0] == 0.0 && d[1] == 0.0) ? 0.0 : atan2(d[1], d[0]) / DEG;
  return vr_ies_candela(ies, v, h);
}

double vr_ies_max_candela(const vr_ies *ies) {
  double m = 0.0;
  for (size_t i = 0; i < ies->nv * ies->nh; i++)
    if (ies->cd[i] > m) m = ies->cd[i];
  return m;
}

/* int_{V0}^{V1} I(V) sin V dV for I linear from I0 to I1, in closed form:
 * I0 (cos V0 - cos V1) + (I1 - I0)/dV (sin V1 - sin V0 - dV cos V1). */
static double column_integral(const vr_ies *ies, size_t row) {
  const double *c = ies->cd + row * ies->nv;
  double sum = 0.0;
  for (size_t j = 0; j + 1 < ies->nv; j++) {
    double a = ies->v_deg[j] * DEG, b = ies->v_deg[j + 1] * DEG, dv = b - a;
    sum += c[j] * (cos(a) - cos(b)) + (c[j + 1] - c[j]) / dv * (sin(b) - sin(a) - dv * cos(b));
  }
  return sum;
}

double vr_ies_lumens(const vr_ies *ies) {
  if (ies->nh == 1) return 2.0 * PI * column_integral(ies, 0);
  /* Bilinear in H as well: the H integral of each cell is the trapezoid of
   * its two edge columns, exact for a linear function. */
  double sum = 0.0, prev = column_integral(ies, 0);
  for (size_t i = 0; i + 1 < ies->nh; i++) {
    double next = column_integral(ies, i + 1);
    sum += 0.5 * (ies->h_deg[i + 1] - ies->h_deg[i]) * DEG * (prev + next);
    prev = next;
  }
  switch (ies->symmetry) {
  case VR_IES_QUADRANT: return 4.0 * sum;
  case VR_IES_BILATERAL:
  case VR_IES_BILATERAL_90: return 2.0 * sum;
  default: return sum;
  }
}
