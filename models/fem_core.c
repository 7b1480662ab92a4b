/* What the linear and the corotational tetrahedral FEM share (thesis §3.3.2,
 * SPEC §2.2; Müller & Gross 2004 for the warped stiffness):
 *  - element stiffness of a linear tet, K_e = V B^T D B, written per node
 *    pair as V (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I) with g_a
 *    the shape-function gradients (isotropic small strain, Lamé lambda, mu);
 *  - lumped masses, or the consistent mass rho V / 20 (1 + delta_ab) I;
 *  - a node-block pattern (3x3 blocks) and, fixed at create, the CHOLMOD
 *    matrix A = alpha M + beta K (upper triangle) over all 3 nv dofs, analysed
 *    once. Prescribed (Dirichlet) dofs are eliminated: their columns move to
 *    the right-hand side and their rows/columns of A become identity, so A
 *    keeps one pattern and its factor is the factor of the free-free block;
 *  - one step of implicit (backward) Euler with Rayleigh damping C = a M + b K:
 *    (M + dt C + dt^2 K) v+ = M v + dt (f_ext + M g + f_el), x+ = x + dt v+,
 *    or the quasi-static solve K d = f_ext + M g + f_el, x+ = x + d.
 * Solver: supernodal L L^T with METIS ordering for both models, BLAS on one
 * thread. Measured on the liver (1119 nodes, 4545 tets, 3357 dofs, 102
 * nodes fixed; L has ~423k entries with AMD or METIS) on a 2-core machine,
 * steps/s as re-solve (fem) / refactor every step (fem, prescribed set
 * changing) / fem-corot:
 *   supernodal METIS  ~2550 / ~60 / ~45   <- chosen
 *   supernodal AMD    ~2600 / ~50 / ~40
 *   simplicial AMD    ~2500 / ~23 / ~21   (LDL^T, no BLAS)
 * Re-solves cost the same either way (the solve reads L once forward and
 * once back), the numeric factorisation is 2-3x faster supernodal (BLAS-3).
 * With OpenBLAS's default two threads the supernodal re-solve fell to
 * 250-800 steps/s on a loaded machine and the results' last bits depended
 * on the thread count; the BLAS calls here are small, so tb_fem_create sets
 * OpenBLAS to one thread (deterministic, and a single-core benchmark).
 * Re-solves use cholmod_solve2 with persistent X/Y/E, so a step that does
 * not refactor allocates nothing. */
#include <cblas.h> /* OpenBLAS: openblas_set_num_threads */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fem_priv.h"
#include "tb_fem.h"

/* Overridable for measurements (-D...). */
#ifndef TB_FEM_LINEAR_SUPERNODAL
#define TB_FEM_LINEAR_SUPERNODAL 1
#endif
#ifndef TB_FEM_LINEAR_ORDERING
#define TB_FEM_LINEAR_ORDERING CHOLMOD_METIS
#endif
#ifndef TB_FEM_COROT_SUPERNODAL
#define TB_FEM_COROT_SUPERNODAL 1
#endif
#ifndef TB_FEM_COROT_ORDERING
#define TB_FEM_COROT_ORDERING CHOLMOD_METIS
#endif

/* A pivot below this fraction of its diagonal entry is a singular matrix
 * (rigid modes left free) that rounding made slightly positive or negative;
 * CHOLMOD's simplicial L D L^T does not report a negative D as
 * CHOLMOD_NOT_POSDEF, so every pivot is checked after each factorisation. */
#define TB_FEM_PIVOT_TOL 1e-12

extern const tb_model_class tb_model_fem, tb_model_fem_corot;

/* CHOLMOD reports through Common->status; nothing is printed. */
static void quiet_handler(int status, const char *file, int line, const char *msg) {
  (void)status, (void)file, (void)line, (void)msg;
}

void tb_fem_element_k(tb_mat3 dm_inv, double vol, double lambda, double mu, double *k) {
  tb_vec3 g[4];
  for (int a = 1; a < 4; a++)
    g[a] = tb_v3(dm_inv.m[a - 1][0], dm_inv.m[a - 1][1], dm_inv.m[a - 1][2]);
  g[0] = tb_scale(tb_add(tb_add(g[1], g[2]), g[3]), -1.0);
  for (int a = 0; a < 4; a++)
    for (int b = 0; b < 4; b++) {
      double ga[3] = {g[a].x, g[a].y, g[a].z}, gb[3] = {g[b].x, g[b].y, g[b].z};
      double d = ga[0] * gb[0] + ga[1] * gb[1] + ga[2] * gb[2];
      double *blk = k + 9 * (4 * a + b);
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          blk[3 * i + j] =
              vol * (lambda * (ga[i] * gb[j]) + mu * (ga[j] * gb[i]) + (i == j ? mu * d : 0.0));
    }
}

