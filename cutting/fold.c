/* The scalpel's folded plane (折平面): construction, nearest point, sphere,
 * segment and side tests. Source: the metaball hybrid cutting patent, step 3
 * (1) (see tb_fold.h for the definition and the exactness statement); the
 * segment test is decided with the exact orientation predicates of
 * tb_predicates.h (Shewchuk 1997). */
#include "tb_fold.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collision/tb_predicates.h"

#define PARALLEL_SIN 1e-9

int tb_fold_init(tb_fold *f, const tb_vec3 *p, int count, tb_vec3 depth, tb_error *err) {
  static const char *who = "tb_fold_init";
  memset(f, 0, sizeof *f);
  if (count < 2)
    return tb_error_set(err, who, 0, "the path needs at least 2 points, got %d", count);
  if (!tb_isfinite3(depth)) return tb_error_set(err, who, 0, "the depth vector is not finite");
  double dl = tb_len(depth);
  if (!(dl > 0.0)) return tb_error_set(err, who, 0, "the depth vector is zero");
  for (int i = 0; i < count; i++)
    if (!tb_isfinite3(p[i])) return tb_error_set(err, who, 0, "path point %d is not finite", i);
  for (int k = 0; k + 1 < count; k++) {
    tb_vec3 e = tb_sub(p[k + 1], p[k]);
    if (e.x == 0.0 && e.y == 0.0 && e.z == 0.0)
      return tb_error_set(err, who, 0, "path points %d and %d coincide", k, k + 1);
    double el = tb_len(e), cl = tb_len(tb_cross(e, depth));
    if (!isfinite(el) || !isfinite(cl)) return tb_error_set(err, who, 0, "segment %d overflows", k);
    if (!(cl > PARALLEL_SIN * el * dl))
      return tb_error_set(err, who, 0,
                          "the depth vector is parallel to segment %d (p%d -> p%d): sine of the "
                          "angle %.3g < %g",
                          k, k, k + 1, cl / (el * dl), PARALLEL_SIN);
  }
  f->p = malloc((size_t)count * sizeof *f->p);
  f->q = malloc((size_t)count * sizeof *f->q);
  f->piece = malloc((size_t)(count - 1) * sizeof *f->piece);
  if (!f->p || !f->q || !f->piece) {
    tb_fold_free(f);
    return tb_error_set(err, who, 0, "out of memory");
  }
  f->count = count;
  f->npieces = count - 1;
  f->depth = depth;
  for (int i = 0; i < count; i++) f->p[i] = p[i], f->q[i] = tb_add(p[i], depth);
  for (int k = 0; k < f->npieces; k++) {
    tb_fold_piece *pc = &f->piece[k];
    pc->e = tb_sub(p[k + 1], p[k]);
    pc->n = tb_normalize(tb_cross(pc->e, depth));
    pc->ee = tb_dot(pc->e, pc->e);
    pc->ed = tb_dot(pc->e, depth);
    pc->dd = tb_dot(depth, depth);
    pc->det = pc->ee * pc->dd - pc->ed * pc->ed;
  }
  return 0;
}

void tb_fold_free(tb_fold *f) {
  free(f->p);
  free(f->q);
  free(f->piece);
  memset(f, 0, sizeof *f);
}

static double clamp01(double v) { return v < 0.0 ? 0.0 : (v > 1.0 ? 1.0 : v); }

/* (s, t) of x's projection on piece k's plane (unclamped). */
static void piece_coords(const tb_fold *f, int k, tb_vec3 x, double *s, double *t) {
  const tb_fold_piece *pc = &f->piece[k];
  tb_vec3 w = tb_sub(x, f->p[k]);
  double be = tb_dot(pc->e, w), bd = tb_dot(f->depth, w);
  *s = (pc->dd * be - pc->ed * bd) / pc->det;
  *t = (pc->ee * bd - pc->ed * be) / pc->det;
}

static tb_vec3 piece_point(const tb_fold *f, int k, double s, double t) {
  return tb_madd(tb_madd(f->p[k], s, f->piece[k].e), t, f->depth);
}

