/* Bao 2006's accuracy claim, measured (suites/bao_accuracy.c, in `table
 * bao`): the pressed sphere held at rest on the base mesh, under local
 * refinement and fully subdivided to levels 1-3, against a reference
 * converged in refinement (Richardson extrapolation over the subdivided
 * levels, its own error estimated). */
#ifndef TB_BAO_ACCURACY_H
#define TB_BAO_ACCURACY_H

#include "tb_suites.h"
#include "report/tb_results.h"

/* Adds the accuracy table, its counters and the claim's verdict to su;
 * cost: the locally refined model's CPU time over the base's (table 1).
 * Returns 0, or 1 when a run failed (reported). */
int tb_bao_accuracy(tb_suite *su, const tb_suite_opts *o, tb_est cost);

#endif
