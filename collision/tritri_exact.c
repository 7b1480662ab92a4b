/* Our exact triangle-triangle test: the right answer for every pair of
 * triangles with finite double coordinates, and built to be fast.
 *
 * Structure: Devillers & Guigue 2002 ("Faster triangle-triangle intersection
 * tests", INRIA RR-4488), every sign decided by a filtered predicate and the
 * cases the paper leaves out made exact:
 *   1. the signs of q's vertices against p's plane and of p's against q's,
 *      n . (w - v0) with each plane's normal n = (v1 - v0) x (v2 - v0) computed
 *      once; all three strictly on one side: disjoint;
 *   2. canonical form: each triangle rotated so its apex (the vertex alone on
 *      its closed side of the other plane) comes first, the other triangle
 *      reversed to put that apex on the positive side; the two segments where
 *      the triangles cross each other's plane then lie on the planes' common
 *      line and overlap iff orient3d(P1, P2, Q1, Q2) <= 0 and orient3d(P1, P3,
 *      Q1, Q3) >= 0 (the paper's two tests in the convention of
 *      tb_predicates.h). An apex on the plane is taken only when both other
 *      vertices are strictly on one side, so no edge used lies in the plane;
 *   3. all signs of one side zero: a zero-area triangle (every normal
 *      component exactly 0, by orient2d on the three coordinate planes) is the
 *      segment or point it spans and goes to exact segment/point tests in 3D
 *      (tb_tritri_exact_degenerate); otherwise the triangles are coplanar:
 *      project onto a coordinate plane where the normal component is exactly
 *      nonzero (an affine bijection of the plane, so each orient2d sign is the
 *      3D orientation up to one global sign) and apply the separating-axis
 *      theorem: closed convex polygons are disjoint iff some edge of one has
 *      the whole other strictly outside it (the edges of the Minkowski
 *      difference are the edges of both).
 * Filter: one error bound per pair serves all eight determinants of steps
 * 1-2 (derived at bound_of below). A sign it cannot decide (contacts and
 * coplanar pairs give exact zeros) sends the pair to the slow path, which
 * first checks once whether plain doubles are exact for every determinant of
 * the pair (pair_on_grid: dyadic data such as the degenerate test families);
 * if so every later sign is the plain one, else each is recomputed by
 * tb_orient3d (its own filter, then the exact stages). On
 * x86-64 the fast path runs in SSE2: lane 0 computes p's plane against q's
 * vertices while lane 1 computes q's against p's, then the two final
 * determinants share one pass. The portable scalar path
 * (tb_tritri_exact_portable) does the same operations and stays compiled and
 * tested. */
#include <stdint.h>
#include <string.h>

#include "tb_predicates.h"
#include "tb_tritri.h"

/* ---- small exact helpers ---- */

/* Every helper below takes pl: 1 when pair_on_grid() has proved the plain
 * double formulas exact for every determinant of the pair (then a sign is
 * just the sign of the plain value), 0 to use the exact predicates. */
static int s3(int pl, tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  if (!pl) return tb_orient3d(a, b, c, d);
  double x = tb_orient3d_fast(a, b, c, d);
  return (x > 0) - (x < 0);
}
static int s2(int pl, double ax, double ay, double bx, double by, double cx, double cy) {
  if (!pl) return tb_orient2d(ax, ay, bx, by, cx, cy);
  double x = tb_orient2d_fast(ax, ay, bx, by, cx, cy);
  return (x > 0) - (x < 0);
}

/* orient2d of a, b, c projected along axis k onto (k+1, k+2): the k-th
 * component of (b - a) x (c - a). */
static int o2k(int pl, tb_vec3 a, tb_vec3 b, tb_vec3 c, int k) {
  int i = (k + 1) % 3, j = (k + 2) % 3;
  return s2(pl, tb_comp(a, i), tb_comp(a, j), tb_comp(b, i), tb_comp(b, j), tb_comp(c, i),
            tb_comp(c, j));
}

