/* fem-corot's faster solvers of the implicit step's linear system
 *   A y = b,  A = alpha M + beta K_R,  K_R = sum R_e K_e R_e^T
 * (Müller & Gross 2004's warped stiffness, rotations from the start of the
 * step; y the new velocity, or the increment when quasistatic), with the
 * prescribed dofs eliminated as in fem_core.c. The exact solver refactors A
 * every step; these reuse a factor:
 *  - pcg: conjugate gradients (Hestenes & Stiefel 1952; Saad, "Iterative
 *    methods for sparse linear systems", alg. 9.1) on A, warm-started by
 *    polynomial extrapolation of the last solutions (warm_start), preconditioned
 *    by the CHOLMOD factor of an earlier A_k ("lagged" preconditioner),
 *    rotated per node (cg_rotate): T A_k^-1 T^T with T_n = R_n Q_n^T, R_n
 *    the node's rotation now, Q_n at the factor (exact for a rigid rotation
 *    of the body). When CG needs more than cg_max iterations the current A
 *    is factored and CG restarts from where it is (it then converges in one
 *    or two iterations). Stops at ||b - A y|| <= cg_tol ||b||: exact to
 *    the tolerance. Also refactored at the start of a dynamic step once CG has
 *    taken cg_refactor iterations beyond one per step since the factor
 *    (with a fresh factor CG needs one): rent or buy, a factorisation costs
 *    some tens of solves on the liver.
 *  - lagged: the factor of A is redone every lag steps; the step is a direct
 *    solve with the stale factor plus `refine` iterative refinements
 *    y += P^-1 (b - A y); when a refinement does not halve the residual
 *    (it could diverge) A is factored at once and solved directly.
 *    Approximate (its error is measured).
 *  - pd: projective dynamics (Bouaziz et al. 2014, Liu et al. 2013) with a
 *    constant matrix. Per tet, with H = R^T G(y) the rotated gradient of y,
 *      y^T K_e,R y = V (2 mu |sym H|^2 + lambda tr(H)^2)
 *                  = V min_{W skew, T traceless} (2 mu |G - R W|^2 + 3 lambda |G - R T|^2),
 *    so alternating minimisation over (W, T) (local: W = skew H, T = dev H
 *    per tet) and y (global: one solve with the constant
 *    A_pd = alpha M + beta (2 mu + 3 lambda) L, L = sum V g_a . g_b I, factored
 *    once) converges monotonically to the exact step's solution;
 *    pd_iters iterations per step, warm-started. Approximate: its error
 *    falls with more iterations.
 * Threads (OpenMP) run pd's per-tet loop colour by colour (tets of one
 * colour share no node; pcg's node rotations come with the element loop,
 * fem_corot.c) and the matrix product row by row; the vector loops over
 * the 3 nv dofs are too short to pay for a fork and stay serial, dot
 * products summed in one order:
 * bit-identical results for any thread count. No allocation in a step that
 * does not refactor (cholmod_solve2 reuses R, Z, Y, E). */
#include <math.h>
#include <string.h>

#include "fem_priv.h"

/* out = A y: alpha M + beta K_R over the node blocks, identity on the
 * prescribed dofs and no coupling to them (A's elimination). fem-corot
 * keeps only the blocks (n, m >= n) of the symmetric K_R (fem_corot.c):
 * row n reads the blocks left of its diagonal as the transposes of
 * (m, n). Rows on threads, each summed in one order. */
