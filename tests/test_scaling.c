/* Threads and the scaling suite: msm and sm give
 * bit-identical positions and velocities on 1 and 2 threads (every sm mode,
 * overlapping regions and per-node tet clusters) on a beam large enough
 * that both threads get work (the models stay on one thread below 40000
 * springs or 8000 cluster members), msm on 3 threads too; msm's spatial node
 * order splits a beam into halves across its length; the blow-up check
 * reports the same on 1 and 2 threads; the `scaling` suite run tiny
 * (suites/suite_scaling.c, --scale 0.01: livers of 600, 1200 and 2500
 * tets) writes its tables with their columns, a finite slope and a peak
 * RSS per tet for every model of the table, finite collision slopes, a
 * finite speed-up and bit-identical threads, speed-goal verdicts that are
 * one of the allowed words, and its charts. Timings are checked only for
 * being well formed and finite, never for their size. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "core/tb_threads.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"

/* A 3 x 0.5 x 0.5 beam of 60 x 10 x 10 cubes (7381 nodes, 36000 tets,
 * 45980 springs) held at x = 0, under gravity and a sideways force
 * on its far end, `steps` steps on `threads` threads; x and v copied out. */
static int run(const char *model, const char *kvs, int threads, int steps, tb_vec3 *x, tb_vec3 *v,
               int *nv) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  if (tb_beam(3, 0.5, 0.5, 60, 10, 10, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return -1;
  }
  tb_settings set = tb_test_settings(kvs);
  tb_model md;
  int rc = tb_model_create(&md, model, &m, &set, &err);
  TB_CHECK_MSG(rc == 0, "%s %s: %s", model, kvs, err.msg);
  int *fixed = malloc(sizeof(int) * (size_t)m.nv), nfixed = 0;
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)m.nv), *f = calloc((size_t)m.nv, sizeof(tb_vec3));
  for (int i = 0; i < m.nv; i++) {
    if (m.x[i].x < 1e-9) fixed[nfixed] = i, fx[nfixed++] = m.x[i];
    if (m.x[i].x > 3 - 1e-9) f[i] = tb_v3(0, 0.5, 0.2);
  }
  tb_threads_set(threads);
  tb_step st = {0};
  st.dt = 0.005, st.gravity = tb_v3(0, 0, -9.81), st.force = f;
  st.nfixed = nfixed, st.fixed = fixed, st.fixed_x = fx;
  for (int k = 0; k < steps && !rc; k++) {
    rc = tb_model_step(&md, &st, &err);
    TB_CHECK_MSG(rc == 0, "%s %s step %d: %s", model, kvs, k, err.msg);
  }
  if (!rc) {
    *nv = m.nv;
    memcpy(x, tb_model_positions(&md), sizeof(tb_vec3) * (size_t)m.nv);
    memcpy(v, tb_model_velocities(&md), sizeof(tb_vec3) * (size_t)m.nv);
    tb_model_destroy(&md);
  }
  free(fixed), free(fx), free(f);
  tb_mesh_free(&m);
  return rc;
}

/* 1 and nt threads: the same bits, and the beam moved (the steps did work). */
static void identical_nt(const char *model, const char *kvs, int nt) {
  enum { NV = 61 * 11 * 11, STEPS = 40 };
  static tb_vec3 x1[NV], v1[NV], x2[NV], v2[NV];
  int n1 = 0, n2 = 0, threads = tb_threads();
  int r1 = run(model, kvs, 1, STEPS, x1, v1, &n1), r2 = run(model, kvs, nt, STEPS, x2, v2, &n2);
  tb_threads_set(threads);
  if (r1 || r2) return;
  TB_CHECK(n1 == NV && n2 == NV);
  TB_CHECK_MSG(!memcmp(x1, x2, sizeof x1) && !memcmp(v1, v2, sizeof v1),
               "%s %s: 1 and %d threads differ", model, kvs, nt);
  double moved = 0;
  for (int i = 0; i < NV; i++) moved = fmax(moved, fabs(v1[i].z));
  TB_CHECK_MSG(moved > 1e-3 && isfinite(moved), "%s %s: fastest node %g", model, kvs, moved);
}

static void identical(const char *model, const char *kvs) { identical_nt(model, kvs, 2); }

/* msm on 2 and on 3 threads (parts that do not fall on the halves of its
 * spatial order). */
static void msm_threads_identical(void) {
  identical("msm", "");
  identical("msm", "calibrated=1 node_mass=0 density=1000 E=3000 kd=0.01");
  identical_nt("msm", "", 3);
}

/* tb_spatial_order (models/model_util.c, msm's internal node order) on the
 * beam's nodes, shuffled: a permutation; its first half lies on one side of
 * a plane across the beam's long axis (x), its first quarter within one
 * half of that half's longest side. */
