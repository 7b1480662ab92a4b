/* Position-based dynamics with per-tet strain-energy constraints: the
 * 2022 patent's pbd-stvk (SPEC §2.5; "a collision simulation method of soft
 * tissue and rigid ground", eqs. 2-4 and §[0128]-[0172]) and XPBD beside it
 * (Macklin, Müller & Chentanez 2016, "XPBD: position-based simulation of
 * compliant constrained dynamics"). The step is in pbd_solve.c.
 *
 * Material. The patent calls k both the constraints' stiffness in [0, 1]
 * and "Young's modulus" (its examples: k = 0.4, nu = 0.4). Here E and nu
 * give the Lame parameters (mu = E / (2 (1 + nu)), lambda = E nu / ((1 + nu)
 * (1 - 2 nu))) of the energy psi, and k scales PBD's projection. PBD's
 * projection -C grad C / |grad C|^2 is invariant to scaling the energy, so
 * in pbd-stvk E's magnitude has no effect on the motion: its stiffness is
 * set by k, the iterations and dt (and nu, the ratio of lambda to mu); E
 * only scales the stresses and the energy reported. In xpbd-stvk E is the
 * real modulus (compliance 1 on C = sqrt(2 V psi)) and k is not used: the
 * result converges to backward Euler of the material as iterations grow.
 *
 * Energies: St. Venant-Kirchhoff (the patent's) or compressible
 * Neo-Hookean (energy=neohookean). Inversion: StVK's energy vanishes on
 * the mirror image of a tet's rest shape, so a tet pushed through itself
 * would come to rest inverted with C = 0, and Neo-Hookean's is undefined
 * for det F <= 0. Both are handled: an inverted or flat tet gets the
 * invertible stress of Irving et al. 2004 (pbd_solve.c), which pushes it
 * back; the scene's detector still counts inverted tets (or stops on them
 * with inversion=1). tests/test_pbd.c restores a mirrored tet with both.
 *
 * Damping: rayleigh_stiffness (constraint damping of strain rates, like
 * fem's Rayleigh b; pbd_solve.c says how each model applies it)
 * and damping (Müller 2007: velocities relative to the rigid motion).
 *
 * The ground is projected with the tets (own_ground): see pbd_solve.c.
 *
 * Cutting removes the tets the blade touches (carve.c): their constraints
 * leave the schedule, the masses are lumped again from the tets left. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbd_priv.h"

static void destroy(void *self) {
  pbd *s = self;
  if (!s) return;
  free(s->x), free(s->xm1), free(s->p), free(s->v), free(s->vm1), free(s->mass), free(s->invm),
      free(s->w);
  free(s->depth), free(s->cids), free(s->cp), free(s->cdepth), free(s->cvn), free(s->keep),
      free(s->fric);
  free(s->tet), free(s->vol), free(s->dminv), free(s->lam), free(s->tmesh);
  free(s->xo), free(s->vo), free(s->hit), free(s->orig), free(s->cost), free(s->done);
  tb_tet_slabs_free(&s->sl);
  tb_carve_free(&s->carve);
  free(s);
}

static void *create_any(const tb_mesh *mesh, const void *settings, int xpbd, tb_error *err) {
  const pbd_settings *set = settings;
  const char *name = xpbd ? "xpbd-stvk" : "pbd-stvk";
  if (mesh->ntet < 1) {
    tb_error_set(err, name, 0, "needs a tet mesh (the mesh has no tets)");
    return NULL;
  }
  pbd *s = calloc(1, sizeof *s);
  if (!s) {
    tb_error_set(err, name, 0, "out of memory");
    return NULL;
  }
  s->xpbd = xpbd, s->set = *set;
  tb_lame(set->E, set->nu, &s->lambda, &s->mu);
  int nv = s->nv = mesh->nv, nt = s->nt = mesh->ntet;
  size_t V = (size_t)nv, T = (size_t)nt;
  s->x = malloc(sizeof(tb_vec3) * V), s->xm1 = malloc(sizeof(tb_vec3) * V);
  s->p = malloc(sizeof(tb_vec3) * V), s->v = calloc(V, sizeof(tb_vec3));
  s->vm1 = calloc(V, sizeof(tb_vec3));
  s->mass = malloc(sizeof(double) * V), s->invm = malloc(sizeof(double) * V);
  s->w = malloc(sizeof(double) * V), s->depth = calloc(V, sizeof(double));
  s->cids = malloc(sizeof(int) * V), s->cp = malloc(sizeof(tb_vec3) * V);
  s->cdepth = malloc(sizeof(double) * V), s->cvn = malloc(sizeof(double) * V);
  s->keep = malloc(sizeof(double) * V), s->fric = calloc(V, sizeof(tb_vec3));
  s->tet = malloc(sizeof *s->tet * T), s->vol = malloc(sizeof(double) * T);
  s->dminv = malloc(sizeof *s->dminv * T), s->lam = calloc(T, sizeof(double));
  s->tmesh = malloc(sizeof(int) * 4 * T);
  s->xo = malloc(sizeof(tb_vec3) * V), s->vo = calloc(V, sizeof(tb_vec3));
  if (!s->x || !s->xm1 || !s->p || !s->v || !s->vm1 || !s->mass || !s->invm || !s->w || !s->depth ||
      !s->cids || !s->cp || !s->cdepth || !s->cvn || !s->keep || !s->fric || !s->tet || !s->vol ||
      !s->dminv || !s->lam || !s->tmesh || !s->xo || !s->vo) {
    tb_error_set(err, name, 0, "out of memory (%d nodes, %d tets)", nv, nt);
    goto fail;
  }
  if (tb_check_tets(mesh, err) || tb_carve_init(&s->carve, mesh, name, err) ||
      tb_lumped_masses(mesh, set->density, set->node_mass, s->carve.mass, err) ||
      tb_tet_slabs_build(mesh, TB_SWEEP_SLABS, &s->sl, err))
    goto fail;
  const int *old = s->sl.old, *order = s->sl.order;
  for (int n = 0; n < nv; n++) {
    s->mass[n] = s->carve.mass[old[n]], s->invm[n] = 1 / s->mass[n];
    s->x[n] = s->xm1[n] = s->p[n] = mesh->x[old[n]];
  }
  memcpy(s->xo, mesh->x, sizeof(tb_vec3) * V);
  for (int k = 0; k < nt; k++) { /* schedule order: nodes, volume, D_m^-1 */
    const int *e = mesh->tet + 4 * order[k];
    for (int j = 0; j < 4; j++) s->tet[k][j] = s->sl.nw[e[j]];
    tb_vec3 x3 = mesh->x[e[3]];
    tb_mat3 dm;
    for (int j = 0; j < 3; j++) {
      tb_vec3 d = tb_sub(mesh->x[e[j]], x3);
      dm.m[0][j] = d.x, dm.m[1][j] = d.y, dm.m[2][j] = d.z;
    }
    s->vol[k] = tb_tet_volume(mesh->x[e[0]], mesh->x[e[1]], mesh->x[e[2]], x3);
    tb_mat3 inv;
    if (!tb_m3_inverse(dm, &inv)) { /* volume > 0 (tb_check_tets) but numerically flat */
      tb_error_set(err, "mesh", 0, "tet %d is degenerate (volume %g)", order[k], s->vol[k]);
      goto fail;
    }
    for (int r = 0; r < 3; r++)
      for (int c = 0; c < 3; c++) s->dminv[k][3 * r + c] = inv.m[r][c];
  }
  s->hit = calloc(T, 1), s->orig = malloc(sizeof(int) * T);
  s->cost = malloc(sizeof(double) * (size_t)s->sl.ntasks);
  s->done = malloc(sizeof(atomic_int) * (size_t)s->sl.ntasks);
  if (!s->hit || !s->orig || !s->cost || !s->done) {
    tb_error_set(err, name, 0, "out of memory");
    goto fail;
  }
  memcpy(s->orig, order, sizeof(int) * T);
  for (int q = 0; q < s->sl.ntasks; q++) {
    s->cost[q] = s->sl.task[q + 1] - s->sl.task[q];
    atomic_init(&s->done[q], 0);
  }
  return s;
