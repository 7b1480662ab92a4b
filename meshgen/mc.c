/* Marching cubes (thesis §2.3.2, after Lorensen & Cline 1987): the
 * isosurface f = iso of a grey-value volume as an indexed triangle mesh.
 * Vertices sit on grid edges at the linear interpolation point of eq. 2-3;
 * their normals interpolate the central-difference gradients of eq. 2-2.
 *
 * The 256-case table is not typed in: it is derived once from rules.
 * For a corner sign pattern, every cube face with sign changes gets
 * segments joining its crossing points, one segment per run of inside
 * corners around the face (so on an ambiguous face the two inside corners
 * are always cut off separately). A face's segments depend on that face's
 * four samples only, so the two cells sharing it agree and the surface has
 * no cracks. Each segment runs from the edge where the face cycle (counter-
 * clockwise seen from outside the cube) enters the inside run to the edge
 * where it leaves it; chained, the segments make closed loops on the cube,
 * and each loop is triangulated (shortest diagonals, never a diagonal
 * between two crossings on one face that the face's rule did not join, so
 * every mesh edge is used by exactly two triangles). The triangles face
 * from inside (f >= iso) to outside. */
#include <float.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"

#define MC_MAX_TRI 12

typedef struct mc_case {
  int ntri;
  signed char tri[3 * MC_MAX_TRI]; /* cube edge ids 0..11 */
} mc_case;

static mc_case mc_table[256];
static int mc_table_ready;

/* Corner c is at (c&1, c>>1&1, c>>2&1). Edge 4a + bb + 2bd runs along axis
 * a from the corner with bit a clear; bb, bd are the bits of the corner on
 * the axes a+1 and a+2 (mod 3). */
static int mc_bit(int c, int axis) { return (c >> axis) & 1; }

static int mc_edge_start(int e) {
  int a = e / 4, b = (a + 1) % 3, d = (a + 2) % 3;
  return ((e & 1) << b) | (((e >> 1) & 1) << d);
}

static int mc_edge_of(int u, int v) {
  int diff = u ^ v, a = diff == 1 ? 0 : (diff == 2 ? 1 : 2);
  int s = u & ~diff;
  return 4 * a + mc_bit(s, (a + 1) % 3) + 2 * mc_bit(s, (a + 2) % 3);
}

static tb_vec3 mc_edge_mid(int e) {
  int s = mc_edge_start(e), a = e / 4;
  double p[3] = {mc_bit(s, 0), mc_bit(s, 1), mc_bit(s, 2)};
  p[a] = 0.5;
  return tb_v3(p[0], p[1], p[2]);
}

/* Do cube edges e and f lie on a common cube face? */
static int mc_share_face(int e, int f) {
  int se = mc_edge_start(e), sf = mc_edge_start(f);
  for (int ax = 0; ax < 3; ax++)
    if (ax != e / 4 && ax != f / 4 && mc_bit(se, ax) == mc_bit(sf, ax)) return 1;
  return 0;
}

/* Triangulates the loop lp[0..n-1] (min total diagonal length, dynamic
 * programming over sub-polygons) into out; returns triangles written or -1. */
static int mc_triangulate(const int *lp, int n, signed char *out) {
  double cost[12][12];
  int split[12][12];
  for (int i = 0; i < n; i++)
    for (int j = 0; j < n; j++) cost[i][j] = 0.0, split[i][j] = -1;
  for (int len = 2; len < n; len++)
    for (int i = 0; i + len < n; i++) {
      int j = i + len;
      cost[i][j] = DBL_MAX;
      int chord = !(i == 0 && j == n - 1);
      if (chord && mc_share_face(lp[i], lp[j])) continue; /* forbidden */
      double w = chord ? tb_dist(mc_edge_mid(lp[i]), mc_edge_mid(lp[j])) : 0.0;
      for (int k = i + 1; k < j; k++) {
        if (cost[i][k] == DBL_MAX || cost[k][j] == DBL_MAX) continue;
        double c = cost[i][k] + cost[k][j] + w;
        if (c < cost[i][j]) cost[i][j] = c, split[i][j] = k;
      }
    }
  if (split[0][n - 1] < 0) return -1;
  int stack[64], top = 0, nt = 0;
  stack[top++] = 0, stack[top++] = n - 1;
  while (top > 0) {
    int j = stack[--top], i = stack[--top];
    if (j - i < 2) continue;
    int k = split[i][j];
    out[3 * nt] = (signed char)lp[i], out[3 * nt + 1] = (signed char)lp[k];
    out[3 * nt + 2] = (signed char)lp[j];
    nt++;
    stack[top++] = i, stack[top++] = k, stack[top++] = k, stack[top++] = j;
  }
  return nt;
}

