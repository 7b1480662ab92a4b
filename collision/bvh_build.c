/* Top-down construction of binary bounding volume hierarchies (thesis
 * §4.3.3 part 4). A node's triangles are split by a plane normal to a
 * coordinate axis (the split axis) through a split point:
 *   axis: longest extent of the triangle centroids (eq. 4-2), largest
 *         variance of the centroids, or smallest sum of the two children's
 *         box volumes (each axis tried with the chosen split point);
 *   point: mean of the centroid projections (a centroid on the point goes to
 *          the side with fewer triangles, the left on a tie) or their median
 *          (on the point: left).
 * Stop rules (the thesis's three principles): a node at max_depth, or with
 * at most max_leaf triangles, or too few to give two children of min_leaf,
 * is a leaf. A split that leaves a side empty (children must shrink) or
 * smaller than min_leaf falls back to cutting the centroids, sorted along
 * the axis, at their middle index. Boxes are exact (min-max of the
 * vertices), each node's sphere circumscribes its box; the layer kind of a
 * node follows its depth. Children are allocated in pairs (child, child+1).
 * Vertices must be finite and within TB_COORD_MAX (core/tb_mesh.h), else
 * the build is refused: beyond it squared distances of the sphere tests
 * could overflow (1e200 gave no pairs at all).
 * Everything is deterministic: ties go to the lower axis and, in sorts, to
 * the lower triangle number. */
#include <stdlib.h>
#include <string.h>

#include "tb_bvh.h"
#include "core/tb_mesh.h"

tb_bvh_def tb_bvh_default_def(void) {
  tb_bvh_def d;
  d.axis = TB_SPLIT_LONGEST;
  d.point = TB_SPLIT_MEDIAN;
  d.max_depth = 40;
  d.min_leaf = 1;
  d.max_leaf = 10;
  d.sphere_layers = 0;
  d.both_layers = 0;
  d.box_check = 0;
  return d;
}

/* Deeper than any hierarchy can be: every node is a Sphere. */
#define ALL_LAYERS (1 << 20)

tb_bvh_def tb_bvh_kind_def(const char *kind) {
  tb_bvh_def d = tb_bvh_default_def();
  if (kind && !strcmp(kind, "aabb")) return d;
  if (kind && !strcmp(kind, "sphere")) {
    d.sphere_layers = ALL_LAYERS;
    return d;
  }
  if (kind && !strcmp(kind, "composite")) {
    d.sphere_layers = 3, d.both_layers = 3; /* the thesis's liver: 3/3/5 */
    d.box_check = 1;
    return d;
  }
  memset(&d, 0, sizeof d);
  return d;
}

void tb_bvh_free(tb_bvh *b) {
  if (!b) return;
  free(b->box), free(b->sph), free(b->child), free(b->first), free(b->count);
  free(b->kind), free(b->tri_index), free(b->box0), free(b->sph0);
  free(b->sub_end);
  memset(b, 0, sizeof *b);
}

/* ---- build state ---- */
typedef struct keyed { /* a triangle and its projection */
  double k;
  int t;
} keyed;
typedef struct builder {
  const tb_bvh_def *def;
  tb_vec3 *cen;  /* triangle centroids */
  tb_aabb *tbox; /* triangle boxes */
  double *key;   /* scratch: projections of a range */
  int *tmp;      /* scratch: a partitioned range */
  int *ord;      /* tri_index of the hierarchy */
  keyed *kt;     /* scratch: a range sorted along an axis */
} builder;

/* Plain comparisons: fmin/fmax are library calls here (NaN rules); the
 * input is checked finite. */
static tb_vec3 vmin(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x < b.x ? a.x : b.x, a.y < b.y ? a.y : b.y, a.z < b.z ? a.z : b.z);
}
static tb_vec3 vmax(tb_vec3 a, tb_vec3 b) {
  return tb_v3(a.x > b.x ? a.x : b.x, a.y > b.y ? a.y : b.y, a.z > b.z ? a.z : b.z);
}
static tb_aabb box_union(tb_aabb a, tb_aabb b) {
  tb_aabb r;
  r.lo = vmin(a.lo, b.lo), r.hi = vmax(a.hi, b.hi);
  return r;
}
static double box_volume(tb_aabb a) {
  return (a.hi.x - a.lo.x) * (a.hi.y - a.lo.y) * (a.hi.z - a.lo.z);
}
static tb_aabb range_box(const builder *B, int first, int n) {
  tb_aabb r = B->tbox[B->ord[first]];
  for (int k = 1; k < n; k++) r = box_union(r, B->tbox[B->ord[first + k]]);
  return r;
}

/* The k-th smallest of a[0..n) (a is reordered): Hoare's selection with a
 * median-of-three pivot, deterministic. */
