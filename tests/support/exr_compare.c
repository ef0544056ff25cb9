/* vr-test-exr-compare A.exr B.exr [TOL]: the largest relative difference
 * between two RGB OpenEXR images, value by value (values below 1e-12 in
 * both are equal); exit 0 if it is at most TOL (default 1e-6), 1 if not,
 * 2 if an image cannot be read or the sizes differ.  For the command-line
 * tests that compare renders made in different ways. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "vr/image.h"

int main(int argc, char **argv) {
  if (argc < 3) {
    fputs("usage: vr-test-exr-compare A.exr B.exr [TOL]\n", stderr);
    return 2;
  }
  double tol = argc > 3 ? atof(argv[3]) : 1e-6;
  vr_image a = {0}, b = {0};
  vr_error e = {0};
  if (vr_image_read(argv[1], &a, &e) || vr_image_read(argv[2], &b, &e)) {
    fprintf(stderr, "%s\n", e.message);
    vr_image_free(&a);
    return 2;
  }
  if (a.width != b.width || a.height != b.height) {
    fprintf(stderr, "sizes differ: %dx%d and %dx%d\n", a.width, a.height, b.width, b.height);
    vr_image_free(&a);
    vr_image_free(&b);
    return 2;
  }
  double worst = 0, sum = 0;
  size_t n = (size_t)a.width * a.height * 3;
  for (size_t i = 0; i < n; i++) {
    double u = a.data[i], v = b.data[i], m = fmax(fabs(u), fabs(v));
    sum += u;
    if (m > 1e-12) worst = fmax(worst, fabs(u - v) / m);
  }
  printf("largest relative difference %.3g over %zu values (sum %.6g)\n", worst, n, sum);
  vr_image_free(&a);
  vr_image_free(&b);
  return worst <= tol && sum > 0 ? 0 : 1;
}
