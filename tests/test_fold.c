/* Tests of the scalpel's folded plane (cutting/tb_fold.h; the metaball
 * hybrid cutting patent, step 3 (1) and (5), fig. 5). Oracles independent of
 * the code under test: the sphere test against the distance to densely
 * sampled pieces; the segment test against an exact solve in GMP rationals
 * (integer fold corners, so the pieces are exactly the stored ones); the
 * triangle cuts against hand-computed points. */
#include <gmp.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_rng.h"
#include "cutting/tb_fold.h"

/* Fold A: two vertical pieces, y = 0 for x in [0, 2], then y = x - 2 for x
 * in [2, 4]; z in [0, 2]. */
static void fold_a(tb_fold *f) {
  const tb_vec3 p[3] = {{0, 0, 0}, {2, 0, 0}, {4, 2, 0}};
  TB_CHECK(tb_fold_init(f, p, 3, tb_v3(0, 0, 2), NULL) == 0);
}

/* ---- construction ---- */

static void expect_init_error(const tb_vec3 *p, int n, tb_vec3 d, const char *reason) {
  tb_fold f;
  tb_error err = {{0}};
  int rc = tb_fold_init(&f, p, n, d, &err);
  TB_CHECK_MSG(rc != 0, "init should fail (%s)", reason);
  TB_CHECK_MSG(strstr(err.msg, "tb_fold_init: ") == err.msg && strstr(err.msg, reason),
               "message '%s' lacks '%s'", err.msg, reason);
  TB_CHECK(f.p == NULL && f.npieces == 0);
  tb_fold_free(&f);
}

