// Reference mesh-mesh collision from Bullet's GImpact (libbullet 3.24, double
// precision: pkg-config bullet-float64, BT_USE_DOUBLE_PRECISION).
//
// Build: a btTriangleIndexVertexArray over our own copy of the vertices
// (doubles, read in place, PHY_DOUBLE) and triangles (PHY_INTEGER), a
// btGImpactMeshShape over it (one btGImpactMeshShapePart, whose
// TrimeshPrimitiveManager reads the triangles), margin set to 0, then
// updateBound(), which builds the part's btGImpactQuantizedBvh (buildSet).
// Triangle numbers are GImpact's primitive indices, i.e. ours.
//
// Query: btGImpactQuantizedBvh::find_collision(bvh_a, identity, bvh_b,
// identity, pairs) gives the candidate pairs, the leaf-box overlaps GImpact's
// own gimpact_vs_gimpact pipeline feeds to its triangle test. Then
//  - bullet-gimpact: each candidate through Bullet's triangle test exactly as
//    tb_tritri_bullet (ref_bullet.cpp) runs it: btPrimitiveTriangle from the
//    primitive manager (margin 0), buildTriPlane(),
//    find_triangle_collision_clip_method();
//  - bullet-gimpact-exact: the same candidates through tb_tritri_exact.
// Bullet's test keeps its known wrong answers (ref_bullet.cpp): on the
// liver's faces against the instrument it adds 130 non-intersecting pairs to
// 287 true ones (746 to 1106); in 116 of the 130 one triangle lies wholly
// behind the other's plane, which the one-sided clip test takes for
// penetration. Every candidate pair appears once (one triangle per leaf), so
// there are no duplicates.
//
// Margins: the part's TrimeshPrimitiveManager starts with margin 0.1 (0.01
// for the default constructor) and grows every triangle's box by it;
// btGImpactMeshShape::setMargin(0) sets 0 on every part, so leaf boxes are
// the triangles' exact min/max boxes before quantization. Box tests during
// the traversal add BT_BOX_BOX_TRANSFORM_CACHE's 1e-6 * |R| slack (even at
// the identity), which only widens them.
//
// Known inexactness of the candidates: GImpact stores boxes quantized to 16
// bits per axis over the mesh's box enlarged by 1.0 on every side
// (btQuantizedBvhTree::calc_quantization, boundMargin = 1), and quantizes by
// rounding to nearest (bt_quantize_clamp adds 0.5), not outward: a box edge
// may move inward by half a quantum (extent + 2) / 65535 / 2, so a pair whose
// triangle boxes overlap by less than about a quantum on some axis can be
// missed, with either triangle test. Such misses are Bullet's answer and are
// kept; tests/test_refbvh.c checks that every pair bullet-gimpact leaves out
// is of that kind (on its meshes bullet-gimpact-exact misses none).
//
// Update: the vertex copy is overwritten in place, then postUpdate() and
// updateBound(), which refits the quantized tree bottom-up
// (btGImpactQuantizedBvh::refit) with the quantization range of the build.
// Refit clamps boxes to that range, so a mesh that grows past it is no
// longer found (bullet3 issue #4588, refit after scaling a GImpact mesh);
// when any triangle vertex leaves the range the shape is rebuilt instead
// (a new btGImpactMeshShape and buildSet), as that workaround does.

// Bullet's GImpact headers copy btAABB through an implicit assignment that
// -Wdeprecated-copy flags (btAABB declares a copy constructor only).
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wdeprecated-copy"
#include <BulletCollision/CollisionShapes/btTriangleIndexVertexArray.h>
#include <BulletCollision/Gimpact/btGImpactQuantizedBvh.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <BulletCollision/Gimpact/btTriangleShapeEx.h>
#pragma GCC diagnostic pop

#include <memory>
#include <vector>

#include "refbvh_priv.h"

extern "C" {
#include "collision/tb_tritri.h"
}

namespace {

// Locks a part's primitive manager (points it at the vertex and index
// arrays) for the lifetime of the guard; locks nest.
struct PartLock {
  const btGImpactMeshShapePart *part;
  explicit PartLock(const btGImpactMeshShapePart *p) : part(p) { part->lockChildShapes(); }
  ~PartLock() { part->unlockChildShapes(); }
};

struct BulletModel : tb_ref_bvh {
  std::vector<double> xyz;  // 3 per vertex, read by Bullet in place
  std::vector<int> idx;     // 3 per triangle
  std::unique_ptr<btTriangleIndexVertexArray> array;
  std::unique_ptr<btGImpactMeshShape> shape;
  double qlo[3], qhi[3];  // quantization range of the last build
  btPairSet pairs;        // candidates, reused

