/* Sampling the reference displacement field at rest-space points: a uniform
 * grid over the rest mesh's box lists every tet in the cells its box
 * overlaps; a point takes the tet of its cell that contains it (largest
 * smallest barycentric coordinate, so points on shared faces pick one tet
 * deterministically), or, outside the mesh, the tet nearest to it (exact
 * point-tet distance: the closest point on its four faces, Ericson,
 * Real-Time Collision Detection §5.1.5), whose shape functions are then
 * extrapolated. The field is the element's: sum_a N_a(L) u_a with the
 * 10-node (or 4-node) shape functions of ref_element.c. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ref_priv.h"

#define TB_REF_INSIDE_TOL 1e-10

int tb_ref_grid_build(tb_ref_solution *s, tb_error *err) {
  tb_vec3 lo = s->X[0], hi = s->X[0];
  for (int i = 1; i < s->nv; i++) lo = tb_vmin(lo, s->X[i]), hi = tb_vmax(hi, s->X[i]);
  tb_vec3 ext = tb_sub(hi, lo);
  double big = fmax(ext.x, fmax(ext.y, ext.z));
  /* about one tet per cell, flat boxes clamped to one cell thick */
  double vol = fmax(ext.x, 1e-3 * big) * fmax(ext.y, 1e-3 * big) * fmax(ext.z, 1e-3 * big);
  double h = cbrt(vol / s->ntet);
  if (!(h > 0)) h = 1;
  for (int c = 0; c < 3; c++) {
    double n = ceil(tb_comp(ext, c) / h);
    s->dim[c] = n < 1 ? 1 : (n > 512 ? 512 : (int)n);
  }
  s->lo = lo;
  s->h = h;
  for (int c = 0; c < 3; c++) /* cells cover the box even where 512 clamped */
    s->h = fmax(s->h, tb_comp(ext, c) / s->dim[c]);
  size_t ncell = (size_t)s->dim[0] * s->dim[1] * s->dim[2];
  s->cell_start = calloc(ncell + 1, sizeof(int));
  if (!s->cell_start) return tb_error_set(err, "reference", 0, "out of memory");
  for (int pass = 0; pass < 2; pass++) {
    for (int t = 0; t < s->ntet; t++) {
      const int *e = s->elem + (size_t)t * s->npe;
      tb_vec3 a = s->X[e[0]], b = a;
      for (int k = 1; k < 4; k++) a = tb_vmin(a, s->X[e[k]]), b = tb_vmax(b, s->X[e[k]]);
      int i0[3], i1[3];
      for (int c = 0; c < 3; c++) {
        i0[c] = (int)floor((tb_comp(a, c) - tb_comp(lo, c)) / s->h);
        i1[c] = (int)floor((tb_comp(b, c) - tb_comp(lo, c)) / s->h);
        i0[c] = i0[c] < 0 ? 0 : (i0[c] >= s->dim[c] ? s->dim[c] - 1 : i0[c]);
        i1[c] = i1[c] < 0 ? 0 : (i1[c] >= s->dim[c] ? s->dim[c] - 1 : i1[c]);
      }
      for (int z = i0[2]; z <= i1[2]; z++)
        for (int y = i0[1]; y <= i1[1]; y++)
          for (int x = i0[0]; x <= i1[0]; x++) {
            size_t cell = ((size_t)z * s->dim[1] + y) * s->dim[0] + x;
            if (pass)
              s->cell_tet[s->cell_start[cell]++] = t;
            else
              s->cell_start[cell + 1]++;
          }
    }
    if (!pass) {
      for (size_t c = 0; c < ncell; c++) {
        if (s->cell_start[c + 1] > 0x7fffffff - s->cell_start[c])
          return tb_error_set(err, "reference", 0, "mesh too large for the sampling grid");
        s->cell_start[c + 1] += s->cell_start[c];
      }
      s->cell_tet = malloc(sizeof(int) * ((size_t)s->cell_start[ncell] + 1));
      if (!s->cell_tet) return tb_error_set(err, "reference", 0, "out of memory");
    } else {
      for (size_t c = ncell; c > 0; c--) s->cell_start[c] = s->cell_start[c - 1];
      s->cell_start[0] = 0;
    }
  }
  return 0;
}

static void barycentric(const tb_ref_solution *s, int t, tb_vec3 p, double L[4]) {
  const tb_vec3 *g = s->gl + 4 * (size_t)t;
  tb_vec3 d = tb_sub(p, s->X[s->elem[(size_t)t * s->npe]]);
  L[1] = tb_dot(g[1], d), L[2] = tb_dot(g[2], d), L[3] = tb_dot(g[3], d);
  L[0] = 1 - L[1] - L[2] - L[3];
}

static double tet_distance2(const tb_ref_solution *s, int t, tb_vec3 p) {
  static const int face[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  const int *e = s->elem + (size_t)t * s->npe;
  double best = INFINITY;
  for (int f = 0; f < 4; f++) {
    tb_vec3 q =
        tb_closest_on_triangle(p, s->X[e[face[f][0]]], s->X[e[face[f][1]]], s->X[e[face[f][2]]]);
    tb_vec3 d = tb_sub(p, q);
    best = fmin(best, tb_dot(d, d));
  }
  return best;
}

static int locate(const tb_ref_solution *s, tb_vec3 p, double L[4]) {
  int cell[3];
  for (int c = 0; c < 3; c++) {
    double f = floor((tb_comp(p, c) - tb_comp(s->lo, c)) / s->h);
    cell[c] = f < 0 ? 0 : (f >= s->dim[c] ? s->dim[c] - 1 : (int)f);
  }
  size_t k = ((size_t)cell[2] * s->dim[1] + cell[1]) * s->dim[0] + cell[0];
  int best = -1;
  double best_min = -TB_REF_INSIDE_TOL, Lt[4];
  for (int q = s->cell_start[k]; q < s->cell_start[k + 1]; q++) {
    int t = s->cell_tet[q];
    barycentric(s, t, p, Lt);
    double m = fmin(fmin(Lt[0], Lt[1]), fmin(Lt[2], Lt[3]));
    if (m > best_min || (best < 0 && m >= best_min)) best = t, best_min = m;
  }
  if (best < 0) { /* outside: the nearest tet */
    double d2 = INFINITY;
    for (int t = 0; t < s->ntet; t++) {
      double dt = tet_distance2(s, t, p);
      if (dt < d2) d2 = dt, best = t;
    }
  }
  barycentric(s, best, p, L);
  return best;
}

int tb_ref_sample(const tb_ref_solution *s, const tb_vec3 *points, int n, tb_vec3 *u,
                  tb_error *err) {
  if (!s || n < 0 || (n > 0 && (!points || !u)))
    return tb_error_set(err, "reference", 0, "bad sample request (%d points)", n);
  for (int i = 0; i < n; i++) {
    if (!tb_isfinite3(points[i]))
      return tb_error_set(err, "reference", 0, "sample point %d is not finite", i);
    double L[4], N[10];
    int t = locate(s, points[i], L);
    tb_ref_shape(s->npe, L, N);
    const int *e = s->elem + (size_t)t * s->npe;
    tb_vec3 v = tb_v3(0, 0, 0);
    for (int a = 0; a < s->npe; a++) v = tb_madd(v, N[a], s->u[e[a]]);
    u[i] = v;
  }
  return 0;
}
