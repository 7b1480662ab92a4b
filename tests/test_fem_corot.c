/* Tests of fem-corot's solvers (models/fem_solve.c: exact, pcg, lagged,
 * pd) and of the FEM's threads: on a beam held at one end whose other end
 * is turned 120 degrees about the axis under gravity (a large deformation),
 * pcg matches the exact path to 1e-6 relative, dynamic and quasi-static;
 * pd's error is bounded and falls with more iterations; the iteration and
 * factorisation counters follow the settings; bad settings are refused;
 * fem and every fem-corot solver give the same bits on 1 and 2 threads. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "tb_test_models.h"
#include "core/tb_threads.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_fem.h"
#include "models/tb_model.h"

#define STEPS 80
#define TURN (2 * M_PI / 3) /* the end face's final turn */

/* The beam 4 x 1 x 1 (8 x 2 x 2 cubes), its root (x = 0) held, its end
 * (x = 4) turned about the axis y = z = 0.5 over the first 60 steps. */
typedef struct twist {
  tb_mesh mesh;
  int nfixed, *fixed;
  tb_vec3 *at;
} twist;

static int twist_make(twist *w) {
  tb_error err;
  memset(w, 0, sizeof *w);
  if (tb_beam(4, 1, 1, 8, 2, 2, &w->mesh, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return -1;
  }
  w->fixed = malloc(sizeof(int) * (size_t)w->mesh.nv);
  w->at = malloc(sizeof(tb_vec3) * (size_t)w->mesh.nv);
  for (int i = 0; i < w->mesh.nv; i++)
    if (w->mesh.x[i].x < 1e-9 || w->mesh.x[i].x > 4 - 1e-9) w->fixed[w->nfixed++] = i;
  return 0;
}

static void twist_free(twist *w) {
  tb_mesh_free(&w->mesh);
  free(w->fixed), free(w->at);
}

/* Step k's input: the end turned min(k + 1, 60) / 60 of TURN. */
static tb_step twist_step(twist *w, int k) {
  double a = TURN * fmin(k + 1, 60) / 60.0;
  tb_mat3 r = tb_m3_rotation(tb_v3(1, 0, 0), a);
  for (int j = 0; j < w->nfixed; j++) {
    tb_vec3 x = w->mesh.x[w->fixed[j]];
    w->at[j] =
        x.x < 1e-9 ? x : tb_add(tb_m3_mulv(r, tb_sub(x, tb_v3(0, 0.5, 0.5))), tb_v3(0, 0.5, 0.5));
  }
  tb_step s;
  memset(&s, 0, sizeof s);
  s.dt = 0.01, s.gravity = tb_v3(0, 0, -9.81);
  s.nfixed = w->nfixed, s.fixed = w->fixed, s.fixed_x = w->at;
  return s;
}

/* Runs model with settings kvs for n steps; positions into x (nv), stats
 * into st (may be NULL). Returns 0 or -1 (checked). */
static int run(twist *w, const char *model, const char *kvs, int n, tb_vec3 *x, tb_fem_stats *st) {
  tb_settings d = tb_test_settings(kvs);
  tb_model m;
  tb_error err;
  if (tb_model_create(&m, model, &w->mesh, &d, &err)) {
    TB_CHECK_MSG(0, "%s %s: %s", model, kvs, err.msg);
    return -1;
  }
  int rc = 0;
  for (int k = 0; k < n && !rc; k++) {
    tb_step s = twist_step(w, k);
    rc = tb_model_step(&m, &s, &err);
    TB_CHECK_MSG(rc == 0, "%s %s step %d: %s", model, kvs, k, err.msg);
  }
  if (!rc) memcpy(x, tb_model_positions(&m), sizeof(tb_vec3) * (size_t)w->mesh.nv);
  if (!rc && st) rc = tb_fem_get_stats(&m, st, &err);
  tb_model_destroy(&m);
  return rc;
}

/* max |x - ref| / max |ref - X| */
static double rel_error(const twist *w, const tb_vec3 *x, const tb_vec3 *ref) {
  double d = 0, u = 0;
  for (int i = 0; i < w->mesh.nv; i++)
    d = fmax(d, tb_dist(x[i], ref[i])), u = fmax(u, tb_dist(ref[i], w->mesh.x[i]));
  return d / u;
}

/* pcg (the default; rotated or not, any cg_max) matches the exact path to 1e-6, after a
 * large dynamic twist and in the quasi-static solve. */
static void test_pcg_exact(void) {
  twist w;
  if (twist_make(&w)) return;
  int nv = w.mesh.nv;
  tb_vec3 *ref = malloc(sizeof(tb_vec3) * (size_t)nv), *x = malloc(sizeof(tb_vec3) * (size_t)nv);
  static const char *const dyn[] = {"", "solver=pcg cg_rotate=0",
                                    "solver=pcg cg_max=2 cg_tol=1e-10", "solver=pcg cg_warm=1"};
  for (int qs = 0; qs < 2; qs++) {
    char base[64];
    snprintf(base, sizeof base, "quasistatic=%d solver=exact", qs);
    int n = qs ? 70 : STEPS;
    if (run(&w, "fem-corot", base, n, ref, NULL)) break;
    snprintf(base, sizeof base, "quasistatic=%d", qs);
    double u = 0;
    for (int i = 0; i < nv; i++) u = fmax(u, tb_dist(ref[i], w.mesh.x[i]));
    TB_CHECK_MSG(u > 0.5, "the twist moves the beam by %g only", u);
    for (int v = 0; v < (int)(sizeof dyn / sizeof dyn[0]); v++) {
      char kvs[128];
      snprintf(kvs, sizeof kvs, "%s %s", base, dyn[v]);
      tb_fem_stats st;
      if (run(&w, "fem-corot", kvs, n, x, &st)) continue;
      double e = rel_error(&w, x, ref);
      printf("  %-50s error %.2g, %.2f iterations/step, %d factorisations\n", kvs, e,
             (double)st.iterations / n, st.factorizations);
      TB_CHECK_MSG(e <= 1e-6, "%s: error %.3g against exact", kvs, e);
      TB_CHECK_MSG(st.residual <= 1e-7, "%s: last residual %.3g", kvs, st.residual);
    }
  }
  free(ref), free(x);
  twist_free(&w);
}

/* pd: bounded error that falls with the iterations; lagged: small error. */
static void test_pd_error(void) {
  twist w;
  if (twist_make(&w)) return;
  int nv = w.mesh.nv;
  tb_vec3 *ref = malloc(sizeof(tb_vec3) * (size_t)nv), *x = malloc(sizeof(tb_vec3) * (size_t)nv);
  if (run(&w, "fem-corot", "solver=exact", STEPS, ref, NULL) == 0) {
    static const int iters[] = {1, 4, 16, 64};
    double prev = INFINITY;
    for (int k = 0; k < 4; k++) {
      char kvs[64];
      snprintf(kvs, sizeof kvs, "solver=pd pd_iters=%d", iters[k]);
      if (run(&w, "fem-corot", kvs, STEPS, x, NULL)) continue;
      double e = rel_error(&w, x, ref);
      printf("  pd, %2d iterations: error %.3g\n", iters[k], e);
      TB_CHECK_MSG(e < 0.5, "pd %d iterations: error %.3g", iters[k], e);
      TB_CHECK_MSG(e < prev, "pd %d iterations: error %.3g, not below %.3g", iters[k], e, prev);
      prev = e;
    }
    TB_CHECK_MSG(prev < 1e-3, "pd 64 iterations: error %.3g", prev);
    if (run(&w, "fem-corot", "solver=lagged", STEPS, x, NULL) == 0) {
      double e = rel_error(&w, x, ref);
      printf("  lagged (lag 10, refine 2): error %.3g\n", e);
      TB_CHECK_MSG(e < 1e-3, "lagged: error %.3g", e);
    }
  }
  free(ref), free(x);
  twist_free(&w);
}

/* Counters: exact factors every step, pd once, lagged every lag steps
 * (or more when refinement stalls), pcg rarely; iterations add up. */
static void test_counters(void) {
  twist w;
  if (twist_make(&w)) return;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)w.mesh.nv);
  tb_fem_stats st;
  int n = 40;
  if (run(&w, "fem-corot", "solver=exact", n, x, &st) == 0)
    TB_CHECK_MSG(st.factorizations == n && st.iterations == 0, "exact: %d factors, %ld iterations",
                 st.factorizations, st.iterations);
  if (run(&w, "fem-corot", "solver=pd pd_iters=3", n, x, &st) == 0)
    TB_CHECK_MSG(st.factorizations == 1 && st.iterations == 3 * n && st.solves == 3 * n,
                 "pd: %d factors, %ld iterations, %ld solves", st.factorizations, st.iterations,
                 st.solves);
  if (run(&w, "fem-corot", "solver=lagged lag=5 refine=1", n, x, &st) == 0)
    TB_CHECK_MSG(st.factorizations >= n / 5 && st.factorizations < n && st.iterations <= n,
                 "lagged: %d factors, %ld refinements", st.factorizations, st.iterations);
  int loose = -1;
  if (run(&w, "fem-corot", "solver=pcg", n, x, &st) == 0) {
    TB_CHECK_MSG(st.factorizations >= 1 && st.factorizations < n / 2 && st.iterations >= n,
                 "pcg: %d factors, %ld iterations", st.factorizations, st.iterations);
    TB_CHECK_MSG(st.last_iterations >= 1 && st.last_iterations <= 2 * 8 + 20,
                 "pcg: %d iterations in the last step", st.last_iterations);
    loose = st.factorizations;
  }
  /* one CG iteration allowed before refactoring: more factorisations */
  if (run(&w, "fem-corot", "solver=pcg cg_max=1 cg_tol=1e-12", n, x, &st) == 0)
    TB_CHECK_MSG(st.factorizations > loose, "pcg cg_max=1: %d factors (cg_max=8: %d)",
                 st.factorizations, loose);
  free(x);
  twist_free(&w);
}

