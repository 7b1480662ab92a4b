/* Tests of the fidelity work: the metrics (measure/fidelity.c), the Pareto
 * front, the points file and advise's choice (commands/cmd_advise.c) on
 * synthetic tables, and the pareto, calibration and advise commands on the
 * smoke variants (tiny meshes). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "commands/tb_cli.h"
#include "measure/tb_fidelity.h"
#include "measure/tb_points.h"
#include "meshgen/tb_meshgen.h"

/* ---- metrics on arrays ---- */

static void surface_nodes(void) {
  tb_mesh m;
  tb_error err;
  TB_CHECK(tb_beam(4, 1, 1, 8, 2, 2, &m, &err) == 0);
  int *idx, n = tb_fid_surface_nodes(&m, &idx);
  /* 9 x 3 x 3 grid nodes, 7 x 1 x 1 inside */
  TB_CHECK_MSG(n == 81 - 7, "%d surface nodes", n);
  int ascending = 1, inside = 0;
  for (int k = 0; k < n; k++) {
    if (k && idx[k] <= idx[k - 1]) ascending = 0;
    tb_vec3 x = m.x[idx[k]];
    if (x.x > 1e-9 && x.x < 4 - 1e-9 && x.y > 1e-9 && x.y < 1 - 1e-9 && x.z > 1e-9 &&
        x.z < 1 - 1e-9)
      inside++;
  }
  TB_CHECK(ascending);
  TB_CHECK_MSG(inside == 0, "%d interior nodes listed", inside);
  free(idx);
  m.ntri = 0; /* no boundary triangles: no surface */
  TB_CHECK(tb_fid_surface_nodes(&m, &idx) == 0);
  free(idx);
  tb_mesh_free(&m);
}

static void disp_error(void) {
  tb_vec3 X[4] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tb_vec3 x[4], u[3];
  for (int i = 0; i < 4; i++) x[i] = tb_add(X[i], tb_v3(0.1 * i, 0, 0));
  int idx[3] = {1, 2, 3};
  /* reference displacements off by 0, 0.3 and 0.4 (along y and z) */
  u[0] = tb_v3(0.1, 0, 0), u[1] = tb_v3(0.2, 0.3, 0), u[2] = tb_v3(0.3, 0, -0.4);
  double rms, max;
  tb_fid_disp_error(X, x, idx, 3, u, 2.0, &rms, &max);
  TB_CHECK_NEAR(max, 0.4 / 2.0, 1e-12);
  TB_CHECK_NEAR(rms, sqrt((0.09 + 0.16) / 3) / 2.0, 1e-12);
  /* the exact answer: no error */
  u[1] = tb_v3(0.2, 0, 0), u[2] = tb_v3(0.3, 0, 0);
  tb_fid_disp_error(X, x, idx, 3, u, 1.0, &rms, &max);
  TB_CHECK(rms < 1e-15 && max < 1e-15);
  /* a NaN position is never a small error */
  x[2].y = NAN;
  tb_fid_disp_error(X, x, idx, 3, u, 1.0, &rms, &max);
  TB_CHECK(isnan(rms) && isnan(max));
}

static void pareto_front(void) {
  /* speed, error: 0 fast but bad, 1 slow and good, 2 dominated by 0 and 1's middle 3,
   * 3 in the middle, 4 a copy of 3 (ties: neither dominates), 5 invalid and best at
   * both, 6 NaN error */
  const double sp[] = {1000, 10, 5, 100, 100, 1e6, 1e5};
  const double er[] = {0.5, 0.01, 0.6, 0.1, 0.1, 1e-6, NAN};
  const char valid[] = {1, 1, 1, 1, 1, 0, 1};
  char on[7];
  int n = tb_fid_pareto(sp, er, valid, 7, on);
  TB_CHECK_MSG(n == 4, "%d on the front", n);
  TB_CHECK(on[0] && on[1] && !on[2] && on[3] && on[4] && !on[5] && !on[6]);
  /* equal speed, better error dominates */
  const double sp2[] = {10, 10}, er2[] = {0.2, 0.1};
  const char v2[] = {1, 1};
  TB_CHECK(tb_fid_pareto(sp2, er2, v2, 2, on) == 1 && !on[0] && on[1]);
}

/* ---- points and advise ---- */

static tb_point pt(const char *model, int res, double sps, double rms, const char *state) {
  tb_point p;
  memset(&p, 0, sizeof p);
  snprintf(p.model, sizeof p.model, "%s", model);
  p.resolution = res, p.nodes = 10 * res;
  snprintf(p.params, sizeof p.params, "dt=0.01");
  p.steps_per_s = sps, p.ms_step = 1e3 / sps;
  p.rms_err = rms, p.max_err = 2 * rms;
  p.volume_change = 0, p.reaction_err = NAN, p.settle_time = 1, p.recovery_err = NAN;
  snprintf(p.state, sizeof p.state, "%s", state);
  return p;
}

