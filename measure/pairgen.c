/* The pair families of the correctness table (issue: general position;
 * coplanar on axis and diagonal planes; shared vertex and edge; vertex on
 * face; edge through edge and through vertex; near misses with gaps from
 * 2^-30 (~1e-9) down to the smallest subnormal 2^-1074; far from the origin
 * (1e6) and tiny (2^-23 ~ 1.2e-7); zero-area triangles). Degenerate
 * families use integer coordinates in [-8, 8] and fractions k/8 of them,
 * which doubles hold exactly, then exact symmetries (axis permutations,
 * sign flips, vertex order, swapping the triangles). tb_pairs_scaled gives
 * the scaled copies of the correctness table's "scaled" rows. */
#include <math.h>
#include <string.h>

#include "tb_pairgen.h"

static int irand(tb_rng *r, int lo, int hi) {
  return lo + (int)tb_rng_below(r, (uint64_t)(hi - lo + 1));
}
static tb_vec3 grid(tb_rng *r) { return tb_v3(irand(r, -8, 8), irand(r, -8, 8), irand(r, -8, 8)); }
static void grid_tri(tb_rng *r, tb_vec3 *t) {
  for (int k = 0; k < 3; k++) t[k] = grid(r);
}
/* A point of triangle t: t0 + s (t1 - t0) + u (t2 - t0), s, u in k/8, s + u <= 1. */
static tb_vec3 on_face(tb_rng *r, const tb_vec3 *t) {
  int a = irand(r, 0, 8), b = irand(r, 0, 8 - a);
  return tb_add(
      t[0], tb_add(tb_scale(tb_sub(t[1], t[0]), a / 8.0), tb_scale(tb_sub(t[2], t[0]), b / 8.0)));
}
static tb_vec3 on_edge(tb_rng *r, const tb_vec3 *t) {
  int e = irand(r, 0, 2);
  return tb_add(t[e], tb_scale(tb_sub(t[(e + 1) % 3], t[e]), irand(r, 0, 8) / 8.0));
}

/* Exact symmetries: permute and flip axes, reorder vertices, swap p and q. */
static void shuffle(tb_rng *r, tb_tripair *pr) {
  int perm[3] = {0, 1, 2};
  for (int i = 2; i > 0; i--) {
    int j = irand(r, 0, i), t = perm[i];
    perm[i] = perm[j], perm[j] = t;
  }
  double sign[3] = {irand(r, 0, 1) ? -1 : 1, irand(r, 0, 1) ? -1 : 1, irand(r, 0, 1) ? -1 : 1};
  tb_vec3 *v[6] = {&pr->p[0], &pr->p[1], &pr->p[2], &pr->q[0], &pr->q[1], &pr->q[2]};
  for (int i = 0; i < 6; i++) {
    double c[3] = {v[i]->x, v[i]->y, v[i]->z};
    *v[i] = tb_v3(sign[0] * c[perm[0]], sign[1] * c[perm[1]], sign[2] * c[perm[2]]);
  }
  for (int k = 0; k < 2; k++) {
    tb_vec3 *t = k ? pr->q : pr->p;
    int rot = irand(r, 0, 2);
    tb_vec3 a = t[rot], b = t[(rot + 1) % 3], c = t[(rot + 2) % 3];
    if (irand(r, 0, 1))
      t[0] = a, t[1] = c, t[2] = b;
    else
      t[0] = a, t[1] = b, t[2] = c;
  }
  if (irand(r, 0, 1)) {
    tb_tripair s = {{pr->q[0], pr->q[1], pr->q[2]}, {pr->p[0], pr->p[1], pr->p[2]}};
    *pr = s;
  }
}

static void fam_random(tb_rng *r, tb_tripair *pr) {
  for (int k = 0; k < 3; k++) {
    pr->p[k] = tb_v3(tb_rng_uniform(r), tb_rng_uniform(r), tb_rng_uniform(r));
    pr->q[k] = tb_v3(tb_rng_uniform(r), tb_rng_uniform(r), tb_rng_uniform(r));
  }
}

static void fam_coplanar_axis(tb_rng *r, tb_tripair *pr) {
  double c = irand(r, -8, 8) / 4.0;
  for (int k = 0; k < 3; k++) {
    pr->p[k] = tb_v3(irand(r, 0, 16) / 4.0, irand(r, 0, 16) / 4.0, c);
    pr->q[k] = tb_v3(irand(r, 0, 16) / 4.0, irand(r, 0, 16) / 4.0, c);
  }
  shuffle(r, pr);
}

