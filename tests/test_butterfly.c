/* Half-edge surfaces and the modified butterfly scheme (Bao 2006 §3.1, §3.4; Zorin et al.
 * 1996): the half-edge invariants and errors, every stencil against points computed here with
 * explicit weights on meshes whose valences and rings are known by construction, the
 * subdivision's counts, topology and quadtree numbering, flat patches, the geodesic sphere, and
 * `tissuebench mesh subdivide`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_butterfly.h"
#include "core/tb_mesh_io.h"
#include "meshgen/tb_meshgen.h"

/* ---- meshes with known structure ---- */
static void alloc_mesh(tb_mesh *m, int nv, int nf) {
  memset(m, 0, sizeof *m);
  m->nv = nv, m->ntri = nf;
  m->x = calloc((size_t)nv, sizeof(tb_vec3));
  m->tri = calloc(3 * (size_t)nf, sizeof(int));
}

static void set_tri(tb_mesh *m, int f, int a, int b, int c) {
  m->tri[3 * f] = a, m->tri[3 * f + 1] = b, m->tri[3 * f + 2] = c;
}

/* The wheel: C (0) with ring R_j = 1 + j (j < k) on top; under R_0 the fan R_1, X_0, ...,
 * X_{m-1}, R_{k-1} (X_i = 1 + k + i), the rest closed by D = 1 + k + m. Valences: C k, R_0 3 + m.
 * Triangles (C, R_j, R_{j+1}) come first, so out[C] = 0 and C's ring is R_0, R_1, ..., and
 * R_0's ring from C is C, R_{k-1}, X_{m-1}, ..., X_0, R_1. Positions: generic (no symmetry). */
enum { C = 0 };
#define R(j) (1 + (j))
#define X(i) (1 + k + (i))
static void wheel(int k, int m, tb_mesh *w) {
  int D = 1 + k + m, f = 0;
  alloc_mesh(w, k + m + 2, k + (m + 1) + (m + 1) + (k - 2));
  for (int j = 0; j < k; j++) set_tri(w, f++, C, R(j), R((j + 1) % k));
  set_tri(w, f++, R(0), X(0), R(1));
  for (int i = 0; i + 1 < m; i++) set_tri(w, f++, R(0), X(i + 1), X(i));
  set_tri(w, f++, R(0), R(k - 1), X(m - 1));
  set_tri(w, f++, D, R(1), X(0));
  for (int i = 0; i + 1 < m; i++) set_tri(w, f++, D, X(i), X(i + 1));
  set_tri(w, f++, D, X(m - 1), R(k - 1));
  for (int j = 1; j <= k - 2; j++) set_tri(w, f++, D, R(j + 1), R(j));
  w->x[C] = tb_v3(0.1, -0.05, 1.2);
  for (int j = 0; j < k; j++) {
    double t = 2 * M_PI * j / k;
    w->x[R(j)] = tb_v3(cos(t) * (1 + 0.1 * j), sin(t) * (1 - 0.03 * j * j), 0.07 * j);
  }
  for (int i = 0; i < m; i++) w->x[X(i)] = tb_v3(0.6 - 0.1 * i, 0.3 * i - 0.2, -0.5 - 0.05 * i);
  w->x[D] = tb_v3(0.02, 0.03, -1.1);
}

/* Torus grid n1 x n2, vertex (i, j) = i n2 + j, cells split along (i, j)-(i+1, j+1): every
 * vertex has valence 6, neighbours (±1, 0), (0, ±1), ±(1, 1). Perturbed torus positions. */
static int tv(int n1, int n2, int i, int j) {
  return ((i % n1 + n1) % n1) * n2 + (j % n2 + n2) % n2;
}
static void torus(int n1, int n2, tb_mesh *t) {
  alloc_mesh(t, n1 * n2, 2 * n1 * n2);
  for (int i = 0; i < n1; i++)
    for (int j = 0; j < n2; j++) {
      double u = 2 * M_PI * i / n1, v = 2 * M_PI * j / n2, r = 3 + cos(v) + 0.1 * sin(7.0 * i + j);
      t->x[tv(n1, n2, i, j)] = tb_v3(r * cos(u), r * sin(u), sin(v) + 0.05 * cos(3.0 * j + i));
      int f = 2 * (i * n2 + j);
      set_tri(t, f, tv(n1, n2, i, j), tv(n1, n2, i + 1, j), tv(n1, n2, i + 1, j + 1));
      set_tri(t, f + 1, tv(n1, n2, i, j), tv(n1, n2, i + 1, j + 1), tv(n1, n2, i, j + 1));
    }
}