/* V g_a . g_b, g the shape-function gradients (rows of dm_inv, g_0 = -sum). */
static double laplacian_entry(tb_mat3 dm_inv, double vol, int a, int b) {
  tb_vec3 g[4];
  for (int c = 1; c < 4; c++)
    g[c] = tb_v3(dm_inv.m[c - 1][0], dm_inv.m[c - 1][1], dm_inv.m[c - 1][2]);
  g[0] = tb_scale(tb_add(tb_add(g[1], g[2]), g[3]), -1.0);
  return vol * tb_dot(g[a], g[b]);
}

void tb_fem_laplacian(tb_fem *f) {
  memset(f->lb, 0, sizeof(double) * (size_t)f->nblk);
  for (int t = 0; t < f->ntet; t++)
    for (int ab = 0; ab < 16; ab++)
      f->lb[f->tet_blk[16 * t + ab]] += laplacian_entry(f->dm_inv[t], f->vol[t], ab / 4, ab % 4);
}

void tb_fem_add_element(tb_fem *f, int t, const double *k) {
  const int *blk = f->tet_blk + 16 * t;
  for (int ab = 0; ab < 16; ab++) {
    double *dst = f->kb + 9 * blk[ab];
    const double *src = k + 9 * ab;
    for (int q = 0; q < 9; q++) dst[q] += src[q];
  }
}

void tb_fem_kmul(const tb_fem *f, const tb_vec3 *u, tb_vec3 *y) {
  for (int i = 0; i < f->nv; i++) {
    double s0 = 0, s1 = 0, s2 = 0;
    for (int p = f->row[i]; p < f->row[i + 1]; p++) {
      const double *k = f->kb + 9 * p;
      tb_vec3 w = u[f->col[p]];
      s0 += k[0] * w.x + k[1] * w.y + k[2] * w.z;
      s1 += k[3] * w.x + k[4] * w.y + k[5] * w.z;
      s2 += k[6] * w.x + k[7] * w.y + k[8] * w.z;
    }
    y[i] = tb_v3(s0, s1, s2);
  }
}

double tb_fem_kinetic(const tb_fem *f) {
  double e = 0;
  for (int i = 0; i < f->nv; i++) {
    tb_vec3 s = tb_v3(0, 0, 0);
    for (int p = f->row[i]; p < f->row[i + 1]; p++)
      if (f->mb[p] != 0) s = tb_madd(s, f->mb[p], f->v[f->col[p]]);
    e += tb_dot(f->v[i], s);
  }
  return 0.5 * e;
}

/* ---- create ---- */

static int cmp_int(const void *a, const void *b) {
  int x = *(const int *)a, y = *(const int *)b;
  return (x > y) - (x < y);
}

static int find_block(const tb_fem *f, int n, int m) {
  int lo = f->row[n], hi = f->row[n + 1] - 1;
  while (lo <= hi) {
    int mid = (lo + hi) / 2;
    if (f->col[mid] == m) return mid;
    if (f->col[mid] < m)
      lo = mid + 1;
    else
      hi = mid - 1;
  }
  return -1;
}

/* Node adjacency through the tet edges, each row ascending with the node itself. */
static int build_blocks(tb_fem *f, const tb_mesh *mesh, tb_error *err) {
  int *edges = NULL;
  int ne = tb_mesh_edges(mesh, &edges);
  if (ne < 0) return tb_error_set(err, f->name, 0, "out of memory");
  int nv = f->nv;
  f->row = calloc((size_t)nv + 1, sizeof(int));
  f->diag = malloc(sizeof(int) * (size_t)nv);
  int *fill = malloc(sizeof(int) * (size_t)nv);
  if (!f->row || !f->diag || !fill) goto oom;
  for (int n = 0; n < nv; n++) f->row[n + 1] = 1;
  for (int e = 0; e < ne; e++) f->row[edges[2 * e] + 1]++, f->row[edges[2 * e + 1] + 1]++;
  for (int n = 0; n < nv; n++) f->row[n + 1] += f->row[n];
  f->nblk = f->row[nv];
  f->col = malloc(sizeof(int) * (size_t)f->nblk);
  f->kb = calloc((size_t)f->nblk * 9, sizeof(double));
  f->mb = calloc((size_t)f->nblk, sizeof(double));
  if (!f->col || !f->kb || !f->mb) goto oom;
  for (int n = 0; n < nv; n++) f->col[f->row[n]] = n, fill[n] = f->row[n] + 1;
  for (int e = 0; e < ne; e++) {
    int a = edges[2 * e], b = edges[2 * e + 1];
    f->col[fill[a]++] = b, f->col[fill[b]++] = a;
  }
  for (int n = 0; n < nv; n++) {
    qsort(f->col + f->row[n], (size_t)(f->row[n + 1] - f->row[n]), sizeof(int), cmp_int);
    f->diag[n] = find_block(f, n, n);
  }
  free(edges), free(fill);
  return 0;
oom:
  free(edges), free(fill);
  return tb_error_set(err, f->name, 0, "out of memory");
}

