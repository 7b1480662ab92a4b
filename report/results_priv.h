/* Private to the results writer (core/results*.c): the layout of tables
 * and suites, and the helpers its files share. Not for suites: use
 * tb_results.h. */
#ifndef TB_RESULTS_PRIV_H
#define TB_RESULTS_PRIV_H

#include <stdio.h>

#include "tb_results.h"

struct tb_table {
  char *name, *title;
  int ncols, nrows, cap_rows, next; /* next: column of the next cell */
  char **cols;
  char **csv_cols;      /* the CSV's header when it differs, else NULL */
  unsigned char *only;  /* per column: 0, TB_MD_ONLY or TB_CSV_ONLY */
  char **cells;         /* nrows * ncols, NULL when empty */
  double *vals;         /* nrows * ncols: a numeric cell's value for the CSV */
  unsigned char *isnum; /* nrows * ncols: 1 for tb_table_num cells */
  char err[200];
};

/* A cell's text, "" when it was never set. */
static inline const char *tb_results_cell(const tb_table *t, int r, int j) {
  const char *c = t->cells[(size_t)r * (size_t)t->ncols + (size_t)j];
  return c ? c : "";
}

/* What table.md holds, in order. */
enum { TB_ITEM_NOTE, TB_ITEM_TABLE, TB_ITEM_CHART, TB_ITEM_FIGURE };
typedef struct tb_results_item {
  int kind;
  char *text; /* a note's text, a chart's outbase, or a figure's file name */
  tb_table *table;
  char *caption; /* a chart's or figure's caption, NULL when none */
} tb_results_item;

typedef struct tb_results_bench {
  char *name;
  const char *unit; /* one of "ns", "us", "ms", "s" */
  int n;            /* 0: counters only */
  int threads;      /* in effect when it was added */
  double *real, *cpu;
  int ncounters, cap_counters;
  char **keys;
  double *counters;
} tb_results_bench;

/* A case that ran here (report/results_shard.c). */
typedef struct tb_results_case {
  char key[TB_CASE_KEY];
  int every, done;
  tb_case c;
} tb_results_case;

struct tb_suite {
  char *dir, *name, *title;
  char exe[512];
  tb_context ctx;
  tb_noise_mark start; /* the machine's load at tb_suite_begin */
  tb_results_item *items;
  int nitems, cap_items;
  tb_results_bench *benches;
  int nbenches, cap_benches;
  char err[400]; /* the first misuse, reported by tb_suite_end */
  /* cases (shard mode: the outcomes that ran here, for cases.ini) */
  tb_results_case *cases;
  int ncases, cap_cases;
  int used_cases; /* asked for a case in shard mode: the tables are partial */
  int case_open;  /* 1 while the case case_key runs (until tb_suite_case_done) */
  char case_key[TB_CASE_KEY];
};

/* report/results.c */
char *tb_results_dup(const char *s);
char *tb_results_join(const char *dir, const char *name); /* dir/name, malloc'd */
/* Grows an array to hold `need` elements; NULL (old array intact) when out
 * of memory. */
void *tb_results_grow(void *p, int *cap, int need, size_t size);
/* Appends to table.md's items (takes text and t); -1 when out of memory. */
int tb_results_add(tb_suite *s, int kind, char *text, tb_table *t);
/* mkdir -p dir. */
int tb_results_make_dirs(const char *dir, tb_error *err);
/* Records the first misuse of the run. */
void tb_results_fail(tb_suite *s, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* report/results_files.c: writes table.md, table-<name>.csv and data.json. */
int tb_results_write_files(tb_suite *s, tb_error *err);
/* The run's context as a markdown list (table.md's and REPORT.md's header). */
void tb_results_md_context(FILE *f, const tb_context *c);
/* table.md's body (notes, tables, charts, figures in order): tables headed
 * at `level` ("##" for 2), links prefixed with `prefix` (the suite folder
 * seen from where f lives, "" for table.md), charts shown as <outbase>.<ext>. */
void tb_results_md_body(FILE *f, const tb_suite *s, const char *prefix, int level, const char *ext);

/* report/results_shard.c: writes <dir>/cases.ini (shard mode). */
int tb_results_shard_write(tb_suite *s, tb_error *err);
/* 1 when s is a sharded suite's partial run: no tables, charts or files. */
static inline int tb_results_partial(const tb_suite *s) {
  return tb_shard_active() && s->used_cases;
}

/* report/results_report.c: hands a finished suite to the open report, if
 * any, when its folder lies inside the report's. */
void tb_results_report_add(const tb_suite *s);

#endif