static void amul(const tb_fem *f, double alpha, double beta, const double *y, double *out) {
#pragma omp parallel for schedule(static) if (f->nv >= TB_FEM_PAR_ROWS)
  for (int i = 0; i < f->nv; i++) {
    if (f->fixed[i]) {
      out[3 * i] = y[3 * i], out[3 * i + 1] = y[3 * i + 1], out[3 * i + 2] = y[3 * i + 2];
      continue;
    }
    double s0 = 0, s1 = 0, s2 = 0;
    for (int p = f->row[i]; p < f->row[i + 1]; p++) {
      int j = f->col[p];
      if (f->fixed[j]) continue;
      const double *w = y + 3 * j, m = alpha * f->mb[p];
      if (p >= f->diag[i]) {
        const double *k = f->kb + 9 * p;
        s0 += beta * (k[0] * w[0] + k[1] * w[1] + k[2] * w[2]) + m * w[0];
        s1 += beta * (k[3] * w[0] + k[4] * w[1] + k[5] * w[2]) + m * w[1];
        s2 += beta * (k[6] * w[0] + k[7] * w[1] + k[8] * w[2]) + m * w[2];
      } else {
        const double *k = f->kb + 9 * f->blk_tr[p];
        s0 += beta * (k[0] * w[0] + k[3] * w[1] + k[6] * w[2]) + m * w[0];
        s1 += beta * (k[1] * w[0] + k[4] * w[1] + k[7] * w[2]) + m * w[1];
        s2 += beta * (k[2] * w[0] + k[5] * w[1] + k[8] * w[2]) + m * w[2];
      }
    }
    out[3 * i] = s0, out[3 * i + 1] = s1, out[3 * i + 2] = s2;
  }
}

/* out = A_pd y: alpha M + beta (2 mu + 3 lambda) L, eliminated the same way. */
static void pdmul(const tb_fem *f, double alpha, double beta, const double *y, double *out) {
  double c = beta * (2 * f->mu + 3 * f->lambda);
  for (int i = 0; i < f->nv; i++) {
    if (f->fixed[i]) {
      out[3 * i] = y[3 * i], out[3 * i + 1] = y[3 * i + 1], out[3 * i + 2] = y[3 * i + 2];
      continue;
    }
    double s0 = 0, s1 = 0, s2 = 0;
    for (int p = f->row[i]; p < f->row[i + 1]; p++) {
      int j = f->col[p];
      if (f->fixed[j]) continue;
      double a = alpha * f->mb[p] + c * f->lb[p];
      s0 += a * y[3 * j], s1 += a * y[3 * j + 1], s2 += a * y[3 * j + 2];
    }
    out[3 * i] = s0, out[3 * i + 1] = s1, out[3 * i + 2] = s2;
  }
}

/* One fixed order whatever the thread count. */
static double dot(const double *a, const double *b, int n) {
  double s = 0;
  for (int i = 0; i < n; i++) s += a[i] * b[i];
  return s;
}

/* pd's local step: out += beta V R (2 mu skew H + 3 lambda dev H) g_a on the
 * free nodes a of every tet, H = R^T sum_b y_b g_b^T. This is
 * (A_pd - A) y, so b0 + local(y) is the global step's right-hand side. */
static void pd_local(tb_fem *f, double beta, const double *y, double *out) {
  double tm = beta * f->mu, tl = 3 * beta * f->lambda; /* 2 mu (H - H^T) / 2 */
#pragma omp parallel
  for (int c = 0; c < f->ncolours; c++) {
#pragma omp for schedule(static)
    for (int q = f->col_start[c]; q < f->col_start[c + 1]; q++) {
      int t = f->col_order[q];
      const int *e = f->tet + 4 * t;
      const tb_mat3 *di = f->dm_inv + t, *r = f->rot + t;
      double g[4][3], G[3][3] = {{0}}, H[3][3], P[3][3];
      for (int a = 1; a < 4; a++)
        for (int j = 0; j < 3; j++) g[a][j] = di->m[a - 1][j];
      for (int j = 0; j < 3; j++) g[0][j] = -(g[1][j] + g[2][j] + g[3][j]);
      for (int a = 0; a < 4; a++) {
        const double *ya = y + 3 * e[a];
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) G[i][j] += ya[i] * g[a][j];
      }
      for (int i = 0; i < 3; i++) /* H = R^T G */
        for (int j = 0; j < 3; j++)
          H[i][j] = r->m[0][i] * G[0][j] + r->m[1][i] * G[1][j] + r->m[2][i] * G[2][j];
      double tr3 = (H[0][0] + H[1][1] + H[2][2]) / 3, v = f->vol[t];
      double S[3][3];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          S[i][j] = v * (tm * (H[i][j] - H[j][i]) + tl * (H[i][j] - (i == j ? tr3 : 0.0)));
      for (int i = 0; i < 3; i++) /* P = R S */
        for (int j = 0; j < 3; j++)
          P[i][j] = r->m[i][0] * S[0][j] + r->m[i][1] * S[1][j] + r->m[i][2] * S[2][j];
      for (int a = 0; a < 4; a++) {
        if (f->fixed[e[a]]) continue;
        double *o = out + 3 * e[a];
        for (int i = 0; i < 3; i++)
          o[i] += P[i][0] * g[a][0] + P[i][1] * g[a][1] + P[i][2] * g[a][2];
      }
    }
  }
}

