/* The patent's simplified meshless elasticity for the point set (metaball
 * hybrid cutting patent, step 3 (2) "点集驱动", eqs 4-8; after
 * Müller et al. 2004, "Point based animation of elastic, plastic and
 * melting objects"). Energy is evaluated at the points only, each point's
 * energy density held over its volume V_i.
 *
 * Support and links: s = the mean over points of the distance to the
 * nearest other point (the sample spacing), h = 2 s for every point (the
 * patent: twice the mean neighbour distance), so links are symmetric. i and
 * j are linked when |X_j - X_i| < h and the segment does not cross the cut
 * (crosses(ctx, x_i, x_j) == 0). Found with a uniform grid of cell >= h:
 * O(n) for a sampled body; each list ascending.
 *
 * Kernel, fixed at the rest state X (the patent's w_ij): the cubic B-spline
 * of support h, q = r / h,
 *   w(q) = 8 / (pi h^3) * { 1 - 6 q^2 + 6 q^3   0 <= q <= 1/2
 *                         { 2 (1 - q)^3         1/2 < q <= 1,  0 beyond,
 * normalised to unit integral over R^3. The normalisation cancels: w enters
 * only through A^-1 sum(... w).
 *
 * Eq 4, with X_ij = X_j - X_i and u = x - X:
 *   A_i = sum_j X_ij X_ij^T w_ij,   d_ij = A_i^-1 X_ij w_ij,
 *   J_i = I + grad(u_i)^T = I + sum_j (u_j - u_i) d_ij^T,
 * so J[a][b] = dx_a / dX_b; a linear field u = G X + t gives J - I = G.
 * Strain: Green's, eps = (J^T J - I) / 2. The patent (and Müller) write
 * eps = J^T J - I, twice Green's: with it the body is 4 times stiffer than
 * E says (energy quadratic in eps). Here E is the small-strain Young's
 * modulus. sigma = lambda tr(eps) I + 2 mu eps (Hooke, isotropic; eq 5),
 * energy U_i = V_i eps : sigma / 2. Since dU/dJ = V J sigma (with the
 * patent's strain it is 2 V J sigma, its factor 2), eqs 7-8 become
 *   F_e = -V_i J_i sigma_i,  f_j = F_e d_ij,  f_i = -sum_j f_j,
 * exactly minus the gradient of sum_i U_i (J_i is linear in x and d_ij is
 * fixed), so linear and angular momentum are conserved.
 *
 * A point whose A_i is degenerate (fewer than 3 non-coplanar neighbours, or
 * a nearly flat stencil: det A <= c (tr A / 3)^3, c = 1e-3 by default or
 * tb_meshless_set_flatness, the smallest eigenvalue below roughly c of the
 * mean), or with fewer neighbours than tb_meshless_set_min_neighbours asks
 * (none by default), is inactive: it has no strain
 * energy of its own (J = I) but still enters its neighbours' sums, or moves
 * freely when it has no active neighbour; no NaN comes from it. (A dt
 * beyond the explicit bound still blows up: tb_meshless_step reports it.)
 *
 * The forces are gathered: each stencil's P_i = -V_i J_i sigma_i, then each
 * point's sum over the stencils holding it through the transposed links, in
 * ascending order; both loops split among threads (OpenMP), each result
 * computed whole by one thread, so the thread count changes no bit.
 *
 * Volumes: given, or s^3. Masses m_i = density V_i.
 *
 * Time integration. The patent (normalised to simplified script; its "显示"
 * read as 显式, explicit): "交替式显式积分法 ... 在半步长内获取力, 通过该力
 * 获取位移, 在后半个步长内更新速度" (alternating explicit: within a half
 * step get the force and from it the displacement; in the second half step
 * update the velocity). Read as the half-step (kick-drift-kick) scheme
 *   v' = v + dt/2 a(x),  x += dt v',  v = v' + dt/2 a(x_new),
 * i.e. velocity Verlet: one force evaluation per step (a(x_new) is kept for
 * the next step), symplectic, exact under constant acceleration. Against
 * symplectic Euler the displacement takes dt^2/2 a(x) instead of dt^2 a(x)
 * and the velocity the mean of the old and new accelerations, in line with
 * the patent's remark that velocity comes out larger and displacement
 * smaller ("相对中合"). Option: symplectic Euler, v += dt a(x), x += dt v.
 * Damping multiplies v by exp(-c dt) once per step.
 *
 * Explicit stability needs dt omega < 2, omega the largest angular
 * frequency of the free points (sqrt of the largest eigenvalue of M^-1 K,
 * K the stiffness at rest). tb_meshless_frequency_bound bounds it without
 * iterating: U_i = V_i psi(H_i) with H_i = sum_b u_b d_ib^T over i's
 * stencil (b = i included, d_ii = -sum_j d_ij), psi's Hessian at rest is
 * Hooke's, H : C : H = 2 mu |sym H|^2 + lambda (tr H)^2, so K = sum_i K_i
 * with u^T K_i u <= V_i (2 mu |H_i|^2 + lambda (sum_b u_b . d_ib)^2), b over
 * the free points only (the driven ones are prescribed). The element
 * eigenvalue theorem (Irons 1970; Fried 1972, "Bounds on the extremal
 * eigenvalues of the finite element stiffness and mass matrices", the
 * explicit FEM's critical step) splits each point's mass among the
 * stencils holding it, m_b = sum_i m_ib, and gives omega^2 <= max_i of
 * stencil i's own largest eigenvalue against its masses, here at most
 * V_i (2 mu lambda_max(G_i) + lambda tr(G_i)), G_i = sum_b d_ib d_ib^T / m_ib
 * (|U D|_F^2 <= |U M^1/2|_F^2 lambda_max(D^T M^-1 D), and Cauchy-Schwarz for
 * the trace term). The split: m_ib = m_b t_ib / T_b with t_ib = V_i S_i
 * |d_ib|, S_i = sum over i's free b of |d_ib|, T_b = sum_i t_ib; bounding
 * the bracket by kappa tr(G_i), kappa = 2 mu + 3 lambda, would give block
 * Gershgorin (Feingold & Varga 1962), omega^2 <= max_b kappa T_b / m_b, so
 * this one is never looser (eigenvalue: Smith 1961). A 6^3 lattice: 1.05 x
 * the power-iterated omega against block Gershgorin's 1.65; the liver's
 * point set at the end of microbench/metaball_cut_timing's cut, the bound
 * linearised there as below: 1.21 x (block Gershgorin: about 1.75). Away from rest the
 * bound is of the forces linearised at the current positions: the Hessian
 * of psi in J = F is 2 mu |sym(F^T H)|^2 + lambda (F : H)^2 + S : H^T H
 * (S = sigma, the second Piola-Kirchhoff stress), at most
 * sigma_max(F)^2 (2 mu |H|^2 + lambda (tr-like term)) + max(lambda_max(S),
 * 0) |H|^2, so stencil i's bound is multiplied by sigma_max(F_i)^2 +
 * max(lambda_max(S_i), 0) / (2 mu) (sigma_max^2 = 1 + 2 lambda_max(eps)):
 * 1 at rest. (A global factor sqrt(1 + 3 eps_max), the uniaxial tangent,
 * is not enough: with it the steak held at one end and cut blows up.) The
 * same Hessian at rest
 * gives a group's stiffness under a common translation t of its
 * points (u_b = t for b in the group): H_i = t g_i^T, g_i = sum over the
 * group's points b in i's stencil of d_ib, |sym H_i| <= |t| |g_i| and
 * (tr H_i)^2 <= |t|^2 |g_i|^2, so the energy's curvature is at most
 * sum_i V_i (2 mu + lambda) |g_i|^2 (tb_meshless_group_stiffness). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_meshless.h"

struct tb_meshless {
  int n;
  tb_vec3 *X, *x, *v, *f; /* rest, current, velocity, internal force */
  double *vol, *mass;
  double *nn;       /* distance to the nearest other point */
  int *start, *nbr; /* CSR links: nbr[start[i] .. start[i+1]-1] */
  double *dl;       /* |d_ij| per link (the stability bound's) */
  tb_vec3 *d;       /* d_ij = A_i^-1 X_ij w_ij per link */
  tb_vec3 *dii;     /* per point: d_ii = -sum_j d_ij */
  unsigned char *active;
  unsigned *mark; /* driven this step when mark[i] == stamp */
  unsigned stamp;
  /* for the steps: the driven set of the last one (lids), its free points
   * and the live stencils (active, holding a free point), valid while the
   * set and the links stay; u = x - X for the forces */
  int *lids, nlids, *freep, nfree, *live, nlive, lvalid;
  tb_vec3 *u;
  /* the forces as gathers: each stencil's -V J sigma (P), and the links
   * transposed (point j: the stencils i holding it, t: j's entry in i's
   * list), rebuilt when the links change */
  tb_mat3 *P;
  int *rstart, *rsrc, *rpos, rcap, rvalid; /* rvalid: rebuilt before the next forces */
  double h, lambda, mu, damping, density;
  double flat;  /* a stencil with det A <= flat (tr A / 3)^3 is inactive */
  int min_nbrs; /* ... and one of fewer neighbours */
  int integrator, fvalid;
};