static void advise_pick(void) {
  tb_point p[9];
  p[0] = pt("fem", 40, 300, 0.01, "settled");
  p[1] = pt("sm", 10, 50000, 0.40, "settled");
  p[2] = pt("msm", 20, 8000, 0.04, "settled");
  p[3] = pt("fem", 10, 9000, 0.05, "settled");
  p[4] = pt("msm", 10, 90000, 0.001, "unstable (velocity beyond bound)"); /* never */
  p[5] = pt("sm", 20, 8000, 0.03, "settled");                             /* ties on speed with 2 */
  p[6] = pt("fem", 20, 2000, 0.02, "settled");
  p[7] = pt("msm", 40, 1e6, NAN, "settled"); /* no error measured: never */
  p[8] = pt("sm", 40, 1e5, 0.0001, "not settled (speed >= 1e-4 after 40 s)"); /* never */
  /* the cheapest within 5%: fem 10 (9000 steps/s) */
  TB_CHECK(tb_advise_pick(p, 9, 0.05, 0) == 3);
  /* within 4%: msm 20 and sm 20 tie at 8000 steps/s; the smaller error wins */
  TB_CHECK(tb_advise_pick(p, 9, 0.04, 0) == 5);
  /* an exact tie: the earlier row */
  p[5].rms_err = 0.04;
  TB_CHECK(tb_advise_pick(p, 9, 0.04, 0) == 2);
  /* within 1.5%: only fem 40 (the unstable and the unsettled rows are ignored) */
  TB_CHECK(tb_advise_pick(p, 9, 0.015, 0) == 0);
  /* none qualifies */
  TB_CHECK(tb_advise_pick(p, 9, 0.005, 0) == -1);
  TB_CHECK(tb_advise_pick(p, 4, 0.001, 0) == -1);
  /* budget: the most accurate at <= 0.2 ms/step (5000 steps/s and up) */
  TB_CHECK(tb_advise_pick(p, 9, 0, 0.2) == 2);
  /* both: the cheapest within 5% and 0.2 ms */
  TB_CHECK(tb_advise_pick(p, 9, 0.05, 0.2) == 3);
  TB_CHECK(tb_advise_pick(p, 9, 0.02, 0.2) == -1);
  TB_CHECK(tb_advise_pick(p, 0, 0.05, 0) == -1);
}

static void points_file(void) {
  tb_point a = pt("fem-corot", 1206, 38.5, 0.0152, "settled");
  snprintf(a.params, sizeof a.params, "quasistatic=1 dt=0.01");
  a.reaction_err = 0.0296;
  tb_point b = pt("msm", 400, 36000, NAN, "unstable (at t = 0.07, velocity 3e3, node 258)");
  char text[4096], line[1024];
  int len = snprintf(text, sizeof text, "%s\n", TB_POINTS_HEADER);
  tb_point_format(&a, line, sizeof line);
  len += snprintf(text + len, sizeof text - (size_t)len, "%s\n", line);
  tb_point_format(&b, line, sizeof line);
  TB_CHECK(!strstr(line, "t = 0.07,")); /* commas in text never split a row */
  snprintf(text + len, sizeof text - (size_t)len, "%s\n", line);
  const char *path = tb_test_file("points.csv", text, -1);
  tb_point *p;
  int n;
  tb_error err;
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == 0, "%s", err.msg);
  TB_CHECK(n == 2);
  if (n == 2) {
    TB_CHECK(!strcmp(p[0].model, "fem-corot") && p[0].resolution == 1206 && p[0].nodes == 12060 &&
             !strcmp(p[0].params, "quasistatic=1 dt=0.01"));
    TB_CHECK_NEAR(p[0].steps_per_s, 38.5, 1e-9);
    TB_CHECK_NEAR(p[0].rms_err, 0.0152, 1e-9);
    TB_CHECK_NEAR(p[0].reaction_err, 0.0296, 1e-9);
    TB_CHECK(isnan(p[0].recovery_err) && p[0].line == 2);
    TB_CHECK(tb_point_usable(&p[0]) && !tb_point_usable(&p[1]));
    TB_CHECK(strstr(p[1].state, "unstable (at t = 0.07; velocity") != NULL);
  }
  free(p);
  /* malformed: a field short on line 3, a bad number, another header, nothing */
  snprintf(text, sizeof text, "%s\n%s\nfem,10,44,lumped,1,2,3\n", TB_POINTS_HEADER, line);
  path = tb_test_file("short.csv", text, -1);
  TB_CHECK(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, "short.csv:3:") &&
           strstr(err.msg, "7 fields"));
  snprintf(text, sizeof text, "%s\nfem,10,44,lumped,fast,2,3,4,5,6,7,8,settled\n",
           TB_POINTS_HEADER);
  path = tb_test_file("word.csv", text, -1);
  TB_CHECK(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, "word.csv:2:") &&
           strstr(err.msg, "steps/s"));
  path = tb_test_file("other.csv", "a,b,c\n1,2,3\n", -1);
  TB_CHECK(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, "other.csv:1:"));
  path = tb_test_file("empty.csv", "", 0);
  TB_CHECK(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, "empty"));
  TB_CHECK(tb_points_read("/nonexistent/points.csv", &p, &n, &err) == -1 &&
           strstr(err.msg, "/nonexistent/points.csv"));
}

