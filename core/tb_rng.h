/* Seeded pseudo-random numbers: xoshiro256** seeded through splitmix64
 * (Blackman & Vigna 2018). Same seed, same sequence, on every platform. */
#ifndef TB_RNG_H
#define TB_RNG_H

#include <stdint.h>

typedef struct tb_rng {
  uint64_t s[4];
} tb_rng;

tb_rng tb_rng_seed(uint64_t seed);
uint64_t tb_rng_next(tb_rng *r);
/* Uniform in [0, 1) with 53 random bits. */
double tb_rng_uniform(tb_rng *r);
/* Uniform in [lo, hi). */
double tb_rng_range(tb_rng *r, double lo, double hi);
/* Uniform integer in [0, n), n > 0, without modulo bias. */
uint64_t tb_rng_below(tb_rng *r, uint64_t n);
/* Standard normal (Marsaglia polar method). */
double tb_rng_normal(tb_rng *r);

#endif
