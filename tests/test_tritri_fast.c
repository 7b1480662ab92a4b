/* Tests of the three published triangle-triangle methods (moller, yuhe,
 * improved): hand-built pairs for every case of thesis fig. 4.14 (a)-(f) and
 * every rejection step (V, W, H), parallel planes, coplanar overlap,
 * containment both ways and disjoint, the known wrong answers the methods'
 * inexact arithmetic gives (listed, not skipped), every finite input
 * answered with 0 or 1, 100000 random general-position pairs against a
 * brute-force edge-through-triangle reference, and the JGT Shen-2003 pairs
 * when ../shared/data is present. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_tritri.h"
#include "core/tb_rng.h"

typedef struct method {
  const char *name;
  tb_tritri_fn fn;
} method;
static const method methods[] = {
    {"moller", tb_tritri_moller}, {"yuhe", tb_tritri_yuhe}, {"improved", tb_tritri_improved}};
#define NMETHODS 3

/* A in z = 0 with P1 at the origin and P1P2 along x: the thesis's computing
 * frame is then the world frame exactly, so B's z* is B's z bit for bit. */
static const tb_vec3 frame_a[3] = {{0.2, 1.0, 0.0}, {0.0, 0.0, 0.0}, {1.0, 0.0, 0.0}};

typedef struct hand_case {
  const char *name;
  tb_vec3 b[3];
  int expect;
  /* 1: the contact is exact and only holds in the canonical frame (B's
   * vertex order is still permuted, A is not moved). */
  int touching;
} hand_case;

