/* Exact orientation predicates (tb_predicates.h), after the ideas of
 * Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
 * geometric predicates", written for this project.
 *
 * Stage 1, the filter (inline in the header). Model: each operation rounds,
 * fl(x op y) = (x op y)(1 + d) + h with |d| <= u = 2^-53 and |h| <= 2^-1075,
 * h = 0 for + and - (sums are exact below the normal range). Ignoring h, a
 * cofactor evaluation of orient3d rounds each of its products of three
 * differences 8 times: the three differences, the two products, the minor's
 * subtraction and two of the three additions; the last addition cannot change
 * the sign, so |det - exact| <= gamma_7 * perm with gamma_7 = 7u/(1 - 7u) and
 * perm the permanent (the same sum with every term made positive). Comparing
 * the computed det against the computed perm costs a few more factors
 * (1 + u), which the constant 8u covers with room: 7u + O(u^2) < 8u. For
 * orient2d the count is 4, less the last: 3u + O(u^2) < 4u. The h terms: an
 * underflowed product inside a minor adds at most 2^-1074 * |u_i| (times
 * 1 + O(u)); the perm carries TINY = 2^-960 next to each minor, so the bound
 * gains 8u * 2^-960 * |u_i| = 2^-1010 |u_i|, which covers it (when that term
 * underflows, |u_i| < 2^-12 and the error is below 2^-1086). The final
 * products' and the bound's own underflows are below 2^-1070, covered by the
 * absolute TINY. Overflow makes det or the bound inf or NaN: no comparison
 * succeeds and the exact stage decides.
 *
 * Stage 2, floating-point expansions. Two-sum (Knuth) and two-product
 * (fma() when the target has a fused multiply-add, else Dekker's split) are
 * exact; expansions (sums of doubles, nonoverlapping, increasing magnitude)
 * are added by repeated grow-expansion, scaled by scale-expansion and
 * compressed (Shewchuk's theorems 10, 19 and 23, valid with round-to-nearest-
 * even); the sign of the value is the sign of the largest component. The
 * determinant is taken in exact differences (two-sum), expanded along the x
 * column so every minor is a (y, z) product. Exactness needs every product's
 * error to be representable and no overflow. Per axis k, read from the
 * representation: hi_k with every |coordinate| < 2^hi_k, lo_k the lowest set
 * bit of all of them, span_k = hi_k - lo_k (at most 53 for one double, up to
 * 2098 across doubles). Stage 2 runs on the coordinates as they are when
 * lo_y + lo_z >= -1074, lo_x + lo_y + lo_z >= -1074 (products of three stay
 * multiples of 2^-1074), hi_k <= 990, hi_y + hi_z <= 986 and hi_x + hi_y +
 * hi_z <= 1010 (every intermediate below 2^1018, Dekker's split included);
 * otherwise each axis is first scaled by its own power of two (the sign of a
 * determinant is unchanged by positive column scalings; the scaling is exact
 * as the results stay representable) to put its lowest bit at 2^-358
 * (orient2d: lo_x + lo_y >= -1074, hi_k <= 990, hi_x + hi_y <= 1010, lowest
 * bits moved to 2^-537). Range of this stage, whatever the magnitudes:
 *   orient3d: span_k <= 1348, span_y + span_z <= 1702, sum span_k <= 2084;
 *   orient2d: span_k <= 1527, span_x + span_y <= 2084.
 * It covers every input whose coordinates on each axis lie within a factor
 * 2^600 of each other (and subnormals among values near 1 on one axis).
 * Shortcuts: an axis whose coordinates are all equal gives 0; when the
 * differences are exact and their spans add up to at most 50 bits (47 +
 * 3 for orient3d, 52 + 1 for orient2d) the plain double evaluation is exact
 * (dyadic and integer data, the degenerate configurations of the tests).
 *
 * Stage 3, beyond that range: every coordinate becomes an exact integer (its
 * axis scaled by 2^-lo) in GMP, and the determinant is taken in integers. */
#include <float.h>
#include <gmp.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "tb_predicates.h"

#if !defined(FLT_EVAL_METHOD) || FLT_EVAL_METHOD != 0
#error "the exact predicates need double operations rounded to double (FLT_EVAL_METHOD 0)"
#endif

/* ---- exact building blocks ---- */

static inline void two_sum(double a, double b, double *x, double *y) {
  double s = a + b, bv = s - a, av = s - bv;
  *x = s, *y = (a - av) + (b - bv);
}

