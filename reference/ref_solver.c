/* Placeholder: the reference hyperelastic solver is being written. */
#include <stddef.h>

#include "tb_reference.h"

tb_ref_solution *tb_ref_solve(const tb_ref_problem *p, const tb_ref_def *def, tb_error *err) {
  (void)p, (void)def;
  tb_error_set(err, "reference", 0, "not written yet");
  return NULL;
}