static int transpose(tb_meshless *m);

/* ---- uniform grid: points binned by cell, ascending index in a cell ---- */

typedef struct grid {
  tb_vec3 lo;
  double cell;
  int dim[3];
  int *start, *pt;
} grid;

static int grid_coord(const grid *g, double p, double lo, int k) {
  int c = (int)floor((p - lo) / g->cell);
  return c < 0 ? 0 : (c >= g->dim[k] ? g->dim[k] - 1 : c);
}

static int grid_cell(const grid *g, tb_vec3 p, int c[3]) {
  c[0] = grid_coord(g, p.x, g->lo.x, 0);
  c[1] = grid_coord(g, p.y, g->lo.y, 1);
  c[2] = grid_coord(g, p.z, g->lo.z, 2);
  return (c[2] * g->dim[1] + c[1]) * g->dim[0] + c[0];
}

/* Bins p[0..n-1] in cells of at least `cell`, at most 8n + 64 cells. */
static int grid_build(grid *g, int n, const tb_vec3 *p, double cell) {
  tb_vec3 lo = p[0], hi = p[0];
  for (int i = 1; i < n; i++) lo = tb_vmin(lo, p[i]), hi = tb_vmax(hi, p[i]);
  double ext[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
  for (;;) {
    double cells = 1;
    for (int k = 0; k < 3; k++) {
      g->dim[k] = (int)fmin(ext[k] / cell, 1e6) + 1;
      cells *= g->dim[k];
    }
    if (cells <= 8.0 * n + 64) break;
    cell *= 1.5;
  }
  g->lo = lo, g->cell = cell;
  int nc = g->dim[0] * g->dim[1] * g->dim[2], c[3];
  g->start = calloc((size_t)nc + 1, sizeof(int));
  g->pt = malloc(sizeof(int) * (size_t)n);
  if (!g->start || !g->pt) return -1;
  for (int i = 0; i < n; i++) g->start[grid_cell(g, p[i], c) + 1]++;
  for (int k = 0; k < nc; k++) g->start[k + 1] += g->start[k];
  for (int i = 0; i < n; i++) g->pt[g->start[grid_cell(g, p[i], c)]++] = i;
  for (int k = nc; k > 0; k--) g->start[k] = g->start[k - 1];
  g->start[0] = 0;
  return 0;
}

/* The cells of the 3 x 3 x 3 block around p's cell that lie in the grid,
 * z, then y, then x ascending; their count. */
static int grid_around(const grid *g, tb_vec3 p, int cells[27]) {
  int c[3], n = 0;
  grid_cell(g, p, c);
  for (int e = c[2] - 1; e <= c[2] + 1; e++)
    for (int b = c[1] - 1; b <= c[1] + 1; b++)
      for (int a = c[0] - 1; a <= c[0] + 1; a++)
        if (a >= 0 && b >= 0 && e >= 0 && a < g->dim[0] && b < g->dim[1] && e < g->dim[2])
          cells[n++] = (e * g->dim[1] + b) * g->dim[0] + a;
  return n;
}

static void grid_free(grid *g) {
  free(g->start), free(g->pt);
  g->start = NULL, g->pt = NULL;
}

/* Distance from p[i] to its nearest other point (searching rings of cells
 * until no closer point can remain); 0 for duplicates. */
static double nearest(const grid *g, const tb_vec3 *p, int i) {
  int c[3], maxd = g->dim[0] + g->dim[1] + g->dim[2];
  grid_cell(g, p[i], c);
  double best = INFINITY;
  for (int r = 0; r <= maxd && !(best <= (r - 1) * g->cell); r++)
    for (int e = c[2] - r < 0 ? 0 : c[2] - r; e <= c[2] + r && e < g->dim[2]; e++)
      for (int b = c[1] - r < 0 ? 0 : c[1] - r; b <= c[1] + r && b < g->dim[1]; b++)
        for (int a = c[0] - r < 0 ? 0 : c[0] - r; a <= c[0] + r && a < g->dim[0]; a++) {
          if (abs(a - c[0]) != r && abs(b - c[1]) != r && abs(e - c[2]) != r) continue;
          int k = (e * g->dim[1] + b) * g->dim[0] + a;
          for (int q = g->start[k]; q < g->start[k + 1]; q++)
            if (g->pt[q] != i) best = fmin(best, tb_dist(p[i], p[g->pt[q]]));
        }
  return best;
}

static double kernel(double r, double h) {
  double q = r / h, s = 8.0 / (M_PI * h * h * h);
  if (q <= 0.5) return s * (1 - 6 * q * q + 6 * q * q * q);
  return q < 1 ? s * 2 * (1 - q) * (1 - q) * (1 - q) : 0.0;
}

static void sort_ints(int *a, int n) {
  for (int i = 1; i < n; i++) {
    int t = a[i], j = i;
    for (; j > 0 && a[j - 1] > t; j--) a[j] = a[j - 1];
    a[j] = t;
  }
}

/* Links every pair closer than h (w > 0) that does not cross the cut. */
static int link(tb_meshless *m, tb_meshless_crosses crosses, void *ctx) {
  grid g = {0};
  int cap = 32 * m->n + 16, len = 0, cells[27];
  m->nbr = malloc(sizeof(int) * (size_t)cap);
  if (!m->nbr || grid_build(&g, m->n, m->X, m->h)) return grid_free(&g), -1;
  for (int i = 0; i < m->n; i++) {
    m->start[i] = len;
    for (int t = 0, nc = grid_around(&g, m->X[i], cells); t < nc; t++)
      for (int q = g.start[cells[t]]; q < g.start[cells[t] + 1]; q++) {
        int j = g.pt[q];
        if (j == i || kernel(tb_dist(m->X[i], m->X[j]), m->h) <= 0) continue;
        if (crosses && crosses(ctx, m->x[i], m->x[j])) continue;
        if (len == cap) {
          int *grown = realloc(m->nbr, sizeof(int) * (size_t)(cap *= 2));
          if (!grown) return grid_free(&g), -1;
          m->nbr = grown;
        }
        m->nbr[len++] = j;
      }
    sort_ints(m->nbr + m->start[i], len - m->start[i]);
  }
  m->start[m->n] = len;
  grid_free(&g);
  m->dl = malloc(sizeof(double) * (size_t)(len + 1));
  m->d = malloc(sizeof(tb_vec3) * (size_t)(len + 1));
  return m->dl && m->d ? 0 : -1;
}

/* A_i, d_ij (w_ij from the rest positions), |d_ij| and the active flag of
 * point i from its links. */
static void moment(tb_meshless *m, int i) {
  tb_mat3 A = {{{0}}};
  for (int k = m->start[i]; k < m->start[i + 1]; k++) {
    tb_vec3 e = tb_sub(m->X[m->nbr[k]], m->X[i]);
    double p[3] = {e.x, e.y, e.z}, w = kernel(tb_len(e), m->h);
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) A.m[a][b] += w * p[a] * p[b];
  }
  double tr = (A.m[0][0] + A.m[1][1] + A.m[2][2]) / 3, det = tb_m3_det(A);
  m->active[i] =
      tr > 0 && det > m->flat * tr * tr * tr && m->start[i + 1] - m->start[i] >= m->min_nbrs;
  tb_mat3 inv = tb_m3_transpose(tb_m3_cofactor(A));
  for (int k = m->start[i]; k < m->start[i + 1]; k++) {
    tb_vec3 e = tb_sub(m->X[m->nbr[k]], m->X[i]);
    double w = kernel(tb_len(e), m->h);
    m->d[k] = m->active[i] ? tb_scale(tb_m3_mulv(inv, e), w / det) : tb_v3(0, 0, 0);
    m->dl[k] = tb_len(m->d[k]);
  }
  tb_vec3 s = tb_v3(0, 0, 0);
  for (int k = m->start[i]; k < m->start[i + 1]; k++) s = tb_sub(s, m->d[k]);
  m->dii[i] = s;
}

