/* Mesh-mesh queries: every intersecting triangle pair of two meshes, by
 * simultaneous descent of their hierarchies (thesis §4.3.2, fig. 4.4), and
 * by brute force.
 *
 * Descent: a stack of node pairs (no recursion, no depth limit). A popped
 * pair's volumes are tested by the rule of fig. 4.4 on the two nodes' layer
 * kinds: both carry a sphere (top/top, top/middle, middle/middle) ->
 * sphere-sphere; else both carry a box (middle/bottom, bottom/bottom) ->
 * AABB-AABB; else (top/bottom) the top node's sphere against the other's
 * box. With box_check (the "composite" default, tb_bvh.h) a pair must
 * also pass box against box, tested first. Why: the sphere of a box has
 * half its diagonal for radius, so for a long thin part (SOFA's dental
 * instrument, 0.4 x 0.04 x 7.1) the top spheres are many times its
 * thickness and meet the liver's spheres whenever the instrument is
 * anywhere near: on SOFA's liver-smooth against dental_instrument,
 * separated by 0.5-1 along x, the thesis's rule alone took 83-109 node
 * tests per query where the boxes need 11 (0.30-0.39 us against FCL
 * OBBRSS's 0.08-0.09 us). The layers, their kinds and each pair's fig. 4.4
 * test are unchanged -- the composite is still the thesis's Sphere /
 * Sphere+AABB / AABB hierarchy; every node already keeps its box up to
 * date (build, refit and the rotated-AABB update compute both), so the
 * extra test is a second bound on the same node and only rejects pairs
 * whose triangles cannot meet.
 * An overlapping pair descends the node that is not a leaf, or when both
 * are inner nodes the larger one (sphere radius, A on a tie). Two
 * overlapping leaves: each leaf's triangles whose boxes miss the other
 * leaf's box are dropped, then every remaining pair whose triangle boxes
 * overlap goes to the triangle test.
 * Each triangle belongs to one leaf, so every pair is met at most once: the
 * output has no duplicates. Counters: bv_tests counts node volume tests,
 * tri_tests calls of the triangle test (triangle box checks are not
 * counted). Large queries run on threads (below: the same output). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "tb_bvh.h"
#include "core/tb_threads.h"

/* ---- pair lists ---- */
void tb_pairlist_free(tb_pairlist *p) {
  if (!p) return;
  free(p->ij);
  p->ij = NULL, p->n = p->cap = 0;
}

int tb_pairlist_push(tb_pairlist *p, int i, int j) {
  if (p->n == p->cap) {
    if (p->cap > (1 << 28)) return -1;
    int cap = p->cap ? 2 * p->cap : 256;
    int *ij = realloc(p->ij, (size_t)cap * 2 * sizeof *ij);
    if (!ij) return -1;
    p->ij = ij, p->cap = cap;
  }
  p->ij[2 * p->n] = i, p->ij[2 * p->n + 1] = j;
  p->n++;
  return 0;
}

static int cmp_pair(const void *x, const void *y) {
  const int *a = x, *b = y;
  if (a[0] != b[0]) return (a[0] > b[0]) - (a[0] < b[0]);
  return (a[1] > b[1]) - (a[1] < b[1]);
}

void tb_pairlist_sort_unique(tb_pairlist *p) {
  if (!p || p->n < 2) return;
  qsort(p->ij, (size_t)p->n, 2 * sizeof *p->ij, cmp_pair);
  int m = 1;
  for (int k = 1; k < p->n; k++)
    if (p->ij[2 * k] != p->ij[2 * m - 2] || p->ij[2 * k + 1] != p->ij[2 * m - 1])
      p->ij[2 * m] = p->ij[2 * k], p->ij[2 * m + 1] = p->ij[2 * k + 1], m++;
  p->n = m;
}

