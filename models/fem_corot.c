/* Corotational (warped-stiffness) linear FEM, Müller & Gross 2004
 * "Interactive virtual materials": per tet the rotation R of the polar
 * decomposition of F = D_s D_m^-1 (tb_m3_polar), the force
 * f_e = -R K_e (R^T x_e - X_e) and the stiffness R K_e R^T, with K_e the
 * linear element of thesis §3.3.2. The assembled matrix changes every step:
 * CHOLMOD refactors it numerically each step on the pattern analysed once.
 * Same implicit Euler, Rayleigh damping (C = a M + b K_R) and Dirichlet
 * elimination as fem (fem_core.c). quasistatic=1 does one warped-stiffness
 * iteration of the static equilibrium per step (rotations from the current
 * shape), which converges over steps. Rigid motions cost no energy. */
#include <stddef.h>
#include <string.h>

#include "fem_priv.h"

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const tb_fem_settings *def = settings;
  return tb_fem_create(mesh, def, 1, "fem-corot", err);
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
  tb_mat3 r = tb_m3_polar(tb_m3_mul(ds, f->dm_inv[t]));
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

/* kb <- sum R K_e R^T, fel <- -sum R K_e (R^T x_e - X_e). */
static void assemble(tb_fem *f) {
  memset(f->kb, 0, sizeof(double) * 9 * (size_t)f->nblk);
  memset(f->fel, 0, sizeof(tb_vec3) * (size_t)f->nv);
  for (int t = 0; t < f->ntet; t++) {
    const int *e = f->tet + 4 * t, *blk = f->tet_blk + 16 * t;
    const double *k = f->ke + 144 * (size_t)t;
    double d[12], kd[12];
    tb_mat3 r = element_rotation(f, t, f->x, d);
    element_mul(k, d, kd);
    for (int a = 0; a < 4; a++) {
      tb_vec3 fa = tb_m3_mulv(r, tb_v3(kd[3 * a], kd[3 * a + 1], kd[3 * a + 2]));
      f->fel[e[a]] = tb_sub(f->fel[e[a]], fa);
    }
    for (int a = 0; a < 4; a++)
      for (int b = a; b < 4; b++) {
        const double *kab = k + 9 * (4 * a + b);
        double tmp[3][3], rk[3][3];
        for (int i = 0; i < 3; i++) /* tmp = R K_ab */
          for (int j = 0; j < 3; j++)
            tmp[i][j] = r.m[i][0] * kab[j] + r.m[i][1] * kab[3 + j] + r.m[i][2] * kab[6 + j];
        for (int i = 0; i < 3; i++) /* rk = tmp R^T */
          for (int j = 0; j < 3; j++)
            rk[i][j] = tmp[i][0] * r.m[j][0] + tmp[i][1] * r.m[j][1] + tmp[i][2] * r.m[j][2];
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
}

static int step(void *self, const tb_step *in, tb_error *err) {
  tb_fem *f = self;
  assemble(f);
  return tb_fem_advance(f, in, 0, 1, err);
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

static const tb_setting settings[] = {TB_FEM_SETTINGS};

const tb_model_class tb_model_fem_corot = {
    .name = "fem-corot",
    .summary = "corotational (warped-stiffness) FEM, Müller & Gross 2004, refactored each step",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(tb_fem_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = tb_fem_masses,
    .correct = tb_fem_correct,
};