fail:
  destroy(s);
  return NULL;
}

static void *create_pbd(const tb_mesh *mesh, const void *set, tb_error *err) {
  return create_any(mesh, set, 0, err);
}
static void *create_xpbd(const tb_mesh *mesh, const void *set, tb_error *err) {
  return create_any(mesh, set, 1, err);
}

static const tb_vec3 *positions(const void *self) { return ((const pbd *)self)->xo; }
static const tb_vec3 *velocities(const void *self) { return ((const pbd *)self)->vo; }
static const double *masses(const void *self) { return ((const pbd *)self)->carve.mass; }

/* Kinetic energy plus the strain energy of the material E, nu names (for
 * pbd-stvk a measure, not a conserved quantity: see the head of the file).
 * A Neo-Hookean tet with det F <= 0 has infinite energy. */
static double energy(const void *self) {
  const pbd *s = self;
  double e = 0;
  for (int i = 0; i < s->nv; i++) e += 0.5 * s->mass[i] * tb_dot(s->v[i], s->v[i]);
  for (int t = 0; t < s->nt; t++) {
    const int *n = s->tet[t];
    const double *D = s->dminv[t];
    double F[9], P[9], psi;
    pbd_deformation(s->x, n, D, F);
    if (!pbd_energy(s->set.energy, s->mu, s->lambda, F, &psi, P)) return INFINITY;
    e += s->vol[t] * psi;
  }
  return e;
}

