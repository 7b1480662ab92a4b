/* Tests of the results pipeline (report/tb_results.h): statistics on known
 * samples, the files of a suite run (table.md, one tidy CSV per table with
 * quoting and bare numbers, data.json with counters checked by a small JSON
 * validator below), the run context,
 * gnuplot charts and their errors, the charts' palette and the papers'
 * series on the suites' charts, and the progress bar's tty rule. */
#define _XOPEN_SOURCE 700 /* posix_openpt, grantpt, ptsname */
#include <ctype.h>
#include <dirent.h>
#include <fcntl.h>
#include <math.h>
#include <poll.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tb_test.h"
#include "commands/tb_cli.h"
#include "report/tb_results.h"

/* ---- helpers ---- */

static const char *path_in(const char *dir, const char *name) {
  static char buf[4][700];
  static int slot;
  char *p = buf[slot++ % 4];
  if (snprintf(p, 700, "%s/%s", dir, name) >= 700) p[0] = 0; /* too long: names no file */
  return p;
}

static long size_of(const char *path) {
  struct stat sb;
  return stat(path, &sb) == 0 ? (long)sb.st_size : -1;
}

/* ---- a JSON validator (RFC 8259 grammar, recursive descent) ---- */

static const char *js_value(const char *p, int depth);

static const char *js_ws(const char *p) {
  while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') p++;
  return p;
}

static const char *js_string(const char *p) {
  if (*p++ != '"') return NULL;
  for (;;) {
    unsigned char c = (unsigned char)*p++;
    if (c == '"') return p;
    if (c < 0x20) return NULL; /* also the end of the text */
    if (c != '\\') continue;
    c = (unsigned char)*p++;
    if (c == 'u') {
      for (int i = 0; i < 4; i++, p++)
        if (!strchr("0123456789abcdefABCDEF", *p) || !*p) return NULL;
    } else if (!c || !strchr("\"\\/bfnrt", c)) {
      return NULL;
    }
  }
}

static const char *js_digits(const char *p) {
  if (*p < '0' || *p > '9') return NULL;
  while (*p >= '0' && *p <= '9') p++;
  return p;
}

static const char *js_number(const char *p) {
  if (*p == '-') p++;
  if (*p == '0')
    p++;
  else if (!(p = js_digits(p)))
    return NULL;
  if (*p == '.' && !(p = js_digits(p + 1))) return NULL;
  if (*p == 'e' || *p == 'E') {
    p++;
    if (*p == '+' || *p == '-') p++;
    if (!(p = js_digits(p))) return NULL;
  }
  return p;
}

static const char *js_list(const char *p, int depth, char close, int object) {
  p = js_ws(p + 1);
  if (*p == close) return p + 1;
  for (;;) {
    if (object) {
      if (!(p = js_string(p))) return NULL;
      p = js_ws(p);
      if (*p++ != ':') return NULL;
    }
    if (!(p = js_value(p, depth + 1))) return NULL;
    p = js_ws(p);
    if (*p == close) return p + 1;
    if (*p++ != ',') return NULL;
    p = js_ws(p);
  }
}

static const char *js_value(const char *p, int depth) {
  if (depth > 64) return NULL;
  p = js_ws(p);
  switch (*p) {
    case '{':
      return js_list(p, depth, '}', 1);
    case '[':
      return js_list(p, depth, ']', 0);
    case '"':
      return js_string(p);
    case 't':
      return strncmp(p, "true", 4) ? NULL : p + 4;
    case 'f':
      return strncmp(p, "false", 5) ? NULL : p + 5;
    case 'n':
      return strncmp(p, "null", 4) ? NULL : p + 4;
    default:
      return js_number(p);
  }
}

static int json_valid(const char *text) {
  const char *end = text ? js_value(text, 0) : NULL;
  return end && *js_ws(end) == 0;
}

/* The number after "key": following `from` in text, NAN when absent. */
static double json_number_after(const char *text, const char *from, const char *key) {
  const char *p = text ? strstr(text, from) : NULL;
  char k[64];
  snprintf(k, sizeof k, "\"%s\": ", key);
  p = p ? strstr(p, k) : NULL;
  return p ? strtod(p + strlen(k), NULL) : NAN;
}

static void test_json_validator(void) {
  TB_CHECK(json_valid("{\"a\": [1, -2.5e3, true, null, \"x\\\"y\\u00e9\"], \"b\": {}}"));
  TB_CHECK(!json_valid("{\"a\": [1, 2,]}"));
  TB_CHECK(!json_valid("{\"a\": \"tab\there\"}"));
  TB_CHECK(!json_valid("{\"a\": 01}"));
  TB_CHECK(!json_valid("{\"a\": nan}"));
  TB_CHECK(!json_valid("{\"a\": 1} x"));
}

/* ---- statistics ---- */

static void test_stats_odd(void) {
  const double x[] = {5, 1, 3};
  tb_stats s = tb_stats_of(x, 3);
  TB_CHECK(s.n == 3);
  TB_CHECK_NEAR(s.median, 3, 0);
  TB_CHECK_NEAR(s.mean, 3, 1e-15);
  TB_CHECK_NEAR(s.stddev, 2, 1e-15); /* (4 + 4 + 0) / (3 - 1) = 4 */
  TB_CHECK_NEAR(s.min, 1, 0);
  TB_CHECK_NEAR(s.max, 5, 0);
  TB_CHECK(x[0] == 5 && x[1] == 1 && x[2] == 3); /* the input is not sorted */
}

static void test_stats_even(void) {
  const double x[] = {4, 1, 3, 2};
  tb_stats s = tb_stats_of(x, 4);
  TB_CHECK_NEAR(s.median, 2.5, 0);
  TB_CHECK_NEAR(s.mean, 2.5, 1e-15);
  TB_CHECK_NEAR(s.stddev, sqrt(5.0 / 3.0), 1e-15);
  TB_CHECK_NEAR(s.min, 1, 0);
  TB_CHECK_NEAR(s.max, 4, 0);
}

static void test_stats_one_and_none(void) {
  const double x[] = {7.25};
  tb_stats s = tb_stats_of(x, 1);
  TB_CHECK(s.n == 1);
  TB_CHECK(s.mean == 7.25 && s.median == 7.25 && s.min == 7.25 && s.max == 7.25);
  TB_CHECK(s.stddev == 0);
  tb_stats z = tb_stats_of(x, 0);
  TB_CHECK(z.n == 0 && z.mean == 0 && z.median == 0 && z.stddev == 0 && z.min == 0 && z.max == 0);
  z = tb_stats_of(NULL, 5);
  TB_CHECK(z.n == 0 && z.mean == 0);
}

/* ---- a suite run ---- */

