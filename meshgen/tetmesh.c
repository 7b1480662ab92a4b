/* A user's closed surface to a tet mesh: the checks TetGen needs (closed,
 * manifold, oriented, no self-intersection, by our own exact test), TetGen
 * with a radius-edge bound and a volume bound or a tet count (the bound
 * searched by bisection on its logarithm), the mesh's shape (dihedral
 * angles, radius-edge ratios), and a local repair of self-intersections by
 * umbrella smoothing. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collision/tb_bvh.h"
#include "tb_meshgen.h"

tb_tetmesh_opts tb_tetmesh_default_opts(void) {
  tb_tetmesh_opts o = {TB_TETMESH_QUALITY, 0, 0, 0};
  return o;
}

int tb_tetmesh_check(const tb_mesh *surf, const char *name, tb_error *err) {
  tb_mesh_topo t = tb_mesh_topology(surf);
  if (t.degenerate_tris)
    return tb_error_set(err, name, 0, "%d degenerate triangles (a vertex repeated)",
                        t.degenerate_tris);
  if (!t.closed)
    return tb_error_set(err, name, 0,
                        "the surface is open (%d boundary edges): TetGen needs a closed surface "
                        "(tissuebench mesh close caps holes)",
                        t.boundary_edges);
  if (!t.manifold)
    return tb_error_set(err, name, 0, "not manifold (%d edges, %d vertices)", t.nonmanifold_edges,
                        t.nonmanifold_verts);
  if (t.misoriented_edges)
    return tb_error_set(err, name, 0,
                        "not consistently oriented (%d edges traversed twice the same way)",
                        t.misoriented_edges);
  if (surf->ntri < 4)
    return tb_error_set(err, name, 0, "%d triangles: not a closed surface", surf->ntri);
  tb_pairlist self = {0, 0, NULL};
  if (tb_collide_self(surf->x, surf->tri, surf->ntri, &self, err)) return -1;
  if (self.n) {
    int a = self.ij[0], b = self.ij[1];
    const int *ta = surf->tri + 3 * a;
    tb_vec3 c = tb_scale(tb_add(tb_add(surf->x[ta[0]], surf->x[ta[1]]), surf->x[ta[2]]), 1.0 / 3);
    tb_error_set(err, name, 0,
                 "self-intersecting: triangles %d and %d (0-based) cross near (%.6g, %.6g, "
                 "%.6g), %d crossing pair%s in all; TetGen cannot mesh it",
                 a, b, c.x, c.y, c.z, self.n, self.n == 1 ? "" : "s");
    tb_pairlist_free(&self);
    return -1;
  }
  return 0;
}

/* balance of tb_tetgen_search: decreasing as the volume bound grows */
static double balance(const tb_mesh *m, double tv, double tt) {
  if (tv <= 0) return m->ntet / tt - 1;
  return tt > 0 ? m->nv / tv + m->ntet / tt - 2 : m->nv / tv - 1;
}

int tb_tetgen_search(const tb_mesh *surf, const char *prefix, double lo, double hi, double tv,
                     double tt, int iters, double width, double stop, tb_mesh *best, double *best_b,
                     tb_error *err) {
  memset(best, 0, sizeof *best);
  *best_b = INFINITY;
  for (int it = 0; it < iters && hi - lo > width && fabs(*best_b) > stop; it++) {
    double mid = 0.5 * (lo + hi);
    char sw[96];
    snprintf(sw, sizeof sw, "%sa%.17g", prefix, exp(mid));
    tb_mesh m;
    if (tb_tetgen(surf, sw, &m, err)) {
      tb_mesh_free(best);
      return -1;
    }
    double b = balance(&m, tv, tt);
    if (fabs(b) < fabs(*best_b)) {
      tb_mesh_free(best);
      *best = m, *best_b = b;
    } else {
      tb_mesh_free(&m);
    }
    if (b > 0)
      lo = mid; /* too many: allow larger tets */
    else
      hi = mid;
  }
  return 0;
}

