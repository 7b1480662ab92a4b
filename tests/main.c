/* Test runner: runs every case of every table in its own child process (a
 * crash fails that case, not the run), prints failures and SKIP lines, and
 * ends with "N passed, N failed, N skipped". Arguments: substrings; a case
 * runs when its "suite/name" contains any of them (all run without any).
 * --list prints the selected cases' names without running them; a filter
 * that selects nothing is an error (exit 2). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "tb_test.h"
#include "core/tb_mesh_io.h"
#include "core/tb_threads.h"
#include "reference/tb_oracles.h"

#define SKIP_CODE 77

static int failures;
static int skipped;
static char tmpdir[512];

void tb_test_fail(const char *file, int line, const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "  %s:%d: check failed: ", file, line);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  failures++;
}

void tb_test_skip(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  printf("SKIP: ");
  vprintf(fmt, ap);
  putchar('\n');
  va_end(ap);
  skipped = 1;
}

/* Reads path expecting failure with message "in:LINE: ...REASON..." (line
 * 0: "in: ...", -1: any line or none) and an empty mesh; `in` is the file
 * the reader blames (path itself, or a partner such as a TetGen .ele). */
void tb_test_expect_read_error_in(const char *path, const char *in, long line, const char *reason) {
  tb_mesh m;
  tb_error err = {{0}};
  char prefix[700];
  if (line > 0)
    snprintf(prefix, sizeof prefix, "%s:%ld: ", in, line);
  else
    snprintf(prefix, sizeof prefix, "%s:%s", in, line ? "" : " ");
  int rc = tb_mesh_read(path, &m, &err);
  TB_CHECK_MSG(rc != 0, "%s: read should fail (%s)", path, reason);
  TB_CHECK_MSG(strncmp(err.msg, prefix, strlen(prefix)) == 0, "message '%s' lacks prefix '%s'",
               err.msg, prefix);
  TB_CHECK_MSG(strstr(err.msg, reason) != NULL, "message '%s' lacks '%s'", err.msg, reason);
  TB_CHECK(m.nv == 0 && m.ntri == 0 && m.ntet == 0 && !m.x && !m.tri && !m.tet);
  if (rc == 0) tb_mesh_free(&m);
}

void tb_test_expect_read_error(const char *path, long line, const char *reason) {
  tb_test_expect_read_error_in(path, path, line, reason);
}

void tb_test_expect_read_errors(const tb_test_bad_file *c) {
  for (; c->name; c++)
    tb_test_expect_read_error(tb_test_file(c->name, c->text, -1), c->line, c->reason);
}

const char *tb_test_tmp_path(const char *name) {
  static char p[4][600];
  static int slot;
  char *s = p[slot++ % 4];
  snprintf(s, 600, "%s/%s", tb_test_tmpdir(), name);
  return s;
}

/* The whole file as a string (NULL when unreadable); the caller frees. */
char *tb_test_slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  size_t n = 0, cap = 4096;
  char *s = malloc(cap);
  int c;
  while (s && (c = fgetc(f)) != EOF) {
    if (n + 1 >= cap) {
      char *t = realloc(s, cap *= 2);
      if (!t) free(s);
      s = t;
    }
    if (s) s[n++] = (char)c;
  }
  fclose(f);
  if (s) s[n] = 0;
  return s;
}

const char *tb_test_tmpdir(void) { return tmpdir; }
const char *tb_test_cli(void) { return TB_BUILD_ROOT "/tissuebench"; }
const char *tb_test_source_root(void) { return TB_SOURCE_ROOT; }

int tb_test_csv_field(const char *line, int k, char *out, size_t cap) {
  size_t n = 0;
  int quoted = 0, f = 0;
  for (const char *p = line; *p && *p != '\n' && f <= k; p++) {
    if (*p == '"')
      quoted = !quoted;
    else if (*p == ',' && !quoted)
      f++;
    else if (f == k && n + 1 < cap)
      out[n++] = *p;
  }
  out[n] = 0;
  return f >= k;
}

