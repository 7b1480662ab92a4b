/* Bounding volume hierarchies (collision/tb_bvh.h): the volume tests on
 * hand-made and random cases (sphere-AABB against a sampled box), the
 * structure every build option gives (partition, containment, layer kinds,
 * stop rules, the split rules on hand-made centroids), the test rules of
 * fig. 4.4, and the query's pair set equal to brute force under the exact
 * triangle test: generated meshes (spheres, beams, soups, the liver and the
 * instrument) at random poses, after the rotated-AABB update, after refits
 * (delta 0 and delta > 0), and FCL's env/rob meshes at FCL's own kind of
 * random transforms when ../shared/data is present. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_bvh.h"
#include "core/tb_mesh_io.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "meshgen/tb_meshgen.h"

/* ---- helpers ---- */
static tb_mat3 random_rotation(tb_rng *r) {
  tb_vec3 axis = tb_v3(tb_rng_normal(r), tb_rng_normal(r), tb_rng_normal(r));
  return tb_m3_rotation(axis, tb_rng_range(r, 0, 2 * M_PI));
}
static void move(const tb_vec3 *x, int nv, tb_mat3 R, tb_vec3 t, tb_vec3 *y) {
  for (int v = 0; v < nv; v++) y[v] = tb_add(tb_m3_mulv(R, x[v]), t);
}
static tb_aabb tri_box(const tb_vec3 *x, const int *tri, int t) {
  tb_aabb b;
  b.lo = b.hi = x[tri[3 * t]];
  for (int k = 1; k < 3; k++)
    b.lo = tb_vmin(b.lo, x[tri[3 * t + k]]), b.hi = tb_vmax(b.hi, x[tri[3 * t + k]]);
  return b;
}
static int box_holds(tb_aabb outer, tb_aabb in) {
  return outer.lo.x <= in.lo.x && outer.lo.y <= in.lo.y && outer.lo.z <= in.lo.z &&
         outer.hi.x >= in.hi.x && outer.hi.y >= in.hi.y && outer.hi.z >= in.hi.z;
}
static int box_equal(tb_aabb a, tb_aabb b) { return box_holds(a, b) && box_holds(b, a); }
/* Every corner within the radius, in long double. */
static int sphere_holds(tb_sphere s, tb_aabb b) {
  for (int c = 0; c < 8; c++) {
    long double dx = (long double)(c & 1 ? b.hi.x : b.lo.x) - s.c.x;
    long double dy = (long double)(c & 2 ? b.hi.y : b.lo.y) - s.c.y;
    long double dz = (long double)(c & 4 ? b.hi.z : b.lo.z) - s.c.z;
    if (dx * dx + dy * dy + dz * dz > (long double)s.r * s.r) return 0;
  }
  return 1;
}
static tb_pairlist no_pairs(void) {
  tb_pairlist p = {0, 0, NULL};
  return p;
}
static int same_pairs(const tb_pairlist *a, const tb_pairlist *b) {
  return a->n == b->n && (a->n == 0 || !memcmp(a->ij, b->ij, (size_t)a->n * 2 * sizeof(int)));
}

/* The 18 build options: kind x axis x point (composite with the variance
 * axis: without box_check). */
static const char *const KINDS[3] = {"sphere", "aabb", "composite"};
static tb_bvh_def option(int k) {
  tb_bvh_def d = tb_bvh_kind_def(KINDS[k % 3]);
  d.axis = (tb_split_axis)(k / 3 % 3);
  d.point = k / 9 ? TB_SPLIT_MEAN : TB_SPLIT_MEDIAN;
  if (k % 3 == 2 && k / 3 % 3 == 1) d.box_check = 0; /* the thesis's rule alone */
  return d;
}
#define NOPTIONS 18

/* ---- structural invariants ---- */
/* Modes: EXACT (after a build or a refit with delta 0): boxes are the
 * min-max boxes of the geometry x; LOOSE (refit with delta > 0): boxes hold
 * the geometry and their children; MOVED (after tb_bvh_transform): boxes
 * and spheres hold the geometry (a moved sphere need not hold its box). */
enum { LOOSE = 0, EXACT = 1, MOVED = 2 };
static int sphere_holds_tris(tb_sphere s, const tb_vec3 *x, const tb_bvh *b, int i) {
  for (int k = 0; k < b->count[i]; k++)
    for (int v = 0; v < 3; v++) {
      tb_vec3 p = x[b->tri[3 * b->tri_index[b->first[i] + k] + v]];
      long double dx = (long double)p.x - s.c.x, dy = (long double)p.y - s.c.y,
                  dz = (long double)p.z - s.c.z;
      if (dx * dx + dy * dy + dz * dz > (long double)s.r * s.r) return 0;
    }
  return 1;
}
static void check_structure(const tb_bvh *b, const tb_vec3 *x, const tb_bvh_def *d, int mode) {
  int exact = mode == EXACT;
  int n = b->nnodes, bad = 0, leaves = 0;
  int *depth = malloc((size_t)n * sizeof *depth), *seen = calloc((size_t)b->ntri, sizeof *seen);
  int *parents = calloc((size_t)n, sizeof *parents);
  if (!depth || !seen || !parents) {
    TB_CHECK_MSG(0, "out of memory");
    free(depth), free(seen), free(parents);
    return;
  }
  depth[0] = 0;
  int maxdepth = 0;
  for (int i = 0; i < n; i++) {
    int c = b->child[i], first = b->first[i], cnt = b->count[i];
    if (i > 0 && parents[i] != 1) bad |= 1;
    bad |= (first < 0 || cnt < 1 || first + cnt > b->ntri) << 1;
    if (depth[i] > maxdepth) maxdepth = depth[i];
    /* layer kind by depth */
    unsigned char want = depth[i] < d->sphere_layers                    ? TB_BV_SPHERE
                         : depth[i] < d->sphere_layers + d->both_layers ? TB_BV_SPHERE | TB_BV_AABB
                                                                        : TB_BV_AABB;
    bad |= (b->kind[i] != want) << 2;
    bad |= !(mode == MOVED ? sphere_holds_tris(b->sph[i], x, b, i)
                           : sphere_holds(b->sph[i], b->box[i]))
           << 3;
    tb_aabb tight = tri_box(x, b->tri, b->tri_index[first]);
    for (int k = 0; k < cnt; k++) {
      tb_aabb t = tri_box(x, b->tri, b->tri_index[first + k]);
      tight.lo = tb_vmin(tight.lo, t.lo), tight.hi = tb_vmax(tight.hi, t.hi);
    }
    bad |= !(exact ? box_equal(b->box[i], tight) : box_holds(b->box[i], tight)) << 4;
    if (c < 0) {
      leaves++;
      for (int k = 0; k < cnt; k++) seen[b->tri_index[first + k]]++;
      /* a leaf is at the depth limit, small enough, or too small to split */
      bad |= !(depth[i] == d->max_depth || cnt <= d->max_leaf || cnt < 2 * d->min_leaf) << 5;
      continue;
    }
    if (c <= i || c + 1 >= n) {
      bad |= 1 << 6;
      continue;
    }
    parents[c]++, parents[c + 1]++;
    depth[c] = depth[c + 1] = depth[i] + 1;
    /* children split the range, shrink, respect min_leaf and sit in the box */
    bad |= (b->first[c] != first || b->first[c + 1] != first + b->count[c] ||
            b->count[c] + b->count[c + 1] != cnt)
           << 7;
    bad |= (b->count[c] < d->min_leaf || b->count[c + 1] < d->min_leaf || b->count[c] == cnt ||
            b->count[c + 1] == cnt)
           << 8;
    if (mode != MOVED)
      bad |= !(box_holds(b->box[i], b->box[c]) && box_holds(b->box[i], b->box[c + 1])) << 9;
    bad |= (depth[i] >= d->max_depth) << 10;
  }
  for (int t = 0; t < b->ntri; t++) bad |= (seen[t] != 1) << 11;
  bad |= (n != 2 * leaves - 1 || maxdepth != b->depth || b->depth > d->max_depth) << 12;
  TB_CHECK_MSG(!bad, "hierarchy invariants broken (mask %#x), %d nodes", (unsigned)bad, n);
  free(depth), free(seen), free(parents);
}

/* ---- meshes ---- */
/* A soup of n random triangles in the unit cube, half of the vertices
 * snapped to a 1/8 grid (touching and coplanar pairs), some degenerate. */
static void soup(tb_mesh *m, int n, uint64_t seed) {
  tb_rng r = tb_rng_seed(seed);
  memset(m, 0, sizeof *m);
  m->nv = 3 * n, m->ntri = n;
  m->x = malloc((size_t)m->nv * sizeof *m->x), m->tri = malloc((size_t)m->nv * sizeof(int));
  if (!m->x || !m->tri) return;
  for (int t = 0; t < n; t++) {
    tb_vec3 c = tb_v3(tb_rng_uniform(&r), tb_rng_uniform(&r), tb_rng_uniform(&r));
    double s = tb_rng_range(&r, 0.02, 0.2);
    for (int k = 0; k < 3; k++) {
      tb_vec3 p = tb_madd(c, s, tb_v3(tb_rng_normal(&r), tb_rng_normal(&r), tb_rng_normal(&r)));
      if (t % 2) p = tb_v3(floor(p.x * 8) / 8, floor(p.y * 8) / 8, floor(p.z * 8) / 8);
      m->x[3 * t + k] = p;
      m->tri[3 * t + k] = 3 * t + k;
    }
    if (t % 17 == 0) m->tri[3 * t + 2] = m->tri[3 * t + 1]; /* a segment */
  }
}