static void fam_coplanar_diagonal(tb_rng *r, tb_tripair *pr) {
  int s = irand(r, -4, 4);
  for (int k = 0; k < 6; k++) {
    int x = irand(r, -8, 8), y = irand(r, -8, 8);
    (k < 3 ? pr->p : pr->q)[k % 3] = tb_v3(x, y, s - x - y); /* x + y + z = s */
  }
  shuffle(r, pr);
}

static void fam_shared_vertex(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  grid_tri(r, pr->q);
  pr->q[0] = pr->p[0];
  shuffle(r, pr);
}

static void fam_shared_edge(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  grid_tri(r, pr->q);
  pr->q[0] = pr->p[0], pr->q[1] = pr->p[1];
  shuffle(r, pr);
}

static void fam_vertex_on_face(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  grid_tri(r, pr->q);
  pr->q[0] = on_face(r, pr->p);
  shuffle(r, pr);
}

static void fam_edge_edge(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  tb_vec3 x = on_edge(r, pr->p), d = grid(r);
  pr->q[0] = tb_add(x, d), pr->q[1] = tb_sub(x, tb_scale(d, irand(r, 1, 8) / 8.0));
  pr->q[2] = grid(r);
  shuffle(r, pr);
}

static void fam_edge_vertex(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  tb_vec3 x = pr->p[irand(r, 0, 2)], d = grid(r);
  pr->q[0] = tb_add(x, d), pr->q[1] = tb_sub(x, tb_scale(d, irand(r, 1, 8) / 8.0));
  pr->q[2] = grid(r);
  shuffle(r, pr);
}

/* A in z = 0; B's vertex (or edge) a gap 2^-e above A's face (or edge),
 * e in [30, 1074]; B's other vertices at z >= 1. Never intersecting. */
static void fam_near_miss(tb_rng *r, tb_tripair *pr) {
  for (int k = 0; k < 3; k++) pr->p[k] = tb_v3(irand(r, -8, 8), irand(r, -8, 8), 0);
  double gap = ldexp(1.0, -irand(r, 30, 1074));
  tb_vec3 x = irand(r, 0, 1) ? on_face(r, pr->p) : on_edge(r, pr->p);
  x.z = gap;
  pr->q[0] = x;
  if (irand(r, 0, 1)) { /* an edge of B passes above x, parallel to z = 0 */
    tb_vec3 d = tb_v3(irand(r, -8, 8), irand(r, -8, 8), 0);
    pr->q[0] = tb_add(x, d), pr->q[1] = tb_sub(x, d);
  } else {
    pr->q[1] = tb_v3(irand(r, -8, 8), irand(r, -8, 8), irand(r, 1, 8));
  }
  pr->q[2] = tb_v3(irand(r, -8, 8), irand(r, -8, 8), irand(r, 1, 8));
  shuffle(r, pr);
}

static void fam_zero_area(tb_rng *r, tb_tripair *pr) {
  grid_tri(r, pr->p);
  tb_vec3 x = irand(r, 0, 1) ? on_face(r, pr->p) : on_edge(r, pr->p), d = grid(r);
  switch (irand(r, 0, 3)) {
    case 0: /* a segment through a point of A, its middle vertex on it */
      pr->q[0] = tb_add(x, d), pr->q[1] = tb_sub(x, d), pr->q[2] = x;
      break;
    case 1: /* a segment with a repeated vertex, ending at or near A */
      pr->q[0] = pr->q[1] = tb_add(x, tb_scale(d, irand(r, 0, 1) / 8.0)), pr->q[2] = tb_add(x, d);
      break;
    case 2: /* a point on A or next to it */
      pr->q[0] = pr->q[1] = pr->q[2] = irand(r, 0, 1) ? x : tb_add(x, tb_scale(d, 1.0 / 64));
      break;
    default: /* both degenerate: two segments through x */
      pr->q[0] = tb_add(x, d), pr->q[1] = tb_sub(x, d), pr->q[2] = tb_add(x, tb_scale(d, 0.5));
      d = grid(r);
      pr->p[0] = tb_add(x, d), pr->p[1] = tb_sub(x, tb_scale(d, irand(r, 0, 8) / 8.0));
      pr->p[2] = pr->p[irand(r, 0, 1)];
      break;
  }
  shuffle(r, pr);
}

