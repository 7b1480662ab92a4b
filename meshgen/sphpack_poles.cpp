// Reference adapter: inner Voronoi poles of surface samples through CGAL's
// 3D Delaunay triangulation, behind tb_voronoi_poles() (meshgen/tb_sphpack.h).
//
// The poles are those of Amenta, Choi & Kolluri's power crust (2001): the
// Voronoi cell of a sample p is bounded by the circumcentres of the Delaunay
// tetrahedra incident to p; of these, the inner pole is the one farthest from
// p on the inner side, i.e. with (c - p) . n < 0 for p's outward normal n. For
// a dense sample of a smooth closed surface it lies near the medial axis, and
// |c - p| approximates its distance to the surface.
//
// CGAL 5.5, Delaunay_triangulation_3 on Exact_predicates_inexact_constructions_kernel:
// the triangulation's predicates are exact (with symbolic perturbation for
// cospherical points), the circumcentres are computed in doubles. Points are
// inserted as one range, each with its sample number; a sample equal to an
// earlier one shares its vertex and gets no pole. The result does not depend
// on the insertion order CGAL picks: the triangulation is unique (exact
// predicates, symbolic perturbation), each circumcentre is computed from the
// corners in sample order, and equal pole radii go to the smaller centre
// (xyz order).
#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_3.h>

#include <algorithm>
#include <tuple>
#include <utility>
#include <vector>

extern "C" {
#include "tb_sphpack.h"
}

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Triangulation_vertex_base_with_info_3<int, K> Vb;
typedef CGAL::Delaunay_triangulation_cell_base_3<K> Cb;
typedef CGAL::Triangulation_data_structure_3<Vb, Cb> Tds;
typedef CGAL::Delaunay_triangulation_3<K, Tds> Delaunay;
typedef K::Point_3 Point;

int poles(const tb_vec3 *p, const tb_vec3 *n, int np, tb_vec3 *pole, double *pole_r) {
  std::vector<std::pair<Point, int>> pts;
  pts.reserve(np);
  for (int i = 0; i < np; i++) {
    pole_r[i] = -1;
    pole[i] = p[i];
    if (!tb_isfinite3(p[i])) return -1;
    pts.push_back(std::make_pair(Point(p[i].x, p[i].y, p[i].z), i));
  }
  Delaunay dt(pts.begin(), pts.end());
  std::vector<Delaunay::Cell_handle> cells;
  for (auto v = dt.finite_vertices_begin(); v != dt.finite_vertices_end(); ++v) {
    int i = v->info();
    cells.clear();
    dt.incident_cells(v, std::back_inserter(cells));
    for (const Delaunay::Cell_handle &c : cells) {
      if (dt.is_infinite(c)) continue;
      // The circumcentre (a Voronoi vertex of p's cell) from the corners in
      // sample order, so its rounding does not depend on how CGAL stored the cell.
      int ord[4] = {0, 1, 2, 3};
      std::sort(ord, ord + 4,
                [&](int a, int b) { return c->vertex(a)->info() < c->vertex(b)->info(); });
      const Point &a = c->vertex(ord[0])->point(), &b = c->vertex(ord[1])->point(),
                  &e = c->vertex(ord[2])->point(), &f = c->vertex(ord[3])->point();
      // The circumcentre a + (|u|^2 v x w + |v|^2 w x u + |w|^2 u x v) /
      // (2 u . v x w), u, v, w the edges from a; a flat cell (the geodesic
      // sphere has cospherical samples on a plane) has none: skipped
      // (CGAL's own construction asserts on it in a debug build).
      if (K::Orientation_3()(a, b, e, f) == CGAL::COPLANAR) continue;
      tb_vec3 pa = tb_v3(a.x(), a.y(), a.z()), u = tb_sub(tb_v3(b.x(), b.y(), b.z()), pa),
              v = tb_sub(tb_v3(e.x(), e.y(), e.z()), pa),
              w = tb_sub(tb_v3(f.x(), f.y(), f.z()), pa);
      double den = 2 * tb_dot(u, tb_cross(v, w));
      if (!(den != 0)) continue;
      tb_vec3 num = tb_add(
          tb_add(tb_scale(tb_cross(v, w), tb_dot(u, u)), tb_scale(tb_cross(w, u), tb_dot(v, v))),
          tb_scale(tb_cross(u, v), tb_dot(w, w)));
      tb_vec3 cq = tb_add(pa, tb_scale(num, 1 / den));
      tb_vec3 d = tb_sub(cq, p[i]);
      if (tb_dot(d, n[i]) >= 0 || !tb_isfinite3(cq)) continue;
      double r = tb_len(d);
      if (r > pole_r[i] ||
          (r == pole_r[i] &&
           std::make_tuple(cq.x, cq.y, cq.z) < std::make_tuple(pole[i].x, pole[i].y, pole[i].z))) {
        pole_r[i] = r;
        pole[i] = cq;
      }
    }
  }
  return 0;
}

}  // namespace

extern "C" int tb_voronoi_poles(const tb_vec3 *p, const tb_vec3 *n, int np, tb_vec3 *pole,
                                double *pole_r) {
  try {
    return poles(p, n, np, pole, pole_r);
  } catch (...) {
    return -1;
  }
}