/* pcg's warm start: while the end turns smoothly the extrapolation through
 * up to 6 past solutions picks a high order and saves CG iterations
 * against the line (2) and the last solution (1); once the end stops
 * (a kink in the motion) it falls back to a low order for a few steps. */
static void test_warm_start(void) {
  twist w;
  if (twist_make(&w)) return;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)w.mesh.nv);
  tb_fem_stats st;
  long it[7] = {0};
  int order = 0;
  for (int o = 1; o <= 6; o++) {
    char kvs[64];
    snprintf(kvs, sizeof kvs, "solver=pcg cg_rotate=0 cg_warm=%d", o);
    if (run(&w, "fem-corot", kvs, 58, x, &st)) break;
    it[o] = st.iterations;
    if (o == 6) order = st.warm_order;
    printf("  cg_warm=%d: %ld CG iterations in 58 steps, last order %d\n", o, it[o], st.warm_order);
    TB_CHECK_MSG(st.warm_order >= 1 && st.warm_order <= o, "cg_warm=%d: order %d", o,
                 st.warm_order);
  }
  TB_CHECK_MSG(it[6] < it[2] && it[2] < it[1], "iterations %ld (6), %ld (2), %ld (1)", it[6], it[2],
               it[1]);
  TB_CHECK_MSG(order >= 3, "smooth turn: order %d", order);
  /* steps are 0-based: the end last moves in step 59, rests from step 60;
   * step 62 is the first to choose its order by predictions across the
   * stop (of step 61 from 60, 59, ...); step 70 is 8 steps later */
  if (run(&w, "fem-corot", "solver=pcg cg_rotate=0", 62 + 1, x, &st) == 0)
    TB_CHECK_MSG(st.warm_order <= 2, "just after the stop: order %d", st.warm_order);
  if (run(&w, "fem-corot", "solver=pcg cg_rotate=0", 70 + 1, x, &st) == 0)
    TB_CHECK_MSG(st.warm_order >= 3, "10 steps after the stop: order %d", st.warm_order);
  free(x);
  twist_free(&w);
}

