/* Yu & He 2013 ("Testing the intersection status of two triangles",
 * 图学学报 / Journal of Graphics, 2013 no. 4) as the thesis describes the
 * original in §4.4.2 part 2 (fig. 4.14):
 * "the original algorithm uses only the V and H projections" and, when the V
 * projection is not case (a) or (b) of fig. 4.14, "computes the intersection
 * points of the three edges of B_V with the y* axis and branches on their
 * number". Steps:
 *   1. computing frame on A, B transformed into it (eqs. 4-3..4-7,
 *      tritri_proj.h);
 *   2. case (a), all z* of B zero: B_V and A_V are segments on the y* axis,
 *      rejected when they do not overlap (fig. 4.15), else the coplanar test
 *      in H; case (b), all z* of one sign: separated;
 *   3. otherwise each edge QiQj of B_V is tested against the y* axis: a
 *      vertex with z* == 0 is a crossing (counted at the edge it starts),
 *      an edge with zi*zj < 0 crosses at Qj + t(Qi - Qj), t = |zj|/(|zi|+|zj|)
 *      (eq. 4-9 and fig. 4.19; the same t gives the 3D point Q_L or Q_R);
 *   4. one crossing: Q_L = Q_R, a point: rejected unless Q_LV lies on A_V,
 *      then point in A_H (fig. 4.18); two crossings: L_B = Q_L Q_R, rejected
 *      unless L_BV overlaps A_V, then L_B against A_H; none: separated.
 * No W-plane rejection: that is the thesis's improvement (tritri_improved.c).
 * The thesis does not say how the original clips L_B by A in H (only that
 * Sun's clipping, used by the improved test, "is simpler and handles every
 * clipping case"); we use parametric clipping of the segment against A's
 * three closed edge half-planes (Cyrus-Beck), the textbook way to clip a
 * segment by a convex polygon. Coplanar triangles in H (case a): any edge of
 * B meeting A, else a vertex of A inside B (fig. 4.17).
 * Plain doubles and exact comparisons with 0 as in the thesis's text: no
 * epsilon, so touching and coplanar input is decided by rounding. */
#include "tb_tritri.h"
#include "tritri_proj.h"

/* Segment (lx,ly)-(rx,ry) against the closed counter-clockwise triangle A in
 * H: keep the parameter range [t0, t1] inside every edge's half-plane. */
static int segment_in_a(const tb_proj *f, double lx, double ly, double rx, double ry) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; i++) {
    int j = i == 2 ? 0 : i + 1;
    double ex = f->ax[j] - f->ax[i], ey = f->ay[j] - f->ay[i];
    double fl = ex * (ly - f->ay[i]) - ey * (lx - f->ax[i]);
    double fr = ex * (ry - f->ay[i]) - ey * (rx - f->ax[i]);
    if (fl < 0.0 && fr < 0.0) return 0;
    if (fl < 0.0)
      t0 = fmax(t0, fl / (fl - fr)); /* enters the half-plane */
    else if (fr < 0.0)
      t1 = fmin(t1, fl / (fl - fr)); /* leaves it */
  }
  return t0 <= t1;
}

/* Case (a): A_H and B_H in the same plane. */
static int coplanar(const tb_proj *f) {
  for (int i = 0; i < 3; i++) {
    int j = i == 2 ? 0 : i + 1;
    if (segment_in_a(f, f->x[i], f->y[i], f->x[j], f->y[j])) return 1;
  }
  for (int k = 0; k < 3; k++)
    if (tb_proj_point_in_tri(f->ax[k], f->ay[k], f->x, f->y)) return 1;
  return 0;
}

int tb_tritri_yuhe(const tb_vec3 p[3], const tb_vec3 q[3]) {
  tb_proj f;
  tb_proj_frame(p, q, &f);
  const double *z = f.z;
  int npos = (z[0] > 0.0) + (z[1] > 0.0) + (z[2] > 0.0);
  int nneg = (z[0] < 0.0) + (z[1] < 0.0) + (z[2] < 0.0);
  if (npos == 0 && nneg == 0) { /* (a): B_V on the y* axis */
    double lo = fmin(f.y[0], fmin(f.y[1], f.y[2])), hi = fmax(f.y[0], fmax(f.y[1], f.y[2]));
    if (!tb_proj_overlap(lo, hi, 0.0, f.ay[0])) return 0;
    return coplanar(&f);
  }
  if (npos == 3 || nneg == 3) return 0; /* (b): B_V above or below A_V */

  /* The crossings of B_V's edges with the y* axis. */
  double cx[2], cy[2];
  int n = 0;
  for (int i = 0; i < 3 && n < 2; i++) {
    int j = i == 2 ? 0 : i + 1;
    if (z[i] == 0.0) {
      cx[n] = f.x[i], cy[n] = f.y[i], n++;
    } else if (z[i] * z[j] < 0.0) {
      double t = fabs(z[j]) / (fabs(z[i]) + fabs(z[j]));
      cx[n] = f.x[j] + t * (f.x[i] - f.x[j]), cy[n] = f.y[j] + t * (f.y[i] - f.y[j]), n++;
    }
  }
  if (n == 0) return 0;
  if (n == 1) { /* one crossing: the point Q_L = Q_R */
    if (!tb_proj_overlap(cy[0], cy[0], 0.0, f.ay[0])) return 0;
    return tb_proj_point_in_tri(cx[0], cy[0], f.ax, f.ay);
  }
  if (!tb_proj_overlap(cy[0], cy[1], 0.0, f.ay[0])) return 0; /* L_BV against A_V */
  return segment_in_a(&f, cx[0], cy[0], cx[1], cy[1]);        /* L_B against A_H */
}