/* Builds one case; returns 0, or -1 when the rules fail (never expected). */
static int mc_build_case(int cfg, mc_case *mcase) {
  int next[12];
  for (int e = 0; e < 12; e++) next[e] = -1;
  for (int a = 0; a < 3; a++)
    for (int side = 0; side < 2; side++) {
      int b = (a + 1) % 3, d = (a + 2) % 3, q[4];
      static const int cyc[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
      for (int k = 0; k < 4; k++) {
        int kk = side ? k : 3 - k; /* counter-clockwise seen from outside */
        q[k] = (side << a) | (cyc[kk][0] << b) | (cyc[kk][1] << d);
      }
      for (int k = 0; k < 4; k++) {
        int prev = (k + 3) % 4;
        if (!mc_bit(cfg, q[k]) || mc_bit(cfg, q[prev])) continue; /* run start */
        int end = k;
        while (mc_bit(cfg, q[(end + 1) % 4])) end = (end + 1) % 4;
        int ein = mc_edge_of(q[prev], q[k]), eout = mc_edge_of(q[end], q[(end + 1) % 4]);
        if (next[ein] >= 0) return -1;
        next[ein] = eout;
      }
    }
  int used[12] = {0};
  mcase->ntri = 0;
  for (int e0 = 0; e0 < 12; e0++) {
    if (next[e0] < 0 || used[e0]) continue;
    int lp[12], n = 0, e = e0;
    do {
      if (n == 12 || e < 0 || used[e]) return -1;
      used[e] = 1;
      lp[n++] = e;
      e = next[e];
    } while (e != e0);
    if (n < 3) return -1;
    int nt = mc_triangulate(lp, n, mcase->tri + 3 * mcase->ntri);
    if (nt < 0 || mcase->ntri + nt > MC_MAX_TRI) return -1;
    mcase->ntri += nt;
  }
  return 0;
}

static int mc_table_init(void) {
  if (mc_table_ready) return 0;
  for (int cfg = 0; cfg < 256; cfg++)
    if (mc_build_case(cfg, &mc_table[cfg]) != 0) return -1;
  mc_table_ready = 1;
  return 0;
}

void tb_volume_free(tb_volume *v) {
  if (!v) return;
  free(v->f);
  v->f = NULL;
  v->nx = v->ny = v->nz = 0;
}

typedef struct mc_grow {
  int n, cap, elem;
  void *p;
} mc_grow;

static int mc_reserve(mc_grow *g, int more) {
  if (g->n + more <= g->cap) return 0;
  int cap = g->cap ? g->cap : 256;
  while (cap < g->n + more) {
    if (cap > INT32_MAX / 2) return -1;
    cap *= 2;
  }
  void *p = realloc(g->p, (size_t)cap * (size_t)g->elem);
  if (!p) return -1;
  g->p = p, g->cap = cap;
  return 0;
}

/* Central-difference gradient (eq. 2-2), one-sided at the border. */
static tb_vec3 mc_gradient(const tb_volume *v, int i, int j, int k) {
  int n[3] = {v->nx, v->ny, v->nz}, c[3] = {i, j, k};
  double h[3] = {v->h.x, v->h.y, v->h.z}, g[3];
  size_t stride[3] = {1, (size_t)v->nx, (size_t)v->nx * (size_t)v->ny};
  size_t at = ((size_t)k * (size_t)v->ny + (size_t)j) * (size_t)v->nx + (size_t)i;
  for (int a = 0; a < 3; a++) {
    int lo = c[a] > 0, hi = c[a] < n[a] - 1;
    double f1 = v->f[hi ? at + stride[a] : at], f0 = v->f[lo ? at - stride[a] : at];
    g[a] = (lo + hi) ? (f1 - f0) / ((lo + hi) * h[a]) : 0.0;
  }
  return tb_v3(g[0], g[1], g[2]);
}

static int mc_check(const tb_volume *v, double iso, tb_error *err) {
  if (!v || !v->f) return tb_error_set(err, "marching cubes", 0, "no volume samples");
  if (v->nx < 2 || v->ny < 2 || v->nz < 2)
    return tb_error_set(err, "marching cubes", 0, "volume is %dx%dx%d, needs at least 2x2x2", v->nx,
                        v->ny, v->nz);
  if ((double)v->nx * v->ny * v->nz > (double)INT32_MAX / 3)
    return tb_error_set(err, "marching cubes", 0, "volume %dx%dx%d is too large", v->nx, v->ny,
                        v->nz);
  if (!(v->h.x > 0 && v->h.y > 0 && v->h.z > 0) || !tb_isfinite3(v->h) || !tb_isfinite3(v->origin))
    return tb_error_set(err, "marching cubes", 0, "spacing must be positive and finite");
  if (!isfinite(iso)) return tb_error_set(err, "marching cubes", 0, "isovalue is not finite");
  for (int k = 0; k < v->nz; k++)
    for (int j = 0; j < v->ny; j++)
      for (int i = 0; i < v->nx; i++) {
        double f = v->f[((size_t)k * v->ny + j) * v->nx + i];
        if (!isfinite(f))
          return tb_error_set(err, "marching cubes", 0, "sample (%d,%d,%d) is not finite", i, j, k);
        int border =
            i == 0 || j == 0 || k == 0 || i == v->nx - 1 || j == v->ny - 1 || k == v->nz - 1;
        if (border && f >= iso)
          return tb_error_set(err, "marching cubes", 0,
                              "border sample (%d,%d,%d) is inside (f >= iso): pad the volume", i, j,
                              k);
      }
  return 0;
}

int tb_marching_cubes(const tb_volume *v, double iso, tb_mesh *out, tb_vec3 **normals,
                      tb_error *err) {
  memset(out, 0, sizeof *out);
  if (normals) *normals = NULL;
  if (mc_check(v, iso, err)) return -1;
  if (mc_table_init())
    return tb_error_set(err, "marching cubes", 0, "internal error building the case table");
  int nx = v->nx, ny = v->ny, nz = v->nz;
  size_t nsamp = (size_t)nx * ny * nz;
  int *edge_vert = malloc(3 * nsamp * sizeof *edge_vert);
  mc_grow xs = {0, 0, sizeof(tb_vec3), NULL}, ns = {0, 0, sizeof(tb_vec3), NULL};
  mc_grow ts = {0, 0, 3 * sizeof(int), NULL};
  if (!edge_vert) return tb_error_set(err, "marching cubes", 0, "out of memory");
  for (size_t s = 0; s < 3 * nsamp; s++) edge_vert[s] = -1;
  double hh[3] = {v->h.x, v->h.y, v->h.z};
  for (int k = 0; k + 1 < nz; k++)
    for (int j = 0; j + 1 < ny; j++)
      for (int i = 0; i + 1 < nx; i++) {
        int cfg = 0;
        for (int c = 0; c < 8; c++) {
          size_t at =
              ((size_t)(k + mc_bit(c, 2)) * ny + (j + mc_bit(c, 1))) * nx + (i + mc_bit(c, 0));
          if (v->f[at] >= iso) cfg |= 1 << c;
        }
        const mc_case *mcase = &mc_table[cfg];
        if (mcase->ntri == 0) continue;
        if (mc_reserve(&ts, mcase->ntri)) goto oom;
        for (int t = 0; t < 3 * mcase->ntri; t++) {
          int e = mcase->tri[t], a = e / 4, s = mc_edge_start(e);
          int c0[3] = {i + mc_bit(s, 0), j + mc_bit(s, 1), k + mc_bit(s, 2)};
          size_t at0 = ((size_t)c0[2] * ny + c0[1]) * nx + c0[0];
          int *slot = &edge_vert[3 * at0 + (size_t)a];
          if (*slot < 0) {
            int c1[3] = {c0[0], c0[1], c0[2]};
            c1[a]++;
            size_t at1 = ((size_t)c1[2] * ny + c1[1]) * nx + c1[0];
            double f0 = v->f[at0], f1 = v->f[at1], df = f1 - f0;
            double tt = df != 0.0 ? (iso - f0) / df : 0.5; /* eq. 2-3 */
            tt = tt < 0.0 ? 0.0 : (tt > 1.0 ? 1.0 : tt);
            double p0[3] = {c0[0] * hh[0], c0[1] * hh[1], c0[2] * hh[2]};
            p0[a] += tt * hh[a];
            if (mc_reserve(&xs, 1) || (normals && mc_reserve(&ns, 1))) goto oom;
            ((tb_vec3 *)xs.p)[xs.n] = tb_add(v->origin, tb_v3(p0[0], p0[1], p0[2]));
            if (normals) {
              tb_vec3 g = tb_lerp(mc_gradient(v, c0[0], c0[1], c0[2]),
                                  mc_gradient(v, c1[0], c1[1], c1[2]), tt);
              /* inside is f > iso, so outward is -grad f; a flat spot
               * falls back to the edge direction towards its outside end */
              if (!(tb_len(g) > 0.0)) g = tb_v3(a == 0 ? df : 0, a == 1 ? df : 0, a == 2 ? df : 0);
              ((tb_vec3 *)ns.p)[ns.n++] = tb_normalize(tb_scale(g, -1.0));
            }
            *slot = xs.n++;
          }
          ((int *)ts.p)[3 * ts.n + t] = *slot;
        }
        ts.n += mcase->ntri;
      }
  free(edge_vert);
  out->nv = xs.n, out->x = xs.p;
  out->ntri = ts.n, out->tri = ts.p;
  if (normals) *normals = ns.p;
  return 0;
oom:
  free(edge_vert);
  free(xs.p), free(ns.p), free(ts.p);
  return tb_error_set(err, "marching cubes", 0, "out of memory");
}
