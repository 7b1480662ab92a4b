/* Families of triangle pairs for the correctness table: random pairs in
 * general position and degenerate configurations built with exactly
 * representable coordinates (small integers and dyadic fractions, exact
 * offsets and power-of-two scalings), so the configuration is exactly what
 * its name says. Same seed, same pairs. */
#ifndef TB_PAIRGEN_H
#define TB_PAIRGEN_H

#include <stdint.h>

#include "collision/tb_pairs.h"
#include "core/tb_rng.h"

typedef struct tb_pair_family {
  const char *name;
  const char *summary;
  void (*make)(tb_rng *r, tb_tripair *out);
} tb_pair_family;

const tb_pair_family *tb_pair_families(int *count);
const tb_pair_family *tb_pair_family_find(const char *name);
/* Appends n pairs of the family to set (expect -1). 0, or -1 out of memory. */
int tb_pairgen(const tb_pair_family *f, int n, uint64_t seed, tb_pairset *set);

/* Appends to out every pair of in whose coordinates all scale exactly by
 * 2^e (finite, and no bit lost to underflow), scaled; index[k] (when not
 * NULL, room for in->n) gets the number in `in` of out's k-th new pair.
 * Returns how many were appended, -1 out of memory. */
int tb_pairs_scaled(const tb_pairset *in, int e, tb_pairset *out, int *index);

#endif
