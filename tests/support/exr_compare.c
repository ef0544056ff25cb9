/* vr-test-exr-compare --error REF.exr A.exr: A's luminance error against a
 * reference (error_mode below), for the benchmarks.
 * vr-test-exr-compare [--spectral] A.exr B.exr [TOL]: the largest relative
 * difference between two OpenEXR images, value by value (values below
 * 1e-12 in both are equal): their R, G, B, or with --spectral every band
 * of two spectral EXRs (with the same wavelengths).  Exit 0 if it is at
 * most TOL (default 1e-6) and the image is not black, 1 if not, 2 if an
 * image cannot be read or the sizes differ.  For the command-line tests
 * that compare renders made in different ways. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vr/image.h"
#include "vr/spectral_exr.h"

static int verdict(const float *a, const float *b, size_t n, double tol) {
  double worst = 0, sum = 0;
  for (size_t i = 0; i < n; i++) {
    double u = a[i], v = b[i], m = fmax(fabs(u), fabs(v));
    sum += u;
    if (m > 1e-12) worst = fmax(worst, fabs(u - v) / m);
  }
  printf("largest relative difference %.3g over %zu values (sum %.6g)\n", worst, n, sum);
  return worst <= tol && sum > 0 ? 0 : 1;
}

static int spectral(const char *pa, const char *pb, double tol) {
  vr_spectral_image a = {0}, b = {0};
  vr_error e = {0};
  if (vr_spectral_exr_read(pa, &a, NULL, &e) || vr_spectral_exr_read(pb, &b, NULL, &e)) {
    fprintf(stderr, "%s\n", e.message);
    vr_spectral_image_free(&a);
    return 2;
  }
  int rc = 2;
  if (a.width != b.width || a.height != b.height || a.nbands != b.nbands ||
      memcmp(a.wavelengths_nm, b.wavelengths_nm, a.nbands * sizeof(double)))
    fprintf(stderr, "sizes or bands differ: %dx%d x %zu and %dx%d x %zu\n", a.width, a.height,
            a.nbands, b.width, b.height, b.nbands);
  else
    rc = verdict(a.data, b.data, (size_t)a.width * (size_t)a.height * a.nbands, tol);
  vr_spectral_image_free(&a);
  vr_spectral_image_free(&b);
  return rc;
}

static int cmp_double(const void *a, const void *b) {
  double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

/* --error REF.exr A.exr: A's luminance error against the reference, per
 * pixel |Y_a - Y_ref| / max(Y_ref, 1 % of the reference's mean Y) (Y from
 * linear sRGB by BT.709's weights), as the root mean square and the 95th
 * percentile over the pixels, and both images' mean Y. */
static int error_mode(const char *pref, const char *pa) {
  vr_image r = {0}, a = {0};
  vr_error e = {0};
  if (vr_image_read(pref, &r, &e) || vr_image_read(pa, &a, &e)) {
    fprintf(stderr, "%s\n", e.message);
    vr_image_free(&r);
    return 2;
  }
  size_t n = (size_t)r.width * (size_t)r.height;
  double *rel = a.width == r.width && a.height == r.height ? malloc((n ? n : 1) * sizeof *rel) : NULL;
  if (!rel) {
    fprintf(stderr, "sizes differ or out of memory\n");
    vr_image_free(&r);
    vr_image_free(&a);
    return 2;
  }
  double mr = 0, ma = 0, s2 = 0;
  for (size_t p = 0; p < n; p++) {
    const float *x = &r.data[3 * p], *y = &a.data[3 * p];
    mr += 0.2126 * x[0] + 0.7152 * x[1] + 0.0722 * x[2];
    ma += 0.2126 * y[0] + 0.7152 * y[1] + 0.0722 * y[2];
  }
  mr /= (double)n;
  ma /= (double)n;
  for (size_t p = 0; p < n; p++) {
    const float *x = &r.data[3 * p], *y = &a.data[3 * p];
    double Yr = 0.2126 * x[0] + 0.7152 * x[1] + 0.0722 * x[2];
    double Ya = 0.2126 * y[0] + 0.7152 * y[1] + 0.0722 * y[2];
    rel[p] = fabs(Ya - Yr) / fmax(Yr, 0.01 * mr);
    s2 += rel[p] * rel[p];
  }
  /* Where the error is: the share of the squared error in each ninth of
   * the image (3 x 3 blocks, rows from the top). */
  double part[9] = {0};
  for (size_t p = 0; p < n; p++) {
    int bx = (int)(p % (size_t)r.width) * 3 / r.width, by = (int)(p / (size_t)r.width) * 3 / r.height;
    part[by * 3 + bx] += rel[p] * rel[p] / (s2 > 0 ? s2 : 1);
  }
  printf("# squared error by ninth of the image:");
  for (int k = 0; k < 9; k++) printf(" %.2f", part[k]);
  printf("\n");
  qsort(rel, n, sizeof *rel, cmp_double);
  printf("rms_rel %.5f p95_rel %.5f mean_ref %.6g mean %.6g\n", sqrt(s2 / (double)n),
         rel[(size_t)(0.95 * (double)(n - 1))], mr, ma);
  free(rel);
  vr_image_free(&r);
  vr_image_free(&a);
  return 0;
}

int main(int argc, char **argv) {
  if (argc == 4 && !strcmp(argv[1], "--error")) return error_mode(argv[2], argv[3]);
  int at = argc > 1 && !strcmp(argv[1], "--spectral") ? 2 : 1;
  if (argc - at < 2) {
    fputs("usage: vr-test-exr-compare [--spectral] A.exr B.exr [TOL]\n"
          "       vr-test-exr-compare --error REF.exr A.exr\n", stderr);
    return 2;
  }
  double tol = argc - at > 2 ? atof(argv[at + 2]) : 1e-6;
  if (at == 2) return spectral(argv[at], argv[at + 1], tol);
  vr_image a = {0}, b = {0};
  vr_error e = {0};
  if (vr_image_read(argv[at], &a, &e) || vr_image_read(argv[at + 1], &b, &e)) {
    fprintf(stderr, "%s\n", e.message);
    vr_image_free(&a);
    return 2;
  }
  int rc = 2;
  if (a.width != b.width || a.height != b.height)
    fprintf(stderr, "sizes differ: %dx%d and %dx%d\n", a.width, a.height, b.width, b.height);
  else
    rc = verdict(a.data, b.data, (size_t)a.width * (size_t)a.height * 3, tol);
  vr_image_free(&a);
  vr_image_free(&b);
  return rc;
}
