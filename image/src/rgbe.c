/* Radiance pictures: RGBE writing and reading (vr/rgbe.h). */
#include "vr/rgbe.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A pixel's four bytes (Ward 1991): the largest component's exponent is
 * shared; each mantissa is value / 2^(e-8), truncated. */
static void to_rgbe(const float rgb[3], unsigned char out[4]) {
  double v = fmax(fmax(rgb[0], rgb[1]), rgb[2]);
  if (!(v > 1e-32)) {
    memset(out, 0, 4);
    return;
  }
  int e;
  double m = frexp(v, &e); /* v = m 2^e, 0.5 <= m < 1 */
  if (e > 127) {           /* beyond the format: the largest it holds */
    e = 127;
    m = 255.0 / 256.0;
    v = ldexp(m, e);
  }
  double scale = m * 256.0 / v;
  for (int c = 0; c < 3; c++) {
    double x = rgb[c] > 0 ? rgb[c] * scale : 0.0;
    out[c] = (unsigned char)(x < 255.0 ? x : 255.0);
  }
  out[3] = (unsigned char)(e + 128);
}

static void from_rgbe(const unsigned char in[4], float out[3]) {
  if (!in[3]) {
    out[0] = out[1] = out[2] = 0;
    return;
  }
  double f = ldexp(1.0, (int)in[3] - (128 + 8));
  for (int c = 0; c < 3; c++) out[c] = (float)((in[c] + 0.5) * f);
}

/* One component of a scanline in runs: a run of 4 or more equal bytes as
 * (128 + n, byte), n <= 127; other bytes as (n, n bytes), n <= 128. */
static void put_component(FILE *f, const unsigned char *b, int w) {
  int i = 0;
  while (i < w) {
    /* the next run of at least 4 */
    int run_at = i, run = 1;
    while (run_at < w) {
      run = 1;
      while (run_at + run < w && run < 127 && b[run_at + run] == b[run_at]) run++;
      if (run >= 4) break;
      run_at += run;
    }
    if (run_at >= w) run = 0;
    /* the bytes before it, as literals */
    while (i < run_at) {
      int n = run_at - i < 128 ? run_at - i : 128;
      fputc(n, f);
      fwrite(b + i, 1, (size_t)n, f);
      i += n;
    }
    if (run >= 4) {
      fputc(128 + run, f);
      fputc(b[run_at], f);
      i = run_at + run;
    }
  }
}

vr_status vr_rgbe_write(const char *path, const vr_image *img, const vr_rgbe_header *h,
                        vr_error *err) {
  int W = img->width, H = img->height;
  if (W < 1 || H < 1 || !img->data)
    return vr_error_set(err, VR_E_ARG, "%s: no picture to write", path);
  size_t n = (size_t)W * (size_t)H * 3;
  for (size_t i = 0; i < n; i++)
    if (!isfinite(img->data[i]))
      return vr_error_set(err, VR_E_RANGE, "%s: pixel (%zu, %zu) is %s: a Radiance picture holds "
                          "finite values only", path, i / 3 % (size_t)W, i / 3 / (size_t)W,
                          isnan(img->data[i]) ? "NaN" : "infinite");
  unsigned char *row = malloc((size_t)W * 4), *comp = malloc((size_t)W);
  if (!row || !comp) {
    free(row);
    free(comp);
    return vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
  }
  FILE *f = fopen(path, "wb");
  if (!f) {
    free(row);
    free(comp);
    return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  }
  fprintf(f, "#?RADIANCE\n");
  if (h && h->software) fprintf(f, "SOFTWARE=%s\n", h->software);
  fprintf(f, "FORMAT=32-bit_rle_rgbe\n");
  if (h && h->exposure > 0) fprintf(f, "EXPOSURE=%.9g\n", h->exposure);
  if (h) {
    bool any = false;
    for (int k = 0; k < 8; k++) any |= h->primaries[k] != 0;
    if (any)
      fprintf(f, "PRIMARIES= %.4f %.4f %.4f %.4f %.4f %.4f %.4f %.4f\n", h->primaries[0],
              h->primaries[1], h->primaries[2], h->primaries[3], h->primaries[4], h->primaries[5],
              h->primaries[6], h->primaries[7]);
    if (h->view) fprintf(f, "VIEW=%s\n", h->view);
  }
  fprintf(f, "\n-Y %d +X %d\n", H, W);
  bool rle = W >= 8 && W < 32768;
  for (int y = 0; y < H; y++) {
    for (int x = 0; x < W; x++) to_rgbe(img->data + 3 * ((size_t)y * (size_t)W + (size_t)x), row + 4 * x);
    if (!rle) {
      fwrite(row, 4, (size_t)W, f);
      continue;
    }
    fputc(2, f), fputc(2, f), fputc(W >> 8, f), fputc(W & 255, f);
    for (int c = 0; c < 4; c++) {
      for (int x = 0; x < W; x++) comp[x] = row[4 * x + c];
      put_component(f, comp, W);
    }
  }
  free(row);
  free(comp);
  if (ferror(f) | (fclose(f) != 0)) return vr_error_set(err, VR_E_IO, "%s: write failed", path);
  return VR_OK;
}