static int find_he(const tb_halfedge *he, int a, int b) {
  for (int h = 0; h < 3 * he->nf; h++)
    if (he->vert[h] == a && he->vert[tb_he_next(h)] == b) return h;
  return -1;
}

#define CHECK_V3(p, q, tol)           \
  do {                                \
    TB_CHECK_NEAR((p).x, (q).x, tol); \
    TB_CHECK_NEAR((p).y, (q).y, tol); \
    TB_CHECK_NEAR((p).z, (q).z, tol); \
  } while (0)

/* sum of w[i] x[v[i]] */
static tb_vec3 combo(const tb_vec3 *x, int n, const int *v, const double *w) {
  tb_vec3 p = tb_v3(0, 0, 0);
  for (int i = 0; i < n; i++) p = tb_madd(p, w[i], x[v[i]]);
  return p;
}

/* The butterfly point of edge (a, b) of m, from both half-edges (bit-identical), and the new
 * vertex tb_butterfly puts there, against `want`. */
static void check_edge(const tb_mesh *m, int a, int b, tb_vec3 want) {
  tb_halfedge he;
  tb_error err;
  TB_CHECK(tb_halfedge_build(&he, m->nv, m->ntri, m->tri, "t", &err) == 0);
  int h = find_he(&he, a, b);
  TB_CHECK_MSG(h >= 0, "no half-edge %d -> %d", a, b);
  if (h < 0) return;
  tb_vec3 p = tb_butterfly_point(&he, m->x, h), q = tb_butterfly_point(&he, m->x, he.pair[h]);
  CHECK_V3(p, want, 1e-12);
  TB_CHECK(!memcmp(&p, &q, sizeof p));
  tb_mesh out;
  int *mid = NULL;
  TB_CHECK(tb_butterfly(m, &out, &mid, &err) == 0);
  CHECK_V3(out.x[mid[h]], want, 1e-12);
  free(mid), tb_mesh_free(&out), tb_halfedge_free(&he);
}

/* ---- half-edges ---- */
static void halfedge_invariants(const tb_mesh *m, int euler) {
  tb_halfedge he;
  tb_error err;
  TB_CHECK_MSG(tb_halfedge_build(&he, m->nv, m->ntri, m->tri, "m", &err) == 0, "%s", err.msg);
  int nh = 3 * m->ntri, sumval = 0, ring[64];
  for (int h = 0; h < nh; h++) {
    TB_CHECK(he.pair[h] >= 0 && he.pair[h] != h && he.pair[he.pair[h]] == h);
    TB_CHECK(tb_he_next(tb_he_next(tb_he_next(h))) == h && tb_he_prev(tb_he_next(h)) == h);
    TB_CHECK(tb_he_face(tb_he_next(h)) == tb_he_face(h));
    TB_CHECK(he.vert[he.pair[h]] == he.vert[tb_he_next(h)]);
    TB_CHECK(he.vert[h] == m->tri[h]);
  }
  for (int v = 0; v < m->nv; v++) {
    TB_CHECK(he.vert[he.out[v]] == v);
    int k = tb_halfedge_valence(&he, v);
    TB_CHECK(tb_halfedge_ring(&he, v, ring, 64) == k && k <= 64);
    TB_CHECK(ring[0] == he.vert[tb_he_next(he.out[v])]);
    for (int j = 0; j < k; j++) /* (v, ring[j], ring[j+1]) is a triangle as oriented */
      TB_CHECK(tb_he_next(find_he(&he, v, ring[j])) == find_he(&he, ring[j], ring[(j + 1) % k]));
    sumval += k;
  }
  TB_CHECK(sumval % 2 == 0 && sumval == nh); /* 2E = 3F */
  TB_CHECK_MSG(m->nv - sumval / 2 + m->ntri == euler, "V - E + F = %d", m->nv - nh / 2 + m->ntri);
  tb_halfedge_free(&he);
}

