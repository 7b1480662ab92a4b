/* Tests of marching cubes (meshgen/mc.c), the surface clean-up
 * (meshgen/remesh.c) and the synthetic liver surface (meshgen/liver.c). */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "tb_test.h"
#include "core/tb_rng.h"
#include "meshgen/tb_meshgen.h"

#define PI 3.14159265358979323846

typedef double (*field_fn)(tb_vec3 p);

/* n^3 samples on [-half, half]^3. */
static tb_volume sample(int n, double half, field_fn fn) {
  tb_volume v = {n, n, n, tb_v3(-half, -half, -half), tb_v3(0, 0, 0), NULL};
  double h = 2.0 * half / (n - 1);
  v.h = tb_v3(h, h, h);
  v.f = malloc((size_t)n * n * n * sizeof *v.f);
  if (!v.f) return v;
  for (int k = 0; k < n; k++)
    for (int j = 0; j < n; j++)
      for (int i = 0; i < n; i++)
        v.f[((size_t)k * n + j) * n + i] = fn(tb_v3(-half + i * h, -half + j * h, -half + k * h));
  return v;
}

/* off-centre so that no sample lies exactly on the sphere */
static const tb_vec3 sphere_c = {0.0123, -0.0071, 0.0047};
static double f_sphere(tb_vec3 p) { return 1.0 - tb_dist(p, sphere_c); }
static double f_blobs(tb_vec3 p) {
  return fmax(0.8 - tb_dist(p, tb_v3(-1.1, 0, 0)), 0.7 - tb_dist(p, tb_v3(1.1, 0.1, 0)));
}
static double f_torus(tb_vec3 p) {
  double q = hypot(p.x, p.y) - 1.0;
  return 0.4 - hypot(q, p.z);
}

/* Closed, manifold, consistently oriented, no degenerate index triples. */
static void check_closed(const tb_mesh *m, tb_mesh_topo *out) {
  tb_mesh_topo t = tb_mesh_topology(m);
  TB_CHECK_MSG(t.closed && t.manifold && t.misoriented_edges == 0 && t.degenerate_tris == 0 &&
                   t.unused_verts == 0,
               "closed %d manifold %d misoriented %d degenerate %d unused %d", t.closed, t.manifold,
               t.misoriented_edges, t.degenerate_tris, t.unused_verts);
  if (out) *out = t;
}

static double min_angle_deg(const tb_mesh *m) {
  double worst = 180.0;
  for (int t = 0; t < m->ntri; t++)
    for (int c = 0; c < 3; c++) {
      tb_vec3 a = m->x[m->tri[3 * t + c]], b = m->x[m->tri[3 * t + (c + 1) % 3]],
              d = m->x[m->tri[3 * t + (c + 2) % 3]];
      tb_vec3 u = tb_sub(b, a), w = tb_sub(d, a);
      double cs = tb_dot(u, w) / (tb_len(u) * tb_len(w));
      double ang = acos(fmax(-1.0, fmin(1.0, cs))) * 180.0 / PI;
      if (!(ang >= worst)) worst = ang;
    }
  return worst;
}

static int count_short(const tb_mesh *m, double len) {
  int n = 0;
  for (int t = 0; t < m->ntri; t++)
    for (int c = 0; c < 3; c++)
      n += tb_dist(m->x[m->tri[3 * t + c]], m->x[m->tri[3 * t + (c + 1) % 3]]) < len;
  return n / 2;
}

static int cmp_vec(const void *pa, const void *pb) {
  const tb_vec3 *a = pa, *b = pb;
  if (a->x != b->x) return a->x < b->x ? -1 : 1;
  if (a->y != b->y) return a->y < b->y ? -1 : 1;
  return (a->z > b->z) - (a->z < b->z);
}

