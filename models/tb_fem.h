/* Test and benchmark hooks of the fem and fem-corot models (models/fem_core.c):
 * solver statistics, the residual of the last CHOLMOD solve, and setting
 * the state (e.g. a rigidly rotated body) without stepping. */
#ifndef TB_FEM_H
#define TB_FEM_H

#include "tb_model.h"

typedef struct tb_fem_stats {
  int factorizations;  /* numeric factorisations so far */
  long solves;         /* solves with the factor so far (pcg: preconditioner applications) */
  double residual;     /* ||A y - b|| / ||b|| of the last solve (cholmod_sdmult), NAN before any;
                          fem-corot's iterative solvers: of the last step's system */
  long iterations;     /* fem-corot pcg: CG iterations; lagged: refinements; pd: iterations */
  int last_iterations; /* the same, of the last step */
  int warm_order;      /* pcg: the last step's warm-start order (0 before the second step) */
  int supernodal;      /* 1: supernodal L L^T, 0: simplicial L D L^T */
  int ordering;        /* CHOLMOD_AMD, CHOLMOD_METIS, ... (cholmod.h) */
  double nnz_factor;   /* entries of L (CHOLMOD's lnz) */
  int dofs;            /* 3 * nodes */
} tb_fem_stats;

/* Fills *s for a fem or fem-corot model; anything else is an error. */
int tb_fem_get_stats(tb_model *m, tb_fem_stats *s, tb_error *err);
/* Replaces positions and velocities (nv each; v may be NULL for zero). */
int tb_fem_set_state(tb_model *m, const tb_vec3 *x, const tb_vec3 *v, tb_error *err);

/* The rotation of the polar decomposition F = R S, det F > 0, by Newton's
 * method on the rotation started from the unit quaternion q (the last
 * step's; updated): quadratic convergence from a close start. Inverted F,
 * or a start that does not converge in a few steps, go to
 * tb_m3_polar_newton (q set from its result). */
tb_mat3 tb_fem_polar_warm(tb_mat3 F, double *q);

#endif
