/* Option handling shared by every subcommand (commands/tb_cli.h): --help, a
 * strict number, the message for an unknown option (with the command's
 * usage), and the check that no option is given twice. The usage texts
 * live in main.c's command table, registered at start-up with
 * tb_cli_set_commands (the tests call commands without it: they get a
 * pointer to --help instead). */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"

static const tb_command *commands;
static int ncommands;

void tb_cli_set_commands(const tb_command *c, int n) { commands = c, ncommands = n; }

int tb_cli_has_help(int argc, char **argv) {
  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) return 1;
  return 0;
}

int tb_cli_parse_double(const char *what, const char *text, double *out) {
  char *end;
  errno = 0;
  double v = strtod(text, &end);
  if (end == text || *end || isnan(v)) {
    fprintf(stderr, "tissuebench: %s: not a number: '%s'\n", what, text);
    return -1;
  }
  if (!isfinite(v) || (errno == ERANGE && fabs(v) > 1)) {
    fprintf(stderr, "tissuebench: %s: '%s' is out of range (a finite double)\n", what, text);
    return -1;
  }
  *out = v;
  return 0;
}

/* The usage of command `cmd` (its first word: "mesh" for "mesh list"). */
static void print_usage(const char *cmd) {
  size_t n = strcspn(cmd, " ");
  for (int i = 0; i < ncommands; i++)
    if (strlen(commands[i].name) == n && !strncmp(commands[i].name, cmd, n)) {
      fprintf(stderr, "usage: %s\n", commands[i].usage);
      return;
    }
  fprintf(stderr, "(tissuebench %.*s --help shows the options)\n", (int)n, cmd);
}

int tb_cli_bad_option(const char *cmd, const char *arg) {
  fprintf(stderr, "tissuebench %s: unknown or incomplete option '%s'\n", cmd, arg);
  print_usage(cmd);
  return TB_EXIT_INPUT;
}

/* Is argv[i] "--set KEY=..." with a KEY an earlier --set gave? */
static int set_key_again(int i, char **argv) {
  if (strcmp(argv[i], "--set") || !argv[i + 1]) return 0;
  size_t n = strcspn(argv[i + 1], "=");
  for (int j = 1; j < i; j++)
    if (!strcmp(argv[j], "--set") && !strncmp(argv[j + 1], argv[i + 1], n) &&
        (argv[j + 1][n] == '=' || !argv[j + 1][n]))
      return 1;
  return 0;
}

int tb_cli_check_repeats(const char *cmd, int argc, char **argv) {
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (i + 1 < argc && set_key_again(i, argv)) {
      fprintf(stderr, "tissuebench %s: --set %.*s given twice\n", cmd,
              (int)strcspn(argv[i + 1], "="), argv[i + 1]);
      print_usage(cmd);
      return TB_EXIT_INPUT;
    }
    if (strncmp(a, "--", 2) || !a[2] || !strcmp(a, "--set")) continue;
    for (int j = 1; j < i; j++)
      if (!strcmp(argv[j], a)) {
        fprintf(stderr, "tissuebench %s: %s given twice (give each option once)\n", cmd, a);
        print_usage(cmd);
        return TB_EXIT_INPUT;
      }
  }
  return 0;
}
