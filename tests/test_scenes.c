/* Scene files and the driver (scenes/): file errors with FILE:LINE, the
 * built-in files reproducing the old hand-coded scenes, a static solution
 * checked against an independent assembly, ground contact with friction
 * (rest, stick, slide), the instrument's real-mesh contact, and every model
 * stable on every built-in scene at its defaults. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "core/tb_vtu.h"
#include "scenes/sim_priv.h"
#include "scenes/tb_sim.h"

static const char *scene_file(const char *name, const char *text) {
  return tb_test_file(name, text, -1);
}

/* ---- errors ---- */

static void expect_cli_error(const char *file, const char *text, int line, const char *what) {
  const char *p = scene_file(file, text);
  char args[1400], want[1200];
  snprintf(args, sizeof args, "simulate --model fem --scene %s", p);
  int rc = tb_test_cli_run(args);
  snprintf(want, sizeof want, "%s:%d: ", p, line);
  TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, want) && strstr(tb_test_out, what),
               "%s: exit %d, wanted '%s' and '%s' in: %s", file, rc, want, what, tb_test_out);
}

#define BEAM "[mesh]\ngenerate = beam\nnx = 4\nny = 1\nnz = 1\n"

static void file_errors(void) {
  expect_cli_error("unknown-key.ini", "[scene]\ndt = 0.01\nbogus = 3\n" BEAM, 3,
                   "unknown key 'bogus'");
  expect_cli_error("bad-value.ini", "[scene]\n\ndt = abc\n" BEAM, 3, "dt: 'abc'");
  expect_cli_error("missing-mesh.ini", "# a scene\n[mesh]\nfile = no-such-mesh.obj\n", 3,
                   "cannot read");
  expect_cli_error("out-of-range.ini", BEAM "[fix]\nids = 0, 1, 5000\n", 7,
                   "node id 5000 is out of range");
  expect_cli_error("empty-fix.ini", BEAM "[fix]\nbox = 100,100,100, 101,101,101\n", 7,
                   "selects no node");
  expect_cli_error("section.ini", BEAM "[fixed]\nids = 1\n", 7, "unknown section [fixed]");
  expect_cli_error("twice.ini", "[scene]\ndt = 0.01\ndt = 0.02\n" BEAM, 3, "'dt' given twice");
  expect_cli_error("keyframes.ini",
                   BEAM "[move]\nids = 1\nkeyframe = 1, 0,0,0\nkeyframe = 0.5, 1,0,0\n", 9,
                   "times must increase");
  expect_cli_error("syntax.ini", BEAM "[fix\nids = 1\n", 6, "not INI syntax");
  expect_cli_error("force.ini", BEAM "[force tip]\nids = 3\n", 7, "needs total = or each =");
  expect_cli_error("model-key.ini", BEAM "[model]\nE = 3000\nwobble = 2\n", 8, "wobble");
  expect_cli_error("range.ini", BEAM "[model]\nnu = 0.7\n", 7, "nu");
  expect_cli_error("settle.ini", BEAM "[ground]\nnormal = 0,0,1\nsettle = -1\n", 7,
                   "settle must be in [0, 1000] s");
  /* the scalpel: a path of one point, no stop, a model that cannot be cut */
  expect_cli_error("cut-one.ini", BEAM "[cut]\npoint = 0,0,0\nstop = 1\n", 7, "two or more 'point");
  expect_cli_error("cut-stop.ini", BEAM "[cut]\npoint = 0,0,0\npoint = 1,0,0\n", 7, "needs stop");
  expect_cli_error("cut-bad.ini", BEAM "[cut]\npoint = 0,0\n", 7, "point: '0,0'");
  expect_cli_error("cut-fem.ini",
                   BEAM "[cut]\npoint = 0,-1,-1\npoint = 0,2,-1\ndepth = 0,0,3\nstop = 0.1\n", 7,
                   "fem model cannot be cut");
  /* a model's file setting: relative to the scene, and read */
  expect_cli_error("sph-missing.ini", BEAM "[model]\nspheres_file = no-such.sph\n", 7,
                   "spheres_file: cannot read the file");
  {
    const char *sph = tb_test_file("beam-spheres.sph",
                                   "sph 1.0\n#nums 5\nsphe 0 1 0.5 0.5 0.8\nsphe 1 3 0.5 0.5 "
                                   "0.8\nsphe 2 5 0.5 0.5 0.8\nsphe 3 7 0.5 0.5 0.8\nsphe 4 9 "
                                   "0.5 0.5 0.8\n",
                                   -1);
    (void)sph; /* beside the scene: named relative to it */
    const char *sc = scene_file("sph-beam.ini", "[scene]\nduration = 0.05\n" BEAM
                                                "[model]\nspheres_file = beam-spheres.sph\n");
    char args[1400];
    snprintf(args, sizeof args, "simulate --model metaball --scene %s", sc);
    int rc = tb_test_cli_run(args);
    TB_CHECK_MSG(rc == 0 && strstr(tb_test_out, "stable"), "exit %d: %s", rc, tb_test_out);
  }
  /* the id file's own line */
  const char *ids = tb_test_file("ids.txt", "# fixed nodes\n0 1\n2 x3\n", -1);
  char text[1200];
  snprintf(text, sizeof text, BEAM "[fix]\nid_file = %s\n", ids);
  const char *p = scene_file("idfile.ini", text);
  char args[1400], want[1200];
  snprintf(args, sizeof args, "simulate --model fem --scene %s", p);
  snprintf(want, sizeof want, "%s:3: ", ids);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, want), "%s", tb_test_out);
}

