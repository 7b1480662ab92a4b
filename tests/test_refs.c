/* Tests for the reference adapters (reference/ref_*.cpp): tb_tritri_cgal,
 * the exact oracle, must give the hand-checked answer on every pair, in every
 * vertex order and both argument orders; tb_tritri_fcl and tb_tritri_bullet
 * must give the answer they give today. Where that answer is wrong it is
 * written down as a known-wrong expectation (the library is used as is,
 * never patched): the pair's comment says why. Coordinates are dyadic, so
 * FCL's arithmetic on them is exact and its answers are those of its
 * algorithm; Bullet normalises its planes, so Bullet is not asserted where
 * its answer depends on how those roundings fall (NA). Also: CGAL's
 * exactness near contact, far from the origin, huge and subnormal
 * coordinates, non-finite input, and all three on the JGT Shen-2003 pairs. */
#include <math.h>
#include <stdio.h>

#include "tb_test.h"
#include "collision/tb_pairs.h"
#include "collision/tb_tritri.h"
#include "reference/tb_oracles.h"

#define NA (-1)                      /* not asserted */
#define ONE_ZERO 2                   /* 1 for (p, q) but 0 for (q, p) */
#define T0 0, 0, 0, 1, 0, 0, 0, 1, 0 /* the unit right triangle in z = 0 */

typedef struct ref_case {
  const char *name;
  double p[9], q[9];
  int truth;       /* checked by hand */
  int fcl, bullet; /* what the library answers today: 0, 1, ONE_ZERO or NA */
} ref_case;

