// Reference adapter: Bullet's classic soft body (btSoftBody, Debian's
// libbullet-dev 3.24 in double precision: libBulletSoftBody-float64 from
// pkg-config bullet-float64, BT_USE_DOUBLE_PRECISION) behind the C API of
// tb_softbody.h, as a speed peer of pbd-stvk on the liver-drop scene.
//
// Build: btSoftBody(worldInfo, nv, x, m) with our node masses (density x a
// quarter of each incident tet's volume), then appendLink(i, j) once per
// distinct tet edge (tb_mesh_edges order) with the default material, whose
// m_kLST is the stiffness. No tetras, faces or clusters: Bullet's tetras
// are not used by its classic solver, and setVolumeMass/setVolumeDensity
// would redistribute our masses. Config: piterations = iterations, kDF =
// friction, kDP = damping, kKHR = hardness (Bullet's hardness of contacts
// with static and kinematic bodies; its default 0.1 corrects a tenth of a
// contact's depth per iteration, so a resting body sinks in), viterations 0
// and collisions SDF_RS (Bullet's defaults); the collision margin is set on
// the body's shape.
//
// World: btSoftRigidDynamicsWorld over btSoftBodyRigidBodyCollisionConfiguration,
// btCollisionDispatcher, btDbvtBroadphase, btSequentialImpulseConstraintSolver;
// gravity in both the world and its btSoftBodyWorldInfo; the world info's
// btSparseSDF initialised. Each step is stepSimulation(dt, 0) (one step of
// exactly dt, no interpolation), then the sparse SDF's garbage collection,
// as Bullet's soft-body demos do.
//
// Ground: Bullet's soft bodies meet rigid bodies through a sparse signed
// distance field that btSparseSDF::DistanceToShape evaluates only for
// convex shapes (it returns 0 for others), so btStaticPlaneShape, being
// concave, would give no contact. The ground is therefore a static
// btBoxShape (mass 0, friction 1) whose top face lies in the ground plane:
// half-extents 10 body diagonals + 10 in the plane, one diagonal thick. A
// node closer than the margin to it is a contact (Bullet's PSolve_RContacts
// moves it the hardness's share of the way to the margin each iteration,
// with friction kDF x 1).
//
// Models (tb_softbody_step_nodes, for models/bullet_softbody.c): node
// masses may be given instead of the density's; gravity is set in the
// world and its world info each step; external node forces go through
// btSoftBody::addForce (m_f, applied in predictMotion, none on zero-mass
// nodes); a prescribed node gets setMass(i, 0) (Bullet's fixed node: no
// gravity, force or link correction moves it; setMass also marks the
// links' constants for an update) and the velocity (fixed_x - x) / dt
// before the step, which predictMotion integrates, and after the step
// exactly fixed_x and that velocity; leaving the set gives its mass back.
// Bullet hands the soft-body solver dt as a float
// (btSoftRigidDynamicsWorld::predictUnconstraintMotion: float(timeStep)),
// so positions follow dt rounded to float.
//
// Threads: Bullet's default soft-body solver (btDefaultSoftBodySolver) runs
// on the calling thread.

// Bullet's headers leave virtual defaults' parameters unnamed-but-unused.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>
#pragma GCC diagnostic pop

#include <cmath>
#include <cstdlib>
#include <new>
#include <vector>

extern "C" {
#include "tb_softbody.h"
}

struct tb_softbody {
  btSoftBodyRigidBodyCollisionConfiguration config;
  btCollisionDispatcher dispatcher;
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btSoftRigidDynamicsWorld world;
  btBoxShape *ground_shape = nullptr;
  btDefaultMotionState *ground_motion = nullptr;
  btRigidBody *ground = nullptr;
  btSoftBody *body = nullptr;
  double total_mass = 0;
  std::vector<double> mass;          // the node masses given at create
  std::vector<unsigned char> fixed;  // prescribed in the last tb_softbody_step_nodes
  std::vector<btVector3> vfix;       // a prescribed node's velocity in this step
  double diag = 0;                   // the rest mesh's bounding-box diagonal

  tb_softbody() : dispatcher(&config), world(&dispatcher, &broadphase, &solver, &config, nullptr) {}
  ~tb_softbody() {
    if (body) {
      world.removeSoftBody(body);
      delete body;
    }
    if (ground) {
      world.removeRigidBody(ground);
      delete ground;
    }
    delete ground_motion;
    delete ground_shape;
  }
};

extern "C" tb_softbody_def tb_softbody_default_def(void) {
  tb_softbody_def d;
  d.density = 1, d.stiffness = 1, d.iterations = 1, d.friction = 0.2, d.damping = 0;
  d.hardness = 0.1;
  d.margin = 0.25;
  d.gravity = tb_v3(0, 0, 0);
  d.has_ground = 0;
  d.ground_p = tb_v3(0, 0, 0), d.ground_n = tb_v3(0, 0, 1);
  d.mass = nullptr;
  return d;
}

static btVector3 bt(tb_vec3 v) { return btVector3(v.x, v.y, v.z); }

