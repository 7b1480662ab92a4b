/* Triangle against the scalpel's folded plane: the cut polyline the patent's
 * surface splitting (表面分裂, step 3 (5), fig. 5) works from. Each piece is
 * clipped by the triangle's plane (corner sides decided exactly with
 * tb_orient3d), the resulting segment clipped to the triangle in barycentric
 * coordinates, and consecutive pieces joined at their crease. A crease point
 * is computed from the crease's own two corners in both pieces, so the joint
 * is the same double in each. */
#include <float.h>
#include <math.h>
#include <string.h>

#include "tb_fold.h"
#include "collision/tb_predicates.h"

#define BARY_SNAP 1e-12

typedef struct qpt {
  tb_vec3 x;
  double s, t;
} qpt;

/* Piece k against the triangle's plane: -1 when the piece lies in it, else
 * the number of points (0, 1 or 2) of the cut segment, ordered by (s, t). */
static int piece_plane_cut(const tb_fold *f, int k, const tb_vec3 T[3], tb_vec3 nT, qpt seg[2]) {
  const tb_vec3 c[4] = {f->p[k], f->p[k + 1], f->q[k + 1], f->q[k]};
  static const double cs[4] = {0, 1, 1, 0}, ct[4] = {0, 0, 1, 1};
  /* Path, crease k+1, crease k, depth; creases run p -> q in both pieces. */
  static const int edge[4][2] = {{0, 1}, {1, 2}, {0, 3}, {3, 2}};
  int sg[4], zeros = 0;
  double dv[4];
  for (int i = 0; i < 4; i++) {
    sg[i] = tb_orient3d(T[0], T[1], T[2], c[i]);
    dv[i] = tb_dot(nT, tb_sub(c[i], T[0]));
    if (sg[i] == 0)
      dv[i] = 0.0, zeros++;
    else if ((dv[i] > 0.0) != (sg[i] > 0))
      dv[i] = sg[i] * DBL_MIN; /* the exact sign wins over the rounded value */
  }
  if (zeros == 4) return -1;
  qpt pts[8];
  int np = 0;
  for (int i = 0; i < 4; i++)
    if (sg[i] == 0) pts[np].x = c[i], pts[np].s = cs[i], pts[np].t = ct[i], np++;
  for (int j = 0; j < 4; j++) {
    int a = edge[j][0], b = edge[j][1];
    if (sg[a] * sg[b] >= 0) continue;
    double l = dv[a] / (dv[a] - dv[b]);
    pts[np].x = tb_lerp(c[a], c[b], l);
    pts[np].s = cs[a] == cs[b] ? cs[a] : cs[a] + l * (cs[b] - cs[a]);
    pts[np].t = ct[a] == ct[b] ? ct[a] : ct[a] + l * (ct[b] - ct[a]);
    np++;
  }
  if (np == 0) return 0;
  int lo = 0, hi = 0;
  for (int i = 1; i < np; i++) {
    if (pts[i].s < pts[lo].s || (pts[i].s == pts[lo].s && pts[i].t < pts[lo].t)) lo = i;
    if (pts[i].s > pts[hi].s || (pts[i].s == pts[hi].s && pts[i].t > pts[hi].t)) hi = i;
  }
  seg[0] = pts[lo], seg[1] = pts[hi];
  return lo == hi ? 1 : 2;
}

static void bary_of(const tb_vec3 T[3], tb_vec3 nT, double nn, tb_vec3 x, double b[3]) {
  for (int i = 0; i < 3; i++) {
    tb_vec3 u = tb_sub(T[(i + 1) % 3], x), v = tb_sub(T[(i + 2) % 3], x);
    b[i] = tb_dot(nT, tb_cross(u, v)) / nn;
  }
}

static void snap(double b[3]) {
  for (int i = 0; i < 3; i++)
    if (fabs(b[i]) < BARY_SNAP) b[i] = 0.0;
}

/* Fills the triangle and fold locations of a point whose x, bary, s, t and
 * piece (k, unconverted) are set. */
static void classify(const tb_fold *f, tb_fold_tpoint *p) {
  int z[3], nz = 0;
  for (int i = 0; i < 3; i++) z[i] = p->bary[i] == 0.0, nz += z[i];
  if (nz == 0)
    p->tri_loc = TB_FOLD_TRI_INTERIOR, p->tri_index = -1;
  else if (nz == 1)
    p->tri_loc = TB_FOLD_TRI_EDGE, p->tri_index = z[0] ? 0 : (z[1] ? 1 : 2);
  else
    p->tri_loc = TB_FOLD_TRI_VERTEX, p->tri_index = !z[0] ? 0 : (!z[1] ? 1 : 2);
  int k = p->piece, loc = 0;
  if (p->s == 0.0) {
    if (k > 0)
      loc |= TB_FOLD_CREASE, p->piece = k - 1, p->s = 1.0;
    else
      loc |= TB_FOLD_START;
  } else if (p->s == 1.0) {
    loc |= k + 1 < f->npieces ? TB_FOLD_CREASE : TB_FOLD_END;
  }
  if (p->t == 0.0) loc |= TB_FOLD_PATH;
  if (p->t == 1.0) loc |= TB_FOLD_DEPTH;
  p->fold_loc = loc;
}