/* `prefer_rotate` turns the preferred file alone (a beam 10 x 1 x 1 along
 * x ends along y after 90 degrees about z); the generator, used when the
 * file cannot be read, is not turned; a zero axis is an error. */
static void prefer_rotate(void) {
  char args[600], text[1600];
  snprintf(args, sizeof args, "mesh beam --set nx=4 --set ny=1 --set nz=1 --out %s/pr.node",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  const char *files[] = {"pr.node", "no-such.node"};
  for (int k = 0; k < 2; k++) {
    snprintf(text, sizeof text,
             "[mesh]\ngenerate = beam\nnx = 4\nny = 1\nnz = 1\nprefer = %s/%s\n"
             "prefer_rotate = 0,0,1, 90\n",
             tb_test_tmpdir(), files[k]);
    tb_mesh m;
    tb_error err;
    if (tb_sim_mesh(scene_file("prefer.ini", text), NULL, &m, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      continue;
    }
    tb_vec3 lo = m.x[0], hi = m.x[0];
    for (int i = 1; i < m.nv; i++) lo = tb_vmin(lo, m.x[i]), hi = tb_vmax(hi, m.x[i]);
    double along_x = hi.x - lo.x, along_y = hi.y - lo.y;
    TB_CHECK_MSG(k == 0 ? fabs(along_y - 10) < 1e-9 && fabs(along_x - 1) < 1e-9
                        : fabs(along_x - 10) < 1e-9 && fabs(along_y - 1) < 1e-9,
                 "%s: extent %g along x, %g along y", files[k], along_x, along_y);
    tb_mesh_free(&m);
  }
  snprintf(text, sizeof text,
           "[mesh]\ngenerate = beam\nprefer = %s/pr.node\nprefer_rotate = 0,0,0, 90\n",
           tb_test_tmpdir());
  expect_cli_error("prefer-axis.ini", text, 2, "prefer_rotate: the axis must not be zero");
  expect_cli_error("prefer-syntax.ini", BEAM "prefer_rotate = 0,0,1\n", 6,
                   "prefer_rotate: '0,0,1' is not ax,ay,az, degrees");
}

/* ---- the quick form and the CLI's bounds ---- */

static void quick_form(void) {
  char args[1400];
  const char *beam = tb_test_file("qbeam.node", "", -1);
  (void)beam;
  snprintf(args, sizeof args, "mesh beam --set nx=8 --set ny=2 --set nz=2 --out %s/qbeam.node",
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0);
  /* a small load: linear fem's large deflection (gravity 9.81: 14 units on
   * this beam of 4) ends degraded, its volume grown by 228% */
  snprintf(args, sizeof args,
           "simulate --model fem --mesh %s/qbeam.node --fix-box -1,-1,-1,0.001,2,2 --gravity "
           "0,0,-0.1 --static",
           tb_test_tmpdir());
  int rc = tb_test_cli_run(args);
  TB_CHECK_MSG(rc == 0 && strstr(tb_test_out, "max displacement ") &&
                   strstr(tb_test_out, " at node ") &&
                   strstr(tb_test_out, "static equilibrium after "),
               "%s", tb_test_out);
  /* gravity 0 means 0 */
  snprintf(args, sizeof args,
           "simulate --model fem --mesh %s/qbeam.node --fix 0,1,2 --gravity 0,0,-9.81 --set "
           "gravity=0 --steps 5",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "max displacement 0 at node 0"),
               "%s", tb_test_out);
  /* bounds: a step count too large, a folder that cannot be made */
  snprintf(args, sizeof args, "simulate --model fem --scene beam --dt 1e-300");
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "steps"), "%s", tb_test_out);
  snprintf(args, sizeof args, "simulate --model fem --scene beam --set duration=1e9");
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "steps"), "%s", tb_test_out);
  snprintf(args, sizeof args, "simulate --model fem --scene beam --vtk /proc/no/such/dir");
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "cannot create"), "%s",
               tb_test_out);
  snprintf(args, sizeof args, "simulate --model fem --mesh %s/qbeam.node --fix 0,1,99999",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "out of range"), "%s",
               tb_test_out);
  /* a setting the user gave is the one an error names */
  TB_CHECK_MSG(tb_test_cli_run("simulate --model sm --scene liver-stretch --set nodes=100") == 2 &&
                   strstr(tb_test_out, "nodes = 100") && !strstr(tb_test_out, "surface_verts"),
               "%s", tb_test_out);
  /* the beam's 2 s are not its rest */
  TB_CHECK_MSG(tb_test_cli_run("simulate --model fem --scene beam") == 0 &&
                   strstr(tb_test_out, "NOT at rest"),
               "%s", tb_test_out);
}

