/* The surface cutter's topology helpers (tb_cut_surface.h): growable
 * arrays, per-vertex stars of directed edges, the closed-manifold check,
 * components, the enclosed volume, inside-ness by exact ray parity, and
 * the output's vertices and triangles. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cut_priv.h"
#include "collision/tb_predicates.h"

/* ---- growable arrays ---- */

int cut_grow(void **a, int *cap, int need, size_t size) {
  if (need <= *cap) return 0;
  int c = *cap ? *cap : 16;
  while (c < need) c *= 2;
  void *b = realloc(*a, (size_t)c * size);
  if (!b) return -1;
  *a = b, *cap = c;
  return 0;
}

/* ---- topology utilities ---- */

int cut_vstar_build(vstar *vs, int nv, int ntri, const int *tri) {
  vs->start = calloc((size_t)nv + 2, sizeof *vs->start);
  vs->out = malloc((size_t)(3 * ntri + 1) * sizeof *vs->out);
  if (!vs->start || !vs->out) return -1;
  for (int i = 0; i < 3 * ntri; i++) vs->start[tri[i] + 2]++;
  for (int v = 0; v < nv; v++) vs->start[v + 2] += vs->start[v + 1];
  for (int i = 0; i < 3 * ntri; i++) vs->out[vs->start[tri[i] + 1]++] = i;
  return 0;
}
void cut_vstar_free(vstar *vs) { free(vs->start), free(vs->out); }

/* The corner 3 t + k whose edge runs a -> b, the first in triangle order; -1 when none. */
int cut_find_edge(const vstar *vs, const int *tri, int a, int b) {
  for (int i = vs->start[a]; i < vs->start[a + 1]; i++) {
    int h = vs->out[i];
    if (tri[h - h % 3 + (h % 3 + 1) % 3] == b) return h;
  }
  return -1;
}

int tb_cut_is_closed_manifold(int nv, int ntri, const int *tri) {
  if (nv <= 0 || ntri <= 0) return 0;
  for (int i = 0; i < 3 * ntri; i++)
    if (tri[i] < 0 || tri[i] >= nv) return 0;
  for (int t = 0; t < ntri; t++) {
    const int *c = tri + 3 * t;
    if (c[0] == c[1] || c[1] == c[2] || c[2] == c[0]) return 0;
  }
  vstar vs;
  int ok = cut_vstar_build(&vs, nv, ntri, tri) == 0;
  /* every directed edge once, its reverse present */
  for (int h = 0; ok && h < 3 * ntri; h++) {
    int a = tri[h], b = tri[h - h % 3 + (h % 3 + 1) % 3];
    ok = cut_find_edge(&vs, tri, a, b) == h && cut_find_edge(&vs, tri, b, a) >= 0;
  }
  /* The link of v: from the corner (v, w, ..), the triangle running w -> v is the next around
   * v; the walk must visit every corner of v. */
  for (int v = 0; v < nv && ok; v++) {
    int deg = vs.start[v + 1] - vs.start[v];
    if (!deg) continue;
    int h0 = vs.out[vs.start[v]], h = h0, steps = 0;
    do {
      int w = tri[h - h % 3 + (h % 3 + 1) % 3], g = cut_find_edge(&vs, tri, w, v);
      h = g < 0 ? -1 : g - g % 3 + (g % 3 + 1) % 3; /* the corner of v in that triangle */
      steps++;
    } while (h >= 0 && h != h0 && steps <= deg);
    ok = h == h0 && steps == deg;
  }
  cut_vstar_free(&vs);
  return ok;
}

int cut_uf_find(int *p, int i) {
  while (p[i] != i) i = p[i] = p[p[i]];
  return i;
}
void cut_uf_join(int *p, int a, int b) {
  a = cut_uf_find(p, a), b = cut_uf_find(p, b);
  if (a != b) p[a > b ? a : b] = a < b ? a : b;
}

