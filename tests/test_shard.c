/* Sweeps across machines: `reproduce --shard k/N` and `merge` (commands/cmd_merge.c,
 * report/results_shard.c). Three shards run by GNU parallel through
 * scripts/slurm-array.sh, merged, give every non-timing column of an unsharded
 * run; cases.ini keeps every bit of a number and every character of a text;
 * folders that are not the shards of one run are refused. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tb_test.h"
#include "report/tb_results.h"

/* The columns of a CSV line (at most 32, each < 256 characters). */
static int fields(const char *line, char out[32][256]) {
  int n = 0;
  while (n < 32 && tb_test_csv_field(line, n, out[n], sizeof out[n])) n++;
  return n;
}

/* Timing columns (and the front, which ranks by speed) differ between runs. */
static int timing_column(const char *name) {
  return strstr(name, "steps/s") || strstr(name, "ms/step") || !strcmp(name, "front") ||
         strstr(name, "(ms)") || strstr(name, "made (s)");
}

/* Two CSV files equal in every non-timing column, row by row. */
static void same_but_timing(const char *a_path, const char *b_path, int min_rows) {
  char *a = tb_test_slurp(a_path), *b = tb_test_slurp(b_path);
  TB_CHECK_MSG(a && b, "missing %s or %s", a_path, b_path);
  if (!a || !b) {
    free(a), free(b);
    return;
  }
  static char ha[32][256], fa[32][256], fb[32][256];
  char *sa, *sb;
  char *la = strtok_r(a, "\n", &sa), *lb = strtok_r(b, "\n", &sb);
  int nh = la ? fields(la, ha) : 0, rows = 0, diffs = 0;
  TB_CHECK(nh > 3 && lb && !strcmp(la, lb)); /* the same header */
  for (;;) {
    la = strtok_r(NULL, "\n", &sa), lb = strtok_r(NULL, "\n", &sb);
    if (!la || !lb) {
      TB_CHECK_MSG(!la && !lb, "%s and %s have different row counts", a_path, b_path);
      break;
    }
    rows++;
    int na = fields(la, fa), nb = fields(lb, fb);
    TB_CHECK(na == nb);
    for (int j = 0; j < na && j < nb && j < nh; j++)
      if (!timing_column(ha[j]) && strcmp(fa[j], fb[j]) && diffs++ < 5)
        TB_CHECK_MSG(0, "%s row %d column '%s': %s against %s", b_path, rows, ha[j], fa[j], fb[j]);
  }
  TB_CHECK_MSG(rows >= min_rows, "%s: only %d rows", a_path, rows);
  printf("  %d rows of %s equal but for timing\n", rows, b_path);
  free(a), free(b);
}

static int exists(const char *dir, const char *name) {
  char p[2200];
  struct stat sb;
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return stat(p, &sb) == 0;
}

static void merge_equals_unsharded(void) {
  const char *tmp = tb_test_tmpdir(), *root = tb_test_source_root();
  const char *args =
      "--only pareto,stability,pbd-stiffness,scaling,figure-3.10 --scene beam --scale 0.1";
  char cmd[4096], out[8192];
  snprintf(cmd, sizeof cmd, "reproduce %s --results '%s/u' 2>&1", args, tmp);
  TB_CHECK_MSG(tb_test_cli_run(cmd) == 0, "%s", tb_test_out);
  /* the three tasks of a Slurm array, run by GNU parallel, then the merge */
  snprintf(cmd, sizeof cmd,
           "cd '%s' && export TB_SHARDS='%s/shards' TB_BUILD_DIR='%s' && "
           "parallel --will-cite SLURM_ARRAY_TASK_ID={} SLURM_ARRAY_TASK_MIN=0 "
           "SLURM_ARRAY_TASK_COUNT=3 scripts/slurm-array.sh %s ::: 0 1 2 && "
           "scripts/slurm-array.sh --merge 3 --out '%s/m' 2>&1",
           root, tmp, TB_BUILD_ROOT, args, tmp);
  int rc = tb_test_run(cmd, out, sizeof out);
  TB_CHECK_MSG(rc == 0, "%s", out);
  char m[1024], s[1024];
  snprintf(m, sizeof m, "%s/m/pareto/beam", tmp);
  const char *csv[] = {"pareto/beam/table-points.csv", "pareto/beam/points.csv",
                       "pbd-stiffness/table-sag.csv", "scaling/table-collision.csv"};
  const int min_rows[] = {10, 10, 10, 3};
  for (int i = 0; i < 4; i++) {
    char a[1100], b[1100];
    snprintf(a, sizeof a, "%s/u/%s", tmp, csv[i]);
    snprintf(b, sizeof b, "%s/m/%s", tmp, csv[i]);
    same_but_timing(a, b, min_rows[i]);
  }
  /* the stability maps, their bounds and the large deformations have no timing column */
  const char *whole_csv[] = {
      "map_msm.csv",      "table-map_fem-corot_n10.csv", "table-msm_bound_n10.csv",
      "table-deform.csv", "msm-vvs_edges.csv",           "table-map_msm-vvs-euler.csv"};
  for (int i = 0; i < 6; i++) {
    char a[1100], b[1100];
    snprintf(a, sizeof a, "%s/u/stability/%s", tmp, whole_csv[i]);
    snprintf(b, sizeof b, "%s/m/stability/%s", tmp, whole_csv[i]);
    char *ta = tb_test_slurp(a), *tb = tb_test_slurp(b);
    TB_CHECK_MSG(ta && tb && !strcmp(ta, tb), "%s differs from the unsharded run's", b);
    free(ta), free(tb);
  }
  TB_CHECK(exists(m, "pareto.svg") && exists(m, "data.json") && exists(m, "table.md"));
  /* a shard holds only its cases; the whole suite sits on one shard */
  int cases = 0, whole = 0;
  for (int k = 1; k <= 3; k++) {
    snprintf(s, sizeof s, "%s/shards/%d/pareto/beam", tmp, k);
    cases += exists(s, "cases.ini");
    TB_CHECK(!exists(s, "table.md"));
    snprintf(s, sizeof s, "%s/shards/%d/pbd-stiffness", tmp, k);
    cases += exists(s, "cases.ini");
    snprintf(s, sizeof s, "%s/shards/%d/stability", tmp, k);
    cases += exists(s, "cases.ini");
    snprintf(s, sizeof s, "%s/shards/%d/scaling", tmp, k);
    cases += exists(s, "cases.ini");
    snprintf(s, sizeof s, "%s/shards/%d", tmp, k);
    whole += exists(s, "figure-3.10/table.md");
  }
  TB_CHECK(cases == 12 && whole == 1);
  snprintf(s, sizeof s, "%s/m", tmp);
  TB_CHECK(exists(s, "figure-3.10/table.md") && !exists(s, "figure-3.10/" TB_REPORT_SECTION));
  snprintf(s, sizeof s, "%s/m/REPORT.md", tmp);
  char *rep = tb_test_slurp(s);
  TB_CHECK(rep && strstr(rep, "### pareto/beam") && strstr(rep, "### figure-3.10") &&
           strstr(rep, "### pbd-stiffness") && strstr(rep, "### stability") &&
           !strstr(rep, "Failed"));
  free(rep);
}