static void spatial_order_halves(void) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  if (tb_beam(3, 0.8, 0.8, 30, 8, 8, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  const int n = m.nv;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)n);
  int *order = malloc(sizeof(int) * (size_t)n), *seen = calloc((size_t)n, sizeof(int));
  for (int i = 0; i < n; i++) x[i] = m.x[(int)((long)i * 1237 % n)]; /* 1237 is prime to n */
  TB_CHECK(tb_spatial_order(x, n, order) == 0);
  int perm = 1;
  for (int r = 0; r < n; r++) perm &= order[r] >= 0 && order[r] < n && !seen[order[r]]++;
  TB_CHECK_MSG(perm, "not a permutation of %d points", n);
  double lo_max = -HUGE_VAL, hi_min = HUGE_VAL, q_max = -HUGE_VAL, q_min = HUGE_VAL;
  for (int r = 0; perm && r < n; r++) {
    const tb_vec3 p = x[order[r]];
    if (r < n / 2)
      lo_max = fmax(lo_max, p.x);
    else
      hi_min = fmin(hi_min, p.x);
  }
  TB_CHECK_MSG(lo_max <= hi_min, "halves overlap along x: %g > %g", lo_max, hi_min);
  for (int r = 0; perm && r < n / 4; r++)
    q_max = fmax(q_max, x[order[r]].x), q_min = fmin(q_min, x[order[r]].x);
  TB_CHECK_MSG(q_max - q_min <= 0.8 + 1e-9, "first quarter spans %g in x", q_max - q_min);
  free(x), free(order), free(seen);
  tb_mesh_free(&m);
}

static void sm_threads_identical(void) {
  static const char *const kvs[] = {
      "sm_mode=rigid clusters=12 radius=1.0",     "sm_mode=linear clusters=12 radius=1.0",
      "sm_mode=quadratic clusters=12 radius=1.0", "sm_mode=rigid cluster_mode=tets",
      "sm_mode=linear cluster_mode=tets",         "sm_mode=quadratic cluster_mode=tets"};
  for (int k = 0; k < 6; k++) identical("sm", kvs[k]);
}

/* tb_model_health (models/model_util.c; one thread whatever the count) on
 * a 60 x 18 x 18 beam (22021 nodes, 116640 tets): the first bad node and
 * the inverted tets' count and first, on 1 and 2 threads alike. */
static void health_threads(void) {
  tb_mesh m;
  tb_error err;
  memset(&m, 0, sizeof m);
  if (tb_beam(6, 1.8, 1.8, 60, 18, 18, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  const int nv = m.nv, threads = tb_threads();
  TB_CHECK(nv >= 20000 && m.ntet >= 20000);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)nv), *v = calloc((size_t)nv, sizeof(tb_vec3));
  char want[3][96];
  snprintf(want[0], sizeof want[0], "NaN or inf (node %d)", nv / 3);
  snprintf(want[1], sizeof want[1], "velocity 20 beyond bound 10 (node %d)", nv / 4);
  tb_vec3 *xm = malloc(sizeof(tb_vec3) * (size_t)nv); /* the part x < 3 mirrored about x = 8 */
  for (int i = 0; i < nv; i++)
    xm[i] = m.x[i].x < 3 - 1e-9 ? tb_v3(16 - m.x[i].x, m.x[i].y, m.x[i].z) : m.x[i];
  int cut = 0, first = -1; /* inverted tets, counted here one by one */
  for (int t = 0; t < m.ntet; t++) {
    const int *e = m.tet + 4 * t;
    if (!(tb_tet_volume(xm[e[0]], xm[e[1]], xm[e[2]], xm[e[3]]) > 0) && !cut++) first = t;
  }
  TB_CHECK(cut > 1000 && first >= 0);
  snprintf(want[2], sizeof want[2], "inverted elements (%d, first tet %d)", cut, first);
  for (int nt = 1; nt <= 2; nt++) {
    tb_threads_set(nt);
    memcpy(x, m.x, sizeof(tb_vec3) * (size_t)nv);
    TB_CHECK(tb_model_health(&m, x, v, 10, 1).ok);
    x[nv / 3].y = NAN, x[nv - 5].z = INFINITY;
    tb_health h = tb_model_health(&m, x, v, 10, 1);
    TB_CHECK_MSG(!h.ok && !strcmp(h.reason, want[0]), "%d threads: %s", nt, h.reason);
    memcpy(x, m.x, sizeof(tb_vec3) * (size_t)nv);
    v[nv / 4] = v[nv - 3] = tb_v3(0, 20, 0);
    h = tb_model_health(&m, x, v, 10, 1);
    TB_CHECK_MSG(!h.ok && !strcmp(h.reason, want[1]), "%d threads: %s", nt, h.reason);
    v[nv / 4] = v[nv - 3] = tb_v3(0, 0, 0);
    h = tb_model_health(&m, xm, v, 10, 1);
    TB_CHECK_MSG(!h.ok && !strcmp(h.reason, want[2]), "%d threads: %s, not %s", nt, h.reason,
                 want[2]);
  }
  tb_threads_set(threads);
  free(x), free(v), free(xm);
  tb_mesh_free(&m);
}