/* The prescribed entries of y are known: y = b there. */
static void prescribe(tb_fem *f, double *y, const double *b) {
  for (int k = 0; k < f->nfixed; k++) {
    int n = f->fixed_list[k];
    memcpy(y + 3 * n, b + 3 * n, 3 * sizeof(double));
  }
}

/* The factor is of the current A: Q = R, T = I. */
static void rotations_factored(tb_fem *f) {
  memcpy(f->nq, f->nrot, sizeof(tb_mat3) * (size_t)f->nv);
  for (int n = 0; n < f->nv; n++) f->ntr[n] = tb_m3_identity();
}

/* z = T A_k^-1 T^T r (Z->x), or A_k^-1 r without rotations. */
static int precondition(tb_fem *f, const double *r, tb_error *err) {
  double *u = f->R->x;
  if (!f->cg_rotate) {
    memcpy(u, r, sizeof(double) * 3 * (size_t)f->nv);
    return tb_fem_solve(f, f->R, &f->Z, err);
  }
  for (int n = 0; n < f->nv; n++) {
    tb_vec3 w = tb_m3_mulv(tb_m3_transpose(f->ntr[n]), tb_v3(r[3 * n], r[3 * n + 1], r[3 * n + 2]));
    u[3 * n] = w.x, u[3 * n + 1] = w.y, u[3 * n + 2] = w.z;
  }
  if (tb_fem_solve(f, f->R, &f->Z, err)) return -1;
  double *z = f->Z->x;
  for (int n = 0; n < f->nv; n++) {
    tb_vec3 w = tb_m3_mulv(f->ntr[n], tb_v3(z[3 * n], z[3 * n + 1], z[3 * n + 2]));
    z[3 * n] = w.x, z[3 * n + 1] = w.y, z[3 * n + 2] = w.z;
  }
  return 0;
}

/* binom[j][z - 1] = (-1)^(z+1) C(j, z): the polynomial of degree j - 1
 * through the last j solutions s_1 (newest) .. s_j, at the next step, is
 * sum_z binom[j][z - 1] s_z. */
static const double binom[TB_FEM_WARM + 1][TB_FEM_WARM] = {
    {0}, {1}, {2, -1}, {3, -3, 1}, {4, -6, 4, -1}, {5, -10, 10, -5, 1}, {6, -15, 20, -15, 6, -1}};

/* y (the last step's solution y_1) <- the extrapolated guess for this step;
 * y_1 then joins the ring. Dynamic steps take the order j (1..TB_FEM_WARM)
 * whose polynomial through y_2 .. y_j+1 came closest to y_1: high orders
 * while the motion is smooth (on table 3.5's liver stretch, 60 steps,
 * 2.45 CG iterations per step where the quadratic alone took 3.02), low
 * ones for a few steps after a jump (a release, a contact). Quasi-static
 * steps, whose increments die out, take the line through the last two
 * (the quadratic took more iterations there, 5.6 against 5.1 per step on
 * the test's beam). */