// The static box whose top face is the ground plane (p, n).
static void add_ground(tb_softbody *b, tb_vec3 p, tb_vec3 n_in) {
  double half = 10 * b->diag + 10;
  b->ground_shape = new btBoxShape(btVector3(half, half, 0.5 * b->diag));
  btVector3 n = bt(n_in).normalized();
  btTransform tr;
  tr.setIdentity();
  tr.setRotation(shortestArcQuat(btVector3(0, 0, 1), n));
  tr.setOrigin(bt(p) - n * (0.5 * b->diag));
  b->ground_motion = new btDefaultMotionState(tr);
  btRigidBody::btRigidBodyConstructionInfo info(0, b->ground_motion, b->ground_shape);
  info.m_friction = 1;
  b->ground = new btRigidBody(info);
  b->world.addRigidBody(b->ground);
}

extern "C" tb_softbody *tb_softbody_create(const tb_mesh *mesh, const tb_softbody_def *def,
                                           tb_error *err) {
  if (mesh->ntet < 1) {
    tb_error_set(err, "btSoftBody", 0, "needs a tet mesh (the mesh has no tets)");
    return nullptr;
  }
  if (!(def->density > 0) || !(def->stiffness > 0 && def->stiffness <= 1) || def->iterations < 1 ||
      !(def->friction >= 0 && def->friction <= 1) || !(def->damping >= 0 && def->damping <= 1) ||
      !(def->hardness > 0 && def->hardness <= 1) || !(def->margin > 0) ||
      (def->has_ground && !(tb_len(def->ground_n) > 0))) {
    tb_error_set(err, "btSoftBody", 0,
                 "bad settings: density %g > 0, stiffness %g in (0, 1], iterations %d >= 1, "
                 "friction %g and damping %g in [0, 1], hardness %g in (0, 1], margin %g > 0, "
                 "ground normal not zero",
                 def->density, def->stiffness, def->iterations, def->friction, def->damping,
                 def->hardness, def->margin);
    return nullptr;
  }
  int *edges = nullptr;
  tb_softbody *b = nullptr;
  try {
    std::vector<btScalar> mass((size_t)mesh->nv, 0.0);
    std::vector<btVector3> x((size_t)mesh->nv);
    for (int t = 0; t < mesh->ntet; t++) {
      const int *e = mesh->tet + 4 * t;
      double v = tb_tet_volume(mesh->x[e[0]], mesh->x[e[1]], mesh->x[e[2]], mesh->x[e[3]]);
      if (!(v > 0)) {
        tb_error_set(err, "mesh", 0, "tet %d has volume %g <= 0", t, v);
        return nullptr;
      }
      for (int k = 0; k < 4; k++) mass[(size_t)e[k]] += 0.25 * def->density * v;
    }
    if (def->mass)
      for (int i = 0; i < mesh->nv; i++) mass[(size_t)i] = def->mass[i];
    for (int i = 0; i < mesh->nv; i++) {
      if (!(mass[(size_t)i] > 0)) {
        tb_error_set(err, "mesh", 0, "node %d is in no tet (no mass)", i);
        return nullptr;
      }
      x[(size_t)i] = bt(mesh->x[i]);
    }
    int ne = tb_mesh_edges(mesh, &edges);
    if (ne < 0) throw std::bad_alloc();
    b = new tb_softbody();
    tb_vec3 lo, hi;
    tb_mesh_bbox(mesh, &lo, &hi);
    b->diag = tb_len(tb_sub(hi, lo));
    b->mass.assign(mass.begin(), mass.end());
    b->fixed.assign((size_t)mesh->nv, 0);
    b->vfix.assign((size_t)mesh->nv, btVector3(0, 0, 0));
    btSoftBodyWorldInfo &wi = b->world.getWorldInfo();
    wi.m_gravity = bt(def->gravity);
    wi.m_sparsesdf.Initialize();
    b->world.setGravity(bt(def->gravity));
    b->body = new btSoftBody(&wi, mesh->nv, x.data(), mass.data());
    btSoftBody *sb = b->body;
    sb->m_materials[0]->m_kLST = def->stiffness;
    for (int k = 0; k < ne; k++) sb->appendLink(edges[2 * k], edges[2 * k + 1]);
    sb->m_cfg.piterations = def->iterations;
    sb->m_cfg.kDF = def->friction;
    sb->m_cfg.kDP = def->damping;
    sb->m_cfg.kKHR = def->hardness;
    sb->getCollisionShape()->setMargin(def->margin);
    b->total_mass = sb->getTotalMass();
    b->world.addSoftBody(sb);
    if (def->has_ground) add_ground(b, def->ground_p, def->ground_n);
  } catch (const std::bad_alloc &) {
    delete b;
    free(edges);
    tb_error_set(err, "btSoftBody", 0, "out of memory (%d nodes, %d tets)", mesh->nv, mesh->ntet);
    return nullptr;
  }
  free(edges);
  return b;
}

