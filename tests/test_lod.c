/* Levels of detail (models/lod.c): whatever is refined or coarsened, the
 * active surface stays closed, 2-manifold, oriented and free of
 * T-vertices, with levels differing by at most one across an edge. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "core/tb_rng.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_lod.h"

static int sphere_lod(tb_lod *lod, int levels) {
  tb_mesh s;
  tb_error err;
  if (tb_geosphere(252, 1, &s, &err)) return -1;
  int rc = tb_lod_create(lod, &s, levels, &err);
  TB_CHECK_MSG(rc == 0, "%s", err.msg);
  tb_mesh_free(&s);
  return rc;
}

/* The active surface as a mesh over every vertex (unused ones are not
 * counted by the topology's Euler characteristic). */
static tb_mesh_topo surface_topology(const tb_lod *lod) {
  tb_mesh m = {0};
  m.nv = lod->nv, m.x = lod->rest, m.ntri = lod->ntri, m.tri = lod->out_tri;
  return tb_mesh_topology(&m);
}

/* Levels of the two leaves on either side of every active edge differ by
 * at most one; returns the largest difference. */
static int level_jump(const tb_lod *lod) {
  int n = lod->ntri, worst = 0;
  long *key = malloc(sizeof(long) * 3 * (size_t)n);
  int *lev = malloc(sizeof(int) * 3 * (size_t)n);
  for (int t = 0; t < n; t++) {
    int f, l = tb_lod_level(lod, lod->out_leaf[t], &f);
    for (int k = 0; k < 3; k++) {
      long a = lod->out_tri[3 * t + k], b = lod->out_tri[3 * t + (k + 1) % 3];
      key[3 * t + k] = a < b ? a * lod->nv + b : b * lod->nv + a;
      lev[3 * t + k] = l;
    }
  }
  for (int i = 0; i < 3 * n; i++) /* quadratic, but the meshes are small */
    for (int j = i + 1; j < 3 * n; j++)
      if (key[i] == key[j] && abs(lev[i] - lev[j]) > worst) worst = abs(lev[i] - lev[j]);
  free(key), free(lev);
  return worst;
}

static void check_surface(const tb_lod *lod, const char *when) {
  tb_mesh_topo t = surface_topology(lod);
  TB_CHECK_MSG(t.closed && t.manifold && !t.misoriented_edges && !t.degenerate_tris,
               "%s: closed %d manifold %d misoriented %d degenerate %d", when, t.closed, t.manifold,
               t.misoriented_edges, t.degenerate_tris);
  TB_CHECK_MSG(t.euler == 2, "%s: Euler characteristic %d", when, t.euler);
  int used = 0;
  for (int v = 0; v < lod->nv; v++) used += lod->active[v];
  TB_CHECK_MSG(used == lod->nv - t.unused_verts, "%s: %d active, %d used", when, used,
               lod->nv - t.unused_verts);
}

/* One face of level 0 split: its three neighbours become the transition
 * band (two triangles each): 500 - 1 + 4 + 3 triangles, 3 new vertices. */
static void one_face_band(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 3)) return;
  TB_CHECK(lod.ntri == 500 && lod.level_nv[1] == 1002 && lod.level_nf[2] == 8000);
  TB_CHECK(tb_lod_refine(&lod, 0, 17) == 1);
  tb_lod_surface(&lod);
  TB_CHECK_MSG(lod.ntri == 506, "%d triangles", lod.ntri);
  int used = 0;
  for (int v = 0; v < lod.nv; v++) used += lod.active[v];
  TB_CHECK_MSG(used == 255, "%d vertices", used);
  check_surface(&lod, "one face");
  TB_CHECK(tb_lod_coarsen(&lod, 0, 17) == 1);
  tb_lod_surface(&lod);
  TB_CHECK(lod.ntri == 500);
  tb_lod_free(&lod);
}

/* Splitting a face two levels down pulls its coarser neighbours along
 * (balance), and two split neighbours split a leaf (closure). */
static void balance_and_closure(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 4)) return;
  TB_CHECK(tb_lod_refine(&lod, 0, 0) == 1);
  int n = tb_lod_refine(&lod, 1, 0); /* a corner child: touches two neighbours of face 0 */
  TB_CHECK_MSG(n >= 2, "%d faces split", n);
  TB_CHECK(tb_lod_refine(&lod, 2, 0) >= 1);
  tb_lod_surface(&lod);
  check_surface(&lod, "deep");
  TB_CHECK_MSG(level_jump(&lod) <= 1, "levels jump by %d", level_jump(&lod));
  /* face 0 of level 0 cannot be coarsened while its children are split */
  TB_CHECK(tb_lod_coarsen(&lod, 0, 0) == 0);
  tb_lod_free(&lod);
}

/* Everything split to the finest level is the fully subdivided mesh, and
 * coarsening everything gives the base back. */
static void full_and_back(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 3)) return;
  for (int l = 0; l < 2; l++)
    for (int f = 0; f < lod.level_nf[l]; f++) tb_lod_refine(&lod, l, f);
  tb_lod_surface(&lod);
  TB_CHECK_MSG(lod.ntri == 8000, "%d triangles", lod.ntri);
  int used = 0;
  for (int v = 0; v < lod.nv; v++) used += lod.active[v];
  TB_CHECK(used == lod.nv && lod.nv == 4002);
  check_surface(&lod, "full");
  /* a face inside the split region cannot be coarsened alone */
  TB_CHECK(tb_lod_coarsen(&lod, 1, 40) == 0);
  tb_lod_reset(&lod);
  TB_CHECK_MSG(lod.ntri == 500, "%d triangles after the reset", lod.ntri);
  int base = 0;
  for (int v = 0; v < lod.nv; v++) base += lod.active[v];
  TB_CHECK(base == 252);
  tb_lod_free(&lod);
}

