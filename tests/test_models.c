/* Tests of the model interface and its shared helpers (models/model.c,
 * models/model_util.c) and of the simulation driver (bench/sim.c). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_meshgen.h"
#include "tb_model.h"
#include "tb_rng.h"
#include "tb_sim.h"
#include "tb_test.h"

static double m3_diff(tb_mat3 a, tb_mat3 b) {
  double d = 0;
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) d = fmax(d, fabs(a.m[i][j] - b.m[i][j]));
  return d;
}

static tb_mat3 random_rotation(tb_rng *r) {
  tb_vec3 axis = tb_v3(tb_rng_normal(r), tb_rng_normal(r), tb_rng_normal(r));
  return tb_m3_rotation(axis, tb_rng_range(r, -3.1, 3.1));
}

static tb_mat3 diag(double a, double b, double c) {
  tb_mat3 d = tb_m3_identity();
  d.m[0][0] = a, d.m[1][1] = b, d.m[2][2] = c;
  return d;
}

/* R S with S symmetric positive definite gives back R; det R = +1 always. */
static void polar_recovers_rotation(void) {
  tb_rng r = tb_rng_seed(7);
  for (int k = 0; k < 1000; k++) {
    tb_mat3 R = random_rotation(&r), Q = random_rotation(&r);
    tb_mat3 S = tb_m3_mul(tb_m3_mul(Q, diag(tb_rng_range(&r, 0.1, 3), tb_rng_range(&r, 0.1, 3),
                                            tb_rng_range(&r, 0.1, 3))),
                          tb_m3_transpose(Q));
    tb_mat3 P = tb_m3_polar(tb_m3_mul(R, S));
    TB_CHECK_MSG(m3_diff(P, R) < 1e-9, "case %d: |P - R| = %g", k, m3_diff(P, R));
  }
  /* singular (flattened) and inverted matrices still give a proper rotation */
  for (int k = 0; k < 1000; k++) {
    tb_mat3 R = random_rotation(&r), Q = random_rotation(&r);
    double s0 = k % 2 ? 0.0 : -tb_rng_range(&r, 0.01, 1);
    tb_mat3 A = tb_m3_mul(R, tb_m3_mul(Q, tb_m3_mul(diag(s0, 1, 2), tb_m3_transpose(Q))));
    tb_mat3 P = tb_m3_polar(A);
    TB_CHECK_NEAR(tb_m3_det(P), 1.0, 1e-9);
    TB_CHECK(m3_diff(tb_m3_mul(tb_m3_transpose(P), P), tb_m3_identity()) < 1e-9);
  }
  TB_CHECK(m3_diff(tb_m3_polar(diag(0, 0, 0)), tb_m3_identity()) == 0);
}

static void eigen_and_inverse(void) {
  tb_rng r = tb_rng_seed(3);
  for (int k = 0; k < 200; k++) {
    tb_mat3 Q = random_rotation(&r), V;
    double w[3], a = tb_rng_range(&r, -5, 5), b = tb_rng_range(&r, -5, 5), c = a; /* a repeated */
    tb_mat3 A = tb_m3_mul(tb_m3_mul(Q, diag(a, b, c)), tb_m3_transpose(Q));
    tb_m3_sym_eigen(A, w, &V);
    TB_CHECK(w[0] <= w[1] && w[1] <= w[2]);
    TB_CHECK_NEAR(w[0] + w[1] + w[2], a + b + c, 1e-9);
    TB_CHECK(m3_diff(tb_m3_mul(tb_m3_mul(V, diag(w[0], w[1], w[2])), tb_m3_transpose(V)), A) <
             1e-9);
    tb_mat3 inv;
    if (fabs(a) > 0.1 && fabs(b) > 0.1) {
      TB_CHECK(tb_m3_inverse(A, &inv));
      TB_CHECK(m3_diff(tb_m3_mul(A, inv), tb_m3_identity()) < 1e-9);
    }
  }
  tb_mat3 inv;
  TB_CHECK(!tb_m3_inverse(diag(1, 1, 0), &inv));
}