/* ---- the descent ---- */
/* The volume tests of bv.c, inlined here (plain comparisons, no fmin). */
/* Bitwise and: no branch per comparison (they mispredict in leaf loops). */
static inline int box_box(const tb_aabb *a, const tb_aabb *b) {
  return (a->lo.x <= b->hi.x) & (b->lo.x <= a->hi.x) & (a->lo.y <= b->hi.y) & (b->lo.y <= a->hi.y) &
         (a->lo.z <= b->hi.z) & (b->lo.z <= a->hi.z);
}
static inline int sph_sph(const tb_sphere *a, const tb_sphere *b) {
  double dx = a->c.x - b->c.x, dy = a->c.y - b->c.y, dz = a->c.z - b->c.z, r = a->r + b->r;
  return dx * dx + dy * dy + dz * dz <= r * r;
}
static inline double excess(double v, double lo, double hi) {
  return v < lo ? lo - v : (v > hi ? v - hi : 0.0);
}
static inline int sph_box(const tb_sphere *s, const tb_aabb *b) {
  double dx = excess(s->c.x, b->lo.x, b->hi.x), dy = excess(s->c.y, b->lo.y, b->hi.y);
  double dz = excess(s->c.z, b->lo.z, b->hi.z);
  return dx * dx + dy * dy + dz * dz <= s->r * s->r;
}
static inline double min3(double a, double b, double c) {
  double m = a < b ? a : b;
  return m < c ? m : c;
}
static inline double max3(double a, double b, double c) {
  double m = a > b ? a : b;
  return m > c ? m : c;
}

/* The test of fig. 4.4 for the two nodes' layer kinds; with check (box_check,
 * tb_bvh.h) the two boxes must meet too. The box test goes first: on a near
 * miss it is the one that rejects, and the conjunction does not depend on
 * the order. */
#ifdef __GNUC__
#define HOT inline __attribute__((always_inline)) /* a call per node pair costs ~1 ns */
#define COLD __attribute__((noinline))            /* its arrays stay off a small query's frame */
#else
#define HOT inline
#define COLD
#endif
static HOT int overlap(const tb_bvh *A, int i, const tb_bvh *B, int j, int check) {
  unsigned ka = A->kind[i], kb = B->kind[j];
  if (check && !box_box(A->box + i, B->box + j)) return 0;
  if (ka & kb & TB_BV_SPHERE) return sph_sph(A->sph + i, B->sph + j);
  if (ka & kb & TB_BV_AABB) return check || box_box(A->box + i, B->box + j);
  if (ka & TB_BV_SPHERE) return sph_box(A->sph + i, B->box + j);
  return sph_box(B->sph + j, A->box + i);
}

/* A leaf's triangles gathered in chunks of up to CHUNK: numbers, vertices,
 * boxes. The descent meets one leaf with many leaves of the other
 * hierarchy in a row, so the last gathered chunk of each side is kept. */
#define CHUNK 32
typedef struct gathered {
  int node, k0, n; /* the chunk held: node's triangles ord[k0..k0+n) */
  int id[CHUNK];
  tb_vec3 v[3 * CHUNK];
  tb_aabb box[CHUNK];
} gathered;

static void gather(gathered *g, const tb_vec3 *x, const int *tri, const int *ord, int node, int k0,
                   int k1) {
  if (g->node == node && g->k0 == k0) return;
  g->node = node, g->k0 = k0, g->n = k1 - k0;
  for (int k = k0; k < k1; k++) {
    int t = ord[k], u = k - k0;
    tb_vec3 p = x[tri[3 * t]], q = x[tri[3 * t + 1]], r = x[tri[3 * t + 2]];
    g->box[u].lo = tb_v3(min3(p.x, q.x, r.x), min3(p.y, q.y, r.y), min3(p.z, q.z, r.z));
    g->box[u].hi = tb_v3(max3(p.x, q.x, r.x), max3(p.y, q.y, r.y), max3(p.z, q.z, r.z));
    g->id[u] = t;
    g->v[3 * u] = p, g->v[3 * u + 1] = q, g->v[3 * u + 2] = r;
  }
}

/* Positions in g of the triangles whose boxes meet `other`; returns how many. */
static int select_meeting(const gathered *g, const tb_aabb *other, unsigned char *sel) {
  int m = 0;
  for (int u = 0; u < g->n; u++) sel[m] = (unsigned char)u, m += box_box(g->box + u, other);
  return m;
}

typedef struct query {
  const tb_bvh *A, *B;
  const tb_vec3 *xa, *xb;
  tb_tritri_fn test;
  tb_pairlist *out;
  long tri_tests;
  gathered ga, gb;
} query;

