/* LBNL optical standard files (*.std with *.ssp, *.dsp, *.wvl tables) and
 * the weighted means they define; vr/optical_standard.h has the formulas. */
#include "vr/optical_standard.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "vr/colour.h"
#include "vr/csv.h"
#include "vr/file.h"

typedef struct vr_embedded_file {
  const char *name;
  const unsigned char *data;
  const unsigned long *len;
} vr_embedded_file;
extern const vr_embedded_file vr_std_files[];
extern const unsigned long vr_std_files_count;

static const struct {
  const char *name, *file;
} BUILTIN[] = {
    {"nfrc", "W5_NFRC_2003.std"},
    {"en410", "prEN_410.std"},
    {"iso9050", "ISO_9050.std"},
};

const char *vr_standard_builtin_names(void) { return "nfrc en410 iso9050"; }

/* Where the table files of a standard come from. */
typedef struct loader {
  bool builtin;
  char dir[4096];
} loader;

static char *dup_text(const char *s, size_t n) {
  char *d = malloc(n + 1);
  if (d) {
    memcpy(d, s, n);
    d[n] = '\0';
  }
  return d;
}

/* Reads a whole file, from the built-in set or from the loader's folder. */
static vr_status load_text(const loader *ld, const char *name, char **text, size_t *len,
                           char *shown, size_t shown_size, vr_error *err) {
  if (ld->builtin) {
    for (unsigned long i = 0; i < vr_std_files_count; i++) {
      if (strcmp(vr_std_files[i].name, name) == 0) {
        snprintf(shown, shown_size, "built-in:%s", name);
        *len = *vr_std_files[i].len;
        *text = dup_text((const char *)vr_std_files[i].data, *len);
        return *text ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
      }
    }
    return vr_error_set(err, VR_E_NOT_FOUND, "built-in standard file \"%s\" does not exist", name);
  }
  snprintf(shown, shown_size, "%s%s", ld->dir, name);
  return vr_read_file(shown, 0, text, len, err);
}

/* Next line of text as a NUL-terminated, right-trimmed copy in line[]. */
static bool next_line(const char **p, const char *end, char *line, size_t size) {
  if (*p >= end) return false;
  const char *s = *p, *e = memchr(s, '\n', (size_t)(end - s));
  if (!e) e = end;
  size_t n = (size_t)(e - s);
  if (n >= size) n = size - 1;
  memcpy(line, s, n);
  line[n] = '\0';
  while (n > 0 && isspace((unsigned char)line[n - 1])) line[--n] = '\0';
  *p = e < end ? e + 1 : end;
  return true;
}

static const char *skip_space(const char *s) {
  while (isspace((unsigned char)*s)) s++;
  return s;
}

/* "Key : value" or "Key: value"; returns false when the line has no colon. */
static bool split_key(char *line, char **key, char **value) {
  char *colon = strchr(line, ':');
  if (!colon) return false;
  *colon = '\0';
  char *k = (char *)skip_space(line);
  size_t n = strlen(k);
  while (n > 0 && isspace((unsigned char)k[n - 1])) k[--n] = '\0';
  *key = k;
  *value = (char *)skip_space(colon + 1);
  return true;
}

/* A table file: header lines "Key: value" (Wavelength Units among them),
 * then rows "wavelength [value]" split by blanks or commas. */