/* ---- reading ---- */

static vr_status bad(vr_error *err, const char *path, const char *what, int y) {
  if (y >= 0) return vr_error_set(err, VR_E_PARSE, "%s: scanline %d: %s", path, y, what);
  return vr_error_set(err, VR_E_PARSE, "%s: %s", path, what);
}

/* Reads scanline y (W pixels) into row. */
static vr_status read_row(FILE *f, const char *path, int y, int W, unsigned char *row,
                          vr_error *err) {
  unsigned char b4[4];
  if (fread(b4, 1, 4, f) != 4) return bad(err, path, "the file ends here", y);
  bool rle = W >= 8 && W < 32768 && b4[0] == 2 && b4[1] == 2 && !(b4[2] & 0x80);
  if (!rle) {
    memcpy(row, b4, 4);
    if (W > 1 && fread(row + 4, 4, (size_t)W - 1, f) != (size_t)W - 1)
      return bad(err, path, "the file ends here", y);
    /* (1, 1, 1, n) repeats the pixel before it in the old encoding, as
     * Radiance reads any such pixel of a flat row. */
    for (int x = 1; x < W; x++)
      if (row[4 * x] == 1 && row[4 * x + 1] == 1 && row[4 * x + 2] == 1)
        return bad(err, path, "old-style run-length encoding, not read (convert with ra_rgbe)", y);
    return VR_OK;
  }
  if ((b4[2] << 8 | b4[3]) != W)
    return bad(err, path, "its run-length header gives another width than the picture's", y);
  for (int c = 0; c < 4; c++)
    for (int x = 0; x < W;) {
      int n = fgetc(f);
      if (n == EOF) return bad(err, path, "the file ends here", y);
      if (n > 128) {
        n -= 128;
        int v = fgetc(f);
        if (v == EOF) return bad(err, path, "the file ends here", y);
        if (x + n > W) return bad(err, path, "a run goes past the scanline's end", y);
        for (int k = 0; k < n; k++) row[4 * (x + k) + c] = (unsigned char)v;
        x += n;
      } else {
        if (n == 0 || x + n > W) return bad(err, path, "a literal run is empty or goes past the scanline's end", y);
        for (int k = 0; k < n; k++) {
          int v = fgetc(f);
          if (v == EOF) return bad(err, path, "the file ends here", y);
          row[4 * (x + k) + c] = (unsigned char)v;
        }
        x += n;
      }
    }
  return VR_OK;
}

