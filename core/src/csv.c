/* Delimited-text reader with positions: see vr/csv.h. */
#include "vr/csv.h"
#include "vr/file.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

typedef struct field { char *text; long col; } field;
typedef struct row { size_t first, count; long line; } row;

struct vr_csv {
  char *name;
  char *buf;                 /* private copy of the text, split in place */
  field *fields; size_t nfields, capfields;
  row *rows; size_t nrows, caprows;
  char **comments; size_t ncomments, capcomments;
};

static int grow(void **p, size_t *cap, size_t need, size_t elem) {
  if (need <= *cap) return 0;
  size_t c = *cap ? *cap * 2 : 64;
  while (c < need) c *= 2;
  void *q = realloc(*p, c * elem);
  if (!q) return -1;
  *p = q;
  *cap = c;
  return 0;
}

static char detect_separator(const char *line, size_t len) {
  int in_quotes = 0;
  char found = 0;
  const char order[] = {',', ';', '\t'};
  for (size_t k = 0; k < sizeof order && !found; k++)
    for (size_t i = 0; i < len; i++) {
      if (line[i] == '"') in_quotes = !in_quotes;
      if (!in_quotes && line[i] == order[k]) { found = order[k]; break; }
    }
  return found ? found : ' ';
}

static int is_blank(char c) { return c == ' ' || c == '\t'; }

/* Splits one line (NUL-terminated, inside buf) into fields. */
static vr_status split_line(vr_csv *csv, char *line, long lineno, char sep, vr_error *err) {
  row r = {csv->nfields, 0, lineno};
  char *p = line;
  for (;;) {
    if (sep == ' ')
      while (is_blank(*p)) p++;
    if (sep == ' ' && *p == '\0') break;
    while (sep != ' ' && is_blank(*p) && *p != sep) p++;
    long col = (long)(p - line) + 1;
    char *start = p, *out = p;
    if (*p == '"') {
      p++;
      for (;;) {
        if (*p == '\0')
          return vr_error_at(err, VR_E_PARSE, csv->name, lineno, col, "unterminated quoted field");
        if (*p == '"') {
          if (p[1] == '"') { *out++ = '"'; p += 2; continue; }
          p++;
          break;
        }
        *out++ = *p++;
      }
      while (is_blank(*p) && *p != sep) p++;
      if (*p != '\0' && *p != sep)
        return vr_error_at(err, VR_E_PARSE, csv->name, lineno, (long)(p - line) + 1,
                           "unexpected text after a quoted field");
    } else {
      while (*p != '\0' && *p != sep && !(sep == ' ' && is_blank(*p))) *out++ = *p++;
      while (out > start && is_blank(out[-1])) out--;
    }
    int more = *p == sep && sep != ' ';
    if (*p != '\0') p++;
    *out = '\0';
    if (grow((void **)&csv->fields, &csv->capfields, csv->nfields + 1, sizeof(field)))
      return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", csv->name);
    csv->fields[csv->nfields++] = (field){start, col};
    r.count++;
    if (sep != ' ' && !more) break;
    if (sep == ' ' && *p == '\0') break;
  }
  if (grow((void **)&csv->rows, &csv->caprows, csv->nrows + 1, sizeof(row)))
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", csv->name);
  csv->rows[csv->nrows++] = r;
  return VR_OK;
}

vr_status vr_csv_parse(const char *text, size_t len, const char *name, vr_csv **out,
                       vr_error *err) {
  *out = NULL;
  vr_csv *csv = calloc(1, sizeof *csv);
  if (!csv) return vr_error_set(err, VR_E_NOMEM, "out of memory");
  csv->name = strdup(name ? name : "<input>");
  csv->buf = malloc(len + 1);
  if (!csv->name || !csv->buf) {
    vr_csv_destroy(csv);
    return vr_error_set(err, VR_E_NOMEM, "out of memory");
  }
  memcpy(csv->buf, text, len);
  csv->buf[len] = '\0';
  vr_status enc = vr_text_check_encoding(text, len, name ? name : "<input>", err);
  if (enc) {
    vr_csv_destroy(csv);
    return enc;
  }
  if (memchr(csv->buf, '\0', len)) {
    vr_csv_destroy(csv);
    return vr_error_at(err, VR_E_PARSE, name, 0, 0, "binary data (NUL byte) in a text file");
  }
  char *p = csv->buf;
  if (len >= 3 && (unsigned char)p[0] == 0xEF && (unsigned char)p[1] == 0xBB &&
      (unsigned char)p[2] == 0xBF)
    p += 3;
  char sep = 0;
  long lineno = 0;
  while (*p) {
    lineno++;
    char *line = p;
    char *nl = strchr(p, '\n');
    p = nl ? nl + 1 : p + strlen(p);
    if (nl) *nl = '\0';
    size_t l = strlen(line);
    if (l && line[l - 1] == '\r') line[--l] = '\0';
    char *q = line;
    while (is_blank(*q)) q++;
    if (*q == '\0') continue;
    if (*q == '#') {
      if (grow((void **)&csv->comments, &csv->capcomments, csv->ncomments + 1, sizeof(char *))) {
        vr_csv_destroy(csv);
        return vr_error_set(err, VR_E_NOMEM, "out of memory");
      }
      csv->comments[csv->ncomments++] = q + 1;
      continue;
    }
    if (!sep) sep = detect_separator(line, l);
    vr_status st = split_line(csv, line, lineno, sep, err);
    if (st) {
      vr_csv_destroy(csv);
      return st;
    }
  }
  *out = csv;
  return VR_OK;
}

