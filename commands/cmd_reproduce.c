/* `tissuebench reproduce`: runs the reproduction suites (suites/suites.c),
 * each writing results/<suite>/ through the results pipeline
 * (report/tb_results.h), then results/REPORT.md gathering them in the
 * documents' order; and `tissuebench table NAME` / `figure NAME`: one suite
 * by the name of the table or figure it makes.
 * `--shard k/N` runs a share of the work for `merge` (commands/cmd_merge.c):
 * of a suite made of cases, every N-th case (counted over the run); of the
 * others, every N-th suite whole (counted over the suites that run). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "core/tb_paths.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"
#include "suites/tb_suites.h"

int tb_cmd_reproduce(int argc, char **argv) {
  int nsuites;
  const tb_suite_entry *suites = tb_suites(&nsuites);
  tb_suite_opts o = {0, 1.0, 1, tb_results_dir(), NULL, NULL};
  const char *only = NULL;
  int shard_k = 0, shard_n = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--quick"))
      o.full = 0;
    else if (!strcmp(a, "--full"))
      o.full = 1;
    else if (!strcmp(a, "--list")) {
      tb_suites_print(stdout);
      return TB_EXIT_OK;
    } else if (!strcmp(a, "--only") && i + 1 < argc)
      only = argv[++i];
    else if (!strcmp(a, "--results") && i + 1 < argc)
      o.results = argv[++i];
    else if (!strcmp(a, "--model") && i + 1 < argc)
      o.model = argv[++i];
    else if (!strcmp(a, "--scene") && i + 1 < argc)
      o.scene = argv[++i];
    else if (!strcmp(a, "--scale") && i + 1 < argc) {
      double v;
      if (tb_cli_parse_double("--scale", argv[++i], &v)) return TB_EXIT_INPUT;
      if (!(v > 0 && v <= 100)) {
        fprintf(stderr, "tissuebench reproduce: --scale must be in (0, 100]\n");
        return TB_EXIT_INPUT;
      }
      o.scale = v;
    } else if (!strcmp(a, "--shard") && i + 1 < argc) {
      const char *v = argv[++i];
      char *slash, *end;
      long k = strtol(v, &slash, 10), n = *slash == '/' ? strtol(slash + 1, &end, 10) : 0;
      if (slash == v || *slash != '/' || end == slash + 1 || *end || n < 1 || n > 10000 || k < 1 ||
          k > n) {
        fprintf(stderr,
                "tissuebench reproduce: --shard needs k/N with 1 <= k <= N <= 10000, "
                "got '%s'\n",
                v);
        return TB_EXIT_INPUT;
      }
      shard_k = (int)k, shard_n = (int)n;
    } else if (!strcmp(a, "--seed") && i + 1 < argc) {
      char *end;
      unsigned long long s = strtoull(argv[++i], &end, 10);
      if (*end || end == argv[i]) {
        fprintf(stderr, "tissuebench reproduce: --seed needs a whole number\n");
        return TB_EXIT_INPUT;
      }
      o.seed = s;
    } else
      return tb_cli_bad_option("reproduce", a);
  }
  char canon[512] = "";
  if (only) { /* every listed name must be a suite (or its alias); no empty list or item */
    size_t used = 0;
    for (const char *p = only;;) {
      const char *c = strchr(p, ',');
      size_t len = c ? (size_t)(c - p) : strlen(p);
      if (!len) {
        fprintf(stderr, "tissuebench reproduce: --only '%s': an empty suite name (--list)\n", only);
        return TB_EXIT_INPUT;
      }
      int s = tb_suite_find(p, len);
      if (s < 0) {
        fprintf(stderr, "tissuebench reproduce: unknown suite '%.*s' (--list)\n", (int)len, p);
        return TB_EXIT_INPUT;
      }
      int n = snprintf(canon + used, sizeof canon - used, "%s%s", used ? "," : "", suites[s].name);
      if (n < 0 || (size_t)n >= sizeof canon - used) {
        fprintf(stderr, "tissuebench reproduce: --only: too many suites\n");
        return TB_EXIT_INPUT;
      }
      used += (size_t)n;
      if (!c) break;
      p = c + 1;
    }
    only = canon;
  }
  int failed = 0, status[TB_SHARD_SUITES];
  tb_error err = {{0}};
  tb_shard_info info;
  memset(&info, 0, sizeof info);
  if (shard_n) {
    if (tb_shard_set(shard_k, shard_n, o.results, &err)) {
      fprintf(stderr, "tissuebench reproduce: %s\n", err.msg);
      return TB_EXIT_FAIL;
    }
    info.k = shard_k, info.n = shard_n, info.full = o.full, info.scale = o.scale,
    info.seed = o.seed;
    snprintf(info.only, sizeof info.only, "%s", only ? only : "");
    snprintf(info.model, sizeof info.model, "%s", o.model ? o.model : "");
    snprintf(info.scene, sizeof info.scene, "%s", o.scene ? o.scene : "");
  }
  tb_report *report = tb_report_begin(o.results, "tissuebench: the reproduction", o.seed, &err);
  if (!report) fprintf(stderr, "tissuebench reproduce: no REPORT.md: %s\n", err.msg);
  uint64_t t0 = tb_time_ns();
  for (int s = 0, pos = 0; s < nsuites; s++) {
    status[s] = TB_REPORT_NOT_RUN;
    if (only && !tb_suite_listed(only, suites[s].name)) continue;
    if (shard_n && !suites[s].cases && pos++ % shard_n != shard_k - 1) {
      info.status[s] = TB_SHARD_ELSEWHERE; /* a whole suite another shard runs */
      continue;
    }
    fprintf(stderr, "== %s (%s)\n", suites[s].name, o.full ? "full" : "quick");
    uint64_t ts = tb_time_ns();
    int rc = suites[s].run(&o);
    fprintf(stderr, "== %s: %s in %.1f s -> %s/%s/\n", suites[s].name, rc ? "FAILED" : "done",
            (double)(tb_time_ns() - ts) * 1e-9, o.results, suites[s].name);
    failed += rc != 0;
    status[s] = rc ? TB_REPORT_FAILED : TB_REPORT_DONE;
    info.status[s] = rc ? TB_SHARD_FAILED : TB_SHARD_DONE;
  }
  if (shard_n) {
    tb_shard_reset();
    if (tb_shard_info_write(o.results, &info, &err)) {
      fprintf(stderr, "tissuebench reproduce: %s\n", err.msg);
      failed++;
    }
  }
  int no_report = !report || tb_reproduce_report(report, status);
  if (!no_report) fprintf(stderr, "reproduce: report in %s/REPORT.md\n", o.results);
  fprintf(stderr, "reproduce: %d suite(s) failed, %.1f s in all\n", failed,
          (double)(tb_time_ns() - t0) * 1e-9);
  return failed || no_report ? TB_EXIT_FAIL : TB_EXIT_OK;
}