static void test_sphere(void) {
  tb_volume v = sample(51, 1.25, f_sphere);
  tb_mesh m;
  tb_vec3 *nrm = NULL;
  tb_error err;
  TB_CHECK(tb_marching_cubes(&v, 0.0, &m, &nrm, &err) == 0);
  tb_mesh_topo t;
  check_closed(&m, &t);
  TB_CHECK(t.euler == 2 && t.components == 1);
  TB_CHECK_NEAR(tb_mesh_volume(&m) / (4.0 / 3.0 * PI), 1.0, 0.01);
  TB_CHECK_NEAR(tb_mesh_area(&m) / (4.0 * PI), 1.0, 0.01);
  double worst = 0.0;
  for (int i = 0; i < m.nv; i++) {
    tb_vec3 r = tb_sub(m.x[i], sphere_c);
    TB_CHECK_NEAR(tb_len(r), 1.0, 1e-3); /* eq. 2-3 on a distance field */
    double ang = acos(fmin(1.0, tb_dot(nrm[i], tb_normalize(r)))) * 180.0 / PI;
    worst = fmax(worst, ang);
  }
  TB_CHECK_MSG(worst < 3.0, "normal off the radial direction by %g deg", worst);
  /* one vertex per grid edge: no two vertices at the same place */
  tb_vec3 *xs = malloc((size_t)m.nv * sizeof *xs);
  memcpy(xs, m.x, (size_t)m.nv * sizeof *xs);
  qsort(xs, (size_t)m.nv, sizeof *xs, cmp_vec);
  int dup = 0;
  for (int i = 1; i < m.nv; i++) dup += cmp_vec(&xs[i - 1], &xs[i]) == 0;
  TB_CHECK(dup == 0);
  free(xs), free(nrm);
  tb_mesh_free(&m);
  tb_volume_free(&v);
}

static void test_blobs_torus(void) {
  tb_volume v = sample(48, 2.2, f_blobs);
  tb_mesh m;
  tb_mesh_topo t;
  TB_CHECK(tb_marching_cubes(&v, 0.0, &m, NULL, NULL) == 0);
  check_closed(&m, &t);
  TB_CHECK_MSG(t.components == 2 && t.euler == 4, "components %d euler %d", t.components, t.euler);
  TB_CHECK_NEAR(tb_mesh_volume(&m) / (4.0 / 3.0 * PI * (0.512 + 0.343)), 1.0, 0.02);
  tb_mesh_free(&m);
  tb_volume_free(&v);
  v = sample(61, 1.6, f_torus);
  TB_CHECK(tb_marching_cubes(&v, 0.0, &m, NULL, NULL) == 0);
  check_closed(&m, &t);
  TB_CHECK_MSG(t.components == 1 && t.euler == 0, "components %d euler %d", t.components, t.euler);
  TB_CHECK_NEAR(tb_mesh_volume(&m) / (2.0 * PI * PI * 0.16), 1.0, 0.02);
  tb_mesh_free(&m);
  tb_volume_free(&v);
}

/* Components of the inside corners of one cube, joined along cube edges. */
static int corner_components(int cfg) {
  int lab[8], n = 0;
  for (int c = 0; c < 8; c++) lab[c] = -1;
  for (int c = 0; c < 8; c++) {
    if (!(cfg >> c & 1) || lab[c] >= 0) continue;
    int stack[8], top = 0;
    lab[c] = n, stack[top++] = c;
    while (top) {
      int u = stack[--top];
      for (int b = 0; b < 3; b++) {
        int w = u ^ (1 << b);
        if ((cfg >> w & 1) && lab[w] < 0) lab[w] = n, stack[top++] = w;
      }
    }
    n++;
  }
  return n;
}

/* Every corner pattern, embedded as the middle 2x2x2 samples of a 4x4x4
 * grid with an outside border, with three sets of random values. */
static void test_all_cases(void) {
  tb_rng rng = tb_rng_seed(7);
  double f[64];
  tb_volume v = {4, 4, 4, tb_v3(0, 0, 0), tb_v3(1, 1, 1), f};
  int bad = 0;
  for (int rep = 0; rep < 3; rep++)
    for (int cfg = 0; cfg < 256; cfg++) {
      for (int s = 0; s < 64; s++) f[s] = tb_rng_range(&rng, -1.0, -0.01);
      for (int c = 0; c < 8; c++) {
        int at = ((1 + (c >> 2 & 1)) * 4 + 1 + (c >> 1 & 1)) * 4 + 1 + (c & 1);
        f[at] = (cfg >> c & 1) ? tb_rng_range(&rng, 0.0, 1.0) : tb_rng_range(&rng, -1.0, -0.01);
      }
      tb_mesh m;
      tb_error err;
      if (tb_marching_cubes(&v, 0.0, &m, NULL, &err) != 0) {
        bad++;
        continue;
      }
      if (cfg == 0) {
        TB_CHECK(m.nv == 0 && m.ntri == 0);
        continue;
      }
      tb_mesh_topo t = tb_mesh_topology(&m);
      int ncomp = corner_components(cfg);
      int ok = t.closed && t.manifold && t.misoriented_edges == 0 && t.degenerate_tris == 0 &&
               t.components == ncomp && t.euler == 2 * ncomp && tb_mesh_volume(&m) > 0;
      if (!ok && bad++ < 5)
        TB_CHECK_MSG(0, "case %d: closed %d manifold %d misoriented %d components %d/%d euler %d",
                     cfg, t.closed, t.manifold, t.misoriented_edges, t.components, ncomp, t.euler);
      tb_mesh_free(&m);
    }
  TB_CHECK(bad == 0);
}

