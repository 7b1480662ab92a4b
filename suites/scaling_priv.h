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

/* One model on one mesh, one thread. */
typedef struct cell {
  int ok;       /* timed and healthy */
  int steps;    /* timed steps */
  double ms;    /* median CPU ms per step */
  double wall;  /* median wall ms per step */
  double rss;   /* peak RSS added, KiB (NAN: unknown) */
  uint64_t sum; /* hash of positions and velocities after the run */
  char why[160];
} cell;

/* One model on a threads mesh: runs on 1, 2, 4, ... threads and on every
 * core, live side by side and taking turns step by step. */
#define SCALING_MAX_COUNTS 6 /* 1, 2, 4, 8, 16 and the cores at most */
typedef struct thread_cell {
  int ok, steps;                 /* steps: timed steps of each run */
  int ncounts;                   /* counts run; [ncounts - 1]: every core */
  int count[SCALING_MAX_COUNTS]; /* their thread counts */
  double wall[SCALING_MAX_COUNTS], cpu[SCALING_MAX_COUNTS]; /* medians, ms per step */
  tb_est speedup[SCALING_MAX_COUNTS]; /* one thread's wall time over this count's, paired by step */
  int identical;                      /* positions and velocities the same bits on every count */
  int busy;      /* the machine did not leave the cores free (tb_suite_noise) */
  double others; /* the cores other processes kept busy */
  int cores;     /* the machine's */
  char why[160];
} thread_cell;

/* The speed-up a count of n threads is predicted to reach from the
 * measured one on the most threads (Karp & Flatt 1990: the serial share e
 * that explains it, held constant): 1 / (e + (1 - e) / n); *e gets the
 * share. NAN when fewer than 2 threads were measured. */
double tb_scaling_predict(const thread_cell *t, int n, double *e);

/* One mesh of the ladder. */
typedef struct size_row {
  int ok, target, ntet, nv, ntri, pairs;
  double gen_s, refit_ms, query_ms; /* CPU, one thread */
  double both_wall;                 /* refit + query, wall */
  char why[160];
} size_row;

typedef struct scaling_run {
  int nsizes, nm, cores, big, frames; /* big: the largest mesh made (-1: none) */
  int nthread_rows, thread_rows[2];   /* the sizes the thread counts run on */
  double budget, seconds;
  size_row rows[SCALING_MAX_SIZES];
  cell cells[SCALING_MAX_MODELS][SCALING_MAX_SIZES]; /* [model of the table][size], 1 thread */
  thread_cell thr[SCALING_MAX_MODELS][2];            /* [model][thread row]: the thread counts */
} scaling_run;

/* Tables, notes and charts; 1 when something failed. */
int tb_scaling_report(tb_suite *su, const scaling_run *sr);

#endif
