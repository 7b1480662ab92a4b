/* Devillers & Guigue 2002, "Faster triangle-triangle intersection tests"
 * (INRIA RR-4488; J. Graphics Tools 8(1), 2003), written from the paper: every
 * decision is the sign of an orientation determinant.
 *   1. signs of p's vertices against q's plane, then of q's against p's
 *      (each plane's normal computed once, measured from its third vertex);
 *      all three strictly on one side: disjoint;
 *   2. canonical form: rotate p so that its apex (the vertex alone on its
 *      closed side of q's plane) comes first, reverse q when that apex is on
 *      the negative side; the same for q against p's plane. The paper's case
 *      analysis of the sign triples (zeros included) is the 27-entry table
 *      below;
 *   3. the two segments where each triangle crosses the other's plane lie on
 *      the planes' common line and overlap iff [p1, q1, p2, q2] <= 0 and
 *      [p1, r1, r2, p2] <= 0 -- here orient3d(P1, P2, Q1, Q2) <= 0 and
 *      orient3d(P1, P3, Q1, Q3) >= 0 in the convention of tb_predicates.h;
 *   4. coplanar (all signs of one side zero): project onto the coordinate plane
 *      where p's normal is largest, make both triangles counter-clockwise,
 *      locate p1 against q's edges (inside, or in an edge or a vertex region)
 *      and finish with the paper's decision trees of 2D orientations.
 * tb_tritri_guigue evaluates every determinant in plain doubles, as the paper
 * does: faithful, no patch. Zero-area triangles are outside the paper; they
 * take whatever path the signs give (all zero: the coplanar branch, on the
 * xy plane when p's normal is zero).
 * tb_tritri_guigue_exact is the same algorithm with the exact predicates of
 * tb_predicates.h, plus two documented additions needed for exact answers on
 * every input: (a) a zero-area triangle always reaches step 4 (its own
 * "plane" gives the other triangle all-zero signs), and there, triangles of
 * zero area (decided exactly) are the segment or point they span and are
 * answered by the exact segment/point tests of tritri_exact.c; (b) the
 * projection axis is the largest normal component if that component is
 * exactly nonzero, else another one that is. */
#include "tb_predicates.h"
#include "tb_tritri.h"

typedef struct pt2 {
  double x, y;
} pt2;

static inline int sgn(double x) { return (x > 0.0) - (x < 0.0); }

/* The two predicates, in doubles (ex = 0) or exact (ex = 1); callers pass a
 * constant so each variant is compiled on its own. */
static inline int or2(int ex, pt2 a, pt2 b, pt2 c) {
  return ex ? tb_orient2d(a.x, a.y, b.x, b.y, c.x, c.y)
            : sgn(tb_orient2d_fast(a.x, a.y, b.x, b.y, c.x, c.y));
}
static inline int or3(int ex, tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  return ex ? tb_orient3d(a, b, c, d) : sgn(tb_orient3d_fast(a, b, c, d));
}

/* ---- the 2D test (section 4 of the paper): counter-clockwise triangles ---- */

/* p1 outside edge r2p2 only. */
static int edge_region(int ex, pt2 p1, pt2 q1, pt2 r1, pt2 p2, pt2 q2, pt2 r2) {
  (void)q2;
  if (or2(ex, r2, p2, q1) >= 0) {
    if (or2(ex, p1, p2, q1) >= 0) return or2(ex, p1, q1, r2) >= 0;
    return or2(ex, q1, r1, p2) >= 0 && or2(ex, r1, p1, p2) >= 0;
  }
  if (or2(ex, r2, p2, r1) < 0 || or2(ex, p1, p2, r1) < 0) return 0;
  return or2(ex, p1, r1, r2) >= 0 || or2(ex, q1, r1, r2) >= 0;
}

/* p1 in the vertex region of r2 (outside edges q2r2 and r2p2). */
static int vertex_region(int ex, pt2 p1, pt2 q1, pt2 r1, pt2 p2, pt2 q2, pt2 r2) {
  if (or2(ex, r2, p2, q1) >= 0) {
    if (or2(ex, r2, q2, q1) <= 0) {
      if (or2(ex, p1, p2, q1) > 0) return or2(ex, p1, q2, q1) <= 0;
      return or2(ex, p1, p2, r1) >= 0 && or2(ex, q1, r1, p2) >= 0;
    }
    return or2(ex, p1, q2, q1) <= 0 && or2(ex, r2, q2, r1) <= 0 && or2(ex, q1, r1, q2) >= 0;
  }
  if (or2(ex, r2, p2, r1) < 0) return 0;
  if (or2(ex, q1, r1, r2) >= 0) return or2(ex, p1, p2, r1) >= 0;
  return or2(ex, q1, r1, q2) >= 0 && or2(ex, r2, r1, q2) >= 0;
}

