/* One libFuzzer harness: the entry of fuzz_targets.c named by
 * TB_FUZZ_TARGET at compile time. A broken contract prints what broke and
 * aborts, so libFuzzer saves the input as crash-*. */
#include <stdio.h>
#include <stdlib.h>

#include "fuzz_check.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  static const tb_fuzz_target *t;
  char why[1024];
  if (!t && !(t = tb_fuzz_target_find(TB_FUZZ_TARGET))) {
    fprintf(stderr, "fuzz: no target %s\n", TB_FUZZ_TARGET);
    abort();
  }
  int rc = tb_fuzz_run(t, data, size, why, sizeof why);
  if (rc) {
    fprintf(stderr, "fuzz_%s: contract broken: %s\n", t->name, why);
    abort();
  }
  return 0;
}
