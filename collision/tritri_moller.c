/* Moller 1997, "A fast triangle-triangle intersection test", Journal of
 * Graphics Tools 2(2):25-30, written from the paper's description:
 *   1. plane of triangle 1, N1 = (V1-V0) x (V2-V0), d1 = -N1·V0; signed
 *      distances of triangle 2's vertices d_Ui = N1·Ui + d1; reject when all
 *      three are nonzero and of one sign; the same with the roles swapped;
 *   2. the planes meet in the line L = O + t D, D = N1 x N2; each triangle
 *      is projected on L by keeping the coordinate of D of largest magnitude
 *      (p_Vi = Vi[index], "the projection on the largest axis");
 *   3. each triangle's interval on L: with V0 the vertex alone on its side,
 *      t1 = p_V0 + (p_V1 - p_V0) d_V0 / (d_V0 - d_V1) and likewise t2 with V2
 *      (the paper's eq. for the interval endpoints); the triangles intersect
 *      when the two intervals overlap. The intervals are closed: they are
 *      rejected only when one ends strictly before the other begins, so
 *      touching counts;
 *   4. coplanar (every distance zero): project on the axis-aligned plane
 *      where the triangles' area is largest (drop N1's largest coordinate);
 *      test every closed edge of triangle 1 against every closed edge of
 *      triangle 2, then containment by one point-in-triangle test each way.
 * Robustness: the paper's epsilon test, |d| < EPSILON sets d = 0, with the
 * paper's code's EPSILON = 1e-6 (absolute, on the unnormalised distances).
 * The 2D edge-edge test is the one the paper's code uses (Antonio, Graphics
 * Gems III: parameters of both segments from two cross products, inclusive
 * bounds; parallel edges report no crossing), and its point-in-triangle is
 * strict (same nonzero side of all three edges): contacts on the boundary
 * are left to the closed edge tests. Plain doubles throughout. */
#include "tb_tritri.h"

#define MOLLER_EPSILON 1e-6

/* Closed 2D segments a0a1 and b0b1 cross (Antonio's test). */
static int edge_edge(const double a0[2], const double a1[2], const double b0[2],
                     const double b1[2]) {
  double ax = a1[0] - a0[0], ay = a1[1] - a0[1];
  double bx = b0[0] - b1[0], by = b0[1] - b1[1];
  double cx = a0[0] - b0[0], cy = a0[1] - b0[1];
  double f = ay * bx - ax * by; /* zero: parallel */
  double d = by * cx - bx * cy; /* a's parameter times f */
  if (f > 0.0) {
    if (d < 0.0 || d > f) return 0;
  } else if (f < 0.0) {
    if (d > 0.0 || d < f) return 0;
  } else {
    return 0;
  }
  double e = ax * cy - ay * cx; /* b's parameter times f */
  if (f > 0.0) return e >= 0.0 && e <= f;
  return e <= 0.0 && e >= f;
}

/* Strictly inside: the point is on the same nonzero side of every edge. */
static int point_in_tri(const double pt[2], double t[3][2]) {
  double s[3];
  for (int i = 0; i < 3; i++) {
    int j = i == 2 ? 0 : i + 1;
    s[i] = (t[j][0] - t[i][0]) * (pt[1] - t[i][1]) - (t[j][1] - t[i][1]) * (pt[0] - t[i][0]);
  }
  return s[0] * s[1] > 0.0 && s[0] * s[2] > 0.0;
}

static int coplanar(tb_vec3 n, const tb_vec3 p[3], const tb_vec3 q[3]) {
  double nx = fabs(n.x), ny = fabs(n.y), nz = fabs(n.z);
  int i0, i1; /* the two coordinates kept */
  if (nx > ny) {
    if (nx > nz)
      i0 = 1, i1 = 2;
    else
      i0 = 0, i1 = 1;
  } else {
    if (nz > ny)
      i0 = 0, i1 = 1;
    else
      i0 = 0, i1 = 2;
  }
  double a[3][2], b[3][2];
  for (int i = 0; i < 3; i++) {
    a[i][0] = tb_comp(p[i], i0), a[i][1] = tb_comp(p[i], i1);
    b[i][0] = tb_comp(q[i], i0), b[i][1] = tb_comp(q[i], i1);
  }
  for (int i = 0; i < 3; i++) {
    int i2 = i == 2 ? 0 : i + 1;
    for (int j = 0; j < 3; j++) {
      int j2 = j == 2 ? 0 : j + 1;
      if (edge_edge(a[i], a[i2], b[j], b[j2])) return 1;
    }
  }
  return point_in_tri(a[0], b) || point_in_tri(b[0], a);
}

/* The interval of a triangle on L from its projections pv and distances d to
 * the other plane; 0 when all distances are zero (coplanar). */
static int interval(const double pv[3], const double d[3], double *lo, double *hi) {
  int k; /* the vertex alone on its side */
  if (d[0] * d[1] > 0.0)
    k = 2;
  else if (d[0] * d[2] > 0.0)
    k = 1;
  else if (d[1] * d[2] > 0.0 || d[0] != 0.0)
    k = 0;
  else if (d[1] != 0.0)
    k = 1;
  else if (d[2] != 0.0)
    k = 2;
  else
    return 0;
  int k1 = k == 2 ? 0 : k + 1, k2 = k1 == 2 ? 0 : k1 + 1;
  double t1 = pv[k] + (pv[k1] - pv[k]) * d[k] / (d[k] - d[k1]);
  double t2 = pv[k] + (pv[k2] - pv[k]) * d[k] / (d[k] - d[k2]);
  *lo = fmin(t1, t2), *hi = fmax(t1, t2);
  return 1;
}

/* Signed distances of the points v to the plane (n, d), with the epsilon test;
 * 0 when all three are nonzero and of one sign. */
static int distances(tb_vec3 n, double d, const tb_vec3 v[3], double out[3]) {
  for (int i = 0; i < 3; i++) {
    out[i] = tb_dot(n, v[i]) + d;
    if (fabs(out[i]) < MOLLER_EPSILON) out[i] = 0.0;
  }
  return !(out[0] * out[1] > 0.0 && out[0] * out[2] > 0.0);
}

int tb_tritri_moller(const tb_vec3 p[3], const tb_vec3 q[3]) {
  tb_vec3 n1 = tb_cross(tb_sub(p[1], p[0]), tb_sub(p[2], p[0]));
  double du[3];
  if (!distances(n1, -tb_dot(n1, p[0]), q, du)) return 0;
  tb_vec3 n2 = tb_cross(tb_sub(q[1], q[0]), tb_sub(q[2], q[0]));
  double dv[3];
  if (!distances(n2, -tb_dot(n2, q[0]), p, dv)) return 0;

  tb_vec3 dir = tb_cross(n1, n2);
  double mx = fabs(dir.x), my = fabs(dir.y), mz = fabs(dir.z);
  int index = 0;
  if (my > mx) index = 1, mx = my;
  if (mz > mx) index = 2;
  double vp[3], up[3];
  for (int i = 0; i < 3; i++) vp[i] = tb_comp(p[i], index), up[i] = tb_comp(q[i], index);

  double a0, a1, b0, b1;
  if (!interval(vp, dv, &a0, &a1)) return coplanar(n1, p, q);
  if (!interval(up, du, &b0, &b1)) return coplanar(n1, p, q);
  return !(a1 < b0 || b1 < a0);
}
