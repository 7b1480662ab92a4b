/* points.csv: the measured runs of `figure pareto` (one row each: model,
 * resolution, parameters, speed, errors against the reference, state),
 * which `advise` chooses from (measure/points.c). */
#ifndef TB_POINTS_H
#define TB_POINTS_H

#include "core/tb_error.h"

#define TB_POINTS_HEADER                                                             \
  "model,resolution,nodes,params,steps/s,ms/step,rms error,max error,volume change," \
  "reaction error,settle time (s),recovery error,state"

typedef struct tb_point {
  char model[32];
  int resolution, nodes;
  char params[160];
  double steps_per_s, ms_step; /* per step of the scene's dt, CPU time on one thread */
  double rms_err, max_err, volume_change, reaction_err, settle_time, recovery_err;
  char state[192];
  int line; /* in the file */
} tb_point;

/* One line of points.csv for p (no newline; commas in text become ';'). */
int tb_point_format(const tb_point *p, char *buf, int cap);
/* Reads path: the header above, then rows of 13 fields; a bad line is an
 * error "path:line: reason". *out is malloc'ed (free it). */
int tb_points_read(const char *path, tb_point **out, int *n, tb_error *err);
/* Usable (on the front, advised): the run settled (state "settled") and its
 * error and speed are finite. An unstable run has no answer, and a run that
 * did not settle has a passing snapshot, not an equilibrium. */
int tb_point_usable(const tb_point *p);

#endif