/* ---- runs against the reference (tiny beam) ---- */

/* Dynamic fem with drag settles where quasi-static fem lands; both are
 * compared with the reference; the coarse linear tets are stiffer. */
static void run_settles(void) {
  tb_fid_plan plan;
  tb_error err;
  TB_CHECK(tb_fid_plan_for("beam", 0, 1, &plan, &err) == 0);
  TB_CHECK(tb_fid_plan_for("liver-press", 0, 1, &plan, &err) == -1 &&
           strstr(err.msg, "no static problem"));
  TB_CHECK(tb_fid_plan_for("beam", 0, 1, &plan, &err) == 0);
  tb_settings md = tb_test_settings("");
  tb_fid_ref ref;
  tb_sim_def rd = plan.def;
  rd.nodes = plan.ref_res;
  TB_CHECK_MSG(tb_fid_reference("beam", &rd, plan.t_eq, &md, &ref, &err) == 0, "%s", err.msg);
  if (!ref.sol) return;
  /* the load gives about 1% of the length (Euler-Bernoulli 0.1) */
  TB_CHECK_MSG(ref.umax > 0.05 && ref.umax < 0.15, "reference umax %g", ref.umax);
  TB_CHECK(!ref.has_reaction && fabs(ref.volume_change) < 1e-3);
  tb_sim_def sd = plan.def;
  sd.nodes = plan.res[2];
  tb_fid_mesh fm;
  TB_CHECK_MSG(tb_fid_mesh_make(&ref, &sd, &fm, &err) == 0, "%s", err.msg);
  tb_fid_opts o = plan.opts;
  o.settle_speed *= ref.umax;
  o.max_time = 40;
  tb_fid_result dyn, qs;
  double node_mass = 0;
  TB_CHECK(tb_fid_equal_masses(&fm.mesh, "fem", &md, &err) == 0 &&
           tb_model_setting("fem", &md, "node_mass", &node_mass) == 0 && node_mass > 0);
  TB_CHECK(tb_fid_run(&ref, &fm, "fem", &md, &sd, &o, &dyn, &err) == 0);
  tb_settings_set(&md, "quasistatic=1", NULL);
  TB_CHECK(tb_fid_run(&ref, &fm, "fem", &md, &sd, &o, &qs, &err) == 0);
  TB_CHECK_MSG(dyn.stable && dyn.settled && qs.stable && qs.settled, "%s / %s", dyn.state,
               qs.state);
  TB_CHECK_MSG(fabs(dyn.rms_err - qs.rms_err) < 0.01 * qs.rms_err, "dynamic %g, static %g",
               dyn.rms_err, qs.rms_err);
  TB_CHECK_MSG(qs.rms_err > 0.05 && qs.rms_err < 1 && qs.max_err >= qs.rms_err, "%g %g", qs.rms_err,
               qs.max_err);
  TB_CHECK(dyn.settle_time > 0 && isnan(qs.settle_time) && dyn.ms_step > 0);
  TB_CHECK(isnan(dyn.reaction_err) && isnan(dyn.recovery_err));
  /* a model that blows up says so */
  tb_settings hot = tb_test_settings("ks=1e6");
  TB_CHECK(tb_fid_equal_masses(&fm.mesh, "msm", &hot, &err) == 0);
  tb_fid_result bad;
  TB_CHECK(tb_fid_run(&ref, &fm, "msm", &hot, &sd, &o, &bad, &err) == 0);
  TB_CHECK_MSG(!bad.stable && !strncmp(bad.state, "unstable (", 10), "%s", bad.state);
  tb_fid_mesh_free(&fm);
  tb_fid_ref_free(&ref);
}

