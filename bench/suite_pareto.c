/* Placeholder: the pareto suite is being written. */
#include <stdio.h>

#include "tb_cli.h"

int tb_suite_pareto(const tb_suite_opts *o) {
  (void)o;
  fprintf(stderr, "pareto: not written yet\n");
  return 1;
}
