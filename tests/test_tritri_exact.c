/* Tests of the exact predicates (collision/predicates.c) and of the exact
 * triangle-triangle tests (exact, guigue-exact; plain guigue is measured, not
 * required). The oracles are independent of the code under test:
 *  - predicates: the determinant in GMP rationals (mpq_t, exact from doubles);
 *  - triangles: closed triangles P, Q meet iff 0 lies in the convex hull of
 *    the nine points p_i - q_j (the Minkowski difference), iff (Caratheodory)
 *    0 lies in a point, segment, triangle or tetrahedron of them; each of
 *    those is a sign test on GMP integer determinants (every axis scaled by
 *    its own power of two so all coordinates are integers).
 * Pairs are built with exactly representable coordinates (small integers,
 * dyadic fractions, exact offsets, power-of-two scalings, 1-ulp nudges), so
 * each family is exactly the configuration it names. */
#include <gmp.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_pairs.h"
#include "collision/tb_predicates.h"
#include "collision/tb_tritri.h"
#include "core/tb_rng.h"
#include "measure/tb_pairgen.h"

/* ---- oracles ---- */

static int q_orient2d(const double v[6]) {
  mpq_t a[6], l, r;
  for (int i = 0; i < 6; i++) mpq_init(a[i]), mpq_set_d(a[i], v[i]);
  mpq_inits(l, r, NULL);
  for (int i = 2; i < 6; i++) mpq_sub(a[i], a[i], a[i % 2]);
  mpq_mul(l, a[2], a[5]), mpq_mul(r, a[3], a[4]), mpq_sub(l, l, r);
  int s = mpq_sgn(l);
  for (int i = 0; i < 6; i++) mpq_clear(a[i]);
  mpq_clears(l, r, NULL);
  return s;
}

static int q_orient3d(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) {
  const tb_vec3 pt[4] = {a, b, c, d};
  mpq_t m[4][3], t, s, det;
  for (int i = 0; i < 4; i++)
    for (int k = 0; k < 3; k++) mpq_init(m[i][k]), mpq_set_d(m[i][k], tb_comp(pt[i], k));
  mpq_inits(t, s, det, NULL);
  for (int i = 1; i < 4; i++)
    for (int k = 0; k < 3; k++) mpq_sub(m[i][k], m[i][k], m[0][k]);
  for (int k = 0; k < 3; k++) {
    int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    mpq_mul(t, m[2][k1], m[3][k2]), mpq_mul(s, m[2][k2], m[3][k1]);
    mpq_sub(t, t, s), mpq_mul(t, t, m[1][k]), mpq_add(det, det, t);
  }
  int r = mpq_sgn(det);
  for (int i = 0; i < 4; i++)
    for (int k = 0; k < 3; k++) mpq_clear(m[i][k]);
  mpq_clears(t, s, det, NULL);
  return r;
}

static void z_of(mpz_t z, double v, int lo) {
  if (v == 0.0) {
    mpz_set_ui(z, 0);
    return;
  }
  int e;
  double m = frexp(v, &e);
  mpz_set_d(z, ldexp(m, 53));
  mpz_mul_2exp(z, z, (mp_bitcnt_t)(e - 53 - lo));
}