/* The nearest point of piece k to x. */
static void piece_nearest(const tb_fold *f, int k, tb_vec3 x, tb_fold_near *out) {
  const tb_fold_piece *pc = &f->piece[k];
  double s, t;
  piece_coords(f, k, x, &s, &t);
  out->piece = k;
  if (s >= 0.0 && s <= 1.0 && t >= 0.0 && t <= 1.0) {
    out->s = s, out->t = t;
    out->point = piece_point(f, k, s, t);
    out->dist = tb_dist(x, out->point);
    return;
  }
  /* Outside: the nearest point is on one of the four sides. */
  out->dist = INFINITY;
  for (int side = 0; side < 4; side++) {
    int along_e = side < 2; /* sides t = 0, t = 1 run along e; s = 0, s = 1 along D */
    double fixed = (double)(side & 1);
    tb_vec3 o = along_e ? piece_point(f, k, 0.0, fixed) : piece_point(f, k, fixed, 0.0);
    tb_vec3 v = along_e ? pc->e : f->depth;
    double l = clamp01(tb_dot(tb_sub(x, o), v) / (along_e ? pc->ee : pc->dd));
    double ss = along_e ? l : fixed, tt = along_e ? fixed : l;
    tb_vec3 y = piece_point(f, k, ss, tt);
    double d = tb_dist(x, y);
    if (d < out->dist) out->s = ss, out->t = tt, out->point = y, out->dist = d;
  }
}

void tb_fold_nearest(const tb_fold *f, tb_vec3 x, tb_fold_near *out) {
  tb_fold_near cur;
  out->dist = INFINITY;
  out->piece = -1;
  for (int k = 0; k < f->npieces; k++) {
    piece_nearest(f, k, x, &cur);
    if (cur.dist < out->dist) *out = cur;
  }
}

int tb_fold_sphere(const tb_fold *f, tb_vec3 c, double r, tb_fold_near *out) {
  tb_fold_near tmp;
  if (!out) out = &tmp;
  tb_fold_nearest(f, c, out);
  return out->dist <= r;
}

int tb_fold_side(const tb_fold *f, tb_vec3 x) {
  tb_fold_near nr;
  tb_fold_nearest(f, x, &nr);
  int k = nr.piece;
  tb_vec3 m = f->piece[k].n;
  if (nr.s == 0.0 && k > 0) m = tb_add(m, f->piece[k - 1].n);
  if (nr.s == 1.0 && k + 1 < f->npieces) m = tb_add(m, f->piece[k + 1].n);
  double v = tb_dot(tb_sub(x, nr.point), m);
  return (v > 0.0) - (v < 0.0);
}

/* ---- exact segment test ---- */

static int sgn3(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d) { return tb_orient3d(a, b, c, d); }

/* 2-D (dropping axis ax): point x in the closed triangle abc (nondegenerate). */
static void drop(tb_vec3 v, int ax, double *x, double *y) {
  *x = ax == 0 ? v.y : v.x;
  *y = ax == 2 ? v.y : v.z;
}
static int o2(tb_vec3 a, tb_vec3 b, tb_vec3 c, int ax) {
  double v[6];
  drop(a, ax, &v[0], &v[1]), drop(b, ax, &v[2], &v[3]), drop(c, ax, &v[4], &v[5]);
  return tb_orient2d(v[0], v[1], v[2], v[3], v[4], v[5]);
}
static int in_tri2(tb_vec3 x, tb_vec3 a, tb_vec3 b, tb_vec3 c, int ax) {
  int s1 = o2(a, b, x, ax), s2 = o2(b, c, x, ax), s3 = o2(c, a, x, ax);
  return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}
/* c lies in the closed box of segment ab (used once c is collinear with it). */
static int in_box2(tb_vec3 a, tb_vec3 b, tb_vec3 c, int ax) {
  double v[6];
  drop(a, ax, &v[0], &v[1]), drop(b, ax, &v[2], &v[3]), drop(c, ax, &v[4], &v[5]);
  return fmin(v[0], v[2]) <= v[4] && v[4] <= fmax(v[0], v[2]) && fmin(v[1], v[3]) <= v[5] &&
         v[5] <= fmax(v[1], v[3]);
}
static int seg_seg2(tb_vec3 a, tb_vec3 b, tb_vec3 c, tb_vec3 d, int ax) {
  int s1 = o2(a, b, c, ax), s2 = o2(a, b, d, ax), s3 = o2(c, d, a, ax), s4 = o2(c, d, b, ax);
  if (s1 * s2 < 0 && s3 * s4 < 0) return 1;
  return (s1 == 0 && in_box2(a, b, c, ax)) || (s2 == 0 && in_box2(a, b, d, ax)) ||
         (s3 == 0 && in_box2(c, d, a, ax)) || (s4 == 0 && in_box2(c, d, b, ax));
}

