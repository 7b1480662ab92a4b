/* Element-removal cutting of the tet models (models/carve.c, pbd.c,
 * fem_cut.c) on a beam of cubes 0.5 wide: a blade through one layer of
 * cubes removes exactly that layer's tets and leaves two closed, manifold
 * pieces whose masses are those of the tets left; a blade stopping inside
 * removes the cubes it reached and leaves one piece; after the cut the held
 * piece stays and the free one falls, no tet left inverted, the same run
 * twice the same; the scene's detector and VTK frames see the tets left;
 * consistent masses are refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "meshgen/tb_meshgen.h"

static const char *const models[] = {"pbd-stvk", "xpbd-stvk", "fem-corot"};
enum { NMODELS = 3 };
#define CUTX 2.1 /* inside the fifth layer of cubes, x in [2, 2.5] */

static int beam(tb_mesh *m) {
  tb_error err;
  int rc = tb_beam(4, 1, 1, 8, 2, 2, m, &err);
  TB_CHECK_MSG(rc == 0, "beam: %s", err.msg);
  return rc;
}

/* The blade's edge under the beam along y from y0 to y1 at x = CUTX, its
 * depth through the thickness, in one MOVE; then END. */
static int cut(tb_model *m, double y0, double y1, tb_cut_stats *st) {
  tb_error err;
  tb_vec3 path[2] = {tb_v3(CUTX, y0, -0.5), tb_v3(CUTX, y1, -0.5)}, depth = tb_v3(0, 0, 2);
  tb_cut_event ev[3] = {
      {TB_CUT_BEGIN, 0, NULL, depth}, {TB_CUT_MOVE, 2, path, depth}, {TB_CUT_END, 0, NULL, depth}};
  for (int k = 0; k < 3; k++)
    if (tb_model_cut(m, &ev[k], k == 2 ? st : NULL, &err)) {
      tb_test_fail(__FILE__, __LINE__, "%s: cut event %d: %s", m->cls->name, k, err.msg);
      return -1;
    }
  return 0;
}

static tb_mesh_topo topology(const tb_model *m) {
  tb_surface su = tb_model_surface(m);
  tb_mesh view = {.nv = su.nv, .x = (tb_vec3 *)su.x, .ntri = su.ntri, .tri = (int *)su.tri};
  return tb_mesh_topology(&view);
}

/* The tets a blade across the whole width removes are those of the layer
 * x in [2, 2.5]; the surface: two closed, manifold pieces, no vertex inside
 * the layer; the masses: density x volume of the tets left. */
static void through_removes_the_layer(void) {
  tb_mesh mesh;
  if (beam(&mesh)) return;
  for (int k = 0; k < NMODELS; k++) {
    tb_model m;
    tb_error err;
    tb_settings set = tb_test_settings("density=2");
    if (tb_model_create(&m, models[k], &mesh, &set, &err)) {
      tb_test_fail(__FILE__, __LINE__, "%s: %s", models[k], err.msg);
      continue;
    }
    unsigned long v0 = tb_model_surface(&m).version;
    tb_cut_stats st;
    if (cut(&m, -0.5, 1.5, &st)) {
      tb_model_destroy(&m);
      continue;
    }
    const unsigned char *alive = tb_model_tets_alive(&m);
    TB_CHECK_MSG(alive != NULL, "%s: no alive flags after a cut", models[k]);
    int removed = 0, wrong = 0;
    double vol = 0;
    for (int t = 0; alive && t < mesh.ntet; t++) {
      const int *e = mesh.tet + 4 * t;
      double lo = INFINITY, hi = -INFINITY;
      for (int a = 0; a < 4; a++) lo = fmin(lo, mesh.x[e[a]].x), hi = fmax(hi, mesh.x[e[a]].x);
      int in_layer = lo >= 2 - 1e-12 && hi <= 2.5 + 1e-12;
      removed += !alive[t];
      wrong += alive[t] == in_layer;
      if (alive[t]) vol += tb_tet_volume(mesh.x[e[0]], mesh.x[e[1]], mesh.x[e[2]], mesh.x[e[3]]);
    }
    TB_CHECK_MSG(removed == 24 && wrong == 0, "%s: %d removed, %d wrong (24 expected: 4 cubes)",
                 models[k], removed, wrong);
    TB_CHECK_MSG(st.removed == 24 && st.components == 2, "%s: stats %d removed, %d pieces",
                 models[k], st.removed, st.components);
    tb_surface su = tb_model_surface(&m);
    TB_CHECK_MSG(su.version != v0, "%s: the surface's version did not change", models[k]);
    tb_mesh_topo tp = topology(&m);
    TB_CHECK_MSG(tp.components == 2 && tp.closed && tp.manifold,
                 "%s: %d pieces, closed %d, manifold %d", models[k], tp.components, tp.closed,
                 tp.manifold);
    int inside = 0;
    for (int q = 0; q < 3 * su.ntri; q++) {
      double x = su.x[su.tri[q]].x;
      inside += x > 2 + 1e-9 && x < 2.5 - 1e-9;
    }
    TB_CHECK_MSG(inside == 0, "%s: %d surface corners inside the removed layer", models[k], inside);
    TB_CHECK_NEAR(vol, 3.5, 1e-9);
    /* nodes of the tets left carry their mass; the layer's inner nodes none */
    const double *mass = tb_model_masses(&m);
    double total = 0;
    for (int i = 0; i < mesh.nv; i++)
      if (mesh.x[i].x < 2 + 1e-9 || mesh.x[i].x > 2.5 - 1e-9) total += mass[i];
    TB_CHECK_MSG(fabs(total - 2 * vol) < 1e-9, "%s: mass of the nodes left %.12g, expected %.12g",
                 models[k], total, 2 * vol);
    tb_model_destroy(&m);
  }
  tb_mesh_free(&mesh);
}