/* The suite's CSV file into buf; 0 when read. */
static int slurp(const char *file, char *buf, int cap) {
  char cmd[700];
  snprintf(cmd, sizeof cmd, "cat %s/rsc/scaling/%s", tb_test_tmpdir(), file);
  return tb_test_run(cmd, buf, cap);
}

/* 1 when the CSV's header line holds every column of cols. */
static int has_columns(const char *csv, const char *const *cols, int n) {
  const char *nl = strchr(csv, '\n');
  size_t len = nl ? (size_t)(nl - csv) : strlen(csv);
  for (int k = 0; k < n; k++) {
    const char *p = strstr(csv, cols[k]);
    if (!p || (size_t)(p - csv) >= len) {
      TB_CHECK_MSG(0, "no column '%s' in %.*s", cols[k], (int)len, csv);
      return 0;
    }
  }
  return 1;
}

/* 1 when text starts with one of the verdicts a timed goal may have. */
static int verdict_word(const char *text) {
  static const char *const words[] = {"met", "not met", "inconclusive (", "not measurable (",
                                      "not measured ("};
  for (size_t k = 0; k < sizeof words / sizeof words[0]; k++)
    if (!strncmp(text, words[k], strlen(words[k]))) return 1;
  return 0;
}

/* `figure scaling --scale 0.01`: three small livers; every table's columns,
 * a row per model of the table with a finite slope (any value: it is a
 * timing), the collision's finite slopes, finite thread timings and
 * speed-ups, bit-identical threads, well-formed goal verdicts, the charts. */