/* Meshes from meshgen/ (the error goes to the test log). */
static int made(int rc, const char *what, const tb_error *err) {
  TB_CHECK_MSG(rc == 0, "%s: %s", what, err->msg);
  return rc;
}
static int geosphere(int nv, double radius, tb_mesh *m) {
  tb_error err;
  return made(tb_geosphere(nv, radius, m, &err), "geosphere", &err);
}
/* A beam lx x 0.5 x 0.5 of nx x 2 x 2 cells: its boundary triangles. */
static int beam(double lx, int nx, tb_mesh *m) {
  tb_error err;
  return made(tb_beam(lx, 0.5, 0.5, nx, 2, 2, m, &err), "beam", &err);
}
static int instrument(tb_mesh *m) {
  tb_error err;
  tb_instrument_def d = tb_instrument_default_def();
  return made(tb_instrument(&d, m, &err), "instrument", &err);
}
/* The liver's collision model (every tet face) and its surface. */
static int liver_faces(tb_mesh *faces, tb_mesh *surface) {
  tb_error err;
  tb_liver_def d = tb_liver_default_def();
  if (made(tb_liver_surface(&d, surface, &err), "liver surface", &err)) return -1;
  if (made(tb_liver_tets(&d, surface, faces, &err), "liver tets", &err)) {
    tb_mesh_free(surface);
    return -1;
  }
  free(faces->tri);
  faces->ntri = tb_mesh_tet_faces(faces, &faces->tri);
  TB_CHECK(faces->ntri > 9000);
  if (faces->ntri > 0) return 0;
  tb_mesh_free(faces), tb_mesh_free(surface);
  return -1;
}

/* ---- volume tests ---- */
static tb_aabb aabb(double x0, double y0, double z0, double x1, double y1, double z1) {
  tb_aabb b;
  b.lo = tb_v3(x0, y0, z0), b.hi = tb_v3(x1, y1, z1);
  return b;
}
static tb_sphere sphere(double x, double y, double z, double r) {
  tb_sphere s;
  s.c = tb_v3(x, y, z), s.r = r;
  return s;
}

static void volumes_hand(void) {
  TB_CHECK(tb_sphere_sphere(sphere(0, 0, 0, 1), sphere(3, 4, 0, 4))); /* touching */
  TB_CHECK(!tb_sphere_sphere(sphere(0, 0, 0, 1), sphere(3, 4, 0, 3.99)));
  TB_CHECK(tb_sphere_sphere(sphere(0, 0, 0, 5), sphere(1, 0, 0, 0.1))); /* inside */
  tb_aabb u = aabb(0, 0, 0, 1, 1, 1);
  TB_CHECK(tb_aabb_aabb(u, aabb(1, 1, 1, 2, 2, 2)));             /* corner */
  TB_CHECK(tb_aabb_aabb(u, aabb(0.2, 0.2, 0.2, 0.3, 0.3, 0.3))); /* inside */
  for (int a = 0; a < 3; a++) {                                  /* separated along one axis only */
    double lo[3] = {0.5, 0.5, 0.5}, hi[3] = {2, 2, 2};
    lo[a] = 1.0001;
    TB_CHECK(!tb_aabb_aabb(u, aabb(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])));
    lo[a] = 1.0;
    TB_CHECK(tb_aabb_aabb(u, aabb(lo[0], lo[1], lo[2], hi[0], hi[1], hi[2])));
  }
  /* sphere-AABB: the four Voronoi cases (inside, face, edge, vertex) */
  TB_CHECK(tb_sphere_aabb(sphere(0.5, 0.5, 0.5, 0.01), u));
  TB_CHECK(tb_sphere_aabb(sphere(0.5, 0.5, 3, 2), u) &&
           !tb_sphere_aabb(sphere(0.5, 0.5, 3, 1.99), u));
  TB_CHECK(tb_sphere_aabb(sphere(4, 5, 0.5, 5), u) && !tb_sphere_aabb(sphere(4, 5, 0.5, 4.99), u));
  TB_CHECK(tb_sphere_aabb(sphere(0.5, -3, -4, 5), u) &&
           !tb_sphere_aabb(sphere(0.5, -3, -4, 4.99), u));
  TB_CHECK(tb_sphere_aabb(sphere(1 + 2, 1 + 6, 1 + 3, 7), u)); /* vertex, 2-3-6-7 */
  TB_CHECK(!tb_sphere_aabb(sphere(3, 7, 4, 6.99), u));
  /* a box-corner sphere: the thesis's circumscribed sphere */
  tb_sphere s = tb_aabb_sphere(aabb(-1, -2, -2, 1, 2, 2));
  TB_CHECK(s.c.x == 0 && s.c.y == 0 && s.c.z == 0);
  TB_CHECK_NEAR(s.r, 3.0, 1e-10);
  TB_CHECK(s.r >= 3.0);
}

static void volumes_random(void) {
  tb_rng r = tb_rng_seed(41);
  int wrong = 0, hits = 0, tried = 0;
  for (int it = 0; it < 3000; it++) {
    tb_vec3 lo = tb_v3(tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1));
    tb_vec3 hi =
        tb_add(lo, tb_v3(tb_rng_range(&r, 0, 1), tb_rng_range(&r, 0, 1), tb_rng_range(&r, 0, 1)));
    tb_aabb b = aabb(lo.x, lo.y, lo.z, hi.x, hi.y, hi.z);
    tb_sphere s = sphere(tb_rng_range(&r, -2.5, 2.5), tb_rng_range(&r, -2.5, 2.5),
                         tb_rng_range(&r, -2.5, 2.5), tb_rng_range(&r, 0, 1.5));
    /* the distance to the box by sampling a 21^3 grid of it: the true
     * distance lies in [dmin - half a cell diagonal, dmin] */
    double dmin = HUGE_VAL, cell = tb_dist(lo, hi) / 20.0;
    for (int i = 0; i <= 20; i++)
      for (int j = 0; j <= 20; j++)
        for (int k = 0; k <= 20; k++) {
          tb_vec3 p = tb_v3(lo.x + (hi.x - lo.x) * i / 20, lo.y + (hi.y - lo.y) * j / 20,
                            lo.z + (hi.z - lo.z) * k / 20);
          double d = tb_dist(p, s.c);
          if (d < dmin) dmin = d;
        }
    int got = tb_sphere_aabb(s, b);
    if (s.r >= dmin) tried++, wrong += !got;
    if (s.r < dmin - 0.5 * cell) tried++, wrong += got;
    hits += got;
    /* sphere-sphere and box-box against their definitions */
    tb_sphere t = sphere(tb_rng_range(&r, -2, 2), 0, 0, tb_rng_range(&r, 0, 1));
    double gap = tb_dist(s.c, t.c) - (s.r + t.r);
    if (fabs(gap) > 1e-12) wrong += tb_sphere_sphere(s, t) != (gap < 0);
    tb_aabb c = aabb(s.c.x, s.c.y, s.c.z, s.c.x + s.r, s.c.y + s.r, s.c.z + s.r);
    int ov = 1;
    for (int a = 0; a < 3; a++)
      ov &= tb_comp(c.lo, a) <= tb_comp(b.hi, a) && tb_comp(b.lo, a) <= tb_comp(c.hi, a);
    wrong += tb_aabb_aabb(b, c) != ov || tb_aabb_aabb(c, b) != ov;
    /* the circumscribed sphere holds the box even far from the origin */
    double far = pow(10, tb_rng_range(&r, 0, 9));
    tb_aabb f = aabb(lo.x + far, lo.y - far, lo.z, hi.x + far, hi.y - far, hi.z);
    wrong += !sphere_holds(tb_aabb_sphere(f), f) || !sphere_holds(tb_aabb_sphere(b), b);
  }
  TB_CHECK_MSG(!wrong, "%d wrong volume tests", wrong);
  TB_CHECK_MSG(tried > 2500 && hits > 150 && hits < 2700, "tried %d hits %d", tried, hits);
}

/* ---- fig. 4.4: which test a pair of layer kinds uses ---- */
/* Two 2-triangle meshes (each spanning its box) with leaves of one triangle:
 * the root pair's test decides whether the descent goes on (bv_tests > 1). */
static void fig44_rules(void) {
  static const int tri[6] = {0, 1, 2, 3, 4, 5};
  static const tb_vec3 ua[6] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 1}, {1, 1, 1}, {0, 1, 0}, {1, 0, 1}};
  /* kinds S, SA, A by (sphere_layers, both_layers) at the root */
  static const int layers[3][2] = {{1, 0}, {0, 1}, {0, 0}};
  /* gap 0.1: boxes apart, spheres and sphere-box meet; gap 0.5: only the
   * spheres meet. Expected "descends" for [gap][kind A][kind B]. */
  static const int expect[2][3][3] = {{{1, 1, 1}, {1, 1, 0}, {1, 0, 0}},
                                      {{1, 1, 0}, {1, 1, 0}, {0, 0, 0}}};
  const double gaps[2] = {0.1, 0.5};
  for (int g = 0; g < 2; g++) {
    tb_vec3 ub[6];
    for (int v = 0; v < 6; v++) ub[v] = tb_add(ua[v], tb_v3(1 + gaps[g], 0, 0));
    for (int ka = 0; ka < 3; ka++)
      for (int kb = 0; kb < 3; kb++) {
        tb_bvh_def da = tb_bvh_default_def(), db = da;
        da.max_leaf = db.max_leaf = 1;
        da.sphere_layers = layers[ka][0], da.both_layers = layers[ka][1];
        db.sphere_layers = layers[kb][0], db.both_layers = layers[kb][1];
        tb_bvh A, B;
        tb_error err;
        TB_CHECK(tb_bvh_build(&A, ua, tri, 2, &da, &err) == 0);
        TB_CHECK(tb_bvh_build(&B, ub, tri, 2, &db, &err) == 0);
        tb_pairlist p = no_pairs();
        tb_collide_stats st;
        TB_CHECK(tb_bvh_collide(&A, ua, &B, ub, tb_tritri_exact, &p, &st) == 0);
        TB_CHECK_MSG((st.bv_tests > 1) == expect[g][ka][kb], "gap %g, kinds %d/%d: %ld tests",
                     gaps[g], ka, kb, st.bv_tests);
        TB_CHECK(p.n == 0);
        tb_pairlist_free(&p);
        tb_bvh_free(&A), tb_bvh_free(&B);
      }
  }
}

