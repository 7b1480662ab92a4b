/* Corotational (warped-stiffness) linear FEM, Müller & Gross 2004
 * "Interactive virtual materials": per tet the rotation R of the polar
 * decomposition of F = D_s D_m^-1 (tb_m3_polar_newton), the force
 * f_e = -R K_e (R^T x_e - X_e) and the stiffness R K_e R^T, with K_e the
 * linear element of thesis §3.3.2. The assembled matrix changes every step:
 * the exact solver has CHOLMOD refactor it numerically each step on the
 * pattern analysed once.
 * Same implicit Euler, Rayleigh damping (C = a M + b K_R) and Dirichlet
 * elimination as fem (fem_core.c). quasistatic=1 does one warped-stiffness
 * iteration of the static equilibrium per step (rotations from the current
 * shape), which converges over steps. Rigid motions cost no energy.
 *
 * solver= chooses how each step's linear system is solved (fem_solve.c):
 * pcg, the default (CG preconditioned by a stale factor rotated per node,
 * refactored when CG needs more than cg_max iterations, exact to cg_tol:
 * within 1e-7 of the exact path on the liver and the beam, about 3x as fast,
 * table 3.5's fem-corot solvers), exact (refactor every step, the reference),
 * lagged (refactor every lag steps, direct solve + refine refinements), pd
 * (projective-dynamics-style local/global iterations with one constant
 * factor; approximate).
 * Each tet's rotation is found by Newton's method on the rotation itself
 * (tb_fem_polar_warm), started from the tet's last one: the iterations
 * depend on how far it turned in a step, not on its stretch as Higham's
 * Newton iteration does. The per-element loop (rotations, forces, h = R g)
 * runs on threads over all tets into per-tet buffers, then each node sums
 * its forces and its row's blocks of R K_e R^T from them in a fixed order
 * (2 barriers per step, not one per colour; bit-identical for any thread
 * count). Cutting removes the tets the blade touches (fem_cut.c). */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "fem_priv.h"
#include "tb_fem.h"

/* fem's settings and the solver's. */
typedef struct corot_settings {
  tb_fem_settings fem; /* first: TB_FEM_SETTINGS's offsets hold */
  int solver;
  double cg_tol;
  int cg_max, cg_refactor, cg_rotate, cg_warm, lag, refine, pd_iters;
} corot_settings;

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const corot_settings *def = settings;
  tb_fem *f = tb_fem_create(mesh, &def->fem, 1, "fem-corot", err);
  if (!f) return NULL;
  f->solver = def->solver, f->cg_tol = def->cg_tol, f->cg_max = def->cg_max;
  f->cg_refactor = def->cg_refactor, f->cg_rotate = def->cg_rotate, f->cg_warm = def->cg_warm,
  f->lag = def->lag, f->refine = def->refine, f->pd_iters = def->pd_iters;
  return f;
}

/* Rotation of tet t in positions x, and the rotated-back displacement
 * d_a = R^T (x_a - x_0) - (X_a - X_0) (K_e ignores translations). */
static tb_mat3 element_rotation(const tb_fem *f, int t, const tb_vec3 *x, double d[12]) {
  const int *e = f->tet + 4 * t;
  tb_mat3 ds;
  for (int c = 0; c < 3; c++) {
    tb_vec3 s = tb_sub(x[e[c + 1]], x[e[0]]);
    ds.m[0][c] = s.x, ds.m[1][c] = s.y, ds.m[2][c] = s.z;
  }
  tb_mat3 r = tb_m3_polar_newton(tb_m3_mul(ds, f->dm_inv[t]));
  tb_mat3 rt = tb_m3_transpose(r);
  d[0] = d[1] = d[2] = 0;
  for (int a = 1; a < 4; a++) {
    tb_vec3 w = tb_sub(tb_m3_mulv(rt, tb_sub(x[e[a]], x[e[0]])), tb_sub(f->X[e[a]], f->X[e[0]]));
    d[3 * a] = w.x, d[3 * a + 1] = w.y, d[3 * a + 2] = w.z;
  }
  return r;
}