static void settings_parse_and_check(void) {
  tb_model_def d = tb_model_default_def();
  tb_error err;
  TB_CHECK(d.ks == 180 && d.kd == 5 && d.E == 3000 && d.nu == 0.3 && d.clusters == 50 &&
           d.alpha == 0.72 && d.beta == 0.63 && d.sm_mode == TB_SM_QUADRATIC && d.radius == 1);
  TB_CHECK(tb_model_def_set(&d, "ks=200.5", &err) == 0 && d.ks == 200.5);
  TB_CHECK(tb_model_def_set(&d, "sm_mode=linear", &err) == 0 && d.sm_mode == TB_SM_LINEAR);
  TB_CHECK(tb_model_def_set(&d, "cluster_mode=tets", &err) == 0 && d.cluster_mode == 1);
  TB_CHECK(tb_model_def_set(&d, "clusters=8", &err) == 0 && d.clusters == 8);
  TB_CHECK(tb_model_def_set(&d, "clusters=8.5", &err) && strstr(err.msg, "clusters"));
  TB_CHECK(tb_model_def_set(&d, "sm_mode=cubic", &err) && strstr(err.msg, "rigid, linear"));
  TB_CHECK(tb_model_def_set(&d, "E=abc", &err) && strstr(err.msg, "E: 'abc'"));
  TB_CHECK(tb_model_def_set(&d, "E=inf", &err));
  TB_CHECK(tb_model_def_set(&d, "stiffness=3", &err) && strstr(err.msg, "unknown model setting"));
  TB_CHECK(tb_model_def_set(&d, "ks", &err) && strstr(err.msg, "key=value"));
  TB_CHECK(tb_model_def_check(&d, &err) == 0);
  d.nu = 0.5;
  TB_CHECK(tb_model_def_check(&d, &err) && strstr(err.msg, "nu"));
  d = tb_model_default_def(), d.alpha = 1.5;
  TB_CHECK(tb_model_def_check(&d, &err) && strstr(err.msg, "alpha"));
  tb_mesh m;
  memset(&m, 0, sizeof m);
  tb_model model;
  d = tb_model_default_def();
  TB_CHECK(tb_model_create(&model, "springs", &m, &d, &err) && strstr(err.msg, "unknown model"));
  for (int i = 0; i < tb_model_count; i++)
    TB_CHECK(tb_model_find(tb_model_classes[i]->name) == tb_model_classes[i]);
}

static void health_detects_blow_up(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_beam(2, 1, 1, 2, 1, 1, &m, &err) == 0);
  tb_vec3 x[64], v[64];
  TB_CHECK(m.nv <= 64);
  memcpy(x, m.x, sizeof(tb_vec3) * (size_t)m.nv);
  memset(v, 0, sizeof v);
  TB_CHECK(tb_model_health(&m, x, v, 10, 1).ok);
  v[3] = tb_v3(0, 20, 0);
  tb_health h = tb_model_health(&m, x, v, 10, 1);
  TB_CHECK(!h.ok && strstr(h.reason, "velocity"));
  v[3] = tb_v3(0, 0, 0);
  x[2].y = NAN;
  h = tb_model_health(&m, x, v, 10, 1);
  TB_CHECK(!h.ok && strstr(h.reason, "NaN"));
  for (int i = 0; i < m.nv; i++) x[i] = tb_v3(-m.x[i].x, m.x[i].y, m.x[i].z); /* mirrored */
  h = tb_model_health(&m, x, v, 10, 1);
  TB_CHECK_MSG(!h.ok && strstr(h.reason, "inverted elements (12"), "%s", h.reason);
  TB_CHECK(tb_model_health(&m, x, v, 10, 0).ok); /* inversion not checked */
  tb_mesh_free(&m);
}

static void scene_settings(void) {
  tb_sim_def d;
  memset(&d, 0, sizeof d);
  tb_error err;
  TB_CHECK(tb_sim_def_set(&d, "dt=0.005", &err) == 0 && d.dt == 0.005);
  TB_CHECK(tb_sim_def_set(&d, "nodes=600", &err) == 0 && d.nodes == 600);
  TB_CHECK(tb_sim_def_set(&d, "nodes=6.5", &err) == -1 && strstr(err.msg, "nodes"));
  TB_CHECK(tb_sim_def_set(&d, "amplitude=-1", &err) == -1);
  TB_CHECK(tb_sim_def_set(&d, "ks=3", &err) == 1); /* a model key */
  int n;
  const char *const *names = tb_sim_scene_names(&n);
  TB_CHECK(n >= 4 && !strcmp(names[0], "liver-stretch"));
  tb_sim s;
  tb_model_def md = tb_model_default_def();
  TB_CHECK(tb_sim_create(&s, "liver-squeeze", NULL, "msm", &md, NULL, &err) &&
           strstr(err.msg, "unknown scene"));
}

