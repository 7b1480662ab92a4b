/* Thesis fig. 3.10 (§3.4.5): shape-matching time per frame against the
 * number of particles, for 1, 8 and 50 clusters, linear and quadratic.
 * As in the thesis, particles get random rest positions (a cube) and random
 * current positions (the rest perturbed); a frame is one step of the sm
 * model. The thesis found time linear in particles, growing with clusters
 * and from linear to quadratic, and "100 objects of 100 particles, 8
 * clusters, quadratic: 50 fps"; both are measured here. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_rng.h"
#include "core/tb_timer.h"
#include "models/tb_sm.h"
#include "report/tb_results.h"

#define SIDE 10.0

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

/* Median ms per frame of `frames` steps of `count` models (each of the
 * cloud m, perturbed), or -1 with err. */
static double time_frames(const tb_mesh *m, int count, const tb_settings *d, int frames, tb_rng *r,
                          tb_error *err) {
  tb_model *models = calloc((size_t)count, sizeof *models);
  tb_vec3 *fx = malloc(sizeof(tb_vec3) * (size_t)m->nv);
  int *fi = malloc(sizeof(int) * (size_t)m->nv);
  double *ms = malloc(sizeof(double) * (size_t)frames), med = -1;
  if (!models || !fx || !fi || !ms) {
    tb_error_set(err, "figure 3.10", 0, "out of memory");
    goto done;
  }
  int made = 0;
  for (; made < count; made++)
    if (tb_model_create(&models[made], "sm", m, d, err)) goto done;
  /* first step: every particle prescribed to its random current position */
  for (int i = 0; i < m->nv; i++) {
    fi[i] = i;
    fx[i] = tb_madd(m->x[i], 0.2 * SIDE,
                    tb_v3(tb_rng_range(r, -1, 1), tb_rng_range(r, -1, 1), tb_rng_range(r, -1, 1)));
  }
  tb_step in = {0};
  memset(&in, 0, sizeof in);
  in.dt = 0.01;
  in.nfixed = m->nv, in.fixed = fi, in.fixed_x = fx;
  for (int k = 0; k < count; k++)
    if (tb_model_step(&models[k], &in, err)) goto done;
  in.nfixed = 0;
  for (int f = 0; f < frames; f++) {
    uint64_t t0 = tb_time_ns();
    for (int k = 0; k < count; k++)
      if (tb_model_step(&models[k], &in, err)) goto done;
    ms[f] = (double)(tb_time_ns() - t0) * 1e-6;
  }
  med = tb_stats_of(ms, frames).median;
done:
  for (int k = 0; models && k < count; k++) tb_model_destroy(&models[k]);
  free(models), free(fx), free(fi), free(ms);
  return med;
}

