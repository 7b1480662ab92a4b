/* Tests for the reference mesh-mesh adapters (reference/ref_bvh_*.cpp):
 * every pair set is compared pair by pair with a brute-force loop over all
 * triangle pairs written here. fcl-aabb, fcl-obbrss and bullet-gimpact-exact
 * must equal brute force under our exact test on two geodesic spheres at
 * several offsets (overlapping, identical, disjoint), after refits (within
 * and beyond Bullet's quantization range) and on the liver against the
 * instrument; fcl-aabb must also equal brute force under FCL's own test
 * restricted to pairs whose boxes touch (what its traversal computes).
 * bullet-gimpact (Bullet's own triangle test) must report only pairs that
 * tb_tritri_bullet accepts, and every pair tb_tritri_bullet accepts that it
 * leaves out must have triangle boxes overlapping by less than GImpact's
 * box quantization (or not at all). Bad input must give errors. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_tritri.h"
#include "core/tb_rng.h"
#include "meshgen/tb_generators.h"
#include "reference/tb_oracles.h"
#include "reference/tb_refbvh.h"

static const tb_ref_kind kinds[] = {TB_REF_FCL_AABB, TB_REF_FCL_OBBRSS, TB_REF_BULLET_GIMPACT,
                                    TB_REF_BULLET_GIMPACT_EXACT};
static const char *const kind_names[] = {"fcl-aabb", "fcl-obbrss", "bullet-gimpact",
                                         "bullet-gimpact-exact"};
enum { NKINDS = 4 };

/* ---- pair lists, kept here so the tests do not depend on tb_bvh's ---- */
static int push(tb_pairlist *p, int i, int j) {
  if (p->n == p->cap) {
    int cap = p->cap ? 2 * p->cap : 256;
    int *ij = realloc(p->ij, sizeof *ij * 2 * (size_t)cap);
    if (!ij) return -1;
    p->ij = ij, p->cap = cap;
  }
  p->ij[2 * p->n] = i, p->ij[2 * p->n + 1] = j;
  p->n++;
  return 0;
}
static int pair_cmp(const void *a, const void *b) {
  const int *x = a, *y = b;
  if (x[0] != y[0]) return x[0] < y[0] ? -1 : 1;
  return x[1] < y[1] ? -1 : x[1] > y[1];
}
/* Sorts and removes duplicates; returns the number of duplicates removed. */
static int sort_unique(tb_pairlist *p) {
  if (p->n == 0) return 0;
  qsort(p->ij, (size_t)p->n, 2 * sizeof(int), pair_cmp);
  int m = 1;
  for (int k = 1; k < p->n; k++)
    if (pair_cmp(p->ij + 2 * k, p->ij + 2 * (m - 1))) {
      p->ij[2 * m] = p->ij[2 * k], p->ij[2 * m + 1] = p->ij[2 * k + 1];
      m++;
    }
  int dup = p->n - m;
  p->n = m;
  return dup;
}
static int has(const tb_pairlist *sorted, const int *ij) {
  return sorted->n > 0 && bsearch(ij, sorted->ij, (size_t)sorted->n, 2 * sizeof(int), pair_cmp);
}
static void pl_free(tb_pairlist *p) {
  free(p->ij);
  memset(p, 0, sizeof *p);
}

/* A mesh's vertices in world space (the triangles are the mesh's). */
typedef struct posed {
  const tb_mesh *m;
  tb_vec3 *x;
} posed;

static void tri_of(const posed *a, int i, tb_vec3 p[3]) {
  for (int c = 0; c < 3; c++) p[c] = a->x[a->m->tri[3 * i + c]];
}

static void brute(const posed *a, const posed *b, tb_tritri_fn test, tb_pairlist *out) {
  out->n = 0;
  for (int i = 0; i < a->m->ntri; i++) {
    tb_vec3 p[3], q[3];
    tri_of(a, i, p);
    for (int j = 0; j < b->m->ntri; j++) {
      tri_of(b, j, q);
      if (test(p, q) && push(out, i, j)) {
        TB_CHECK_MSG(0, "out of memory");
        return;
      }
    }
  }
}