/* Writes a small suite into <tmp>/<sub>/run; returns that folder. */
static const char *run_suite(const char *sub) {
  static char dir[600];
  snprintf(dir, sizeof dir, "%s/%s/run", tb_test_tmpdir(), sub);
  tb_error err = {{0}};
  tb_suite *s = tb_suite_begin(dir, "demo", "Demo suite", 42, &err);
  TB_CHECK_MSG(s, "tb_suite_begin: %s", err.msg);
  if (!s) return dir;
  tb_suite_note(s, "First note, %d.", 1);
  const char *c1[] = {"mesh", "time (ms)", "paper (ms)", "ours / paper", "change"};
  tb_table *t = tb_table_new("speed", "Speed beside the paper", 5, c1);
  tb_table_csv_name(t, 4, "change (%)");
  tb_table_row(t);
  tb_table_cell(t, "liver, \"coarse\"");
  tb_table_num(t, 1.5, "%.1f");
  tb_table_cell(t, "2");
  tb_table_num(t, 0.75, "%.2fx");
  tb_table_num(t, -25, "%+.0f%%");
  tb_table_row(t);
  tb_table_cell(t, "a|b");
  tb_table_cell(t, "3");
  tb_table_numf(t, 2, "%d (%+.0f%%)", 2, 50.0);
  tb_table_num(t, NAN, "%.2fx");
  tb_suite_table(s, t); /* its second row lacks the last cell */
  tb_suite_note(s, "Second note.");
  const char *c2[] = {"mesh", "vertices", "vertices", "closed, Euler", "closed", "Euler"};
  t = tb_table_new("counts", "", 6, c2);
  tb_table_only(t, 3, TB_MD_ONLY);
  tb_table_only(t, 4, TB_CSV_ONLY);
  tb_table_only(t, 5, TB_CSV_ONLY);
  tb_table_row(t);
  tb_table_cell(t, "sphere");
  tb_table_cell(t, "252");
  tb_table_cell(t, "250");
  tb_table_cell(t, "yes, 2");
  tb_table_cell(t, "yes");
  tb_table_num(t, 2, "%.0f");
  tb_suite_table(s, t);
  const double real[] = {3, 1, 2, 4}, cpu[] = {2, 1, 1, 2};
  tb_suite_bench(s, "solve", real, cpu, 4, "ms");
  const double one[] = {500};
  tb_suite_bench(s, "odd \"name\"\\", one, one, 1, "us");
  tb_suite_counter(s, "solve", "error", 0.25);
  tb_suite_counter(s, "solve", "pairs", 1e6);
  tb_suite_counter(s, "deflection", "tip_mm", 1.125); /* counters only */
  TB_CHECK_MSG(tb_suite_end(s, &err) == 0, "tb_suite_end: %s", err.msg);
  return dir;
}

static void test_suite_writes_files(void) {
  const char *dir = run_suite("three/deep");
  TB_CHECK(size_of(path_in(dir, "table.md")) > 0);
  TB_CHECK(size_of(path_in(dir, "table-speed.csv")) > 0);
  TB_CHECK(size_of(path_in(dir, "table-counts.csv")) > 0);
  TB_CHECK(size_of(path_in(dir, "table-timings.csv")) > 0);
  TB_CHECK(size_of(path_in(dir, "data.json")) > 0);
  TB_CHECK(size_of(path_in(dir, "data.csv")) < 0); /* no stacked CSV any more */
}

static void test_table_md(void) {
  char *md = tb_test_slurp(path_in(run_suite("md"), "table.md"));
  TB_CHECK(md);
  if (!md) return;
  TB_CHECK(strncmp(md, "# Demo suite\n", 13) == 0);
  const char *want[] = {"**Date**",
                        "**CPU**",
                        "**Compiler**",
                        TB_COMPILER,
                        "**Commit**",
                        "FCL 0.7.0",
                        "CGAL 5.5.1",
                        "**Seed**: 42",
                        "## Speed beside the paper",
                        "| mesh | time (ms) | paper (ms) | ours / paper | change |",
                        "| --- | ---: | --- | --- | --- |",
                        "| liver, \"coarse\" | 1.5 | 2 | 0.75x | -25% |",
                        "| a\\|b | 3 | 2 (+50%) | - |  |",
                        "## counts",
                        "| mesh | vertices | vertices | closed, Euler |\n",
                        "| sphere | 252 | 250 | yes, 2 |\n",
                        "| 1.5 | 1 | 2 | 2.5 | 2.5 | 1 | 4 |"};
  for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
    TB_CHECK_MSG(strstr(md, want[i]), "table.md lacks \"%s\"", want[i]);
  /* notes and tables in the order added, the timings last */
  const char *a = strstr(md, "First note, 1."), *b = strstr(md, "## Speed"),
             *c = strstr(md, "Second note."), *d = strstr(md, "## counts"),
             *e = strstr(md, "## Timings");
  TB_CHECK(a && b && c && d && e && a < b && b < c && c < d && d < e);
  /* the us benchmark converted to ms: 500 us = 0.5 ms */
  TB_CHECK(strstr(md, "median CPU (ms)") && strstr(md, "| 0.5 | 0.5 | 0.5 | 0.5 | 0.5 |"));
  /* the machine's load over the suite, as a note */
  TB_CHECK(strstr(md, "Machine load during this suite"));
  free(md);
}

/* ---- tidy CSV: a small RFC 4180 reader and a checker ---- */

/* The next field of a CSV line at *p into out; 1 when a field was read
 * (*p then after its comma or at the line's end), 0 at the line's end. */
static int csv_next(const char **p, char *out, size_t cap, int *more) {
  const char *q = *p;
  size_t n = 0;
  if (!*more) return 0;
  if (*q == '"') {
    for (q++; *q && !(*q == '"' && q[1] != '"'); q++) {
      if (*q == '"') q++;
      if (n + 1 < cap) out[n++] = *q;
    }
    if (*q == '"') q++;
  } else {
    for (; *q && *q != ',' && *q != '\n'; q++)
      if (n + 1 < cap) out[n++] = *q;
  }
  out[n] = 0;
  *more = *q == ',';
  *p = *q == ',' ? q + 1 : q;
  return 1;
}

/* "" when the CSV is tidy: the same number of fields on every line, and in
 * every column either only bare numbers (and empty cells) or no cell that
 * starts like a number; else what is wrong. A unit or sign inside a numeric
 * cell ("2.1x", "12 ms", "5%") fails both ways. */
