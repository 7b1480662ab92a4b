/* Moving and deforming hierarchies (thesis §4.3.3 parts 3 and 5).
 *
 * Rigid motion: the rotated-AABB update (the thesis's method (3), after
 * Ericson 2005 §4.2.6): the box of the rotated rest box has centre R c + t
 * and half extents |R| h (|R| elementwise), always computed from the rest
 * box -- never from an already rotated one, which would grow without
 * bound. Spheres move with their centres and keep their radii (R must be a
 * rotation). Both are widened by 16 ulps of the coordinate magnitudes
 * sum_j |R_ij| (|c_j| + h_j) + |t_i|, which covers the rounding of this
 * update and of any ordinary evaluation of R x + t by the caller, so the
 * moved volumes contain the moved triangles and queries stay exact. A
 * motion that takes a volume beyond +-1e150 (where the tests' squares
 * could overflow) gives that node a volume that meets everything, so the
 * query falls back to testing its triangles.
 *
 * Deformation: bottom-up refit (part 5). Leaf boxes are recomputed from
 * the vertices; an inner node whose children both kept their boxes keeps
 * its own; otherwise its new box B' is the union of its children's boxes.
 * With B the stored box, the thesis replaces B by B' when
 *   ||Min' - Min||_2 + ||Max' - Max||_2 > delta
 * and otherwise keeps B. Kept as is, B could miss the moved geometry (the
 * thesis accepts the lost accuracy); here a kept box is grown to B u B',
 * which holds the geometry, is never farther than B from B' in the measure
 * above (so every stored box stays within delta of the exact one), and
 * equals B whenever B already contains B' -- the thesis's "no update". With
 * delta = 0 every box is exact. A node's sphere is recomputed from its box
 * when the box changed, or when it no longer contains it (after a rigid
 * motion the moved sphere is tighter than the moved box).
 *
 * Threads (tb_threads.h): whole subtrees per task, then the nodes above
 * them (see tb_bvh_refit below): the same volumes for any thread count. */
#include <float.h>
#ifdef __SSE2__
#include <emmintrin.h>
#endif
#include <stdlib.h>
#include <string.h>

#include "tb_bvh.h"
#include "core/tb_mesh.h"
#include "core/tb_threads.h"

/* Volumes moved beyond +-BV_SAFE (far past TB_COORD_MAX) become volumes
 * that meet everything: up to it, squared distances and radius sums of
 * the tests (bvh_query.c) stay finite (3 (2e150)^2 << DBL_MAX). */
#define BV_SAFE 1e150

void tb_bvh_transform(tb_bvh *b, tb_mat3 R, tb_vec3 t) {
  if (!b || b->nnodes == 0) return;
  double A[3][3], T[3] = {t.x, t.y, t.z};
  int finite = tb_isfinite3(t);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) A[i][j] = fabs(R.m[i][j]), finite &= isfinite(R.m[i][j]) != 0;
  const double slack = 16.0 * DBL_EPSILON;
  for (int k = 0; k < b->nnodes; k++) {
    if (!finite) { /* no finite motion: volumes that meet everything */
      b->box[k].lo = tb_v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
      b->box[k].hi = tb_v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
      b->sph[k].c = tb_v3(0, 0, 0), b->sph[k].r = HUGE_VAL;
      continue;
    }
    tb_aabb a = b->box0[k];
    double c[3] = {0.5 * (a.lo.x + a.hi.x), 0.5 * (a.lo.y + a.hi.y), 0.5 * (a.lo.z + a.hi.z)};
    double h[3] = {0.5 * (a.hi.x - a.lo.x), 0.5 * (a.hi.y - a.lo.y), 0.5 * (a.hi.z - a.lo.z)};
    tb_sphere s = b->sph0[k];
    double sc[3] = {s.c.x, s.c.y, s.c.z}, lo[3], hi[3], nc[3], se = 0.0;
    for (int i = 0; i < 3; i++) {
      double cc = T[i], hh = 0.0, e = fabs(T[i]), sm = T[i];
      for (int j = 0; j < 3; j++) {
        cc += R.m[i][j] * c[j];
        hh += A[i][j] * h[j];
        e += A[i][j] * (fabs(c[j]) + h[j]);
        sm += R.m[i][j] * sc[j];
        se += A[i][j] * (fabs(sc[j]) + s.r);
      }
      se += fabs(T[i]);
      hh += slack * e;
      lo[i] = cc - hh, hi[i] = cc + hh, nc[i] = sm;
    }
    double r = s.r + slack * se;
    int far = !(r <= BV_SAFE);
    for (int i = 0; i < 3; i++)
      far |= !((fabs(lo[i]) <= BV_SAFE) & (fabs(hi[i]) <= BV_SAFE) & (fabs(nc[i]) <= BV_SAFE));
    if (far) { /* moved beyond what the tests can square: meets everything */
      b->box[k].lo = tb_v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
      b->box[k].hi = tb_v3(HUGE_VAL, HUGE_VAL, HUGE_VAL);
      b->sph[k].c = tb_v3(0, 0, 0), b->sph[k].r = HUGE_VAL;
      continue;
    }
    b->box[k].lo = tb_v3(lo[0], lo[1], lo[2]), b->box[k].hi = tb_v3(hi[0], hi[1], hi[2]);
    b->sph[k].c = tb_v3(nc[0], nc[1], nc[2]);
    b->sph[k].r = r;
  }
}