typedef void (*maker)(tb_rng *, tb_tripair *);
static const maker degenerate[] = {fam_coplanar_axis, fam_coplanar_diagonal, fam_shared_vertex,
                                   fam_shared_edge,   fam_vertex_on_face,    fam_edge_edge,
                                   fam_edge_vertex,   fam_zero_area};
static const int ndegenerate = (int)(sizeof degenerate / sizeof degenerate[0]);

/* Half the pairs a degenerate configuration, half random unit-size
 * triangles; then every coordinate times 2^scale plus offset (exact). */
static void transformed(tb_rng *r, tb_tripair *pr, int scale, double offset) {
  if (irand(r, 0, 1))
    degenerate[irand(r, 0, ndegenerate - 1)](r, pr);
  else
    fam_random(r, pr);
  tb_vec3 *v[6] = {&pr->p[0], &pr->p[1], &pr->p[2], &pr->q[0], &pr->q[1], &pr->q[2]};
  for (int i = 0; i < 6; i++)
    *v[i] = tb_v3(ldexp(v[i]->x, scale) + offset, ldexp(v[i]->y, scale) + offset,
                  ldexp(v[i]->z, scale) + offset);
}
static void fam_far(tb_rng *r, tb_tripair *pr) { transformed(r, pr, 0, 1e6); }
static void fam_tiny(tb_rng *r, tb_tripair *pr) { transformed(r, pr, -23, 0.0); }

static const tb_pair_family families[] = {
    {"random", "uniform in the unit cube: general position", fam_random},
    {"coplanar-axis", "both in one plane z = c (then axes permuted)", fam_coplanar_axis},
    {"coplanar-diag", "both in the plane x + y + z = s", fam_coplanar_diagonal},
    {"shared-vertex", "one vertex in common", fam_shared_vertex},
    {"shared-edge", "one edge in common", fam_shared_edge},
    {"vertex-on-face", "a vertex of B on A (face, edge or vertex)", fam_vertex_on_face},
    {"edge-edge", "an edge of B through a point of an edge of A", fam_edge_edge},
    {"edge-vertex", "an edge of B through a vertex of A", fam_edge_vertex},
    {"near-miss", "B a gap 2^-30 .. 2^-1074 above A's face or edge", fam_near_miss},
    {"far", "degenerate or random pairs offset by 1e6", fam_far},
    {"tiny", "degenerate or random pairs scaled by 2^-23", fam_tiny},
    {"zero-area", "segments and points against triangles and segments", fam_zero_area},
};

const tb_pair_family *tb_pair_families(int *count) {
  *count = (int)(sizeof families / sizeof families[0]);
  return families;
}

const tb_pair_family *tb_pair_family_find(const char *name) {
  int n;
  const tb_pair_family *f = tb_pair_families(&n);
  for (int i = 0; i < n; i++)
    if (!strcmp(f[i].name, name)) return &f[i];
  return NULL;
}

int tb_pairgen(const tb_pair_family *f, int n, uint64_t seed, tb_pairset *set) {
  tb_rng r = tb_rng_seed(seed ^ (uint64_t)(f - families) * 0x9e3779b97f4a7c15ull);
  for (int i = 0; i < n; i++) {
    tb_tripair pr;
    f->make(&r, &pr);
    if (tb_pairs_add(set, &pr, -1)) return -1;
  }
  return 0;
}

/* x 2^e without loss: finite, and back again by 2^-e gives x. */
static int scales_exactly(double x, int e, double *y) {
  *y = ldexp(x, e);
  return isfinite(*y) && ldexp(*y, -e) == x;
}

int tb_pairs_scaled(const tb_pairset *in, int e, tb_pairset *out, int *index) {
  int added = 0;
  for (int i = 0; i < in->n; i++) {
    const tb_tripair *p = &in->pairs[i];
    const tb_vec3 *v[6] = {&p->p[0], &p->p[1], &p->p[2], &p->q[0], &p->q[1], &p->q[2]};
    tb_vec3 w[6];
    int ok = 1;
    for (int k = 0; k < 6 && ok; k++)
      ok = scales_exactly(v[k]->x, e, &w[k].x) && scales_exactly(v[k]->y, e, &w[k].y) &&
           scales_exactly(v[k]->z, e, &w[k].z);
    if (!ok) continue;
    tb_tripair q = {{w[0], w[1], w[2]}, {w[3], w[4], w[5]}};
    if (tb_pairs_add(out, &q, in->expect ? in->expect[i] : -1)) return -1;
    if (index) index[added] = i;
    added++;
  }
  return added;
}
