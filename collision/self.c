/* A triangle surface's self-intersections (collision/tb_bvh.h): the AABB
 * hierarchy of the surface queried against itself for candidate pairs
 * (overlapping triangle boxes), then each pair decided. A pair counts
 * when its triangles cross, not when they only touch: each has corners on
 * both sides of the other's plane, farther from it than 1e-9 of the pair's
 * longest edge, and the closed triangles meet (tb_tritri_exact). So sheets
 * that touch (the two sides of a fresh cut, whose vertices were rounded
 * onto the blade's plane; a face resting on an edge) are not counted, and
 * what the pair shares is left aside, whether a vertex of both or two
 * vertices at the same point (the twins of a cut held together by a clamp):
 *  - a vertex v: the edge opposite v in one must cross the other's plane
 *    so and meet that triangle (a segment is the degenerate triangle
 *    (a, b, b) to tb_tritri_exact);
 *  - an edge: they meet along it; a fold of one onto the other is not
 *    looked for.
 * Degenerate triangles (zero area) are left out. */
#include <math.h>
#include <stdlib.h>

#include "tb_bvh.h"
#include "tb_tritri.h"

static int candidate(const tb_vec3 p[3], const tb_vec3 q[3]) {
  (void)p, (void)q;
  return 1;
}

static int degenerate(const tb_vec3 *x, const int *t) {
  tb_vec3 n = tb_cross(tb_sub(x[t[1]], x[t[0]]), tb_sub(x[t[2]], x[t[0]]));
  return !(n.x != 0 || n.y != 0 || n.z != 0);
}

#define TOUCH 1e-9 /* a corner this close to a plane (of the longest edge) touches it */

/* Signed distance of y from the plane of p, and the plane's scale. */
static double side(const tb_vec3 *x, const int *p, tb_vec3 y, double *scale) {
  tb_vec3 a = x[p[0]], n = tb_cross(tb_sub(x[p[1]], a), tb_sub(x[p[2]], a));
  double l = tb_len(n);
  *scale =
      fmax(fmax(tb_dist(x[p[0]], x[p[1]]), tb_dist(x[p[1]], x[p[2]])), tb_dist(x[p[2]], x[p[0]]));
  return l > 0 ? tb_dot(tb_sub(y, a), n) / l : 0;
}

/* 1 when the points q[0 .. n) lie on both sides of the plane of p, beyond
 * touching. */
static int straddles(const tb_vec3 *x, const int *p, const tb_vec3 *q, int n) {
  double lo = 0, hi = 0, s = 0;
  for (int k = 0; k < n; k++) {
    double d = side(x, p, q[k], &s);
    lo = fmin(lo, d), hi = fmax(hi, d);
  }
  return hi > TOUCH * s && lo < -TOUCH * s;
}

/* Triangle a beyond its corner k crosses triangle b: the edge opposite k
 * crosses b's plane and meets b. */
static int edge_crosses(const tb_vec3 *x, const int *ta, int k, const int *tb) {
  const tb_vec3 s[3] = {x[ta[(k + 1) % 3]], x[ta[(k + 2) % 3]], x[ta[(k + 2) % 3]]};
  const tb_vec3 q[3] = {x[tb[0]], x[tb[1]], x[tb[2]]};
  return straddles(x, tb, s, 2) && tb_tritri_exact(s, q);
}

static int same_point(tb_vec3 a, tb_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

/* Triangles i and j (i != j) cross other than in what they share. */
static int cross(const tb_vec3 *x, const int *ti, const int *tj) {
  int shared = 0, ki = -1, kj = -1;
  for (int a = 0; a < 3; a++)
    for (int b = 0; b < 3; b++)
      if (ti[a] == tj[b] || same_point(x[ti[a]], x[tj[b]])) shared++, ki = a, kj = b;
  if (shared >= 2) return 0;
  if (shared == 1) return edge_crosses(x, ti, ki, tj) || edge_crosses(x, tj, kj, ti);
  const tb_vec3 p[3] = {x[ti[0]], x[ti[1]], x[ti[2]]}, q[3] = {x[tj[0]], x[tj[1]], x[tj[2]]};
  return straddles(x, ti, q, 3) && straddles(x, tj, p, 3) && tb_tritri_exact(p, q);
}

int tb_collide_self(const tb_vec3 *x, const int *tri, int ntri, tb_pairlist *out, tb_error *err) {
  out->n = 0;
  if (ntri < 2) return 0;
  tb_bvh b;
  tb_bvh_def def = tb_bvh_default_def();
  if (tb_bvh_build(&b, x, tri, ntri, &def, err)) return -1;
  tb_pairlist cand = {0, 0, NULL};
  int rc = tb_bvh_collide(&b, x, &b, x, candidate, &cand, NULL);
  tb_bvh_free(&b);
  if (rc) return tb_error_set(err, "self-intersections", 0, "out of memory");
  for (int k = 0; k < cand.n && !rc; k++) {
    int i = cand.ij[2 * k], j = cand.ij[2 * k + 1];
    if (i >= j || degenerate(x, tri + 3 * i) || degenerate(x, tri + 3 * j)) continue;
    if (cross(x, tri + 3 * i, tri + 3 * j) && tb_pairlist_push(out, i, j))
      rc = tb_error_set(err, "self-intersections", 0, "out of memory");
  }
  tb_pairlist_free(&cand);
  if (!rc) tb_pairlist_sort_unique(out);
  return rc;
}
