/* The deforming case: the liver (all tet faces) deformed every frame by a
 * smooth time-varying displacement (suites/collision_scene.c) around the instrument
 * held inside it. Per frame and method: the update (our refit with delta = 0
 * and with the thesis's delta, our full rebuild, FCL's refit, Bullet's
 * update), then the query, every method on one thread; every frame's pair
 * set is checked against brute force with the exact test. Then our refit
 * and query on threads (suites/refit_threads.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_collision_scene.h"
#include "tb_refit_threads.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
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
  double upd[NVAR], qry[NVAR];
  int bad[NVAR];
  double *u = malloc(sizeof(double) * (size_t)frames), *q = malloc(sizeof(double) * (size_t)frames);
  int threads = tb_threads();
  tb_threads_set(1); /* as the references: ours on one thread too (threads: below) */
  for (int v = 0; v < NVAR && !failed && u && q; v++) {
    tb_progress("refit", v, NVAR);
    tb_collider *c = tb_collider_new(variants[v].method, &liver, &inst, NULL, NULL, NULL, &err);
    if (!c || tb_collider_pose(c, R, t, &err)) {
      fprintf(stderr, "refit: %s: %s\n", variants[v].label, err.msg);
      tb_collider_free(c);
      failed = 1;
      break;
    }
    bad[v] = 0;
    double d = variants[v].delta < 0 ? -1 : (variants[v].delta ? delta : 0);
    for (int f = 0; f < frames && !failed; f++) {
      tb_collision_scene_deform(liver.x, liver.nv, 0.1 * (f + 1), amp, x);
      uint64_t t0 = tb_time_ns();
      if (tb_collider_deform(c, x, d, &err)) failed = 1;
      uint64_t t1 = tb_time_ns();
      if (tb_collider_query(c, &pl, NULL, &err)) failed = 1;
      uint64_t t2 = tb_time_ns();
      u[f] = (double)(t1 - t0) * 1e-6, q[f] = (double)(t2 - t1) * 1e-6;
      bad[v] += tb_pairlist_difference(&pl, &truth[f]) != 0;
    }
    upd[v] = tb_stats_of(u, frames).median, qry[v] = tb_stats_of(q, frames).median;
    char bname[128];
    snprintf(bname, sizeof bname, "refit/%s/update", variants[v].label);
    tb_suite_bench(s, bname, u, u, frames, "ms");
    snprintf(bname, sizeof bname, "refit/%s/query", variants[v].label);
    tb_suite_bench(s, bname, q, q, frames, "ms");
    tb_collider_free(c);
  }
  tb_progress("refit", NVAR, NVAR);
  tb_threads_set(threads);
  if (!failed) {
    static const char *cols[] = {"method", "update (ms, median)", "query (ms, median)",
                                 "frames with the exact pair set", "frames"};
    tb_table *tt = tb_table_new(
        "refit", "Per frame: update, then query (liver deformed, instrument inside)", 5, cols);
    tb_table_only(tt, 4, TB_CSV_ONLY);
    for (int v = 0; v < NVAR; v++) {
      tb_table_row(tt);
      tb_table_cell(tt, "%s", variants[v].label);
      tb_table_cell(tt, "%.3f", upd[v]);
      tb_table_cell(tt, "%.3f", qry[v]);
      tb_table_numf(tt, frames - bad[v], "%d of %d", frames - bad[v], frames);
      tb_table_cell(tt, "%d", frames);
      if (bad[v] && strcmp(variants[v].method, "bullet-gimpact")) failed = 1;
    }
    tb_suite_table(s, tt);
    double ratio = upd[4] > 0 ? upd[0] / upd[4] : 0;
    tb_suite_note(
        s,
        "%d frames; displacement amplitude %.2f; the thesis gives no value for delta: we "
        "use 1%% of the liver's box diagonal (%.3f). A kept box is still grown to contain "
        "its children, so refit with delta stays exact. Target: our refit at "
        "most half of FCL's AABB refit time: %.2f of it, %s. Bullet's pair sets use its "
        "own triangle test (see the correctness table).",
        frames, amp, delta, ratio, ratio <= 0.5 ? "met" : "NOT met");
  }
  if (!failed && tb_refit_threads(s, o, &err)) {
    fprintf(stderr, "refit (threads): %s\n", err.msg);
    failed = 1;
  }
  for (int f = 0; f < frames && truth; f++) tb_pairlist_free(&truth[f]);
  free(truth), free(x), free(u), free(q);
  tb_pairlist_free(&pl);
  tb_mesh_free(&liver), tb_mesh_free(&inst);
  if (tb_suite_end(s, &err)) return fprintf(stderr, "refit: %s\n", err.msg), 1;
  return failed;
}
