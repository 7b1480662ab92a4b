/* Private to the `metaball` suite (the metaball patent's tables and
 * figures): suites/suite_metaball.c (table 1, re-packing,
 * the speed goal, figs 7-10) and suites/suite_metaball_cmp.c (table 2 and
 * the convergence after a push, against the tet models on the steak). */
#ifndef TB_SUITE_METABALL_H
#define TB_SUITE_METABALL_H

#include "tb_suites.h"
#include "models/tb_model.h"
#include "report/tb_results.h"

#define TB_MBS_DT 0.01        /* every run's time step (s) */
#define TB_MBS_G 9.81         /* gravity along -z (per s^2) */
#define TB_MBS_END_SHARE 0.08 /* held: points within this share of the long extent of each end */

/* How a deformation is timed: warm frames, then nblocks blocks of block
 * frames, each block's mean ms per frame one sample. */
typedef struct tb_mbs_plan {
  int warm, block, nblocks;
} tb_mbs_plan;

/* The points of x[0..n) within TB_MBS_END_SHARE of both ends of the longer
 * horizontal extent (x or y): ids ascending and their positions
 * (malloc'ed). Returns how many, or -1 with err. */
int tb_mbs_end_holds(const tb_vec3 *x, int n, int **ids, tb_vec3 **at, tb_error *err);
/* n frames of m under in, the step alone timed: the mean wall and CPU ms
 * per frame into *wall and *cpu (either may be NULL). A failed step or a
 * non-finite point is an error. */
int tb_mbs_frames(tb_model *m, const tb_step *in, int n, double *wall, double *cpu, tb_error *err);
/* The plan's frames of m under in: wall and cpu get nblocks samples each. */
int tb_mbs_deform(tb_model *m, const tb_step *in, const tb_mbs_plan *p, double *wall, double *cpu,
                  tb_error *err);
/* Table 1's cut, for any model that cuts: the blade's edge under the
 * organ across its shorter horizontal extent through the middle, its depth
 * through the whole thickness (10% margins), crossing in
 * TB_MBS_CUT_FRAMES frames (a frame: MOVE with the path so far, then a
 * step under in, each timed), then END (timed). */
#define TB_MBS_CUT_FRAMES 20
typedef struct tb_mbs_cut_times {
  double move[TB_MBS_CUT_FRAMES], step[TB_MBS_CUT_FRAMES]; /* CPU ms */
  double wall[TB_MBS_CUT_FRAMES];                          /* a frame's wall ms */
  double end_cpu, end_wall;
  tb_cut_stats st;
  tb_vec3 blade[4]; /* the plane the blade swept: path start, end, end + depth, start + depth */
} tb_mbs_cut_times;
int tb_mbs_cut(tb_model *m, const tb_step *in, tb_mbs_cut_times *o, tb_error *err);
/* 1 when every point of m is finite. */
int tb_mbs_finite(const tb_model *m);

/* Table 2 (the patent's comparison on the steak) and the convergence
 * table; returns 0, or 1 when a run failed (the tables say which). */
int tb_mbs_compare(tb_suite *su, const tb_suite_opts *o);

#endif
