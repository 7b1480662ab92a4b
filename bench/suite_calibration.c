/* Placeholder: the calibration suite is being written. */
#include <stdio.h>

#include "tb_cli.h"

int tb_suite_calibration(const tb_suite_opts *o) {
  (void)o;
  fprintf(stderr, "calibration: not written yet\n");
  return 1;
}