/* The upper triangle of A over dofs 3n + c, and where each entry comes from. */
static int build_matrix(tb_fem *f, tb_error *err) {
  int nv = f->nv, n3 = 3 * nv;
  size_t nnz = 0;
  for (int n = 0; n < nv; n++) nnz += 9 * (size_t)(f->diag[n] - f->row[n]) + 6;
  if (nnz > 2000000000u) return tb_error_set(err, f->name, 0, "mesh too large");
  f->A = cholmod_allocate_sparse((size_t)n3, (size_t)n3, nnz, 1, 1, 1, CHOLMOD_REAL, &f->cc);
  f->a_blk = malloc(sizeof(int) * nnz);
  f->a_mass = malloc(sizeof(int) * nnz);
  f->a_diag = malloc(sizeof(int) * (size_t)n3);
  if (!f->A || !f->a_blk || !f->a_mass || !f->a_diag)
    return tb_error_set(err, f->name, 0, "out of memory");
  int *Ap = f->A->p, *Ai = f->A->i, p = 0;
  for (int n = 0; n < nv; n++)
    for (int c = 0; c < 3; c++) {
      Ap[3 * n + c] = p;
      for (int q = f->row[n]; q <= f->diag[n]; q++) { /* blocks (n, m), m <= n */
        int m = f->col[q];
        for (int r = 0; r < 3; r++) {
          if (m == n && r > c) break;
          Ai[p] = 3 * m + r;
          /* K(3m+r, 3n+c) = block(n,m)[c][r] = block(m,n)[r][c] (fem-corot
           * keeps the blocks (n, m >= n) only) */
          f->a_blk[p] = f->corot ? 9 * f->blk_tr[q] + 3 * r + c : 9 * q + 3 * c + r;
          f->a_mass[p] = r == c ? q : -1;
          if (m == n && r == c) f->a_diag[3 * n + c] = p;
          p++;
        }
      }
    }
  Ap[n3] = p;
  return 0;
}

/* fem-corot's gather lists (f->nl, f->bl, f->blk_tr), t ascending. */
static int build_gather(tb_fem *f, tb_error *err) {
  int nv = f->nv, nt = f->ntet, nb = f->nblk;
  f->nl_start = calloc((size_t)nv + 1, sizeof(int));
  f->nl = malloc(sizeof(int) * 4 * (size_t)nt);
  f->bl_start = calloc((size_t)nb + 1, sizeof(int));
  f->bl = malloc(sizeof(int) * 16 * (size_t)nt);
  f->blk_tr = malloc(sizeof(int) * (size_t)nb);
  f->tf = malloc(sizeof(double) * 12 * (size_t)nt);
  f->th = malloc(sizeof(double) * 24 * (size_t)nt);
  int *fill = malloc(sizeof(int) * ((size_t)nv > (size_t)nb ? (size_t)nv : (size_t)nb));
  if (!f->nl_start || !f->nl || !f->bl_start || !f->bl || !f->blk_tr || !f->tf || !f->th || !fill) {
    free(fill);
    return tb_error_set(err, f->name, 0, "out of memory");
  }
  for (int t = 0; t < nt; t++)
    for (int a = 0; a < 4; a++) {
      f->nl_start[f->tet[4 * t + a] + 1]++;
      for (int b = 0; b < 4; b++)
        if (f->tet[4 * t + a] <= f->tet[4 * t + b])
          f->bl_start[f->tet_blk[16 * t + 4 * a + b] + 1]++;
    }
  for (int n = 0; n < nv; n++) f->nl_start[n + 1] += f->nl_start[n], fill[n] = f->nl_start[n];
  for (int t = 0; t < nt; t++)
    for (int a = 0; a < 4; a++) f->nl[fill[f->tet[4 * t + a]]++] = 4 * t + a;
  for (int p = 0; p < nb; p++) f->bl_start[p + 1] += f->bl_start[p], fill[p] = f->bl_start[p];
  for (int t = 0; t < nt; t++)
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++)
        if (f->tet[4 * t + a] <= f->tet[4 * t + b])
          f->bl[fill[f->tet_blk[16 * t + 4 * a + b]]++] = 16 * t + 4 * a + b;
  for (int n = 0; n < nv; n++)
    for (int p = f->row[n]; p < f->row[n + 1]; p++) f->blk_tr[p] = find_block(f, f->col[p], n);
  free(fill);
  return 0;
}