static int oracle(const tb_vec3 p[3], const tb_vec3 q[3]) {
  mpz_t d[9][3], c[9][9][3], t, u, n[3];
  signed char det[9][9][9];
  int lo[3];
  for (int k = 0; k < 3; k++) {
    lo[k] = 0;
    for (int i = 0; i < 6; i++) {
      double v = tb_comp(i < 3 ? p[i] : q[i - 3], k);
      int e;
      if (v != 0.0 && (frexp(v, &e), e - 53 < lo[k])) lo[k] = e - 53;
    }
  }
  mpz_inits(t, u, n[0], n[1], n[2], NULL);
  for (int a = 0; a < 9; a++)
    for (int k = 0; k < 3; k++) {
      mpz_init(d[a][k]);
      z_of(t, tb_comp(p[a / 3], k), lo[k]), z_of(u, tb_comp(q[a % 3], k), lo[k]);
      mpz_sub(d[a][k], t, u);
    }
  for (int a = 0; a < 9; a++)
    for (int b = a + 1; b < 9; b++)
      for (int k = 0; k < 3; k++) {
        int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        mpz_init(c[a][b][k]);
        mpz_mul(c[a][b][k], d[a][k1], d[b][k2]), mpz_submul(c[a][b][k], d[a][k2], d[b][k1]);
      }
  int found = 0;
  for (int a = 0; a < 9 && !found; a++) /* a point: some p_i = q_j */
    found = !mpz_sgn(d[a][0]) && !mpz_sgn(d[a][1]) && !mpz_sgn(d[a][2]);
  for (int a = 0; a < 9 && !found; a++) /* a segment through 0 */
    for (int b = a + 1; b < 9 && !found; b++) {
      if (mpz_sgn(c[a][b][0]) || mpz_sgn(c[a][b][1]) || mpz_sgn(c[a][b][2])) continue;
      mpz_mul(t, d[a][0], d[b][0]), mpz_addmul(t, d[a][1], d[b][1]);
      mpz_addmul(t, d[a][2], d[b][2]);
      found = mpz_sgn(t) <= 0;
    }
  for (int a = 0; a < 9; a++)
    for (int b = a + 1; b < 9; b++)
      for (int e = b + 1; e < 9; e++) {
        mpz_mul(t, d[a][0], c[b][e][0]), mpz_addmul(t, d[a][1], c[b][e][1]);
        mpz_addmul(t, d[a][2], c[b][e][2]);
        det[a][b][e] = (signed char)mpz_sgn(t);
      }
  for (int a = 0; a < 9 && !found; a++) /* a triangle through 0 */
    for (int b = a + 1; b < 9 && !found; b++)
      for (int e = b + 1; e < 9 && !found; e++) {
        if (det[a][b][e]) continue; /* 0 off its plane */
        for (int k = 0; k < 3; k++) /* n = (b - a) x (e - a) */
          mpz_add(n[k], c[a][b][k], c[b][e][k]), mpz_sub(n[k], n[k], c[a][e][k]);
        if (!mpz_sgn(n[0]) && !mpz_sgn(n[1]) && !mpz_sgn(n[2])) continue;
        int neg = 0; /* barycentrics of 0: n.(b x e), n.(e x a), n.(a x b) */
        for (int r = 0; r < 3; r++) {
          mpz_t *w = r == 0 ? c[b][e] : r == 1 ? c[a][e] : c[a][b];
          mpz_mul(t, n[0], w[0]), mpz_addmul(t, n[1], w[1]), mpz_addmul(t, n[2], w[2]);
          neg |= (r == 1 ? -mpz_sgn(t) : mpz_sgn(t)) < 0;
        }
        found = !neg;
      }
  for (int a = 0; a < 9 && !found; a++) /* a tetrahedron around 0 */
    for (int b = a + 1; b < 9 && !found; b++)
      for (int e = b + 1; e < 9 && !found; e++)
        for (int f = e + 1; f < 9 && !found; f++) {
          int l[4] = {det[b][e][f], -det[a][e][f], det[a][b][f], -det[a][b][e]};
          int pos = 0, neg = 0;
          for (int i = 0; i < 4; i++) pos |= l[i] > 0, neg |= l[i] < 0;
          found = pos != neg;
        }
  for (int a = 0; a < 9; a++) {
    for (int b = a + 1; b < 9; b++)
      for (int k = 0; k < 3; k++) mpz_clear(c[a][b][k]);
    for (int k = 0; k < 3; k++) mpz_clear(d[a][k]);
  }
  mpz_clears(t, u, n[0], n[1], n[2], NULL);
  return found;
}

/* ---- the predicates ---- */

static double pick(tb_rng *r, int mode) {
  double x = tb_rng_uniform(r) * 2.0 - 1.0;
  switch (mode) {
    case 0:
      return x;
    case 1:
      return ldexp(x, (int)tb_rng_below(r, 2000) - 1000); /* anything */
    case 2:
      return ldexp(floor(x * 8.0), -1074 + (int)tb_rng_below(r, 4)); /* subnormal */
    case 3:
      return tb_rng_below(r, 3) ? floor(x * 4.0) : ldexp(floor(x * 8.0), -1074);
    case 4:
      return ldexp(x, 990 + (int)tb_rng_below(r, 33)); /* huge */
    default:
      return tb_rng_below(r, 2) ? x * 1e-300 : x * 1e300;
  }
}

static void predicates_vs_rationals(void) {
  tb_rng r = tb_rng_seed(11);
  int bad = 0, n2 = 0, n3 = 0, stage2 = 0;
  for (int it = 0; it < 60000; it++) {
    int mode = it % 6;
    tb_vec3 v[4];
    for (int i = 0; i < 4; i++) v[i] = tb_v3(pick(&r, mode), pick(&r, mode), pick(&r, mode));
    if (tb_rng_below(&r, 3) == 0) { /* d on the plane of a, b, c up to rounding */
      double s = tb_rng_uniform(&r), t = tb_rng_uniform(&r);
      tb_vec3 d = tb_madd(tb_madd(v[0], s, tb_sub(v[1], v[0])), t, tb_sub(v[2], v[0]));
      v[3] = tb_isfinite3(d) ? d : v[0];
    }
    if (tb_rng_below(&r, 6) == 0) v[3] = v[tb_rng_below(&r, 3)];
    int want = q_orient3d(v[0], v[1], v[2], v[3]),
        x = tb_orient3d_expansion(v[0], v[1], v[2], v[3]);
    bad += tb_orient3d(v[0], v[1], v[2], v[3]) != want;
    bad += tb_orient3d_exact(v[0], v[1], v[2], v[3]) != want;
    bad += x != 2 && x != want;
    stage2 += x != 2, n3++;
    double w[6] = {v[0].x, v[0].y, v[1].x, v[1].y, v[3].x, v[3].z};
    int want2 = q_orient2d(w), x2 = tb_orient2d_expansion(w[0], w[1], w[2], w[3], w[4], w[5]);
    bad += tb_orient2d(w[0], w[1], w[2], w[3], w[4], w[5]) != want2;
    bad += tb_orient2d_exact(w[0], w[1], w[2], w[3], w[4], w[5]) != want2;
    bad += x2 != 2 && x2 != want2;
    n2++;
  }
  TB_CHECK_MSG(bad == 0, "%d wrong signs in %d orient2d and %d orient3d", bad, n2, n3);
  TB_CHECK(stage2 > n3 / 3 && stage2 < n3); /* both exact stages were exercised */
}

