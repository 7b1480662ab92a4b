/* Half-edge surfaces (Bao 2006, §3.4): building the pairs from a triangle list by sorting the
 * undirected edge keys, with the checks that make the surface a closed, oriented 2-manifold,
 * and walking around a vertex (valence, 1-ring). */
#include "tb_halfedge.h"

#include <stdlib.h>
#include <string.h>

typedef struct edge_key {
  int lo, hi; /* the edge's vertices, lo < hi */
  int h;      /* the half-edge */
} edge_key;

static int cmp_edge_key(const void *pa, const void *pb) {
  const edge_key *a = pa, *b = pb;
  if (a->lo != b->lo) return a->lo < b->lo ? -1 : 1;
  if (a->hi != b->hi) return a->hi < b->hi ? -1 : 1;
  return (a->h > b->h) - (a->h < b->h);
}

static int he_end(const tb_halfedge *he, int h) { return he->vert[tb_he_next(h)]; }

/* Every triangle has indices in [0, nv) and three distinct vertices. */
static int check_triangles(int nv, int nf, const int *tri, const char *name, tb_error *err) {
  for (int f = 0; f < nf; f++) {
    const int *t = tri + 3 * f;
    for (int k = 0; k < 3; k++)
      if (t[k] < 0 || t[k] >= nv)
        return tb_error_set(err, name, 0, "triangle %d: vertex index %d out of range [0, %d)", f,
                            t[k], nv);
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
      return tb_error_set(err, name, 0, "triangle %d (%d, %d, %d) is degenerate: a vertex repeats",
                          f, t[0], t[1], t[2]);
  }
  return 0;
}

/* Pairs the half-edges of each undirected edge; every edge must have exactly two, opposite. */
static int find_pairs(tb_halfedge *he, const char *name, tb_error *err) {
  int nh = 3 * he->nf, rc = 0;
  edge_key *k = malloc(sizeof *k * (size_t)nh);
  if (!k) return tb_error_set(err, name, 0, "out of memory");
  for (int h = 0; h < nh; h++) {
    int a = he->vert[h], b = he_end(he, h);
    k[h].lo = a < b ? a : b, k[h].hi = a < b ? b : a, k[h].h = h;
  }
  qsort(k, (size_t)nh, sizeof *k, cmp_edge_key);
  for (int i = 0; i < nh && !rc;) {
    int j = i + 1;
    while (j < nh && k[j].lo == k[i].lo && k[j].hi == k[i].hi) j++;
    int h0 = k[i].h, n = j - i;
    if (n == 1)
      rc = tb_error_set(err, name, 0,
                        "edge (%d, %d) is a boundary edge (only triangle %d uses it): the "
                        "surface is open",
                        k[i].lo, k[i].hi, tb_he_face(h0));
    else if (n > 2)
      rc = tb_error_set(err, name, 0,
                        "edge (%d, %d) is non-manifold: %d triangles use it (%d, %d, %d%s)",
                        k[i].lo, k[i].hi, n, tb_he_face(h0), tb_he_face(k[i + 1].h),
                        tb_he_face(k[i + 2].h), n > 3 ? ", ..." : "");
    else if (he->vert[h0] == he->vert[k[i + 1].h])
      rc = tb_error_set(
          err, name, 0, "edge (%d, %d) is misoriented: triangles %d and %d both run it %d -> %d",
          k[i].lo, k[i].hi, tb_he_face(h0), tb_he_face(k[i + 1].h), he->vert[h0], he_end(he, h0));
    else
      he->pair[h0] = k[i + 1].h, he->pair[k[i + 1].h] = h0;
    i = j;
  }
  free(k);
  return rc;
}

/* Every vertex is used, and the half-edges leaving it form one cycle under rotation. */
static int check_fans(tb_halfedge *he, const char *name, tb_error *err) {
  int *deg = calloc((size_t)he->nv, sizeof(int));
  if (!deg) return tb_error_set(err, name, 0, "out of memory");
  for (int v = 0; v < he->nv; v++) he->out[v] = -1;
  for (int h = 3 * he->nf - 1; h >= 0; h--) {
    he->out[he->vert[h]] = h; /* descending: ends at the smallest */
    deg[he->vert[h]]++;
  }
  int rc = 0;
  for (int v = 0; v < he->nv && !rc; v++) {
    if (he->out[v] < 0) {
      rc = tb_error_set(err, name, 0, "vertex %d is unused: no triangle has it", v);
      break;
    }
    int n = tb_halfedge_valence(he, v);
    if (n != deg[v])
      rc = tb_error_set(err, name, 0,
                        "vertex %d is non-manifold: its %d triangles are not one fan (the fan "
                        "of triangle %d closes after %d)",
                        v, deg[v], tb_he_face(he->out[v]), n);
  }
  free(deg);
  return rc;
}

int tb_halfedge_build(tb_halfedge *he, int nv, int nf, const int *tri, const char *name,
                      tb_error *err) {
  memset(he, 0, sizeof *he);
  if (nf <= 0 || nv <= 0) return tb_error_set(err, name, 0, "no triangles: not a closed surface");
  if (nf > (1 << 29)) return tb_error_set(err, name, 0, "%d triangles: too many", nf);
  if (check_triangles(nv, nf, tri, name, err)) return -1;
  he->nv = nv, he->nf = nf;
  he->vert = malloc(sizeof(int) * 3 * (size_t)nf);
  he->pair = malloc(sizeof(int) * 3 * (size_t)nf);
  he->out = malloc(sizeof(int) * (size_t)nv);
  if (!he->vert || !he->pair || !he->out) {
    tb_halfedge_free(he);
    return tb_error_set(err, name, 0, "out of memory");
  }
  memcpy(he->vert, tri, sizeof(int) * 3 * (size_t)nf);
  if (find_pairs(he, name, err) || check_fans(he, name, err)) {
    tb_halfedge_free(he);
    return -1;
  }
  return 0;
}

void tb_halfedge_free(tb_halfedge *he) {
  free(he->vert), free(he->pair), free(he->out);
  memset(he, 0, sizeof *he);
}

int tb_halfedge_valence(const tb_halfedge *he, int v) {
  int h0 = he->out[v], h = h0, n = 0;
  do {
    n++;
    h = tb_he_rotate(he, h);
  } while (h != h0);
  return n;
}

int tb_halfedge_ring(const tb_halfedge *he, int v, int *ring, int max) {
  int h0 = he->out[v], h = h0, n = 0;
  do {
    if (n < max) ring[n] = he_end(he, h);
    n++;
    h = tb_he_rotate(he, h);
  } while (h != h0);
  return n;
}