/* ---- building ---- */
/* Tiny triangles at the given centroids (x, y, 0). */
static void at_centroids(const double *cx, const double *cy, int n, tb_vec3 *x, int *tri) {
  for (int t = 0; t < n; t++) {
    x[3 * t] = tb_v3(cx[t] - 0.01, cy[t] - 0.01, 0);
    x[3 * t + 1] = tb_v3(cx[t] + 0.02, cy[t] - 0.01, 0);
    x[3 * t + 2] = tb_v3(cx[t] - 0.01, cy[t] + 0.02, 0);
    for (int k = 0; k < 3; k++) tri[3 * t + k] = 3 * t + k;
  }
}
/* Builds one split (max_depth 1) and returns the left child's triangles as
 * a bit set. */
static unsigned root_left(const double *cx, const double *cy, int n, tb_split_axis axis,
                          tb_split_point point) {
  tb_vec3 x[48];
  int tri[48];
  at_centroids(cx, cy, n, x, tri);
  tb_bvh_def d = tb_bvh_default_def();
  d.axis = axis, d.point = point, d.max_depth = 1, d.max_leaf = 1;
  tb_bvh b;
  tb_error err;
  unsigned set = 0;
  if (tb_bvh_build(&b, x, tri, n, &d, &err) || b.nnodes != 3) {
    TB_CHECK_MSG(0, "no split");
    return 0;
  }
  for (int k = 0; k < b.count[1]; k++) set |= 1u << b.tri_index[b.first[1] + k];
  tb_bvh_free(&b);
  return set;
}

static void split_rules(void) {
  const double zero[16] = {0};
  /* mean 3: centroids on it go to the side with fewer, the left on a tie */
  const double m1[4] = {0, 3, 3, 6}, m2[5] = {0, 1, 3, 3, 8};
  TB_CHECK(root_left(m1, zero, 4, TB_SPLIT_LONGEST, TB_SPLIT_MEAN) == 0x7);
  TB_CHECK(root_left(m2, zero, 5, TB_SPLIT_LONGEST, TB_SPLIT_MEAN) == 0x3);
  /* median: on the split point -> left */
  const double d1[4] = {3, 0, 2, 1}, d2[5] = {0, 1, 1, 1, 5};
  TB_CHECK(root_left(d1, zero, 4, TB_SPLIT_LONGEST, TB_SPLIT_MEDIAN) == 0xa);
  TB_CHECK(root_left(d2, zero, 5, TB_SPLIT_LONGEST, TB_SPLIT_MEDIAN) == 0xf);
  /* axis: x has the longest extent, y the largest variance; the median on y
   * puts all on the left, so the fallback cuts the sorted y at the middle */
  const double ax[5] = {0, 0, 0, 0, 10}, ay[5] = {9, 0, 9, 0, 9};
  TB_CHECK(root_left(ax, ay, 5, TB_SPLIT_LONGEST, TB_SPLIT_MEDIAN) == 0xf);
  TB_CHECK(root_left(ax, ay, 5, TB_SPLIT_VARIANCE, TB_SPLIT_MEDIAN) == 0xa);
  /* children must shrink: all centroids equal -> halves, down to single
   * triangles; min_leaf 3 of 10 -> no node below 3, nodes under 6 leaves */
  tb_vec3 x[48];
  int tri[48];
  at_centroids(zero, zero, 8, x, tri);
  tb_bvh b;
  tb_error err;
  for (int p = 0; p < 2; p++) {
    tb_bvh_def d = tb_bvh_default_def();
    d.point = p ? TB_SPLIT_MEAN : TB_SPLIT_MEDIAN, d.max_leaf = 1;
    TB_CHECK(tb_bvh_build(&b, x, tri, 8, &d, &err) == 0);
    TB_CHECK(b.nnodes == 15 && b.depth == 3);
    check_structure(&b, x, &d, EXACT);
    tb_bvh_free(&b);
  }
  const double ten[10] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
  at_centroids(ten, zero, 10, x, tri);
  tb_bvh_def d = tb_bvh_default_def();
  d.max_leaf = 1, d.min_leaf = 3;
  TB_CHECK(tb_bvh_build(&b, x, tri, 10, &d, &err) == 0);
  TB_CHECK(b.nnodes == 3); /* 10 -> 5 + 5; a 5 cannot give two children of 3 */
  check_structure(&b, x, &d, EXACT);
  tb_bvh_free(&b);
  d.max_depth = 0;
  TB_CHECK(tb_bvh_build(&b, x, tri, 10, &d, &err) == 0 && b.nnodes == 1 && b.count[0] == 10);
  tb_bvh_free(&b);
}

/* Smallest sum of child volumes: the root's split is no worse than the
 * median split along any other axis (recomputed here). */
static double median_split_volume(const tb_mesh *m, int axis) {
  int n = m->ntri;
  double *key = malloc((size_t)n * sizeof *key), *sorted = malloc((size_t)n * sizeof *sorted);
  double v = HUGE_VAL;
  if (key && sorted) {
    for (int t = 0; t < n; t++) {
      const int *f = m->tri + 3 * t;
      key[t] =
          (tb_comp(m->x[f[0]], axis) + tb_comp(m->x[f[1]], axis) + tb_comp(m->x[f[2]], axis)) / 3.0;
      sorted[t] = key[t];
    }
    for (int i = 1; i < n; i++) /* insertion sort: small meshes */
      for (int j = i; j > 0 && sorted[j - 1] > sorted[j]; j--) {
        double s = sorted[j];
        sorted[j] = sorted[j - 1], sorted[j - 1] = s;
      }
    double med = sorted[(n - 1) / 2];
    tb_aabb side[2];
    int has[2] = {0, 0};
    for (int t = 0; t < n; t++) {
      int s = key[t] > med;
      tb_aabb b = tri_box(m->x, m->tri, t);
      side[s] = has[s] ? aabb(fmin(side[s].lo.x, b.lo.x), fmin(side[s].lo.y, b.lo.y),
                              fmin(side[s].lo.z, b.lo.z), fmax(side[s].hi.x, b.hi.x),
                              fmax(side[s].hi.y, b.hi.y), fmax(side[s].hi.z, b.hi.z))
                       : b;
      has[s] = 1;
    }
    if (has[0] && has[1]) {
      v = 0;
      for (int s = 0; s < 2; s++)
        v += (side[s].hi.x - side[s].lo.x) * (side[s].hi.y - side[s].lo.y) *
             (side[s].hi.z - side[s].lo.z);
    }
  }
  free(key), free(sorted);
  return v;
}

static void build_invariants(void) {
  tb_mesh ms[3];
  tb_error err;
  int ok = geosphere(252, 1.0, &ms[0]) == 0 && beam(3, 6, &ms[1]) == 0;
  soup(&ms[2], 700, 5);
  TB_CHECK(ok && ms[2].x);
  if (!ok || !ms[2].x) return;
  static const int limits[4][3] = {{40, 1, 10}, {4, 1, 1}, {40, 3, 4}, {6, 2, 2}};
  int built = 0;
  for (int mi = 0; mi < 3; mi++)
    for (int k = 0; k < NOPTIONS; k++)
      for (int l = 0; l < 4; l++) {
        tb_bvh_def d = option(k);
        d.max_depth = limits[l][0], d.min_leaf = limits[l][1], d.max_leaf = limits[l][2];
        if (l == 3) d.sphere_layers = 1, d.both_layers = 2;
        tb_bvh b, b2;
        if (tb_bvh_build(&b, ms[mi].x, ms[mi].tri, ms[mi].ntri, &d, &err)) {
          TB_CHECK_MSG(0, "%s", err.msg);
          continue;
        }
        built++;
        check_structure(&b, ms[mi].x, &d, EXACT);
        /* deterministic: the same input gives the same arrays */
        TB_CHECK(tb_bvh_build(&b2, ms[mi].x, ms[mi].tri, ms[mi].ntri, &d, &err) == 0);
        TB_CHECK(b2.nnodes == b.nnodes &&
                 !memcmp(b.tri_index, b2.tri_index, (size_t)b.ntri * sizeof(int)) &&
                 !memcmp(b.child, b2.child, (size_t)b.nnodes * sizeof(int)));
        if (d.axis == TB_SPLIT_MIN_VOLUME && d.point == TB_SPLIT_MEDIAN && l == 0 && b.nnodes > 1) {
          double v = 0;
          for (int c = 1; c <= 2; c++)
            v += (b.box[c].hi.x - b.box[c].lo.x) * (b.box[c].hi.y - b.box[c].lo.y) *
                 (b.box[c].hi.z - b.box[c].lo.z);
          for (int a = 0; a < 3; a++) TB_CHECK(v <= median_split_volume(&ms[mi], a) * (1 + 1e-12));
        }
        tb_bvh_free(&b), tb_bvh_free(&b2);
      }
  TB_CHECK(built == 3 * NOPTIONS * 4);
  for (int mi = 0; mi < 3; mi++) tb_mesh_free(&ms[mi]);
}