/* Shewchuk's figure: orient2d of (0.5 + i 2^-53, 0.5 + j 2^-53), (12, 12),
 * (24, 24) over a 256 x 256 grid; plus the same grid against a plane. */
static void predicates_near_degenerate(void) {
  int bad = 0, zero = 0, nonzero = 0;
  for (int i = 0; i < 256; i++)
    for (int j = 0; j < 256; j++) {
      double ax = 0.5 + i * 0x1p-53, ay = 0.5 + j * 0x1p-53;
      double w[6] = {ax, ay, 12, 12, 24, 24};
      int s = tb_orient2d(ax, ay, 12, 12, 24, 24);
      bad += s != q_orient2d(w);
      zero += s == 0, nonzero += s != 0;
      tb_vec3 d = tb_v3(ax, ay, 1.0 - ax - ay + 0.5); /* near x + y + z = 1.5 */
      bad += tb_orient3d(tb_v3(1.5, 0, 0), tb_v3(0, 1.5, 0), tb_v3(0, 0, 1.5), d) !=
             q_orient3d(tb_v3(1.5, 0, 0), tb_v3(0, 1.5, 0), tb_v3(0, 0, 1.5), d);
    }
  TB_CHECK_MSG(bad == 0, "%d wrong signs on the grids", bad);
  TB_CHECK(zero > 0 && nonzero > 0);
  /* points exactly on a line and a plane, and 1 ulp off it */
  TB_CHECK(tb_orient2d(0.1, 0.1, 0.3, 0.3, 0.7, 0.7) == 0);
  TB_CHECK(tb_orient2d(0.1, 0.1, 0.3, 0.3, 0.7, nextafter(0.7, 1)) == 1);
  TB_CHECK(tb_orient2d(0.1, 0.1, 0.3, 0.3, 0.7, nextafter(0.7, 0)) == -1);
  tb_vec3 a = tb_v3(0.1, 0.2, 0.3), b = tb_v3(1e6, 0.2, 0.3), c = tb_v3(0.1, 7.5, 0.3);
  TB_CHECK(tb_orient3d(a, b, c, tb_v3(3.3, 4.4, 0.3)) == 0);
  TB_CHECK(tb_orient3d(a, b, c, tb_v3(3.3, 4.4, nextafter(0.3, 1))) == 1);
  TB_CHECK(tb_orient3d(a, b, c, tb_v3(3.3, 4.4, nextafter(0.3, 0))) == -1);
}

static void predicates_extremes(void) {
  const double tiny = 0x1p-1074, big = 0x1.fffffffffffffp1023;
  /* conventions: counter-clockwise positive; orient3d has tb_tet_volume's sign */
  TB_CHECK(tb_orient2d(0, 0, 1, 0, 0, 1) == 1);
  tb_vec3 o = tb_v3(0, 0, 0), x = tb_v3(1, 0, 0), y = tb_v3(0, 1, 0), z = tb_v3(0, 0, 1);
  TB_CHECK(tb_orient3d(o, x, y, z) == 1 && tb_tet_volume(o, x, y, z) > 0);
  /* subnormal offsets: plain doubles underflow, the sign is still exact */
  TB_CHECK(tb_orient2d(0, 0, tiny, 0, 0, tiny) == 1);
  TB_CHECK(tb_orient2d_fast(0, 0, tiny, 0, 0, tiny) == 0.0);
  TB_CHECK(tb_orient3d(o, tb_v3(tiny, 0, 0), tb_v3(0, tiny, 0), tb_v3(0, 0, tiny)) == 1);
  TB_CHECK(tb_orient3d(o, x, y, tb_v3(0.25, 0.25, -tiny)) == -1);
  /* beyond the expansions' range: all three axes span 1 .. 2^-1074 */
  tb_vec3 t1 = tb_v3(1, tiny, 0), t2 = tb_v3(tiny, 1, tiny), t3 = tb_v3(0, tiny, 1);
  tb_vec3 t4 = tb_v3(tiny, tiny, tiny);
  TB_CHECK(tb_orient3d_expansion(t1, t2, t3, t4) == 2);
  TB_CHECK(tb_orient3d(t1, t2, t3, t4) == q_orient3d(t1, t2, t3, t4));
  TB_CHECK(tb_orient2d_expansion(1, tiny, big, -big, -big, 1) == 2);
  double w[6] = {1, tiny, big, -big, -big, 1};
  TB_CHECK(tb_orient2d(1, tiny, big, -big, -big, 1) == q_orient2d(w));
  /* huge: differences overflow in doubles */
  TB_CHECK(tb_orient2d(-big, -big, big, -big, 0, big) == 1);
  TB_CHECK(tb_orient3d(tb_v3(-big, -big, -big), tb_v3(big, -big, -big), tb_v3(-big, big, -big),
                       tb_v3(0, 0, big)) == 1);
  /* non-finite input: 0, no crash */
  TB_CHECK(tb_orient2d(NAN, 0, 1, 0, 0, 1) == 0);
  TB_CHECK(tb_orient3d(o, x, y, tb_v3(INFINITY, 0, 0)) == 0);
}

