/* bullet-softbody: Bullet's classic soft body (btSoftBody 3.24, double
 * precision) as a peer deformation model, through models/tb_softbody.h:
 * one node per mesh node, one link (Bullet's distance constraint with
 * linear stiffness kLST, solved by its position solver, piterations
 * iterations a step) per tet edge; see models/bullet_softbody_peer.cpp.
 *
 * Settings: stiffness is the links' kLST in (0, 1] and iterations the
 * position iterations: Bullet's links have no modulus, so E and nu are in
 * the table (as every model's) but not read. Node masses density * (volume
 * of the node's tets) / 4, or node_mass; damping is Bullet's kDP (a share
 * of the velocity removed per step). Gravity as Bullet's world gravity,
 * external node forces through btSoftBody::addForce, prescribed nodes as
 * Bullet's zero-mass nodes moved to their positions within the step.
 *
 * Ground: by default left to the scene (its contact and Coulomb friction,
 * as for the other models that do not own it); contact=bullet gives it to
 * Bullet, as a Bullet user has it: at the first step that has a ground, a
 * static box whose top face is the ground plane
 * (models/bullet_softbody_peer.cpp); a node nearer than the margin is a
 * contact, moved the hardness's share of the way out per iteration, with
 * the ground's kinetic friction as the links' kDF (Bullet has no static
 * friction). Energy: NAN (Bullet's links have no energy). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_model.h"
#include "tb_softbody.h"

typedef struct bsb_settings {
  double density, node_mass, E, nu, stiffness, damping;
  int iterations;
  int contact; /* CONTACT_* */
  double hardness, margin;
} bsb_settings;

enum { CONTACT_SCENE = 0, CONTACT_BULLET = 1 };

typedef struct bsb {
  tb_softbody *b;
  int own_ground; /* contact=bullet */
  int nv;
  double *mass;
  tb_vec3 *x, *v; /* copies of Bullet's node state, for the C side */
} bsb;

static void destroy(void *self) {
  bsb *s = self;
  if (!s) return;
  if (s->b) tb_softbody_destroy(s->b);
  free(s->mass), free(s->x), free(s->v);
  free(s);
}

static void *create(const tb_mesh *mesh, const void *settings, tb_error *err) {
  const bsb_settings *def = settings;
  if (tb_check_tets(mesh, err)) return NULL;
  if (mesh->ntet < 1) {
    tb_error_set(err, "bullet-softbody", 0, "needs a tet mesh (the mesh has no tets)");
    return NULL;
  }
  bsb *s = calloc(1, sizeof *s);
  if (!s) {
    tb_error_set(err, "bullet-softbody", 0, "out of memory");
    return NULL;
  }
  size_t nv = (size_t)mesh->nv;
  s->nv = mesh->nv;
  s->mass = malloc(sizeof(double) * nv);
  s->x = malloc(sizeof(tb_vec3) * nv);
  s->v = calloc(nv, sizeof(tb_vec3));
  if (!s->mass || !s->x || !s->v) {
    tb_error_set(err, "bullet-softbody", 0, "out of memory");
    goto fail;
  }
  if (tb_lumped_masses(mesh, def->density, def->node_mass, s->mass, err)) goto fail;
  tb_softbody_def d = tb_softbody_default_def();
  d.density = def->density > 0 ? def->density : 1; /* masses given below */
  d.mass = s->mass;
  d.stiffness = def->stiffness;
  d.iterations = def->iterations;
  d.damping = def->damping;
  d.hardness = def->hardness;
  tb_vec3 lo, hi;
  tb_mesh_bbox(mesh, &lo, &hi);
  d.margin = def->margin * tb_len(tb_sub(hi, lo));
  s->b = tb_softbody_create(mesh, &d, err);
  if (!s->b) goto fail;
  s->own_ground = def->contact == CONTACT_BULLET;
  tb_softbody_positions(s->b, s->x);
  return s;
fail:
  destroy(s);
  return NULL;
}

static int step(void *self, const tb_step *in, tb_error *err) {
  bsb *s = self;
  if (s->own_ground && in->ground && !tb_softbody_has_ground(s->b) &&
      tb_softbody_set_ground(s->b, in->ground->p, in->ground->n, in->ground->mu_k, err))
    return -1;
  int rc = tb_softbody_step_nodes(s->b, in->dt, in->gravity, in->force, in->nfixed, in->fixed,
                                  in->fixed_x, err);
  tb_softbody_positions(s->b, s->x);
  tb_softbody_velocities(s->b, s->v);
  return rc;
}

static const tb_vec3 *positions(const void *self) { return ((const bsb *)self)->x; }
static int owns_ground(const void *self) { return ((const bsb *)self)->own_ground; }
static const tb_vec3 *velocities(const void *self) { return ((const bsb *)self)->v; }
static const double *masses(const void *self) { return ((const bsb *)self)->mass; }
static double energy(const void *self) {
  (void)self;
  return NAN;
}

static void correct(void *self, int n, const int *ids, const tb_vec3 *x, const tb_vec3 *v) {
  bsb *s = self;
  tb_softbody_correct(s->b, n, ids, x, v);
  for (int k = 0; k < n; k++) {
    if (x) s->x[ids[k]] = x[k];
    if (v) s->v[ids[k]] = v[k];
  }
}

#define S bsb_settings
static const tb_setting settings[] = {
    TB_SETTINGS_MASS(S, 0.0),
    TB_SETTING_YOUNG(S, "not read: Bullet's links have no modulus (stiffness sets them)"),
    TB_SETTING_R(S, nu, 0.3, -1.0, 0.5, TB_OPEN_LO | TB_OPEN_HI, "not read (as E)"),
    TB_SETTING_R(S, stiffness, 1.0, 0.0, 1.0, TB_OPEN_LO,
                 "the links' linear stiffness, Bullet's Material::m_kLST"),
    TB_SETTING_I(S, iterations, 5, 1, 1000, "position solver iterations, Bullet's piterations"),
    TB_SETTING_R(S, damping, 0.0, 0.0, 1.0, 0, "Bullet's velocity damping kDP"),
    TB_SETTING_C(S, contact, CONTACT_SCENE, 1, "scene|bullet",
                 "the ground's contact: the scene's (Coulomb friction), or Bullet's own"),
    TB_SETTING_R(S, hardness, 1.0, 0.0, 1.0, TB_OPEN_LO,
                 "contact=bullet: share of a contact's depth corrected per iteration (kKHR)"),
    TB_SETTING_R(S, margin, 1e-3, 0.0, 1.0, TB_OPEN_LO,
                 "contact=bullet: contact margin, a share of the mesh's box diagonal"),
};
#undef S

const tb_model_class tb_model_bullet_softbody = {
    .name = "bullet-softbody",
    .peer = 1,
    .summary = "Bullet 3.24's classic btSoftBody: a link per tet edge, its position solver",
    .settings = settings,
    .nsettings = (int)(sizeof settings / sizeof settings[0]),
    .settings_size = sizeof(bsb_settings),
    .create = create,
    .step = step,
    .positions = positions,
    .velocities = velocities,
    .energy = energy,
    .destroy = destroy,
    .masses = masses,
    .correct = correct,
    .owns_ground = owns_ground,
};
