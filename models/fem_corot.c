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
 * exact (refactor every step, the reference), pcg (CG preconditioned by a
 * stale factor rotated per node, refactored when CG needs more than cg_max
 * iterations, exact to cg_tol),
 * lagged (refactor every lag steps, direct solve + refine refinements), pd
 * (projective-dynamics-style local/global iterations with one constant
 * factor; approximate). The per-element loop (rotations, forces,
 * R K_e R^T) runs on threads colour by colour (tet_colour.c): each node and
 * block sums its tets in the colouring's order, bit-identical for any
 * thread count. */
#include <stddef.h>
#include <string.h>

#include "fem_priv.h"

/* fem's settings and the solver's. */
typedef struct corot_settings {
  tb_fem_settings fem; /* first: TB_FEM_SETTINGS's offsets hold */
  int solver;
  double cg_tol;
  int cg_max, cg_rotate, lag, refine, pd_iters;
} corot_settings;

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const corot_settings *def = settings;
  tb_fem *f = tb_fem_create(mesh, &def->fem, 1, "fem-corot", err);
  if (!f) return NULL;
  f->solver = def->solver, f->cg_tol = def->cg_tol, f->cg_max = def->cg_max;
  f->cg_rotate = def->cg_rotate, f->lag = def->lag, f->refine = def->refine,
  f->pd_iters = def->pd_iters;
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

/* Tet t: its rotation R (polar decomposition of F = D_s D_m^-1) into
 * f->rot, its forces added to fel and, with kb, R K_e R^T added to the
 * blocks. With g_a the shape-function gradients (g_0 = -g_1 - g_2 - g_3),
 * K_e's blocks are V (lambda g_a g_b^T + mu g_b g_a^T + mu g_a.g_b I)
 * (tb_fem_element_k), so
 *   R K_ab R^T = V (lambda h_a h_b^T + mu h_b h_a^T + mu g_a.g_b I), h = R g,
 *   -R K_e (R^T x_e - X_e) at node a = -V R sigma g_a,
 *   sigma = 2 mu eps + lambda tr(eps) I, eps = sym(R^T F) - I
 * (R^T x_e - X_e has the gradient R^T F - I): a few 3x3 products per tet
 * instead of K_e's 144 entries. */
static void element(tb_fem *f, int t, int kb) {
  const int *e = f->tet + 4 * t, *blk = f->tet_blk + 16 * t;
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
  tb_mat3 r = f->rot[t] = tb_m3_polar_newton(F);
  if (f->cg_rotate && f->solver == TB_FEM_PCG) /* node rotations (fem_solve.c) */
    for (int a = 0; a < 4; a++)
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) f->nrot[e[a]].m[i][j] += vol * r.m[i][j];
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
  for (int a = 0; a < 4; a++) {
    tb_vec3 fa = tb_v3(P[0][0] * g[a][0] + P[0][1] * g[a][1] + P[0][2] * g[a][2],
                       P[1][0] * g[a][0] + P[1][1] * g[a][1] + P[1][2] * g[a][2],
                       P[2][0] * g[a][0] + P[2][1] * g[a][1] + P[2][2] * g[a][2]);
    f->fel[e[a]] = tb_sub(f->fel[e[a]], fa);
  }
  if (!kb) return;
  double h[4][3];
  for (int a = 0; a < 4; a++)
    for (int i = 0; i < 3; i++)
      h[a][i] = r.m[i][0] * g[a][0] + r.m[i][1] * g[a][1] + r.m[i][2] * g[a][2];
  double vl = vol * lam, vm = vol * mu;
  for (int a = 0; a < 4; a++)
    for (int b = a; b < 4; b++) {
      double d = vm * (g[a][0] * g[b][0] + g[a][1] * g[b][1] + g[a][2] * g[b][2]), rk[3][3];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
          rk[i][j] = vl * h[a][i] * h[b][j] + vm * h[b][i] * h[a][j] + (i == j ? d : 0.0);
      double *dst = f->kb + 9 * blk[4 * a + b];
      for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) dst[3 * i + j] += rk[i][j];
      if (b != a) {
        double *dt = f->kb + 9 * blk[4 * b + a];
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) dt[3 * j + i] += rk[i][j];
      }
    }
}

/* rot, fel <- -sum R K_e (R^T x_e - X_e) and, with kb, kb <- sum R K_e R^T;
 * colour by colour (tets of one colour share no node, hence no block). */
static void assemble(tb_fem *f, int kb) {
#pragma omp parallel
  {
    if (kb) {
#pragma omp for schedule(static)
      for (int p = 0; p < 9 * f->nblk; p++) f->kb[p] = 0;
    }
#pragma omp for schedule(static)
    for (int i = 0; i < f->nv; i++) f->fel[i] = tb_v3(0, 0, 0), f->nrot[i] = (tb_mat3){{{0}}};
    for (int c = 0; c < f->ncolours; c++) {
#pragma omp for schedule(static)
      for (int q = f->col_start[c]; q < f->col_start[c + 1]; q++) element(f, f->col_order[q], kb);
    }
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
    TB_SETTING_C(corot_settings, solver, TB_FEM_EXACT, 3, "exact|pcg|lagged|pd",
                 "linear solve per step: exact refactor, CG with a stale factor, lagged factor, "
                 "projective-dynamics iterations"),
    TB_SETTING_R(corot_settings, cg_tol, 1e-7, 0.0, 1.0, TB_OPEN_LO | TB_OPEN_HI,
                 "pcg: relative residual ||b - A y|| / ||b|| to stop at"),
    TB_SETTING_I(corot_settings, cg_max, 8, 1, 1000,
                 "pcg: CG iterations after which the preconditioner is refactored"),
    TB_SETTING_I(corot_settings, cg_rotate, 1, 0, 1,
                 "pcg: 1 rotates the preconditioner per node (R_n Q_n^T A_k^-1 Q_n R_n^T)"),
    TB_SETTING_I(corot_settings, lag, 10, 1, 1000000, "lagged: refactor every lag steps"),
    TB_SETTING_I(corot_settings, refine, 2, 0, 1000,
                 "lagged: iterative refinements with the stale factor"),
    TB_SETTING_I(corot_settings, pd_iters, 5, 1, 1000, "pd: local/global iterations per step"),
};

const tb_model_class tb_model_fem_corot = {
    .name = "fem-corot",
    .summary =
        "corotational (warped-stiffness) FEM, Müller & Gross 2004; exact, pcg, lagged "
        "or pd solver",
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
};