/* One pair per line where it fits: {name, p, q, truth, fcl, bullet}. */
/* clang-format off */
static const ref_case ref_cases[] = {
  /* ---- two proper triangles ---- */
  {"separated, parallel planes", {T0}, {0, 0, 1, 1, 0, 1, 0, 1, 1}, 0, 0, 0},
  {"separated, plane x = 2", {T0}, {2, 0, -1, 2, 0, 1, 2, 1, 0}, 0, 0, 0},
  {"crossing", {T0}, {0.25, 0.25, -1, 0.25, 0.25, 1, -1, -1, 0}, 1, 1, 1},
  {"crossing, general", {T0},
   {0.25, 0.375, -0.5, 0.625, -0.125, 0.75, -0.375, 0.5, 0.25}, 1, 1, 1},
  {"touching at a shared vertex", {T0}, {0, 0, 0, -1, 0, 1, 0, -1, 1}, 1, 1, 1},
  {"vertex on the face", {T0}, {0.25, 0.25, 0, 0, 0, 1, 1, 0, 1}, 1, 1, 1},
  {"vertex 2^-60 above the face", {T0}, {0.25, 0.25, 0x1p-60, 0, 0, 1, 1, 0, 1}, 0, 0, 0},
  /* q's edge (0.5,0.5,1)-(0.5,-0.5,-1) meets p's edge y = 0 at (0.5,0,0) only;
   * Bullet's answer rests on rounded edge planes through that point. */
  {"edge-edge touching", {T0}, {0.5, 0.5, 1, 0.5, -0.5, -1, 0.5, -2, 0}, 1, 1, NA},
  {"edge-edge, gap 2^-40", {T0},
   {0.5, 0.5 - 0x1p-40, 1, 0.5, -0.5 - 0x1p-40, -1, 0.5, -2 - 0x1p-40, 0}, 0, 0, 0},
  {"coplanar overlap", {T0}, {0.25, 0.25, 0, 2, 0.25, 0, 0.25, 2, 0}, 1, 1, 1},
  {"coplanar overlap, opposite winding", {T0}, {0.25, 0.25, 0, 0.25, 2, 0, 2, 0.25, 0}, 1, 1, 1},
  {"coplanar containment", {T0}, {0.125, 0.125, 0, 0.5, 0.125, 0, 0.125, 0.5, 0}, 1, 1, 1},
  {"coplanar disjoint", {T0}, {1, 1, 0, 2, 1, 0, 1, 2, 0}, 0, 0, 0},
  {"coplanar, touching at a vertex", {T0}, {1, 0, 0, 2, 0, 0, 1, 1, 0}, 1, 1, 1},
  {"coplanar, shared hypotenuse", {T0}, {1, 0, 0, 0, 1, 0, 1, 1, 0}, 1, 1, 1},
  {"coplanar, shared edge on y = 0", {T0}, {0, 0, 0, 1, 0, 0, 0, -1, 0}, 1, 1, 1},
  {"parallel planes, face to face", {T0}, {0, 0, -1, 1, 0, -1, 0, 1, -1}, 0, 0, 0},
  /* known wrong: Bullet keeps clipped points lying behind the other plane
   * (one-sided test), so triangles back to back (normals pointing away from
   * each other) each lie "behind" the other: reported intersecting. */
  {"parallel planes, back to back", {T0}, {0, 0, -1, 0, 1, -1, 1, 0, -1}, 0, 0, 1},
  /* q touches the face of p (plane x+y+z = 1) at its vertex, then one ulp
   * above; exact for FCL (normal (1,1,1)), rounded for Bullet. */
  {"tilted plane, vertex on the face", {1, 0, 0, 0, 1, 0, 0, 0, 1},
   {0.25, 0.25, 0.5, 2, 2, 2, 2, 0, 2}, 1, 1, NA},
  {"tilted plane, vertex one ulp above", {1, 0, 0, 0, 1, 0, 0, 0, 1},
   {0.25, 0.25, 0x1.0000000000001p-1, 2, 2, 2, 2, 0, 2}, 0, 0, NA},
  /* known wrong: FCL's rounded separating-axis test calls this pair
   * intersecting when p comes first (not when q does); all three vertices
   * of q lie strictly below the plane of p (checked with rational
   * arithmetic): disjoint. Found by moving q's first vertex to a rounded
   * point of p's face. */
  {"near-touching, rounded vertex",
   {0x1.091ec522123d9p-3, 0x1.af22b5835e457p-3, 0x1.204a468a40949p-1,
    0x1.9676c9d32ced9p-3, 0x1.deada8cbbd5b5p-1, 0x1.815837bf02b07p-1,
    0x1.d5102943aa205p-3, 0x1.a8eb0eeb51d62p-1, 0x1.1e0aa4e23c155p-3},
   {0x1.419eb048e9ac7p-3, 0x1.9f294d6b1b74p-2, 0x1.ef8c01eeb4faap-2,
    0x1.5d645258bac8ap+0, 0x1.3b13428276268p-5, 0x1.212dd7fa425bbp-1,
    0x1.a0d215ef41a43p-1, 0x1.73862008e70c4p+0, 0x1.45e4891a8bc91p-2},
   0, ONE_ZERO, NA},

  /* ---- zero-area triangles: segments (three collinear points) and points.
   * Bullet builds a NaN plane for a zero-area triangle, and every one of
   * these pairs comes out 0: known wrong wherever the truth is 1. FCL loses
   * the axes of a zero-area triangle, so it misses separations that need
   * them: known wrong wherever it says 1 and the truth is 0. ---- */
  {"segment crossing a triangle",
   {0.25, 0.25, -1, 0.25, 0.25, 1, 0.25, 0.25, 0.5}, {T0}, 1, 1, 0},
  {"segment missing a triangle", {2, 2, -1, 2, 2, 1, 2, 2, 0}, {T0}, 0, 0, 0},
  {"segment ending on a triangle",
   {0.25, 0.25, 0, 0.25, 0.25, 1, 0.25, 0.25, 0.5}, {T0}, 1, 1, 0},
  {"segment through a triangle, coplanar",
   {-1, 0.25, 0, 2, 0.25, 0, 0.5, 0.25, 0}, {T0}, 1, 1, 0},
  /* only the segment's in-plane normal separates it from the triangle:
   * known wrong for FCL. */
  {"segment beside a coplanar triangle", {1.25, -1, 0, 0.75, 3, 0, 1, 1, 0}, {T0}, 0, 1, 0},
  /* middle point listed first: the segment is (0,0,0)-(2,0,0) */
  {"collinear segments overlapping",
   {1, 0, 0, 0, 0, 0, 2, 0, 0}, {1.75, 0, 0, 3, 0, 0, 2.5, 0, 0}, 1, 1, 0},
  /* known wrong for FCL */
  {"collinear segments disjoint",
   {1, 0, 0, 0, 0, 0, 2, 0, 0}, {2.5, 0, 0, 3, 0, 0, 2.75, 0, 0}, 0, 1, 0},
  {"collinear segments touching, direction (1,-1,1)",
   {1, -1, 1, 0, 0, 0, 2, -2, 2}, {3, -3, 3, 2, -2, 2, 2.5, -2.5, 2.5}, 1, 1, 0},
  {"segments crossing",
   {0, 0, 0, 2, 2, 0, 1, 1, 0}, {0, 2, 0, 2, 0, 0, 1.5, 0.5, 0}, 1, 1, 0},
  {"segments skew",
   {0, 0, 0, 2, 2, 0, 1, 1, 0}, {0, 2, 1, 2, 0, 1, 1.5, 0.5, 1}, 0, 0, 0},
  /* known wrong for FCL */
  {"segments coplanar, missing",
   {0, 0, 0, 2, 2, 0, 1, 1, 0}, {0, 2, 0, 0.5, 1.5, 0, 0.25, 1.75, 0}, 0, 1, 0},
  {"point inside a triangle", {0.25, 0.25, 0, 0.25, 0.25, 0, 0.25, 0.25, 0}, {T0}, 1, 1, 0},
  {"point on a triangle's edge", {0.5, 0.5, 0, 0.5, 0.5, 0, 0.5, 0.5, 0}, {T0}, 1, 1, 0},
  {"point on a triangle's vertex", {1, 0, 0, 1, 0, 0, 1, 0, 0}, {T0}, 1, 1, 0},
  {"point off a triangle's plane", {0.25, 0.25, 1, 0.25, 0.25, 1, 0.25, 0.25, 1}, {T0}, 0, 0, 0},
  {"point in the plane, outside", {1, 1, 0, 1, 1, 0, 1, 1, 0}, {T0}, 0, 0, 0},
  {"point on a segment",
   {0.5, 0.5, 0, 0.5, 0.5, 0, 0.5, 0.5, 0}, {0, 0, 0, 1, 1, 0, 2, 2, 0}, 1, 1, 0},
  /* known wrong for FCL (both) */
  {"point off a segment",
   {0.5, 0.25, 0, 0.5, 0.25, 0, 0.5, 0.25, 0}, {0, 0, 0, 1, 1, 0, 2, 2, 0}, 0, 1, 0},
  {"point beyond a segment's end",
   {3, 3, 0, 3, 3, 0, 3, 3, 0}, {0, 0, 0, 1, 1, 0, 2, 2, 0}, 0, 1, 0},
  {"same point", {1, 2, 3, 1, 2, 3, 1, 2, 3}, {1, 2, 3, 1, 2, 3, 1, 2, 3}, 1, 1, 0},
  /* known wrong for FCL */
  {"different points", {1, 2, 3, 1, 2, 3, 1, 2, 3}, {1, 2, 4, 1, 2, 4, 1, 2, 4}, 0, 1, 0},
};
/* clang-format on */
#define REF_NCASES ((int)(sizeof ref_cases / sizeof ref_cases[0]))