static void moments(tb_meshless *m) {
  for (int i = 0; i < m->n; i++) moment(m, i);
}

tb_meshless *tb_meshless_create(int n, const tb_vec3 *x, const double *volume, double E, double nu,
                                double density, tb_meshless_crosses crosses, void *ctx,
                                tb_error *err) {
  if (n < 2 || !x) return tb_error_set(err, "meshless", 0, "needs at least 2 points"), NULL;
  if (!(E > 0) || !(nu > -1 && nu < 0.5) || !(density > 0))
    return tb_error_set(err, "meshless", 0, "bad material (E > 0, -1 < nu < 1/2, density > 0)"),
           NULL;
  for (int i = 0; i < n; i++)
    if (!tb_isfinite3(x[i]) || (volume && !(volume[i] > 0 && isfinite(volume[i]))))
      return tb_error_set(err, "meshless", 0, "point %d: non-finite position or bad volume", i),
             NULL;
  tb_meshless *m = calloc(1, sizeof *m);
  if (!m) return tb_error_set(err, "meshless", 0, "out of memory"), NULL;
  size_t nv = (size_t)n;
  m->n = n;
  m->X = malloc(sizeof(tb_vec3) * nv), m->x = malloc(sizeof(tb_vec3) * nv);
  m->v = calloc(nv, sizeof(tb_vec3)), m->f = calloc(nv, sizeof(tb_vec3));
  m->vol = malloc(sizeof(double) * nv), m->mass = malloc(sizeof(double) * nv);
  m->start = malloc(sizeof(int) * (nv + 1)), m->active = malloc(nv);
  m->mark = calloc(nv, sizeof(unsigned)), m->nn = malloc(sizeof(double) * nv);
  m->lids = malloc(sizeof(int) * nv), m->freep = malloc(sizeof(int) * nv);
  m->live = malloc(sizeof(int) * nv), m->u = malloc(sizeof(tb_vec3) * nv);
  m->P = malloc(sizeof(tb_mat3) * nv), m->rstart = malloc(sizeof(int) * (nv + 1));
  m->dii = malloc(sizeof(tb_vec3) * nv);
  grid g = {0};
  if (!m->X || !m->x || !m->v || !m->f || !m->vol || !m->mass || !m->start || !m->active ||
      !m->mark || !m->nn || !m->lids || !m->freep || !m->live || !m->u || !m->P || !m->rstart ||
      !m->dii)
    goto oom;
  memcpy(m->X, x, sizeof(tb_vec3) * nv), memcpy(m->x, x, sizeof(tb_vec3) * nv);
  /* Spacing s: mean nearest-neighbour distance, on a grid of ~1 point/cell. */
  tb_vec3 lo = x[0], hi = x[0];
  for (int i = 1; i < n; i++) lo = tb_vmin(lo, x[i]), hi = tb_vmax(hi, x[i]);
  tb_vec3 ext = tb_sub(hi, lo);
  double big = fmax(ext.x, fmax(ext.y, ext.z));
  if (!(big > 0)) {
    tb_meshless_destroy(m);
    return tb_error_set(err, "meshless", 0, "all points coincide"), NULL;
  }
  if (grid_build(&g, n, x, big / cbrt((double)n))) goto oom;
  double s = 0;
  for (int i = 0; i < n; i++) s += m->nn[i] = nearest(&g, x, i);
  grid_free(&g);
  s /= n;
  if (!(s > 0)) {
    tb_meshless_destroy(m);
    return tb_error_set(err, "meshless", 0, "mean point spacing is zero"), NULL;
  }
  m->h = 2 * s;
  for (int i = 0; i < n; i++) {
    m->vol[i] = volume ? volume[i] : s * s * s;
    m->mass[i] = density * m->vol[i];
  }
  tb_lame(E, nu, &m->lambda, &m->mu);
  m->density = density;
  m->flat = 1e-3;
  if (link(m, crosses, ctx)) goto oom;
  moments(m);
  return m;
oom:
  grid_free(&g);
  tb_meshless_destroy(m);
  tb_error_set(err, "meshless", 0, "out of memory");
  return NULL;
}

