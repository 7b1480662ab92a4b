/* Mesh-mesh collision end to end: the collide CLI with every method against
 * brute force, its errors, and the 4.2 and refit tables (small scale). */
#include <stdio.h>
#include <string.h>

#include "tb_test.h"

/* `collide --bvh M a.obj b.obj --xform-b X --pairs` output for method M. */
static int pairs_of(const char *method, const char *xform, char *buf, int cap) {
  char cmd[2048];
  snprintf(cmd, sizeof cmd,
           "'%s' collide --bvh %s %s/a.obj %s/b.obj --xform-b '%s' --pairs 2>/dev/null",
           tb_test_cli(), method, tb_test_tmpdir(), tb_test_tmpdir(), xform);
  return tb_test_run(cmd, buf, cap);
}

static void collide_cli_all_methods(void) {
  char args[1024];
  snprintf(args, sizeof args, "mesh sphere --set verts=252 --out %s/a.obj", tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0);
  snprintf(args, sizeof args, "mesh instrument --out %s/b.obj", tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0);
  static const char *xf[] = {"1 0 0 0.3  0 1 0 0.1  0 0 1 -2", "0 0 1 0  0 1 0 0.2  -1 0 0 0.5",
                             "1 0 0 5  0 1 0 0  0 0 1 0"};
  static char truth[1 << 16], got[1 << 16];
  static const char *methods[] = {"sphere",   "aabb",       "composite",
                                  "fcl-aabb", "fcl-obbrss", "bullet-gimpact-exact"};
  for (int x = 0; x < 3; x++) {
    TB_CHECK(pairs_of("brute", xf[x], truth, sizeof truth) == 0);
    if (x < 2)
      TB_CHECK_MSG(strlen(truth) > 20, "pose %d: too few pairs to be a test", x);
    else
      TB_CHECK(truth[0] == 0); /* far apart */
    for (int m = 0; m < 6; m++) {
      TB_CHECK(pairs_of(methods[m], xf[x], got, sizeof got) == 0);
      TB_CHECK_MSG(!strcmp(got, truth), "%s differs from brute force at pose %d", methods[m], x);
    }
  }
  snprintf(args, sizeof args, "collide --bvh composite %s/a.obj %s/b.obj --tritest moller",
           tb_test_tmpdir(), tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "volume tests") &&
           strstr(tb_test_out, "triangle tests (moller)"));
  snprintf(args, sizeof args, "collide --bvh kd-tree %s/a.obj %s/b.obj", tb_test_tmpdir(),
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2);
  snprintf(args, sizeof args, "collide --bvh aabb %s/a.obj %s/b.obj --xform-b '1 2 3'",
           tb_test_tmpdir(), tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2);
  snprintf(args, sizeof args, "collide --bvh fcl-aabb --tritest exact %s/a.obj %s/b.obj",
           tb_test_tmpdir(), tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2);
  snprintf(args, sizeof args, "collide --bvh aabb %s/a.obj %s/missing.obj", tb_test_tmpdir(),
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2);
}

static void tables_42_refit(void) {
  char args[1024], cmd[1024];
  snprintf(args, sizeof args, "table 4.2 --scale 0.01 --results %s/r", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "cat %s/r/table-4.2/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK(strstr(tb_test_out, "1106") && strstr(tb_test_out, "53.2") &&
           strstr(tb_test_out, "composite+exact (queries/s)") && strstr(tb_test_out, "fcl-obbrss"));
  snprintf(cmd, sizeof cmd, "test -s %s/r/table-4.2/table42.svg", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  snprintf(args, sizeof args, "table refit --scale 0.01 --results %s/r", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "cat %s/r/refit/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK(strstr(tb_test_out, "fcl-aabb refit") && strstr(tb_test_out, "3 of 3"));
}

const tb_test_case tb_tests_collide[] = {
    {"collide_cli_all_methods", collide_cli_all_methods},
    {"tables_42_refit", tables_42_refit},
    {0, 0},
};
