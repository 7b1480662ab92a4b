/* xoshiro256** with splitmix64 seeding (Blackman & Vigna, "Scrambled linear
 * pseudorandom number generators", 2018). */
#include "tb_rng.h"

#include <math.h>

static uint64_t splitmix64(uint64_t *x) {
  uint64_t z = (*x += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

tb_rng tb_rng_seed(uint64_t seed) {
  tb_rng r;
  for (int i = 0; i < 4; i++) r.s[i] = splitmix64(&seed);
  return r;
}

uint64_t tb_rng_next(tb_rng *r) {
  uint64_t *s = r->s;
  uint64_t result = rotl(s[1] * 5, 7) * 9;
  uint64_t t = s[1] << 17;
  s[2] ^= s[0];
  s[3] ^= s[1];
  s[1] ^= s[2];
  s[0] ^= s[3];
  s[2] ^= t;
  s[3] = rotl(s[3], 45);
  return result;
}

double tb_rng_uniform(tb_rng *r) { return (double)(tb_rng_next(r) >> 11) * 0x1.0p-53; }

double tb_rng_range(tb_rng *r, double lo, double hi) { return lo + (hi - lo) * tb_rng_uniform(r); }

uint64_t tb_rng_below(tb_rng *r, uint64_t n) {
  uint64_t limit = UINT64_MAX - UINT64_MAX % n;
  uint64_t x;
  do x = tb_rng_next(r);
  while (x >= limit);
  return x % n;
}

double tb_rng_normal(tb_rng *r) {
  double u, v, s;
  do {
    u = 2.0 * tb_rng_uniform(r) - 1.0;
    v = 2.0 * tb_rng_uniform(r) - 1.0;
    s = u * u + v * v;
  } while (s >= 1.0 || s == 0.0);
  return u * sqrt(-2.0 * log(s) / s);
}