tb_fem *tb_fem_create(const tb_mesh *mesh, const tb_fem_settings *def, int corot, const char *name,
                      tb_error *err) {
  if (mesh->nv < 1 || mesh->ntet < 1) {
    tb_error_set(err, name, 0, "needs a tet mesh (nodes %d, tets %d)", mesh->nv, mesh->ntet);
    return NULL;
  }
  if (mesh->nv > 100000000 || mesh->ntet > 100000000) {
    tb_error_set(err, name, 0, "mesh too large");
    return NULL;
  }
  for (int t = 0; t < mesh->ntet; t++)
    for (int k = 0; k < 4; k++)
      if (mesh->tet[4 * t + k] < 0 || mesh->tet[4 * t + k] >= mesh->nv) {
        tb_error_set(err, name, 0, "tet %d has node index %d outside [0, %d)", t,
                     mesh->tet[4 * t + k], mesh->nv);
        return NULL;
      }
  tb_fem *f = calloc(1, sizeof *f);
  if (!f) {
    tb_error_set(err, name, 0, "out of memory");
    return NULL;
  }
  openblas_set_num_threads(1); /* see the top of this file */
  cholmod_start(&f->cc);
  f->cc.print = 0;
  f->cc.error_handler = quiet_handler;
  f->cc.nmethods = 1;
  f->cc.method[0].ordering = corot ? TB_FEM_COROT_ORDERING : TB_FEM_LINEAR_ORDERING;
  f->cc.postorder = 1;
  int super = corot ? TB_FEM_COROT_SUPERNODAL : TB_FEM_LINEAR_SUPERNODAL;
  f->cc.supernodal = super ? CHOLMOD_SUPERNODAL : CHOLMOD_SIMPLICIAL;
  f->cc.final_asis = 1;
  f->name = name, f->corot = corot;
  f->nv = mesh->nv, f->ntet = mesh->ntet;
  f->a = def->rayleigh_mass, f->b = def->rayleigh_stiffness;
  f->quasistatic = def->quasistatic != 0;
  size_t nv = (size_t)f->nv, nt = (size_t)f->ntet;
  f->x = malloc(sizeof(tb_vec3) * nv);
  f->v = calloc(nv, sizeof(tb_vec3));
  f->X = malloc(sizeof(tb_vec3) * nv);
  f->fel = calloc(nv, sizeof(tb_vec3));
  f->yc = calloc(nv, sizeof(tb_vec3));
  f->fixed = calloc(nv, 1);
  f->fixed_list = malloc(sizeof(int) * nv);
  f->tet = malloc(sizeof(int) * 4 * nt);
  f->dm_inv = malloc(sizeof(tb_mat3) * nt);
  f->ke = malloc(sizeof(double) * 144 * nt);
  f->tet_blk = malloc(sizeof(int) * 16 * nt);
  double *mass = f->mass = malloc(sizeof(double) * nv);
  if (!f->x || !f->v || !f->X || !f->fel || !f->yc || !f->fixed || !f->fixed_list || !f->tet ||
      !f->dm_inv || !f->ke || !f->tet_blk || !mass) {
    tb_error_set(err, name, 0, "out of memory");
    goto fail;
  }
  memcpy(f->X, mesh->x, sizeof(tb_vec3) * nv);
  memcpy(f->x, mesh->x, sizeof(tb_vec3) * nv);
  memcpy(f->tet, mesh->tet, sizeof(int) * 4 * nt);
  for (size_t i = 0; i < nv; i++)
    if (!tb_isfinite3(f->X[i])) {
      tb_error_set(err, name, 0, "node %d has a non-finite position", (int)i);
      goto fail;
    }
  double lambda, mu;
  tb_lame(def->E, def->nu, &lambda, &mu);
  f->lambda = lambda, f->mu = mu;
  f->rot = malloc(sizeof(tb_mat3) * nt);
  f->quat = calloc(4 * (nt + nv), sizeof(double)); /* tets', then nodes' */
  f->vol = malloc(sizeof(double) * nt);
  f->b0 = calloc(3 * nv, sizeof(double));
  f->cg_p = calloc(3 * nv, sizeof(double));
  f->cg_q = calloc(3 * nv, sizeof(double));
  f->warm = calloc(3 * nv * TB_FEM_WARM, sizeof(double));
  f->cg_r = calloc(3 * nv, sizeof(double));
  f->nrot = calloc(nv, sizeof(tb_mat3));
  f->nq = calloc(nv, sizeof(tb_mat3));
  f->ntr = calloc(nv, sizeof(tb_mat3));
  if (!f->rot || !f->quat || !f->vol || !f->b0 || !f->cg_p || !f->cg_q || !f->warm || !f->cg_r ||
      !f->nrot || !f->nq || !f->ntr) {
    tb_error_set(err, name, 0, "out of memory");
    goto fail;
  }
  for (size_t t = 0; t < nt; t++) f->rot[t] = tb_m3_identity();
  for (size_t k = 0; k < nt + nv; k++) f->quat[4 * k] = 1;
  if (tb_tet_colours(mesh, &f->ncolours, &f->col_order, &f->col_start, err)) goto fail;
  for (int t = 0; t < f->ntet; t++) {
    const int *e = f->tet + 4 * t;
    tb_vec3 d1 = tb_sub(f->X[e[1]], f->X[e[0]]), d2 = tb_sub(f->X[e[2]], f->X[e[0]]),
            d3 = tb_sub(f->X[e[3]], f->X[e[0]]);
    tb_mat3 dm;
    for (int r = 0; r < 3; r++)
      dm.m[r][0] = tb_comp(d1, r), dm.m[r][1] = tb_comp(d2, r), dm.m[r][2] = tb_comp(d3, r);
    double vol = f->vol[t] = tb_m3_det(dm) / 6.0;
    if (!(vol > 0) || !tb_m3_inverse(dm, &f->dm_inv[t])) {
      tb_error_set(
          err, name, 0,
          "tet %d is inverted or degenerate (volume %g): K_e would not be positive semi-definite",
          t, vol);
      goto fail;
    }
    tb_fem_element_k(f->dm_inv[t], vol, lambda, mu, f->ke + 144 * (size_t)t);
  }
  if (tb_lumped_masses(mesh, def->density, def->node_mass, mass, err)) goto fail;
  if (build_blocks(f, mesh, err)) goto fail;
  for (int t = 0; t < f->ntet; t++)
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++)
        f->tet_blk[16 * t + 4 * a + b] = find_block(f, f->tet[4 * t + a], f->tet[4 * t + b]);
  if (corot && build_gather(f, err)) goto fail;
  if (def->consistent_mass && !(def->node_mass > 0)) {
    for (int t = 0; t < f->ntet; t++) {
      const int *e = f->tet + 4 * t;
      double vol = tb_tet_volume(f->X[e[0]], f->X[e[1]], f->X[e[2]], f->X[e[3]]);
      for (int a = 0; a < 4; a++)
        for (int b = 0; b < 4; b++)
          f->mb[f->tet_blk[16 * t + 4 * a + b]] += def->density * vol / 20.0 * (a == b ? 2.0 : 1.0);
    }
  } else {
    for (int n = 0; n < f->nv; n++) f->mb[f->diag[n]] = mass[n];
  }
  f->lb = calloc((size_t)f->nblk, sizeof(double));
  if (!f->lb) {
    tb_error_set(err, name, 0, "out of memory");
    goto fail;
  }
  tb_fem_laplacian(f);
  f->density = def->density, f->node_mass = def->node_mass;
  f->consistent = def->consistent_mass && !(def->node_mass > 0);
  f->hit = calloc(nt, 1);
  if (!f->hit) {
    tb_error_set(err, name, 0, "out of memory");
    goto fail;
  }
  if (tb_carve_init(&f->carve, mesh, name, err)) goto fail;
  memcpy(f->carve.mass, mass, sizeof(double) * nv);
  if (build_matrix(f, err)) goto fail;
  f->L = cholmod_analyze(f->A, &f->cc);
  f->B = cholmod_zeros((size_t)f->A->nrow, 1, CHOLMOD_REAL, &f->cc);
  f->Xs = cholmod_zeros((size_t)f->A->nrow, 1, CHOLMOD_REAL, &f->cc);
  f->R = cholmod_zeros((size_t)f->A->nrow, 1, CHOLMOD_REAL, &f->cc);
  f->Z = cholmod_zeros((size_t)f->A->nrow, 1, CHOLMOD_REAL, &f->cc);
  if (!f->L || !f->B || !f->Xs || !f->R || !f->Z || f->cc.status < CHOLMOD_OK) {
    tb_error_set(err, name, 0, "CHOLMOD analysis failed (status %d)", f->cc.status);
    goto fail;
  }
  return f;
