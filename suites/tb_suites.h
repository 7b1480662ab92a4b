/* The reproduction's suites: each writes results/<name>/ (tables, CSVs,
 * charts, data.json) through the results pipeline (results/tb_results.h).
 * The table of suites and REPORT.md's order are in suites/suites.c; the
 * commands `reproduce`, `table` and `figure` run them. */
#ifndef TB_SUITES_H
#define TB_SUITES_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/tb_paths.h"

/* Real data from the field, read at run time when present. */
#define TB_SHARED_DATA_FILE(rel) tb_path_in(tb_shared_data(), rel)
/* The 40 designed triangle pairs (thesis §4.4.2; ours, hand-verified). */
#define TB_DESIGNED_PAIRS tb_path_in(tb_root(), "tests/data/designed40.txt")

/* Options every suite receives. */
typedef struct tb_suite_opts {
  int full;     /* paper scale instead of --quick */
  double scale; /* multiplies pair and test counts (--scale; smoke tests) */
  uint64_t seed;
  const char *results; /* results/ folder */
  const char *model;   /* --model: the suites that take one (NULL: their default) */
  const char *scene;   /* --scene: likewise */
} tb_suite_opts;

/* A suite of the reproduction: writes results/<name>/. Returns 0 or 1. */
typedef struct tb_suite_entry {
  const char *name;   /* results/<name>/ */
  const char *table;  /* `tissuebench table NAME` (NULL: none) */
  const char *figure; /* `tissuebench figure NAME` (NULL: none) */
  const char *summary;
  int (*run)(const tb_suite_opts *opts);
  /* 1: the suite's work is cases (tb_suite_case): with --shard every shard
   * runs its share of them; 0: the whole suite runs on one shard */
  int cases;
} tb_suite_entry;

struct tb_report;
/* The suites, in the order they run (suites/suites.c). */
const tb_suite_entry *tb_suites(int *n);
/* Is name in the comma-separated list? */
int tb_suite_listed(const char *list, const char *name);
/* The suite called name (n characters; its results folder) or aliased so
 * (its table or figure name, e.g. 4.1 for table-4.1): its index in
 * tb_suites(), or -1. */
int tb_suite_find(const char *name, size_t n);
/* Every suite, one line each: its name, its aliases and what it makes. */
void tb_suites_print(FILE *f);
/* Places the suites in REPORT.md in the documents' order, status[s] for
 * suite s (TB_REPORT_*), and writes it (tb_report_end). */
int tb_reproduce_report(struct tb_report *r, const int *status);

int tb_suite_meshes(const tb_suite_opts *opts);
int tb_suite_correctness(const tb_suite_opts *opts);
int tb_suite_table41(const tb_suite_opts *opts);
int tb_suite_table42(const tb_suite_opts *opts);
int tb_suite_refit(const tb_suite_opts *opts);
int tb_suite_table35(const tb_suite_opts *opts);
int tb_suite_fig310(const tb_suite_opts *opts);
int tb_suite_stability(const tb_suite_opts *opts);
int tb_suite_figures(const tb_suite_opts *opts);
int tb_suite_pareto(const tb_suite_opts *opts);
int tb_suite_calibration(const tb_suite_opts *opts);
int tb_suite_reference(const tb_suite_opts *opts);
int tb_suite_pbd_stiffness(const tb_suite_opts *opts);
int tb_suite_pbd(const tb_suite_opts *opts);
int tb_suite_bao(const tb_suite_opts *opts);
int tb_suite_metaball(const tb_suite_opts *opts);
int tb_suite_scaling(const tb_suite_opts *opts);
int tb_suite_cuts(const tb_suite_opts *opts);

#endif
