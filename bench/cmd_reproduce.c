/* `tissuebench reproduce`: runs the reproduction suites, each writing
 * results/<suite>/ through the results pipeline (core/tb_results.h), then
 * results/REPORT.md gathering them in the documents' order; and
 * `tissuebench table NAME`: one suite by the name of the table it makes.
 * A suite is one entry of the table below.
 * `--shard k/N` runs a share of the work for `merge` (bench/cmd_merge.c):
 * of a suite made of cases, every N-th case (counted over the run); of the
 * others, every N-th suite whole (counted over the suites that run). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "tb_results.h"
#include "tb_timer.h"

static const tb_suite_entry suites[] = {
    {"meshes", "meshes", NULL,
     "generated meshes: counts beside the documents' (thesis §2.5, Bao 2006)", tb_suite_meshes, 0},
    {"correctness", "correctness", NULL,
     "triangle tests: wrong answers against the exact oracle, per family of pairs",
     tb_suite_correctness, 0},
    {"table-4.1", "4.1", NULL,
     "thesis table 4.1: time for 0.1-2 million tests; ns/pair on the JGT pairs", tb_suite_table41,
     0},
    {"table-4.2", "4.2", NULL,
     "thesis table 4.2: queries/s against intersecting pairs, liver against instrument",
     tb_suite_table42, 0},
    {"refit", "refit", NULL, "the deforming liver: refit, rebuild, FCL refit, Bullet update, query",
     tb_suite_refit, 0},
    {"table-3.5", "3.5", NULL,
     "thesis §3.5: steps/s of msm, fem, fem-corot, sm on the liver; recovery after a far stretch",
     tb_suite_table35, 0},
    {"figure-3.10", NULL, "3.10",
     "thesis fig. 3.10: shape-matching time per frame against particles, clusters, variant",
     tb_suite_fig310, 0},
    {"reference", "reference", NULL,
     "the reference solver's refinement study: cantilever T4/T10 against beam theory",
     tb_suite_reference, 0},
    {"calibration", "calibration", NULL,
     "model parameters fitted to the reference solution; errors with documents' vs fitted values",
     tb_suite_calibration, 0},
    {"pareto", NULL, "pareto",
     "error against the reference vs steps/s: every model x resolution x key parameter (--scene)",
     tb_suite_pareto, 1},
    {"stability", NULL, "stability",
     "stable/unstable over dt x stiffness per model (--model); large-deformation tests",
     tb_suite_stability, 1},
    {"pbd-stiffness", NULL, "pbd-stiffness",
     "PBD and XPBD: the beam's static sag under gravity over the material's, against "
     "iterations and dt",
     tb_suite_pbd_stiffness, 1},
    {"pbd", "pbd", NULL,
     "2022 patent tables 1-2: pbd-stvk solve time per step and element on 596-12829-tet livers "
     "dropped on a ground, 1 vs all threads (bit-identical?), Bullet btSoftBody beside it",
     tb_suite_pbd, 0},
    {"bao", "bao", NULL,
     "Bao 2006 table 1 and figs 6-8: msm-vvs on the sphere, base vs fully subdivided vs locally "
     "refined (time, accuracy), the conventional and the improved model pressed and released",
     tb_suite_bao, 0},
    {"metaball", "metaball", "metaball",
     "metaball patent tables 1-2 and figs 7-10: organs of spheres driven by PBD, deform and cut "
     "ms per frame, re-packing, convergence against the tet models, the speed goal",
     tb_suite_metaball, 0},
    {"scaling", NULL, "scaling",
     "ms per step against mesh size (600 to 100k+ tets) for every model of the table, fitted "
     "exponents, 30/300 Hz limits, peak RSS per tet, 1 vs all threads, collision refit + query",
     tb_suite_scaling, 1},
    {"figures", NULL, "pictures",
     "the documents' pictures rendered: figs. 2.15, 3.11-3.15, 4.21, 5.5-5.7", tb_suite_figures, 0},
};
static const int nsuites = (int)(sizeof suites / sizeof suites[0]);

const tb_suite_entry *tb_suites(int *n) {
  *n = nsuites;
  return suites;
}

/* REPORT.md's order, the documents': the thesis' chapter 2 (meshes), its
 * chapter 3 (deformation: its table and figure, then our reference, the
 * calibration against it, the error/speed trade-off, stability), its
 * chapter 4 (collision: correctness first, then its tables, then the
 * deforming liver); then the 2022 patent's performance tables; then Bao
 * 2006's sphere (its table 1, figs 6-8); then the metaball patent's organs
 * (its tables 1-2, figs 7-10); then how every model and the collision
 * hierarchy scale with the mesh. A chapter
 * is a heading then suite names; every suite above appears once
 * (tests/test_cli.c checks through --only). */