static const char *csv_untidy(const char *csv) {
  static char why[256];
  enum { MAXC = 32 };
  int ncols = -1, kind[MAXC] = {0}; /* 1 number, 2 text */
  const char *p = csv;
  for (int line = 1; *p; line++) {
    char f[512];
    int n = 0, more = 1;
    while (csv_next(&p, f, sizeof f, &more)) {
      if (n >= MAXC) return "too many columns";
      if (line > 1 && f[0]) {
        char *end;
        strtod(f, &end);
        int k = *end == 0 ? 1 : 2;
        if (k == 2 && end != f) {
          snprintf(why, sizeof why, "line %d: \"%s\" is a number with text", line, f);
          return why;
        }
        if (kind[n] && kind[n] != k) {
          snprintf(why, sizeof why, "line %d: column %d mixes numbers and text (\"%s\")", line,
                   n + 1, f);
          return why;
        }
        kind[n] = k;
      }
      n++;
    }
    if (*p == '\n') p++;
    if (ncols >= 0 && n != ncols) {
      snprintf(why, sizeof why, "line %d has %d fields, the header %d", line, n, ncols);
      return why;
    }
    ncols = n;
  }
  return "";
}

static void test_csv_checker(void) {
  TB_CHECK(*csv_untidy("a,b (ms)\nx,1.5\n\"y, z\",\n") == 0);
  TB_CHECK(strstr(csv_untidy("a,b\nx,2.1x\n"), "number with text"));
  TB_CHECK(strstr(csv_untidy("a,b (ms)\nx,12 ms\n"), "number with text"));
  TB_CHECK(strstr(csv_untidy("a,b\nx,5%\n"), "number with text"));
  TB_CHECK(strstr(csv_untidy("a,b\nx,1\ny,fast\n"), "mixes"));
  TB_CHECK(strstr(csv_untidy("a,b\nx\n"), "fields"));
}

static void test_data_csv(void) {
  const char *dir = run_suite("csv");
  char *speed = tb_test_slurp(path_in(dir, "table-speed.csv"));
  char *counts = tb_test_slurp(path_in(dir, "table-counts.csv"));
  char *timings = tb_test_slurp(path_in(dir, "table-timings.csv"));
  TB_CHECK(speed && counts && timings);
  if (speed) {
    /* bare numbers: no 'x' or '%' from table.md, the unit in the header, "-" empty */
    const char *want =
        "mesh,time (ms),paper (ms),ours / paper,change (%)\n"
        "\"liver, \"\"coarse\"\"\",1.5,2,0.75,-25\n"
        "a|b,3,2,,\n";
    TB_CHECK_MSG(strcmp(speed, want) == 0, "table-speed.csv is\n%s", speed);
    TB_CHECK_MSG(*csv_untidy(speed) == 0, "%s", csv_untidy(speed));
  }
  if (counts)
    TB_CHECK_MSG(strcmp(counts, "mesh,vertices,vertices,closed,Euler\nsphere,252,250,yes,2\n") == 0,
                 "%s", counts);
  if (timings) {
    const char *head =
        "benchmark,repetitions,threads,median CPU (ms),CPU 95% low (ms),CPU 95% high (ms),"
        "median wall (ms),mean wall (ms),min wall (ms),max wall (ms)\n";
    TB_CHECK_MSG(strncmp(timings, head, strlen(head)) == 0, "%s", timings);
    TB_CHECK(strstr(timings, "\nsolve,4,") && strstr(timings, ",1.5,1,2,2.5,2.5,1,4\n"));
    TB_CHECK(strstr(timings, "\n\"odd \"\"name\"\"\\\",1,"));
    TB_CHECK(strstr(timings, "deflection") == NULL); /* counters only: no time */
    TB_CHECK_MSG(*csv_untidy(timings) == 0, "%s", csv_untidy(timings));
  }
  free(speed), free(counts), free(timings);
}

/* A column with "2.1x" among numbers is reported; the files are written. */
static void test_mixed_column_reported(void) {
  char dir[600];
  snprintf(dir, sizeof dir, "%s/mixed", tb_test_tmpdir());
  tb_error err = {{0}};
  tb_suite *s = tb_suite_begin(dir, "mixed", NULL, 1, &err);
  TB_CHECK(s);
  if (!s) return;
  const char *cols[] = {"what", "ratio"};
  tb_table *t = tb_table_new("ratios", "R", 2, cols);
  tb_table_row(t);
  tb_table_cell(t, "a");
  tb_table_num(t, 1.25, "%.2f");
  tb_table_row(t);
  tb_table_cell(t, "b");
  tb_table_cell(t, "%.1fx", 2.1);
  tb_suite_table(s, t);
  TB_CHECK(tb_suite_end(s, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "\"ratio\"") && strstr(err.msg, "2.1x"), "message: %s", err.msg);
  TB_CHECK(size_of(path_in(dir, "table-ratios.csv")) > 0);
  /* a format without one floating conversion is a misuse too */
  s = tb_suite_begin(dir, "mixed", NULL, 1, &err);
  t = tb_table_new("fmt", "F", 1, cols);
  tb_table_row(t);
  tb_table_num(t, 3, "%d items");
  tb_suite_table(s, t);
  TB_CHECK(tb_suite_end(s, &err) != 0 && strstr(err.msg, "floating conversion"));
}

static void test_data_json(void) {
  char *js = tb_test_slurp(path_in(run_suite("json"), "data.json"));
  TB_CHECK(js);
  if (!js) return;
  TB_CHECK(json_valid(js));
  const char *want[] = {"\"context\": {",
                        "\"host_name\": \"",
                        "\"num_cpus\": ",
                        "\"cpu_model\": \"",
                        "\"fcl_version\": \"0.7.0\"",
                        "\"cgal_version\": \"5.5.1\"",
                        "\"seed\": 42",
                        "\"caches\": [",
                        "\"load_avg\": [",
                        "\"benchmarks\": [",
                        "\"run_type\": \"iteration\"",
                        "\"aggregate_name\": \"median\"",
                        "\"name\": \"solve_max\"",
                        "\"name\": \"odd \\\"name\\\"\\\\_mean\"",
                        "\"time_unit\": \"us\""};
  for (size_t i = 0; i < sizeof want / sizeof want[0]; i++)
    TB_CHECK_MSG(strstr(js, want[i]), "data.json lacks %s", want[i]);
  /* Google Benchmark's types: a bool, numbers, a string */
  TB_CHECK(strstr(js, "\"cpu_scaling_enabled\": true,") ||
           strstr(js, "\"cpu_scaling_enabled\": false,"));
  TB_CHECK(json_number_after(js, "\"context\"", "num_cpus") >= 1);
  TB_CHECK(!isnan(json_number_after(js, "\"context\"", "mhz_per_cpu")));
  char bt[64];
  snprintf(bt, sizeof bt, "\"library_build_type\": \"%s\"",
           strcmp(TB_BUILD_TYPE, "release") == 0 ? "release" : "debug");
  TB_CHECK_MSG(strstr(js, bt), "data.json lacks %s", bt);
  /* counters: on every entry of their benchmark, 0 on stddev */
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_median\"", "error"), 0.25, 0);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_median\"", "pairs"), 1e6, 0);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_stddev\"", "error"), 0, 0);
  TB_CHECK_NEAR(json_number_after(js, "\"repetition_index\": 2", "error"), 0.25, 0);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"deflection\"", "tip_mm"), 1.125, 0);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"deflection\"", "real_time"), 0, 0);
  TB_CHECK(strstr(js, "\"name\": \"deflection_mean\"") == NULL);
  /* one time unit in the file, the largest in which every median is at least 1: us here (the
   * odd benchmark's 1 us), so solve's milliseconds are written as microseconds */
  TB_CHECK(!strstr(js, "\"time_unit\": \"ms\"") && !strstr(js, "\"time_unit\": \"s\""));
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_median\"", "real_time"), 2500, 1e-9);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_median\"", "cpu_time"), 1500, 1e-9);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_stddev\"", "real_time"),
                1000 * sqrt(5.0 / 3.0), 1e-6);
  TB_CHECK_NEAR(json_number_after(js, "\"name\": \"solve_min\"", "real_time"), 1000, 1e-9);
  TB_CHECK_NEAR(json_number_after(js, "\"repetition_index\": 3", "real_time"), 4000, 1e-9);
  free(js);
}

