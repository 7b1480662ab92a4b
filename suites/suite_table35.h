/* Private to the table-3.5 suite: suites/suite_table35.c (speed, recovery,
 * contact) and suites/suite_corot.c (fem-corot's solvers). */
#ifndef TB_SUITE_TABLE35_H
#define TB_SUITE_TABLE35_H

#include "tb_suites.h"
#include "models/tb_model.h"
#include "report/tb_results.h"

/* The "fem-corot solvers" table on the liver (the given mesh of
 * liver-stretch) and the beam. Returns 0, or 1 when a run failed. */
int tb_table35_corot(tb_suite *su, const tb_suite_opts *o, const tb_mesh *liver);

#endif
