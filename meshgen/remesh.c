/* Surface clean-up for marching-cubes output: collapse of short edges
 * (Hoppe et al. 1993, with the link condition of Dey et al. 1999 that keeps
 * a closed 2-manifold a closed 2-manifold), edge flips that raise the
 * smallest angle between nearly coplanar triangles, and Taubin's lambda|mu
 * smoothing (Taubin 1995, "A signal processing approach to fair surface
 * design") with the uniform Laplacian. Meant for some thousand triangles. */
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

/* Per-vertex lists of incident triangles. */
typedef struct rm_fan {
  int n, cap;
  int *t;
} rm_fan;

typedef struct rm_edge {
  double len;
  int a, b;
} rm_edge;

static int rm_fan_push(rm_fan *f, int t) {
  if (f->n == f->cap) {
    int cap = f->cap ? 2 * f->cap : 8;
    int *p = realloc(f->t, (size_t)cap * sizeof *p);
    if (!p) return -1;
    f->t = p, f->cap = cap;
  }
  f->t[f->n++] = t;
  return 0;
}

static void rm_fan_remove(rm_fan *f, int t) {
  for (int i = 0; i < f->n; i++)
    if (f->t[i] == t) {
      memmove(f->t + i, f->t + i + 1, (size_t)(f->n - i - 1) * sizeof *f->t);
      f->n--;
      return;
    }
}

static int rm_edge_cmp(const void *pa, const void *pb) {
  const rm_edge *a = pa, *b = pb;
  if (a->len != b->len) return a->len < b->len ? -1 : 1;
  if (a->a != b->a) return a->a < b->a ? -1 : 1;
  return (a->b > b->b) - (a->b < b->b);
}

static int rm_pair_cmp(const void *pa, const void *pb) {
  const int *a = pa, *b = pb;
  if (a[0] != b[0]) return a[0] < b[0] ? -1 : 1;
  return (a[1] > b[1]) - (a[1] < b[1]);
}

static int rm_valid(const tb_mesh *m) {
  if (m->nv < 0 || m->ntri < 0 || (m->ntri > 0 && (!m->tri || !m->x))) return 0;
  for (int i = 0; i < 3 * m->ntri; i++)
    if (m->tri[i] < 0 || m->tri[i] >= m->nv) return 0;
  return 1;
}

/* Sorted undirected edges (2 per entry, a < b), duplicates kept; n = 3*ntri. */
static int *rm_all_edges(const tb_mesh *m) {
  int *e = malloc((size_t)6 * (size_t)(m->ntri > 0 ? m->ntri : 1) * sizeof *e);
  if (!e) return NULL;
  for (int t = 0; t < m->ntri; t++)
    for (int s = 0; s < 3; s++) {
      int a = m->tri[3 * t + s], b = m->tri[3 * t + (s + 1) % 3];
      e[6 * t + 2 * s] = a < b ? a : b, e[6 * t + 2 * s + 1] = a < b ? b : a;
    }
  qsort(e, (size_t)3 * m->ntri, 2 * sizeof *e, rm_pair_cmp);
  return e;
}

/* Triangle fans of every vertex, and the vertices that must not move: those
 * on an edge not shared by exactly two triangles. Returns 0, or -1 when out
 * of memory. */
static int rm_prepare(const tb_mesh *m, rm_fan *fan, char *frozen) {
  int ntri = m->ntri, *e = rm_all_edges(m);
  if (!e) return -1;
  for (int i = 0; i < 3 * ntri;) {
    int j = i;
    while (j < 3 * ntri && e[2 * j] == e[2 * i] && e[2 * j + 1] == e[2 * i + 1]) j++;
    if (j - i != 2) frozen[e[2 * i]] = frozen[e[2 * i + 1]] = 1;
    i = j;
  }
  free(e);
  for (int t = 0; t < ntri; t++)
    for (int c = 0; c < 3; c++)
      if (rm_fan_push(&fan[m->tri[3 * t + c]], t)) return -1;
  return 0;
}

static tb_vec3 rm_normal(tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  return tb_cross(tb_sub(b, a), tb_sub(c, a));
}

/* Distinct neighbours of v (through its fan) into buf; returns the count. */
static int rm_ring(const tb_mesh *m, const rm_fan *fan, int v, int *buf, int cap) {
  int n = 0;
  for (int i = 0; i < fan[v].n; i++) {
    const int *t = m->tri + 3 * fan[v].t[i];
    for (int s = 0; s < 3; s++) {
      int w = t[s], seen = w == v;
      for (int q = 0; q < n && !seen; q++) seen = buf[q] == w;
      if (!seen && n < cap) buf[n++] = w;
    }
  }
  return n;
}

