/* Tests of the stability work: the simulation driver's detector
 * (bench/sim.c tb_sim_step: NaN/inf, velocity, inversion, energy growth)
 * on known-unstable and known-stable runs, the large-deformation scenes
 * (bench/scene_deform.c), points and edges of msm-vvs's map over ks x kd
 * (suites/tb_stab_vvs.h), and the `figure stability` suite's smoke run. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "scenes/tb_sim.h"
#include "suites/tb_stab_vvs.h"

/* A sim of `scene` with unit node masses; model settings from kv pairs. */
static int make(tb_sim *s, const char *scene, const char *model, tb_sim_def *sd,
                const char *const *kv, int nkv) {
  tb_settings md = tb_test_settings("node_mass=1");
  tb_error err;
  for (int i = 0; i < nkv; i++)
    if (tb_settings_set(&md, kv[i], &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      return -1;
    }
  if (tb_sim_create(s, scene, sd, model, &md, NULL, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return -1;
  }
  return 0;
}

/* Steps up to n times; returns the number of steps done before a failure
 * (n when none), the failure in err. */
static long run(tb_sim *s, long n, tb_error *err) {
  for (long k = 0; k < n; k++)
    if (tb_sim_step(s, err)) return k;
  return n;
}

static int finite_state(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  for (int i = 0; i < s->mesh.nv; i++)
    if (!tb_isfinite3(x[i]) || !tb_isfinite3(v[i])) return 0;
  return 1;
}

static tb_sim_def beam_def(double dt, double duration) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = dt, sd.duration = duration, sd.nodes = 10, sd.seed = 1;
  return sd;
}

/* msm at 10x the one-spring bound 2 sqrt(m/k) (ks 180, m 1: 0.149): the
 * detector stops it within a few steps and names a reason. */
static void msm_far_above_bound(void) {
  tb_sim_def sd = beam_def(10 * 2 * sqrt(1.0 / 180), 100.0);
  tb_sim s;
  if (make(&s, "beam", "msm", &sd, NULL, 0)) return;
  tb_error err;
  long n = run(&s, 50, &err);
  TB_CHECK_MSG(n < 50, "ran %ld steps", n);
  TB_CHECK(!s.health.ok);
  TB_CHECK_MSG(strstr(err.msg, "unstable at t = ") &&
                   (strstr(err.msg, "NaN or inf") || strstr(err.msg, "velocity") ||
                    strstr(err.msg, "energy growth") || strstr(err.msg, "inverted")),
               "%s", err.msg);
  tb_sim_destroy(&s);
}

/* msm without damping (kd 0) at dt 0.065: above the stable range of this
 * mesh (10 x 2 x 2 cubes, symmetric split: stable at 0.035, unstable from
 * 0.04 on, measured; the one-spring bound is 0.149), so a mode grows
 * slowly; checked every step, the energy detector names it while the state
 * is still finite. At dt 0.03 the same run is stable: no false alarm. */
static void msm_energy_growth_before_nan(void) {
  static const char *const kv[] = {"kd=0"};
  tb_sim_def sd = beam_def(0.065, 40.0);
  sd.energy_every = 1;
  tb_sim s;
  if (make(&s, "beam", "msm", &sd, kv, 1)) return;
  tb_error err;
  long n = run(&s, 600, &err);
  TB_CHECK_MSG(n < 600 && !s.health.ok, "ran %ld steps", n);
  TB_CHECK_MSG(!strncmp(s.health.reason, "energy growth (E = ", 19), "%s", s.health.reason);
  TB_CHECK(strstr(err.msg, "energy growth") && strstr(err.msg, "bound"));
  TB_CHECK(finite_state(&s));
  TB_CHECK(isfinite(s.energy) && s.energy > s.energy_bound && s.energy_bound > 0);
  tb_sim_destroy(&s);

  sd.dt = 0.03;
  if (make(&s, "beam", "msm", &sd, kv, 1)) return;
  n = run(&s, 600, &err);
  TB_CHECK_MSG(n == 600 && s.health.ok, "%s", err.msg);
  TB_CHECK(s.energy_bound > 0 && s.energy < 0.01 * s.energy_bound);
  tb_sim_destroy(&s);
}

/* The detector's settings parse; the default checks the energy on the
 * first 16 steps and then every 16th. */
static void detector_settings(void) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  tb_error err;
  TB_CHECK(tb_sim_def_set(&sd, "energy_every=1", &err) == 0 && sd.energy_every == 1);
  TB_CHECK(tb_sim_def_set(&sd, "energy_factor=10", &err) == 0 && sd.energy_factor == 10);
  TB_CHECK(tb_sim_def_set(&sd, "energy_every=1.5", &err) == -1);
  sd = beam_def(0.01, 1.0);
  tb_sim s;
  if (make(&s, "beam", "fem", &sd, NULL, 0)) return;
  TB_CHECK(s.def.energy_every == 16 && s.def.energy_factor == 100);
  for (int k = 1; k <= 40; k++) {
    s.energy_bound = -1;
    if (tb_sim_step(&s, &err)) {
      TB_CHECK_MSG(0, "%s", err.msg);
      break;
    }
    int checked = s.energy_bound >= 0;
    TB_CHECK_MSG(checked == (k <= 16 || k % 16 == 0), "step %d checked %d", k, checked);
  }
  tb_sim_destroy(&s);
}

