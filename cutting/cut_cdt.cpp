// Reference adapter: a 2D constrained Delaunay triangulation through CGAL,
// behind tb_cdt2_build() (cutting/tb_cut_surface.h), for the crack and the
// split triangles of the surface cut (the metaball patent, step 3 (5): the
// crack is "a triangulation with the boundary respected": all points
// triangulated, the triangles outside the boundary removed, fig. 6).
//
// CGAL 5.5, Constrained_Delaunay_triangulation_2 on
// Exact_predicates_inexact_constructions_kernel with the default
// No_constraint_intersection_requiring_constructions_tag: the predicates are
// exact, no point is ever constructed, so every vertex of the result is an
// input point; constraints that cross (which would need a new point) make
// CGAL throw, reported here as -2. A point lying exactly on a constraint
// splits it (no construction needed). The output does not depend on CGAL's
// internal order: triangles are listed with their smallest index first
// (counter-clockwise kept) and sorted, and regions are numbered in that order.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <vector>

extern "C" {
#include "tb_cut_surface.h"
}

namespace {

typedef CGAL::Exact_predicates_inexact_constructions_kernel K;
typedef CGAL::Triangulation_vertex_base_with_info_2<int, K> Vb;
typedef CGAL::Triangulation_face_base_with_info_2<int, K> Fbi;
typedef CGAL::Constrained_triangulation_face_base_2<K, Fbi> Fb;
typedef CGAL::Triangulation_data_structure_2<Vb, Fb> Tds;
typedef CGAL::Constrained_Delaunay_triangulation_2<K, Tds> Cdt;
typedef Cdt::Vertex_handle Vh;
typedef Cdt::Face_handle Fh;

int build(const double *xy, int np, const int *seg, int nseg, tb_cdt2 *out) {
  Cdt cdt;
  std::vector<Vh> vh(np);
  for (int i = 0; i < np; i++) {
    if (!std::isfinite(xy[2 * i]) || !std::isfinite(xy[2 * i + 1])) return -1;
    std::size_t before = cdt.number_of_vertices();
    vh[i] = cdt.insert(Cdt::Point(xy[2 * i], xy[2 * i + 1]));
    if (cdt.number_of_vertices() == before) return -3;  // a duplicate point
    vh[i]->info() = i + 1;
  }
  for (int i = 0; i < nseg; i++) {
    int a = seg[2 * i], b = seg[2 * i + 1];
    if (a < 0 || b < 0 || a >= np || b >= np || a == b) return -1;
    cdt.insert_constraint(vh[a], vh[b]);
  }
  // Faces in a canonical order.
  std::vector<std::array<int, 4>> key;  // a, b, c (smallest first), then the face's slot
  std::vector<Fh> faces;
  for (Cdt::Finite_faces_iterator f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    int v[3];
    for (int k = 0; k < 3; k++) v[k] = f->vertex(k)->info() - 1;
    int r = v[1] < v[0] ? (v[2] < v[1] ? 2 : 1) : (v[2] < v[0] ? 2 : 0);
    key.push_back({v[r], v[(r + 1) % 3], v[(r + 2) % 3], (int)faces.size()});
    faces.push_back(f);
  }
  std::sort(key.begin(), key.end());
  int nt = (int)key.size();
  for (int i = 0; i < nt; i++) faces[key[i][3]]->info() = i;
  out->ntri = nt;
  out->tri = (int *)malloc(sizeof(int) * 3 * (nt ? nt : 1));
  out->region = (int *)malloc(sizeof(int) * (nt ? nt : 1));
  if (!out->tri || !out->region) return -1;
  for (int i = 0; i < nt; i++) {
    for (int k = 0; k < 3; k++) out->tri[3 * i + k] = key[i][k];
    out->region[i] = -1;
  }
  // Regions: faces joined across edges that are not constrained.
  std::vector<int> stack;
  out->nregion = 0;
  for (int i = 0; i < nt; i++) {
    if (out->region[i] >= 0) continue;
    int r = out->nregion++;
    out->region[i] = r;
    stack.push_back(i);
    while (!stack.empty()) {
      Fh f = faces[key[stack.back()][3]];
      stack.pop_back();
      for (int k = 0; k < 3; k++) {
        if (f->is_constrained(k)) continue;
        Fh g = f->neighbor(k);
        if (cdt.is_infinite(g) || out->region[g->info()] >= 0) continue;
        out->region[g->info()] = r;
        stack.push_back(g->info());
      }
    }
  }
  return 0;
}

}  // namespace

extern "C" int tb_cdt2_build(const double *xy, int np, const int *seg, int nseg, tb_cdt2 *out) {
  out->ntri = 0, out->nregion = 0, out->tri = NULL, out->region = NULL;
  int rc;
  try {
    rc = build(xy, np, seg, nseg, out);
  } catch (...) {
    rc = -2;  // crossing constraints (CGAL refuses to construct the crossing point)
  }
  if (rc) tb_cdt2_free(out);
  return rc;
}

extern "C" void tb_cdt2_free(tb_cdt2 *c) {
  free(c->tri);
  free(c->region);
  c->tri = NULL, c->region = NULL, c->ntri = 0, c->nregion = 0;
}