static vr_status read_table(const loader *ld, const char *name, bool values, vr_spectrum **spec,
                            double **list, size_t *count, vr_error *err) {
  char *text = NULL, shown[4200];
  size_t len = 0;
  vr_status st = load_text(ld, name, &text, &len, shown, sizeof shown, err);
  if (st) return st;
  vr_wl_unit unit = VR_UNIT_UNKNOWN;
  size_t cap = 256, n = 0;
  double *wl = malloc(cap * sizeof *wl), *val = malloc(cap * sizeof *val);
  const char *p = text, *end = text + len;
  char line[1024];
  long lineno = 0;
  st = (wl && val) ? VR_OK : vr_error_set(err, VR_E_NOMEM, "out of memory");
  while (!st && next_line(&p, end, line, sizeof line)) {
    lineno++;
    const char *s = skip_space(line);
    if (*s == '\0') continue;
    if (isalpha((unsigned char)*s)) {
      char *key, *value;
      if (split_key(line, &key, &value) && strcasecmp(key, "Wavelength Units") == 0) {
        unit = vr_wavelength_unit_of(value);
        if (unit == VR_UNIT_UNKNOWN)
          st = vr_error_at(err, VR_E_PARSE, shown, lineno, 0, "unknown wavelength unit \"%s\"",
                           value);
      }
      continue;
    }
    if (unit == VR_UNIT_UNKNOWN) {
      st = vr_error_at(err, VR_E_PARSE, shown, lineno, 0,
                       "data before a \"Wavelength Units\" line");
      break;
    }
    for (char *c = line; *c; c++)
      if (*c == ',' || *c == '\t') *c = ' ';
    char *q = (char *)s, *stop;
    double x = strtod(q, &stop), y = 1;
    if (stop == q || !isfinite(x)) {
      st = vr_error_at(err, VR_E_PARSE, shown, lineno, 1, "wavelength is not a number");
      break;
    }
    if (values) {
      q = stop;
      y = strtod(q, &stop);
      if (stop == q || !isfinite(y)) {
        st = vr_error_at(err, VR_E_PARSE, shown, lineno, 2, "value is not a number");
        break;
      }
    }
    if (n == cap) {
      cap *= 2;
      double *w2 = realloc(wl, cap * sizeof *wl), *v2 = w2 ? realloc(val, cap * sizeof *val) : NULL;
      if (w2) wl = w2;
      if (v2) val = v2;
      if (!w2 || !v2) {
        st = vr_error_set(err, VR_E_NOMEM, "out of memory");
        break;
      }
    }
    wl[n] = vr_wavelength_to_nm(x, unit);
    val[n] = y;
    if (n > 0 && wl[n] <= wl[n - 1]) {
      st = vr_error_at(err, VR_E_PARSE, shown, lineno, 1,
                       "wavelengths must increase (%g nm after %g nm)", wl[n], wl[n - 1]);
      break;
    }
    n++;
  }
  if (!st && n == 0) st = vr_error_set(err, VR_E_PARSE, "%s: no data rows", shown);
  if (!st && spec) {
    *spec = vr_spectrum_create(n, wl, val, err);
    if (!*spec) st = err ? err->status : VR_E_NOMEM;
  }
  if (!st && list) {
    *list = wl;
    *count = n;
    wl = NULL;
  }
  free(wl);
  free(val);
  free(text);
  return st;
}

static void method_free(vr_std_method *m) {
  free(m->name);
  free(m->description);
  vr_spectrum_destroy(m->source);
  vr_spectrum_destroy(m->detector);
  free(m->list_nm);
  free(m->unsupported);
}

void vr_standard_destroy(vr_standard *s) {
  if (!s) return;
  for (size_t i = 0; i < s->count; i++) method_free(&s->methods[i]);
  free(s->methods);
  free(s->name);
  free(s->description);
  free(s);
}

static void mark_unsupported(vr_std_method *m, const char *what, const char *value) {
  if (m->unsupported) return;
  size_t n = strlen(what) + strlen(value) + 32;
  m->unsupported = malloc(n);
  if (m->unsupported) snprintf(m->unsupported, n, "%s \"%s\" is not supported", what, value);
}

static bool is_none(const char *v) { return strcasecmp(v, "None") == 0; }