/* The thesis's settings on the liver's 9813-ish faces: 11 levels, 3/3/5,
 * leaves of at most 10; the instrument: 9 levels, 2/2/5. */
static void thesis_layers(void) {
  tb_mesh faces, surf, inst;
  tb_error err;
  if (liver_faces(&faces, &surf)) return;
  if (instrument(&inst)) {
    tb_mesh_free(&faces), tb_mesh_free(&surf);
    return;
  }
  tb_bvh_def d = tb_bvh_kind_def("composite");
  d.max_depth = 10;
  tb_bvh b;
  TB_CHECK(tb_bvh_build(&b, faces.x, faces.tri, faces.ntri, &d, &err) == 0);
  TB_CHECK(b.depth == 10);
  check_structure(&b, faces.x, &d, EXACT);
  int maxleaf = 0;
  for (int i = 0; i < b.nnodes; i++)
    if (b.child[i] < 0 && b.count[i] > maxleaf) maxleaf = b.count[i];
  TB_CHECK(maxleaf <= 10);
  tb_bvh_free(&b);
  d.max_depth = 8, d.sphere_layers = 2, d.both_layers = 2;
  TB_CHECK(tb_bvh_build(&b, inst.x, inst.tri, inst.ntri, &d, &err) == 0);
  TB_CHECK(b.depth == 8);
  check_structure(&b, inst.x, &d, EXACT);
  tb_bvh_free(&b);
  tb_mesh_free(&faces), tb_mesh_free(&surf), tb_mesh_free(&inst);
}

/* ---- queries against brute force ---- */
/* Compares one query with the reference (sorted); returns 1 when equal. */
static int query_equals(const tb_bvh *A, const tb_vec3 *xa, const tb_bvh *B, const tb_vec3 *xb,
                        const tb_pairlist *ref) {
  tb_pairlist p = no_pairs();
  tb_collide_stats st;
  int ok = tb_bvh_collide(A, xa, B, xb, tb_tritri_exact, &p, &st) == 0;
  int n = p.n;
  tb_pairlist_sort_unique(&p);
  ok = ok && n == p.n && same_pairs(&p, ref) && st.tri_tests >= p.n && st.bv_tests >= 1;
  tb_pairlist_free(&p);
  return ok;
}

/* Mesh A fixed, mesh B at random poses (B's centre somewhere in A's box,
 * scaled by spread): for all 18 options, and mixed kinds, B built at the
 * pose and B built at rest then transformed must give brute force's pairs. */
static void collide_case(const char *name, const tb_mesh *a, const tb_mesh *b, int poses,
                         double spread, uint64_t seed) {
  tb_rng r = tb_rng_seed(seed);
  tb_bvh A[NOPTIONS], B0[NOPTIONS];
  tb_error err;
  tb_vec3 *xb = malloc((size_t)b->nv * sizeof *xb), alo, ahi, blo, bhi;
  int ok = xb != NULL;
  for (int k = 0; k < NOPTIONS; k++) {
    tb_bvh_def d = option(k);
    ok &= tb_bvh_build(&A[k], a->x, a->tri, a->ntri, &d, &err) == 0;
    ok &= tb_bvh_build(&B0[k], b->x, b->tri, b->ntri, &d, &err) == 0;
  }
  TB_CHECK_MSG(ok, "%s: build failed", name);
  if (!ok) return;
  tb_mesh_bbox(a, &alo, &ahi), tb_mesh_bbox(b, &blo, &bhi);
  tb_vec3 bc = tb_scale(tb_add(blo, bhi), 0.5), ac = tb_scale(tb_add(alo, ahi), 0.5);
  long total = 0;
  int wrong = 0;
  for (int p = 0; p < poses; p++) {
    tb_mat3 R = p == 0 ? tb_m3_identity() : random_rotation(&r);
    tb_vec3 at = tb_v3(tb_rng_range(&r, alo.x, ahi.x), tb_rng_range(&r, alo.y, ahi.y),
                       tb_rng_range(&r, alo.z, ahi.z));
    at = p == 0 ? ac : tb_lerp(ac, at, spread);
    tb_vec3 t = tb_sub(at, tb_m3_mulv(R, bc));
    move(b->x, b->nv, R, t, xb);
    tb_pairlist ref = no_pairs();
    if (tb_collide_brute(a->x, a->tri, a->ntri, xb, b->tri, b->ntri, tb_tritri_exact, &ref, NULL)) {
      TB_CHECK(0);
      continue;
    }
    tb_pairlist_sort_unique(&ref);
    total += ref.n;
    for (int k = 0; k < NOPTIONS; k++) tb_bvh_transform(&B0[k], R, t);
    for (int k = 0; k < NOPTIONS; k++) {
      tb_bvh_def d = option(k);
      tb_bvh Bp;
      if (tb_bvh_build(&Bp, xb, b->tri, b->ntri, &d, &err)) {
        wrong++;
        continue;
      }
      check_structure(&B0[k], xb, &d, MOVED);
      int e1 = query_equals(&A[k], a->x, &Bp, xb, &ref),
          e2 = query_equals(&A[k], a->x, &B0[k], xb, &ref);
      /* mixed kinds: A of one kind against B of another */
      int e3 = query_equals(&A[k], a->x, &B0[(k + 1) % NOPTIONS], xb, &ref);
      if (!e1 || !e2 || !e3)
        wrong++, fprintf(stderr, "  %s pose %d option %d: built %d transformed %d mixed %d\n", name,
                         p, k, e1, e2, e3);
      tb_bvh_free(&Bp);
    }
    tb_pairlist_free(&ref);
  }
  TB_CHECK_MSG(!wrong, "%s: %d queries differ from brute force", name, wrong);
  TB_CHECK_MSG(total > 0, "%s: no intersecting pairs at any pose", name);
  for (int k = 0; k < NOPTIONS; k++) tb_bvh_free(&A[k]), tb_bvh_free(&B0[k]);
  free(xb);
}

static void collide_generated(void) {
  tb_mesh s1, s2, bm, soup1, soup2;
  int ok = geosphere(252, 1.0, &s1) == 0 && geosphere(1002, 0.7, &s2) == 0 && beam(2, 8, &bm) == 0;
  soup(&soup1, 400, 11), soup(&soup2, 300, 12);
  TB_CHECK(ok && soup1.x && soup2.x);
  if (!ok || !soup1.x || !soup2.x) return;
  collide_case("sphere/sphere", &s1, &s2, 4, 0.6, 1);
  collide_case("sphere/itself", &s1, &s1, 1, 0, 2); /* identity: every neighbour touches */
  collide_case("beam/sphere", &bm, &s2, 4, 0.7, 3);
  collide_case("beam/beam", &bm, &bm, 3, 0.3, 4);
  collide_case("soup/soup", &soup1, &soup2, 4, 0.5, 5);
  tb_mesh_free(&s1), tb_mesh_free(&s2), tb_mesh_free(&bm), tb_mesh_free(&soup1),
      tb_mesh_free(&soup2);
}

static void collide_liver_instrument(void) {
  tb_mesh faces, surf, inst;
  if (liver_faces(&faces, &surf)) return;
  if (instrument(&inst)) {
    tb_mesh_free(&faces), tb_mesh_free(&surf);
    return;
  }
  collide_case("liver faces/instrument", &faces, &inst, 3, 0.5, 6);
  collide_case("liver surface/instrument", &surf, &inst, 2, 0.5, 7);
  tb_mesh_free(&faces), tb_mesh_free(&surf), tb_mesh_free(&inst);
}

/* ---- near misses ---- */
/* Pairs of A against B at rest moved by (R, o + s d), by the hierarchies
 * (B0 built at rest, moved by the rotated-AABB update); y: scratch. */
static int pairs_at(const tb_bvh *A, const tb_mesh *a, tb_bvh *B0, const tb_mesh *b, tb_mat3 R,
                    tb_vec3 t, tb_vec3 *y, tb_collide_stats *st) {
  move(b->x, b->nv, R, t, y);
  tb_bvh_transform(B0, R, t);
  tb_pairlist p = no_pairs();
  int n = tb_bvh_collide(A, a->x, B0, y, tb_tritri_exact, &p, st) ? -1 : p.n;
  tb_pairlist_free(&p);
  return n;
}

/* B (at rest: b) rotated by a few rotations and slid from A's centre along
 * a direction until the two just part (bisection on the AABB hierarchy's
 * pair count), then placed clear by gap (relative to B's size) -- poses
 * where every top volume meets and only the lower ones can separate the
 * meshes. At each: brute force finds no pair, and neither does any of our
 * hierarchies; the pose the bisection ended on just inside has pairs, and
 * they agree with brute force; the composite with box_check never needs
 * more node tests than the AABB hierarchy (it visits a subset of its node
 * pairs) nor than the thesis's rule alone. */
