/* Helpers shared by the acquire/ image tests: a private temporary directory
 * per test program (removed at the end, and checked to hold only the files
 * the test wrote, so a leftover temporary file of an "atomic" write shows),
 * raw file writing, and test images with known values. */
#ifndef VR_IMAGE_TEST_UTIL_H
#define VR_IMAGE_TEST_UTIL_H

#include "vr_test.h"
#include "vr/image.h"

#include <dirent.h>

static char test_dir[64];

static inline int make_test_dir(void **state) {
  (void)state;
  snprintf(test_dir, sizeof test_dir, "/tmp/vr_image_XXXXXX");
  return mkdtemp(test_dir) ? 0 : -1;
}

/* Number of entries in the test directory (without . and ..). */
static inline int test_dir_entries(void) {
  DIR *d = opendir(test_dir);
  if (!d) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)))
    if (strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0) n++;
  closedir(d);
  return n;
}

static inline int remove_test_dir(void **state) {
  (void)state;
  DIR *d = opendir(test_dir);
  if (!d) return -1;
  struct dirent *e;
  char path[512];
  while ((e = readdir(d))) {
    if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0) continue;
    snprintf(path, sizeof path, "%s/%s", test_dir, e->d_name);
    unlink(path);
  }
  closedir(d);
  return rmdir(test_dir);
}

/* Path of name inside the test directory (8 rotating buffers). */
static inline const char *in_dir(const char *name) {
  static char paths[8][256];
  static int next;
  char *p = paths[next++ % 8];
  snprintf(p, 256, "%s/%s", test_dir, name);
  return p;
}

static inline void write_file(const char *path, const void *bytes, size_t len) {
  FILE *f = fopen(path, "wb");
  assert_non_null(f);
  assert_int_equal(fwrite(bytes, 1, len, f), len);
  assert_int_equal(fclose(f), 0);
}

static inline long file_size(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return -1;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fclose(f);
  return n;
}

static inline float *px(const vr_image *img, int x, int y) {
  return img->data + ((size_t)y * (size_t)img->width + (size_t)x) * 3;
}

/* w x h image whose channel c at (x, y) is the integer code
 * (x*7 + y*13 + c*101) mod (top+1), divided by top: every value exactly
 * representable in an 8-bit (top 255) or 16-bit (top 65535) file. */
static inline void make_coded_image(vr_image *img, int w, int h, int top) {
  vr_error err = {0};
  assert_int_equal(vr_image_alloc(img, w, h, &err), VR_OK);
  for (int y = 0; y < h; y++)
    for (int x = 0; x < w; x++)
      for (int c = 0; c < 3; c++) {
        long code = ((long)x * 7 * (top / 255) + (long)y * 13 * (top / 255) + c * 101L) % (top + 1);
        px(img, x, y)[c] = (float)code / (float)top;
      }
}

/* Largest |a - b| over all samples; the images must have the same size. */
static inline double max_abs_diff(const vr_image *a, const vr_image *b) {
  assert_int_equal(a->width, b->width);
  assert_int_equal(a->height, b->height);
  double m = 0;
  for (size_t i = 0; i < (size_t)a->width * (size_t)a->height * 3; i++)
    m = fmax(m, fabs((double)a->data[i] - (double)b->data[i]));
  return m;
}

#endif