#define RM_RING 256
#define RM_MIN_COS 0.25

/* Whether collapsing edge (a,b) into its midpoint is allowed; fills the two
 * triangles on the edge. */
static int rm_can_collapse(const tb_mesh *m, const rm_fan *fan, const char *frozen, int a, int b,
                           tb_vec3 p, int *t2) {
  int nt = 0, opp[2];
  if (frozen[a] || frozen[b]) return 0;
  for (int i = 0; i < fan[a].n; i++) {
    const int *t = m->tri + 3 * fan[a].t[i];
    if (t[0] != b && t[1] != b && t[2] != b) continue;
    if (nt == 2) return 0;
    t2[nt] = fan[a].t[i];
    opp[nt++] = t[0] != a && t[0] != b ? t[0] : (t[1] != a && t[1] != b ? t[1] : t[2]);
  }
  if (nt != 2 || opp[0] == opp[1]) return 0;
  int ra[RM_RING], rb[RM_RING], rc[RM_RING];
  int na = rm_ring(m, fan, a, ra, RM_RING), nb = rm_ring(m, fan, b, rb, RM_RING);
  if (na >= RM_RING || nb >= RM_RING) return 0;
  /* link condition: the common neighbours are exactly the two opposite vertices */
  int common = 0;
  for (int i = 0; i < na; i++)
    for (int j = 0; j < nb; j++)
      if (ra[i] == rb[j]) {
        if (ra[i] != opp[0] && ra[i] != opp[1]) return 0;
        common++;
      }
  if (common != 2) return 0;
  /* valences stay >= 3 */
  if (na + nb - 4 < 3) return 0;
  for (int s = 0; s < 2; s++)
    if (rm_ring(m, fan, opp[s], rc, RM_RING) - 1 < 3) return 0;
  /* no triangle flips or degenerates */
  tb_vec3 region = tb_v3(0, 0, 0);
  for (int s = 0; s < 2; s++) {
    int v = s ? b : a;
    for (int i = 0; i < fan[v].n; i++) {
      const int *t = m->tri + 3 * fan[v].t[i];
      region = tb_add(region, rm_normal(m->x[t[0]], m->x[t[1]], m->x[t[2]]));
    }
  }
  for (int s = 0; s < 2; s++) {
    int v = s ? b : a;
    for (int i = 0; i < fan[v].n; i++) {
      int ti = fan[v].t[i];
      if (ti == t2[0] || ti == t2[1]) continue;
      const int *t = m->tri + 3 * ti;
      tb_vec3 q[3], o[3];
      double lmax = 0.0;
      for (int c = 0; c < 3; c++) o[c] = m->x[t[c]], q[c] = t[c] == v ? p : o[c];
      for (int c = 0; c < 3; c++) {
        double l = tb_dist(q[c], q[(c + 1) % 3]);
        lmax = l > lmax ? l : lmax;
      }
      tb_vec3 nold = rm_normal(o[0], o[1], o[2]), nnew = rm_normal(q[0], q[1], q[2]);
      double lold = tb_len(nold), lnew = tb_len(nnew);
      if (!(lnew > 1e-12 * lmax * lmax)) return 0;
      /* a needle's own normal means little: compare with the region's */
      tb_vec3 ref = lold > 1e-3 * lmax * lmax ? nold : region;
      if (!(tb_dot(nnew, ref) > RM_MIN_COS * lnew * tb_len(ref))) return 0;
    }
  }
  return 1;
}

static void rm_collapse(tb_mesh *m, rm_fan *fan, char *dead_t, int a, int b, tb_vec3 p,
                        const int *t2) {
  m->x[a] = p;
  for (int s = 0; s < 2; s++) {
    const int *t = m->tri + 3 * t2[s];
    dead_t[t2[s]] = 1;
    for (int c = 0; c < 3; c++) rm_fan_remove(&fan[t[c]], t2[s]);
  }
  for (int i = 0; i < fan[b].n; i++) {
    int *t = m->tri + 3 * fan[b].t[i];
    for (int c = 0; c < 3; c++)
      if (t[c] == b) t[c] = a;
    rm_fan_push(&fan[a], fan[b].t[i]); /* capacity reserved by the caller */
  }
  fan[b].n = 0;
}