int tb_tetmesh(const tb_mesh *surf, const char *name, const tb_tetmesh_opts *o, tb_mesh *out,
               tb_error *err) {
  memset(out, 0, sizeof *out);
  if (!(o->quality >= 1.1 && o->quality <= 100))
    return tb_error_set(err, name, 0, "quality %g: give a radius-edge bound in [1.1, 100]",
                        o->quality);
  if (!(o->max_volume >= 0) || !isfinite(o->max_volume) || o->tets < 0 ||
      (o->max_volume > 0 && o->tets > 0))
    return tb_error_set(err, name, 0, "give a volume bound (> 0) or a tet count (> 0), not both");
  /* the triangles alone (a tet mesh's tets would be kept), copied to drop unused vertices */
  tb_mesh tris = {surf->nv, surf->x, surf->ntri, surf->tri, 0, NULL, 0}, s;
  if (tb_mesh_copy(&s, &tris)) return tb_error_set(err, name, 0, "out of memory");
  int rc = tb_mesh_drop_unused(&s) < 0 ? tb_error_set(err, name, 0, "out of memory")
                                       : tb_tetmesh_check(&s, name, err);
  double volume = fabs(tb_mesh_volume(&s));
  char prefix[64];
  snprintf(prefix, sizeof prefix, "p%sq%.6g", o->split_surface ? "" : "Y", o->quality);
  if (!rc && o->tets > 0) {
    double tt = o->tets, best_b;
    rc = tb_tetgen_search(&s, prefix, log(volume / (4.0 * tt)), log(volume), 0, tt, 40, 1e-4, 0.01,
                          out, &best_b, err);
    if (!rc && fabs(best_b) > 0.1) {
      tb_error_set(err, name, 0,
                   "no mesh within 10%% of %d tets (closest: %d; TetGen's coarsest mesh at "
                   "quality %g%s bounds it from below)",
                   o->tets, out->ntet, o->quality,
                   o->split_surface ? "" : " with the surface kept");
      tb_mesh_free(out);
      rc = -1;
    }
  } else if (!rc) {
    char sw[128];
    if (o->max_volume > 0)
      snprintf(sw, sizeof sw, "%sa%.17g", prefix, o->max_volume);
    else
      snprintf(sw, sizeof sw, "%s", prefix);
    rc = tb_tetgen(&s, sw, out, err);
  }
  tb_mesh_free(&s);
  return rc ? -1 : 0;
}

/* The angle at edge (a, b) between the faces (a, b, c) and (a, b, d). */
static double dihedral(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  tb_vec3 u = tb_sub(b, a);
  double uu = tb_dot(u, u);
  tb_vec3 vc = tb_sub(c, a), vd = tb_sub(d, a);
  vc = tb_sub(vc, tb_scale(u, tb_dot(vc, u) / uu));
  vd = tb_sub(vd, tb_scale(u, tb_dot(vd, u) / uu));
  double cs = tb_dot(vc, vd) / sqrt(tb_dot(vc, vc) * tb_dot(vd, vd));
  return acos(fmax(-1.0, fmin(1.0, cs))) * 180.0 / M_PI;
}

