/* Private to models/fem*.c: the state the linear (fem.c) and corotational
 * (fem_corot.c) tetrahedral FEM models share, and the shared steps
 * (fem_core.c): element stiffness K_e = V B^T D B (thesis §3.3.2), the node
 * block pattern, the fixed CHOLMOD pattern, Dirichlet elimination and one
 * implicit-Euler (or quasi-static) solve. */
#ifndef TB_FEM_PRIV_H
#define TB_FEM_PRIV_H

#include <cholmod.h>

#include "carve_priv.h"
#include "tb_model.h"

/* The settings fem and fem-corot read; each declares its table in its own
 * file from TB_FEM_SETTINGS. */
typedef struct tb_fem_settings {
  double density, node_mass, E, nu;
  double rayleigh_mass, rayleigh_stiffness; /* C = a M + b K */
  int consistent_mass, quasistatic;
} tb_fem_settings;
#define TB_FEM_SETTINGS                                                                 \
  TB_SETTINGS_MASS(tb_fem_settings, 0.0), TB_SETTINGS_MATERIAL(tb_fem_settings),        \
      TB_SETTING_R(tb_fem_settings, rayleigh_mass, 0.0, 0.0, HUGE_VAL, 0,               \
                   "Rayleigh damping a of C = a M + b K"),                              \
      TB_SETTING_R(tb_fem_settings, rayleigh_stiffness, 0.02, 0.0, HUGE_VAL, 0,         \
                   "Rayleigh damping b of C = a M + b K"),                              \
      TB_SETTING_I(tb_fem_settings, consistent_mass, 0, 0, 1,                           \
                   "1: consistent mass matrix instead of lumped (not with node_mass)"), \
      TB_SETTING_I(tb_fem_settings, quasistatic, 0, 0, 1,                               \
                   "1: each step solves the static equilibrium (velocities 0)")

typedef struct tb_fem {
  /* hot state: current and rest positions, velocities (nv each) */
  tb_vec3 *x, *v, *X;
  int nv, ntet;
  int corot;        /* 1: element rotations from the polar decomposition */
  const char *name; /* "fem" or "fem-corot", for errors */
  double a, b;      /* Rayleigh factors: C = a M + b K */
  int quasistatic;
  double *mass; /* lumped node masses */

  /* per tet */
  int *tet;        /* 4*ntet node indices */
  tb_mat3 *dm_inv; /* D_m^-1 (rest edge matrix inverse), for F = D_s D_m^-1 */
  double *ke;      /* 144 per tet: K_e, node blocks (a,b) of 3x3 row-major at 9*(4a+b) */
  int *tet_blk;    /* 16 per tet: the block (row e[a], column e[b]) in the pattern */

  /* node-block pattern, both triangles (block CSR): node n couples to
   * col[row[n] .. row[n+1]-1], ascending, itself included at diag[n] */
  int nblk;
  int *row, *col, *diag;
  double *kb; /* 9 per block: K (fem) or R K_e R^T summed (fem-corot: blocks (n, m >= n) only) */
  double *mb; /* 1 per block: the mass block is mb * I (lumped: diagonal only) */

  /* scratch, nv each */
  tb_vec3 *fel; /* elastic node forces (fem-corot) */
  tb_vec3 *yc;  /* prescribed unknowns (velocity or increment) at fixed nodes, 0 elsewhere */
  unsigned char *fixed; /* 1 for prescribed nodes */
  int *fixed_list;      /* the prescribed set of the current factor */
  int nfixed;

  /* CHOLMOD: A = alpha M + beta K with identity rows/columns for the
   * prescribed dofs, upper triangle (stype 1), pattern fixed at create */
  cholmod_common cc;
  cholmod_sparse *A;
  int *a_blk;  /* per entry of A: 9*block + 3*r + c (the K entry) */
  int *a_mass; /* per entry of A: the mass block, or -1 off the block diagonal */
  int *a_diag; /* per dof: its diagonal entry in A */
  cholmod_factor *L;
  cholmod_dense *B, *Xs, *Y, *E; /* right-hand side, solution, solve workspaces */
  int factored;                  /* L holds the factor of the current A */
  double f_alpha, f_beta;        /* the coefficients A was built with */
  int nfactor;                   /* numeric factorisations done */
  long nsolve;

  /* tet colouring (tet_colour.c): tets of one colour share no node, so the
   * per-element loops add into nodes and blocks in parallel, in an order
   * fixed by the colouring (bit-identical for any thread count) */
  int ncolours, *col_order, *col_start;
  tb_mat3 *rot;       /* per tet: the rotation of the current step (fem-corot) */
  double *tf, *th;    /* per tet: node forces (12); h_a = R g_a (12), then V h_a (12) */
  int *nl_start, *nl; /* per node: its (tet, corner) pairs 4 t + a, t ascending */
  int *bl_start, *bl; /* per block (n, m >= n): its (t, a, b) as 16 t + 4 a + b, t ascending */
  int *blk_tr;        /* per block (n, m): the block (m, n) */
  double *quat;       /* per tet, then per node (pcg): the last rotation as a unit quaternion (4) */
  double *vol;        /* per tet: rest volume */
  double lambda, mu;

  /* fem-corot's solvers (fem_solve.c); solver TB_FEM_EXACT for fem */
  int solver;
  double cg_tol;             /* pcg: relative residual */
  int cg_max;                /* pcg: iterations before the preconditioner is refactored */
  int cg_refactor;           /* pcg: extra iterations since the factor that make a refactor */
  long cg_excess;            /* pcg: those extra iterations so far */
  int lag, refine, pd_iters; /* lagged: refactor every lag steps, refinements; pd iterations */
  double *lb;                /* per block: the Laplacian sum V g_a.g_b (pd's constant matrix) */
  double *b0, *cg_p, *cg_q;  /* n3 each */
  double *warm;              /* TB_FEM_WARM n3: pcg's solutions before the last, a ring */
  int warm_head, warm_order; /* the newest's slot; the last warm start's order */
  double *cg_r;              /* n3: pcg's residual */
  int cg_rotate;             /* pcg: preconditioner rotated per node */
  int cg_warm;               /* pcg: highest warm-start order (1..TB_FEM_WARM) */
  tb_mat3 *nrot, *nq, *ntr;  /* nv each: node rotations now, at the factor, T = R Q^T */
  long nsteps;               /* steps through tb_fem_iterate */
  cholmod_dense *R, *Z;      /* preconditioner solve: residual in, correction out */
  int since_factor;          /* steps since the preconditioner was factored */
  long iters;                /* CG iterations, refinements or pd iterations so far */
  int last_iters;
  double last_res; /* ||b - A y|| / ||b|| of the last iterative solve */

  /* cutting (fem_cut.c): a removed tet keeps its index with volume 0 and
   * K_e 0 (carve.alive[t] == 0); the masses are lumped again from the tets
   * left */
  tb_carve carve;
  unsigned char *hit; /* per tet: touched by the blade at this MOVE */
  double density, node_mass;
  int consistent; /* consistent masses: not cut */
} tb_fem;