/* Drops dead triangles and unused vertices, keeping the order. */
static int rm_compact(tb_mesh *m, const char *dead_t) {
  int *map = malloc((size_t)(m->nv > 0 ? m->nv : 1) * sizeof *map);
  if (!map) return -1;
  for (int v = 0; v < m->nv; v++) map[v] = -1;
  int nt = 0;
  for (int t = 0; t < m->ntri; t++) {
    if (dead_t[t]) continue;
    for (int c = 0; c < 3; c++) {
      m->tri[3 * nt + c] = m->tri[3 * t + c];
      map[m->tri[3 * t + c]] = 0;
    }
    nt++;
  }
  int nv = 0;
  for (int v = 0; v < m->nv; v++)
    if (map[v] == 0) {
      m->x[nv] = m->x[v];
      map[v] = nv++;
    }
  for (int i = 0; i < 3 * nt; i++) m->tri[i] = map[m->tri[i]];
  m->nv = nv, m->ntri = nt;
  free(map);
  return 0;
}

int tb_remesh_collapse_short(tb_mesh *m, double min_len) {
  if (!m || !rm_valid(m) || !(min_len >= 0)) return -1;
  if (m->ntri == 0 || min_len == 0) return 0;
  int nv = m->nv, ntri = m->ntri, total = 0, ret = -1;
  rm_fan *fan = calloc((size_t)nv, sizeof *fan);
  char *dead_t = calloc((size_t)ntri, 1), *frozen = calloc((size_t)nv, 1);
  rm_edge *cand = malloc((size_t)3 * ntri * sizeof *cand);
  if (!fan || !dead_t || !frozen || !cand) goto done;
  if (rm_prepare(m, fan, frozen)) goto done;
  for (int pass = 0; pass < 64; pass++) {
    int nc = 0, done_now = 0;
    for (int t = 0; t < ntri; t++) {
      if (dead_t[t]) continue;
      for (int s = 0; s < 3; s++) {
        int a = m->tri[3 * t + s], b = m->tri[3 * t + (s + 1) % 3];
        if (a > b) continue; /* each interior edge once, from one side */
        double l = tb_dist(m->x[a], m->x[b]);
        if (l < min_len) cand[nc++] = (rm_edge){l, a, b};
      }
    }
    qsort(cand, (size_t)nc, sizeof *cand, rm_edge_cmp);
    for (int i = 0; i < nc; i++) {
      int a = cand[i].a, b = cand[i].b, t2[2];
      if (fan[a].n == 0 || fan[b].n == 0) continue; /* gone */
      if (!(tb_dist(m->x[a], m->x[b]) < min_len)) continue;
      tb_vec3 p = tb_scale(tb_add(m->x[a], m->x[b]), 0.5);
      if (!rm_can_collapse(m, fan, frozen, a, b, p, t2)) continue;
      /* reserve room so the collapse itself cannot fail */
      for (int r = 0; r < fan[b].n; r++)
        if (rm_fan_push(&fan[a], -1)) goto done;
      fan[a].n -= fan[b].n;
      rm_collapse(m, fan, dead_t, a, b, p, t2);
      done_now++;
    }
    total += done_now;
    if (done_now == 0) break;
  }
  if (rm_compact(m, dead_t)) goto done;
  ret = total;
done:
  if (fan)
    for (int v = 0; v < nv; v++) free(fan[v].t);
  free(fan), free(dead_t), free(frozen), free(cand);
  return ret;
}

/* Smallest interior angle of triangle (a,b,c), as a cosine (larger = worse). */
static double rm_max_cos(tb_vec3 a, tb_vec3 b, tb_vec3 c) {
  tb_vec3 p[3] = {a, b, c};
  double worst = -1.0;
  for (int i = 0; i < 3; i++) {
    tb_vec3 u = tb_sub(p[(i + 1) % 3], p[i]), w = tb_sub(p[(i + 2) % 3], p[i]);
    double l = tb_len(u) * tb_len(w), cs = l > 0 ? tb_dot(u, w) / l : 1.0;
    worst = cs > worst ? cs : worst;
  }
  return worst;
}

#define RM_FLAT_COS 0.94 /* flip only where the two triangles bend < ~20 deg */

