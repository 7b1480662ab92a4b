/* The PBD patent's models at rest against the converged FEM solution
 * (suites/pbd_accuracy.c, in `table pbd`): the liver hanging from a patch
 * of its top under gravity (liver-hang), pbd-stvk and xpbd-stvk at the
 * patent's settings (k 0.4, 5 iterations, dt 0.005) and at converged ones,
 * each run until it settles, its surface compared with the reference
 * (measure/tb_fidelity.h) of the same material. */
#ifndef TB_PBD_ACCURACY_H
#define TB_PBD_ACCURACY_H

#include "tb_suites.h"
#include "report/tb_results.h"

/* Adds the table, its counters and notes to su; returns 0, or 1 when a run
 * or the reference failed (reported). */
int tb_pbd_accuracy(tb_suite *su, const tb_suite_opts *o);

#endif
