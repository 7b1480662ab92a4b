/* The scaling suite's tables, notes and log-log charts (the measurements:
 * suites/suite_scaling.c). Exponents are least-squares lines through
 * log10(CPU ms, one thread) against log10(size) over the sizes a model ran
 * healthy on; the
 * interactive limits are where those lines reach 33.3 ms (30 Hz) and
 * 3.33 ms (300 Hz), marked "extrapolated" outside the sizes measured. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scaling_priv.h"
#include "models/tb_model.h"

/* The thread runs' speed goals: the model on 2 threads at least this many
 * times its one-thread speed (wall time) at about this many tets. */
static const struct {
  const char *model;
  int tets;
  double speedup;
} thread_goals[] = {{"pbd-stvk", 12800, 1.8},  {"msm", 12800, 1.8},  {"sm", 12800, 1.8},
                    {"pbd-stvk", 100000, 1.9}, {"msm", 100000, 1.9}, {"sm", 100000, 1.9}};

/* The core counts a prediction is given for. */
static const int predicted[] = {4, 8, 16};

double tb_scaling_predict(const thread_cell *t, int n, double *e) {
  *e = NAN;
  int q = t->ncounts - 1;
  if (!t->ok || q < 1 || t->count[q] < 2 || !(t->speedup[q].value > 0)) return NAN;
  double p = t->count[q], s = t->speedup[q].value;
  *e = fmax(0, (1 / s - 1 / p) / (1 - 1 / p)); /* superlinear: no serial share */
  if (*e >= 1) return NAN;                     /* no gain measured: nothing to extrapolate */
  return 1 / (*e + (1 - *e) / n);
}

/* A least-squares line log10(y) = a + b log10(x). */
typedef struct fit {
  int n;
  double a, b, xlo, xhi;
} fit;

