/* Thesis §3.5: the three physical models (and corotational FEM) on the
 * liver with the thesis's parameters (MSM ks 180, kd 5; FEM E 3000, nu 0.3;
 * shape matching 50 clusters, radius 1, alpha 0.72, beta 0.63, quadratic),
 * the same scene (liver-stretch), dt and node masses for all. Part 1: steps
 * per second (median over repetitions of the median step), the thesis's FPS
 * beside ours. Part 2: the recovery experiment (thesis figs. 3.14, 3.15):
 * stretch far, let go, the displacement left after a fixed time, as a table
 * and a chart. Part 3 (suite_corot.c): fem-corot's solvers against the
 * exact one and linear fem. A run that blows up is printed as
 * `unstable (reason)`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "suite_table35.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "models/tb_sm.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

/* The thesis's FPS (Intel i3-2100, rendering included) and our targets. */
static const struct {
  const char *label, *model;
  double thesis_fps, target; /* target steps/s (0: none) */
  int members;               /* sm: radius chosen for this mean cluster size (0: radius 1) */
} rows[] = {{"msm", "msm", 335.7, 3357, 0},
            {"fem", "fem", 36.5, 1000, 0},
            {"fem-corot", "fem-corot", 0, 0, 0},
            {"sm (radius 1)", "sm", 787.0, 7870, 0},
            {"sm (96 per cluster)", "sm", 787.0, 7870, 96}};
#define NROWS ((int)(sizeof rows / sizeof rows[0]))

#define DT 0.01       /* one step per frame, as in the thesis's demo */
#define NODE_MASS 1.0 /* unit particle masses, as mass-spring demos use */
#define DRAG 1.5      /* recovery: ambient drag for every model, so the motion dies out */

static double radius96 = 1.0; /* set by speed(): sm regions of 96 particles on average */

static tb_settings thesis_def(int row) {
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_setd(&d, "node_mass", NODE_MASS, NULL);
  if (rows[row].members) tb_settings_setd(&d, "radius", radius96, NULL);
  return d;
}

/* Mean particles per cluster of sm on mesh with region radius r (-1 on error). */
static double members_at(const tb_mesh *mesh, double r) {
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_setd(&d, "node_mass", NODE_MASS, NULL);
  tb_settings_setd(&d, "radius", r, NULL);
  tb_model m;
  tb_error err;
  int nc;
  double mean = -1;
  if (tb_model_create(&m, "sm", mesh, &d, &err)) return -1;
  if (tb_sm_cluster_stats(&m, &nc, &mean)) mean = -1;
  tb_model_destroy(&m);
  return mean;
}

/* The radius whose regions hold `members` particles on average (bisection). */
static double radius_for(const tb_mesh *mesh, int members) {
  double lo = 0.5, hi = 4.0;
  for (int it = 0; it < 16; it++) {
    double mid = 0.5 * (lo + hi);
    if (members_at(mesh, mid) < members)
      lo = mid;
    else
      hi = mid;
  }
  return 0.5 * (lo + hi);
}

/* Runs the stretch scene; per-step wall and CPU ms into wall and cpu (steps
 * entries each, or NULL), the rms displacement every `every` steps into
 * series (may be NULL). Returns 0, or -1 with the reason in err. */
static int run_model(const tb_mesh *liver, const char *label, const char *model,
                     const tb_settings *md, const tb_sim_def *sd, double *wall, double *cpu,
                     long steps, double *series, int every, tb_sim_metrics *end,
                     tb_sim_metrics *peak, tb_sim_metrics *before, tb_error *err) {
  tb_sim s;
  if (tb_sim_create(&s, "liver-stretch", sd, model, md, liver, err)) return -1;
  int rc = 0;
  for (long k = 0; k < steps && !rc; k++) {
    tb_clock c = tb_clock_start();
    rc = tb_sim_step(&s, err);
    tb_clock_ms(&c, wall ? wall + k : NULL, cpu ? cpu + k : NULL);
    tb_progress_tick("%s: step %ld/%ld", label, k + 1, steps);
    if (!rc && peak && fabs(s.t - s.def.release) < 0.5 * s.def.dt) *peak = tb_sim_measure(&s);
    if (!rc && before && k + 1 == steps - lround(1.0 / s.def.dt)) *before = tb_sim_measure(&s);
    if (!rc && series && (k + 1) % every == 0)
      series[(k + 1) / every] = tb_sim_measure(&s).rms_disp;
  }
  if (!rc && end) *end = tb_sim_measure(&s);
  tb_sim_destroy(&s);
  return rc;
}

