/* The results pipeline every suite uses. A suite run writes results/<suite>/:
 *   table.md   the documents' figures beside ours, units in headers, the
 *              run's context in a short header;
 *   table-<name>.csv  one tidy CSV per table: the header carries the units,
 *              numeric cells hold bare numbers (tb_table_num), "-" and
 *              non-finite values are empty;
 *   data.json  Google Benchmark's JSON layout: "context" and "benchmarks"
 *              with mean/median/stddev/min/max aggregates, measurements that
 *              are not times as user counters (tb_suite_counter);
 *   *.png/svg  charts drawn by gnuplot from scripts in scripts/.
 * A progress bar goes to stderr when stderr is a terminal. */
#ifndef TB_RESULTS_H
#define TB_RESULTS_H

#include <stddef.h>
#include <stdint.h>

#include "core/tb_error.h"

/* ---- how busy the machine was (report/noise.c) ---- */
typedef struct tb_noise_mark {
  uint64_t wall_ns;
  double busy_s, all_s, steal_s; /* every CPU's busy, all and stolen time (/proc/stat) */
  double self_s;                 /* this process's and its children's CPU time */
  long nivcsw;                   /* its involuntary context switches */
  double load1;
  int ok; /* /proc/stat was read */
} tb_noise_mark;
void tb_noise_mark_take(tb_noise_mark *m);
typedef struct tb_noise {
  int known; /* /proc/stat read at both marks */
  double seconds;
  int cores;
  double others;   /* cores other processes kept busy, on average */
  double steal;    /* the share of all CPU time the hypervisor took */
  double switches; /* this process's involuntary context switches a second */
  double load1;    /* the load average at the second mark */
  int scaling;     /* cpu0's frequency governor is not "performance" */
  int busy;        /* the others left fewer cores than `threads` (with half a core of slack), or the
                      steal was over 5%: times on that many threads are not measurable */
} tb_noise;
/* Between marks a and b, for work on `threads` threads. */
tb_noise tb_noise_between(const tb_noise_mark *a, const tb_noise_mark *b, int threads);
/* One sentence for notes and stderr: quiet or BUSY, with the figures. */
void tb_noise_describe(const tb_noise *n, char *buf, size_t cap);

/* ---- run context (machine, compiler, commit, dependency versions) ---- */
typedef struct tb_context {
  char date[32]; /* ISO 8601, UTC */
  char host[128];
  char cpu[160]; /* model name from /proc/cpuinfo */
  int cores;
  int mhz;            /* 0 when unknown */
  char compiler[128]; /* e.g. "gcc 12.2.0" */
  char flags[256];    /* build type and C flags */
  char commit[48];    /* git commit, or "unknown" */
  int dirty;          /* uncommitted changes at run time: 1, 0, or -1 unknown */
  char cholmod[32], fcl[32], bullet[32], cgal[32], tetgen[32];
  uint64_t seed;
  int threads; /* worker threads in effect (core/tb_threads.h) */
  /* Google Benchmark's context fields */
  int cpu_scaling; /* 1 when cpu0's governor is not "performance", 0 also when absent */
  struct tb_cache {
    char type[16]; /* "Data", "Instruction", "Unified" */
    int level, num_sharing;
    long size; /* bytes */
  } caches[8];
  int ncaches;
  double load[3]; /* 1, 5, 15 minute load averages */
  int have_load;
  char build_type[16]; /* "release" or "debug" */
  /* how busy the machine was over the suite (tb_suite_end fills it) */
  int have_noise;
  tb_noise noise;
} tb_context;

/* Fills c; fields that cannot be read say "unknown" (numbers 0). */
void tb_context_collect(tb_context *c, uint64_t seed);

/* ---- estimates with intervals, and verdicts (report/estimate.c) ----
 * A measurement that decides a ratio or a verdict is repeated, the two
 * sides interleaved (A, B, A, B, ...), and carries its 95% interval; a
 * verdict is "met" or "not met" only when the interval is on one side of
 * the goal, else "inconclusive (noise)". */
typedef struct tb_est {
  double value, lo, hi; /* the median and its 95% interval */
  int n;                /* samples it came from (finite ones) */
} tb_est;
/* The median of the finite samples of x[0..n) with its distribution-free
 * interval (order statistics; for n < TB_EST_MIN: [min, max], which covers
 * the median with probability 1 - 2^(1-n), less than 95%). */
#define TB_EST_MIN 6
tb_est tb_median_est(const double *x, int n);
/* The paired ratios a[i] / b[i] of interleaved repetitions: their median
 * and its interval (pairs with a non-finite or non-positive side left out). */
