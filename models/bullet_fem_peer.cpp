// Reference adapter: Bullet's deformable world (Debian's libbullet-dev 3.24
// in double precision: libBulletSoftBody-float64 from pkg-config
// bullet-float64) behind the C API of tb_deformable.h, as a peer of our fem
// and fem-corot.
//
// World, as Bullet's DeformableDemo/VolumetricDeformable.cpp sets it up:
// btDeformableMultiBodyDynamicsWorld over btSoftBodyRigidBodyCollisionConfiguration,
// btCollisionDispatcher, btDbvtBroadphase and a btDeformableMultiBodyConstraintSolver
// whose deformable solver is a btDeformableBodySolver; setImplicit(implicit),
// setLineSearch(false), setUseProjection(true) (Dirichlet nodes and contacts
// as projections in the CG solve, with Bullet's mass preconditioner; it
// also turns Bullet's strain limiting on). No rigid bodies: the ground is
// left to the scene (see models/bullet_fem.c).
//
// What one implicit step does (btDeformableBodySolver, 3.24): the elastic
// force at x_n is first applied explicitly to the velocities, and then
// discarded again (setupDeformableSolve resets v to v_n); one Newton
// iteration (m_maxNewtonIterations = 1) solves
//   (M - dt D - dt^2 K) dv = dt (f_el(x_n + dt v_n) + f_damp(v_n) + M g + f_ext),
// (D, K the force's damping and stiffness differentials at x_n + dt v_n) by
// CG (at most 300 iterations), v_{n+1} = v_n + dv, x_{n+1} = x_n + dt v_{n+1}:
// linearised backward Euler around the predicted position. Under gravity
// alone this is v_{n+1} = v_n + dt g, x_{n+1} = x_n + dt v_{n+1} (symplectic
// Euler), exactly, since a rigid translation has no elastic force and one
// CG iteration solves M dv = dt M g. The velocities are clamped to
// m_maxDisplacement / dt per component (1000 / dt: not reached here).
//
// Body: btSoftBody(worldInfo, nv, x, m) with the model's lumped masses, one
// appendTetra per mesh tet (mesh order, mesh orientation: positive volume),
// then initializeDmInverse and the tet scratch arrays, as
// btSoftBodyHelpers::CreateFromTetGenData does; no links or faces (the
// deformable forces read only the tets; with no faces Bullet's CCD has
// nothing to do). Sleeping is off (m_sleepingThreshold 0 and
// DISABLE_DEACTIVATION), as in the demo, so a body at rest keeps stepping.
//
// Forces (btDeformableMultiBodyDynamicsWorld::addForce): one elastic force,
// btDeformableNeoHookeanForce(mu, lambda, damping),
// btDeformableLinearElasticityForce(mu, lambda, damping_alpha, damping_beta)
// or btDeformableCorotatedForce(mu, lambda), with Lamé mu, lambda from E, nu;
// a btDeformableGravityForce whose m_gravity is the step's gravity; and the
// step's external node forces through a small force of our own (NodeForce
// below), which adds them to Bullet's right-hand side as its gravity force
// does. Bullet's corotated force implements neither force differential, so
// its implicit step is explicit in the elasticity (the system matrix is M):
// it blows up beyond the explicit stability limit, and it has no energy.
//
// Energy: the force's totalElasticEnergy at the current positions minus its
// value at rest (Bullet's neo-Hookean density, Smith et al. 2018's stable
// form, is not 0 at F = I). Bullet's linear force is in fact corotated: its
// stress comes from the small strain of R^T F with R the tets' m_corotation,
// while its energy density takes the small strain of F itself (not rotation
// invariant); we report what Bullet computes.
//
// Prescribed nodes: Bullet's Dirichlet nodes are nodes of zero inverse mass
// (btDeformableContactProjection makes them static constraints: their dv is
// projected to 0, so they keep v_n). Before a step each prescribed node
// gets m_im = 0 and v_n = m_v = m_vn = (fixed_x - x) / dt, so Bullet moves it
// to fixed_x while the free nodes feel it moving; after the step its
// position is set to fixed_x exactly (removing the rounding of x + dt v) and
// its velocity stays (fixed_x - x) / dt. A node that leaves the prescribed
// set gets its inverse mass back.
//
// Threads: Bullet's deformable solver runs on the calling thread.