/* Smallest overlap over the axes of the two triangles' boxes (negative when
 * the boxes are apart), and whether it is within GImpact's quantization:
 * a box edge may move inward by half a quantum (extent + 2) / 65535. */
static void box_of(const posed *a, int i, tb_vec3 *lo, tb_vec3 *hi) {
  tb_vec3 p[3];
  tri_of(a, i, p);
  *lo = tb_vmin(p[0], tb_vmin(p[1], p[2]));
  *hi = tb_vmax(p[0], tb_vmax(p[1], p[2]));
}
static void mesh_box(const posed *a, tb_vec3 *lo, tb_vec3 *hi) {
  box_of(a, 0, lo, hi);
  for (int i = 1; i < a->m->ntri; i++) {
    tb_vec3 l, h;
    box_of(a, i, &l, &h);
    *lo = tb_vmin(*lo, l), *hi = tb_vmax(*hi, h);
  }
}
static int within_quantum(const posed *a, int i, const posed *b, int j, tb_vec3 qa, tb_vec3 qb) {
  tb_vec3 la, ha, lb, hb;
  box_of(a, i, &la, &ha);
  box_of(b, j, &lb, &hb);
  for (int d = 0; d < 3; d++) {
    double overlap = fmin(tb_comp(ha, d), tb_comp(hb, d)) - fmax(tb_comp(la, d), tb_comp(lb, d));
    if (overlap <= 0.5 * (tb_comp(qa, d) + tb_comp(qb, d)) * 1.001) return 1;
  }
  return 0;
}
/* GImpact's quanta: the box the tree was built for (the mesh at build time). */
static tb_vec3 quantum(const posed *built) {
  tb_vec3 lo, hi;
  mesh_box(built, &lo, &hi);
  return tb_scale(tb_add(tb_sub(hi, lo), tb_v3(2, 2, 2)), 1.0 / 65535.0);
}

/* got (sorted) must equal want (sorted). */
static void check_equal(const char *what, const tb_pairlist *got, const tb_pairlist *want) {
  int missing = 0, extra = 0, first[2] = {-1, -1};
  for (int k = 0; k < want->n; k++)
    if (!has(got, want->ij + 2 * k) && missing++ == 0)
      memcpy(first, want->ij + 2 * k, sizeof first);
  for (int k = 0; k < got->n; k++)
    if (!has(want, got->ij + 2 * k) && extra++ == 0) memcpy(first, got->ij + 2 * k, sizeof first);
  TB_CHECK_MSG(missing == 0 && extra == 0,
               "%s: %d pairs, brute force %d: %d missing, %d extra (first: %d %d)", what, got->n,
               want->n, missing, extra, first[0], first[1]);
}

/* bullet-gimpact: every pair it reports passes tb_tritri_bullet; with want
 * (brute force under tb_tritri_bullet, sorted) also every pair it leaves out
 * is explained by the quantized boxes. */
static void check_gimpact(const char *what, const tb_pairlist *got, const tb_pairlist *want,
                          const posed *a, const posed *b, tb_vec3 qa, tb_vec3 qb) {
  int unexplained = 0, extra = 0;
  for (int k = 0; want && k < want->n; k++) {
    const int *ij = want->ij + 2 * k;
    if (!has(got, ij) && !within_quantum(a, ij[0], b, ij[1], qa, qb)) unexplained++;
  }
  for (int k = 0; k < got->n; k++) {
    tb_vec3 p[3], q[3];
    tri_of(a, got->ij[2 * k], p);
    tri_of(b, got->ij[2 * k + 1], q);
    extra += !tb_tritri_bullet(p, q);
  }
  TB_CHECK_MSG(unexplained == 0 && extra == 0, "%s: %d unexplained misses, %d extra", what,
               unexplained, extra);
}

/* fcl-aabb against brute force under FCL's test on pairs whose closed
 * triangle boxes touch: the traversal's exact semantics. */