static int same_point(const tb_fold_tpoint *a, const tb_fold_tpoint *b) {
  return a->x.x == b->x.x && a->x.y == b->x.y && a->x.z == b->x.z && a->piece == b->piece;
}

static void push(tb_fold_cut *cut, const tb_fold_tpoint *p, int *open) {
  if (*open && cut->n > 0 && same_point(&cut->pt[cut->n - 1], p)) return;
  if (cut->n >= TB_FOLD_CUT_MAX) {
    cut->truncated = 1;
    return;
  }
  tb_fold_tpoint q = *p;
  if (!*open) cut->npoly++, *open = 1;
  q.polyline = cut->npoly - 1;
  cut->pt[cut->n++] = q;
}

static int collinear(const tb_vec3 T[3]) {
  return !tb_orient2d(T[0].x, T[0].y, T[1].x, T[1].y, T[2].x, T[2].y) &&
         !tb_orient2d(T[0].y, T[0].z, T[1].y, T[1].z, T[2].y, T[2].z) &&
         !tb_orient2d(T[0].z, T[0].x, T[1].z, T[1].x, T[2].z, T[2].x);
}

int tb_fold_triangle(const tb_fold *f, const tb_vec3 tri[3], tb_fold_cut *cut) {
  memset(cut, 0, sizeof *cut);
  if (!tb_isfinite3(tri[0]) || !tb_isfinite3(tri[1]) || !tb_isfinite3(tri[2]) || collinear(tri)) {
    cut->degenerate = 1;
    return 0;
  }
  tb_vec3 nT = tb_cross(tb_sub(tri[1], tri[0]), tb_sub(tri[2], tri[0]));
  double nn = tb_dot(nT, nT);
  int open = 0, prev_coplanar = 0;
  for (int k = 0; k < f->npieces; k++) {
    qpt seg[2];
    int m = piece_plane_cut(f, k, tri, nT, seg);
    int coplanar = m < 0;
    if (coplanar) cut->coplanar++;
    int skip = m <= 0 || (k > 0 && !prev_coplanar && m == 2 && seg[0].s == 0.0 && seg[1].s == 0.0);
    prev_coplanar = coplanar;
    if (skip) {
      open = 0;
      continue;
    }
    if (m == 1) seg[1] = seg[0];
    /* Clip u in [0, 1] along seg to the triangle: bary affine in u. */
    double b0[3], b1[3], u0 = 0.0, u1 = 1.0;
    int e0 = -1, e1 = -1;
    bary_of(tri, nT, nn, seg[0].x, b0);
    bary_of(tri, nT, nn, seg[1].x, b1);
    snap(b0), snap(b1);
    int empty = 0;
    for (int i = 0; i < 3 && !empty; i++) {
      if (b0[i] < 0.0 && b1[i] < 0.0)
        empty = 1;
      else if (b0[i] < 0.0) {
        double u = b0[i] / (b0[i] - b1[i]);
        if (u > u0) u0 = u, e0 = i;
      } else if (b1[i] < 0.0) {
        double u = b0[i] / (b0[i] - b1[i]);
        if (u < u1) u1 = u, e1 = i;
      }
    }
    if (!empty && u0 > u1 && u0 - u1 < 1e-12) u1 = u0; /* a touch at a vertex */
    if (empty || u0 > u1) {
      open = 0;
      continue;
    }
    for (int end = 0; end < 2; end++) {
      double u = end ? u1 : u0;
      int ei = end ? e1 : e0;
      tb_fold_tpoint p;
      memset(&p, 0, sizeof p);
      p.x = tb_lerp(seg[0].x, seg[1].x, u);
      for (int i = 0; i < 3; i++) p.bary[i] = b0[i] + u * (b1[i] - b0[i]);
      if (ei >= 0) p.bary[ei] = 0.0;
      snap(p.bary);
      p.s = seg[0].s + u * (seg[1].s - seg[0].s);
      p.t = seg[0].t + u * (seg[1].t - seg[0].t);
      p.piece = k;
      classify(f, &p);
      /* A piece continues the open polyline only from the shared crease point. */
      if (end == 0 && !(open && cut->n > 0 && same_point(&cut->pt[cut->n - 1], &p))) open = 0;
      push(cut, &p, &open);
    }
    if (u1 < 1.0) open = 0; /* left through the triangle's side */
  }
  return cut->n;
}