/* One "Key : value" line of a method block. */
static vr_status method_set(const loader *ld, vr_std_method *m, const char *key, const char *value,
                            const char *file, long line, vr_error *err) {
  if (strcasecmp(key, "Description") == 0) {
    free(m->description);
    m->description = strdup(value);
    return VR_OK;
  }
  if (strcasecmp(key, "Source Spectrum") == 0) {
    double T;
    if (is_none(value)) return VR_OK;
    if (sscanf(value, "Blackbody (T=%lfK)", &T) == 1 && T > 0) {
      m->blackbody_K = T;
      return VR_OK;
    }
    return read_table(ld, value, true, &m->source, NULL, NULL, err);
  }
  if (strcasecmp(key, "Detector Spectrum") == 0) {
    if (is_none(value)) return VR_OK;
    if (sscanf(value, "UV Action (a=%lf, b=%lf)", &m->uv_a, &m->uv_b) == 2) {
      m->uv_action = true;
      return VR_OK;
    }
    if (strcasecmp(value, "Krochmann") == 0) {
      mark_unsupported(m, "detector", value);
      return VR_OK;
    }
    return read_table(ld, value, true, &m->detector, NULL, NULL, err);
  }
  if (strcasecmp(key, "Wavelength Set") == 0) {
    if (strcasecmp(value, "Source") == 0) m->wlset = VR_WLSET_SOURCE;
    else if (strcasecmp(value, "Data") == 0) m->wlset = VR_WLSET_DATA;
    else if (strcasecmp(value, "Detector") == 0) m->wlset = VR_WLSET_DETECTOR;
    else {
      m->wlset = VR_WLSET_LIST;
      return read_table(ld, value, false, NULL, &m->list_nm, &m->nlist, err);
    }
    return VR_OK;
  }
  if (strcasecmp(key, "Integration Rule") == 0) {
    double k;
    if (strncasecmp(value, "Trapezoidal", 11) == 0) m->rule = VR_INTEG_TRAPEZOIDAL;
    else if (strncasecmp(value, "Rectangular", 11) == 0) m->rule = VR_INTEG_RECTANGULAR;
    else if (strncasecmp(value, "Pre-weighted Table", 18) == 0) {
      m->rule = VR_INTEG_PREWEIGHTED;
      return VR_OK;
    } else {
      mark_unsupported(m, "integration rule", value);
      return VR_OK;
    }
    const char *k_at = strstr(value, "k=");
    if (strstr(value, "Normalized") && k_at && sscanf(k_at, "k=%lf", &k) == 1) m->norm_k = k;
    /* "Rectangular Centroid" and similar variants change where the sample
     * sits inside its interval; they are not the plain rule. */
    const char *rest = skip_space(value + 11);
    if (*rest && *rest != '(') mark_unsupported(m, "integration rule", value);
    return VR_OK;
  }
  if (strcasecmp(key, "Minimum Wavelength") == 0 || strcasecmp(key, "Maximum Wavelength") == 0) {
    bool is_max = tolower((unsigned char)key[1]) == 'a';
    if (strcasecmp(value, "Wavelength set") == 0) {
      if (is_max) m->max_nm = INFINITY;
      else m->min_nm = 0;
      return VR_OK;
    }
    double um;
    if (vr_parse_double(value, &um) != VR_OK || um <= 0)
      return vr_error_at(err, VR_E_PARSE, file, line, 0, "%s is not a positive number of um: \"%s\"",
                         key, value);
    if (is_max) m->max_nm = um * 1000.0;
    else m->min_nm = um * 1000.0;
    return VR_OK;
  }
  return vr_error_at(err, VR_E_PARSE, file, line, 0, "unknown key \"%s\" in method %s", key,
                     m->name);
}

static vr_status parse_std(const loader *ld, const char *text, size_t len, const char *shown,
                           vr_standard *s, vr_error *err) {
  const char *p = text, *end = text + len;
  char line[1024];
  long lineno = 0;
  vr_std_method *cur = NULL;
  while (next_line(&p, end, line, sizeof line)) {
    lineno++;
    if (*skip_space(line) == '\0') continue;
    char *key, *value;
    if (!split_key(line, &key, &value))
      return vr_error_at(err, VR_E_PARSE, shown, lineno, 0, "expected \"Key : value\"");
    if (strcasecmp(key, "Standard Description") == 0) {
      free(s->description);
      s->description = strdup(value);
      continue;
    }
    if (strcasecmp(key, "Standard Provides Methods") == 0) continue;
    if (strcasecmp(key, "Name") == 0) {
      vr_std_method *grown = realloc(s->methods, (s->count + 1) * sizeof *grown);
      if (!grown) return vr_error_set(err, VR_E_NOMEM, "out of memory");
      s->methods = grown;
      cur = &s->methods[s->count++];
      memset(cur, 0, sizeof *cur);
      cur->name = strdup(value);
      cur->max_nm = INFINITY;
      continue;
    }
    if (!cur)
      return vr_error_at(err, VR_E_PARSE, shown, lineno, 0, "\"%s\" before the first \"Name :\"",
                         key);
    vr_status st = method_set(ld, cur, key, value, shown, lineno, err);
    if (st) {
      vr_error_prefix(err, "%s:%ld: method %s: ", shown, lineno, cur->name);
      return st;
    }
  }
  if (s->count == 0) return vr_error_set(err, VR_E_PARSE, "%s: no methods (\"Name :\" blocks)", shown);
  return VR_OK;
}