/* A shard.ini by hand (no suite ran). */
static void shard_dir(const char *name, int k, int n, int seed) {
  char path[512], body[512];
  snprintf(path, sizeof path, "%s/sh-%s", tb_test_tmpdir(), name);
  mkdir(path, 0777);
  snprintf(path, sizeof path, "sh-%s/shard.ini", name);
  snprintf(body, sizeof body,
           "[shard]\nk = %d\nn = %d\nfull = 1\nscale = 1\nseed = %d\ncommit = abc\nonly = meshes\n"
           "model = \nscene = \n[suites]\nmeshes = not-run\n",
           k, n, seed);
  tb_test_file(path, body, -1);
}

static void expect_merge(const char *dirs, int code, const char *says) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "merge %s --out '%s/mo' 2>&1", dirs, tb_test_tmpdir());
  int rc = tb_test_cli_run(cmd);
  TB_CHECK_MSG(rc == code && strstr(tb_test_out, says), "merge %s: exit %d, '%s'", dirs, rc,
               tb_test_out);
}

static void merge_refuses_mismatch(void) {
  const char *t = tb_test_tmpdir();
  shard_dir("a", 1, 3, 1), shard_dir("b", 2, 3, 1), shard_dir("c", 3, 3, 1);
  shard_dir("d", 3, 3, 2), shard_dir("e", 2, 3, 1);
  char dirs[1024];
  snprintf(dirs, sizeof dirs, "'%s/sh-a' '%s/sh-b' '%s/sh-c'", t, t, t);
  expect_merge(dirs, 0, "merge: 3 shard(s)");
  snprintf(dirs, sizeof dirs, "'%s/sh-a' '%s/sh-b'", t, t);
  expect_merge(dirs, 2, "but 2 shard folders given");
  snprintf(dirs, sizeof dirs, "'%s/sh-a' '%s/sh-b' '%s/sh-d'", t, t, t);
  expect_merge(dirs, 2, "--seed differs");
  snprintf(dirs, sizeof dirs, "'%s/sh-a' '%s/sh-b' '%s/sh-e'", t, t, t);
  expect_merge(dirs, 2, "shard 2/3 again");
  snprintf(dirs, sizeof dirs, "'%s/sh-a' '%s' '%s/sh-c'", t, t, t);
  expect_merge(dirs, 2, "not a `reproduce --shard` folder");
  shard_dir("f", 1, 1, 1);
  tb_test_file("sh-f/shard.ini", "[shard]\nk = 1\nn = 1\nfull = maybe\n", -1);
  snprintf(dirs, sizeof dirs, "'%s/sh-f'", t);
  expect_merge(dirs, 2, "sh-f/shard.ini:4: not a whole number: 'maybe'");
  const char *bad[] = {"0/3", "4/3", "1/0", "x", "1/3x", "/3", "2/"};
  for (int i = 0; i < 7; i++) {
    char cmd[256];
    snprintf(cmd, sizeof cmd, "reproduce --only meshes --shard %s --results '%s/r' 2>&1", bad[i],
             t);
    int rc = tb_test_cli_run(cmd);
    TB_CHECK_MSG(rc == 2 && strstr(tb_test_out, "--shard needs k/N"), "--shard %s: %d %s", bad[i],
                 rc, tb_test_out);
  }
}