int tb_remesh_flip(tb_mesh *m) {
  if (!m || !rm_valid(m)) return -1;
  if (m->ntri == 0) return 0;
  int nv = m->nv, ntri = m->ntri, total = 0, ret = -1;
  rm_fan *fan = calloc((size_t)nv, sizeof *fan);
  char *frozen = calloc((size_t)nv, 1);
  if (!fan || !frozen) goto done;
  if (rm_prepare(m, fan, frozen)) goto done;
  for (int pass = 0; pass < 32; pass++) {
    int flips = 0;
    for (int t = 0; t < ntri; t++)
      for (int s = 0; s < 3; s++) {
        int *T = m->tri + 3 * t, a = T[s], b = T[(s + 1) % 3], c = T[(s + 2) % 3];
        if (a > b || frozen[a] || frozen[b]) continue;
        /* the other triangle (b, a, d) */
        int u = -1, d = -1, na = 0, nb = 0, seen_cd = 0;
        for (int i = 0; i < fan[a].n; i++) {
          int *U = m->tri + 3 * fan[a].t[i];
          for (int q = 0; q < 3; q++)
            if (U[q] == b && U[(q + 1) % 3] == a) u = fan[a].t[i], d = U[(q + 2) % 3];
        }
        if (u < 0 || d == c) continue;
        int ring[RM_RING];
        na = rm_ring(m, fan, a, ring, RM_RING);
        nb = rm_ring(m, fan, b, ring, RM_RING);
        if (na <= 3 || nb <= 3) continue; /* valences stay >= 3 */
        int nc = rm_ring(m, fan, c, ring, RM_RING);
        for (int q = 0; q < nc; q++) seen_cd |= ring[q] == d;
        if (seen_cd) continue; /* c-d already an edge */
        tb_vec3 A = m->x[a], B = m->x[b], C = m->x[c], D = m->x[d];
        tb_vec3 n1 = rm_normal(A, B, C), n2 = rm_normal(B, A, D);
        if (!(tb_dot(n1, n2) > RM_FLAT_COS * tb_len(n1) * tb_len(n2))) continue;
        tb_vec3 n3 = rm_normal(C, D, B), n4 = rm_normal(D, C, A), ns = tb_add(n1, n2);
        if (!(tb_dot(n3, ns) > 0 && tb_dot(n4, ns) > 0)) continue;
        double before = fmax(rm_max_cos(A, B, C), rm_max_cos(B, A, D));
        double after = fmax(rm_max_cos(C, D, B), rm_max_cos(D, C, A));
        if (!(after < before - 1e-9)) continue;
        /* (a,b,c),(b,a,d) -> (c,d,b),(d,c,a) */
        T[0] = c, T[1] = d, T[2] = b;
        int *U = m->tri + 3 * u;
        U[0] = d, U[1] = c, U[2] = a;
        rm_fan_remove(&fan[a], t), rm_fan_remove(&fan[b], u);
        if (rm_fan_push(&fan[c], u) || rm_fan_push(&fan[d], t)) goto done;
        flips++;
        s = 3; /* this triangle changed: next one */
      }
    total += flips;
    if (flips == 0) break;
  }
  ret = total;
done:
  if (fan)
    for (int v = 0; v < nv; v++) free(fan[v].t);
  free(fan), free(frozen);
  return ret;
}

void tb_remesh_taubin(tb_mesh *m, int iters, double lambda, double mu) {
  if (!m || !rm_valid(m) || m->ntri == 0 || iters <= 0) return;
  if (!isfinite(lambda) || !isfinite(mu)) return;
  int nv = m->nv, ne = 0, *fill = NULL;
  int *e = rm_all_edges(m);
  int *start = calloc((size_t)nv + 1, sizeof *start);
  int *adj = malloc((size_t)6 * m->ntri * sizeof *adj);
  tb_vec3 *d = malloc((size_t)nv * sizeof *d);
  if (!e || !start || !adj || !d) goto done;
  /* distinct edges, then compressed adjacency rows */
  for (int i = 0; i < 3 * m->ntri; i++)
    if (i == 0 || e[2 * i] != e[2 * ne - 2] || e[2 * i + 1] != e[2 * ne - 1]) {
      e[2 * ne] = e[2 * i], e[2 * ne + 1] = e[2 * i + 1];
      ne++;
    }
  for (int i = 0; i < ne; i++) start[e[2 * i] + 1]++, start[e[2 * i + 1] + 1]++;
  for (int v = 0; v < nv; v++) start[v + 1] += start[v];
  fill = malloc((size_t)nv * sizeof *fill);
  if (!fill) goto done;
  memcpy(fill, start, (size_t)nv * sizeof *fill);
  for (int i = 0; i < ne; i++) {
    adj[fill[e[2 * i]]++] = e[2 * i + 1];
    adj[fill[e[2 * i + 1]]++] = e[2 * i];
  }
  for (int it = 0; it < 2 * iters; it++) {
    double w = (it & 1) ? mu : lambda;
    for (int v = 0; v < nv; v++) {
      int n = start[v + 1] - start[v];
      tb_vec3 s = tb_v3(0, 0, 0);
      for (int q = start[v]; q < start[v + 1]; q++) s = tb_add(s, m->x[adj[q]]);
      d[v] = n > 0 ? tb_sub(tb_scale(s, 1.0 / n), m->x[v]) : tb_v3(0, 0, 0);
    }
    for (int v = 0; v < nv; v++) m->x[v] = tb_madd(m->x[v], w, d[v]);
  }
done:
  free(e), free(start), free(adj), free(d), free(fill);
}
