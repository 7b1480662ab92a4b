/* The command line: one table of subcommands; each takes argc/argv after
 * its name and returns the process exit code (0 ok, 1 failed, 2 bad input). */
#ifndef TB_CLI_H
#define TB_CLI_H

#include <stdint.h>

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
} tb_suite_entry;

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

/* Helpers shared by the commands. */
int tb_cli_has_help(int argc, char **argv);
/* Parses key=value into a double; returns 0 or prints an error and -1. */
int tb_cli_parse_double(const char *what, const char *text, double *out);

#endif