vr_status vr_csv_read(const char *path, vr_csv **out, vr_error *err) {
  *out = NULL;
  char *text;
  size_t len;
  vr_status st = vr_read_file(path, VR_TEXT_MAX_BYTES, &text, &len, err);
  if (st) return st;
  st = vr_csv_parse(text, len, path, out, err);
  free(text);
  return st;
}

void vr_csv_destroy(vr_csv *csv) {
  if (!csv) return;
  free(csv->name);
  free(csv->buf);
  free(csv->fields);
  free(csv->rows);
  free(csv->comments);
  free(csv);
}

const char *vr_csv_name(const vr_csv *csv) { return csv->name; }
size_t vr_csv_rows(const vr_csv *csv) { return csv->nrows; }
size_t vr_csv_cols(const vr_csv *csv, size_t r) { return r < csv->nrows ? csv->rows[r].count : 0; }
long vr_csv_line(const vr_csv *csv, size_t r) { return r < csv->nrows ? csv->rows[r].line : 0; }
size_t vr_csv_comment_count(const vr_csv *csv) { return csv->ncomments; }
const char *vr_csv_comment(const vr_csv *csv, size_t i) {
  return i < csv->ncomments ? csv->comments[i] : NULL;
}

const char *vr_csv_field(const vr_csv *csv, size_t r, size_t c) {
  if (r >= csv->nrows || c >= csv->rows[r].count) return NULL;
  return csv->fields[csv->rows[r].first + c].text;
}

long vr_csv_col_pos(const vr_csv *csv, size_t r, size_t c) {
  if (r >= csv->nrows) return 0;
  if (c >= csv->rows[r].count) {
    /* Past the last field: point just after it. */
    if (csv->rows[r].count == 0) return 1;
    const field *f = &csv->fields[csv->rows[r].first + csv->rows[r].count - 1];
    return f->col + (long)strlen(f->text);
  }
  return csv->fields[csv->rows[r].first + c].col;
}

int vr_parse_double(const char *s, double *out) {
  while (isspace((unsigned char)*s)) s++;
  if (*s == '\0') return -1;
  char *end;
  errno = 0;
  double v = strtod(s, &end);
  if (end == s) return -1;
  while (isspace((unsigned char)*end)) end++;
  if (*end != '\0') return -1;
  if (!isfinite(v)) return -2;
  if (errno == ERANGE && fabs(v) > 1.0) return -2;
  *out = v;
  return 0;
}

vr_status vr_csv_number(const vr_csv *csv, size_t r, size_t c, const char *field_name,
                        double *out, vr_error *err) {
  const char *s = vr_csv_field(csv, r, c);
  long line = vr_csv_line(csv, r), col = vr_csv_col_pos(csv, r, c);
  if (!s)
    return vr_error_at(err, VR_E_PARSE, csv->name, line, col,
                       "field '%s' (column %zu) is missing", field_name, c + 1);
  int rc = vr_parse_double(s, out);
  if (rc == -2)
    return vr_error_at(err, VR_E_RANGE, csv->name, line, col,
                       "field '%s': '%s' is not a finite number", field_name, s);
  if (rc)
    return vr_error_at(err, VR_E_PARSE, csv->name, line, col,
                       "field '%s': expected a number, got '%s'", field_name, s);
  return VR_OK;
}

long vr_csv_find_column(const vr_csv *csv, size_t header_row, const char *name) {
  for (size_t c = 0; c < vr_csv_cols(csv, header_row); c++)
    if (strcasecmp(vr_csv_field(csv, header_row, c), name) == 0) return (long)c;
  return -1;
}

int vr_parse_doubles(const char *s, double *out, size_t max, size_t *n) {
  *n = 0;
  const char *p = s;
  char field[128];
  for (;;) {
    const char *comma = strchr(p, ',');
    size_t len = comma ? (size_t)(comma - p) : strlen(p);
    if (len >= sizeof field || *n == max) return -1;
    memcpy(field, p, len);
    field[len] = '\0';
    if (vr_parse_double(field, &out[*n])) return -1;
    (*n)++;
    if (!comma) return 0;
    p = comma + 1;
  }
}

void vr_csv_write_field(FILE *f, const char *s) {
  if (!strpbrk(s, ",\"\r\n")) {
    fputs(s, f);
    return;
  }
  fputc('"', f);
  for (; *s; s++) {
    if (*s == '"') fputc('"', f);
    fputc(*s, f);
  }
  fputc('"', f);
}