static void near_miss_case(const char *name, const tb_mesh *a, const tb_mesh *b) {
  tb_error err;
  tb_vec3 *y = malloc((size_t)b->nv * sizeof *y), alo, ahi, blo, bhi;
  tb_bvh A[4], B0[4];
  tb_bvh_def defs[4] = {tb_bvh_kind_def("aabb"), tb_bvh_kind_def("composite"),
                        tb_bvh_kind_def("composite"), tb_bvh_kind_def("sphere")};
  defs[2].box_check = 0;
  int ok = y != NULL;
  for (int k = 0; k < 4; k++)
    ok &= tb_bvh_build(&A[k], a->x, a->tri, a->ntri, &defs[k], &err) == 0 &&
          tb_bvh_build(&B0[k], b->x, b->tri, b->ntri, &defs[k], &err) == 0;
  TB_CHECK_MSG(ok, "%s: build failed", name);
  if (!ok) return;
  tb_mesh_bbox(a, &alo, &ahi), tb_mesh_bbox(b, &blo, &bhi);
  tb_vec3 ac = tb_scale(tb_add(alo, ahi), 0.5), bc = tb_scale(tb_add(blo, bhi), 0.5);
  double size = tb_dist(alo, ahi) + tb_dist(blo, bhi);
  static const double gaps[2] = {1e-3, 0.05};
  int wrong = 0, fewer = 0, poses = 0, inside = 0;
  for (int p = 0; p < 4; p++) {
    tb_mat3 R = p == 0 ? tb_m3_identity() : tb_m3_rotation(tb_v3(1, 2 - p, p), 0.7 * p);
    tb_vec3 d = tb_normalize(tb_v3(p == 2 ? -1 : 0.3 * p, 1, p == 3 ? 1 : 0.2));
    /* o + s d with o placing B's centre at A's: s = size is clear of A */
    tb_vec3 o = tb_sub(ac, tb_m3_mulv(R, bc));
    double lo = 0, hi = size; /* hi: apart; lo: touching (if at all) */
    if (pairs_at(&A[0], a, &B0[0], b, R, o, y, NULL) == 0 ||
        pairs_at(&A[0], a, &B0[0], b, R, tb_add(o, tb_scale(d, hi)), y, NULL) != 0)
      continue; /* not a pose that passes from touching to apart */
    for (int it = 0; it < 40; it++) {
      double mid = 0.5 * (lo + hi);
      if (pairs_at(&A[0], a, &B0[0], b, R, tb_add(o, tb_scale(d, mid)), y, NULL))
        lo = mid;
      else
        hi = mid;
    }
    /* just inside: pairs, equal to brute force for every kind */
    tb_vec3 tin = tb_add(o, tb_scale(d, lo));
    move(b->x, b->nv, R, tin, y);
    tb_pairlist ref = no_pairs();
    TB_CHECK(tb_collide_brute(a->x, a->tri, a->ntri, y, b->tri, b->ntri, tb_tritri_exact, &ref,
                              NULL) == 0);
    tb_pairlist_sort_unique(&ref);
    inside += ref.n > 0;
    for (int k = 0; k < 4; k++) {
      tb_bvh_transform(&B0[k], R, tin);
      wrong += !query_equals(&A[k], a->x, &B0[k], y, &ref);
    }
    tb_pairlist_free(&ref);
    for (int g = 0; g < 2; g++) {
      tb_vec3 t = tb_add(o, tb_scale(d, hi + gaps[g] * size));
      long tests[4];
      for (int k = 0; k < 4; k++) {
        tb_collide_stats st;
        int n = pairs_at(&A[k], a, &B0[k], b, R, t, y, &st);
        wrong += n != 0;
        tests[k] = st.bv_tests;
      }
      tb_pairlist bf = no_pairs();
      TB_CHECK(tb_collide_brute(a->x, a->tri, a->ntri, y, b->tri, b->ntri, tb_tritri_exact, &bf,
                                NULL) == 0);
      wrong += bf.n != 0;
      tb_pairlist_free(&bf);
      fewer += tests[1] <= tests[0] && tests[1] <= tests[2];
      poses++;
      if (tests[1] > tests[0] || tests[1] > tests[2])
        fprintf(stderr, "  %s pose %d gap %g: node tests aabb %ld composite %ld thesis rule %ld\n",
                name, p, gaps[g], tests[0], tests[1], tests[2]);
    }
  }
  TB_CHECK_MSG(poses >= 6, "%s: only %d near-miss poses found", name, poses);
  TB_CHECK_MSG(inside == poses / 2, "%s: %d of %d contact poses have pairs", name, inside,
               poses / 2);
  TB_CHECK_MSG(!wrong, "%s: %d near-miss queries differ from brute force", name, wrong);
  TB_CHECK_MSG(fewer == poses, "%s: composite needs more node tests at %d of %d poses", name,
               poses - fewer, poses);
  for (int k = 0; k < 4; k++) tb_bvh_free(&A[k]), tb_bvh_free(&B0[k]);
  free(y);
}

static void near_miss(void) {
  tb_mesh faces, surf, inst;
  if (liver_faces(&faces, &surf)) return;
  if (instrument(&inst)) {
    tb_mesh_free(&faces), tb_mesh_free(&surf);
    return;
  }
  near_miss_case("liver faces/instrument", &faces, &inst);
  tb_mesh_free(&faces), tb_mesh_free(&surf), tb_mesh_free(&inst);
}

/* SOFA's liver-smooth against its dental instrument (long and thin: the
 * case where the top spheres are loosest). */
