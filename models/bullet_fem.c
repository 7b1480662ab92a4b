/* bullet-fem: Bullet's deformable FEM (btDeformableMultiBodyDynamicsWorld,
 * btDeformableBodySolver: one Newton iteration of backward Euler with its
 * CG solve and projections) as a peer deformation model, through
 * models/tb_deformable.h (ref_deformable.cpp says what Bullet does).
 *
 * force picks Bullet's element force: neohookean (btDeformableNeoHookeanForce),
 * linear (btDeformableLinearElasticityForce: despite its name corotated
 * linear elasticity, small strain of R^T F; so it compares with our
 * fem-corot rather than fem) or corotated
 * (btDeformableCorotatedForce, which has no force differential: Bullet's
 * implicit step treats it explicitly, and it blows up beyond the explicit
 * limit; shown, not hidden, in the suites). E and nu become Lamé mu =
 * E / (2 (1 + nu)), lambda = E nu / ((1 + nu)(1 - 2 nu)). Node masses
 * density * (volume of the node's tets) / 4, or node_mass. Gravity through
 * btDeformableGravityForce, external node forces as a force of ours on
 * Bullet's right-hand side, prescribed nodes as Bullet's zero-inverse-mass
 * (Dirichlet) nodes moved to their positions within the step.
 *
 * Damping as Bullet's forces take it: damping is neohookean's damping and
 * linear's damping_beta (damping stresses from damping * mu, damping *
 * lambda on the strain rate: stiffness-proportional, like our fem's
 * rayleigh_stiffness); damping_mass is linear's damping_alpha (a force
 * -alpha m v, like rayleigh_mass). Bullet's corotated force has no
 * damping: it ignores both (documented in the table, not rejected, so the
 * defaults work for every force).
 *
 * Ground: Bullet's deformable contacts are against rigid collision objects
 * through its sparse SDF (convex shapes only; no plane); this model does
 * not build one, so the scene corrects ground contacts after each step
 * (own_ground 0). Energy: Bullet's elastic energy of the force (less its
 * value at rest) plus the kinetic energy (NAN for corotated: Bullet's force
 * has no energy). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_deformable.h"
#include "tb_model.h"

typedef struct bfem_settings {
  double density, node_mass, E, nu, damping, damping_mass;
  int force, implicit;
} bfem_settings;

typedef struct bfem {
  tb_deformable *b;
  double *mass;
  int nv;
} bfem;

static void destroy(void *self) {
  bfem *s = self;
  if (!s) return;
  if (s->b) tb_deformable_destroy(s->b);
  free(s->mass);
  free(s);
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const bfem_settings *def = settings;
  if (tb_check_tets(mesh, err)) return NULL;
  if (mesh->ntet < 1) {
    tb_error_set(err, "bullet-fem", 0, "needs a tet mesh (the mesh has no tets)");
    return NULL;
  }
  bfem *s = calloc(1, sizeof *s);
  if (!s || !(s->mass = malloc(sizeof(double) * (size_t)mesh->nv))) {
    free(s);
    tb_error_set(err, "bullet-fem", 0, "out of memory");
    return NULL;
  }
  s->nv = mesh->nv;
  if (tb_lumped_masses(mesh, def->density, def->node_mass, s->mass, err)) goto fail;
  tb_deformable_def d = {.force = def->force,
                         .E = def->E,
                         .nu = def->nu,
                         .damping = def->force == TB_DEFORMABLE_COROTATED ? 0 : def->damping,
                         .damping_mass = def->force == TB_DEFORMABLE_LINEAR ? def->damping_mass : 0,
                         .implicit = def->implicit};
  if (def->force != TB_DEFORMABLE_LINEAR && def->damping_mass != 0) {
    tb_error_set(err, "bullet-fem", 0,
                 "damping_mass = %g: only force=linear has a mass damping (Bullet's "
                 "damping_alpha)",
                 def->damping_mass);
    goto fail;
  }
  s->b = tb_deformable_create(mesh, s->mass, &d, err);
  if (!s->b) goto fail;
  return s;
fail:
  destroy(s);
  return NULL;
}

static int step(void *self, const tb_step *in, tb_error *err) {
  bfem *s = self;
  return tb_deformable_step(s->b, in->dt, in->gravity, in->force, in->nfixed, in->fixed,
                            in->fixed_x, err);
}

static const tb_vec3 *positions(const void *self) {
  return tb_deformable_positions(((const bfem *)self)->b);
}
static const tb_vec3 *velocities(const void *self) {
  return tb_deformable_velocities(((const bfem *)self)->b);
}
static const double *masses(const void *self) { return ((const bfem *)self)->mass; }

static double energy(const void *self) {
  const bfem *s = self;
  double w = tb_deformable_elastic_energy(s->b), t = 0;
  const tb_vec3 *v = tb_deformable_velocities(s->b);
  for (int i = 0; i < s->nv; i++) t += 0.5 * s->mass[i] * tb_dot(v[i], v[i]);
  return w + t;
}

static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  tb_deformable_correct(((bfem *)self)->b, n, ids, x, v);
}

#define S bfem_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 0.0),
    TB_SETTINGS_MATERIAL(S),
    TB_SETTING_C(S, force, 0, 2, "neohookean|linear|corotated",
                 "Bullet's element force (corotated: no force differential, no damping)"),
    TB_SETTING_R(S, damping, 0.02, 0.0, HUGE_VAL, 0,
                 "stiffness damping: neohookean's damping, linear's damping_beta"),
    TB_SETTING_R(S, damping_mass, 0.0, 0.0, HUGE_VAL, 0,
                 "mass damping: linear's damping_alpha (other forces: must be 0)"),
    TB_SETTING_I(S, implicit, 1, 0, 1, "1: Bullet's implicit (backward Euler) step; 0: explicit"),
};
#undef S

const tb_model_class tb_model_bullet_fem = {
    .name = "bullet-fem",
    .peer = 1,
    .summary =
        "Bullet 3.24's deformable FEM: backward Euler (1 Newton step, CG, projections), "
        "neohookean|linear|corotated force",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(bfem_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
};