/* Runs a scene with a model for n steps; returns the sim (caller destroys). */
static int run_scene(tb_sim *s, const char *scene, const char *model, tb_sim_def *sd, long n,
                     tb_error *err) {
  tb_model_def md = tb_model_default_def();
  md.node_mass = 1;
  if (tb_sim_create(s, scene, sd, model, &md, NULL, err)) return -1;
  for (long k = 0; k < n; k++)
    if (tb_sim_step(s, err)) return -1;
  return 0;
}

/* Free fall: every model's centre of mass drops by about g t^2 / 2. */
static void drop_follows_gravity(void) {
  for (int i = 0; i < tb_model_count; i++) {
    tb_sim_def sd;
    memset(&sd, 0, sizeof sd);
    sd.nodes = 300, sd.duration = 0.3;
    tb_sim s;
    tb_error err;
    const char *name = tb_model_classes[i]->name;
    if (run_scene(&s, "drop", name, &sd, 30, &err)) {
      TB_CHECK_MSG(0, "%s: %s", name, err.msg);
      tb_sim_destroy(&s);
      continue;
    }
    double z0 = 0;
    for (int k = 0; k < s.mesh.nv; k++) z0 += s.mesh.x[k].z;
    z0 /= s.mesh.nv;
    double drop = z0 - tb_sim_measure(&s).com_z, exact = 0.5 * 9.81 * 0.3 * 0.3;
    /* explicit and implicit Euler are first order: within 10% at dt 0.01 */
    TB_CHECK_MSG(fabs(drop - exact) < 0.1 * exact, "%s: dropped %g, g t^2 / 2 = %g", name, drop,
                 exact);
    tb_sim_destroy(&s);
  }
}

/* Stretch: the patch is where the scene puts it until release; the
 * anchored back never moves. */
static void stretch_drives_patch(void) {
  for (int i = 0; i < tb_model_count; i++) {
    tb_sim_def sd;
    memset(&sd, 0, sizeof sd);
    sd.nodes = 300, sd.release = 0.5, sd.amplitude = 1.0;
    tb_sim s;
    tb_error err;
    const char *name = tb_model_classes[i]->name;
    if (run_scene(&s, "liver-stretch", name, &sd, 50, &err)) {
      TB_CHECK_MSG(0, "%s: %s", name, err.msg);
      tb_sim_destroy(&s);
      continue;
    }
    const tb_vec3 *x = tb_model_positions(&s.model);
    TB_CHECK(s.ndriven > 3 && s.nanchor > 10);
    for (int k = 0; k < s.ndriven; k++)
      TB_CHECK_NEAR(tb_dist(x[s.driven[k]], s.mesh.x[s.driven[k]]), 1.0, 1e-9);
    for (int k = 0; k < s.nanchor; k++)
      TB_CHECK(tb_dist(x[s.anchor[k]], s.mesh.x[s.anchor[k]]) == 0);
    tb_sim_metrics m = tb_sim_measure(&s);
    TB_CHECK_MSG(m.max_disp >= 1.0 - 1e-9 && m.rms_disp > 0.01, "%s: max %g rms %g", name,
                 m.max_disp, m.rms_disp);
    tb_sim_destroy(&s);
  }
}

/* Press: the instrument comes into contact, the top goes down, and no
 * surface node is left inside the instrument's capsule. */
