// Reference adapter and oracle: CGAL's exact triangle-triangle test behind
// tb_tritri_cgal().
//
// CGAL 5.5 on Exact_predicates_inexact_constructions_kernel (Epick). There
// do_intersect is itself a filtered predicate: it is evaluated in interval
// arithmetic and redone with exact rationals when the intervals cannot
// decide, so its answer is exact for the double inputs, including the points
// and lines do_intersect constructs internally.
//
// CGAL's 3D do_intersect requires non-degenerate triangles and segments, so
// each input triangle is first classified with exact predicates: three
// non-collinear points stay a Triangle_3; collinear points become the
// Segment_3 between the two extreme ones, which are the lexicographic minimum
// and maximum (along a line, xyz order is the order along the line, and
// comparing doubles is exact); three equal points become a Point_3. Then the
// matching do_intersect overload is called (CGAL 5.5 has all nine pairs of
// Point_3, Segment_3 and Triangle_3). Non-finite coordinates give 0.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Intersections_3/Point_3_Point_3.h>
#include <CGAL/Intersections_3/Point_3_Segment_3.h>
#include <CGAL/Intersections_3/Point_3_Triangle_3.h>
#include <CGAL/Intersections_3/Segment_3_Segment_3.h>
#include <CGAL/Intersections_3/Segment_3_Triangle_3.h>
#include <CGAL/Intersections_3/Triangle_3_Triangle_3.h>

extern "C" {
#include "tb_oracles.h"
}

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef K::Point_3 Point;
typedef K::Segment_3 Segment;
typedef K::Triangle_3 Triangle;

enum Kind { POINT, SEGMENT, TRIANGLE };

// A triangle as the set it spans: a point (a), a segment (a, b) or a
// triangle (a, b, c).
struct Shape {
  Kind kind;
  Point a, b, c;
};

Shape cgal_shape(const tb_vec3 v[3]) {
  Shape s;
  s.a = Point(v[0].x, v[0].y, v[0].z);
  s.b = Point(v[1].x, v[1].y, v[1].z);
  s.c = Point(v[2].x, v[2].y, v[2].z);
  if (!CGAL::collinear(s.a, s.b, s.c)) {
    s.kind = TRIANGLE;
    return s;
  }
  Point lo = s.a, hi = s.a;
  if (s.b < lo) lo = s.b;
  if (s.c < lo) lo = s.c;
  if (hi < s.b) hi = s.b;
  if (hi < s.c) hi = s.c;
  s.a = lo;
  s.b = hi;
  s.kind = lo == hi ? POINT : SEGMENT;
  return s;
}

// do_intersect of shape s against the object o.
template <class T>
bool cgal_meets(const Shape &s, const T &o) {
  switch (s.kind) {
    case POINT:
      return CGAL::do_intersect(s.a, o);
    case SEGMENT:
      return CGAL::do_intersect(Segment(s.a, s.b), o);
    default:
      return CGAL::do_intersect(Triangle(s.a, s.b, s.c), o);
  }
}

bool cgal_finite(const tb_vec3 v[3]) {
  return tb_isfinite3(v[0]) && tb_isfinite3(v[1]) && tb_isfinite3(v[2]);
}

}  // namespace

// Returns -1 only if CGAL throws, which valid finite input never makes it do.
extern "C" int tb_tritri_cgal(const tb_vec3 p[3], const tb_vec3 q[3]) {
  if (!cgal_finite(p) || !cgal_finite(q)) return 0;
  try {
    const Shape s = cgal_shape(p), t = cgal_shape(q);
    switch (t.kind) {
      case POINT:
        return cgal_meets(s, t.a) ? 1 : 0;
      case SEGMENT:
        return cgal_meets(s, Segment(t.a, t.b)) ? 1 : 0;
      default:
        return cgal_meets(s, Triangle(t.a, t.b, t.c)) ? 1 : 0;
    }
  } catch (...) {
    return -1;
  }
}