static void test_context(void) {
  tb_context c;
  tb_context_collect(&c, 7);
  TB_CHECK(c.seed == 7);
  TB_CHECK_MSG(strlen(c.date) == 20 && c.date[4] == '-' && c.date[10] == 'T' && c.date[19] == 'Z',
               "date \"%s\"", c.date);
  TB_CHECK(c.host[0] && c.cpu[0] && c.cores >= 1);
  TB_CHECK(strcmp(c.compiler, TB_COMPILER) == 0 && strcmp(c.flags, TB_BUILD_FLAGS) == 0);
  TB_CHECK(c.commit[0] && c.dirty >= -1 && c.dirty <= 1);
  TB_CHECK(c.cpu_scaling == 0 || c.cpu_scaling == 1);
  TB_CHECK(c.ncaches >= 0 && c.ncaches <= 8);
  for (int i = 0; i < c.ncaches; i++)
    TB_CHECK_MSG(c.caches[i].level >= 1 && c.caches[i].size > 0 && c.caches[i].num_sharing >= 1 &&
                     c.caches[i].type[0],
                 "cache %d: %s L%d %ld bytes, %d sharing", i, c.caches[i].type, c.caches[i].level,
                 c.caches[i].size, c.caches[i].num_sharing);
  if (access("/sys/devices/system/cpu/cpu0/cache/index0/size", R_OK) == 0) TB_CHECK(c.ncaches >= 1);
  TB_CHECK(c.have_load && c.load[0] >= 0);
  TB_CHECK(strcmp(c.build_type, "release") == 0 || strcmp(c.build_type, "debug") == 0);
  TB_CHECK_MSG(strcmp(c.fcl, "0.7.0") == 0, "FCL \"%s\"", c.fcl);
  TB_CHECK_MSG(strcmp(c.cgal, "5.5.1") == 0, "CGAL \"%s\"", c.cgal);
  TB_CHECK_MSG(strcmp(c.bullet, "3.24") == 0, "Bullet \"%s\"", c.bullet);
  TB_CHECK_MSG(strcmp(c.cholmod, "3.0.14") == 0, "CHOLMOD \"%s\"", c.cholmod);
  TB_CHECK_MSG(strcmp(c.tetgen, TB_TETGEN_VERSION[0] ? TB_TETGEN_VERSION : "unknown") == 0,
               "TetGen \"%s\"", c.tetgen);
  /* a commit is 40 hex digits or "unknown" */
  TB_CHECK(strcmp(c.commit, "unknown") == 0 ||
           (strlen(c.commit) == 40 && strspn(c.commit, "0123456789abcdef") == 40));
}

/* ---- misuse is reported, not a crash ---- */

static void test_misuse_reported(void) {
  char dir[600];
  snprintf(dir, sizeof dir, "%s/misuse", tb_test_tmpdir());
  tb_error err = {{0}};
  tb_suite *s = tb_suite_begin(dir, "misuse", NULL, 1, &err);
  TB_CHECK(s);
  if (!s) return;
  const char *cols[] = {"a"};
  tb_table *t = tb_table_new("t", "T", 1, cols);
  tb_table_row(t);
  tb_table_cell(t, "1");
  tb_table_cell(t, "2"); /* one too many */
  tb_suite_table(s, t);
  const double x[] = {1};
  tb_suite_bench(s, "b", x, x, 1, "minutes");
  TB_CHECK(tb_suite_end(s, &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "more cells than columns"), "message: %s", err.msg);
  TB_CHECK(size_of(path_in(dir, "table.md")) > 0); /* the files are still written */

  TB_CHECK(tb_table_new("x", "X", 0, cols) == NULL);
  s = tb_suite_begin(dir, "misuse", NULL, 1, &err);
  tb_suite_counter(s, "b", "real_time", 1);
  TB_CHECK(tb_suite_end(s, &err) != 0 && strstr(err.msg, "real_time"));
  TB_CHECK(tb_suite_end(NULL, &err) != 0);
  s = tb_suite_begin(dir, "misuse", NULL, 1, &err);
  tb_suite_bench(s, "b", x, x, 1, "minutes");
  TB_CHECK(tb_suite_end(s, &err) != 0 && strstr(err.msg, "minutes"));
  /* wall times without CPU times are refused, never passed off as CPU */
  s = tb_suite_begin(dir, "misuse", NULL, 1, &err);
  tb_suite_bench(s, "b", x, NULL, 1, "ms");
  TB_CHECK(tb_suite_end(s, &err) != 0 && strstr(err.msg, "CPU times"));
  /* a folder below a regular file cannot be made */
  const char *file = tb_test_file("plain", "x", -1);
  snprintf(dir, sizeof dir, "%s/sub", file);
  TB_CHECK(tb_suite_begin(dir, "x", NULL, 1, &err) == NULL);
  TB_CHECK_MSG(strstr(err.msg, "plain/sub"), "message: %s", err.msg);
}

/* ---- data files and charts ---- */

static tb_suite *chart_suite(const char *sub, char *dir, size_t cap) {
  snprintf(dir, cap, "%s/%s", tb_test_tmpdir(), sub);
  tb_error err = {{0}};
  tb_suite *s = tb_suite_begin(dir, "chart", "Charts", 3, &err);
  TB_CHECK_MSG(s, "%s", err.msg);
  if (s)
    TB_CHECK(tb_suite_write_data(s, "lines.csv", "n,a (ms),b (ms)", "1,2,3\n10,4,5\n100,8,6",
                                 &err) == 0);
  return s;
}