extern "C" int tb_softbody_set_ground(tb_softbody *b, tb_vec3 p, tb_vec3 n, double friction,
                                      tb_error *err) {
  if (b->ground) return tb_error_set(err, "btSoftBody", 0, "the body has a ground already");
  if (!(tb_len(n) > 0) || !(friction >= 0 && friction <= 1))
    return tb_error_set(err, "btSoftBody", 0, "bad ground: normal not zero, friction %g in [0, 1]",
                        friction);
  try {
    add_ground(b, p, n);
  } catch (const std::bad_alloc &) {
    return tb_error_set(err, "btSoftBody", 0, "out of memory");
  }
  b->body->m_cfg.kDF = friction;
  return 0;
}

extern "C" int tb_softbody_has_ground(const tb_softbody *b) { return b->ground != nullptr; }

extern "C" int tb_softbody_step(tb_softbody *b, double dt, tb_error *err) {
  if (!(dt > 0) || !std::isfinite(dt))
    return tb_error_set(err, "btSoftBody", 0, "dt must be > 0 (got %g)", dt);
  b->world.stepSimulation(dt, 0);
  b->world.getWorldInfo().m_sparsesdf.GarbageCollect();
  return 0;
}

extern "C" int tb_softbody_step_nodes(tb_softbody *b, double dt, tb_vec3 g, const tb_vec3 *force,
                                      int nfixed, const int *fixed, const tb_vec3 *fixed_x,
                                      tb_error *err) {
  btSoftBody *sb = b->body;
  const int nv = sb->m_nodes.size();
  if (!(dt > 0) || !std::isfinite(dt))
    return tb_error_set(err, "btSoftBody", 0, "dt must be > 0 (got %g)", dt);
  if (nfixed < 0 || (nfixed > 0 && (!fixed || !fixed_x)))
    return tb_error_set(err, "btSoftBody", 0, "bad prescribed set (nfixed %d)", nfixed);
  for (int p = 0; p < nfixed; p++)
    if (fixed[p] < 0 || fixed[p] >= nv || (p > 0 && fixed[p] <= fixed[p - 1]))
      return tb_error_set(err, "btSoftBody", 0,
                          "prescribed nodes must be strictly ascending in [0, %d): entry %d is %d",
                          nv, p, fixed[p]);
  btSoftBodyWorldInfo &wi = b->world.getWorldInfo();
  wi.m_gravity = bt(g);
  b->world.setGravity(bt(g));
  // setMass marks the links' constants for an update (m_bUpdateRtCst)
  for (int i = 0, p = 0; i < nv; i++) {
    const bool now = p < nfixed && fixed[p] == i;
    if (now) {
      if (!b->fixed[(size_t)i]) sb->setMass(i, 0);
      sb->m_nodes[i].m_v = b->vfix[(size_t)i] = (bt(fixed_x[p]) - sb->m_nodes[i].m_x) / dt;
      p++;
    } else if (b->fixed[(size_t)i]) {
      sb->setMass(i, b->mass[(size_t)i]);
    }
  }
  if (force)
    for (int i = 0; i < nv; i++) sb->addForce(bt(force[i]), i);  // m_f, ignored at zero mass
  b->world.stepSimulation(dt, 0);
  wi.m_sparsesdf.GarbageCollect();
  for (int i = 0, p = 0; i < nv; i++) {
    const bool now = p < nfixed && fixed[p] == i;
    b->fixed[(size_t)i] = now;
    if (now) {
      sb->m_nodes[i].m_v = b->vfix[(size_t)i];
      sb->m_nodes[i].m_x = bt(fixed_x[p]);
      p++;
    }
  }
  return 0;
}

extern "C" void tb_softbody_velocities(const tb_softbody *b, tb_vec3 *v) {
  const btSoftBody::tNodeArray &n = b->body->m_nodes;
  for (int i = 0; i < n.size(); i++) v[i] = tb_v3(n[i].m_v.x(), n[i].m_v.y(), n[i].m_v.z());
}

extern "C" void tb_softbody_correct(tb_softbody *b, int n, const int *ids, const tb_vec3 *x,
                                    const tb_vec3 *v) {
  btSoftBody::tNodeArray &nodes = b->body->m_nodes;
  for (int k = 0; k < n; k++) {
    if (x) nodes[ids[k]].m_x = bt(x[k]);
    if (v) nodes[ids[k]].m_v = bt(v[k]);
  }
}

extern "C" void tb_softbody_positions(const tb_softbody *b, tb_vec3 *x) {
  const btSoftBody::tNodeArray &n = b->body->m_nodes;
  for (int i = 0; i < n.size(); i++) x[i] = tb_v3(n[i].m_x.x(), n[i].m_x.y(), n[i].m_x.z());
}

extern "C" int tb_softbody_nodes(const tb_softbody *b) { return b->body->m_nodes.size(); }
extern "C" int tb_softbody_links(const tb_softbody *b) { return b->body->m_links.size(); }
extern "C" double tb_softbody_total_mass(const tb_softbody *b) { return b->total_mass; }

extern "C" void tb_softbody_destroy(tb_softbody *b) { delete b; }
