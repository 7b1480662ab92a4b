/* Distance and inside queries on a closed triangle surface, for the sphere
 * packing (meshgen/tb_sphpack.h): nearest triangle through the project's AABB
 * hierarchy (collision/tb_bvh.h) and Ericson's closest point on a triangle
 * (core/tb_math.h); inside by ray parity along +z with the rasterisers'
 * top-left tie rule (a point on an edge shared by two triangles projected
 * the same way round belongs to exactly one of them). */
#include <float.h>
#include <math.h>
#include <string.h>

#include "tb_sphpack.h"

int tb_closed_surface_init(tb_closed_surface *s, const tb_mesh *m, const char *name,
                           tb_error *err) {
  memset(s, 0, sizeof *s);
  if (m->ntri < 4) return tb_error_set(err, name, 0, "%d triangles: not a closed surface", m->ntri);
  tb_mesh_topo t = tb_mesh_topology(m);
  if (!t.closed || !t.manifold || t.misoriented_edges || t.degenerate_tris)
    return tb_error_set(err, name, 0,
                        "not a closed, oriented 2-manifold surface (%d boundary edges, %d "
                        "non-manifold edges, %d misoriented edges, %d degenerate triangles)",
                        t.boundary_edges, t.nonmanifold_edges, t.misoriented_edges,
                        t.degenerate_tris);
  for (int v = 0; v < m->nv; v++)
    if (!tb_isfinite3(m->x[v])) return tb_error_set(err, name, 0, "vertex %d is not finite", v + 1);
  s->x = m->x;
  s->tri = m->tri;
  s->ntri = m->ntri;
  tb_bvh_def def = tb_bvh_default_def();
  if (tb_bvh_build(&s->bvh, m->x, m->tri, m->ntri, &def, err)) return -1;
  return 0;
}

void tb_closed_surface_free(tb_closed_surface *s) {
  tb_bvh_free(&s->bvh);
  memset(s, 0, sizeof *s);
}

static double box_dist2(tb_aabb b, tb_vec3 p) {
  double d = 0, w[3] = {p.x, p.y, p.z}, lo[3] = {b.lo.x, b.lo.y, b.lo.z},
         hi[3] = {b.hi.x, b.hi.y, b.hi.z};
  for (int k = 0; k < 3; k++) {
    double e = w[k] < lo[k] ? lo[k] - w[k] : (w[k] > hi[k] ? w[k] - hi[k] : 0);
    d += e * e;
  }
  return d;
}

double tb_closed_surface_distance(const tb_closed_surface *s, tb_vec3 p) {
  const tb_bvh *b = &s->bvh;
  int stack[256], top = 0;
  double best = DBL_MAX;
  stack[top++] = 0;
  while (top > 0) {
    int node = stack[--top];
    if (box_dist2(b->box[node], p) >= best) continue;
    int c = b->child[node];
    if (c < 0) {
      for (int k = b->first[node]; k < b->first[node] + b->count[node]; k++) {
        const int *t = s->tri + 3 * b->tri_index[k];
        tb_vec3 q = tb_closest_on_triangle(p, s->x[t[0]], s->x[t[1]], s->x[t[2]]);
        tb_vec3 d = tb_sub(q, p);
        double d2 = tb_dot(d, d);
        if (d2 < best) best = d2;
      }
    } else if (top + 2 <= (int)(sizeof stack / sizeof *stack)) {
      int nearer = box_dist2(b->box[c], p) <= box_dist2(b->box[c + 1], p) ? c : c + 1;
      stack[top++] = nearer == c ? c + 1 : c; /* the farther one waits */
      stack[top++] = nearer;
    }
  }
  return sqrt(best);
}

/* Side of (px, py) from the edge a->b of the projection: +1 left, -1 right,
 * 0 on it; computed from the lower vertex index so that both triangles of an
 * edge see the same value. */
static double edge_fn(const tb_vec3 *x, int ia, int ib, double px, double py) {
  int lo = ia < ib ? ia : ib, hi = ia < ib ? ib : ia;
  tb_vec3 a = x[lo], b = x[hi];
  double e = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
  return ia < ib ? e : -e;
}

/* The top-left rule for the edge a->b of a counter-clockwise triangle. */
static int owns(tb_vec3 a, tb_vec3 b) { return b.y < a.y || (b.y == a.y && b.x < a.x); }

/* 1 and *z the height of the crossing when the vertical line through (px,
 * py) passes through triangle t (0 for triangles seen edge-on). */
static int crosses(const tb_closed_surface *s, int t, double px, double py, double *z) {
  const int *v = s->tri + 3 * t;
  tb_vec3 p0 = s->x[v[0]], p1 = s->x[v[1]], p2 = s->x[v[2]];
  if ((px < p0.x && px < p1.x && px < p2.x) || (px > p0.x && px > p1.x && px > p2.x) ||
      (py < p0.y && py < p1.y && py < p2.y) || (py > p0.y && py > p1.y && py > p2.y))
    return 0;
  double w0 = edge_fn(s->x, v[1], v[2], px, py), w1 = edge_fn(s->x, v[2], v[0], px, py),
         w2 = edge_fn(s->x, v[0], v[1], px, py);
  double area = (p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x);
  if (area == 0) return 0;
  double sg = area > 0 ? 1 : -1; /* make the triangle counter-clockwise */
  double w[3] = {sg * w0, sg * w1, sg * w2};
  tb_vec3 a[3] = {p1, p2, p0}, b[3] = {p2, p0, p1}; /* edge k is opposite vertex k */
  for (int k = 0; k < 3; k++) {
    if (w[k] < 0) return 0;
    if (w[k] == 0 && !(sg > 0 ? owns(a[k], b[k]) : owns(b[k], a[k]))) return 0;
  }
  double sum = w[0] + w[1] + w[2];
  if (!(sum > 0)) return 0;
  *z = (w[0] * p0.z + w[1] * p1.z + w[2] * p2.z) / sum;
  return 1;
}

int tb_closed_surface_inside(const tb_closed_surface *s, tb_vec3 p) {
  int n = 0;
  double z;
  for (int t = 0; t < s->ntri; t++)
    if (crosses(s, t, p.x, p.y, &z) && z > p.z) n++;
  return n & 1;
}

/* Heights where the vertical line through (px, py) crosses the surface,
 * ascending, into z (room for ntri); returns how many. */
int tb_closed_surface_column(const tb_closed_surface *s, double px, double py, double *z) {
  int n = 0;
  for (int t = 0; t < s->ntri; t++)
    if (crosses(s, t, px, py, &z[n])) {
      double v = z[n];
      int k = n++;
      for (; k > 0 && z[k - 1] > v; k--) z[k] = z[k - 1]; /* insertion: few crossings */
      z[k] = v;
    }
  return n;
}
