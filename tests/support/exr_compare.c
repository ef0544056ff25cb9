/* vr-test-exr-compare [--spectral] A.exr B.exr [TOL]: the largest relative
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

int main(int argc, char **argv) {
  int at = argc > 1 && !strcmp(argv[1], "--spectral") ? 2 : 1;
  if (argc - at < 2) {
    fputs("usage: vr-test-exr-compare [--spectral] A.exr B.exr [TOL]\n", stderr);
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
