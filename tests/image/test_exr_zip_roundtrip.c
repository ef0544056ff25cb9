/* OpenEXR files written with ZIP compression read back bit for bit, also
 * for chunks whose deflated size comes out equal to their packed size
 * (OpenEXR issue #2306: the library of Debian 12, 3.1.5, stores such a
 * chunk deflated and its reader takes it for raw pixels; image/src/
 * exr_zip_guard.c stores it raw).
 *
 * The images: one ZIP chunk (16 rows) of 40 x 16 pixels, each value a
 * pseudo-random float with probability p, else a constant, for p from 0 to
 * 1 in fine steps and several seeds: as p grows the deflated chunk grows
 * through the packed size, and some of these images meet it exactly (with
 * the guard removed, the test fails on them: 5 of the 2400 images on
 * this machine).  Every value must come back equal, bit for bit, by our
 * reader and by the channel count. */
#include <math.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

#include "vr/image.h"

static uint64_t next(uint64_t *s) {
  /* splitmix64 (Steele, Lea & Flood 2014) */
  uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static void test_zip_chunks_read_back(void **state) {
  (void)state;
  char dir[] = "/tmp/vr-exr-zip-XXXXXX";
  assert_non_null(mkdtemp(dir));
  char path[64];
  snprintf(path, sizeof path, "%s/a.exr", dir);
  const int W = 40, H = 16;
  vr_image img = {.width = W, .height = H, .channels = 3, .bit_depth = 32,
                  .data = malloc(sizeof(float) * 3 * W * H)};
  assert_non_null(img.data);
  int bad = 0, images = 0;
  for (uint64_t seed = 1; seed <= 6; seed++)
    for (int step = 0; step < 400; step++, images++) {
      double p = step / 399.0;
      uint64_t s = seed * 1000003u + (uint64_t)step;
      for (int i = 0; i < 3 * W * H; i++) {
        bool random = (double)(next(&s) >> 11) * 0x1p-53 < p;
        img.data[i] = random ? (float)((double)(next(&s) >> 11) * 0x1p-53 * 5000.0) : 247.0f;
      }
      vr_error e = {0};
      if (vr_image_write_exr_with(path, &img, NULL, &e)) fail_msg("write: %s", e.message);
      vr_image back = {0};
      if (vr_image_read(path, &back, &e)) fail_msg("read: %s", e.message);
      assert_int_equal(back.width, W);
      assert_int_equal(back.height, H);
      if (memcmp(back.data, img.data, sizeof(float) * 3 * W * H) != 0) bad++;
      vr_image_free(&back);
    }
  print_message("    %d of %d ZIP images read back different\n", bad, images);
  assert_int_equal(bad, 0);
  free(img.data);
  unlink(path);
  rmdir(dir);
}

int main(void) {
  const struct CMUnitTest tests[] = {cmocka_unit_test(test_zip_chunks_read_back)};
  return cmocka_run_group_tests(tests, NULL, NULL);
}