static inline void two_prod(double a, double b, double *x, double *y) {
  double p = a * b;
#ifdef __FP_FAST_FMA
  *y = fma(a, b, -p);
#else
  const double split = 134217729.0; /* 2^27 + 1: halves of 26 bits */
  double c = split * a, ahi = c - (c - a), alo = a - ahi;
  double d = split * b, bhi = d - (d - b), blo = b - bhi;
  *y = alo * blo - (((p - ahi * bhi) - alo * bhi) - ahi * blo);
#endif
  *x = p;
}

/* e += b in place (grow-expansion, zero elimination); e has room n + 1. */
static int grow(int n, double *e, double b) {
  double q = b;
  int k = 0;
  for (int i = 0; i < n; i++) {
    double h;
    two_sum(q, e[i], &q, &h);
    if (h != 0.0) e[k++] = h;
  }
  if (q != 0.0 || k == 0) e[k++] = q;
  return k;
}

/* h = e + f; h has room max(m + n, 1) and is not e or f. */
static int ex_sum(int m, const double *e, int n, const double *f, double *h) {
  for (int i = 0; i < m; i++) h[i] = e[i];
  int k = m;
  for (int j = 0; j < n; j++)
    if (f[j] != 0.0) k = grow(k, h, f[j]);
  if (k == 0) h[k++] = 0.0;
  return k;
}

/* h = b * e (scale-expansion, zero elimination); h has room 2n. */
static int ex_scale(int n, const double *e, double b, double *h) {
  double q, t;
  int k = 0;
  two_prod(e[0], b, &q, &t);
  if (t != 0.0) h[k++] = t;
  for (int i = 1; i < n; i++) {
    double p1, p0, s, r;
    two_prod(e[i], b, &p1, &p0);
    two_sum(q, p0, &s, &r);
    if (r != 0.0) h[k++] = r;
    two_sum(p1, s, &q, &r);
    if (r != 0.0) h[k++] = r;
  }
  if (q != 0.0 || k == 0) h[k++] = q;
  return k;
}

/* Compress in place (two sweeps of two-sums); the value is unchanged. */
static int ex_compress(int n, double *e) {
  double g[256];
  int bottom = n - 1;
  double q = e[n - 1];
  for (int i = n - 2; i >= 0; i--) {
    double s, r;
    two_sum(q, e[i], &s, &r);
    if (r != 0.0) {
      g[bottom--] = s;
      q = r;
    } else {
      q = s;
    }
  }
  int top = 0;
  for (int i = bottom + 1; i < n; i++) {
    double s, r;
    two_sum(g[i], q, &s, &r);
    if (r != 0.0) e[top++] = r;
    q = s;
  }
  e[top++] = q;
  return top;
}

static int ex_sign(int n, const double *e) { return (e[n - 1] > 0.0) - (e[n - 1] < 0.0); }

/* a - b as an expansion of one or two components. */
static int ex_diff(double a, double b, double *h) {
  double x, y;
  two_sum(a, -b, &x, &y);
  if (y == 0.0) return h[0] = x, 1;
  h[0] = y, h[1] = x;
  return 2;
}

/* h = e * f for e of at most 16 components and f of one or two (an exact
 * difference); h has room 4m. */
static int ex_mul(int m, const double *e, int n, const double *f, double *h) {
  if (n == 1) return ex_compress(ex_scale(m, e, f[0], h), h);
  double a[32], b[32];
  int na = ex_scale(m, e, f[0], a), nb = ex_scale(m, e, f[1], b);
  return ex_compress(ex_sum(na, a, nb, b, h), h);
}

/* ---- exponent ranges and per-axis scaling ---- */

/* Nonzero finite v: |v| < 2^hi, and v is a multiple of 2^lo (its last set
 * bit), read from the representation. */
static void bit_range(double v, int *hi, int *lo) {
  uint64_t b;
  memcpy(&b, &v, sizeof b);
  int e = (int)(b >> 52 & 0x7ff);
  uint64_t m = b & 0xfffffffffffffULL;
  if (e) {
    m |= 1ULL << 52;
    *hi = e - 1022, *lo = e - 1075 + __builtin_ctzll(m);
  } else { /* subnormal: m 2^-1074 */
    *hi = 64 - __builtin_clzll(m) - 1074, *lo = -1074 + __builtin_ctzll(m);
  }
}