fail:
  tb_fem_destroy(f);
  return NULL;
}

void tb_fem_destroy(tb_fem *f) {
  if (!f) return;
  cholmod_free_factor(&f->L, &f->cc);
  cholmod_free_sparse(&f->A, &f->cc);
  cholmod_free_dense(&f->B, &f->cc);
  cholmod_free_dense(&f->Xs, &f->cc);
  cholmod_free_dense(&f->Y, &f->cc);
  cholmod_free_dense(&f->E, &f->cc);
  cholmod_free_dense(&f->R, &f->cc);
  cholmod_free_dense(&f->Z, &f->cc);
  cholmod_finish(&f->cc);
  free(f->col_order), free(f->col_start), free(f->rot), free(f->quat), free(f->tf), free(f->th),
      free(f->nl_start), free(f->nl), free(f->bl_start), free(f->bl), free(f->blk_tr), free(f->vol),
      free(f->lb);
  free(f->b0), free(f->cg_p), free(f->cg_q), free(f->warm), free(f->cg_r);
  free(f->nrot), free(f->nq), free(f->ntr);
  free(f->x), free(f->v), free(f->X), free(f->fel), free(f->yc), free(f->fixed);
  free(f->fixed_list), free(f->tet), free(f->dm_inv), free(f->ke), free(f->tet_blk);
  free(f->row), free(f->col), free(f->diag), free(f->kb), free(f->mb);
  free(f->a_blk), free(f->a_mass), free(f->a_diag), free(f->mass);
  free(f->hit);
  tb_carve_free(&f->carve);
  free(f);
}

