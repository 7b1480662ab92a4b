/* One cut of an organ, run and judged (measure/cut_trial.c): the organ's
 * surface and spheres from files, one end held, gravity, one or more
 * blades, then a second more; at the last blade's end and at the run's end
 * the surface's pieces (closed? self-intersecting?), the sphere graph
 * against them, the pieces' volumes over that second, and the CPU time of
 * the frames the blades moved in. The cut torture suite and the tests run
 * these. */
#ifndef TB_CUT_TRIAL_H
#define TB_CUT_TRIAL_H

#include "core/tb_error.h"
#include "core/tb_math.h"

#define TB_CUT_TRIAL_BLADES 3
#define TB_CUT_TRIAL_POINTS 6

typedef struct tb_cut_blade {
  int n; /* path points, 2 .. TB_CUT_TRIAL_POINTS */
  tb_vec3 p[TB_CUT_TRIAL_POINTS], depth;
  double start, stop;
} tb_cut_blade;

typedef struct tb_cut_trial {
  char name[64];
  char mesh[512], spheres[512]; /* the organ's surface and its .sph */
  tb_vec3 hold_lo, hold_hi;     /* the points in this box are held */
  int nblade;
  tb_cut_blade blade[TB_CUT_TRIAL_BLADES];
  double after; /* simulated seconds after the last blade's stop */
  double dt;
} tb_cut_trial;

typedef struct tb_cut_outcome {
  int ran;       /* the run reached its end */
  char why[240]; /* else the reason */
  /* at the last blade's end, and at the run's end */
  int pieces_cut, pieces_end, closed_cut, closed_end, self_cut, self_end;
  int overlap_cut, overlap_end; /* crossing triangle pairs of two pieces */
  int self_before;              /* crossing pairs of the organ's surface before the cut */
  double deepest_end;           /* the deepest crossing at the run's end, mean edges (tb_pieces) */
  int spheres_cut;              /* components of the sphere graph at the cut's end */
  int consistent_cut;           /* they are the pieces (tb_pieces_spheres) */
  int crossing_cut;             /* points bound across the cut */
  double drift;                 /* the largest |V / V_cut - 1| of a piece over the second after */
  double frame_ms;              /* median CPU ms of the frames the blades moved in */
  int vertices_cut;             /* the surface's vertices after the cut */
} tb_cut_outcome;

/* Runs t; the outcome says how it went. Returns 0, or -1 with err when the
 * trial could not be set up (no files, no memory): a cut that fails or a
 * run that blows up is an outcome, not an error. */
int tb_cut_trial_run(const tb_cut_trial *t, tb_cut_outcome *o, tb_error *err);

/* "ok" when the outcome meets everything a cut must (ran, closed and with
 * no self-intersection the organ did not have at both ends, no piece
 * inside another, the sphere graph's components the pieces, drift at most
 * max_drift), else the first thing it misses. */
const char *tb_cut_outcome_verdict(const tb_cut_outcome *o, double max_drift, char *buf,
                                   size_t cap);

#endif