/* Random refinements and coarsenings (seeded): the rules hold after each. */
static void random_walk(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 4)) return;
  tb_rng r = tb_rng_seed(7);
  int bad = 0, refined = 0, coarsened = 0;
  for (int it = 0; it < 300 && !bad; it++) {
    /* a leaf of the surface: split it, or coarsen its parent */
    int id = lod.out_leaf[tb_rng_below(&r, (uint64_t)lod.ntri)], f;
    int l = tb_lod_level(&lod, id, &f);
    if (tb_rng_uniform(&r) < 0.6)
      refined += tb_lod_refine(&lod, l, f) > 0;
    else if (l > 0)
      coarsened += tb_lod_coarsen(&lod, l - 1, f / 4);
    tb_lod_surface(&lod);
    tb_mesh_topo t = surface_topology(&lod);
    bad = !(t.closed && t.manifold && !t.misoriented_edges && t.euler == 2);
    if (it % 50 == 0 || bad) TB_CHECK_MSG(level_jump(&lod) <= 1, "step %d: levels jump", it);
  }
  TB_CHECK_MSG(!bad, "the surface broke after a random step");
  TB_CHECK_MSG(refined > 20 && coarsened > 5, "%d refined, %d coarsened", refined, coarsened);
  check_surface(&lod, "random");
  tb_lod_free(&lod);
}

/* Depths per vertex (the paper's §3.3 for every node at once): a vertex
 * of depth 1 splits its fan of level-0 faces; depth 2 splits again around
 * it; depth everywhere is the full subdivision. */
static void apply_depths(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 3)) return;
  unsigned char *depth = calloc((size_t)lod.nv, 1);
  int v = 0, k = 0, h = lod.out[0][v];
  do k++, h = lod.pair[0][h - h % 3 + (h + 2) % 3];
  while (h != lod.out[0][v]);
  depth[v] = 1;
  tb_lod_apply(&lod, depth);
  check_surface(&lod, "depth 1");
  int split = 0;
  for (int f = 0; f < lod.level_nf[0]; f++) split += lod.state[f] == TB_LOD_SPLIT;
  TB_CHECK_MSG(split >= k, "%d faces split around a vertex of valence %d", split, k);
  int n1 = lod.ntri;
  depth[v] = 2;
  tb_lod_apply(&lod, depth);
  check_surface(&lod, "depth 2");
  TB_CHECK_MSG(lod.ntri > n1, "%d triangles at depth 2, %d at depth 1", lod.ntri, n1);
  TB_CHECK(level_jump(&lod) <= 1);
  for (int i = 0; i < lod.nv; i++) depth[i] = 2;
  tb_lod_apply(&lod, depth);
  TB_CHECK_MSG(lod.ntri == 8000, "%d triangles with depth 2 everywhere", lod.ntri);
  memset(depth, 0, (size_t)lod.nv);
  tb_lod_apply(&lod, depth);
  TB_CHECK(lod.ntri == 500);
  free(depth);
  tb_lod_free(&lod);
}

/* Depths at random over four levels: after tb_lod_apply no face of level
 * l around a vertex of depth > l is left a leaf (a split's balance turning
 * on faces around a vertex already passed left some, 10 at levels 4). */
static void apply_any_order(void) {
  tb_lod lod;
  if (sphere_lod(&lod, 4)) return;
  unsigned char *depth = calloc((size_t)lod.nv, 1);
  unsigned long long r = 12345;
  for (int trial = 0; trial < 20; trial++) {
    for (int v = 0; v < lod.nv; v++) {
      r = r * 6364136223846793005ULL + 1442695040888963407ULL;
      depth[v] = (r >> 33) % 40 == 0 ? (unsigned char)(1 + (r >> 40) % 3) : 0;
    }
    tb_lod_apply(&lod, depth);
    int missed = 0;
    for (int l = 0; l + 1 < lod.nlevels; l++)
      for (int v = 0; v < lod.level_nv[l]; v++) {
        if (depth[v] <= l) continue;
        int h0 = lod.out[l][v], h = h0;
        do {
          missed += lod.state[lod.first[l] + h / 3] == TB_LOD_LEAF;
          h = lod.pair[l][h - h % 3 + (h + 2) % 3];
        } while (h != h0);
      }
    TB_CHECK_MSG(missed == 0, "trial %d: %d faces left unsplit", trial, missed);
    check_surface(&lod, "random depths");
  }
  free(depth);
  tb_lod_free(&lod);
}

static void bad_base(void) {
  tb_lod lod;
  tb_error err;
  tb_vec3 x[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  int tri[9] = {0, 2, 1, 0, 1, 3, 0, 3, 2}; /* a tetrahedron missing a face */
  tb_mesh m = {0};
  m.nv = 4, m.x = x, m.ntri = 3, m.tri = tri;
  TB_CHECK(tb_lod_create(&lod, &m, 2, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "lod") != NULL, "%s", err.msg);
  TB_CHECK(tb_lod_create(&lod, &m, 9, &err) != 0);
}

const tb_test_case tb_tests_lod[] = {
    {"one_face_band", one_face_band}, {"balance_and_closure", balance_and_closure},
    {"full_and_back", full_and_back}, {"random_walk", random_walk},
    {"apply_depths", apply_depths},   {"apply_any_order", apply_any_order},
    {"bad_base", bad_base},           {NULL, NULL},
};
