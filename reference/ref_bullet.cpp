// Reference adapter: Bullet's GImpact triangle-triangle test behind
// tb_tritri_bullet().
//
// btPrimitiveTriangle::find_triangle_collision_clip_method
// (BulletCollision/Gimpact/btTriangleShapeEx.h, double-precision Bullet
// 3.24, BT_USE_DOUBLE_PRECISION from pkg-config bullet-float64). Both
// triangles get margin 0 (the class default is 0.01) and their planes from
// buildTriPlane(); the answer is the call's return value. How it decides:
// clip the other triangle by this triangle's three edge planes (a point counts
// as inside up to SIMD_EPSILON = DBL_EPSILON past a plane), keep the clipped
// points on or behind this triangle's plane (signed distance <= margin = 0),
// then the same with the roles swapped; intersecting when both keep a point.
// GImpact's own pipeline (btGImpactCollisionAlgorithm::collide_sat_triangles)
// calls overlap_test_conservative() first; with margin 0 that pre-filter
// rejects only pairs the clip method rejects too (in exact arithmetic), so it
// is left out here.
// Used as is, without patches; its known wrong answers:
//  - the "behind the plane" test is one-sided, so separated triangles each
//    lying behind the other's plane (e.g. parallel triangles back to back,
//    normals pointing away from each other) are reported as intersecting;
//  - a zero-area triangle has no plane (buildTriPlane normalises a zero
//    vector into NaNs), so every pair with a zero-area triangle is reported
//    as not intersecting, touching or not;
//  - planes and clipped points are rounded, so near-coplanar and
//    near-touching pairs can be decided wrong either way.
#include <BulletCollision/Gimpact/btTriangleShapeEx.h>

extern "C" {
#include "tb_oracles.h"
}

static void bullet_triangle(btPrimitiveTriangle &t, const tb_vec3 v[3]) {
  for (int i = 0; i < 3; i++) t.m_vertices[i].setValue(v[i].x, v[i].y, v[i].z);
  t.m_margin = 0;
  t.buildTriPlane();
}

extern "C" int tb_tritri_bullet(const tb_vec3 p[3], const tb_vec3 q[3]) {
  btPrimitiveTriangle a, b;
  bullet_triangle(a, p);
  bullet_triangle(b, q);
  GIM_TRIANGLE_CONTACT contact;
  return a.find_triangle_collision_clip_method(b, contact) ? 1 : 0;
}
