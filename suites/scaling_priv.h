/* What the scaling suite measures (suites/suite_scaling.c) and hands to its
 * tables and charts (suites/suite_scaling_report.c). */
#ifndef TB_SCALING_PRIV_H
#define TB_SCALING_PRIV_H

#include <stdint.h>

#include "report/tb_results.h"

#define SCENE "liver-stretch"
#define MS_30HZ (1000.0 / 30)   /* 30 Hz: graphics */
#define MS_300HZ (1000.0 / 300) /* 300 Hz: haptics */
#define SCALING_MAX_SIZES 12
#define SCALING_MAX_MODELS 16

/* One model on one mesh. */
typedef struct cell {
  int ok;       /* timed and healthy */
  int steps;    /* timed steps */
  double ms;    /* median ms per step */
  double rss;   /* peak RSS added, KiB (NAN: unknown) */
  uint64_t sum; /* hash of positions and velocities after the run */
  char why[160];
} cell;

/* One mesh of the ladder. */
typedef struct size_row {
  int ok, target, ntet, nv, ntri, pairs;
  double gen_s, refit_ms, query_ms;
  char why[160];
} size_row;

typedef struct scaling_run {
  int nsizes, nm, cores, big, frames; /* big: the largest mesh made (-1: none) */
  int threads_row;                    /* the size of the one against all threads table */
  double budget, seconds;
  size_row rows[SCALING_MAX_SIZES];
  cell cells[SCALING_MAX_MODELS][SCALING_MAX_SIZES]; /* [model of the table][size], 1 thread */
  cell all[SCALING_MAX_MODELS];                      /* the largest mesh on every core */
} scaling_run;

/* Tables, notes and charts; 1 when something failed. */
int tb_scaling_report(tb_suite *su, const scaling_run *sr);

#endif
