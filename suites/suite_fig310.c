/* Thesis fig. 3.10 (§3.4.5): shape-matching time per frame against the
 * number of particles, for 1, 8 and 50 clusters, linear and quadratic.
 * As in the thesis, particles get random rest positions (a cube) and random
 * current positions (the rest perturbed); a frame is one step of the sm
 * model. The thesis found time linear in particles, growing with clusters
 * and from linear to quadratic, and "100 objects of 100 particles, 8
 * clusters, quadratic: 50 fps"; both are measured here, in CPU time on
 * one thread, every series' repetitions taking turns (size by size,
 * variant by variant, then again) so that a slow spell of the machine falls
 * on all of them alike. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "models/tb_sm.h"
#include "report/tb_results.h"

#define SIDE 10.0
#define MAX_SIZES 16
#define NVAR 6 /* 1, 8, 50 clusters, linear then quadratic */
#define MAX_REPS 9

/* A point cloud of n particles: rest positions uniform in the cube. */
static int cloud(int n, tb_rng *r, tb_mesh *m) {
  memset(m, 0, sizeof *m);
  m->x = malloc(sizeof(tb_vec3) * (size_t)n);
  if (!m->x) return -1;
  m->nv = n;
  for (int i = 0; i < n; i++)
    m->x[i] = tb_v3(tb_rng_range(r, 0, SIDE), tb_rng_range(r, 0, SIDE), tb_rng_range(r, 0, SIDE));
  return 0;
}

static tb_settings sm_def(int clusters, const char *mode) {
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_setd(&d, "node_mass", 1, NULL);
  tb_settings_setd(&d, "clusters", clusters, NULL);
  tb_settings_set(&d, mode, NULL);
  tb_settings_setd(&d, "radius", 0.6 * SIDE / cbrt((double)clusters), NULL); /* overlapping */
  return d;
}

/* Median CPU and wall ms per frame of `frames` steps of `count` models
 * (each of the cloud m, perturbed by the numbers of seed) into *cpu and
 * *wall; returns 0, or -1 with err. */
static int time_frames(const tb_mesh *m, int count, const tb_settings *d, int frames, uint64_t seed,
                       double *cpu, double *wall, tb_error *err) {
  tb_model *models = calloc((size_t)count, sizeof *models);
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)m->nv);
  int *fi = malloc(sizeof(int) * (size_t)m->nv), made = 0, rc = -1;
  double *ms = malloc(sizeof(double) * 2 * (size_t)frames), *wms = ms ? ms + frames : NULL;
  tb_rng r = tb_rng_seed(seed);
  if (!models || !fx || !fi || !ms) {
    tb_error_set(err, "figure 3.10", 0, "out of memory");
    goto done;
  }
  for (; made < count; made++)
    if (tb_model_create(&models[made], "sm", m, d, err)) goto done;
  /* first step: every particle prescribed to its random current position */
  for (int i = 0; i < m->nv; i++) {
    fi[i] = i;
    fx[i] =
        tb_madd(m->x[i], 0.2 * SIDE,
                tb_v3(tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1), tb_rng_range(&r, -1, 1)));
  }
  tb_step in = {0};
  memset(&in, 0, sizeof in);
  in.dt = 0.01;
  in.nfixed = m->nv, in.fixed = fi, in.fixed_x = fx;
  for (int k = 0; k < count; k++)
    if (tb_model_step(&models[k], &in, err)) goto done;
  in.nfixed = 0;
  for (int f = 0; f < frames; f++) {
    tb_clock c = tb_clock_start();
    for (int k = 0; k < count; k++)
      if (tb_model_step(&models[k], &in, err)) goto done;
    tb_clock_ms(&c, &wms[f], &ms[f]);
  }
  *cpu = tb_stats_of(ms, frames).median, *wall = tb_stats_of(wms, frames).median;
  rc = 0;
