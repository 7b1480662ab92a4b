/* The thesis's improved projection test, thesis §4.4.2
 * ("基于投影降维的三角形间相交测试算法"), step by step:
 *   1. computing frame on A, B transformed into it (part 1, fig. 4.13,
 *      eqs. 4-3..4-7; tritri_proj.h);
 *   2. the V-plane classification of fig. 4.14 from the signs of B's z*
 *      (part 2): (a) all zero, B_V on the y* axis: V then W rejection by
 *      overlap of collinear segments (fig. 4.15), then the coplanar test in
 *      H; (b) all of one sign: separated; (c) one zero, two of one sign: the
 *      point Q_L = Q_R = Q0; (d) two zero: L_B = Q0 Q1; (e) one zero, two of
 *      opposite signs: Q_L = Q0, Q_R on Q1Q2; (f) none zero: Q_L on Q0Q1,
 *      Q_R on Q0Q2. The cases are read from one 27-entry table indexed by
 *      the three signs, which also gives the vertex rotation ("坐标轮换")
 *      that makes the fixed vertex Q0 (c, e, f; in d the nonzero vertex
 *      becomes Q2), so a fixed edge of B_V crosses the y* axis;
 *   3. the crossing points by eq. 4-9 and fig. 4.19: on edge QiQj,
 *      Q = Qj + t(Qi - Qj) with t = |zj| / (|zi| + |zj|);
 *   4. early rejection on V (L_BV against A_V on the y* axis), then on W
 *      (L_BW against A_W on the x* axis: "W 平面上的类似");
 *   5. in H: a point by edge sides (part 3.(4), fig. 4.18), a segment by
 *      Sun's convex-polygon line clipping (part 3.(2), the thesis's
 *      ref. [58], fig. 4.16, eq. 4-8 and its pseudocode), coplanar triangles by B's edges clipped
 * by A, then a vertex of A inside B (part 3.(3), fig. 4.17). Ambiguities and how they are read:
 *   - eq. 4-8's pseudocode loops i = 0..3 and reads e[i+1], and lists
 *     P3 = P1; we take the closed polygon P0 P1 P2 P3 = P0 and loop over its
 *     three edges (i = 0..2), which is what the text "P_i, i = 0..3" needs;
 *   - "the crossing is (not) on L1" and "Q1Q2 overlaps L1" are decided by
 *     coordinates as in fig. 4.15, on the axis (x* or y*) along which L1
 *     extends more;
 *   - case (c) checks V and W before the point in triangle, as the text;
 *     the coplanar test checks all three vertices of A ("whether some vertex
 *     of A lies in B"); B inside A is found by the clipping of B's edges.
 * Plain doubles and exact comparisons with 0 as in the thesis (no epsilon),
 * so touching and coplanar input is decided by rounding. */
#include "tb_tritri.h"
#include "tritri_proj.h"

enum { CASE_A, CASE_B, CASE_C, CASE_D, CASE_E, CASE_F };

/* Indexed by s0 + 3 s1 + 9 s2, si = 0 (z* == 0), 1 (> 0), 2 (< 0):
 * {case of fig. 4.14, rotation r: the new Qk is the old Q(k+r mod 3)}. */
static const unsigned char cases[27][2] = {
    {CASE_A, 0}, {CASE_D, 1}, {CASE_D, 1}, {CASE_D, 2}, {CASE_C, 2}, {CASE_E, 2}, {CASE_D, 2},
    {CASE_E, 2}, {CASE_C, 2}, {CASE_D, 0}, {CASE_C, 1}, {CASE_E, 1}, {CASE_C, 0}, {CASE_B, 0},
    {CASE_F, 0}, {CASE_E, 0}, {CASE_F, 1}, {CASE_F, 2}, {CASE_D, 0}, {CASE_E, 1}, {CASE_C, 1},
    {CASE_E, 0}, {CASE_F, 2}, {CASE_F, 1}, {CASE_C, 0}, {CASE_F, 0}, {CASE_B, 0}};

static int sign_code(double z) { return (z > 0.0) + 2 * (z < 0.0); }

/* Sun's clipping: the closed segment L1 = (lx,ly)-(rx,ry) against triangle
 * (tx, ty) in H. The line of L1 is a x + b y + c = 0 (eq. 4-8); e[i] is its
 * value at Pi; the pseudocode collects at most two points where the line
 * meets the triangle's boundary (vertices with e == 0, edges with a sign
 * change), then L1 meets the triangle when that point lies on L1 or that
 * segment Q1Q2 overlaps L1. */
