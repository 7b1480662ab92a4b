// Reference mesh-mesh collision from FCL 0.7 (Debian libfcl-dev):
// fcl::BVHModel<AABB<double>> and BVHModel<OBBRSS<double>>, and the public
// C entry points of tb_refbvh.h for every kind (Bullet's kinds are built in
// ref_bvh_bullet.cpp).
//
// Build: beginModel / addSubModel(vertices, triangles) / endModel from the
// world-space vertices, with FCL's default fitter and splitter
// (SPLIT_METHOD_MEAN: at the mean of the triangle centroids along the box's
// longest side, or along the OBB's first axis for OBBRSS); triangle numbers
// are FCL's primitive ids.
//
// Query: FCL's own traversal node driven directly, both models at the
// identity transform: MeshCollisionTraversalNode<AABB> or
// MeshCollisionTraversalNodeOBBRSS, initialize(), collide(&node). That is the
// traversal fcl::collide() runs, without its per-call overhead: for AABB
// (BVHCollideImpl in collision_func_matrix-inl.h) fcl::collide deep-copies
// both BVHModels on every call, identity transform or not, and on a
// non-identity transform also transforms every vertex and refits the copy
// (fcl issue #38, "Collision detection between meshes"; the same copy is
// still open in FCL's fork coal, coal issue #559). OBBRSS goes through
// orientedMeshCollide, which does not copy. Measured (throwaway program in
// /tmp, -O2, 2-core machine shared with other jobs) on the liver's 9813 tet
// faces against the 1248-triangle instrument with 287 intersecting pairs:
// fcl::collide 0.74 ms (AABB) / 0.94 ms (OBBRSS), the direct traversal
// 0.58 ms / 0.92 ms; with 0 pairs fcl::collide on AABB still takes 0.14 ms,
// the two model copies. The direct traversal is the one timed here, so FCL
// is charged only for its traversal and triangle tests.
//
// Every intersecting pair: CollisionRequest(num_max_contacts, enable_contact
// = false) with num_max_contacts = ntri_a * ntri_b. num_max_contacts bounds
// the contacts of one object pair, not of the query (fcl issue #465); the
// leaf test adds one Contact (b1, b2 = the primitive ids) per intersecting
// triangle pair and the traversal stops only when num_max_contacts contacts
// are stored, so it never stops early. The result's vector grows with the
// pairs found only (nothing is reserved from num_max_contacts). With
// enable_contact = true FCL may add two contacts for one pair, so it stays
// off. The leaf test is fcl::detail::Intersect::intersect_Triangle (see
// ref_fcl.cpp for its known wrong answers); each leaf holds one triangle and
// each leaf pair is visited once, so pairs come out without duplicates.
//
// Update: beginUpdateModel / updateSubModel(new vertices) /
// endUpdateModel(refit = true, bottomup = true): leaves refit, parents merged,
// the tree's shape kept. FCL fits each refit leaf around the triangle's
// previous and new positions (its continuous-collision swept volume,
// recursiveRefitTree_bottomup in BVH_model-inl.h), so refit volumes are
// looser than freshly built ones (tests/test_refbvh.c checks the pair sets
// after refits). OBBRSS refit merges oriented boxes up the tree and is far
// slower than AABB refit (liver: 30 ms against 0.8 ms). (fcl issue #577:
// updating vertices does not refresh a CollisionObject's AABB; no
// CollisionObject is used here.)
//
// FCL reports misuse on std::cerr and returns BVH_ERR_* codes; codes and
// exceptions become tb_error.
#include <fcl/geometry/bvh/BVH_model.h>
#include <fcl/math/bv/AABB.h>
#include <fcl/math/bv/OBBRSS.h>
#include <fcl/math/bv/utility.h>
#include <fcl/narrowphase/collision_request.h>
#include <fcl/narrowphase/collision_result.h>
#include <fcl/narrowphase/detail/traversal/collision/mesh_collision_traversal_node.h>
#include <fcl/narrowphase/detail/traversal/collision_node.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <stdexcept>
#include <vector>

#include "refbvh_priv.h"

