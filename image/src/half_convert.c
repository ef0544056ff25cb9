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

/* One half from one float (tails of the planar conversion). */
__attribute__((target("f16c"))) static uint16_t half_of(float v) {
  return (uint16_t)_mm_extract_epi16(_mm_cvtps_ph(_mm_set_ss(v), _MM_FROUND_TO_NEAREST_INT), 0);
}

/* Blocks of 8 pixels x 8 bands: eight rows loaded (a row is one pixel's 8
 * bands; the last block of bands loads through a mask, so nothing past a
 * pixel's nb floats is read), transposed in registers (unpack, shuffle,
 * 128-bit permute: Intel's 8x8 idiom, all AVX), and each column, one band
 * of 8 pixels, converted to 8 halves and stored in its band's run. */
__attribute__((target("avx,f16c"))) static void planar_f16c(const float *in, uint16_t *out,
                                                            size_t lines, size_t width,
                                                            size_t nb) {
  for (size_t y = 0; y < lines; y++) {
    const float *row = in + y * width * nb;
    uint16_t *dst = out + y * nb * width;
    size_t x0 = 0;
    for (; x0 + 8 <= width; x0 += 8)
      for (size_t b0 = 0; b0 < nb; b0 += 8) {
        const size_t nbb = nb - b0 < 8 ? nb - b0 : 8;
        __m256 r[8];
        if (nbb == 8) {
          for (int i = 0; i < 8; i++) r[i] = _mm256_loadu_ps(row + (x0 + (size_t)i) * nb + b0);
        } else {
          int lane[8];
          for (int j = 0; j < 8; j++) lane[j] = (size_t)j < nbb ? -1 : 0;
          const __m256i mask = _mm256_loadu_si256((const __m256i *)lane);
          for (int i = 0; i < 8; i++)
            r[i] = _mm256_maskload_ps(row + (x0 + (size_t)i) * nb + b0, mask);
        }
        __m256 t0 = _mm256_unpacklo_ps(r[0], r[1]), t1 = _mm256_unpackhi_ps(r[0], r[1]);
        __m256 t2 = _mm256_unpacklo_ps(r[2], r[3]), t3 = _mm256_unpackhi_ps(r[2], r[3]);
        __m256 t4 = _mm256_unpacklo_ps(r[4], r[5]), t5 = _mm256_unpackhi_ps(r[4], r[5]);
        __m256 t6 = _mm256_unpacklo_ps(r[6], r[7]), t7 = _mm256_unpackhi_ps(r[6], r[7]);
        __m256 s0 = _mm256_shuffle_ps(t0, t2, 0x44), s1 = _mm256_shuffle_ps(t0, t2, 0xEE);
        __m256 s2 = _mm256_shuffle_ps(t1, t3, 0x44), s3 = _mm256_shuffle_ps(t1, t3, 0xEE);
        __m256 s4 = _mm256_shuffle_ps(t4, t6, 0x44), s5 = _mm256_shuffle_ps(t4, t6, 0xEE);
        __m256 s6 = _mm256_shuffle_ps(t5, t7, 0x44), s7 = _mm256_shuffle_ps(t5, t7, 0xEE);
        __m256 c[8];
        c[0] = _mm256_permute2f128_ps(s0, s4, 0x20);
        c[1] = _mm256_permute2f128_ps(s1, s5, 0x20);
        c[2] = _mm256_permute2f128_ps(s2, s6, 0x20);
        c[3] = _mm256_permute2f128_ps(s3, s7, 0x20);
        c[4] = _mm256_permute2f128_ps(s0, s4, 0x31);
        c[5] = _mm256_permute2f128_ps(s1, s5, 0x31);
        c[6] = _mm256_permute2f128_ps(s2, s6, 0x31);
        c[7] = _mm256_permute2f128_ps(s3, s7, 0x31);
        for (size_t j = 0; j < nbb; j++)
          _mm_storeu_si128((__m128i *)(dst + (b0 + j) * width + x0),
                           _mm256_cvtps_ph(c[j], _MM_FROUND_TO_NEAREST_INT));
      }
    for (; x0 < width; x0++)
      for (size_t b = 0; b < nb; b++) dst[b * width + x0] = half_of(row[x0 * nb + b]);
  }
}

int vr_half_available(void) { return !vr_half_disable_f16c && cpu_has_f16c(); }

void vr_half_convert_planar(const float *in, uint16_t *out, size_t lines, size_t width,
                            size_t nb) {
  planar_f16c(in, out, lines, width, nb);
}

void vr_half_convert(const float *in, uint16_t *out, size_t n) { convert_f16c(in, out, n); }
#else
int vr_half_available(void) { return 0; }

void vr_half_convert(const float *in, uint16_t *out, size_t n) {
  (void)in;
  (void)out;
  (void)n;
}

void vr_half_convert_planar(const float *in, uint16_t *out, size_t lines, size_t width,
                            size_t nb) {
  (void)in;
  (void)out;
  (void)lines;
  (void)width;
  (void)nb;
}
#endif