static int run(const tb_mesh *liver, int row, const tb_sim_def *sd, double *wall, double *cpu,
               long steps, double *series, int every, tb_sim_metrics *end, tb_sim_metrics *peak,
               tb_sim_metrics *before, tb_error *err) {
  tb_settings md = thesis_def(row);
  return run_model(liver, rows[row].label, rows[row].model, &md, sd, wall, cpu, steps, series,
                   every, end, peak, before, err);
}

/* Bullet 3.24's peers on the same scene, dt and unit node masses,
 * E 3000 and nu 0.3 as our fem (bullet-fem's stiffness damping 0.02 as our
 * Rayleigh's), bullet-softbody at its defaults (kLST 1, 5 iterations). */
static const struct {
  const char *label, *model, *kvs;
} peers[] = {{"bullet-fem neohookean", "bullet-fem", "force=neohookean"},
             {"bullet-fem linear", "bullet-fem", "force=linear"},
             {"bullet-fem corotated", "bullet-fem", "force=corotated"},
             {"bullet-softbody", "bullet-softbody", ""}};
#define NPEERS ((int)(sizeof peers / sizeof peers[0]))

/* One model's timed runs: per repetition the median CPU and wall ms per
 * step over all steps, and over the first `first` steps (the peers' share). */
typedef struct timed {
  int bad;
  char why[200];
  tb_sim_metrics end;
  double *cpu, *wall, *cpu_first, *wall_first; /* reps each */
} timed;

/* Repetition k of model (label, model, md) into w: steps (or only `first`
 * for a peer) on the stretch scene. */
static void time_one(const tb_mesh *liver, const char *label, const char *model,
                     const tb_settings *md, const tb_sim_def *sd, long steps, long first, int k,
                     double *wall, double *cpu, timed *w) {
  tb_error err;
  if (w->bad) return;
  if (run_model(liver, label, model, md, sd, wall, cpu, steps, NULL, 1, &w->end, NULL, NULL,
                &err)) {
    w->bad = 1;
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    return;
  }
  w->cpu[k] = tb_stats_of(cpu, (int)steps).median,
  w->wall[k] = tb_stats_of(wall, (int)steps).median;
  w->cpu_first[k] = tb_stats_of(cpu, (int)first).median;
  w->wall_first[k] = tb_stats_of(wall, (int)first).median;
}

/* The peers' table: Bullet's steps/s beside ours, the ratios from
 * repetitions that took turns with ours (w: the rows, then the peers). */