void tb_meshless_destroy(tb_meshless *m) {
  if (!m) return;
  free(m->X), free(m->x), free(m->v), free(m->f), free(m->vol), free(m->mass);
  free(m->start), free(m->nbr), free(m->dl), free(m->d), free(m->active), free(m->mark);
  free(m->nn), free(m->lids), free(m->freep), free(m->live), free(m->u), free(m->P);
  free(m->rstart), free(m->rsrc), free(m->rpos), free(m->dii), free(m);
}

/* The links transposed (when changed since): for point j, the stencils i
 * holding it (ascending) and j's entry in i's list. 0, or -1 out of memory. */
static int transpose(tb_meshless *m) {
  int n = m->n, len = m->start[n];
  if (m->rvalid) return 0;
  if (len > m->rcap) {
    int *a = realloc(m->rsrc, sizeof(int) * (size_t)(len + 1));
    if (a) m->rsrc = a;
    int *b = realloc(m->rpos, sizeof(int) * (size_t)(len + 1));
    if (b) m->rpos = b;
    if (!a || !b) return -1;
    m->rcap = len;
  }
  memset(m->rstart, 0, sizeof(int) * (size_t)(n + 1));
  for (int k = 0; k < len; k++) m->rstart[m->nbr[k] + 1]++;
  for (int j = 0; j < n; j++) m->rstart[j + 1] += m->rstart[j];
  for (int i = 0; i < n; i++)
    for (int k = m->start[i]; k < m->start[i + 1]; k++) {
      int at = m->rstart[m->nbr[k]]++; /* the cursor: j's start, moved on */
      m->rsrc[at] = i, m->rpos[at] = k;
    }
  for (int j = n; j > 0; j--) m->rstart[j] = m->rstart[j - 1];
  m->rstart[0] = 0;
  m->rvalid = 1;
  return 0;
}

/* Keeps the links with crosses(x_i, x_j) == 0 (crosses NULL: all) and
 * keep(i, j) != 0 (keep NULL: all), in place; changed stencils anew. */
static void filter(tb_meshless *m, tb_meshless_crosses crosses, tb_meshless_keep keep, void *ctx) {
  int len = 0;
  for (int i = 0; i < m->n; i++) {
    int b = m->start[i], e = m->start[i + 1], at = len;
    m->start[i] = len;
    for (int k = b; k < e; k++) {
      int j = m->nbr[k];
      if ((crosses && crosses(ctx, m->x[i], m->x[j])) || (keep && !keep(ctx, i, j))) continue;
      m->nbr[len] = j, m->dl[len] = m->dl[k], m->d[len++] = m->d[k];
    }
    if (len - at < e - b) m->active[i] = 2; /* lost links: its moments anew, below */
  }
  m->start[m->n] = len;
  for (int i = 0; i < m->n; i++)
    if (m->active[i] == 2) moment(m, i);
  m->fvalid = 0, m->lvalid = 0, m->rvalid = 0;
}

int tb_meshless_relink(tb_meshless *m, tb_meshless_crosses crosses, void *ctx, tb_error *err) {
  (void)err; /* compacts in place: cannot fail */
  filter(m, crosses, NULL, ctx);
  return 0;
}

void tb_meshless_unlink(tb_meshless *m, tb_meshless_keep keep, void *ctx) {
  filter(m, NULL, keep, ctx);
}

/* ---- incremental insertion ---- */

typedef struct pairs {
  int n, cap;
  int (*p)[2]; /* (owner, neighbour) */
} pairs;

static int pairs_push(pairs *q, int owner, int nb) {
  if (q->n == q->cap) {
    int cap = q->cap ? 2 * q->cap : 256;
    int(*t)[2] = realloc(q->p, sizeof *t * (size_t)cap);
    if (!t) return -1;
    q->p = t, q->cap = cap;
  }
  q->p[q->n][0] = owner, q->p[q->n++][1] = nb;
  return 0;
}

