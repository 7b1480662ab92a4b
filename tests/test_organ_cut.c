/* Cutting an organ through the model interface: the
 * metaball model (models/metaball_model.c) cut by a scalpel's folded plane
 * with tb_model_cut, the volume (spheres -> points -> spheres) and the
 * surface (split, crack) together. A straight cut through the patent's
 * steak and folded cuts through the liver leave a closed, oriented
 * 2-manifold with two components where the cut goes through and one where
 * it stops inside; no sphere link crosses the cut; with one side held the
 * other falls away; the same cut gives the same result. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "cutting/tb_cut_surface.h"
#include "cutting/tb_fold.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"

#define DT 0.01

/* The organ's surface (verts 0: the patent's count) as a metaball model. */
static int organ(const char *name, int verts, const char *kv, tb_model *m, tb_mesh *mesh) {
  tb_error err;
  if (tb_organ_surface(name, verts, 1, mesh, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return -1;
  }
  tb_settings s = tb_test_settings(kv);
  if (tb_model_create(m, "metaball", mesh, &s, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    tb_mesh_free(mesh);
    return -1;
  }
  return 0;
}

/* Steps without gravity (the blade's frames and after). */
static int idle(tb_model *m, int n, tb_vec3 g) {
  tb_step in = {.dt = DT, .gravity = g};
  tb_error err;
  for (int k = 0; k < n; k++)
    if (tb_model_step(m, &in, &err)) {
      TB_CHECK_MSG(0, "step: %s", err.msg);
      return -1;
    }
  return 0;
}

/* The blade along path[0..n) in frames: BEGIN, then MOVEs along each
 * segment in `frames` equal parts, a step after each, then END. */
static int cut(tb_model *m, const tb_vec3 *path, int n, tb_vec3 depth, int frames,
               tb_cut_stats *st) {
  tb_error err;
  tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, depth};
  if (tb_model_cut(m, &ev, NULL, &err)) {
    TB_CHECK_MSG(0, "begin: %s", err.msg);
    return -1;
  }
  tb_vec3 p[16];
  for (int k = 0; k + 1 < n; k++)
    for (int f = 1; f <= frames; f++) {
      for (int q = 0; q <= k; q++) p[q] = path[q];
      p[k + 1] = tb_add(path[k], tb_scale(tb_sub(path[k + 1], path[k]), (double)f / frames));
      ev = (tb_cut_event){TB_CUT_MOVE, k + 2, p, depth};
      if (tb_model_cut(m, &ev, NULL, &err)) {
        TB_CHECK_MSG(0, "move: %s", err.msg);
        return -1;
      }
      if (idle(m, 1, tb_v3(0, 0, 0))) return -1;
    }
  ev = (tb_cut_event){TB_CUT_END, 0, NULL, depth};
  if (tb_model_cut(m, &ev, st, &err)) {
    TB_CHECK_MSG(0, "end: %s", err.msg);
    return -1;
  }
  return 0;
}

/* The surface is a closed 2-manifold of `parts` components; no sphere link
 * crosses the fold (path, depth) at the current positions. */
static void check_cut(tb_model *m, const tb_vec3 *path, int n, tb_vec3 depth, int parts) {
  tb_surface su = tb_model_surface(m);
  TB_CHECK_MSG(tb_cut_is_closed_manifold(su.nv, su.ntri, su.tri), "not a closed 2-manifold");
  int comp = tb_cut_components(su.nv, su.ntri, su.tri);
  TB_CHECK_MSG(comp == parts, "%d components, expected %d", comp, parts);
  TB_CHECK(tb_cut_volume(su.x, su.ntri, su.tri) > 0);
  tb_fold f;
  tb_error err;
  if (tb_fold_init(&f, path, n, depth, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  tb_model_spheres sp = m->cls->spheres(m->self);
  int crossing = 0;
  for (int e = 0; e < sp.nlinks; e++)
    crossing += tb_fold_segment(&f, sp.c[sp.links[2 * e]], sp.c[sp.links[2 * e + 1]], NULL);
  TB_CHECK_MSG(crossing == 0, "%d sphere links cross the cut", crossing);
  for (int v = 0; v < su.nv; v++)
    TB_CHECK(isfinite(su.x[v].x) && isfinite(su.x[v].y) && isfinite(su.x[v].z));
  tb_fold_free(&f);
}

/* The steak (8 x 5 x 1.5 about the origin) cut straight through at x = 0.3:
 * two pieces; with the x < 0.3 piece held, the other falls under gravity
 * (as freely as its own links allow), while uncut the held half keeps it up. */
static void steak_straight_cut(void) {
  tb_vec3 path[2] = {tb_v3(0.3, -3.5, -1.5), tb_v3(0.3, 3.5, -1.5)}, depth = tb_v3(0, 0, 3);
  double drop[2];
  for (int cutit = 0; cutit < 2; cutit++) {
    tb_model m;
    tb_mesh mesh;
    if (organ("steak", 0, "spheres=539", &m, &mesh)) return;
    tb_cut_stats st = {0};
    if (cutit && cut(&m, path, 2, depth, 8, &st)) goto done;
    if (cutit) {
      check_cut(&m, path, 2, depth, 2);
      TB_CHECK(st.removed > 0 && st.created > 0 && st.split_tris > 0 && st.crack_tris > 0);
    }
    /* hold every point left of the cut, let gravity act for 0.3 s */
    int np = tb_model_npoints(&m), nf = 0, nr = 0;
    const tb_vec3 *x = tb_model_positions(&m);
    int *ids = malloc(sizeof(int) * (size_t)np);
    tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)np);
    double z0 = 0;
    for (int v = 0; v < np; v++)
      if (x[v].x < 0.3 - 1e-9)
        ids[nf] = v, at[nf++] = x[v];
      else if (x[v].x > 1.3)
        z0 += x[v].z, nr++;
    tb_step in = {
        .dt = DT, .gravity = tb_v3(0, 0, -9.81), .nfixed = nf, .fixed = ids, .fixed_x = at};
    tb_error err;
    for (int k = 0; k < 30; k++)
      if (tb_model_step(&m, &in, &err)) {
        TB_CHECK_MSG(0, "%s", err.msg);
        break;
      }
    x = tb_model_positions(&m);
    double z1 = 0;
    for (int v = 0; v < np; v++)
      if (x[v].x > 1.3 && !(x[v].x < 0.3 - 1e-9)) z1 += x[v].z;
    drop[cutit] = (z0 - z1) / nr;
    free(ids), free(at);
  done:
    tb_model_destroy(&m);
    tb_mesh_free(&mesh);
  }
  /* free fall for 0.3 s: 0.44; the cut side must fall most of it */
  TB_CHECK_MSG(drop[1] > 0.3, "cut: the free side fell %g (free fall 0.44)", drop[1]);
  TB_CHECK_MSG(drop[0] < 0.5 * drop[1], "uncut: it fell %g, cut %g", drop[0], drop[1]);
}

/* A folded blade (3 pieces) through the liver at 2000 vertices: two pieces
 * when its depth spans the liver, one (a slit) when it stops halfway. */
static void liver_folded_cuts(void) {
  tb_vec3 path[4] = {tb_v3(-1.0, -4, -3), tb_v3(0.0, -0.5, -3), tb_v3(1.2, 0.8, -3),
                     tb_v3(1.5, 4, -3)};
  for (int through = 0; through < 2; through++) {
    tb_model m;
    tb_mesh mesh;
    if (organ("liver", 2000, "spheres=200", &m, &mesh)) return;
    tb_vec3 depth = tb_v3(0, 0, through ? 6 : 3.2);
    tb_cut_stats st;
    if (!cut(&m, path, 4, depth, 3, &st)) {
      check_cut(&m, path, 4, depth, through ? 2 : 1);
      TB_CHECK(idle(&m, 20, tb_v3(0, 0, 0)) == 0);
    }
    tb_model_destroy(&m);
    tb_mesh_free(&mesh);
  }
}

/* The same cut twice, on one thread and on two (the steak at 2400
 * vertices, so that the skin's loops share out too): the same points and
 * triangles, bit for bit. */
static void same_cut_same_result(void) {
  tb_vec3 path[2] = {tb_v3(-0.7, -3.5, -1.5), tb_v3(0.5, 3.5, -1.5)}, depth = tb_v3(0, 0, 3);
  tb_model m[2];
  tb_mesh mesh[2];
  int threads = tb_threads(), made = 0;
  for (int r = 0; r < 2; r++, made++) {
    tb_threads_set(r ? 2 : 1);
    if (organ("steak", 2400, "spheres=150", &m[r], &mesh[r])) break;
    cut(&m[r], path, 2, depth, 4, NULL);
    idle(&m[r], 5, tb_v3(0, 0, -9.81));
  }
  tb_threads_set(threads);
  if (made == 2) {
    tb_surface a = tb_model_surface(&m[0]), b = tb_model_surface(&m[1]);
    TB_CHECK(a.nv == b.nv && a.ntri == b.ntri);
    if (a.nv == b.nv && a.ntri == b.ntri) {
      TB_CHECK(!memcmp(a.x, b.x, sizeof(tb_vec3) * (size_t)a.nv));
      TB_CHECK(!memcmp(a.tri, b.tri, sizeof(int) * 3 * (size_t)a.ntri));
    }
  }
  for (int r = 0; r < made; r++) tb_model_destroy(&m[r]), tb_mesh_free(&mesh[r]);
}

/* Awkward blades through the whole model: along the steak's full length,
 * one just touching its top (tangent to the top spheres' skin), one that
 * misses; each leaves a closed 2-manifold and a model that steps on. */
static void awkward_blades(void) {
  struct {
    tb_vec3 a, b, depth;
    int parts; /* components expected; 0: 1 or 2 */
  } blade[] = {
      {{-4.5, 0.2, -1.5}, {4.5, 0.2, -1.5}, {0, 0, 3}, 2}, /* the whole length */
      {{-4.5, -3, 2.0}, {4.5, -3, 2.0}, {0, 6, 0}, 1},     /* above it: misses */
      {{-1, -3, 0.0}, {1, -3, 0.0}, {0, 6, 0}, 0},         /* a shallow slice at mid-height */
  };
  for (size_t k = 0; k < sizeof blade / sizeof blade[0]; k++) {
    tb_model m;
    tb_mesh mesh;
    if (organ("steak", 600, "spheres=150", &m, &mesh)) return;
    tb_vec3 path[2] = {blade[k].a, blade[k].b};
    tb_cut_stats st;
    if (!cut(&m, path, 2, blade[k].depth, 4, &st)) {
      tb_surface su = tb_model_surface(&m);
      TB_CHECK_MSG(tb_cut_is_closed_manifold(su.nv, su.ntri, su.tri), "blade %d", (int)k);
      int c = tb_cut_components(su.nv, su.ntri, su.tri);
      TB_CHECK_MSG(blade[k].parts ? c == blade[k].parts : c >= 1 && c <= 2,
                   "blade %d: %d components", (int)k, c);
      if (blade[k].parts == 1) TB_CHECK(su.ntri == mesh.ntri && st.removed == 0);
      TB_CHECK(idle(&m, 10, tb_v3(0, 0, -9.81)) == 0);
    }
    tb_model_destroy(&m);
    tb_mesh_free(&mesh);
  }
}

/* A blade whose plane is tangent to the largest sphere (z = c.z + r):
 * the tangent sphere counts as touched (tb_fold_sphere), nothing breaks. */
static void tangent_to_a_sphere(void) {
  tb_model m;
  tb_mesh mesh;
  if (organ("steak", 600, "spheres=150", &m, &mesh)) return;
  tb_model_spheres sp = m.cls->spheres(m.self);
  int big = 0;
  for (int i = 1; i < sp.n; i++)
    if (sp.r[i] > sp.r[big]) big = i;
  double z = sp.c[big].z + sp.r[big];
  tb_vec3 path[2] = {tb_v3(sp.c[big].x - 1, -3, z), tb_v3(sp.c[big].x + 1, -3, z)};
  tb_cut_stats st;
  if (!cut(&m, path, 2, tb_v3(0, 6, 0), 4, &st)) {
    tb_surface su = tb_model_surface(&m);
    TB_CHECK(tb_cut_is_closed_manifold(su.nv, su.ntri, su.tri));
    TB_CHECK_MSG(st.removed >= 1, "the tangent sphere was not touched (%d removed)", st.removed);
    TB_CHECK(idle(&m, 10, tb_v3(0, 0, -9.81)) == 0);
  }
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* Random blades (seeded): 2 to 4 path points across or into the steak,
 * depth up or sideways, through or stopping inside; every cut leaves a
 * closed 2-manifold of 1 to 3 pieces and a model that steps on under
 * gravity, never an error or a crash. (Folded blades whose crease lay
 * wholly inside the organ were refused until the crease got points of its
 * own: 6 of 60; cut_surface/crease_inside.) */
#define NRANDOM 30
static void random_blades(void) {
  tb_rng rng = tb_rng_seed(14);
  int errors = 0;
  for (int k = 0; k < NRANDOM; k++) {
    tb_model m;
    tb_mesh mesh;
    if (organ("steak", 600, "spheres=150", &m, &mesh)) return;
    int n = 2 + (int)tb_rng_below(&rng, 3);
    tb_vec3 path[4];
    double y0 = -3.5, y1 = tb_rng_range(&rng, 0, 3.5), z = tb_rng_range(&rng, -1.6, -0.3);
    for (int i = 0; i < n; i++)
      path[i] = tb_v3(tb_rng_range(&rng, -2, 2), y0 + (y1 - y0) * i / (n - 1), z);
    tb_vec3 depth = tb_v3(tb_rng_range(&rng, -0.5, 0.5), 0, tb_rng_range(&rng, 0.8, 3.2));
    tb_error err;
    tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, depth};
    int rc = tb_model_cut(&m, &ev, NULL, &err);
    for (int i = 2; i <= n && !rc; i++) {
      ev = (tb_cut_event){TB_CUT_MOVE, i, path, depth};
      rc = tb_model_cut(&m, &ev, NULL, &err) || idle(&m, 1, tb_v3(0, 0, 0));
    }
    tb_cut_stats st;
    ev = (tb_cut_event){TB_CUT_END, 0, NULL, depth};
    if (!rc) rc = tb_model_cut(&m, &ev, &st, &err);
    if (rc) {
      errors++;
      TB_CHECK_MSG(strstr(err.msg, "tb_cut_surface") != NULL, "blade %d: %s", k, err.msg);
    } else {
      tb_surface su = tb_model_surface(&m);
      int c = tb_cut_components(su.nv, su.ntri, su.tri);
      TB_CHECK_MSG(tb_cut_is_closed_manifold(su.nv, su.ntri, su.tri), "blade %d: not closed", k);
      TB_CHECK_MSG(c >= 1 && c <= 3, "blade %d: %d pieces", k, c);
      TB_CHECK_MSG(idle(&m, 10, tb_v3(0, 0, -9.81)) == 0, "blade %d: the model failed after", k);
    }
    tb_model_destroy(&m);
    tb_mesh_free(&mesh);
  }
  printf("random blades: %d of %d refused by the surface cutter\n", errors, NRANDOM);
  TB_CHECK_MSG(errors == 0, "%d of %d random blades were refused", errors, NRANDOM);
}

/* Events out of order and models that cannot be cut are errors. */
static void bad_events(void) {
  tb_model m;
  tb_mesh mesh;
  if (organ("steak", 600, "spheres=150", &m, &mesh)) return;
  tb_error err;
  tb_vec3 p[2] = {tb_v3(0, -3, -1), tb_v3(0, 3, -1)};
  tb_cut_event mv = {TB_CUT_MOVE, 2, p, tb_v3(0, 0, 2)},
               end = {TB_CUT_END, 0, NULL, tb_v3(0, 0, 0)};
  TB_CHECK(tb_model_cut(&m, &mv, NULL, &err) != 0);
  TB_CHECK(tb_model_cut(&m, &end, NULL, &err) != 0);
  tb_cut_event begin = {TB_CUT_BEGIN, 0, NULL, tb_v3(0, 0, 2)};
  TB_CHECK(tb_model_cut(&m, &begin, NULL, &err) == 0);
  TB_CHECK(tb_model_cut(&m, &begin, NULL, &err) != 0);
  tb_cut_event short_path = {TB_CUT_MOVE, 1, p, tb_v3(0, 0, 2)};
  TB_CHECK(tb_model_cut(&m, &short_path, NULL, &err) != 0);
  tb_cut_event parallel = {TB_CUT_MOVE, 2, p, tb_v3(0, 1, 0)}; /* depth along the path */
  TB_CHECK(tb_model_cut(&m, &parallel, NULL, &err) != 0);
  TB_CHECK(tb_model_cut(&m, &end, NULL, &err) == 0); /* the blade never moved: nothing cut */
  TB_CHECK(tb_model_surface(&m).ntri == mesh.ntri);
  tb_model_destroy(&m);
  tb_model fem;
  tb_mesh beam;
  if (!tb_beam(1, 0.2, 0.2, 5, 1, 1, &beam, &err)) {
    if (!tb_model_create(&fem, "fem", &beam, NULL, &err)) {
      TB_CHECK(!tb_model_can_cut(&fem));
      TB_CHECK(tb_model_cut(&fem, &begin, NULL, &err) != 0 && strstr(err.msg, "cannot be cut"));
      tb_model_destroy(&fem);
    }
    tb_mesh_free(&beam);
  }
  tb_mesh_free(&mesh);
}

const tb_test_case tb_tests_organ_cut[] = {
    {"steak_straight_cut", steak_straight_cut},
    {"liver_folded_cuts", liver_folded_cuts},
    {"same_cut_same_result", same_cut_same_result},
    {"awkward_blades", awkward_blades},
    {"tangent_to_a_sphere", tangent_to_a_sphere},
    {"random_blades", random_blades},
    {"bad_events", bad_events},
    {NULL, NULL},
};
