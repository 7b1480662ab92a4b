/* Capping an open surface: each boundary loop of a consistently oriented
 * 2-manifold gets a new vertex at the loop's centroid and a fan of
 * triangles to it, oriented like the surface, so "inside" is defined for
 * contact and TetGen. A cap that crosses the surface (a loop far from
 * planar or star-shaped around its centroid) is an error, not kept. */
#include <stdlib.h>
#include <string.h>

#include "collision/tb_bvh.h"
#include "tb_meshgen.h"

static int cmp_long(const void *a, const void *b) {
  long x = *(const long *)a, y = *(const long *)b;
  return (x > y) - (x < y);
}

/* Directed boundary edges a->b (no triangle has b->a): *next[a] = b, or -1.
 * Returns how many, or -1 when a vertex starts two (a pinched boundary). */
static int boundary(const tb_mesh *m, int *next, long *key) {
  long ne = 3L * m->ntri, nv = m->nv;
  for (long k = 0; k < ne; k++)
    key[k] = m->tri[3 * (k / 3) + k % 3] * nv + m->tri[3 * (k / 3) + (k + 1) % 3];
  qsort(key, (size_t)ne, sizeof(long), cmp_long);
  for (int v = 0; v < m->nv; v++) next[v] = -1;
  int n = 0;
  for (long k = 0; k < ne; k++) {
    long a = key[k] / nv, b = key[k] % nv, rev = b * nv + a;
    if (bsearch(&rev, key, (size_t)ne, sizeof(long), cmp_long)) continue;
    if (next[a] >= 0) return -1;
    next[a] = (int)b, n++;
  }
  return n;
}

int tb_mesh_close(tb_mesh *m, int *loops, tb_error *err) {
  *loops = 0;
  tb_mesh_topo t = tb_mesh_topology(m);
  if (m->ntet) return tb_error_set(err, "close", 0, "a tet mesh is closed already");
  if (!t.manifold || t.misoriented_edges || t.degenerate_tris)
    return tb_error_set(err, "close", 0,
                        "the surface must be a consistently oriented 2-manifold (%d non-manifold "
                        "edges, %d non-manifold vertices, %d misoriented edges, %d degenerate)",
                        t.nonmanifold_edges, t.nonmanifold_verts, t.misoriented_edges,
                        t.degenerate_tris);
  if (t.closed) return 0;
  int *next = malloc(sizeof(int) * (size_t)m->nv);
  long *key = malloc(sizeof(long) * 3 * (size_t)m->ntri);
  int nb = next && key ? boundary(m, next, key) : -2;
  free(key);
  if (nb < 0) {
    free(next);
    return tb_error_set(err, "close", 0,
                        nb == -2 ? "out of memory" : "a vertex lies on two holes' boundaries");
  }
  /* at most one new vertex per loop, nb new triangles */
  tb_vec3 *x = realloc(m->x, sizeof(tb_vec3) * (size_t)(m->nv + nb));
  if (x) m->x = x;
  int *tri = realloc(m->tri, sizeof(int) * 3 * (size_t)(m->ntri + nb));
  if (tri) m->tri = tri;
  if (!x || !tri) {
    free(next);
    return tb_error_set(err, "close", 0, "out of memory");
  }
  int nv0 = m->nv, ntri0 = m->ntri;
  for (int s = 0; s < nv0; s++) {
    if (next[s] < 0) continue;
    tb_vec3 c = tb_v3(0, 0, 0);
    int len = 0, v = s;
    do {
      c = tb_add(c, m->x[v]), len++;
      v = next[v];
    } while (v != s && v >= 0 && len <= nb);
    if (v != s) {
      free(next);
      m->nv = nv0, m->ntri = ntri0;
      return tb_error_set(err, "close", 0, "a boundary that is not a loop");
    }
    int centre = m->nv++;
    m->x[centre] = tb_scale(c, 1.0 / len);
    for (int w; next[v] >= 0; v = w) {
      w = next[v];
      int *f = m->tri + 3 * m->ntri++;
      f[0] = w, f[1] = v, f[2] = centre; /* the surface has v->w, so the cap runs w->v */
      next[v] = -1;
    }
    (*loops)++;
  }
  free(next);
  tb_pairlist self = {0, 0, NULL};
  if (tb_collide_self(m->x, m->tri, m->ntri, &self, err)) return -1;
  int crossing = 0;
  for (int k = 0; k < 2 * self.n && !crossing; k += 2) crossing = self.ij[k + 1] >= ntri0;
  tb_pairlist_free(&self);
  if (crossing) {
    m->nv = nv0, m->ntri = ntri0;
    return tb_error_set(err, "close", 0,
                        "a cap's fan crosses the surface (a hole far from planar)");
  }
  return 0;
}
