/* The low-discrepancy samplers behind vr_rng (vr/rng.h): `stratified` and
 * `sobol`.  Both keep the key of the independent sampler, (seed, stream,
 * sample, depth, dimension), so no integrator changes with the sampler.
 *
 * sobol is pbrt-v4's padded Sobol sampler (Pharr, Jakob & Humphreys,
 * Physically Based Rendering, 4th ed., 2023, section 8.7.3): dimensions go
 * in 2D pairs (vr_rng_pair), and each pair of a stream at a depth takes the
 * first two dimensions of the Sobol sequence, the van der Corput radical
 * inverse and Sobol's second dimension, which together form a
 * (0,2)-sequence in base 2: the first 2^m points are a (0,m,2)-net, one
 * point in every elementary interval of area 2^-m (Sobol 1967; Niederreiter
 * 1992, ch. 4).  A pair's points are scrambled by a hash of (seed, stream,
 * depth, pair) with a nested, Owen-style permutation of the binary digits,
 * which keeps every net a net (Owen 1995), and the sample index is
 * permuted within each block of `count` samples by another hash, so two
 * pairs of one sample are not the same point (padding, Kollig & Keller
 * 2002).  A dimension alone takes the radical inverse, a (0,1)-sequence.
 *
 * stratified jitters the pixel (PIXEL_X, PIXEL_Y) and lens (LENS_U,
 * LENS_V) pairs over an nx x ny grid of `count` cells, nx the largest
 * divisor of count not above its square root: sample i of a block of count
 * samples falls in cell permute(i) (each cell once), at a uniform place
 * inside it.  Other dimensions are the independent sampler's numbers.
 *
 * Both are unbiased: for any one sample every dimension is uniform on
 * [0, 1) and different pairs are independent (different hashes). */
#include <math.h>
#include <stdbool.h>

#include "vr/rng.h"

vr_rng_seed vr_rng_seed_make(uint64_t value, uint32_t sampler, uint32_t count) {
  if (count < 1) count = 1;
  uint32_t nx = (uint32_t)floor(sqrt((double)count));
  while (nx > 1 && (nx * nx > count || count % nx)) nx--;
  if (nx < 1) nx = 1;
  vr_rng_seed s = {value, vr_mix64(value ^ 0x50B015EEDull), sampler, count, nx};
  return s;
}

static uint32_t reverse32(uint32_t v) {
  v = __builtin_bswap32(v);
  v = ((v >> 4) & 0x0F0F0F0Fu) | ((v & 0x0F0F0F0Fu) << 4);
  v = ((v >> 2) & 0x33333333u) | ((v & 0x33333333u) << 2);
  return ((v >> 1) & 0x55555555u) | ((v & 0x55555555u) << 1);
}

uint32_t vr_sobol_0(uint32_t i) { return reverse32(i); }

/* Sobol's second dimension: primitive polynomial x + 1, m_1 = 1, so the
 * direction numbers are v_1 = 1/2 and v_k = v_{k-1} xor v_{k-1}/2 (the
 * Pascal matrix mod 2); the point is the xor of v_k over the bits k of i.
 * Here with the bits reversed (v_1 = 1, each next one xor itself shifted
 * up), as the scrambling below wants them. */
static uint32_t sobol_1_reversed(uint32_t i) {
  uint32_t v = 1, x = 0;
  for (; i; i >>= 1, v ^= v << 1)
    if (i & 1) x ^= v;
  return x;
}

uint32_t vr_sobol_1(uint32_t i) { return reverse32(sobol_1_reversed(i)); }

/* Burley's hash-based Owen scrambling ("Practical Hash-based Owen
 * Scrambling", JCGT 9(4), 2020) in pbrt-v4's constants (FastOwenScrambler),
 * on the reversed bits: each step changes a bit only from the bits below it
 * (xor with an even multiple, addition, an odd product), so on the
 * fraction each digit is flipped by a function of the digits above it: a
 * nested permutation, which maps elementary intervals onto elementary
 * intervals of the same shape. */
static uint32_t owen_reversed(uint32_t v, uint32_t seed) {
  v ^= v * 0x3d20adeau;
  v += seed;
  v *= (seed >> 16) | 1u;
  v ^= v * 0x05526c56u;
  v ^= v * 0x53a22864u;
  return v;
}

uint32_t vr_owen_scramble(uint32_t v, uint32_t seed) {
  return reverse32(owen_reversed(reverse32(v), seed));
}

/* Kensler's hashed permutation ("Correlated Multi-Jittered Sampling",
 * Pixar technical memo 13-01, 2013): a bijection of the next power of two
 * above n - 1, walked until it lands below n, then rotated by the seed. */
uint32_t vr_permute(uint32_t i, uint32_t n, uint32_t p) {
  if (n <= 1) return 0;
  uint32_t w = n - 1;
  bool pow2 = !(n & w);
  w |= w >> 1, w |= w >> 2, w |= w >> 4, w |= w >> 8, w |= w >> 16;
  do {
    i ^= p;
    i *= 0xe170893du;
    i ^= p >> 16;
    i ^= (i & w) >> 4;
    i ^= p >> 8;
    i *= 0x0929eb3fu;
    i ^= p >> 23;
    i ^= (i & w) >> 1;
    i *= 1u | p >> 27;
    i *= 0x6935fa69u;
    i ^= (i & w) >> 11;
    i *= 0x74dcb303u;
    i ^= (i & w) >> 2;
    i *= 0x9e501cc3u;
    i ^= (i & w) >> 2;
    i *= 0xc860a3dfu;
    i &= w;
    i ^= i >> 5;
  } while (i >= n);
  return pow2 ? (i + p) & w : (uint32_t)(((uint64_t)i + p) % n);
}