/* Farthest corner of box from the sphere's centre within its radius? */
static int sphere_holds_box(tb_sphere s, tb_aabb b) {
  double dx = fmax(fabs(b.lo.x - s.c.x), fabs(b.hi.x - s.c.x));
  double dy = fmax(fabs(b.lo.y - s.c.y), fabs(b.hi.y - s.c.y));
  double dz = fmax(fabs(b.lo.z - s.c.z), fabs(b.hi.z - s.c.z));
  return dx * dx + dy * dy + dz * dz <= s.r * s.r * (1.0 - 1e-13);
}

static int same_box(tb_aabb a, tb_aabb b) {
  return a.lo.x == b.lo.x && a.lo.y == b.lo.y && a.lo.z == b.lo.z && a.hi.x == b.hi.x &&
         a.hi.y == b.hi.y && a.hi.z == b.hi.z;
}

#define CHANGED 0x80 /* scratch bit in kind[] during a refit */
/* Refits of hierarchies with fewer nodes (and finiteness checks of fewer
 * vertex references) stay on the calling thread: starting the threads
 * costs more than such a refit. */
#define REFIT_PAR_MIN 16384

/* Plain comparisons: fmin/fmax are library calls here (NaN rules). */
static inline tb_vec3 vmin(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z);
}
static inline tb_vec3 vmax(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z);
}

/* 1 when a vertex referenced by ref[0..n) is not finite or lies beyond
 * TB_COORD_MAX (tb_coord_ok, core/tb_mesh.h), else 0. "Not |v| <= max" also
 * catches NaN. With SSE2 the three coordinates are compared two and one at a
 * time and the results or-ed into a register, converted once at the end:
 * about 0.45 ns per reference against 0.65 ns for the finiteness test alone
 * (v * 0 != 0) it replaces and 0.9 ns for scalar comparisons (liver faces,
 * 29k references, gcc 12 -O2). */
static int refs_bad(const tb_vec3 *x, const int *ref, int n) {
#ifdef __SSE2__
  const __m128d absmask = _mm_castsi128_pd(_mm_set1_epi64x(0x7fffffffffffffffLL));
  const __m128d lim = _mm_set1_pd(TB_COORD_MAX);
  __m128d acc = _mm_setzero_pd();
  for (int k = 0; k < n; k++) {
    const double *p = &x[ref[k]].x;
    __m128d xy = _mm_and_pd(_mm_loadu_pd(p), absmask), z = _mm_and_pd(_mm_load_sd(p + 2), absmask);
    acc = _mm_or_pd(acc, _mm_or_pd(_mm_cmpnle_pd(xy, lim), _mm_cmpnle_sd(z, lim)));
  }
  return _mm_movemask_pd(acc) != 0;
#else
  int bad = 0;
  for (int k = 0; k < n; k++) bad |= !tb_coord_ok(x[ref[k]]);
  return bad;
#endif
}

/* References per task of the parallel check. */
#define CHECK_CHUNK 4096

/* Node k's new volumes from the vertices (a leaf) or its children (refit
 * before it); returns 1 when a volume changed. */