/* Random grey values (border outside): any mix of neighbouring cases. */
static void test_random_volumes(void) {
  for (uint64_t seed = 1; seed <= 20; seed++) {
    tb_rng rng = tb_rng_seed(seed);
    int n = 10;
    double f[1000];
    tb_volume v = {n, n, n, tb_v3(0, 0, 0), tb_v3(0.5, 0.5, 0.5), f};
    for (int k = 0; k < n; k++)
      for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
          int border = i == 0 || j == 0 || k == 0 || i == n - 1 || j == n - 1 || k == n - 1;
          f[(k * n + j) * n + i] = border ? -1.0 : tb_rng_range(&rng, -1.0, 1.0);
        }
    tb_mesh m;
    TB_CHECK(tb_marching_cubes(&v, 0.0, &m, NULL, NULL) == 0);
    tb_mesh_topo t;
    check_closed(&m, &t);
    TB_CHECK(t.euler % 2 == 0 && tb_mesh_volume(&m) > 0);
    tb_mesh_free(&m);
  }
}

static void test_mc_errors(void) {
  double f[27] = {0};
  tb_volume v = {3, 3, 3, tb_v3(0, 0, 0), tb_v3(1, 1, 1), f};
  tb_mesh m;
  tb_error err;
  f[13] = 0.5; /* the centre sample equals iso: inside, a zero-size octahedron */
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) == 0);
  tb_mesh_topo t;
  check_closed(&m, &t);
  TB_CHECK(m.nv == 6 && m.ntri == 8 && t.euler == 2);
  for (int i = 0; i < m.nv; i++) TB_CHECK(tb_dist(m.x[i], tb_v3(1, 1, 1)) == 0.0);
  tb_mesh_free(&m);
  f[0] = 1.0; /* a border sample inside */
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) != 0 && strstr(err.msg, "border"));
  TB_CHECK(m.nv == 0 && m.x == NULL && m.tri == NULL);
  f[0] = 0.0, f[13] = NAN;
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) != 0 && strstr(err.msg, "not finite"));
  f[13] = 0.5;
  TB_CHECK(tb_marching_cubes(&v, NAN, &m, NULL, &err) != 0);
  v.nz = 1;
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) != 0 && strstr(err.msg, "2x2x2"));
  v.nz = 3, v.h.y = 0.0;
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) != 0 && strstr(err.msg, "spacing"));
  v.h.y = 1.0, v.f = NULL;
  TB_CHECK(tb_marching_cubes(&v, 0.5, &m, NULL, &err) != 0);
}

static void test_collapse(void) {
  tb_volume v = sample(23, 1.25, f_sphere);
  tb_mesh m;
  TB_CHECK(tb_marching_cubes(&v, 0.0, &m, NULL, NULL) == 0);
  double h = v.h.x, vol0 = tb_mesh_volume(&m);
  int short0 = count_short(&m, 0.25 * h), nv0 = m.nv;
  int nc = tb_remesh_collapse_short(&m, 0.25 * h);
  TB_CHECK(short0 > 0 && nc > 0 && nc == nv0 - m.nv);
  TB_CHECK_MSG(count_short(&m, 0.25 * h) * 5 < short0, "short edges %d -> %d", short0,
               count_short(&m, 0.25 * h));
  tb_mesh_topo t;
  check_closed(&m, &t);
  TB_CHECK(t.euler == 2 && t.components == 1 && m.ntri == 2 * m.nv - 4);
  TB_CHECK_NEAR(tb_mesh_volume(&m) / vol0, 1.0, 0.01);
  /* flips raise the smallest angle and keep the surface */
  double a0 = min_angle_deg(&m);
  TB_CHECK(tb_remesh_flip(&m) > 0);
  check_closed(&m, &t);
  TB_CHECK(t.euler == 2 && min_angle_deg(&m) > a0);
  TB_CHECK_NEAR(tb_mesh_volume(&m) / vol0, 1.0, 0.01);
  tb_mesh_free(&m);
  tb_volume_free(&v);
}

