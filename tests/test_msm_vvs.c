/* Tests of msm-vvs (models/msm_vvs.c; Bao 2006 eqs 1-3, §2): rest is a
 * fixed point, the virtual volumetric spring's force and the quasi-static
 * update against hand-computed values, the paper's claim measured on
 * sphere-press (recovery with the virtual springs, a lasting and deeper
 * dent without), the interior nodes of a tet mesh following the surface,
 * bad input, and the stability bound of the quasi-static step. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"
#include "scenes/tb_sim.h"

static int create(tb_model *m, const tb_mesh *mesh, const char *kvs) {
  tb_error err;
  tb_settings s = tb_test_settings(kvs);
  if (tb_model_create(m, "msm-vvs", mesh, &s, &err)) {
    tb_test_fail(__FILE__, __LINE__, "create: %s", err.msg);
    return -1;
  }
  return 0;
}

static int step(tb_model *m, double dt) {
  tb_step in;
  memset(&in, 0, sizeof in);
  in.dt = dt;
  tb_error err;
  if (tb_model_step(m, &in, &err)) {
    tb_test_fail(__FILE__, __LINE__, "step: %s", err.msg);
    return -1;
  }
  return 0;
}

/* The surface of the tet (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward. */
static void tet_surface(tb_mesh *m) {
  static const int tri[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
  memset(m, 0, sizeof *m);
  m->nv = 4, m->ntri = 4;
  m->x = malloc(sizeof(tb_vec3) * 4);
  m->tri = malloc(sizeof tri);
  m->x[0] = tb_v3(0, 0, 0), m->x[1] = tb_v3(1, 0, 0), m->x[2] = tb_v3(0, 1, 0);
  m->x[3] = tb_v3(0, 0, 1);
  memcpy(m->tri, tri, sizeof tri);
}

/* 1. One step from rest moves nothing, bit for bit (both integrators; a
 * surface, and a tet mesh whose interior nodes follow). */
static void rest_is_fixed_point(void) {
  tb_mesh sphere, beam;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &sphere, &err) == 0);
  TB_CHECK(tb_beam(3, 1, 1, 6, 2, 2, &beam, &err) == 0);
  const tb_mesh *meshes[2] = {&sphere, &beam};
  const char *kvs[2] = {"", "integrator=euler"};
  for (int q = 0; q < 4; q++) {
    const tb_mesh *mesh = meshes[q / 2];
    tb_model m;
    if (create(&m, mesh, kvs[q % 2])) continue;
    for (int k = 0; k < 3; k++) step(&m, 0.01);
    const tb_vec3 *x = tb_model_positions(&m), *v = tb_model_velocities(&m);
    int moved = 0;
    for (int i = 0; i < mesh->nv; i++)
      moved += memcmp(&x[i], &mesh->x[i], sizeof x[i]) || v[i].x != 0 || v[i].y != 0 || v[i].z != 0;
    TB_CHECK_MSG(!moved, "%s %s: %d nodes moved from rest", q / 2 ? "beam" : "sphere", kvs[q % 2],
                 moved);
    TB_CHECK(tb_model_energy(&m) == 0);
    tb_model_destroy(&m);
  }
  tb_mesh_free(&sphere), tb_mesh_free(&beam);
}

/* 2. The virtual volumetric spring alone (ks = kd = 0): a node displaced
 * by dx with velocity v gets -[k's |dx| + k'd (v.dx)/|dx|] dx/|dx|, read
 * back through one quasi-static step (dx_new = alpha F dt^2 / m) and one
 * Euler step (v_new = v + dt F / m); at dx = 0 it gets nothing. */