/* The range over the nonzero values among v[0..n-1]; 0 when all are zero. */
static int range_of(const double *v, int n, int *hi, int *lo) {
  int any = 0;
  *hi = -5000, *lo = 5000;
  for (int i = 0; i < n; i++) {
    if (v[i] == 0.0) continue;
    int h, l;
    bit_range(v[i], &h, &l);
    *hi = h > *hi ? h : *hi, *lo = l < *lo ? l : *lo, any = 1;
  }
  return any;
}

/* Ranges of the coordinates on each of dim axes (n points, row-major):
 * 0 when some axis is constant, which makes the determinant 0. */
static int axis_ranges(const double *pt, int n, int dim, int *hi, int *lo) {
  for (int k = 0; k < dim; k++) {
    double v[4];
    int same = 1;
    for (int i = 0; i < n; i++) v[i] = pt[i * dim + k], same &= v[i] == v[0];
    if (same) return 0;
    range_of(v, n, &hi[k], &lo[k]);
  }
  return 1;
}

static int finite_all(const double *v, int n) {
  for (int i = 0; i < n; i++)
    if (!isfinite(v[i])) return 0;
  return 1;
}

/* The ranges where stage 2 is exact (see the top of the file), with T_k = hi_k
 * and the last bits at lo_k. */
static int o2d_fits(const int *hi, const int *lo) {
  return lo[0] + lo[1] >= -1074 && hi[0] <= 990 && hi[1] <= 990 && hi[0] + hi[1] <= 1010;
}
static int o3d_fits(const int *hi, const int *lo) {
  return lo[1] + lo[2] >= -1074 && lo[0] + lo[1] + lo[2] >= -1074 && hi[0] <= 990 && hi[1] <= 990 &&
         hi[2] <= 990 && hi[1] + hi[2] <= 986 && hi[0] + hi[1] + hi[2] <= 1010;
}

/* Fits as it is, or after moving each axis's last bits to 2^target (exact
 * power-of-two scaling of pt); 0 when neither. */
static int fit_or_scale(double *pt, int n, int dim, int *hi, int *lo, int target,
                        int (*fits)(const int *, const int *)) {
  if (fits(hi, lo)) return 1;
  int h[3], l[3];
  for (int k = 0; k < dim; k++) h[k] = hi[k] + target - lo[k], l[k] = target;
  if (!fits(h, l)) return 0;
  for (int k = 0; k < dim; k++)
    for (int i = 0; i < n; i++) pt[i * dim + k] = ldexp(pt[i * dim + k], target - lo[k]);
  return 1;
}

/* ---- stage 2: a shortcut when doubles are exact, then expansions ---- */

/* The shortcut: differences of the raw coordinates that are exact (two-sum
 * tail 0), with bit spans per axis s_k = hi_k - lo_k over the differences
 * (lowest set bit to top) adding up to at most 53 - extra: every product and
 * sum of the cofactor evaluation is then an exact double, provided products
 * stay multiples of 2^-1074 and below 2^1023 (checked). Returns the sign, or
 * 2 when the shortcut does not apply. d holds the differences, dim per row. */
static int plain_exact(const double *d, int rows, int dim, int extra, double det) {
  int hi[3], lo[3], span = 0, los = 0, his = 0;
  for (int k = 0; k < dim; k++) {
    double v[3];
    for (int r = 0; r < rows; r++) v[r] = d[r * dim + k];
    if (!range_of(v, rows, &hi[k], &lo[k])) return 0; /* a zero column */
    span += hi[k] - lo[k], los += lo[k], his += hi[k];
  }
  if (span + extra > 53 || los < -1074 || lo[dim - 2] + lo[dim - 1] < -1074 || his + extra > 1020 ||
      hi[dim - 2] + hi[dim - 1] > 1020)
    return 2;
  return (det > 0) - (det < 0);
}

static int o2d_plain(double pt[3][2]) {
  double d[4], t = 0.0;
  for (int r = 0; r < 2; r++)
    for (int k = 0; k < 2; k++) {
      double y;
      two_sum(pt[r + 1][k], -pt[0][k], &d[r * 2 + k], &y);
      t = y != 0.0 ? 1.0 : t;
    }
  if (t != 0.0) return 2;
  return plain_exact(d, 2, 2, 1, d[0] * d[3] - d[1] * d[2]);
}