static void test_collapse_limits(void) {
  /* octahedron: collapses stop while the surface is still a closed manifold */
  tb_vec3 x[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  int tri[24] = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  tb_mesh m = {6, malloc(sizeof x), 8, malloc(sizeof tri), 0, NULL, 0};
  memcpy(m.x, x, sizeof x), memcpy(m.tri, tri, sizeof tri);
  tb_mesh_topo t;
  check_closed(&m, &t);
  int nc = tb_remesh_collapse_short(&m, 100.0);
  check_closed(&m, &t);
  TB_CHECK(nc >= 1 && m.nv >= 4 && m.nv == 6 - nc && t.euler == 2);
  for (int v = 0; v < m.nv; v++) {
    int val = 0;
    for (int i = 0; i < 3 * m.ntri; i++) val += m.tri[i] == v;
    TB_CHECK(val >= 3);
  }
  /* a tetrahedron admits no collapse; bad indices are refused */
  tb_mesh_free(&m);
  tb_vec3 y[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int tt[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  m = (tb_mesh){4, y, 4, tt, 0, NULL, 0};
  TB_CHECK(tb_remesh_collapse_short(&m, 100.0) == 0 && m.nv == 4 && m.ntri == 4);
  TB_CHECK(tb_remesh_flip(&m) == 0);
  tt[5] = 9;
  TB_CHECK(tb_remesh_collapse_short(&m, 1.0) == -1 && tb_remesh_flip(&m) == -1);
}

static double radial_rms(const tb_mesh *m) {
  double s = 0, mean = 0;
  for (int i = 0; i < m->nv; i++) mean += tb_dist(m->x[i], sphere_c) / m->nv;
  for (int i = 0; i < m->nv; i++) s += pow(tb_dist(m->x[i], sphere_c) - mean, 2);
  return sqrt(s / m->nv);
}

static void test_taubin(void) {
  tb_volume v = sample(31, 1.25, f_sphere);
  tb_mesh m, lap;
  TB_CHECK(tb_marching_cubes(&v, 0.0, &m, NULL, NULL) == 0);
  tb_rng rng = tb_rng_seed(3);
  for (int i = 0; i < m.nv; i++) {
    tb_vec3 r = tb_sub(m.x[i], sphere_c);
    m.x[i] = tb_madd(sphere_c, 1.0 + 0.02 * tb_rng_range(&rng, -1, 1), r);
  }
  double vol0 = tb_mesh_volume(&m), rms0 = radial_rms(&m);
  TB_CHECK(tb_mesh_copy(&lap, &m) == 0);
  tb_remesh_taubin(&m, 10, 0.5, -0.53);
  tb_remesh_taubin(&lap, 10, 0.5, 0.0); /* plain Laplacian: shrinks */
  TB_CHECK_NEAR(tb_mesh_volume(&m) / vol0, 1.0, 0.03);
  TB_CHECK(fabs(tb_mesh_volume(&m) - vol0) < 0.5 * fabs(tb_mesh_volume(&lap) - vol0));
  TB_CHECK_MSG(radial_rms(&m) < 0.5 * rms0, "radial rms %g -> %g", rms0, radial_rms(&m));
  tb_mesh_free(&m), tb_mesh_free(&lap);
  tb_volume_free(&v);
}

static int liver_ok(const tb_liver_def *d, tb_mesh *m) {
  tb_error err;
  if (tb_liver_surface(d, m, &err) != 0) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return 0;
  }
  tb_mesh_topo t;
  check_closed(m, &t);
  TB_CHECK_MSG(abs(m->nv - d->surface_verts) * 20 <= d->surface_verts, "%d vertices for %d", m->nv,
               d->surface_verts);
  TB_CHECK(t.components == 1 && t.euler == 2 && m->ntri == 2 * m->nv - 4);
  TB_CHECK(tb_mesh_volume(m) > 0);
  return 1;
}

static void test_liver(void) {
  tb_liver_def d = tb_liver_default_def();
  TB_CHECK(d.surface_verts == 725 && d.tet_verts == 1206 && d.length == 10.0 && d.seed == 1);
  tb_mesh a, b;
  clock_t c0 = clock();
  if (!liver_ok(&d, &a)) return;
  double secs = (double)(clock() - c0) / CLOCKS_PER_SEC;
  TB_CHECK_MSG(secs < 5.0, "liver surface took %g s", secs);
  tb_vec3 lo, hi;
  tb_mesh_bbox(&a, &lo, &hi);
  TB_CHECK_NEAR(hi.x - lo.x, 10.0, 0.5);
  TB_CHECK(hi.y - lo.y > 3.5 && hi.y - lo.y < 5.5 && hi.z - lo.z > 2.0 && hi.z - lo.z < 3.2);
  TB_CHECK_MSG(min_angle_deg(&a) > 15.0, "min angle %g deg", min_angle_deg(&a));
  /* same definition, same bytes; another seed, another liver */
  if (liver_ok(&d, &b)) {
    TB_CHECK(a.nv == b.nv && a.ntri == b.ntri);
    TB_CHECK(a.nv == b.nv && memcmp(a.x, b.x, (size_t)a.nv * sizeof *a.x) == 0);
    TB_CHECK(a.ntri == b.ntri && memcmp(a.tri, b.tri, (size_t)3 * a.ntri * sizeof(int)) == 0);
    tb_mesh_free(&b);
  }
  d.seed = 2;
  if (liver_ok(&d, &b)) {
    TB_CHECK(a.nv != b.nv || memcmp(a.x, b.x, (size_t)a.nv * sizeof *a.x) != 0);
    tb_mesh_free(&b);
  }
  tb_mesh_free(&a);
}

static void test_liver_resolutions(void) {
  tb_liver_def d = tb_liver_default_def();
  int targets[2] = {300, 3000};
  for (int i = 0; i < 2; i++) {
    tb_mesh m;
    d.surface_verts = targets[i];
    if (liver_ok(&d, &m)) tb_mesh_free(&m);
  }
  d = tb_liver_default_def();
  d.length = 20.0;
  tb_mesh m;
  if (liver_ok(&d, &m)) {
    tb_vec3 lo, hi;
    tb_mesh_bbox(&m, &lo, &hi);
    TB_CHECK_NEAR(hi.x - lo.x, 20.0, 1.0);
    tb_mesh_free(&m);
  }
}

/* The grey values: background outside, tissue inside, one component even
 * at the largest noise and a fine grid. */
static void test_liver_volume(void) {
  for (uint64_t seed = 1; seed <= 3; seed++) {
    tb_liver_def d = tb_liver_default_def();
    d.noise = 0.3, d.seed = seed;
    tb_volume v;
    double iso;
    tb_error err;
    TB_CHECK(tb_liver_volume(&d, 0.08, &v, &iso, &err) == 0);
    double lo = 1e9, hi = -1e9;
    size_t n = (size_t)v.nx * v.ny * v.nz;
    for (size_t s = 0; s < n; s++) lo = fmin(lo, v.f[s]), hi = fmax(hi, v.f[s]);
    TB_CHECK(iso == 0.5 && lo < 0.2 && hi > 0.8);
    tb_mesh m;
    TB_CHECK(tb_marching_cubes(&v, iso, &m, NULL, &err) == 0);
    tb_mesh_topo t;
    check_closed(&m, &t);
    TB_CHECK_MSG(t.components == 1 && t.euler == 2, "seed %d: components %d euler %d", (int)seed,
                 t.components, t.euler);
    tb_mesh_free(&m);
    tb_volume_free(&v);
  }
}

static void test_liver_errors(void) {
  tb_liver_def d = tb_liver_default_def();
  tb_mesh m;
  tb_volume v;
  double iso;
  tb_error err;
  d.length = 0;
  TB_CHECK(tb_liver_surface(&d, &m, &err) != 0 && strstr(err.msg, "length"));
  d.length = NAN;
  TB_CHECK(tb_liver_volume(&d, 0.5, &v, &iso, &err) != 0 && v.f == NULL);
  d = tb_liver_default_def();
  d.noise = -0.1;
  TB_CHECK(tb_liver_surface(&d, &m, &err) != 0 && strstr(err.msg, "noise"));
  d = tb_liver_default_def();
  d.surface_verts = 10;
  TB_CHECK(tb_liver_surface(&d, &m, &err) != 0 && strstr(err.msg, "surface_verts"));
  d = tb_liver_default_def();
  TB_CHECK(tb_liver_volume(&d, 0.0, &v, &iso, &err) != 0 && strstr(err.msg, "spacing"));
  TB_CHECK(tb_liver_volume(&d, 1e-4, &v, &iso, &err) != 0 && strstr(err.msg, "spacing"));
}

const tb_test_case tb_tests_mc[] = {
    {"sphere", test_sphere},
    {"blobs_torus", test_blobs_torus},
    {"all_256_cases", test_all_cases},
    {"random_volumes", test_random_volumes},
    {"errors", test_mc_errors},
    {"remesh_collapse_flip", test_collapse},
    {"remesh_collapse_limits", test_collapse_limits},
    {"remesh_taubin", test_taubin},
    {"liver_surface", test_liver},
    {"liver_resolutions", test_liver_resolutions},
    {"liver_volume", test_liver_volume},
    {"liver_errors", test_liver_errors},
    {0, 0},
};