static int leaf_pair(query *Q, int i, int j) {
  const tb_bvh *A = Q->A, *B = Q->B;
  int a0 = A->first[i], a1 = a0 + A->count[i], b0 = B->first[j], b1 = b0 + B->count[j];
  unsigned char sa[CHUNK], sb[CHUNK];
  for (int ka = a0; ka < a1; ka += CHUNK) {
    gather(&Q->ga, Q->xa, A->tri, A->tri_index, i, ka, ka + CHUNK < a1 ? ka + CHUNK : a1);
    int na = select_meeting(&Q->ga, B->box + j, sa);
    if (!na) continue;
    for (int kb = b0; kb < b1; kb += CHUNK) {
      gather(&Q->gb, Q->xb, B->tri, B->tri_index, j, kb, kb + CHUNK < b1 ? kb + CHUNK : b1);
      int nb = select_meeting(&Q->gb, A->box + i, sb);
      for (int u = 0; u < na; u++)
        for (int v = 0; v < nb; v++) {
          const gathered *ga = &Q->ga, *gb = &Q->gb;
          int pu = sa[u], pv = sb[v];
          if (!box_box(ga->box + pu, gb->box + pv)) continue;
          Q->tri_tests++;
          if (Q->test(ga->v + 3 * pu, gb->v + 3 * pv) &&
              tb_pairlist_push(Q->out, ga->id[pu], gb->id[pv]))
            return -1;
        }
    }
  }
  return 0;
}

/* ---- on threads ---- */
/* The descent is a pre-order walk, so it can be cut: a left-to-right cut
 * of its tree of node pairs (such as the stack of a paused walk, read from
 * the top), each cut pair's walk appends a contiguous run of the serial
 * output, and the runs concatenated in cut order are the serial output,
 * pair for pair. So a query first walks on the calling thread. One still
 * going after BUDGET node tests, with more than one thread set, hands the
 * pairs on its stack to the threads, after growing them breadth first to
 * at least FRONT (each untested pair tested, an overlapping one replaced by
 * its two children pairs in descent order, leaf pairs kept untested); a
 * query that dies near the top (separated or barely touching meshes) never
 * pays for threads. The cut depends on the hierarchies only, never on the
 * thread count, and every pair is still tested once, so the counters are
 * the serial ones too. Fewer than PAR_MIN cut pairs are walked on the
 * calling thread. Each task writes its own run; the runs are copied to the
 * output in cut order. */
#define BUDGET 16384
#define FRONT 64
#define PAR_MIN 16
enum { FRONT_CAP = 4 * FRONT };

/* The pair of nodes to descend first when both overlap: the node that is
 * not a leaf, or of two inner nodes the larger (sphere radius, A on a tie);
 * its two children pairs in (first, second) order. */
static inline void children(const tb_bvh *a, int i, const tb_bvh *b, int j, int *c) {
  int ci = a->child[i], cj = b->child[j];
  if (cj < 0 || (ci >= 0 && a->sph[i].r >= b->sph[j].r))
    c[0] = ci, c[1] = j, c[2] = ci + 1, c[3] = j;
  else
    c[0] = i, c[1] = cj, c[2] = i, c[3] = cj + 1;
}

/* Depth-first descent from the node pair (i0, j0): pairs appended to
 * Q->out, node tests added to *bv. With budget > 0 it stops once it has
 * made that many node tests and its stack holds at most FRONT pairs: the
 * pairs left, in the order they would be popped, go to front (*left of
 * them; 0 when it finished). */
