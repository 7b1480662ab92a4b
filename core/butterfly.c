/* Modified butterfly subdivision: Zorin, Schröder & Sweldens, "Interpolating Subdivision for
 * Meshes with Arbitrary Topology", SIGGRAPH 1996, as Bao 2006 §3.1 (figures 2 and 3) gives it.
 * The new point of edge (a1, a2):
 * - both ends valence 6 (figure 2, Dyn, Levin & Gregory's 8-point butterfly with tension
 *   w = 1/16): a = 1/2 on a1, a2; b = 1/8 on the two vertices opposite the edge; c = -1/16 on
 *   the four "wing" vertices across the other edges of those two triangles. (Bao prints
 *   c = 1/16 beside the figure; the wings carry -1/16, as in Zorin, and the weights then sum
 *   to 1.)
 * - one end of valence k != 6, the other regular (figure 3): the irregular end's 1-ring only:
 *   3/4 on the irregular vertex and s_j on its ring vertex j, j = 0 at the edge's other end,
 *   counting around: k = 3: 5/12, -1/12, -1/12; k = 4: 3/8, 0, -1/8, 0; k >= 5:
 *   s_j = (1/4 + cos(2 pi j / k) + 1/2 cos(4 pi j / k)) / k. The s_j sum to 1/4.
 * - both ends irregular: the average of the two one-end stencils.
 * A vertex of valence 2 (a closed "pillow": two triangles on the same three vertices) has no
 * rule; tb_butterfly_point takes the edge's midpoint for its end, and tb_butterfly refuses such
 * a surface (its split would put four triangles on an edge). */
#include "tb_butterfly.h"

#include <stdlib.h>
#include <string.h>

static const double tb_pi = 3.14159265358979323846;

/* Weight of ring vertex j of a vertex of valence k (k >= 3). */
static double ring_weight(int k, int j) {
  static const double w3[3] = {5.0 / 12, -1.0 / 12, -1.0 / 12};
  static const double w4[4] = {3.0 / 8, 0.0, -1.0 / 8, 0.0};
  if (k == 3) return w3[j];
  if (k == 4) return w4[j];
  double t = 2.0 * tb_pi * j / k;
  return (0.25 + cos(t) + 0.5 * cos(2.0 * t)) / k;
}

/* The one-end stencil of the start vertex of h, of valence k. */
static tb_vec3 one_end(const tb_halfedge *he, const tb_vec3 *x, int h, int k) {
  int a = he->vert[h];
  if (k < 3) return tb_lerp(x[a], x[he->vert[tb_he_next(h)]], 0.5);
  tb_vec3 p = tb_scale(x[a], 0.75);
  int g = h;
  for (int j = 0; j < k; j++, g = tb_he_rotate(he, g))
    p = tb_madd(p, ring_weight(k, j), x[he->vert[tb_he_next(g)]]);
  return p;
}

/* The vertex across the edge of half-edge g from g's face: the wing. */
static int across(const tb_halfedge *he, int g) { return he->vert[tb_he_prev(he->pair[g])]; }

/* The 8-point butterfly of h's edge (both ends valence 6). */
static tb_vec3 regular(const tb_halfedge *he, const tb_vec3 *x, int h) {
  int r = he->pair[h];
  tb_vec3 a = tb_add(x[he->vert[h]], x[he->vert[r]]);
  tb_vec3 b = tb_add(x[he->vert[tb_he_prev(h)]], x[he->vert[tb_he_prev(r)]]);
  tb_vec3 c = tb_add(tb_add(x[across(he, tb_he_next(h))], x[across(he, tb_he_prev(h))]),
                     tb_add(x[across(he, tb_he_next(r))], x[across(he, tb_he_prev(r))]));
  return tb_add(tb_add(tb_scale(a, 0.5), tb_scale(b, 0.125)), tb_scale(c, -0.0625));
}

tb_vec3 tb_butterfly_point(const tb_halfedge *he, const tb_vec3 *x, int h) {
  int r = he->pair[h];
  int k1 = tb_halfedge_valence(he, he->vert[h]), k2 = tb_halfedge_valence(he, he->vert[r]);
  if (k1 == 6 && k2 == 6) return regular(he, x, h);
  if (k2 == 6) return one_end(he, x, h, k1);
  if (k1 == 6) return one_end(he, x, r, k2);
  return tb_scale(tb_add(one_end(he, x, h, k1), one_end(he, x, r, k2)), 0.5); /* h, r alike */
}

int tb_butterfly(const tb_mesh *in, tb_mesh *out, int **midpoint, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (midpoint) *midpoint = NULL;
  if (in->ntet)
    return tb_error_set(err, "butterfly", 0,
                        "a tet mesh (%d tets): subdivision takes a closed triangle surface",
                        in->ntet);
  tb_halfedge he;
  if (tb_halfedge_build(&he, in->nv, in->ntri, in->tri, "butterfly", err)) return -1;
  int nv = in->nv, nf = in->ntri, nh = 3 * nf, ne = nh / 2;
  for (int v = 0; v < nv; v++)
    if (tb_halfedge_valence(&he, v) < 3) {
      tb_halfedge_free(&he);
      return tb_error_set(err, "butterfly", 0,
                          "vertex %d has valence 2 (two triangles on the same three vertices): "
                          "its split would not be a manifold",
                          v);
    }
  if (nf > (1 << 29) / 4 || nv > (1 << 30) - ne) {
    tb_halfedge_free(&he);
    return tb_error_set(err, "butterfly", 0, "%d triangles: the result would be too large", nf);
  }
  int *mid = malloc(sizeof(int) * (size_t)nh);
  out->x = malloc(sizeof(tb_vec3) * ((size_t)nv + (size_t)ne));
  out->tri = malloc(sizeof(int) * 12 * (size_t)nf);
  if (!mid || !out->x || !out->tri) {
    free(mid), tb_halfedge_free(&he), tb_mesh_free(out);
    return tb_error_set(err, "butterfly", 0, "out of memory");
  }
  memcpy(out->x, in->x, sizeof(tb_vec3) * (size_t)nv);
  int e = 0;
  for (int h = 0; h < nh; h++) {
    if (he.pair[h] < h) continue; /* numbered at its pair, the smaller index */
    mid[h] = mid[he.pair[h]] = nv + e;
    out->x[nv + e] = tb_butterfly_point(&he, in->x, h);
    e++;
  }
  for (int f = 0; f < nf; f++) {
    const int *t = in->tri + 3 * f;
    int ab = mid[3 * f], bc = mid[3 * f + 1], ca = mid[3 * f + 2];
    int c[12] = {t[0], ab, ca, ab, t[1], bc, ca, bc, t[2], ab, bc, ca};
    memcpy(out->tri + 12 * f, c, sizeof c);
  }
  out->nv = nv + ne;
  out->ntri = 4 * nf;
  tb_halfedge_free(&he);
  if (midpoint)
    *midpoint = mid;
  else
    free(mid);
  return 0;
}