static void check_fcl_aabb(const char *what, const tb_pairlist *got, const posed *a,
                           const posed *b) {
  tb_pairlist want = {0};
  brute(a, b, tb_tritri_fcl, &want);
  int m = 0;
  for (int k = 0; k < want.n; k++) {
    tb_vec3 la, ha, lb, hb;
    box_of(a, want.ij[2 * k], &la, &ha);
    box_of(b, want.ij[2 * k + 1], &lb, &hb);
    if (la.x <= hb.x && lb.x <= ha.x && la.y <= hb.y && lb.y <= ha.y && la.z <= hb.z &&
        lb.z <= ha.z)
      want.ij[2 * m] = want.ij[2 * k], want.ij[2 * m + 1] = want.ij[2 * k + 1], m++;
  }
  want.n = m;
  check_equal(what, got, &want);
  pl_free(&want);
}

/* 1: the FCL kinds are held to brute force under FCL's own triangle test
 * (on box-touching pairs) instead of the exact one: where that
 * floating-point test overflows (test_scaled), its answers are its own. */
static int fcl_own_test;

/* Collides a and b with every kind (a_built/b_built: the positions the
 * Bullet trees were built for, for the quanta) and checks the pair sets;
 * full: also the checks that need brute force under Bullet's and FCL's
 * tests. */
static void check_all(const char *label, tb_ref_bvh *ra[NKINDS], tb_ref_bvh *rb[NKINDS],
                      const posed *a, const posed *b, const posed *a_built, const posed *b_built,
                      int full) {
  tb_pairlist exact = {0}, bullet = {0};
  brute(a, b, tb_tritri_exact, &exact);
  if (full) brute(a, b, tb_tritri_bullet, &bullet);
  const tb_vec3 qa = quantum(a_built), qb = quantum(b_built);
  for (int k = 0; k < NKINDS; k++) {
    char what[160];
    snprintf(what, sizeof what, "%s, %s", label, kind_names[k]);
    tb_pairlist got = {0};
    tb_error err = {""};
    int rc = tb_ref_bvh_collide(ra[k], rb[k], &got, &err);
    TB_CHECK_MSG(rc == 0, "%s: %s", what, err.msg);
    TB_CHECK_MSG(sort_unique(&got) == 0, "%s: duplicate pairs", what);
    if (fcl_own_test && (kinds[k] == TB_REF_FCL_AABB || kinds[k] == TB_REF_FCL_OBBRSS))
      check_fcl_aabb(what, &got, a, b); /* FCL's floating-point test decides */
    else if (kinds[k] == TB_REF_BULLET_GIMPACT)
      check_gimpact(what, &got, full ? &bullet : NULL, a, b, qa, qb);
    else
      check_equal(what, &got, &exact);
    if (full && kinds[k] == TB_REF_FCL_AABB) check_fcl_aabb(what, &got, a, b);
    pl_free(&got);
  }
  pl_free(&exact);
  pl_free(&bullet);
}

static int build_all(tb_ref_bvh *r[NKINDS], const posed *a) {
  for (int k = 0; k < NKINDS; k++) {
    tb_error err = {""};
    r[k] = tb_ref_bvh_build(kinds[k], a->x, a->m->nv, a->m->tri, a->m->ntri, &err);
    TB_CHECK_MSG(r[k] != NULL, "%s: %s", kind_names[k], err.msg);
    if (!r[k]) return -1;
  }
  return 0;
}
static void free_all(tb_ref_bvh *r[NKINDS]) {
  for (int k = 0; k < NKINDS; k++) tb_ref_bvh_free(r[k]), r[k] = NULL;
}

/* A mesh from the generator table with its default settings. */
static int generate(const char *name, tb_mesh_part part, tb_mesh *out) {
  const tb_generator *g = tb_generator_find(name);
  TB_CHECK_MSG(g != NULL, "no generator %s", name);
  if (!g) return -1;
  double p[TB_GEN_MAX_PARAMS];
  tb_generator_defaults(g, p);
  tb_gen_result r;
  memset(&r, 0, sizeof r);
  tb_error err = {""};
  int rc = tb_generator_run(g, p, &r, &err);
  if (!rc) rc = tb_gen_result_part(&r, part, out, &err);
  TB_CHECK_MSG(rc == 0, "%s: %s", name, err.msg);
  tb_gen_result_free(&r);
  return rc;
}