/* Grows every per-point array to n points (m->n unchanged); 0 or -1. */
static int grow(tb_meshless *m, int n) {
  size_t N = (size_t)n;
  m->lvalid = 0;
  tb_vec3 **v3[] = {&m->X, &m->x, &m->v, &m->f, &m->u, &m->dii};
  for (int a = 0; a < 6; a++) {
    tb_vec3 *t = realloc(*v3[a], sizeof(tb_vec3) * N);
    if (!t) return -1;
    *v3[a] = t;
  }
  double **d1[] = {&m->vol, &m->mass, &m->nn};
  for (int a = 0; a < 3; a++) {
    double *t = realloc(*d1[a], sizeof(double) * N);
    if (!t) return -1;
    *d1[a] = t;
  }
  int *st = realloc(m->start, sizeof(int) * (N + 1));
  if (st) m->start = st;
  unsigned char *ac = realloc(m->active, N);
  if (ac) m->active = ac;
  unsigned *mk = realloc(m->mark, sizeof(unsigned) * N);
  if (mk) m->mark = mk;
  tb_mat3 *P = realloc(m->P, sizeof(tb_mat3) * N);
  if (!P) return -1;
  m->P = P;
  int *rs = realloc(m->rstart, sizeof(int) * (N + 1));
  if (!rs) return -1;
  m->rstart = rs;
  int **i1[] = {&m->lids, &m->freep, &m->live};
  for (int a = 0; a < 3; a++) {
    int *t = realloc(*i1[a], sizeof(int) * N);
    if (!t) return -1;
    *i1[a] = t;
  }
  return st && ac && mk ? 0 : -1;
}

/* The new links (see tb_meshless_add): pairs (owner, neighbour) for every
 * new point j and each point q within h: j's own entry, and q's when q is
 * old; j ascending, so an old point's new entries come ascending. */
static int new_links(tb_meshless *m, int n0, int n, tb_meshless_crosses crosses, void *ctx,
                     pairs *out) {
  grid g = {0};
  int cells[27];
  if (grid_build(&g, n, m->X, m->h)) return grid_free(&g), -1;
  for (int j = n0; j < n; j++) m->nn[j] = nearest(&g, m->X, j);
  for (int j = n0; j < n; j++)
    for (int t = 0, nc = grid_around(&g, m->X[j], cells); t < nc; t++)
      for (int k = g.start[cells[t]]; k < g.start[cells[t] + 1]; k++) {
        int q = g.pt[k];
        double r = tb_dist(m->X[j], m->X[q]);
        if (q == j || kernel(r, m->h) <= 0) continue;
        m->nn[q] = fmin(m->nn[q], r);
        if ((!crosses || !crosses(ctx, m->x[j], m->x[q])) && pairs_push(out, j, q))
          return grid_free(&g), -1;
        if (q < n0 && (!crosses || !crosses(ctx, m->x[q], m->x[j])) && pairs_push(out, q, j))
          return grid_free(&g), -1;
      }
  grid_free(&g);
  return 0;
}

int tb_meshless_add(tb_meshless *m, int k, const tb_vec3 *X, const tb_vec3 *x, const tb_vec3 *v,
                    const double *volume, tb_meshless_crosses crosses, void *ctx, tb_error *err) {
  if (k < 0 || (k > 0 && (!X || !x)))
    return tb_error_set(err, "meshless", 0, "add: bad count or missing positions");
  if (k > INT_MAX / 64 - m->n) return tb_error_set(err, "meshless", 0, "add: too many points");
  for (int i = 0; i < k; i++)
    if (!tb_isfinite3(X[i]) || !tb_isfinite3(x[i]) || (v && !tb_isfinite3(v[i])) ||
        (volume && !(volume[i] > 0 && isfinite(volume[i]))))
      return tb_error_set(err, "meshless", 0, "added point %d: non-finite or bad volume", i);
  if (k == 0) return 0;
  int n0 = m->n, n = n0 + k, *cnt = NULL, *nbr = NULL, *ost = NULL;
  double *dl = NULL, s = m->h / 2;
  tb_vec3 *d = NULL;
  pairs q = {0};
  if (grow(m, n)) goto oom;
  for (int i = 0; i < k; i++) {
    int p = n0 + i;
    m->X[p] = X[i], m->x[p] = x[i], m->v[p] = v ? v[i] : tb_v3(0, 0, 0), m->f[p] = tb_v3(0, 0, 0);
    m->vol[p] = volume ? volume[i] : s * s * s, m->mass[p] = m->density * m->vol[p];
    m->mark[p] = 0, m->active[p] = 0;
  }
  cnt = calloc((size_t)n + 1, sizeof(int)), ost = malloc(sizeof(int) * ((size_t)n0 + 1));
  if (!cnt || !ost || new_links(m, n0, n, crosses, ctx, &q)) goto oom;
  memcpy(ost, m->start, sizeof(int) * ((size_t)n0 + 1));
  /* the new CSR: an old point's list, then its new entries (all ascending) */
  for (int e = 0; e < q.n; e++) cnt[q.p[e][0] + 1]++;
  int len = ost[n0] + q.n;
  nbr = malloc(sizeof(int) * (size_t)(len + 1)), dl = malloc(sizeof(double) * (size_t)(len + 1));
  d = malloc(sizeof(tb_vec3) * (size_t)(len + 1));
  if (!nbr || !dl || !d) goto oom;
  int *fill = cnt; /* reused: fill[i] = where i's next new entry goes */
  for (int i = 0, at = 0; i < n; i++) {
    int b = i < n0 ? ost[i] : 0, e = i < n0 ? ost[i + 1] : 0, extra = cnt[i + 1];
    memcpy(nbr + at, m->nbr + b, sizeof(int) * (size_t)(e - b));
    memcpy(dl + at, m->dl + b, sizeof(double) * (size_t)(e - b));
    memcpy(d + at, m->d + b, sizeof(tb_vec3) * (size_t)(e - b));
    m->start[i] = at, fill[i] = at + (e - b), at += e - b + extra;
    m->start[i + 1] = at;
  }
  for (int e = 0; e < q.n; e++) nbr[fill[q.p[e][0]]++] = q.p[e][1];
  free(m->nbr), free(m->dl), free(m->d);
  m->nbr = nbr, m->dl = dl, m->d = d, m->n = n;
  /* stencils that changed: the new points', and the old ones that gained */
  for (int e = 0; e < q.n; e++) m->active[q.p[e][0]] = 2;
  for (int i = n0; i < n; i++) sort_ints(m->nbr + m->start[i], m->start[i + 1] - m->start[i]);
  for (int i = 0; i < n; i++)
    if (i >= n0 || m->active[i] == 2) moment(m, i);
  free(cnt), free(ost), free(q.p);
  m->fvalid = 0, m->lvalid = 0, m->rvalid = 0;
  return 0;
oom:
  free(cnt), free(ost), free(q.p), free(nbr), free(dl), free(d);
  return tb_error_set(err, "meshless", 0, "out of memory");
}

