/* Tests of the triangle against the folded plane (cutting/fold_tri.c; the
 * metaball hybrid cutting patent, step 3 (5), fig. 5: through one piece,
 * across a fold, the cut starting or ending inside the triangle, none), and
 * of its degenerate inputs. Every expected point is computed by hand in the
 * comments; the folds are vertical walls over the xy path with D = (0, 0, 2):
 *   fold A: y = 0 for x in [0, 2] (piece 0), y = x - 2 for x in [2, 4] (1);
 *   fold B: fold A then y = 2 for x in [4, 5] (piece 2). */
#include <math.h>
#include <string.h>

#include "tb_test.h"
#include "cutting/tb_fold.h"

typedef struct want {
  double x, y, z, b0, b1, b2;
  int tri_loc, tri_index, piece, fold_loc;
} want;

enum { IN = TB_FOLD_TRI_INTERIOR, ED = TB_FOLD_TRI_EDGE, VX = TB_FOLD_TRI_VERTEX };
enum { CR = TB_FOLD_CREASE, ST = TB_FOLD_START, EN = TB_FOLD_END, PA = TB_FOLD_PATH };
enum { DE = TB_FOLD_DEPTH };

static void make_fold(tb_fold *f, int three) {
  const tb_vec3 p[4] = {{0, 0, 0}, {2, 0, 0}, {4, 2, 0}, {5, 2, 0}};
  TB_CHECK(tb_fold_init(f, p, three ? 4 : 3, tb_v3(0, 0, 2), NULL) == 0);
}

/* Cuts tri with the fold and compares with the n expected points, which
 * form npoly polylines, point i in polyline poly_at[i]. */
static void expect_cut_poly(const char *what, int three, const tb_vec3 tri[3], int n, int npoly,
                            const want *w, int coplanar, const int *poly_at) {
  tb_fold f;
  make_fold(&f, three);
  tb_fold_cut cut, again;
  int got = tb_fold_triangle(&f, tri, &cut);
  tb_fold_triangle(&f, tri, &again);
  TB_CHECK_MSG(!memcmp(&cut, &again, sizeof cut), "%s: not deterministic", what);
  TB_CHECK_MSG(got == n && cut.n == n && cut.npoly == npoly && cut.coplanar == coplanar &&
                   !cut.truncated && !cut.degenerate,
               "%s: %d points in %d polylines, coplanar %d; want %d in %d, %d", what, cut.n,
               cut.npoly, cut.coplanar, n, npoly, coplanar);
  for (int i = 0; i < n && i < cut.n; i++) {
    const tb_fold_tpoint *p = &cut.pt[i];
    tb_vec3 x = tb_v3(w[i].x, w[i].y, w[i].z);
    double bx = w[i].b0 - p->bary[0], by = w[i].b1 - p->bary[1], bz = w[i].b2 - p->bary[2];
    TB_CHECK_MSG(tb_dist(p->x, x) <= 1e-12 && fabs(bx) + fabs(by) + fabs(bz) <= 1e-12,
                 "%s point %d: (%.17g %.17g %.17g) bary (%.17g %.17g %.17g)", what, i, p->x.x,
                 p->x.y, p->x.z, p->bary[0], p->bary[1], p->bary[2]);
    TB_CHECK_MSG(p->tri_loc == w[i].tri_loc && p->tri_index == w[i].tri_index &&
                     p->piece == w[i].piece && p->fold_loc == w[i].fold_loc,
                 "%s point %d: tri %d/%d piece %d fold %d; want %d/%d %d %d", what, i, p->tri_loc,
                 p->tri_index, p->piece, p->fold_loc, w[i].tri_loc, w[i].tri_index, w[i].piece,
                 w[i].fold_loc);
    int poly = poly_at[i];
    TB_CHECK_MSG(p->polyline == poly, "%s point %d: polyline %d, want %d", what, i, p->polyline,
                 poly);
    /* The point is on its piece at (s, t), and on the triangle by bary. */
    tb_vec3 y = tb_madd(tb_madd(f.p[p->piece], p->s, f.piece[p->piece].e), p->t, f.depth);
    tb_vec3 z =
        tb_madd(tb_madd(tb_scale(tri[0], p->bary[0]), p->bary[1], tri[1]), p->bary[2], tri[2]);
    TB_CHECK_MSG(tb_dist(y, p->x) <= 1e-12 && tb_dist(z, p->x) <= 1e-12, "%s point %d: s, t", what,
                 i);
  }
  tb_fold_free(&f);
}