static void press_contacts(void) {
  tb_sim_def sd;
  memset(&sd, 0, sizeof sd);
  sd.nodes = 300, sd.amplitude = 0.8, sd.duration = 0.8;
  tb_sim s;
  tb_error err;
  tb_model_def md = tb_model_default_def();
  md.node_mass = 1;
  TB_CHECK_MSG(tb_sim_create(&s, "liver-press", &sd, "fem", &md, NULL, &err) == 0, "%s", err.msg);
  int most = 0;
  for (int k = 0; k < 80; k++) {
    TB_CHECK_MSG(tb_sim_step(&s, &err) == 0, "%s", err.msg);
    most = s.ncontact > most ? s.ncontact : most;
  }
  TB_CHECK_MSG(most >= 3, "at most %d nodes in contact", most);
  tb_sim_metrics m = tb_sim_measure(&s);
  TB_CHECK_MSG(m.max_disp > 0.5, "max displacement %g", m.max_disp);
  tb_sim_destroy(&s);
}

static void simulate_cli(void) {
  for (int i = 0; i < tb_model_count; i++) {
    char args[256];
    snprintf(args, sizeof args,
             "simulate --model %s --scene beam --steps 20 --set nodes=10 --set node_mass=1",
             tb_model_classes[i]->name);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
    TB_CHECK_MSG(strstr(tb_test_out, "status: stable") && strstr(tb_test_out, "steps/s") &&
                     strstr(tb_test_out, "volume change"),
                 "%s", tb_test_out);
  }
  char args[512];
  snprintf(args, sizeof args,
           "simulate --model fem --scene beam --steps 10 --every 5 --set nodes=10 --vtk %s/vtk",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  char cmd[512];
  snprintf(cmd, sizeof cmd, "ls %s/vtk | grep -c frame_", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0 && atoi(tb_test_out) == 3);
  /* a run that blows up says why and fails */
  TB_CHECK(tb_test_cli_run("simulate --model msm --scene beam --dt 0.5 --steps 200 "
                           "--set nodes=10 --set ks=5000") == 1);
  TB_CHECK_MSG(strstr(tb_test_out, "status: unstable (") && !strstr(tb_test_out, "steps/s"), "%s",
               tb_test_out);
  /* bad input */
  TB_CHECK(tb_test_cli_run("simulate --model springs --scene beam") == 2);
  TB_CHECK(strstr(tb_test_out, "unknown model 'springs'"));
  TB_CHECK(tb_test_cli_run("simulate --model msm --scene oven") == 2);
  TB_CHECK(tb_test_cli_run("simulate --model msm --scene beam --set bogus=1") == 2);
  TB_CHECK(strstr(tb_test_out, "unknown model setting 'bogus'"));
  TB_CHECK(tb_test_cli_run("simulate --model msm --scene beam --dt 0") == 2);
  TB_CHECK(tb_test_cli_run("simulate --model sm --scene beam --set alpha=2") == 2);
  TB_CHECK(tb_test_cli_run("simulate --model msm") == 2);
}

static void suites_smoke(void) {
  char args[512], cmd[600];
  snprintf(args, sizeof args, "table 3.5 --scale 0.01 --results %s/r", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "cat %s/r/table-3.5/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "335.7") && strstr(tb_test_out, "787.0") &&
                   strstr(tb_test_out, "fem-corot") && strstr(tb_test_out, "Recovery"),
               "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "test -s %s/r/table-3.5/recovery.svg", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  snprintf(args, sizeof args, "figure 3.10 --scale 0.01 --results %s/r", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "test -s %s/r/figure-3.10/fig310.svg", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  TB_CHECK(tb_test_cli_run("figure 9.9") == 2);
  snprintf(args, sizeof args, "table reference --scale 0.01 --results %s/r", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "cat %s/r/reference/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "| 20 | T10 | Neo-Hookean | 0.0996") &&
                   strstr(tb_test_out, "| 20 | T4 | Neo-Hookean | 0.05"),
               "%s", tb_test_out);
}

const tb_test_case tb_tests_models[] = {
    {"polar_recovers_rotation", polar_recovers_rotation},
    {"eigen_and_inverse", eigen_and_inverse},
    {"settings_parse_and_check", settings_parse_and_check},
    {"health_detects_blow_up", health_detects_blow_up},
    {"scene_settings", scene_settings},
    {"drop_follows_gravity", drop_follows_gravity},
    {"stretch_drives_patch", stretch_drives_patch},
    {"press_contacts", press_contacts},
    {"simulate_cli", simulate_cli},
    {"suites_smoke", suites_smoke},
    {0, 0},
};