/* ---- elasticity ---- */

tb_mat3 tb_meshless_jacobian(const tb_meshless *m, int i) {
  tb_mat3 J = tb_m3_identity();
  if (!m->active[i]) return J;
  tb_vec3 ui = tb_sub(m->x[i], m->X[i]);
  for (int k = m->start[i]; k < m->start[i + 1]; k++) {
    int j = m->nbr[k];
    tb_vec3 du = tb_sub(tb_sub(m->x[j], m->X[j]), ui), d = m->d[k];
    double p[3] = {du.x, du.y, du.z}, q[3] = {d.x, d.y, d.z};
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) J.m[a][b] += p[a] * q[b];
  }
  return J;
}

tb_mat3 tb_meshless_strain(const tb_meshless *m, int i) {
  tb_mat3 J = tb_meshless_jacobian(m, i), e = tb_m3_mul(tb_m3_transpose(J), J);
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) e.m[a][b] = 0.5 * (e.m[a][b] - (a == b));
  return e;
}

static tb_mat3 stress(const tb_meshless *m, tb_mat3 e) {
  double tr = e.m[0][0] + e.m[1][1] + e.m[2][2];
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) e.m[a][b] = 2 * m->mu * e.m[a][b] + (a == b) * m->lambda * tr;
  return e;
}

/* Stencil i's P_i = -V_i J_i sigma_i (m->u = x - X already set): its
 * force on neighbour j is P_i d_ij, on i itself P_i d_ii. */
static void stencil_P(const tb_meshless *m, int i) {
  const tb_vec3 *u = m->u, *d = m->d;
  const int *nbr = m->nbr;
  tb_vec3 ui = u[i];
  double j00 = 1, j01 = 0, j02 = 0, j10 = 0, j11 = 1, j12 = 0, j20 = 0, j21 = 0, j22 = 1;
  for (int k = m->start[i]; k < m->start[i + 1]; k++) { /* J = I + sum_j (u_j - u_i) d_ij^T */
    tb_vec3 du = tb_sub(u[nbr[k]], ui), q = d[k];
    j00 += du.x * q.x, j01 += du.x * q.y, j02 += du.x * q.z;
    j10 += du.y * q.x, j11 += du.y * q.y, j12 += du.y * q.z;
    j20 += du.z * q.x, j21 += du.z * q.y, j22 += du.z * q.z;
  }
  tb_mat3 J = {{{j00, j01, j02}, {j10, j11, j12}, {j20, j21, j22}}};
  tb_mat3 e = tb_m3_mul(tb_m3_transpose(J), J);
  for (int a = 0; a < 3; a++) e.m[a][a] -= 1;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) e.m[a][b] *= 0.5;
  tb_mat3 P = tb_m3_mul(J, stress(m, e));
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++) P.m[a][b] *= -m->vol[i];
  m->P[i] = P;
}

/* Point j's force, gathered: its own stencil's P_j d_jj and P_i d_ij from each active stencil i
 * holding it (the transposed links, ascending i): each point's sum in a fixed order, whoever
 * computes it. */
static tb_vec3 gather(const tb_meshless *m, int j) {
  tb_vec3 f = tb_v3(0, 0, 0);
  if (m->active[j]) f = tb_m3_mulv(m->P[j], m->dii[j]);
  for (int r = m->rstart[j]; r < m->rstart[j + 1]; r++) {
    int i = m->rsrc[r];
    if (m->active[i]) f = tb_add(f, tb_m3_mulv(m->P[i], m->d[m->rpos[r]]));
  }
  return f;
}

/* The forces on the npts points of pts (NULL: all) from the nlist stencils
 * of list (NULL: every active one), which must hold every active stencil
 * holding those points (the live list does for the free points). Threads
 * split both loops into fixed parts; each P_i and f_j is computed whole by
 * one thread in a fixed order, so the count changes nothing. */
static int forces(tb_meshless *m, tb_vec3 *f, int nlist, const int *list, int npts,
                  const int *pts) {
  int n = m->n, ns = list ? nlist : n, np = pts ? npts : n;
  if (transpose(m)) return -1;
#pragma omp parallel if (ns > 256)
  {
#pragma omp for schedule(static)
    for (int i = 0; i < n; i++) m->u[i] = tb_sub(m->x[i], m->X[i]);
#pragma omp for schedule(static)
    for (int k = 0; k < ns; k++) {
      int i = list ? list[k] : k;
      if (m->active[i]) stencil_P(m, i);
    }
#pragma omp for schedule(static)
    for (int k = 0; k < np; k++) {
      int j = pts ? pts[k] : k;
      f[j] = gather(m, j);
    }
  }
  return 0;
}

int tb_meshless_forces(tb_meshless *m, tb_vec3 *f) { return forces(m, f, 0, NULL, 0, NULL); }

double tb_meshless_energy(const tb_meshless *m) {
  double U = 0;
  for (int i = 0; i < m->n; i++) {
    if (!m->active[i]) continue;
    tb_mat3 e = tb_meshless_strain(m, i), s = stress(m, e);
    double es = 0;
    for (int a = 0; a < 3; a++)
      for (int b = 0; b < 3; b++) es += e.m[a][b] * s.m[a][b];
    U += 0.5 * m->vol[i] * es;
  }
  return U;
}

double tb_meshless_kinetic(const tb_meshless *m) {
  double K = 0;
  for (int i = 0; i < m->n; i++) K += 0.5 * m->mass[i] * tb_dot(m->v[i], m->v[i]);
  return K;
}

/* ---- stability bound and group stiffness (see the head) ---- */