/* An axis where (b - a) x (c - a) has an exactly nonzero component (the
 * largest estimate tried first), or -1 when a, b, c are collinear. */
static int normal_axis(int pl, tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  tb_vec3 n = tb_cross(tb_sub(b, a), tb_sub(c, a));
  double m[3] = {fabs(n.x), fabs(n.y), fabs(n.z)};
  int order[3] = {0, 1, 2};
  for (int i = 0; i < 2; i++)
    for (int j = i + 1; j < 3; j++)
      if (m[order[j]] > m[order[i]]) {
        int t = order[i];
        order[i] = order[j], order[j] = t;
      }
  for (int i = 0; i < 3; i++)
    if (o2k(pl, a, b, c, order[i])) return order[i];
  return -1;
}

static int same_point(tb_vec3 a, tb_vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

static int collinear(int pl, tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  return !o2k(pl, a, b, c, 0) && !o2k(pl, a, b, c, 1) && !o2k(pl, a, b, c, 2);
}

/* Closed axis-aligned boxes of [a, b] and [c, d] meet. */
static int boxes_meet(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  for (int k = 0; k < 3; k++) {
    double a0 = tb_comp(a, k), a1 = tb_comp(b, k), c0 = tb_comp(c, k), c1 = tb_comp(d, k);
    if (fmax(a0, a1) < fmin(c0, c1) || fmax(c0, c1) < fmin(a0, a1)) return 0;
  }
  return 1;
}

/* ---- zero-area triangles: segments and points ---- */

typedef struct shape {
  int kind; /* 0 point a, 1 segment [a, b], 2 triangle with normal axis `axis` */
  tb_vec3 a, b;
  int axis;
} shape;

static shape classify(int pl, const tb_vec3 t[3]) {
  shape s = {2, t[0], t[0], normal_axis(pl, t[0], t[1], t[2])};
  if (s.axis >= 0) return s;
  int k = 0;
  while (k < 3 && tb_comp(t[0], k) == tb_comp(t[1], k) && tb_comp(t[0], k) == tb_comp(t[2], k)) k++;
  if (k == 3) return s.kind = 0, s;
  /* collinear: the extreme points along an axis where they differ */
  int lo = 0, hi = 0;
  for (int i = 1; i < 3; i++) {
    if (tb_comp(t[i], k) < tb_comp(t[lo], k)) lo = i;
    if (tb_comp(t[i], k) > tb_comp(t[hi], k)) hi = i;
  }
  s.kind = 1, s.a = t[lo], s.b = t[hi];
  return s;
}

static int point_segment(int pl, tb_vec3 x, tb_vec3 a, tb_vec3 b) {
  return collinear(pl, a, b, x) && boxes_meet(x, x, a, b);
}

static int segment_segment(int pl, tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  if (s3(pl, a, b, c, d)) return 0;
  int cc = collinear(pl, a, b, c);
  if (cc && collinear(pl, a, b, d)) return boxes_meet(a, b, c, d);
  int k = cc ? normal_axis(pl, a, b, d) : normal_axis(pl, a, b, c);
  int o1 = o2k(pl, a, b, c, k), o2 = o2k(pl, a, b, d, k);
  int o3 = o2k(pl, c, d, a, k), o4 = o2k(pl, c, d, b, k);
  return o1 * o2 <= 0 && o3 * o4 <= 0;
}

/* Point x in the closed triangle t (positive area, normal axis k). */
static int point_triangle(int pl, tb_vec3 x, const tb_vec3 t[3], int k) {
  if (s3(pl, t[0], t[1], t[2], x)) return 0;
  int e0 = o2k(pl, t[0], t[1], x, k), e1 = o2k(pl, t[1], t[2], x, k);
  int e2 = o2k(pl, t[2], t[0], x, k);
  return !((e0 < 0 || e1 < 0 || e2 < 0) && (e0 > 0 || e1 > 0 || e2 > 0));
}

/* Closed segment [a, b] (a != b) against the closed triangle t. */
static int segment_triangle(int pl, tb_vec3 a, tb_vec3 b, const tb_vec3 t[3], int k) {
  int sa = s3(pl, t[0], t[1], t[2], a), sb = s3(pl, t[0], t[1], t[2], b);
  if (sa * sb > 0) return 0;
  int neg = 0, pos = 0;
  if (sa == 0 && sb == 0) { /* in the plane: separating axes in 2D */
    int o = o2k(pl, t[0], t[1], t[2], k);
    for (int i = 0; i < 3; i++) {
      tb_vec3 u = t[i], v = t[(i + 1) % 3];
      if (o2k(pl, u, v, a, k) * o < 0 && o2k(pl, u, v, b, k) * o < 0) return 0;
    }
    int side = 0; /* the triangle strictly on one side of the segment's line */
    for (int i = 0; i < 3; i++) side += o2k(pl, a, b, t[i], k);
    return side != 3 && side != -3;
  }
  /* the line crosses the plane at one point of the segment: inside iff the
   * line passes on one side (or on) of all three edges */
  for (int i = 0; i < 3; i++) {
    int s = s3(pl, a, b, t[i], t[(i + 1) % 3]);
    neg |= (s < 0);
    pos |= (s > 0);
  }
  return !(neg && pos);
}

static int degenerate(int pl, const tb_vec3 p[3], const tb_vec3 q[3]) {
  shape s = classify(pl, p), t = classify(pl, q);
  if (s.kind == 2 && t.kind == 2) return -1;
  if (s.kind < t.kind) { /* put the larger shape first */
    shape x = s;
    s = t, t = x;
    const tb_vec3 *y = p;
    p = q, q = y;
  }
  if (s.kind == 2)
    return t.kind == 1 ? segment_triangle(pl, t.a, t.b, p, s.axis)
                       : point_triangle(pl, t.a, p, s.axis);
  if (s.kind == 1)
    return t.kind == 1 ? segment_segment(pl, s.a, s.b, t.a, t.b) : point_segment(pl, t.a, s.a, s.b);
  return same_point(s.a, t.a);
}

int tb_tritri_exact_degenerate(const tb_vec3 p[3], const tb_vec3 q[3]) {
  return degenerate(0, p, q);
}

/* Coplanar triangles of positive area, normal axis k: separating axes. */
static int coplanar(int pl, const tb_vec3 p[3], const tb_vec3 q[3], int k) {
  double a[2][3][2]; /* both triangles projected along axis k */
  for (int i = 0; i < 3; i++)
    for (int c = 0; c < 2; c++)
      a[0][i][c] = tb_comp(p[i], (k + 1 + c) % 3), a[1][i][c] = tb_comp(q[i], (k + 1 + c) % 3);
  for (int t = 0; t < 2; t++) {
    double(*e)[2] = a[t], (*o)[2] = a[1 - t];
    int turn = s2(pl, e[0][0], e[0][1], e[1][0], e[1][1], e[2][0], e[2][1]);
    for (int i = 0; i < 3; i++) {
      const double *u = e[i], *v = e[(i + 1) % 3];
      int out = 1; /* the other triangle strictly outside this edge */
      for (int j = 0; j < 3 && out; j++)
        out = s2(pl, u[0], u[1], v[0], v[1], o[j][0], o[j][1]) * turn < 0;
      if (out) return 0;
    }
  }
  return 1;
}

static int flat_case(int pl, const tb_vec3 p[3], const tb_vec3 q[3]) {
  int r = degenerate(pl, p, q);
  return r >= 0 ? r : coplanar(pl, p, q, normal_axis(pl, p[0], p[1], p[2]));
}

/* ---- the filtered fast path ---- */

/* One error bound for every determinant of steps 1-2. Each is u . (v x w)
 * with u, v, w differences of two of the six points, so with D_k = max_k -
 * min_k the extent of the pair's bounding box on axis k, every computed
 * difference has |d_k| <= D_k (rounding is monotone) and the permanent is at
 * most 6 Dx Dy Dz. The rounding error is below 7u (1 + O(u)) times the
 * permanent (predicates.c), i.e. below 42u (1 + O(u)) Dx Dy Dz; underflowed
 * products add at most 2^-1074 (Dx + Dy + Dz) + 2^-1073. The bound
 * 48u (Dx + T)(Dy + T)(Dz + T), T = 2^-330, exceeds both: it contains
 * 48u Dx Dy Dz, 48u T^2 (Dx + Dy + Dz) >= 2^-707 (Dx + Dy + Dz) and
 * 48u T^3 > 2^-1038, and its own rounding (nine monotone operations) costs a
 * factor 1 - 9u. Unlike per-determinant permanents, a box bound does not see
 * an overflowed product (Dx tiny, Dy Dz > DBL_MAX gives d = inf and a finite
 * bound), so extents summing above 2^330 make the bound infinite: every filter
 * fails and the exact stage decides. NaN does the same. */
#define BIG_EXTENT 0x1p330
static inline double bound_of(double dx, double dy, double dz) {
  const double t = 0x1p-330;
  double b = 48.0 * 0x1p-53 * ((dx + t) * (dy + t) * (dz + t));
  return dx + dy + dz <= BIG_EXTENT ? b : INFINITY;
}

/* Apex table, index pos + 8 neg (bit j of pos / neg: sign j positive /
 * negative; neither: zero): the vertex alone on its closed side, plus 4 when
 * the other triangle must be reversed to put it on the positive side; -1 when
 * all three signs are equal (and for impossible masks). Entry by entry the
 * paper's dispatch, e.g. (+, +, -): apex 2 reversed; (0, -, -): apex 0. */
static const signed char apex_of[64] = {
    -1, 0,  1,  6,  2,  5,  4,  -1, 4,  -1, 4,  -1, 4,  -1, 4,  -1, 5,  0,  -1, -1, 5, 5,
    -1, -1, 2,  -1, -1, -1, 2,  -1, -1, -1, 6,  0,  1,  6,  -1, -1, -1, -1, 1,  -1, 1, -1,
    -1, -1, -1, -1, 0,  0,  -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
static const unsigned char mod3[5] = {0, 1, 2, 0, 1};

static int d_sign(double d, double bound) { return (d > bound) - (d < -bound); }

/* Steps 2-3 from the sign masks of p's vertices (smask, against q's plane)
 * and of q's (tmask, against p's plane). */
static int finish(int pl, const tb_vec3 p[3], const tb_vec3 q[3], int smask, int tmask,
                  double bound) {
  int ea = apex_of[smask], eb = apex_of[tmask];
  if (ea < 0 || eb < 0) return flat_case(pl, p, q); /* all zero on one side */
  int a = ea & 3, fa = ea >> 2, b = eb & 3, fb = eb >> 2;
  tb_vec3 P1 = p[a], P2 = p[mod3[a + 1 + fb]], P3 = p[mod3[a + 2 - fb]];
  tb_vec3 Q1 = q[b], Q2 = q[mod3[b + 1 + fa]], Q3 = q[mod3[b + 2 - fa]];
  int r1 = d_sign(tb_orient3d_fast(P1, P2, Q1, Q2), bound);
  int r2 = d_sign(tb_orient3d_fast(P1, P3, Q1, Q3), bound);
  if (!r1) r1 = s3(pl, P1, P2, Q1, Q2);
  if (!r2) r2 = s3(pl, P1, P3, Q1, Q3);
  return r1 <= 0 && r2 >= 0;
}

/* Lowest set bit of v (v a multiple of 2^lowbit), 5000 for 0. */
static int lowbit(double v) {
  uint64_t b;
  memcpy(&b, &v, sizeof b);
  int e = (int)(b >> 52 & 0x7ff);
  uint64_t m = b & 0xfffffffffffffULL;
  if (e) return e - 1075 + __builtin_ctzll(m | 1ULL << 52);
  return m ? -1074 + __builtin_ctzll(m) : 5000;
}

/* 1 when the plain double formulas (tb_orient3d_fast, tb_orient2d_fast, the
 * plane dots) are exact for every determinant of the pair. Per axis k, all
 * six coordinates are multiples of 2^L_k and the box extent is below 2^H_k,
 * so every difference is exact with at most H_k - L_k bits; each
 * determinant multiplies one difference per axis and adds at most 3 more
 * bits, so sum (H_k - L_k) + 3 <= 53 keeps every operation exact, with no
 * underflow when the L_k of the axes multiplied together add up to at least
 * -1074 and no overflow when sum H_k <= 1017. An axis without extent only
 * contributes exact zeros. Degenerate pairs built on dyadic grids (small
 * integers, halves, far offsets, power-of-two scalings) qualify. */
static int axis_grid(const double v[6], int *h, int *l) {
  double lo = v[0], hi = v[0];
  int b = 5000;
  for (int i = 0; i < 6; i++) {
    int t = lowbit(v[i]);
    lo = v[i] < lo ? v[i] : lo, hi = v[i] > hi ? v[i] : hi, b = t < b ? t : b;
  }
  double d = hi - lo; /* rounding is monotone: every |difference| <= d */
  if (d == 0.0) return 0;
  if (!(d < 0x1p1000)) return -1;
  frexp(d, h); /* d < 2^h */
  *l = b;
  return 1;
}

static int pair_on_grid(const tb_vec3 p[3], const tb_vec3 q[3]) {
  const double v[3][6] = {{p[0].x, p[1].x, p[2].x, q[0].x, q[1].x, q[2].x},
                          {p[0].y, p[1].y, p[2].y, q[0].y, q[1].y, q[2].y},
                          {p[0].z, p[1].z, p[2].z, q[0].z, q[1].z, q[2].z}};
  int bits = 3, lsum = 0, hsum = 0, lmax = -5000, n = 0;
  for (int k = 0; k < 3; k++) {
    int h, l, r = axis_grid(v[k], &h, &l);
    if (r < 0) return 0;
    if (r) bits += h - l, lsum += l, hsum += h, lmax = l > lmax ? l : lmax, n++;
  }
  /* the smallest sum of L over two axes is lsum - lmax (three axes) */
  return bits <= 53 && lsum >= -1074 && (n < 3 || lsum - lmax >= -1074) && hsum <= 1017;
}

/* Some plane sign undecided by the pair's bound. gt / lt: the decided ones
 * (bit 2j: q_j above / below p's plane; bit 2j + 1: p_j above / below q's);
 * the others in plain doubles when pair_on_grid() allows, else by
 * tb_orient3d (its own tighter filter, then the exact stages); then on. */
static __attribute__((noinline)) int slow_path(const tb_vec3 p[3], const tb_vec3 q[3], double bound,
                                               int gt, int lt) {
  int pl = pair_on_grid(p, q), tm = 0, sm = 0;
  for (int j = 0; j < 3; j++) {
    int t = gt >> 2 * j & 1 ? 1 : lt >> 2 * j & 1 ? -1 : s3(pl, p[0], p[1], p[2], q[j]);
    int s = gt >> (2 * j + 1) & 1 ? 1 : lt >> (2 * j + 1) & 1 ? -1 : s3(pl, q[0], q[1], q[2], p[j]);
    tm |= (t > 0) << j | (t < 0) << (j + 3);
    sm |= (s > 0) << j | (s < 0) << (j + 3);
  }
  if ((tm & 7) == 7 || tm >> 3 == 7 || (sm & 7) == 7 || sm >> 3 == 7) return 0;
  return finish(pl, p, q, sm, tm, bound);
}

#define MIN3(a, b, c) ((a) < (b) ? ((a) < (c) ? (a) : (c)) : ((b) < (c) ? (b) : (c)))
#define MAX3(a, b, c) ((a) > (b) ? ((a) > (c) ? (a) : (c)) : ((b) > (c) ? (b) : (c)))

int tb_tritri_exact_portable(const tb_vec3 p[3], const tb_vec3 q[3]) {
  double dx = fmax(MAX3(p[0].x, p[1].x, p[2].x), MAX3(q[0].x, q[1].x, q[2].x)) -
              fmin(MIN3(p[0].x, p[1].x, p[2].x), MIN3(q[0].x, q[1].x, q[2].x));
  double dy = fmax(MAX3(p[0].y, p[1].y, p[2].y), MAX3(q[0].y, q[1].y, q[2].y)) -
              fmin(MIN3(p[0].y, p[1].y, p[2].y), MIN3(q[0].y, q[1].y, q[2].y));
  double dz = fmax(MAX3(p[0].z, p[1].z, p[2].z), MAX3(q[0].z, q[1].z, q[2].z)) -
              fmin(MIN3(p[0].z, p[1].z, p[2].z), MIN3(q[0].z, q[1].z, q[2].z));
  double bound = bound_of(dx, dy, dz);
  int gt = 0, lt = 0; /* the layout of slow_path() */
  for (int j = 0; j < 3; j++) {
    double d = tb_orient3d_fast(p[0], p[1], p[2], q[j]);
    gt |= (d > bound) << 2 * j, lt |= (d < -bound) << 2 * j;
  }
  if ((gt & 0x15) == 0x15 || (lt & 0x15) == 0x15) return 0;
  for (int j = 0; j < 3; j++) {
    double d = tb_orient3d_fast(q[0], q[1], q[2], p[j]);
    gt |= (d > bound) << (2 * j + 1), lt |= (d < -bound) << (2 * j + 1);
  }
  if ((gt & 0x2a) == 0x2a || (lt & 0x2a) == 0x2a) return 0;
  if ((gt | lt) != 0x3f) return slow_path(p, q, bound, gt, lt);
  int tm = (gt & 1) | (gt >> 1 & 2) | (gt >> 2 & 4),
      sm = (gt >> 1 & 1) | (gt >> 2 & 2) | (gt >> 3 & 4);
  return finish(0, p, q, sm | (7 & ~sm) << 3, tm | (7 & ~tm) << 3, bound);
}

#if defined(__SSE2__)
#include <emmintrin.h>

static inline __m128d ld2(const double *a, const double *b) {
  return _mm_loadh_pd(_mm_load_sd(a), b);
}
static inline __m128d swap2(__m128d v) { return _mm_shuffle_pd(v, v, 1); }

/* The fast path (all six signs decided and nonzero, not separated) needs no
 * apex table: the positive-sign bits of the three plane comparisons (bit 2j:
 * q_j above p's plane, bit 2j + 1: p_j above q's) give the canonical orders
 * at once: bits 0-1, 2-3, 4-5 are P1, P2, P3 (indices into p), bits 8-9,
 * 10-11, 12-13 Q1, Q2, Q3, as apex_of and the reversals make them. */
static const unsigned short order_of[64] = {
    0x0000, 0x0000, 0x0000, 0x2424, 0x0000, 0x0000, 0x0924, 0x1218, 0x0000, 0x2409, 0x0000,
    0x1812, 0x0909, 0x1221, 0x2112, 0x0606, 0x0000, 0x0000, 0x1224, 0x0918, 0x0000, 0x0000,
    0x2418, 0x0000, 0x1209, 0x0921, 0x0612, 0x2106, 0x2421, 0x0000, 0x1806, 0x0000, 0x0000,
    0x2412, 0x0000, 0x1809, 0x0912, 0x1206, 0x2109, 0x0621, 0x0000, 0x1824, 0x0000, 0x0000,
    0x2124, 0x0618, 0x0000, 0x0000, 0x1212, 0x0906, 0x0609, 0x2121, 0x2406, 0x0000, 0x1821,
    0x0000, 0x0624, 0x2118, 0x0000, 0x0000, 0x1818, 0x0000, 0x0000, 0x0000};

/* The final pair of signs when the bound left one undecided (bit 0 of dg /
 * dl: the first determinant proved positive / negative; bit 1: the second). */
static __attribute__((noinline)) int finals(const tb_vec3 *P1, const tb_vec3 *P2, const tb_vec3 *P3,
                                            const tb_vec3 *Q1, const tb_vec3 *Q2, const tb_vec3 *Q3,
                                            int dg, int dl) {
  int r1 = dg & 1 ? 1 : dl & 1 ? -1 : tb_orient3d(*P1, *P2, *Q1, *Q2);
  int r2 = dg & 2 ? 1 : dl & 2 ? -1 : tb_orient3d(*P1, *P3, *Q1, *Q3);
  return r1 <= 0 && r2 >= 0;
}

static inline __attribute__((always_inline)) int tritri_exact(const tb_vec3 p[3],
                                                              const tb_vec3 q[3]) {
  /* lanes: (p_i, q_i) per coordinate */
  __m128d x0 = ld2(&p[0].x, &q[0].x), y0 = ld2(&p[0].y, &q[0].y), z0 = ld2(&p[0].z, &q[0].z);
  __m128d x1 = ld2(&p[1].x, &q[1].x), y1 = ld2(&p[1].y, &q[1].y), z1 = ld2(&p[1].z, &q[1].z);
  __m128d x2 = ld2(&p[2].x, &q[2].x), y2 = ld2(&p[2].y, &q[2].y), z2 = ld2(&p[2].z, &q[2].z);
  /* the box extents and bound_of() */
  __m128d lx = _mm_min_pd(_mm_min_pd(x0, x1), x2), hx = _mm_max_pd(_mm_max_pd(x0, x1), x2);
  __m128d ly = _mm_min_pd(_mm_min_pd(y0, y1), y2), hy = _mm_max_pd(_mm_max_pd(y0, y1), y2);
  __m128d lz = _mm_min_pd(_mm_min_pd(z0, z1), z2), hz = _mm_max_pd(_mm_max_pd(z0, z1), z2);
  __m128d lxy = _mm_min_pd(_mm_unpacklo_pd(lx, ly), _mm_unpackhi_pd(lx, ly));
  __m128d hxy = _mm_max_pd(_mm_unpacklo_pd(hx, hy), _mm_unpackhi_pd(hx, hy));
  __m128d dxy = _mm_sub_pd(hxy, lxy);
  __m128d dz = _mm_sub_sd(_mm_max_sd(hz, swap2(hz)), _mm_min_sd(lz, swap2(lz)));
  double bound = bound_of(_mm_cvtsd_f64(dxy), _mm_cvtsd_f64(swap2(dxy)), _mm_cvtsd_f64(dz));
  __m128d bp = _mm_set1_pd(bound), bn = _mm_set1_pd(-bound);
  /* both planes: lane 0 p's normal against q_j - p0, lane 1 q's against p_j - q0 */
  __m128d e1x = x1 - x0, e1y = y1 - y0, e1z = z1 - z0, e2x = x2 - x0, e2y = y2 - y0, e2z = z2 - z0;
  __m128d nx = e1y * e2z - e1z * e2y, ny = e1z * e2x - e1x * e2z, nz = e1x * e2y - e1y * e2x;
  __m128d d0 = nx * (swap2(x0) - x0) + ny * (swap2(y0) - y0) + nz * (swap2(z0) - z0);
  __m128d d1 = nx * (swap2(x1) - x0) + ny * (swap2(y1) - y0) + nz * (swap2(z1) - z0);
  __m128d d2 = nx * (swap2(x2) - x0) + ny * (swap2(y2) - y0) + nz * (swap2(z2) - z0);
  int gt = _mm_movemask_pd(_mm_cmpgt_pd(d0, bp)) | _mm_movemask_pd(_mm_cmpgt_pd(d1, bp)) << 2 |
           _mm_movemask_pd(_mm_cmpgt_pd(d2, bp)) << 4;
  int lt = _mm_movemask_pd(_mm_cmplt_pd(d0, bn)) | _mm_movemask_pd(_mm_cmplt_pd(d1, bn)) << 2 |
           _mm_movemask_pd(_mm_cmplt_pd(d2, bn)) << 4;
  /* bits 0, 2, 4: q's vertices against p's plane; 1, 3, 5: p's against q's */
  if ((gt & 0x15) == 0x15 || (lt & 0x15) == 0x15 || (gt & 0x2a) == 0x2a || (lt & 0x2a) == 0x2a)
    return 0;
  if (__builtin_expect((gt | lt) != 0x3f, 0)) return slow_path(p, q, bound, gt, lt);
  unsigned o = order_of[gt];
  const tb_vec3 *P1 = &p[o & 3], *P2 = &p[o >> 2 & 3], *P3 = &p[o >> 4 & 3];
  const tb_vec3 *Q1 = &q[o >> 8 & 3], *Q2 = &q[o >> 10 & 3], *Q3 = &q[o >> 12 & 3];
  /* lane 0: orient3d(P1, P2, Q1, Q2), lane 1: orient3d(P1, P3, Q1, Q3) */
  __m128d px = _mm_load1_pd(&P1->x), py = _mm_load1_pd(&P1->y), pz = _mm_load1_pd(&P1->z);
  __m128d ux = _mm_load1_pd(&Q1->x) - px, uy = _mm_load1_pd(&Q1->y) - py;
  __m128d uz = _mm_load1_pd(&Q1->z) - pz;
  __m128d ax = ld2(&P2->x, &P3->x) - px, ay = ld2(&P2->y, &P3->y) - py;
  __m128d az = ld2(&P2->z, &P3->z) - pz;
  __m128d bx = ld2(&Q2->x, &Q3->x) - px, by = ld2(&Q2->y, &Q3->y) - py;
  __m128d bz = ld2(&Q2->z, &Q3->z) - pz;
  __m128d d = ax * (uy * bz - uz * by) + ay * (uz * bx - ux * bz) + az * (ux * by - uy * bx);
  int dg = _mm_movemask_pd(_mm_cmpgt_pd(d, bp)), dl = _mm_movemask_pd(_mm_cmplt_pd(d, bn));
  if (__builtin_expect((dg | dl) != 3, 0)) return finals(P1, P2, P3, Q1, Q2, Q3, dg, dl);
  return ((dg & 1) | (dl & 2)) == 0; /* orient3d(P1, P2, Q1, Q2) < 0, the other > 0 */
}
#else
#define tritri_exact tb_tritri_exact_portable
#endif

int tb_tritri_exact(const tb_vec3 p[3], const tb_vec3 q[3]) { return tritri_exact(p, q); }

/* Two pairs per iteration: the core overlaps their dependency chains (20.5
 * against 21.3 ns/pair on the JGT 50/50 mix here). */
void tb_tritri_exact_batch(const tb_vec3 *p, const tb_vec3 *q, int n, unsigned char *out) {
  int i = 0;
  for (; i + 1 < n; i += 2) {
    int a = tritri_exact(p + 3 * i, q + 3 * i), b = tritri_exact(p + 3 * i + 3, q + 3 * i + 3);
    out[i] = (unsigned char)a, out[i + 1] = (unsigned char)b;
  }
  for (; i < n; i++) out[i] = (unsigned char)tritri_exact(p + 3 * i, q + 3 * i);
}
