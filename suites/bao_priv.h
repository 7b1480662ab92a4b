/* Private to the bao suite (suites/suite_bao.c, suites/bao_accuracy.c):
 * msm-vvs on Bao 2006's sphere, the pieces both files use. */
#ifndef TB_BAO_PRIV_H
#define TB_BAO_PRIV_H

#include "tb_suites.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

#define TB_BAO_MODEL "msm-vvs"
#define TB_BAO_GOAL 1.2 /* the goal: local refinement <= 1.2 x the base per step */

/* Scene `scene` with msm-vvs, its settings "k=v k=v ..." and the scene
 * settings d (suites/suite_bao.c). */
int tb_bao_open(tb_sim *s, const char *scene, const char *settings, tb_sim_def d, tb_error *err);
/* The vertices the current surface uses (mark: the surface's nv bytes, scratch). */
int tb_bao_used_vertices(const tb_sim *s, char *mark);
/* The dent: the length of the probe's mean displacement. */
double tb_bao_dent(const tb_sim *s);

/* Bao 2006's accuracy claim, measured (suites/bao_accuracy.c, in `table
 * bao`): the pressed sphere held at rest on the base mesh, under local
 * refinement and fully subdivided to levels 1-3, against a reference
 * converged in refinement (Richardson extrapolation over the subdivided
 * levels, its own error estimated). Adds the accuracy table, its counters
 * and the claim's verdict to su; cost: the locally refined model's CPU time
 * over the base's (table 1). Returns 0, or 1 when a run failed (reported). */
int tb_bao_accuracy(tb_suite *su, const tb_suite_opts *o, tb_est cost);

#endif