static void near_miss_sofa(void) {
  char pl[1024], pi[1024];
  snprintf(pl, sizeof pl, "%s/../shared/data/sofa/liver-smooth.obj", tb_test_source_root());
  snprintf(pi, sizeof pi, "%s/../shared/data/sofa/dental_instrument.obj", tb_test_source_root());
  FILE *probe = fopen(pl, "r");
  if (!probe) {
    tb_test_skip("%s absent (../shared/data not present)", pl);
    return;
  }
  fclose(probe);
  tb_mesh liver, inst;
  tb_error err;
  if (tb_mesh_read(pl, &liver, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  if (tb_mesh_read(pi, &inst, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    tb_mesh_free(&liver);
    return;
  }
  near_miss_case("SOFA liver-smooth/dental_instrument", &liver, &inst);
  tb_mesh_free(&liver), tb_mesh_free(&inst);
}

/* ---- motion and deformation ---- */
static void transform_rules(void) {
  tb_mesh m;
  tb_error err;
  if (geosphere(252, 2.0, &m)) return;
  tb_bvh_def d = tb_bvh_kind_def("composite");
  tb_bvh b;
  TB_CHECK(tb_bvh_build(&b, m.x, m.tri, m.ntri, &d, &err) == 0);
  tb_aabb *rest = malloc((size_t)b.nnodes * sizeof *rest),
          *once = malloc((size_t)b.nnodes * sizeof *once);
  if (!rest || !once) return;
  memcpy(rest, b.box, (size_t)b.nnodes * sizeof *rest);
  tb_rng r = tb_rng_seed(3);
  tb_mat3 R = random_rotation(&r);
  tb_vec3 t = tb_v3(100, -50, 7);
  tb_bvh_transform(&b, R, t);
  memcpy(once, b.box, (size_t)b.nnodes * sizeof *once);
  /* the thesis's formula from Min/Max per axis agrees with centre/extent */
  int bad = 0;
  for (int i = 0; i < b.nnodes; i++)
    for (int a = 0; a < 3; a++) {
      double lo = tb_comp(t, a), hi = lo;
      for (int j = 0; j < 3; j++) {
        double e = R.m[a][j] * tb_comp(rest[i].lo, j), f = R.m[a][j] * tb_comp(rest[i].hi, j);
        lo += fmin(e, f), hi += fmax(e, f);
      }
      bad += fabs(lo - tb_comp(b.box[i].lo, a)) > 1e-9 || fabs(hi - tb_comp(b.box[i].hi, a)) > 1e-9;
    }
  TB_CHECK_MSG(!bad, "%d rotated-AABB bounds differ from the thesis's formula", bad);
  /* repeating the motion replaces, never grows; back to the identity gives
   * the rest boxes up to the rounding margin */
  for (int k = 0; k < 5; k++) tb_bvh_transform(&b, R, t);
  TB_CHECK(!memcmp(once, b.box, (size_t)b.nnodes * sizeof *once));
  tb_bvh_transform(&b, tb_m3_identity(), tb_v3(0, 0, 0));
  for (int i = 0; i < b.nnodes; i++) {
    bad += !box_holds(b.box[i], rest[i]) || fabs(b.box[i].lo.x - rest[i].lo.x) > 1e-13;
    bad += fabs(b.sph[i].r - b.sph0[i].r) > 1e-13;
  }
  TB_CHECK(!bad);
  /* a non-finite motion gives volumes that meet everything (no silent miss) */
  R.m[1][1] = NAN;
  tb_bvh_transform(&b, R, t);
  TB_CHECK(tb_aabb_aabb(b.box[0], aabb(1e300, 1e300, 1e300, 1e300, 1e300, 1e300)));
  TB_CHECK(tb_sphere_sphere(b.sph[3], sphere(-1e300, 0, 0, 0)));
  /* a motion beyond 1e150 too (squares of such volumes could overflow):
   * every volume meets everything, and a query still finds every pair */
  tb_vec3 far = tb_v3(1e200, -1e200, 1e160);
  tb_bvh_transform(&b, tb_m3_identity(), far);
  for (int i = 0; i < b.nnodes; i++)
    bad += !tb_aabb_aabb(b.box[i], aabb(-1e300, -1e300, -1e300, -1e300, -1e300, -1e300)) ||
           !(b.sph[i].r == HUGE_VAL);
  TB_CHECK_MSG(!bad, "%d volumes moved by 1e200 do not meet everything", bad);
  tb_vec3 *y = malloc((size_t)m.nv * sizeof *y);
  if (y) {
    move(m.x, m.nv, tb_m3_identity(), far, y);
    tb_pairlist ref = no_pairs();
    TB_CHECK(tb_collide_brute(y, m.tri, m.ntri, y, m.tri, m.ntri, tb_tritri_exact, &ref, NULL) ==
             0);
    tb_pairlist_sort_unique(&ref);
    TB_CHECK(ref.n > 0 && query_equals(&b, y, &b, y, &ref));
    tb_pairlist_free(&ref);
    free(y);
  }
  free(rest), free(once);
  tb_bvh_free(&b);
  tb_mesh_free(&m);
}

/* A smooth time-varying displacement of amplitude amp. */
static void deform(const tb_vec3 *x, int nv, double time, double amp, tb_vec3 *y) {
  for (int v = 0; v < nv; v++) {
    tb_vec3 p = x[v];
    y[v] = tb_add(
        p, tb_scale(tb_v3(sin(1.3 * p.y + time), cos(0.9 * p.z + 2 * time), sin(0.7 * p.x - time)),
                    amp));
  }
}

static void refit_vs_brute(void) {
  tb_mesh faces, surf, inst;
  tb_error err;
  if (liver_faces(&faces, &surf)) return;
  if (instrument(&inst)) {
    tb_mesh_free(&faces), tb_mesh_free(&surf);
    return;
  }
  tb_vec3 *x = malloc((size_t)faces.nv * sizeof *x), *xi = malloc((size_t)inst.nv * sizeof *xi);
  if (!x || !xi) return;
  tb_rng r = tb_rng_seed(9);
  move(inst.x, inst.nv, random_rotation(&r), tb_v3(0.5, 0.2, 0), xi);
  int wrong = 0;
  long total = 0;
  const double deltas[3] = {0, 0.05, 0.3};
  for (int k = 0; k < 3; k++) {
    tb_bvh_def d = tb_bvh_kind_def(KINDS[k]);
    tb_bvh L, I;
    if (tb_bvh_build(&L, faces.x, faces.tri, faces.ntri, &d, &err) ||
        tb_bvh_build(&I, xi, inst.tri, inst.ntri, &d, &err))
      return;
    for (int di = 0; di < 3; di++) {
      int changes = 0;
      for (int f = 1; f <= 4; f++) {
        deform(faces.x, faces.nv, 0.4 * f, 0.08 * f / 4.0, x);
        int changed = tb_bvh_refit(&L, x, deltas[di]);
        /* delta 0: every moved box changes; delta > 0: grown boxes may
         * already hold the new positions */
        TB_CHECK(changed >= (deltas[di] == 0) && changed <= L.nnodes);
        changes += changed;
        check_structure(&L, x, &d, deltas[di] == 0 ? EXACT : LOOSE);
        /* every leaf box within delta of the exact one (thesis measure;
         * inner boxes are within delta of their children's union) */
        for (int i = 0; i < L.nnodes && deltas[di] > 0; i++) {
          if (L.child[i] >= 0) continue;
          tb_aabb e = tri_box(x, L.tri, L.tri_index[L.first[i]]);
          for (int m = 0; m < L.count[i]; m++) {
            tb_aabb t = tri_box(x, L.tri, L.tri_index[L.first[i] + m]);
            e.lo = tb_vmin(e.lo, t.lo), e.hi = tb_vmax(e.hi, t.hi);
          }
          wrong +=
              tb_dist(e.lo, L.box[i].lo) + tb_dist(e.hi, L.box[i].hi) > deltas[di] * (1 + 1e-12);
        }
        tb_pairlist ref = no_pairs();
        TB_CHECK(tb_collide_brute(x, faces.tri, faces.ntri, xi, inst.tri, inst.ntri,
                                  tb_tritri_exact, &ref, NULL) == 0);
        tb_pairlist_sort_unique(&ref);
        total += ref.n;
        wrong += !query_equals(&L, x, &I, xi, &ref);
        tb_pairlist_free(&ref);
      }
      TB_CHECK(changes > 0);
      /* the same positions again: nothing changes */
      TB_CHECK(tb_bvh_refit(&L, x, deltas[di]) == 0);
    }
    /* non-finite positions are refused and change nothing */
    tb_aabb root = L.box[0];
    x[faces.tri[0]].x = NAN;
    TB_CHECK(tb_bvh_refit(&L, x, 0) == -1 && box_equal(L.box[0], root));
    /* after a transform, a refit at the moved positions gives exact boxes */
    tb_mat3 R = random_rotation(&r);
    tb_vec3 t = tb_v3(1, 2, 3);
    tb_vec3 *xm = malloc((size_t)inst.nv * sizeof *xm);
    if (xm) {
      move(xi, inst.nv, R, t, xm);
      tb_bvh_transform(&I, R, t);
      TB_CHECK(tb_bvh_refit(&I, xm, 0) > 0);
      check_structure(&I, xm, &d, EXACT);
      free(xm);
    }
    tb_bvh_free(&L), tb_bvh_free(&I);
  }
  TB_CHECK_MSG(!wrong, "%d refit checks failed", wrong);
  TB_CHECK(total > 0);
  free(x), free(xi);
  tb_mesh_free(&faces), tb_mesh_free(&surf), tb_mesh_free(&inst);
}

/* ---- FCL's env/rob at FCL-style random transforms ---- */
/* test/test_fcl_utility.h: Euler angles a, b, c uniform in [0, 2pi). */
static tb_mat3 fcl_euler(double a, double b, double c) {
  double c1 = cos(a), c2 = cos(b), c3 = cos(c), s1 = sin(a), s2 = sin(b), s3 = sin(c);
  tb_mat3 R = {{{c1 * c2, -c2 * s1, s2},
                {c3 * s1 + c1 * s2 * s3, c1 * c3 - s1 * s2 * s3, -c2 * s3},
                {s1 * s3 - c1 * c3 * s2, c3 * s1 * s2 + c1 * s3, c2 * c3}}};
  return R;
}

static void fcl_env_rob(void) {
  char pe[1024], pr[1024];
  snprintf(pe, sizeof pe, "%s/../shared/data/fcl/env.obj", tb_test_source_root());
  snprintf(pr, sizeof pr, "%s/../shared/data/fcl/rob.obj", tb_test_source_root());
  FILE *probe = fopen(pe, "r");
  if (!probe) {
    tb_test_skip("%s absent (../shared/data not present)", pe);
    return;
  }
  fclose(probe);
  tb_mesh env, rob;
  tb_error err;
  if (tb_mesh_read(pe, &env, &err) || tb_mesh_read(pr, &rob, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  tb_vec3 *xe = malloc((size_t)env.nv * sizeof *xe);
  tb_bvh E[NOPTIONS], Rb[NOPTIONS];
  int ok = xe != NULL;
  for (int k = 0; k < NOPTIONS; k++) {
    tb_bvh_def d = option(k);
    ok &= tb_bvh_build(&E[k], env.x, env.tri, env.ntri, &d, &err) == 0;
    ok &= tb_bvh_build(&Rb[k], rob.x, rob.tri, rob.ntri, &d, &err) == 0;
  }
  TB_CHECK(ok);
  if (!ok) return;
  /* as FCL's mesh-mesh test: env moved by the transform, rob at rest */
  tb_rng r = tb_rng_seed(2024);
  int wrong = 0, hit_poses = 0;
  for (int p = 0; p < 20; p++) {
    tb_vec3 t = tb_v3(tb_rng_range(&r, -3000, 3000), tb_rng_range(&r, -3000, 3000),
                      tb_rng_range(&r, 0, 3000));
    double a = tb_rng_range(&r, 0, 2 * M_PI), b = tb_rng_range(&r, 0, 2 * M_PI),
           c = tb_rng_range(&r, 0, 2 * M_PI);
    tb_mat3 R = fcl_euler(a, b, c);
    move(env.x, env.nv, R, t, xe);
    tb_pairlist ref = no_pairs();
    TB_CHECK(tb_collide_brute(xe, env.tri, env.ntri, rob.x, rob.tri, rob.ntri, tb_tritri_exact,
                              &ref, NULL) == 0);
    tb_pairlist_sort_unique(&ref);
    hit_poses += ref.n > 0;
    for (int k = 0; k < NOPTIONS; k++) {
      tb_bvh_transform(&E[k], R, t);
      wrong += !query_equals(&E[k], xe, &Rb[k], rob.x, &ref);
    }
    tb_pairlist_free(&ref);
  }
  TB_CHECK_MSG(!wrong, "%d env/rob queries differ from brute force", wrong);
  TB_CHECK_MSG(hit_poses >= 5, "only %d of 20 poses intersect", hit_poses);
  for (int k = 0; k < NOPTIONS; k++) tb_bvh_free(&E[k]), tb_bvh_free(&Rb[k]);
  free(xe);
  tb_mesh_free(&env), tb_mesh_free(&rob);
}

/* ---- threads ---- */
/* A large sphere (tens of thousands of triangles, above the thresholds of
 * the refit's and the query's threads) deformed, refit and queried against
 * a deformed, shifted copy of itself: 1 and 2 threads give the same refit
 * volumes (bit for bit), the same change counts, the same pair list in the
 * same order and the same counters, for the composite and AABB kinds and
 * delta 0 and > 0; a non-finite vertex is refused on threads too. */
static void threads_identical(void) {
  tb_mesh m;
  if (geosphere(40962, 1.0, &m)) return;
  int was = tb_threads();
  tb_vec3 *ya = malloc((size_t)m.nv * sizeof *ya), *yb = malloc((size_t)m.nv * sizeof *yb);
  TB_CHECK(ya && yb);
  static const char *const kinds[2] = {"composite", "aabb"};
  int differ = 0;
  long most = 0;
  for (int kd = 0; kd < 2 && ya && yb; kd++)
    for (int dl = 0; dl < 2; dl++) {
      tb_bvh_def d = tb_bvh_kind_def(kinds[kd]);
      tb_bvh A[2], B[2];
      tb_pairlist p[2] = {no_pairs(), no_pairs()};
      tb_collide_stats st[2];
      int changed[2][2];
      tb_error err;
      for (int t = 0; t < 2; t++) {
        tb_threads_set(t + 1);
        TB_CHECK(tb_bvh_build(&A[t], m.x, m.tri, m.ntri, &d, &err) == 0);
        TB_CHECK(tb_bvh_build(&B[t], m.x, m.tri, m.ntri, &d, &err) == 0);
        deform(m.x, m.nv, 0.3, 0.05, ya);
        deform(m.x, m.nv, 1.1, 0.05, yb);
        for (int v = 0; v < m.nv; v++) yb[v] = tb_add(yb[v], tb_v3(0.3, 0.2, 0.1));
        changed[t][0] = tb_bvh_refit(&A[t], ya, dl ? 0.02 : 0);
        changed[t][1] = tb_bvh_refit(&B[t], yb, dl ? 0.02 : 0);
        TB_CHECK(tb_bvh_collide(&A[t], ya, &B[t], yb, tb_tritri_exact, &p[t], &st[t]) == 0);
      }
      size_t nb = (size_t)A[0].nnodes;
      TB_CHECK_MSG(A[0].nnodes > 16384 && A[1].nnodes == A[0].nnodes, "%d nodes", A[0].nnodes);
      differ += changed[0][0] != changed[1][0] || changed[0][1] != changed[1][1];
      differ += memcmp(A[0].box, A[1].box, nb * sizeof *A[0].box) != 0;
      differ += memcmp(A[0].sph, A[1].sph, nb * sizeof *A[0].sph) != 0;
      differ += memcmp(B[0].box, B[1].box, nb * sizeof *B[0].box) != 0;
      differ += memcmp(B[0].sph, B[1].sph, nb * sizeof *B[0].sph) != 0;
      differ += p[0].n != p[1].n || !same_pairs(&p[0], &p[1]);
      differ += st[0].bv_tests != st[1].bv_tests || st[0].tri_tests != st[1].tri_tests;
      most = p[0].n > most ? p[0].n : most;
      TB_CHECK_MSG(changed[0][0] > 0, "%s: the refit changed nothing", kinds[kd]);
      /* a non-finite vertex: refused on threads too, the volumes untouched */
      tb_threads_set(2);
      deform(m.x, m.nv, 2.0, 0.05, ya); /* another frame: a refit would change boxes */
      ya[m.tri[3 * (m.ntri / 2)]].y = NAN;
      TB_CHECK(tb_bvh_refit(&A[1], ya, 0) == -1);
      TB_CHECK(!memcmp(A[0].box, A[1].box, nb * sizeof *A[0].box));
      /* so is one beyond TB_COORD_MAX, in the last chunk of the check */
      ya[m.tri[3 * (m.ntri / 2)]].y = 0;
      ya[m.tri[3 * m.ntri - 1]].z = -1.0000001e90;
      TB_CHECK(tb_bvh_refit(&A[1], ya, 0) == -1);
      TB_CHECK(!memcmp(A[0].box, A[1].box, nb * sizeof *A[0].box));
      for (int t = 0; t < 2; t++) tb_bvh_free(&A[t]), tb_bvh_free(&B[t]), tb_pairlist_free(&p[t]);
    }
  tb_threads_set(was);
  TB_CHECK_MSG(!differ, "%d results differ between 1 and 2 threads", differ);
  TB_CHECK_MSG(most > 1000, "only %ld pairs: too few for the query's threads", most);
  free(ya), free(yb);
  tb_mesh_free(&m);
}

/* A chain: triangles near the planes x = c_k, c_0 = 1e-300, c_k = (k + 2)
 * c_(k-1) (up to ~1e77, within TB_COORD_MAX), so every mean split peels off
 * the farthest one (the mean of the first k + 1 exceeds c_k / (k + 1) > all
 * but the last) and the hierarchy is N - 1 deep; a self-query then needs a
 * traversal stack beyond its initial 256 pairs. */
static void deep_chain(void) {
  enum { N = 200 };
  static tb_vec3 x[3 * N];
  static int tri[3 * N];
  double c = 1e-300;
  for (int k = 0; k < N; k++, c *= k + 2) {
    x[3 * k] = tb_v3(c, 0, 0), x[3 * k + 1] = tb_v3(c * (1 + 1e-9), 1, 0);
    x[3 * k + 2] = tb_v3(c, 0, 1);
  }
  for (int k = 0; k < 3 * N; k++) tri[k] = k;
  tb_bvh_def d = tb_bvh_default_def();
  d.point = TB_SPLIT_MEAN, d.max_leaf = 1, d.max_depth = 1000;
  tb_bvh b;
  tb_error err;
  TB_CHECK(tb_bvh_build(&b, x, tri, N, &d, &err) == 0);
  TB_CHECK_MSG(b.depth == N - 1, "depth %d", b.depth);
  check_structure(&b, x, &d, EXACT);
  tb_pairlist ref = no_pairs();
  TB_CHECK(tb_collide_brute(x, tri, N, x, tri, N, tb_tritri_exact, &ref, NULL) == 0);
  tb_pairlist_sort_unique(&ref);
  TB_CHECK_MSG(ref.n == N, "%d pairs", ref.n);
  TB_CHECK(query_equals(&b, x, &b, x, &ref));
  tb_pairlist_free(&ref);
  tb_bvh_free(&b);
}

/* ---- bad input, empty meshes, pair lists ---- */
static void errors_and_edges(void) {
  tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  int tri[3] = {0, 1, 2}, neg[3] = {0, -1, 2};
  tb_bvh b;
  tb_error err;
  tb_bvh_def d = tb_bvh_kind_def("nonsense");
  TB_CHECK(d.max_leaf == 0 && tb_bvh_build(&b, x, tri, 1, &d, &err) != 0 && strstr(err.msg, "bvh"));
  d = tb_bvh_default_def();
  d.max_leaf = 0;
  TB_CHECK(tb_bvh_build(&b, x, tri, 1, &d, &err) != 0 && strstr(err.msg, "max_leaf"));
  d = tb_bvh_default_def();
  d.axis = (tb_split_axis)7;
  TB_CHECK(tb_bvh_build(&b, x, tri, 1, &d, &err) != 0 && strstr(err.msg, "axis"));
  d = tb_bvh_default_def();
  TB_CHECK(tb_bvh_build(&b, x, neg, 1, &d, &err) != 0 && strstr(err.msg, "negative"));
  x[1].y = INFINITY;
  TB_CHECK(tb_bvh_build(&b, x, tri, 1, &d, &err) != 0 && strstr(err.msg, "non-finite"));
  TB_CHECK(b.nnodes == 0 && b.box == NULL);
  x[1].y = 0;
  /* an empty mesh: no nodes, no pairs; a one-triangle mesh: one leaf */
  tb_bvh e, one;
  TB_CHECK(tb_bvh_build(&e, x, tri, 0, &d, &err) == 0 && e.nnodes == 0);
  TB_CHECK(tb_bvh_build(&one, x, tri, 1, &d, &err) == 0 && one.nnodes == 1 && one.child[0] == -1);
  tb_pairlist p = no_pairs();
  tb_collide_stats st;
  TB_CHECK(tb_bvh_collide(&e, x, &one, x, tb_tritri_exact, &p, &st) == 0 && p.n == 0);
  TB_CHECK(tb_bvh_collide(&one, x, &one, x, tb_tritri_exact, &p, &st) == 0 && p.n == 1 &&
           st.bv_tests == 1 && st.tri_tests == 1);
  TB_CHECK(tb_bvh_refit(&e, x, 0) == 0 && tb_bvh_refit(&one, x, 0) == 0);
  tb_bvh_free(&e), tb_bvh_free(&one);
  tb_pairlist_free(&p);
  /* pair lists: sorted by (i, j), duplicates removed */
  static const int in[] = {3, 1, 0, 5, 3, 1, 0, 2, 3, 0, 0, 5};
  for (int k = 0; k < 6; k++) TB_CHECK(tb_pairlist_push(&p, in[2 * k], in[2 * k + 1]) == 0);
  tb_pairlist_sort_unique(&p);
  static const int want[] = {0, 2, 0, 5, 3, 0, 3, 1};
  TB_CHECK(p.n == 4 && !memcmp(p.ij, want, sizeof want));
  tb_pairlist_free(&p);
  TB_CHECK(p.n == 0 && p.ij == NULL);
  /* brute force calls a test that claims no exactness on every pair */
  tb_vec3 far[3] = {{10, 10, 10}, {11, 10, 10}, {10, 11, 10}};
  TB_CHECK(tb_collide_brute(x, tri, 1, far, tri, 1, tb_tritri_moller, &p, &st) == 0 &&
           st.tri_tests == 1);
  TB_CHECK(tb_collide_brute(x, tri, 1, far, tri, 1, tb_tritri_exact, &p, &st) == 0 &&
           st.tri_tests == 0);
  TB_CHECK(p.n == 0);
  tb_pairlist_free(&p);
}

/* ---- coordinates over the whole range readers accept ---- */
static void scaled_copy(const tb_vec3 *x, int nv, int e, tb_vec3 *y) {
  for (int v = 0; v < nv; v++) y[v] = tb_v3(ldexp(x[v].x, e), ldexp(x[v].y, e), ldexp(x[v].z, e));
}

/* Two random soups scaled by exact powers of two, from 2^-1000 (extents
 * ~1e-303: squares of them underflow) up to 2^290 (coordinates ~1e87, just
 * within TB_COORD_MAX): for every one of the 18 build options, built at
 * the scaled positions and refit to them from the unscaled build, the
 * query gives brute force's pairs and every sphere holds its box. */
static void scaled_soups(void) {
  static const int scales[] = {-1000, -800, -700, -530, -520, -510, -290,
                               -150,  -40,  0,    40,   150,  290};
  const int nscales = (int)(sizeof scales / sizeof scales[0]);
  tb_mesh s1, s2;
  soup(&s1, 300, 21), soup(&s2, 200, 22);
  tb_vec3 *y1 = malloc((size_t)s1.nv * sizeof *y1), *y2 = malloc((size_t)s2.nv * sizeof *y2);
  TB_CHECK(s1.x && s2.x && y1 && y2);
  if (!s1.x || !s2.x || !y1 || !y2) return;
  tb_error err;
  int wrong = 0;
  for (int si = 0; si < nscales; si++) {
    scaled_copy(s1.x, s1.nv, scales[si], y1), scaled_copy(s2.x, s2.nv, scales[si], y2);
    tb_pairlist ref = no_pairs(), self = no_pairs();
    TB_CHECK(tb_collide_brute(y1, s1.tri, s1.ntri, y2, s2.tri, s2.ntri, tb_tritri_exact, &ref,
                              NULL) == 0);
    TB_CHECK(tb_collide_brute(y1, s1.tri, s1.ntri, y1, s1.tri, s1.ntri, tb_tritri_exact, &self,
                              NULL) == 0);
    tb_pairlist_sort_unique(&ref), tb_pairlist_sort_unique(&self);
    TB_CHECK_MSG(ref.n > 0 && self.n > 0, "2^%d: %d and %d pairs", scales[si], ref.n, self.n);
    for (int k = 0; k < NOPTIONS; k++) {
      tb_bvh_def d = option(k);
      tb_bvh A, B, R;
      if (tb_bvh_build(&A, y1, s1.tri, s1.ntri, &d, &err) ||
          tb_bvh_build(&B, y2, s2.tri, s2.ntri, &d, &err)) {
        TB_CHECK_MSG(0, "2^%d option %d: %s", scales[si], k, err.msg);
        continue;
      }
      check_structure(&A, y1, &d, EXACT), check_structure(&B, y2, &d, EXACT);
      int e1 = query_equals(&A, y1, &B, y2, &ref), e2 = query_equals(&A, y1, &A, y1, &self), e3 = 1;
      /* refit from the unit-scale build to the scaled positions */
      if (tb_bvh_build(&R, s2.x, s2.tri, s2.ntri, &d, &err) == 0) {
        TB_CHECK(tb_bvh_refit(&R, y2, 0) >= (scales[si] != 0));
        check_structure(&R, y2, &d, EXACT);
        e3 = query_equals(&A, y1, &R, y2, &ref);
        tb_bvh_free(&R);
      }
      if (!e1 || !e2 || !e3)
        wrong++, fprintf(stderr, "  2^%d option %d (%s): built %d self %d refit %d\n", scales[si],
                         k, KINDS[k % 3], e1, e2, e3);
      tb_bvh_free(&A), tb_bvh_free(&B);
    }
    tb_pairlist_free(&ref), tb_pairlist_free(&self);
  }
  TB_CHECK_MSG(!wrong, "%d scaled queries differ from brute force", wrong);
  free(y1), free(y2);
  tb_mesh_free(&s1), tb_mesh_free(&s2);
}

/* The issue's triangle (1e200 on each axis) collided with itself: at
 * 1e90 (the bound) and 1e-90 every kind finds the one pair; beyond the
 * bound the build and the refit refuse it with a clear message. */
static void issue_coords(void) {
  int tri[3] = {0, 1, 2};
  const double at[3] = {1e90, 1e-90, 5e-324};
  tb_error err;
  for (int a = 0; a < 3; a++) {
    tb_vec3 x[3] = {{at[a], 0, 0}, {0, at[a], 0}, {0, 0, at[a]}};
    for (int k = 0; k < 3; k++) {
      tb_bvh_def d = tb_bvh_kind_def(KINDS[k]);
      tb_bvh b;
      if (tb_bvh_build(&b, x, tri, 1, &d, &err)) {
        TB_CHECK_MSG(0, "%g %s: %s", at[a], KINDS[k], err.msg);
        continue;
      }
      TB_CHECK(sphere_holds(b.sph[0], b.box[0]));
      tb_pairlist p = no_pairs();
      TB_CHECK(tb_bvh_collide(&b, x, &b, x, tb_tritri_exact, &p, NULL) == 0);
      TB_CHECK_MSG(p.n == 1, "%g %s: %d pairs", at[a], KINDS[k], p.n);
      tb_pairlist_free(&p);
      if (a == 0) { /* refit beyond the bound: refused, nothing changes */
        tb_vec3 y[3] = {{1e200, 0, 0}, {0, 1e200, 0}, {0, 0, 1e200}};
        tb_aabb root = b.box[0];
        TB_CHECK(tb_bvh_refit(&b, y, 0) == -1 && box_equal(b.box[0], root));
      }
      tb_bvh_free(&b);
    }
  }
  const double beyond[3] = {1e200, -1.0000001e90, 1e91};
  for (int a = 0; a < 3; a++) {
    tb_vec3 x[3] = {{beyond[a], 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int k = 0; k < 3; k++) {
      tb_bvh_def d = tb_bvh_kind_def(KINDS[k]);
      tb_bvh b;
      int rc = tb_bvh_build(&b, x, tri, 1, &d, &err);
      TB_CHECK_MSG(rc != 0 && b.nnodes == 0 && strstr(err.msg, "bvh") &&
                       strstr(err.msg, "triangle 0") && strstr(err.msg, "1e+90"),
                   "%g: rc %d, '%s'", beyond[a], rc, rc ? err.msg : "");
    }
  }
}

/* Refit keeps spheres conservative: at scales from 2^-1000 to 2^290, soups
 * deformed and refit (delta 0 and > 0) have every node's sphere holding
 * its triangles (long double check). */
static void refit_spheres_hold(void) {
  static const int scales[] = {-1000, -700, -290, 0, 290};
  tb_mesh s;
  soup(&s, 500, 31);
  tb_vec3 *y = malloc((size_t)s.nv * sizeof *y), *z = malloc((size_t)s.nv * sizeof *z);
  TB_CHECK(s.x && y && z);
  if (!s.x || !y || !z) return;
  tb_error err;
  int bad = 0;
  for (int si = 0; si < 5; si++)
    for (int k = 0; k < 3; k++) {
      tb_bvh_def d = tb_bvh_kind_def(KINDS[k]);
      tb_bvh b;
      scaled_copy(s.x, s.nv, scales[si], y);
      if (tb_bvh_build(&b, y, s.tri, s.ntri, &d, &err)) {
        TB_CHECK_MSG(0, "%s", err.msg);
        continue;
      }
      for (int f = 1; f <= 6; f++) {
        deform(s.x, s.nv, 0.3 * f, 0.01 * f, z);
        scaled_copy(z, s.nv, scales[si], y);
        double delta = f % 2 ? 0.0 : ldexp(0.02, scales[si]);
        TB_CHECK(tb_bvh_refit(&b, y, delta) >= 0);
        for (int i = 0; i < b.nnodes; i++)
          bad += !sphere_holds_tris(b.sph[i], y, &b, i) || !sphere_holds(b.sph[i], b.box[i]);
      }
      tb_bvh_free(&b);
    }
  TB_CHECK_MSG(!bad, "%d spheres smaller than their contents after refit", bad);
  free(y), free(z);
  tb_mesh_free(&s);
}

const tb_test_case tb_tests_bvh[] = {{"volumes_hand", volumes_hand},
                                     {"volumes_random", volumes_random},
                                     {"fig44_rules", fig44_rules},
                                     {"split_rules", split_rules},
                                     {"build_invariants", build_invariants},
                                     {"thesis_layers", thesis_layers},
                                     {"collide_generated", collide_generated},
                                     {"collide_liver_instrument", collide_liver_instrument},
                                     {"near_miss", near_miss},
                                     {"near_miss_sofa", near_miss_sofa},
                                     {"transform_rules", transform_rules},
                                     {"refit_vs_brute", refit_vs_brute},
                                     {"fcl_env_rob", fcl_env_rob},
                                     {"deep_chain", deep_chain},
                                     {"threads_identical", threads_identical},
                                     {"errors_and_edges", errors_and_edges},
                                     {"scaled_soups", scaled_soups},
                                     {"issue_coords", issue_coords},
                                     {"refit_spheres_hold", refit_spheres_hold},
                                     {0, 0}};
