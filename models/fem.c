/* Linear tetrahedral FEM (thesis §3.3.2, SPEC §2.2): linear shape
 * functions, small strain, isotropic (E, nu); the global stiffness K is
 * assembled once from K_e = V B^T D B and the elastic force is -K (x - X).
 * Implicit Euler with Rayleigh damping, or quasi-static solves, through the
 * shared core (fem_core.c): the CHOLMOD factor of the free-free block is
 * computed once and reused; it is redone only when the prescribed set or dt
 * changes. The assembly runs on threads (OpenMP) colour by colour
 * (tet_colour.c), bit-identical for any count. Not rotation invariant: a rigidly rotated body feels
 * large spurious forces (fem-corot removes them). */
#include <stddef.h>

#include "fem_priv.h"

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const tb_fem_settings *def = settings;
  tb_fem *f = tb_fem_create(mesh, def, 0, "fem", err);
  if (!f) return NULL;
    /* K = sum K_e, colour by colour: tets of one colour share no node, hence
     * no block, so every block sums its elements in the colouring's order
     * whatever the thread count */
#pragma omp parallel
  for (int c = 0; c < f->ncolours; c++) {
#pragma omp for schedule(static)
    for (int k = f->col_start[c]; k < f->col_start[c + 1]; k++) {
      int t = f->col_order[k];
      tb_fem_add_element(f, t, f->ke + 144 * (size_t)t);
    }
  }
  return f;
}

static int step(void *self, const tb_step *in, tb_error *err) {
  return tb_fem_advance(self, in, 1, 0, err);
}

static const tb_vec3 *positions(const void *self) { return ((const tb_fem *)self)->x; }
static const tb_vec3 *velocities(const void *self) { return ((const tb_fem *)self)->v; }

/* 1/2 u^T K u + 1/2 v^T M v, u = x - X. */
static double energy(const void *self) {
  const tb_fem *f = self;
  double e = 0;
  for (int i = 0; i < f->nv; i++) {
    tb_vec3 ui = tb_sub(f->x[i], f->X[i]);
    for (int p = f->row[i]; p < f->row[i + 1]; p++) {
      const double *k = f->kb + 9 * p;
      tb_vec3 u = tb_sub(f->x[f->col[p]], f->X[f->col[p]]);
      e += ui.x * (k[0] * u.x + k[1] * u.y + k[2] * u.z) +
           ui.y * (k[3] * u.x + k[4] * u.y + k[5] * u.z) +
           ui.z * (k[6] * u.x + k[7] * u.y + k[8] * u.z);
    }
  }
  return 0.5 * e + tb_fem_kinetic(f);
}

static void destroy(void *self) { tb_fem_destroy(self); }

static const tb_setting settings[] = {TB_FEM_SETTINGS};

const tb_model_class tb_model_fem = {
    .name = "fem",
    .summary = "linear tetrahedral FEM, implicit Euler + Rayleigh damping, CHOLMOD factor reused",
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
