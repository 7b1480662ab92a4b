/* Thesis table 4.1: the 40 designed pairs repeated to 0.1, 0.5, 1, 1.5 and
 * 2 million tests, CPU milliseconds per method (median of repetitions that
 * take turns method by method, one thread), the thesis's figures beside
 * ours (Yu-He original 70/392/654/947/1256 ms, improved 42/231/384/557/739
 * ms on an i3-2100), with a chart of time against tests; then ns/pair on
 * the JGT Shen-2003 pairs mixed to 0%, 10%, 50% and 100% intersecting,
 * every method's speed as a ratio to fcl's (paired passes, with its 95%
 * interval) and the target verdict. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "measure/tb_tritri_run.h"
#include "report/tb_results.h"

#define NCOUNTS 5
static const double counts_m[NCOUNTS] = {0.1, 0.5, 1.0, 1.5, 2.0};
static const double thesis_yuhe[NCOUNTS] = {70, 392, 654, 947, 1256};
static const double thesis_improved[NCOUNTS] = {42, 231, 384, 557, 739};

/* Runs n tests cycling through the set; returns 0/1 answers summed. */
static long run_cycle(const tb_tritri_method *m, const tb_pairset *s, long n) {
  long acc = 0;
  for (long i = 0, k = 0; i < n; i++) {
    acc += m->test(s->pairs[k].p, s->pairs[k].q);
    if (++k == s->n) k = 0;
  }
  return acc;
}

/* "a and b" from their verdicts: not met when either is not met (the
 * target fails whatever the other says), else inconclusive when either is,
 * else met. */
static int both(int a, int b) {
  if (a == TB_NOT_MET || b == TB_NOT_MET) return TB_NOT_MET;
  return a == TB_NOISE || b == TB_NOISE ? TB_NOISE : TB_MET;
}

/* Which side of 1 a ratio a/b is on, in words, only when its interval
 * excludes 1. */
static const char *side_of_one(tb_est e, const char *a, const char *b, char *buf, size_t cap) {
  if (e.n < TB_EST_MIN)
    snprintf(buf, cap, "too few repetitions (%d) to say which of %s and %s is faster", e.n, a, b);
  else if (e.hi < 1)
    snprintf(buf, cap, "%s is faster than %s", a, b);
  else if (e.lo > 1)
    snprintf(buf, cap, "%s is slower than %s", a, b);
  else
    snprintf(buf, cap, "%s and %s are within noise of each other", a, b);
  return buf;
}

/* Time for N tests of the 40 designed pairs: at every N the methods take
 * turns repetition by repetition (A, B, C, A, B, C, ...), each repetition
 * timed in CPU and wall time. */
