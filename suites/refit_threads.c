/* The refit suite's thread table: our composite hierarchy's
 * refit (level by level, collision/bvh_update.c) and all-pairs query (a
 * fixed cut of the descent walked on threads, collision/bvh_query.c) on a
 * large deforming mesh, on one thread and on the thread count in effect (at
 * least 2). A geodesic sphere of 40962 vertices (81920 triangles; --full:
 * 163842 and 327680) against a deformed, shifted copy of itself; each
 * repetition refits both hierarchies to the next frame of the displacement
 * and queries. The two runs must give the same volumes bit for bit and the
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

typedef struct run {
  double refit_ms, query_ms;
  double *rf, *q;    /* every frame's times (ms) */
  tb_pairlist pairs; /* the last frame's */
  tb_aabb *box;      /* A's last volumes */
  tb_sphere *sph;
  int nnodes;
} run;

static int one_run(const tb_mesh *m, int threads, int reps, run *r, tb_error *err) {
  tb_threads_set(threads);
  tb_bvh_def d = tb_bvh_kind_def("composite");
  tb_bvh A = {0}, B = {0};
  tb_vec3 *ya = malloc(sizeof(tb_vec3) * (size_t)m->nv), *yb = malloc(sizeof(tb_vec3) * m->nv);
  double *rf = malloc(sizeof(double) * (size_t)reps), *q = malloc(sizeof(double) * (size_t)reps);
  int rc = !ya || !yb || !rf || !q ? tb_error_set(err, "refit threads", 0, "out of memory") : 0;
  if (!rc && (tb_bvh_build(&A, m->x, m->tri, m->ntri, &d, err) ||
              tb_bvh_build(&B, m->x, m->tri, m->ntri, &d, err)))
    rc = -1;
  memset(r, 0, sizeof *r);
  for (int k = 0; k < reps && !rc; k++) {
    frame(m, k, 0, ya), frame(m, k, 1, yb);
    uint64_t t0 = tb_time_ns();
    if (tb_bvh_refit(&A, ya, 0) < 0 || tb_bvh_refit(&B, yb, 0) < 0)
      rc = tb_error_set(err, "refit threads", 0, "refit refused the frame");
    uint64_t t1 = tb_time_ns();
    r->pairs.n = 0;
    if (!rc && tb_bvh_collide(&A, ya, &B, yb, tb_tritri_exact, &r->pairs, NULL))
      rc = tb_error_set(err, "refit threads", 0, "out of memory");
    rf[k] = (double)(t1 - t0) * 0.5e-6; /* per hierarchy */
    q[k] = (double)(tb_time_ns() - t1) * 1e-6;
  }
  if (!rc) {
    r->refit_ms = tb_stats_of(rf, reps).median, r->query_ms = tb_stats_of(q, reps).median;
    r->rf = rf, r->q = q, rf = q = NULL;
    r->nnodes = A.nnodes;
    r->box = malloc(sizeof(tb_aabb) * (size_t)A.nnodes);
    r->sph = malloc(sizeof(tb_sphere) * (size_t)A.nnodes);
    if (r->box && r->sph) {
      memcpy(r->box, A.box, sizeof(tb_aabb) * (size_t)A.nnodes);
      memcpy(r->sph, A.sph, sizeof(tb_sphere) * (size_t)A.nnodes);
    } else
      rc = tb_error_set(err, "refit threads", 0, "out of memory");
  }
  if (A.nnodes) tb_bvh_free(&A);
  if (B.nnodes) tb_bvh_free(&B);
  free(ya), free(yb), free(rf), free(q);
  return rc;
}

static void run_free(run *r) {
  tb_pairlist_free(&r->pairs);
  free(r->rf), free(r->q);
  free(r->box), free(r->sph);
}

int tb_refit_threads(tb_suite *s, const tb_suite_opts *o, tb_error *err) {
  int threads = tb_threads(), many = threads > 2 ? threads : 2;
  int reps = o->full ? 21 : 9, nsize = o->full ? 2 : 1;
  static const int verts[2] = {40962, 163842};
  static const char *cols[] = {"mesh (triangles)", "step",         "1 thread (ms)",
                               "threads (count)",  "threads (ms)", "speed-up (ratio)",
                               "same result (1/0)"};
  tb_table *t =
      tb_table_new("threads", "Refit and query on threads: composite, large sphere", 7, cols);
  int rc = 0, same_all = 1;
  for (int z = 0; z < nsize && !rc; z++) {
    tb_mesh m;
    if (tb_geosphere(verts[z], 1.0, &m, err)) {
      rc = -1;
      break;
    }
    run r1, rn;
    memset(&rn, 0, sizeof rn);
    tb_progress("refit (threads)", 2 * z, 2 * nsize);
    rc = one_run(&m, 1, reps, &r1, err);
    tb_progress("refit (threads)", 2 * z + 1, 2 * nsize);
    if (!rc) rc = one_run(&m, many, reps, &rn, err);
    if (!rc) {
      int same = r1.nnodes == rn.nnodes && r1.pairs.n == rn.pairs.n &&
                 !memcmp(r1.pairs.ij, rn.pairs.ij, sizeof(int) * 2 * (size_t)r1.pairs.n) &&
                 !memcmp(r1.box, rn.box, sizeof(tb_aabb) * (size_t)r1.nnodes) &&
                 !memcmp(r1.sph, rn.sph, sizeof(tb_sphere) * (size_t)r1.nnodes);
      same_all &= same;
      const char *step[2] = {"refit (per hierarchy)", "query"};
      double a[2] = {r1.refit_ms, r1.query_ms}, b[2] = {rn.refit_ms, rn.query_ms};
      for (int k = 0; k < 2; k++) {
        tb_table_row(t);
        tb_table_cell(t, "%d", m.ntri);
        tb_table_cell(t, "%s", step[k]);
        tb_table_num(t, a[k], "%.3f");
        tb_table_cell(t, "%d", many);
        tb_table_num(t, b[k], "%.3f");
        tb_table_num(t, b[k] > 0 ? a[k] / b[k] : NAN, "%.2f");
        tb_table_cell(t, "%d", same);
        char name[128];
        snprintf(name, sizeof name, "refit-threads/%s/%d triangles/1 thread", step[k], m.ntri);
        tb_suite_bench(s, name, k ? r1.q : r1.rf, NULL, reps, "ms");
        snprintf(name, sizeof name, "refit-threads/%s/%d triangles/%d threads", step[k], m.ntri,
                 many);
        tb_suite_bench(s, name, k ? rn.q : rn.rf, NULL, reps, "ms");
      }
    }
    run_free(&r1), run_free(&rn);
    tb_mesh_free(&m);
  }
  tb_progress("refit (threads)", 2 * nsize, 2 * nsize);
  tb_threads_set(threads);
  tb_suite_table(s, t);
  tb_suite_note(s,
                "Threads: medians of %d frames; the refit column is per hierarchy "
                "(two are refit per frame), the query finds the pairs along the two spheres' "
                "crossing. One thread and %d threads give the same volumes and the same pair "
                "list in the same order: %s.",
                reps, many, same_all ? "yes" : "NO");
  if (!rc && !same_all) rc = tb_error_set(err, "refit threads", 0, "results differ by threads");
  return rc;
}