/* The largest eigenvalue of a symmetric 3x3 matrix (Smith 1961, "Eigenvalues
 * of a symmetric 3 x 3 matrix": a = q I + p B, det B / 2 = cos 3 phi), raised
 * by 1e-9 of its scale so that rounding never puts it below the true one. */
static double sym3_max_eig(const double a[6]) { /* xx yy zz xy xz yz */
  double q = (a[0] + a[1] + a[2]) / 3, off = a[3] * a[3] + a[4] * a[4] + a[5] * a[5];
  double b0 = a[0] - q, b1 = a[1] - q, b2 = a[2] - q;
  double p = sqrt((b0 * b0 + b1 * b1 + b2 * b2 + 2 * off) / 6);
  double scale = fabs(q) + 3 * p;
  if (!(p > 1e-15 * scale)) return q + 1e-9 * scale;
  b0 /= p, b1 /= p, b2 /= p;
  double c3 = a[3] / p, c4 = a[4] / p, c5 = a[5] / p;
  double r = (b0 * (b1 * b2 - c5 * c5) - c3 * (c3 * b2 - c5 * c4) + c4 * (c3 * c5 - b1 * c4)) / 2;
  double phi = r <= -1 ? M_PI / 3 : r >= 1 ? 0 : acos(r) / 3;
  return q + 2 * p * cos(phi) + 1e-9 * scale;
}

/* Stencil i's stiffening at the current positions (see the head):
 * sigma_max(J)^2 + max(lambda_max(S), 0) / (2 mu), 1 at rest. */
static double stiffening(const tb_meshless *m, int i) {
  tb_mat3 e = tb_meshless_strain(m, i), S = stress(m, e);
  double ev[6] = {e.m[0][0], e.m[1][1], e.m[2][2], e.m[0][1], e.m[0][2], e.m[1][2]};
  double sv[6] = {S.m[0][0], S.m[1][1], S.m[2][2], S.m[0][1], S.m[0][2], S.m[1][2]};
  return fmax(1 + 2 * sym3_max_eig(ev), 0) + fmax(sym3_max_eig(sv), 0) / (2 * m->mu);
}

void tb_meshless_rest_bounds(const tb_meshless *m, const unsigned char *driven, double *row,
                             double *bound) {
  double kappa = 2 * m->mu + 3 * m->lambda;
  /* row[b] = kappa T_b (see the head) */
  memset(row, 0, sizeof(double) * (size_t)m->n);
  for (int i = 0; i < m->n; i++) {
    if (!m->active[i]) continue;
    double dii = tb_len(m->dii[i]), sum = driven && driven[i] ? 0 : dii;
    for (int k = m->start[i]; k < m->start[i + 1]; k++)
      if (!driven || !driven[m->nbr[k]]) sum += m->dl[k];
    double a = m->vol[i] * kappa * sum;
    row[i] += a * dii;
    for (int k = m->start[i]; k < m->start[i + 1]; k++) row[m->nbr[k]] += a * m->dl[k];
  }
  for (int i = 0; i < m->n; i++) {
    bound[i] = 0;
    if (!m->active[i]) continue;
    /* g = sum over free b of d_ib d_ib^T / |d_ib| row[b] / m_b */
    double g[6] = {0, 0, 0, 0, 0, 0}, S = 0;
    for (int k = m->start[i] - 1; k < m->start[i + 1]; k++) {
      int b = k < m->start[i] ? i : m->nbr[k];
      if (driven && driven[b]) continue;
      tb_vec3 d = k < m->start[i] ? m->dii[i] : m->d[k];
      double len = k < m->start[i] ? tb_len(d) : m->dl[k];
      if (!(len > 0)) continue;
      double s = row[b] / (m->mass[b] * len);
      S += len;
      g[0] += s * d.x * d.x, g[1] += s * d.y * d.y, g[2] += s * d.z * d.z;
      g[3] += s * d.x * d.y, g[4] += s * d.x * d.z, g[5] += s * d.y * d.z;
    }
    if (S > 0) /* row holds kappa: G_i = g / (kappa V_i S_i) */
      bound[i] = (2 * m->mu * sym3_max_eig(g) + m->lambda * (g[0] + g[1] + g[2])) / (kappa * S);
  }
}

double tb_meshless_frequency_at(const tb_meshless *m, const double *bound) {
  double w2 = 0; /* a maximum: the same for any thread count */
#pragma omp parallel for schedule(static) reduction(max : w2) if (m->n > 256)
  for (int i = 0; i < m->n; i++)
    if (bound[i] > 0) w2 = fmax(w2, stiffening(m, i) * bound[i]);
  return sqrt(w2);
}

double tb_meshless_frequency_bound(const tb_meshless *m, const unsigned char *driven, double *row) {
  double *bound = row + m->n;
  tb_meshless_rest_bounds(m, driven, row, bound);
  return tb_meshless_frequency_at(m, bound);
}

void tb_meshless_group_stiffness(const tb_meshless *m, const int *group, int ngroups, double *k,
                                 tb_vec3 *scratch) {
  double kappa = 2 * m->mu + m->lambda; /* see the head */
  for (int g = 0; g < ngroups; g++) k[g] = 0, scratch[g] = tb_v3(0, 0, 0);
  for (int i = 0; i < m->n; i++) {
    if (!m->active[i]) continue;
    int k0 = m->start[i] - 1, k1 = m->start[i + 1]; /* k0: i itself */
    /* g_i per group in the stencil, summed in stencil order; each group's
     * term added at its first member (NaN marks it added), then cleared */
    for (int q = k0; q < k1; q++) {
      int g = group[q == k0 ? i : m->nbr[q]];
      if (g >= 0 && g < ngroups) scratch[g] = tb_add(scratch[g], q == k0 ? m->dii[i] : m->d[q]);
    }
    for (int q = k0; q < k1; q++) {
      int g = group[q == k0 ? i : m->nbr[q]];
      if (g < 0 || g >= ngroups || isnan(scratch[g].x)) continue;
      k[g] += m->vol[i] * kappa * tb_dot(scratch[g], scratch[g]);
      scratch[g].x = NAN;
    }
    for (int q = k0; q < k1; q++) {
      int g = group[q == k0 ? i : m->nbr[q]];
      if (g >= 0 && g < ngroups) scratch[g] = tb_v3(0, 0, 0);
    }
  }
}

/* ---- time stepping ---- */

