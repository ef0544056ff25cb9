/* A ray's wire form between ranks (render/src/ddm/ray_wire.h): the record
 * with its zero 8-byte words left out.  What must hold is exactness (the
 * image of several ranks equals one process's only if a ray arrives bit
 * for bit as it left) and refusal of what is not a record:
 *   - random records with random words zeroed, and the special values a
 *     path carries (-0.0, infinities, NaN with a payload, subnormals),
 *     come back byte for byte;
 *   - a record of zeros takes the 8-byte mask alone, one without a zero
 *     word the mask and all 38 words (312 bytes), and in general 8 bytes
 *     per non-zero word plus the mask (the format's definition);
 *   - a mask naming a word past the record's 38, or more words than the
 *     bytes left, is refused (0), as is anything shorter than a mask. */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "ddm/ray_wire.h"

static uint64_t next(uint64_t *s) { /* splitmix64 */
  uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static void round_trip(const vr_ray *r, size_t want_bytes) {
  unsigned char buf[VR_RAY_WIRE_MAX];
  size_t n = vr_ray_pack(r, buf);
  assert_int_equal(n, want_bytes);
  vr_ray back;
  memset(&back, 0xA5, sizeof back);
  assert_int_equal(vr_ray_unpack(buf, n, &back), n);
  assert_memory_equal(&back, r, sizeof *r);
  /* One byte short is not a record. */
  assert_int_equal(vr_ray_unpack(buf, n - 1, &back), 0);
}

static void test_round_trip_random(void **state) {
  (void)state;
  uint64_t s = 42;
  assert_int_equal(sizeof(vr_ray), 304);
  for (int k = 0; k < 20000; k++) {
    uint64_t w[38];
    size_t nonzero = 0;
    for (int i = 0; i < 38; i++) {
      w[i] = (next(&s) % 3 == 0) ? 0 : next(&s);
      nonzero += w[i] != 0;
    }
    vr_ray r;
    memcpy(&r, w, sizeof r);
    round_trip(&r, 8 + 8 * nonzero);
  }
}

static void test_extremes(void **state) {
  (void)state;
  vr_ray r;
  memset(&r, 0, sizeof r);
  round_trip(&r, 8); /* all zeros: the mask alone */
  memset(&r, 0xFF, sizeof r);
  round_trip(&r, VR_RAY_WIRE_MAX); /* no zero word: 312 bytes */
  assert_int_equal(VR_RAY_WIRE_MAX, 312);
  /* The values a path may carry, bit for bit. */
  memset(&r, 0, sizeof r);
  r.org[0] = -0.0;
  r.org[1] = 4.9e-324; /* the smallest subnormal */
  r.dir[2] = -1.0;
  r.tmax = INFINITY;
  r.tnear = -INFINITY;
  uint64_t qnan = 0x7FF8000000000123ull;
  memcpy(&r.dir[0], &qnan, 8);
  r.cell = 7;
  r.kind = 1;
  r.crossings = 65535;
  r.payload[VR_RAY_PAYLOAD - 1] = 1;
  round_trip(&r, 8 + 8 * 8); /* org 0 and 1, dir 0 and 2, tnear, tmax, cell word, last payload word */
  unsigned char buf[VR_RAY_WIRE_MAX];
  vr_ray_pack(&r, buf);
  vr_ray back;
  vr_ray_unpack(buf, sizeof buf, &back);
  assert_true(signbit(back.org[0]) && back.org[0] == 0.0);
}

static void test_refuses_what_is_not_a_ray(void **state) {
  (void)state;
  unsigned char buf[VR_RAY_WIRE_MAX];
  memset(buf, 0, sizeof buf);
  vr_ray r;
  /* Shorter than a mask. */
  assert_int_equal(vr_ray_unpack(buf, 7, &r), 0);
  /* A word the record does not have (bit 38). */
  uint64_t mask = (uint64_t)1 << 38;
  memcpy(buf, &mask, 8);
  assert_int_equal(vr_ray_unpack(buf, sizeof buf, &r), 0);
  /* Three words named, two present. */
  mask = 7;
  memcpy(buf, &mask, 8);
  assert_int_equal(vr_ray_unpack(buf, 8 + 16, &r), 0);
  assert_int_equal(vr_ray_unpack(buf, 8 + 24, &r), 8 + 24);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_round_trip_random),
      cmocka_unit_test(test_extremes),
      cmocka_unit_test(test_refuses_what_is_not_a_ray),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