/* ---- an independent static check: K u = f assembled here ---- */

/* Linear-elastic tet stiffness (constant strain): K_e = V B^T D B. */
static void assemble(const tb_mesh *m, double E, double nu, double *K, int n3) {
  double lam = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  for (int t = 0; t < m->ntet; t++) {
    const int *e = m->tet + 4 * t;
    tb_vec3 x[4];
    for (int a = 0; a < 4; a++) x[a] = m->x[e[a]];
    double V = tb_tet_volume(x[0], x[1], x[2], x[3]);
    /* gradients of the barycentric coordinates: area vectors of the opposite faces / (3V) */
    tb_vec3 g[4];
    for (int a = 0; a < 4; a++) {
      tb_vec3 p = x[(a + 1) % 4], q = x[(a + 2) % 4], r = x[(a + 3) % 4];
      tb_vec3 nrm = tb_scale(tb_cross(tb_sub(q, p), tb_sub(r, p)), 0.5);
      if (tb_dot(nrm, tb_sub(x[a], p)) < 0) nrm = tb_scale(nrm, -1);
      g[a] = tb_scale(nrm, 1.0 / (3 * V));
    }
    for (int a = 0; a < 4; a++)
      for (int b = 0; b < 4; b++)
        for (int i = 0; i < 3; i++)
          for (int j = 0; j < 3; j++) {
            double ga = tb_comp(g[a], i), gb = tb_comp(g[b], j);
            double kij = lam * tb_comp(g[a], i) * tb_comp(g[b], j) +
                         mu * tb_comp(g[a], j) * tb_comp(g[b], i) +
                         (i == j ? mu * tb_dot(g[a], g[b]) : 0);
            (void)ga, (void)gb;
            K[(size_t)(3 * e[a] + i) * n3 + 3 * e[b] + j] += V * kij;
          }
  }
}

/* Runs a static solve (fem, quasistatic) of a scene file and checks it
 * against K and f assembled here. */