static void test_bad_settings(void) {
  static const char *const bad[] = {"solver=cg",  "solver=4",    "cg_tol=0",  "cg_tol=1",
                                    "cg_max=0",   "cg_rotate=2", "lag=0",     "refine=-1",
                                    "pd_iters=0", "cg_tol=abc",  "cg_warm=0", "cg_warm=7"};
  tb_mesh m;
  tb_error err;
  if (tb_beam(2, 1, 1, 2, 1, 1, &m, &err)) {
    TB_CHECK_MSG(0, "%s", err.msg);
    return;
  }
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    tb_settings d;
    tb_settings_init(&d);
    tb_model mod;
    if (tb_settings_set(&d, bad[k], &err)) continue; /* refused already: fine */
    int rc = tb_model_create(&mod, "fem-corot", &m, &d, &err);
    TB_CHECK_MSG(rc != 0, "fem-corot accepted %s", bad[k]);
    if (rc == 0)
      tb_model_destroy(&mod);
    else
      TB_CHECK_MSG(strstr(err.msg, bad[k]) || strstr(err.msg, "solver") || strstr(err.msg, "cg_") ||
                       strstr(err.msg, "lag") || strstr(err.msg, "refine") ||
                       strstr(err.msg, "pd_iters"),
                   "%s: error does not name the setting: %s", bad[k], err.msg);
  }
  tb_mesh_free(&m);
}