/* x = R m.x + t into a fresh array. */
static tb_vec3 *moved(const tb_mesh *m, tb_mat3 R, tb_vec3 t) {
  tb_vec3 *x = malloc(sizeof *x * (size_t)m->nv);
  if (!x) return NULL;
  for (int i = 0; i < m->nv; i++) x[i] = tb_add(tb_m3_mulv(R, m->x[i]), t);
  return x;
}

static void test_spheres(void) {
  tb_mesh s = {0};
  tb_error err = {""};
  if (generate("sphere", TB_PART_SURFACE, &s)) return; /* 252 vertices, radius 1 */
  TB_CHECK(s.nv == 252);
  posed a = {&s, s.x};
  tb_ref_bvh *ra[NKINDS] = {0};
  if (build_all(ra, &a)) goto done;
  /* B rotated and offset: partial overlap, deeper, nearly coincident, the
   * same sphere (every triangle touches its copy and its copy's
   * neighbours), disjoint. */
  static const double offsets[][3] = {
      {1.2, 0.35, 0.1}, {0.6, -0.45, 0.25}, {0.13, 0.07, -0.05}, {0, 0, 0}, {2.5, 0.1, 0}};
  static const double angles[] = {0.3, 1.1, 0.05, 0, 0.7};
  for (int c = 0; c < 5; c++) {
    tb_vec3 *xb = moved(&s, tb_m3_rotation(tb_v3(1, 2, 3), angles[c]),
                        tb_v3(offsets[c][0], offsets[c][1], offsets[c][2]));
    TB_CHECK(xb != NULL);
    if (!xb) break;
    posed b = {&s, xb};
    tb_ref_bvh *rb[NKINDS] = {0};
    if (build_all(rb, &b) == 0) {
      char label[64];
      snprintf(label, sizeof label, "spheres, case %d", c);
      check_all(label, ra, rb, &a, &b, &a, &b, 1);
      if (c == 4) {
        tb_pairlist got = {0};
        TB_CHECK(tb_ref_bvh_collide(ra[0], rb[0], &got, &err) == 0 && got.n == 0);
        pl_free(&got);
      }
    }
    free_all(rb);
    free(xb);
  }
done:
  free_all(ra);
  tb_mesh_free(&s);
}

/* The spheres of test_spheres (partial overlap) scaled by exact powers of
 * two across the coordinates readers accept (TB_COORD_MAX = 1e90 ~ 2^299,
 * down to 2^-290): the reference hierarchies stay equal to brute force
 * (every hierarchy, not only ours); at 2^290 FCL's own
 * triangle test loses pairs to overflow (counted, see the correctness
 * table's scaled rows), and FCL's hierarchies equal brute force under it. */
static void test_scaled(void) {
  tb_mesh s = {0};
  if (generate("sphere", TB_PART_SURFACE, &s)) return;
  static const int scales[] = {-290, -100, 100, 290};
  tb_vec3 *xa = malloc(sizeof *xa * (size_t)s.nv),
          *xb = moved(&s, tb_m3_rotation(tb_v3(1, 2, 3), 1.1), tb_v3(0.6, -0.45, 0.25));
  TB_CHECK(xa && xb);
  for (int e = 0; xa && xb && e < 4; e++) {
    tb_vec3 *yb = malloc(sizeof *yb * (size_t)s.nv);
    if (!yb) break;
    for (int i = 0; i < s.nv; i++) {
      xa[i] =
          tb_v3(ldexp(s.x[i].x, scales[e]), ldexp(s.x[i].y, scales[e]), ldexp(s.x[i].z, scales[e]));
      yb[i] =
          tb_v3(ldexp(xb[i].x, scales[e]), ldexp(xb[i].y, scales[e]), ldexp(xb[i].z, scales[e]));
    }
    posed a = {&s, xa}, b = {&s, yb};
    tb_ref_bvh *ra[NKINDS] = {0}, *rb[NKINDS] = {0};
    if (build_all(ra, &a) == 0 && build_all(rb, &b) == 0) {
      char label[64];
      snprintf(label, sizeof label, "spheres x 2^%d", scales[e]);
      /* at 2^290 FCL's triangle test (products of up to six coordinates)
       * overflows and misses pairs: its hierarchies are then checked
       * against brute force under that test, and the misses counted */
      fcl_own_test = scales[e] == 290;
      check_all(label, ra, rb, &a, &b, &a, &b, 1);
      fcl_own_test = 0;
      if (scales[e] == 290) {
        tb_pairlist exact = {0}, fcl = {0};
        brute(&a, &b, tb_tritri_exact, &exact), brute(&a, &b, tb_tritri_fcl, &fcl);
        int missed = 0, extra = 0;
        for (int k = 0; k < exact.n; k++) missed += !has(&fcl, exact.ij + 2 * k);
        for (int k = 0; k < fcl.n; k++) extra += !has(&exact, fcl.ij + 2 * k);
        printf("  2^290: FCL's triangle test misses %d of %d pairs, adds %d\n", missed, exact.n,
               extra);
        TB_CHECK(exact.n > 0);
        pl_free(&exact), pl_free(&fcl);
      }
    }
    free_all(ra), free_all(rb);
    free(yb);
  }
  free(xa), free(xb);
  tb_mesh_free(&s);
}