static const char *const report_order[] = {
    "#Chapter 2: meshes",
    "meshes",
    "#Chapter 3: deformation",
    "table-3.5",
    "figure-3.10",
    "reference",
    "calibration",
    "pareto",
    "stability",
    "#Chapter 4: collision detection",
    "correctness",
    "table-4.1",
    "table-4.2",
    "refit",
    "#2022 patent: position-based dynamics, a liver dropped on a rigid ground",
    "pbd",
    "pbd-stiffness",
    "#Bao 2006: a surface mass-spring model with virtual volumetric springs and local refinement",
    "bao",
    "#The metaball patent: organs of overlapping spheres, PBD, hybrid sphere - point set cutting",
    "metaball",
    "#Scaling: every model and the collision hierarchy against mesh size",
    "scaling",
    "#Pictures: the documents' figures, rendered",
    "figures",
};

int tb_reproduce_report(tb_report *r, const int *status) {
  for (size_t k = 0; k < sizeof report_order / sizeof report_order[0]; k++) {
    const char *e = report_order[k];
    if (e[0] == '#') {
      tb_report_chapter(r, e + 1, NULL);
      continue;
    }
    for (int s = 0; s < nsuites; s++)
      if (!strcmp(suites[s].name, e)) tb_report_suite(r, e, suites[s].summary, status[s]);
  }
  tb_error err = {{0}};
  if (tb_report_end(r, &err)) {
    fprintf(stderr, "tissuebench reproduce: %s\n", err.msg);
    return 1;
  }
  return 0;
}

int tb_suite_listed(const char *list, const char *name) {
  size_t n = strlen(name);
  for (const char *p = list; p && *p;) {
    const char *c = strchr(p, ',');
    size_t len = c ? (size_t)(c - p) : strlen(p);
    if (len == n && !strncmp(p, name, n)) return 1;
    p = c ? c + 1 : NULL;
  }
  return 0;
}

int tb_cmd_reproduce(int argc, char **argv) {
  tb_suite_opts o = {0, 1.0, 1, TB_SOURCE_ROOT "/results", NULL, NULL};
  const char *only = NULL;
  int shard_k = 0, shard_n = 0;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    if (!strcmp(a, "--quick"))
      o.full = 0;
    else if (!strcmp(a, "--full"))
      o.full = 1;
    else if (!strcmp(a, "--list")) {
      for (int s = 0; s < nsuites; s++) printf("%-12s %s\n", suites[s].name, suites[s].summary);
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
  if (only) { /* every listed name must be a suite; no empty list or item */
    for (const char *p = only;;) {
      const char *c = strchr(p, ',');
      size_t len = c ? (size_t)(c - p) : strlen(p);
      if (!len) {
        fprintf(stderr, "tissuebench reproduce: --only '%s': an empty suite name (--list)\n", only);
        return TB_EXIT_INPUT;
      }
      int found = 0;
      for (int s = 0; s < nsuites; s++)
        found |= strlen(suites[s].name) == len && !strncmp(suites[s].name, p, len);
      if (!found) {
        fprintf(stderr, "tissuebench reproduce: unknown suite '%.*s' (--list)\n", (int)len, p);
        return TB_EXIT_INPUT;
      }
      if (!c) break;
      p = c + 1;
    }
  }
  int failed = 0, status[sizeof suites / sizeof suites[0]];
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

/* `table NAME` / `figure NAME` [options]: reproduce --only the suite that
 * makes it. */
static int run_alias(const char *kind, int argc, char **argv) {
  int fig = !strcmp(kind, "figure");
  if (argc < 2 || argv[1][0] == '-') {
    fprintf(stderr, "usage: tissuebench %s NAME [--quick|--full] [--seed N] [--results DIR]\n",
            kind);
    for (int s = 0; s < nsuites; s++) {
      const char *alias = fig ? suites[s].figure : suites[s].table;
      if (alias) fprintf(stderr, "  %-12s %s\n", alias, suites[s].summary);
    }
    return TB_EXIT_INPUT;
  }
  for (int s = 0; s < nsuites; s++) {
    const char *alias = fig ? suites[s].figure : suites[s].table;
    if (!alias || strcmp(alias, argv[1])) continue;
    char *args[64];
    int n = 0;
    args[n++] = "reproduce";
    args[n++] = "--only";
    args[n++] = (char *)suites[s].name;
    for (int i = 2; i < argc; i++) {
      if (!strcmp(argv[i], "--only") || n == 63) /* the alias is the --only */
        return tb_cli_bad_option(kind, argv[i]);
      args[n++] = argv[i];
    }
    args[n] = NULL;
    return tb_cmd_reproduce(n, args);
  }
  fprintf(stderr, "tissuebench %s: unknown %s '%s' (tissuebench %s lists them)\n", kind, kind,
          argv[1], kind);
  return TB_EXIT_INPUT;
}

int tb_cmd_table(int argc, char **argv) { return run_alias("table", argc, argv); }
int tb_cmd_figure(int argc, char **argv) { return run_alias("figure", argc, argv); }
