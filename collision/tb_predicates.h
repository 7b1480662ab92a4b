/* Orientation predicates, exact in sign (Shewchuk 1997, "Adaptive precision
 * floating-point arithmetic and fast robust geometric predicates": a double
 * determinant with a forward error bound, and an exact fallback in
 * floating-point expansions). Written for this project; see predicates.c for
 * the derivation of the bounds and the range of the expansion stage.
 *
 * Conventions:
 *   orient2d(a, b, c) = det[b - a, c - a]: > 0 when a, b, c turn counter-
 *     clockwise (c left of the directed line a -> b);
 *   orient3d(a, b, c, d) = det[b - a, c - a, d - a] = ((b-a) x (c-a)) . (d-a):
 *     > 0 when d lies on the side the normal (b-a) x (c-a) points to (the sign
 *     of tb_tet_volume; it is the opposite of Shewchuk's orient3d).
 * The exact versions return -1, 0 or +1, correct for all finite doubles
 * (subnormals included): the expansion stage covers the range stated in
 * predicates.c; inputs beyond it are decided with GMP integers. Non-finite
 * input gives 0. */
#ifndef TB_PREDICATES_H
#define TB_PREDICATES_H

#include <math.h>

#include "core/tb_math.h"

/* The filters' error bounds (predicates.c derives them; u = 2^-53):
 * |det| > TB_O2D_ERR * perm + TB_PRED_TINY decides the sign of orient2d, with
 * perm = |ux*vy| + |uy*vx| as computed; for orient3d in cofactor form
 * det = sum_i u_i * (v_j w_k - v_k w_j), perm = sum_i |u_i| *
 * (|v_j w_k| + |v_k w_j| + TB_PRED_TINY) and the bound TB_O3D_ERR. The TINY
 * terms cover products that underflow. */
#define TB_O2D_ERR (4.0 * 0x1p-53)
#define TB_O3D_ERR (8.0 * 0x1p-53)
#define TB_PRED_TINY 0x1p-960

/* Plain double determinants: no guarantee on the sign. */
static inline double tb_orient2d_fast(double ax, double ay, double bx, double by, double cx,
                                      double cy) {
  return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}
static inline double tb_orient3d_fast(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  return tb_dot(tb_sub(b, a), tb_cross(tb_sub(c, a), tb_sub(d, a)));
}

/* Exact signs without the filter: floating-point expansions, GMP beyond
 * their range. */
int tb_orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy);
int tb_orient3d_exact(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d);
/* The expansion stage alone: the sign, or 2 when the input is outside its
 * range (for the tests). */
int tb_orient2d_expansion(double ax, double ay, double bx, double by, double cx, double cy);
int tb_orient3d_expansion(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d);

/* Exact signs: the filter inline, the exact stage when it cannot decide
 * (including overflow, where the filter sees inf or NaN). */
static inline int tb_orient2d(double ax, double ay, double bx, double by, double cx, double cy) {
  double l = (bx - ax) * (cy - ay), r = (by - ay) * (cx - ax);
  double det = l - r, bound = TB_O2D_ERR * (fabs(l) + fabs(r)) + TB_PRED_TINY;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return tb_orient2d_exact(ax, ay, bx, by, cx, cy);
}
static inline int tb_orient3d(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  tb_vec3 u = tb_sub(b, a), v = tb_sub(c, a), w = tb_sub(d, a);
  double yz = v.y * w.z, zy = v.z * w.y, zx = v.z * w.x, xz = v.x * w.z;
  double xy = v.x * w.y, yx = v.y * w.x;
  double det = u.x * (yz - zy) + u.y * (zx - xz) + u.z * (xy - yx);
  double perm = fabs(u.x) * (fabs(yz) + fabs(zy) + TB_PRED_TINY) +
                fabs(u.y) * (fabs(zx) + fabs(xz) + TB_PRED_TINY) +
                fabs(u.z) * (fabs(xy) + fabs(yx) + TB_PRED_TINY);
  double bound = TB_O3D_ERR * perm + TB_PRED_TINY;
  if (det > bound) return 1;
  if (-det > bound) return -1;
  return tb_orient3d_exact(a, b, c, d);
}

/* Shared by tritri_guigue.c and tritri_exact.c (defined in tritri_exact.c):
 * when p or q has zero area (decided exactly), the exact answer for the
 * closed sets (segment or point against triangle, segment or point); -1 when
 * both triangles have positive area. */
int tb_tritri_exact_degenerate(const tb_vec3 p[3], const tb_vec3 q[3]);
/* tb_tritri_exact without SIMD (what non-x86 builds run), for the tests. */
int tb_tritri_exact_portable(const tb_vec3 p[3], const tb_vec3 q[3]);

#endif