/* A blade stopping at y = 0.4 removes the two cubes (y in [0, 0.5]) of the
 * layer it reached: one piece, closed. */
static void partial_keeps_one_piece(void) {
  tb_mesh mesh;
  if (beam(&mesh)) return;
  for (int k = 0; k < NMODELS; k++) {
    tb_model m;
    tb_error err;
    if (tb_model_create(&m, models[k], &mesh, NULL, &err)) {
      tb_test_fail(__FILE__, __LINE__, "%s: %s", models[k], err.msg);
      continue;
    }
    tb_cut_stats st;
    if (!cut(&m, -0.5, 0.4, &st)) {
      TB_CHECK_MSG(st.removed == 12 && st.components == 1, "%s: %d removed, %d pieces", models[k],
                   st.removed, st.components);
      tb_mesh_topo tp = topology(&m);
      TB_CHECK_MSG(tp.closed && tp.components == 1, "%s: closed %d, %d pieces", models[k],
                   tp.closed, tp.components);
    }
    tb_model_destroy(&m);
  }
  tb_mesh_free(&mesh);
}

/* Held at x = 0 and cut: the free piece falls, the held one hangs; no tet
 * left inverted; everything finite; the same run twice is the same. */
static void pieces_fall_apart(void) {
  tb_mesh mesh;
  if (beam(&mesh)) return;
  int fixed[64], nf = 0;
  tb_vec3 at[64];
  for (int i = 0; i < mesh.nv; i++)
    if (mesh.x[i].x == 0) fixed[nf] = i, at[nf++] = mesh.x[i];
  tb_step in = {
      .dt = 0.01, .gravity = tb_v3(0, 0, -9.81), .nfixed = nf, .fixed = fixed, .fixed_x = at};
  for (int k = 0; k < NMODELS; k++) {
    tb_vec3 *first = NULL;
    for (int run = 0; run < 2; run++) {
      tb_model m;
      tb_error err;
      tb_settings set = tb_test_settings("E=20000");
      if (tb_model_create(&m, models[k], &mesh, &set, &err)) {
        tb_test_fail(__FILE__, __LINE__, "%s: %s", models[k], err.msg);
        break;
      }
      tb_cut_stats st;
      if (tb_test_steps(&m, &in, 5) || cut(&m, -0.5, 1.5, &st) || tb_test_steps(&m, &in, 40)) {
        tb_model_destroy(&m);
        break;
      }
      const tb_vec3 *x = tb_model_positions(&m);
      const unsigned char *alive = tb_model_tets_alive(&m);
      int inverted = 0, finite = 1;
      for (int t = 0; t < mesh.ntet; t++) {
        const int *e = mesh.tet + 4 * t;
        if (alive[t]) inverted += !(tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]) > 0);
      }
      double near = 0, far = 0;
      int nn = 0, nfar = 0;
      for (int i = 0; i < mesh.nv; i++) {
        finite &= tb_isfinite3(x[i]);
        if (mesh.x[i].x <= 1) near += x[i].z - mesh.x[i].z, nn++;
        if (mesh.x[i].x >= 3) far += x[i].z - mesh.x[i].z, nfar++;
      }
      near /= nn, far /= nfar;
      TB_CHECK_MSG(finite && inverted == 0, "%s: finite %d, %d tets left inverted", models[k],
                   finite, inverted);
      /* 0.45 s of free fall from the cut: about 1 down; the held end sags little */
      TB_CHECK_MSG(far < -0.5 && near > -0.2, "%s: the free end moved %.3f, the held end %.3f",
                   models[k], far, near);
      if (run == 0) {
        first = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
        if (first) memcpy(first, x, sizeof(tb_vec3) * (size_t)mesh.nv);
      } else if (first) {
        TB_CHECK_MSG(!memcmp(first, x, sizeof(tb_vec3) * (size_t)mesh.nv), "%s: two runs differ",
                     models[k]);
      }
      tb_model_destroy(&m);
    }
    free(first);
  }
  tb_mesh_free(&mesh);
}