/* ---- triangle pairs ---- */

static int ri(tb_rng *r, int lo, int hi) {
  return lo + (int)tb_rng_below(r, (uint64_t)(hi - lo + 1));
}
static tb_vec3 rpt(tb_rng *r, int k) { return tb_v3(ri(r, -k, k), ri(r, -k, k), ri(r, -k, k)); }
/* A dyadic point of triangle t: barycentrics (a, b, c) / 4. */
static tb_vec3 bary(tb_rng *r, const tb_vec3 t[3]) {
  int a = ri(r, 0, 4), b = ri(r, 0, 4 - a), c = 4 - a - b;
  return tb_scale(tb_add(tb_add(tb_scale(t[0], a), tb_scale(t[1], b)), tb_scale(t[2], c)), 0.25);
}
/* A dyadic point of the line ab: on the segment (ts[2..6]) or anywhere. */
static tb_vec3 on_line(tb_rng *r, tb_vec3 a, tb_vec3 b, int anywhere) {
  static const double ts[] = {-1, -0.5, 0, 0.25, 0.5, 0.75, 1, 1.5, 2};
  int i = anywhere ? ri(r, 0, 8) : ri(r, 2, 6);
  return tb_madd(a, ts[i], tb_sub(b, a));
}
static tb_vec3 nudge(tb_rng *r, tb_vec3 v) { /* one coordinate 1 ulp either way */
  double c[3] = {v.x, v.y, v.z};
  int k = ri(r, 0, 2);
  c[k] = nextafter(c[k], tb_rng_below(r, 2) ? HUGE_VAL : -HUGE_VAL);
  return tb_v3(c[0], c[1], c[2]);
}

enum {
  F_RANDOM,
  F_COPL_AXIS,
  F_COPL_DIAG,
  F_SHARED_V,
  F_SHARED_E,
  F_V_ON_FACE,
  F_EDGE_EDGE,
  F_EDGE_V,
  F_COLLINEAR,
  F_NEAR_ULP,
  F_NEAR_GAP,
  F_FAR,
  F_TINY,
  F_SUBNORMAL,
  F_ZERO_AREA,
  F_COUNT
};
static const char *fam_names[F_COUNT] = {
    "random",          "coplanar-axis",  "coplanar-diagonal", "shared-vertex",
    "shared-edge",     "vertex-on-face", "edge-through-edge", "edge-through-vertex",
    "collinear-edges", "near-miss-1ulp", "near-miss-gap",     "far-1e6",
    "tiny-2^-23",      "subnormal",      "zero-area"};

static void touching(tb_rng *r, tb_vec3 p[3], tb_vec3 q[3], int kind) {
  int j = ri(r, 0, 2), k = ri(r, 0, 2);
  tb_vec3 d = rpt(r, 2);
  switch (kind) {
    case 0:
      q[k] = p[j];
      break; /* shared vertex */
    case 1:
      q[k] = p[j], q[(k + 1) % 3] = p[(j + 1) % 3];
      break; /* shared edge */
    case 2:
      q[k] = bary(r, p);
      break;  /* vertex on face */
    case 3: { /* edge through edge */
      tb_vec3 x = on_line(r, p[j], p[(j + 1) % 3], 0);
      q[k] = tb_add(x, d), q[(k + 1) % 3] = tb_sub(x, d);
    } break;
    case 4:
      q[k] = tb_add(p[j], d), q[(k + 1) % 3] = tb_sub(p[j], d);
      break; /* through vertex */
    default: /* collinear edges */
      q[k] = on_line(r, p[j], p[(j + 1) % 3], 1);
      q[(k + 1) % 3] = on_line(r, p[j], p[(j + 1) % 3], 1);
  }
}