static void halfedge_structure(void) {
  tb_mesh m;
  tb_error err;
  static const int nv[3] = {12, 42, 252};
  for (int i = 0; i < 3; i++) {
    TB_CHECK(tb_geosphere(nv[i], 1.0, &m, &err) == 0);
    halfedge_invariants(&m, 2);
    tb_halfedge he;
    TB_CHECK(tb_halfedge_build(&he, m.nv, m.ntri, m.tri, "s", &err) == 0);
    int n5 = 0, n6 = 0;
    for (int v = 0; v < m.nv; v++) {
      n5 += tb_halfedge_valence(&he, v) == 5;
      n6 += tb_halfedge_valence(&he, v) == 6;
    }
    TB_CHECK(n5 == 12 && n6 == m.nv - 12); /* icosahedron: all 5 */
    tb_halfedge_free(&he), tb_mesh_free(&m);
  }
  torus(9, 8, &m);
  halfedge_invariants(&m, 0);
  tb_mesh_free(&m);
  /* rings by construction: C's is R_0.., R_0's from out[R_0] = R_0 -> R_1 */
  int k = 5, mm = 3, ring[16];
  wheel(k, mm, &m);
  halfedge_invariants(&m, 2);
  tb_halfedge he;
  TB_CHECK(tb_halfedge_build(&he, m.nv, m.ntri, m.tri, "w", &err) == 0);
  TB_CHECK(he.out[C] == 0 && tb_halfedge_ring(&he, C, ring, 16) == k);
  for (int j = 0; j < k; j++) TB_CHECK(ring[j] == R(j));
  int want[6] = {R(1), C, R(k - 1), X(2), X(1), X(0)};
  TB_CHECK(tb_halfedge_ring(&he, R(0), ring, 3) == 6); /* max respected, valence returned */
  TB_CHECK(tb_halfedge_ring(&he, R(0), ring, 16) == 6 && !memcmp(ring, want, sizeof want));
  tb_halfedge_free(&he), tb_mesh_free(&m);
}

/* Consistent tetrahedron, then broken copies. */
static const int tet4[12] = {0, 1, 2, 0, 3, 1, 0, 2, 3, 1, 3, 2};
static void expect_build_error(int nv, int nf, const int *tri, const char *what, const char *w2) {
  tb_halfedge he;
  tb_error err = {{0}};
  int rc = tb_halfedge_build(&he, nv, nf, tri, "bad.obj", &err);
  TB_CHECK_MSG(rc != 0, "build should fail: %s", what);
  TB_CHECK_MSG(!strncmp(err.msg, "bad.obj: ", 9) && strstr(err.msg, what) && strstr(err.msg, w2),
               "'%s' lacks '%s' / '%s'", err.msg, what, w2);
  TB_CHECK(!he.vert && !he.pair && !he.out);
}

static void halfedge_errors(void) {
  tb_halfedge he;
  tb_error err;
  TB_CHECK(tb_halfedge_build(&he, 4, 4, tet4, "tet", &err) == 0);
  halfedge_invariants(&(tb_mesh){4, NULL, 4, (int *)tet4, 0, NULL, 0}, 2);
  tb_halfedge_free(&he);
  expect_build_error(4, 3, tet4, "edge (1, 2) is a boundary edge", "open");
  int flip[12];
  memcpy(flip, tet4, sizeof flip);
  flip[10] = 2, flip[11] = 3; /* (1, 2, 3) */
  expect_build_error(4, 4, flip, "edge (1, 2) is misoriented", "triangles 0 and 3");
  static const int three[9] = {0, 1, 2, 1, 0, 3, 0, 1, 4};
  expect_build_error(5, 3, three, "edge (0, 1) is non-manifold", "3 triangles");
  int bowtie[24];
  memcpy(bowtie, tet4, sizeof tet4);
  for (int i = 0; i < 12; i++) bowtie[12 + i] = tet4[i] ? tet4[i] + 3 : 0;
  expect_build_error(7, 8, bowtie, "vertex 0 is non-manifold", "not one fan");
  expect_build_error(5, 4, tet4, "vertex 4 is unused", "");
  int degen[12];
  memcpy(degen, tet4, sizeof degen);
  degen[5] = 0;
  expect_build_error(4, 4, degen, "triangle 1 (0, 3, 0) is degenerate", "");
  degen[5] = 7;
  expect_build_error(4, 4, degen, "triangle 1: vertex index 7 out of range", "");
  expect_build_error(4, 0, tet4, "no triangles", "");
}