static double select_kth(double *a, int n, int k) {
  int lo = 0, hi = n - 1;
  while (hi > lo) {
    double x = a[lo], y = a[lo + (hi - lo) / 2], z = a[hi];
    double pivot = x < y ? (y < z ? y : (x < z ? z : x)) : (x < z ? x : (y < z ? z : y));
    int i = lo, j = hi;
    while (i <= j) {
      while (a[i] < pivot) i++;
      while (a[j] > pivot) j--;
      if (i <= j) {
        double t = a[i];
        a[i++] = a[j], a[j--] = t;
      }
    }
    if (k <= j)
      hi = j;
    else if (k >= i)
      lo = i;
    else
      return a[k]; /* between the two parts: equal to the pivot */
  }
  return a[k];
}

/* The split axis for the centroids of ord[first..first+n). */
static int axis_by_spread(const builder *B, int first, int n, tb_split_axis how) {
  double lo[3], hi[3], s[3] = {0, 0, 0}, s2[3] = {0, 0, 0};
  for (int a = 0; a < 3; a++) lo[a] = hi[a] = tb_comp(B->cen[B->ord[first]], a);
  for (int k = 0; k < n; k++) {
    tb_vec3 c = B->cen[B->ord[first + k]];
    for (int a = 0; a < 3; a++) {
      double v = tb_comp(c, a);
      if (v < lo[a]) lo[a] = v;
      if (v > hi[a]) hi[a] = v;
      s[a] += v;
    }
  }
  double score[3];
  for (int a = 0; a < 3; a++) score[a] = hi[a] - lo[a];
  if (how == TB_SPLIT_VARIANCE) {
    for (int k = 0; k < n; k++)
      for (int a = 0; a < 3; a++) {
        double d = tb_comp(B->cen[B->ord[first + k]], a) - s[a] / n;
        s2[a] += d * d;
      }
    for (int a = 0; a < 3; a++) score[a] = s2[a];
  }
  int best = 0;
  for (int a = 1; a < 3; a++)
    if (score[a] > score[best]) best = a;
  return best;
}

/* The split point along axis a: centroids with projection < *s go left,
 * > *s right, == *s left when *on_left. */
static void split_point(const builder *B, int first, int n, int a, double *s, int *on_left) {
  double *key = B->key;
  for (int k = 0; k < n; k++) key[k] = tb_comp(B->cen[B->ord[first + k]], a);
  if (B->def->point == TB_SPLIT_MEDIAN) {
    *s = select_kth(key, n, (n - 1) / 2);
    *on_left = 1;
    return;
  }
  double sum = 0.0;
  for (int k = 0; k < n; k++) sum += key[k];
  double m = sum / n;
  int L = 0, R = 0;
  for (int k = 0; k < n; k++) L += key[k]<m, R += key[k]> m;
  *s = m;
  *on_left = L <= R;
}

static int goes_left(double v, double s, int on_left) { return v < s || (v == s && on_left); }

/* Number of triangles the split puts on the left; with boxes != NULL also
 * the two children's boxes (meaningful when both sides are non-empty). */
static int count_left(const builder *B, int first, int n, int a, double s, int on_left,
                      tb_aabb *boxes) {
  int nl = 0;
  if (boxes) /* empty boxes: every union replaces them */
    for (int c = 0; c < 2; c++)
      boxes[c].lo = tb_v3(HUGE_VAL, HUGE_VAL, HUGE_VAL),
      boxes[c].hi = tb_v3(-HUGE_VAL, -HUGE_VAL, -HUGE_VAL);
  for (int k = 0; k < n; k++) {
    int t = B->ord[first + k], left = goes_left(tb_comp(B->cen[t], a), s, on_left);
    if (boxes) boxes[!left] = box_union(boxes[!left], B->tbox[t]);
    nl += left;
  }
  return nl;
}

static int valid_split(int nl, int n, int min_leaf) {
  return nl >= min_leaf && n - nl >= min_leaf && nl > 0 && nl < n;
}

/* Stable partition of the range by the split; returns the left count. */
static int partition(builder *B, int first, int n, int a, double s, int on_left) {
  int nl = 0, nr = 0, *o = B->ord + first;
  for (int k = 0; k < n; k++)
    if (goes_left(tb_comp(B->cen[o[k]], a), s, on_left))
      o[nl++] = o[k];
    else
      B->tmp[nr++] = o[k];
  memcpy(o + nl, B->tmp, (size_t)nr * sizeof *o);
  return nl;
}

/* Fallback: sort the range by (projection on a, triangle number), cut at
 * the middle. */
