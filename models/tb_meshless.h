/* The point set of the metaball/meshless cutting patent (step
 * 3 (2) "点集驱动", eqs 4-8; after Müller et al. 2004): a standalone
 * simplified meshless elastic body of n points. models/meshless.c documents
 * the kernel, the strain convention and the integrators. */
#ifndef TB_MESHLESS_H
#define TB_MESHLESS_H

#include "core/tb_error.h"
#include "core/tb_math.h"

typedef struct tb_meshless tb_meshless;

/* Says whether the segment a-b crosses the cut (non-zero: it does). */
typedef int (*tb_meshless_crosses)(void *ctx, tb_vec3 a, tb_vec3 b);

/* Integrators of tb_meshless_step. ALTERNATING is the patent's
 * "交替式显式积分" as read in models/meshless.c (a half-step scheme,
 * velocity Verlet); SYMPLECTIC_EULER updates v, then x with the new v. */
enum { TB_MESHLESS_ALTERNATING = 0, TB_MESHLESS_SYMPLECTIC_EULER = 1 };

/* A body of n >= 2 points at rest at x (copied). volume: per-point volumes,
 * or NULL for s^3 each, s the mean nearest-neighbour distance. Support
 * h = 2 s; pairs closer than h are linked unless crosses(ctx, x_i, x_j)
 * (crosses may be NULL: no cut). E > 0, -1 < nu < 1/2, density > 0.
 * Returns NULL with err filled on bad input. */
tb_meshless *tb_meshless_create(int n, const tb_vec3 *x, const double *volume, double E, double nu,
                                double density, tb_meshless_crosses crosses, void *ctx,
                                tb_error *err);
void tb_meshless_destroy(tb_meshless *m);

/* Mass-proportional damping: each step scales velocities by exp(-c dt)
 * (c >= 0, default 0). */
void tb_meshless_set_damping(tb_meshless *m, double c);
/* Points whose moment matrix has det A <= c (tr A / 3)^3 become inactive
 * (default c = 1e-3; clamped to [0, 0.5]): a larger c drops nearly flat
 * stencils, the stiffest, so an explicit step may be longer. */
void tb_meshless_set_flatness(tb_meshless *m, double c);
/* Points with fewer than k neighbours become inactive too (default 0): a
 * stencil of three or four neighbours fits any motion of them exactly,
 * like a lone tet, and can turn inside out under the blade. */
void tb_meshless_set_min_neighbours(tb_meshless *m, int k);
/* TB_MESHLESS_ALTERNATING (default) or TB_MESHLESS_SYMPLECTIC_EULER. */
void tb_meshless_set_integrator(tb_meshless *m, int integrator);

/* Advances by dt under gravity. Points ids[0..nfixed-1] are driven: they end
 * the step at fixed_x[k] with velocity (fixed_x[k] - x_old) / dt. Allocates
 * nothing. Returns 0, or -1 with err filled (bad id, dt <= 0, or a
 * non-finite state: the step is then left half done). */
int tb_meshless_step(tb_meshless *m, double dt, tb_vec3 gravity, int nfixed, const int *ids,
                     const tb_vec3 *fixed_x, tb_error *err);

/* Re-links the points with a new cut: pairs linked so far stay linked
 * unless crosses(ctx, x_i, x_j) at the current positions; weights are those
 * of the rest state. A point left with a degenerate stencil becomes
 * inactive. Compacts the lists in place (allocates nothing; moments anew
 * only for the stencils that lost links); returns 0.
 * err is unused (kept for symmetry). */
int tb_meshless_relink(tb_meshless *m, tb_meshless_crosses crosses, void *ctx, tb_error *err);
/* Drops the links i -> j with keep(ctx, i, j) == 0 (either direction is
 * asked on its own), in place; the stencils that lost links are computed
 * anew. */
typedef int (*tb_meshless_keep)(void *ctx, int i, int j);
void tb_meshless_unlink(tb_meshless *m, tb_meshless_keep keep, void *ctx);