static int table41(const tb_suite_opts *o, tb_suite *s, const tb_pairset *d40, int reps) {
  int nm;
  const tb_tritri_method *m = tb_tritri_methods(&nm);
  if (nm > 16) nm = 16;
  const char *cols[3 + 2 * 16];
  cols[0] = "tests (million)";
  cols[1] = "thesis Yu-He (ms, i3-2100)";
  cols[2] = "thesis improved (ms, i3-2100)";
  char names[2 * 16][48];
  for (int j = 0; j < nm; j++) {
    snprintf(names[j], sizeof names[j], "%s (ms)", m[j].name);
    snprintf(names[16 + j], sizeof names[16 + j], "%s wall (ms)", m[j].name);
    cols[3 + j] = names[j];
    cols[3 + nm + j] = names[16 + j];
  }
  double ms[NCOUNTS][16], wms[NCOUNTS][16];
  size_t per = (size_t)nm * (size_t)reps;
  double *cpu = malloc(sizeof(double) * 2 * per), *wall = cpu ? cpu + per : NULL;
  if (!cpu) return 1;
  const tb_tritri_method *yh = tb_tritri_find("yuhe"), *im = tb_tritri_find("improved");
  int iy = yh ? (int)(yh - m) : -1, ii = im ? (int)(im - m) : -1;
  if (iy < 0 || ii < 0 || iy >= nm || ii >= nm) iy = ii = -1;
  tb_est imp_yuhe = {NAN, NAN, NAN, 0};
  long last_n = 0;
  volatile long sink = 0;
  for (int j = 0; j < nm; j++) sink += run_cycle(&m[j], d40, 100000); /* warm-up */
  for (int c = 0; c < NCOUNTS; c++) {
    tb_progress("table 4.1", c, NCOUNTS);
    long n = (long)(counts_m[c] * 1e6 * o->scale);
    if (n < 40) n = 40;
    for (int r = 0; r < reps; r++)
      for (int j = 0; j < nm; j++) {
        tb_clock cl = tb_clock_start();
        sink += run_cycle(&m[j], d40, n);
        size_t at = (size_t)j * (size_t)reps + (size_t)r;
        tb_clock_ms(&cl, &wall[at], &cpu[at]);
      }
    for (int j = 0; j < nm; j++) {
      const double *pc = cpu + (size_t)j * (size_t)reps, *pw = wall + (size_t)j * (size_t)reps;
      ms[c][j] = tb_stats_of(pc, reps).median, wms[c][j] = tb_stats_of(pw, reps).median;
      char bname[96];
      snprintf(bname, sizeof bname, "table4.1/%s/tests:%ld", m[j].name, n);
      tb_suite_bench(s, bname, pw, pc, reps, "ms");
    }
    if (c == NCOUNTS - 1 && iy >= 0)
      imp_yuhe =
          tb_ratio_est(cpu + (size_t)ii * (size_t)reps, cpu + (size_t)iy * (size_t)reps, reps);
    last_n = n;
  }
  tb_progress("table 4.1", NCOUNTS, NCOUNTS);
  (void)sink;
  free(cpu);
  tb_table *t = tb_table_new(
      "table4.1",
      "Table 4.1: CPU time for N tests of the 40 designed pairs (median ms, one thread; wall time "
      "in the CSV)",
      3 + 2 * nm, cols);
  for (int j = 0; j < nm; j++) tb_table_only(t, 3 + nm + j, TB_CSV_ONLY);
  char body[8192];
  int len = 0;
  for (int c = 0; c < NCOUNTS; c++) {
    double n = counts_m[c] * o->scale;
    tb_table_row(t);
    tb_table_cell(t, "%g", n);
    tb_table_cell(t, "%g", thesis_yuhe[c]);
    tb_table_cell(t, "%g", thesis_improved[c]);
    len += snprintf(body + len, sizeof body - (size_t)len, "%g", n);
    for (int j = 0; j < nm; j++) {
      tb_table_num(t, ms[c][j], "%.1f");
      len += snprintf(body + len, sizeof body - (size_t)len, ",%.4f", ms[c][j]);
    }
    for (int j = 0; j < nm; j++) tb_table_num(t, wms[c][j], "%.1f");
    len += snprintf(body + len, sizeof body - (size_t)len, "\n");
  }
  tb_suite_table(s, t);
  if (iy >= 0) {
    char side[160];
    tb_suite_note(s,
                  "At 2 million tests the thesis's improved test took %.0f%% of the original's "
                  "time; here, at %ld tests, improved takes %.0f%% of yuhe's CPU time (95%% "
                  "interval %.0f%%-%.0f%%, the median of %d paired repetitions): %s.",
                  100.0 * thesis_improved[4] / thesis_yuhe[4], last_n, 100.0 * imp_yuhe.value,
                  100.0 * imp_yuhe.lo, 100.0 * imp_yuhe.hi, imp_yuhe.n,
                  side_of_one(imp_yuhe, "improved", "yuhe", side, sizeof side));
  }
  tb_suite_note(s,
                "Every method ran the same 40 pairs cycled to N tests on one thread; at every N "
                "the methods took turns, repetition by repetition; the figures are the medians "
                "of %d repetitions' CPU time (the calling thread's).",
                reps);
  char header[1024] = "tests (million)";
  for (int j = 0; j < nm; j++) {
    strncat(header, ",", sizeof header - strlen(header) - 1);
    strncat(header, m[j].name, sizeof header - strlen(header) - 1);
  }
  /* the thesis's series at its own counts (ours are scaled by --scale) */
  char paper[512];
  int plen = 0;
  for (int c = 0; c < NCOUNTS; c++)
    plen += snprintf(paper + plen, sizeof paper - (size_t)plen, "%g,%g,%g\n", counts_m[c],
                     thesis_yuhe[c], thesis_improved[c]);
  tb_error err;
  if (tb_suite_write_data(s, "table41.csv", header, body, &err) ||
      tb_suite_write_data(s, "table41_thesis.csv",
                          "tests (million),thesis Yu-He (i3-2100),thesis improved (i3-2100)", paper,
                          &err) ||
      tb_suite_chart_vars(s, "chart_lines.gp", "table41.csv", "table41",
                          "title='Table 4.1: CPU time for N tests of the 40 designed pairs "
                          "(dashed: the thesis, i3-2100)'; xlabel='tests (million)'; "
                          "ylabel='CPU time (ms)'; points=1; paperfile='table41_thesis.csv'",
                          &err)) {
    fprintf(stderr, "table 4.1: %s\n", err.msg);
    return 1;
  }
  tb_suite_caption(s, "table41",
                   "CPU time for 0.1 to 2 million triangle-triangle tests, every method, one "
                   "thread (thesis table 4.1)");
  return 0;
}