/* det[u; v; w] = u_x (v_y w_z - v_z w_y) - v_x (u_y w_z - u_z w_y)
 *              + w_x (u_y v_z - u_z v_y), rows u, v, w in d. */
static int o3d_plain(double pt[4][3]) {
  double d[9], t = 0.0;
  for (int r = 0; r < 3; r++)
    for (int k = 0; k < 3; k++) {
      double y;
      two_sum(pt[r + 1][k], -pt[0][k], &d[r * 3 + k], &y);
      t = y != 0.0 ? 1.0 : t;
    }
  if (t != 0.0) return 2;
  double det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[3] * (d[1] * d[8] - d[2] * d[7]) +
               d[6] * (d[1] * d[5] - d[2] * d[4]);
  return plain_exact(d, 3, 3, 3, det);
}

static int o2d_expansion(double pt[3][2]) {
  int hi[2], lo[2];
  if (!axis_ranges(&pt[0][0], 3, 2, hi, lo)) return 0;
  if (!fit_or_scale(&pt[0][0], 3, 2, hi, lo, -537, o2d_fits)) return 2;
  double ux[2], uy[2], vx[2], vy[2], l[8], r[8], det[16];
  int nux = ex_diff(pt[1][0], pt[0][0], ux), nuy = ex_diff(pt[1][1], pt[0][1], uy);
  int nvx = ex_diff(pt[2][0], pt[0][0], vx), nvy = ex_diff(pt[2][1], pt[0][1], vy);
  int nl = ex_mul(nux, ux, nvy, vy, l), nr = ex_mul(nuy, uy, nvx, vx, r);
  for (int i = 0; i < nr; i++) r[i] = -r[i];
  int n = ex_compress(ex_sum(nl, l, nr, r, det), det);
  return ex_sign(n, det);
}

/* a_y b_z - a_z b_y for two-component rows; h has room 16. */
static int minor_yz(int na[3], double a[3][2], int nb[3], double b[3][2], double *h) {
  double l[8], r[8];
  int nl = ex_mul(na[1], a[1], nb[2], b[2], l), nr = ex_mul(na[2], a[2], nb[1], b[1], r);
  for (int i = 0; i < nr; i++) r[i] = -r[i];
  return ex_compress(ex_sum(nl, l, nr, r, h), h);
}

static int o3d_expansion(double pt[4][3]) {
  int hi[3], lo[3];
  if (!axis_ranges(&pt[0][0], 4, 3, hi, lo)) return 0;
  if (!fit_or_scale(&pt[0][0], 4, 3, hi, lo, -358, o3d_fits)) return 2;
  double u[3][2], v[3][2], w[3][2];
  int nu[3], nv[3], nw[3];
  for (int k = 0; k < 3; k++) {
    nu[k] = ex_diff(pt[1][k], pt[0][k], u[k]);
    nv[k] = ex_diff(pt[2][k], pt[0][k], v[k]);
    nw[k] = ex_diff(pt[3][k], pt[0][k], w[k]);
  }
  /* the same cofactor form as o3d_plain */
  double m[16], t1[64], t2[64], t3[64], s12[128], det[192];
  int nm = minor_yz(nv, v, nw, w, m);
  int n1 = ex_mul(nm, m, nu[0], u[0], t1);
  nm = minor_yz(nu, u, nw, w, m);
  int n2 = ex_mul(nm, m, nv[0], v[0], t2);
  for (int i = 0; i < n2; i++) t2[i] = -t2[i];
  nm = minor_yz(nu, u, nv, v, m);
  int n3 = ex_mul(nm, m, nw[0], w[0], t3);
  int n12 = ex_sum(n1, t1, n2, t2, s12);
  int n = ex_compress(ex_sum(n12, s12, n3, t3, det), det);
  return ex_sign(n, det);
}

/* ---- stage 3: GMP integers ---- */

/* z = v 2^-lo, an integer since v is a multiple of 2^lo. */
static void to_mpz(mpz_t z, double v, int lo) {
  if (v == 0.0) {
    mpz_set_ui(z, 0);
    return;
  }
  int e;
  double m = frexp(v, &e); /* v = (m 2^53) 2^(e - 53), 1/2 <= |m| < 1 */
  mpz_set_d(z, ldexp(m, 53));
  if (e - 53 >= lo)
    mpz_mul_2exp(z, z, (mp_bitcnt_t)(e - 53 - lo));
  else
    mpz_tdiv_q_2exp(z, z, (mp_bitcnt_t)(lo - e + 53)); /* exact: trailing zeros */
}