static void test_write_data(void) {
  char dir[600];
  tb_suite *s = chart_suite("data", dir, sizeof dir);
  if (!s) return;
  char *text = tb_test_slurp(path_in(dir, "lines.csv"));
  TB_CHECK(text && strcmp(text, "n,a (ms),b (ms)\n1,2,3\n10,4,5\n100,8,6\n") == 0);
  free(text);
  tb_error err = {{0}};
  TB_CHECK(tb_suite_write_data(s, "../escape.csv", "a", "1", &err) != 0);
  TB_CHECK(tb_suite_write_data(s, "/tmp/abs.csv", "a", "1", &err) != 0);
  TB_CHECK(tb_suite_end(s, &err) == 0);
}

static void test_chart(void) {
  char dir[600];
  tb_suite *s = chart_suite("chart", dir, sizeof dir);
  if (!s) return;
  tb_error err = {{0}};
  int rc = tb_suite_chart_vars(s, "chart_lines.gp", "lines.csv", "lines",
                               "title='It''s a test'; xlabel='n'; logx=1", &err);
  TB_CHECK_MSG(rc == 0, "chart: %s", err.msg);
  TB_CHECK(size_of(path_in(dir, "lines.png")) > 0);
  TB_CHECK(size_of(path_in(dir, "lines.svg")) > 0);
  rc = tb_suite_chart(s, "chart_lines.gp", "lines.csv", "plain", &err);
  TB_CHECK_MSG(rc == 0, "chart: %s", err.msg);
  TB_CHECK(size_of(path_in(dir, "plain.png")) > 0 && size_of(path_in(dir, "plain.svg")) > 0);
  char *svg = tb_test_slurp(path_in(dir, "lines.svg"));
  TB_CHECK(svg && strstr(svg, "<svg") && strstr(svg, "a (ms)"));
  free(svg);
  TB_CHECK(tb_suite_end(s, &err) == 0);
  char *md = tb_test_slurp(path_in(dir, "table.md"));
  TB_CHECK(md && strstr(md, "![lines](lines.svg)") && strstr(md, "![plain](plain.svg)"));
  free(md);
}

static void test_chart_errors(void) {
  char dir[600];
  tb_suite *s = chart_suite("chart_err", dir, sizeof dir);
  if (!s) return;
  tb_error err = {{0}};
  TB_CHECK(tb_suite_chart(s, "no_such_script.gp", "lines.csv", "x", &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "no_such_script.gp: no such gnuplot script"), "%s", err.msg);
  TB_CHECK(tb_suite_chart(s, "../scripts/chart_lines.gp", "lines.csv", "x", &err) != 0);
  TB_CHECK(tb_suite_chart(s, "chart_lines.gp", "missing.csv", "x", &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "missing.csv: chart data file not found"), "%s", err.msg);
  /* a failing script: a syntax error in the variables */
  TB_CHECK(tb_suite_chart_vars(s, "chart_lines.gp", "lines.csv", "bad", "logy=", &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "gnuplot failed"), "%s", err.msg);
  TB_CHECK(size_of(path_in(dir, "bad.png")) < 0);
  /* no gnuplot on PATH (this case runs in its own process) */
  setenv("PATH", "/nonexistent", 1);
  TB_CHECK(tb_suite_chart(s, "chart_lines.gp", "lines.csv", "nogp", &err) != 0);
  TB_CHECK_MSG(strstr(err.msg, "gnuplot"), "%s", err.msg);
  TB_CHECK(tb_suite_end(s, &err) == 0);
}

/* ---- the palette and the papers' series on the suites' charts ---- */

/* The plotted series of a gnuplot SVG: each <g id="gnuplot_plot_N"> group
 * with a title of its own (untitled ones are titled gnuplot_plot_N), its
 * colour the first rgb(...) inside the group. Returns the number of titled
 * series, or -1 (with why) when two share a colour or one has none. */
static int svg_series(const char *svg, char *why, size_t cap) {
  static const char *open_tag = "<g id=\"gnuplot_plot_";
  char colours[64][32], titles[64][80];
  int n = 0;
  why[0] = 0;
  for (const char *g = strstr(svg, open_tag); g && n < 64;) {
    const char *next = strstr(g + 1, open_tag), *t = strstr(g, "<title>");
    if (!t || (next && t > next)) {
      g = next;
      continue;
    }
    t += strlen("<title>");
    const char *te = strstr(t, "</title>");
    if (!te || !strncmp(t, "gnuplot_plot_", 13)) {
      g = next;
      continue;
    }
    snprintf(titles[n], sizeof titles[n], "%.*s", (int)(te - t), t);
    const char *c = strstr(te, "rgb(");
    if (!c || (next && c > next)) {
      snprintf(why, cap, "series \"%s\" has no colour", titles[n]);
      return -1;
    }
    const char *ce = strchr(c, ')');
    if (!ce) return snprintf(why, cap, "unterminated rgb("), -1;
    size_t k = 0;
    for (const char *q = c; q <= ce && k + 1 < sizeof colours[n]; q++)
      if (*q != ' ') colours[n][k++] = *q;
    colours[n][k] = 0;
    for (int j = 0; j < n; j++)
      if (!strcmp(colours[j], colours[n])) {
        snprintf(why, cap, "\"%s\" and \"%s\" both %s", titles[j], titles[n], colours[n]);
        return -1;
      }
    n++;
    g = next;
  }
  return n;
}

static void test_svg_series_checker(void) {
  char why[256];
  const char *two =
      "<g id=\"gnuplot_plot_1\" ><title>a</title><path stroke='rgb(1, 2, 3)'/></g>"
      "<g id=\"gnuplot_plot_2\" ><title>gnuplot_plot_2</title>"
      "<path stroke='rgb(1, 2, 3)'/></g>"
      "<g id=\"gnuplot_plot_3\" ><title>b</title><path stroke='rgb(1,2,4)'/></g>";
  TB_CHECK_MSG(svg_series(two, why, sizeof why) == 2, "%s", why);
  const char *same =
      "<g id=\"gnuplot_plot_1\" ><title>a</title><path stroke='rgb(1, 2, 3)'/></g>"
      "<g id=\"gnuplot_plot_2\" ><title>b</title><use color='rgb(1,2,3)'/></g>";
  TB_CHECK(svg_series(same, why, sizeof why) == -1 && strstr(why, "\"a\" and \"b\""));
  const char *none = "<g id=\"gnuplot_plot_1\" ><title>a</title><path stroke='black'/></g>";
  TB_CHECK(svg_series(none, why, sizeof why) == -1 && strstr(why, "no colour"));
}