static void warm_start(tb_fem *f, double *y) {
  int n3 = 3 * f->nv, have = f->nsteps - 1 < f->cg_warm ? (int)f->nsteps - 1 : f->cg_warm, j;
  if (f->nsteps == 0) return;
  const double *past[TB_FEM_WARM + 1]; /* past[z]: the solution z steps before y_1 */
  for (int z = 1; z <= TB_FEM_WARM; z++)
    past[z] = f->warm + (size_t)n3 * (size_t)((f->warm_head + z - 1) % TB_FEM_WARM);
  if (f->quasistatic) {
    j = f->nsteps >= 2 && f->cg_warm >= 2 ? 2 : 1;
  } else {
    double e[TB_FEM_WARM + 1] = {0};
    for (int i = 0; i < n3; i++)
      for (int o = 1; o <= have; o++) {
        double d = -y[i];
        for (int z = 1; z <= o; z++) d += binom[o][z - 1] * past[z][i];
        e[o] += d * d;
      }
    j = 1;
    for (int o = 2; o <= have; o++)
      if (e[o] < e[j]) j = o;
  }
  f->warm_order = j;
  /* y_1 goes into the slot of the oldest, which order j <= TB_FEM_WARM never reads */
  int slot = (f->warm_head + TB_FEM_WARM - 1) % TB_FEM_WARM;
  double *dst = f->warm + (size_t)n3 * (size_t)slot;
  for (int i = 0; i < n3; i++) {
    double s = binom[j][0] * y[i];
    for (int z = 1; z < j; z++) s += binom[j][z] * past[z][i];
    dst[i] = y[i], y[i] = s;
  }
  f->warm_head = slot;
}

static int pcg(tb_fem *f, double alpha, double beta, tb_error *err) {
  int n3 = 3 * f->nv, it = 0, fresh = 1, refactored = 0;
  double *b = f->B->x, *y = f->Xs->x, *r = f->cg_r, *p = f->cg_p, *q = f->cg_q;
  warm_start(f, y);
  prescribe(f, y, b);
  amul(f, alpha, beta, y, q);
  for (int i = 0; i < n3; i++) r[i] = b[i] - q[i];
  double nb = sqrt(dot(b, b, n3)), rr = sqrt(dot(r, r, n3)), rz_old = 1;
  while (rr > f->cg_tol * nb) {
    if (it >= f->cg_max && !refactored) { /* stale preconditioner: factor this A */
      if (tb_fem_refactor(f, alpha, beta, 0, err)) return -1;
      rotations_factored(f);
      refactored = fresh = 1;
    } else if (it >= 2 * f->cg_max + 20 || !isfinite(rr)) {
      return tb_error_set(err, f->name, 0,
                          "pcg: relative residual %.3g after %d iterations (cg_tol %g)", rr / nb,
                          it, f->cg_tol);
    }
    if (precondition(f, r, err)) return -1;
    const double *z = f->Z->x;
    double rz = dot(r, z, n3), beta_cg = fresh ? 0.0 : rz / rz_old;
    for (int i = 0; i < n3; i++) p[i] = z[i] + beta_cg * p[i];
    amul(f, alpha, beta, p, q);
    double pq = dot(p, q, n3);
    if (!(pq > 0))
      return tb_error_set(err, f->name, 0, "pcg: matrix not positive definite (p.Ap %.3g)", pq);
    double a = rz / pq;
    for (int i = 0; i < n3; i++) y[i] += a * p[i], r[i] -= a * q[i];
    rr = sqrt(dot(r, r, n3)), rz_old = rz, fresh = 0;
    it++;
  }
  f->last_iters = it, f->iters += it;
  /* iterations beyond the one a fresh factor needs, since the last factor */
  f->cg_excess = refactored ? 0 : f->cg_excess + (it > 1 ? it - 1 : 0);
  f->last_res = nb > 0 ? rr / nb : rr;
  return 0;
}