static void check_static(const char *path, double E, double nu, double rho, tb_vec3 g) {
  tb_sim s;
  tb_error err;
  tb_settings set;
  tb_settings_init(&set);
  TB_CHECK(tb_settings_set(&set, "quasistatic=1", &err) == 0);
  if (tb_sim_create(&s, path, NULL, "fem", &set, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  TB_CHECK_MSG(tb_sim_step(&s, &err) == 0, "%s", err.msg);
  const tb_mesh *m = &s.mesh;
  int n3 = 3 * m->nv;
  double *K = calloc((size_t)n3 * n3, sizeof(double)), *f = calloc((size_t)n3, sizeof(double));
  assemble(m, E, nu, K, n3);
  for (int t = 0; t < m->ntet; t++) {
    const int *e = m->tet + 4 * t;
    double V = tb_tet_volume(m->x[e[0]], m->x[e[1]], m->x[e[2]], m->x[e[3]]);
    for (int a = 0; a < 4; a++) {
      f[3 * e[a]] += rho * V / 4 * g.x, f[3 * e[a] + 1] += rho * V / 4 * g.y;
      f[3 * e[a] + 2] += rho * V / 4 * g.z;
    }
  }
  char *fixed = calloc((size_t)m->nv, 1);
  for (int k = 0; k < s.nanchor; k++) fixed[s.anchor[k]] = 1;
  const tb_vec3 *x = tb_model_positions(&s.model);
  double res2 = 0, f2 = 0, react[3] = {0, 0, 0}, load[3] = {0, 0, 0};
  for (int r = 0; r < n3; r++) {
    double ku = 0;
    for (int c = 0; c < n3; c++)
      ku += K[(size_t)r * n3 + c] * (tb_comp(x[c / 3], c % 3) - tb_comp(m->x[c / 3], c % 3));
    load[r % 3] += f[r];
    if (fixed[r / 3])
      react[r % 3] += ku - f[r];
    else
      res2 += (ku - f[r]) * (ku - f[r]), f2 += f[r] * f[r];
  }
  TB_CHECK_MSG(sqrt(res2 / f2) <= 1e-10, "%s: relative residual %g", path, sqrt(res2 / f2));
  double lsz = sqrt(load[0] * load[0] + load[1] * load[1] + load[2] * load[2]);
  for (int c = 0; c < 3; c++)
    TB_CHECK_MSG(fabs(react[c] + load[c]) <= 1e-10 * lsz, "%s: reaction %g against load %g", path,
                 react[c], load[c]);
  TB_CHECK(s.nanchor >= 3 && lsz > 0);
  free(K), free(f), free(fixed);
  tb_sim_destroy(&s);
}

static void static_solution(void) {
  /* a generated beam (runs everywhere) */
  const char *p = scene_file("static-beam.ini", "[scene]\ngravity = 9.81\n" BEAM
                                                "[model]\nE = 3000\nnu = 0.3\ndensity = 1\n"
                                                "[fix]\nbox_fraction = 0,0,0, 0,1,1\n");
  check_static(p, 3000, 0.3, 1, tb_v3(0, 0, -9.81));
  /* SOFA's liver demo */
  char liver[1024];
  snprintf(liver, sizeof liver, "%s/../shared/data/sofa/liver.msh", tb_test_source_root());
  if (access(liver, R_OK)) {
    tb_test_skip("%s absent (../shared/data not present): the SOFA liver demo not checked", liver);
    return;
  }
  char sc[1024];
  snprintf(sc, sizeof sc, "%s/scenes/examples/sofa-liver.ini", tb_test_source_root());
  check_static(sc, 3000, 0.3, 1, tb_v3(0, -9.81, 0));
  int rc = tb_test_cli_run(
      "simulate --model fem --mesh data:sofa/liver.msh --fix 3,39,64 "
      "--gravity 0,-9.81,0 --static");
  TB_CHECK_MSG(rc == 0 && strstr(tb_test_out, "static equilibrium after 2 solve(s)") &&
                   strstr(tb_test_out, " at node "),
               "%s", tb_test_out);
}

/* ---- ground ---- */

/* A block (1 x 1 x 0.5) dropped onto the ground comes to rest on it, for
 * every model; no node is ever below the plane after a step. */
static void ground_rest(void) {
  for (int i = 0; i < tb_model_count; i++) {
    const char *name = tb_model_classes[i]->name;
    char text[1024];
    snprintf(text, sizeof text,
             "[scene]\ndt = 0.002\nduration = 4\ngravity = 9.81\ndrag = 4\n"
             "[mesh]\ngenerate = beam\nlx = 1\nly = 1\nlz = 0.5\nnx = 2\nny = 2\nnz = 1\n"
             "translate = 0,0,0.3\n[ground]\npoint = 0,0,0\nnormal = 0,0,1\nmu_s = 0.5\n"
             "mu_k = 0.4\n%s",
             !strcmp(name, "msm") ? "[model]\nks = 2000\nkd = 5\n"
             : !strcmp(name, "msm-vvs")
                 ? "[model]\nintegrator = euler\n" /* quasi-static: no fall */
                 : "");
    const char *p = scene_file("drop-block.ini", text);
    tb_sim s;
    tb_error err;
    if (tb_sim_create(&s, p, NULL, name, NULL, NULL, &err)) {
      TB_CHECK_MSG(0, "%s: %s", name, err.msg);
      continue;
    }
    double worst = 0;
    int failed = 0;
    for (long k = 0; k < 2000 && !failed; k++) {
      failed = tb_sim_step(&s, &err) != 0;
      worst = fmax(worst, s.pen_ground);
    }
    TB_CHECK_MSG(!failed, "%s: %s", name, err.msg);
    double speed, tol, zmin = INFINITY;
    const tb_vec3 *x = tb_model_positions(&s.model);
    for (int k = 0; k < s.mesh.nv; k++) zmin = fmin(zmin, x[k].z);
    TB_CHECK_MSG(worst <= 1e-9 * s.size, "%s: a node %g below the ground after a step", name,
                 worst);
    TB_CHECK_MSG(tb_sim_at_rest(&s, &speed, &tol), "%s: not at rest (speed %g)", name, speed);
    TB_CHECK_MSG(zmin > -1e-9 && zmin < 0.02, "%s: lowest node at z = %g", name, zmin);
    tb_sim_destroy(&s);
  }
}

/* A block on a slope of angle a (mu_s 0.5: atan = 26.57 deg, mu_k 0.4): it
 * stays below, slides above with acceleration g (sin a - mu_k cos a). */
static double slide(const char *model, double deg, double T) {
  double a = deg * M_PI / 180;
  char text[1200];
  snprintf(text, sizeof text,
           "[scene]\ndt = 0.001\nduration = %g\ngravity = 9.81\n"
           "[mesh]\ngenerate = beam\nlx = 1\nly = 1\nlz = 0.5\nnx = 2\nny = 2\nnz = 1\n"
           "rotate = 0,1,0, %.17g\n[model]\nE = 1e5\n"
           "[ground]\npoint = 0,0,0\nnormal = %.17g,0,%.17g\nmu_s = 0.5\nmu_k = 0.4\n",
           T, deg, sin(a), cos(a));
  const char *p = scene_file("slope.ini", text);
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, p, NULL, model, NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return NAN;
  }
  long n = lround(T / 0.001);
  for (long k = 0; k < n; k++)
    if (tb_sim_step(&s, &err)) {
      TB_CHECK_MSG(0, "%s at %g deg: %s", model, deg, err.msg);
      break;
    }
  /* mean displacement down the slope: along (cos a, 0, -sin a) */
  const tb_vec3 *x = tb_model_positions(&s.model);
  tb_vec3 down = tb_v3(cos(a), 0, -sin(a));
  double d = 0;
  for (int k = 0; k < s.mesh.nv; k++) d += tb_dot(tb_sub(x[k], s.mesh.x[k]), down);
  d /= s.mesh.nv;
  TB_CHECK_MSG(s.pen_ground_max <= 1e-9 * s.size, "%s: penetration %g", model, s.pen_ground_max);
  tb_sim_destroy(&s);
  return d;
}

static void ground_slope(void) {
  const char *models[] = {"fem-corot", "fem"};
  for (int m = 0; m < 2; m++) {
    double T = 0.5;
    double stick = slide(models[m], 20, T), slow = slide(models[m], 25, T);
    double fast = slide(models[m], 35, T);
    double a = 35 * M_PI / 180, want = 0.5 * 9.81 * (sin(a) - 0.4 * cos(a)) * T * T;
    TB_CHECK_MSG(fabs(stick) < 2e-3 && fabs(slow) < 2e-3, "%s: moved %g at 20 deg, %g at 25 deg",
                 models[m], stick, slow);
    TB_CHECK_MSG(fabs(fast - want) < 0.1 * want, "%s: slid %g at 35 deg, Coulomb %g", models[m],
                 fast, want);
  }
}

/* The built-in slope (mu_s 0.5: atan = 26.57 deg, mu_k 0.4), the block
 * settled onto it before t = 0, for every model at its defaults: over 1 s
 * it stays put at 22, 24 and 26 degrees and slides at 28 and 30 as a rigid
 * block would, s = g (sin a - mu_k cos a) t^2 / 2 within 5% (mean
 * displacement down the slope from t = 0). The two mass-spring models at
 * their papers' settings (node mass 1, ks 180; Bao's ks, kd) sag by more than
 * 20% of the block's volume on it and are reported degraded: checked as
 * such, so that one made meaningful here joins the others. msm with springs
 * stiff enough for the block (ks 5000) is checked as the others; msm-vvs's
 * quasi-static step has no inertia, hence no acceleration to compare. */
static void slope_every_model(void) {
  static const double angle[5] = {22, 24, 26, 28, 30};
  for (int m = 0; m <= tb_model_count; m++) { /* the last: msm with stiffer springs */
    const char *name = m < tb_model_count ? tb_model_classes[m]->name : "msm";
    int sags = m < tb_model_count && (!strcmp(name, "msm") || !strcmp(name, "msm-vvs"));
    tb_settings set;
    tb_settings_init(&set);
    tb_error e0;
    if (m == tb_model_count) TB_CHECK(tb_settings_set(&set, "ks=5000", &e0) == 0);
    for (int k = 0; k < 5; k++) {
      tb_sim_def def;
      tb_sim_def_init(&def);
      def.amplitude = angle[k];
      tb_sim s;
      tb_error err;
      if (tb_sim_create(&s, "slope", &def, name, &set, NULL, &err)) {
        TB_CHECK_MSG(0, "%s at %g deg: %s", name, angle[k], err.msg);
        continue;
      }
      TB_CHECK_MSG(s.settle_steps > 0 && (sags || s.settle_motion <= 1e-9 * s.size),
                   "%s at %g deg: %ld settling steps, last motion %g", name, angle[k],
                   s.settle_steps, s.settle_motion);
      tb_vec3 *x0 = malloc(sizeof(tb_vec3) * (size_t)s.mesh.nv);
      memcpy(x0, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)s.mesh.nv);
      long n = lround(s.def.duration / s.def.dt);
      int failed = 0;
      for (long q = 0; q < n && !failed; q++)
        if ((failed = tb_sim_step(&s, &err)))
          TB_CHECK_MSG(0, "%s at %g deg: %s", name, angle[k], err.msg);
      char why[200];
      int degraded = tb_sim_degraded(&s, why, sizeof why);
      if (sags) {
        TB_CHECK_MSG(degraded, "%s at %g deg is no longer degraded: test it with the others", name,
                     angle[k]);
      } else if (!failed) {
        double a = angle[k] * M_PI / 180, d = 0;
        tb_vec3 down = tb_v3(cos(a), 0, -sin(a));
        const tb_vec3 *x = tb_model_positions(&s.model);
        for (int i = 0; i < s.mesh.nv; i++) d += tb_dot(tb_sub(x[i], x0[i]), down) / s.mesh.nv;
        double want = angle[k] < 26.57 ? 0 : 0.5 * 9.81 * (sin(a) - 0.4 * cos(a)) * s.t * s.t;
        TB_CHECK_MSG(!degraded, "%s at %g deg: %s", name, angle[k], why);
        if (want == 0)
          TB_CHECK_MSG(fabs(d) < 0.005, "%s at %g deg moved %g down the slope", name, angle[k], d);
        else
          TB_CHECK_MSG(fabs(d - want) < 0.05 * want, "%s at %g deg slid %g, Coulomb %g", name,
                       angle[k], d, want);
      }
      free(x0);
      tb_sim_destroy(&s);
    }
  }
}

