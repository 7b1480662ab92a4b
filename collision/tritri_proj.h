/* Private to tritri_yuhe.c and tritri_improved.c: the computing frame both
 * projection tests build on triangle A (thesis §4.4.2 part 1, fig. 4.13,
 * eqs. 4-3..4-7), B's vertices transformed into it, and the small planar
 * helpers both use: overlap of two collinear segments (§4.4.2 3.(1),
 * fig. 4.15) and point in triangle by edge sides (§4.4.2 3.(4), fig. 4.18).
 *
 * Frame: origin P1; x* = unit(P1P2); z* = unit(P1P2 x P1P0); y* =
 * unit(z* x x*). Eq. 4-6 writes the transform as a row vector times T·R with
 * R's rows n1, n2, n3; read literally that product would give the inverse
 * rotation, so we take the evident intent, x* = (v - P1)·n1, y* = (v - P1)·n2,
 * z* = (v - P1)·n3, the only reading under which A lies in H as the thesis
 * states. A's own coordinates are set from the statement "A_H = A; A_V and
 * A_W lie on the y* and x* axes": P1 = (0,0,0), P2 = (|P1P2|,0,0), P0 =
 * (P1P0·n1, P1P0·n2, 0), so A is counter-clockwise in H (P0 has y* >= 0).
 * A zero-area A gives zero axes (tb_normalize leaves a zero vector alone):
 * no division by zero, just a wrong frame, as the thesis has no such case. */
#ifndef TB_TRITRI_PROJ_H
#define TB_TRITRI_PROJ_H

#include "core/tb_math.h"

typedef struct tb_proj {
  /* A in H, vertex order P0, P1, P2: ax = {x*P0, 0, |P1P2|}, ay = {y*P0, 0, 0}. */
  double ax[3], ay[3];
  /* A_V = [0, ay[0]] on the y* axis; A_W = [wlo, whi] on the x* axis. */
  double wlo, whi;
  /* B's vertices Q0, Q1, Q2 in the frame. */
  double x[3], y[3], z[3];
} tb_proj;

static inline void tb_proj_frame(const tb_vec3 p[3], const tb_vec3 q[3], tb_proj *f) {
  tb_vec3 e = tb_sub(p[2], p[1]), w = tb_sub(p[0], p[1]);
  tb_vec3 n1 = tb_normalize(e);                /* (1) */
  tb_vec3 n3 = tb_normalize(tb_cross(e, w));   /* (2) */
  tb_vec3 n2 = tb_normalize(tb_cross(n3, n1)); /* (3) */
  f->ax[0] = tb_dot(w, n1), f->ay[0] = tb_dot(w, n2);
  f->ax[1] = 0.0, f->ay[1] = 0.0;
  f->ax[2] = tb_dot(e, n1), f->ay[2] = 0.0;
  f->wlo = fmin(0.0, f->ax[0]);
  f->whi = fmax(f->ax[2], f->ax[0]);
  for (int i = 0; i < 3; i++) {
    tb_vec3 d = tb_sub(q[i], p[1]);
    f->x[i] = tb_dot(d, n1), f->y[i] = tb_dot(d, n2), f->z[i] = tb_dot(d, n3);
  }
}

/* Fig. 4.15: closed collinear segments [a0, a1] and [b0, b1] (each given in
 * either order) overlap unless one ends before the other starts. */
static inline int tb_proj_overlap(double a0, double a1, double b0, double b1) {
  double alo = fmin(a0, a1), ahi = fmax(a0, a1);
  double blo = fmin(b0, b1), bhi = fmax(b0, b1);
  return !(ahi < blo || bhi < alo);
}

/* Fig. 4.18: translate so (px, py) is the origin; the point is in the closed
 * triangle (tx, ty) when it lies on the same side (or on) every edge, left
 * or right, so either orientation of the triangle works. */
static inline int tb_proj_point_in_tri(double px, double py, const double tx[3],
                                       const double ty[3]) {
  double ux0 = tx[0] - px, uy0 = ty[0] - py;
  double ux1 = tx[1] - px, uy1 = ty[1] - py;
  double ux2 = tx[2] - px, uy2 = ty[2] - py;
  double s0 = ux0 * uy1 - ux1 * uy0;
  double s1 = ux1 * uy2 - ux2 * uy1;
  double s2 = ux2 * uy0 - ux0 * uy2;
  int neg = s0 < 0.0 || s1 < 0.0 || s2 < 0.0;
  int pos = s0 > 0.0 || s1 > 0.0 || s2 > 0.0;
  return !(neg && pos);
}

#endif
