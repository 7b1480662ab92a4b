/* Placeholder: the stability suite is being written. */
#include <stdio.h>

#include "tb_cli.h"

int tb_suite_stability(const tb_suite_opts *o) {
  (void)o;
  fprintf(stderr, "stability: not written yet\n");
  return 1;
}