done:
  for (int k = 0; k < made; k++) tb_model_destroy(&models[k]);
  free(models), free(fx), free(fi), free(ms);
  return rc;
}

static const int clusters[] = {1, 8, 50};

static void variant_name(int v, char *buf, size_t cap) {
  snprintf(buf, cap, "%d cluster%s, %s", clusters[v % 3], clusters[v % 3] == 1 ? "" : "s",
           v < 3 ? "linear" : "quadratic");
}

/* The series' time per frame (median over repetitions of each
 * repetition's median frame), CPU or wall, one row per size. */
static tb_table *frame_table(const char *name, const char *title, const int *sizes, int nsizes,
                             double (*x)[NVAR][MAX_REPS], int reps, const char *what) {
  char heads[NVAR + 1][64];
  const char *cols[NVAR + 1];
  snprintf(heads[0], sizeof heads[0], "particles");
  for (int v = 0; v < NVAR; v++)
    snprintf(heads[v + 1], sizeof heads[v + 1], "%d %s %s (ms)", clusters[v % 3],
             v < 3 ? "linear" : "quadratic", what);
  for (int c = 0; c <= NVAR; c++) cols[c] = heads[c];
  tb_table *t = tb_table_new(name, title, NVAR + 1, cols);
  for (int i = 0; i < nsizes; i++) {
    tb_table_row(t);
    tb_table_num(t, sizes[i], "%.0f");
    for (int v = 0; v < NVAR; v++) tb_table_num(t, tb_median_est(x[i][v], reps).value, "%.4f");
  }
  return t;
}

