/* The fuzzing harnesses' inputs in the normal test suite: every
 * file of tests/fuzz/regressions (named HARNESS-NAME, an input a harness
 * once broke the contract with) and of tests/fuzz/seeds/HARNESS/ goes
 * through the same reader and the same contract checks as the libFuzzer
 * harness (tests/fuzz/fuzz_targets.c, fuzz_check.c), and the checks
 * themselves are shown to catch each kind of broken contract. */
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "fuzz/fuzz_check.h"
#include "measure/tb_points.h"
#include "scenes/tb_scene_file.h"

static int by_name(const void *a, const void *b) {
  return strcmp(*(char *const *)a, *(char *const *)b);
}

/* The regular files of dir, sorted; *n of them (the caller frees). */
static char **files_in(const char *dir, int *n) {
  *n = 0;
  DIR *d = opendir(dir);
  if (!d) return NULL;
  char **v = NULL;
  int cap = 0;
  struct dirent *e;
  while ((e = readdir(d))) {
    if (e->d_name[0] == '.') continue;
    if (*n == cap) {
      char **w = realloc(v, sizeof *v * (size_t)(cap = cap ? 2 * cap : 16));
      if (!w) break;
      v = w;
    }
    v[(*n)++] = strdup(e->d_name);
  }
  closedir(d);
  if (*n) qsort(v, (size_t)*n, sizeof *v, by_name);
  return v;
}

/* Runs harness `name` on the file; a failed check names the file. Returns
 * 1 when the reader accepted the file. */
static int run_file(const char *name, const char *path) {
  const tb_fuzz_target *t = tb_fuzz_target_find(name);
  TB_CHECK_MSG(t != NULL, "%s: no harness '%s'", path, name);
  if (!t) return 0;
  long len = 0;
  char *data = NULL;
  FILE *f = fopen(path, "rb");
  if (f && !fseek(f, 0, SEEK_END) && (len = ftell(f)) >= 0 && !fseek(f, 0, SEEK_SET)) {
    data = malloc((size_t)len + 1);
    if (data && fread(data, 1, (size_t)len, f) != (size_t)len) free(data), data = NULL;
  }
  if (f) fclose(f);
  TB_CHECK_MSG(data != NULL, "cannot read %s", path);
  if (!data) return 0;
  char why[1024] = "";
  int rc = tb_fuzz_run(t, (const uint8_t *)data, (size_t)len, why, sizeof why);
  TB_CHECK_MSG(rc == 0, "fuzz_%s on %s: %s", name, path, why);
  free(data);
  return rc == 0 && tb_fuzz_accepted();
}

static void test_regressions(void) {
  char dir[600], path[900];
  snprintf(dir, sizeof dir, "%s/tests/fuzz/regressions", tb_test_source_root());
  int n;
  char **v = files_in(dir, &n);
  int runs = 0;
  for (int i = 0; i < n; i++) {
    char name[64];
    size_t len = strlen(v[i]);
    if (len > 3 && !strcmp(v[i] + len - 3, ".md")) { /* the folder's README */
      free(v[i]);
      continue;
    }
    runs++;
    snprintf(name, sizeof name, "%.*s", (int)strcspn(v[i], "-"), v[i]);
    snprintf(path, sizeof path, "%s/%s", dir, v[i]);
    run_file(name, path);
    free(v[i]);
  }
  free(v);
  if (runs == 0) printf("  no reproducers in %s: only the seeds and checks are tested\n", dir);
}

/* Every committed seed passes its harness and is a file its reader accepts
 * (so a harness that feeds its reader wrongly shows up). */
static void test_seeds(void) {
  int nt;
  const tb_fuzz_target *t = tb_fuzz_targets(&nt);
  int total = 0;
  for (int k = 0; k < nt; k++) {
    char dir[600], path[900];
    snprintf(dir, sizeof dir, "%s/tests/fuzz/seeds/%s", tb_test_source_root(), t[k].name);
    int n;
    char **v = files_in(dir, &n);
    for (int i = 0; i < n; i++) {
      snprintf(path, sizeof path, "%s/%s", dir, v[i]);
      TB_CHECK_MSG(run_file(t[k].name, path), "fuzz_%s: the reader refused the seed %s", t[k].name,
                   path);
      free(v[i]);
    }
    free(v);
    total += n;
  }
  TB_CHECK_MSG(total >= 10, "only %d seeds under tests/fuzz/seeds", total);
}