static void ref_load(const double a[9], tb_vec3 v[3]) {
  for (int i = 0; i < 3; i++) v[i] = tb_v3(a[3 * i], a[3 * i + 1], a[3 * i + 2]);
}

/* v in vertex order number k (0..5) */
static void ref_permute(const tb_vec3 v[3], int k, tb_vec3 out[3]) {
  static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};
  for (int i = 0; i < 3; i++) out[i] = v[perm[k][i]];
}

static void cgal_designed(void) {
  for (int c = 0; c < REF_NCASES; c++) {
    tb_vec3 p[3], q[3], pp[3], qq[3];
    ref_load(ref_cases[c].p, p);
    ref_load(ref_cases[c].q, q);
    int wrong = 0;
    for (int i = 0; i < 6; i++)
      for (int j = 0; j < 6; j++) {
        ref_permute(p, i, pp);
        ref_permute(q, j, qq);
        wrong += tb_tritri_cgal(pp, qq) != ref_cases[c].truth;
        wrong += tb_tritri_cgal(qq, pp) != ref_cases[c].truth;
      }
    TB_CHECK_MSG(wrong == 0, "%s: cgal wrong in %d of 72 vertex and argument orders",
                 ref_cases[c].name, wrong);
  }
}

/* The library's answer, both argument orders, against the recorded one. */
static void ref_library(const char *lib, tb_tritri_fn fn, int bullet) {
  int asserted = 0, known_wrong = 0;
  for (int c = 0; c < REF_NCASES; c++) {
    int want = bullet ? ref_cases[c].bullet : ref_cases[c].fcl;
    if (want == NA) continue;
    tb_vec3 p[3], q[3];
    ref_load(ref_cases[c].p, p);
    ref_load(ref_cases[c].q, q);
    int want_pq = want == ONE_ZERO ? 1 : want, want_qp = want == ONE_ZERO ? 0 : want;
    int a = fn(p, q), b = fn(q, p);
    int wrong = want_pq != ref_cases[c].truth || want_qp != ref_cases[c].truth;
    TB_CHECK_MSG(a == want_pq && b == want_qp,
                 "%s: %s answers %d and %d (swapped), recorded %d and %d%s", ref_cases[c].name, lib,
                 a, b, want_pq, want_qp, wrong ? " (a known wrong answer)" : "");
    asserted++;
    known_wrong += wrong;
  }
  /* the table itself: enough asserted pairs, and the known wrong ones listed */
  TB_CHECK(asserted >= 30 && known_wrong >= 1);
}