/* A smooth displacement of amplitude amp, then scaled by s about the origin. */
static void deform(const tb_mesh *m, double amp, double s, tb_vec3 shift, tb_vec3 *x) {
  for (int i = 0; i < m->nv; i++) {
    tb_vec3 p = m->x[i];
    tb_vec3 d = tb_v3(sin(2 * p.y + 0.3), cos(3 * p.z), sin(p.x + p.z));
    x[i] = tb_add(tb_scale(tb_madd(p, amp, d), s), shift);
  }
}

static void test_update(void) {
  tb_mesh s = {0};
  tb_error err = {""};
  if (generate("sphere", TB_PART_SURFACE, &s)) return; /* 252 vertices, radius 1 */
  TB_CHECK(s.nv == 252);
  tb_vec3 *xa = malloc(sizeof *xa * (size_t)s.nv), *xa0 = malloc(sizeof *xa0 * (size_t)s.nv);
  tb_vec3 *xb = moved(&s, tb_m3_rotation(tb_v3(0, 1, 1), 0.4), tb_v3(1.1, 0.2, -0.15));
  tb_vec3 *xb0 = moved(&s, tb_m3_rotation(tb_v3(0, 1, 1), 0.4), tb_v3(1.1, 0.2, -0.15));
  TB_CHECK(xa && xa0 && xb && xb0);
  if (!xa || !xa0 || !xb || !xb0) goto out;
  memcpy(xa, s.x, sizeof *xa * (size_t)s.nv);
  memcpy(xa0, s.x, sizeof *xa * (size_t)s.nv);
  posed a = {&s, xa}, b = {&s, xb}, a0 = {&s, xa0}, b0 = {&s, xb0};
  tb_ref_bvh *ra[NKINDS] = {0}, *rb[NKINDS] = {0};
  if (build_all(ra, &a) == 0 && build_all(rb, &b) == 0) {
    /* 1: A deformed within Bullet's quantization range (refit). 2: A
     * inflated to radius about 1.6 and moved, past the range (Bullet
     * rebuilds). 3: B deformed too, A back to rest. */
    for (int step = 1; step <= 3; step++) {
      if (step == 1) deform(&s, 0.12, 1.0, tb_v3(0, 0, 0), xa);
      if (step == 2) deform(&s, 0.12, 1.6, tb_v3(0.5, 0, 0.2), xa);
      if (step == 3) {
        memcpy(xa, s.x, sizeof *xa * (size_t)s.nv);
        for (int i = 0; i < s.nv; i++)
          xb[i] = tb_madd(xb0[i], 0.1, tb_v3(sin(3 * xb0[i].z), 0, cos(2 * xb0[i].x)));
      }
      for (int k = 0; k < NKINDS; k++) {
        TB_CHECK_MSG(tb_ref_bvh_update(ra[k], xa, &err) == 0, "%s", err.msg);
        if (step == 3) TB_CHECK_MSG(tb_ref_bvh_update(rb[k], xb, &err) == 0, "%s", err.msg);
      }
      char label[64];
      snprintf(label, sizeof label, "update step %d", step);
      /* Bullet's quanta are those of its last build: a0 holds A's positions
       * then (the rest shape, then step 2's after the rebuild). */
      if (step == 2) memcpy(xa0, xa, sizeof *xa * (size_t)s.nv);
      check_all(label, ra, rb, &a, &b, &a0, &b0, 1);
    }
  }
  free_all(ra);
  free_all(rb);
out:
  free(xa), free(xa0), free(xb), free(xb0);
  tb_mesh_free(&s);
}