/* scripts/palette.gp: tb_colours[N] holds N distinct colours, enough for the
 * largest chart (table 4.2: 10 series of ours, 3 of the thesis); every other
 * script loads it and spells no colour of its own. */
static void test_chart_palette(void) {
  char path[1200];
  snprintf(path, sizeof path, "%s/scripts/palette.gp", tb_test_source_root());
  char *pal = tb_test_slurp(path);
  TB_CHECK_MSG(pal, "cannot read %s", path);
  if (!pal) return;
  const char *a = strstr(pal, "array tb_colours[");
  TB_CHECK(a != NULL);
  int declared = a ? atoi(a + strlen("array tb_colours[")) : 0, n = 0, distinct = 1;
  char cols[64][8];
  for (const char *p = a ? strchr(a, '=') : NULL; p && *p && *p != ']' && n < 64; p++)
    if (*p == '#' && p[-1] == '"') {
      int k = 0;
      for (; k < 7 && p[k] && p[k] != '"'; k++) cols[n][k] = (char)tolower((unsigned char)p[k]);
      cols[n][k] = 0;
      for (int j = 0; j < n; j++) distinct &= strcmp(cols[j], cols[n]) != 0;
      n++;
    }
  TB_CHECK_MSG(n == declared && n >= 13, "%d colours listed, %d declared", n, declared);
  TB_CHECK_MSG(distinct, "two colours of scripts/palette.gp are the same");
  free(pal);
  snprintf(path, sizeof path, "%s/scripts", tb_test_source_root());
  DIR *d = opendir(path);
  TB_CHECK(d != NULL);
  int scripts = 0;
  for (struct dirent *e; d && (e = readdir(d));) {
    size_t len = strlen(e->d_name);
    if (len < 4 || strcmp(e->d_name + len - 3, ".gp") || !strcmp(e->d_name, "palette.gp")) continue;
    char sp[1500];
    snprintf(sp, sizeof sp, "%s/%s", path, e->d_name);
    char *text = tb_test_slurp(sp);
    TB_CHECK_MSG(text && strstr(text, "load tb_dir.\"palette.gp\""), "%s does not load palette.gp",
                 e->d_name);
    TB_CHECK_MSG(text && !strstr(text, "\"#") && !strstr(text, "'#"),
                 "%s spells a colour of its own", e->d_name);
    free(text);
    scripts++;
  }
  if (d) closedir(d);
  TB_CHECK_MSG(scripts >= 3, "%d chart scripts in scripts/", scripts);
}

/* The chart path of a suite at a small scale: the papers' series in the
 * data files and on the chart, every series its own colour. */
static void check_chart(const char *dir, const char *svgname, int least,
                        const char *const *titles) {
  char *svg = tb_test_slurp(path_in(dir, svgname)), why[256];
  TB_CHECK_MSG(svg, "no %s/%s", dir, svgname);
  if (!svg) return;
  int n = svg_series(svg, why, sizeof why);
  TB_CHECK_MSG(n >= least, "%s: %d series (at least %d expected) %s", svgname, n, least, why);
  for (int k = 0; titles[k]; k++) {
    char t[160];
    snprintf(t, sizeof t, "<title>%s</title>", titles[k]);
    TB_CHECK_MSG(strstr(svg, t), "%s has no series \"%s\"", svgname, titles[k]);
  }
  free(svg);
}

static void check_text(const char *path, const char *want) {
  char *text = tb_test_slurp(path);
  TB_CHECK_MSG(text && strstr(text, want), "%s lacks \"%s\"", path, want);
  free(text);
}

static void test_chart_paper_series(void) {
  char res[400], dir[500];
  snprintf(res, sizeof res, "%s/papers", tb_test_tmpdir());
  tb_suite_opts o;
  memset(&o, 0, sizeof o);
  o.scale = 0.01, o.seed = 1, o.results = res;
  TB_CHECK(tb_suite_table41(&o) == 0);
  snprintf(dir, sizeof dir, "%s/table-4.1", res);
  check_text(path_in(dir, "table41_thesis.csv"),
             "tests (million),thesis Yu-He (i3-2100),thesis improved (i3-2100)\n0.1,70,42\n");
  check_text(path_in(dir, "table41_thesis.csv"), "\n2,1256,739\n");
  static const char *const t41[] = {"moller", "exact", "thesis Yu-He (i3-2100)",
                                    "thesis improved (i3-2100)", NULL};
  check_chart(dir, "table41.svg", 11, t41);

  TB_CHECK(tb_suite_table42(&o) == 0);
  snprintf(dir, sizeof dir, "%s/table-4.2", res);
  check_text(path_in(dir, "table42_thesis.csv"), "\n0,263.2,263.2,254.7\n");
  check_text(path_in(dir, "table42_thesis.csv"), "\n1106,53.2,17.2,42.7\n");
  check_text(path_in(dir, "table42.svg"), "whole-frame FPS"); /* the thesis's own panel */
  check_text(path_in(dir, "table42.svg"), "frames per second (1/s)");
  static const char *const t42[] = {"composite+exact", "thesis composite (FPS)",
                                    "thesis Sphere (FPS)", "thesis AABB (FPS)", NULL};
  check_chart(dir, "table42.svg", 13, t42);

  TB_CHECK(tb_suite_fig310(&o) == 0);
  snprintf(dir, sizeof dir, "%s/figure-3.10", res);
  char *fit = tb_test_slurp(path_in(dir, "fig310_fit.csv"));
  int lines = 0;
  for (const char *p = fit; p && *p; p++) lines += *p == '\n';
  TB_CHECK_MSG(fit && lines == 3 && !strncmp(fit, "particles,1 linear", 18), "fig310_fit.csv: %s",
               fit ? fit : "(none)");
  free(fit);
  static const char *const t310[] = {"1 linear", "50 quadratic", "dashed: least-squares line",
                                     NULL};
  check_chart(dir, "fig310.svg", 7, t310);
}

/* ---- progress ---- */

static void test_progress_silent_without_tty(void) {
  const char *path = tb_test_file("progress.txt", "", 0);
  fflush(stderr);
  int saved = dup(2), fd = open(path, O_WRONLY | O_TRUNC);
  TB_CHECK(saved >= 0 && fd >= 0);
  if (saved < 0 || fd < 0) return;
  dup2(fd, 2);
  close(fd);
  for (long i = 0; i <= 10; i++) tb_progress("work", i, 10);
  fflush(stderr);
  dup2(saved, 2);
  close(saved);
  TB_CHECK_MSG(size_of(path) == 0, "progress wrote %ld bytes to a file", size_of(path));
}

