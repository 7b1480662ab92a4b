/* What the files of the reference solver share (reference/ref_*.c; the
 * public side is tb_reference.h): the element kernel (ref_element.c), the
 * assembled system with its CHOLMOD factor (ref_system.c), the solution the
 * public getters and the sampler read (ref_solver.c, ref_sample.c).
 * Element nodes: the linear tet's corners 0..3, then (10-node tets) the
 * midside nodes of edges (0,1) (1,2) (0,2) (0,3) (1,3) (2,3). Outside this
 * folder only tests/test_reference.c includes this header. */
#ifndef TB_REF_PRIV_H
#define TB_REF_PRIV_H

#include <cholmod.h>

#include "tb_reference.h"

/* ---- element kernel (ref_element.c) ---- */

extern const int tb_ref_edge_ends[6][2]; /* local corners of midside node 4 + e */

/* A quadrature rule on the tet in barycentric coordinates, weights summing
 * to 1 (multiply by the volume). */
typedef struct tb_ref_rule {
  int n;
  const double (*L)[4];
  const double *w;
} tb_ref_rule;
/* npe = 10: the symmetric 14-point degree-5 rule (positive weights);
 * npe = 4: the centroid (gradients are constant). */
tb_ref_rule tb_ref_rule_for(int npe);

/* Shape functions (npe = 4 or 10) at barycentric coordinates L, and their
 * rest-space gradients given the corners' barycentric gradients gl. */
void tb_ref_shape(int npe, const double L[4], double *N);
void tb_ref_shape_grad(int npe, const double L[4], const tb_vec3 gl[4], tb_vec3 *G);

/* Rest volume of tet (a,b,c,d) and the gradients of its barycentric
 * coordinates; returns the signed volume (gl untouched unless > 0). */
double tb_ref_tet_grads(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d, tb_vec3 gl[4]);

typedef struct tb_ref_material {
  int kind; /* TB_REF_* */
  double lambda, mu;
} tb_ref_material;

/* Energy density psi, first Piola-Kirchhoff stress P (row-major 3x3, P[3i+J])
 * and, when A is not NULL, the tangent A[9 (3i+J) + 3k+L] = dP_iJ / dF_kL at
 * the deformation gradient F (row-major). Returns -1 (nothing else written
 * but *J) when det F <= 0 for a nonlinear material. */
int tb_ref_stress(const tb_ref_material *m, const double F[9], double *psi, double P[9], double *A,
                  double *J);

/* One element: rest barycentric gradients gl and volume vol, nodal
 * displacements u (npe). Adds the element energy to *energy, its internal
 * forces to f (npe) and, when K is not NULL, its tangent to K (row-major,
 * 3 npe x 3 npe, dof 3a + i). *jmin gets min(*jmin, det F over the points).
 * Returns -1 when det F <= 0 somewhere (nonlinear materials). */
int tb_ref_element(const tb_ref_material *m, int npe, const tb_vec3 gl[4], double vol,
                   const tb_vec3 *u, double *energy, tb_vec3 *f, double *K, double *jmin);

/* ---- assembled system (ref_system.c) ---- */

typedef struct tb_ref_sys {
  tb_ref_material mat;
  int nn, ntet, npe; /* nodes (corners then midside), tets, nodes per element */
  const int *elem;   /* npe per tet */
  const tb_vec3 *gl; /* 4 per tet */
  const double *vol;
  const int *free_of; /* 3 nn: free index of each dof, -1 when prescribed */
  int nfree;
  /* 3x3 node blocks, all nodes, both triangles: block q of row n couples n
   * and col[q], kb[9 q + 3 r + c] = K(3 n + r, 3 col[q] + c) */
  int *row, *col, *diag;
  double *kb;
  int *elem_blk; /* npe^2 per tet */
  /* CHOLMOD: upper triangle over the free dofs, entry p = kb[a_src[p]] */
  cholmod_common cc;
  int started;
  cholmod_sparse *A;
  int *a_src, *a_diag;
  cholmod_factor *L;
  int factorisations;
} tb_ref_sys;

/* Pattern, matrix and symbolic analysis (the fields above must be set). */
int tb_ref_sys_init(tb_ref_sys *s, tb_error *err);
void tb_ref_sys_free(tb_ref_sys *s);
/* Internal forces fint (nn), energy and the smallest det F at displacements
 * u; the tangent's blocks too when want_k. Returns -1 when det F <= 0 (the
 * first such tet in *bad). */
int tb_ref_sys_eval(tb_ref_sys *s, const tb_vec3 *u, tb_vec3 *fint, double *energy, int want_k,
                    double *jmin, int *bad);
/* y = K v over all nodes (blocks of the last evaluation with want_k). */
void tb_ref_sys_mul(const tb_ref_sys *s, const tb_vec3 *v, tb_vec3 *y);
/* Factorises the free-free block plus shift on its diagonal. Returns 0, 1
 * when not positive definite (or singular: a pivot below 1e-10 of its
 * diagonal entry; the node in *node), -1 on CHOLMOD failure (err set). */
int tb_ref_sys_factor(tb_ref_sys *s, double shift, int *node, tb_error *err);
/* The mean diagonal entry of the free-free block. */
double tb_ref_sys_mean_diag(const tb_ref_sys *s);
/* Solves with the last factor: b and x are nfree long. */
int tb_ref_sys_solve(tb_ref_sys *s, const double *b, double *x, tb_error *err);

/* ---- the solution (ref_solver.c; the grid is built by ref_sample.c) ---- */

struct tb_ref_solution {
  int nv, nn, ntet, npe;
  tb_vec3 *X;  /* nv rest corners */
  int *elem;   /* npe per tet */
  tb_vec3 *gl; /* 4 per tet */
  tb_vec3 *u;  /* nn displacements */
  tb_vec3 *x;  /* nv equilibrium positions */
  int nfixed;
  tb_vec3 *reaction;
  int iterations, load_steps;
  double residual, jmin;
  /* point location: a uniform grid over the mesh's box, tets listed in
   * every cell their box overlaps */
  tb_vec3 lo;
  double h;
  int dim[3];
  int *cell_start, *cell_tet;
};

int tb_ref_grid_build(tb_ref_solution *s, tb_error *err);
/* The smallest det F at the quadrature points of the solution. */
double tb_ref_min_jacobian(const tb_ref_solution *s);

#endif