vr_status vr_standard_open(const char *name_or_path, vr_standard **out, vr_error *err) {
  *out = NULL;
  loader ld = {.builtin = false};
  const char *file = name_or_path;
  for (size_t i = 0; i < sizeof BUILTIN / sizeof BUILTIN[0]; i++)
    if (strcasecmp(name_or_path, BUILTIN[i].name) == 0) {
      ld.builtin = true;
      file = BUILTIN[i].file;
    }
  if (!ld.builtin) {
    const char *slash = strrchr(name_or_path, '/');
    if (slash) {
      size_t n = (size_t)(slash - name_or_path) + 1;
      if (n >= sizeof ld.dir) return vr_error_set(err, VR_E_ARG, "path too long: %s", name_or_path);
      memcpy(ld.dir, name_or_path, n);
      ld.dir[n] = '\0';
      file = slash + 1;
    } else if (!strchr(name_or_path, '.')) {
      return vr_error_set(err, VR_E_NOT_FOUND, "unknown standard \"%s\" (built-in: %s, or a path to an .std file)",
                          name_or_path, vr_standard_builtin_names());
    }
  }
  char *text = NULL, shown[4200];
  size_t len = 0;
  vr_status st = load_text(&ld, file, &text, &len, shown, sizeof shown, err);
  if (st) return st;
  vr_standard *s = calloc(1, sizeof *s);
  if (!s) {
    free(text);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  s->name = strdup(name_or_path);
  st = parse_std(&ld, text, len, shown, s, err);
  free(text);
  if (st) {
    vr_standard_destroy(s);
    return st;
  }
  *out = s;
  return VR_OK;
}

const vr_std_method *vr_standard_method(const vr_standard *s, const char *name) {
  for (size_t i = 0; i < s->count; i++)
    if (strcasecmp(s->methods[i].name, name) == 0) return &s->methods[i];
  return NULL;
}

/* Source times detector at one wavelength. */
static double weight_at(const vr_std_method *m, double nm) {
  double w = 1.0;
  if (m->source) w *= vr_spectrum_eval(m->source, nm, VR_INTERP_LINEAR);
  else if (m->blackbody_K > 0) w *= vr_planck(nm, m->blackbody_K);
  if (m->detector) w *= vr_spectrum_eval(m->detector, nm, VR_INTERP_LINEAR);
  if (m->uv_action) w *= exp(m->uv_a - m->uv_b * nm / 1000.0);
  return w;
}

static vr_status set_grid(const vr_std_method *m, const vr_spectrum *data, const double **wl,
                          size_t *n, vr_error *err) {
  switch (m->wlset) {
  case VR_WLSET_SOURCE:
    if (!m->source)
      return vr_error_set(err, VR_E_ARG, "method %s: wavelength set \"Source\" without a source table",
                          m->name);
    *wl = m->source->nm;
    *n = m->source->n;
    return VR_OK;
  case VR_WLSET_DETECTOR:
    if (!m->detector)
      return vr_error_set(err, VR_E_ARG,
                          "method %s: wavelength set \"Detector\" without a detector table", m->name);
    *wl = m->detector->nm;
    *n = m->detector->n;
    return VR_OK;
  case VR_WLSET_DATA:
    *wl = data->nm;
    *n = data->n;
    return VR_OK;
  case VR_WLSET_LIST:
    *wl = m->list_nm;
    *n = m->nlist;
    return VR_OK;
  }
  return vr_error_set(err, VR_E_ARG, "method %s: bad wavelength set", m->name);
}

/* sum_w f S D and sum_w S D; f may be NULL (f = 1). */
static vr_status sums(const vr_std_method *m, const vr_spectrum *data, double *num, double *den,
                     vr_error *err) {
  if (m->unsupported) return vr_error_set(err, VR_E_ARG, "method %s: %s", m->name, m->unsupported);
  const double *wl = NULL;
  size_t n = 0;
  vr_status st = set_grid(m, data, &wl, &n, err);
  if (st) return st;
  const double tol = 1e-9 * m->min_nm + 1e-9;
  double a = 0, b = 0;
  for (size_t i = 0; i < n; i++) {
    if (wl[i] < m->min_nm - tol || wl[i] > m->max_nm + tol) continue;
    double w = weight_at(m, wl[i]);
    double f = data ? vr_spectrum_eval(data, wl[i], VR_INTERP_LINEAR) : 1.0;
    if (m->rule == VR_INTEG_TRAPEZOIDAL) {
      if (i + 1 >= n || wl[i + 1] > m->max_nm + tol) continue;
      double w1 = weight_at(m, wl[i + 1]);
      double f1 = data ? vr_spectrum_eval(data, wl[i + 1], VR_INTERP_LINEAR) : 1.0;
      double h = wl[i + 1] - wl[i];
      a += 0.5 * (f * w + f1 * w1) * h;
      b += 0.5 * (w + w1) * h;
    } else if (m->rule == VR_INTEG_PREWEIGHTED) {
      a += f * w;
      b += w;
    } else {
      double h = i + 1 < n ? wl[i + 1] - wl[i] : (n > 1 ? wl[i] - wl[i - 1] : 1.0);
      a += f * w * h;
      b += w * h;
    }
  }
  if (!(b > 0))
    return vr_error_set(err, VR_E_RANGE,
                        "method %s: no weight between %g and %g nm on its wavelength set", m->name,
                        m->min_nm, m->max_nm);
  *num = a;
  *den = b;
  return VR_OK;
}

/* The method's weight outside the data, as a share of its weight over its
 * range, on the source's (else detector's, else listed, else a 1 nm) grid:
 * the data's own grid cannot show what it lacks. */
static double uncovered_share(const vr_std_method *m, const vr_spectrum *data) {
  const double *wl = m->source ? m->source->nm : m->detector ? m->detector->nm
                   : m->wlset == VR_WLSET_LIST ? m->list_nm : NULL;
  size_t n = m->source ? m->source->n : m->detector ? m->detector->n
           : m->wlset == VR_WLSET_LIST ? m->nlist : 0;
  double lo = data->nm[0], hi = data->nm[data->n - 1], tol = 1e-9 * m->max_nm + 1e-9;
  double total = 0, out = 0;
  size_t steps = wl ? n : (size_t)(m->max_nm - m->min_nm) + 1;
  for (size_t i = 0; i < steps; i++) {
    double x = wl ? wl[i] : m->min_nm + (double)i;
    if (x < m->min_nm - tol || x > m->max_nm + tol) continue;
    double h = wl ? (i + 1 < n ? wl[i + 1] - x : (i > 0 ? x - wl[i - 1] : 1.0)) : 1.0;
    double w = fabs(weight_at(m, x)) * h;
    total += w;
    if (x < lo - tol || x > hi + tol) out += w;
  }
  return total > 0 ? out / total : (hi < m->min_nm || lo > m->max_nm ? 1.0 : 0.0);
}

static vr_status check_coverage(const vr_std_method *m, const vr_spectrum *data, vr_error *err) {
  double share = uncovered_share(m, data);
  if (data->nm[data->n - 1] < m->min_nm || data->nm[0] > m->max_nm || share > VR_STD_MAX_UNCOVERED)
    return vr_error_set(err, VR_E_RANGE,
                        "method %s needs data between %g and %g nm; the data span %g-%g nm, "
                        "leaving %.3g%% of its weight unmeasured (at most %g%% may be filled by "
                        "the nearest measured value)",
                        m->name, m->min_nm, m->max_nm, data->nm[0], data->nm[data->n - 1],
                        100 * share, 100 * VR_STD_MAX_UNCOVERED);
  return VR_OK;
}

vr_status vr_std_average(const vr_std_method *m, const vr_spectrum *data, double *out,
                         vr_error *err) {
  vr_status cs = check_coverage(m, data, err);
  if (cs) return cs;
  double a, b;
  vr_status st = sums(m, data, &a, &b, err);
  if (st) return st;
  *out = a / b;
  return VR_OK;
}

vr_status vr_std_sums(const vr_std_method *m, const vr_spectrum *data, double *num, double *den,
                      vr_error *err) {
  if (!data && m->wlset == VR_WLSET_DATA)
    return vr_error_set(err, VR_E_ARG, "method %s: its wavelength set is the data's", m->name);
  if (data) {
    vr_status cs = check_coverage(m, data, err);
    if (cs) return cs;
  }
  return sums(m, data, num, den, err);
}