#ifdef __GNUC__
__attribute__((always_inline)) /* its loop is the whole refit */
#endif
static inline int
refit_node(tb_bvh *b, const tb_vec3 *x, double delta, int k) {
  int c = b->child[k];
  tb_aabb nb, old = b->box[k];
  if (c < 0) {
    const int *ord = b->tri_index + b->first[k], *tri = b->tri;
    nb.lo = nb.hi = x[tri[3 * ord[0]]];
    for (int m = 0; m < b->count[k]; m++) {
      const int *f = tri + 3 * ord[m];
      tb_vec3 p = x[f[0]], q = x[f[1]], r = x[f[2]];
      nb.lo = vmin(nb.lo, vmin(p, vmin(q, r))), nb.hi = vmax(nb.hi, vmax(p, vmax(q, r)));
    }
  } else if ((b->kind[c] | b->kind[c + 1]) & CHANGED) {
    nb.lo = vmin(b->box[c].lo, b->box[c + 1].lo);
    nb.hi = vmax(b->box[c].hi, b->box[c + 1].hi);
  } else {
    nb = old;
  }
  if (!same_box(nb, old) && delta > 0) {
    double d = tb_dist(nb.lo, old.lo) + tb_dist(nb.hi, old.hi);
    if (!(d > delta)) nb.lo = vmin(nb.lo, old.lo), nb.hi = vmax(nb.hi, old.hi);
  }
  if (!same_box(nb, old)) {
    b->box[k] = nb;
    b->sph[k] = tb_aabb_sphere(nb);
    b->kind[k] |= CHANGED;
    return 1;
  }
  if (!sphere_holds_box(b->sph[k], nb)) {
    b->sph[k] = tb_aabb_sphere(nb);
    return 1;
  }
  return 0;
}

/* Fixed tasks for the threads, whatever their count: the top of the tree
 * is cut breadth first into at least TASKS subtrees (or all leaves above);
 * a task refits its subtree's descendants from the last back (children
 * come after their parent), then its root; the nodes above the cut follow
 * on the calling thread. A node reads only its children and writes only
 * itself, so the volumes are those of the serial refit; the change count
 * is an integer sum. */
#define TASKS 64
enum { TASK_CAP = 4 * TASKS };

/* The cut: roots of the tasks in cut[] (returns how many) and the nodes
 * above it in top[] (*ntop). */
static int cut_tree(const tb_bvh *b, int *cut, int *top, int *ntop) {
  int n = 1, m = 0;
  cut[0] = 0, *ntop = 0;
  while (n < TASKS) {
    int next[TASK_CAP], k2 = 0, grew = 0;
    for (int k = 0; k < n; k++) {
      int c = b->child[cut[k]];
      if (c < 0) {
        next[k2++] = cut[k];
        continue;
      }
      top[m++] = cut[k];
      next[k2++] = c, next[k2++] = c + 1, grew = 1;
    }
    memcpy(cut, next, (size_t)k2 * sizeof *cut);
    n = k2;
    if (!grew) break;
  }
  *ntop = m;
  return n;
}

int tb_bvh_refit(tb_bvh *b, const tb_vec3 *x, double delta) {
  if (!b || b->nnodes == 0) return 0;
  if (!x) return -1;
  if (!(delta > 0)) delta = 0; /* negative or NaN: exact */
  int nchanged = 0;
  if (b->nnodes < REFIT_PAR_MIN || tb_threads() == 1) {
    if (refs_bad(x, b->tri, 3 * b->ntri)) return -1;
    /* children come after their parent: the same volumes, in memory order */
    for (int k = b->nnodes - 1; k >= 0; k--) nchanged += refit_node(b, x, delta, k);
  } else { /* one parallel region: the coordinate check, then the tasks */
    int cut[TASK_CAP], top[TASK_CAP], ntop, n = cut_tree(b, cut, top, &ntop), bad = 0;
    const int nref = 3 * b->ntri, nchunk = (nref + CHECK_CHUNK - 1) / CHECK_CHUNK;
#pragma omp parallel
    {
#pragma omp for schedule(static) reduction(+ : bad)
      for (int c = 0; c < nchunk; c++) {
        int k0 = c * CHECK_CHUNK, k1 = k0 + CHECK_CHUNK < nref ? k0 + CHECK_CHUNK : nref;
        bad += refs_bad(x, b->tri + k0, k1 - k0);
      }
      if (!bad) { /* the reduced count, the same on every thread */
#pragma omp for schedule(dynamic, 1) reduction(+ : nchanged)
        for (int t = 0; t < n; t++) {
          int r = cut[t], c = b->child[r];
          if (c >= 0)
            for (int k = b->sub_end[r] - 1; k >= c; k--) nchanged += refit_node(b, x, delta, k);
          nchanged += refit_node(b, x, delta, r);
        }
      }
    }
    if (bad) return -1;
    for (int k = ntop - 1; k >= 0; k--) nchanged += refit_node(b, x, delta, top[k]);
  }
  for (int k = 0; k < b->nnodes; k++) b->kind[k] &= (unsigned char)~CHANGED;
  memcpy(b->box0, b->box, (size_t)b->nnodes * sizeof *b->box);
  memcpy(b->sph0, b->sph, (size_t)b->nnodes * sizeof *b->sph);
  return nchanged;
}
