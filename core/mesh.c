/* Mesh measures and topology: bounding box, volume, area, edges, the faces
 * of a tet mesh and its boundary, and the closed/manifold checks. */
#include "tb_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void tb_mesh_free(tb_mesh *m) {
  free(m->x);
  free(m->tri);
  free(m->tet);
  memset(m, 0, sizeof *m);
}

static void *dup(const void *p, size_t n) {
  if (n == 0) return NULL;
  void *q = malloc(n);
  if (q) memcpy(q, p, n);
  return q;
}

int tb_mesh_copy(tb_mesh *dst, const tb_mesh *src) {
  tb_mesh m = *src;
  m.x = dup(src->x, sizeof(tb_vec3) * (size_t)src->nv);
  m.tri = dup(src->tri, sizeof(int) * 3 * (size_t)src->ntri);
  m.tet = dup(src->tet, sizeof(int) * 4 * (size_t)src->ntet);
  if ((src->nv && !m.x) || (src->ntri && !m.tri) || (src->ntet && !m.tet)) {
    tb_mesh_free(&m);
    return -1;
  }
  *dst = m;
  return 0;
}

int tb_mesh_drop_unused(tb_mesh *m) {
  int *map = malloc(sizeof(int) * (size_t)(m->nv ? m->nv : 1));
  if (!map) return -1;
  for (int i = 0; i < m->nv; i++) map[i] = -1;
  for (long k = 0; k < 3L * m->ntri; k++) map[m->tri[k]] = 0;
  for (long k = 0; k < 4L * m->ntet; k++) map[m->tet[k]] = 0;
  int n = 0;
  for (int i = 0; i < m->nv; i++)
    if (map[i] == 0) {
      m->x[n] = m->x[i];
      map[i] = n++;
    }
  for (long k = 0; k < 3L * m->ntri; k++) m->tri[k] = map[m->tri[k]];
  for (long k = 0; k < 4L * m->ntet; k++) m->tet[k] = map[m->tet[k]];
  int dropped = m->nv - n;
  m->nv = n;
  free(map);
  return dropped;
}

static int same_bytes(const void *a, const void *b, size_t n) { return n == 0 || !memcmp(a, b, n); }

int tb_mesh_equal(const tb_mesh *a, const tb_mesh *b) {
  return a->nv == b->nv && a->ntri == b->ntri && a->ntet == b->ntet &&
         same_bytes(a->x, b->x, sizeof(tb_vec3) * (size_t)a->nv) &&
         same_bytes(a->tri, b->tri, sizeof(int) * 3 * (size_t)a->ntri) &&
         same_bytes(a->tet, b->tet, sizeof(int) * 4 * (size_t)a->ntet);
}

void tb_mesh_bbox(const tb_mesh *m, tb_vec3 *lo, tb_vec3 *hi) {
  *lo = *hi = m->nv ? m->x[0] : tb_v3(0, 0, 0);
  for (int i = 1; i < m->nv; i++) {
    *lo = tb_vmin(*lo, m->x[i]);
    *hi = tb_vmax(*hi, m->x[i]);
  }
}

static double tet_vol(const tb_mesh *m, int t) {
  const int *v = m->tet + 4 * t;
  return tb_tet_volume(m->x[v[0]], m->x[v[1]], m->x[v[2]], m->x[v[3]]);
}

int tb_coord_ok(tb_vec3 x) {
  return fabs(x.x) <= TB_COORD_MAX && fabs(x.y) <= TB_COORD_MAX && fabs(x.z) <= TB_COORD_MAX;
}

int tb_mesh_check_coords(const tb_mesh *m, const char *what, tb_error *err) {
  for (int i = 0; i < m->nv; i++)
    if (!tb_coord_ok(m->x[i]))
      return tb_error_set(
          err, what, 0,
          "vertex %d at (%.17g, %.17g, %.17g): coordinates must be finite and within +-%g", i,
          m->x[i].x, m->x[i].y, m->x[i].z, TB_COORD_MAX);
  return 0;
}

int tb_mesh_bad_index(const tb_mesh *m, int *tet, long *elem, int *vertex) {
  for (int k = 0; k < 2; k++) {
    const int *ix = k ? m->tet : m->tri;
    long n = k ? 4L * m->ntet : 3L * m->ntri;
    for (long i = 0; i < n; i++)
      if (ix[i] < 0 || ix[i] >= m->nv) {
        *tet = k, *elem = i / (k ? 4 : 3), *vertex = ix[i];
        return 1;
      }
  }
  return 0;
}

double tb_mesh_volume(const tb_mesh *m) {
  double s = 0.0;
  if (m->ntet) {
    for (int t = 0; t < m->ntet; t++) s += tet_vol(m, t);
    return s;
  }
  for (int t = 0; t < m->ntri; t++) {
    const int *v = m->tri + 3 * t;
    s += tb_dot(m->x[v[0]], tb_cross(m->x[v[1]], m->x[v[2]]));
  }
  return s / 6.0;
}

