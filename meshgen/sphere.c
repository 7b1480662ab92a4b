/* Geodesic spheres: each face of an icosahedron split into f*f triangles on
 * a barycentric lattice and projected onto the sphere: 10 f^2 + 2 vertices,
 * 20 f^2 triangles. f = 5 and 10 give Bao 2006's 252/500 and 1002/2000. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

/* The icosahedron (0, +-1, +-phi) and cyclic permutations: faces are the
 * triples at mutual distance 2, oriented outward. */
static int icosahedron(tb_vec3 *v, int *faces) {
  const double p = (1.0 + sqrt(5.0)) / 2.0;
  int n = 0, nf = 0;
  for (int axis = 0; axis < 3; axis++)
    for (int s1 = -1; s1 <= 1; s1 += 2)
      for (int s2 = -1; s2 <= 1; s2 += 2) {
        double c[3] = {0, 0, 0};
        c[(axis + 1) % 3] = s1;
        c[(axis + 2) % 3] = s2 * p;
        v[n++] = tb_v3(c[0], c[1], c[2]);
      }
  for (int a = 0; a < 12; a++)
    for (int b = a + 1; b < 12; b++)
      for (int c = b + 1; c < 12; c++) {
        if (fabs(tb_dist(v[a], v[b]) - 2) > 1e-9 || fabs(tb_dist(v[b], v[c]) - 2) > 1e-9 ||
            fabs(tb_dist(v[a], v[c]) - 2) > 1e-9)
          continue;
        tb_vec3 nrm = tb_cross(tb_sub(v[b], v[a]), tb_sub(v[c], v[a]));
        int out = tb_dot(nrm, v[a]) > 0;
        faces[3 * nf] = a, faces[3 * nf + 1] = out ? b : c, faces[3 * nf + 2] = out ? c : b;
        nf++;
      }
  return nf;
}

/* A lattice point is sum(w_i * corner_i) / f; its key lists the (corner,
 * weight) pairs with w > 0 in corner order, so shared edge points match. */
static uint64_t lattice_key(const int *corner, const int *w) {
  int c[3], k[3], n = 0;
  for (int i = 0; i < 3; i++)
    if (w[i] > 0) c[n] = corner[i], k[n] = w[i], n++;
  for (int i = 1; i < n; i++)
    for (int j = i; j > 0 && c[j - 1] > c[j]; j--) {
      int t = c[j], u = k[j];
      c[j] = c[j - 1], k[j] = k[j - 1], c[j - 1] = t, k[j - 1] = u;
    }
  uint64_t key = 0;
  for (int i = 0; i < n; i++) key = (key << 20) | ((uint64_t)c[i] << 16) | (uint64_t)k[i];
  return key;
}

typedef struct lattice {
  uint64_t *keys;
  int *ids;
  int cap;
} lattice;

/* Index of the lattice point, added (and projected) on first sight. */
static int lattice_vertex(lattice *L, tb_mesh *m, const tb_vec3 *ico, const int *corner,
                          const int *w, int f, double radius) {
  uint64_t key = lattice_key(corner, w);
  uint64_t h = (key * 0x9e3779b97f4a7c15ull) >> 20;
  for (int i = (int)(h % (uint64_t)L->cap);; i = (i + 1) % L->cap) {
    if (L->ids[i] < 0) {
      tb_vec3 p = tb_v3(0, 0, 0);
      for (int j = 0; j < 3; j++) p = tb_madd(p, (double)w[j] / f, ico[corner[j]]);
      m->x[m->nv] = tb_scale(tb_normalize(p), radius);
      L->keys[i] = key;
      return L->ids[i] = m->nv++;
    }
    if (L->keys[i] == key) return L->ids[i];
  }
}

int tb_geosphere(int nv, double radius, tb_mesh *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  int f = 1;
  while (10 * f * f + 2 < nv) f++;
  if (nv < 12 || 10 * f * f + 2 != nv || f > 1000)
    return tb_error_set(err, "sphere", 0,
                        "%d vertices: a geodesic sphere has 10 f^2 + 2 (12, 42, 92, ..., 252, "
                        "..., 1002, ...)",
                        nv);
  if (!(radius > 0) || !isfinite(radius))
    return tb_error_set(err, "sphere", 0, "radius must be positive and finite");
  tb_vec3 ico[12];
  int faces[60];
  icosahedron(ico, faces);
  lattice L = {malloc(sizeof(uint64_t) * 4 * (size_t)nv), malloc(sizeof(int) * 4 * (size_t)nv),
               4 * nv};
  out->x = malloc(sizeof(tb_vec3) * (size_t)nv);
  out->tri = malloc(sizeof(int) * 3 * 20 * (size_t)f * f);
  if (!L.keys || !L.ids || !out->x || !out->tri) {
    free(L.keys), free(L.ids), tb_mesh_free(out);
    return tb_error_set(err, "sphere", 0, "out of memory");
  }
  for (int i = 0; i < L.cap; i++) L.ids[i] = -1;
  for (int t = 0; t < 20; t++) {
    const int *c = faces + 3 * t;
    for (int a = 0; a < f; a++)
      for (int b = 0; a + b < f; b++) {
        /* up triangle (a,b) (a+1,b) (a,b+1); down (a+1,b) (a+1,b+1) (a,b+1) */
        int w[4][3] = {{f - a - b, a, b},
                       {f - a - b - 1, a + 1, b},
                       {f - a - b - 1, a, b + 1},
                       {f - a - b - 2, a + 1, b + 1}};
        int id[4];
        for (int k = 0; k < 3; k++) id[k] = lattice_vertex(&L, out, ico, c, w[k], f, radius);
        int *tri = out->tri + 3 * out->ntri;
        tri[0] = id[0], tri[1] = id[1], tri[2] = id[2];
        out->ntri++;
        if (a + b + 1 < f) {
          id[3] = lattice_vertex(&L, out, ico, c, w[3], f, radius);
          tri += 3;
          tri[0] = id[1], tri[1] = id[3], tri[2] = id[2];
          out->ntri++;
        }
      }
  }
  free(L.keys), free(L.ids);
  return 0;
}