int tb_cut_components(int nv, int ntri, const int *tri) {
  int *p = malloc((size_t)(nv > 0 ? nv : 1) * sizeof *p),
      *used = calloc((size_t)(nv > 0 ? nv : 1), sizeof *used);
  if (!p || !used) {
    free(p), free(used);
    return -1;
  }
  for (int i = 0; i < nv; i++) p[i] = i;
  for (int t = 0; t < ntri; t++) {
    const int *c = tri + 3 * t;
    if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[0] >= nv || c[1] >= nv || c[2] >= nv) continue;
    used[c[0]] = used[c[1]] = used[c[2]] = 1;
    cut_uf_join(p, c[0], c[1]), cut_uf_join(p, c[0], c[2]);
  }
  int n = 0;
  for (int i = 0; i < nv; i++) n += used[i] && cut_uf_find(p, i) == i;
  free(p), free(used);
  return n;
}

double tb_cut_volume(const tb_vec3 *x, int ntri, const int *tri) {
  double v = 0.0;
  for (int t = 0; t < ntri; t++)
    v += tb_dot(x[tri[3 * t]], tb_cross(x[tri[3 * t + 1]], x[tri[3 * t + 2]]));
  return v / 6.0;
}

/* ---- inside the organ: exact ray parity ---- */

/* The axis projections of cut_ray: (i, j) the plane, a the ray's axis. */
static const int ray_axes[3][3] = {{0, 1, 2}, {2, 0, 1}, {1, 2, 0}};

int cut_ray(tb_vec3 A, tb_vec3 B, tb_vec3 C, tb_vec3 p, int r) {
  int i = ray_axes[r][0], j = ray_axes[r][1], a = ray_axes[r][2];
  double pi = tb_comp(p, i), pj = tb_comp(p, j), pa = tb_comp(p, a);
  double ai = tb_comp(A, i), bi = tb_comp(B, i), ci = tb_comp(C, i);
  if ((pi < ai && pi < bi && pi < ci) || (pi > ai && pi > bi && pi > ci)) return 0;
  double aj = tb_comp(A, j), bj = tb_comp(B, j), cj = tb_comp(C, j);
  if ((pj < aj && pj < bj && pj < cj) || (pj > aj && pj > bj && pj > cj)) return 0;
  if (pa > tb_comp(A, a) && pa > tb_comp(B, a) && pa > tb_comp(C, a)) return 0;
  int o0 = tb_orient2d(bi, bj, ci, cj, pi, pj), o1 = tb_orient2d(ci, cj, ai, aj, pi, pj);
  int o2 = tb_orient2d(ai, aj, bi, bj, pi, pj);
  if ((o0 > 0 || o1 > 0 || o2 > 0) && (o0 < 0 || o1 < 0 || o2 < 0)) return 0;
  if (!o0 && !o1 && !o2) return 0; /* a triangle seen edge-on along the ray */
  if (!o0 || !o1 || !o2) return -1;
  int o3 = tb_orient3d(A, B, C, p);
  if (o3 == 0) return -2;
  return o3 * o0 < 0;
}

/* 1 inside, 0 outside, -1 undecided (on the surface, or every axis ray
 * grazes an edge). */
int cut_inside_organ(const tb_vec3 *x, int ntri, const int *tri, tb_vec3 p) {
  for (int r = 0; r < 3; r++) {
    int n = 0, grazed = 0;
    for (int t = 0; t < ntri && !grazed; t++) {
      int h = cut_ray(x[tri[3 * t]], x[tri[3 * t + 1]], x[tri[3 * t + 2]], p, r);
      if (h == -2) return -1;
      grazed = h == -1, n += h == 1;
    }
    if (!grazed) return n & 1;
  }
  return -1;
}

int cut_new_vertex(cutter *c, tb_vec3 x) {
  if (GROW(c->v, c->nvr + 1, c->capv)) return -1;
  vrec *r = &c->v[c->nvr];
  memset(r, 0, sizeof *r);
  r->x = x, r->piece = -1, r->origin = -1;
  return c->nvr++;
}

int cut_emit(cutter *c, int a, int b, int d, int from, int lab) {
  if (GROW(c->otri, 3 * (c->nout + 1), c->capout) || GROW(c->ofrom, c->nout + 1, c->capfrom) ||
      GROW(c->olab, c->nout + 1, c->caplab))
    return -1;
  c->otri[3 * c->nout] = a, c->otri[3 * c->nout + 1] = b, c->otri[3 * c->nout + 2] = d;
  c->ofrom[c->nout] = from, c->olab[c->nout] = lab;
  c->nout++;
  return 0;
}