static void scaling_suite_smoke(void) {
  static char csv[32768];
  char args[600];
  snprintf(args, sizeof args, "figure scaling --scale 0.01 --results %s/rsc", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  static const char *const time_cols[] = {"model",
                                          "tets",
                                          "nodes",
                                          "ms/step CPU (median)",
                                          "ms/step wall (median)",
                                          "steps timed",
                                          "peak RSS added (MiB)",
                                          "RSS per tet (KiB)",
                                          "status"};
  TB_CHECK(slurp("table-time.csv", csv, sizeof csv) == 0 && has_columns(csv, time_cols, 9));
  for (int k = 0; k < tb_model_count; k++) {
    const char *name = tb_model_classes[k]->name;
    double cpu = tb_test_csv_num(csv, name, 3), wall = tb_test_csv_num(csv, name, 4);
    TB_CHECK_MSG(isfinite(cpu) && cpu >= 0 && isfinite(wall) && wall >= 0, "%s: %s", name, csv);
  }
  static const char *const fit_cols[] = {"series",
                                         "x",
                                         "sizes fitted",
                                         "slope (log-log)",
                                         "largest x at 33.3 ms (30 Hz)",
                                         "largest x at 3.33 ms (300 Hz)",
                                         "RSS per tet at the largest (KiB)"};
  TB_CHECK(slurp("table-fit.csv", csv, sizeof csv) == 0 && has_columns(csv, fit_cols, 7));
  for (int k = 0; k < tb_model_count; k++) {
    const char *name = tb_model_classes[k]->name;
    double slope = tb_test_csv_num(csv, name, 3), rss = tb_test_csv_num(csv, name, 7);
    TB_CHECK_MSG(tb_test_csv_num(csv, name, 2) == 3 && isfinite(slope), "%s: %s", name, csv);
    TB_CHECK_MSG(rss > 0 && rss < 1000, "%s: RSS per tet %g KiB", name, rss);
  }
  static const char *const coll[] = {"collision: refit", "collision: query",
                                     "collision: refit + query"};
  for (int k = 0; k < 3; k++)
    TB_CHECK_MSG(isfinite(tb_test_csv_num(csv, coll[k], 3)), "%s: %s", coll[k], csv);
  static const char *const thr_cols[] = {"model",
                                         "ms/step wall, 1 thread (median)",
                                         "ms/step wall, all threads (median)",
                                         "ms/step CPU, 1 thread (median)",
                                         "ms/step CPU, all threads (median)",
                                         "speed-up, wall (95% interval)",
                                         "speed-up low",
                                         "speed-up high",
                                         "speed-up measurable",
                                         "identical",
                                         "serial share (Karp-Flatt)",
                                         "predicted speed-up, 4 cores",
                                         "predicted speed-up, 8 cores",
                                         "predicted speed-up, 16 cores"};
  TB_CHECK(slurp("table-threads.csv", csv, sizeof csv) == 0 && has_columns(csv, thr_cols, 14));
  for (int k = 0; k < tb_model_count; k++) {
    const char *name = tb_model_classes[k]->name;
    for (int c = 3; c <= 9; c++) /* the times, the speed-up and its interval */
      TB_CHECK_MSG(isfinite(tb_test_csv_num(csv, name, c)) && tb_test_csv_num(csv, name, c) > 0,
                   "%s, column %d: %s", name, c, csv);
    const char *m = tb_test_csv_cell(csv, name, 10);
    TB_CHECK_MSG(!strcmp(m, "yes") || !strncmp(m, "not measurable (", 16), "%s: %s", name, m);
    TB_CHECK_MSG(!strcmp(tb_test_csv_cell(csv, name, 11), "yes"), "%s: %s", name, csv);
    /* predicted where measurable: a serial share below 1, speed-ups growing with the
     * cores and never beyond them; none where the threads gained nothing */
    double e = tb_test_csv_num(csv, name, 12), p4 = tb_test_csv_num(csv, name, 13),
           p8 = tb_test_csv_num(csv, name, 14), p16 = tb_test_csv_num(csv, name, 15);
    if (!strcmp(m, "yes") && tb_threads_cores() >= 2 && e < 1)
      TB_CHECK_MSG(e >= 0 && p4 >= 1 && p4 <= p8 && p8 <= p16 && p4 <= 4 && p8 <= 8 && p16 <= 16,
                   "%s: e %g, predicted %g %g %g", name, e, p4, p8, p16);
    else if (!strcmp(m, "yes") && tb_threads_cores() >= 2)
      TB_CHECK_MSG(isnan(p4) && isnan(p16), "%s: no gain, yet predicted %g %g", name, p4, p16);
  }
  /* the thread axis: every model's counts measured, 1 thread first with a speed-up of 1 */
  static const char *const axis_cols[] = {"model", "tets", "threads", "source", "speed-up"};
  TB_CHECK(slurp("table-thread-axis.csv", csv, sizeof csv) == 0 && has_columns(csv, axis_cols, 5));
  for (int k = 0; k < tb_model_count; k++) {
    const char *name = tb_model_classes[k]->name;
    TB_CHECK_MSG(tb_test_csv_num(csv, name, 2) == 1 &&
                     !strcmp(tb_test_csv_cell(csv, name, 3), "measured") &&
                     tb_test_csv_num(csv, name, 6) == 1,
                 "%s: %s", name, csv);
  }
  static const char *const col_cols[] = {"tets", "triangles (all tet faces)", "refit CPU (ms)",
                                         "query CPU (ms)", "refit + query wall (ms)"};
  TB_CHECK(slurp("table-collision.csv", csv, sizeof csv) == 0 && has_columns(csv, col_cols, 5));
  static char md[65536];
  TB_CHECK(slurp("table.md", md, sizeof md) == 0);
  static const char *const goals[] = {"Speed goal: pbd-stvk on 2 threads", "Speed goal: msm on 2",
                                      "Speed goal: sm on 2"};
  for (int k = 0; k < 3; k++) { /* "...(wall time): [measured; ]verdict." */
    const char *g = strstr(md, goals[k]), *p = g ? strstr(g, "(wall time): ") : NULL;
    const char *semi = p ? strstr(p, "; ") : NULL, *end = p ? strchr(p, '\n') : NULL;
    TB_CHECK_MSG(
        p && (verdict_word(p + 13) || (semi && (!end || semi < end) && verdict_word(semi + 2))),
        "%s: %.300s", goals[k], g ? g : md);
  }
  snprintf(args, sizeof args,
           "test -s %s/rsc/scaling/time.png && test -s %s/rsc/scaling/collision.png && test -s "
           "%s/rsc/scaling/data.json && test -s %s/rsc/scaling/threads.png",
           tb_test_tmpdir(), tb_test_tmpdir(), tb_test_tmpdir(), tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(args, tb_test_out, sizeof tb_test_out) == 0, "%s", tb_test_out);
}

const tb_test_case tb_tests_scaling[] = {
    {"scaling_suite_smoke", scaling_suite_smoke},
    {"msm_threads_identical", msm_threads_identical},
    {"sm_threads_identical", sm_threads_identical},
    {"spatial_order_halves", spatial_order_halves},
    {"health_threads", health_threads},
    {0, 0},
};