static int cmp_keyed(const void *x, const void *y) {
  const keyed *u = x, *v = y;
  if (u->k != v->k) return u->k < v->k ? -1 : 1;
  return (u->t > v->t) - (u->t < v->t);
}
static int split_middle(builder *B, int first, int n, int a) {
  for (int k = 0; k < n; k++)
    B->kt[k].t = B->ord[first + k], B->kt[k].k = tb_comp(B->cen[B->kt[k].t], a);
  qsort(B->kt, (size_t)n, sizeof *B->kt, cmp_keyed);
  for (int k = 0; k < n; k++) B->ord[first + k] = B->kt[k].t;
  return n / 2;
}

/* Splits ord[first..first+n) in place; returns the left count. */
static int split(builder *B, int first, int n) {
  const tb_bvh_def *d = B->def;
  int a;
  double s;
  int on_left;
  if (d->axis == TB_SPLIT_MIN_VOLUME) {
    double best = HUGE_VAL;
    a = -1;
    for (int k = 0; k < 3; k++) {
      tb_aabb ch[2];
      split_point(B, first, n, k, &s, &on_left);
      int nl = count_left(B, first, n, k, s, on_left, ch);
      if (!valid_split(nl, n, d->min_leaf)) continue;
      double v = box_volume(ch[0]) + box_volume(ch[1]);
      if (a < 0 || v < best) best = v, a = k;
    }
    if (a < 0) return split_middle(B, first, n, axis_by_spread(B, first, n, TB_SPLIT_LONGEST));
  } else {
    a = axis_by_spread(B, first, n, d->axis);
  }
  split_point(B, first, n, a, &s, &on_left);
  int nl = count_left(B, first, n, a, s, on_left, NULL);
  if (!valid_split(nl, n, d->min_leaf)) return split_middle(B, first, n, a);
  return partition(B, first, n, a, s, on_left);
}

static unsigned char layer_kind(const tb_bvh_def *d, int depth) {
  if (depth < d->sphere_layers) return TB_BV_SPHERE;
  if ((long)depth < (long)d->sphere_layers + d->both_layers) return TB_BV_SPHERE | TB_BV_AABB;
  return TB_BV_AABB;
}

static int check_def(const tb_bvh_def *d, tb_error *err) {
  if (!d) return tb_error_set(err, "bvh", 0, "no definition");
  if (d->axis != TB_SPLIT_LONGEST && d->axis != TB_SPLIT_VARIANCE && d->axis != TB_SPLIT_MIN_VOLUME)
    return tb_error_set(err, "bvh", 0, "unknown split axis %d", (int)d->axis);
  if (d->point != TB_SPLIT_MEAN && d->point != TB_SPLIT_MEDIAN)
    return tb_error_set(err, "bvh", 0, "unknown split point %d", (int)d->point);
  if (d->max_depth < 0 || d->max_depth > 1000)
    return tb_error_set(err, "bvh", 0, "max_depth must be in [0, 1000], not %d", d->max_depth);
  if (d->min_leaf < 1 || d->max_leaf < 1)
    return tb_error_set(err, "bvh", 0, "min_leaf (%d) and max_leaf (%d) must be at least 1",
                        d->min_leaf, d->max_leaf);
  if (d->sphere_layers < 0 || d->both_layers < 0)
    return tb_error_set(err, "bvh", 0, "layer depths must not be negative (%d, %d)",
                        d->sphere_layers, d->both_layers);
  if (d->box_check != 0 && d->box_check != 1)
    return tb_error_set(err, "bvh", 0, "box_check must be 0 or 1, not %d", d->box_check);
  return 0;
}

static int alloc_all(tb_bvh *b, builder *B, int ntri) {
  size_t m = (size_t)(2 * ntri - 1), n = (size_t)ntri;
  b->box = malloc(m * sizeof *b->box), b->sph = malloc(m * sizeof *b->sph);
  b->box0 = malloc(m * sizeof *b->box0), b->sph0 = malloc(m * sizeof *b->sph0);
  b->child = malloc(m * sizeof(int)), b->first = malloc(m * sizeof(int));
  b->count = malloc(m * sizeof(int)), b->kind = malloc(m);
  b->tri_index = malloc(n * sizeof(int));
  B->cen = malloc(n * sizeof *B->cen), B->tbox = malloc(n * sizeof *B->tbox);
  B->key = malloc(n * sizeof *B->key), B->tmp = malloc(n * sizeof(int));
  B->kt = malloc(n * sizeof *B->kt);
  return b->box && b->sph && b->box0 && b->sph0 && b->child && b->first && b->count && b->kind &&
         b->tri_index && B->cen && B->tbox && B->key && B->tmp && B->kt;
}

/* sub_end: children come after their parent, so one pass from the last
 * node back gives each node's end from its children's. */