static void virtual_spring_force(void) {
  tb_mesh mesh;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &mesh, &err) == 0);
  const tb_vec3 dx = tb_v3(0.1, -0.2, 0.05), v = tb_v3(0.3, 0.1, -0.4);
  /* by hand: |dx|^2 = 0.0525, v.dx = -0.01, k's 1.5, k'd 0.5:
   * F = -(1.5 + 0.5 * -0.01 / 0.0525) dx = -1.4047619047619047 dx */
  const double c = -(1.5 - 0.005 / 0.0525);
  TB_CHECK_NEAR(c, -1.4047619047619047, 1e-15);
  const tb_vec3 F = tb_scale(dx, c);
  const double dt = 0.1, m = 2.0, alpha = 3.0;
  for (int euler = 0; euler < 2; euler++) {
    tb_model md;
    char kvs[128];
    snprintf(kvs, sizeof kvs, "ks=0 kd=0 ks_v=1.5 kd_v=0.5 node_mass=2 alpha=3 integrator=%s",
             euler ? "euler" : "quasistatic");
    if (create(&md, &mesh, kvs)) continue;
    int id = 17;
    tb_vec3 x0 = tb_add(mesh.x[id], dx);
    tb_model_correct(&md, 1, &id, &x0, &v);
    step(&md, dt);
    tb_vec3 got = tb_model_positions(&md)[id], gv = tb_model_velocities(&md)[id];
    tb_vec3 want, wantv;
    if (euler) {
      wantv = tb_madd(v, dt / m, F), want = tb_madd(x0, dt, wantv);
    } else {
      want = tb_madd(x0, alpha * dt * dt / m, F), wantv = tb_scale(tb_sub(want, x0), 1 / dt);
    }
    TB_CHECK_MSG(tb_dist(got, want) < 1e-15 && tb_dist(gv, wantv) < 1e-13,
                 "%s: x off by %g, v off by %g", euler ? "euler" : "quasistatic",
                 tb_dist(got, want), tb_dist(gv, wantv));
    /* every other node: no force, no motion */
    int moved = 0;
    for (int i = 0; i < mesh.nv; i++)
      moved += i != id && memcmp(&tb_model_positions(&md)[i], &mesh.x[i], sizeof(tb_vec3));
    TB_CHECK(!moved);
    /* at dx = 0 with a velocity: no force from the spring (and no NaN) */
    tb_vec3 vx = tb_v3(1, 2, 3);
    tb_model_correct(&md, 1, &id, &mesh.x[id], &vx);
    step(&md, dt);
    got = tb_model_positions(&md)[id], gv = tb_model_velocities(&md)[id];
    if (euler)
      TB_CHECK(tb_dist(gv, vx) == 0 && tb_dist(got, tb_madd(mesh.x[id], dt, vx)) == 0);
    else
      TB_CHECK(tb_dist(got, mesh.x[id]) == 0 && tb_len(gv) == 0);
    tb_model_destroy(&md);
  }
  tb_mesh_free(&mesh);
}

/* 3. The quasi-static update on the tet's surface with node 0 displaced by
 * (-0.1, 0, 0): by hand, edge 0-1 is 1.1 long (rest 1), edges 0-2 and 0-3
 * sqrt(1.01) (rest 1), so with ks 3, k's 1.5
 *   F_0 = (0.3 + 2 * 3 (l - 1)/l * 0.1 + 0.15, 3 (l - 1)/l, 3 (l - 1)/l),
 *   F_1 = (-0.3, 0, 0), F_2 = 3 (l - 1)/l (-0.1, -1, 0), F_3 = 3 (l - 1)/l (-0.1, 0, -1),
 * and each node moves alpha F dt^2 / m (alpha 2, dt 0.01, m 1). */
static void quasistatic_update(void) {
  tb_mesh mesh;
  tet_surface(&mesh);
  tb_model md;
  if (create(&md, &mesh, "alpha=2")) {
    tb_mesh_free(&mesh);
    return;
  }
  int id = 0;
  tb_vec3 x0 = tb_v3(-0.1, 0, 0), zero = tb_v3(0, 0, 0);
  tb_model_correct(&md, 1, &id, &x0, &zero);
  step(&md, 0.01);
  const double l = sqrt(1.01), s = 3 * (l - 1) / l, h = 2 * 0.01 * 0.01;
  const tb_vec3 F[4] = {tb_v3(0.3 + 2 * s * 0.1 + 0.15, s, s), tb_v3(-0.3, 0, 0),
                        tb_v3(-0.1 * s, -s, 0), tb_v3(-0.1 * s, 0, -s)};
  const tb_vec3 *x = tb_model_positions(&md), *v = tb_model_velocities(&md);
  for (int i = 0; i < 4; i++) {
    tb_vec3 start = i ? mesh.x[i] : x0, want = tb_madd(start, h, F[i]);
    TB_CHECK_MSG(tb_dist(x[i], want) < 1e-16, "node %d off by %g", i, tb_dist(x[i], want));
    TB_CHECK(tb_dist(v[i], tb_scale(F[i], h / 0.01)) < 1e-14); /* v = dx / dt */
  }
  tb_model_destroy(&md);
  tb_mesh_free(&mesh);
}