/* A segment or a point standing for triangle t. */
static void flatten(tb_rng *r, tb_vec3 t[3]) {
  if (tb_rng_below(r, 3) == 0)
    t[1] = t[2] = t[0];
  else if (tb_rng_below(r, 2))
    t[2] = on_line(r, t[0], t[1], 1);
  else
    t[2] = t[ri(r, 0, 1)];
}

static void make_pair(tb_rng *r, int fam, tb_vec3 p[3], tb_vec3 q[3]) {
  for (int i = 0; i < 3; i++) p[i] = rpt(r, 3), q[i] = rpt(r, 3);
  switch (fam) {
    case F_RANDOM:
      for (int i = 0; i < 6; i++)
        (i < 3 ? p : q)[i % 3] = tb_v3(tb_rng_uniform(r), tb_rng_uniform(r), tb_rng_uniform(r));
      break;
    case F_COPL_AXIS:
    case F_COPL_DIAG: { /* contacts first, then an affine projection */
      if (tb_rng_below(r, 2)) touching(r, p, q, ri(r, 0, 5));
      int plane = fam == F_COPL_AXIS ? ri(r, 0, 2) : ri(r, 3, 4);
      double c = ri(r, -2, 2);
      for (int i = 0; i < 6; i++) {
        tb_vec3 *v = i < 3 ? &p[i] : &q[i - 3];
        if (plane == 0) v->x = c; /* x = c, y = c, z = c */
        if (plane == 1) v->y = c;
        if (plane == 2) v->z = c;
        if (plane == 3) v->z = c - v->x - v->y; /* x + y + z = c */
        if (plane == 4) v->y = v->x;            /* x = y */
      }
    } break;
    case F_SHARED_V:
    case F_SHARED_E:
    case F_V_ON_FACE:
    case F_EDGE_EDGE:
    case F_EDGE_V:
    case F_COLLINEAR:
      touching(r, p, q, fam - F_SHARED_V);
      break;
    case F_NEAR_ULP:
      touching(r, p, q, ri(r, 2, 5));
      for (int i = 0; i < 3; i++) q[i] = tb_rng_below(r, 2) ? nudge(r, q[i]) : q[i];
      break;
    case F_NEAR_GAP: { /* p in z = 0, a vertex of q on p (face, edge or vertex), then lifted */
      for (int i = 0; i < 3; i++) p[i].z = 0;
      int k = ri(r, 0, 2);
      q[k] = bary(r, p);
      q[k].z = ldexp(tb_rng_below(r, 2) ? 1.0 : -1.0, -ri(r, 30, 1074));
      if (tb_rng_below(r, 2)) q[(k + 1) % 3].z = q[k].z; /* an edge parallel to p */
    } break;
    case F_FAR:
    case F_TINY:
    case F_SUBNORMAL: { /* a random, coplanar, touching or zero-area pair, moved or scaled */
      static const int base[] = {F_RANDOM,    F_COPL_AXIS, F_COPL_DIAG, F_V_ON_FACE,
                                 F_EDGE_EDGE, F_COLLINEAR, F_ZERO_AREA};
      make_pair(r, base[tb_rng_below(r, 7)], p, q);
      for (int i = 0; i < 6; i++) {
        tb_vec3 *v = i < 3 ? &p[i] : &q[i - 3];
        *v = fam == F_FAR ? tb_add(*v, tb_v3(1e6, -1e6, 1e6))
                          : tb_scale(*v, fam == F_TINY ? 0x1p-23 : 0x1p-1068);
      }
      return;
    }
    default: /* F_ZERO_AREA */
      touching(r, p, q, ri(r, 0, 5));
      if (tb_rng_below(r, 3)) flatten(r, q);
      if (tb_rng_below(r, 2)) flatten(r, p);
  }
  if (tb_rng_below(r, 2)) /* a rotation or reflection of the vertex order */
    for (int i = 0; i < 2; i++) {
      tb_vec3 x = p[i];
      p[i] = p[i + 1], p[i + 1] = x;
    }
  if (tb_rng_below(r, 2))
    for (int i = 0; i < 3; i++) {
      tb_vec3 x = p[i];
      p[i] = q[i], q[i] = x;
    }
}

static void print_pair(const char *what, const tb_vec3 p[3], const tb_vec3 q[3], int want) {
  fprintf(stderr, "  %s (oracle %d):", what, want);
  for (int i = 0; i < 6; i++) {
    tb_vec3 v = i < 3 ? p[i] : q[i - 3];
    fprintf(stderr, " %a %a %a", v.x, v.y, v.z);
  }
  fputc('\n', stderr);
}

/* Every method that claims exactness against the oracle on one pair;
 * returns the number of wrong answers (and prints the first ones). */