int tb_suite_fig310(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/figure-3.10", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(dir, "figure-3.10",
                               "Thesis fig. 3.10: shape-matching time per frame", o->seed, &err);
  if (!s) return fprintf(stderr, "figure 3.10: %s\n", err.msg), 1;
  static const int sizes_full[] = {500, 1000, 2000, 4000, 6000, 8000, 10000, 15000, 20000};
  static const int sizes_quick[] = {500, 1000, 2500, 5000, 7500, 10000};
  static const int sizes_smoke[] = {200, 400};
  const int *sizes = o->scale < 1 ? sizes_smoke : (o->full ? sizes_full : sizes_quick);
  int nsizes = o->scale < 1 ? 2 : (o->full ? 9 : 6), frames = o->full ? 301 : 101, failed = 0;
  static const int clusters[] = {1, 8, 50};
  static const char *cols[] = {"particles",        "1 linear (ms)",    "8 linear (ms)",
                               "50 linear (ms)",   "1 quadratic (ms)", "8 quadratic (ms)",
                               "50 quadratic (ms)"};
  tb_table *t = tb_table_new("frame", "Time per frame (median ms) against particles", 7, cols);
  double ms[16][6], slope[6] = {0}, icept[6] = {0};
  size_t cap = 4096, len = 0;
  char *body = malloc(cap);
  tb_rng rng = tb_rng_seed(o->seed);
  for (int i = 0; i < nsizes && !failed; i++) {
    tb_progress("figure 3.10", i, nsizes);
    tb_mesh m;
    if (cloud(sizes[i], &rng, &m)) failed = 1;
    tb_table_row(t);
    tb_table_cell(t, "%d", sizes[i]);
    for (int v = 0; v < 6 && !failed; v++) {
      tb_settings d = sm_def(clusters[v % 3], v < 3 ? "sm_mode=linear" : "sm_mode=quadratic");
      ms[i][v] = time_frames(&m, 1, &d, frames, &rng, &err);
      if (ms[i][v] < 0) {
        fprintf(stderr, "figure 3.10: %s\n", err.msg);
        failed = 1;
      }
      tb_table_cell(t, "%.4f", ms[i][v]);
      char bname[96]; /* the median of the frames, one repetition */
      snprintf(bname, sizeof bname, "sm/clusters:%d/%s/particles:%d", clusters[v % 3],
               v < 3 ? "linear" : "quadratic", sizes[i]);
      if (!failed) tb_suite_bench(s, bname, &ms[i][v], NULL, 1, "ms");
    }
    tb_mesh_free(&m);
    if (body && !failed) {
      len += (size_t)snprintf(body + len, cap - len, "%d", sizes[i]);
      for (int v = 0; v < 6; v++) len += (size_t)snprintf(body + len, cap - len, ",%.6g", ms[i][v]);
      len += (size_t)snprintf(body + len, cap - len, "\n");
    }
  }
  tb_progress("figure 3.10", nsizes, nsizes);
  tb_suite_table(s, t);
  if (!failed) {
    /* linearity: least-squares line through each series, R^2 and the slope */
    static const char *lc[] = {"variant", "us per particle (slope)", "R^2 of a line",
                               "time(largest) / time(smallest)", "particles ratio"};
    tb_table *lt = tb_table_new("linearity", "Time per frame is linear in particles", 5, lc);
    for (int v = 0; v < 6; v++) {
      double sx = 0, sy = 0, sxx = 0, sxy = 0, syy = 0, n = nsizes;
      for (int i = 0; i < nsizes; i++) {
        double x = sizes[i], y = ms[i][v];
        sx += x, sy += y, sxx += x * x, sxy += x * y, syy += y * y;
      }
      double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
      slope[v] = b, icept[v] = (sy - b * sx) / n;
      double r = (n * sxy - sx * sy) / sqrt((n * sxx - sx * sx) * (n * syy - sy * sy));
      tb_table_row(lt);
      tb_table_cell(lt, "%d clusters, %s", clusters[v % 3], v < 3 ? "linear" : "quadratic");
      tb_table_cell(lt, "%.4f", 1e3 * b);
      tb_table_cell(lt, "%.4f", r * r);
      tb_table_cell(lt, "%.1f", ms[nsizes - 1][v] / ms[0][v]);
      tb_table_cell(lt, "%.1f", (double)sizes[nsizes - 1] / sizes[0]);
      char bname[96];
      snprintf(bname, sizeof bname, "linearity/clusters:%d/%s", clusters[v % 3],
               v < 3 ? "linear" : "quadratic");
      tb_suite_counter(s, bname, "us_per_particle", 1e3 * b);
      tb_suite_counter(s, bname, "r_squared", r * r);
    }
    tb_suite_table(s, lt);
  }
  /* the thesis's 100 objects x 100 particles, 8 clusters, quadratic */
  if (!failed) {
    tb_mesh m;
    if (cloud(100, &rng, &m)) failed = 1;
    tb_settings d = sm_def(8, "sm_mode=quadratic");
    double f = failed ? -1 : time_frames(&m, 100, &d, frames, &rng, &err);
    if (!failed) tb_mesh_free(&m);
    static const char *oc[] = {"case", "frames/s (ours)", "thesis fps", "ours / thesis"};
    tb_table *ot =
        tb_table_new("objects", "100 objects x 100 particles, 8 clusters, quadratic", 4, oc);
    tb_table_row(ot);
    tb_table_cell(ot, "100 x 100, 8 clusters, quadratic");
    if (f > 0) {
      tb_table_cell(ot, "%.0f", 1e3 / f);
      tb_table_cell(ot, "50");
      tb_table_num(ot, 1e3 / f / 50, "%.0fx");
      tb_suite_bench(s, "objects/100x100/clusters:8/quadratic", &f, NULL, 1, "ms");
      tb_suite_counter(s, "objects/100x100/clusters:8/quadratic", "frames_per_s", 1e3 / f);
    } else {
      fprintf(stderr, "figure 3.10: %s\n", err.msg);
      failed = 1;
    }
    tb_suite_table(s, ot);
  }
  tb_suite_note(s,
                "Random clouds in a %g-cube (seeded), every particle first moved to a random "
                "position up to %g away, then %d frames timed (one sm step each, dt 0.01); "
                "regions of radius 0.6 * side / clusters^(1/3), particles outside every region "
                "join the nearest. The thesis's figure (i3-2100) gives no numbers to set beside "
                "these, only its shape: linear in particles, costlier with more clusters and with "
                "quadratic; and 50 fps for 100 objects x 100 particles.",
                SIDE, 0.2 * SIDE, frames);
  /* the least-squares lines of the linearity table, at the smallest and largest sizes */
  char fit[512];
  int flen = 0;
  for (int e = 0; e < 2; e++) {
    double x = sizes[e ? nsizes - 1 : 0];
    flen += snprintf(fit + flen, sizeof fit - (size_t)flen, "%g", x);
    for (int v = 0; v < 6; v++)
      flen += snprintf(fit + flen, sizeof fit - (size_t)flen, ",%.6g", icept[v] + slope[v] * x);
    flen += snprintf(fit + flen, sizeof fit - (size_t)flen, "\n");
  }
  static const char *fig_header =
      "particles,1 linear,8 linear,50 linear,1 quadratic,"
      "8 quadratic,50 quadratic";
  if (!failed && body &&
      (tb_suite_write_data(s, "fig310.csv", fig_header, body, &err) ||
       tb_suite_write_data(s, "fig310_fit.csv", fig_header, fit, &err) ||
       tb_suite_chart_vars(s, "chart_lines.gp", "fig310.csv", "fig310",
                           "title='Shape matching: time per frame (thesis fig. 3.10), clusters "
                           "and mode per series'; xlabel='particles (count)'; "
                           "ylabel='time per frame (ms)'; fitfile='fig310_fit.csv'",
                           &err))) {
    fprintf(stderr, "figure 3.10: %s\n", err.msg);
    failed = 1;
  } else if (!failed && body)
    tb_suite_caption(s, "fig310",
                     "Shape matching: milliseconds per frame against the number of particles, "
                     "for 1, 8 and 50 clusters, linear and quadratic (thesis fig. 3.10)");
  free(body);
  if (tb_suite_end(s, &err)) fprintf(stderr, "figure 3.10: %s\n", err.msg), failed = 1;
  return failed;
}