static void expect_cut(const char *what, int three, const tb_vec3 tri[3], int n, int npoly,
                       const want *w, int coplanar) {
  const int one_poly[TB_FOLD_CUT_MAX] = {0};
  expect_cut_poly(what, three, tri, n, npoly, w, coplanar, one_poly);
}

/* Fig. 5's cases at height z = 1 (t = 1/2). */
static void test_fig5(void) {
  /* Through piece 0 alone: y = 0 meets edge v0-v2 at its midpoint (0.75, 0)
   * and edge v1-v2 at (1.25, 0); ordered by s = x / 2. */
  const tb_vec3 one[3] = {{0.5, -1, 1}, {1.5, -1, 1}, {1, 1, 1}};
  const want w1[2] = {{0.75, 0, 1, 0.5, 0, 0.5, ED, 1, 0, 0},
                      {1.25, 0, 1, 0, 0.5, 0.5, ED, 0, 0, 0}};
  expect_cut("one piece", 0, one, 2, 1, w1, 0);
  /* Across the fold: edge v0-v2 (x = 1 + a, y = -1 + 4a) at a = 1/4; the
   * crease (2, 0) inside with bary (3/8, 3/8, 1/4); piece 1's y = x - 2
   * leaves through v1-v2 (x = 3 - a, y = -1 + 4a) at a = 2/5. */
  const tb_vec3 fold[3] = {{1, -1, 1}, {3, -1, 1}, {2, 3, 1}};
  const want w2[3] = {{1.25, 0, 1, 0.75, 0, 0.25, ED, 1, 0, 0},
                      {2, 0, 1, 0.375, 0.375, 0.25, IN, -1, 0, CR},
                      {2.6, 0.6, 1, 0, 0.6, 0.4, ED, 0, 1, 0}};
  expect_cut("across the fold", 0, fold, 3, 1, w2, 0);
  /* The cut starts inside: p_0's edge at (0, 0), bary (1/4, 1/4, 1/2); exit
   * through v1-v2 at its midpoint. */
  const tb_vec3 start[3] = {{-1, -1, 1}, {1, -1, 1}, {0, 1, 1}};
  const want w3[2] = {{0, 0, 1, 0.25, 0.25, 0.5, IN, -1, 0, ST},
                      {0.5, 0, 1, 0, 0.5, 0.5, ED, 0, 0, 0}};
  expect_cut("starts inside", 0, start, 2, 1, w3, 0);
  /* The cut ends inside: piece 1 enters through v0-v2 (x = 3 + a, y = 4a)
   * at a = 1/3, ends at p_2 = (4, 2), bary (1/4, 1/4, 1/2). Piece 0's line
   * y = 0 touches v0's line but not the triangle. */
  const tb_vec3 end[3] = {{3, 0, 1}, {5, 0, 1}, {4, 4, 1}};
  const want w4[2] = {{10.0 / 3, 4.0 / 3, 1, 2.0 / 3, 0, 1.0 / 3, ED, 1, 1, 0},
                      {4, 2, 1, 0.25, 0.25, 0.5, IN, -1, 1, EN}};
  expect_cut("ends inside", 0, end, 2, 1, w4, 0);
  /* The depth edge inside: the triangle stands in x = 1; the wall y = 0
   * meets it from (1, 0, 0.5) on v0-v1 up to the depth edge (1, 0, 2),
   * bary (0.2, 0.2, 0.6). */
  const tb_vec3 depth[3] = {{1, -1, 0.5}, {1, 1, 0.5}, {1, 0, 3}};
  const want w5[2] = {{1, 0, 0.5, 0.5, 0.5, 0, ED, 2, 0, 0},
                      {1, 0, 2, 0.2, 0.2, 0.6, IN, -1, 0, DE}};
  expect_cut("depth edge inside", 0, depth, 2, 1, w5, 0);
  /* A vertex and an interior point (the first case's variant): v1 lies on
   * the wall; p_0's edge at (0, 0) has bary (1/6, 2/3, 1/6). */
  const tb_vec3 vert[3] = {{-1, -1, 1}, {0.5, 0, 1}, {-1, 1, 1}};
  const want w6[2] = {{0, 0, 1, 1.0 / 6, 2.0 / 3, 1.0 / 6, IN, -1, 0, ST},
                      {0.5, 0, 1, 0, 1, 0, VX, 1, 0, 0}};
  expect_cut("vertex and interior point", 0, vert, 2, 1, w6, 0);
  /* Fold B across both creases, ending inside: (1, 0) on v0-v2 (x = 4a,
   * y = -2 + 8a, a = 1/4); creases (2, 0) and (4, 2); the end (5, 2). */
  const tb_vec3 big[3] = {{0, -2, 1}, {8, -2, 1}, {4, 6, 1}};
  const want w7[4] = {{1, 0, 1, 0.75, 0, 0.25, ED, 1, 0, 0},
                      {2, 0, 1, 0.625, 0.125, 0.25, IN, -1, 0, CR},
                      {4, 2, 1, 0.25, 0.25, 0.5, IN, -1, 1, CR},
                      {5, 2, 1, 0.125, 0.375, 0.5, IN, -1, 2, EN}};
  expect_cut("two creases", 1, big, 4, 1, w7, 0);
  /* In, out and in again: the chord from (1, 0) to (3, 1) bounds a triangle
   * on the bend's concave side, which misses the crease (2, 0). A = (0.5,
   * -0.25), B = (3.5, 1.25), C = (2, 2): piece 0 from (2/3, 0) on AC (1/9 of
   * the way) to (1, 0) on AB (1/6); piece 1 from (3, 1) on AB (5/6) to
   * (10/3, 4/3) on BC (1/9 of the way from B). Two polylines. */
  const tb_vec3 twice[3] = {{0.5, -0.25, 1}, {3.5, 1.25, 1}, {2, 2, 1}};
  const want w8[4] = {{2.0 / 3, 0, 1, 8.0 / 9, 0, 1.0 / 9, ED, 1, 0, 0},
                      {1, 0, 1, 5.0 / 6, 1.0 / 6, 0, ED, 2, 0, 0},
                      {3, 1, 1, 1.0 / 6, 5.0 / 6, 0, ED, 2, 1, 0},
                      {10.0 / 3, 4.0 / 3, 1, 0, 8.0 / 9, 1.0 / 9, ED, 0, 1, 0}};
  const int p8[4] = {0, 0, 1, 1};
  expect_cut_poly("in, out and in again", 0, twice, 4, 2, w8, 0, p8);
  const tb_vec3 none[3] = {{10, 10, 1}, {11, 10, 1}, {10, 11, 1}};
  expect_cut("no intersection", 0, none, 0, 0, NULL, 0);
}