static fit fit_loglog(int n, const double *x, const double *y) {
  fit f = {0, NAN, NAN, INFINITY, -INFINITY};
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (int k = 0; k < n; k++) {
    if (!(x[k] > 0) || !(y[k] > 0) || !isfinite(y[k])) continue;
    double lx = log10(x[k]), ly = log10(y[k]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly, f.n++;
    f.xlo = fmin(f.xlo, x[k]), f.xhi = fmax(f.xhi, x[k]);
  }
  double d = f.n * sxx - sx * sx;
  if (f.n < 2 || !(d > 0)) return f;
  f.b = (f.n * sxy - sx * sy) / d;
  f.a = (sy - f.b * sx) / f.n;
  return f;
}

static double fit_y(fit f, double x) { return pow(10, f.a + f.b * log10(x)); }
/* The x where the line reaches y (NAN when it does not rise). */
static double fit_x(fit f, double y) { return f.b > 0 ? pow(10, (log10(y) - f.a) / f.b) : NAN; }

/* A model's line through its healthy sizes. */
static fit model_fit(const scaling_run *sr, int k) {
  double x[SCALING_MAX_SIZES], y[SCALING_MAX_SIZES];
  for (int r = 0; r < sr->nsizes; r++) {
    x[r] = sr->rows[r].ntet;
    y[r] = sr->rows[r].ok && sr->cells[k][r].ok ? sr->cells[k][r].ms : NAN;
  }
  return fit_loglog(sr->nsizes, x, y);
}

/* what: 0 refit, 1 query, 2 both; against triangles. */
static fit collision_fit(const scaling_run *sr, int what) {
  double x[SCALING_MAX_SIZES], y[SCALING_MAX_SIZES];
  for (int r = 0; r < sr->nsizes; r++) {
    const size_row *w = &sr->rows[r];
    x[r] = w->ntri;
    y[r] = !w->ok      ? NAN
           : what == 0 ? w->refit_ms
           : what == 1 ? w->query_ms
                       : w->refit_ms + w->query_ms;
  }
  return fit_loglog(sr->nsizes, x, y);
}

/* The interactive limit cell: the x on the line, "extrapolated" outside the
 * sizes measured. */
static void limit_cell(tb_table *t, fit f, double ms) {
  double x = fit_x(f, ms);
  if (!isfinite(x)) {
    tb_table_cell(t, "-");
    return;
  }
  if (x > 100 * f.xhi)
    tb_table_numf(t, x, "> 100x the largest (extrapolated: %.2g)", x);
  else
    tb_table_numf(t, x, "%.0f%s", x, x < f.xlo || x > f.xhi ? " (extrapolated)" : "");
}

static void time_table(tb_suite *su, const scaling_run *sr) {
  static const char *cols[] = {"model",
                               "tets",
                               "nodes",
                               "ms/step CPU (median)",
                               "ms/step wall (median)",
                               "steps timed",
                               "peak RSS added (MiB)",
                               "RSS per tet (KiB)",
                               "status"};
  tb_table *t = tb_table_new("time",
                             "Median ms per step against tets, one thread, CPU time (wall beside), "
                             "liver-stretch; peak memory the model added",
                             9, cols);
  for (int k = 0; k < sr->nm; k++)
    for (int r = 0; r < sr->nsizes; r++) {
      const size_row *w = &sr->rows[r];
      const cell *c = &sr->cells[k][r];
      if (!w->ok) continue;
      tb_table_row(t);
      tb_table_cell(t, "%s", tb_model_classes[k]->name);
      tb_table_num(t, w->ntet, "%.0f");
      tb_table_num(t, w->nv, "%.0f");
      tb_table_num(t, c->ok ? c->ms : NAN, "%.4g");
      tb_table_num(t, c->ok ? c->wall : NAN, "%.4g");
      tb_table_num(t, c->ok ? c->steps : NAN, "%.0f");
      tb_table_num(t, c->rss / 1024, "%.1f");
      tb_table_num(t, c->rss / w->ntet, "%.2f");
      tb_table_cell(t, "%s", c->ok ? "ok" : c->why);
    }
  tb_suite_table(su, t);
}

/* The largest healthy size of model k (-1: none). */
static int largest_ok(const scaling_run *sr, int k) {
  int best = -1;
  for (int r = 0; r < sr->nsizes; r++)
    if (sr->rows[r].ok && sr->cells[k][r].ok) best = r;
  return best;
}

static void fit_table(tb_suite *su, const scaling_run *sr) {
  static const char *cols[] = {"series",
                               "x",
                               "sizes fitted",
                               "slope (log-log)",
                               "ms at the largest x (fitted)",
                               "largest x at 33.3 ms (30 Hz)",
                               "largest x at 3.33 ms (300 Hz)",
                               "RSS per tet at the largest (KiB)",
                               "note"};
  tb_table *t = tb_table_new("fit",
                             "Least-squares lines log(ms) = a + slope log(x), CPU time on one "
                             "thread; where each model stops being interactive",
                             9, cols);
  for (int k = 0; k < sr->nm; k++) {
    fit f = model_fit(sr, k);
    int r = largest_ok(sr, k);
    tb_table_row(t);
    tb_table_cell(t, "%s", tb_model_classes[k]->name);
    tb_table_cell(t, "tets");
    tb_table_num(t, f.n, "%.0f");
    tb_table_num(t, f.b, "%.3f");
    tb_table_num(t, f.n >= 2 ? fit_y(f, f.xhi) : NAN, "%.4g");
    limit_cell(t, f, MS_30HZ);
    limit_cell(t, f, MS_300HZ);
    tb_table_num(t, r >= 0 ? sr->cells[k][r].rss / sr->rows[r].ntet : NAN, "%.2f");
    if (r < 0) { /* never ran: the reason of the first size */
      const cell *c = &sr->cells[k][0];
      tb_table_cell(t, "skipped: %s", c->why[0] ? c->why : "no mesh");
    } else if (f.n < sr->nsizes) {
      tb_table_cell(t, "%d of %d sizes healthy", f.n, sr->nsizes);
    } else {
      tb_table_cell(t, "-");
    }
  }
  static const char *names[] = {"collision: refit", "collision: query", "collision: refit + query"};
  for (int w = 0; w < 3; w++) {
    fit f = collision_fit(sr, w);
    tb_table_row(t);
    tb_table_cell(t, "%s", names[w]);
    tb_table_cell(t, "triangles");
    tb_table_num(t, f.n, "%.0f");
    tb_table_num(t, f.b, "%.3f");
    tb_table_num(t, f.n >= 2 ? fit_y(f, f.xhi) : NAN, "%.4g");
    limit_cell(t, f, MS_30HZ);
    limit_cell(t, f, MS_300HZ);
    tb_table_cell(t, "-");
    tb_table_cell(t, "-");
  }
  tb_suite_table(su, t);
}

/* "not measurable (...)" when the thread runs of t could not have the
 * cores, else NULL. */
static const char *busy_text(const thread_cell *t, int cores, char *buf, size_t cap) {
  if (cores < 2) return snprintf(buf, cap, "not measurable (one core)"), buf;
  if (!t->busy) return NULL;
  snprintf(buf, cap, "not measurable (machine busy: others kept %.1f of %d cores busy)", t->others,
           t->cores);
  return buf;
}

/* The threads table, one row per model and size: one thread against every
 * core, and the speed-ups predicted for more cores; returns 1 when a count
 * changed a bit. */
static int thread_table(tb_suite *su, const scaling_run *sr) {
  static const char *cols[] = {"model",
                               "tets",
                               "threads",
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
  char title[240];
  int bad = 0;
  snprintf(title, sizeof title,
           "Threads: one against all %d cores (measured, wall time, CPU beside; the runs taking "
           "turns step by step; bit-identical on every count?) and the speed-ups predicted for "
           "4, 8 and 16 cores",
           sr->cores);
  tb_table *t = tb_table_new("threads", title, 16, cols);
  tb_table_only(t, 8, TB_CSV_ONLY), tb_table_only(t, 9, TB_CSV_ONLY);
  for (int k = 0; k < sr->nm; k++)
    for (int g = 0; g < sr->nthread_rows; g++) {
      int r = sr->thread_rows[g];
      if (!sr->rows[r].ok) continue;
      const thread_cell *x = &sr->thr[k][g];
      int a = x->ncounts - 1;
      tb_table_row(t);
      tb_table_cell(t, "%s", tb_model_classes[k]->name);
      tb_table_num(t, sr->rows[r].ntet, "%.0f");
      tb_table_num(t, sr->cores, "%.0f");
      if (!x->ok || a < 0) {
        for (int c = 3; c < 11; c++) tb_table_cell(t, "-");
        tb_table_cell(t, "%s", x->why[0] ? x->why : "-");
        for (int c = 12; c < 16; c++) tb_table_cell(t, "-");
        continue;
      }
      tb_table_num(t, x->wall[0], "%.4g");
      tb_table_num(t, x->wall[a], "%.4g");
      tb_table_num(t, x->cpu[0], "%.4g");
      tb_table_num(t, x->cpu[a], "%.4g");
      tb_est su_all = x->speedup[a];
      if (isfinite(su_all.value))
        tb_table_numf(t, su_all.value, "%.2fx (%.2f-%.2f)", su_all.value, su_all.lo, su_all.hi);
      else
        tb_table_cell(t, "-");
      tb_table_num(t, su_all.lo, "%.6g"), tb_table_num(t, su_all.hi, "%.6g");
      char busy[160];
      const char *why = busy_text(x, sr->cores, busy, sizeof busy);
      tb_table_cell(t, "%s", why ? why : "yes");
      tb_table_cell(t, "%s", x->identical ? "yes" : "NO");
      bad |= !x->identical;
      double e;
      tb_scaling_predict(x, 2, &e);
      tb_table_num(t, why ? NAN : e, "%.3f");
      for (int c = 0; c < 3; c++) /* none where the threads gained nothing (e >= 1) */
        tb_table_num(t, why ? NAN : tb_scaling_predict(x, predicted[c], &e), "%.2f");
    }
  tb_suite_table(su, t);
  return bad;
}

/* Every count measured and predicted, tidy: one row per model, size and
 * count, measured or predicted. */
static void thread_axis_table(tb_suite *su, const scaling_run *sr) {
  static const char *cols[] = {"model",
                               "tets",
                               "threads",
                               "source",
                               "ms/step wall (median)",
                               "ms/step CPU (median)",
                               "speed-up",
                               "speed-up low",
                               "speed-up high"};
  tb_table *t = tb_table_new("thread-axis",
                             "Speed-up against threads: measured on this machine's counts, "
                             "predicted (Karp-Flatt) beyond them",
                             9, cols);
  for (int k = 0; k < sr->nm; k++)
    for (int g = 0; g < sr->nthread_rows; g++) {
      int r = sr->thread_rows[g];
      const thread_cell *x = &sr->thr[k][g];
      if (!sr->rows[r].ok || !x->ok) continue;
      char busy[160];
      int measurable = !busy_text(x, sr->cores, busy, sizeof busy);
      for (int q = 0; q < x->ncounts; q++) {
        tb_table_row(t);
        tb_table_cell(t, "%s", tb_model_classes[k]->name);
        tb_table_num(t, sr->rows[r].ntet, "%.0f");
        tb_table_num(t, x->count[q], "%.0f");
        tb_table_cell(t, "measured");
        tb_table_num(t, x->wall[q], "%.4g"), tb_table_num(t, x->cpu[q], "%.4g");
        tb_table_num(t, x->speedup[q].value, "%.3f");
        tb_table_num(t, x->speedup[q].lo, "%.3f"), tb_table_num(t, x->speedup[q].hi, "%.3f");
      }
      for (int c = 0; c < 3 && measurable; c++) {
        if (predicted[c] <= x->count[x->ncounts - 1]) continue;
        double e, v = tb_scaling_predict(x, predicted[c], &e);
        if (!isfinite(v)) continue;
        tb_table_row(t);
        tb_table_cell(t, "%s", tb_model_classes[k]->name);
        tb_table_num(t, sr->rows[r].ntet, "%.0f");
        tb_table_num(t, predicted[c], "%.0f");
        tb_table_cell(t, "predicted");
        for (int z = 0; z < 2; z++) tb_table_num(t, NAN, "%.4g");
        tb_table_num(t, v, "%.3f");
        for (int z = 0; z < 2; z++) tb_table_num(t, NAN, "%.3f");
      }
    }
  tb_suite_table(su, t);
}

static void collision_table(tb_suite *su, const scaling_run *sr) {
  static const char *cols[] = {
      "tets",           "triangles (all tet faces)", "pairs (last frame)",      "refit CPU (ms)",
      "query CPU (ms)", "refit + query CPU (ms)",    "refit + query wall (ms)", "mesh made (s)"};
  tb_table *t = tb_table_new("collision",
                             "Composite hierarchy: refit (delta 0) and all-pairs query against "
                             "the instrument, per deformed frame (median), one thread, CPU time",
                             8, cols);
  for (int r = 0; r < sr->nsizes; r++) {
    const size_row *w = &sr->rows[r];
    tb_table_row(t);
    if (!w->ok) {
      tb_table_num(t, w->target, "%.0f");
      tb_table_cell(t, "%s", w->why);
      for (int c = 2; c < 8; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w->ntet, "%.0f");
    tb_table_num(t, w->ntri, "%.0f");
    tb_table_num(t, w->pairs, "%.0f");
    tb_table_num(t, w->refit_ms, "%.4g");
    tb_table_num(t, w->query_ms, "%.4g");
    tb_table_num(t, w->refit_ms + w->query_ms, "%.4g");
    tb_table_num(t, w->both_wall, "%.4g");
    tb_table_num(t, w->gen_s, "%.2f");
  }
  tb_suite_table(su, t);
}

/* Appends to a growing text buffer. */
typedef struct buf {
  char *p;
  size_t len, cap;
} buf;
static void put(buf *b, const char *fmt, double v) {
  char tmp[64];
  int n = isfinite(v) ? snprintf(tmp, sizeof tmp, fmt, v) : snprintf(tmp, sizeof tmp, "NaN");
  if (b->len + (size_t)n + 2 > b->cap) {
    size_t cap = 2 * b->cap + (size_t)n + 256;
    char *p = realloc(b->p, cap);
    if (!p) return;
    b->p = p, b->cap = cap;
  }
  memcpy(b->p + b->len, tmp, (size_t)n + 1);
  b->len += (size_t)n;
}

/* ms/step against tets per model (+ the 30 and 300 Hz budgets), the lines;
 * refit and query against triangles. */
static int charts(tb_suite *su, const scaling_run *sr) {
  buf data = {0}, line = {0}, cd = {0}, cl = {0};
  char head[1024];
  int hl = snprintf(head, sizeof head, "tets");
  for (int k = 0; k < sr->nm; k++)
    hl += snprintf(head + hl, sizeof head - (size_t)hl, ",%s", tb_model_classes[k]->name);
  snprintf(head + hl, sizeof head - (size_t)hl, ",33.3 ms (30 Hz),3.33 ms (300 Hz)");
  double xlo = INFINITY, xhi = 0, tlo = INFINITY, thi = 0;
  for (int r = 0; r < sr->nsizes; r++) {
    const size_row *w = &sr->rows[r];
    if (!w->ok) continue;
    xlo = fmin(xlo, w->ntet), xhi = fmax(xhi, w->ntet);
    tlo = fmin(tlo, w->ntri), thi = fmax(thi, w->ntri);
    put(&data, "%.0f", w->ntet);
    for (int k = 0; k < sr->nm; k++)
      put(&data, ",%.6g", sr->cells[k][r].ok ? sr->cells[k][r].ms : NAN);
    put(&data, ",%.6g", MS_30HZ), put(&data, ",%.6g\n", MS_300HZ);
    put(&cd, "%.0f", w->ntri), put(&cd, ",%.6g", w->refit_ms), put(&cd, ",%.6g", w->query_ms);
    put(&cd, ",%.6g\n", w->refit_ms + w->query_ms);
  }
  for (int e = 0; e < 2 && xhi > 0; e++) {
    double x = e ? xhi : xlo, tx = e ? thi : tlo;
    put(&line, "%.0f", x);
    for (int k = 0; k < sr->nm; k++) {
      fit f = model_fit(sr, k);
      put(&line, ",%.6g", f.n >= 2 ? fit_y(f, x) : NAN);
    }
    put(&line, ",%.6g", MS_30HZ), put(&line, ",%.6g\n", MS_300HZ);
    put(&cl, "%.0f", tx);
    for (int w = 0; w < 3; w++) {
      fit f = collision_fit(sr, w);
      put(&cl, ",%.6g", f.n >= 2 ? fit_y(f, tx) : NAN);
    }
    put(&cl, "\n", 0);
  }
  /* speed-up against threads on the largest thread size: measured, and
   * predicted (dashed) */
  buf td = {0}, tp = {0};
  char th[1024];
  int tl = snprintf(th, sizeof th, "threads");
  for (int k = 0; k < sr->nm; k++)
    tl += snprintf(th + tl, sizeof th - (size_t)tl, ",%s", tb_model_classes[k]->name);
  snprintf(th + tl, sizeof th - (size_t)tl, ",linear");
  int g = sr->nthread_rows - 1, gr = sr->thread_rows[g], ref = -1;
  for (int k = 0; k < sr->nm && ref < 0; k++)
    if (sr->thr[k][g].ok) ref = k;
  for (int q = 0; ref >= 0 && q < sr->thr[ref][g].ncounts; q++) {
    int n = sr->thr[ref][g].count[q];
    put(&td, "%.0f", n);
    for (int k = 0; k < sr->nm; k++) {
      const thread_cell *x = &sr->thr[k][g];
      put(&td, ",%.6g", x->ok && q < x->ncounts ? x->speedup[q].value : NAN);
    }
    put(&td, ",%.6g\n", n);
  }
  for (int n = 1; ref >= 0 && n <= 16; n *= 2) {
    put(&tp, "%.0f", n);
    for (int k = 0; k < sr->nm; k++) {
      double e;
      char busy[160];
      const thread_cell *x = &sr->thr[k][g];
      put(&tp, ",%.6g",
          busy_text(x, sr->cores, busy, sizeof busy) ? NAN : tb_scaling_predict(x, n, &e));
    }
    put(&tp, ",%.6g\n", n);
  }
  char vars[400];
  snprintf(vars, sizeof vars,
           "title='Speed-up against threads, %d tets, liver-stretch (solid: measured on this "
           "machine; dashed: predicted, Karp-Flatt)'; xlabel='threads'; ylabel='speed-up over "
           "one thread (wall time)'; logx=1; logy=1; fitfile='threads_fit.csv'",
           sr->rows[gr].ntet);
  int rc = 0;
  tb_error err;
  if (ref >= 0 && td.p && tp.p &&
      (tb_suite_write_data(su, "threads.csv", th, td.p, &err) ||
       tb_suite_write_data(su, "threads_fit.csv", th, tp.p, &err) ||
       tb_suite_chart_vars(su, "chart_lines.gp", "threads.csv", "threads", vars, &err))) {
    fprintf(stderr, "scaling: %s\n", err.msg);
    rc = 1;
  } else if (ref >= 0 && td.p && tp.p) {
    tb_suite_caption(su, "threads",
                     "Speed-up over one thread against the thread count on the largest liver "
                     "of the thread runs: measured on this machine's counts (solid), predicted "
                     "beyond them from the serial share the most threads showed (dashed)");
  }
  free(td.p), free(tp.p);
  const char *ch = "triangles,refit,query,refit + query";
  if (!data.p || !line.p || !cd.p || !cl.p ||
      tb_suite_write_data(su, "time.csv", head, data.p, &err) ||
      tb_suite_write_data(su, "time_fit.csv", head, line.p, &err) ||
      tb_suite_chart_vars(su, "chart_lines.gp", "time.csv", "time",
                          "title='CPU ms per step against tets, one thread, liver-stretch (dashed: "
                          "least-squares lines)'; xlabel='tets'; ylabel='CPU time per step (ms)'; "
                          "logx=1; logy=1; fitfile='time_fit.csv'",
                          &err) ||
      tb_suite_write_data(su, "collision.csv", ch, cd.p, &err) ||
      tb_suite_write_data(su, "collision_fit.csv", ch, cl.p, &err) ||
      tb_suite_chart_vars(su, "chart_lines.gp", "collision.csv", "collision",
                          "title='Composite hierarchy: refit and query against triangles "
                          "(dashed: least-squares lines)'; xlabel='triangles'; ylabel='CPU time "
                          "per frame (ms)'; logx=1; logy=1; fitfile='collision_fit.csv'",
                          &err)) {
    fprintf(stderr, "scaling: %s\n", data.p && line.p && cd.p && cl.p ? err.msg : "no data");
    rc = 1;
  } else {
    tb_suite_caption(
        su, "time",
        "Median CPU ms per step against tets (log-log), one thread, every model of the "
        "table in liver-stretch, with least-squares lines and the 30 Hz and 300 Hz "
        "budgets");
    tb_suite_caption(su, "collision",
                     "Refit and all-pairs query of the composite hierarchy (CPU time, one thread) "
                     "against the number of triangles (all tet faces of each liver, log-log), with "
                     "least-squares lines");
  }
  free(data.p), free(line.p), free(cd.p), free(cl.p);
  return rc;
}

int tb_scaling_report(tb_suite *su, const scaling_run *sr) {
  const tb_context *c = tb_suite_context(su);
  int failed = 0;
  double load = c->have_load ? c->load[0] : NAN;
  tb_suite_note(
      su,
      "Scene %s (the liver held along its back, a far surface patch pulled out and let go) on "
      "TetGen livers of %d sizes (tb_liver_of_tets: the default liver's shape, a surface of "
      "725 (tets/4230)^0.8 vertices, TetGen's maximum tet volume searched to within 2%% of the "
      "tet count), every model of models/model.c's table with the scene's settings (metaball, "
      "a surface model, on each liver's boundary surface). Timed: the "
      "model's step alone on one thread, CPU time (the thread's own, which other processes' "
      "time slices do not inflate; wall beside), after one warm-up step (fem factorises its "
      "matrix there), until %.2f s of CPU time in steps (at least 3, at most 400), the median "
      "reported; the exponents and the 30 and 300 Hz limits come from the CPU times; the "
      "health check (NaN, velocity bound, inverted tets) after every step, untimed. Memory, "
      "as a difference in the suite's process: before each one-thread run freed memory is "
      "handed back to the system (blocks above 64 KiB from mmap, malloc_trim) and the peak "
      "RSS reset (5 to /proc/self/clear_refs); VmHWM after the run (building the scene with "
      "its copy of the mesh, the model, the steps) minus VmRSS before it is the peak the run "
      "added. (A forked child per run would be cleaner, but CHOLMOD starts OpenMP threads and "
      "libgomp hangs in a child of a process that has used threads.) The suite "
      "took %.1f s. This machine: %d cores (%s), load average %.2f at the start.",
      SCENE, sr->nsizes, sr->budget, sr->seconds, sr->cores, c->cpu, load);
  time_table(su, sr);
  fit_table(su, sr);
  tb_suite_note(su,
                "Slope: the exponent of ms per step in the size (1: linear). The limits are the "
                "sizes where a model's line reaches 33.3 ms per step (30 Hz, graphics) and "
                "3.33 ms (300 Hz, haptics): the largest mesh it steps at that rate on one thread "
                "of this machine, marked extrapolated outside the sizes measured. A model that "
                "cannot take a tet liver, or blew up on every size, is listed as skipped with "
                "its reason.");
  failed |= thread_table(su, sr);
  thread_axis_table(su, sr);
  tb_suite_note(
      su,
      "Threads, set explicitly (not the automatic count): a model's runs on 1, 2, 4, ... "
      "threads and on all %d cores (one warm-up step each, then as many steps as its "
      "one-thread run above timed, at least %d) live side by side and take turns step by step, "
      "so that a busy spell of the machine falls on all alike; a speed-up is the median of the "
      "steps' paired wall-time ratios (one thread over the count) with its 95%% interval. When "
      "other processes did not leave the cores free (over the suite up to that run), the "
      "speed-up is not measurable and says so; the numbers are still shown. Measured columns "
      "are this machine's counts; the predicted columns (and the `predicted` rows of "
      "table-thread-axis.csv, dashed in the chart) extrapolate the speed-up measured on the "
      "most threads, p, by Karp and Flatt's serial share e = (1/S - 1/p) / (1 - 1/p), held "
      "constant: S(n) = 1 / (e + (1 - e) / n). e lumps what the measurement saw: the serial "
      "parts, the barriers, the work imbalance, the memory traffic between cores. The "
      "prediction is optimistic where those grow with n (a barrier across more cores costs "
      "more, memory bandwidth is shared by all cores, pbd's sweeps have 2 tasks a slab and "
      "at most %d slabs, so n beyond the tasks of a phase waits) and pessimistic where the "
      "measured run was held up by something n does not make worse (one slow step, another "
      "process). Where the threads gained nothing (e >= 1) nothing is predicted. A machine "
      "with more cores runs the same suite and gets measured columns instead.",
      sr->cores, TB_EST_MIN, TB_SWEEP_SLABS);
  for (int q = 0; q < (int)(sizeof thread_goals / sizeof thread_goals[0]); q++) {
    const char *name = thread_goals[q].model;
    double goal = thread_goals[q].speedup;
    int k = 0, g = 0, two = -1; /* the model, its thread row, the count of 2 threads */
    while (k < sr->nm && strcmp(tb_model_classes[k]->name, name)) k++;
    while (g < sr->nthread_rows && !(sr->rows[sr->thread_rows[g]].ok &&
                                     fabs((double)sr->rows[sr->thread_rows[g]].ntet -
                                          thread_goals[q].tets) <= 0.1 * thread_goals[q].tets))
      g++;
    const thread_cell *x = k < sr->nm && g < sr->nthread_rows ? &sr->thr[k][g] : NULL;
    for (int c = 0; x && c < x->ncounts; c++)
      if (x->count[c] == 2) two = c;
    tb_est est = two >= 0 ? x->speedup[two] : (tb_est){NAN, NAN, NAN, 0};
    char v[200], busy[160], key[64];
    const char *why = x ? busy_text(x, sr->cores, busy, sizeof busy) : NULL;
    if (!x)
      snprintf(v, sizeof v, "not measured (no thread runs at about %d tets in this run)",
               thread_goals[q].tets);
    else if (!x->ok)
      snprintf(v, sizeof v, "not measured (%s)", x->why);
    else if (two < 0)
      snprintf(v, sizeof v, "not measured (one core)");
    else if (why)
      snprintf(v, sizeof v, "%s", why);
    else
      tb_verdict_text(est, goal, 1, v, sizeof v);
    char got[120] = "";
    if (est.n > 0)
      snprintf(got, sizeof got, "%.2fx, 95%% interval %.2f-%.2f over %d steps; ", est.value, est.lo,
               est.hi, est.n);
    tb_suite_note(su,
                  "Speed goal: %s on 2 threads at least %.1fx one thread at %d tets (wall "
                  "time): %s%s.",
                  name, goal, x ? sr->rows[sr->thread_rows[g]].ntet : thread_goals[q].tets, got, v);
    int measurable = x && x->ok && two >= 0 && !why;
    snprintf(key, sizeof key, "thread_goal/%s/%d", name, thread_goals[q].tets);
    tb_suite_counter_est(su, key, "speedup", est);
    tb_suite_counter(su, key, "goal", goal);
    tb_suite_counter(su, key, "measurable", measurable);
    if (measurable) tb_suite_counter(su, key, "verdict", tb_verdict(est, goal, 1));
  }
  collision_table(su, sr);
  tb_suite_note(su,
                "Collision: the liver's every tet face (the thesis's liver model, as the refit "
                "suite) in the composite hierarchy (collision/tb_bvh.h), the instrument held "
                "inside it (the refit suite's pose), the liver deformed by the same smooth "
                "displacement each of %d frames; refit with delta 0, then the all-pairs query "
                "(exact triangle test), medians per frame, CPU time on one thread.",
                sr->frames);
  failed |= charts(su, sr);
  return failed;
}