static void peer_table(tb_suite *su, const tb_sim_def *sd, long first, int reps, const timed *w) {
  static const char *cols[] = {"model",
                               "steps/s (CPU)",
                               "ms/step CPU (median)",
                               "ms/step wall (median)",
                               "msm / this (steps/s)",
                               "fem / this (steps/s)",
                               "fem-corot / this (steps/s)",
                               "state"};
  char title[200];
  snprintf(title, sizeof title,
           "Bullet 3.24's deformable peers on the liver (liver-stretch, first %.2g s): steps per "
           "second (CPU time, one thread), ours / Bullet's with its 95%% interval",
           first * sd->dt);
  tb_table *t = tb_table_new("bullet", title, 8, cols);
  for (int p = 0; p < NPEERS; p++) {
    const timed *u = &w[NROWS + p];
    tb_table_row(t);
    tb_table_cell(t, "%s", peers[p].label);
    if (u->bad) {
      for (int c = 0; c < 6; c++) tb_table_cell(t, "-");
      tb_table_cell(t, "unstable (%s)", u->why);
      continue;
    }
    char name[96];
    snprintf(name, sizeof name, "bullet/%s", peers[p].label);
    tb_suite_bench(su, name, u->wall_first, u->cpu_first, reps, "ms");
    double cpu = tb_median_est(u->cpu_first, reps).value;
    tb_table_num(t, 1e3 / cpu, "%.1f");
    tb_table_num(t, cpu, "%.4f");
    tb_table_num(t, tb_median_est(u->wall_first, reps).value, "%.4f");
    for (int r = 0; r < 3; r++) { /* rows 0..2: msm, fem, fem-corot */
      static const char *const key[3] = {"msm_over_this", "fem_over_this", "fem_corot_over_this"};
      if (w[r].bad) {
        tb_table_cell(t, "-");
        continue;
      }
      tb_est e = tb_ratio_est(u->cpu_first, w[r].cpu_first, reps);
      tb_table_est(t, e, "%.3g", "");
      tb_suite_counter(su, name, key[r], e.value);
    }
    tb_table_cell(t, "stable; max displacement %.3g, volume %+.2f%%", u->end.max_disp,
                  100 * u->end.volume_change);
  }
  tb_suite_table(su, t);
  tb_suite_note(
      su,
      "Bullet peers (models/bullet_fem.c, models/bullet_softbody.c): bullet-fem is "
      "Bullet's deformable world (btDeformableBodySolver: backward Euler linearised once, CG "
      "with projections) with E 3000, nu 0.3 as Lame mu, lambda and stiffness damping 0.02; "
      "bullet-softbody the classic btSoftBody, one link per tet edge, kLST 1, 5 position "
      "iterations; same unit node masses and dt %g. `ours / this` is Bullet's CPU time per step "
      "over ours (how many times faster ours is), the median of %d repetitions that took turns "
      "with ours, over the same first %ld steps, with its 95%% interval. Bullet's linear force "
      "is in fact corotated (strain of R^T F). Its corotated force has no force differential: "
      "Bullet's implicit step then solves with the mass matrix alone, i.e. the elasticity is "
      "explicit, and at dt %g the liver's stiff small tets are far beyond the explicit limit, "
      "so it blows up within a few steps; the blow-up detector reports it (not tuned away). "
      "The ground is the scene's (Bullet meets one only as a rigid convex body).",
      sd->dt, reps, first, sd->dt);
}

/* Part 1: every row and peer, the repetitions taking turns (row 0, 1, ...,
 * peer 0, 1, ..., then again), one thread, CPU time. */