/* Closed segment ab against closed triangle ABC, exact. *coplanar is set when
 * both endpoints lie in the triangle's plane. */
static int seg_tri(tb_vec3 a, tb_vec3 b, tb_vec3 A, tb_vec3 B, tb_vec3 C, int *coplanar) {
  int sa = sgn3(A, B, C, a), sb = sgn3(A, B, C, b);
  *coplanar = 0;
  if (sa == sb && sa != 0) return 0;
  if (sa == 0 && sb == 0) {
    *coplanar = 1;
    tb_vec3 n = tb_cross(tb_sub(B, A), tb_sub(C, A));
    double nx = fabs(n.x), ny = fabs(n.y), nz = fabs(n.z);
    int ax = nx >= ny && nx >= nz ? 0 : (ny >= nz ? 1 : 2);
    return in_tri2(a, A, B, C, ax) || in_tri2(b, A, B, C, ax) || seg_seg2(a, b, A, B, ax) ||
           seg_seg2(a, b, B, C, ax) || seg_seg2(a, b, C, A, ax);
  }
  int s1 = sgn3(a, b, A, B), s2 = sgn3(a, b, B, C), s3 = sgn3(a, b, C, A);
  return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

/* First parameter u of segment ab inside piece k, given that they meet. */
static double first_u(const tb_fold *f, int k, tb_vec3 a, tb_vec3 b, int coplanar) {
  if (!coplanar) {
    tb_vec3 n = f->piece[k].n;
    double da = tb_dot(n, tb_sub(a, f->p[k])), db = tb_dot(n, tb_sub(b, f->p[k]));
    return da == db ? 0.0 : clamp01(da / (da - db));
  }
  /* In the plane: clip u in [0, 1] against s, t in [0, 1] (Liang-Barsky). */
  double s0, t0, s1, t1, lo = 0.0, hi = 1.0;
  piece_coords(f, k, a, &s0, &t0);
  piece_coords(f, k, b, &s1, &t1);
  double v0[2] = {s0, t0}, dv[2] = {s1 - s0, t1 - t0};
  for (int i = 0; i < 2; i++) {
    if (dv[i] == 0.0) continue;
    double ua = (0.0 - v0[i]) / dv[i], ub = (1.0 - v0[i]) / dv[i];
    lo = fmax(lo, fmin(ua, ub));
    hi = fmin(hi, fmax(ua, ub));
  }
  return lo <= hi ? lo : clamp01(hi); /* rounding can cross them on a touch */
}

int tb_fold_segment(const tb_fold *f, tb_vec3 a, tb_vec3 b, tb_fold_hit *hit) {
  int found = 0;
  double best = INFINITY;
  for (int k = 0; k < f->npieces; k++) {
    tb_vec3 p0 = f->p[k], p1 = f->p[k + 1], q0 = f->q[k], q1 = f->q[k + 1];
    int cop1, cop2;
    int h1 = seg_tri(a, b, p0, p1, q1, &cop1);
    int h2 = !h1 || hit ? seg_tri(a, b, p0, q1, q0, &cop2) : 0;
    if (!h1 && !h2) continue;
    if (!hit) return 1;
    double u = first_u(f, k, a, b, (h1 && cop1) || (h2 && cop2));
    if (!found || u < best) {
      best = u;
      hit->piece = k;
      hit->u = u;
      hit->point = tb_lerp(a, b, u);
      piece_coords(f, k, hit->point, &hit->s, &hit->t);
      hit->s = clamp01(hit->s), hit->t = clamp01(hit->t);
    }
    found = 1;
  }
  return found;
}