double tb_mesh_area(const tb_mesh *m) {
  double s = 0.0;
  for (int t = 0; t < m->ntri; t++) {
    const int *v = m->tri + 3 * t;
    s += tb_tri_area(m->x[v[0]], m->x[v[1]], m->x[v[2]]);
  }
  return s;
}

double tb_mesh_min_tet_volume(const tb_mesh *m) {
  double lo = 0.0;
  for (int t = 0; t < m->ntet; t++) {
    double v = tet_vol(m, t);
    if (t == 0 || v < lo) lo = v;
  }
  return lo;
}

/* ---- sorting small integer tuples ---- */
typedef struct key3 {
  int k[3]; /* sorted vertex indices (k[2] unused for edges) */
  int f[3]; /* the element as oriented in its source */
  int src;  /* source element */
} key3;

static int cmp_key3(const void *pa, const void *pb) {
  const key3 *a = pa, *b = pb;
  for (int i = 0; i < 3; i++)
    if (a->k[i] != b->k[i]) return a->k[i] < b->k[i] ? -1 : 1;
  return (a->src > b->src) - (a->src < b->src);
}

static void sort3(int *k) {
  int t;
  if (k[0] > k[1]) t = k[0], k[0] = k[1], k[1] = t;
  if (k[1] > k[2]) t = k[1], k[1] = k[2], k[2] = t;
  if (k[0] > k[1]) t = k[0], k[0] = k[1], k[1] = t;
}

static int same_key(const key3 *a, const key3 *b) {
  return a->k[0] == b->k[0] && a->k[1] == b->k[1] && a->k[2] == b->k[2];
}