/* The thesis scene: the liver's tet faces and the instrument moved along
 * x into it (as measure/collision_scene.c's path), plus two seeded random poses. */
static void test_liver(void) {
  tb_mesh liver = {0}, inst = {0};
  tb_error err = {""};
  if (generate("liver", TB_PART_FACES, &liver) || generate("instrument", TB_PART_SURFACE, &inst))
    goto out;
  posed a = {&liver, liver.x};
  tb_ref_bvh *ra[NKINDS] = {0};
  tb_rng rng = tb_rng_seed(42);
  if (build_all(ra, &a) == 0) {
    for (int c = 0; c < 4; c++) {
      tb_mat3 R = tb_m3_rotation(tb_v3(0, 1, 0), M_PI / 2 + 0.15);
      tb_vec3 t = tb_v3(7.0 - 3.5 * (c ? 0.6 : 0.48), 0.2, 0.35);
      if (c >= 2) {
        tb_vec3 axis = tb_v3(tb_rng_normal(&rng), tb_rng_normal(&rng), tb_rng_normal(&rng));
        R = tb_m3_rotation(axis, tb_rng_range(&rng, 0, 2 * M_PI));
        t = tb_v3(tb_rng_range(&rng, -3, 3), tb_rng_range(&rng, -1, 1), tb_rng_range(&rng, -1, 1));
      }
      tb_vec3 *xb = moved(&inst, R, t);
      TB_CHECK(xb != NULL);
      if (!xb) break;
      posed b = {&inst, xb};
      tb_ref_bvh *rb[NKINDS] = {0};
      if (build_all(rb, &b) == 0) {
        char label[64];
        snprintf(label, sizeof label, "liver, pose %d", c);
        check_all(label, ra, rb, &a, &b, &a, &b, c == 0);
        if (c < 2) { /* the scripted poses reach into the liver */
          tb_pairlist got = {0};
          TB_CHECK(tb_ref_bvh_collide(ra[3], rb[3], &got, &err) == 0 && got.n > 100);
          pl_free(&got);
        }
      }
      free_all(rb);
      free(xb);
    }
  }
  free_all(ra);
out:
  tb_mesh_free(&liver);
  tb_mesh_free(&inst);
}

/* Two single-triangle meshes crossing: (0, 0) from every kind; a
 * zero-area triangle builds and collides without trouble. */
static void test_small(void) {
  const tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const tb_vec3 y[3] = {{0.25, 0.25, -1}, {0.25, 0.25, 1}, {-1, -1, 0}};
  const tb_vec3 z[3] = {{0.2, 0.2, 0}, {0.2, 0.2, 0}, {0.2, 0.2, 0}}; /* a point on x's face */
  const int tri[3] = {0, 1, 2};
  for (int k = 0; k < NKINDS; k++) {
    tb_error err = {""};
    tb_ref_bvh *a = tb_ref_bvh_build(kinds[k], x, 3, tri, 1, &err);
    tb_ref_bvh *b = tb_ref_bvh_build(kinds[k], y, 3, tri, 1, &err);
    tb_ref_bvh *c = tb_ref_bvh_build(kinds[k], z, 3, tri, 1, &err);
    TB_CHECK_MSG(a && b && c, "%s: %s", kind_names[k], err.msg);
    if (a && b && c) {
      tb_pairlist got = {0};
      TB_CHECK(tb_ref_bvh_collide(a, b, &got, &err) == 0);
      TB_CHECK_MSG(got.n == 1 && got.ij[0] == 0 && got.ij[1] == 0, "%s: %d pairs", kind_names[k],
                   got.n);
      got.n = 0;
      TB_CHECK(tb_ref_bvh_collide(a, c, &got, &err) == 0);
      /* exact answer 1; Bullet's plane of a zero-area triangle is NaN: 0 */
      if (kinds[k] == TB_REF_BULLET_GIMPACT_EXACT) TB_CHECK(got.n == 1);
      if (kinds[k] == TB_REF_BULLET_GIMPACT) TB_CHECK(got.n == 0);
      pl_free(&got);
    }
    tb_ref_bvh_free(a), tb_ref_bvh_free(b), tb_ref_bvh_free(c);
  }
}