static int speed(tb_suite *su, const tb_suite_opts *o, const tb_mesh *liver) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = DT, sd.duration = 2.0, sd.release = 1.0, sd.amplitude = 2.0;
  long steps = lround(sd.duration / sd.dt);
  long first = o->scale < 1 ? 3 : (o->full ? steps : 50); /* the peers' steps */
  int reps = o->scale < 1 ? 1 : (o->full ? 9 : TB_EST_MIN), failed = 0, n = NROWS + NPEERS;
  radius96 = radius_for(liver, 96);
  timed w[NROWS + NPEERS];
  double *wall = malloc(sizeof(double) * (size_t)steps),
         *cpu = malloc(sizeof(double) * (size_t)steps);
  double *store = calloc((size_t)n * 4 * (size_t)reps, sizeof(double));
  if (!wall || !cpu || !store) {
    free(wall), free(cpu), free(store);
    fprintf(stderr, "table 3.5: out of memory\n");
    return 1;
  }
  for (int r = 0; r < n; r++) {
    memset(&w[r], 0, sizeof w[r]);
    double *at = store + (size_t)r * 4 * (size_t)reps;
    w[r].cpu = at, w[r].wall = at + reps, w[r].cpu_first = at + 2 * reps,
    w[r].wall_first = at + 3 * reps;
  }
  for (int k = 0; k < reps; k++)
    for (int r = 0; r < n; r++) {
      tb_progress("table 3.5 speed", k * n + r, reps * n);
      if (r < NROWS) {
        tb_settings md = thesis_def(r);
        time_one(liver, rows[r].label, rows[r].model, &md, &sd, steps, first, k, wall, cpu, &w[r]);
      } else {
        const int p = r - NROWS;
        tb_settings md;
        tb_settings_init(&md);
        tb_settings_setd(&md, "node_mass", NODE_MASS, NULL);
        if (peers[p].kvs[0]) tb_settings_set(&md, peers[p].kvs, NULL);
        time_one(liver, peers[p].label, peers[p].model, &md, &sd, first, first, k, wall, cpu,
                 &w[r]);
      }
    }
  tb_progress("table 3.5 speed", reps * n, reps * n);
  free(wall), free(cpu);
  static const char *cols[] = {
      "model",        "steps/s (CPU)", "ms/step CPU (median)",    "ms/step wall (median)",
      "thesis FPS",   "ours / thesis", "target steps/s",          "target met",
      "state at 2 s", "state",         "max displacement at 2 s", "volume change at 2 s (%)"};
  tb_table *t = tb_table_new(
      "speed", "Steps per second on the liver (liver-stretch; CPU time, one thread)", 12, cols);
  tb_table_csv_name(t, 6, "target steps/s (at least)");
  tb_table_only(t, 8, TB_MD_ONLY); /* "stable; max displacement ..." split for the CSV */
  for (int j = 9; j < 12; j++) tb_table_only(t, j, TB_CSV_ONLY);
  for (int r = 0; r < NROWS; r++) {
    const timed *u = &w[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", rows[r].label);
    if (u->bad) {
      for (int c = 0; c < 7; c++) tb_table_cell(t, "-");
      tb_table_cell(t, "unstable (%s)", u->why);
      tb_table_cell(t, "unstable (%s)", u->why);
      failed |= rows[r].target > 0;
      continue;
    }
    tb_suite_bench(su, rows[r].label, u->wall, u->cpu, reps, "ms");
    double sps_k[16];
    for (int k = 0; k < reps; k++) sps_k[k] = 1e3 / u->cpu[k];
    tb_est sps = tb_median_est(sps_k, reps);
    double cpu_ms = tb_median_est(u->cpu, reps).value;
    tb_table_num(t, sps.value, "%.0f");
    tb_table_num(t, cpu_ms, "%.4f");
    tb_table_num(t, tb_median_est(u->wall, reps).value, "%.4f");
    if (rows[r].thesis_fps > 0) {
      tb_table_cell(t, "%.1f", rows[r].thesis_fps);
      tb_table_num(t, sps.value / rows[r].thesis_fps, "%.1fx");
    } else
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    if (rows[r].target > 0) {
      char v[160];
      tb_table_numf(t, rows[r].target, ">= %.0f", rows[r].target);
      tb_table_cell(t, "%s", tb_verdict_text(sps, rows[r].target, 1, v, sizeof v));
    } else
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    tb_table_cell(t, "stable; max displacement %.3g, volume %+.2f%%", u->end.max_disp,
                  100 * u->end.volume_change);
    tb_table_cell(t, "stable");
    tb_table_num(t, u->end.max_disp, "%.3g");
    tb_table_num(t, 100 * u->end.volume_change, "%+.2f");
  }
  tb_suite_table(su, t);
  tb_suite_note(su,
                "Steps per second from CPU time on one thread: the median over %d repetitions, "
                "which took turns model by model, of each run's median step; a target is met "
                "or not when the 95%% interval of those repetitions is on one side of it, else "
                "inconclusive (noise). Wall time beside it.",
                reps);
  peer_table(su, &sd, first, reps, w);
  free(store);
  tb_suite_note(su,
                "Shape matching with the thesis's region radius 1 has %.1f particles per cluster "
                "on our liver; the thesis had 96 per match, which radius %.3f gives (%.1f). Both "
                "are measured.",
                members_at(liver, 1.0), radius96, members_at(liver, radius96));
  return failed;
}

