/* Tests of the metaball model behind the model interface
 * (models/metaball_model.c): rest, rigid skin, sag to rest, recovery after
 * a push, free fall, prescribed nodes, spheres from a .sph file. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "meshgen/tb_meshgen.h"
#include "meshgen/tb_sphpack.h"
#include "models/tb_metaball.h"
#include "models/tb_model.h"

/* The 252-vertex sphere of radius 1 as a metaball model. */
static int ball(tb_model *m, tb_mesh *mesh, const char *kv) {
  tb_error err;
  if (tb_geosphere(252, 1.0, mesh, &err)) {
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

static double max_move(const tb_mesh *mesh, const tb_vec3 *x) {
  double d = 0;
  for (int i = 0; i < mesh->nv; i++) d = fmax(d, tb_dist(x[i], mesh->x[i]));
  return d;
}

/* Without loads nothing moves, bit for bit up to rounding. */
static void rest_stays(void) {
  tb_model m;
  tb_mesh mesh;
  if (ball(&m, &mesh, "")) return;
  tb_error err;
  tb_step in = {0};
  in.dt = 0.01;
  double d0 = max_move(&mesh, tb_model_positions(&m)), d = 0;
  for (int k = 0; k < 100; k++) {
    TB_CHECK(tb_model_step(&m, &in, &err) == 0);
    d = fmax(d, max_move(&mesh, tb_model_positions(&m)));
  }
  /* the skin at rest is the Gaussian blend of rest offsets: the nodes */
  TB_CHECK_MSG(d0 < 1e-12 && d < 1e-12, "moved %g (at create %g)", d, d0);
  double M = 0;
  for (int i = 0; i < mesh.nv; i++) M += tb_model_masses(&m)[i];
  TB_CHECK_NEAR(M, tb_mesh_volume(&mesh), 1e-9 * M); /* density 1 */
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* A rigid motion of the spheres moves the skin rigidly (to 1e-12 of the
 * size: the skin is sum w (c + R o) with weights summing to 1). */
static void rigid_skin(void) {
  tb_mesh mesh;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &mesh, &err) == 0);
  tb_sphpack_def def = tb_sphpack_default_def(40);
  tb_spheres sp = {0};
  TB_CHECK_MSG(tb_sphere_pack(&mesh, "ball", &def, &sp, NULL, &err) == 0, "%s", err.msg);
  tb_metaball_settings set;
  tb_metaball_settings_default(&set);
  tb_metaball *mb = tb_metaball_create(sp.n, sp.c, sp.r, &mesh, &set, &err);
  TB_CHECK(mb != NULL);
  if (mb) {
    tb_mat3 R = tb_m3_rotation(tb_normalize(tb_v3(1, 2, 3)), 0.7);
    double r9[9];
    for (int a = 0; a < 9; a++) r9[a] = R.m[a / 3][a % 3];
    tb_vec3 t = tb_v3(0.3, -2, 5);
    tb_metaball_transform(mb, r9, t);
    double worst = 0;
    for (int v = 0; v < mesh.nv; v++)
      worst = fmax(worst, tb_dist(tb_metaball_skin(mb)[v], tb_add(tb_m3_mulv(R, mesh.x[v]), t)));
    TB_CHECK_MSG(worst < 1e-12 * 2, "skin off the rigid image by %g", worst);
    tb_metaball_destroy(mb);
  }
  tb_spheres_free(&sp);
  tb_mesh_free(&mesh);
}

/* Ids of the nodes with (x - c).n > h (a cap of the ball). */
static int cap(const tb_mesh *mesh, tb_vec3 n, double h, int *ids) {
  int k = 0;
  for (int i = 0; i < mesh->nv; i++)
    if (tb_dot(mesh->x[i], n) > h) ids[k++] = i;
  return k;
}

/* Held by its bottom under gravity, the ball sags and comes to rest. */
static void sag_to_rest(void) {
  tb_model m;
  tb_mesh mesh;
  if (ball(&m, &mesh, "")) return;
  int *ids = malloc(sizeof(int) * (size_t)mesh.nv);
  tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
  int nf = cap(&mesh, tb_v3(0, 0, -1), 0.9, ids);
  TB_CHECK(nf >= 3);
  for (int k = 0; k < nf; k++) at[k] = mesh.x[ids[k]];
  tb_step in = {0};
  in.dt = 0.01, in.gravity = tb_v3(1, 0, -9.81), in.nfixed = nf, in.fixed = ids, in.fixed_x = at;
  tb_error err;
  double vmax = 0;
  for (int k = 0; k < 1500; k++) TB_CHECK(tb_model_step(&m, &in, &err) == 0);
  const tb_vec3 *x = tb_model_positions(&m), *v = tb_model_velocities(&m);
  double zc = 0;
  for (int i = 0; i < mesh.nv; i++) {
    TB_CHECK(tb_isfinite3(x[i]));
    vmax = fmax(vmax, tb_len(v[i])), zc += x[i].z - mesh.x[i].z;
  }
  TB_CHECK_MSG(vmax < 1e-4, "still moving: %g", vmax);
  TB_CHECK_MSG(max_move(&mesh, x) > 1e-3, "no sag: %g", max_move(&mesh, x));
  for (int k = 0; k < nf; k++) TB_CHECK(tb_dist(x[ids[k]], at[k]) == 0);
  free(ids), free(at);
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* Pushed sideways at the top for 0.3 s while held at the bottom, then let
 * go: back to the rest shape within 1e-3 of the size (the unit
 * constraints' fixed points are the rest shape's rigid images). */
static void push_and_recover(void) {
  tb_model m;
  tb_mesh mesh;
  if (ball(&m, &mesh, "")) return;
  int *ids = malloc(sizeof(int) * (size_t)mesh.nv), *top = malloc(sizeof(int) * (size_t)mesh.nv);
  tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
  tb_vec3 *f = calloc((size_t)mesh.nv, sizeof(tb_vec3));
  int nf = cap(&mesh, tb_v3(0, 0, -1), 0.9, ids), nt = cap(&mesh, tb_v3(0, 0, 1), 0.8, top);
  for (int k = 0; k < nf; k++) at[k] = mesh.x[ids[k]];
  tb_step in = {0};
  in.dt = 0.01, in.nfixed = nf, in.fixed = ids, in.fixed_x = at, in.force = f;
  tb_error err;
  double most = 0;
  for (int k = 0; k < 1000; k++) {
    for (int q = 0; q < nt; q++) f[top[q]] = k < 30 ? tb_v3(20.0 / nt, 0, 0) : tb_v3(0, 0, 0);
    TB_CHECK(tb_model_step(&m, &in, &err) == 0);
    most = fmax(most, max_move(&mesh, tb_model_positions(&m)));
  }
  double left = max_move(&mesh, tb_model_positions(&m));
  TB_CHECK_MSG(most > 0.02, "the push moved it only %g", most);
  TB_CHECK_MSG(left < 1e-3 * 2, "left displaced by %g (largest %g)", left, most);
  free(ids), free(top), free(at), free(f);
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* Free fall: symplectic Euler's drop g dt^2 n (n + 1) / 2 exactly (the
 * damping acts relative to the rigid motion only). */
static void free_fall(void) {
  tb_model m;
  tb_mesh mesh;
  if (ball(&m, &mesh, "")) return;
  tb_step in = {0};
  in.dt = 0.01, in.gravity = tb_v3(0, 0, -9.81);
  tb_error err;
  int n = 30;
  for (int k = 0; k < n; k++) TB_CHECK(tb_model_step(&m, &in, &err) == 0);
  double want = 9.81 * in.dt * in.dt * n * (n + 1) / 2, worst = 0;
  for (int i = 0; i < mesh.nv; i++) {
    tb_vec3 d = tb_sub(tb_model_positions(&m)[i], mesh.x[i]);
    worst = fmax(worst, tb_dist(d, tb_v3(0, 0, -want)));
  }
  TB_CHECK_MSG(worst < 1e-9, "off the exact drop %g by %g", want, worst);
  TB_CHECK_NEAR(tb_model_velocities(&m)[0].z, -9.81 * in.dt * n, 1e-9);
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* Prescribed nodes end the step exactly at their targets with the velocity
 * that moved them; bad prescribed sets are errors. */
static void prescribed_exact(void) {
  tb_model m;
  tb_mesh mesh;
  if (ball(&m, &mesh, "")) return;
  int *ids = malloc(sizeof(int) * (size_t)mesh.nv);
  tb_vec3 *at = malloc(sizeof(tb_vec3) * (size_t)mesh.nv);
  int nf = cap(&mesh, tb_v3(1, 0, 0), 0.85, ids);
  tb_step in = {0};
  in.dt = 0.01, in.nfixed = nf, in.fixed = ids, in.fixed_x = at;
  tb_error err;
  for (int k = 1; k <= 50; k++) {
    for (int q = 0; q < nf; q++) at[q] = tb_add(mesh.x[ids[q]], tb_v3(0.004 * k, 0, 0));
    tb_vec3 before = tb_model_positions(&m)[ids[0]];
    TB_CHECK(tb_model_step(&m, &in, &err) == 0);
    for (int q = 0; q < nf; q++) TB_CHECK(tb_dist(tb_model_positions(&m)[ids[q]], at[q]) == 0);
    tb_vec3 v = tb_model_velocities(&m)[ids[0]];
    TB_CHECK(tb_dist(v, tb_scale(tb_sub(at[0], before), 1 / in.dt)) < 1e-12);
  }
  /* the body follows the pulled side */
  double pulled = 0;
  for (int i = 0; i < mesh.nv; i++) pulled += tb_model_positions(&m)[i].x - mesh.x[i].x;
  TB_CHECK_MSG(pulled / mesh.nv > 0.02, "mean x displacement %g", pulled / mesh.nv);
  int bad[2] = {5, 3};
  in.nfixed = 2, in.fixed = bad;
  TB_CHECK(tb_model_step(&m, &in, &err) && strstr(err.msg, "ascending"));
  free(ids), free(at);
  tb_model_destroy(&m);
  tb_mesh_free(&mesh);
}

/* A tet mesh: every node (interior ones too) is a point; an open surface
 * is refused with a reason. */
static void inputs(void) {
  tb_mesh beam, open = {0};
  tb_error err;
  TB_CHECK(tb_beam(2, 1, 1, 4, 2, 2, &beam, &err) == 0);
  tb_model m;
  TB_CHECK_MSG(tb_model_create(&m, "metaball", &beam, NULL, &err) == 0, "%s", err.msg);
  if (m.self) {
    TB_CHECK(tb_model_npoints(&m) == beam.nv);
    TB_CHECK(max_move(&beam, tb_model_positions(&m)) < 1e-12);
    tb_model_destroy(&m);
  }
  open.nv = 3, open.x = beam.x, open.ntri = 1;
  int tri[3] = {0, 1, 2};
  open.tri = tri;
  TB_CHECK(tb_model_create(&m, "metaball", &open, NULL, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "closed") || strstr(err.msg, "boundary"), "%s", err.msg);
  tb_mesh_free(&beam);
}

/* spheres_file: the model takes a SOFA .sph file's spheres instead of
 * packing (their count, centres and radii, every node skinned and at
 * rest); with spheres also set, a missing file or a malformed one, create
 * fails saying why (the file's name; FILE:LINE for a bad line). */
static void spheres_from_file(void) {
  tb_mesh mesh;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &mesh, &err) == 0);
  const char *good =
      tb_test_file("ball.sph",
                   "sph 1.0\n#nums 5\nsphe 0 0 0 0 0.7\nsphe 1 0.45 0 0 0.5\n"
                   "sphe 2 -0.45 0 0 0.5\nsphe 3 0 0.45 0 0.5\nsphe 4 0 -0.45 0 0.5\n",
                   -1);
  char kv[700];
  snprintf(kv, sizeof kv, "spheres_file=%s", good);
  tb_settings s = tb_test_settings(kv);
  tb_model m;
  int rc = tb_model_create(&m, "metaball", &mesh, &s, &err);
  TB_CHECK_MSG(rc == 0, "%s", err.msg);
  if (rc == 0) {
    tb_model_spheres ms = m.cls->spheres(m.self);
    TB_CHECK_MSG(ms.n == 5, "%d spheres, the file has 5", ms.n);
    TB_CHECK(ms.n == 5 && ms.r[0] == 0.7 && ms.c[1].x == 0.45 && ms.r[4] == 0.5);
    TB_CHECK(max_move(&mesh, tb_model_positions(&m)) < 1e-12);
    tb_model_destroy(&m);
  }
  snprintf(kv, sizeof kv, "spheres_file=%s spheres=5", good);
  s = tb_test_settings(kv);
  TB_CHECK(tb_model_create(&m, "metaball", &mesh, &s, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "not both"), "%s", err.msg);
  s = tb_test_settings("spheres_file=/nonexistent/x.sph");
  TB_CHECK(tb_model_create(&m, "metaball", &mesh, &s, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "/nonexistent/x.sph"), "%s", err.msg);
  const char *bad =
      tb_test_file("bad.sph", "sph 1.0\n#nums 2\nsphe 0 0 0 0 0.5\nsphe 1 0 0 x 0.5\n", -1);
  snprintf(kv, sizeof kv, "spheres_file=%s", bad);
  s = tb_test_settings(kv);
  TB_CHECK(tb_model_create(&m, "metaball", &mesh, &s, &err) != 0);
  char want[700];
  snprintf(want, sizeof want, "%s:4", bad);
  TB_CHECK_MSG(strstr(err.msg, want), "%s", err.msg);
  tb_mesh_free(&mesh);
}

const tb_test_case tb_tests_metaball_model[] = {
    {"rest_stays", rest_stays},
    {"rigid_skin", rigid_skin},
    {"sag_to_rest", sag_to_rest},
    {"push_and_recover", push_and_recover},
    {"free_fall", free_fall},
    {"prescribed_exact", prescribed_exact},
    {"inputs", inputs},
    {"spheres_from_file", spheres_from_file},
    {NULL, NULL},
};