namespace {

typedef fcl::AABB<double> Aabb;
typedef fcl::OBBRSS<double> Obbrss;

// The traversal nodes differ per volume: the generic node takes the models
// non-const (it would transform them in place on a non-identity transform;
// at the identity it leaves them alone), the OBBRSS node const.
void traverse(fcl::BVHModel<Aabb> &a, fcl::BVHModel<Aabb> &b,
              const fcl::CollisionRequest<double> &req, fcl::CollisionResult<double> &res) {
  fcl::detail::MeshCollisionTraversalNode<Aabb> node;
  fcl::Transform3<double> ta = fcl::Transform3<double>::Identity();
  fcl::Transform3<double> tb = fcl::Transform3<double>::Identity();
  if (!fcl::detail::initialize(node, a, ta, b, tb, req, res))
    throw std::runtime_error("initialize");
  fcl::detail::collide<double>(&node);
}

void traverse(fcl::BVHModel<Obbrss> &a, fcl::BVHModel<Obbrss> &b,
              const fcl::CollisionRequest<double> &req, fcl::CollisionResult<double> &res) {
  fcl::detail::MeshCollisionTraversalNodeOBBRSS<double> node;
  const fcl::Transform3<double> id = fcl::Transform3<double>::Identity();
  if (!fcl::detail::initialize(node, a, id, b, id, req, res))
    throw std::runtime_error("initialize");
  fcl::detail::collide<double>(&node);
}

template <typename BV>
struct FclModel : tb_ref_bvh {
  fcl::BVHModel<BV> model;
  std::vector<fcl::Vector3<double>> pos;  // vertex buffer for build and update
  fcl::CollisionResult<double> result;    // reused, so its vector keeps capacity

  FclModel(tb_ref_kind k, int n_vertices, int n_triangles)
      : tb_ref_bvh(k, n_vertices, n_triangles) {}

  void load(const tb_vec3 *x) {
    pos.resize((size_t)nv);
    for (int i = 0; i < nv; i++) pos[(size_t)i] = fcl::Vector3<double>(x[i].x, x[i].y, x[i].z);
  }

  int fail(const char *what, int code, tb_error *err) {
    return tb_error_set(err, tb_refbvh_name(kind), 0, "FCL %s failed (BVH code %d)", what, code);
  }

  int build(const tb_vec3 *x, const int *tri, tb_error *err) {
    load(x);
    std::vector<fcl::Triangle> t((size_t)ntri);
    for (int i = 0; i < ntri; i++)
      t[(size_t)i] =
          fcl::Triangle((size_t)tri[3 * i], (size_t)tri[3 * i + 1], (size_t)tri[3 * i + 2]);
    int rc = model.beginModel(ntri, nv);
    if (rc != fcl::BVH_OK) return fail("beginModel", rc, err);
    rc = model.addSubModel(pos, t);
    if (rc != fcl::BVH_OK) return fail("addSubModel", rc, err);
    rc = model.endModel();
    if (rc != fcl::BVH_OK) return fail("endModel", rc, err);
    return 0;
  }

  int update(const tb_vec3 *x, tb_error *err) override {
    load(x);
    int rc = model.beginUpdateModel();
    if (rc != fcl::BVH_OK) return fail("beginUpdateModel", rc, err);
    rc = model.updateSubModel(pos);
    if (rc != fcl::BVH_OK) return fail("updateSubModel", rc, err);
    rc = model.endUpdateModel(true, true);
    if (rc != fcl::BVH_OK) return fail("endUpdateModel", rc, err);
    return 0;
  }

  int collide(tb_ref_bvh &other, tb_pairlist *out, tb_error *err) override {
    FclModel<BV> &b = static_cast<FclModel<BV> &>(other);
    const size_t max_pairs = (size_t)ntri * (size_t)b.ntri;
    fcl::CollisionRequest<double> req(max_pairs, false);
    result.clear();
    traverse(model, b.model, req, result);
    for (size_t k = 0; k < result.numContacts(); k++) {
      const fcl::Contact<double> &c = result.getContact(k);
      if (tb_refbvh_push(out, (int)c.b1, (int)c.b2))
        return tb_error_set(err, tb_refbvh_name(kind), 0, "out of memory");
    }
    return 0;
  }
};

template <typename BV>
tb_ref_bvh *fcl_new(tb_ref_kind kind, const tb_vec3 *x, int nv, const int *tri, int ntri,
                    tb_error *err) {
  FclModel<BV> *m = new FclModel<BV>(kind, nv, ntri);
  if (m->build(x, tri, err)) {
    delete m;
    return NULL;
  }
  return m;
}

// The mesh must be usable by every library: FCL and Bullet index without
// checks, and non-finite coordinates poison their volume fitting.
int check_mesh(const char *name, const tb_vec3 *x, int nv, const int *tri, int ntri,
               tb_error *err) {
  if (nv <= 0 || !x) return tb_error_set(err, name, 0, "mesh has no vertices");
  if (ntri <= 0 || !tri) return tb_error_set(err, name, 0, "mesh has no triangles");
  for (int i = 0; i < nv; i++)
    if (!tb_isfinite3(x[i])) return tb_error_set(err, name, 0, "vertex %d is not finite", i);
  for (int i = 0; i < 3 * ntri; i++)
    if (tri[i] < 0 || tri[i] >= nv)
      return tb_error_set(err, name, 0, "triangle %d uses vertex %d, outside 0..%d", i / 3, tri[i],
                          nv - 1);
  return 0;
}

// Runs f, turning exceptions into err; returns f's result or fallback.
template <typename R, typename F>
R guarded(const char *name, R fallback, tb_error *err, F f) {
  try {
    return f();
  } catch (const std::bad_alloc &) {
    tb_error_set(err, name, 0, "out of memory");
  } catch (const std::exception &e) {
    tb_error_set(err, name, 0, "library error: %s", e.what());
  } catch (...) {
    tb_error_set(err, name, 0, "library error (unknown exception)");
  }
  return fallback;
}

}  // namespace