/* Part 2: stretch by each amplitude, let go at 1 s, measure at the end. */
static int recovery(tb_suite *su, const tb_suite_opts *o, const tb_mesh *liver, double length) {
  const double amps_full[] = {0.25, 0.5, 1.0}, amps_quick[] = {0.5}; /* of the length */
  const double *amps = o->full ? amps_full : amps_quick;
  int namps = o->full ? 3 : 1, failed = 0;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = DT, sd.release = 1.0, sd.duration = o->scale < 1 ? 1.5 : (o->full ? 21.0 : 11.0);
  sd.drag = DRAG;
  long steps = lround(sd.duration / sd.dt);
  int every = 5, npts = (int)(steps / every) + 1;
  static const char *cols[] = {"model",
                               "stretch (of length)",
                               "max displacement at release",
                               "rms left / rms at release",
                               "max left / stretch",
                               "inverted tets left",
                               "rms change in the last second",
                               "state"};
  char title[160];
  snprintf(title, sizeof title,
           "Recovery: stretched, let go at 1 s, displacement left at %.1f s with ambient drag "
           "%g (thesis: MSM distorts and does not recover, SM always recovers)",
           sd.duration, DRAG);
  tb_table *t = tb_table_new("recovery", title, 8, cols);
  tb_table_csv_name(t, 1, "stretch (% of length)");
  tb_table_csv_name(t, 6, "rms change in the last second (%)");
  /* chart: rms displacement against time for the farthest stretch */
  double *series = malloc(sizeof(double) * (size_t)npts * NROWS);
  for (int i = 0; series && i < npts * NROWS; i++) series[i] = NAN;
  for (int a = 0; a < namps; a++)
    for (int r = 0; r < NROWS; r++) {
      tb_progress("table 3.5 recovery", a * NROWS + r, namps * NROWS);
      sd.amplitude = amps[a] * length;
      tb_sim_metrics end, peak, before;
      memset(&peak, 0, sizeof peak);
      memset(&before, 0, sizeof before);
      tb_error err;
      double *ser = a == namps - 1 && series ? series + (size_t)r * npts : NULL;
      if (ser) ser[0] = 0;
      int bad = run(liver, r, &sd, NULL, NULL, steps, ser, every, &end, &peak, &before, &err);
      tb_table_row(t);
      tb_table_cell(t, "%s", rows[r].label);
      tb_table_num(t, 100 * amps[a], "%.0f%%");
      if (bad) {
        for (int c = 0; c < 5; c++) tb_table_cell(t, "-");
        tb_table_cell(t, "unstable (%s)", err.msg);
        continue;
      }
      tb_table_cell(t, "%.3g", peak.max_disp);
      tb_table_cell(t, "%.3g", peak.rms_disp > 0 ? end.rms_disp / peak.rms_disp : NAN);
      tb_table_cell(t, "%.3g", end.max_disp / sd.amplitude);
      tb_table_cell(t, "%d", end.inverted);
      double rate = before.rms_disp > 0 ? end.rms_disp / before.rms_disp - 1 : 0;
      tb_table_num(t, 100 * rate, "%+.1f%%");
      tb_table_cell(t, "%s",
                    end.max_disp < 0.05 * sd.amplitude
                        ? "recovered"
                        : (rate > -0.01 ? "stuck distorted" : "still recovering"));
    }
  tb_progress("table 3.5 recovery", namps * NROWS, namps * NROWS);
  tb_suite_table(su, t);
  tb_suite_note(su,
                "State: `recovered` when the largest displacement left is under 5%% of the "
                "stretch; otherwise `still recovering` when the rms displacement fell by more "
                "than 1%% in the last second, else `stuck distorted`. The drag (a force -%g m v "
                "on every node, the same for every model) makes the motion die out in the time "
                "simulated; without it the undamped shape-matching oscillation never settles "
                "(eq. 3-42 has no damping). Inverted tets are counted, not treated as a failure, "
                "in this table (shape matching does not know the tets).",
                DRAG);
  if (!series) return 1;
  size_t cap = (size_t)npts * 160 + 64;
  char *body = malloc(cap), header[256];
  size_t len = 0;
  len = (size_t)snprintf(header, sizeof header, "time (s)");
  for (int r = 0; r < NROWS; r++)
    len += (size_t)snprintf(header + len, sizeof header - len, ",%s", rows[r].label);
  len = 0;
  for (int k = 0; body && k < npts; k++) {
    len += (size_t)snprintf(body + len, cap - len, "%g", k * every * sd.dt);
    for (int r = 0; r < NROWS; r++) {
      double v = series[(size_t)r * npts + k];
      len += (size_t)(isnan(v) ? snprintf(body + len, cap - len, ",NaN")
                               : snprintf(body + len, cap - len, ",%.6g", v));
    }
    len += (size_t)snprintf(body + len, cap - len, "\n");
  }
  tb_error err;
  char vars[256];
  snprintf(vars, sizeof vars,
           "title='Liver stretched by %.0f%% of its length, let go at 1 s'; xlabel='time (s)'; "
           "ylabel='rms displacement from rest (scene units)'; points=0",
           100 * amps[namps - 1]);
  if (!body || tb_suite_write_data(su, "recovery.csv", header, body, &err) ||
      tb_suite_chart_vars(su, "chart_lines.gp", "recovery.csv", "recovery", vars, &err)) {
    fprintf(stderr, "table 3.5: %s\n", body ? err.msg : "out of memory");
    failed = 1;
  } else
    tb_suite_caption(su, "recovery",
                     "rms displacement from rest against time, every model, after a stretch of "
                     "%.0f%% of the liver's length let go at 1 s (thesis §3.5: recovery)",
                     100 * amps[namps - 1]);
  free(body);
  free(series);
  return failed;
}