const char *tb_test_csv_cell(const char *csv, const char *name, int k) {
  static char f[256];
  for (const char *line = csv; line && *line;
       line = strchr(line, '\n'), line = line ? line + 1 : NULL)
    if (tb_test_csv_field(line, 0, f, sizeof f) && !strcmp(f, name)) {
      if (!tb_test_csv_field(line, k, f, sizeof f)) f[0] = 0;
      return f;
    }
  return "";
}

double tb_test_csv_num(const char *csv, const char *name, int k) {
  const char *c = tb_test_csv_cell(csv, name, k);
  return c[0] ? atof(c) : NAN;
}

const char *tb_test_file(const char *name, const char *content, long len) {
  static char paths[8][600];
  static int slot;
  char *p = paths[slot++ % 8];
  snprintf(p, 600, "%s/%s", tmpdir, name);
  FILE *f = fopen(p, "wb");
  if (!f) {
    tb_test_fail(__FILE__, __LINE__, "cannot write %s", p);
    return p;
  }
  fwrite(content, 1, len < 0 ? strlen(content) : (size_t)len, f);
  fclose(f);
  return p;
}

int tb_test_run(const char *cmd, char *out, int cap) {
  char full[4096];
  snprintf(full, sizeof full, "(%s) 2>&1", cmd);
  FILE *p = popen(full, "r");
  if (!p) return -1;
  int n = 0, c;
  while ((c = fgetc(p)) != EOF)
    if (out && n < cap - 1) out[n++] = (char)c;
  if (out && cap > 0) out[n] = 0;
  int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

char tb_test_out[1 << 16];

int tb_test_cli_run(const char *args) {
  char cmd[4096];
  snprintf(cmd, sizeof cmd, "'%s' %s", tb_test_cli(), args);
  return tb_test_run(cmd, tb_test_out, sizeof tb_test_out);
}

static const struct {
  const char *name;
  const tb_test_case *cases;
} suites[] = {
    {"layers", tb_tests_layers},
    {"verdicts", tb_tests_verdicts},
    {"core", tb_tests_core},
    {"io", tb_tests_io},
    {"io_hostile", tb_tests_io_hostile},
    {"vtu", tb_tests_vtu},
    {"mc", tb_tests_mc},
    {"results", tb_tests_results},
    {"meshgen", tb_tests_meshgen},
    {"cli", tb_tests_cli},
    {"tetmesh", tb_tests_tetmesh},
    {"tritri_fast", tb_tests_tritri_fast},
    {"tritri_exact", tb_tests_tritri_exact},
    {"refs", tb_tests_refs},
    {"tritri", tb_tests_tritri},
    {"bvh", tb_tests_bvh},
    {"refbvh", tb_tests_refbvh},
    {"collide", tb_tests_collide},
    {"models", tb_tests_models},
    {"msm", tb_tests_msm},
    {"msm_vvs", tb_tests_msm_vvs},
    {"fem", tb_tests_fem},
    {"fem_corot", tb_tests_fem_corot},
    {"sm", tb_tests_sm},
    {"pbd", tb_tests_pbd},
    {"reference", tb_tests_reference},
    {"fidelity", tb_tests_fidelity},
    {"stability", tb_tests_stability},
    {"scenes", tb_tests_scenes},
    {"render", tb_tests_render},
    {"pbd_stiffness", tb_tests_pbd_stiffness},
    {"lod", tb_tests_lod},
    {"vvs_refine", tb_tests_vvs_refine},
    {"metaball", tb_tests_metaball},
    {"softbody", tb_tests_softbody},
    {"bullet_models", tb_tests_bullet_models},
    {"butterfly", tb_tests_butterfly},
    {"sph", tb_tests_sph},
    {"meshless", tb_tests_meshless},
    {"fold", tb_tests_fold},
    {"fold_tri", tb_tests_fold_tri},
    {"organs", tb_tests_organs},
    {"metaball_model", tb_tests_metaball_model},
    {"organ_cut", tb_tests_organ_cut},
    {"cuts", tb_tests_cuts},
    {"metaball_cut", tb_tests_metaball_cut},
    {"carve", tb_tests_carve},
    {"cut_surface", tb_tests_cut_surface},
    {"metaball_suite", tb_tests_metaball_suite},
    {"shard", tb_tests_shard},
    {"scaling", tb_tests_scaling},
    {"fuzz_regressions", tb_tests_fuzz_regressions},
};

static int selected(const char *id, int argc, char **argv) {
  if (argc < 2) return 1;
  for (int i = 1; i < argc; i++)
    if (strstr(id, argv[i])) return 1;
  return 0;
}

/* Runs one case in a child; returns 0 pass, 1 fail, 2 skip. */
static int run_case(const tb_test_case *tc) {
  fflush(stdout);
  fflush(stderr);
  pid_t pid = fork();
  if (pid == 0) {
    tc->fn();
    fflush(stdout);
    exit(failures ? 1 : (skipped ? SKIP_CODE : 0)); /* exit, so LeakSanitizer checks */
  }
  int st = 0;
  if (pid < 0 || waitpid(pid, &st, 0) < 0) return 1;
  if (WIFSIGNALED(st)) {
    fprintf(stderr, "  crashed with signal %d\n", WTERMSIG(st));
    return 1;
  }
  int code = WEXITSTATUS(st);
  return code == 0 ? 0 : (code == SKIP_CODE ? 2 : 1);
}

/* Prints the selected "suite/name" lines; returns how many. */
static int list_cases(int argc, char **argv, int print) {
  int n = 0;
  for (size_t s = 0; s < sizeof suites / sizeof suites[0]; s++)
    for (const tb_test_case *tc = suites[s].cases; tc->name; tc++) {
      char id[256];
      snprintf(id, sizeof id, "%s/%s", suites[s].name, tc->name);
      if (!selected(id, argc, argv)) continue;
      if (print) printf("%s\n", id);
      n++;
    }
  return n;
}

int main(int argc, char **argv) {
  tb_threads_environment(0, argv);
  tb_oracles_register();
  int list = 0, k = 1; /* drop --list from the filters */
  for (int i = 1; i < argc; i++) {
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      printf(
          "usage: tissuebench test [--list] [SUBSTRING...]\n"
          "  runs the test cases whose \"suite/name\" contains any SUBSTRING (all without), each\n"
          "  in its own process; ends with \"N passed, N failed, N skipped\" (exit 1 on a "
          "failure);\n"
          "  --list prints their names without running them; no match is an error (exit 2)\n");
      return 0;
    }
    if (strcmp(argv[i], "--list") == 0)
      list = 1;
    else
      argv[k++] = argv[i];
  }
  argc = k;
  int nsel = list_cases(argc, argv, list);
  if (nsel == 0) {
    fprintf(stderr, "tb_tests: no test case matches");
    for (int i = 1; i < argc; i++) fprintf(stderr, " '%s'", argv[i]);
    fprintf(stderr, " (tissuebench test --list shows them)\n");
    return 2;
  }
  if (list) return 0;
  snprintf(tmpdir, sizeof tmpdir, "%s/tb_tests.XXXXXX",
           getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 2;
  }
  int npass = 0, nfail = 0, nskip = 0;
  for (size_t s = 0; s < sizeof suites / sizeof suites[0]; s++) {
    for (const tb_test_case *tc = suites[s].cases; tc->name; tc++) {
      char id[256];
      snprintf(id, sizeof id, "%s/%s", suites[s].name, tc->name);
      if (!selected(id, argc, argv)) continue;
      int r = run_case(tc);
      printf("%s %s\n", r == 0 ? "ok  " : (r == 1 ? "FAIL" : "skip"), id);
      if (r == 0)
        npass++;
      else if (r == 1)
        nfail++;
      else
        nskip++;
    }
  }
  char rm[600];
  snprintf(rm, sizeof rm, "rm -rf '%s'", tmpdir);
  if (system(rm) != 0) fprintf(stderr, "warning: could not remove %s\n", tmpdir);
  printf("%d passed, %d failed, %d skipped\n", npass, nfail, nskip);
  return nfail ? 1 : 0;
}