/* The free points and the live stencils for the driven set marked with the
 * current stamp (ids, nfixed), kept for the next steps when it fits. */
static void live_lists(tb_meshless *m, int nfixed, const int *ids) {
  unsigned st = m->stamp;
  m->nfree = m->nlive = 0;
  for (int i = 0; i < m->n; i++) {
    if (m->mark[i] != st) m->freep[m->nfree++] = i;
    if (!m->active[i]) continue;
    int k = m->start[i];
    if (m->mark[i] == st)
      while (k < m->start[i + 1] && m->mark[m->nbr[k]] == st) k++;
    if (m->mark[i] != st || k < m->start[i + 1]) m->live[m->nlive++] = i;
  }
  m->lvalid = nfixed <= m->n, m->nlids = nfixed;
  if (m->lvalid && nfixed > 0) memcpy(m->lids, ids, sizeof(int) * (size_t)nfixed);
}

int tb_meshless_step(tb_meshless *m, double dt, tb_vec3 gravity, int nfixed, const int *ids,
                     const tb_vec3 *fixed_x, tb_error *err) {
  if (!(dt > 0)) return tb_error_set(err, "meshless", 0, "dt must be positive");
  /* the same driven set as the last step: its marks, lists and check stand */
  int same = m->lvalid && nfixed == m->nlids &&
             (nfixed == 0 || !memcmp(ids, m->lids, sizeof(int) * (size_t)nfixed));
  if (!same) {
    for (int k = 0; k < nfixed; k++)
      if (ids[k] < 0 || ids[k] >= m->n)
        return tb_error_set(err, "meshless", 0, "driven point %d out of range", ids[k]);
    if (++m->stamp == 0) {
      memset(m->mark, 0, sizeof(unsigned) * (size_t)m->n), m->stamp = 1, m->fvalid = 0;
    }
    for (int k = 0; k < nfixed; k++) m->mark[ids[k]] = m->stamp;
    /* the last step's forces left out stencils driven then: valid unless a
     * point driven then is free now */
    for (int i = 0; i < m->n && m->fvalid; i++)
      if (m->stamp > 1 && m->mark[i] == m->stamp - 1) m->fvalid = 0;
    live_lists(m, nfixed, ids);
  }
  int verlet = m->integrator == TB_MESHLESS_ALTERNATING, nf = m->nfree, bad = -1;
  const int *fr = m->freep;
  double damp = exp(-m->damping * dt), kick = verlet ? 0.5 * dt : dt, inv = 1 / dt;
  if (!m->fvalid && forces(m, m->f, m->nlive, m->live, m->nfree, m->freep))
    return tb_error_set(err, "meshless", 0, "out of memory");
  for (int k = 0; k < nf; k++) {
    int i = fr[k];
    m->v[i] = tb_madd(tb_madd(m->v[i], kick / m->mass[i], m->f[i]), kick, gravity);
    if (!verlet) m->v[i] = tb_scale(m->v[i], damp);
    m->x[i] = tb_madd(m->x[i], dt, m->v[i]);
  }
  for (int k = 0; k < nfixed; k++) {
    int i = ids[k];
    m->v[i] = tb_scale(tb_sub(fixed_x[k], m->x[i]), inv);
    m->x[i] = fixed_x[k];
    if (bad < 0 && !tb_isfinite3(m->x[i])) bad = i;
  }
  m->fvalid = 0;
  if (verlet) {
    if (forces(m, m->f, m->nlive, m->live, m->nfree, m->freep))
      return tb_error_set(err, "meshless", 0, "out of memory");
    m->fvalid = 1;
    for (int k = 0; k < nf; k++) {
      int i = fr[k];
      m->v[i] = tb_madd(tb_madd(m->v[i], kick / m->mass[i], m->f[i]), kick, gravity);
      m->v[i] = tb_scale(m->v[i], damp);
    }
  }
  for (int k = 0; k < nf && bad < 0; k++)
    if (!tb_isfinite3(m->x[fr[k]]) || !tb_isfinite3(m->v[fr[k]])) bad = fr[k];
  if (bad >= 0)
    return tb_error_set(err, "meshless", 0, "point %d: non-finite state (dt too large?)", bad);
  return 0;
}

/* ---- settings and accessors ---- */

void tb_meshless_set_damping(tb_meshless *m, double c) { m->damping = c > 0 ? c : 0; }
void tb_meshless_set_flatness(tb_meshless *m, double c) {
  m->flat = c > 0 ? fmin(c, 0.5) : 0;
  moments(m);
  m->fvalid = 0, m->lvalid = 0;
}
void tb_meshless_set_min_neighbours(tb_meshless *m, int k) {
  m->min_nbrs = k > 0 ? k : 0;
  moments(m);
  m->fvalid = 0, m->lvalid = 0;
}
void tb_meshless_set_velocities(tb_meshless *m, const tb_vec3 *v) {
  memcpy(m->v, v, sizeof(tb_vec3) * (size_t)m->n);
}
void tb_meshless_set_integrator(tb_meshless *m, int integrator) {
  m->integrator = integrator == TB_MESHLESS_SYMPLECTIC_EULER ? integrator : TB_MESHLESS_ALTERNATING;
}
void tb_meshless_set_positions(tb_meshless *m, const tb_vec3 *x) {
  memcpy(m->x, x, sizeof(tb_vec3) * (size_t)m->n);
  m->fvalid = 0;
}
int tb_meshless_count(const tb_meshless *m) { return m->n; }
const tb_vec3 *tb_meshless_positions(const tb_meshless *m) { return m->x; }
const tb_vec3 *tb_meshless_velocities(const tb_meshless *m) { return m->v; }
const tb_vec3 *tb_meshless_rest(const tb_meshless *m) { return m->X; }
double tb_meshless_support(const tb_meshless *m) { return m->h; }
double tb_meshless_spacing(const tb_meshless *m) {
  double s = 0;
  for (int i = 0; i < m->n; i++) s += m->nn[i];
  return s / m->n;
}
double tb_meshless_mass(const tb_meshless *m, int i) { return m->mass[i]; }
int tb_meshless_neighbours(const tb_meshless *m, int i, const int **list) {
  if (list) *list = m->nbr + m->start[i];
  return m->start[i + 1] - m->start[i];
}
int tb_meshless_active(const tb_meshless *m, int i) { return m->active[i]; }