/* ---- stencils ---- */
static void stencil_regular(void) {
  /* torus: edges along (1,0), (1,1), (0,1) with a, b, c by the grid */
  int n1 = 9, n2 = 8;
  tb_mesh m;
  torus(n1, n2, &m);
  static const int d[3][2] = {{1, 0}, {1, 1}, {0, 1}};
  static const int bc[3][6][2] = {
      {{1, 1}, {0, -1}, {0, 1}, {2, 1}, {-1, -1}, {1, -1}},
      {{1, 0}, {0, 1}, {0, -1}, {2, 1}, {-1, 0}, {1, 2}},
      {{1, 1}, {-1, 0}, {1, 0}, {1, 2}, {-1, -1}, {-1, 1}},
  };
  static const double w[8] = {0.5, 0.5, 0.125, 0.125, -0.0625, -0.0625, -0.0625, -0.0625};
  for (int e = 0; e < 3; e++)
    for (int s = 0; s < 4; s++) {
      int i = 2 * s + 1, j = 3 * s, v[8];
      v[0] = tv(n1, n2, i, j), v[1] = tv(n1, n2, i + d[e][0], j + d[e][1]);
      for (int q = 0; q < 6; q++) v[2 + q] = tv(n1, n2, i + bc[e][q][0], j + bc[e][q][1]);
      check_edge(&m, v[0], v[1], combo(m.x, 8, v, w));
    }
  tb_mesh_free(&m);
  /* the wheel with k = 6, m = 3: both ends regular, wings R_2, X_0, R_4, X_2 */
  int k = 6;
  wheel(k, 3, &m);
  int v[8] = {C, R(0), R(1), R(5), R(2), X(0), R(4), X(2)};
  check_edge(&m, C, R(0), combo(m.x, 8, v, w));
  tb_mesh_free(&m);
}

/* s_j for k = 3, 4, 5 (exact) and 7 (decimal), j = 0..k-1 */
static const double s3[3] = {5.0 / 12, -1.0 / 12, -1.0 / 12};
static const double s4[4] = {3.0 / 8, 0, -1.0 / 8, 0};
#define S5A 0.030901699437494742  /* (sqrt 5 - 1) / 40 */
#define S5B -0.080901699437494742 /* -(sqrt 5 + 1) / 40 */
static const double s5[5] = {0.35, S5A, S5B, S5B, S5A};
static const double s7[7] = {0.25,
                             0.10888990498293946,
                             -0.060429338272503428,
                             -0.048460566710436045,
                             -0.048460566710436045,
                             -0.060429338272503428,
                             0.10888990498293946};
static const double *sk(int k) { return k == 3 ? s3 : k == 4 ? s4 : k == 5 ? s5 : s7; }

static void stencil_one_irregular(void) {
  static const int ks[4] = {3, 4, 5, 7};
  for (int t = 0; t < 4; t++) {
    int k = ks[t], v[8];
    double w[8];
    tb_mesh m;
    wheel(k, 3, &m);
    tb_halfedge he;
    tb_error err;
    TB_CHECK(tb_halfedge_build(&he, m.nv, m.ntri, m.tri, "w", &err) == 0);
    TB_CHECK(tb_halfedge_valence(&he, C) == k && tb_halfedge_valence(&he, R(0)) == 6);
    tb_halfedge_free(&he);
    double sum = 0.75;
    v[0] = C, w[0] = 0.75;
    for (int j = 0; j < k; j++) v[1 + j] = R(j), w[1 + j] = sk(k)[j], sum += sk(k)[j];
    TB_CHECK_NEAR(sum, 1.0, 1e-15);
    check_edge(&m, C, R(0), combo(m.x, 1 + k, v, w));
    tb_mesh_free(&m);
  }
}