/* R of a unit quaternion q = (w, x, y, z). */
static inline tb_mat3 quat_rot(const double *q) {
  double w = q[0], x = q[1], y = q[2], z = q[3];
  return (tb_mat3){{{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                    {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                    {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}}};
}

/* The unit quaternion of a rotation matrix (Shepperd 1978: from its
 * largest component). */
static void rot_quat(tb_mat3 r, double *q) {
  double(*m)[3] = r.m, t = m[0][0] + m[1][1] + m[2][2], n;
  if (t >= m[0][0] && t >= m[1][1] && t >= m[2][2]) {
    n = sqrt(1 + t) * 2;
    q[0] = n / 4, q[1] = (m[2][1] - m[1][2]) / n, q[2] = (m[0][2] - m[2][0]) / n;
    q[3] = (m[1][0] - m[0][1]) / n;
  } else if (m[0][0] >= m[1][1] && m[0][0] >= m[2][2]) {
    n = sqrt(1 + m[0][0] - m[1][1] - m[2][2]) * 2;
    q[0] = (m[2][1] - m[1][2]) / n, q[1] = n / 4, q[2] = (m[0][1] + m[1][0]) / n;
    q[3] = (m[0][2] + m[2][0]) / n;
  } else if (m[1][1] >= m[2][2]) {
    n = sqrt(1 - m[0][0] + m[1][1] - m[2][2]) * 2;
    q[0] = (m[0][2] - m[2][0]) / n, q[1] = (m[0][1] + m[1][0]) / n, q[2] = n / 4;
    q[3] = (m[1][2] + m[2][1]) / n;
  } else {
    n = sqrt(1 - m[0][0] - m[1][1] + m[2][2]) * 2;
    q[0] = (m[1][0] - m[0][1]) / n, q[1] = (m[0][2] + m[2][0]) / n;
    q[2] = (m[1][2] + m[2][1]) / n, q[3] = n / 4;
  }
}

tb_mat3 tb_fem_polar_warm(tb_mat3 F, double *q) {
  if (tb_m3_det(F) > 0)
    for (int it = 0; it < 6; it++) {
      tb_mat3 r = quat_rot(q);
      double S[3][3];
      for (int i = 0; i < 3; i++) /* S = R^T F */
        for (int j = 0; j < 3; j++)
          S[i][j] = r.m[0][i] * F.m[0][j] + r.m[1][i] * F.m[1][j] + r.m[2][i] * F.m[2][j];
      /* R exp(w^) makes S symmetric to first order: (tr S I - sym S) w = axial(S - S^T) */
      double w0 = S[2][1] - S[1][2], w1 = S[0][2] - S[2][0], w2 = S[1][0] - S[0][1];
      double a00 = S[1][1] + S[2][2], a11 = S[0][0] + S[2][2], a22 = S[0][0] + S[1][1];
      double a01 = -0.5 * (S[0][1] + S[1][0]), a02 = -0.5 * (S[0][2] + S[2][0]),
             a12 = -0.5 * (S[1][2] + S[2][1]);
      double c00 = a11 * a22 - a12 * a12, c01 = a02 * a12 - a01 * a22, c02 = a01 * a12 - a02 * a11;
      double det = a00 * c00 + a01 * c01 + a02 * c02;
      /* the maximum of tr(R^T F) (the polar rotation) has this Hessian
       * positive definite; else (a saddle, far start) the cold iteration */
      if (!(a00 > 0) || !(a00 * a11 - a01 * a01 > 0) || !(det > 0)) break;
      double c11 = a00 * a22 - a02 * a02, c12 = a01 * a02 - a00 * a12, c22 = a00 * a11 - a01 * a01;
      double id = 1 / det, o0 = (c00 * w0 + c01 * w1 + c02 * w2) * id,
             o1 = (c01 * w0 + c11 * w1 + c12 * w2) * id, o2 = (c02 * w0 + c12 * w1 + c22 * w2) * id;
      double oo = o0 * o0 + o1 * o1 + o2 * o2;
      /* q <- q (1, w/2), normalised (Newton's step along the rotation) */
      double h0 = 0.5 * o0, h1 = 0.5 * o1, h2 = 0.5 * o2;
      double n0 = q[0] - q[1] * h0 - q[2] * h1 - q[3] * h2;
      double n1 = q[1] + q[0] * h0 + q[2] * h2 - q[3] * h1;
      double n2 = q[2] + q[0] * h1 + q[3] * h0 - q[1] * h2;
      double n3 = q[3] + q[0] * h2 + q[1] * h1 - q[2] * h0;
      double in = 1 / sqrt(n0 * n0 + n1 * n1 + n2 * n2 + n3 * n3);
      q[0] = n0 * in, q[1] = n1 * in, q[2] = n2 * in, q[3] = n3 * in;
      /* quadratic convergence: the rotation is now exact to about |w|^2 */
      if (oo < 1e-16) return quat_rot(q);
    }
  tb_mat3 r = tb_m3_polar_newton(F);
  rot_quat(r, q);
  return r;
}

/* k d for the 12x12 element matrix in node blocks. */
static void element_mul(const double *k, const double d[12], double out[12]) {
  for (int a = 0; a < 4; a++)
    for (int i = 0; i < 3; i++) {
      double s = 0;
      for (int b = 0; b < 4; b++) {
        const double *blk = k + 9 * (4 * a + b) + 3 * i;
        s += blk[0] * d[3 * b] + blk[1] * d[3 * b + 1] + blk[2] * d[3 * b + 2];
      }
      out[3 * a + i] = s;
    }
}

/* Tet t: its rotation R (polar decomposition of F = D_s D_m^-1, warm
 * started from the last step's) into f->rot, its node forces into f->tf
 * (12) and, with kb, h_a = R g_a into f->th (12). With g_a the
 * shape-function gradients (g_0 = -g_1 - g_2 - g_3), K_e's blocks are
 * V (lambda g_a g_b^T + mu g_b g_a^T + mu g_a.g_b I) (tb_fem_element_k), so
 *   R K_ab R^T = V (lambda h_a h_b^T + mu h_b h_a^T + mu g_a.g_b I),
 *   -R K_e (R^T x_e - X_e) at node a = -V R sigma g_a,
 *   sigma = 2 mu eps + lambda tr(eps) I, eps = sym(R^T F) - I
 * (R^T x_e - X_e has the gradient R^T F - I): a few 3x3 products per tet
 * instead of K_e's 144 entries. */
static void element(tb_fem *f, int t, int kb) {
  const int *e = f->tet + 4 * t;
  const tb_mat3 *di = f->dm_inv + t;
  double g[4][3], vol = f->vol[t], lam = f->lambda, mu = f->mu;
  for (int a = 1; a < 4; a++)
    for (int j = 0; j < 3; j++) g[a][j] = di->m[a - 1][j];
  for (int j = 0; j < 3; j++) g[0][j] = -(g[1][j] + g[2][j] + g[3][j]);
  tb_mat3 ds;
  for (int c = 0; c < 3; c++) {
    tb_vec3 s = tb_sub(f->x[e[c + 1]], f->x[e[0]]);
    ds.m[0][c] = s.x, ds.m[1][c] = s.y, ds.m[2][c] = s.z;
  }
  tb_mat3 F = tb_m3_mul(ds, *di);
  tb_mat3 r = f->rot[t] = tb_fem_polar_warm(F, f->quat + 4 * t);
  double S[3][3], sig[3][3], P[3][3];
  for (int i = 0; i < 3; i++) /* S = R^T F */
    for (int j = 0; j < 3; j++)
      S[i][j] = r.m[0][i] * F.m[0][j] + r.m[1][i] * F.m[1][j] + r.m[2][i] * F.m[2][j];
  double tr = S[0][0] + S[1][1] + S[2][2] - 3;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      sig[i][j] = mu * (S[i][j] + S[j][i]) + (i == j ? lam * tr - 2 * mu : 0.0);
  for (int i = 0; i < 3; i++) /* P = V R sigma */
    for (int j = 0; j < 3; j++)
      P[i][j] = vol * (r.m[i][0] * sig[0][j] + r.m[i][1] * sig[1][j] + r.m[i][2] * sig[2][j]);
  double *tf = f->tf + 12 * (size_t)t;
  for (int a = 0; a < 4; a++)
    for (int i = 0; i < 3; i++)
      tf[3 * a + i] = -(P[i][0] * g[a][0] + P[i][1] * g[a][1] + P[i][2] * g[a][2]);
  if (!kb) return;
  double *th = f->th + 24 * (size_t)t; /* h_a, then V h_a */
  for (int a = 0; a < 4; a++)
    for (int i = 0; i < 3; i++) {
      double h = r.m[i][0] * g[a][0] + r.m[i][1] * g[a][1] + r.m[i][2] * g[a][2];
      th[3 * a + i] = h, th[12 + 3 * a + i] = vol * h;
    }
}

/* Node n's sums over its tets in ascending order (f->nl): the force fel,
 * with rot its rotation nrot (and ntr), and with kb its blocks
 * (n, m >= n) of sum R K_e R^T = mu lb I + sum V (lambda h_a h_b^T +
 * mu h_b h_a^T) (f->bl). */
static void gather(tb_fem *f, int n, int kb, int rot) {
  tb_vec3 s = tb_v3(0, 0, 0);
  tb_mat3 nr = {{{0}}};
  for (int k = f->nl_start[n]; k < f->nl_start[n + 1]; k++) {
    int t = f->nl[k] >> 2, a = f->nl[k] & 3;
    const double *tf = f->tf + 12 * (size_t)t + 3 * a;
    s.x += tf[0], s.y += tf[1], s.z += tf[2];
    if (rot)
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) nr.m[i][j] += f->vol[t] * f->rot[t].m[i][j];
  }
  f->fel[n] = s;
  if (rot) {
    /* pcg's node rotation R_n: the polar rotation of the volume-weighted
     * sum of its tets' (warm started from its last); T_n = R_n Q_n^T, Q_n
     * the node rotations when the preconditioner's factor was made. For a
     * rigid rotation R of the whole body A = R A_k R^T, so the
     * preconditioner T A_k^-1 T^T (fem_solve.c) is exact; T is orthogonal
     * per node, so it stays symmetric positive definite. */
    f->nrot[n] = tb_fem_polar_warm(nr, f->quat + 4 * ((size_t)f->ntet + n));
    f->ntr[n] = tb_m3_mul(f->nrot[n], tb_m3_transpose(f->nq[n]));
  }
  if (!kb) return;
  double lam = f->lambda, mu = f->mu;
  for (int p = f->diag[n]; p < f->row[n + 1]; p++) {
    /* M = sum V h_a h_b^T; sum V h_b h_a^T is M^T: the block is
     * lambda M + mu M^T + mu lb I */
    double m0 = 0, m1 = 0, m2 = 0, m3 = 0, m4 = 0, m5 = 0, m6 = 0, m7 = 0, m8 = 0;
    for (int q = f->bl_start[p]; q < f->bl_start[p + 1]; q++) {
      int c = f->bl[q];
      const double *h = f->th + 24 * (size_t)(c >> 4);
      const double *wa = h + 12 + 3 * ((c >> 2) & 3), *hb = h + 3 * (c & 3);
      m0 += wa[0] * hb[0], m1 += wa[0] * hb[1], m2 += wa[0] * hb[2];
      m3 += wa[1] * hb[0], m4 += wa[1] * hb[1], m5 += wa[1] * hb[2];
      m6 += wa[2] * hb[0], m7 += wa[2] * hb[1], m8 += wa[2] * hb[2];
    }
    double d = mu * f->lb[p], *k = f->kb + 9 * p;
    k[0] = lam * m0 + mu * m0 + d, k[1] = lam * m1 + mu * m3, k[2] = lam * m2 + mu * m6;
    k[3] = lam * m3 + mu * m1, k[4] = lam * m4 + mu * m4 + d, k[5] = lam * m5 + mu * m7;
    k[6] = lam * m6 + mu * m2, k[7] = lam * m7 + mu * m5, k[8] = lam * m8 + mu * m8 + d;
  }
}

/* rot, fel <- -sum R K_e (R^T x_e - X_e) and, with kb, kb <- sum R K_e R^T
 * on the blocks (n, m >= n) only (the rest is never read: fem_core.c's
 * matrix and right-hand side and fem_solve.c's product take the
 * transposes): per tet into per-tet buffers, then per node in a fixed
 * order (two phases: bit-identical for any thread count). */
static void assemble(tb_fem *f, int kb) {
  int rot = f->cg_rotate && f->solver == TB_FEM_PCG;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (int t = 0; t < f->ntet; t++) element(f, t, kb);
#pragma omp for schedule(static)
    for (int n = 0; n < f->nv; n++) gather(f, n, kb, rot);
  }
}