static void fcl_designed(void) { ref_library("fcl", tb_tritri_fcl, 0); }
static void bullet_designed(void) { ref_library("bullet", tb_tritri_bullet, 1); }

/* Answers that rounded arithmetic cannot give: contact and gaps of one unit
 * in the last place, far from the origin, with huge and subnormal numbers. */
static void cgal_exact(void) {
  tb_vec3 p[3], q[3];
  /* p in the plane x+y+z = 2^21 + 1 far from the origin; q's vertex on it,
   * then one ulp away in z */
  const double o = 0x1p20;
  p[0] = tb_v3(o + 1, o, 0), p[1] = tb_v3(o, o + 1, 0), p[2] = tb_v3(o, o, 1);
  q[0] = tb_v3(o + 0.25, o + 0.25, 0.5), q[1] = tb_v3(o + 2, o + 2, 2), q[2] = tb_v3(o + 2, o, 2);
  TB_CHECK(tb_tritri_cgal(p, q) == 1);
  q[0].z = nextafter(0.5, 1.0);
  TB_CHECK(tb_tritri_cgal(p, q) == 0);
  q[0].z = nextafter(0.5, 0.0);
  TB_CHECK(tb_tritri_cgal(p, q) == 1); /* below the plane: q now crosses p */
  /* huge: products overflow doubles */
  const double h = 0x1p1000;
  p[0] = tb_v3(0, 0, 0), p[1] = tb_v3(h, 0, 0), p[2] = tb_v3(0, h, 0);
  q[0] = tb_v3(h / 4, h / 4, 0), q[1] = tb_v3(0, 0, h), q[2] = tb_v3(h, 0, h);
  TB_CHECK(tb_tritri_cgal(p, q) == 1);
  q[0].z = 0x1p-1074;
  TB_CHECK(tb_tritri_cgal(p, q) == 0);
  /* subnormal: products underflow to zero */
  const double s = 0x1p-1060;
  p[0] = tb_v3(0, 0, 0), p[1] = tb_v3(s, 0, 0), p[2] = tb_v3(0, s, 0);
  q[0] = tb_v3(s / 4, s / 4, 0), q[1] = tb_v3(0, 0, s), q[2] = tb_v3(s, 0, s);
  TB_CHECK(tb_tritri_cgal(p, q) == 1);
  q[0].z = 0x1p-1074;
  TB_CHECK(tb_tritri_cgal(p, q) == 0);
  /* a subnormal-length segment (three distinct collinear points) through p */
  p[0] = tb_v3(0, 0, 0), p[1] = tb_v3(1, 0, 0), p[2] = tb_v3(0, 1, 0);
  q[0] = tb_v3(0.25, 0.25, -0x1p-1074), q[1] = tb_v3(0.25, 0.25, 0x1p-1074),
  q[2] = tb_v3(0.25, 0.25, 0);
  TB_CHECK(tb_tritri_cgal(p, q) == 1 && tb_tritri_cgal(q, p) == 1);
  q[0].z = 0x1p-1073, q[2].z = 0x1.8p-1073; /* now entirely above */
  TB_CHECK(tb_tritri_cgal(p, q) == 0 && tb_tritri_cgal(q, p) == 0);
}