/* Known stable: fem at a moderate dt, inversion checking on, the energy
 * checked every step (and really checked: a bound was set); sm at any dt. */
static void stable_fem_and_sm(void) {
  tb_sim_def sd = beam_def(0.01, 2.0);
  sd.inversion = 1, sd.energy_every = 1;
  tb_sim s;
  tb_error err;
  if (make(&s, "beam", "fem", &sd, NULL, 0)) return;
  long n = run(&s, 200, &err);
  TB_CHECK_MSG(n == 200 && s.health.ok, "fem: %s", err.msg);
  TB_CHECK(s.energy_bound > 0 && isfinite(s.energy) && s.energy < s.energy_bound);
  TB_CHECK(tb_sim_measure(&s).max_disp > 0.003); /* the tip load did bend it (0.0068 at 2 s) */
  tb_sim_destroy(&s);
  /* sm's stiffness against a load is about alpha m / dt^2: from dt 10 on
   * the tip load's impulse inverts tets (though nothing blows up), so
   * inversion is checked up to dt 1 only */
  static const double dts[] = {1e-4, 1e-2, 0.1, 1.0, 10.0};
  for (int i = 0; i < 5; i++) {
    sd = beam_def(dts[i], 100 * dts[i]);
    sd.inversion = dts[i] <= 1, sd.energy_every = 1;
    if (make(&s, "beam", "sm", &sd, NULL, 0)) return;
    n = run(&s, 100, &err);
    TB_CHECK_MSG(n == 100 && s.health.ok, "sm dt %g: %s", dts[i], err.msg);
    TB_CHECK(isnan(s.energy) && finite_state(&s)); /* sm has no energy: no such check */
    tb_sim_destroy(&s);
  }
}

/* The end-face nodes (x = L at rest) of a deform scene. */
static int end_face(const tb_sim *s, int k) { return s->mesh.x[s->driven[k]].x > 4.0 - 1e-9; }

/* The deform scenes with fem: the end face at 2L / turned 180 deg / at L/2
 * at the end of the ramp (halfway there at half the ramp), the held face
 * at rest, and the end face free after release. */
static void deform_scenes(void) {
  static const char *const scenes[] = {"beam-stretch", "beam-twist", "beam-crush"};
  int count;
  const char *const *names = tb_sim_scene_names(&count);
  int found = 0;
  for (int i = 0; i < count; i++)
    for (int j = 0; j < 3; j++) found += !strcmp(names[i], scenes[j]);
  TB_CHECK(found == 3);
  for (int j = 0; j < 3; j++) {
    tb_sim_def sd;
    tb_sim_def_init(&sd);
    sd.nodes = 4, sd.seed = 1; /* dt 0.01, release 1: the ramp ends at 0.5 s */
    tb_sim s;
    if (make(&s, scenes[j], "fem", &sd, NULL, 0)) return;
    TB_CHECK(s.def.release == 1.0 && s.def.dt == 0.01 && s.ndriven == 4 && s.nanchor == 4);
    tb_error err;
    double worst_half = 0, worst_end = 0, worst_root = 0;
    for (int step = 1; step <= 50; step++) {
      if (tb_sim_step(&s, &err)) {
        TB_CHECK_MSG(0, "%s: %s", scenes[j], err.msg);
        break;
      }
      if (step != 25 && step != 50) continue;
      double f = step / 50.0;
      const tb_vec3 *x = tb_model_positions(&s.model);
      for (int k = 0; k < s.ndriven; k++) {
        TB_CHECK(end_face(&s, k));
        tb_vec3 X = s.mesh.x[s.driven[k]], want = X;
        if (j == 0) want.x = 4.0 * (1 + f);
        if (j == 2) want.x = 4.0 * (1 - 0.5 * f);
        if (j == 1) { /* turned f * 180 deg about y = z = 0.5 */
          double a = f * M_PI, y = X.y - 0.5, z = X.z - 0.5;
          want.y = 0.5 + cos(a) * y - sin(a) * z, want.z = 0.5 + sin(a) * y + cos(a) * z;
        }
        double d = tb_dist(x[s.driven[k]], want);
        if (step == 25) worst_half = fmax(worst_half, d);
        if (step == 50) worst_end = fmax(worst_end, d);
      }
      if (step == 50 && j == 1) /* at 180 deg: (y, z) -> (1 - y, 1 - z) */
        for (int k = 0; k < s.ndriven; k++) {
          tb_vec3 X = s.mesh.x[s.driven[k]], p = x[s.driven[k]];
          worst_end = fmax(worst_end, tb_dist(p, tb_v3(X.x, 1 - X.y, 1 - X.z)));
        }
      for (int k = 0; k < s.nanchor; k++)
        worst_root = fmax(worst_root, tb_dist(x[s.anchor[k]], s.mesh.x[s.anchor[k]]));
    }
    TB_CHECK_MSG(worst_half < 1e-9 && worst_end < 1e-9, "%s: %g %g", scenes[j], worst_half,
                 worst_end);
    TB_CHECK(worst_root == 0);
    /* let go at t = 1: the end face springs back */
    tb_vec3 held = tb_model_positions(&s.model)[s.driven[0]];
    long n = run(&s, 70, &err);
    TB_CHECK_MSG(n == 70, "%s: %s", scenes[j], err.msg);
    double moved = tb_dist(tb_model_positions(&s.model)[s.driven[0]], held);
    TB_CHECK_MSG(moved > 0.1, "%s: the end face moved %g after release", scenes[j], moved);
    tb_sim_destroy(&s);
  }
}