/* Part 3 (thesis ch. 5: "the instrument neither passes through nor leaves
 * the tissue"): every model on liver-press, the grasper's real mesh pushed
 * 1 into the liver's top; per model the steps per second, the largest
 * displacement, the most nodes held on the instrument, and the largest
 * depth of a node inside the instrument before the contact response (what
 * the model's own step did) and after it (what a frame would show). */
static int press(tb_suite *su, const tb_suite_opts *o) {
  static const char *cols[] = {"model",
                               "steps/s (CPU)",
                               "max displacement",
                               "most nodes in contact",
                               "deepest before response",
                               "deepest after response"};
  tb_table *t =
      tb_table_new("press", "Contact: the grasper pushed into the liver (liver-press)", 6, cols);
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.seed = o->seed;
  if (o->scale < 1) sd.duration = 0.3;
  int failed = 0;
  double size = 0;
  for (int r = 0; r < NROWS - 1; r++) {
    tb_settings d = thesis_def(r);
    tb_sim s;
    tb_error err;
    tb_table_row(t);
    tb_table_cell(t, "%s", rows[r].label);
    if (tb_sim_create(&s, "liver-press", &sd, rows[r].model, &d, NULL, &err)) {
      fprintf(stderr, "table 3.5: %s\n", err.msg);
      failed = 1;
      continue;
    }
    size = s.size;
    long n = lround(s.def.duration / s.def.dt);
    double *ms = malloc(sizeof(double) * 2 * (size_t)n), *cpu = ms ? ms + n : NULL;
    int most = 0, bad = !ms;
    for (long k = 0; k < n && !bad; k++) {
      tb_clock c = tb_clock_start();
      bad = tb_sim_step(&s, &err) != 0;
      tb_clock_ms(&c, ms + k, cpu + k);
      if (s.ncontact > most) most = s.ncontact;
      tb_progress_tick("step %ld/%ld", k + 1, n);
    }
    if (bad) {
      tb_table_cell(t, "unstable (%.120s)", ms ? err.msg : "out of memory");
    } else {
      char name[96];
      snprintf(name, sizeof name, "press/%s", rows[r].label);
      tb_suite_bench(su, name, ms, cpu, (int)n, "ms");
      tb_stats st = tb_stats_of(cpu, (int)n);
      tb_sim_metrics m = tb_sim_measure(&s);
      tb_table_num(t, 1e3 / st.median, "%.0f");
      tb_table_num(t, m.max_disp, "%.3f");
      tb_table_num(t, most, "%.0f");
      tb_table_num(t, s.pen_tool_before_max, "%.3g");
      tb_table_num(t, s.pen_tool_max, "%.3g");
      tb_suite_counter(su, name, "max_displacement", m.max_disp);
      tb_suite_counter(su, name, "most_contacts", most);
      tb_suite_counter(su, name, "depth_before_response", s.pen_tool_before_max);
      tb_suite_counter(su, name, "depth_after_response", s.pen_tool_max);
    }
    free(ms);
    tb_sim_destroy(&s);
  }
  tb_suite_table(su, t);
  tb_suite_note(
      su,
      "Scene liver-press: the liver resting on its lowest 15%%, the grasper (jaws closed, "
      "its real 1248-triangle mesh) pushed %g down into the top over %g s, dt %g, unit "
      "node masses. Each step, nodes the instrument would hold or push are prescribed on "
      "its surface; after the step the composite BVH finds the surface triangles crossing "
      "it and any node inside is put back on its surface (scenes/contact.c). Depths are in "
      "scene units (the liver's box diagonal is %.3g).",
      1.0, 0.75 * (o->scale < 1 ? 0.3 : 1.5), DT, size);
  return failed;
}