const char *tb_refbvh_name(tb_ref_kind kind) {
  switch (kind) {
    case TB_REF_FCL_AABB:
      return "fcl-aabb";
    case TB_REF_FCL_OBBRSS:
      return "fcl-obbrss";
    case TB_REF_BULLET_GIMPACT:
      return "bullet-gimpact";
    case TB_REF_BULLET_GIMPACT_EXACT:
      return "bullet-gimpact-exact";
  }
  return NULL;
}

int tb_refbvh_push(tb_pairlist *out, int i, int j) {
  if (out->n >= out->cap) {
    if (out->cap > (1 << 28)) return -1;
    const int cap = out->cap > 0 ? 2 * out->cap : 256;
    int *ij = (int *)std::realloc(out->ij, sizeof(int) * 2 * (size_t)cap);
    if (!ij) return -1;
    out->ij = ij;
    out->cap = cap;
  }
  out->ij[2 * out->n] = i;
  out->ij[2 * out->n + 1] = j;
  out->n++;
  return 0;
}

extern "C" tb_ref_bvh *tb_ref_bvh_build(tb_ref_kind kind, const tb_vec3 *x, int nv, const int *tri,
                                        int ntri, tb_error *err) {
  // A C caller may pass any int; C++ may not load an enum outside its
  // values (UBSan's -fsanitize=enum), so the bytes are checked first.
  unsigned raw;
  static_assert(sizeof raw == sizeof kind, "tb_ref_kind is not int-sized");
  std::memcpy(&raw, &kind, sizeof raw);
  if (raw > (unsigned)TB_REF_BULLET_GIMPACT_EXACT) {
    tb_error_set(err, "refbvh", 0, "unknown reference kind %d", (int)raw);
    return NULL;
  }
  const char *name = tb_refbvh_name(kind);
  if (check_mesh(name, x, nv, tri, ntri, err)) return NULL;
  return guarded<tb_ref_bvh *>(name, NULL, err, [&]() -> tb_ref_bvh * {
    switch (kind) {
      case TB_REF_FCL_AABB:
        return fcl_new<Aabb>(kind, x, nv, tri, ntri, err);
      case TB_REF_FCL_OBBRSS:
        return fcl_new<Obbrss>(kind, x, nv, tri, ntri, err);
      default:
        return tb_refbvh_bullet_new(kind, x, nv, tri, ntri, err);
    }
  });
}

extern "C" int tb_ref_bvh_update(tb_ref_bvh *m, const tb_vec3 *x, tb_error *err) {
  if (!m) return tb_error_set(err, "refbvh", 0, "no model");
  const char *name = tb_refbvh_name(m->kind);
  if (!x) return tb_error_set(err, name, 0, "no vertices");
  for (int i = 0; i < m->nv; i++)
    if (!tb_isfinite3(x[i])) return tb_error_set(err, name, 0, "vertex %d is not finite", i);
  return guarded<int>(name, -1, err, [&]() { return m->update(x, err); });
}

extern "C" int tb_ref_bvh_collide(tb_ref_bvh *a, tb_ref_bvh *b, tb_pairlist *out, tb_error *err) {
  if (!a || !b || !out) return tb_error_set(err, "refbvh", 0, "no model or no pair list");
  const char *name = tb_refbvh_name(a->kind);
  if (a->kind != b->kind)
    return tb_error_set(err, name, 0, "cannot collide with a %s model", tb_refbvh_name(b->kind));
  return guarded<int>(name, -1, err, [&]() { return a->collide(*b, out, err); });
}

extern "C" void tb_ref_bvh_free(tb_ref_bvh *m) { delete m; }