/* ---- factorisation ---- */

static void fill_matrix(tb_fem *f, double alpha, double beta, int pd) {
  const int *Ap = f->A->p, *Ai = f->A->i;
  double *Ax = f->A->x;
  double c = 2 * f->mu + 3 * f->lambda; /* pd: (2 mu + 3 lambda) L */
#pragma omp parallel for schedule(static)
  for (int j = 0; j < 3 * f->nv; j++) {
    int fj = f->fixed[j / 3];
    for (int p = Ap[j]; p < Ap[j + 1]; p++) {
      int i = Ai[p], q = f->a_mass[p];
      if (fj || f->fixed[i / 3])
        Ax[p] = i == j ? 1.0 : 0.0;
      else if (pd)
        Ax[p] = q >= 0 ? beta * c * f->lb[q] + alpha * f->mb[q] : 0.0;
      else
        Ax[p] = beta * f->kb[f->a_blk[p]] + (q >= 0 ? alpha * f->mb[q] : 0.0);
    }
  }
}

/* The pivot of permuted column k: L_kk^2 (L L^T) or D_kk (L D L^T). */
static double pivot(const cholmod_factor *L, int k, int *s) {
  const double *Lx = L->x;
  if (L->is_super) {
    const int *super = L->super, *pi = L->pi, *px = L->px;
    while (super[*s + 1] <= k) (*s)++;
    int nsrow = pi[*s + 1] - pi[*s], jj = k - super[*s];
    double d = Lx[px[*s] + jj * nsrow + jj];
    return d * d;
  }
  double d = Lx[((const int *)L->p)[k]];
  return L->is_ll ? d * d : d;
}

static int factor(tb_fem *f, tb_error *err) {
  f->factored = 0;
  int ok = cholmod_factorize(f->A, f->L, &f->cc);
  f->nfactor++;
  const int *perm = f->L->Perm;
  if (f->cc.status == CHOLMOD_NOT_POSDEF || f->L->minor < f->L->n) {
    int k = (int)f->L->minor;
    return tb_error_set(err, f->name, 0,
                        "stiffness matrix not positive definite at column %d (node %d)", k,
                        perm[k] / 3);
  }
  if (!ok || f->cc.status < CHOLMOD_OK)
    return tb_error_set(err, f->name, 0, "CHOLMOD factorisation failed (status %d)", f->cc.status);
  const double *Ax = f->A->x;
  int s = 0;
  for (int k = 0; k < (int)f->L->n; k++) {
    double d = pivot(f->L, k, &s), a = Ax[f->a_diag[perm[k]]];
    if (!(d > TB_FEM_PIVOT_TOL * a))
      return tb_error_set(err, f->name, 0,
                          "stiffness matrix not positive definite at column %d (node %d): pivot "
                          "%.3g of diagonal %.3g, singular (too few prescribed nodes?)",
                          k, perm[k] / 3, d, a);
  }
  f->factored = 1;
  return 0;
}

/* ---- one step ---- */

static int check_step(const tb_fem *f, const tb_step *in, tb_error *err) {
  if (!(in->dt > 0) || !isfinite(in->dt)) return tb_error_set(err, f->name, 0, "dt must be > 0");
  if (!tb_isfinite3(in->gravity)) return tb_error_set(err, f->name, 0, "gravity is not finite");
  if (in->nfixed < 0 || in->nfixed > f->nv || (in->nfixed > 0 && (!in->fixed || !in->fixed_x)))
    return tb_error_set(err, f->name, 0, "bad prescribed set (%d nodes)", in->nfixed);
  for (int k = 0; k < in->nfixed; k++) {
    int n = in->fixed[k];
    if (n < 0 || n >= f->nv || (k > 0 && n <= in->fixed[k - 1]))
      return tb_error_set(err, f->name, 0,
                          "prescribed node %d (entry %d) out of range or not ascending", n, k);
    if (!tb_isfinite3(in->fixed_x[k]))
      return tb_error_set(err, f->name, 0, "prescribed position of node %d is not finite", n);
  }
  return 0;
}