int tb_suite_table35(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/table-3.5", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(dir, "table-3.5", "Thesis §3.5: deformation models on the liver",
                               o->seed, &err);
  if (!s) return fprintf(stderr, "table 3.5: %s\n", err.msg), 1;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.seed = o->seed;
  tb_mesh liver;
  if (tb_sim_mesh("liver-stretch", &sd, &liver, &err)) {
    fprintf(stderr, "table 3.5: %s\n", err.msg);
    tb_suite_end(s, &err);
    return 1;
  }
  tb_vec3 lo, hi;
  tb_mesh_bbox(&liver, &lo, &hi);
  tb_suite_note(s,
                "Scene liver-stretch: the liver (%d nodes, %d tets) held along its back, a surface "
                "patch at the far lobe pulled out and let go at 1 s; dt %g for every model, unit "
                "node masses (the thesis gives no masses; mass-spring demos use 1). Thesis "
                "parameters: MSM ks 180, kd 5; FEM E 3000, nu 0.3 (Rayleigh stiffness damping "
                "0.02); shape matching 50 clusters, radius 1, alpha 0.72, beta 0.63, quadratic. "
                "The thesis's FPS were measured on an Intel i3-2100 with rendering; ours are "
                "simulation steps only, so the ratio is a ratio of machines and programs.",
                liver.nv, liver.ntet, DT);
  int threads = tb_threads_setting();
  tb_threads_set(1); /* a comparison of methods: one thread, CPU time */
  int failed = speed(s, o, &liver);
  failed |= tb_table35_corot(s, o, &liver);
  failed |= recovery(s, o, &liver, hi.x - lo.x);
  failed |= press(s, o);
  tb_threads_set(threads);
  tb_mesh_free(&liver);
  if (tb_suite_end(s, &err)) fprintf(stderr, "table 3.5: %s\n", err.msg), failed = 1;
  return failed;
}