static int fig310(tb_suite *s, const tb_suite_opts *o) {
  static const int sizes_full[] = {500, 1000, 2000, 4000, 6000, 8000, 10000, 15000, 20000};
  static const int sizes_quick[] = {500, 1000, 2500, 5000, 7500, 10000};
  static const int sizes_smoke[] = {200, 400};
  const int *sizes = o->scale < 1 ? sizes_smoke : (o->full ? sizes_full : sizes_quick);
  int nsizes = o->scale < 1 ? 2 : (o->full ? 9 : 6), failed = 0;
  /* repetitions of every series, each `frames` frames long */
  int reps = o->scale < 1 ? 1 : (o->full ? MAX_REPS : TB_EST_MIN);
  int frames = o->full ? 301 : 101;
  tb_error err;
  /* per size, variant and repetition: CPU and wall ms per frame */
  static double cpu[MAX_SIZES][NVAR][MAX_REPS], wall[MAX_SIZES][NVAR][MAX_REPS];
  double obj_cpu[MAX_REPS], obj_wall[MAX_REPS]; /* the 100 objects */
  double med[MAX_SIZES][NVAR], slope[NVAR] = {0}, icept[NVAR] = {0};
  tb_mesh clouds[MAX_SIZES + 1];
  memset(clouds, 0, sizeof clouds);
  tb_rng rng = tb_rng_seed(o->seed);
  for (int i = 0; i <= nsizes && !failed; i++) /* clouds[nsizes]: an object of 100 */
    if (cloud(i < nsizes ? sizes[i] : 100, &rng, &clouds[i])) failed = 1;
  if (failed) tb_error_set(&err, "figure 3.10", 0, "out of memory");
  const uint64_t seed = tb_rng_next(&rng); /* the perturbations, the same in every repetition */
  for (int r = 0; r < reps && !failed; r++)
    for (int i = 0; i <= nsizes && !failed; i++) {
      tb_progress("figure 3.10", r * (nsizes + 1) + i, reps * (nsizes + 1));
      if (i == nsizes) { /* the thesis's 100 objects x 100 particles, 8 clusters, quadratic */
        tb_settings d = sm_def(8, "sm_mode=quadratic");
        failed = time_frames(&clouds[i], 100, &d, frames, seed + 1000, &obj_cpu[r], &obj_wall[r],
                             &err) != 0;
        continue;
      }
      for (int v = 0; v < NVAR && !failed; v++) {
        tb_settings d = sm_def(clusters[v % 3], v < 3 ? "sm_mode=linear" : "sm_mode=quadratic");
        failed = time_frames(&clouds[i], 1, &d, frames, seed + (uint64_t)(NVAR * i + v),
                             &cpu[i][v][r], &wall[i][v][r], &err) != 0;
      }
    }
  tb_progress("figure 3.10", reps * (nsizes + 1), reps * (nsizes + 1));
  for (int i = 0; i <= nsizes; i++) tb_mesh_free(&clouds[i]);
  if (failed) {
    fprintf(stderr, "figure 3.10: %s\n", err.msg);
    tb_suite_note(s, "The figure could not be measured: %s", err.msg);
    return 1;
  }
  for (int i = 0; i < nsizes; i++)
    for (int v = 0; v < NVAR; v++) {
      med[i][v] = tb_median_est(cpu[i][v], reps).value;
      char bname[96]; /* each repetition's median frame */
      snprintf(bname, sizeof bname, "sm/clusters:%d/%s/particles:%d", clusters[v % 3],
               v < 3 ? "linear" : "quadratic", sizes[i]);
      tb_suite_bench(s, bname, wall[i][v], cpu[i][v], reps, "ms");
    }
  tb_suite_table(s, frame_table("frame",
                                "Time per frame against particles: CPU time, one thread (median "
                                "ms over the repetitions)",
                                sizes, nsizes, cpu, reps, "CPU"));
  tb_suite_table(s, frame_table("frame_wall", "The same in wall time (median ms)", sizes, nsizes,
                                wall, reps, "wall"));
  /* linearity: least-squares line through each series' medians, R^2 and the slope */
  static const char *lc[] = {"variant",        "us per particle (slope, CPU)",
                             "R^2 of a line",  "time(largest) / time(smallest)",
                             "ratio low",      "ratio high",
                             "particles ratio"};
  tb_table *lt = tb_table_new("linearity",
                              "Least-squares line of CPU time per frame against particles", 7, lc);
  tb_table_csv_name(lt, 3, "time(largest) / time(smallest) (median of paired repetitions)");
  tb_table_only(lt, 4, TB_CSV_ONLY), tb_table_only(lt, 5, TB_CSV_ONLY);
  for (int v = 0; v < NVAR; v++) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0, n = nsizes;
    for (int i = 0; i < nsizes; i++) {
      double x = sizes[i], y = med[i][v];
      sx += x, sy += y, sxx += x * x, sxy += x * y, syy += y * y;
    }
    double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
    slope[v] = b, icept[v] = (sy - b * sx) / n;
    double rr = (n * sxy - sx * sy) / sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
    tb_est grow = tb_ratio_est(cpu[nsizes - 1][v], cpu[0][v], reps);
    char name[64];
    variant_name(v, name, sizeof name);
    tb_table_row(lt);
    tb_table_cell(lt, "%s", name);
    tb_table_num(lt, 1e3 * b, "%.4f");
    tb_table_num(lt, rr * rr, "%.4f");
    tb_table_est(lt, grow, "%.1f", "");
    tb_table_num(lt, grow.lo, "%.1f"), tb_table_num(lt, grow.hi, "%.1f");
    tb_table_num(lt, (double)sizes[nsizes - 1] / sizes[0], "%.1f");
    char bname[96];
    snprintf(bname, sizeof bname, "linearity/clusters:%d/%s", clusters[v % 3],
             v < 3 ? "linear" : "quadratic");
    tb_suite_counter(s, bname, "us_per_particle", 1e3 * b);
    tb_suite_counter(s, bname, "r_squared", rr * rr);
    tb_suite_counter(s, bname, "largest_over_smallest", grow.value);
    tb_suite_counter(s, bname, "ratio_low", grow.lo);
    tb_suite_counter(s, bname, "ratio_high", grow.hi);
  }
  tb_suite_table(s, lt);
  /* the thesis's shape: costlier with more clusters and from linear to quadratic, at the
   * largest size, each a ratio of repetitions that took turns */
  static const struct {
    int a, b; /* variant a over variant b */
  } pairs[] = {{1, 0}, {2, 1}, {4, 3}, {5, 4}, {3, 0}, {4, 1}, {5, 2}};
  static const char *sc[] = {"comparison", "particles",  "CPU time ratio",
                             "ratio low",  "ratio high", "costlier (ratio >= 1)"};
  char stitle[160];
  snprintf(stitle, sizeof stitle,
           "The thesis's shape at %d particles: CPU time per frame of one series over another",
           sizes[nsizes - 1]);
  tb_table *st = tb_table_new("shape", stitle, 6, sc);
  tb_table_csv_name(st, 2, "CPU time ratio (median of paired repetitions)");
  tb_table_only(st, 3, TB_CSV_ONLY), tb_table_only(st, 4, TB_CSV_ONLY);
  int nmet = 0, nnot = 0;
  for (size_t k = 0; k < sizeof pairs / sizeof pairs[0]; k++) {
    char a[64], b[64], verdict[200];
    variant_name(pairs[k].a, a, sizeof a), variant_name(pairs[k].b, b, sizeof b);
    tb_est e = tb_ratio_est(cpu[nsizes - 1][pairs[k].a], cpu[nsizes - 1][pairs[k].b], reps);
    int vd = tb_verdict(e, 1, 1);
    nmet += vd == TB_MET, nnot += vd == TB_NOT_MET;
    tb_table_row(st);
    tb_table_cell(st, "%s / %s", a, b);
    tb_table_num(st, sizes[nsizes - 1], "%.0f");
    tb_table_est(st, e, "%.3g", "");
    tb_table_num(st, e.lo, "%.3g"), tb_table_num(st, e.hi, "%.3g");
    tb_table_cell(st, "%s", tb_verdict_text(e, 1, 1, verdict, sizeof verdict));
    char bname[160];
    snprintf(bname, sizeof bname, "shape/clusters:%d/%s/over/clusters:%d/%s",
             clusters[pairs[k].a % 3], pairs[k].a < 3 ? "linear" : "quadratic",
             clusters[pairs[k].b % 3], pairs[k].b < 3 ? "linear" : "quadratic");
    tb_suite_counter_est(s, bname, "ratio", e);
  }
  tb_suite_table(s, st);
  /* the 100 objects beside the thesis's 50 fps: a ratio to a published figure */
  tb_est oc = tb_median_est(obj_cpu, reps), ow = tb_median_est(obj_wall, reps);
  static const char *ocols[] = {"case", "frames/s CPU (ours, median)",
                                "frames/s wall (ours, median)", "thesis fps",
                                "ours / thesis (CPU)"};
  tb_table *ot =
      tb_table_new("objects", "100 objects x 100 particles, 8 clusters, quadratic", 5, ocols);
  tb_table_row(ot);
  tb_table_cell(ot, "100 x 100, 8 clusters, quadratic");
  tb_table_num(ot, 1e3 / oc.value, "%.0f");
  tb_table_num(ot, 1e3 / ow.value, "%.0f");
  tb_table_num(ot, 50, "%.0f");
  tb_table_num(ot, 1e3 / oc.value / 50, "%.1fx");
  tb_suite_table(s, ot);
  tb_suite_bench(s, "objects/100x100/clusters:8/quadratic", obj_wall, obj_cpu, reps, "ms");
  tb_suite_counter(s, "objects/100x100/clusters:8/quadratic", "frames_per_s", 1e3 / oc.value);
  tb_suite_note(s,
                "Random clouds in a %g-cube (seeded), every particle first moved to a random "
                "position up to %g away, then %d frames timed (one sm step each, dt 0.01), the "
                "median frame kept; %d repetition(s) of every series, taking turns size by size "
                "and series by series (the 100 objects among them), on one thread; times are "
                "CPU time (other processes on the machine do not enter them), wall time in its "
                "own table; each figure is the median over the repetitions, each ratio the "
                "median of the repetitions' paired ratios with its 95%% interval (a verdict is "
                "inconclusive below %d repetitions or when the interval holds 1). Regions of "
                "radius 0.6 * side / clusters^(1/3), particles outside every region join the "
                "nearest. The thesis's figure (i3-2100) gives no numbers to set beside these, "
                "only its shape: linear in particles (the R^2 of a line), costlier with more "
                "clusters and with quadratic (the ratios at %d particles: %d met, %d not met, "
                "%d inconclusive); and 50 fps for 100 objects x 100 particles. `ours / thesis` "
                "is our median CPU frames/s over that published figure, a ratio of machines and "
                "programs (the thesis's with rendering), not a comparison measured in one run.",
                SIDE, 0.2 * SIDE, frames, reps, TB_EST_MIN, sizes[nsizes - 1], nmet, nnot,
                (int)(sizeof pairs / sizeof pairs[0]) - nmet - nnot);
  /* the series' medians, and the least-squares lines at the smallest and largest sizes */
  size_t cap = 4096, len = 0;
  char body[4096], fit[512];
  body[0] = 0;
  for (int i = 0; i < nsizes; i++) {
    len += (size_t)snprintf(body + len, cap - len, "%d", sizes[i]);
    for (int v = 0; v < NVAR; v++)
      len += (size_t)snprintf(body + len, cap - len, ",%.6g", med[i][v]);
    len += (size_t)snprintf(body + len, cap - len, "\n");
  }
  int flen = 0;
  for (int e = 0; e < 2; e++) {
    double x = sizes[e ? nsizes - 1 : 0];
    flen += snprintf(fit + flen, sizeof fit - (size_t)flen, "%g", x);
    for (int v = 0; v < NVAR; v++)
      flen += snprintf(fit + flen, sizeof fit - (size_t)flen, ",%.6g", icept[v] + slope[v] * x);
    flen += snprintf(fit + flen, sizeof fit - (size_t)flen, "\n");
  }
  static const char *fig_header =
      "particles,1 linear,8 linear,50 linear,1 quadratic,"
      "8 quadratic,50 quadratic";
  if (tb_suite_write_data(s, "fig310.csv", fig_header, body, &err) ||
      tb_suite_write_data(s, "fig310_fit.csv", fig_header, fit, &err) ||
      tb_suite_chart_vars(s, "chart_lines.gp", "fig310.csv", "fig310",
                          "title='Shape matching: time per frame (thesis fig. 3.10), clusters "
                          "and mode per series'; xlabel='particles (count)'; "
                          "ylabel='CPU time per frame (ms, one thread)'; fitfile='fig310_fit.csv'",
                          &err)) {
    fprintf(stderr, "figure 3.10: %s\n", err.msg);
    return 1;
  }
  tb_suite_caption(s, "fig310",
                   "Shape matching: CPU milliseconds per frame (one thread) against the number of "
                   "particles, for 1, 8 and 50 clusters, linear and quadratic (thesis fig. 3.10)");
  return 0;
}

int tb_suite_fig310(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/figure-3.10", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(dir, "figure-3.10",
                               "Thesis fig. 3.10: shape-matching time per frame", o->seed, &err);
  if (!s) return fprintf(stderr, "figure 3.10: %s\n", err.msg), 1;
  /* a comparison of variants, not of threads: one thread, CPU time */
  int threads = tb_threads_setting();
  tb_threads_set(1);
  int failed = fig310(s, o);
  tb_threads_set(threads);
  if (tb_suite_end(s, &err)) fprintf(stderr, "figure 3.10: %s\n", err.msg), failed = 1;
  return failed;
}
