/* A ray's wire form between ranks (render/src/ddm/ray_wire.c, the paths'
 * payload codec render/src/integrators/payload_wire.c, vr/wire.h).  What
 * must hold:
 *   - exactness: the image of several ranks equals one process's only if
 *     a ray arrives bit for bit as it left.  Random records (numbers that
 *     a float holds and numbers it does not, -0.0, infinities, NaN with a
 *     payload, subnormals; random payloads of every wavelength count, with
 *     and without a portal distance and a ray cone) come back exactly,
 *     through the generic payload form and through the paths' codec;
 *   - size: issue 31 asks for at most 96 bytes a ray on the wire; a path
 *     ray as vr_flow_push leaves it (four hero wavelengths) takes the
 *     bytes the format's definition gives (74 for a 320 x 240 camera ray),
 *     and so do the other kinds below;
 *   - the varints are LEB128 and ZigZag as Protocol Buffers define them
 *     (protobuf.dev/programming-guides/encoding: 150 is 96 01, 300 is
 *     ac 02; ZigZag maps 0, -1, 1, -2, 2147483647, -2147483648 to 0, 1, 2,
 *     3, 4294967294, 4294967295);
 *   - refusal: every truncation of a record, flags out of range, a codec's
 *     payload where no codec is, a wavelength count past the slots;
 *   - rays a real run sent (two ranks on the sample room) read whole, each
 *     within 96 bytes, and written again byte for byte. */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <cmocka.h>

#include "ddm/ray_wire.h"
#include "integrators/pass.h"
#include "vr/wire.h"