// Bullet's deformable headers have unused parameters and variables,
// misordered initialisers and deprecated copies: not ours to fix.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-variable"
#pragma GCC diagnostic ignored "-Wreorder"
#pragma GCC diagnostic ignored "-Wdeprecated-copy"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableCorotatedForce.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableLinearElasticityForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btDeformableNeoHookeanForce.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <cstring>
#include <new>
#include <vector>

extern "C" {
#include "tb_deformable.h"
}

namespace {

// External node forces as a Lagrangian force: added to the right-hand side
// (explicit and implicit alike), no differentials. Bullet's addForce merges
// forces of one type, so this one takes a type of its own: 7, outside
// Bullet's enumerators (1..6) but inside the enumeration's range.
class NodeForce : public btDeformableLagrangianForce {
 public:
  const tb_vec3 *f = nullptr;  // nv forces for this step, or none

  void add(btScalar scale, TVStack &force) {
    if (!f) return;
    for (int i = 0; i < m_softBodies.size(); ++i) {
      btSoftBody *psb = m_softBodies[i];
      for (int j = 0; j < psb->m_nodes.size(); ++j) {
        const btSoftBody::Node &n = psb->m_nodes[j];
        if (n.m_im > 0) force[n.index] += scale * btVector3(f[j].x, f[j].y, f[j].z);
      }
    }
  }
  void addScaledForces(btScalar scale, TVStack &force) override { add(scale, force); }
  void addScaledExplicitForce(btScalar scale, TVStack &force) override { add(scale, force); }
  void addScaledDampingForce(btScalar, TVStack &) override {}
  void addScaledElasticForceDifferential(btScalar, const TVStack &, TVStack &) override {}
  void addScaledDampingForceDifferential(btScalar, const TVStack &, TVStack &) override {}
  void buildDampingForceDifferentialDiagonal(btScalar, TVStack &) override {}
  btDeformableLagrangianForceType getForceType() override {
    return static_cast<btDeformableLagrangianForceType>(7);
  }
};

}  // namespace

struct tb_deformable {
  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher;
  btDbvtBroadphase broadphase;
  btDeformableBodySolver body_solver;
  btDeformableMultiBodyConstraintSolver solver;
  btDeformableMultiBodyDynamicsWorld *world = nullptr;
  btSoftBody *body = nullptr;
  btDeformableLagrangianForce *elastic = nullptr;
  btDeformableGravityForce *gravity = nullptr;
  NodeForce *external = nullptr;
  int force = 0;
  double rest_energy = 0;  // Bullet's elastic energy at rest (neohookean's is not 0)
  std::vector<double> mass;
  std::vector<unsigned char> fixed;  // prescribed in the last step
  std::vector<tb_vec3> x, v;         // what the C side reads

  tb_deformable() : dispatcher(&config) { solver.setDeformableSolver(&body_solver); }
  ~tb_deformable() {
    if (world && body) {
      if (elastic) world->removeForce(body, elastic);
      if (gravity) world->removeForce(body, gravity);
      if (external) world->removeForce(body, external);
      world->removeSoftBody(body);
    }
    delete body;
    delete elastic;
    delete gravity;
    delete external;
    delete world;
  }
  void read_back() {
    const btSoftBody::tNodeArray &n = body->m_nodes;
    for (int i = 0; i < n.size(); i++) {
      x[(size_t)i] = tb_v3(n[i].m_x.x(), n[i].m_x.y(), n[i].m_x.z());
      v[(size_t)i] = tb_v3(n[i].m_v.x(), n[i].m_v.y(), n[i].m_v.z());
    }
  }
};

static btVector3 bt(tb_vec3 a) { return btVector3(a.x, a.y, a.z); }

extern "C" void tb_deformable_lame(double E, double nu, double *mu, double *lambda) {
  *mu = E / (2 * (1 + nu));
  *lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
}