/* Every case of fig. 4.14 and every exit of the projection tests. */
static const hand_case hand[] = {
    /* (a) coplanar */
    {"a overlap", {{0.5, 0.2, 0}, {1.5, 0.2, 0}, {0.5, 1.2, 0}}, 1, 0},
    {"a V-reject", {{0.1, 2, 0}, {0.9, 2, 0}, {0.5, 3, 0}}, 0, 0},
    {"a W-reject", {{5, 0.1, 0}, {6, 0.1, 0}, {5.5, 0.9, 0}}, 0, 0},
    {"a disjoint in H", {{0.9, 0.9, 0}, {1.5, 0.9, 0}, {1.5, 0.5, 0}}, 0, 0},
    {"a A inside B", {{-1, -1, 0}, {3, -1, 0}, {-1, 3, 0}}, 1, 0},
    {"a B inside A", {{0.3, 0.2, 0}, {0.5, 0.2, 0}, {0.4, 0.4, 0}}, 1, 0},
    {"a shared vertex", {{1, 0, 0}, {2, 0, 0}, {1.5, 1, 0}}, 1, 1},
    /* (b) all on one side */
    {"b above", {{0.1, 0.1, 0.5}, {0.9, 0.1, 0.5}, {0.3, 0.8, 0.5}}, 0, 0},
    {"b below", {{0.1, 0.1, -0.5}, {0.9, 0.1, -2}, {0.3, 0.8, -1}}, 0, 0},
    /* (c) one vertex on H, two on one side */
    {"c point inside", {{0.3, 0.3, 0}, {0.2, 0.5, 1}, {0.6, 0.4, 1}}, 1, 1},
    {"c V-reject", {{0.3, 2, 0}, {0.2, 0.5, 1}, {0.6, 0.4, 1}}, 0, 0},
    {"c W-reject", {{5, 0.5, 0}, {0.2, 0.5, -1}, {0.6, 0.4, -1}}, 0, 0},
    {"c point outside", {{0.95, 0.9, 0}, {0.2, 0.5, 1}, {0.6, 0.4, 1}}, 0, 0},
    /* (d) two vertices on H */
    {"d segment inside", {{0.1, 0.1, 0}, {0.5, 0.2, 0}, {0.3, 0.3, 1}}, 1, 1},
    {"d segment across", {{-0.5, 0.5, 0}, {1.5, 0.5, 0}, {0.3, 0.3, -1}}, 1, 1},
    {"d V-reject", {{0.1, 2, 0}, {0.5, 3, 0}, {0.3, 0.3, 1}}, 0, 0},
    {"d W-reject", {{2, 0.2, 0}, {3, 0.5, 0}, {0.3, 0.3, 1}}, 0, 0},
    {"d H miss", {{0.9, 0.9, 0}, {1.5, 0.5, 0}, {0.3, 0.3, 1}}, 0, 0},
    {"d line hits A, segment not", {{0.95, 0.6, 0}, {0.96, 0.8, 0}, {0.5, 0.5, 1}}, 0, 0},
    {"d line through P2 only", {{1, 0.5, 0}, {1, 0.8, 0}, {0.5, 0.5, 1}}, 0, 1},
    {"d segment through P2", {{1, -0.5, 0}, {1, 0.5, 0}, {0.5, 0.5, 1}}, 1, 1},
    {"d segment through P0", {{0.2, 1.5, 0}, {0.2, 0.5, 0}, {0.5, 0.5, 1}}, 1, 1},
    /* (e) one vertex on H, two on opposite sides */
    {"e segment inside", {{0.3, 0.3, 0}, {0.3, 0.6, 1}, {0.3, 0.6, -1}}, 1, 1},
    {"e H miss", {{0.9, 0.9, 0}, {0.7, 0.95, 1}, {0.7, 0.95, -1}}, 0, 0},
    {"e V-reject", {{0.3, 1.5, 0}, {0.3, 1.6, 1}, {0.3, 1.6, -1}}, 0, 0},
    {"e W-reject", {{1.5, 0.5, 0}, {1.2, 0.9, 1}, {1.2, 0.9, -1}}, 0, 0},
    /* (f) no vertex on H */
    {"f piercing", {{0.3, 0.3, 1}, {0.2, 0.2, -1}, {0.5, 0.2, -1}}, 1, 0},
    {"f piercing from below", {{0.3, 0.3, -1}, {0.2, 0.2, 1}, {0.5, 0.2, 1}}, 1, 0},
    {"f segment across A", {{0.5, 0.5, 1}, {-2.5, 0.5, -1}, {3.5, 0.5, -1}}, 1, 0},
    {"f H miss", {{0.9, 0.9, 1}, {0.8, 0.95, -1}, {1.0, 0.85, -1}}, 0, 0},
    {"f V-reject", {{0.3, 2, 1}, {0.2, 2.5, -1}, {0.5, 2.2, -1}}, 0, 0},
    {"f W-reject", {{3, 0.3, 1}, {3.5, 0.2, -1}, {4, 0.5, -1}}, 0, 0},
    /* parallel planes */
    {"parallel planes", {{0.2, 1, 0.5}, {0, 0, 0.5}, {1, 0, 0.5}}, 0, 0},
};
#define NHAND (int)(sizeof hand / sizeof hand[0])

static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {2, 1, 0}, {1, 0, 2}};

/* Each case with B's vertices in all 6 orders; a clear (not touching) case
 * also with A's vertices rotated (another frame) and with A and B swapped. */
static void fig414_cases(void) {
  for (int c = 0; c < NHAND; c++)
    for (int m = 0; m < NMETHODS; m++)
      for (int k = 0; k < 6; k++) {
        tb_vec3 b[3] = {hand[c].b[perm[k][0]], hand[c].b[perm[k][1]], hand[c].b[perm[k][2]]};
        int got = methods[m].fn(frame_a, b);
        TB_CHECK_MSG(got == hand[c].expect, "%s, %s, B order %d: got %d", methods[m].name,
                     hand[c].name, k, got);
        if (hand[c].touching) continue;
        for (int r = 1; r < 3; r++) {
          tb_vec3 a[3] = {frame_a[r], frame_a[(r + 1) % 3], frame_a[(r + 2) % 3]};
          got = methods[m].fn(a, b);
          TB_CHECK_MSG(got == hand[c].expect, "%s, %s, A rotated %d: got %d", methods[m].name,
                       hand[c].name, r, got);
        }
        got = methods[m].fn(b, frame_a);
        TB_CHECK_MSG(got == hand[c].expect, "%s, %s, swapped: got %d", methods[m].name,
                     hand[c].name, got);
      }
}

