// Reference adapter: FCL 0.7's triangle-triangle test behind tb_tritri_fcl().
//
// fcl::detail::Intersect<double>::intersect_Triangle (header
// fcl/narrowphase/detail/traversal/collision/intersect.h; the double
// instantiation is compiled into libfcl.so) is a separating-axis test in
// double arithmetic over 17 axes: the two normals, the nine edge-edge cross
// products and the six in-plane edge normals edge x normal. An axis separates
// only when the projected intervals are strictly apart, so touching counts as
// intersecting. Used as is, without patches; its known wrong answers:
//  - a zero-area triangle has zero normal and zero in-plane edge normals, so
//    the axis that separates it within a shared plane is missing: a segment
//    beside a coplanar triangle, two coplanar segments that miss, a point and
//    a segment, or two distinct points are reported as intersecting;
//  - near-touching pairs are decided by rounded dot products of rounded cross
//    products, so answers within rounding of contact can be wrong either way.
#include <fcl/narrowphase/detail/traversal/collision/intersect.h>

extern "C" {
#include "tb_oracles.h"
}

static fcl::Vector3<double> fcl_point(tb_vec3 v) { return fcl::Vector3<double>(v.x, v.y, v.z); }

extern "C" int tb_tritri_fcl(const tb_vec3 p[3], const tb_vec3 q[3]) {
  const fcl::Vector3<double> p0 = fcl_point(p[0]), p1 = fcl_point(p[1]), p2 = fcl_point(p[2]);
  const fcl::Vector3<double> q0 = fcl_point(q[0]), q1 = fcl_point(q[1]), q2 = fcl_point(q[2]);
  return fcl::detail::Intersect<double>::intersect_Triangle(p0, p1, p2, q0, q1, q2) ? 1 : 0;
}