static int subtree_ends(tb_bvh *b) {
  b->sub_end = malloc((size_t)b->nnodes * sizeof(int));
  if (!b->sub_end) return -1;
  for (int k = b->nnodes - 1; k >= 0; k--) {
    int c = b->child[k], e = k + 1;
    if (c >= 0) e = b->sub_end[c] > b->sub_end[c + 1] ? b->sub_end[c] : b->sub_end[c + 1];
    b->sub_end[k] = e;
  }
  return 0;
}

int tb_bvh_build(tb_bvh *b, const tb_vec3 *x, const int *tri, int ntri, const tb_bvh_def *def,
                 tb_error *err) {
  if (!b) return tb_error_set(err, "bvh", 0, "no hierarchy to build");
  memset(b, 0, sizeof *b);
  if (check_def(def, err)) return -1;
  if (ntri < 0 || ntri > (1 << 29))
    return tb_error_set(err, "bvh", 0, "triangle count %d out of range", ntri);
  if (ntri > 0 && (!x || !tri)) return tb_error_set(err, "bvh", 0, "no vertices or triangles");
  b->tri = tri, b->ntri = ntri, b->box_check = def->box_check;
  if (ntri == 0) return 0;
  builder B = {def, NULL, NULL, NULL, NULL, NULL, NULL};
  int rc = 0;
  int(*stack)[2] = NULL;
  if (!alloc_all(b, &B, ntri) ||
      !(stack = malloc((size_t)(def->max_depth + 2) * 2 * sizeof *stack))) {
    rc = tb_error_set(err, "bvh", 0, "out of memory for %d triangles", ntri);
    goto done;
  }
  B.ord = b->tri_index;
  for (int t = 0; t < ntri; t++) {
    const int *v = tri + 3 * t;
    if (v[0] < 0 || v[1] < 0 || v[2] < 0) {
      rc = tb_error_set(err, "bvh", 0, "triangle %d has a negative vertex index", t);
      goto done;
    }
    tb_vec3 p = x[v[0]], q = x[v[1]], r = x[v[2]];
    if (!tb_isfinite3(p) || !tb_isfinite3(q) || !tb_isfinite3(r)) {
      rc = tb_error_set(err, "bvh", 0, "triangle %d has a non-finite vertex", t);
      goto done;
    }
    for (int k = 0; k < 3; k++)
      if (!tb_coord_ok(x[v[k]])) {
        tb_vec3 w = x[v[k]];
        rc = tb_error_set(err, "bvh", 0,
                          "triangle %d: vertex %d at (%.17g, %.17g, %.17g) is beyond the "
                          "coordinate bound +-%g",
                          t, v[k], w.x, w.y, w.z, TB_COORD_MAX);
        goto done;
      }
    B.tbox[t].lo = vmin(p, vmin(q, r)), B.tbox[t].hi = vmax(p, vmax(q, r));
    B.cen[t] = tb_v3((p.x + q.x + r.x) / 3.0, (p.y + q.y + r.y) / 3.0, (p.z + q.z + r.z) / 3.0);
    b->tri_index[t] = t;
  }
  /* depth-first: the stack holds (node, depth); a split pushes two */
  int top = 0;
  b->nnodes = 1, b->first[0] = 0, b->count[0] = ntri;
  stack[top][0] = 0, stack[top][1] = 0, top++;
  while (top > 0) {
    top--;
    int i = stack[top][0], depth = stack[top][1], first = b->first[i], n = b->count[i];
    b->box[i] = range_box(&B, first, n);
    b->sph[i] = tb_aabb_sphere(b->box[i]);
    b->kind[i] = layer_kind(def, depth);
    b->child[i] = -1;
    if (depth > b->depth) b->depth = depth;
    if (depth >= def->max_depth || n <= def->max_leaf || n < 2L * def->min_leaf) continue;
    int nl = split(&B, first, n), c = b->nnodes;
    b->nnodes += 2;
    b->child[i] = c;
    b->first[c] = first, b->count[c] = nl;
    b->first[c + 1] = first + nl, b->count[c + 1] = n - nl;
    stack[top][0] = c + 1, stack[top][1] = depth + 1, top++;
    stack[top][0] = c, stack[top][1] = depth + 1, top++;
  }
  memcpy(b->box0, b->box, (size_t)b->nnodes * sizeof *b->box);
  memcpy(b->sph0, b->sph, (size_t)b->nnodes * sizeof *b->sph);
  if (subtree_ends(b)) rc = tb_error_set(err, "bvh", 0, "out of memory for %d triangles", ntri);
done:
  free(stack), free(B.cen), free(B.tbox), free(B.key), free(B.tmp), free(B.kt);
  if (rc) tb_bvh_free(b);
  return rc;
}