static int ccw_overlap(int ex, pt2 p1, pt2 q1, pt2 r1, pt2 p2, pt2 q2, pt2 r2) {
  int a = or2(ex, p2, q2, p1) >= 0, b = or2(ex, q2, r2, p1) >= 0, c = or2(ex, r2, p2, p1) >= 0;
  if (a && b && c) return 1;
  if (a && b) return edge_region(ex, p1, q1, r1, p2, q2, r2);
  if (a && c) return edge_region(ex, p1, q1, r1, r2, p2, q2);
  if (b && c) return edge_region(ex, p1, q1, r1, q2, r2, p2);
  if (a) return vertex_region(ex, p1, q1, r1, p2, q2, r2);
  if (b) return vertex_region(ex, p1, q1, r1, q2, r2, p2);
  return vertex_region(ex, p1, q1, r1, r2, p2, q2);
}

static pt2 proj(tb_vec3 v, int k) {
  pt2 r = {tb_comp(v, (k + 1) % 3), tb_comp(v, (k + 2) % 3)};
  return r;
}

static int coplanar(int ex, const tb_vec3 p[3], const tb_vec3 q[3]) {
  if (ex) {
    int r = tb_tritri_exact_degenerate(p, q);
    if (r >= 0) return r;
  }
  tb_vec3 n = tb_cross(tb_sub(p[1], p[0]), tb_sub(p[2], p[0]));
  double nx = fabs(n.x), ny = fabs(n.y), nz = fabs(n.z);
  int k = (nx > nz && nx >= ny) ? 0 : (ny > nz && ny >= nx) ? 1 : 2;
  pt2 a[3], b[3];
  for (int i = 0; i < 3; i++) a[i] = proj(p[i], k);
  if (ex) /* the axis must keep p's area exactly nonzero */
    for (int t = 0; t < 3 && !or2(ex, a[0], a[1], a[2]); t++) {
      k = (k + 1) % 3;
      for (int i = 0; i < 3; i++) a[i] = proj(p[i], k);
    }
  for (int i = 0; i < 3; i++) b[i] = proj(q[i], k);
  if (or2(ex, a[0], a[1], a[2]) < 0) {
    pt2 t = a[1];
    a[1] = a[2], a[2] = t;
  }
  if (or2(ex, b[0], b[1], b[2]) < 0) {
    pt2 t = b[1];
    b[1] = b[2], b[2] = t;
  }
  return ccw_overlap(ex, a[0], a[1], a[2], b[0], b[1], b[2]);
}

/* ---- the 3D test ---- */

/* Signs of b's vertices against a's plane. */
static inline void plane_signs(int ex, const tb_vec3 a[3], const tb_vec3 b[3], int s[3]) {
  if (ex) {
    for (int j = 0; j < 3; j++) s[j] = tb_orient3d(a[0], a[1], a[2], b[j]);
    return;
  }
  tb_vec3 n = tb_cross(tb_sub(a[1], a[0]), tb_sub(a[2], a[0]));
  for (int j = 0; j < 3; j++) s[j] = sgn(tb_dot(tb_sub(b[j], a[2]), n));
}

/* Index 9 (s0 + 1) + 3 (s1 + 1) + (s2 + 1): the apex, plus 4 when the other
 * triangle is reversed; -1 when all three signs are equal. Entry by entry the
 * paper's dispatch: e.g. (+, +, -) apex 2 reversed, (0, -, -) apex 0, (0, 0, +)
 * apex 2, (0, -, +) apex 1 reversed. */
static const signed char apex_of[27] = {-1, 2, 2, 1, 4, 4, 1, 4, 4, 0, 5, 5, 6, -1,
                                        2,  1, 1, 4, 0, 0, 5, 0, 0, 5, 6, 6, -1};

static inline int guigue(int ex, const tb_vec3 p[3], const tb_vec3 q[3]) {
  int s[3], t[3];
  plane_signs(ex, q, p, s);
  if (s[0] == s[1] && s[1] == s[2] && s[0]) return 0;
  plane_signs(ex, p, q, t);
  if (t[0] == t[1] && t[1] == t[2] && t[0]) return 0;
  int ea = apex_of[9 * s[0] + 3 * s[1] + s[2] + 13];
  int eb = apex_of[9 * t[0] + 3 * t[1] + t[2] + 13];
  if (ea < 0 || eb < 0) return coplanar(ex, p, q);
  int a = ea & 3, b = eb & 3;
  tb_vec3 P1 = p[a], P2 = p[(a + 1) % 3], P3 = p[(a + 2) % 3];
  tb_vec3 Q1 = q[b], Q2 = q[(b + 1) % 3], Q3 = q[(b + 2) % 3];
  if (eb & 4) {
    tb_vec3 x = P2;
    P2 = P3, P3 = x;
  }
  if (ea & 4) {
    tb_vec3 x = Q2;
    Q2 = Q3, Q3 = x;
  }
  return or3(ex, P1, P2, Q1, Q2) <= 0 && or3(ex, P1, P3, Q1, Q3) >= 0;
}

int tb_tritri_guigue(const tb_vec3 p[3], const tb_vec3 q[3]) { return guigue(0, p, q); }
int tb_tritri_guigue_exact(const tb_vec3 p[3], const tb_vec3 q[3]) { return guigue(1, p, q); }