/* Contact response between steps: the BDF2 history is made consistent
 * with the new state (x_{n-1} = x - dt v, v_{n-1} = v). */
static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  pbd *s = self;
  for (int k = 0; k < n; k++) {
    int i = s->sl.nw[ids[k]];
    if (x) s->x[i] = s->xo[ids[k]] = x[k];
    if (v) s->v[i] = s->vo[ids[k]] = v[k];
    s->xm1[i] = s->have_prev ? tb_madd(s->x[i], -s->last_dt, s->v[i]) : s->x[i];
    s->vm1[i] = s->v[i];
  }
}

/* A cut event: at MOVE the tets the blade touched leave every per-tet
 * array (the schedule's order kept), then the masses and the surface follow. */
static int cut(void *self, const tb_cut_event *ev, tb_cut_stats *st, tb_error *err) {
  pbd *s = self;
  int nhit = tb_carve_event(&s->carve, ev, s->x, (const int *)s->tet, s->nt, NULL, s->hit, err);
  if (nhit < 0) return -1;
  if (ev->kind == TB_CUT_END && st) tb_carve_stats(&s->carve, st);
  if (nhit == 0) return 0;
  int n = 0, *task = s->sl.task;
  for (int q = 0; q < s->sl.ntasks; q++) {
    int a = task[q], b = task[q + 1];
    task[q] = n;
    for (int t = a; t < b; t++) {
      if (s->hit[t]) {
        s->carve.alive[s->orig[t]] = 0;
        continue;
      }
      s->orig[n] = s->orig[t];
      memcpy(s->tet[n], s->tet[t], sizeof s->tet[n]);
      memcpy(s->dminv[n], s->dminv[t], sizeof s->dminv[n]);
      s->vol[n] = s->vol[t], s->lam[n] = s->lam[t];
      n++;
    }
  }
  task[s->sl.ntasks] = n;
  memset(s->hit, 0, (size_t)s->nt);
  s->nt = n;
  for (int t = 0; t < n; t++)
    for (int j = 0; j < 4; j++) s->tmesh[4 * t + j] = s->sl.old[s->tet[t][j]];
  if (tb_carve_update(&s->carve, s->tmesh, n, NULL, nhit, s->set.density, s->set.node_mass, err))
    return -1;
  for (int i = 0; i < s->nv; i++) {
    s->mass[i] = s->carve.mass[s->sl.old[i]], s->invm[i] = 1 / s->mass[i];
  }
  return 0;
}