/* Moller's intervals: the lone vertex found by each branch of the paper's
 * interval computation (distance patterns (+,+,-), (+,-,+), (-,+,+),
 * (+,0,-), (0,+,-), (0,0,+)), with the answer each must give. */
static void moller_interval_branches(void) {
  const tb_vec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const struct {
    tb_vec3 b[3];
    int expect;
  } c[] = {
      {{{0.2, 0.2, 1}, {0.3, 0.2, 1}, {0.2, 0.3, -1}}, 1},
      {{{0.2, 0.2, 1}, {0.3, 0.2, -1}, {0.2, 0.3, 1}}, 1},
      {{{0.2, 0.2, -1}, {0.3, 0.2, 1}, {0.2, 0.3, 1}}, 1},
      {{{0.2, 0.2, 1}, {0.3, 0.2, 0}, {0.2, 0.3, -1}}, 1},
      {{{0.2, 0.2, 0}, {0.3, 0.2, 1}, {0.2, 0.3, -1}}, 1},
      {{{0.2, 0.2, 0}, {0.3, 0.2, 0}, {0.2, 0.3, 1}}, 1},
      {{{2.2, 0.2, 0}, {2.3, 0.2, 0}, {2.2, 0.3, 1}}, 0},
      {{{2.2, 0.2, 1}, {2.3, 0.2, 0}, {2.2, 0.3, -1}}, 0},
  };
  for (int i = 0; i < (int)(sizeof c / sizeof c[0]); i++) {
    TB_CHECK_MSG(tb_tritri_moller(a, c[i].b) == c[i].expect, "pattern %d", i);
    TB_CHECK_MSG(tb_tritri_moller(c[i].b, a) == c[i].expect, "pattern %d swapped", i);
  }
}

/* Moller's coplanar branch on each projection plane (normal along x, y, z):
 * overlap by edges, containment both ways, disjoint, and collinear edges. */
static void moller_coplanar(void) {
  const tb_vec3 t[3] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}};
  const tb_vec3 cases[][3] = {
      {{1, 1, 0}, {5, 1, 0}, {1, 5, 0}},     /* edges cross: 1 */
      {{-1, -1, 0}, {9, -1, 0}, {-1, 9, 0}}, /* t inside: 1 */
      {{1, 1, 0}, {2, 1, 0}, {1, 2, 0}},     /* inside t: 1 */
      {{5, 5, 0}, {6, 5, 0}, {5, 6, 0}},     /* disjoint: 0 */
  };
  const int expect[] = {1, 1, 1, 0};
  for (int axis = 0; axis < 3; axis++)
    for (int i = 0; i < 4; i++) {
      tb_vec3 a[3], b[3];
      for (int v = 0; v < 3; v++) { /* rotate coordinates: the normal moves to x, y, z */
        const tb_vec3 *s = &t[v], *u = &cases[i][v];
        a[v] = axis == 0 ? tb_v3(s->z, s->x, s->y) : axis == 1 ? tb_v3(s->y, s->z, s->x) : *s;
        b[v] = axis == 0 ? tb_v3(u->z, u->x, u->y) : axis == 1 ? tb_v3(u->y, u->z, u->x) : *u;
      }
      TB_CHECK_MSG(tb_tritri_moller(a, b) == expect[i], "axis %d case %d", axis, i);
      TB_CHECK_MSG(tb_tritri_moller(b, a) == expect[i], "axis %d case %d swapped", axis, i);
    }
  /* Collinear edges sharing a segment: the parallel pair reports no crossing
   * (Antonio's f == 0), the contact is found by the edges that end on it. */
  const tb_vec3 b[3] = {{2, 0, 0}, {6, 0, 0}, {6, -4, 0}};
  TB_CHECK(tb_tritri_moller(t, b) == 1 && tb_tritri_moller(b, t) == 1);
}