static int step(void *self, const tb_step *in, tb_error *err) {
  tb_fem *f = self;
  assemble(f, f->solver != TB_FEM_PD);
  if (f->solver == TB_FEM_EXACT) return tb_fem_advance(f, in, 0, 1, err);
  return tb_fem_iterate(f, in, err);
}

static const tb_vec3 *positions(const void *self) { return ((const tb_fem *)self)->x; }
static const tb_vec3 *velocities(const void *self) { return ((const tb_fem *)self)->v; }

/* 1/2 sum (R^T x_e - X_e)^T K_e (R^T x_e - X_e) + 1/2 v^T M v, R from the current shape. */
static double energy(const void *self) {
  const tb_fem *f = self;
  double e = 0;
  for (int t = 0; t < f->ntet; t++) {
    double d[12], kd[12];
    element_rotation(f, t, f->x, d);
    element_mul(f->ke + 144 * (size_t)t, d, kd);
    for (int q = 0; q < 12; q++) e += d[q] * kd[q];
  }
  return 0.5 * e + tb_fem_kinetic(f);
}

static void destroy(void *self) { tb_fem_destroy(self); }

static const tb_setting settings[] = {
    TB_FEM_SETTINGS,
    TB_SETTING_C(corot_settings, solver, TB_FEM_PCG, 3, "exact|pcg|lagged|pd",
                 "linear solve per step: exact refactor (the reference), CG with a stale "
                 "factor (exact to cg_tol), lagged factor, projective-dynamics iterations"),
    TB_SETTING_R(corot_settings, cg_tol, 1e-7, 0.0, 1.0, TB_OPEN_LO | TB_OPEN_HI,
                 "pcg: relative residual ||b - A y|| / ||b|| to stop at"),
    TB_SETTING_I(corot_settings, cg_max, 8, 1, 1000,
                 "pcg: CG iterations after which the preconditioner is refactored"),
    TB_SETTING_I(corot_settings, cg_refactor, 40, 1, 1000000,
                 "pcg, dynamic steps: refactor once CG took this many iterations beyond 1 per "
                 "step since the last factorisation"),
    TB_SETTING_I(corot_settings, cg_rotate, 1, 0, 1,
                 "pcg: 1 rotates the preconditioner per node (R_n Q_n^T A_k^-1 Q_n R_n^T)"),
    TB_SETTING_I(corot_settings, cg_warm, TB_FEM_WARM, 1, TB_FEM_WARM,
                 "pcg: highest order of the warm start (extrapolation through up to this many "
                 "past solutions; 1 starts from the last)"),
    TB_SETTING_I(corot_settings, lag, 10, 1, 1000000, "lagged: refactor every lag steps"),
    TB_SETTING_I(corot_settings, refine, 2, 0, 1000,
                 "lagged: iterative refinements with the stale factor"),
    TB_SETTING_I(corot_settings, pd_iters, 5, 1, 1000, "pd: local/global iterations per step"),
};

const tb_model_class tb_model_fem_corot = {
    .name = "fem-corot",
    .summary =
        "corotational (warped-stiffness) FEM, Müller & Gross 2004; pcg (default), exact, "
        "lagged or pd solver",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(corot_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = tb_fem_masses,
    .correct = tb_fem_correct,
    .cut = tb_fem_cut,
    .surface = tb_fem_surface,
    .tets_alive = tb_fem_tets_alive,
};