/* One msm-vvs run as the quick map's (3 s, let go at 1.5 s); its code. */
static int vvs_code(int integrator, double ks, double kd, tb_vvs_cell *c) {
  tb_vvs_run r;
  tb_vvs_run_init(&r);
  r.integrator = integrator, r.ks = ks, r.kd = kd;
  tb_error err;
  if (tb_vvs_run_cell(&r, NULL, c, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return -1;
  }
  return c->code;
}

/* The map's points: the paper's defaults (ks 3, kd 0.5) stable with both
 * integrators over the whole run; far outside the paper's region the
 * quasi-static update blows up with a reason (ks 1000, kd 50), while
 * symplectic Euler at dt 0.01 holds ks 1000 (its edge is near 6800) and
 * fails only past its own damping limit (kd 500: kd dt / m = 5 > 2). */
static void vvs_map_points(void) {
  tb_vvs_cell c;
  for (int integ = 0; integ < 2; integ++) {
    TB_CHECK_MSG(vvs_code(integ, 3, 0.5, &c) == 0, "integrator %d: %s", integ, c.reason);
    TB_CHECK(fabs(c.t - 3.0) < 1e-9 && !c.reason[0]);
  }
  static const double far[][2] = {{1000, 0.5}, {3, 50}};
  for (int k = 0; k < 2; k++) {
    int code = vvs_code(TB_VVS_QUASISTATIC, far[k][0], far[k][1], &c);
    TB_CHECK_MSG(code > 0 && c.t < 1.0 && c.reason[0], "ks %g kd %g: code %d at %g", far[k][0],
                 far[k][1], code, c.t);
    TB_CHECK_MSG(!strncmp(c.reason, "energy growth", 13) || !strncmp(c.reason, "velocity", 8) ||
                     !strncmp(c.reason, "NaN", 3),
                 "%s", c.reason);
  }
  TB_CHECK_MSG(vvs_code(TB_VVS_EULER, 1000, 0.5, &c) == 0, "%s", c.reason);
  TB_CHECK_MSG(vvs_code(TB_VVS_EULER, 3, 500, &c) > 0 && c.reason[0], "%s", c.reason);
}

/* The measured edge against models/msm_vvs.c's bound (a + 2 b < 2, Euler
 * < 4) with K = lambda ks + k'_s and c from kd + k'_d (low end) to kd
 * (high end): one grid step of the quick map (ks x 1.94, kd 0.5) inside
 * the low end is stable, one past the high end unstable, and the bisected
 * edges from the defaults lie within a grid step of [low, high] (over the
 * scene's 12 s: at 3 s a mode just past Euler's damping limit, kd ~ 200,
 * grows too slowly to be caught before kd 203). */
static void vvs_edge_vs_formula(void) {
  tb_vvs_linear p, p0;
  tb_error err;
  if (tb_vvs_linear_init(&p, NULL, 1, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  /* at most 2 x the valence (6 on the geodesic sphere): the file's bound */
  TB_CHECK_MSG(p.lambda > 3 && p.lambda <= 12, "lambda %g", p.lambda);
  TB_CHECK(p.alpha == 50 && p.mass == 1 && p.ks_v == 1.5 && p.kd_v == 0.5);
  p0 = p, p0.kd_v = 0;
  const double dt = 0.01, rks = pow(200.0, 1.0 / 8), dkd = 0.5; /* the quick grid's steps */
  /* quasi-static at alpha 50: kd < 1 / (alpha dt) - k'_d = 1.5 before any stiffness */
  double ks_lo = tb_vvs_ks_limit(&p, TB_VVS_QUASISTATIC, dt, 0.5),
         ks_hi = tb_vvs_ks_limit(&p0, TB_VVS_QUASISTATIC, dt, 0.5),
         kd_lo = tb_vvs_kd_limit(&p, TB_VVS_QUASISTATIC, dt, 3),
         kd_hi = tb_vvs_kd_limit(&p0, TB_VVS_QUASISTATIC, dt, 3);
  TB_CHECK_MSG(kd_lo < 1.5 && kd_lo > 1.3 && kd_hi < 2 && ks_lo > 20 && ks_hi < 60, "%g..%g %g..%g",
               ks_lo, ks_hi, kd_lo, kd_hi);
  tb_vvs_cell c;
  TB_CHECK_MSG(vvs_code(TB_VVS_QUASISTATIC, ks_lo / rks, 0.5, &c) == 0, "%s", c.reason);
  TB_CHECK(vvs_code(TB_VVS_QUASISTATIC, ks_hi * rks, 0.5, &c) > 0);
  TB_CHECK_MSG(vvs_code(TB_VVS_QUASISTATIC, 3, kd_lo - dkd, &c) == 0, "%s", c.reason);
  TB_CHECK(vvs_code(TB_VVS_QUASISTATIC, 3, kd_hi + dkd, &c) > 0);
  for (int integ = 0; integ < 2; integ++)
    for (int along_kd = 0; along_kd < 2; along_kd++) {
      tb_vvs_run r;
      tb_vvs_run_init(&r);
      r.integrator = integ, r.duration = 12, r.release = 4; /* the scene's run, as --full */
      double lo, hi;
      int runs;
      if (tb_vvs_edge(&r, NULL, along_kd, along_kd ? 1e4 : 1e6, 6, &lo, &hi, &runs, &err)) {
        TB_CHECK_MSG(0, "%s", err.msg);
        return;
      }
      double a = along_kd ? tb_vvs_kd_limit(&p, integ, dt, 3) : tb_vvs_ks_limit(&p, integ, dt, 0.5),
             b = along_kd ? tb_vvs_kd_limit(&p0, integ, dt, 3)
                          : tb_vvs_ks_limit(&p0, integ, dt, 0.5);
      int ok = along_kd ? lo > a - dkd && lo < b + dkd : lo > a / rks && lo < b * rks;
      TB_CHECK_MSG(ok && lo < hi && isfinite(hi) && runs > 6,
                   "integrator %d, %s: measured %g..%g, predicted %g..%g", integ,
                   along_kd ? "kd" : "ks", lo, hi, a, b);
    }
}

static int has_file(const char *dir, const char *name) {
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "test -s %s/%s", dir, name);
  return tb_test_run(cmd, NULL, 0) == 0;
}

/* The smoke run writes the table, a CSV per model and the charts;
 * --model restricts it to one model; an unknown model is an error. */
static void suite_smoke(void) {
  char args[900], dir[900];
  snprintf(args, sizeof args, "figure stability --scale 0.01 --results %s/all", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(dir, sizeof dir, "%s/all/stability", tb_test_tmpdir());
  static const char *const files[] = {"table.md",
                                      "table-deform.csv",
                                      "map_msm.csv",
                                      "map_fem.csv",
                                      "map_fem-corot.csv",
                                      "map_sm.csv",
                                      "map_msm_n10.png",
                                      "map_msm_n10.svg",
                                      "map_sm_n10.svg",
                                      "map_fem-corot_n10.svg",
                                      "msm_bound.csv",
                                      "map_pbd-stvk.csv",
                                      "map_pbd-stvk-iterations.csv",
                                      "map_pbd-stvk-iterations_n10.svg",
                                      "map_xpbd-stvk.csv",
                                      "map_xpbd-stvk_n10.svg",
                                      "map_msm-vvs.csv",
                                      "msm-vvs_edges.csv",
                                      "map_msm-vvs-quasistatic.svg",
                                      "map_msm-vvs-euler.svg"};
  for (size_t i = 0; i < sizeof files / sizeof files[0]; i++)
    TB_CHECK_MSG(has_file(dir, files[i]), "no %s", files[i]);
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "cat %s/table.md", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "| stable |") && strstr(tb_test_out, "unstable (") &&
                   strstr(tb_test_out, "2 sqrt(m/k)") && strstr(tb_test_out, "twist 180 deg") &&
                   strstr(tb_test_out, "Inversion checking is OFF"),
               "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "head -1 %s/map_msm.csv", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0 &&
           !strncmp(tb_test_out, "dt,stiffness,status,cells,t,reason", 34));

  snprintf(args, sizeof args, "figure stability --scale 0.01 --model msm --results %s/one",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(dir, sizeof dir, "%s/one/stability", tb_test_tmpdir());
  TB_CHECK(has_file(dir, "map_msm.csv") && has_file(dir, "map_msm_n10.svg"));
  TB_CHECK(!has_file(dir, "map_fem.csv") && !has_file(dir, "map_sm.csv") &&
           !has_file(dir, "map_msm-vvs.csv"));
  snprintf(cmd, sizeof cmd, "cat %s/table.md", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK(strstr(tb_test_out, "| msm | crush 50% |") && !strstr(tb_test_out, "| fem |") &&
           !strstr(tb_test_out, "| sm |"));

  /* a model with two maps (k, iterations): both, and its deformations once */
  snprintf(args, sizeof args, "figure stability --scale 0.01 --model pbd-stvk --results %s/pbd",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(dir, sizeof dir, "%s/pbd/stability", tb_test_tmpdir());
  TB_CHECK(has_file(dir, "map_pbd-stvk.csv") && has_file(dir, "map_pbd-stvk-iterations.csv"));
  TB_CHECK(!has_file(dir, "map_xpbd-stvk.csv") && !has_file(dir, "map_msm.csv"));
  snprintf(cmd, sizeof cmd, "cat %s/table.md", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  const char *twist = strstr(tb_test_out, "| pbd-stvk | twist 180 deg |");
  TB_CHECK_MSG(twist && !strstr(twist + 1, "| pbd-stvk | twist 180 deg |") &&
                   strstr(tb_test_out, "| iterations |") && strstr(tb_test_out, "| k |"),
               "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "cut -d, -f2 %s/map_pbd-stvk-iterations.csv | sort -un | tr '\\n' ' '",
           dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "1 10 100"), "iterations axis: %s", tb_test_out);

  /* msm-vvs: its map over ks x kd alone (no dt maps, no deformations) */
  snprintf(args, sizeof args, "figure stability --scale 0.01 --model msm-vvs --results %s/vvs",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(dir, sizeof dir, "%s/vvs/stability", tb_test_tmpdir());
  TB_CHECK(has_file(dir, "map_msm-vvs.csv") && has_file(dir, "msm-vvs_edges.csv") &&
           has_file(dir, "map_msm-vvs-euler.svg"));
  TB_CHECK(!has_file(dir, "map_msm.csv") && !has_file(dir, "table-deform.csv"));
  snprintf(cmd, sizeof cmd, "cat %s/table.md", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "| quasi-static | ks | kd 0.5 |") &&
                   strstr(tb_test_out, "| symplectic Euler | kd | ks 3 |") &&
                   strstr(tb_test_out, "Against the paper's region (ks < 20, kd < 2)"),
               "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "head -1 %s/map_msm-vvs.csv", dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0 &&
           !strncmp(tb_test_out, "kd,ks,status,integrator,t,reason", 32));
  snprintf(cmd, sizeof cmd, "tail -n +2 %s/map_msm-vvs.csv | cut -d, -f4 | sort | uniq -c | xargs",
           dir);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "9 euler 9 quasistatic"), "%s", tb_test_out);

  snprintf(args, sizeof args, "figure stability --scale 0.01 --model nope --results %s/bad",
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) != 0);
  TB_CHECK_MSG(strstr(tb_test_out, "unknown model 'nope'"), "%s", tb_test_out);
}

const tb_test_case tb_tests_stability[] = {
    {"msm_far_above_bound", msm_far_above_bound},
    {"msm_energy_growth_before_nan", msm_energy_growth_before_nan},
    {"detector_settings", detector_settings},
    {"stable_fem_and_sm", stable_fem_and_sm},
    {"deform_scenes", deform_scenes},
    {"vvs_map_points", vvs_map_points},
    {"vvs_edge_vs_formula", vvs_edge_vs_formula},
    {"suite_smoke", suite_smoke},
    {0, 0},
};