/* Row loops over at least this many nodes (the iterative solvers' matrix
 * product, the right-hand side) run on threads; each row is summed by one
 * thread in one order, so the result does not depend on the count. */
#define TB_FEM_PAR_ROWS 256

/* pcg's warm start extrapolates through at most this many solutions. */
#define TB_FEM_WARM 6

enum { TB_FEM_EXACT, TB_FEM_PCG, TB_FEM_LAGGED, TB_FEM_PD };

/* Builds everything but the rotations: masses (lumped, or consistent when
 * def->consistent_mass and no node_mass), K_e, the patterns, the symbolic
 * analysis, workspaces. Returns NULL with err filled. */
tb_fem *tb_fem_create(const tb_mesh *mesh, const tb_fem_settings *def, int corot, const char *name,
                      tb_error *err);
/* pd's Laplacian sums lb (V g_a . g_b per node pair) over the tets (a
 * removed tet, volume 0, adds nothing). */
void tb_fem_laplacian(tb_fem *f);
/* fem-corot's cut (removes the tets the blade touches) and its surface
 * (the boundary of the tets left), fem_cut.c. */
int tb_fem_cut(void *self, const tb_cut_event *ev, tb_cut_stats *st, tb_error *err);
tb_surface tb_fem_surface(const void *self);
const unsigned char *tb_fem_tets_alive(const void *self);

/* The class functions fem and fem-corot share. */
const double *tb_fem_masses(const void *self);
void tb_fem_correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v);
void tb_fem_destroy(tb_fem *f);

/* Adds the 12x12 element matrix k (node blocks, 144 doubles) of tet t into kb. */
void tb_fem_add_element(tb_fem *f, int t, const double *k);
/* y = K u over the node-block pattern (both triangles). */
void tb_fem_kmul(const tb_fem *f, const tb_vec3 *u, tb_vec3 *y);

/* One step: checks the prescribed set, rebuilds A and refactors when the
 * set, the coefficients or (corot) the matrix changed, assembles the
 * right-hand side with the prescribed columns moved to it, solves, and
 * advances x, v. Linear fem passes lin = 1 (elastic force -K(x - X) from kb);
 * fem-corot passes lin = 0 with f->fel filled and kb rotated, and
 * refactor = 1. */
int tb_fem_advance(tb_fem *f, const tb_step *in, int lin, int refactor, tb_error *err);

/* The pieces of tb_fem_advance the iterative solvers (fem_solve.c) share.
 * begin: checks the step, updates the prescribed set and the coefficients
 * (alpha M + beta K); returns 1 when the factor must be redone (set or
 * coefficients changed, or none yet), 0 if not, -1 on error. */
int tb_fem_begin(tb_fem *f, const tb_step *in, double *alpha, double *beta, tb_error *err);
/* A <- alpha M + beta K (pd: beta (2 mu + 3 lambda) L) with identity rows
 * and columns for the prescribed dofs, then the numeric factorisation. */
int tb_fem_refactor(tb_fem *f, double alpha, double beta, int pd, tb_error *err);
/* B <- the right-hand side (f->yc set here); the prescribed columns moved
 * over with K's blocks (kb), or pd's (2 mu + 3 lambda) lb I blocks. */
void tb_fem_rhs(tb_fem *f, const tb_step *in, int lin, double alpha, double beta, int pd);
/* X <- A^-1 B with the current factor, no allocation after the first call. */
int tb_fem_solve(tb_fem *f, cholmod_dense *B, cholmod_dense **X, tb_error *err);
/* x, v from the solution in f->Xs. */
void tb_fem_finish(tb_fem *f, const tb_step *in, double dt);

/* fem-corot's iterative step (pcg, lagged, pd) after its element loop. */
int tb_fem_iterate(tb_fem *f, const tb_step *in, tb_error *err);
/* ||b - A y|| / ||b|| of the last iterative step's system (A, b of that
 * step, y its solution), NAN before any solve. */
double tb_fem_residual(tb_fem *f);

/* 1/2 v^T M v. */
double tb_fem_kinetic(const tb_fem *f);

/* The element matrices of one tet with rest edge inverse dm_inv and volume
 * vol (lambda, mu Lamé): k (144) as in tb_fem.ke. */
void tb_fem_element_k(tb_mat3 dm_inv, double vol, double lambda, double mu, double *k);

#endif