/* fem and every fem-corot solver: 1 and 2 threads give the same bits. */
static void test_threads(void) {
  twist w;
  if (twist_make(&w)) return;
  int nv = w.mesh.nv, threads = tb_threads();
  tb_vec3 *a = malloc(sizeof(tb_vec3) * (size_t)nv), *b = malloc(sizeof(tb_vec3) * (size_t)nv);
  static const struct {
    const char *model, *kvs;
  } runs[] = {{"fem", ""},
              {"fem", "quasistatic=1"},
              {"fem-corot", "solver=exact"},
              {"fem-corot", "solver=pcg"},
              {"fem-corot", "solver=pcg cg_rotate=0"},
              {"fem-corot", "solver=lagged"},
              {"fem-corot", "solver=pd"},
              {"fem-corot", "solver=pcg quasistatic=1"}};
  for (size_t k = 0; k < sizeof runs / sizeof runs[0]; k++) {
    tb_threads_set(1);
    int ra = run(&w, runs[k].model, runs[k].kvs, 30, a, NULL);
    tb_threads_set(2);
    int rb = run(&w, runs[k].model, runs[k].kvs, 30, b, NULL);
    if (ra || rb) continue;
    TB_CHECK_MSG(memcmp(a, b, sizeof(tb_vec3) * (size_t)nv) == 0,
                 "%s %s: positions differ between 1 and 2 threads", runs[k].model, runs[k].kvs);
  }
  tb_threads_set(threads);
  free(a), free(b);
  twist_free(&w);
}

/* tb_fem_polar_warm gives tb_m3_polar_newton's rotation (to rounding) from
 * starts near it (a step's turn), far from it (up to a half turn: a saddle
 * falls back) and for inverted F (falls back), and leaves q at it. */
static void test_polar_warm(void) {
  srand(7);
  double worst = 0, qworst = 0;
  for (int k = 0; k < 3000; k++) {
    tb_mat3 a;
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) a.m[i][j] = (i == j) + 0.8 * (rand() / (double)RAND_MAX - 0.5);
    if (k % 10 == 0) a.m[0][0] = a.m[0][1] = a.m[0][2] = 0, a.m[0][k % 3] = -1; /* inverted */
    tb_vec3 ax = tb_normalize(tb_v3(rand() % 7 - 3.1, rand() % 5 - 2.1, 1));
    tb_mat3 f = tb_m3_mul(tb_m3_rotation(ax, 6.0 * rand() / (double)RAND_MAX), a);
    tb_mat3 want = tb_m3_polar_newton(f);
    double turn = k % 3 == 0 ? 1e-3 : k % 3 == 1 ? 0.1 : 3.1 * rand() / (double)RAND_MAX;
    tb_mat3 start = tb_m3_mul(want, tb_m3_rotation(tb_normalize(tb_v3(1, -2, 3)), turn));
    /* the start as a quaternion: from the axis-angle of start (w = cos(h)) */
    double tr = start.m[0][0] + start.m[1][1] + start.m[2][2], q[4];
    q[0] = 0.5 * sqrt(fmax(1 + tr, 1e-30));
    q[1] = (start.m[2][1] - start.m[1][2]) / (4 * q[0]);
    q[2] = (start.m[0][2] - start.m[2][0]) / (4 * q[0]);
    q[3] = (start.m[1][0] - start.m[0][1]) / (4 * q[0]);
    tb_mat3 got = tb_fem_polar_warm(f, q), back = tb_fem_polar_warm(f, q);
    for (int i = 0; i < 3; i++)
      for (int j = 0; j < 3; j++) {
        worst = fmax(worst, fabs(got.m[i][j] - want.m[i][j]));
        qworst = fmax(qworst, fabs(back.m[i][j] - want.m[i][j]));
      }
  }
  printf("  largest entry difference to tb_m3_polar_newton %.2g, restarted from its q %.2g\n",
         worst, qworst);
  TB_CHECK(worst < 1e-12);
  TB_CHECK(qworst < 1e-12);
}

const tb_test_case tb_tests_fem_corot[] = {
    {"polar_warm", test_polar_warm}, {"pcg_exact", test_pcg_exact},
    {"pd_error", test_pd_error},     {"counters", test_counters},
    {"warm_start", test_warm_start}, {"bad_settings", test_bad_settings},
    {"threads", test_threads},       {0, 0},
};
