/* The project's one pseudo-random generator: a 64-bit linear congruential
 * generator (Knuth's MMIX constants), s <- 6364136223846793005 s +
 * 1442695040888963407. It is used where a reproducible, seedable sequence is
 * all that is needed (Lanczos start vectors, perturbations, jittered test
 * meshes); it is not for statistics. Every stream is determined by its seed,
 * so runs are bit-for-bit repeatable on every machine. */
#ifndef CB_RNG_H
#define CB_RNG_H

#include <stdint.h>

typedef struct cb_rng {
  uint64_t s; /* state; any value is a valid seed */
} cb_rng;

/* A generator whose state is the raw seed s. */
static inline cb_rng cb_rng_raw(uint64_t s) { return (cb_rng){s}; }
/* A generator for a small seed index k (0, 1, 2, ...): the state is k times
 * the 64-bit golden ratio, so neighbouring indices start far apart. */
static inline cb_rng cb_rng_seed(uint64_t k) { return (cb_rng){0x9E3779B97F4A7C15ULL * k}; }
/* The next 64-bit state. */
static inline uint64_t cb_rng_next(cb_rng *r) {
  r->s = r->s * 6364136223846793005ULL + 1442695040888963407ULL;
  return r->s;
}
/* Uniform in [0, 1): the top 53 bits of the next state over 2^53. */
static inline double cb_rng_uniform(cb_rng *r) { return (double)(cb_rng_next(r) >> 11) / 9007199254740992.0; }

#endif