tb_est tb_ratio_est(const double *a, const double *b, int n);
enum { TB_MET = 0, TB_NOT_MET = 1, TB_NOISE = 2 };
/* e against "value >= goal" (at_least 1) or "value <= goal" (0): TB_MET or
 * TB_NOT_MET when its whole interval is on that side, TB_NOISE when the
 * interval holds the goal or has fewer than TB_EST_MIN samples. */
int tb_verdict(tb_est e, double goal, int at_least);
/* "met", "not met", "inconclusive (noise: the 95% interval LO-HI holds
 * GOAL)" or "inconclusive (N repetitions: ...)" into buf; returns buf. */
const char *tb_verdict_text(tb_est e, double goal, int at_least, char *buf, size_t cap);

/* ---- tables ---- */
typedef struct tb_table tb_table;
/* Column names carry their units, e.g. "time (ms)". NULL on bad arguments
 * or no memory (tb_suite_table then records the error). A row with more
 * cells than columns, or a cell before the first row, is an error reported
 * by tb_suite_end; missing cells are empty. */
tb_table *tb_table_new(const char *name, const char *title, int ncols, const char *const *cols);
void tb_table_row(tb_table *t); /* starts a new row */
/* A text cell (names, status words). A cell of only "-" means "no value"
 * and is empty in the CSV. A column whose cells mix numbers and other text
 * (e.g. "2.1x" among numbers) is a misuse reported by tb_suite_end: use
 * tb_table_num for such cells. */