extern "C" tb_deformable *tb_deformable_create(const tb_mesh *mesh, const double *mass,
                                               const tb_deformable_def *def, tb_error *err) {
  if (mesh->ntet < 1) {
    tb_error_set(err, "bullet-fem", 0, "needs a tet mesh (the mesh has no tets)");
    return nullptr;
  }
  if (def->force < 0 || def->force > 2 || !(def->E > 0) || !std::isfinite(def->E) ||
      !(def->nu > -1 && def->nu < 0.5) || !(def->damping >= 0) || !std::isfinite(def->damping) ||
      !(def->damping_mass >= 0) || !std::isfinite(def->damping_mass) ||
      (def->force != TB_DEFORMABLE_LINEAR && def->damping_mass != 0) ||
      (def->force == TB_DEFORMABLE_COROTATED && def->damping != 0) ||
      (def->implicit != 0 && def->implicit != 1)) {
    tb_error_set(err, "bullet-fem", 0,
                 "bad settings: force %d in {0 neohookean, 1 linear, 2 corotated}, E %g > 0, nu %g "
                 "in (-1, 0.5), damping %g >= 0 (0 for corotated: Bullet's has none), "
                 "damping_mass %g >= 0 (linear only), implicit %d in {0, 1}",
                 def->force, def->E, def->nu, def->damping, def->damping_mass, def->implicit);
    return nullptr;
  }
  tb_deformable *b = nullptr;
  try {
    std::vector<btVector3> x0((size_t)mesh->nv);
    std::vector<btScalar> m((size_t)mesh->nv);
    for (int i = 0; i < mesh->nv; i++) {
      if (!(mass[i] > 0) || !std::isfinite(mass[i])) {
        tb_error_set(err, "bullet-fem", 0, "node %d has mass %g (must be > 0)", i, mass[i]);
        return nullptr;
      }
      x0[(size_t)i] = bt(mesh->x[i]), m[(size_t)i] = mass[i];
    }
    for (int t = 0; t < mesh->ntet; t++) {
      const int *e = mesh->tet + 4 * t;
      for (int k = 0; k < 4; k++)
        if (e[k] < 0 || e[k] >= mesh->nv) {
          tb_error_set(err, "mesh", 0, "tet %d refers to node %d outside [0, %d)", t, e[k],
                       mesh->nv);
          return nullptr;
        }
      double vol = tb_tet_volume(mesh->x[e[0]], mesh->x[e[1]], mesh->x[e[2]], mesh->x[e[3]]);
      if (!(vol > 0)) {
        tb_error_set(err, "mesh", 0, "tet %d has volume %g <= 0", t, vol);
        return nullptr;
      }
    }
    b = new tb_deformable();
    b->world = new btDeformableMultiBodyDynamicsWorld(&b->dispatcher, &b->broadphase, &b->solver,
                                                      &b->config, &b->body_solver);
    btDeformableMultiBodyDynamicsWorld *w = b->world;
    w->setGravity(btVector3(0, 0, 0));
    w->getWorldInfo().m_gravity = btVector3(0, 0, 0);
    b->body = new btSoftBody(&w->getWorldInfo(), mesh->nv, x0.data(), m.data());
    btSoftBody *sb = b->body;
    for (int t = 0; t < mesh->ntet; t++) {
      const int *e = mesh->tet + 4 * t;
      sb->appendTetra(e[0], e[1], e[2], e[3]);
    }
    sb->initializeDmInverse();
    sb->m_tetraScratches.resize(sb->m_tetras.size());
    sb->m_tetraScratchesTn.resize(sb->m_tetras.size());
    sb->m_sleepingThreshold = 0;
    sb->setActivationState(DISABLE_DEACTIVATION);
    w->addSoftBody(sb);
    double mu, lambda;
    tb_deformable_lame(def->E, def->nu, &mu, &lambda);
    b->force = def->force;
    if (def->force == TB_DEFORMABLE_NEOHOOKEAN)
      b->elastic = new btDeformableNeoHookeanForce(mu, lambda, def->damping);
    else if (def->force == TB_DEFORMABLE_LINEAR)
      b->elastic =
          new btDeformableLinearElasticityForce(mu, lambda, def->damping_mass, def->damping);
    else
      b->elastic = new btDeformableCorotatedForce(mu, lambda);
    w->addForce(sb, b->elastic);
    b->gravity = new btDeformableGravityForce(btVector3(0, 0, 0));
    w->addForce(sb, b->gravity);
    b->external = new NodeForce();
    w->addForce(sb, b->external);
    w->setImplicit(def->implicit != 0);
    w->setLineSearch(false);
    w->setUseProjection(true);
    b->mass.assign(mass, mass + mesh->nv);
    b->fixed.assign((size_t)mesh->nv, 0);
    b->x.resize((size_t)mesh->nv);
    b->v.resize((size_t)mesh->nv);
    b->read_back();
    b->rest_energy = tb_deformable_elastic_energy(b);
  } catch (const std::bad_alloc &) {
    delete b;
    tb_error_set(err, "bullet-fem", 0, "out of memory (%d nodes, %d tets)", mesh->nv, mesh->ntet);
    return nullptr;
  }
  return b;
}