tb_tet_shape tb_tet_mesh_shape(const tb_mesh *m) {
  static const int edge[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                 {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  tb_tet_shape s = {m->ntet ? 180 : 0, 0, 0};
  for (int t = 0; t < m->ntet; t++) {
    tb_vec3 p[4];
    for (int j = 0; j < 4; j++) p[j] = m->x[m->tet[4 * t + j]];
    double shortest = INFINITY;
    for (int e = 0; e < 6; e++) {
      const int *k = edge[e];
      double a = dihedral(p[k[0]], p[k[1]], p[k[2]], p[k[3]]);
      s.min_dihedral = fmin(s.min_dihedral, a), s.max_dihedral = fmax(s.max_dihedral, a);
      shortest = fmin(shortest, tb_dist(p[k[0]], p[k[1]]));
    }
    /* circumradius: |a^2 (b x c) + b^2 (c x a) + c^2 (a x b)| / (2 det) */
    tb_vec3 a = tb_sub(p[1], p[0]), b = tb_sub(p[2], p[0]), c = tb_sub(p[3], p[0]);
    tb_vec3 n = tb_add(
        tb_add(tb_scale(tb_cross(b, c), tb_dot(a, a)), tb_scale(tb_cross(c, a), tb_dot(b, b))),
        tb_scale(tb_cross(a, b), tb_dot(c, c)));
    double r = tb_len(n) / (2 * fabs(tb_dot(a, tb_cross(b, c))));
    s.max_radius_edge = fmax(s.max_radius_edge, r / shortest);
  }
  return s;
}

/* ---- untangling ---- */
/* Vertex neighbours as CSR: the k-th neighbour of v is adj[start[v] + k]. */
static int neighbours(const tb_mesh *m, int **start, int **adj) {
  int *st = calloc((size_t)m->nv + 1, sizeof(int)),
      *ad = malloc(sizeof(int) * 6 * (size_t)(m->ntri + 1));
  if (!st || !ad) {
    free(st), free(ad);
    return -1;
  }
  for (int k = 0; k < 3 * m->ntri; k++) st[m->tri[k] + 1] += 2;
  for (int v = 0; v < m->nv; v++) st[v + 1] += st[v];
  int *fill = malloc(sizeof(int) * (size_t)(m->nv + 1));
  if (!fill) {
    free(st), free(ad);
    return -1;
  }
  memcpy(fill, st, sizeof(int) * (size_t)m->nv);
  for (int t = 0; t < m->ntri; t++)
    for (int j = 0; j < 3; j++) {
      int v = m->tri[3 * t + j];
      ad[fill[v]++] = m->tri[3 * t + (j + 1) % 3];
      ad[fill[v]++] = m->tri[3 * t + (j + 2) % 3];
    }
  free(fill);
  *start = st, *adj = ad;
  return 0;
}

static double mean_edge(const tb_mesh *m) {
  double sum = 0;
  for (int t = 0; t < m->ntri; t++)
    for (int j = 0; j < 3; j++)
      sum += tb_dist(m->x[m->tri[3 * t + j]], m->x[m->tri[3 * t + (j + 1) % 3]]);
  return m->ntri ? sum / (3.0 * m->ntri) : 0;
}

int tb_surface_untangle(tb_mesh *m, int rounds, double *moved, int *nmoved, tb_error *err) {
  *moved = 0, *nmoved = 0;
  int *start = NULL, *adj = NULL;
  tb_vec3 *x0 = malloc(sizeof(tb_vec3) * (size_t)(m->nv + 1));
  tb_vec3 *next = malloc(sizeof(tb_vec3) * (size_t)(m->nv + 1));
  char *mark = calloc((size_t)m->nv + 1, 1), *grow = calloc((size_t)m->nv + 1, 1);
  if (!x0 || !next || !mark || !grow || neighbours(m, &start, &adj)) {
    free(x0), free(next), free(mark), free(grow), free(start), free(adj);
    return tb_error_set(err, "untangle", 0, "out of memory");
  }
  memcpy(x0, m->x, sizeof(tb_vec3) * (size_t)m->nv);
  int left = -1;
  for (int r = 0; r <= rounds; r++) {
    tb_pairlist self = {0, 0, NULL};
    if (tb_collide_self(m->x, m->tri, m->ntri, &self, err)) {
      left = -1;
      break;
    }
    left = self.n;
    if (left == 0 || r == rounds) {
      tb_pairlist_free(&self);
      break;
    }
    /* the crossing triangles' vertices, grown by r + 1 rings */
    memset(mark, 0, (size_t)m->nv);
    for (int k = 0; k < 2 * self.n; k++)
      for (int j = 0; j < 3; j++) mark[m->tri[3 * self.ij[k] + j]] = 1;
    tb_pairlist_free(&self);
    for (int ring = 0; ring <= r; ring++) {
      memcpy(grow, mark, (size_t)m->nv);
      for (int v = 0; v < m->nv; v++)
        if (mark[v])
          for (int k = start[v]; k < start[v + 1]; k++) grow[adj[k]] = 1;
      memcpy(mark, grow, (size_t)m->nv);
    }
    for (int it = 0; it < 10; it++) { /* umbrella steps, half way to the neighbours' mean */
      for (int v = 0; v < m->nv; v++) {
        next[v] = m->x[v];
        if (!mark[v] || start[v + 1] == start[v]) continue;
        tb_vec3 c = tb_v3(0, 0, 0);
        for (int k = start[v]; k < start[v + 1]; k++) c = tb_add(c, m->x[adj[k]]);
        c = tb_scale(c, 1.0 / (start[v + 1] - start[v]));
        next[v] = tb_add(m->x[v], tb_scale(tb_sub(c, m->x[v]), 0.5));
      }
      memcpy(m->x, next, sizeof(tb_vec3) * (size_t)m->nv);
    }
  }
  double h = mean_edge(m);
  for (int v = 0; v < m->nv; v++) {
    double d = tb_dist(m->x[v], x0[v]);
    if (d > 0) (*nmoved)++;
    *moved = fmax(*moved, h > 0 ? d / h : 0);
  }
  free(x0), free(next), free(mark), free(grow), free(start), free(adj);
  return left;
}
