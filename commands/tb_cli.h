/* The command line: one table of subcommands; each takes argc/argv after
 * its name and returns the process exit code (0 ok, 1 failed, 2 bad input). */
#ifndef TB_CLI_H
#define TB_CLI_H

#include <stdint.h>
#include <stdio.h>

#include "core/tb_error.h"
#include "measure/tb_points.h"
#include "scenes/tb_sim.h"
#include "suites/tb_suites.h"

typedef struct tb_command {
  const char *name;
  const char *summary;
  const char *usage; /* printed by --help */
  int (*run)(int argc, char **argv);
  void (*lists)(FILE *f); /* --help's lists from the registries (suites, scenes, ...), or NULL */
} tb_command;

/* Exit codes: 1 a failure or an unstable run, 2 bad input, 3 a run that
 * ended degraded (tb_sim_degraded). */
enum { TB_EXIT_OK = 0, TB_EXIT_FAIL = 1, TB_EXIT_INPUT = 2, TB_EXIT_DEGRADED = 3 };

int tb_cmd_mesh(int argc, char **argv);
/* `mesh spheres ...` (commands/cmd_spheres.c); tb_spheres_info prints a .sph file's count, radii
 * and, with a surface (may be NULL), its coverage on a grid of that many points. */
int tb_cmd_mesh_spheres(int argc, char **argv);
int tb_spheres_info(const char *path, const char *surface, int grid);
/* `mesh tetrahedralize ...` and `mesh close ...` (commands/cmd_mesh_tets.c). */
int tb_cmd_mesh_tetrahedralize(int argc, char **argv);
int tb_cmd_mesh_close(int argc, char **argv);
int tb_cmd_reproduce(int argc, char **argv);
int tb_cmd_table(int argc, char **argv);
int tb_cmd_figure(int argc, char **argv);
int tb_cmd_tritri(int argc, char **argv);
int tb_cmd_collide(int argc, char **argv);
int tb_cmd_simulate(int argc, char **argv);
int tb_cmd_render(int argc, char **argv);
int tb_cmd_advise(int argc, char **argv);

/* ---- sweeps across machines (commands/cmd_merge.c) ----
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

/* `simulate --json FILE` (commands/simulate_json.c): the summary simulate prints, for programs:
 * the status ("stable", "degraded", "unstable") and its reason, the times per step, and, when
 * the run ended (have_metrics), the final state. */
typedef struct tb_run_summary {
  const char *status, *reason;
  long steps;
  double cpu_ms, wall_ms, cpu_min_ms, cpu_max_ms;
  int have_metrics;
  tb_sim_metrics m;
  int rest;
  double speed, rest_tol;
} tb_run_summary;
int tb_simulate_json(const char *path, const tb_sim *s, const tb_run_summary *r, tb_error *err);

/* advise's choice: with tol > 0, among usable points with rms_err <= tol
 * (and ms_step <= budget_ms when budget_ms > 0) the fastest (ties: the
 * smaller error, then the earlier row); with only budget_ms > 0, among usable
 * points with ms_step <= budget_ms the most accurate (ties: the faster,
 * then the earlier row). Returns the index or -1 when none qualifies. */
int tb_advise_pick(const tb_point *p, int n, double tol, double budget_ms);
/* Helpers shared by the commands (commands/cli.c). */
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