int tb_fem_begin(tb_fem *f, const tb_step *in, double *alpha, double *beta, tb_error *err) {
  if (check_step(f, in, err)) return -1;
  double dt = in->dt;
  int qs = f->quasistatic;
  int changed =
      in->nfixed != f->nfixed ||
      (in->nfixed > 0 && memcmp(in->fixed, f->fixed_list, sizeof(int) * (size_t)in->nfixed));
  if (changed) {
    for (int k = 0; k < f->nfixed; k++) f->fixed[f->fixed_list[k]] = 0;
    for (int k = 0; k < in->nfixed; k++) f->fixed[in->fixed[k]] = 1;
    if (in->nfixed > 0) memcpy(f->fixed_list, in->fixed, sizeof(int) * (size_t)in->nfixed);
    f->nfixed = in->nfixed;
  }
  *alpha = qs ? 0.0 : 1.0 + dt * f->a, *beta = qs ? 1.0 : dt * f->b + dt * dt;
  return changed || !f->factored || *alpha != f->f_alpha || *beta != f->f_beta;
}

int tb_fem_refactor(tb_fem *f, double alpha, double beta, int pd, tb_error *err) {
  fill_matrix(f, alpha, beta, pd);
  f->f_alpha = alpha, f->f_beta = beta;
  f->since_factor = 0;
  return factor(f, err);
}

void tb_fem_rhs(tb_fem *f, const tb_step *in, int lin, double alpha, double beta, int pd) {
  double dt = in->dt;
  int qs = f->quasistatic;
  /* prescribed unknowns: velocity (dynamic) or increment (quasi-static) */
  double inv = qs ? 1.0 : 1.0 / dt, s = qs ? 1.0 : dt;
  for (int k = 0; k < in->nfixed; k++) {
    int n = in->fixed[k];
    f->yc[n] = tb_scale(tb_sub(in->fixed_x[k], f->x[n]), inv);
  }
  /* right-hand side: M p - K q + s h, prescribed columns moved over */
  tb_vec3 g = in->gravity, gdt = tb_scale(g, dt);
  double *b = f->B->x, cpd = 2 * f->mu + 3 * f->lambda;
#pragma omp parallel for schedule(static) if (f->nv >= TB_FEM_PAR_ROWS)
  for (int i = 0; i < f->nv; i++) {
    tb_vec3 acc;
    if (f->fixed[i]) {
      acc = f->yc[i];
    } else {
      acc = tb_v3(0, 0, 0);
      if (in->force) acc = tb_scale(in->force[i], s);
      if (!lin) acc = tb_madd(acc, s, f->fel[i]);
      for (int p = f->row[i]; p < f->row[i + 1]; p++) {
        int j = f->col[p];
        tb_vec3 q = lin ? tb_scale(tb_sub(f->x[j], f->X[j]), s) : tb_v3(0, 0, 0);
        if (f->mb[p] != 0) {
          tb_vec3 pm = qs ? g : tb_add(f->v[j], gdt);
          if (f->fixed[j]) pm = tb_madd(pm, -alpha, f->yc[j]);
          acc = tb_madd(acc, f->mb[p], pm);
        }
        if (pd) {
          if (f->fixed[j]) acc = tb_madd(acc, -beta * cpd * f->lb[p], f->yc[j]);
          continue;
        }
        if (!lin && !f->fixed[j]) continue; /* q = 0 */
        if (f->fixed[j]) q = tb_madd(q, beta, f->yc[j]);
        const double *k = f->kb + 9 * p;
        double kt[9];
        if (f->corot && j < i) { /* fem-corot keeps the blocks (n, m >= n) only */
          const double *u = f->kb + 9 * f->blk_tr[p];
          for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) kt[3 * r + c] = u[3 * c + r];
          k = kt;
        }
        acc.x -= k[0] * q.x + k[1] * q.y + k[2] * q.z;
        acc.y -= k[3] * q.x + k[4] * q.y + k[5] * q.z;
        acc.z -= k[6] * q.x + k[7] * q.y + k[8] * q.z;
      }
    }
    b[3 * i] = acc.x, b[3 * i + 1] = acc.y, b[3 * i + 2] = acc.z;
  }
}