/* cases.ini keeps every bit and every character: a shard writes, a replay reads. */
static void cases_round_trip(void) {
  const char *t = tb_test_tmpdir();
  char root[512], dir[600];
  snprintf(root, sizeof root, "%s/rt", t);
  snprintf(dir, sizeof dir, "%s/suite/part", root);
  const double v[] = {-0.0, NAN, -INFINITY, 5e-324, 0.1, 1.0 / 3, -1e308};
  const char *text = "a; b # c [d] = e %41 \"f\" 'g'\nh\\i";
  const char *key =
      "res:3/msm/ks=180 kd=5; x#y/a key longer than inih's 50-character section names";
  tb_error err = {{0}};
  TB_CHECK(tb_shard_set(1, 1, root, &err) == 0);
  tb_suite *su = tb_suite_begin(dir, "part", "round trip", 1, &err);
  tb_case c;
  TB_CHECK(su && tb_suite_case(su, key, 0, &c) == TB_CASE_RUN);
  c.nv = 7;
  memcpy(c.v, v, sizeof v);
  c.nt = 2;
  snprintf(c.t[1], sizeof c.t[1], "%s", text);
  tb_suite_case_done(su, &c);
  TB_CHECK(tb_suite_end(su, &err) == 0);
  tb_shard_reset();
  char path[700];
  snprintf(path, sizeof path, "%s/cases.ini", dir);
  TB_CHECK(tb_shard_replay(root, &err) == 0);
  TB_CHECK_MSG(tb_shard_load(path, "suite/part", 1, &err) == 0, "%s", err.msg);
  su = tb_suite_begin(dir, "part", "round trip", 1, &err);
  tb_case r;
  TB_CHECK(tb_suite_case(su, key, 0, &r) == TB_CASE_KNOWN);
  TB_CHECK(r.nv == 7 && r.nt == 2 && !r.t[0][0] && !strcmp(r.t[1], text));
  TB_CHECK(memcmp(r.v, v, sizeof v) == 0 || (isnan(r.v[1]) && !memcmp(r.v + 2, v + 2, 40)));
  TB_CHECK(signbit(r.v[0]) && r.v[0] == 0 && isnan(r.v[1]) && r.v[3] == 5e-324);
  TB_CHECK(tb_suite_case(su, "no such case", 0, &r) == TB_CASE_SKIP);
  TB_CHECK(tb_suite_end(su, &err) != 0 && strstr(err.msg, "is in no shard's cases.ini"));
  /* bad files: FILE:LINE */
  const char *badfile[][2] = {
      {"[case]\nkey = a\nv0 = 1\nv0x = 2\n", ":4: 'v0x': no such field"},
      {"[case]\nkey = a\nv1 = 1.5q\n", ":3: '1.5q': not a number"},
      {"[nocase]\nkey = a\n", ":2: section [nocase]"},
      {"[case]\nkey = b%4\nv0 = 1\n", ":2: 'b%4': not a case's key"},
      {"[case]\nkey = c\nt0 = 100%zz\n", ":3: '100%zz': a bad"},
      {"[case]\nv0 = 1\n", ":2: 'v0' before the case's key"},
      {"[case]\nkey = d\nv0 = 1\n[case]\nkey = d\n", ":5: case \"d\" given twice"}};
  for (int i = 0; i < 7; i++) {
    char name[64];
    snprintf(name, sizeof name, "bad%d.ini", i);
    const char *p = tb_test_file(name, badfile[i][0], -1);
    int rc = tb_shard_load(p, name, 2, &err); /* a folder each */
    TB_CHECK_MSG(rc != 0 && strstr(err.msg, p) && strstr(err.msg, badfile[i][1]), "%s: %s",
                 badfile[i][0], err.msg);
  }
  /* one case from two shards: only a case every shard runs may be */
  const char *p = tb_test_file("dup.ini", "[case]\nkey = a\nv0 = 1\n", -1);
  TB_CHECK(tb_shard_load(p, "dup", 2, &err) == 0);
  TB_CHECK(tb_shard_load(p, "dup", 3, &err) != 0 && strstr(err.msg, "ran on two shards"));
  p = tb_test_file("every.ini", "[case]\nkey = r\nevery = 1\nv0 = 1\n", -1);
  TB_CHECK(tb_shard_load(p, "dup", 2, &err) == 0 && tb_shard_load(p, "dup", 3, &err) == 0);
  tb_shard_reset();
}

const tb_test_case tb_tests_shard[] = {
    {"cases_round_trip", cases_round_trip},
    {"merge_refuses_mismatch", merge_refuses_mismatch},
    {"merge_equals_unsharded", merge_equals_unsharded},
    {NULL, NULL},
};