static int lagged(tb_fem *f, double alpha, double beta, tb_error *err) {
  int n3 = 3 * f->nv;
  f->last_iters = 0;
  if (f->since_factor >= f->lag && tb_fem_refactor(f, alpha, beta, 0, err)) return -1;
  if (tb_fem_solve(f, f->B, &f->Xs, err)) return -1;
  double *b = f->B->x, *y = f->Xs->x, *r = f->R->x, *q = f->cg_q;
  double prev = sqrt(dot(b, b, n3));
  for (int k = 0; k < f->refine; k++) {
    amul(f, alpha, beta, y, q);
    for (int i = 0; i < n3; i++) r[i] = b[i] - q[i];
    double rn = sqrt(dot(r, r, n3));
    if (!(rn <= 0.5 * prev) && f->since_factor > 0) {
      /* the stale factor no longer contracts (refinement could diverge):
       * factor this A and solve directly */
      if (tb_fem_refactor(f, alpha, beta, 0, err) || tb_fem_solve(f, f->B, &f->Xs, err)) return -1;
      break;
    }
    prev = rn;
    if (tb_fem_solve(f, f->R, &f->Z, err)) return -1;
    y = f->Xs->x;
    const double *z = f->Z->x;
    for (int i = 0; i < n3; i++) y[i] += z[i];
    f->last_iters = k + 1;
  }
  f->iters += f->last_iters;
  f->last_res = NAN; /* measured on demand (tb_fem_residual) */
  return 0;
}

static int pd(tb_fem *f, double beta, tb_error *err) {
  int n3 = 3 * f->nv;
  double *b = f->B->x, *b0 = f->b0, *y = f->Xs->x;
  memcpy(b0, b, sizeof(double) * (size_t)n3);
  prescribe(f, y, b0);
  for (int k = 0; k < f->pd_iters; k++) {
    memcpy(b, b0, sizeof(double) * (size_t)n3);
    pd_local(f, beta, y, b);
    if (tb_fem_solve(f, f->B, &f->Xs, err)) return -1;
    y = f->Xs->x;
  }
  f->last_iters = f->pd_iters, f->iters += f->pd_iters;
  f->last_res = NAN;
  return 0;
}

int tb_fem_iterate(tb_fem *f, const tb_step *in, tb_error *err) {
  double alpha, beta;
  int need = tb_fem_begin(f, in, &alpha, &beta, err), s = f->solver;
  if (need < 0) return -1;
  /* pcg, dynamic steps: refactor once the stale factor has cost cg_refactor
   * extra iterations since the last one (rent or buy: a factorisation costs
   * some tens of solves). Not quasi-static: there (no mass term) the
   * liver's system is ill-conditioned while the patch is pulled, an error
   * of 1e-7 in the residual moves the state by up to ~1e-5 depending on the
   * preconditioner, and the extra factors moved table 3.5's static error
   * at 60 steps from 6e-8 to 7e-6 */
  if (s == TB_FEM_PCG && !f->quasistatic && f->cg_excess >= f->cg_refactor)
    need = 1, f->cg_excess = 0;
  if (need && tb_fem_refactor(f, alpha, beta, s == TB_FEM_PD, err)) return -1;
  if (need && s == TB_FEM_PCG && f->cg_rotate) rotations_factored(f);
  tb_fem_rhs(f, in, 0, alpha, beta, s == TB_FEM_PD);
  int rc = s == TB_FEM_PCG      ? pcg(f, alpha, beta, err)
           : s == TB_FEM_LAGGED ? lagged(f, alpha, beta, err)
                                : pd(f, beta, err);
  if (rc) return -1;
  f->since_factor++;
  f->nsteps++;
  tb_fem_finish(f, in, in->dt);
  return 0;
}

double tb_fem_residual(tb_fem *f) {
  if (f->nsolve == 0) return NAN;
  int n3 = 3 * f->nv;
  double alpha = f->f_alpha, beta = f->f_beta, *y = f->Xs->x, *q = f->cg_q, *r = f->cg_p;
  const double *b = f->solver == TB_FEM_PD ? f->b0 : f->B->x;
  if (f->solver == TB_FEM_PD) { /* b0 - A y = b0 + (A_pd - A) y - A_pd y */
    memcpy(r, b, sizeof(double) * (size_t)n3);
    pd_local(f, beta, y, r);
    pdmul(f, alpha, beta, y, q);
  } else {
    memcpy(r, b, sizeof(double) * (size_t)n3);
    amul(f, alpha, beta, y, q);
  }
  for (int i = 0; i < n3; i++) r[i] -= q[i];
  double nb = sqrt(dot(b, b, n3)), nr = sqrt(dot(r, r, n3));
  return nb > 0 ? nr / nb : nr;
}