static void cgal_nonfinite(void) {
  tb_vec3 p[3], q[3];
  ref_load((const double[9]){T0}, p);
  ref_load((const double[9]){T0}, q); /* identical: intersecting */
  TB_CHECK(tb_tritri_cgal(p, q) == 1);
  const double bad[3] = {NAN, INFINITY, -INFINITY};
  for (int k = 0; k < 3; k++)
    for (int i = 0; i < 3; i++) {
      tb_vec3 r[3] = {q[0], q[1], q[2]};
      r[i].y = bad[k];
      TB_CHECK_MSG(tb_tritri_cgal(p, r) == 0 && tb_tritri_cgal(r, p) == 0,
                   "non-finite coordinate %g at vertex %d", bad[k], i);
    }
}

/* The JGT pairs are in general position: the oracle agrees with the files,
 * FCL makes no mistake there, Bullet misses no intersection but calls 626 of
 * the 5000 separated pairs intersecting (known wrong, its one-sided test;
 * counted with Debian 12's Bullet 3.24). */
static void jgt_pairs(void) {
  char path[2][700];
  for (int k = 0; k < 2; k++) {
    snprintf(path[k], sizeof path[k], "%s/../shared/data/jgt-shen2003/%s", tb_test_source_root(),
             k ? "separated.txt" : "intersected.txt");
    FILE *f = fopen(path[k], "r");
    if (!f) {
      tb_test_skip("%s absent (../shared/data not present)", path[k]);
      return;
    }
    fclose(f);
  }
  for (int k = 0; k < 2; k++) {
    tb_pairset s;
    tb_error err;
    int label = k ? 0 : 1;
    if (tb_pairs_read_jgt(path[k], label, &s, &err) != 0) {
      TB_CHECK_MSG(0, "%s", err.msg);
      return;
    }
    int cgal = 0, fcl = 0, bullet = 0;
    for (int i = 0; i < s.n; i++) {
      const tb_tripair *t = &s.pairs[i];
      cgal += tb_tritri_cgal(t->p, t->q) != label;
      fcl += tb_tritri_fcl(t->p, t->q) != label;
      bullet += tb_tritri_bullet(t->p, t->q) != label;
    }
    TB_CHECK_MSG(s.n == 5000 && cgal == 0 && fcl == 0, "%s: %d pairs, cgal %d wrong, fcl %d wrong",
                 path[k], s.n, cgal, fcl);
    TB_CHECK_MSG(bullet == (k ? 626 : 0), "%s: bullet %d wrong", path[k], bullet);
    tb_pairs_free(&s);
  }
}

const tb_test_case tb_tests_refs[] = {
    {"cgal_designed", cgal_designed},
    {"fcl_designed", fcl_designed},
    {"bullet_designed", bullet_designed},
    {"cgal_exact", cgal_exact},
    {"cgal_nonfinite", cgal_nonfinite},
    {"jgt_pairs", jgt_pairs},
    {0, 0},
};