static int check_pair(const tb_vec3 p[3], const tb_vec3 q[3], int want, int *printed) {
  unsigned char batch;
  tb_tritri_exact_batch(p, q, 1, &batch);
  int got[4] = {tb_tritri_exact(p, q), tb_tritri_exact_portable(p, q), batch,
                tb_tritri_guigue_exact(p, q)};
  static const char *names[4] = {"exact", "exact (portable)", "exact_batch", "guigue-exact"};
  int bad = 0;
  for (int m = 0; m < 4; m++)
    if (got[m] != want) {
      if ((*printed)++ < 5) print_pair(names[m], p, q, want);
      bad++;
    }
  return bad;
}

static void families(void) {
  tb_rng r = tb_rng_seed(2024);
  int total_bad = 0, printed = 0;
  for (int f = 0; f < F_COUNT; f++) {
    int n = 1500, hits = 0, bad = 0, gbad = 0;
    for (int i = 0; i < n; i++) {
      tb_vec3 p[3], q[3];
      make_pair(&r, f, p, q);
      int want = oracle(p, q);
      hits += want;
      bad += check_pair(p, q, want, &printed);
      gbad += tb_tritri_guigue(p, q) != want;
    }
    printf("  %-20s %4d pairs, %4d intersecting; plain guigue wrong on %d\n", fam_names[f], n, hits,
           gbad);
    TB_CHECK_MSG(bad == 0, "family %s: %d wrong answers", fam_names[f], bad);
    if (f >= F_SHARED_V && f <= F_EDGE_V) /* contacts by construction */
      TB_CHECK_MSG(hits == n, "family %s: %d of %d intersecting", fam_names[f], hits, n);
    else
      TB_CHECK_MSG(hits > 0 && hits < n, "family %s: %d of %d intersecting, expected a mix",
                   fam_names[f], hits, n);
    total_bad += bad;
  }
  TB_CHECK(total_bad == 0);
}

/* The correctness table's own families (measure/pairgen.c), through our oracle. */
static void table_families(void) {
  int nf, printed = 0;
  const tb_pair_family *fam = tb_pair_families(&nf);
  TB_CHECK(nf > 0);
  for (int f = 0; f < nf; f++) {
    tb_pairset set = {0};
    TB_CHECK(tb_pairgen(&fam[f], 400, 77, &set) == 0);
    int bad = 0;
    for (int i = 0; i < set.n; i++) {
      const tb_tripair *t = &set.pairs[i];
      bad += check_pair(t->p, t->q, oracle(t->p, t->q), &printed);
    }
    TB_CHECK_MSG(bad == 0 && set.n == 400, "pair family %s: %d wrong of %d", fam[f].name, bad,
                 set.n);
    tb_pairs_free(&set);
  }
}

#define V(x, y, z) \
  { x, y, z }
/* Small cases checked by hand (the last one: in doubles a product overflows
 * to +inf while the exact determinant is negative; an unguarded box bound
 * accepted it). */