/* The methods' known wrong answers on degenerate input, kept as expected
 * values: each would flip if the method were silently changed. */
static void known_wrong_answers(void) {
  const tb_vec3 a[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  /* A 1e-7 gap: Moller's epsilon (1e-6 on the distances) closes it. */
  const tb_vec3 gap[3] = {{0.2, 0.2, 1e-7}, {0.3, 0.2, 1}, {0.2, 0.3, 1}};
  TB_CHECK(tb_tritri_moller(a, gap) == 1);
  TB_CHECK(tb_tritri_yuhe(a, gap) == 0 && tb_tritri_improved(a, gap) == 0);
  /* Parallel planes 1e-7 apart: Moller goes to its coplanar branch. */
  const tb_vec3 par[3] = {{0.1, 0.1, 1e-7}, {0.5, 0.1, 1e-7}, {0.1, 0.5, 1e-7}};
  TB_CHECK(tb_tritri_moller(a, par) == 1);
  TB_CHECK(tb_tritri_yuhe(a, par) == 0 && tb_tritri_improved(a, par) == 0);
  /* B crosses A's plane with z* = +-1e-200: the original's crossing test
   * zi*zj < 0 underflows to -0, no crossing is found and the pair is called
   * separated. The improved test classifies by signs (case f) and is right. */
  const tb_vec3 tiny[3] = {{0.2, 0.2, 1e-200}, {0.3, 0.2, -1e-200}, {0.2, 0.3, 1e-200}};
  TB_CHECK(tb_tritri_yuhe(frame_a, tiny) == 0);
  TB_CHECK(tb_tritri_improved(frame_a, tiny) == 1);
}

/* Any finite input, however degenerate or extreme, gets 0 or 1. */
static void always_zero_or_one(void) {
  tb_rng r = tb_rng_seed(7);
  const double scales[] = {1.0, 1e-300, 1e-160, 1e150, 1e300, 1e-7, 1e6};
  for (int it = 0; it < 20000; it++) {
    tb_vec3 v[6];
    double s = scales[it % 7];
    for (int i = 0; i < 6; i++) {
      double c[3];
      for (int k = 0; k < 3; k++) c[k] = s * (double)tb_rng_below(&r, 3); /* lattice: many ties */
      v[i] = tb_v3(c[0], c[1], c[2]);
      if (tb_rng_below(&r, 4) == 0) v[i] = v[tb_rng_below(&r, (uint64_t)i + 1)]; /* repeats */
    }
    for (int m = 0; m < NMETHODS; m++) {
      int got = methods[m].fn(v, v + 3);
      TB_CHECK_MSG(got == 0 || got == 1, "%s returned %d at %d", methods[m].name, got, it);
    }
  }
}

/* ---- brute force in doubles, right in general position ---- */

/* Segment ab meets triangle t: a and b not strictly on one side, and the
 * line ab passes the three edges on one side. */
static int segment_triangle(tb_vec3 a, tb_vec3 b, const tb_vec3 t[3]) {
  double da = tb_tet_volume(t[0], t[1], t[2], a), db = tb_tet_volume(t[0], t[1], t[2], b);
  if ((da > 0 && db > 0) || (da < 0 && db < 0)) return 0;
  double s0 = tb_tet_volume(a, b, t[0], t[1]), s1 = tb_tet_volume(a, b, t[1], t[2]);
  double s2 = tb_tet_volume(a, b, t[2], t[0]);
  return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

static int brute(const tb_vec3 p[3], const tb_vec3 q[3]) {
  for (int i = 0; i < 3; i++) {
    if (segment_triangle(p[i], p[(i + 1) % 3], q)) return 1;
    if (segment_triangle(q[i], q[(i + 1) % 3], p)) return 1;
  }
  return 0;
}

/* Every orientation deciding the answer is well away from zero: vertex
 * against plane (margin above Moller's epsilon) and edge against edge. */
static int general_position(const tb_vec3 p[3], const tb_vec3 q[3]) {
  for (int i = 0; i < 3; i++) {
    if (fabs(6 * tb_tet_volume(p[0], p[1], p[2], q[i])) < 1e-5) return 0;
    if (fabs(6 * tb_tet_volume(q[0], q[1], q[2], p[i])) < 1e-5) return 0;
    for (int j = 0; j < 3; j++)
      if (fabs(6 * tb_tet_volume(p[i], p[(i + 1) % 3], q[j], q[(j + 1) % 3])) < 1e-9) return 0;
  }
  return 1;
}

static void random_general_position(void) {
  tb_rng r = tb_rng_seed(2013);
  int n = 0, hits = 0, skipped = 0, wrong[NMETHODS] = {0};
  while (n < 100000) {
    tb_vec3 v[6];
    /* Triangles of random size (0.05 to 1) around centres in [0, 0.1]^3. */
    for (int t = 0; t < 2; t++) {
      tb_vec3 c =
          tb_v3(tb_rng_range(&r, 0, 0.1), tb_rng_range(&r, 0, 0.1), tb_rng_range(&r, 0, 0.1));
      double s = tb_rng_range(&r, 0.05, 1.0);
      for (int i = 0; i < 3; i++)
        v[3 * t + i] = tb_madd(
            c, s, tb_v3(tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1)));
    }
    if (!general_position(v, v + 3)) {
      skipped++;
      continue;
    }
    n++;
    int want = brute(v, v + 3);
    hits += want;
    for (int m = 0; m < NMETHODS; m++) {
      if (methods[m].fn(v, v + 3) != want || methods[m].fn(v + 3, v) != want) {
        if (wrong[m]++ < 3)
          tb_test_fail(__FILE__, __LINE__, "%s disagrees with the reference at pair %d",
                       methods[m].name, n);
      }
    }
  }
  for (int m = 0; m < NMETHODS; m++)
    TB_CHECK_MSG(wrong[m] == 0, "%s: %d", methods[m].name, wrong[m]);
  TB_CHECK_MSG(hits > 10000 && hits < 90000, "intersecting pairs: %d of 100000", hits);
  TB_CHECK_MSG(skipped < 2000, "near-degenerate pairs skipped: %d", skipped);
}

/* The JGT Shen-2003 pairs: 6 lines "x y z" per pair, 5000 pairs a file. */
static void jgt_file(const char *name, int expect) {
  char path[1024];
  snprintf(path, sizeof path, "%s/../shared/data/jgt-shen2003/%s", tb_test_source_root(), name);
  FILE *fp = fopen(path, "r");
  if (!fp) {
    tb_test_skip("%s absent", path);
    return;
  }
  int n = 0, wrong[NMETHODS] = {0};
  tb_vec3 v[6];
  for (;;) {
    int ok = 1;
    for (int i = 0; i < 6 && ok; i++)
      ok = fscanf(fp, "%lf %lf %lf", &v[i].x, &v[i].y, &v[i].z) == 3;
    if (!ok) break;
    n++;
    for (int m = 0; m < NMETHODS; m++) wrong[m] += methods[m].fn(v, v + 3) != expect;
  }
  fclose(fp);
  TB_CHECK_MSG(n == 5000, "%s: %d pairs", name, n);
  for (int m = 0; m < NMETHODS; m++)
    TB_CHECK_MSG(wrong[m] == 0, "%s on %s: %d wrong", methods[m].name, name, wrong[m]);
}
static void jgt_pairs(void) {
  jgt_file("intersected.txt", 1);
  jgt_file("separated.txt", 0);
}

const tb_test_case tb_tests_tritri_fast[] = {{"fig414_cases", fig414_cases},
                                             {"moller_interval_branches", moller_interval_branches},
                                             {"moller_coplanar", moller_coplanar},
                                             {"known_wrong_answers", known_wrong_answers},
                                             {"always_zero_or_one", always_zero_or_one},
                                             {"random_general_position", random_general_position},
                                             {"jgt_pairs", jgt_pairs},
                                             {0, 0}};