#define MIXES 4

/* ns/pair on JGT mixes: n pairs, the given fraction intersecting. For each
 * mix the methods take turns pass by pass; every pass is timed in CPU and
 * wall time. The target (exact at most 25 ns/pair and at least 5x faster
 * than fcl on the 50% mix) is judged from the 95% intervals of exact's
 * median and of the paired ratios fcl / exact. */
static int jgt(const tb_suite_opts *o, tb_suite *s, int reps) {
  tb_pairset in, sep;
  tb_error err;
  int jrc = tb_pairs_read_jgt_dir(TB_SHARED_DATA_FILE("jgt-shen2003"), &in, &sep, &err);
  if (jrc < 0) {
    fprintf(stderr, "table 4.1: %s\n", err.msg);
    return 1;
  }
  if (jrc > 0) {
    tb_suite_note(s, "JGT Shen-2003 pairs absent (%s): no ns/pair benchmark in this run.", err.msg);
    return 0;
  }
  static const int mix[MIXES] = {0, 10, 50, 100};
  int nm, n = in.n < sep.n ? in.n : sep.n;
  const tb_tritri_method *m = tb_tritri_methods(&nm);
  if (nm > 16) nm = 16;
  const tb_tritri_method *fm = tb_tritri_find("fcl"), *em = tb_tritri_find("exact");
  int ifcl = fm ? (int)(fm - m) : -1, iex = em ? (int)(em - m) : -1;
  if (ifcl < 0 || iex < 0 || ifcl >= nm || iex >= nm) {
    tb_pairs_free(&in), tb_pairs_free(&sep);
    fprintf(stderr, "table 4.1: the exact and fcl tests are not both registered\n");
    return 1;
  }
  /* cpu[((x nm) + j) reps + r]: mix x, method j, pass r (ns/pair); wall likewise */
  size_t per = (size_t)MIXES * (size_t)nm * (size_t)reps;
  double *cpu = malloc(sizeof(double) * 2 * per), *wall = cpu ? cpu + per : NULL;
  if (!cpu) {
    tb_pairs_free(&in), tb_pairs_free(&sep);
    fprintf(stderr, "table 4.1: out of memory\n");
    return 1;
  }
#define AT(x, j) (((size_t)(x) * (size_t)nm + (size_t)(j)) * (size_t)reps)
  double ns[MIXES][16];
  tb_rng r = tb_rng_seed(o->seed);
  for (int x = 0; x < MIXES; x++) {
    tb_pairset set = {0};
    int k = n * mix[x] / 100;
    for (int i = 0; i < n; i++) tb_pairs_add(&set, i < k ? &in.pairs[i] : &sep.pairs[i], i < k);
    for (int i = n - 1; i > 0; i--) { /* shuffle: no branch-predictor gift */
      int j = (int)tb_rng_below(&r, (uint64_t)i + 1);
      tb_tripair t = set.pairs[i];
      set.pairs[i] = set.pairs[j], set.pairs[j] = t;
    }
    double warm[2];
    for (int j = 0; j < nm; j++) tb_tritri_time(&m[j], &set, 2, warm, NULL); /* warm-up */
    for (int p = 0; p < reps; p++) {
      tb_progress("JGT", x * reps + p, MIXES * reps);
      for (int j = 0; j < nm; j++)
        tb_tritri_time(&m[j], &set, 1, cpu + AT(x, j) + p, wall + AT(x, j) + p);
    }
    for (int j = 0; j < nm; j++) {
      ns[x][j] = tb_stats_of(cpu + AT(x, j), reps).median;
      char bname[96];
      snprintf(bname, sizeof bname, "jgt/%s/intersecting:%d%%", m[j].name, mix[x]);
      tb_suite_bench(s, bname, wall + AT(x, j), cpu + AT(x, j), reps, "ns");
    }
    tb_pairs_free(&set);
  }
  tb_progress("JGT", MIXES * reps, MIXES * reps);
  tb_pairs_free(&in), tb_pairs_free(&sep);
  static const char *cols[] = {"method",
                               "0% (ns/pair CPU)",
                               "10% (ns/pair CPU)",
                               "50% (ns/pair CPU)",
                               "100% (ns/pair CPU)",
                               "50% (ns/pair wall)",
                               "fcl / method (50%)",
                               "fcl / method, 95% low",
                               "fcl / method, 95% high"};
  tb_table *t = tb_table_new(
      "jgt",
      "ns per pair on the JGT Shen-2003 pairs, by share intersecting (median CPU time, one thread)",
      9, cols);
  tb_table_csv_name(t, 6, "fcl / method (50%, ratio of CPU times)");
  for (int j = 0; j < nm; j++) {
    tb_est e = tb_ratio_est(cpu + AT(2, ifcl), cpu + AT(2, j), reps);
    tb_table_row(t);
    tb_table_cell(t, "%s", m[j].name);
    for (int x = 0; x < MIXES; x++) tb_table_num(t, ns[x][j], "%.1f");
    tb_table_num(t, tb_stats_of(wall + AT(2, j), reps).median, "%.1f");
    tb_table_num(t, e.value, "%.2fx");
    tb_table_num(t, e.lo, "%.2f");
    tb_table_num(t, e.hi, "%.2f");
    char bname[96];
    snprintf(bname, sizeof bname, "jgt/%s/intersecting:%d%%", m[j].name, mix[2]);
    tb_suite_counter_est(s, bname, "fcl_over_method", e);
  }
  tb_suite_table(s, t);
  /* the target, on the 50% mix */
  tb_est ens = tb_median_est(cpu + AT(2, iex), reps);
  tb_est ratio = tb_ratio_est(cpu + AT(2, ifcl), cpu + AT(2, iex), reps);
  free(cpu);
#undef AT
  int v_ns = tb_verdict(ens, 25, 0), v_ratio = tb_verdict(ratio, 5, 1), v = both(v_ns, v_ratio);
  char t_ns[200], t_ratio[200], t_all[200];
  tb_verdict_text(ens, 25, 0, t_ns, sizeof t_ns);
  tb_verdict_text(ratio, 5, 1, t_ratio, sizeof t_ratio);
  if (v == TB_MET)
    snprintf(t_all, sizeof t_all, "met");
  else if (v == TB_NOT_MET)
    snprintf(t_all, sizeof t_all, "not met");
  else
    snprintf(t_all, sizeof t_all, "inconclusive (%s within noise)",
             v_ns == TB_NOISE && v_ratio == TB_NOISE ? "both conditions"
             : v_ns == TB_NOISE                      ? "the ns/pair condition"
                                                     : "the ratio condition");
  static const char *tcols[] = {
      "condition (50% mix)", "measured", "95% low", "95% high", "goal", "verdict"};
  tb_table *tt = tb_table_new(
      "target",
      "Target: exact at most 25 ns/pair and at least 5x faster than fcl (CPU, one thread)", 6,
      tcols);
  tb_table_row(tt);
  tb_table_cell(tt, "exact, ns/pair CPU (at most)");
  tb_table_num(tt, ens.value, "%.2f");
  tb_table_num(tt, ens.lo, "%.2f");
  tb_table_num(tt, ens.hi, "%.2f");
  tb_table_num(tt, 25, "%.0f");
  tb_table_cell(tt, "%s", t_ns);
  tb_table_row(tt);
  tb_table_cell(tt, "fcl / exact, ratio of CPU times (at least)");
  tb_table_num(tt, ratio.value, "%.2f");
  tb_table_num(tt, ratio.lo, "%.2f");
  tb_table_num(tt, ratio.hi, "%.2f");
  tb_table_num(tt, 5, "%.0f");
  tb_table_cell(tt, "%s", t_ratio);
  tb_table_row(tt);
  tb_table_cell(tt, "both");
  for (int k = 0; k < 4; k++) tb_table_cell(tt, "-");
  tb_table_cell(tt, "%s", t_all);
  tb_suite_table(s, tt);
  tb_suite_note(
      s,
      "JGT mixes: every method on the same shuffled %d pairs per mix, one thread; the methods "
      "took turns pass by pass (%d passes each); ns/pair are medians of the passes' CPU time. "
      "(Run back to back, one method's passes over the same pairs come out faster than when "
      "the methods take turns; the figures here are from taking turns.) "
      "The ratio fcl / method is the median of the paired passes' ratios, with its 95%% "
      "interval. Target: exact at most 25 ns/pair and at least 5x faster than fcl on the 50%% "
      "mix, each condition met or not when its 95%% interval is on one side of the goal, else "
      "inconclusive; the target is not met when either condition is not met, inconclusive when "
      "neither fails and one is inconclusive. Measured: exact %.1f ns/pair (%.1f-%.1f): %s; "
      "%.2fx fcl (%.2f-%.2f): %s. Target: %s.",
      n, reps, ens.value, ens.lo, ens.hi, t_ns, ratio.value, ratio.lo, ratio.hi, t_ratio, t_all);
  tb_suite_counter_est(s, "jgt/target", "exact_ns_per_pair", ens);
  tb_suite_counter_est(s, "jgt/target", "fcl_over_exact", ratio);
  tb_suite_counter(s, "jgt/target", "verdict", v); /* 0 met, 1 not met, 2 inconclusive */
  return 0;
}

int tb_suite_table41(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/table-4.1", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s =
      tb_suite_begin(dir, "table-4.1", "Thesis table 4.1: triangle-test speed", o->seed, &err);
  if (!s) {
    fprintf(stderr, "table 4.1: %s\n", err.msg);
    return 1;
  }
  tb_pairset d40;
  int rc = tb_pairs_read_file(TB_DESIGNED_PAIRS, &d40, &err);
  if (rc) fprintf(stderr, "table 4.1: %s\n", err.msg);
  /* a speed comparison: one thread, so every time is the calling thread's CPU time */
  int was = tb_threads_setting(), reps = o->full ? 11 : 7;
  tb_threads_set(1);
  if (!rc) rc = table41(o, s, &d40, reps) || jgt(o, s, o->full ? 51 : 21);
  tb_threads_set(was);
  tb_pairs_free(&d40);
  if (tb_suite_end(s, &err)) {
    fprintf(stderr, "table 4.1: %s\n", err.msg);
    return 1;
  }
  return rc;
}