/* Integer coordinates of n points of dim coordinates, each axis scaled by
 * 2^-lo; 0 when some axis is constant (determinant 0). */
static int gmp_points(const double *pt, int n, int dim, mpz_t *z) {
  int hi[3], lo[3];
  if (!axis_ranges(pt, n, dim, hi, lo)) return 0;
  for (int k = 0; k < dim; k++)
    for (int i = 0; i < n; i++) to_mpz(z[i * dim + k], pt[i * dim + k], lo[k]);
  return 1;
}

static int o2d_gmp(double pt[3][2]) {
  mpz_t z[6], l, r;
  for (int i = 0; i < 6; i++) mpz_init(z[i]);
  mpz_inits(l, r, NULL);
  int s = 0;
  if (gmp_points(&pt[0][0], 3, 2, z)) {
    for (int i = 2; i < 6; i++) mpz_sub(z[i], z[i], z[i % 2]);
    mpz_mul(l, z[2], z[5]); /* ux vy */
    mpz_mul(r, z[3], z[4]); /* uy vx */
    mpz_sub(l, l, r);
    s = mpz_sgn(l);
  }
  for (int i = 0; i < 6; i++) mpz_clear(z[i]);
  mpz_clears(l, r, NULL);
  return s;
}

static int o3d_gmp(double pt[4][3]) {
  mpz_t z[12], a, b, det;
  for (int i = 0; i < 12; i++) mpz_init(z[i]);
  mpz_inits(a, b, det, NULL);
  int s = 0;
  if (gmp_points(&pt[0][0], 4, 3, z)) {
    for (int i = 3; i < 12; i++) mpz_sub(z[i], z[i], z[i % 3]);
    mpz_t *u = z + 3, *v = z + 6, *w = z + 9;
    mpz_set_ui(det, 0);
    for (int k = 0; k < 3; k++) { /* det += u_k (v_{k+1} w_{k+2} - v_{k+2} w_{k+1}) */
      int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
      mpz_mul(a, v[k1], w[k2]);
      mpz_mul(b, v[k2], w[k1]);
      mpz_sub(a, a, b);
      mpz_addmul(det, u[k], a);
    }
    s = mpz_sgn(det);
  }
  for (int i = 0; i < 12; i++) mpz_clear(z[i]);
  mpz_clears(a, b, det, NULL);
  return s;
}

/* ---- public ---- */

int tb_orient2d_expansion(double ax, double ay, double bx, double by, double cx, double cy) {
  double pt[3][2] = {{ax, ay}, {bx, by}, {cx, cy}};
  if (!finite_all(&pt[0][0], 6)) return 0;
  return o2d_expansion(pt);
}

int tb_orient3d_expansion(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  double pt[4][3] = {{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}, {d.x, d.y, d.z}};
  if (!finite_all(&pt[0][0], 12)) return 0;
  return o3d_expansion(pt);
}

static int same2(const double *a, const double *b) { return a[0] == b[0] && a[1] == b[1]; }
static int same3(const double *a, const double *b) {
  return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

int tb_orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  double pt[3][2] = {{ax, ay}, {bx, by}, {cx, cy}};
  if (!finite_all(&pt[0][0], 6)) return 0;
  if (same2(pt[0], pt[1]) || same2(pt[0], pt[2]) || same2(pt[1], pt[2])) return 0; /* shortcut */
  int s = o2d_plain(pt);
  if (s != 2) return s;
  s = o2d_expansion(pt);
  if (s != 2) return s;
  double raw[3][2] = {{ax, ay}, {bx, by}, {cx, cy}};
  return o2d_gmp(raw);
}

int tb_orient3d_exact(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  double pt[4][3] = {{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}, {d.x, d.y, d.z}};
  if (!finite_all(&pt[0][0], 12)) return 0;
  for (int i = 0; i < 4; i++) /* shortcut: a repeated point */
    for (int j = i + 1; j < 4; j++)
      if (same3(pt[i], pt[j])) return 0;
  int s = o3d_plain(pt);
  if (s != 2) return s;
  s = o3d_expansion(pt);
  if (s != 2) return s;
  double raw[4][3] = {{a.x, a.y, a.z}, {b.x, b.y, b.z}, {c.x, c.y, c.z}, {d.x, d.y, d.z}};
  return o3d_gmp(raw);
}