static void stencil_both_irregular(void) {
  /* C valence k, R_0 valence 3 + mm; R_0's ring from C: C, R_{k-1}, X_{mm-1}, ..., X_0, R_1 */
  static const int cases[2][2] = {{5, 4}, {3, 1}};
  for (int t = 0; t < 2; t++) {
    int k = cases[t][0], mm = cases[t][1], n = 3 + mm, v[16];
    double w[16];
    tb_mesh m;
    wheel(k, mm, &m);
    v[0] = C, w[0] = 0.75 / 2;
    for (int j = 0; j < k; j++) v[1 + j] = R(j), w[1 + j] = sk(k)[j] / 2;
    int *r = v + 1 + k, ring[16] = {C, R(k - 1)};
    for (int i = 0; i < mm; i++) ring[2 + i] = X(mm - 1 - i);
    ring[n - 1] = R(1);
    r[0] = R(0), w[1 + k] = 0.75 / 2;
    for (int j = 0; j < n; j++) r[1 + j] = ring[j], w[2 + k + j] = sk(n)[j] / 2;
    check_edge(&m, C, R(0), combo(m.x, 2 + k + n, v, w));
    tb_mesh_free(&m);
  }
}

/* ---- one level ---- */
/* Counts, old vertices bit-exact, closed oriented manifold of the same Euler characteristic,
 * edge numbering, midpoints and the quadtree numbering of the children. */
static void check_level(const tb_mesh *in, int euler) {
  tb_mesh out;
  tb_error err;
  int *mid = NULL, nf = in->ntri, ne = 3 * nf / 2;
  TB_CHECK_MSG(tb_butterfly(in, &out, &mid, &err) == 0, "%s", err.msg);
  if (!mid) return;
  TB_CHECK(out.nv == in->nv + ne && out.ntri == 4 * nf && out.ntet == 0);
  TB_CHECK(!memcmp(out.x, in->x, sizeof(tb_vec3) * (size_t)in->nv));
  tb_mesh_topo t = tb_mesh_topology(&out);
  TB_CHECK(t.closed && t.manifold && !t.misoriented_edges && t.euler == euler && !t.unused_verts);
  tb_halfedge he;
  TB_CHECK(tb_halfedge_build(&he, in->nv, nf, in->tri, "in", &err) == 0);
  int e = 0;
  for (int h = 0; h < 3 * nf; h++) {
    TB_CHECK(mid[h] == mid[he.pair[h]]);
    if (h < he.pair[h]) TB_CHECK(mid[h] == in->nv + e++);
    tb_vec3 p = tb_butterfly_point(&he, in->x, h);
    TB_CHECK(!memcmp(&out.x[mid[h]], &p, sizeof p));
  }
  TB_CHECK(e == ne);
  for (int f = 0; f < nf; f++) {
    const int *p = in->tri + 3 * f, *c = out.tri + 12 * f;
    int ab = mid[3 * f], bc = mid[3 * f + 1], ca = mid[3 * f + 2];
    int want[12] = {p[0], ab, ca, ab, p[1], bc, ca, bc, p[2], ab, bc, ca};
    TB_CHECK(!memcmp(c, want, sizeof want));
  }
  tb_halfedge_free(&he), free(mid), tb_mesh_free(&out);
}

static void subdivide_counts_topology(void) {
  tb_mesh m, m2;
  tb_error err;
  TB_CHECK(tb_geosphere(12, 1.0, &m, &err) == 0);
  check_level(&m, 2);
  TB_CHECK(tb_butterfly(&m, &m2, NULL, &err) == 0 && m2.nv == 42 && m2.ntri == 80);
  check_level(&m2, 2);
  tb_mesh_free(&m), tb_mesh_free(&m2);
  torus(9, 8, &m);
  check_level(&m, 0);
  tb_mesh_free(&m);
  for (int k = 3; k <= 7; k++) {
    wheel(k, 3, &m);
    check_level(&m, 2);
    tb_mesh_free(&m);
  }
  /* a pillow of two triangles: valence 2, no rule: the point is the edge's midpoint, and
   * tb_butterfly refuses it (its split would put four triangles on an edge) */
  static const int pillow[6] = {0, 1, 2, 0, 2, 1};
  tb_vec3 px[3] = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}};
  tb_mesh p = {3, px, 2, (int *)pillow, 0, NULL, 0};
  tb_halfedge he;
  TB_CHECK(tb_halfedge_build(&he, 3, 2, pillow, "pillow", &err) == 0);
  CHECK_V3(tb_butterfly_point(&he, px, 1), tb_v3(0.5, 1, 0), 0);
  tb_halfedge_free(&he);
  TB_CHECK(tb_butterfly(&p, &m2, NULL, &err) != 0 && strstr(err.msg, "vertex 0 has valence 2") &&
           !m2.x);
  TB_CHECK(tb_geosphere(252, 1.0, &m, &err) == 0);
  m.ntet = 1;
  TB_CHECK(tb_butterfly(&m, &m2, NULL, &err) != 0 && strstr(err.msg, "tet mesh"));
  m.ntet = 0;
  m.tri[4] = m.tri[3]; /* degenerate */
  TB_CHECK(tb_butterfly(&m, &m2, NULL, &err) != 0 && strstr(err.msg, "butterfly: ") &&
           strstr(err.msg, "degenerate") && !m2.x && !m2.tri);
  tb_mesh_free(&m);
}

