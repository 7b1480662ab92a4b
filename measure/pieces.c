/* The pieces of a surface after a cut (measure/tb_pieces.h). Pieces are
 * the connected components of the triangles through shared vertices
 * (union-find), so two pieces touching in one vertex count as one (and
 * that vertex makes the surface non-manifold: not closed). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_pieces.h"
#include "collision/tb_bvh.h"
#include "cutting/tb_cut_surface.h"

static int find(int *uf, int a) {
  while (uf[a] != a) uf[a] = uf[uf[a]], a = uf[a];
  return a;
}
/* How far triangle q reaches through the plane of p on its lesser side. */
static double poke(const tb_vec3 *x, const int *p, const int *q) {
  tb_vec3 a = x[p[0]], n = tb_normalize(tb_cross(tb_sub(x[p[1]], a), tb_sub(x[p[2]], a)));
  double lo = 0, hi = 0;
  for (int k = 0; k < 3; k++) {
    double d = tb_dot(tb_sub(x[q[k]], a), n);
    lo = fmin(lo, d), hi = fmax(hi, d);
  }
  return fmin(hi, -lo);
}

static double mean_edge(const tb_vec3 *x, int ntri, const int *tri) {
  double sum = 0;
  for (int k = 0; k < 3 * ntri; k++) sum += tb_dist(x[tri[k]], x[tri[k - k % 3 + (k + 1) % 3]]);
  return ntri > 0 ? sum / (3.0 * ntri) : 0;
}

static void join(int *uf, int a, int b) {
  a = find(uf, a), b = find(uf, b);
  if (a != b) uf[a < b ? b : a] = a < b ? a : b;
}

int tb_pieces_measure(int nv, const tb_vec3 *x, int ntri, const int *tri, int self, tb_pieces *p,
                      tb_error *err) {
  memset(p, 0, sizeof *p);
  p->nv = nv, p->ntri = ntri, p->self_pairs = p->overlap_pairs = -1;
  int *uf = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1)), *id = NULL, *sub = NULL;
  p->of_vertex = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
  p->of_tri = malloc(sizeof(int) * (size_t)(ntri > 0 ? ntri : 1));
  if (!uf || !p->of_vertex || !p->of_tri) goto oom;
  for (int v = 0; v < nv; v++) uf[v] = v, p->of_vertex[v] = -1;
  for (int t = 0; t < ntri; t++)
    join(uf, tri[3 * t], tri[3 * t + 1]), join(uf, tri[3 * t], tri[3 * t + 2]);
  id = malloc(sizeof(int) * (size_t)(nv > 0 ? nv : 1));
  if (!id) goto oom;
  for (int v = 0; v < nv; v++) id[v] = -1;
  for (int t = 0; t < ntri; t++) { /* pieces numbered in the order of their first triangle */
    int r = find(uf, tri[3 * t]);
    if (id[r] < 0) id[r] = p->n++;
    p->of_tri[t] = id[r];
  }
  for (int v = 0; v < nv; v++) p->of_vertex[v] = id[find(uf, v)];
  for (int t = 0; t < ntri; t++) /* unused vertices stay -1 */
    for (int k = 0; k < 3; k++) uf[tri[3 * t + k]] = -2;
  for (int v = 0; v < nv; v++)
    if (uf[v] != -2) p->of_vertex[v] = -1;
  p->volume = calloc((size_t)(p->n > 0 ? p->n : 1), sizeof *p->volume);
  sub = malloc(sizeof(int) * 3 * (size_t)(ntri > 0 ? ntri : 1));
  if (!p->volume || !sub) goto oom;
  p->closed = 1;
  for (int k = 0; k < p->n; k++) { /* each piece on its own */
    int m = 0;
    for (int t = 0; t < ntri; t++)
      if (p->of_tri[t] == k) memcpy(sub + 3 * m++, tri + 3 * t, 3 * sizeof *sub);
    p->closed &= tb_cut_is_closed_manifold(nv, m, sub);
  }
  tb_pieces_volumes(p, x, tri, p->volume);
  if (self) {
    tb_pairlist pl = {0, 0, NULL};
    if (tb_collide_self(x, tri, ntri, &pl, err)) goto fail;
    p->self_pairs = p->overlap_pairs = 0;
    double h = mean_edge(x, ntri, tri);
    for (int k = 0; k < pl.n; k++) {
      const int *a = tri + 3 * pl.ij[2 * k], *b = tri + 3 * pl.ij[2 * k + 1];
      p->deepest = fmax(p->deepest, fmin(poke(x, a, b), poke(x, b, a)) / h);
      int same = p->of_tri[pl.ij[2 * k]] == p->of_tri[pl.ij[2 * k + 1]];
      if (same)
        p->self_pairs++;
      else
        p->overlap_pairs++;
    }
    tb_pairlist_free(&pl);
  }
  free(uf), free(id), free(sub);
  return 0;
