/* The deforming case: the liver (all tet faces) deformed every frame by a
 * smooth time-varying displacement (measure/collision_scene.c) around the instrument
 * held inside it. Per frame and method: the update (our refit with delta = 0
 * and with the thesis's delta, our full rebuild, FCL's refit, Bullet's
 * update), then the query, every method on one thread, the methods taking
 * turns frame by frame, each update and query timed in CPU and wall time;
 * the target (our refit at most half of FCL's) from the frames' paired
 * ratios and their 95% interval. Every frame's pair set is checked against
 * brute force with the exact test. Then our refit and query on threads
 * (suites/refit_threads.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_refit_threads.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "measure/tb_collision_scene.h"
#include "report/tb_results.h"
#include "scenes/tb_collider.h"

typedef struct variant {
  const char *label, *method;
  int delta; /* 0: delta 0, 1: the thesis's delta, -1: rebuild */
} variant;
static const variant variants[] = {
    {"composite refit (delta 0)", "composite", 0},
    {"composite refit (delta)", "composite", 1},
    {"composite rebuild", "composite", -1},
    {"aabb refit (delta 0)", "aabb", 0},
    {"fcl-aabb refit", "fcl-aabb", 0},
    {"fcl-obbrss refit", "fcl-obbrss", 0},
    {"bullet-gimpact update", "bullet-gimpact", 0},
};
#define NVAR ((int)(sizeof variants / sizeof variants[0]))
#define FCL_AABB 4 /* the target's reference */

