/* Double-precision 3-vectors and 3x3 matrices, header-only and inline.
 * Positions, velocities and forces are stored as flat arrays of tb_vec3. */
#ifndef TB_MATH_H
#define TB_MATH_H

#include <math.h>

typedef struct tb_vec3 {
  double x, y, z;
} tb_vec3;

/* Row-major: m[row][col]. */
typedef struct tb_mat3 {
  double m[3][3];
} tb_mat3;

/* No compound literals: this header is also read by the C++ shims. */
static inline tb_vec3 tb_v3(double x, double y, double z) {
  tb_vec3 r;
  r.x = x, r.y = y, r.z = z;
  return r;
}
static inline tb_vec3 tb_add(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline tb_vec3 tb_sub(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline tb_vec3 tb_scale(tb_vec3 a, double s) { return tb_v3(a.x * s, a.y * s, a.z * s); }
/* a + s*b */
static inline tb_vec3 tb_madd(tb_vec3 a, double s, tb_vec3 b) {
  return tb_v3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}
static inline double tb_dot(tb_vec3 a, tb_vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline tb_vec3 tb_cross(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline double tb_len(tb_vec3 a) { return sqrt(tb_dot(a, a)); }
static inline double tb_dist(tb_vec3 a, tb_vec3 b) { return tb_len(tb_sub(a, b)); }
static inline tb_vec3 tb_normalize(tb_vec3 a) {
  double l = tb_len(a);
  return l > 0.0 ? tb_scale(a, 1.0 / l) : a;
}
static inline tb_vec3 tb_lerp(tb_vec3 a, tb_vec3 b, double t) {
  return tb_madd(a, t, tb_sub(b, a));
}
static inline tb_vec3 tb_vmin(tb_vec3 a, tb_vec3 b) {
  return tb_v3(fmin(a.x, b.x), fmin(a.y, b.y), fmin(a.z, b.z));
}
static inline tb_vec3 tb_vmax(tb_vec3 a, tb_vec3 b) {
  return tb_v3(fmax(a.x, b.x), fmax(a.y, b.y), fmax(a.z, b.z));
}
static inline double tb_comp(tb_vec3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }
static inline int tb_isfinite3(tb_vec3 a) {
  return isfinite(a.x) && isfinite(a.y) && isfinite(a.z);
}

/* Signed volume det[b-a, c-a, d-a] / 6 of tetrahedron (a,b,c,d): positive when
 * d lies on the side of triangle (a,b,c) its normal (b-a)x(c-a) points to. */
static inline double tb_tet_volume(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  return tb_dot(tb_sub(b, a), tb_cross(tb_sub(c, a), tb_sub(d, a))) / 6.0;
}
/* Lame parameters of Young's modulus E and Poisson ratio nu (nu < 1/2). */
static inline void tb_lame(double E, double nu, double *lambda, double *mu) {
  *lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  *mu = E / (2 * (1 + nu));
}
static inline double tb_tri_area(tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  return 0.5 * tb_len(tb_cross(tb_sub(b, a), tb_sub(c, a)));
}

static inline tb_mat3 tb_m3_identity(void) {
  tb_mat3 r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r.m[i][j] = i == j;
  return r;
}
static inline tb_vec3 tb_m3_mulv(tb_mat3 a, tb_vec3 v) {
  return tb_v3(a.m[0][0] * v.x + a.m[0][1] * v.y + a.m[0][2] * v.z,
               a.m[1][0] * v.x + a.m[1][1] * v.y + a.m[1][2] * v.z,
               a.m[2][0] * v.x + a.m[2][1] * v.y + a.m[2][2] * v.z);
}
static inline tb_mat3 tb_m3_mul(tb_mat3 a, tb_mat3 b) {
  tb_mat3 r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++)
      r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
  return r;
}
static inline tb_mat3 tb_m3_transpose(tb_mat3 a) {
  tb_mat3 r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r.m[i][j] = a.m[j][i];
  return r;
}
static inline double tb_m3_det(tb_mat3 a) {
  return a.m[0][0] * (a.m[1][1] * a.m[2][2] - a.m[1][2] * a.m[2][1]) -
         a.m[0][1] * (a.m[1][0] * a.m[2][2] - a.m[1][2] * a.m[2][0]) +
         a.m[0][2] * (a.m[1][0] * a.m[2][1] - a.m[1][1] * a.m[2][0]);
}
/* Cofactor matrix: c[i][j] is the signed minor of a[i][j]; det a = the
 * dot of a row of a with the same row of c, a^-1 = c^T / det a. */
static inline tb_mat3 tb_m3_cofactor(tb_mat3 a) {
  double(*m)[3] = a.m;
  tb_mat3 c;
  c.m[0][0] = m[1][1] * m[2][2] - m[1][2] * m[2][1];
  c.m[0][1] = m[1][2] * m[2][0] - m[1][0] * m[2][2];
  c.m[0][2] = m[1][0] * m[2][1] - m[1][1] * m[2][0];
  c.m[1][0] = m[0][2] * m[2][1] - m[0][1] * m[2][2];
  c.m[1][1] = m[0][0] * m[2][2] - m[0][2] * m[2][0];
  c.m[1][2] = m[0][1] * m[2][0] - m[0][0] * m[2][1];
  c.m[2][0] = m[0][1] * m[1][2] - m[0][2] * m[1][1];
  c.m[2][1] = m[0][2] * m[1][0] - m[0][0] * m[1][2];
  c.m[2][2] = m[0][0] * m[1][1] - m[0][1] * m[1][0];
  return c;
}
/* Rotation of angle (radians) about a unit axis (Rodrigues). */
static inline tb_mat3 tb_m3_rotation(tb_vec3 axis, double angle) {
  double c = cos(angle), s = sin(angle), t = 1.0 - c;
  tb_vec3 u = tb_normalize(axis);
  double w[3] = {u.x, u.y, u.z};
  tb_mat3 r;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) r.m[i][j] = t * w[i] * w[j] + (i == j ? c : 0.0);
  r.m[0][1] -= s * u.z, r.m[1][0] += s * u.z;
  r.m[0][2] += s * u.y, r.m[2][0] -= s * u.y;
  r.m[1][2] -= s * u.x, r.m[2][1] += s * u.x;
  return r;
}

/* Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision
 * Detection, §5.1.5). */
static inline tb_vec3 tb_closest_on_triangle(tb_vec3 p, tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  tb_vec3 ab = tb_sub(b, a), ac = tb_sub(c, a), ap = tb_sub(p, a);
  double d1 = tb_dot(ab, ap), d2 = tb_dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  tb_vec3 bp = tb_sub(p, b);
  double d3 = tb_dot(ab, bp), d4 = tb_dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return tb_madd(a, d1 / (d1 - d3), ab);
  tb_vec3 cp = tb_sub(p, c);
  double d5 = tb_dot(ab, cp), d6 = tb_dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return tb_madd(a, d2 / (d2 - d6), ac);
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return tb_madd(b, (d4 - d3) / ((d4 - d3) + (d5 - d6)), tb_sub(c, b));
  double den = 1.0 / (va + vb + vc);
  return tb_add(a, tb_add(tb_scale(ab, vb * den), tb_scale(ac, vc * den)));
}

#endif