static void test_progress_on_tty(void) {
  int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) || unlockpt(master)) {
    if (master >= 0) close(master);
    tb_test_skip("no pseudo-terminal available");
    return;
  }
  int slave = open(ptsname(master), O_RDWR | O_NOCTTY);
  TB_CHECK(slave >= 0);
  if (slave < 0) return;
  fflush(stderr);
  int saved = dup(2);
  dup2(slave, 2);
  tb_progress("meshes", 1, 4);
  tb_progress("meshes", 4, 4);
  dup2(saved, 2);
  close(saved);
  close(slave);
  char out[512];
  size_t n = 0;
  struct pollfd pfd = {master, POLLIN, 0};
  while (n + 1 < sizeof out && poll(&pfd, 1, 200) > 0) {
    ssize_t got = read(master, out + n, sizeof out - 1 - n);
    if (got <= 0) break;
    n += (size_t)got;
  }
  out[n] = 0;
  close(master);
  TB_CHECK_MSG(strstr(out, "\rmeshes [") && strstr(out, " 25% (1/4)"), "tty got \"%s\"", out);
  TB_CHECK_MSG(strstr(out, "100% (4/4)") && strchr(out, '\n'), "tty got \"%s\"", out);
  TB_CHECK_MSG(strstr(out, " elapsed, ") && strstr(out, " left"), "tty got \"%s\"", out);
}

/* The ETA: time per finished item times the items after the current one,
 * plus what the current one has left of that time; unknown before the
 * first item ends. */
static void test_progress_eta(void) {
  tb_progress_run r;
  memset(&r, 0, sizeof r);
  TB_CHECK(tb_progress_update(&r, "work", 0, 10, 100.0) == 1); /* a new run draws */
  TB_CHECK(r.total == 10 && r.start == 100.0);
  TB_CHECK(tb_progress_eta(&r, 101.0) < 0);
  char line[256];
  tb_progress_format(line, sizeof line, &r, 101.0);
  TB_CHECK_MSG(strstr(line, "work [") && strstr(line, "(0/10) 0:01 elapsed, ? left"), "%s", line);
  tb_progress_update(&r, "work", 4, 10, 108.0); /* 2 s an item */
  TB_CHECK_NEAR(tb_progress_eta(&r, 108.0), 12.0, 1e-9);
  TB_CHECK_NEAR(tb_progress_eta(&r, 109.5), 10.5, 1e-9); /* into the 5th item */
  /* overdue: 15 s over 5 items is 3 s an item, for the 5 after it */
  TB_CHECK_NEAR(tb_progress_eta(&r, 115.0), 15.0, 1e-9);
  tb_progress_format(line, sizeof line, &r, 109.5);
  TB_CHECK_MSG(strstr(line, " 40% (4/10) 0:10 elapsed, ~0:11 left"), "%s", line);
  /* long runs in h:mm:ss */
  tb_progress_update(&r, "work", 5, 10, 100.0 + 3725.0);
  tb_progress_format(line, sizeof line, &r, 100.0 + 3725.0);
  TB_CHECK_MSG(strstr(line, "1:02:05 elapsed, ~1:02:05 left"), "%s", line);
  tb_progress_update(&r, "work", 10, 10, 100.0 + 7000.0);
  TB_CHECK(!r.active && tb_progress_eta(&r, 7100.0) == 0);
  tb_progress_format(line, sizeof line, &r, 7100.0);
  TB_CHECK_MSG(strstr(line, "100% (10/10)") && strstr(line, ", 0:00 left"), "%s", line);
  /* the same end again draws nothing */
  TB_CHECK(tb_progress_update(&r, "work", 10, 10, 7200.0) == 0);
}

/* Within a run the total is the first one's: a call with another total is
 * scaled to it (a caller's "1 of 1" at the end finishes the bar), done never
 * goes back, and a new label or done going back begins a new run. */
static void test_progress_total_never_jumps(void) {
  tb_progress_run r;
  memset(&r, 0, sizeof r);
  tb_progress_update(&r, "maps", 0, 12, 0.0);
  tb_progress_update(&r, "maps", 3, 12, 1.0);
  TB_CHECK(r.total == 12 && r.done == 3);
  tb_progress_update(&r, "maps", 1, 2, 2.0); /* half of another total */
  TB_CHECK_MSG(r.total == 12 && r.done == 6, "total %ld done %ld", r.total, r.done);
  tb_progress_update(&r, "maps", 1, 1, 3.0);
  TB_CHECK(r.total == 12 && r.done == 12 && !r.active);
  /* a new label: a new run with its own total and clock */
  tb_progress_update(&r, "deform", 0, 5, 4.0);
  TB_CHECK(r.active && r.total == 5 && r.done == 0 && r.start == 4.0);
  tb_progress_update(&r, "deform", 2, 5, 6.0);
  tb_progress_update(&r, "deform", 1, 5, 7.0); /* back: a new run */
  TB_CHECK(r.done == 1 && r.start == 7.0);
  /* redraws: not again within a quarter second unless something moved */
  memset(&r, 0, sizeof r);
  TB_CHECK(tb_progress_update(&r, "x", 0, 100000, 0.0) == 1);
  r.last_draw = 0;
  TB_CHECK(tb_progress_update(&r, "x", 1, 100000, 0.1) == 0);
  TB_CHECK(tb_progress_update(&r, "x", 2, 100000, 0.3) == 1);
  /* an unknown total: a count and the time, no bar and no estimate */
  memset(&r, 0, sizeof r);
  tb_progress_update(&r, "scan", 7, 0, 10.0);
  tb_progress_update(&r, "scan", 9, 0, 75.0);
  char line[256];
  tb_progress_format(line, sizeof line, &r, 75.0);
  TB_CHECK_MSG(strcmp(line, "scan: 9 done, 1:05 elapsed") == 0, "%s", line);
  TB_CHECK(tb_progress_eta(&r, 75.0) < 0 && r.active);
  strcpy(r.note, "step 3/8");
  tb_progress_format(line, sizeof line, &r, 75.0);
  TB_CHECK_MSG(strcmp(line, "scan: 9 done, 1:05 elapsed | step 3/8") == 0, "%s", line);
  tb_progress_update(&r, "scan", 10, 0, 76.0); /* a new item drops the note */
  TB_CHECK(r.note[0] == 0);
}

/* A suite ended while a report is open lands in REPORT.md under its place,
 * its links prefixed with its folder, the context once, captions shown. */
