/* Private to the table-3.5 suite: bench/suite_table35.c (speed, recovery,
 * contact) and bench/suite_corot.c (fem-corot's solvers). */
#ifndef TB_SUITE_TABLE35_H
#define TB_SUITE_TABLE35_H

#include "tb_cli.h"
#include "tb_model.h"
#include "tb_results.h"

/* The "fem-corot solvers" table on the liver (the given mesh of
 * liver-stretch) and the beam. Returns 0, or 1 when a run failed. */
int tb_table35_corot(tb_suite *su, const tb_suite_opts *o, const tb_mesh *liver);

#endif