int tb_suite_refit(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/refit", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(dir, "refit", "Deforming liver: update and query", o->seed, &err);
  if (!s) return fprintf(stderr, "refit: %s\n", err.msg), 1;
  tb_mesh liver, inst;
  if (tb_collision_scene_make(o->seed, &liver, &inst, &err)) {
    fprintf(stderr, "refit: %s\n", err.msg);
    tb_suite_end(s, &err);
    return 1;
  }
  int frames = o->scale < 1 ? 3 : (o->full ? 60 : 12), failed = 0;
  tb_vec3 lo, hi;
  tb_mesh_bbox(&liver, &lo, &hi);
  double delta = 0.01 * tb_dist(lo, hi), amp = 0.25;
  tb_mat3 R;
  tb_vec3 t;
  tb_collision_scene_pose(0.5, &R, &t); /* the tip 1.5 inside the liver: several hundred pairs */
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)liver.nv);
  /* the truth, frame by frame */
  tb_pairlist *truth = calloc((size_t)frames, sizeof *truth), pl = {0, 0, NULL};
  tb_collider *brute =
      x && truth ? tb_collider_new("brute", &liver, &inst, NULL, NULL, NULL, &err) : NULL;
  if (!brute || tb_collider_pose(brute, R, t, &err)) failed = 1;
  for (int f = 0; f < frames && !failed; f++) {
    tb_progress("refit (brute force)", f, frames);
    tb_collision_scene_deform(liver.x, liver.nv, 0.1 * (f + 1), amp, x);
    if (tb_collider_deform(brute, x, 0, &err) || tb_collider_query(brute, &truth[f], NULL, &err))
      failed = 1;
  }
  tb_collider_free(brute);
  /* u_cpu[v * frames + f]: variant v's update at frame f (ms); likewise the
   * update's wall time and the query's CPU and wall times */
  size_t nt = (size_t)NVAR * (size_t)frames;
  double *u_cpu = malloc(sizeof(double) * 4 * nt), *u_wall = u_cpu ? u_cpu + nt : NULL,
         *q_cpu = u_cpu ? u_cpu + 2 * nt : NULL, *q_wall = u_cpu ? u_cpu + 3 * nt : NULL;
  int bad[NVAR];
  memset(bad, 0, sizeof bad);
  if (!u_cpu) failed = 1;
  /* a speed comparison: every method on one thread (the references have
   * none; threads are below), CPU time */
  int was = tb_threads_setting();
  tb_threads_set(1);
  /* every method at once, so that they take turns frame by frame */
  tb_collider *col[NVAR];
  memset(col, 0, sizeof col);
  for (int v = 0; v < NVAR && !failed; v++) {
    col[v] = tb_collider_new(variants[v].method, &liver, &inst, NULL, NULL, NULL, &err);
    if (!col[v] || tb_collider_pose(col[v], R, t, &err)) {
      fprintf(stderr, "refit: %s: %s\n", variants[v].label, err.msg);
      failed = 1;
    }
  }
  for (int f = 0; f < frames && !failed; f++) {
    tb_progress("refit", f, frames);
    tb_collision_scene_deform(liver.x, liver.nv, 0.1 * (f + 1), amp, x);
    for (int v = 0; v < NVAR && !failed; v++) {
      double d = variants[v].delta < 0 ? -1 : (variants[v].delta ? delta : 0);
      size_t at = (size_t)v * (size_t)frames + (size_t)f;
      tb_clock cu = tb_clock_start();
      if (tb_collider_deform(col[v], x, d, &err)) failed = 1;
      tb_clock_ms(&cu, &u_wall[at], &u_cpu[at]);
      tb_clock cq = tb_clock_start();
      if (tb_collider_query(col[v], &pl, NULL, &err)) failed = 1;
      tb_clock_ms(&cq, &q_wall[at], &q_cpu[at]);
      bad[v] += tb_pairlist_difference(&pl, &truth[f]) != 0;
    }
  }
  for (int v = 0; v < NVAR; v++) tb_collider_free(col[v]);
  tb_progress("refit", frames, frames);
  tb_threads_set(was);
  if (!failed) {
    static const char *cols[] = {"method",
                                 "update CPU (ms, median)",
                                 "update wall (ms, median)",
                                 "query CPU (ms, median)",
                                 "query wall (ms, median)",
                                 "update / fcl-aabb refit (CPU ratio)",
                                 "update / fcl-aabb refit, 95% low",
                                 "update / fcl-aabb refit, 95% high",
                                 "frames with the exact pair set",
                                 "frames"};
    tb_table *tt = tb_table_new("refit",
                                "Per frame: update, then query (liver deformed, instrument inside; "
                                "one thread, the methods in turn every frame)",
                                10, cols);
    tb_table_only(tt, 9, TB_CSV_ONLY);
    const double *fcl = u_cpu + (size_t)FCL_AABB * (size_t)frames;
    for (int v = 0; v < NVAR; v++) {
      size_t at = (size_t)v * (size_t)frames;
      tb_est e = tb_ratio_est(u_cpu + at, fcl, frames);
      tb_table_row(tt);
      tb_table_cell(tt, "%s", variants[v].label);
      tb_table_num(tt, tb_stats_of(u_cpu + at, frames).median, "%.3f");
      tb_table_num(tt, tb_stats_of(u_wall + at, frames).median, "%.3f");
      tb_table_num(tt, tb_stats_of(q_cpu + at, frames).median, "%.3f");
      tb_table_num(tt, tb_stats_of(q_wall + at, frames).median, "%.3f");
      tb_table_num(tt, e.value, "%.3f");
      tb_table_num(tt, e.lo, "%.3f");
      tb_table_num(tt, e.hi, "%.3f");
      tb_table_numf(tt, frames - bad[v], "%d of %d", frames - bad[v], frames);
      tb_table_cell(tt, "%d", frames);
      if (bad[v] && strcmp(variants[v].method, "bullet-gimpact")) failed = 1;
      char bname[128];
      snprintf(bname, sizeof bname, "refit/%s/update", variants[v].label);
      tb_suite_bench(s, bname, u_wall + at, u_cpu + at, frames, "ms");
      tb_suite_counter_est(s, bname, "over_fcl_aabb", e);
      snprintf(bname, sizeof bname, "refit/%s/query", variants[v].label);
      tb_suite_bench(s, bname, q_wall + at, q_cpu + at, frames, "ms");
    }
    tb_suite_table(s, tt);
    tb_est ratio = tb_ratio_est(u_cpu, fcl, frames); /* composite refit (delta 0) */
    char verdict[200];
    tb_suite_note(
        s,
        "%d frames; displacement amplitude %.2f; the thesis gives no value for delta: we "
        "use 1%% of the liver's box diagonal (%.3f). A kept box is still grown to contain "
        "its children, so refit with delta stays exact. Every method runs on one thread; "
        "at every frame the methods take turns (update, then query, each timed in CPU and "
        "wall time); the medians are over the frames, a ratio is the median of the frames' "
        "paired ratios with its 95%% interval. Target: our refit (composite, delta 0) at most "
        "half of FCL's AABB refit CPU time: %.2f of it (95%% interval %.2f-%.2f), %s. "
        "Bullet's pair sets use its own triangle test (see the correctness table).",
        frames, amp, delta, ratio.value, ratio.lo, ratio.hi,
        tb_verdict_text(ratio, 0.5, 0, verdict, sizeof verdict));
  }
  if (!failed && tb_refit_threads(s, o, &err)) {
    fprintf(stderr, "refit (threads): %s\n", err.msg);
    failed = 1;
  }
  for (int f = 0; f < frames && truth; f++) tb_pairlist_free(&truth[f]);
  free(truth), free(x), free(u_cpu);
  tb_pairlist_free(&pl);
  tb_mesh_free(&liver), tb_mesh_free(&inst);
  if (tb_suite_end(s, &err)) return fprintf(stderr, "refit: %s\n", err.msg), 1;
  return failed;
}