/* Edge list of the tets (6 per tet) or triangles (3 per triangle), sorted. */
static key3 *edge_keys(const tb_mesh *m, int *n) {
  int per = m->ntet ? 6 : 3, nel = m->ntet ? m->ntet : m->ntri;
  static const int tet_e[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  static const int tri_e[3][2] = {{0, 1}, {1, 2}, {2, 0}};
  key3 *k = malloc(sizeof *k * ((size_t)nel * per + 1));
  if (!k) return NULL;
  for (int e = 0; e < nel; e++)
    for (int j = 0; j < per; j++) {
      const int *v = m->ntet ? m->tet + 4 * e : m->tri + 3 * e;
      int a = v[m->ntet ? tet_e[j][0] : tri_e[j][0]], b = v[m->ntet ? tet_e[j][1] : tri_e[j][1]];
      key3 *q = &k[e * per + j];
      q->k[0] = a < b ? a : b;
      q->k[1] = a < b ? b : a;
      q->k[2] = 0;
      q->f[0] = a, q->f[1] = b, q->f[2] = 0;
      q->src = e;
    }
  *n = nel * per;
  qsort(k, (size_t)*n, sizeof *k, cmp_key3);
  return k;
}

int tb_mesh_edges(const tb_mesh *m, int **edges) {
  int n;
  key3 *k = edge_keys(m, &n);
  int *out = malloc(sizeof(int) * 2 * ((size_t)n + 1));
  if (!k || !out) {
    free(k), free(out);
    return -1;
  }
  int ne = 0;
  for (int i = 0; i < n; i++) {
    if (i > 0 && same_key(&k[i], &k[i - 1])) continue;
    out[2 * ne] = k[i].k[0], out[2 * ne + 1] = k[i].k[1];
    ne++;
  }
  free(k);
  *edges = out;
  return ne;
}

/* The four faces of every tet, oriented outward (for a positive tet). */
static key3 *face_keys(const tb_mesh *m) {
  static const int opp[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  key3 *k = malloc(sizeof *k * (4 * (size_t)m->ntet + 1));
  if (!k) return NULL;
  for (int t = 0; t < m->ntet; t++) {
    const int *v = m->tet + 4 * t;
    int flip = tet_vol(m, t) < 0.0;
    for (int j = 0; j < 4; j++) {
      key3 *q = &k[4 * t + j];
      q->f[0] = v[opp[j][0]];
      q->f[1] = v[opp[j][flip ? 2 : 1]];
      q->f[2] = v[opp[j][flip ? 1 : 2]];
      memcpy(q->k, q->f, sizeof q->k);
      sort3(q->k);
      q->src = t;
    }
  }
  qsort(k, 4 * (size_t)m->ntet, sizeof *k, cmp_key3);
  return k;
}

/* Distinct faces (boundary_only: those of exactly one tet, oriented). */
static int collect_faces(const tb_mesh *m, int **faces, int boundary_only) {
  key3 *k = face_keys(m);
  int *out = malloc(sizeof(int) * 3 * (4 * (size_t)m->ntet + 1));
  if (!k || !out) {
    free(k), free(out);
    return -1;
  }
  int n = 4 * m->ntet, nf = 0;
  for (int i = 0; i < n;) {
    int j = i + 1;
    while (j < n && same_key(&k[j], &k[i])) j++;
    if (!boundary_only || j - i == 1) {
      memcpy(out + 3 * nf, boundary_only ? k[i].f : k[i].k, 3 * sizeof(int));
      nf++;
    }
    i = j;
  }
  free(k);
  *faces = out;
  return nf;
}

int tb_mesh_tet_faces(const tb_mesh *m, int **faces) { return collect_faces(m, faces, 0); }
int tb_mesh_tet_boundary(const tb_mesh *m, int **faces) { return collect_faces(m, faces, 1); }

/* ---- topology of the triangles ---- */
static int find(int *parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}
static void unite(int *parent, int a, int b) { parent[find(parent, a)] = find(parent, b); }

/* Is the link of vertex v (the opposite edges of its triangles) one cycle or
 * one path?  tris: the triangles around v. */
static int vertex_is_manifold(const tb_mesh *m, int v, const int *tris, int n, int *scratch) {
  /* local ids: scratch holds up to 2n link vertices, then 2n parents/degrees */
  int *ids = scratch, *deg = scratch + 2 * n, *par = scratch + 4 * n, nl = 0;
  for (int i = 0; i < n; i++) {
    const int *t = m->tri + 3 * tris[i];
    int loc[2], c = 0;
    for (int j = 0; j < 3; j++) {
      if (t[j] == v) continue;
      int l = 0;
      while (l < nl && ids[l] != t[j]) l++;
      if (l == nl) ids[nl] = t[j], deg[nl] = 0, par[nl] = nl, nl++;
      if (c < 2) loc[c++] = l;
    }
    if (c != 2) return 0; /* degenerate triangle around v */
    deg[loc[0]]++, deg[loc[1]]++;
    unite(par, loc[0], loc[1]);
  }
  int ends = 0;
  for (int l = 0; l < nl; l++) {
    if (deg[l] > 2 || find(par, l) != find(par, 0)) return 0;
    ends += deg[l] == 1;
  }
  return ends == 0 || ends == 2;
}

tb_mesh_topo tb_mesh_topology(const tb_mesh *m) {
  tb_mesh_topo r;
  memset(&r, 0, sizeof r);
  int nk, nv = m->nv, nt = m->ntri;
  tb_mesh surf = *m;
  surf.ntet = 0;
  key3 *k = edge_keys(&surf, &nk);
  int *start = calloc((size_t)nv + 1, sizeof(int));
  int *vt = malloc(sizeof(int) * (3 * (size_t)nt + 1));
  int *par = malloc(sizeof(int) * ((size_t)nv + 1));
  int *scratch = NULL;
  if (!k || !start || !vt || !par) goto done;
  /* edges */
  for (int i = 0; i < nk;) {
    int j = i + 1;
    while (j < nk && same_key(&k[j], &k[i])) j++;
    r.nedges++;
    if (j - i == 1)
      r.boundary_edges++;
    else if (j - i > 2)
      r.nonmanifold_edges++;
    else if (k[i].f[0] == k[i + 1].f[0])
      r.misoriented_edges++;
    i = j;
  }
  /* vertex -> triangles, components, used vertices */
  for (int v = 0; v < nv; v++) par[v] = v;
  int maxdeg = 0;
  for (int t = 0; t < nt; t++) {
    const int *f = m->tri + 3 * t;
    if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) r.degenerate_tris++;
    for (int j = 0; j < 3; j++) start[f[j] + 1]++;
    unite(par, f[0], f[1]), unite(par, f[1], f[2]);
  }
  for (int v = 0; v < nv; v++) {
    if (start[v + 1] > maxdeg) maxdeg = start[v + 1];
    start[v + 1] += start[v];
  }
  int *fill = malloc(sizeof(int) * ((size_t)nv + 1));
  scratch = malloc(sizeof(int) * (6 * (size_t)maxdeg + 1));
  if (!fill || !scratch) {
    free(fill);
    goto done;
  }
  memcpy(fill, start, sizeof(int) * (size_t)nv);
  for (int t = 0; t < nt; t++)
    for (int j = 0; j < 3; j++) vt[fill[m->tri[3 * t + j]]++] = t;
  free(fill);
  int used = 0;
  for (int v = 0; v < nv; v++) {
    int n = start[v + 1] - start[v];
    if (n == 0) {
      r.unused_verts++;
      continue;
    }
    used++;
    if (find(par, v) == v) r.components++;
    if (!vertex_is_manifold(m, v, vt + start[v], n, scratch)) r.nonmanifold_verts++;
  }
  r.euler = used - r.nedges + nt;
  r.closed = nt > 0 && r.boundary_edges == 0;
  r.manifold =
      nt > 0 && r.nonmanifold_edges == 0 && r.nonmanifold_verts == 0 && r.degenerate_tris == 0;
done:
  free(k), free(start), free(vt), free(par), free(scratch);
  return r;
}