/* The pulled liver: the reaction on the patch, recovery after release. */
static void run_reaction(void) {
  tb_fid_plan plan;
  tb_error err;
  TB_CHECK(tb_fid_plan_for("liver-stretch", 0, 1, &plan, &err) == 0);
  tb_fid_ref ref;
  tb_sim_def rd = plan.def;
  rd.nodes = plan.ref_res;
  TB_CHECK_MSG(tb_fid_reference("liver-stretch", &rd, plan.t_eq, NULL, &ref, &err) == 0, "%s",
               err.msg);
  if (!ref.sol) return;
  TB_CHECK_NEAR(ref.umax, plan.def.amplitude, 1e-9); /* the patch moved by the pull */
  TB_CHECK(ref.has_reaction && tb_len(ref.reaction) > 0);
  /* the support pulls the patch outward, along the pull */
  tb_vec3 drive = tb_normalize(tb_v3(1, 0, 0.3));
  TB_CHECK_MSG(tb_dot(ref.reaction, drive) > 0.9 * tb_len(ref.reaction), "reaction %g %g %g",
               ref.reaction.x, ref.reaction.y, ref.reaction.z);
  tb_sim_def sd = plan.def;
  sd.nodes = plan.res[0];
  tb_fid_mesh fm;
  TB_CHECK_MSG(tb_fid_mesh_make(&ref, &sd, &fm, &err) == 0, "%s", err.msg);
  tb_fid_opts o = plan.opts;
  o.settle_speed *= ref.umax;
  o.max_time = 4;
  /* fem: reaction from the energy; msm (light damper): from the release step */
  const char *models[2] = {"fem", "msm"};
  for (int k = 0; k < 2; k++) {
    tb_settings d = tb_test_settings(k ? "calibrated=1 kd=0.05" : ""); /* fem: its defaults */
    tb_fid_result r;
    TB_CHECK(tb_fid_equal_masses(&fm.mesh, models[k], &d, &err) == 0);
    o.substeps = k ? 4 : 1;
    TB_CHECK(tb_fid_run(&ref, &fm, models[k], &d, &sd, &o, &r, &err) == 0);
    TB_CHECK_MSG(r.stable, "%s: %s", models[k], r.state);
    /* linear tets on a coarse mesh: within 20% of the reference's force */
    TB_CHECK_MSG(r.reaction_err < 0.2, "%s: reaction error %g", models[k], r.reaction_err);
    TB_CHECK_MSG(r.rms_err < 0.3 && r.max_err < 0.6, "%s: %g %g", models[k], r.rms_err, r.max_err);
    /* elastic: back to rest after release */
    TB_CHECK_MSG(r.recovery_err < 0.05, "%s: left %g", models[k], r.recovery_err);
  }
  tb_fid_mesh_free(&fm);
  tb_fid_ref_free(&ref);
}

/* ---- the commands (smoke variants) ---- */

static void pareto_cli(void) {
  char args[1024], path[1024];
  const char *dir = tb_test_tmpdir();
  snprintf(args, sizeof args, "figure pareto --scale 0.01 --scene beam --results %s/res", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(path, sizeof path, "%s/res/pareto/beam/points.csv", dir);
  tb_point *p;
  int n;
  tb_error err;
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == 0, "%s", err.msg);
  /* every model at 3 resolutions, at least */
  const char *models[6] = {"msm", "fem", "fem-corot", "sm", "pbd-stvk", "xpbd-stvk"};
  for (int m = 0; m < 6; m++) {
    int res[3] = {0, 0, 0}, nr = 0;
    for (int k = 0; k < n; k++) {
      if (strcmp(p[k].model, models[m])) continue;
      int seen = 0;
      for (int j = 0; j < nr; j++) seen |= res[j] == p[k].resolution;
      if (!seen && nr < 3) res[nr++] = p[k].resolution;
    }
    TB_CHECK_MSG(nr == 3, "%s at %d resolutions", models[m], nr);
  }
  free(p);
  snprintf(path, sizeof path, "ls %s/res/pareto/beam/", dir);
  TB_CHECK(tb_test_run(path, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "pareto.png") && strstr(tb_test_out, "table.md"), "%s",
               tb_test_out);
  /* advise on what it wrote */
  snprintf(args, sizeof args, "advise --scene beam --tol 0.9 --results %s/res", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(
      strstr(tb_test_out, "choice") && strstr(tb_test_out, "=>") && strstr(tb_test_out, "evidence"),
      "%s", tb_test_out);
  snprintf(args, sizeof args, "advise --scene beam --tol 1e-9 --results %s/res", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 1 && strstr(tb_test_out, "no settled point"), "%s",
               tb_test_out);
  snprintf(args, sizeof args, "advise --scene beam --budget-ms 1000 --results %s/res", dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "most accurate"), "%s",
               tb_test_out);
  /* a scene with no static problem */
  snprintf(args, sizeof args, "figure pareto --scale 0.01 --scene drop --results %s/res", dir);
  TB_CHECK(tb_test_cli_run(args) == 1 && strstr(tb_test_out, "no static problem"));
}