vr_status vr_rgbe_read(const char *path, vr_image *out, vr_rgbe_info *info, vr_error *err) {
  memset(out, 0, sizeof *out);
  vr_rgbe_info tmp;
  if (!info) info = &tmp;
  memset(info, 0, sizeof *info);
  info->exposure = 1.0;
  FILE *f = fopen(path, "rb");
  if (!f) return vr_error_set(err, VR_E_IO, "%s: %s", path, strerror(errno));
  char line[4096];
  int ln = 0;
  bool magic = false, format_ok = true;
  vr_status st = VR_OK;
  for (;;) {
    if (!fgets(line, sizeof line, f)) {
      st = bad(err, path, "the header does not end (no empty line)", -1);
      goto done;
    }
    ln++;
    size_t len = strlen(line);
    if (len && line[len - 1] != '\n' && !feof(f)) {
      st = vr_error_set(err, VR_E_PARSE, "%s:%d: a header line longer than %zu bytes", path, ln,
                        sizeof line - 2);
      goto done;
    }
    while (len && (line[len - 1] == '\n' || line[len - 1] == '\r')) line[--len] = 0;
    if (ln == 1) {
      magic = !strcmp(line, "#?RADIANCE") || !strcmp(line, "#?RGBE");
      if (!magic) {
        st = vr_error_set(err, VR_E_PARSE, "%s:1: not a Radiance picture (no #?RADIANCE line)", path);
        goto done;
      }
      continue;
    }
    if (!len) break;
    if (!strncmp(line, "FORMAT=", 7)) {
      /* Radiance's formatval skips blanks around the value. */
      char *fv = line + 7;
      while (*fv == ' ' || *fv == '\t') fv++;
      size_t fl = strlen(fv);
      while (fl && (fv[fl - 1] == ' ' || fv[fl - 1] == '\t')) fv[--fl] = 0;
      format_ok = !strcmp(fv, "32-bit_rle_rgbe");
      if (!format_ok) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%d: FORMAT=%s: only 32-bit_rle_rgbe is read", path,
                          ln, line + 7);
        goto done;
      }
    } else if (!strncmp(line, "EXPOSURE=", 9)) {
      char *end;
      double e = strtod(line + 9, &end);
      if (end == line + 9 || !(e > 0) || !isfinite(e)) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%d: EXPOSURE=%s is not a positive number", path, ln,
                          line + 9);
        goto done;
      }
      info->exposure *= e;
    } else if (!strncmp(line, "VIEW=", 5)) {
      size_t m = strlen(line + 5);
      if (m >= sizeof info->view) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%d: a VIEW line longer than %zu bytes", path, ln,
                          sizeof info->view - 1);
        goto done;
      }
      memcpy(info->view, line + 5, m + 1);
    } else if (!strncmp(line, "PRIMARIES=", 10)) {
      double *p = info->primaries;
      if (sscanf(line + 10, "%lf %lf %lf %lf %lf %lf %lf %lf", p, p + 1, p + 2, p + 3, p + 4,
                 p + 5, p + 6, p + 7) != 8) {
        st = vr_error_set(err, VR_E_PARSE, "%s:%d: PRIMARIES= needs 8 numbers", path, ln);
        goto done;
      }
      info->has_primaries = true;
    }
  }
  int W, H;
  if (!fgets(line, sizeof line, f)) {
    st = bad(err, path, "no resolution line after the header", -1);
    goto done;
  }
  ln++;
  char ys[3], xs[3];
  if (sscanf(line, "%2s %d %2s %d", ys, &H, xs, &W) != 4 || strcmp(ys, "-Y") || strcmp(xs, "+X")) {
    st = vr_error_set(err, VR_E_PARSE, "%s:%d: resolution \"%.40s\": only -Y H +X W (rows from "
                      "the top, left to right) is read", path, ln, line);
    goto done;
  }
  if (W < 1 || H < 1 || W > 65535 || H > 65535 || (size_t)W * (size_t)H > ((size_t)1 << 28)) {
    st = vr_error_set(err, VR_E_PARSE, "%s:%d: a picture of %d x %d pixels (at most 65535 a side, "
                      "2^28 in all)", path, ln, W, H);
    goto done;
  }
  if ((st = vr_image_alloc(out, W, H, err))) goto done;
  unsigned char *row = malloc((size_t)W * 4);
  if (!row) {
    st = vr_error_set(err, VR_E_NOMEM, "%s: out of memory", path);
    goto done;
  }
  for (int y = 0; y < H && !st; y++) {
    st = read_row(f, path, y, W, row, err);
    for (int x = 0; x < W && !st; x++)
      from_rgbe(row + 4 * x, out->data + 3 * ((size_t)y * (size_t)W + (size_t)x));
  }
  free(row);
done:
  fclose(f);
  if (st) vr_image_free(out);
  return st;
}
