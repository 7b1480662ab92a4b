/* Strict parsing of command-line values (core/tb_parse.h). */
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stdlib.h>

#include "tb_parse.h"

int tb_parse_vec3(const char *s, tb_vec3 *out, const char **rest) {
  char *end;
  double c[3];
  for (int k = 0; k < 3; k++) {
    errno = 0;
    c[k] = strtod(s, &end);
    if (end == s || errno || !isfinite(c[k]) || (k < 2 && *end != ',')) return -1;
    s = end + (k < 2);
  }
  *out = tb_v3(c[0], c[1], c[2]);
  if (rest) *rest = end;
  return 0;
}

void tb_ini_setup(void) {
  ini_allow_multiline = 0;
  ini_stop_on_first_error = 1;
  ini_use_stack = 0;
  ini_allow_realloc = 1;
  ini_max_line = 4096;
}