extern "C" int tb_deformable_step(tb_deformable *b, double dt, tb_vec3 g, const tb_vec3 *force,
                                  int nfixed, const int *fixed, const tb_vec3 *fixed_x,
                                  tb_error *err) {
  const int nv = (int)b->x.size();
  if (!(dt > 0) || !std::isfinite(dt))
    return tb_error_set(err, "bullet-fem", 0, "dt must be > 0 (got %g)", dt);
  if (nfixed < 0 || (nfixed > 0 && (!fixed || !fixed_x)))
    return tb_error_set(err, "bullet-fem", 0, "bad prescribed set (nfixed %d)", nfixed);
  for (int p = 0; p < nfixed; p++)
    if (fixed[p] < 0 || fixed[p] >= nv || (p > 0 && fixed[p] <= fixed[p - 1]))
      return tb_error_set(err, "bullet-fem", 0,
                          "prescribed nodes must be strictly ascending in [0, %d): entry %d is %d",
                          nv, p, fixed[p]);
  btSoftBody::tNodeArray &n = b->body->m_nodes;
  // the prescribed set: zero inverse mass now, mass back for nodes that left it
  int p = 0;
  for (int i = 0; i < nv; i++) {
    const bool now = p < nfixed && fixed[p] == i;
    if (now) {
      btSoftBody::Node &nd = n[i];
      const btVector3 target = bt(fixed_x[p]);
      nd.m_im = 0;
      nd.m_v = (target - nd.m_x) / dt;
      nd.m_vn = nd.m_v;
      p++;
    } else if (b->fixed[(size_t)i]) {
      n[i].m_im = 1.0 / b->mass[(size_t)i];
    }
  }
  b->gravity->m_gravity = bt(g);
  b->external->f = force;
  b->world->stepSimulation(dt, 0);
  b->external->f = nullptr;
  p = 0;
  for (int i = 0; i < nv; i++) {
    const bool now = p < nfixed && fixed[p] == i;
    b->fixed[(size_t)i] = now;
    if (now) {
      n[i].m_x = n[i].m_q = bt(fixed_x[p]);
      p++;
    }
  }
  b->read_back();
  return 0;
}

extern "C" const tb_vec3 *tb_deformable_positions(const tb_deformable *b) { return b->x.data(); }
extern "C" const tb_vec3 *tb_deformable_velocities(const tb_deformable *b) { return b->v.data(); }

extern "C" void tb_deformable_correct(tb_deformable *b, int n, const int *ids, const tb_vec3 *x,
                                      const tb_vec3 *v) {
  btSoftBody::tNodeArray &nodes = b->body->m_nodes;
  for (int k = 0; k < n; k++) {
    btSoftBody::Node &nd = nodes[ids[k]];
    if (x) nd.m_x = nd.m_q = bt(x[k]);
    if (v) nd.m_v = nd.m_vn = bt(v[k]);
  }
  b->read_back();
}

extern "C" double tb_deformable_elastic_energy(tb_deformable *b) {
  if (b->force == TB_DEFORMABLE_COROTATED) return NAN;
  btSoftBody *sb = b->body;
  // Bullet's energies read the tets' deformation at m_q: bring it to m_x
  for (int i = 0; i < sb->m_nodes.size(); i++) sb->m_nodes[i].m_q = sb->m_nodes[i].m_x;
  sb->updateDeformation();
  return b->elastic->totalElasticEnergy(0) - b->rest_energy;
}

extern "C" void tb_deformable_destroy(tb_deformable *b) { delete b; }
