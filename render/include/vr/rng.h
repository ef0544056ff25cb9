/* Counter-based random numbers (DESIGN §6.5): a number is a pure function
 * of (seed, stream, sample, depth, dimension), where stream is a pixel, a
 * sensor point, a photon or a texel.  No state is carried from one ray to
 * the next, so the image does not depend on which thread, cell or process
 * traced which ray, nor in what order.
 *
 * The mixing function is the SplitMix64 finaliser (Steele, Lea & Flood,
 * "Fast splittable pseudorandom number generators", OOPSLA 2014), applied
 * to each key word in turn; its avalanche makes neighbouring counters
 * independent for rendering purposes.
 *
 * The seed also says which sampler draws the numbers (render sampler=):
 * independent (the hash above, the default), stratified (the pixel and lens
 * dimensions jittered over the samples of a stream) or sobol (padded,
 * Owen-scrambled Sobol points: render/src/sampler.c).  Every integrator
 * keys its numbers the same way whatever the sampler, so each benefits
 * without knowing which one runs. */
#ifndef VR_RNG_H
#define VR_RNG_H

#include <stdint.h>

static inline uint64_t vr_mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/* What a number is for, so that two uses at one depth never share one.
 * The low-discrepancy samplers treat (PIXEL_X, PIXEL_Y), (LENS_U, LENS_V),
 * (DIR_U, DIR_V), (LIGHT_V, LIGHT_W) (the point on an emitter once LIGHT_U
 * has picked its triangle, or a sphere's z and azimuth), (SKY_U, SKY_V),
 * (EMIT_U, EMIT_V), (EMIT_W, EMIT_X) and each gather ray's two numbers as
 * 2D pairs, every other dimension on its own (vr_rng_pair). */
enum {
  VR_DIM_PIXEL_X = 0, VR_DIM_PIXEL_Y, VR_DIM_LENS_U, VR_DIM_LENS_V, VR_DIM_WAVELENGTH,
  VR_DIM_LOBE, VR_DIM_DIR_U, VR_DIM_DIR_V, VR_DIM_LIGHT_PICK, VR_DIM_LIGHT_U, VR_DIM_LIGHT_V,
  VR_DIM_LIGHT_W, VR_DIM_ROULETTE, VR_DIM_SKY_U, VR_DIM_SKY_V, VR_DIM_EMIT_U, VR_DIM_EMIT_V,
  VR_DIM_EMIT_W, VR_DIM_EMIT_X, VR_DIM_EMIT_Y, VR_DIM_SKY_PICK, VR_DIM_SKY_W,
  VR_DIM_ALPHA, /* a see-through (alpha-blended) surface: through or not */
  VR_DIM_GATHER = 32 /* + 2 per gather ray */
};

/* The samplers (render sampler=, vr_scene_settings.sampler). */
typedef enum vr_sampler_kind {
  VR_SAMPLER_INDEPENDENT = 0,
  VR_SAMPLER_STRATIFIED,
  VR_SAMPLER_SOBOL
} vr_sampler_kind;

/* The scene's seed and its sampler: `count` is the number of samples a
 * stream takes (a pixel's spp), which stratified and sobol spread their
 * points over; strata_x the columns of stratified's nx x ny grid; mixed a
 * hash of the seed for them (vr_rng_seed_make fills both).  Independent
 * numbers depend on `value` only. */
typedef struct vr_rng_seed {
  uint64_t value, mixed;
  uint32_t sampler, count, strata_x;
} vr_rng_seed;

typedef struct vr_rng_key {
  vr_rng_seed seed;
  uint64_t stream;
  uint32_t sample, depth;
} vr_rng_key;

/* The seed for a sampler over count samples per stream (count 0 counts as
 * 1): strata_x is the largest divisor of count not above its square root
 * (16 gives 4 x 4, 32 gives 4 x 8). */
vr_rng_seed vr_rng_seed_make(uint64_t value, uint32_t sampler, uint32_t count);

/* The independent sampler's number, whatever the key's sampler. */
static inline double vr_rng_independent(const vr_rng_key *k, uint32_t dim) {
  uint64_t h = vr_mix64(k->seed.value);
  h = vr_mix64(h ^ k->stream);
  h = vr_mix64(h ^ ((uint64_t)k->sample << 32 | k->depth));
  h = vr_mix64(h ^ dim);
  return (double)(h >> 11) * 0x1.0p-53;
}

/* The stratified and sobol samplers' number (render/src/sampler.c). */
double vr_rng_sampler(const vr_rng_key *k, uint32_t dim);

/* A uniform double in [0, 1): 53 random bits from the independent
 * sampler, multiples of 2^-32 from sobol (as pbrt-v4 keeps them). */
static inline double vr_rng(const vr_rng_key *k, uint32_t dim) {
  if (k->seed.sampler != VR_SAMPLER_INDEPENDENT) return vr_rng_sampler(k, dim);
  return vr_rng_independent(k, dim);
}

/* The low-discrepancy building blocks, exposed for the tests: the first
 * dimension of the Sobol sequence (the van der Corput radical inverse in
 * base 2, bits reversed) and its second, as 32-bit fractions of index i;
 * an Owen-style nested scramble of a 32-bit fraction; a bijection of
 * [0, n) keyed by seed; and which 2D pair a dimension belongs to (the
 * pair's first dimension; *component 0 or 1, 0 for a dimension alone). */
uint32_t vr_sobol_0(uint32_t i);
uint32_t vr_sobol_1(uint32_t i);
uint32_t vr_owen_scramble(uint32_t v, uint32_t seed);
uint32_t vr_permute(uint32_t i, uint32_t n, uint32_t seed);
uint32_t vr_rng_pair(uint32_t dim, uint32_t *component);

#endif