/* fem-corot with a consistent mass matrix says it cannot cut. */
static void consistent_mass_refused(void) {
  tb_mesh mesh;
  if (beam(&mesh)) return;
  tb_model m;
  tb_error err;
  tb_settings set = tb_test_settings("consistent_mass=1");
  if (tb_model_create(&m, "fem-corot", &mesh, &set, &err)) {
    tb_test_fail(__FILE__, __LINE__, "%s", err.msg);
  } else {
    tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, tb_v3(0, 0, 1)};
    TB_CHECK(tb_model_cut(&m, &ev, NULL, &err) != 0);
    TB_CHECK_MSG(strstr(err.msg, "lumped masses") != NULL, "%s", err.msg);
    tb_model_destroy(&m);
  }
  tb_mesh_free(&mesh);
}

/* A scene cutting the liver with pbd-stvk: stable, no tet left inverted,
 * the VTK frames hold fewer tets at the end, the surface written in two
 * pieces. */
static void scene_sees_tets_left(void) {
  char dir[1100], scene[1200], args[4096];
  snprintf(dir, sizeof dir, "%s/carve-vtk", tb_test_tmpdir());
  const char *text =
      "[scene]\ndt = 0.01\nduration = 0.5\ngravity = 9.81\n"
      "[mesh]\ngenerate = liver\nnodes = 600\n"
      "[model]\nname = pbd-stvk\n"
      "[fix left]\nbox = -6,-4,-3, -3.5,4,3\n"
      "[cut]\npoint = 1,-3.5,-1.6\npoint = 1,3.5,-1.6\ndepth = 0,0,3.2\nstart = 0.05\nstop = 0.2\n";
  snprintf(scene, sizeof scene, "%s", tb_test_file("carve.ini", text, -1));
  snprintf(args, sizeof args, "simulate --scene %s --vtk %s --every 50 --out-surface %s/cut.off",
           scene, dir, dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "inverted tets 0") && strstr(tb_test_out, "status: stable"),
               "%s", tb_test_out);
  char path[1300];
  snprintf(path, sizeof path, "%s/body_00000.vtu", dir);
  char *a = tb_test_slurp(path);
  snprintf(path, sizeof path, "%s/body_00001.vtu", dir);
  char *b = tb_test_slurp(path);
  const char *ca = a ? strstr(a, "NumberOfCells=\"") : NULL,
             *cb = b ? strstr(b, "NumberOfCells=\"") : NULL;
  TB_CHECK_MSG(ca && cb && atoi(cb + 15) < atoi(ca + 15), "cells before %d, after %d",
               ca ? atoi(ca + 15) : -1, cb ? atoi(cb + 15) : -1);
  free(a), free(b);
  snprintf(args, sizeof args, "mesh info %s/cut.off", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "2 components") &&
                   strstr(tb_test_out, "closed      yes"),
               "%s", tb_test_out);
}

const tb_test_case tb_tests_carve[] = {
    {"through_removes_the_layer", through_removes_the_layer},
    {"partial_keeps_one_piece", partial_keeps_one_piece},
    {"pieces_fall_apart", pieces_fall_apart},
    {"consistent_mass_refused", consistent_mass_refused},
    {"scene_sees_tets_left", scene_sees_tets_left},
    {0, 0},
};