/* liver-hang: gravity against the reference, every model's masses from the
 * density (each node carries its share of the weight) */
static void pareto_liver_hang(void) {
  char args[1024], path[1024];
  const char *dir = tb_test_tmpdir();
  snprintf(args, sizeof args, "figure pareto --scale 0.01 --scene liver-hang --results %s/res",
           dir);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(path, sizeof path, "%s/res/pareto/liver-hang/points.csv", dir);
  tb_point *p;
  int n, settled = 0, pbd = 0;
  tb_error err;
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == 0, "%s", err.msg);
  for (int k = 0; k < n; k++) {
    settled += !strcmp(p[k].state, "settled");
    pbd += !strncmp(p[k].model, "pbd-stvk", 8) || !strncmp(p[k].model, "xpbd-stvk", 9);
  }
  TB_CHECK_MSG(n >= 18 && settled >= 3 && pbd >= 6, "%d points, %d settled, %d position-based", n,
               settled, pbd);
  free(p);
  snprintf(path, sizeof path, "cat %s/res/pareto/liver-hang/table.md", dir);
  TB_CHECK(tb_test_run(path, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "gravity 9.81") && strstr(tb_test_out, "from the density"), "%s",
               tb_test_out);
}

static void advise_cli(void) {
  char args[1024];
  TB_CHECK(tb_test_cli_run("advise --scene beam --tol 0.1 --points /nonexistent/p.csv") == 2);
  TB_CHECK(strstr(tb_test_out, "/nonexistent/p.csv"));
  char text[1024];
  snprintf(text, sizeof text,
           "%s\nfem,10,44,lumped,1000,1,0.1,0.2,0,nan,1,nan,settled\nfem,20,189,lumped\n",
           TB_POINTS_HEADER);
  const char *path = tb_test_file("bad.csv", text, -1);
  snprintf(args, sizeof args, "advise --tol 0.5 --points %s", path);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "bad.csv:3:"), "%s", tb_test_out);
  snprintf(text, sizeof text,
           "%s\nfem,10,44,lumped,1000,1,0.1,0.2,0,nan,1,nan,settled\n"
           "sm,10,44,linear,9000,0.111,0.3,0.5,0,nan,1,nan,settled\n"
           "msm,10,44,kd=5,90000,0.0111,0.01,0.02,0,nan,nan,nan,unstable (blew up)\n",
           TB_POINTS_HEADER);
  path = tb_test_file("good.csv", text, -1);
  snprintf(args, sizeof args, "advise --tol 0.5 --points %s", path);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "=> sm") && strstr(tb_test_out, "1 unstable or unsettled"), "%s",
               tb_test_out);
  snprintf(args, sizeof args, "advise --tol 0.2 --points %s", path);
  TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "=> fem"), "%s", tb_test_out);
  TB_CHECK(tb_test_cli_run("advise --scene beam") == 2 && strstr(tb_test_out, "--tol"));
  TB_CHECK(tb_test_cli_run("advise --scene beam --tol -1") == 2);
  TB_CHECK(tb_test_cli_run("advise --scene beam --tol 0.1 --bogus 1") == 2);
}

static void calibration_cli(void) {
  char args[1024], path[1024];
  snprintf(args, sizeof args, "table calibration --scale 0.01 --results %s/cal", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(path, sizeof path, "cat %s/cal/calibration/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(path, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(strstr(tb_test_out, "fitted: ks") && strstr(tb_test_out, "fitted: alpha") &&
                   strstr(tb_test_out, "documents: ks 180") && strstr(tb_test_out, "liver"),
               "%s", tb_test_out);
}

const tb_test_case tb_tests_fidelity[] = {
    {"surface_nodes", surface_nodes},
    {"disp_error", disp_error},
    {"pareto_front", pareto_front},
    {"advise_pick", advise_pick},
    {"points_file", points_file},
    {"run_settles", run_settles},
    {"run_reaction", run_reaction},
    {"pareto_cli", pareto_cli},
    {"pareto_liver_hang", pareto_liver_hang},
    {"advise_cli", advise_cli},
    {"calibration_cli", calibration_cli},
    {0, 0},
};
