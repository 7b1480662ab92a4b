/* The refit suite's thread table (suites/refit_threads.c): our refit and
 * query on a large deforming mesh, one thread against several (wall time,
 * CPU beside). */
#ifndef TB_REFIT_THREADS_H
#define TB_REFIT_THREADS_H

#include "tb_suites.h"
#include "report/tb_results.h"

/* Adds the table and its note to s; -1 (err says why) on failure or when
 * the thread counts disagree. */
int tb_refit_threads(tb_suite *s, const tb_suite_opts *o, tb_error *err);

#endif