static const unsigned char *tets_alive(const void *self) {
  return ((const pbd *)self)->carve.alive;
}

static tb_surface surface(const void *self) {
  const pbd *s = self;
  return tb_carve_surface(&s->carve, s->xo);
}

#define S pbd_settings
#define COMMON(integ)                                                                      \
  TB_SETTINGS_MASS(S, 0.0),                                                                \
      TB_SETTING_YOUNG(S,                                                                  \
                       "Young's modulus (pbd-stvk: scales only the "                       \
                       "stresses and energy reported)"),                                   \
      TB_SETTING_R(S, nu, 0.4, -1.0, 0.5, TB_OPEN_LO | TB_OPEN_HI,                         \
                   "Poisson ratio (the patent's 0.4)"),                                    \
      TB_SETTING_R(S, rayleigh_stiffness, 0.02, 0.0, HUGE_VAL, 0,                          \
                   "constraint damping b (fem's Rayleigh b): damps strain rates, not the " \
                   "rest (xpbd: Macklin 2016 eq. 26; pbd: on the velocities)"),            \
      TB_SETTING_R(S, damping, 0.0, 0.0, HUGE_VAL, 0,                                      \
                   "per second: velocities relative to the body's rigid motion decay as "  \
                   "exp(-damping t) (Muller et al. 2007, 3.5)"),                           \
      TB_SETTING_I(S, iterations, 5, 1, 10000,                                             \
                   "Gauss-Seidel sweeps per step (the patent: 3-8, 5)"),                   \
      TB_SETTING_C(S, energy, PBD_STVK, 1, "stvk|neohookean",                              \
                   "strain energy: St. Venant-Kirchhoff (the patent) or compressible "     \
                   "Neo-Hookean"),                                                         \
      TB_SETTING_C(S, integrator, integ, 2, "bdf2|patent|euler",                           \
                   "bdf2: second-order backward differences for prediction and velocity; " \
                   "patent: its eqs 2-3 with the BDF2 velocity (falls at 2g); euler: "     \
                   "symplectic prediction, first-order velocity (XPBD's)")
static const tb_setting pbd_table[] = {
    COMMON(PBD_BDF2),
    TB_SETTING_R(S, k, 0.4, 0.0, 1.0, 0,
                 "stiffness: the share of each projection applied (the patent's 0.4)"),
};
static const tb_setting xpbd_table[] = {COMMON(PBD_EULER)};
#undef COMMON
#undef S

const tb_model_class tb_model_pbd_stvk = {
    .name = "pbd-stvk",
    .summary =
        "position-based dynamics, per-tet StVK energy constraints, ground in the solve, "
        "BDF2 velocity (2022 patent)",
    .settings = pbd_table,
    .nsettings = (int)(sizeof pbd_table / sizeof pbd_table[0]),
    .settings_size = sizeof(pbd_settings),
    .create = create_pbd,
    .step = pbd_step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
    .own_ground = 1,
    .cut = cut,
    .surface = surface,
    .tets_alive = tets_alive,
};

const tb_model_class tb_model_xpbd_stvk = {
    .name = "xpbd-stvk",
    .summary =
        "XPBD (Macklin et al. 2016): the same constraints with compliance from E, "
        "converging to backward Euler",
    .settings = xpbd_table,
    .nsettings = (int)(sizeof xpbd_table / sizeof xpbd_table[0]),
    .settings_size = sizeof(pbd_settings),
    .create = create_xpbd,
    .step = pbd_step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
    .own_ground = 1,
    .cut = cut,
    .surface = surface,
    .tets_alive = tets_alive,
};