static void expect_error(const char *what, int failed, const tb_error *err, const char *text) {
  TB_CHECK_MSG(failed, "%s: no error", what);
  TB_CHECK_MSG(strstr(err->msg, text) != NULL, "%s: message \"%s\" lacks \"%s\"", what, err->msg,
               text);
}

static void test_errors(void) {
  const tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  tb_vec3 bad[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  bad[1].y = NAN;
  const int tri[3] = {0, 1, 2}, far[3] = {0, 1, 3}, neg[3] = {0, -1, 2};
  for (int k = 0; k < NKINDS; k++) {
    tb_error err = {""};
    tb_ref_bvh *m = tb_ref_bvh_build(kinds[k], x, 3, tri, 0, &err);
    expect_error("no triangles", m == NULL, &err, "no triangles");
    m = tb_ref_bvh_build(kinds[k], NULL, 0, tri, 1, &err);
    expect_error("no vertices", m == NULL, &err, "no vertices");
    m = tb_ref_bvh_build(kinds[k], x, 3, far, 1, &err);
    expect_error("index 3", m == NULL, &err, "outside 0..2");
    m = tb_ref_bvh_build(kinds[k], x, 3, neg, 1, &err);
    expect_error("index -1", m == NULL, &err, "outside 0..2");
    m = tb_ref_bvh_build(kinds[k], bad, 3, tri, 1, &err);
    expect_error("NaN vertex", m == NULL, &err, "vertex 1 is not finite");
    TB_CHECK_MSG(strstr(err.msg, kind_names[k]) == err.msg, "message names the kind: %s", err.msg);

    m = tb_ref_bvh_build(kinds[k], x, 3, tri, 1, &err);
    tb_ref_bvh *other = tb_ref_bvh_build(kinds[(k + 1) % NKINDS], x, 3, tri, 1, &err);
    TB_CHECK(m && other);
    if (m && other) {
      tb_pairlist got = {0};
      expect_error("kind mismatch", tb_ref_bvh_collide(m, other, &got, &err) != 0, &err,
                   "cannot collide");
      expect_error("update NaN", tb_ref_bvh_update(m, bad, &err) != 0, &err, "not finite");
      expect_error("update NULL", tb_ref_bvh_update(m, NULL, &err) != 0, &err, "no vertices");
      /* the model is unchanged and still answers */
      TB_CHECK(tb_ref_bvh_collide(m, m, &got, &err) == 0 && got.n == 1);
      expect_error("no list", tb_ref_bvh_collide(m, m, NULL, &err) != 0, &err, "no pair list");
      pl_free(&got);
    }
    tb_ref_bvh_free(m), tb_ref_bvh_free(other);
  }
  tb_error err = {""};
  tb_ref_bvh *m = tb_ref_bvh_build((tb_ref_kind)99, x, 3, tri, 1, &err);
  expect_error("unknown kind", m == NULL, &err, "unknown reference kind 99");
  tb_ref_bvh_free(NULL);
}

const tb_test_case tb_tests_refbvh[] = {{"small", test_small},
                                        {"errors", test_errors},
                                        {"scaled", test_scaled},
                                        {"spheres", test_spheres},
                                        {"update", test_update},
                                        {"liver", test_liver},
                                        {0, 0}};
