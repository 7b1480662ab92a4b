/* The reference solution every model is measured against: static
 * nonlinear hyperelastic FEM (compressible Neo-Hookean or St Venant-
 * Kirchhoff; linear elasticity for checks) on 10-node quadratic tets built
 * from a linear tet mesh (edge midpoints added; linear tets lock in
 * bending), solved by Newton's method with a line search and incremental
 * loading, each linear system by CHOLMOD. Validated against analytic cases
 * (tests/test_reference.c): uniaxial traction and a cantilever. */
#ifndef TB_REFERENCE_H
#define TB_REFERENCE_H

#include "core/tb_error.h"
#include "core/tb_mesh.h"

enum { TB_REF_NEOHOOKE = 0, TB_REF_STVK = 1, TB_REF_LINEAR = 2 };

typedef struct tb_ref_def {
  int material;   /* TB_REF_*: Neo-Hookean */
  double E, nu;   /* 3000, 0.3 */
  int quadratic;  /* 1: 10-node tets (default), 0: the linear tets themselves */
  double tol;     /* Newton: residual norm relative to the load's: 1e-9 */
  int max_iter;   /* Newton iterations per load step: 30 */
  int load_steps; /* incremental loading (0: 1, raised automatically on failure) */
} tb_ref_def;
tb_ref_def tb_ref_default_def(void);

/* Loads and supports on the nodes of the linear mesh. */
typedef struct tb_ref_problem {
  const tb_mesh *mesh;  /* rest linear tet mesh */
  double density;       /* for gravity (mass per volume) */
  tb_vec3 gravity;      /* body acceleration */
  const tb_vec3 *force; /* nv nodal forces at the mesh's nodes, or NULL */
  int nfixed;
  const int *fixed;       /* prescribed nodes, strictly ascending */
  const tb_vec3 *fixed_x; /* their positions */
  const int *fixed_mask;  /* per prescribed node: bits 1, 2, 4 = x, y, z held (NULL: all) */
} tb_ref_problem;

typedef struct tb_ref_solution tb_ref_solution;

/* Solves for static equilibrium. Midside nodes of prescribed edges (both
 * ends prescribed) follow the edge's midpoint. Returns NULL with err when
 * Newton fails to converge (after load-step refinement) or a matrix is not
 * positive definite. */
tb_ref_solution *tb_ref_solve(const tb_ref_problem *p, const tb_ref_def *def, tb_error *err);
void tb_ref_free(tb_ref_solution *s);

/* Equilibrium positions of the linear mesh's nodes (nv). */
const tb_vec3 *tb_ref_positions(const tb_ref_solution *s);
/* Reaction force on each prescribed node (nfixed, same order as fixed). */
const tb_vec3 *tb_ref_reactions(const tb_ref_solution *s);
/* Displacements at arbitrary rest-space points, by the element shape
 * functions of the tet containing each point (points outside the mesh use
 * the nearest tet, extrapolated). */
int tb_ref_sample(const tb_ref_solution *s, const tb_vec3 *points, int n, tb_vec3 *u,
                  tb_error *err);
/* Newton iterations and load steps used, final relative residual. */
void tb_ref_stats(const tb_ref_solution *s, int *iterations, int *load_steps, double *residual);

#endif
