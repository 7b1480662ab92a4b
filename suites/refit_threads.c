/* The refit suite's thread table: our composite hierarchy's
 * refit (level by level, collision/bvh_update.c) and all-pairs query (a
 * fixed cut of the descent walked on threads, collision/bvh_query.c) on a
 * large deforming mesh, on one thread and on the thread count in effect (at
 * least 2). A geodesic sphere of 40962 vertices (81920 triangles; --full:
 * 163842 and 327680) against a deformed, shifted copy of itself; each
 * repetition refits both hierarchies to the next frame of the displacement
 * and queries, on one thread and then on several (the two take turns frame
 * by frame), timed in wall time (the speed-up, a paired ratio with its 95%
 * interval) with CPU time beside; on a busy machine the speed-up is "not
 * measurable". The two runs must give the same volumes bit for bit and the
 * same pair list in the same order, else the suite fails. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_refit_threads.h"
#include "tb_suites.h"
#include "collision/tb_bvh.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "meshgen/tb_meshgen.h"
#include "report/tb_results.h"

/* Frame f of a smooth displacement (the copy B: shifted). */
static void frame(const tb_mesh *m, int f, int b, tb_vec3 *y) {
  double t = 0.2 * f + (b ? 0.8 : 0.0), amp = 0.05;
  for (int v = 0; v < m->nv; v++) {
    tb_vec3 p = m->x[v];
    tb_vec3 d = tb_v3(sin(1.3 * p.y + t), cos(0.9 * p.z + 2 * t), sin(0.7 * p.x - t));
    y[v] = tb_add(tb_add(p, tb_scale(d, amp)), b ? tb_v3(0.3, 0.2, 0.1) : tb_v3(0, 0, 0));
  }
}

/* One thread count's hierarchies and what its repetitions measured. */
typedef struct run {
  int threads;
  tb_bvh A, B;
  tb_pairlist pairs;        /* the last frame's */
  double *rf_wall, *rf_cpu; /* every frame's refit, per hierarchy (ms) */
  double *q_wall, *q_cpu;   /* every frame's query (ms) */
} run;

static int run_init(run *r, const tb_mesh *m, int threads, int reps, tb_error *err) {
  memset(r, 0, sizeof *r);
  r->threads = threads;
  tb_threads_set(threads);
  tb_bvh_def d = tb_bvh_kind_def("composite");
  r->rf_wall = malloc(sizeof(double) * 4 * (size_t)reps);
  if (!r->rf_wall) return tb_error_set(err, "refit threads", 0, "out of memory");
  r->rf_cpu = r->rf_wall + reps, r->q_wall = r->rf_wall + 2 * reps,
  r->q_cpu = r->rf_wall + 3 * reps;
  if (tb_bvh_build(&r->A, m->x, m->tri, m->ntri, &d, err) ||
      tb_bvh_build(&r->B, m->x, m->tri, m->ntri, &d, err))
    return -1;
  return 0;
}

/* Frame k (positions ya, yb) on r's thread count: refit both hierarchies,
 * then query; the times into repetition k. */
static int run_frame(run *r, const tb_vec3 *ya, const tb_vec3 *yb, int k, tb_error *err) {
  tb_threads_set(r->threads);
  tb_clock c = tb_clock_start();
  if (tb_bvh_refit(&r->A, ya, 0) < 0 || tb_bvh_refit(&r->B, yb, 0) < 0)
    return tb_error_set(err, "refit threads", 0, "refit refused the frame");
  double w, p;
  tb_clock_ms(&c, &w, &p);
  r->rf_wall[k] = 0.5 * w, r->rf_cpu[k] = 0.5 * p; /* per hierarchy */
  r->pairs.n = 0;
  c = tb_clock_start();
  if (tb_bvh_collide(&r->A, ya, &r->B, yb, tb_tritri_exact, &r->pairs, NULL))
    return tb_error_set(err, "refit threads", 0, "out of memory");
  tb_clock_ms(&c, &r->q_wall[k], &r->q_cpu[k]);
  return 0;
}

static void run_free(run *r) {
  tb_pairlist_free(&r->pairs);
  free(r->rf_wall);
  if (r->A.nnodes) tb_bvh_free(&r->A);
  if (r->B.nnodes) tb_bvh_free(&r->B);
}

/* The same volumes and the same pair list in the same order. */
static int same_result(const run *a, const run *b) {
  size_t n = (size_t)a->A.nnodes;
  return a->A.nnodes == b->A.nnodes && a->pairs.n == b->pairs.n &&
         !memcmp(a->pairs.ij, b->pairs.ij, sizeof(int) * 2 * (size_t)a->pairs.n) &&
         !memcmp(a->A.box, b->A.box, sizeof(tb_aabb) * n) &&
         !memcmp(a->A.sph, b->A.sph, sizeof(tb_sphere) * n);
}

/* "not measurable (machine busy: ...)" when the machine could not give
 * `threads` threads their cores, else NULL. */
static const char *busy_text(const tb_noise *n, char *buf, size_t cap) {
  if (!n->busy) return NULL;
  snprintf(buf, cap, "not measurable (machine busy: others kept %.1f of %d cores busy%s)",
           n->others, n->cores, n->steal > 0.05 ? ", the hypervisor stole over 5%" : "");
  return buf;
}