/* Appends k >= 0 points at rest at X, now at x, with velocities v (NULL:
 * zero) and volumes (NULL: (h / 2)^3), keeping the support h of the body's
 * creation. The new points link to every point closer than h, the old ones
 * gain the new points as neighbours, each entry unless crosses(ctx, x_owner,
 * x_other) (crosses may be NULL); the old links stay as they are. Weights
 * and moment matrices are recomputed only for the stencils that changed, so
 * the body is the one tb_meshless_create would give for all the points with
 * the same h and the same cuts, bit for bit (the same sums in the same
 * order). Returns 0, or -1 with err filled (bad input, out of memory: the
 * body is then unchanged). */
int tb_meshless_add(tb_meshless *m, int k, const tb_vec3 *X, const tb_vec3 *x, const tb_vec3 *v,
                    const double *volume, tb_meshless_crosses crosses, void *ctx, tb_error *err);

/* Sets every position (velocities kept). */
void tb_meshless_set_positions(tb_meshless *m, const tb_vec3 *x);
/* Sets every velocity. */
void tb_meshless_set_velocities(tb_meshless *m, const tb_vec3 *v);

/* An upper bound of the largest angular frequency of the points with
 * driven[i] == 0 (driven may be NULL: none), the forces linearised at the
 * current positions, without iterating (the head of models/meshless.c):
 * explicit steps are stable below 2 / it. row: scratch of 2 n doubles. */
double tb_meshless_frequency_bound(const tb_meshless *m, const unsigned char *driven, double *row);
/* The same in two parts: per stencil its bound of omega^2 at rest (0 when
 * it holds no free point) into bound[n] (row: scratch of n), which depends
 * only on the links and the driven set; then the bound at the current
 * positions from them (each stencil's times its stiffening). */
void tb_meshless_rest_bounds(const tb_meshless *m, const unsigned char *driven, double *row,
                             double *bound);
double tb_meshless_frequency_at(const tb_meshless *m, const double *bound);
/* k[g] (g < ngroups): an upper bound of the stiffness of the points with
 * group[i] == g moved together by a common translation, the others held
 * (group[i] < 0: no group). scratch: ngroups vectors. O(links). */
void tb_meshless_group_stiffness(const tb_meshless *m, const int *group, int ngroups, double *k,
                                 tb_vec3 *scratch);

int tb_meshless_count(const tb_meshless *m);
const tb_vec3 *tb_meshless_positions(const tb_meshless *m);
const tb_vec3 *tb_meshless_velocities(const tb_meshless *m);
const tb_vec3 *tb_meshless_rest(const tb_meshless *m);
double tb_meshless_support(const tb_meshless *m);
/* The mean over the points of the distance to the nearest other point: the
 * spacing s a tb_meshless_create of the points now would take (h = 2 s). After
 * tb_meshless_add an old point's distance is lowered only by new points
 * within h of it (an isolated point may keep a larger one). */
double tb_meshless_spacing(const tb_meshless *m);
double tb_meshless_mass(const tb_meshless *m, int i);
/* Point i's neighbours: their count, and (when list is not NULL) a pointer
 * to their indices in ascending order. */
int tb_meshless_neighbours(const tb_meshless *m, int i, const int **list);
/* 1 when point i has an invertible moment matrix (its own strain energy
 * counts), 0 when it is inactive (fewer than 3 non-coplanar neighbours). */
int tb_meshless_active(const tb_meshless *m, int i);
/* J_i = I + grad(u)^T at the current positions, J[a][b] = dx_a / dX_b
 * (identity for an inactive point). */
tb_mat3 tb_meshless_jacobian(const tb_meshless *m, int i);
/* Green strain eps_i = (J^T J - I) / 2. */
tb_mat3 tb_meshless_strain(const tb_meshless *m, int i);
/* Internal (elastic) forces at the current positions into f[n]; 0, or -1
 * out of memory (the transposed links are rebuilt after a link change). */
int tb_meshless_forces(tb_meshless *m, tb_vec3 *f);
/* Elastic energy sum_i V_i eps_i : sigma_i / 2 at the current positions. */
double tb_meshless_energy(const tb_meshless *m);
/* Kinetic energy sum_i m_i |v_i|^2 / 2. */
double tb_meshless_kinetic(const tb_meshless *m);

#endif
