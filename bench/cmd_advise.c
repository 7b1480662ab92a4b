/* Placeholder: `tissuebench advise` is being written. */
#include <stdio.h>

#include "tb_cli.h"

int tb_cmd_advise(int argc, char **argv) {
  (void)argc, (void)argv;
  fprintf(stderr, "advise: not written yet\n");
  return TB_EXIT_FAIL;
}
