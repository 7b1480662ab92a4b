/* The pieces of a closed surface and which piece holds a point
 * (tb_cut_surface.h): pieces are the components of the triangles through
 * shared vertices; a point's piece is decided by exact ray parity per piece
 * (cutting/cut_topology.c's cut_ray), the ray along +z tested only against
 * the triangles binned on the cell of a uniform (x, y) grid the point falls
 * in (a triangle the ray crosses covers the point in (x, y), so it is
 * binned there), the rays along +x and +y against all triangles when that
 * one grazes an edge. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cut_priv.h"

int tb_cut_piece_of(int nv, int ntri, const int *tri, int *of_tri) {
  int *p = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
  int *id = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
  if (!p || !id) return free(p), free(id), -1;
  for (int v = 0; v < nv; v++) p[v] = v, id[v] = -1;
  for (int t = 0; t < ntri; t++)
    cut_uf_join(p, tri[3 * t], tri[3 * t + 1]), cut_uf_join(p, tri[3 * t], tri[3 * t + 2]);
  int n = 0;
  for (int t = 0; t < ntri; t++) {
    int r = cut_uf_find(p, tri[3 * t]);
    if (id[r] < 0) id[r] = n++;
    of_tri[t] = id[r];
  }
  free(p), free(id);
  return n;
}

typedef struct bins {
  double x0, y0, cell;
  int gx, gy, *start, *list;
} bins;

static int bin_of(const bins *b, double v, double lo, int g) {
  int k = (int)floor((v - lo) / b->cell);
  return k < 0 ? 0 : (k >= g ? g - 1 : k);
}

/* Each triangle in the cells its (x, y) box meets (CSR). */
static int bins_build(bins *b, const tb_vec3 *x, int ntri, const int *tri) {
  double x1 = -INFINITY, y1 = -INFINITY;
  b->x0 = b->y0 = INFINITY;
  for (int i = 0; i < 3 * ntri; i++) {
    tb_vec3 p = x[tri[i]];
    b->x0 = fmin(b->x0, p.x), b->y0 = fmin(b->y0, p.y), x1 = fmax(x1, p.x), y1 = fmax(y1, p.y);
  }
  double side = fmax(fmax(x1 - b->x0, y1 - b->y0), 1e-300);
  int g = (int)ceil(sqrt(ntri / 2.0));
  g = g < 1 ? 1 : (g > 1024 ? 1024 : g);
  b->cell = side / g;
  b->gx = (int)fmin(ceil((x1 - b->x0) / b->cell), 1024) + 1;
  b->gy = (int)fmin(ceil((y1 - b->y0) / b->cell), 1024) + 1;
  size_t nc = (size_t)b->gx * b->gy;
  b->start = calloc(nc + 1, sizeof(int));
  if (!b->start) return -1;
  for (int pass = 0; pass < 2; pass++) {
    for (int t = 0; t < ntri; t++) {
      tb_vec3 A = x[tri[3 * t]], B = x[tri[3 * t + 1]], C = x[tri[3 * t + 2]];
      int i0 = bin_of(b, fmin(fmin(A.x, B.x), C.x), b->x0, b->gx);
      int i1 = bin_of(b, fmax(fmax(A.x, B.x), C.x), b->x0, b->gx);
      int j0 = bin_of(b, fmin(fmin(A.y, B.y), C.y), b->y0, b->gy);
      int j1 = bin_of(b, fmax(fmax(A.y, B.y), C.y), b->y0, b->gy);
      for (int j = j0; j <= j1; j++)
        for (int i = i0; i <= i1; i++) {
          size_t c = (size_t)j * b->gx + i;
          if (pass == 0)
            b->start[c + 1]++;
          else
            b->list[b->start[c]++] = t;
        }
    }
    if (pass == 0) {
      for (size_t c = 0; c < nc; c++) b->start[c + 1] += b->start[c];
      if (!(b->list = malloc(sizeof(int) * (size_t)(b->start[nc] > 0 ? b->start[nc] : 1))))
        return -1;
    } else {
      for (size_t c = nc; c > 0; c--) b->start[c] = b->start[c - 1];
      b->start[0] = 0;
    }
  }
  return 0;
}

/* Point q's piece: the lowest with odd parity, -1 none, -2 undecided. */
static int locate_one(const tb_vec3 *x, int ntri, const int *tri, const int *of_tri,
                      unsigned char *odd, int npieces, const bins *b, tb_vec3 q) {
  for (int r = 0; r < 3; r++) {
    memset(odd, 0, (size_t)npieces);
    int grazed = 0, from = 0, to = ntri;
    const int *list = NULL;
    if (r == 0) {
      int i = (int)floor((q.x - b->x0) / b->cell), j = (int)floor((q.y - b->y0) / b->cell);
      if (i < 0 || j < 0 || i >= b->gx || j >= b->gy) return -1; /* no triangle above or below */
      size_t c = (size_t)j * b->gx + i;
      list = b->list, from = b->start[c], to = b->start[c + 1];
    }
    for (int k = from; k < to && !grazed; k++) {
      int t = list ? list[k] : k;
      int h = cut_ray(x[tri[3 * t]], x[tri[3 * t + 1]], x[tri[3 * t + 2]], q, r);
      if (h == -2) return -2;
      grazed = h == -1;
      if (h == 1) odd[of_tri[t]] ^= 1;
    }
    if (grazed) continue;
    for (int p = 0; p < npieces; p++)
      if (odd[p]) return p;
    return -1;
  }
  return -2;
}

int tb_cut_locate(const tb_vec3 *x, int ntri, const int *tri, const int *of_tri, int npieces,
                  int nq, const tb_vec3 *q, int *out) {
  bins b = {0, 0, 0, 0, 0, NULL, NULL};
  unsigned char *odd = malloc((size_t)(npieces > 0 ? npieces : 1));
  if (!odd || ntri < 1 || bins_build(&b, x, ntri, tri)) {
    free(odd), free(b.start), free(b.list);
    if (ntri < 1 && odd) {
      for (int k = 0; k < nq; k++) out[k] = -1;
      return 0;
    }
    return -1;
  }
  for (int k = 0; k < nq; k++) out[k] = locate_one(x, ntri, tri, of_tri, odd, npieces, &b, q[k]);
  free(odd), free(b.start), free(b.list);
  return 0;
}