/* Degenerate and touching configurations: documented results, no crash. */
static void test_degenerate(void) {
  /* The plane x = 2 holds crease 0|1 but neither piece: the crease, listed
   * once by piece 0; bary of (2,0,0): (3/8, 3/8, 1/4), of (2,0,2): (1/8,
   * 1/8, 3/4). */
  const tb_vec3 cr[3] = {{2, -1, -1}, {2, 1, -1}, {2, 0, 3}};
  const want w1[2] = {{2, 0, 0, 0.375, 0.375, 0.25, IN, -1, 0, CR | PA},
                      {2, 0, 2, 0.125, 0.125, 0.75, IN, -1, 0, CR | DE}};
  expect_cut("plane through the crease", 0, cr, 2, 1, w1, 0);
  /* A triangle edge along the crease. */
  const tb_vec3 ce[3] = {{2, 0, 0}, {2, 0, 2}, {2, 1, 1}};
  const want w2[2] = {{2, 0, 0, 1, 0, 0, VX, 0, 0, CR | PA}, {2, 0, 2, 0, 1, 0, VX, 1, 0, CR | DE}};
  expect_cut("edge along the crease", 0, ce, 2, 1, w2, 0);
  /* The plane z = 0 holds the whole path: the path edge, through the fold
   * vertex p_1. */
  const tb_vec3 pa[3] = {{1, -1, 0}, {3, -1, 0}, {2, 3, 0}};
  const want w3[3] = {{1.25, 0, 0, 0.75, 0, 0.25, ED, 1, 0, PA},
                      {2, 0, 0, 0.375, 0.375, 0.25, IN, -1, 0, CR | PA},
                      {2.6, 0.6, 0, 0, 0.6, 0.4, ED, 0, 1, PA}};
  expect_cut("plane along the path", 0, pa, 3, 1, w3, 0);
  /* The plane z = x - 2 through p_1: piece 0 touches it at p_1 only, piece
   * 1 is cut along its diagonal p_1 -> q_2 (s = t), leaving through v1-v2
   * at (2.6, 0.6, 0.6). */
  const tb_vec3 tv[3] = {{1, -1, -1}, {3, -1, 1}, {2, 3, 0}};
  const want w4[2] = {{2, 0, 0, 0.375, 0.375, 0.25, IN, -1, 0, CR | PA},
                      {2.6, 0.6, 0.6, 0, 0.6, 0.4, ED, 0, 1, 0}};
  expect_cut("through the fold vertex", 0, tv, 2, 1, w4, 0);
  /* Coplanar with piece 0, inside it: counted, not listed. */
  const tb_vec3 cp[3] = {{0.5, 0, 0.5}, {1.5, 0, 0.5}, {1, 0, 1.5}};
  expect_cut("coplanar inside a piece", 0, cp, 0, 0, NULL, 1);
  /* Coplanar with piece 0 and straddling the crease: piece 1 lists the
   * crease inside the triangle, from (2, 0, 0.5) on v0-v1 to v2. */
  const tb_vec3 cs[3] = {{1, 0, 0.5}, {3, 0, 0.5}, {2, 0, 1.5}};
  const want w6[2] = {{2, 0, 0.5, 0.5, 0.5, 0, ED, 2, 0, CR}, {2, 0, 1.5, 0, 0, 1, VX, 2, 0, CR}};
  expect_cut("coplanar across the crease", 0, cs, 2, 1, w6, 1);
  /* A triangle touching piece 0 at its vertex v0 only: one point. */
  const tb_vec3 tp[3] = {{1, 0, 1}, {1, -1, 0.5}, {1.5, -1, 1.5}};
  const want w7[1] = {{1, 0, 1, 1, 0, 0, VX, 0, 0, 0}};
  expect_cut("touching at a vertex", 0, tp, 1, 1, w7, 0);
  /* Tangent to the depth edge from above: the edge's point (1, 0, 2). */
  const tb_vec3 td[3] = {{1, 0, 2}, {0, -1, 3}, {0, 1, 3}};
  const want w8[1] = {{1, 0, 2, 1, 0, 0, VX, 0, 0, DE}};
  expect_cut("touching the depth edge", 0, td, 1, 1, w8, 0);
  /* Piece 1 runs along the triangle's edge v0-v1 (the line y = x - 2, with
   * inexact coordinates): piece 0 enters through v2-v0 at 17/24 of the way
   * from v2, the crease (2, 0) lies on v0-v1 at 7/16 from v0, then the cut
   * follows the edge to v1. */
  const tb_vec3 ae[3] = {{1.3, -0.7, 1}, {2.9, 0.9, 1}, {1.1, 1.7, 1}};
  const want w9[3] = {{1.1 + 0.2 * 17 / 24, 0, 1, 17.0 / 24, 0, 7.0 / 24, ED, 1, 0, 0},
                      {2, 0, 1, 0.5625, 0.4375, 0, ED, 2, 0, CR},
                      {2.9, 0.9, 1, 0, 1, 0, VX, 1, 1, 0}};
  expect_cut("along a triangle edge", 0, ae, 3, 1, w9, 0);
  /* Zero-area triangles: nothing computed. */
  tb_fold f;
  make_fold(&f, 0);
  tb_fold_cut cut;
  const tb_vec3 line[3] = {{0, -1, 0}, {1, 0, 1}, {2, 1, 2}};
  TB_CHECK(tb_fold_triangle(&f, line, &cut) == 0 && cut.degenerate == 1);
  const tb_vec3 pt[3] = {{1, 0, 1}, {1, 0, 1}, {1, 0, 1}};
  TB_CHECK(tb_fold_triangle(&f, pt, &cut) == 0 && cut.degenerate == 1);
  const tb_vec3 bad[3] = {{NAN, 0, 1}, {1, 0, 1}, {2, 0, 1}};
  TB_CHECK(tb_fold_triangle(&f, bad, &cut) == 0 && cut.degenerate == 1);
  tb_fold_free(&f);
}

const tb_test_case tb_tests_fold_tri[] = {
    {"fig5", test_fig5},
    {"degenerate", test_degenerate},
    {NULL, NULL},
};