/* Runs scene with the extra model setting kv (NULL: none) to its end;
 * returns the largest node distance to rest at the end over the radius
 * (1) and the probe's largest mean displacement over the run. */
static int run_sphere(const char *scene, const char *kv, double *residual, double *peak) {
  tb_settings set = tb_test_settings(kv ? kv : "");
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, scene, NULL, NULL, &set, NULL, &err)) {
    tb_test_fail(__FILE__, __LINE__, "%s: %s", scene, err.msg);
    return -1;
  }
  TB_CHECK(!strcmp(s.model.cls->name, "msm-vvs") && s.mesh.nv == 252 && s.mesh.ntri == 500);
  long n = lround(s.def.duration / s.def.dt);
  for (long k = 0; k < n; k++)
    if (tb_sim_step(&s, &err)) {
      tb_test_fail(__FILE__, __LINE__, "%s %s: %s", scene, kv ? kv : "", err.msg);
      tb_sim_destroy(&s);
      return -1;
    }
  *residual = tb_sim_measure(&s).max_disp, *peak = s.probe_peak;
  tb_sim_destroy(&s);
  return 0;
}

/* 4. The paper's claim (§4, figs 6-7): pressed and let go, the sphere with
 * virtual springs returns within 1% of its radius; the hollow shell does
 * not, and the same force dents it deeper. The same for the stretch. */
static void sphere_recovers(void) {
  static const char *const scenes[2] = {"sphere-press", "sphere-stretch"};
  for (int q = 0; q < 2; q++) {
    double res1, peak1, res0, peak0;
    if (run_sphere(scenes[q], NULL, &res1, &peak1) ||
        run_sphere(scenes[q], "volume_springs=0", &res0, &peak0))
      continue;
    printf("  %s: with virtual springs deepest %.4g, residual %.4g; hollow shell %.4g, %.4g\n",
           scenes[q], peak1, res1, peak0, res0);
    TB_CHECK_MSG(peak1 > 0.1 && peak1 < 0.3, "%s: a dent of %g (want 10-30%% of the radius)",
                 scenes[q], peak1);
    TB_CHECK_MSG(res1 < 0.01, "%s: residual %g of the radius with virtual springs", scenes[q],
                 res1);
    TB_CHECK_MSG(res0 > 0.01, "%s: the hollow shell recovered (%g)", scenes[q], res0);
    TB_CHECK_MSG(peak1 < peak0, "%s: dent %g with, %g without", scenes[q], peak1, peak0);
  }
}

/* 5. A tet mesh: the boundary is simulated, each interior node keeps the
 * displacement of its nearest surface node at rest. */
static void interior_follows(void) {
  tb_mesh beam;
  tb_error err;
  TB_CHECK(tb_beam(2, 1, 1, 4, 2, 2, &beam, &err) == 0);
  int *bnd = NULL, nb = tb_mesh_tet_boundary(&beam, &bnd);
  char *on = calloc((size_t)beam.nv, 1);
  for (int k = 0; k < 3 * nb; k++) on[bnd[k]] = 1;
  tb_model md;
  if (create(&md, &beam, "")) return;
  tb_surface surf = tb_model_surface(&md);
  TB_CHECK(surf.ntri == nb && !memcmp(surf.tri, bnd, sizeof(int) * 3 * (size_t)nb));
  tb_vec3 *f = malloc(sizeof(tb_vec3) * (size_t)beam.nv); /* a load varying over the nodes */
  for (int i = 0; i < beam.nv; i++) f[i] = tb_v3(beam.x[i].x, beam.x[i].y * beam.x[i].y, 0.01 * i);
  tb_step in;
  memset(&in, 0, sizeof in);
  in.dt = 0.01, in.gravity = tb_v3(0, 0, -9.81), in.force = f;
  for (int k = 0; k < 10; k++) TB_CHECK(tb_model_step(&md, &in, &err) == 0);
  free(f);
  const tb_vec3 *x = tb_model_positions(&md);
  int interior = 0;
  for (int i = 0; i < beam.nv; i++) {
    if (on[i]) continue;
    interior++;
    int at = -1;
    double best = INFINITY;
    for (int j = 0; j < beam.nv; j++)
      if (on[j] && tb_dist(beam.x[i], beam.x[j]) < best)
        best = tb_dist(beam.x[i], beam.x[j]), at = j;
    tb_vec3 ui = tb_sub(x[i], beam.x[i]), uj = tb_sub(x[at], beam.x[at]);
    TB_CHECK_MSG(tb_dist(ui, uj) < 1e-15 && tb_len(uj) > 0, "node %d: %g", i, tb_dist(ui, uj));
  }
  TB_CHECK(interior == 3);
  tb_model_destroy(&md);
  free(bnd), free(on);
  tb_mesh_free(&beam);
}