/* The checks break on each kind of broken contract. */
static void test_checks_catch(void) {
  char why[512];
  tb_error err = {{0}};
  tb_vec3 x[3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  int tri[3] = {0, 1, 2};
  tb_mesh m = {3, x, 1, tri, 0, NULL, 0};
  TB_CHECK(tb_fuzz_check_mesh("a.obj", 0, &m, &err, why, sizeof why) == 0);
  tri[2] = 3;
  TB_CHECK(tb_fuzz_check_mesh("a.obj", 0, &m, &err, why, sizeof why) != 0 && strstr(why, "index"));
  tri[2] = -1;
  TB_CHECK(tb_fuzz_check_mesh("a.obj", 0, &m, &err, why, sizeof why) != 0);
  tri[2] = 2;
  x[1].y = INFINITY;
  TB_CHECK(tb_fuzz_check_mesh("a.obj", 0, &m, &err, why, sizeof why) != 0);
  x[1].y = 0;
  /* a failed read: the mesh must be empty, the message name the file */
  snprintf(err.msg, sizeof err.msg, "a.obj:3: bad");
  TB_CHECK(tb_fuzz_check_mesh("a.obj", -1, &m, &err, why, sizeof why) != 0 && strstr(why, "left"));
  tb_mesh empty = {0, NULL, 0, NULL, 0, NULL, 0};
  TB_CHECK(tb_fuzz_check_mesh("a.obj", -1, &empty, &err, why, sizeof why) == 0);
  static const char *const bad[] = {"b.obj:3: bad", "a.obj:0: bad", "a.obj:3 bad", "a.obj:",
                                    "a.obj: ",      "a.obj3: bad",  "x a.obj: bad"};
  for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
    snprintf(err.msg, sizeof err.msg, "%s", bad[i]);
    TB_CHECK_MSG(tb_fuzz_check_error("a.obj", &err, why, sizeof why) != 0, "'%s' passed", bad[i]);
  }
  snprintf(err.msg, sizeof err.msg, "a.obj: cannot open");
  TB_CHECK(tb_fuzz_check_error("a.obj", &err, why, sizeof why) == 0);
  /* TetGen: the .ele or .face beside the .node may be named, no other */
  snprintf(err.msg, sizeof err.msg, "d/a.ele:2: bad");
  TB_CHECK(tb_fuzz_check_error("d/a.node", &err, why, sizeof why) == 0);
  snprintf(err.msg, sizeof err.msg, "d/a.face: bad");
  TB_CHECK(tb_fuzz_check_error("d/a.node", &err, why, sizeof why) == 0);
  snprintf(err.msg, sizeof err.msg, "d/a.elf:2: bad");
  TB_CHECK(tb_fuzz_check_error("d/a.node", &err, why, sizeof why) != 0);
  snprintf(err.msg, sizeof err.msg, "d/a.ele:2: bad");
  TB_CHECK(tb_fuzz_check_error("d/a.obj", &err, why, sizeof why) != 0);
  /* spheres, pairs, points */
  tb_vec3 c = {0, 0, 0};
  double r = 0;
  tb_spheres s = {1, &c, &r, -1};
  TB_CHECK(tb_fuzz_check_spheres("a.sph", 0, &s, &err, why, sizeof why) != 0);
  r = 1;
  TB_CHECK(tb_fuzz_check_spheres("a.sph", 0, &s, &err, why, sizeof why) == 0);
  tb_tripair pr;
  memset(&pr, 0, sizeof pr);
  signed char expect = 2;
  tb_pairset ps = {1, 1, &pr, &expect, NULL};
  TB_CHECK(tb_fuzz_check_pairs("a.txt", 0, &ps, &err, why, sizeof why) != 0);
  expect = 1;
  TB_CHECK(tb_fuzz_check_pairs("a.txt", 0, &ps, &err, why, sizeof why) == 0);
  tb_point pt;
  memset(&pt, 0, sizeof pt);
  pt.line = 1; /* line 1 is the header */
  TB_CHECK(tb_fuzz_check_points("a.csv", 0, &pt, 1, &err, why, sizeof why) != 0);
  pt.line = 2;
  TB_CHECK(tb_fuzz_check_points("a.csv", 0, &pt, 1, &err, why, sizeof why) == 0);
  TB_CHECK(tb_fuzz_check_points("a.csv", -1, &pt, 1, &err, why, sizeof why) != 0);
}

/* The TetGen harness splits its input into .node, .ele and .face. */
static void test_tetgen_split(void) {
  static const char in[] = "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n#@ele\n1 4 0\n1 1 2 3 4\n";
  char why[512] = "";
  const tb_fuzz_target *t = tb_fuzz_target_find("tetgen");
  TB_CHECK(t && tb_fuzz_run(t, (const uint8_t *)in, sizeof in - 1, why, sizeof why) == 0);
  /* the .node alone (the first run's .ele removed) keeps the contract too */
  TB_CHECK(t && tb_fuzz_run(t, (const uint8_t *)in, 40, why, sizeof why) == 0);
}

/* Found by fuzz_scene: an empty id_file read the scene's folder as the id
 * file ("DIR/: no node ids in the file"), and a folder was taken for a mesh
 * or id file. Each is now "SCENE:LINE: ..." saying what is wrong, and an
 * error inside an id file follows the scene's line with the id file's own
 * "FILE:LINE: reason". */
static void test_scene_paths(void) {
  static const struct {
    const char *text;
    int line;
    const char *reason;
  } cases[] = {
      {"[fix]\nid_file =\n", 2, "no file named"},
      {"[fix]\nid_file = .\n", 2, "a folder, not a file"},
      {"[mesh]\nfile = .\n", 2, "a folder, not a file"},
      {"[mesh]\nfile =\n", 2, "no file named"},
      {"[scene]\n\n[fix]\nid_file = sp-ids.txt\n", 4, "sp-ids.txt:2: not a node id"},
  };
  tb_test_file("sp-ids.txt", "1 2\n3 x\n", -1);
  for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
    const char *path = tb_test_file("sp.ini", cases[i].text, -1);
    char prefix[700];
    snprintf(prefix, sizeof prefix, "%s:%d: ", path, cases[i].line);
    tb_scene_desc d;
    tb_error err = {{0}};
    int rc = tb_scene_desc_load(&d, path, &err);
    TB_CHECK_MSG(rc != 0, "'%s' loaded", cases[i].text);
    if (rc == 0) {
      tb_scene_desc_free(&d);
      continue;
    }
    TB_CHECK_MSG(!strncmp(err.msg, prefix, strlen(prefix)) && strstr(err.msg, cases[i].reason),
                 "'%s': message '%s', expected '%s...%s'", cases[i].text, err.msg, prefix,
                 cases[i].reason);
  }
}

const tb_test_case tb_tests_fuzz_regressions[] = {
    {"scene_paths", test_scene_paths},   {"checks_catch", test_checks_catch},
    {"tetgen_split", test_tetgen_split}, {"seeds", test_seeds},
    {"regressions", test_regressions},   {NULL, NULL},
};
