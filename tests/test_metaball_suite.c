/* The `metaball` suite (suites/suite_metaball.c, the metaball patent's
 * tables and figures) run small (--scale 0.01: the steak
 * alone, few frames), twice: its tables carry the patent's figures beside
 * ours, the steak has exactly its 1266 vertices and 539 spheres and the cut
 * leaves two pieces of a closed 2-manifold, table 2's tet steaks are within
 * 2% of the patent's element counts with the cut cells empty, every model
 * of the convergence table has a row, the pictures exist, and the two runs
 * give the same re-packing table and the same pictures byte for byte. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"

/* The suite's file into buf; 0 when it was read. */
static int slurp(const char *run, const char *file, char *buf, int cap) {
  char cmd[700];
  snprintf(cmd, sizeof cmd, "cat %s/%s/metaball/%s", tb_test_tmpdir(), run, file);
  return tb_test_run(cmd, buf, cap);
}

static void metaball_suite_smoke(void) {
  static char csv[16384];
  char args[600], cmd[900];
  const char *tmp = tb_test_tmpdir();
  for (int k = 0; k < 2; k++) {
    snprintf(args, sizeof args, "table metaball --scale 0.01 --results %s/rm%d", tmp, k);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  }
  TB_CHECK(slurp("rm0", "table.md", tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(
      strstr(tb_test_out, "| 1.80 |") && strstr(tb_test_out, "| 2.40 |") &&
          strstr(tb_test_out, "| 25.2 |") && strstr(tb_test_out, "| 6.5 |") &&
          strstr(tb_test_out, "bit-identical to the first's: yes") &&
          strstr(tb_test_out, "SOFA liver-smooth: left out") &&
          strstr(tb_test_out, "(steak-before.png)") && strstr(tb_test_out, "(steak-after.png)") &&
          strstr(tb_test_out, "by element removal") && strstr(tb_test_out, "## Convergence"),
      "%s", tb_test_out);
  TB_CHECK(slurp("rm0", "table-table1.csv", csv, sizeof csv) == 0);
  TB_CHECK_MSG(tb_test_csv_num(csv, "steak", 2) == 1266 &&
                   tb_test_csv_num(csv, "steak", 3) == 539 &&
                   tb_test_csv_num(csv, "steak", 4) == 539,
               "%s", csv);
  TB_CHECK_MSG(tb_test_csv_num(csv, "steak", 7) > 80 && tb_test_csv_num(csv, "steak", 8) > 90,
               "coverage: %s", csv);
  TB_CHECK_MSG(tb_test_csv_num(csv, "steak", 9) > 0 && tb_test_csv_num(csv, "steak", 11) > 0 &&
                   tb_test_csv_num(csv, "steak", 13) > 0,
               "times: %s", csv);
  TB_CHECK_MSG(
      tb_test_csv_num(csv, "steak", 15) == 2 && !strcmp(tb_test_csv_cell(csv, "steak", 16), "yes"),
      "cut: %s", csv);
  TB_CHECK(slurp("rm0", "table-table2.csv", csv, sizeof csv) == 0);
  double fem = tb_test_csv_num(csv, "FEM + meshless", 3),
         pbd = tb_test_csv_num(csv, "PBD on tets", 3);
  TB_CHECK_MSG(fabs(fem - 6272) <= 0.02 * 6272 && fabs(pbd - 1477) <= 0.02 * 1477, "%s", csv);
  /* every row deforms and cuts: a cut frame's time, two closed pieces */
  static const char *rows[] = {"FEM + meshless", "PBD on tets", "the patent (metaball)"};
  for (int r = 0; r < 3; r++)
    TB_CHECK_MSG(tb_test_csv_num(csv, rows[r], 5) > 0 && tb_test_csv_num(csv, rows[r], 7) > 0 &&
                     tb_test_csv_num(csv, rows[r], 11) == 2 &&
                     !strcmp(tb_test_csv_cell(csv, rows[r], 12), "yes"),
                 "%s: %s", rows[r], csv);
  TB_CHECK(slurp("rm0", "table-convergence.csv", csv, sizeof csv) == 0);
  static const char *models[] = {"metaball", "pbd-stvk", "fem-corot", "msm"};
  for (int k = 0; k < 4; k++)
    TB_CHECK_MSG(tb_test_csv_num(csv, models[k], 4) > 0 && tb_test_csv_num(csv, models[k], 5) >= 0,
                 "%s: %s", models[k], csv);
  TB_CHECK(slurp("rm0", "table-repack.csv", csv, sizeof csv) == 0);
  TB_CHECK_MSG(tb_test_csv_num(csv, "steak", 1) > 0 && tb_test_csv_num(csv, "steak", 2) > 0 &&
                   tb_test_csv_num(csv, "steak", 7) > 0,
               "%s", csv);
  snprintf(cmd, sizeof cmd,
           "cd %s && cmp rm0/metaball/table-repack.csv rm1/metaball/table-repack.csv && "
           "cmp rm0/metaball/steak-before.png rm1/metaball/steak-before.png && "
           "cmp rm0/metaball/steak-after.png rm1/metaball/steak-after.png && "
           "test -s rm0/metaball/data.json",
           tmp);
  TB_CHECK_MSG(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0, "%s", tb_test_out);
}

const tb_test_case tb_tests_metaball_suite[] = {
    {"metaball_suite_smoke", metaball_suite_smoke},
    {NULL, NULL},
};