oom:
  tb_error_set(err, "pieces", 0, "out of memory");
fail:
  free(uf), free(id), free(sub);
  tb_pieces_free(p);
  return -1;
}

void tb_pieces_volumes(const tb_pieces *p, const tb_vec3 *x, const int *tri, double *volume) {
  for (int k = 0; k < p->n; k++) volume[k] = 0;
  for (int t = 0; t < p->ntri; t++) { /* divergence theorem: a . (b x c) / 6 */
    tb_vec3 a = x[tri[3 * t]], b = x[tri[3 * t + 1]], c = x[tri[3 * t + 2]];
    volume[p->of_tri[t]] += tb_dot(a, tb_cross(b, c)) / 6.0;
  }
}

void tb_pieces_free(tb_pieces *p) {
  free(p->volume), free(p->of_vertex), free(p->of_tri);
  memset(p, 0, sizeof *p);
}

int tb_pieces_spheres(const tb_pieces *p, const tb_model_spheres *sp, int *components,
                      int *crossing) {
  int n = sp->n, *uf = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  int *comp = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  int *owner = NULL, one_to_one = 0; /* per sphere component: its piece, -1 none */
  *components = 0, *crossing = 0;
  if (!uf || !comp) goto done;
  for (int s = 0; s < n; s++) uf[s] = s, comp[s] = -1;
  for (int e = 0; e < sp->nlinks; e++) {
    int a = sp->links[2 * e], b = sp->links[2 * e + 1];
    if (sp->alive[a] && sp->alive[b]) join(uf, a, b);
  }
  for (int s = 0; s < n; s++)
    if (sp->alive[s] && comp[find(uf, s)] < 0) comp[find(uf, s)] = (*components)++;
  /* each component's piece: the one most of the points bound to it are on */
  size_t nc = (size_t)(*components > 0 ? *components : 1), npc = (size_t)(p->n > 0 ? p->n : 1);
  int *votes = calloc(nc * npc, sizeof *votes);
  owner = malloc(sizeof(int) * nc);
  if (!votes || !owner) {
    free(votes);
    goto done;
  }
  int nb = sp->nbound < p->nv ? sp->nbound : p->nv;
  for (int v = 0; v < nb; v++)
    for (int q = 0; q < 3 && p->of_vertex[v] >= 0; q++) {
      int s = sp->bound[v][q];
      if (s >= 0 && s < n && sp->alive[s])
        votes[(size_t)comp[find(uf, s)] * npc + (size_t)p->of_vertex[v]]++;
    }
  for (size_t k = 0; k < nc; k++) {
    owner[k] = -1;
    for (size_t q = 0, best = 0; q < npc; q++)
      if (votes[k * npc + q] > (int)best) best = (size_t)votes[k * npc + q], owner[k] = (int)q;
  }
  free(votes);
  one_to_one = 1;
  for (int v = 0; v < nb; v++) { /* a point bound across: to another piece's component */
    int piece = p->of_vertex[v], bad = 0;
    for (int q = 0; q < 3 && piece >= 0; q++) {
      int s = sp->bound[v][q];
      if (s >= 0 && s < n && sp->alive[s]) bad |= owner[comp[find(uf, s)]] != piece;
    }
    *crossing += bad;
  }
  /* one to one: every piece owns exactly one component (as many of each) */
  for (int q = 0; q < p->n; q++) {
    int k = 0;
    for (int c = 0; c < *components; c++) k += owner[c] == q;
    one_to_one &= k == 1;
  }
done:
  free(uf), free(comp), free(owner);
  return one_to_one && *crossing == 0 && *components == p->n;
}
