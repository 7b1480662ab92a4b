/* Table 4.2's near-miss poses (suites/table42_near.c): the instrument just
 * clear of the liver, ours and SOFA's meshes, every method timed on one
 * thread in CPU time, the methods' repetitions taking turns. */
#ifndef TB_NEAR_MISS_H
#define TB_NEAR_MISS_H

#include "tb_suites.h"
#include "core/tb_mesh.h"
#include "report/tb_results.h"

/* Adds the near-miss table and its note to s (liver, inst: our scene).
 * Returns 0, or -1 when a pose could not be found or a method disagreed
 * with brute force (err says which, or the note counts them). */
int tb_table42_near_miss(tb_suite *s, const tb_suite_opts *o, const tb_mesh *liver,
                         const tb_mesh *inst, tb_error *err);

#endif