/* ---- the instrument ---- */

static void press_real_mesh(void) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.nodes = 300, sd.amplitude = 0.8, sd.duration = 0.8;
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, "liver-press", &sd, "fem", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  int most = 0;
  for (int k = 0; k < 80; k++) {
    if (tb_sim_step(&s, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      break;
    }
    most = s.ncontact > most ? s.ncontact : most;
  }
  TB_CHECK_MSG(most >= 3, "at most %d nodes held on the instrument", most);
  TB_CHECK_MSG(s.pen_tool_before_max > 0, "no node ever went inside the instrument");
  TB_CHECK_MSG(s.pen_tool_max <= 1e-9 * s.size,
               "a node %g inside the instrument after the response", s.pen_tool_max);
  tb_sim_metrics m = tb_sim_measure(&s);
  TB_CHECK_MSG(m.max_disp > 0.5, "max displacement %g", m.max_disp);
  tb_sim_destroy(&s);
}

/* ---- ParaView output ---- */

static void frames_parse_back(void) {
  const char *p = scene_file("frames.ini",
                             "[scene]\ndt = 0.002\ngravity = 9.81\n"
                             "[mesh]\ngenerate = beam\nlx = 1\nly = 1\nlz = 0.5\n"
                             "nx = 2\nny = 2\nnz = 1\ntranslate = 0,0,0.01\n"
                             "[ground]\nnormal = 0,0,1\nmu_s = 0.3\nmu_k = 0.2\n");
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, p, NULL, "fem", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  for (int k = 0; k < 40; k++) TB_CHECK(tb_sim_step(&s, &err) == 0);
  char dir[600], f[700];
  snprintf(dir, sizeof dir, "%s/frames", tb_test_tmpdir());
  TB_CHECK_MSG(tb_sim_write_frame(&s, dir, 3, &err) == 0, "%s", err.msg);
  snprintf(f, sizeof f, "%s/body_00003.vtu", dir);
  tb_mesh m;
  tb_vtu_field disp = {"displacement", 0, 0, 0, NULL}, vm = {"von_mises_stress", 1, 0, 0, NULL};
  TB_CHECK_MSG(tb_vtu_read(f, &m, &disp, &err) == 0, "%s", err.msg);
  const tb_vec3 *x = tb_model_positions(&s.model);
  TB_CHECK(m.nv == s.mesh.nv && m.ntet == s.mesh.ntet && m.ntri == 0); /* the body alone */
  TB_CHECK(disp.ncomp == 3 && disp.ntuples == s.mesh.nv);
  int same = 1;
  for (int i = 0; disp.data && i < s.mesh.nv; i++) {
    tb_vec3 d = tb_sub(x[i], s.mesh.x[i]);
    same &= disp.data[3 * i] == d.x && disp.data[3 * i + 1] == d.y && disp.data[3 * i + 2] == d.z;
    same &= m.x[i].x == x[i].x && m.x[i].y == x[i].y && m.x[i].z == x[i].z;
  }
  TB_CHECK_MSG(same, "the displacement read back differs");
  free(disp.data);
  tb_mesh_free(&m);
  TB_CHECK_MSG(tb_vtu_read(f, &m, &vm, &err) == 0 && vm.ntuples == s.mesh.ntet, "%s", err.msg);
  double most = 0;
  for (int t = 0; vm.data && t < s.mesh.ntet; t++) most = fmax(most, vm.data[t]);
  TB_CHECK_MSG(most > 0, "no stress in a block resting under gravity");
  free(vm.data);
  tb_mesh_free(&m);
  tb_sim_destroy(&s);
  /* the CLI: frames and their collection */
  char args[800];
  snprintf(args, sizeof args, "simulate --model msm --scene beam --set duration=0.2 --vtk %s/cli",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "frames.pvd"), "%s", tb_test_out);
  snprintf(f, sizeof f, "%s/cli/frames.pvd", tb_test_tmpdir());
  FILE *pf = fopen(f, "r");
  char buf[4096] = "";
  if (pf) buf[fread(buf, 1, sizeof buf - 1, pf)] = 0, fclose(pf);
  TB_CHECK_MSG(strstr(buf, "file=\"frame_00000.vtm\"") && strstr(buf, "file=\"frame_00006.vtm\""),
               "%s", buf);
  snprintf(args, sizeof args, "mesh info %s/cli/body_00006.vtu", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
}