static uint64_t next(uint64_t *s) { /* splitmix64 */
  uint64_t z = (*s += 0x9E3779B97F4A7C15ull);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static vr_rscene g_rs;
static vr_pass g_pass;
static const vr_flow_ops g_ops = {NULL, NULL, NULL, NULL, VR_PAYLOAD_WIRE};

static void setup_scene(bool bins, int nwl) {
  memset(&g_rs, 0, sizeof g_rs);
  g_rs.lmin = 360;
  g_rs.lmax = 830;
  g_rs.nwl = nwl;
  g_rs.bins_mode = bins;
  memset(&g_pass, 0, sizeof g_pass);
  g_pass.rs = &g_rs;
}

/* A number of one of the kinds a ray may carry. */
static double any_number(uint64_t *s) {
  uint64_t bits = next(s);
  double d;
  switch (next(s) % 8) {
  case 0: return 0.0;
  case 1: return -0.0;
  case 2: return next(s) & 1 ? INFINITY : -INFINITY;
  case 3: bits = 0x7FF8000000000000ull | (bits & 0xFFFFFFFFFFFull); break; /* NaN, a payload */
  case 4: bits &= 0x800FFFFFFFFFFFFFull; break;                          /* subnormal */
  case 5: return (double)(float)((double)(bits >> 11) * 0x1.0p-40 - 2e3); /* a float */
  default: break;                                                      /* any double */
  }
  memcpy(&d, &bits, 8);
  return d;
}

static void random_header(uint64_t *s, vr_ray *r) {
  memset(r, 0, sizeof *r);
  for (int a = 0; a < 3; a++) {
    r->org[a] = any_number(s);
    r->dir[a] = any_number(s);
  }
  r->tnear = any_number(s);
  r->tmax = any_number(s);
  r->cell = (int32_t)(next(s) % 3 ? next(s) % 64 : next(s) >> 33);
  r->kind = (uint8_t)next(s);
  r->purpose = (uint8_t)next(s);
  r->crossings = (uint16_t)next(s);
}

static void random_payload(uint64_t *s, vr_payload *p) {
  memset(p, 0, sizeof *p); /* padding zero: unpack gives it as zeros */
  p->index = (uint32_t)(next(s) >> (next(s) % 33));
  switch (next(s) % 4) {
  case 0: p->stream = p->index; break;
  case 1: p->stream = VR_STREAM_SENSOR + p->index; break;
  case 2: p->stream = VR_STREAM_PHOTON + (next(s) >> (next(s) % 64)); break; /* may wrap */
  default: p->stream = next(s) >> (next(s) % 64); break;
  }
  p->sample = (uint32_t)(next(s) >> (next(s) % 33));
  p->depth = (uint8_t)next(s);
  p->target = (uint8_t)next(s);
  p->nwl = (uint8_t)(1 + next(s) % VR_MAX_WL);
  p->source = (uint8_t)next(s);
  p->flags = (uint16_t)next(s);
  p->patch = (uint8_t)next(s);
  p->holes = (uint8_t)next(s);
  p->medium = (int32_t)(next(s) % 2 ? -1 : (int64_t)(next(s) >> 32) - 2147483648LL);
  p->weight = any_number(s);
  bool rule = next(s) % 2;
  p->wl[0] = any_number(s);
  for (int i = 1; i < p->nwl; i++)
    p->wl[i] = rule ? vr_wavelength_at(&g_rs, p->wl[0], i) : any_number(s);
  for (int i = 0; i < p->nwl; i++) p->beta[i] = any_number(s);
  if (next(s) % 4 == 0) p->beta[VR_MAX_WL - 1] = any_number(s); /* a tail slot in use */
  if (next(s) % 3 == 0) p->portal_t = any_number(s);
  if (next(s) % 3 == 0) {
    p->cone_w = (float)any_number(s);
    p->cone_a = (float)any_number(s);
  }
}

static size_t round_trip(const vr_flow_ops *ops, const vr_ray *r) {
  unsigned char buf[VR_RAY_WIRE_MAX + 8];
  size_t n = vr_ray_pack(ops, &g_pass, r, buf);
  assert_true(n > 0 && n <= VR_RAY_WIRE_MAX);
  vr_ray back;
  memset(&back, 0xA5, sizeof back);
  assert_int_equal(vr_ray_unpack(ops, &g_pass, buf, n, &back), n);
  assert_memory_equal(&back, r, sizeof *r);
  /* Every truncation is not a record. */
  for (size_t k = 0; k < n; k++) assert_int_equal(vr_ray_unpack(ops, &g_pass, buf, k, &back), 0);
  return n;
}

static void test_varints_as_protobuf_defines(void **state) {
  (void)state;
  unsigned char b[16];
  assert_int_equal(vr_wire_put_u64(b, 150) - b, 2);
  assert_int_equal(b[0], 0x96);
  assert_int_equal(b[1], 0x01);
  assert_int_equal(vr_wire_put_u64(b, 300) - b, 2);
  assert_int_equal(b[0], 0xAC);
  assert_int_equal(b[1], 0x02);
  assert_int_equal(vr_wire_put_u64(b, UINT64_MAX) - b, 10);
  const int64_t zin[] = {0, -1, 1, -2, 2147483647, -2147483648LL};
  const uint64_t zout[] = {0, 1, 2, 3, 4294967294u, 4294967295u};
  for (int i = 0; i < 6; i++) {
    unsigned char z[16], e[16];
    size_t n = (size_t)(vr_wire_put_i64(z, zin[i]) - z);
    assert_int_equal(n, (size_t)(vr_wire_put_u64(e, zout[i]) - e));
    assert_memory_equal(z, e, n);
    vr_wire_in in = {z, z + n};
    int64_t back;
    assert_true(vr_wire_get_i64(&in, &back));
    assert_true(back == zin[i]);
  }
  /* An 11th byte, or a 10th past 64 bits, is not a varint. */
  memset(b, 0x80, 11);
  b[10] = 0;
  vr_wire_in in = {b, b + 11};
  uint64_t v;
  assert_false(vr_wire_get_u64(&in, &v));
  memset(b, 0xFF, 9);
  b[9] = 2;
  in = (vr_wire_in){b, b + 10};
  assert_false(vr_wire_get_u64(&in, &v));
}

static void test_round_trip_generic_payload(void **state) {
  (void)state;
  setup_scene(false, 4);
  uint64_t s = 42;
  for (int k = 0; k < 5000; k++) {
    vr_ray r;
    random_header(&s, &r);
    for (size_t i = 0; i < VR_RAY_PAYLOAD; i += 8)
      if (next(&s) % 3) {
        uint64_t w = next(&s);
        memcpy(r.payload + i, &w, 8);
      }
    round_trip(NULL, &r);
  }
}

static void test_round_trip_paths_codec(void **state) {
  (void)state;
  uint64_t s = 7;
  for (int k = 0; k < 20000; k++) {
    setup_scene(k % 5 == 0, 1 + (int)(k % VR_MAX_WL));
    vr_ray r;
    random_header(&s, &r);
    vr_payload p;
    random_payload(&s, &p);
    memcpy(r.payload, &p, sizeof p);
    round_trip(&g_ops, &r);
  }
}

/* A path ray as vr_flow_push leaves it: rounded, handed over (tnear a
 * double), four hero wavelengths. */
static vr_ray camera_ray(uint32_t pixel) {
  vr_ray r;
  memset(&r, 0, sizeof r);
  r.org[0] = 1.2345678901;
  r.org[1] = -0.7;
  r.org[2] = 2.5;
  r.dir[0] = 0.6;
  r.dir[1] = -0.48;
  r.dir[2] = 0.64;
  r.tmax = INFINITY;
  vr_ray_round(&r);
  r.tnear = 1.0 / 3.0; /* the interface, not a float */
  r.cell = 5;
  r.kind = VR_RAY_CLOSEST;
  r.purpose = 1;
  r.crossings = 1;
  vr_payload p;
  memset(&p, 0, sizeof p);
  p.stream = pixel;
  p.index = pixel;
  p.sample = 15;
  p.nwl = (uint8_t)g_rs.nwl;
  p.flags = VR_PF_SPECULAR_LAST;
  p.patch = VR_NO_PATCH;
  p.medium = -1;
  p.weight = 1.0 / 16.0 * 0.93;
  p.wl[0] = (double)(float)547.123;
  for (int i = 1; i < p.nwl; i++) p.wl[i] = vr_wavelength_at(&g_rs, p.wl[0], i);
  for (int i = 0; i < p.nwl; i++) p.beta[i] = 0.8 / (i + 1);
  memcpy(r.payload, &p, sizeof p);
  vr_payload_round(&g_pass, r.payload);
  return r;
}

static void test_sizes_by_definition(void **state) {
  (void)state;
  setup_scene(false, 4);
  /* Flags 0x340 (tnear a double, the codec, kind and purpose in a byte):
   * 2 bytes; cell, kind and purpose, crossings: 3; seven floats and a
   * double: 36.  Payload: flags 0x1A (the usual fields, the wavelengths'
   * rule, stream = index): 1; sample 1; index 76799: 3; depth 1; target
   * and source 1; flags 1; medium -1: 1; weight 4; the hero 4; four
   * throughputs 16.  41 + 33 = 74. */
  vr_ray r = camera_ray(76799);
  assert_int_equal(round_trip(&g_ops, &r), 74); /* issue 31's bound: 96 */
  /* A 4K frame's last pixel (8294399 < 2^28): the index takes 4 bytes. */
  r = camera_ray(3840 * 2160 - 1);
  assert_int_equal(round_trip(&g_ops, &r), 75);
  /* A shadow ray: tmax a float, not infinite: the same bytes. */
  r = camera_ray(76799);
  r.kind = VR_RAY_SHADOW;
  r.tmax = vr_wire_round(3.75);
  assert_int_equal(round_trip(&g_ops, &r), 74);
  /* A photon: its stream VR_STREAM_PHOTON + 1234 goes as 1234 (2 bytes),
   * its index 0 in 1: 74 - 3 + 1 + 2 = 74. */
  r = camera_ray(76799);
  vr_payload p;
  memcpy(&p, r.payload, sizeof p);
  p.stream = VR_STREAM_PHOTON + 1234;
  p.index = 0;
  memcpy(r.payload, &p, sizeof p);
  assert_int_equal(round_trip(&g_ops, &r), 74);
  /* A sensor path: VR_STREAM_SENSOR + its point 37, the index in 1 byte:
   * 72. */
  p.stream = VR_STREAM_SENSOR + 37;
  p.index = 37;
  memcpy(r.payload, &p, sizeof p);
  assert_int_equal(round_trip(&g_ops, &r), 74 - 2);
  /* Any other stream goes whole: 2^40 takes 6 bytes. */
  p.stream = 1ull << 40;
  memcpy(r.payload, &p, sizeof p);
  assert_int_equal(round_trip(&g_ops, &r), 72 + 6);
  /* A sky shadow ray names its patch: target, nwl, source, patch and
   * holes a byte each, 4 more: 78. */
  r = camera_ray(76799);
  memcpy(&p, r.payload, sizeof p);
  p.patch = 17;
  memcpy(r.payload, &p, sizeof p);
  assert_int_equal(round_trip(&g_ops, &r), 78);
  /* Eight fixed bins (bins mode): four throughputs more: 90. */
  setup_scene(true, 8);
  r = camera_ray(76799);
  assert_int_equal(round_trip(&g_ops, &r), 90);
  /* Unrounded, the same ray goes whole: the weight and throughputs as
   * doubles, 4 bytes more each. */
  setup_scene(false, 4);
  r = camera_ray(76799);
  memcpy(&p, r.payload, sizeof p);
  p.weight = 1.0 / 3.0;
  for (int i = 0; i < 4; i++) p.beta[i] = 1.0 / (3.0 + 2 * i); /* 1/3, 1/5, 1/7, 1/9 */
  memcpy(r.payload, &p, sizeof p);
  /* Flags grow past 7 bits (beta bits 17..20): 3 bytes, not 1. */
  assert_int_equal(round_trip(&g_ops, &r), 74 + 4 + 16 + 2);
}

static void test_rounding(void **state) {
  (void)state;
  setup_scene(false, 4);
  vr_ray r;
  uint64_t s = 3;
  for (int k = 0; k < 1000; k++) {
    random_header(&s, &r);
    vr_payload p;
    random_payload(&s, &p);
    memcpy(r.payload, &p, sizeof p);
    vr_ray_round(&r);
    vr_payload_round(&g_pass, r.payload);
    memcpy(&p, r.payload, sizeof p);
    /* Every number rounded is a float now, or beyond the float's range
     * (kept as it is), or a NaN. */
    double *n[] = {&r.org[0], &r.org[1], &r.org[2], &r.dir[0], &r.dir[1], &r.dir[2],
                   &r.tnear,  &r.tmax,   &p.weight, &p.portal_t};
    for (size_t i = 0; i < sizeof n / sizeof *n; i++)
      assert_true(vr_wire_is_float(*n[i]) || isnan(*n[i]) || fabs(*n[i]) > FLT_MAX);
    for (int i = 0; i < VR_MAX_WL; i++)
      assert_true(vr_wire_is_float(p.beta[i]) || isnan(p.beta[i]) || fabs(p.beta[i]) > FLT_MAX);
    /* The unused slots are zeros. */
    for (int i = p.nwl; i < VR_MAX_WL; i++) assert_true(p.wl[i] == 0 && p.beta[i] == 0);
  }
  /* Nearest: 0.1 becomes the float nearest it (IEEE 754 binary32,
   * 0x3DCCCCCD = 0.100000001490116...). */
  r.org[0] = 0.1;
  vr_ray_round(&r);
  assert_true(r.org[0] == 0.100000001490116119384765625);
}

static void test_refuses_what_is_not_a_ray(void **state) {
  (void)state;
  setup_scene(false, 4);
  vr_ray r = camera_ray(76799), back;
  vr_payload p;
  memcpy(&p, r.payload, sizeof p);
  p.patch = 17; /* not the usual: nwl goes as a byte */
  memcpy(r.payload, &p, sizeof p);
  unsigned char buf[VR_RAY_WIRE_MAX];
  size_t n = vr_ray_pack(&g_ops, &g_pass, &r, buf);
  /* A codec's payload where the pass has none, and the other way round. */
  assert_int_equal(vr_ray_unpack(NULL, NULL, buf, n, &back), 0);
  unsigned char plain[VR_RAY_WIRE_MAX];
  size_t np = vr_ray_pack(NULL, NULL, &r, plain);
  assert_int_equal(vr_ray_unpack(NULL, NULL, plain, np, &back), np);
  assert_int_equal(vr_ray_unpack(&g_ops, &g_pass, plain, np, &back), 0);
  /* Flags past bit 9 (the ray's own flags, 0x340, and bit 10). */
  unsigned char bad[VR_RAY_WIRE_MAX + 2];
  unsigned char *o = vr_wire_put_u64(bad, 0x340 | 1u << 10);
  memcpy(o, buf + 2, n - 2);
  assert_int_equal(vr_ray_unpack(&g_ops, &g_pass, bad, n, &back), 0);
  /* A payload with nine wavelengths (its nwl byte is the payload's 8th:
   * flags, sample, three of index, depth, target; the payload starts after
   * the 41 bytes of the flow's fields). */
  size_t nwl_at = 41 + 1 + 1 + 3 + 1 + 1;
  assert_int_equal(buf[nwl_at], 4);
  memcpy(bad, buf, n);
  assert_int_equal(vr_ray_unpack(&g_ops, &g_pass, bad, n, &back), n);
  bad[nwl_at] = VR_MAX_WL + 1;
  assert_int_equal(vr_ray_unpack(&g_ops, &g_pass, bad, n, &back), 0);
  /* A cell past int32. */
  o = vr_wire_put_u64(bad, 0x340);
  o = vr_wire_put_u64(o, (uint64_t)INT32_MAX + 1);
  memcpy(o, buf + 3, n - 3);
  assert_int_equal(vr_ray_unpack(&g_ops, &g_pass, bad, (size_t)(o - bad) + n - 3, &back), 0);
}

/* Rays as a run wrote them: the first three rays of messages the sample
 * room's two ranks sent each other (tests/fuzz/corpus/ray_wire, captured
 * from `mpirun -np 2 vr-render samples/room.scn --subdomains 16`; a first
 * byte 3 for the scene's four hero wavelengths, then the bytes of the
 * message body).  Each file holds three whole rays, read exactly, each at
 * most 96 bytes (issue 31), and written again byte for byte the same. */
static void test_rays_a_run_sent(void **state) {
  (void)state;
  setup_scene(false, 4);
  int files = 0;
  for (int rank = 0; rank < 2; rank++)
    for (int k = 0; k < 6; k++) {
      char path[1024];
      snprintf(path, sizeof path, "%s/tests/fuzz/corpus/ray_wire/room-2ranks-r%d-%d.bin",
               VR_SOURCE_DIR, rank, k);
      FILE *f = fopen(path, "rb");
      if (!f) fail_msg("cannot open %s", path);
      unsigned char buf[4096];
      size_t len = fread(buf, 1, sizeof buf, f);
      fclose(f);
      assert_true(len > 1 && buf[0] == 3);
      size_t off = 1;
      for (int i = 0; i < 3; i++) {
        vr_ray r;
        size_t used = vr_ray_unpack(&g_ops, &g_pass, buf + off, len - off, &r);
        if (!used || used > 96) fail_msg("%s: ray %d: %zu bytes", path, i, used);
        /* A real ray: a unit direction to float precision, a kind and a
         * purpose tag the flow knows (vr_ray_kind; the stats' 8 tags). */
        double d2 = r.dir[0] * r.dir[0] + r.dir[1] * r.dir[1] + r.dir[2] * r.dir[2];
        assert_true(fabs(d2 - 1) < 1e-6);
        assert_true(r.kind <= VR_RAY_SHADOW && r.purpose < 8);
        unsigned char again[VR_RAY_WIRE_MAX];
        assert_int_equal(vr_ray_pack(&g_ops, &g_pass, &r, again), used);
        assert_memory_equal(again, buf + off, used);
        off += used;
      }
      assert_int_equal(off, len);
      files++;
    }
  assert_int_equal(files, 12);
}

int main(void) {
  const struct CMUnitTest tests[] = {
      cmocka_unit_test(test_varints_as_protobuf_defines),
      cmocka_unit_test(test_round_trip_generic_payload),
      cmocka_unit_test(test_round_trip_paths_codec),
      cmocka_unit_test(test_sizes_by_definition),
      cmocka_unit_test(test_rounding),
      cmocka_unit_test(test_refuses_what_is_not_a_ray),
      cmocka_unit_test(test_rays_a_run_sent),
  };
  return cmocka_run_group_tests(tests, NULL, NULL);
}