/* 6. Bad input: an open surface, a cloud of points, settings out of range;
 * a tet model on a surface scene; the quasi-static step beyond its bound. */
static void bad_input(void) {
  tb_mesh mesh;
  tb_error err;
  TB_CHECK(tb_geosphere(252, 1.0, &mesh, &err) == 0);
  tb_model md;
  mesh.ntri--; /* one triangle less: three open edges */
  TB_CHECK(tb_model_create(&md, "msm-vvs", &mesh, NULL, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "closed manifold surface") && strstr(err.msg, "3 open (boundary)"),
               "%s", err.msg);
  mesh.ntri = 0;
  TB_CHECK(tb_model_create(&md, "msm-vvs", &mesh, NULL, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "no triangles"), "%s", err.msg);
  mesh.ntri = 500;
  static const char *const bad[] = {"alpha=0",  "alpha=-1",         "ks=-3",
                                    "kd_v=-1",  "volume_springs=2", "integrator=rk4",
                                    "ks_v=nan", "node_mass=-1"};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    tb_settings s = tb_test_settings(bad[k]);
    char key[32];
    snprintf(key, sizeof key, "%.*s", (int)strcspn(bad[k], "="), bad[k]);
    TB_CHECK_MSG(tb_model_create(&md, "msm-vvs", &mesh, &s, &err) != 0 && strstr(err.msg, key) &&
                     strstr(err.msg, "msm-vvs"),
                 "%s: %s", bad[k], err.msg);
  }
  tb_mesh_free(&mesh);
  /* the CLI: an open surface file, and a tet model on a surface scene */
  const char *obj =
      tb_test_file("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\n", -1);
  char args[700];
  snprintf(args, sizeof args, "simulate --model msm-vvs --mesh %s --steps 2", obj);
  TB_CHECK(tb_test_cli_run(args) == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "closed manifold surface") && strstr(tb_test_out, "open"), "%s",
               tb_test_out);
  /* a tet model on a surface scene: TetGen meshes the sphere; an open surface cannot be */
  TB_CHECK(tb_test_cli_run("simulate --scene sphere-press --model fem --steps 5") == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "252 vertices and 500 triangles tetrahedralised by TetGen"),
               "%s", tb_test_out);
  snprintf(args, sizeof args, "simulate --model fem --mesh %s --steps 2", obj);
  TB_CHECK(tb_test_cli_run(args) == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "model fem needs tets") && strstr(tb_test_out, "mesh close"),
               "%s", tb_test_out);
  TB_CHECK(tb_test_cli_run("simulate --scene sphere-press --set alpha=0") == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "alpha"), "%s", tb_test_out);
  /* the documented bound alpha (kd + kd_v) dt / m < 1: 95 runs, 120 blows up */
  TB_CHECK(tb_test_cli_run("simulate --scene sphere-press --set alpha=95 --steps 400") == 0);
  TB_CHECK(tb_test_cli_run("simulate --scene sphere-press --set alpha=120 --steps 400") == 1);
  TB_CHECK_MSG(strstr(tb_test_out, "status: unstable"), "%s", tb_test_out);
}

/* 7. The summary of sphere-press: the dent over the run, the time per step. */
static void sphere_press_cli(void) {
  TB_CHECK(tb_test_cli_run("simulate --scene sphere-press") == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "model msm-vvs") && strstr(tb_test_out, "status: stable") &&
                   strstr(tb_test_out, "probe: largest mean displacement over the run 0.2") &&
                   strstr(tb_test_out, "enclosed by the surface") &&
                   strstr(tb_test_out, "at rest at t = 12 s"),
               "%s", tb_test_out);
}

const tb_test_case tb_tests_msm_vvs[] = {
    {"rest_is_fixed_point", rest_is_fixed_point}, {"virtual_spring_force", virtual_spring_force},
    {"quasistatic_update", quasistatic_update},   {"sphere_recovers", sphere_recovers},
    {"interior_follows", interior_follows},       {"bad_input", bad_input},
    {"sphere_press_cli", sphere_press_cli},       {NULL, NULL},
};