/* Bao 2006 table 1: the 252-vertex sphere gives 1002 vertices and 2000 triangles. */
static void subdivide_sphere(void) {
  tb_mesh m, m2, m3;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &m, &err) == 0);
  check_level(&m, 2);
  TB_CHECK(tb_butterfly(&m, &m2, NULL, &err) == 0);
  TB_CHECK(m2.nv == 1002 && m2.ntri == 2000);
  double lo = 2, hi = 0;
  for (int i = 0; i < m2.nv; i++) lo = fmin(lo, tb_len(m2.x[i])), hi = fmax(hi, tb_len(m2.x[i]));
  TB_CHECK_MSG(lo > 0.99 && hi < 1.01, "radius in [%.6f, %.6f]", lo, hi);
  TB_CHECK(tb_butterfly(&m2, &m3, NULL, &err) == 0 && m3.nv == 4002 && m3.ntri == 8000);
  tb_mesh_free(&m), tb_mesh_free(&m2), tb_mesh_free(&m3);
}

/* A closed box, each face an n x n grid split along one diagonal (valence 6 inside a face),
 * turned; new points of edges between interior vertices of the top face stay on its plane. */
static void subdivide_flat_patch(void) {
  enum { n = 6, L = n + 1 };
  int *id = malloc(sizeof(int) * L * L * L), lat[L * L * L][3], nv = 0, nf = 0;
  tb_mesh m;
  alloc_mesh(&m, L * L * L, 12 * n * n);
  for (int i = 0; i < L * L * L; i++) id[i] = -1;
  tb_mat3 rot = tb_m3_rotation(tb_v3(1, 2, 3), 0.7);
  for (int a = 0; a < 3; a++)
    for (int side = 0; side <= n; side += n)
      for (int p = 0; p < n; p++)
        for (int q = 0; q < n; q++) {
          int c[4];
          for (int corner = 0; corner < 4; corner++) {
            int g[3];
            g[a] = side, g[(a + 1) % 3] = p + (corner == 1 || corner == 2);
            g[(a + 2) % 3] = q + (corner >= 2);
            int *s = &id[(g[0] * L + g[1]) * L + g[2]];
            if (*s < 0) {
              memcpy(lat[nv], g, sizeof g);
              m.x[nv] = tb_m3_mulv(rot, tb_v3(g[0] / (double)n - 0.5, g[1] / (double)n - 0.5,
                                              g[2] / (double)n - 0.5));
              *s = nv++;
            }
            c[corner] = *s;
          }
          if (side) /* outward +a: (p,q), (p+1,q), (p+1,q+1), (p,q+1) counter-clockwise */
            set_tri(&m, nf++, c[0], c[1], c[2]), set_tri(&m, nf++, c[0], c[2], c[3]);
          else
            set_tri(&m, nf++, c[0], c[2], c[1]), set_tri(&m, nf++, c[0], c[3], c[2]);
        }
  m.nv = nv;
  TB_CHECK(nv == 6 * n * n + 2 && nf == m.ntri);
  check_level(&m, 2);
  tb_halfedge he;
  tb_mesh out;
  tb_error err;
  int *mid = NULL, checked = 0;
  TB_CHECK(tb_halfedge_build(&he, m.nv, m.ntri, m.tri, "box", &err) == 0);
  TB_CHECK(tb_butterfly(&m, &out, &mid, &err) == 0);
  tb_vec3 normal = tb_m3_mulv(rot, tb_v3(0, 0, 1));
#define INNER_TOP(v) \
  (lat[v][2] == n && lat[v][0] > 0 && lat[v][0] < n && lat[v][1] > 0 && lat[v][1] < n)
  for (int v = 0; v < nv; v++)
    if (INNER_TOP(v)) TB_CHECK(tb_halfedge_valence(&he, v) == 6);
  for (int h = 0; h < 3 * m.ntri && mid; h++) {
    int a = he.vert[h], b = he.vert[he.pair[h]];
    if (h > he.pair[h] || !INNER_TOP(a) || !INNER_TOP(b)) continue;
    TB_CHECK_NEAR(tb_dot(normal, out.x[mid[h]]), 0.5, 1e-12);
    checked++;
  }
  TB_CHECK_MSG(checked == 3 * (n - 2) * (n - 2) + 2 * (n - 2), "%d edges checked", checked);
  free(mid), free(id), tb_mesh_free(&out), tb_mesh_free(&m), tb_halfedge_free(&he);
}