static void hand_cases(void) {
  static const struct {
    const char *what;
    int want;
    tb_vec3 p[3], q[3];
  } c[] = {
      // clang-format off
      {"parallel planes", 0, {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, {V(0, 0, 1), V(1, 0, 1), V(0, 1, 1)}},
      {"piercing", 1, {V(0, 0, 0), V(2, 0, 0), V(0, 2, 0)}, {V(.5, .5, -1), V(.5, .5, 1), V(3, 3, 0)}},
      {"shared vertex", 1, {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, {V(0, 0, 0), V(-1, 0, 0), V(0, 0, 1)}},
      {"shared edge", 1, {V(0, 0, 0), V(1, 0, 0), V(0, 1, 0)}, {V(1, 0, 0), V(0, 0, 0), V(0, 0, 1)}},
      {"vertex on face", 1, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(1, 1, 0), V(1, 1, 1), V(2, 1, 1)}},
      {"a subnormal above", 0, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(1, 1, 0x1p-1074), V(1, 1, 1), V(2, 1, 1)}},
      {"edge through edge", 1, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(2, -1, 0), V(2, 1, 0), V(2, 0, 3)}},
      {"collinear, apart", 0, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(5, 0, 0), V(6, 0, 0), V(5, 0, 1)}},
      {"collinear, touching", 1, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(4, 0, 0), V(6, 0, 0), V(5, 0, 1)}},
      {"coplanar, inside", 1, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(1, 1, 0), V(2, 1, 0), V(1, 2, 0)}},
      {"coplanar, around", 1, {V(1, 1, 0), V(2, 1, 0), V(1, 2, 0)}, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}},
      {"coplanar, vertex on edge", 1, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(2, 2, 0), V(3, 3, 0), V(2, 5, 0)}},
      {"coplanar, apart", 0, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}, {V(2.5, 2, 0), V(3, 3, 0), V(2, 5, 0)}},
      {"segment x triangle", 1, {V(0, 0, 0), V(1, 1, 1), V(2, 2, 2)}, {V(0, 2, 0), V(2, 0, 2), V(5, 5, 5)}},
      {"collinear segments apart", 0, {V(0, 0, 0), V(1, 1, 1), V(2, 2, 2)}, {V(3, 3, 3), V(4, 4, 4), V(4, 4, 4)}},
      {"collinear segments touching", 1, {V(0, 0, 0), V(1, 1, 1), V(2, 2, 2)}, {V(2, 2, 2), V(4, 4, 4), V(3, 3, 3)}},
      {"crossing segments", 1, {V(0, 0, 0), V(2, 0, 0), V(2, 0, 0)}, {V(1, -1, 0), V(1, 1, 0), V(1, 1, 0)}},
      {"skew segments", 0, {V(0, 0, 0), V(2, 0, 0), V(2, 0, 0)}, {V(1, -1, 1), V(1, 1, 1), V(1, 1, 1)}},
      {"equal points", 1, {V(1, 1, 1), V(1, 1, 1), V(1, 1, 1)}, {V(1, 1, 1), V(1, 1, 1), V(1, 1, 1)}},
      {"distinct points", 0, {V(1, 1, 1), V(1, 1, 1), V(1, 1, 1)}, {V(1, 1, 2), V(1, 1, 2), V(1, 1, 2)}},
      {"point in triangle", 1, {V(1, 1, 0), V(1, 1, 0), V(1, 1, 0)}, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}},
      {"point beside", 0, {V(3, 3, 0), V(3, 3, 0), V(3, 3, 0)}, {V(0, 0, 0), V(4, 0, 0), V(0, 4, 0)}},
      {"point on segment", 1, {V(1, 0, 0), V(1, 0, 0), V(1, 0, 0)}, {V(0, 0, 0), V(2, 0, 0), V(2, 0, 0)}},
      {"far", 1, {V(1e6, 1e6, 1e6), V(1e6 + 1, 1e6, 1e6), V(1e6, 1e6 + 1, 1e6)}, {V(1e6 + .25, 1e6 + .25, 1e6 - 1), V(1e6 + .25, 1e6 + .25, 1e6 + 1), V(1e6 + 2, 1e6, 1e6)}},
      {"overflow", 1, {V(0, 0, 0), V(0x1p-1000, 0x1p600, 0), V(0, 0, 0x1p600)}, {V(0x1p-1074, 0x1p590, 2), V(0x1p-1074, 0x1p-1000, -1), V(0x1p-1000, 0x1p590, 0)}},
      // clang-format on
  };
  int printed = 0;
  for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
    TB_CHECK_MSG(oracle(c[i].p, c[i].q) == c[i].want, "oracle on %s", c[i].what);
    TB_CHECK_MSG(check_pair(c[i].p, c[i].q, c[i].want, &printed) == 0, "%s", c[i].what);
    TB_CHECK_MSG(check_pair(c[i].q, c[i].p, c[i].want, &printed) == 0, "%s, swapped", c[i].what);
  }
  /* non-finite coordinates are outside the contract: an answer, no crash */
  tb_vec3 bad[3] = {{NAN, 0, 0}, {1, INFINITY, 0}, {0, 1, -INFINITY}};
  TB_CHECK(tb_tritri_exact(bad, c[1].q) >= 0 && tb_tritri_exact(c[1].q, bad) <= 1);
  TB_CHECK(tb_tritri_guigue_exact(bad, c[1].q) >= 0 && tb_tritri_exact_portable(bad, bad) <= 1);
  /* degenerate dispatch: -1 for two proper triangles */
  TB_CHECK(tb_tritri_exact_degenerate(c[0].p, c[1].p) == -1);
  TB_CHECK(tb_tritri_exact_degenerate(c[13].p, c[13].q) == 1);
}

static void jgt_pairs(void) {
  const char *dir = TB_SOURCE_ROOT "/../shared/data/jgt-shen2003";
  char path[2][1024];
  snprintf(path[0], sizeof path[0], "%s/intersected.txt", dir);
  snprintf(path[1], sizeof path[1], "%s/separated.txt", dir);
  for (int f = 0; f < 2; f++) {
    tb_pairset set = {0};
    tb_error err;
    if (tb_pairs_read_jgt(path[f], f == 0, &set, &err)) {
      tb_test_skip("JGT pairs absent: %s", err.msg);
      return;
    }
    unsigned char *out = malloc((size_t)set.n);
    tb_vec3 *p = malloc(sizeof(tb_vec3) * 3 * (size_t)set.n),
            *q = malloc(sizeof(tb_vec3) * 3 * (size_t)set.n);
    TB_CHECK(out && p && q);
    if (!out || !p || !q) {
      free(out), free(p), free(q), tb_pairs_free(&set);
      return;
    }
    for (int i = 0; i < set.n; i++)
      memcpy(p + 3 * i, set.pairs[i].p, sizeof set.pairs[i].p),
          memcpy(q + 3 * i, set.pairs[i].q, sizeof set.pairs[i].q);
    tb_tritri_exact_batch(p, q, set.n, out);
    int bad = 0, gbad = 0, printed = 0;
    for (int i = 0; i < set.n; i++) {
      const tb_tripair *t = &set.pairs[i];
      int want = oracle(t->p, t->q);
      bad += want != (f == 0) || out[i] != want;
      bad += check_pair(t->p, t->q, want, &printed);
      gbad += tb_tritri_guigue(t->p, t->q) != want;
    }
    TB_CHECK_MSG(bad == 0 && gbad == 0 && set.n == 5000, "%s: %d wrong, plain guigue %d", path[f],
                 bad, gbad);
    free(out), free(p), free(q);
    tb_pairs_free(&set);
  }
}