static HOT int descend(query *Q, int i0, int j0, int check, long *bv, long budget, int *front,
                       int *left) {
  const tb_bvh *a = Q->A, *b = Q->B;
  int local[2 * 256], cap = 256, sp = 0, rc = 0;
  int *stack = local;
  long tests = 0, stop = budget > 0 ? budget : LONG_MAX;
  if (left) *left = 0;
  stack[0] = i0, stack[1] = j0, sp = 1;
  while (sp > 0) {
    if (tests >= stop && sp <= FRONT) {
      for (int k = 0; k < sp; k++)
        front[2 * k] = stack[2 * (sp - 1 - k)], front[2 * k + 1] = stack[2 * (sp - 1 - k) + 1];
      *left = sp;
      break;
    }
    sp--;
    int i = stack[2 * sp], j = stack[2 * sp + 1];
    tests++;
    if (!overlap(a, i, b, j, check)) continue;
    if (a->child[i] < 0 && b->child[j] < 0) {
      if ((rc = leaf_pair(Q, i, j))) break;
      continue;
    }
    if (sp + 2 > cap) {
      int *s = malloc((size_t)cap * 4 * sizeof *s);
      if (!s) {
        rc = -1;
        break;
      }
      memcpy(s, stack, (size_t)sp * 2 * sizeof *s);
      if (stack != local) free(stack);
      stack = s, cap *= 2;
    }
    int c[4];
    children(a, i, b, j, c);
    /* the first child pair on top: popped first */
    stack[2 * sp] = c[2], stack[2 * sp + 1] = c[3];
    stack[2 * sp + 2] = c[0], stack[2 * sp + 3] = c[1];
    sp += 2;
  }
  *bv += tests;
  if (stack != local) free(stack);
  return rc;
}

static void query_init(query *Q, const tb_bvh *a, const tb_vec3 *xa, const tb_bvh *b,
                       const tb_vec3 *xb, tb_tritri_fn test, tb_pairlist *out) {
  Q->A = a, Q->B = b, Q->xa = xa, Q->xb = xb, Q->test = test, Q->out = out, Q->tri_tests = 0;
  Q->ga.node = Q->gb.node = -1;
}

/* Grows the front f (n pairs) in place; returns its new size. */
static COLD int grow_front(const tb_bvh *a, const tb_bvh *b, int check, int *f, int n, long *bv) {
  int g[2 * FRONT_CAP];
  while (n > 0 && n < FRONT) {
    int m = 0, grew = 0;
    for (int k = 0; k < n; k++) {
      int i = f[2 * k], j = f[2 * k + 1];
      if (a->child[i] < 0 && b->child[j] < 0) { /* a leaf pair: kept, untested */
        g[2 * m] = i, g[2 * m + 1] = j, m++;
        continue;
      }
      (*bv)++;
      if (!overlap(a, i, b, j, check)) continue;
      children(a, i, b, j, g + 2 * m);
      m += 2, grew = 1;
    }
    memcpy(f, g, (size_t)m * 2 * sizeof *f);
    n = m;
    if (!grew) break;
  }
  return n;
}

/* One thread's pairs: a buffer kept between queries (no allocation once it
 * is large enough); each front pair's run is [start, start + count) in the
 * buffer of the thread that walked it. */
static _Thread_local tb_pairlist thread_pairs;

static COLD int collide_front(query *Q0, int check, const int *f, int n, long *bv) {
  if (n < PAR_MIN) { /* small: the calling thread, straight into out */
    int rc = 0;
    for (int k = 0; k < n && !rc; k++)
      rc = descend(Q0, f[2 * k], f[2 * k + 1], check, bv, 0, NULL, NULL);
    return rc;
  }
  const tb_pairlist *buf[FRONT_CAP];
  int start[FRONT_CAP], count[FRONT_CAP], bad[FRONT_CAP];
  long tests[FRONT_CAP], tris[FRONT_CAP];
#pragma omp parallel
  {
    query Q = *Q0; /* own gather caches and output */
    tb_pairlist *mine = &thread_pairs;
    mine->n = 0, Q.out = mine, Q.ga.node = Q.gb.node = -1;
#pragma omp for schedule(dynamic, 1)
    for (int k = 0; k < n; k++) {
      buf[k] = mine, start[k] = mine->n, tests[k] = 0, Q.tri_tests = 0;
      bad[k] = descend(&Q, f[2 * k], f[2 * k + 1], check, &tests[k], 0, NULL, NULL);
      count[k] = mine->n - start[k], tris[k] = Q.tri_tests;
    }
  }
  int rc = 0;
  for (int k = 0; k < n && !rc; k++) { /* in front order: the serial output */
    const int *ij = buf[k]->ij + 2 * start[k];
    rc = bad[k];
    for (int m = 0; m < count[k] && !rc; m++)
      rc = tb_pairlist_push(Q0->out, ij[2 * m], ij[2 * m + 1]);
    *bv += tests[k], Q0->tri_tests += tris[k];
  }
  return rc;
}