static void test_init_errors(void) {
  const tb_vec3 ok[3] = {{0, 0, 0}, {1, 0, 0}, {2, 1, 0}};
  const tb_vec3 dup[3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  const tb_vec3 nan[2] = {{0, 0, 0}, {NAN, 0, 0}};
  expect_init_error(ok, 1, tb_v3(0, 0, 1), "at least 2 points");
  expect_init_error(dup, 3, tb_v3(0, 0, 1), "path points 1 and 2 coincide");
  expect_init_error(ok, 3, tb_v3(1, 1, 0), "parallel to segment 1");
  expect_init_error(ok, 3, tb_v3(-3, 0, 0), "parallel to segment 0");
  expect_init_error(ok, 3, tb_v3(1, 1e-12, 0), "parallel to segment 0");
  expect_init_error(ok, 3, tb_v3(0, 0, 0), "depth vector is zero");
  expect_init_error(ok, 3, tb_v3(0, INFINITY, 1), "depth vector is not finite");
  expect_init_error(nan, 2, tb_v3(0, 0, 1), "path point 1 is not finite");
  tb_fold f;
  TB_CHECK(tb_fold_init(&f, ok, 3, tb_v3(1, 1e-6, 0.5), NULL) == 0);
  TB_CHECK(f.npieces == 2 && f.count == 3);
  TB_CHECK_NEAR(tb_len(f.piece[1].n), 1.0, 1e-15);
  tb_fold_free(&f);
}

/* ---- sphere ---- */

/* Distance from c to the pieces sampled on an m x m grid per piece. */
static double sampled_dist(const tb_fold *f, tb_vec3 c, int m) {
  double best = INFINITY;
  for (int k = 0; k < f->npieces; k++)
    for (int i = 0; i <= m; i++)
      for (int j = 0; j <= m; j++) {
        tb_vec3 y =
            tb_madd(tb_madd(f->p[k], (double)i / m, f->piece[k].e), (double)j / m, f->depth);
        double d = tb_dist(c, y);
        if (d < best) best = d;
      }
  return best;
}

static void test_sphere_brute(void) {
  const tb_vec3 p[4] = {{0, 0, 0}, {1, 0.2, 0.1}, {1.6, 0.9, -0.2}, {2.0, 1.0, 0.5}};
  tb_vec3 D = tb_v3(0.1, -0.2, 1.0);
  tb_fold f;
  TB_CHECK(tb_fold_init(&f, p, 4, D, NULL) == 0);
  const int m = 240;
  double h = 0.0; /* half the longest cell diagonal: the sampling's error bound */
  for (int k = 0; k < f.npieces; k++) h = fmax(h, 0.5 * (tb_len(f.piece[k].e) + tb_len(D)) / m);
  tb_vec3 centres[64];
  int nc = 0;
  for (int k = 0; k < 3; k++) { /* near each fold, edge and corner, both sides */
    tb_vec3 n = f.piece[k].n, e = f.piece[k].e;
    for (int sd = -1; sd <= 1; sd += 2) {
      centres[nc++] = tb_madd(tb_madd(f.p[k + 1], 0.5, D), 0.05 * sd, n);        /* fold */
      centres[nc++] = tb_madd(tb_madd(f.p[k], 1.2, D), 0.03 * sd, n);            /* depth edge */
      centres[nc++] = tb_madd(tb_madd(f.p[k], 0.5, e), -0.1 * sd, D);            /* path edge */
      centres[nc++] = tb_madd(tb_madd(f.q[k], -0.05, e), 0.1 * sd, D);           /* corner */
      centres[nc++] = tb_madd(tb_madd(f.p[k], 0.4, e), 0.02 * sd, tb_add(n, D)); /* face */
    }
  }
  tb_rng rng = tb_rng_seed(14);
  while (nc < 64)
    centres[nc++] = tb_v3(tb_rng_range(&rng, -0.5, 2.5), tb_rng_range(&rng, -0.5, 1.5),
                          tb_rng_range(&rng, -0.6, 1.6));
  for (int i = 0; i < nc; i++) {
    tb_fold_near nr;
    double bd = sampled_dist(&f, centres[i], m);
    tb_fold_nearest(&f, centres[i], &nr);
    TB_CHECK_MSG(nr.dist <= bd + 1e-12 && bd - nr.dist <= h, "centre %d: dist %.17g sampled %.17g",
                 i, nr.dist, bd);
    TB_CHECK(nr.s >= 0 && nr.s <= 1 && nr.t >= 0 && nr.t <= 1);
    tb_vec3 y = tb_madd(tb_madd(f.p[nr.piece], nr.s, f.piece[nr.piece].e), nr.t, D);
    TB_CHECK_NEAR(tb_dist(y, nr.point), 0.0, 1e-14);
    TB_CHECK_NEAR(tb_dist(centres[i], nr.point), nr.dist, 1e-14);
    /* Hit for radius >= the sampled distance (1e-12 for rounding), miss below
     * it minus the bound. */
    TB_CHECK_MSG(tb_fold_sphere(&f, centres[i], bd + 1e-12, NULL) == 1, "centre %d should hit", i);
    TB_CHECK_MSG(tb_fold_sphere(&f, centres[i], bd - 2 * h, NULL) == 0, "centre %d should miss", i);
  }
  tb_fold_free(&f);
  /* Tangency is a hit (exact here: distance 3 from y = 0; piece 1's nearest
   * point, the crease, is sqrt 10 away). */
  tb_fold a;
  fold_a(&a);
  tb_fold_near nr;
  TB_CHECK(tb_fold_sphere(&a, tb_v3(1, -3, 1), 3.0, &nr) == 1);
  TB_CHECK(nr.dist == 3.0 && nr.piece == 0 && nr.s == 0.5 && nr.t == 0.5);
  TB_CHECK(tb_fold_sphere(&a, tb_v3(1, -3, 1), nextafter(3.0, 0.0), NULL) == 0);
  /* At the fold both pieces are nearest: the lower index is reported. */
  TB_CHECK(tb_fold_sphere(&a, tb_v3(2.5, -0.5, 1), 1.0, &nr) == 1);
  TB_CHECK(nr.piece == 0 && nr.s == 1.0 && tb_dist(nr.point, tb_v3(2, 0, 1)) < 1e-15);
  /* Beyond a corner: the corner is nearest. */
  TB_CHECK(tb_fold_sphere(&a, tb_v3(-3, -4, 2), 5.0, &nr) == 1);
  TB_CHECK(nr.piece == 0 && nr.s == 0.0 && nr.t == 1.0 && nr.dist == 5.0);
  tb_fold_free(&a);
}

/* ---- segment: exact oracle in rationals ---- */

typedef struct qv {
  mpq_t c[3];
} qv;
static void qv_init(qv *v, tb_vec3 x) {
  for (int i = 0; i < 3; i++) mpq_init(v->c[i]), mpq_set_d(v->c[i], tb_comp(x, i));
}
static void qv_clear(qv *v) {
  for (int i = 0; i < 3; i++) mpq_clear(v->c[i]);
}
static void qv_sub(qv *r, const qv *a, const qv *b) {
  for (int i = 0; i < 3; i++) mpq_sub(r->c[i], a->c[i], b->c[i]);
}
static void qv_cross(qv *r, const qv *a, const qv *b) {
  mpq_t t;
  mpq_init(t);
  for (int i = 0; i < 3; i++) {
    int j = (i + 1) % 3, k = (i + 2) % 3;
    mpq_mul(r->c[i], a->c[j], b->c[k]);
    mpq_mul(t, a->c[k], b->c[j]);
    mpq_sub(r->c[i], r->c[i], t);
  }
  mpq_clear(t);
}
static void qv_dot(mpq_t r, const qv *a, const qv *b) {
  mpq_t t;
  mpq_init(t);
  mpq_set_ui(r, 0, 1);
  for (int i = 0; i < 3; i++) mpq_mul(t, a->c[i], b->c[i]), mpq_add(r, r, t);
  mpq_clear(t);
}

/* Exact: does segment ab meet piece (P, e, D)? *u gets the first parameter,
 * *touch is set when the meeting is not a transversal crossing of the open
 * piece (coplanar, an endpoint, or on the piece's boundary). */
static int oracle_piece(tb_vec3 P, tb_vec3 e, tb_vec3 D, tb_vec3 a, tb_vec3 b, double *u,
                        int *touch) {
  qv qp, qe, qd, qa, qb, d, r, n, w;
  qv_init(&qp, P), qv_init(&qe, e), qv_init(&qd, D), qv_init(&qa, a), qv_init(&qb, b);
  qv_init(&d, tb_v3(0, 0, 0)), qv_init(&r, tb_v3(0, 0, 0));
  qv_init(&n, tb_v3(0, 0, 0)), qv_init(&w, tb_v3(0, 0, 0));
  mpq_t det, nn, v[3], lo, hi, x0, x1, t;
  mpq_inits(det, nn, v[0], v[1], v[2], lo, hi, x0, x1, t, NULL);
  qv_sub(&d, &qb, &qa);
  qv_sub(&r, &qp, &qa);
  qv_cross(&n, &qe, &qd);
  qv_dot(det, &d, &n);
  int hit = 0;
  *touch = 0;
  if (mpq_sgn(det) != 0) {
    /* a + u d = P + s e + t D: u = det[r,e,D]/det, s = -det[d,r,D]/det,
     * t = -det[d,e,r]/det (det[x,y,z] = x . (y x z)). */
    qv_dot(v[0], &r, &n);
    qv_cross(&w, &r, &qd), qv_dot(v[1], &d, &w), mpq_neg(v[1], v[1]);
    qv_cross(&w, &qe, &r), qv_dot(v[2], &d, &w), mpq_neg(v[2], v[2]);
    hit = 1;
    for (int i = 0; i < 3; i++) {
      mpq_div(v[i], v[i], det);
      if (mpq_sgn(v[i]) < 0 || mpq_cmp_ui(v[i], 1, 1) > 0) hit = 0;
      if (mpq_sgn(v[i]) == 0 || mpq_cmp_ui(v[i], 1, 1) == 0) *touch = 1;
    }
    *u = mpq_get_d(v[0]);
  } else {
    qv_dot(t, &r, &n);
    if (mpq_sgn(t) == 0) { /* in the plane: s, t of a and b, clip u */
      qv_dot(nn, &n, &n);
      mpq_set_ui(lo, 0, 1), mpq_set_ui(hi, 1, 1);
      for (int c = 0; c < 2; c++) {
        /* s(x) = ((x-P) x D).n / n.n, t(x) = (e x (x-P)).n / n.n */
        qv_sub(&w, &qa, &qp);
        qv_cross(&r, c == 0 ? &w : &qe, c == 0 ? &qd : &w), qv_dot(x0, &r, &n);
        qv_sub(&w, &qb, &qp);
        qv_cross(&r, c == 0 ? &w : &qe, c == 0 ? &qd : &w), qv_dot(x1, &r, &n);
        mpq_div(x0, x0, nn), mpq_div(x1, x1, nn);
        mpq_sub(x1, x1, x0); /* slope */
        if (mpq_sgn(x1) == 0) {
          if (mpq_sgn(x0) < 0 || mpq_cmp_ui(x0, 1, 1) > 0) mpq_set_si(lo, 2, 1);
          continue;
        }
        /* bounds (0 - x0)/slope and (1 - x0)/slope */
        mpq_t b0, b1;
        mpq_inits(b0, b1, NULL);
        mpq_neg(b0, x0), mpq_div(b0, b0, x1);
        mpq_set_ui(b1, 1, 1), mpq_sub(b1, b1, x0), mpq_div(b1, b1, x1);
        if (mpq_cmp(b0, b1) > 0) mpq_swap(b0, b1);
        if (mpq_cmp(b0, lo) > 0) mpq_set(lo, b0);
        if (mpq_cmp(b1, hi) < 0) mpq_set(hi, b1);
        mpq_clears(b0, b1, NULL);
      }
      hit = mpq_cmp(lo, hi) <= 0;
      *touch = 1;
      *u = mpq_get_d(lo);
    }
  }
  mpq_clears(det, nn, v[0], v[1], v[2], lo, hi, x0, x1, t, NULL);
  qv_clear(&qp), qv_clear(&qe), qv_clear(&qd), qv_clear(&qa), qv_clear(&qb);
  qv_clear(&d), qv_clear(&r), qv_clear(&n), qv_clear(&w);
  return hit;
}

static int oracle(const tb_fold *f, tb_vec3 a, tb_vec3 b, double *u, int *touch) {
  int hit = 0;
  *touch = 0;
  *u = INFINITY;
  for (int k = 0; k < f->npieces; k++) {
    double uk;
    int tk;
    if (oracle_piece(f->p[k], f->piece[k].e, f->depth, a, b, &uk, &tk)) {
      hit = 1;
      *touch |= tk;
      if (uk < *u) *u = uk;
    }
  }
  return hit;
}

/* Fold C: three pieces with integer corners, bent both ways, slanted D. */
static void fold_c(tb_fold *f) {
  const tb_vec3 p[4] = {{0, 0, 0}, {4, 0, 0}, {6, 3, 1}, {10, 2, 0}};
  TB_CHECK(tb_fold_init(f, p, 4, tb_v3(1, -1, 4), NULL) == 0);
}

static void test_segment_brute(void) {
  tb_fold f;
  fold_c(&f);
  tb_rng rng = tb_rng_seed(1414);
  int hits = 0, touches = 0, mism = 0;
  for (int i = 0; i < 6000; i++) {
    tb_vec3 a, b;
    if (i % 2) { /* coarse grid: many exact touches */
      a = tb_v3((double)tb_rng_below(&rng, 12) - 1, (double)tb_rng_below(&rng, 6) - 2,
                (double)tb_rng_below(&rng, 7) - 1);
      b = tb_v3((double)tb_rng_below(&rng, 12) - 1, (double)tb_rng_below(&rng, 6) - 2,
                (double)tb_rng_below(&rng, 7) - 1);
      if (i % 6 == 1) b = tb_v3(a.x + 0.5 * (b.x - a.x), a.y, a.z + 0.5); /* half steps */
    } else {
      a = tb_v3(tb_rng_range(&rng, -1, 11), tb_rng_range(&rng, -3, 4), tb_rng_range(&rng, -1, 5));
      b = tb_v3(tb_rng_range(&rng, -1, 11), tb_rng_range(&rng, -3, 4), tb_rng_range(&rng, -1, 5));
    }
    double u;
    int touch;
    int want = oracle(&f, a, b, &u, &touch);
    tb_fold_hit hit;
    int got = tb_fold_segment(&f, a, b, &hit), got2 = tb_fold_segment(&f, a, b, NULL);
    if (got != want || got2 != want) {
      if (mism++ < 5)
        tb_test_fail(__FILE__, __LINE__, "segment %d (%g %g %g)-(%g %g %g): got %d/%d, want %d", i,
                     a.x, a.y, a.z, b.x, b.y, b.z, got, got2, want);
      continue;
    }
    if (!want) continue;
    hits++, touches += touch;
    TB_CHECK_MSG(fabs(hit.u - u) <= 1e-9, "segment %d: u %.17g want %.17g", i, hit.u, u);
    tb_fold_near nr;
    tb_fold_nearest(&f, hit.point, &nr);
    TB_CHECK_MSG(nr.dist <= 1e-9, "segment %d: hit point off the fold by %g", i, nr.dist);
  }
  TB_CHECK_MSG(hits > 1000 && touches > 150, "hits %d, touching %d", hits, touches);
  tb_fold_free(&f);
}

static void test_segment_touching(void) {
  tb_fold f;
  fold_a(&f);
  tb_fold_hit h;
  /* Endpoint exactly on piece 0's face, the rest on one side. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, 0, 1), tb_v3(1, -3, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && h.u == 0.0 && h.s == 0.5 && h.t == 0.5);
  /* Ending one ulp short of the face: no crossing. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, -nextafter(0.0, 1.0), 1), tb_v3(1, -3, 1), NULL) == 0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, -0x1p-40, 1), tb_v3(1, -3, 1), NULL) == 0);
  /* A transversal crossing: u where y changes sign. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, -1, 1), tb_v3(1, 3, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && h.u == 0.25);
  /* Lying in piece 0, inside and partly outside; in its plane but beyond it. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(0.5, 0, 0.5), tb_v3(1.5, 0, 1.5), &h) == 1);
  TB_CHECK(h.u == 0.0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(-1, 0, 1), tb_v3(1, 0, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && h.u == 0.5 && h.s == 0.0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(-3, 0, 1), tb_v3(-1, 0, 1), NULL) == 0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, 0, 2.5), tb_v3(1, 0, 3), NULL) == 0);
  /* Touching the depth edge from above, the fold line at one point, the
   * crease from outside the bend. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, -1, 3), tb_v3(1, 1, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && h.t == 1.0 && h.u == 0.5);
  TB_CHECK(tb_fold_segment(&f, tb_v3(1, -1, 3), tb_v3(1, 1, 3), NULL) == 0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(3, -1, 1), tb_v3(1, -1, 1), NULL) == 0);
  TB_CHECK(tb_fold_segment(&f, tb_v3(2.5, -0.5, 1), tb_v3(2, 0, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && h.u == 1.0 && h.s == 1.0);
  /* A single point on the crease; a point off the fold. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(2, 0, 2), tb_v3(2, 0, 2), &h) == 1);
  TB_CHECK(tb_fold_segment(&f, tb_v3(2, 0, 2.5), tb_v3(2, 0, 2.5), NULL) == 0);
  /* Crossing pieces 1 then 0: the first along a -> b is reported. */
  TB_CHECK(tb_fold_segment(&f, tb_v3(4, 1.5, 1), tb_v3(0, -0.5, 1), &h) == 1);
  TB_CHECK(h.piece == 1 && fabs(h.u - 0.25) < 1e-15);
  TB_CHECK(tb_fold_segment(&f, tb_v3(0, -0.5, 1), tb_v3(4, 1.5, 1), &h) == 1);
  TB_CHECK(h.piece == 0 && fabs(h.u - 0.25) < 1e-15);
  tb_fold_free(&f);
}

/* ---- side ---- */

static void test_side(void) {
  tb_fold f;
  fold_a(&f);
  /* Piece 0's normal is -y, piece 1's (1, -1, 0) / sqrt 2. */
  TB_CHECK(tb_fold_side(&f, tb_v3(1, -1, 1)) == 1);
  TB_CHECK(tb_fold_side(&f, tb_v3(1, 1, 1)) == -1);
  TB_CHECK(tb_fold_side(&f, tb_v3(3, 0.2, 1)) == 1);    /* near piece 1, y > 0 */
  TB_CHECK(tb_fold_side(&f, tb_v3(3, 1.5, 1)) == -1);   /* inside the bend */
  TB_CHECK(tb_fold_side(&f, tb_v3(2.5, -0.5, 1)) == 1); /* beyond the convex fold */
  TB_CHECK(tb_fold_side(&f, tb_v3(2.5, -0.5, 3)) == 1);
  TB_CHECK(tb_fold_side(&f, tb_v3(1, 0, 1)) == 0); /* on the fold, and on its extension */
  TB_CHECK(tb_fold_side(&f, tb_v3(1, 0, 5)) == 0);
  /* Just either side of the crease: (1.9, 0.05) is nearest piece 0's face,
   * -1; (2.02, 0.01) nearest piece 1's face, where it is on the +1 side
   * (piece 0's normal alone would say -1); (2.07, -0.17) is nearest the
   * crease itself (outside the convex bend): the pseudo-normal gives +1. */
  TB_CHECK(tb_fold_side(&f, tb_v3(1.9, 0.05, 1)) == -1);
  TB_CHECK(tb_fold_side(&f, tb_v3(2.02, 0.01, 1)) == 1);
  tb_fold_near nr;
  tb_fold_nearest(&f, tb_v3(2.07, -0.17, 1), &nr);
  TB_CHECK(nr.piece == 0 && nr.s == 1.0);
  TB_CHECK(tb_fold_side(&f, tb_v3(2.07, -0.17, 1)) == 1);
  tb_fold_free(&f);
  /* A sharp fold (135 degrees back): beyond its tip, where the crease is
   * nearest, piece 0's normal alone says -1; the pseudo-normal +1 (outside
   * the V, as piece 1's normal says). Inside the V: -1. */
  const tb_vec3 v[3] = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  TB_CHECK(tb_fold_init(&f, v, 3, tb_v3(0, 0, 2), NULL) == 0);
  tb_fold_nearest(&f, tb_v3(2.7, 0.6, 1), &nr);
  TB_CHECK(nr.piece == 0 && nr.s == 1.0);
  TB_CHECK(tb_fold_side(&f, tb_v3(2.7, 0.6, 1)) == 1);
  TB_CHECK(tb_fold_side(&f, tb_v3(1.5, 0.2, 1)) == -1);
  tb_fold_free(&f);
  fold_a(&f);
  /* Each side of a crossing segment's ends differ. */
  tb_rng rng = tb_rng_seed(7);
  int checked = 0;
  for (int i = 0; i < 2000; i++) {
    tb_vec3 a = tb_v3(tb_rng_range(&rng, 0.2, 3.8), tb_rng_range(&rng, -1, 2), 1);
    tb_vec3 b = tb_add(a, tb_v3(tb_rng_range(&rng, -0.1, 0.1), tb_rng_range(&rng, -0.1, 0.1), 0));
    tb_fold_near na, nb;
    tb_fold_nearest(&f, a, &na), tb_fold_nearest(&f, b, &nb);
    if (na.dist < 0.05 || nb.dist < 0.05 || na.dist > 0.3 || nb.dist > 0.3) continue;
    int cross = tb_fold_segment(&f, a, b, NULL);
    TB_CHECK_MSG(cross == (tb_fold_side(&f, a) != tb_fold_side(&f, b)), "pair %d", i);
    checked++;
  }
  TB_CHECK(checked > 100);
  tb_fold_free(&f);
}

const tb_test_case tb_tests_fold[] = {
    {"init_errors", test_init_errors},
    {"sphere_brute", test_sphere_brute},
    {"segment_brute", test_segment_brute},
    {"segment_touching", test_segment_touching},
    {"side", test_side},
    {NULL, NULL},
};