uint32_t vr_rng_pair(uint32_t dim, uint32_t *component) {
  *component = 0;
  if (dim >= VR_DIM_GATHER) {
    *component = dim & 1u;
    return dim & ~1u;
  }
  switch (dim) {
  case VR_DIM_PIXEL_Y: case VR_DIM_LENS_V: case VR_DIM_DIR_V: case VR_DIM_LIGHT_W:
  case VR_DIM_SKY_V: case VR_DIM_EMIT_V: case VR_DIM_EMIT_X:
    *component = 1;
    return dim - 1;
  default: return dim;
  }
}

/* A hash of everything but the sample: one per (seed, stream, depth, pair). */
static uint64_t pair_hash(const vr_rng_key *k, uint32_t pair) {
  uint64_t h = vr_mix64(k->seed.mixed ^ k->stream);
  return vr_mix64(h ^ ((uint64_t)k->depth << 32 | pair));
}

/* The sample's index within the stream after the pair's permutation:
 * samples q count ... (q + 1) count - 1 (block q) are permuted among
 * themselves, and the blocks too, by a bijection of the first 2^24 block
 * indices (fewer when spp is above 256) keyed by the pair.  Without the second, a stream that takes
 * many more samples than count (a sensor point's thousands of paths under
 * a camera's spp) would give every pair, at every depth, the points of
 * the same block for the same sample: Owen scrambles with fixed seeds are
 * bijections, so one pair's numbers would be a function of another's (a
 * path's second bounce of its first), and the estimate would converge to
 * a value that depends on the seed.  Every aligned block of 2^m Sobol
 * points is a (0, m, 2)-net, so a pixel's samples keep that property. */
static uint64_t permuted_index(const vr_rng_key *k, uint64_t h) {
  uint32_t n = k->seed.count ? k->seed.count : 1, q, r;
  if (n & (n - 1)) q = k->sample / n, r = k->sample % n;
  else q = k->sample >> __builtin_ctz(n), r = k->sample & (n - 1);
  uint64_t hp = vr_mix64(h ^ (0xB10C0000ull + q)), hq = vr_mix64(h ^ 0xB10C4B5Full);
  /* The blocks permuted are those whose points fit the 32-bit index: with
   * n up to 2^m, 2^min(24, 32 - m) of them (a larger shuffle would wrap
   * blocks onto one another). */
  int m = n > 1 ? 32 - __builtin_clz(n - 1) : 0, bits = 32 - m < 24 ? 32 - m : 24;
  uint32_t qb = q;
  if (bits > 0) {
    uint32_t low = bits == 32 ? ~0u : (1u << bits) - 1;
    qb = (q & ~low) | vr_permute(q & low, low + 1, (uint32_t)(hq ^ hq >> 32));
  }
  return (uint64_t)qb * n + vr_permute(r, n, (uint32_t)(hp ^ hp >> 32));
}

static const double BELOW_ONE = 0x1.fffffffffffffp-1;

/* 32 bits of the scrambled net, as pbrt-v4 keeps: multiples of 2^-32. */
static double sobol_value(const vr_rng_key *k, uint32_t dim) {
  uint32_t comp, pair = vr_rng_pair(dim, &comp);
  uint64_t h = pair_hash(k, pair);
  uint32_t idx = (uint32_t)permuted_index(k, h);
  /* The radical inverse is the index reversed: scrambled unreversed. */
  uint32_t r = comp ? sobol_1_reversed(idx) : idx;
  uint32_t v = reverse32(owen_reversed(r, comp ? (uint32_t)(h >> 32) : (uint32_t)h));
  return (double)v * 0x1.0p-32;
}

static double stratified_value(const vr_rng_key *k, uint32_t dim) {
  uint32_t comp, pair = vr_rng_pair(dim, &comp);
  if (pair != VR_DIM_PIXEL_X && pair != VR_DIM_LENS_U) return vr_rng_independent(k, dim);
  uint64_t h = pair_hash(k, pair);
  uint32_t n = k->seed.count ? k->seed.count : 1;
  uint32_t nx = k->seed.strata_x ? k->seed.strata_x : 1, ny = n / nx;
  uint32_t cell = (uint32_t)(permuted_index(k, h) % n);
  uint32_t c = comp ? cell / nx : cell % nx, cells = comp ? ny : nx;
  double x = ((double)c + vr_rng_independent(k, dim)) / cells;
  return x < BELOW_ONE ? x : BELOW_ONE;
}

double vr_rng_sampler(const vr_rng_key *k, uint32_t dim) {
  switch (k->seed.sampler) {
  case VR_SAMPLER_SOBOL: return sobol_value(k, dim);
  case VR_SAMPLER_STRATIFIED: return stratified_value(k, dim);
  default: return vr_rng_independent(k, dim);
  }
}