/* ---- the command line ---- */
static void cli_subdivide(void) {
  char args[2048], out[600];
  const char *dir = tb_test_tmpdir();
  snprintf(args, sizeof args, "mesh sphere --set verts=252 --out %s/s252.obj", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(out, sizeof out, "%s/s4002.off", dir);
  snprintf(args, sizeof args, "mesh subdivide %s/s252.obj --levels 2 --out %s", dir, out);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "    0       252        500") &&
                   strstr(tb_test_out, "    1      1002       2000") &&
                   strstr(tb_test_out, "    2      4002       8000"),
               "%s", tb_test_out);
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_mesh_read(out, &m, &err) == 0 && m.nv == 4002 && m.ntri == 8000);
  tb_mesh_topo t = tb_mesh_topology(&m);
  TB_CHECK(t.closed && t.manifold && t.euler == 2);
  tb_mesh_free(&m);
  static const struct {
    const char *file, *text, *reason;
  } bad[] = {
      {"open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\n", "open"},
      {"fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0 -1 0\nf 1 2 3\nf 2 1 4\nf 1 2 5\n",
       "non-manifold"},
      {"flip.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 3 4\n",
       "misoriented"},
      {"pillow.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 3 2\n", "valence 2"},
  };
  for (int i = 0; i < 4; i++) {
    const char *p = tb_test_file(bad[i].file, bad[i].text, -1);
    snprintf(args, sizeof args, "mesh subdivide %s --levels 1 --out %s/x.obj", p, dir);
    char prefix[600];
    snprintf(prefix, sizeof prefix, "%s: ", p);
    TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, prefix) &&
                     strstr(tb_test_out, bad[i].reason),
                 "%s: %s", bad[i].file, tb_test_out);
  }
  static const char *levels[] = {"0", "x", "7", "2x", ""};
  for (int i = 0; i < 5; i++) {
    snprintf(args, sizeof args, "mesh subdivide %s/s252.obj --levels '%s' --out %s/y.obj", dir,
             levels[i], dir);
    TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "[1, 6]"), "--levels %s: %s",
                 levels[i], tb_test_out);
  }
  snprintf(args, sizeof args, "mesh beam --out %s/beam.node", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh subdivide %s/beam.node --levels 1 --out %s/y.obj", dir, dir);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "tet mesh"));
  snprintf(args, sizeof args, "mesh subdivide %s/none.obj --levels 1 --out %s/y.obj", dir, dir);
  TB_CHECK(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "none.obj"));
  TB_CHECK(tb_test_cli_run("mesh subdivide --levels 1") == 2);
}

const tb_test_case tb_tests_butterfly[] = {
    {"halfedge_structure", halfedge_structure},
    {"halfedge_errors", halfedge_errors},
    {"stencil_regular", stencil_regular},
    {"stencil_one_irregular", stencil_one_irregular},
    {"stencil_both_irregular", stencil_both_irregular},
    {"subdivide_counts_topology", subdivide_counts_topology},
    {"subdivide_sphere", subdivide_sphere},
    {"subdivide_flat_patch", subdivide_flat_patch},
    {"cli_subdivide", cli_subdivide},
    {NULL, NULL},
};