void tb_table_cell(tb_table *t, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A numeric cell: table.md shows value through fmt, one floating conversion
 * with any decoration, e.g. "%.3f", "%.1fx", "%+.1f%%"; the CSV holds the
 * bare value (%.10g) in the column header's unit. A non-finite value shows
 * "-" and is empty in the CSV. */
void tb_table_num(tb_table *t, double value, const char *fmt);
/* The same when table.md's text needs more than the value, e.g.
 * "725 (+0.4%)" or "< 0.001": text from fmt and its arguments, the CSV
 * holds value (empty when not finite). */
void tb_table_numf(tb_table *t, double value, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* An estimate's cell: table.md shows "median (low-high)" through fmt (one
 * floating conversion, e.g. "%.3g") and unit ("x", " ms", or ""), the CSV
 * the median; a non-finite median shows "-". */
void tb_table_est(tb_table *t, tb_est e, const char *fmt, const char *unit);
/* The header of column col in the CSV when it differs from table.md's, e.g.
 * to name a unit that table.md shows in the cells. */
void tb_table_csv_name(tb_table *t, int col, const char *name);
/* Column col only in table.md (TB_MD_ONLY), e.g. "yes, yes, 2" for reading,
 * or only in the CSV (TB_CSV_ONLY), e.g. the same as three clean columns. */
enum { TB_MD_ONLY = 1, TB_CSV_ONLY = 2 };
void tb_table_only(tb_table *t, int col, int where);
void tb_table_free(tb_table *t);

/* ---- timing samples -> aggregates ---- */
typedef struct tb_stats {
  int n;
  double mean, median, stddev, min, max;
} tb_stats;
/* Sorts a copy; n may be 0 (all zero). Median of an even count: the mean
 * of the middle two; stddev: the sample deviation (n - 1), 0 for n < 2. */
tb_stats tb_stats_of(const double *samples, int n);

/* ---- a suite run ---- */
typedef struct tb_suite tb_suite;
/* The file tb_suite_begin writes into the suite's folder and tb_suite_end
 * removes: a folder holding it is from a run that did not finish. */
#define TB_INCOMPLETE "INCOMPLETE"
/* dir: the output folder (created, with parents). */
tb_suite *tb_suite_begin(const char *dir, const char *name, const char *title, uint64_t seed,
                         tb_error *err);
const tb_context *tb_suite_context(const tb_suite *s);
/* How busy the machine has been since tb_suite_begin, for work on
 * `threads` threads: a suite whose thread-scaling figures need the cores
 * asks it before stating them (busy: "not measurable"). tb_suite_end notes
 * the whole suite's (in table.md, REPORT.md, data.json's context, and on
 * stderr when busy). */
tb_noise tb_suite_noise(const tb_suite *s, int threads);
/* A paragraph of table.md, in order with the tables. */
void tb_suite_note(tb_suite *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* The suite takes ownership of t. */
void tb_suite_table(tb_suite *s, tb_table *t);
/* One benchmark entry: per-repetition wall (real) and CPU times in the
 * given unit ("ns", "us", "ms", "s"), both required (tb_clock measures
 * both; data.json's cpu_time is CPU time, never wall time). The entry
 * records the thread count in effect when it is added. Also summarised in
 * a "timings" table at the end of table.md. */
void tb_suite_bench(tb_suite *s, const char *name, const double *real, const double *cpu, int n,
                    const char *unit);
/* A Google Benchmark user counter: a measurement that is not a time (an
 * error, a count, a deflection) as an extra numeric field `key` of the
 * benchmark entry `bench` (its iteration and aggregate entries; stddev 0).
 * When no tb_suite_bench of that name came before, the entry holds only
 * counters: one iteration with real_time and cpu_time 0 (unit "s").
 * Keys must not be one of the entry's own fields (name, real_time, ...). */
void tb_suite_counter(tb_suite *s, const char *bench, const char *key, double value);
/* An estimate as three counters: key (the median), key_low and key_high
 * (its 95% interval). */
void tb_suite_counter_est(tb_suite *s, const char *bench, const char *key, tb_est e);
/* Writes <dir>/<csv_name>: a header line, then body (free-form rows, for
 * charts). */
int tb_suite_write_data(tb_suite *s, const char *csv_name, const char *header, const char *body,
                        tb_error *err);
/* Runs gnuplot on scripts/<script> with variables datafile (path inside the
 * suite folder), outbase and suitedir (the suite folder, ending in '/', for
 * the other files a script reads); produces <dir>/<outbase>.png and .svg, linked
 * from table.md. A missing gnuplot, script or data file, or a failing
 * script, is an error. */
int tb_suite_chart(tb_suite *s, const char *script, const char *datafile, const char *outbase,
                   tb_error *err);
/* The same with more gnuplot -e assignments, e.g. "title='Solve'; logy=1"
 * (scripts/chart_lines.gp reads title, xlabel, ylabel, logx, logy, points, fitfile,
 * paperfile, paperpanel, ...: see its head). */
int tb_suite_chart_vars(tb_suite *s, const char *script, const char *datafile, const char *outbase,
                        const char *vars, tb_error *err);
/* A picture already in the suite folder (a rendered frame, a photo: PNG,
 * SVG, ...), shown in table.md and REPORT.md where it was added, with the
 * caption made from fmt (NULL: none). A file name that is absolute, holds
 * "..", or names no file is a misuse reported by tb_suite_end. */
void tb_suite_figure(tb_suite *s, const char *file, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* The caption of the chart (its outbase) or figure (its file) called name:
 * one sentence saying what it shows, under the picture in table.md and
 * REPORT.md. No chart or figure of that name is a misuse. */
void tb_suite_caption(tb_suite *s, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Writes table.md, table-<name>.csv per table, data.json; frees s. Also returns the first
 * misuse recorded during the run (the files are still written). */
int tb_suite_end(tb_suite *s, tb_error *err);

/* ---- a sweep split over machines: cases (report/results_shard.c) ----
 * A suite whose work is a list of independent cases (one model run, one map
 * cell) asks for each by a key unique in its folder (at most TB_CASE_KEY/3
 * characters) and keeps the case's outcome in a tb_case: the numbers and
 * short texts its tables, charts and notes are made from. Then
 * `reproduce --shard k/N` runs every N-th case of the run, and `merge` makes
 * the suite's results from the shards' outcomes with the suite's own code.
 * tb_suite_case returns:
 *   TB_CASE_RUN    run the case: fill c, then tb_suite_case_done(s, c);
 *   TB_CASE_KNOWN  c holds the outcome a shard saved (merge);
 *   TB_CASE_SKIP   another shard runs it (or a misuse, reported by
 *                  tb_suite_end): c is empty, leave the case out.
 * every = 1: a case every shard needs (a reference the others compare
 * with) runs on every shard. In a shard, the suite's tables, charts and
 * data files are dropped: tb_suite_end writes only <dir>/cases.ini. */
#define TB_CASE_VALUES 64
#define TB_CASE_TEXTS 24
#define TB_CASE_TEXT 200
#define TB_CASE_KEY 240
enum { TB_CASE_RUN = 0, TB_CASE_KNOWN = 1, TB_CASE_SKIP = 2 };
typedef struct tb_case {
  int nv, nt;
  double v[TB_CASE_VALUES];
  char t[TB_CASE_TEXTS][TB_CASE_TEXT];
} tb_case;
int tb_suite_case(tb_suite *s, const char *key, int every, tb_case *c);
void tb_suite_case_done(tb_suite *s, const tb_case *c);

/* The process's mode (`reproduce` and `merge` set it): shard k of n, the
 * suites writing under root; replay (merge) with the outcomes that
 * tb_shard_load reads from a shard's <root>/<folder>/cases.ini; reset:
 * every case runs. */
int tb_shard_set(int k, int n, const char *root, tb_error *err);
int tb_shard_replay(const char *root, tb_error *err);
int tb_shard_load(const char *path, const char *folder, int shard, tb_error *err);
void tb_shard_reset(void);
int tb_shard_active(void); /* 1 in shard mode */

/* ---- the run's report: <dir>/REPORT.md ----
 * One document for a whole `reproduce`: the run's context once at the top,
 * then every suite's notes, tables, charts and figures (with captions) in
 * the documents' order, chapter by chapter, links relative to <dir>.
 * While a report is open, every suite ended (tb_suite_end) in a folder
 * inside <dir> hands it its body; tb_report_end lays them out in the order
 * of the tb_report_chapter / tb_report_suite calls. One report at a time. */
typedef struct tb_report tb_report;
/* NULL (err set) when dir cannot be created, a report is already open, or
 * no memory. title: the document's heading. */
tb_report *tb_report_begin(const char *dir, const char *title, uint64_t seed, tb_error *err);
/* A chapter heading with an optional paragraph (NULL) under it; a chapter
 * none of whose suites ran is left out. */
void tb_report_chapter(tb_report *r, const char *heading, const char *intro);
/* Whether a suite ran, failed or was not run (listed at the top). */
enum { TB_REPORT_DONE = 0, TB_REPORT_FAILED = 1, TB_REPORT_NOT_RUN = 2 };
/* The suite whose folder is <dir>/<folder> (or under it, e.g. pareto/liver)
 * goes here, captioned with summary. */
void tb_report_suite(tb_report *r, const char *folder, const char *summary, int status);
/* A suite's body that a shard wrote (`reproduce --shard`: a whole suite
 * in <its folder>/report-section.md, TB_REPORT_SECTION), placed as the
 * suite folder `folder` (relative to the report's). */
#define TB_REPORT_SECTION "report-section.md"
int tb_report_section_file(tb_report *r, const char *path, const char *folder, tb_error *err);
/* Writes <dir>/REPORT.md, closes and frees r (also on error). */
int tb_report_end(tb_report *r, tb_error *err);

/* ---- progress on stderr (only when it is a terminal) ----
 * One line redrawn with '\r': label, bar, percent, done/total, the time
 * elapsed and an estimate of the time left; the line ends when done ==
 * total. A run of the bar begins with a new label (or done going back) and
 * keeps its first total: a later call with another total is scaled to it,
 * so the bar never jumps (pass total, total at the end). total <= 0: the
 * total is unknown; the line shows the count and the time, no estimate,
 * and tb_progress_done ends it. */
void tb_progress(const char *label, long done, long total);
/* Ends the current line (a run whose total was unknown). */
void tb_progress_done(void);
/* A heartbeat from inside a long item (call it between sub-steps, e.g.
 * every time step or Newton iteration): redraws the current line, at most
 * four times a second, with the time so far and a note from fmt, e.g.
 * "step %ld/%ld". Cheap: nothing when stderr is not a terminal or no bar
 * runs, else a clock read; fmt is formatted only when the line is drawn.
 * NULL fmt keeps the last note. A note lasts until the next item. */
void tb_progress_tick(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* The pieces of the above, for tests. A run of the bar: */
typedef struct tb_progress_run {
  char label[64];
  char note[64];
  long done, total; /* total <= 0: unknown */
  double start;     /* seconds (any clock) when the run began */
  double t_done;    /* seconds since start when done last grew */
  double last_draw; /* seconds since start of the last redraw, < 0 never */
  int active;
} tb_progress_run;
/* Feeds a tb_progress call made at time now (seconds); returns 1 when the
 * line should be redrawn (a new run, done grew past a tenth of a percent,
 * the end, or a quarter second since the last redraw), else 0. */
int tb_progress_update(tb_progress_run *r, const char *label, long done, long total, double now);
/* Formats r's line at time now (no '\r', no newline) into buf; returns
 * buf. Left (tb_progress_eta): unknown before the first item is done; then
 * the time an item times the items after the current one, plus what the
 * current one has left of that time; the time an item: the finished
 * items' mean, or elapsed / (done + 1) when larger (a slow current item
 * raises the estimate instead of leaving it at zero). */
const char *tb_progress_format(char *buf, size_t cap, const tb_progress_run *r, double now);
/* The estimated seconds left at time now (the clock of start), < 0 when
 * unknown. */
double tb_progress_eta(const tb_progress_run *r, double now);

#endif