/* Exact scaling by a power of two changes no intersection: the oracles
 * (CGAL, the table's, and the rationals above) and the tests that claim
 * exactness give the same answers on the correctness table's families
 * scaled by 2^k (tb_pairs_scaled keeps the pairs that scale exactly), as
 * the scaled rows of the correctness table assume. */
static void scaled_invariance(void) {
  static const int scales[] = {-1000, -600, -500, -300, -40, 40, 300, 500, 600, 900};
  const tb_tritri_method *cgal = tb_tritri_find("cgal"), *ex = tb_tritri_find("exact"),
                         *gex = tb_tritri_find("guigue-exact");
  TB_CHECK(cgal && ex && gex && cgal->exact && ex->exact && gex->exact);
  if (!cgal || !ex || !gex) return;
  /* a lost bit is refused: 2^-1074 cannot be halved, 3 2^-1074 not either */
  tb_tripair tiny = {{{0x1p-1074, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}}};
  tb_pairset one = {0}, out = {0};
  TB_CHECK(tb_pairs_add(&one, &tiny, -1) == 0);
  TB_CHECK(tb_pairs_scaled(&one, -1, &out, NULL) == 0 && out.n == 0);
  TB_CHECK(tb_pairs_scaled(&one, 1, &out, NULL) == 1 && out.n == 1 &&
           out.pairs[0].p[0].x == 0x1p-1073 && out.pairs[0].q[2].z == 2.0);
  TB_CHECK(tb_pairs_scaled(&one, 1024, &out, NULL) == 0 && out.n == 1); /* 2^1024 overflows */
  tb_pairs_free(&one), tb_pairs_free(&out);
  int nf, wrong = 0, kept_all_up = 1, dropped_down = 0;
  long checked = 0;
  const tb_pair_family *fam = tb_pair_families(&nf);
  for (int f = 0; f < nf; f++) {
    tb_pairset set = {0};
    TB_CHECK(tb_pairgen(&fam[f], 150, 78, &set) == 0);
    unsigned char *base = malloc((size_t)set.n + 1);
    int *index = malloc((size_t)set.n * sizeof *index + 1);
    if (!base || !index) {
      TB_CHECK(0);
      free(base), free(index), tb_pairs_free(&set);
      return;
    }
    for (int i = 0; i < set.n; i++) {
      const tb_tripair *t = &set.pairs[i];
      base[i] = (unsigned char)cgal->test(t->p, t->q);
      wrong += oracle(t->p, t->q) != base[i];
    }
    for (int e = 0; e < (int)(sizeof scales / sizeof scales[0]); e++) {
      tb_pairset sc = {0};
      int n = tb_pairs_scaled(&set, scales[e], &sc, index);
      TB_CHECK(n == sc.n);
      if (scales[e] > 0) kept_all_up &= n == set.n;
      if (scales[e] < 0) dropped_down += set.n - n;
      for (int i = 0; i < n; i++) {
        const tb_tripair *t = &sc.pairs[i];
        int want = base[index[i]];
        int bad = (cgal->test(t->p, t->q) != want) + (ex->test(t->p, t->q) != want) +
                  (gex->test(t->p, t->q) != want) + (oracle(t->p, t->q) != want);
        if (bad && wrong < 5)
          fprintf(stderr, "  %s pair %d scaled by 2^%d: %d answers changed\n", fam[f].name,
                  index[i], scales[e], bad);
        wrong += bad != 0, checked++;
      }
      tb_pairs_free(&sc);
    }
    free(base), free(index), tb_pairs_free(&set);
  }
  TB_CHECK_MSG(wrong == 0, "%d scaled pairs changed their answer", wrong);
  TB_CHECK(checked > 10000 && kept_all_up && dropped_down > 0);
}

const tb_test_case tb_tests_tritri_exact[] = {
    {"predicates_vs_rationals", predicates_vs_rationals},
    {"predicates_near_degenerate", predicates_near_degenerate},
    {"predicates_extremes", predicates_extremes},
    {"hand_cases", hand_cases},
    {"families", families},
    {"table_families", table_families},
    {"jgt_pairs", jgt_pairs},
    {"scaled_invariance", scaled_invariance},
    {0, 0}};