static int sun_clip(const double tx[3], const double ty[3], double lx, double ly, double rx,
                    double ry) {
  double a = ry - ly, b = lx - rx, c = rx * ly - lx * ry;
  double e[4];
  for (int i = 0; i < 3; i++) e[i] = a * tx[i] + b * ty[i] + c;
  e[3] = e[0];
  /* Points are compared on the axis along which L1 extends more (fig. 4.15),
   * so only that coordinate of Q1, Q2 is computed. */
  int along_x = fabs(b) >= fabs(a);
  const double *tu = along_x ? tx : ty;
  double s0 = along_x ? lx : ly, s1 = along_x ? rx : ry;
  double qu[2];
  int n = 0;
  if (e[0] == 0.0) qu[0] = tu[0], n = 1;
  for (int i = 0; i < 3; i++) {
    int j = i == 2 ? 0 : i + 1;
    if (e[i + 1] == 0.0) {
      qu[n] = tu[j];
      if (++n == 2) break;
    } else if (e[i] * e[i + 1] < 0.0) {
      qu[n] = tu[i] + e[i] / (e[i] - e[i + 1]) * (tu[j] - tu[i]);
      if (++n == 2) break;
    }
  }
  if (n == 0) return 0;
  return tb_proj_overlap(qu[0], n == 1 ? qu[0] : qu[1], s0, s1);
}

/* Part 3.(3): B's edges clipped by A, then A inside B. */
static int coplanar(const tb_proj *f) {
  for (int i = 0; i < 3; i++) {
    int j = i == 2 ? 0 : i + 1;
    if (sun_clip(f->ax, f->ay, f->x[i], f->y[i], f->x[j], f->y[j])) return 1;
  }
  for (int k = 0; k < 3; k++)
    if (tb_proj_point_in_tri(f->ax[k], f->ay[k], f->x, f->y)) return 1;
  return 0;
}

int tb_tritri_improved(const tb_vec3 p[3], const tb_vec3 q[3]) {
  tb_proj f;
  tb_proj_frame(p, q, &f);
  const unsigned char *k = cases[sign_code(f.z[0]) + 3 * sign_code(f.z[1]) + 9 * sign_code(f.z[2])];
  if (k[0] == CASE_B) return 0;
  if (k[0] == CASE_A) {
    double ylo = fmin(f.y[0], fmin(f.y[1], f.y[2])), yhi = fmax(f.y[0], fmax(f.y[1], f.y[2]));
    if (!tb_proj_overlap(ylo, yhi, 0.0, f.ay[0])) return 0; /* B_V against A_V */
    double xlo = fmin(f.x[0], fmin(f.x[1], f.x[2])), xhi = fmax(f.x[0], fmax(f.x[1], f.x[2]));
    if (!tb_proj_overlap(xlo, xhi, f.wlo, f.whi)) return 0; /* B_W against A_W */
    return coplanar(&f);
  }
  int i0 = k[1], i1 = i0 == 2 ? 0 : i0 + 1, i2 = i1 == 2 ? 0 : i1 + 1;
  const double *x = f.x, *y = f.y, *z = f.z;
  double lx, ly, rx, ry, t;
  switch (k[0]) {
    case CASE_C: /* one point, Q0 */
      if (!tb_proj_overlap(y[i0], y[i0], 0.0, f.ay[0])) return 0;
      if (!tb_proj_overlap(x[i0], x[i0], f.wlo, f.whi)) return 0;
      return tb_proj_point_in_tri(x[i0], y[i0], f.ax, f.ay);
    case CASE_D: /* Q0 Q1 */
      lx = x[i0], ly = y[i0], rx = x[i1], ry = y[i1];
      break;
    case CASE_E: /* Q0, and Q1Q2 crossing H */
      lx = x[i0], ly = y[i0];
      t = fabs(z[i2]) / (fabs(z[i1]) + fabs(z[i2]));
      rx = x[i2] + t * (x[i1] - x[i2]), ry = y[i2] + t * (y[i1] - y[i2]);
      break;
    default: /* CASE_F: Q0Q1 and Q0Q2 crossing H */
      t = fabs(z[i1]) / (fabs(z[i1]) + fabs(z[i0]));
      lx = x[i1] + t * (x[i0] - x[i1]), ly = y[i1] + t * (y[i0] - y[i1]);
      t = fabs(z[i2]) / (fabs(z[i2]) + fabs(z[i0]));
      rx = x[i2] + t * (x[i0] - x[i2]), ry = y[i2] + t * (y[i0] - y[i2]);
      break;
  }
  if (!tb_proj_overlap(ly, ry, 0.0, f.ay[0])) return 0; /* L_BV against A_V */
  if (!tb_proj_overlap(lx, rx, f.wlo, f.whi)) return 0; /* L_BW against A_W */
  return sun_clip(f.ax, f.ay, lx, ly, rx, ry);          /* L_B against A_H */
}