/* `table NAME` / `figure NAME` [options]: reproduce --only the suite of that name (or alias). */
static int run_alias(const char *kind, int argc, char **argv) {
  int nsuites;
  const tb_suite_entry *suites = tb_suites(&nsuites);
  if (argc < 2 || argv[1][0] == '-') {
    fprintf(stderr, "usage: tissuebench %s NAME [--quick|--full] [--seed N] [--results DIR]\n",
            kind);
    tb_suites_print(stderr);
    return TB_EXIT_INPUT;
  }
  int s = tb_suite_find(argv[1], strlen(argv[1]));
  if (s < 0) {
    fprintf(stderr, "tissuebench %s: unknown %s '%s' (tissuebench %s lists them)\n", kind, kind,
            argv[1], kind);
    return TB_EXIT_INPUT;
  }
  char *args[64];
  int n = 0;
  args[n++] = "reproduce";
  args[n++] = "--only";
  args[n++] = (char *)suites[s].name;
  for (int i = 2; i < argc; i++) {
    if (!strcmp(argv[i], "--only") || n == 63) /* the name is the --only */
      return tb_cli_bad_option(kind, argv[i]);
    args[n++] = argv[i];
  }
  args[n] = NULL;
  return tb_cmd_reproduce(n, args);
}

int tb_cmd_table(int argc, char **argv) { return run_alias("table", argc, argv); }
int tb_cmd_figure(int argc, char **argv) { return run_alias("figure", argc, argv); }