static void test_report(void) {
  char dir[600], sub[700];
  snprintf(dir, sizeof dir, "%s/report", tb_test_tmpdir());
  snprintf(sub, sizeof sub, "%s/alpha/scene", dir);
  tb_error err = {{0}};
  tb_report *r = tb_report_begin(dir, "Test report", 7, &err);
  TB_CHECK_MSG(r != NULL, "%s", err.msg);
  if (!r) return;
  TB_CHECK(tb_report_begin(dir, "again", 7, &err) == NULL); /* one at a time */
  tb_suite *s = tb_suite_begin(sub, "alpha", "Alpha suite", 7, &err);
  TB_CHECK(s != NULL);
  if (!s) return;
  static const char *cols[] = {"n", "time (ms)"};
  tb_table *t = tb_table_new("speed", "Speed table", 2, cols);
  tb_table_row(t);
  tb_table_cell(t, "1");
  tb_table_num(t, 2.5, "%.1f");
  tb_suite_note(s, "A note.");
  tb_suite_table(s, t);
  FILE *f = fopen(path_in(sub, "pic.png"), "w");
  if (f) fputs("png", f), fclose(f);
  tb_suite_figure(s, "pic.png", "A rendered %s", "frame");
  TB_CHECK(tb_suite_end(s, &err) == 0);
  tb_report_chapter(r, "Chapter 1: one", NULL);
  tb_report_suite(r, "beta", "never ran", TB_REPORT_NOT_RUN);
  tb_report_chapter(r, "Chapter 2: two", "Intro.");
  tb_report_suite(r, "alpha", "what alpha shows", TB_REPORT_DONE);
  TB_CHECK_MSG(tb_report_end(r, &err) == 0, "%s", err.msg);
  char *md = tb_test_slurp(path_in(dir, "REPORT.md"));
  TB_CHECK(md != NULL);
  if (!md) return;
  TB_CHECK_MSG(strncmp(md, "# Test report\n", 14) == 0, "%s", md);
  TB_CHECK(strstr(md, "- **Seed**: 7") && strstr(strstr(md, "**Seed**") + 1, "**Seed**") == NULL);
  TB_CHECK(strstr(md, "Not run this time (`--only`): `beta`."));
  TB_CHECK(strstr(md, "Chapter 1") == NULL); /* none of its suites ran */
  const char *ch2 = strstr(md, "## Chapter 2: two\n\nIntro.");
  const char *sec = strstr(md, "### alpha/scene: Alpha suite");
  const char *tab = strstr(md, "#### Speed table");
  TB_CHECK_MSG(ch2 && sec && tab && ch2 < sec && sec < tab, "%s", md);
  TB_CHECK(strstr(md, "*what alpha shows.* ([table.md](alpha/scene/table.md)"));
  TB_CHECK(strstr(md, "![A rendered frame](alpha/scene/pic.png)\n\n*A rendered frame*"));
  TB_CHECK(strstr(md, "| 1 | 2.5 |") && strstr(md, "A note."));
  free(md);
  /* table.md shows the figure with its own links; a missing one is a misuse */
  md = tb_test_slurp(path_in(sub, "table.md"));
  TB_CHECK(md && strstr(md, "![A rendered frame](pic.png)"));
  free(md);
  s = tb_suite_begin(sub, "alpha", "Alpha", 7, &err);
  if (!s) return;
  tb_suite_figure(s, "nothing.png", "x");
  tb_suite_caption(s, "nochart", "y");
  TB_CHECK(tb_suite_end(s, &err) != 0 && strstr(err.msg, "nothing.png"));
}

/* A suite's folder is marked INCOMPLETE from tb_suite_begin until tb_suite_end: a run killed in
 * between leaves the mark. */
static void incomplete_mark(void) {
  char dir[600], mark[700];
  snprintf(dir, sizeof dir, "%s/marked", tb_test_tmpdir());
  snprintf(mark, sizeof mark, "%s/" TB_INCOMPLETE, dir);
  tb_error err;
  tb_suite *s = tb_suite_begin(dir, "marked", NULL, 1, &err);
  TB_CHECK_MSG(s, "%s", err.msg);
  FILE *f = fopen(mark, "r");
  char text[400] = "";
  if (f) text[fread(text, 1, sizeof text - 1, f)] = 0, fclose(f);
  TB_CHECK_MSG(strstr(text, "did not finish"), "no mark: '%s'", text);
  TB_CHECK(tb_suite_end(s, &err) == 0);
  TB_CHECK_MSG(!fopen(mark, "r"), "the mark stayed after tb_suite_end");
}

/* Each table also in tidy long form: one measurement a row, the row's text columns, then metric,
 * value and unit (from the header's parentheses when they hold a unit). */
static void long_csv(void) {
  char dir[600];
  snprintf(dir, sizeof dir, "%s/long", tb_test_tmpdir());
  tb_error err = {{0}};
  tb_suite *s = tb_suite_begin(dir, "long", NULL, 1, &err);
  TB_CHECK(s);
  if (!s) return;
  const char *cols[] = {"model", "time (ms)", "steps/s (CPU)", "ratio"};
  tb_table *t = tb_table_new("speed", "S", 4, cols);
  tb_table_row(t);
  tb_table_cell(t, "fem, corot");
  tb_table_num(t, 1.5, "%.2f");
  tb_table_num(t, 2, "%.0f");
  tb_table_num(t, NAN, "%.1f");
  tb_suite_table(s, t);
  TB_CHECK_MSG(tb_suite_end(s, &err) == 0, "%s", err.msg);
  char *text = tb_test_slurp(path_in(dir, "table-speed.long.csv"));
  TB_CHECK_MSG(text && !strcmp(text, "model,metric,value,unit\n\"fem, corot\",time,1.5,ms\n"
                                     "\"fem, corot\",steps/s (CPU),2,\n"),
               "%s", text ? text : "(missing)");
  free(text);
}

const tb_test_case tb_tests_results[] = {
    {"long_csv", long_csv},
    {"incomplete_mark", incomplete_mark},
    {"json_validator", test_json_validator},
    {"stats_odd", test_stats_odd},
    {"stats_even", test_stats_even},
    {"stats_one_and_none", test_stats_one_and_none},
    {"suite_writes_files", test_suite_writes_files},
    {"table_md", test_table_md},
    {"csv_checker", test_csv_checker},
    {"data_csv", test_data_csv},
    {"mixed_column_reported", test_mixed_column_reported},
    {"data_json", test_data_json},
    {"context", test_context},
    {"misuse_reported", test_misuse_reported},
    {"write_data", test_write_data},
    {"chart", test_chart},
    {"chart_errors", test_chart_errors},
    {"svg_series_checker", test_svg_series_checker},
    {"chart_palette", test_chart_palette},
    {"chart_paper_series", test_chart_paper_series},
    {"progress_silent_without_tty", test_progress_silent_without_tty},
    {"progress_on_tty", test_progress_on_tty},
    {"progress_eta", test_progress_eta},
    {"progress_total_never_jumps", test_progress_total_never_jumps},
    {"report", test_report},
    {0, 0},
};