/* The frames read back by VTK's own readers (Debian's python3-vtk9, tests/vtk_check.py): one
 * named block per object, the instrument placed at frame 0, the fixed mask, the arrays. */
static void frames_read_by_vtk(void) {
  if (tb_test_run("/usr/bin/python3 -c 'import vtk' 2>/dev/null", NULL, 0) != 0) {
    tb_test_skip("Debian's python3-vtk9 is missing (./tissuebench test installs it)");
    return;
  }
  tb_sim s;
  tb_error err;
  if (tb_sim_create(&s, "liver-press", NULL, "fem-corot", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  int nfixed = s.nanchor;
  tb_sim_destroy(&s);
  char args[1200], out[4096];
  snprintf(args, sizeof args,
           "simulate --scene liver-press --model fem-corot --set duration=0.3 --vtk %s/press",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) <= 3, "%s", tb_test_out);
  snprintf(args, sizeof args, "/usr/bin/python3 %s/tests/vtk_check.py %s/press %d 2>&1",
           tb_test_source_root(), tb_test_tmpdir(), nfixed);
  TB_CHECK_MSG(tb_test_run(args, out, sizeof out) == 0, "%s", out);
}

/* ---- the built-in files against the old hand-coded scenes ---- */

static void builtin_match_old(void) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.nodes = 300;
  tb_sim s;
  tb_error err;
  /* liver-stretch: anchors x < lo + 0.15 extent; the patch: surface nodes within 0.1 diagonal of
   * the surface node farthest along x; pulled along (1, 0, 0.3) by t / (release / 2) amplitude */
  if (tb_sim_create(&s, "liver-stretch", &sd, "fem", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  const tb_mesh *m = &s.mesh;
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  int na = 0, nd = 0, best = m->tri[0];
  for (int k = 0; k < 3 * m->ntri; k++)
    if (m->x[m->tri[k]].x > m->x[best].x) best = m->tri[k];
  for (int i = 0; i < m->nv; i++) {
    if (m->x[i].x < lo.x + 0.15 * (hi.x - lo.x)) TB_CHECK(na < s.nanchor && s.anchor[na++] == i);
    if (s.priv->on_surface[i] && tb_dist(m->x[i], m->x[best]) < 0.1 * tb_dist(lo, hi))
      TB_CHECK(nd < s.ndriven && s.driven[nd++] == i);
  }
  TB_CHECK(na == s.nanchor && nd == s.ndriven && nd > 3);
  tb_vec3 dir = tb_normalize(tb_v3(1, 0, 0.3));
  double ts[] = {0.13, 0.5, 0.77, 1.0};
  for (int q = 0; q < 4; q++) {
    tb_sim_loads(&s, ts[q], &err);
    double f = ts[q] < 0.5 ? ts[q] / 0.5 : 1.0;
    for (int k = 0; k < s.ndriven; k++) {
      int i = s.driven[k];
      tb_vec3 want = tb_madd(m->x[i], f * 2.0, dir);
      TB_CHECK(s.mark[i] && s.target[i].x == want.x && s.target[i].y == want.y &&
               s.target[i].z == want.z);
    }
  }
  tb_sim_loads(&s, 1.01, &err);
  TB_CHECK(!s.mark[s.driven[0]]); /* let go */
  tb_sim_destroy(&s);
  /* beam: root face held, tip face loaded by -amplitude / n each */
  tb_sim_def_init(&sd);
  if (tb_sim_create(&s, "beam", &sd, "fem", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  TB_CHECK(s.mesh.nv == 21 * 3 * 3 && s.nanchor == 9 && s.ndriven == 9);
  tb_sim_loads(&s, 0.5, &err);
  for (int k = 0; k < 9; k++) {
    TB_CHECK(s.mesh.x[s.anchor[k]].x == 0 && s.mesh.x[s.driven[k]].x == 10);
    TB_CHECK(s.force[s.driven[k]].z == -(0.075 / 9) && s.force[s.driven[k]].x == 0);
  }
  tb_sim_destroy(&s);
  /* beam-twist: the end face turned by f * 180 degrees about (y, z) = (0.5, 0.5) */
  if (tb_sim_create(&s, "beam-twist", &sd, "fem", NULL, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  TB_CHECK(s.nanchor == 9 && s.ndriven == 9);
  tb_sim_loads(&s, 0.25, &err);
  for (int k = 0; k < s.ndriven; k++) {
    tb_vec3 x = s.mesh.x[s.driven[k]], t = s.target[s.driven[k]];
    double a = 0.5 * M_PI, y = x.y - 0.5, z = x.z - 0.5;
    TB_CHECK(x.x == 4);
    TB_CHECK_NEAR(t.y, 0.5 + cos(a) * y - sin(a) * z, 1e-14);
    TB_CHECK_NEAR(t.z, 0.5 + sin(a) * y + cos(a) * z, 1e-14);
    TB_CHECK(t.x == 4);
  }
  tb_sim_destroy(&s);
}

/* The beam scene's tip (its [output] probe) under a vertical load goes
 * straight down: the symmetric cut leaves no sideways bending. */
static void beam_bends_straight(void) {
  int rc = tb_test_cli_run("simulate --model fem --scene beam --static");
  double ux = 1, uy = 1, uz = 0;
  const char *p = strstr(tb_test_out, "probe (9 nodes): mean displacement (");
  TB_CHECK_MSG(rc == 0 && p && sscanf(p + 36, "%lf, %lf, %lf", &ux, &uy, &uz) == 3, "%s",
               tb_test_out);
  TB_CHECK_MSG(uz < -0.01 && fabs(uy) < 1e-9 * fabs(uz) && fabs(ux) < 1e-3 * fabs(uz),
               "tip moved (%g, %g, %g)", ux, uy, uz);
}

/* ---- defaults run ---- */

static void every_model_every_scene(void) {
  int ns;
  const char *const *names = tb_sim_scene_names(&ns);
  for (int q = 0; q < ns; q++) {
    tb_mesh mesh;
    tb_error err;
    if (tb_sim_mesh(names[q], NULL, &mesh, &err)) {
      TB_CHECK_MSG(0, "%s: %s", names[q], err.msg);
      continue;
    }
    for (int i = 0; i < tb_model_count; i++) {
      tb_sim s;
      const char *model = tb_model_classes[i]->name;
      if (tb_sim_create(&s, names[q], NULL, model, NULL, &mesh, &err)) {
        /* a surface scene (no tets) runs only the models that take one */
        int refused = (mesh.ntet == 0 && !tb_model_classes[i]->surface_mesh &&
                       strstr(err.msg, "needs a tet mesh")) ||
                      (!tb_model_classes[i]->cut && strstr(err.msg, "cannot be cut"));
        TB_CHECK_MSG(refused, "%s on %s: %s", model, names[q], err.msg);
        continue;
      }
      /* Bullet's peers cost 10-100 times our models a step (and far more under the
       * sanitizers): their first 0.6 s of each scene */
      long n = lround(s.def.duration / s.def.dt);
      if (tb_model_classes[i]->peer && n > lround(0.6 / s.def.dt)) n = lround(0.6 / s.def.dt);
      double most = 0;
      for (long k = 0; k < n; k++) {
        if (tb_sim_step(&s, &err)) {
          TB_CHECK_MSG(0, "%s on %s at defaults: %s", model, names[q], err.msg);
          break;
        }
        if (k % 10 == 0) most = fmax(most, tb_sim_measure(&s).max_disp);
      }
      /* msm-vvs's quasi-static steps at its default alpha 1 relax with a
       * time constant of about a minute (models/msm_vvs.c): in the beam's
       * 2 s its tip moves 1.6e-4, 4e-5 of the size */
      double least = strcmp(model, "msm-vvs") ? 1e-4 : 1e-5;
      TB_CHECK_MSG(most > least * s.size, "%s on %s: nothing moved (%g)", model, names[q], most);
      tb_sim_destroy(&s);
    }
    tb_mesh_free(&mesh);
  }
}

const tb_test_case tb_tests_scenes[] = {
    {"prefer_rotate", prefer_rotate},
    {"file_errors", file_errors},
    {"quick_form", quick_form},
    {"static_solution", static_solution},
    {"ground_rest", ground_rest},
    {"ground_slope", ground_slope},
    {"slope_every_model", slope_every_model},
    {"press_real_mesh", press_real_mesh},
    {"frames_parse_back", frames_parse_back},
    {"frames_read_by_vtk", frames_read_by_vtk},
    {"builtin_match_old", builtin_match_old},
    {"beam_bends_straight", beam_bends_straight},
    {"every_model_every_scene", every_model_every_scene},
    {NULL, NULL},
};