int tb_refit_threads(tb_suite *s, const tb_suite_opts *o, tb_error *err) {
  int was = tb_threads_setting(), threads = tb_threads(), many = threads > 2 ? threads : 2;
  int reps = o->full ? 21 : 9, nsize = o->full ? 2 : 1;
  static const int verts[2] = {40962, 163842};
  static const char *cols[] = {"mesh (triangles)",   "step",
                               "1 thread wall (ms)", "1 thread CPU (ms)",
                               "threads (count)",    "threads wall (ms)",
                               "threads CPU (ms)",   "speed-up, wall (ratio)",
                               "speed-up, 95% low",  "speed-up, 95% high",
                               "speed-up",           "same result (1/0)"};
  tb_table *t = tb_table_new(
      "threads",
      "Refit and query on threads: composite, large sphere (wall time, medians; CPU beside)", 12,
      cols);
  int rc = 0, same_all = 1, busy = 0;
  for (int z = 0; z < nsize && !rc; z++) {
    tb_mesh m;
    if (tb_geosphere(verts[z], 1.0, &m, err)) {
      rc = -1;
      break;
    }
    run r1, rn;
    tb_vec3 *ya = malloc(sizeof(tb_vec3) * (size_t)m.nv), *yb = malloc(sizeof(tb_vec3) * m.nv);
    memset(&rn, 0, sizeof rn);
    rc = run_init(&r1, &m, 1, reps, err);
    if (!rc) rc = run_init(&rn, &m, many, reps, err);
    if (!rc && (!ya || !yb)) rc = tb_error_set(err, "refit threads", 0, "out of memory");
    /* the repetitions take turns: frame k on one thread, then on `many` */
    for (int k = 0; k < reps && !rc; k++) {
      tb_progress("refit (threads)", z * reps + k, nsize * reps);
      frame(&m, k, 0, ya), frame(&m, k, 1, yb);
      rc = run_frame(&r1, ya, yb, k, err);
      if (!rc) rc = run_frame(&rn, ya, yb, k, err);
    }
    if (!rc) {
      int same = same_result(&r1, &rn);
      same_all &= same;
      tb_noise nz = tb_suite_noise(s, many);
      busy |= nz.busy;
      const char *step[2] = {"refit (per hierarchy)", "query"};
      for (int k = 0; k < 2; k++) {
        const double *w1 = k ? r1.q_wall : r1.rf_wall, *c1 = k ? r1.q_cpu : r1.rf_cpu;
        const double *wn = k ? rn.q_wall : rn.rf_wall, *cn = k ? rn.q_cpu : rn.rf_cpu;
        tb_est up = tb_ratio_est(w1, wn, reps);
        char cell[200];
        tb_table_row(t);
        tb_table_cell(t, "%d", m.ntri);
        tb_table_cell(t, "%s", step[k]);
        tb_table_num(t, tb_stats_of(w1, reps).median, "%.3f");
        tb_table_num(t, tb_stats_of(c1, reps).median, "%.3f");
        tb_table_cell(t, "%d", many);
        tb_table_num(t, tb_stats_of(wn, reps).median, "%.3f");
        tb_table_num(t, tb_stats_of(cn, reps).median, "%.3f");
        tb_table_num(t, up.value, "%.2f");
        tb_table_num(t, up.lo, "%.2f");
        tb_table_num(t, up.hi, "%.2f");
        if (!busy_text(&nz, cell, sizeof cell))
          snprintf(cell, sizeof cell, "%.2fx (%.2f-%.2f)", up.value, up.lo, up.hi);
        tb_table_cell(t, "%s", cell);
        tb_table_cell(t, "%d", same);
        char name[128];
        snprintf(name, sizeof name, "refit-threads/%s/%d triangles/1 thread", step[k], m.ntri);
        tb_suite_bench(s, name, w1, c1, reps, "ms");
        snprintf(name, sizeof name, "refit-threads/%s/%d triangles/%d threads", step[k], m.ntri,
                 many);
        tb_suite_bench(s, name, wn, cn, reps, "ms");
        tb_suite_counter_est(s, name, "speedup_wall", up);
        tb_suite_counter(s, name, "machine_busy", nz.busy);
      }
    }
    run_free(&r1), run_free(&rn);
    free(ya), free(yb);
    tb_mesh_free(&m);
  }
  tb_progress("refit (threads)", nsize * reps, nsize * reps);
  tb_threads_set(was);
  tb_suite_table(s, t);
  tb_suite_note(s,
                "Threads: the frames take turns, each refit and queried on one thread, then on "
                "%d; figures are medians of %d frames, wall time (what threads shorten) with CPU "
                "time beside (every thread's with %d). The speed-up is the median of the "
                "frames' paired wall-time ratios with its 95%% interval%s. The refit column is "
                "per hierarchy (two are refit per frame), the query finds the pairs along the "
                "two spheres' crossing. One thread and %d threads give the same volumes and the "
                "same pair list in the same order: %s.",
                many, reps, many,
                busy ? "; the machine was busy (other processes held cores the threads needed), "
                       "so the speed-up is not measurable in this run"
                     : "",
                many, same_all ? "yes" : "NO");
  if (!rc && !same_all) rc = tb_error_set(err, "refit threads", 0, "results differ by threads");
  return rc;
}