  BulletModel(tb_ref_kind k, int n_vertices, int n_triangles)
      : tb_ref_bvh(k, n_vertices, n_triangles) {}

  const btGImpactMeshShapePart *part() const { return shape->getMeshPart(0); }

  void load(const tb_vec3 *x) {
    for (int i = 0; i < nv; i++) {
      xyz[3 * (size_t)i] = x[i].x;
      xyz[3 * (size_t)i + 1] = x[i].y;
      xyz[3 * (size_t)i + 2] = x[i].z;
    }
  }

  // The box of the triangles' vertices, as buildSet merges it, enlarged by
  // calc_quantization's 1.0; 1 when every triangle vertex lies in the range
  // of the last build.
  int in_range(int record) {
    double lo[3] = {xyz[3 * (size_t)idx[0]], xyz[3 * (size_t)idx[0] + 1],
                    xyz[3 * (size_t)idx[0] + 2]};
    double hi[3] = {lo[0], lo[1], lo[2]};
    for (size_t k = 0; k < idx.size(); k++)
      for (int d = 0; d < 3; d++) {
        const double v = xyz[3 * (size_t)idx[k] + (size_t)d];
        if (v < lo[d]) lo[d] = v;
        if (v > hi[d]) hi[d] = v;
      }
    if (record) {
      for (int d = 0; d < 3; d++) qlo[d] = lo[d] - 1.0, qhi[d] = hi[d] + 1.0;
      return 1;
    }
    for (int d = 0; d < 3; d++)
      if (lo[d] < qlo[d] || hi[d] > qhi[d]) return 0;
    return 1;
  }

  // A new shape over the arrays and its quantized tree (buildSet).
  void make_shape() {
    shape.reset();
    shape.reset(new btGImpactMeshShape(array.get()));
    shape->setMargin(0);
    shape->updateBound();
    in_range(1);
  }

  int build(const tb_vec3 *x, const int *tri) {
    xyz.resize(3 * (size_t)nv);
    idx.assign(tri, tri + 3 * (size_t)ntri);
    load(x);
    array.reset(new btTriangleIndexVertexArray(ntri, idx.data(), 3 * (int)sizeof(int), nv,
                                               xyz.data(), 3 * (int)sizeof(double)));
    make_shape();
    return 0;
  }

  int update(const tb_vec3 *x, tb_error *) override {
    load(x);
    if (in_range(0)) {
      shape->postUpdate();
      shape->updateBound();
    } else {
      make_shape();
    }
    return 0;
  }

  int collide(tb_ref_bvh &other, tb_pairlist *out, tb_error *err) override {
    BulletModel &b = static_cast<BulletModel &>(other);
    btTransform id;
    id.setIdentity();
    pairs.resizeNoInitialize(0);
    btGImpactQuantizedBvh::find_collision(part()->getBoxSet(), id, b.part()->getBoxSet(), id,
                                          pairs);
    const int exact = kind == TB_REF_BULLET_GIMPACT_EXACT;
    PartLock la(part()), lb(b.part());
    const btPrimitiveManagerBase *ma = part()->getPrimitiveManager();
    const btPrimitiveManagerBase *mb = b.part()->getPrimitiveManager();
    for (int k = 0; k < pairs.size(); k++) {
      const int i = pairs[k].m_index1, j = pairs[k].m_index2;
      int hit;
      if (exact) {
        tb_vec3 p[3], q[3];
        for (int c = 0; c < 3; c++) {
          const double *u = &xyz[3 * (size_t)idx[3 * (size_t)i + (size_t)c]];
          const double *w = &b.xyz[3 * (size_t)b.idx[3 * (size_t)j + (size_t)c]];
          p[c] = tb_v3(u[0], u[1], u[2]);
          q[c] = tb_v3(w[0], w[1], w[2]);
        }
        hit = tb_tritri_exact(p, q);
      } else {
        btPrimitiveTriangle ta, tb;
        ma->get_primitive_triangle(i, ta);
        mb->get_primitive_triangle(j, tb);
        ta.buildTriPlane();
        tb.buildTriPlane();
        GIM_TRIANGLE_CONTACT contact;
        hit = ta.find_triangle_collision_clip_method(tb, contact) ? 1 : 0;
      }
      if (hit && tb_refbvh_push(out, i, j))
        return tb_error_set(err, tb_refbvh_name(kind), 0, "out of memory");
    }
    return 0;
  }
};

}  // namespace

tb_ref_bvh *tb_refbvh_bullet_new(tb_ref_kind kind, const tb_vec3 *x, int nv, const int *tri,
                                 int ntri, tb_error *err) {
  (void)err;  // Bullet reports nothing; exceptions are caught by the caller
  std::unique_ptr<BulletModel> m(new BulletModel(kind, nv, ntri));
  m->build(x, tri);
  return m.release();
}
