/* The command line: one table of subcommands; each takes argc/argv after
 * its name and returns the process exit code (0 ok, 1 failed, 2 bad input). */
#ifndef TB_CLI_H
#define TB_CLI_H

#include <stdint.h>

#include "tb_error.h"

typedef struct tb_command {
  const char *name;
  const char *summary;
  const char *usage; /* printed by --help */
  int (*run)(int argc, char **argv);
} tb_command;

/* Real data from the field, read at run time when present. */
#define TB_SHARED_DATA TB_SOURCE_ROOT "/../shared/data"
/* The 40 designed triangle pairs (thesis §4.4.2; ours, hand-verified). */
#define TB_DESIGNED_PAIRS TB_SOURCE_ROOT "/tests/data/designed40.txt"

/* Exit codes. */
enum { TB_EXIT_OK = 0, TB_EXIT_FAIL = 1, TB_EXIT_INPUT = 2 };

int tb_cmd_mesh(int argc, char **argv);
/* `mesh spheres ...` (bench/cmd_spheres.c); tb_spheres_info prints a .sph file's count, radii
 * and, with a surface (may be NULL), its coverage on a grid of that many points. */
int tb_cmd_mesh_spheres(int argc, char **argv);
int tb_spheres_info(const char *path, const char *surface, int grid);
int tb_cmd_reproduce(int argc, char **argv);
int tb_cmd_table(int argc, char **argv);
int tb_cmd_figure(int argc, char **argv);
int tb_cmd_tritri(int argc, char **argv);
int tb_cmd_collide(int argc, char **argv);
int tb_cmd_simulate(int argc, char **argv);
int tb_cmd_render(int argc, char **argv);
int tb_cmd_advise(int argc, char **argv);

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
/* The suites, in the order they run (bench/cmd_reproduce.c). */
const tb_suite_entry *tb_suites(int *n);
/* Is name in the comma-separated list? */
int tb_suite_listed(const char *list, const char *name);
/* Places the suites in REPORT.md in the documents' order, status[s] for
 * suite s (TB_REPORT_*), and writes it (tb_report_end). */
int tb_reproduce_report(struct tb_report *r, const int *status);

/* ---- sweeps across machines (bench/cmd_merge.c) ----
 * `reproduce --shard k/N` writes <results>/shard.ini: the run's options and
 * commit, and each suite's status; `merge` checks that N such folders fit
 * together and makes one results folder of them. */
#define TB_SHARD_SUITES 64
enum { TB_SHARD_NOT_RUN = 0, TB_SHARD_DONE, TB_SHARD_FAILED, TB_SHARD_ELSEWHERE };
typedef struct tb_shard_info {
  int k, n, full;
  double scale;
  uint64_t seed;
  char commit[48];
  char only[512], model[64], scene[256]; /* "" when not given */
  int status[TB_SHARD_SUITES];           /* per suite of tb_suites(), TB_SHARD_* */
} tb_shard_info;
int tb_shard_info_write(const char *dir, const tb_shard_info *s, tb_error *err);
int tb_shard_info_read(const char *dir, tb_shard_info *s, tb_error *err);
int tb_cmd_merge(int argc, char **argv);

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

/* Helpers shared by the commands (bench/cli.c). */
/* main.c's command table, for the usage printed with option errors. */
void tb_cli_set_commands(const tb_command *c, int n);
int tb_cli_has_help(int argc, char **argv);
/* Parses a finite double; returns 0 or prints an error (not a number, or
 * out of range) and -1. */
int tb_cli_parse_double(const char *what, const char *text, double *out);
/* Prints "tissuebench CMD: unknown or incomplete option 'ARG'" and CMD's
 * usage; returns TB_EXIT_INPUT. */
int tb_cli_bad_option(const char *cmd, const char *arg);
/* TB_EXIT_INPUT (message naming the option, and the usage) when an option
 * "--NAME" appears twice among argv[1..argc-1] (--set may repeat, with
 * another KEY each time), else 0.
 * main.c runs it for every command. */
int tb_cli_check_repeats(const char *cmd, int argc, char **argv);

#endif