int tb_bvh_collide(const tb_bvh *a, const tb_vec3 *xa, const tb_bvh *b, const tb_vec3 *xb,
                   tb_tritri_fn test, tb_pairlist *out, tb_collide_stats *stats) {
  if (stats) stats->bv_tests = stats->tri_tests = 0;
  if (!a || !b || !test || !out) return -1;
  if (a->nnodes == 0 || b->nnodes == 0) return 0;
  const int check = a->box_check | b->box_check;
  long bv = 0;
  int rc;
  query q; /* about 9 KB: on the stack, no allocation per query */
  query_init(&q, a, xa, b, xb, test, out);
  int f[2 * FRONT_CAP], n = 0;
  rc = descend(&q, 0, 0, check, &bv, BUDGET, f, &n);
  if (!rc && n > 0) {
    if (tb_threads() > 1)
      rc = collide_front(&q, check, f, grow_front(a, b, check, f, n, &bv), &bv);
    else /* on alone: the same walks in the same order */
      for (int k = 0; k < n && !rc; k++)
        rc = descend(&q, f[2 * k], f[2 * k + 1], check, &bv, 0, NULL, NULL);
  }
  if (stats) stats->bv_tests = bv, stats->tri_tests = q.tri_tests;
  return rc;
}

/* ---- brute force ---- */
/* A method that claims exactness never reports triangles whose boxes are
 * disjoint, so for those the box prefilter changes nothing; any other test
 * is called on every pair. */
static int claims_exact(tb_tritri_fn test) {
  int n;
  const tb_tritri_method *m = tb_tritri_methods(&n);
  for (int k = 0; k < n; k++)
    if (m[k].test == test) return m[k].exact;
  return 0;
}

int tb_collide_brute(const tb_vec3 *xa, const int *ta, int na, const tb_vec3 *xb, const int *tb,
                     int nb, tb_tritri_fn test, tb_pairlist *out, tb_collide_stats *stats) {
  if (stats) stats->bv_tests = stats->tri_tests = 0;
  if (!test || !out || na < 0 || nb < 0) return -1;
  if (na == 0 || nb == 0) return 0;
  int filter = claims_exact(test);
  tb_aabb *bb = malloc((size_t)nb * sizeof *bb);
  if (!bb) return -1;
  for (int j = 0; j < nb; j++) {
    tb_vec3 p = xb[tb[3 * j]], q = xb[tb[3 * j + 1]], r = xb[tb[3 * j + 2]];
    bb[j].lo = tb_v3(min3(p.x, q.x, r.x), min3(p.y, q.y, r.y), min3(p.z, q.z, r.z));
    bb[j].hi = tb_v3(max3(p.x, q.x, r.x), max3(p.y, q.y, r.y), max3(p.z, q.z, r.z));
  }
  long tests = 0;
  int rc = 0;
  for (int i = 0; i < na && !rc; i++) {
    tb_vec3 P[3] = {xa[ta[3 * i]], xa[ta[3 * i + 1]], xa[ta[3 * i + 2]]};
    tb_aabb ba;
    ba.lo = tb_v3(min3(P[0].x, P[1].x, P[2].x), min3(P[0].y, P[1].y, P[2].y),
                  min3(P[0].z, P[1].z, P[2].z));
    ba.hi = tb_v3(max3(P[0].x, P[1].x, P[2].x), max3(P[0].y, P[1].y, P[2].y),
                  max3(P[0].z, P[1].z, P[2].z));
    for (int j = 0; j < nb; j++) {
      if (filter && !box_box(&ba, bb + j)) continue;
      tb_vec3 Q[3] = {xb[tb[3 * j]], xb[tb[3 * j + 1]], xb[tb[3 * j + 2]]};
      tests++;
      if (test(P, Q) && tb_pairlist_push(out, i, j)) {
        rc = -1;
        break;
      }
    }
  }
  if (stats) stats->tri_tests = tests;
  free(bb);
  return rc;
}
