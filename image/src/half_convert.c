/* Float to IEEE 754 binary16 with the processor's F16C instructions, for
 * the spectral writer's half channels: OpenEXR's own conversion, one value
 * at a time, was 11 % of a 12-megapixel texture's CPU time.  Rounding is to
 * nearest, ties to even, with subnormals kept, which is what OpenEXR does,
 * so the files are the same bytes either way (tests/image). */
#include "half_convert.h"

#include <string.h>

int vr_half_disable_f16c = 0;

#if (defined(__x86_64__) || defined(__i386__)) && (defined(__GNUC__) || defined(__clang__))
#include <cpuid.h>
#include <immintrin.h>

/* F16C, with the AVX register state the operating system saves (the
 * instructions are VEX-encoded): CPUID leaf 1 ECX bits 29 (F16C), 28 (AVX)
 * and 27 (OSXSAVE), then XCR0 bits 1 and 2 (Intel SDM vol. 1, 14.3).
 * Asked directly: Clang's __builtin_cpu_supports does not know "f16c". */
static int cpu_has_f16c(void) {
  unsigned a, b, c, d;
  if (!__get_cpuid(1, &a, &b, &c, &d)) return 0;
  const unsigned need = (1u << 29) | (1u << 28) | (1u << 27);
  if ((c & need) != need) return 0;
  unsigned lo, hi;
  __asm__("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
  (void)hi;
  return (lo & 6u) == 6u;
}

__attribute__((target("f16c"))) static void convert_f16c(const float *in, uint16_t *out,
                                                         size_t n) {
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    __m128 x = _mm_loadu_ps(in + i);
    __m128i h = _mm_cvtps_ph(x, _MM_FROUND_TO_NEAREST_INT);
    _mm_storel_epi64((__m128i *)(out + i), h);
  }
  if (i < n) {
    float tail[4] = {0, 0, 0, 0};
    uint16_t th[8];
    memcpy(tail, in + i, (n - i) * sizeof *tail);
    _mm_storeu_si128((__m128i *)th, _mm_cvtps_ph(_mm_loadu_ps(tail), _MM_FROUND_TO_NEAREST_INT));
    memcpy(out + i, th, (n - i) * sizeof *out);
  }
}

int vr_half_available(void) { return !vr_half_disable_f16c && cpu_has_f16c(); }

void vr_half_convert(const float *in, uint16_t *out, size_t n) { convert_f16c(in, out, n); }
#else
int vr_half_available(void) { return 0; }

void vr_half_convert(const float *in, uint16_t *out, size_t n) {
  (void)in;
  (void)out;
  (void)n;
}
#endif