int tb_fem_solve(tb_fem *f, cholmod_dense *B, cholmod_dense **X, tb_error *err) {
  /* CHOLMOD 3.0.14's simplicial solve2 asks for a 4 x n Y but hands it back
   * shaped 1 x n, so the next call would reallocate it: restore the shape
   * (the storage is the same) to keep the re-solve free of allocations. */
  size_t n3 = f->A->nrow;
  if (f->Y && !f->L->is_super && f->Y->nzmax >= 4 * n3)
    f->Y->nrow = 4, f->Y->ncol = n3, f->Y->d = 4;
  if (!cholmod_solve2(CHOLMOD_A, f->L, B, NULL, X, NULL, &f->Y, &f->E, &f->cc))
    return tb_error_set(err, f->name, 0, "CHOLMOD solve failed (status %d)", f->cc.status);
  f->nsolve++;
  return 0;
}

void tb_fem_finish(tb_fem *f, const tb_step *in, double dt) {
  int qs = f->quasistatic;
  const double *y = f->Xs->x;
  for (int i = 0; i < f->nv; i++) {
    tb_vec3 yi = tb_v3(y[3 * i], y[3 * i + 1], y[3 * i + 2]);
    if (qs)
      f->x[i] = tb_add(f->x[i], yi), f->v[i] = tb_v3(0, 0, 0);
    else
      f->x[i] = tb_madd(f->x[i], dt, yi), f->v[i] = yi;
  }
  for (int k = 0; k < in->nfixed; k++) { /* exactly at the prescribed positions */
    int n = in->fixed[k];
    f->x[n] = in->fixed_x[k];
    f->v[n] = qs ? tb_v3(0, 0, 0) : f->yc[n];
  }
}

int tb_fem_advance(tb_fem *f, const tb_step *in, int lin, int refactor, tb_error *err) {
  double alpha, beta;
  int need = tb_fem_begin(f, in, &alpha, &beta, err);
  if (need < 0) return -1;
  if ((need || refactor) && tb_fem_refactor(f, alpha, beta, 0, err)) return -1;
  tb_fem_rhs(f, in, lin, alpha, beta, 0);
  if (tb_fem_solve(f, f->B, &f->Xs, err)) return -1;
  tb_fem_finish(f, in, in->dt);
  return 0;
}

/* ---- hooks (tb_fem.h) ---- */

static tb_fem *of(tb_model *m, tb_error *err) {
  if (!m || !m->self || (m->cls != &tb_model_fem && m->cls != &tb_model_fem_corot)) {
    tb_error_set(err, "fem", 0, "not a fem or fem-corot model");
    return NULL;
  }
  return m->self;
}

int tb_fem_get_stats(tb_model *m, tb_fem_stats *s, tb_error *err) {
  tb_fem *f = of(m, err);
  if (!f) return -1;
  memset(s, 0, sizeof *s);
  s->factorizations = f->nfactor, s->solves = f->nsolve;
  s->supernodal = f->L->is_super;
  s->ordering = f->L->ordering;
  s->nnz_factor = f->cc.lnz;
  s->dofs = 3 * f->nv;
  s->residual = NAN;
  s->iterations = f->iters, s->last_iterations = f->last_iters, s->warm_order = f->warm_order;
  if (f->solver != TB_FEM_EXACT) {
    s->residual = tb_fem_residual(f); /* A holds the preconditioner's matrix, not this step's */
  } else if (f->nsolve > 0) {
    cholmod_dense *r = cholmod_copy_dense(f->B, &f->cc);
    if (!r) return tb_error_set(err, f->name, 0, "out of memory");
    double one[2] = {1, 0}, minus[2] = {-1, 0};
    cholmod_sdmult(f->A, 0, one, minus, f->Xs, r, &f->cc); /* r = A y - b */
    double nb = cholmod_norm_dense(f->B, 2, &f->cc), nr = cholmod_norm_dense(r, 2, &f->cc);
    cholmod_free_dense(&r, &f->cc);
    s->residual = nb > 0 ? nr / nb : nr;
  }
  return 0;
}

const double *tb_fem_masses(const void *self) { return ((const tb_fem *)self)->mass; }

void tb_fem_correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  tb_fem *f = self;
  for (int k = 0; k < n; k++) {
    if (x) f->x[ids[k]] = x[k];
    if (v) f->v[ids[k]] = v[k];
  }
}

int tb_fem_set_state(tb_model *m, const tb_vec3 *x, const tb_vec3 *v, tb_error *err) {
  tb_fem *f = of(m, err);
  if (!f) return -1;
  memcpy(f->x, x, sizeof(tb_vec3) * (size_t)f->nv);
  if (v)
    memcpy(f->v, v, sizeof(tb_vec3) * (size_t)f->nv);
  else
    memset(f->v, 0, sizeof(tb_vec3) * (size_t)f->nv);
  return 0;
}
