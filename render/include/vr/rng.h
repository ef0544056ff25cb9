/* Counter-based random numbers (DESIGN §6.5): a number is a pure function
 * of (seed, stream, sample, depth, dimension), where stream is a pixel, a
 * sensor point, a photon or a texel.  No state is carried from one ray to
 * the next, so the image does not depend on which thread, cell or process
 * traced which ray, nor in what order.
 *
 * The mixing function is the SplitMix64 finaliser (Steele, Lea & Flood,
 * "Fast splittable pseudorandom number generators", OOPSLA 2014), applied
 * to each key word in turn; its avalanche makes neighbouring counters
 * independent for rendering purposes. */
#ifndef VR_RNG_H
#define VR_RNG_H

#include <stdint.h>

static inline uint64_t vr_mix64(uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

/* What a number is for, so that two uses at one depth never share one. */
enum {
  VR_DIM_PIXEL_X = 0, VR_DIM_PIXEL_Y, VR_DIM_LENS_U, VR_DIM_LENS_V, VR_DIM_WAVELENGTH,
  VR_DIM_LOBE, VR_DIM_DIR_U, VR_DIM_DIR_V, VR_DIM_LIGHT_PICK, VR_DIM_LIGHT_U, VR_DIM_LIGHT_V,
  VR_DIM_LIGHT_W, VR_DIM_ROULETTE, VR_DIM_SKY_U, VR_DIM_SKY_V, VR_DIM_EMIT_U, VR_DIM_EMIT_V,
  VR_DIM_EMIT_W, VR_DIM_EMIT_X, VR_DIM_EMIT_Y, VR_DIM_SKY_PICK, VR_DIM_SKY_W, VR_DIM_GATHER = 32 /* + 2 per gather ray */
};

typedef struct vr_rng_key {
  uint64_t seed, stream;
  uint32_t sample, depth;
} vr_rng_key;

/* A uniform double in [0, 1) with 53 random bits. */
static inline double vr_rng(const vr_rng_key *k, uint32_t dim) {
  uint64_t h = vr_mix64(k->seed);
  h = vr_mix64(h ^ k->stream);
  h = vr_mix64(h ^ ((uint64_t)k->sample << 32 | k->depth));
  h = vr_mix64(h ^ dim);
  return (double)(h >> 11) * 0x1.0p-53;
}

#endif
