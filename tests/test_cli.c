/* The command line, end to end through the built binary: help, --help of
 * every subcommand, exit codes, mesh info, mesh generation, reproduce. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_test.h"
#include "collision/tb_pairs.h"
#include "commands/tb_cli.h"
#include "measure/tb_fidelity.h"
#include "measure/tb_points.h"
#include "models/tb_model.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"
#include "suites/tb_suites.h"

static void help_lists_commands(void) {
  TB_CHECK(tb_test_cli_run("help") == 0);
  static const char *names[] = {"help", "reproduce", "test", "mesh"};
  for (int i = 0; i < 4; i++)
    TB_CHECK_MSG(strstr(tb_test_out, names[i]), "help lacks %s", names[i]);
  for (int i = 0; i < 4; i++) {
    char args[64];
    snprintf(args, sizeof args, "%s --help", names[i]);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0 && strstr(tb_test_out, "tissuebench"), "%s --help: %s",
                 names[i], tb_test_out);
  }
  TB_CHECK(tb_test_cli_run("frobnicate") == 2 && strstr(tb_test_out, "unknown command"));
  TB_CHECK(tb_test_cli_run("") == 2);
}

static void mesh_generate_and_info(void) {
  char args[1024];
  snprintf(args, sizeof args, "mesh sphere --set verts=1002 --out %s/s.obj", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh info %s/s.obj", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK(strstr(tb_test_out, "vertices    1002") && strstr(tb_test_out, "triangles   2000"));
  TB_CHECK(strstr(tb_test_out, "closed      yes") && strstr(tb_test_out, "manifold    yes"));
  TB_CHECK(strstr(tb_test_out, "Euler 2"));
  TB_CHECK(tb_test_cli_run("mesh sphere --set verts=250 --stats") == 2 &&
           strstr(tb_test_out, "10 f^2 + 2"));
  TB_CHECK(tb_test_cli_run("mesh sphere --set verts=abc --stats") == 2);
  TB_CHECK(tb_test_cli_run("mesh sphere --set colour=3 --stats") == 2);
  TB_CHECK(tb_test_cli_run("mesh teapot --stats") == 2);
  TB_CHECK(tb_test_cli_run("mesh sphere") == 2); /* neither --out nor --stats */
  TB_CHECK(tb_test_cli_run("mesh list") == 0 && strstr(tb_test_out, "liver") &&
           strstr(tb_test_out, "surface_verts"));
}

/* A tet mesh written as a surface carries only its boundary's vertices. */
static void mesh_surface_compact(void) {
  char args[1024];
  snprintf(args, sizeof args, "mesh beam --set nx=3 --set ny=3 --set nz=3 --out %s/b.off",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  snprintf(args, sizeof args, "mesh info %s/b.off", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  TB_CHECK_MSG(strstr(tb_test_out, "vertices    56\n") && strstr(tb_test_out, "closed      yes"),
               "%s", tb_test_out);
}

static void mesh_info_errors(void) {
  const char *bad = tb_test_file("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", -1);
  char args[1024];
  snprintf(args, sizeof args, "mesh info %s", bad);
  TB_CHECK(tb_test_cli_run(args) == 2);
  char want[700];
  snprintf(want, sizeof want, "%s:4:", bad);
  TB_CHECK_MSG(strstr(tb_test_out, want) != NULL, "got: %s", tb_test_out);
  snprintf(args, sizeof args, "mesh info %s/missing.obj", tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 2);
  const char *unknown = tb_test_file("x.xyz", "1 2 3\n", -1);
  snprintf(args, sizeof args, "mesh info %s", unknown);
  TB_CHECK(tb_test_cli_run(args) == 2);
  TB_CHECK(tb_test_cli_run("mesh info") == 2);
}

static void liver_stats_deterministic(void) {
  char args[1024];
  TB_CHECK(tb_test_cli_run("mesh liver --stats") == 0);
  TB_CHECK(strstr(tb_test_out, "surface vertices") && strstr(tb_test_out, "725") &&
           strstr(tb_test_out, "tets") && strstr(tb_test_out, "4230") &&
           strstr(tb_test_out, "closed, manifold"));
  for (int k = 0; k < 2; k++) {
    snprintf(args, sizeof args, "mesh liver --part %s --out %s/liver%d.vtk", k ? "faces" : "tets",
             tb_test_tmpdir(), k);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  }
  snprintf(args, sizeof args, "mesh liver --part tets --out %s/again.vtk", tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0);
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cmp %s/liver0.vtk %s/again.vtk", tb_test_tmpdir(), tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0, "not byte-identical: %s",
               tb_test_out);
  snprintf(cmd, sizeof cmd, "cmp -s %s/liver0.vtk %s/liver1.vtk", tb_test_tmpdir(),
           tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, NULL, 0) != 0); /* the parts differ */
  snprintf(args, sizeof args, "mesh liver --part edges --out %s/liver.edges", tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 0);
  TB_CHECK(tb_test_cli_run("mesh liver --part bones --stats") == 2);
}

/* REPORT.md of `reproduce --only meshes` (run by reproduce_meshes_suite):
 * the context once, the meshes table, the other suites said not run, and
 * every relative link naming a file that exists. */
static void report_of_meshes(void) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cat %s/res/REPORT.md", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0, "no REPORT.md");
  const char *md = tb_test_out;
  const char *seed = strstr(md, "- **Seed**: ");
  TB_CHECK_MSG(seed && !strstr(seed + 1, "- **Seed**: ") && strstr(md, "- **Commit**: "),
               "the context not once: %s", md);
  TB_CHECK(strstr(md, "**Date**") && strstr(strstr(md, "**Date**") + 1, "**Date**") == NULL);
  TB_CHECK(strstr(md, "## Chapter 2: meshes") && strstr(md, "### meshes: "));
  TB_CHECK(strstr(md, "| liver |") && strstr(md, "#### Mesh counts"));
  TB_CHECK(strstr(md, "Not run this time (`--only`): `table-3.5`") && strstr(md, "`figures`."));
  TB_CHECK(strstr(md, "Chapter 4") == NULL); /* none of its suites ran */
  static const char *names[] = {"table-3.5", "figure-3.10", "reference",     "calibration",
                                "pareto",    "stability",   "pbd-stiffness", "correctness",
                                "table-4.1", "table-4.2",   "refit",         "pbd",
                                "scaling",   "figures"};
  const char *notrun = strstr(md, "Not run this time");
  for (int i = 0; notrun && i < 14; i++) {
    char want[40];
    snprintf(want, sizeof want, "`%s`", names[i]);
    TB_CHECK_MSG(strstr(notrun, want), "%s not listed", names[i]);
  }
  int links = 0;
  for (const char *p = strstr(md, "]("); p; p = strstr(p + 1, "](")) {
    const char *e = strchr(p + 2, ')');
    if (!e) break;
    char link[300];
    snprintf(link, sizeof link, "%.*s", (int)(e - p - 2), p + 2);
    TB_CHECK_MSG(link[0] != '/' && !strstr(link, "://"), "not relative: %s", link);
    char test[1024];
    snprintf(test, sizeof test, "test -s '%s/res/%s'", tb_test_tmpdir(), link);
    TB_CHECK_MSG(tb_test_run(test, NULL, 0) == 0, "REPORT.md links to a missing %s", link);
    links++;
  }
  TB_CHECK_MSG(links >= 2, "%d links", links); /* table.md and data.json */
}

static void reproduce_meshes_suite(void) {
  TB_CHECK(tb_test_cli_run("reproduce --list") == 0 && strstr(tb_test_out, "meshes"));
  TB_CHECK(tb_test_cli_run("reproduce --only nonsense") == 2);
  TB_CHECK(tb_test_cli_run("reproduce --seed x") == 2);
  char args[1024];
  /* into a pipe, the progress is written as whole lines (here every one: the interval 0) */
  snprintf(args, sizeof args,
           "TB_PROGRESS_LOG_S=0 '%s' reproduce --only meshes --results %s/res 2>&1 | cat",
           tb_test_cli(), tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(args, tb_test_out, sizeof tb_test_out) == 0 &&
                   strstr(tb_test_out, "\nmeshes [") && strstr(tb_test_out, "left\n") &&
                   !strchr(tb_test_out, '\r'),
               "%s", tb_test_out);
  snprintf(args, sizeof args, "test -e %s/res/meshes/" TB_INCOMPLETE, tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(args, NULL, 0) != 0, "a finished suite is marked incomplete");
  static const char *files[] = {"table.md",       "table-counts.csv", "data.json",
                                "liver.vtk",      "liver-faces.obj",  "instrument.obj",
                                "sphere-252.obj", "sphere-1002.obj"};
  for (int i = 0; i < 8; i++) {
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "test -s %s/res/meshes/%s", tb_test_tmpdir(), files[i]);
    TB_CHECK_MSG(tb_test_run(cmd, NULL, 0) == 0, "missing %s", files[i]);
  }
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "cat %s/res/meshes/table.md", tb_test_tmpdir());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK(strstr(tb_test_out, "1448") && strstr(tb_test_out, "9313") &&
           strstr(tb_test_out, "6288") && strstr(tb_test_out, "1248"));
  TB_CHECK(strstr(tb_test_out, "| liver |") && strstr(tb_test_out, "NO") == NULL);
  report_of_meshes();
}

/* scripts/setup.sh with fake dpkg-query and id on PATH: a missing package as
 * non-root prints the apt-get line and fails; all present succeeds. */
static void setup_script(void) {
  const char *dir = tb_test_tmpdir();
  char cmd[2048];
  snprintf(cmd, sizeof cmd,
           "mkdir -p %s/fakebin && printf '#!/bin/sh\necho 1000\n' > %s/fakebin/id && "
           "printf '#!/bin/sh\ncase \"$3\" in libcgal-dev) exit 1;; esac\n"
           "echo \"install ok installed\"\n' > %s/fakebin/dpkg-query && chmod +x %s/fakebin/*",
           dir, dir, dir, dir);
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  snprintf(cmd, sizeof cmd, "PATH=%s/fakebin:$PATH sh %s/scripts/setup.sh", dir,
           tb_test_source_root());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) != 0);
  TB_CHECK_MSG(strstr(tb_test_out, "apt-get install -y libcgal-dev") != NULL, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "sed -i 's/libcgal-dev/none-such/' %s/fakebin/dpkg-query", dir);
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  snprintf(cmd, sizeof cmd, "PATH=%s/fakebin:$PATH sh %s/scripts/setup.sh", dir,
           tb_test_source_root());
  TB_CHECK_MSG(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0, "%s", tb_test_out);
}

static void version_flag(void) {
  TB_CHECK_MSG(tb_test_cli_run("--version") == 0, "%s", tb_test_out);
  char want[64];
  snprintf(want, sizeof want, "tissuebench %s", TB_VERSION);
  TB_CHECK_MSG(strncmp(tb_test_out, want, strlen(want)) == 0, "got: %s", tb_test_out);
  /* the version line, then where the files, the shared data and the results are */
  TB_CHECK_MSG(strstr(tb_test_out, "\nfiles:   ") && strstr(tb_test_out, "\ndata:    ") &&
                   strstr(tb_test_out, "\nresults: "),
               "%s", tb_test_out);
}

/* tb_tests --list names cases without running them; no match fails. */
static void test_runner_list_and_no_match(void) {
  char cmd[1024];
  snprintf(cmd, sizeof cmd, "'%s/tb_tests' --list cli/", TB_BUILD_ROOT);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK_MSG(
      strstr(tb_test_out, "cli/version_flag\n") && strstr(tb_test_out, "cli/setup_script\n"), "%s",
      tb_test_out);
  TB_CHECK(strstr(tb_test_out, "results/") == NULL); /* only the selected ones */
  TB_CHECK(strstr(tb_test_out, "passed") == NULL);   /* nothing ran */
  snprintf(cmd, sizeof cmd, "'%s/tb_tests' --list", TB_BUILD_ROOT);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0);
  TB_CHECK(strstr(tb_test_out, "results/data_json\n") && strstr(tb_test_out, "core/"));
  snprintf(cmd, sizeof cmd, "'%s/tb_tests' no-such-case-xyz", TB_BUILD_ROOT);
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "no test case matches 'no-such-case-xyz'"), "%s", tb_test_out);
  TB_CHECK(strstr(tb_test_out, "passed") == NULL);
}

/* ---- hostile command lines ---- */

/* A sanitizer build's LeakSanitizer turns a leak into exit 23 and a report: the exit codes
 * below and the absence of the report both catch it. */
static void no_leak_report(const char *what) {
  TB_CHECK_MSG(!strstr(tb_test_out, "LeakSanitizer") && !strstr(tb_test_out, "AddressSanitizer"),
               "%s: %s", what, tb_test_out);
}

/* Item 3: `mesh NAME --out` that cannot be written (unknown extension, missing folder) frees
 * the mesh: through the binary and in this process (LeakSanitizer at the end of tb_tests). */
static void mesh_out_errors_no_leak(void) {
  char args[1024];
  snprintf(args, sizeof args, "mesh sphere --out %s/x.xyz", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "unknown extension"), "%s",
               tb_test_out);
  no_leak_report("unknown extension");
  snprintf(args, sizeof args, "mesh sphere --out %s/no/such/dir/x.obj", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 1 && strstr(tb_test_out, "x.obj"), "%s", tb_test_out);
  no_leak_report("unwritable");
  snprintf(args, sizeof args, "mesh beam --part faces --out %s/no/such/dir/x.off",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 1, "%s", tb_test_out);
  no_leak_report("unwritable faces");
  const char *tet = tb_test_file("tet.obj",
                                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                 "f 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n",
                                 -1);
  snprintf(args, sizeof args, "mesh subdivide %s --levels 1 --out %s/x.xyz", tet, tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "unknown extension"), "%s",
               tb_test_out);
  snprintf(args, sizeof args, "mesh subdivide %s --levels 1 --out %s/no/such/dir/x.obj", tet,
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 1, "%s", tb_test_out);
  no_leak_report("subdivide unwritable");
  char out[600];
  snprintf(out, sizeof out, "%s/no/such/dir/y.vtk", tb_test_tmpdir());
  char *argv[] = {"mesh", "beam", "--set", "nx=2", "--out", out, NULL};
  TB_CHECK(tb_cmd_mesh(6, argv) == TB_EXIT_FAIL);
  snprintf(out, sizeof out, "%s/y.xyz", tb_test_tmpdir());
  TB_CHECK(tb_cmd_mesh(6, argv) == TB_EXIT_INPUT);
}

/* Item 7: settings out of range name the range and exit 2; generator failures exit 2; a
 * generated mesh beyond TB_COORD_MAX is refused, not described. */
static void settings_out_of_range(void) {
  TB_CHECK(tb_test_cli_run("mesh beam --set lx=1e308 --stats") == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "out of range [") && !strstr(tb_test_out, "inf"), "%s",
               tb_test_out);
  TB_CHECK(tb_test_cli_run("mesh sphere --set verts=1e400 --stats") == 2 &&
           strstr(tb_test_out, "out of range [0, 1e+09]"));
  TB_CHECK(tb_test_cli_run("mesh sphere --set verts=2.5 --stats") == 2 &&
           strstr(tb_test_out, "whole number"));
  TB_CHECK(tb_test_cli_run("mesh instrument --set length=1e90 --set jaw_length=1e90 "
                           "--set radius=1e90 --stats") == 2);
  TB_CHECK_MSG(strstr(tb_test_out, "within +-") && !strstr(tb_test_out, "surface:"), "%s",
               tb_test_out);
  TB_CHECK(tb_test_cli_run("mesh beam --set lx=1e89 --set nx=1 --set ny=1 --set nz=1 --stats") ==
           0);
  static const char *model_bad[] = {"E=1e400", "E=inf", "E=-1", "dt=1e400", "dt=-1"};
  for (int i = 0; i < 5; i++) {
    char args[256];
    snprintf(args, sizeof args, "simulate --scene beam --model fem --set %s", model_bad[i]);
    TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "out of range") &&
                     !strstr(tb_test_out, "not a"),
                 "%s: %s", model_bad[i], tb_test_out);
  }
  TB_CHECK(tb_test_cli_run("simulate --scene beam --model fem --set E=abc") == 2 &&
           strstr(tb_test_out, "not a number"));
}

/* Item 8: unknown options exit 2 with the usage, for every command; an option given twice
 * exits 2 naming it; reproduce --only with nothing in it or in one item exits 2. */
static void options_unknown_and_repeated(void) {
  static const char *unknown[] = {
      "mesh list --bogus",      "help --bogus",          "reproduce --bogus",
      "table 4.2 --bogus",      "tritri --bogus",        "collide --bogus",
      "simulate --bogus",       "render --bogus",        "advise --bogus x",
      "merge --bogus",          "mesh sphere --bogus 1", "mesh info",
      "mesh subdivide --bogus", "mesh spheres --bogus",  "--version --bogus"};
  for (int i = 0; i < (int)(sizeof unknown / sizeof *unknown); i++)
    TB_CHECK_MSG(tb_test_cli_run(unknown[i]) == 2 && strstr(tb_test_out, "usage"), "%s: %s",
                 unknown[i], tb_test_out);
  static const char *twice[][2] = {
      {"reproduce --seed 1 --seed 2 --list", "--seed"},
      {"mesh sphere --out a.obj --out b.obj", "--out"},
      {"mesh steak --seed 1 --seed 2 --stats", "--seed"},
      {"tritri --method list --method exact", "--method"},
      {"collide --bvh brute --bvh aabb a.obj b.obj", "--bvh"},
      {"simulate --scene beam --steps 1 --steps 2", "--steps"},
      {"render --mesh a.obj --out a.png --out b.png", "--out"},
      {"render --mesh a.obj --out a.png --color none --color displacement", "--color"},
      {"advise --scene beam --tol 0.1 --tol 0.2", "--tol"},
      {"merge a b --out c --out d", "--out"},
      {"mesh spheres a.obj --count 3 --count 4 --out x.sph", "--count"},
      {"mesh subdivide a.obj --levels 1 --levels 2 --out b.obj", "--levels"},
      {"table 4.2 --results a --results b", "--results"},
      {"mesh steak --set seed=1 --set verts=1266 --set seed=2 --stats", "--set seed"},
      {"simulate --scene beam --model fem --set E=1 --set E=2", "--set E"}};
  for (int i = 0; i < (int)(sizeof twice / sizeof *twice); i++) {
    char want[64];
    snprintf(want, sizeof want, "%s given twice", twice[i][1]);
    char cmd[1024]; /* in the temporary folder: a regression must not write here */
    snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s", tb_test_tmpdir(), tb_test_cli(), twice[i][0]);
    TB_CHECK_MSG(
        tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 2 && strstr(tb_test_out, want),
        "%s: %s", twice[i][0], tb_test_out);
  }
  TB_CHECK(tb_test_cli_run("simulate --scene beam --model fem --set E=1 --set nu=0.3 --steps 1") ==
           0); /* --set repeats */
  static const char *only[] = {"''", "meshes,", ",meshes", "meshes,,table-4.1", "nonsense"};
  for (int i = 0; i < 5; i++) {
    char args[128];
    snprintf(args, sizeof args, "reproduce --only %s --results %s/never", only[i],
             tb_test_tmpdir());
    TB_CHECK_MSG(tb_test_cli_run(args) == 2, "--only %s: %s", only[i], tb_test_out);
  }
  TB_CHECK(tb_test_cli_run("table 4.2 --only meshes") == 2);
}

/* Item 4: advise's points rows outside their columns' meaning are refused with FILE:LINE. */
static void advise_rejects_bad_rows(void) {
  static const struct {
    const char *row, *want;
  } bad[] = {{"fem,1,10,p,38.5,25.974,-0.5,0.1,0,nan,1,nan,settled", "rms error"},
             {"fem,1,10,p,38.5,25.974,0.01,-0.1,0,nan,1,nan,settled", "max error"},
             {"fem,1,10,p,38.5,-25.974,0.01,0.1,0,nan,1,nan,settled", "ms/step"},
             {"fem,1,10,p,38.5,0,0.01,0.1,0,nan,1,nan,settled", "ms/step"},
             {"fem,1,10,p,inf,25.974,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,-38.5,25.974,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,0,25.974,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,nan,25.974,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,38.5,nan,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,38.5,2.5,0.01,0.1,0,nan,1,nan,settled", "steps/s"},
             {"fem,1,10,p,38.5,25.974,0.01,0.1,inf,nan,1,nan,settled", "volume change"},
             {"fem,1,10,p,38.5,25.974,0.01,0.1,0,-1,1,nan,settled", "reaction error"},
             {"fem,1,10,p,38.5,25.974,0.01,0.1,0,nan,-1,nan,settled", "settle time"},
             {"fem,1,10,p,38.5,25.974,0.01,0.1,0,nan,1,-1e-3,settled", "recovery error"},
             {"fem,1,10,p,38.5,25.974,inf,0.1,0,nan,1,nan,settled", "rms error"}};
  const char *good =
      "fem,1,10,p,38.5,25.974,0.01,0.1,-0.02,nan,1,nan,settled\n"
      "msm,1,10,p,nan,nan,nan,nan,nan,nan,nan,nan,unstable (at t = 0)\n";
  for (int i = 0; i < (int)(sizeof bad / sizeof *bad); i++) {
    char text[1024], name[32];
    snprintf(text, sizeof text, "%s\n%s%s\n", TB_POINTS_HEADER, good, bad[i].row);
    snprintf(name, sizeof name, "bad%d.csv", i);
    const char *path = tb_test_file(name, text, -1);
    tb_point *p = NULL;
    int n;
    tb_error err;
    char want[64];
    snprintf(want, sizeof want, "%s:4: %s", name, bad[i].want);
    TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, want) && !p,
                 "row %d: %s", i, err.msg);
  }
  char text[1024];
  snprintf(text, sizeof text, "%s\n%s", TB_POINTS_HEADER, good);
  const char *path = tb_test_file("good.csv", text, -1);
  tb_point *p = NULL;
  int n = 0;
  tb_error err;
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == 0 && n == 2, "%s", err.msg);
  free(p);
  /* a measured time of 0 is written as nan, so a written file reads back */
  tb_point q;
  memset(&q, 0, sizeof q);
  snprintf(q.model, sizeof q.model, "msm");
  snprintf(q.state, sizeof q.state, "unstable");
  q.steps_per_s = NAN, q.ms_step = 0, q.rms_err = q.max_err = NAN;
  char line[512];
  tb_point_format(&q, line, sizeof line);
  snprintf(text, sizeof text, "%s\n%s\n", TB_POINTS_HEADER, line);
  path = tb_test_file("zero.csv", text, -1);
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == 0 && n == 1, "%s: %s", line, err.msg);
  free(p);
  char args[1024];
  snprintf(args, sizeof args, "advise --points %s/bad0.csv --tol 0.05", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "bad0.csv:4:"), "%s", tb_test_out);
}

/* Item 8: a NUL byte inside a line of a points or pair file is an error at its line, not a
 * line silently cut short. */
static void nul_byte_in_lines(void) {
  char text[1024];
  int len = snprintf(text, sizeof text, "%s\nfem,1,10,p,38.5,25.974,0.01,0.1,0,nan,1,nan,settled",
                     TB_POINTS_HEADER);
  memcpy(text + len, "\0junk\n", 6);
  const char *path = tb_test_file("nul.csv", text, len + 6);
  tb_point *p = NULL;
  int n;
  tb_error err;
  TB_CHECK_MSG(tb_points_read(path, &p, &n, &err) == -1 && strstr(err.msg, "nul.csv:2: NUL"), "%s",
               err.msg);
  static const char pair[] = "0 0 0 1 0 0 0 1 0 0 0 1 1 0 1 0 1 1";
  len = snprintf(text, sizeof text, "# pairs\n%s\n%s", pair, pair);
  memcpy(text + len, "\0 7 7 7\n", 8);
  path = tb_test_file("nul.txt", text, len + 8);
  tb_pairset set;
  TB_CHECK_MSG(tb_pairs_read_file(path, &set, &err) == -1 && strstr(err.msg, "nul.txt:3: NUL"),
               "%s", err.msg);
  len = snprintf(text, sizeof text, "0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 0 1\n0 1 1\n0 0 0");
  memcpy(text + len, "\0 5\n", 4);
  const char *jgt = tb_test_file("nul.jgt", text, len + 4);
  TB_CHECK_MSG(tb_pairs_read_jgt(jgt, 1, &set, &err) == -1 && strstr(err.msg, "nul.jgt:7: NUL"),
               "%s", err.msg);
  char args[1024];
  snprintf(args, sizeof args, "tritri --method exact --input %s", path);
  TB_CHECK_MSG(tb_test_cli_run(args) == 2 && strstr(tb_test_out, "nul.txt:3:"), "%s", tb_test_out);
}

/* A copied checkout and an installed tree read their own scenes and write their own results, not
 * the tree the binary was compiled in; TB_DATA_DIR overrides both. */
static void runs_from_anywhere(void) {
  const char *t = tb_test_tmpdir();
  char cmd[4096], out[8192];
  /* each tree's beam scene runs for its own duration: 0.05 s in the copy, 0.07 s installed */
  snprintf(cmd, sizeof cmd,
           "set -e; cd '%s'; rm -rf copy inst; mkdir -p copy/build copy/scenes inst/bin "
           "inst/share/tissuebench/scenes; cp '%s' copy/build/; cp '%s' inst/bin/; touch "
           "copy/meson.build; sed 's/^duration = .*/duration = 0.05/' '%s/scenes/beam.ini' "
           ">copy/scenes/beam.ini; sed 's/^duration = .*/duration = 0.07/' '%s/scenes/beam.ini' "
           ">inst/share/tissuebench/scenes/beam.ini",
           t, tb_test_cli(), tb_test_cli(), tb_test_source_root(), tb_test_source_root());
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0, "%s", out);
  snprintf(cmd, sizeof cmd, "cd / && '%s/copy/build/tissuebench' --version 2>&1", t);
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0, "%s", out);
  char want[1200];
  snprintf(want, sizeof want, "results: %s/copy/results", t);
  TB_CHECK_MSG(strstr(out, want), "%s", out);
  static const char *const run[3][2] = {
      {"", "copy/build"}, {"", "inst/bin"}, {"TB_DATA_DIR=copy ", "inst/bin"}};
  static const char *const steps[3] = {"5 steps", "7 steps", "5 steps"};
  for (int k = 0; k < 3; k++) {
    snprintf(cmd, sizeof cmd, "cd '%s' && %s%s/tissuebench simulate --scene beam --model msm 2>&1",
             t, run[k][0], run[k][1]);
    TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0 && strstr(out, steps[k]), "%s%s: %s",
                 run[k][0], run[k][1], out);
  }
  snprintf(cmd, sizeof cmd, "cd '%s' && inst/bin/tissuebench --version", t);
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0 && strstr(out, "results: ./results"), "%s",
               out);
  /* meson install (into a staging folder): the installed program finds its installed scenes */
  snprintf(cmd, sizeof cmd,
           "meson install -C '%s' --destdir '%s/staged' --no-rebuild --quiet >/dev/null 2>&1 && "
           "cd '%s' && p=$(find staged -path '*/bin/tissuebench') && $p --version && $p simulate "
           "--scene beam --model msm --steps 2",
           TB_BUILD_ROOT, t, t);
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0 && strstr(out, "/share/tissuebench (") &&
                   strstr(out, "scene beam"),
               "%s", out);
}

/* Every --help is complete: it lists every suite, scene, model and generator the registries
 * hold, and exits 0 (test --help too). */
static void help_from_registries(void) {
  int ns, nsc;
  const tb_suite_entry *su = tb_suites(&ns);
  const char *const *scenes = tb_sim_scene_names(&nsc);
  static const char *const suite_cmds[] = {"reproduce", "table", "figure"};
  for (int c = 0; c < 3; c++) {
    char args[64];
    snprintf(args, sizeof args, "%s --help", suite_cmds[c]);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s: %s", args, tb_test_out);
    for (int s = 0; s < ns; s++)
      TB_CHECK_MSG(strstr(tb_test_out, su[s].name), "%s lacks %s", args, su[s].name);
  }
  static const char *const sim_cmds[] = {"simulate", "render"};
  for (int c = 0; c < 2; c++) {
    char args[64];
    snprintf(args, sizeof args, "%s --help", sim_cmds[c]);
    TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s: %s", args, tb_test_out);
    for (int s = 0; s < nsc; s++)
      TB_CHECK_MSG(strstr(tb_test_out, scenes[s]), "%s lacks scene %s", args, scenes[s]);
    for (int m = 0; m < tb_model_count; m++)
      TB_CHECK_MSG(strstr(tb_test_out, tb_model_classes[m]->name), "%s lacks model %s", args,
                   tb_model_classes[m]->name);
  }
  TB_CHECK(tb_test_cli_run("mesh --help") == 0 && strstr(tb_test_out, "gallbladder") &&
           strstr(tb_test_out, "tetrahedralize"));
  TB_CHECK(tb_test_cli_run("tritri --help") == 0 && strstr(tb_test_out, "cgal"));
  char cmd[1200];
  snprintf(cmd, sizeof cmd, "'%s/tb_tests' --help", TB_BUILD_ROOT);
  TB_CHECK_MSG(
      tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0 && strstr(tb_test_out, "SUBSTRING"),
      "%s", tb_test_out);
}

/* One name per suite: its table's or figure's name finds the same suite everywhere. */
static void suite_names_everywhere(void) {
  TB_CHECK(tb_suite_find("4.1", 3) >= 0 &&
           tb_suite_find("4.1", 3) == tb_suite_find("table-4.1", 9));
  TB_CHECK(tb_suite_find("pictures", 8) >= 0 &&
           tb_suite_find("pictures", 8) == tb_suite_find("figures", 7));
  TB_CHECK(tb_suite_find("4.1x", 4) < 0 && tb_suite_find("4.", 2) < 0);
  TB_CHECK(tb_test_cli_run("reproduce --only meshes,4.2x") == 2 &&
           strstr(tb_test_out, "unknown suite '4.2x'"));
  TB_CHECK(tb_test_cli_run("table nonesuch") == 2);
}

/* getopt_long's spelling --opt=value, for every command's options and --threads. */
static void option_equals_value(void) {
  TB_CHECK_MSG(tb_test_cli_run("simulate --scene=beam --model=msm --steps=3 --threads=1") == 0 &&
                   strstr(tb_test_out, "3 steps") && strstr(tb_test_out, "threads: 1"),
               "%s", tb_test_out);
  TB_CHECK_MSG(
      tb_test_cli_run("mesh sphere --set=verts=162 --stats") == 0 && strstr(tb_test_out, "162"),
      "%s", tb_test_out);
  TB_CHECK(tb_test_cli_run("simulate --scene=beam --model=msm --steps=x") == 2);
}

/* simulate --json: one JSON object a JSON parser reads, with the printed summary's values; an
 * unstable run writes one too. */
static void simulate_json(void) {
  char args[1200], cmd[1400], out[4096];
  snprintf(args, sizeof args, "simulate --scene beam --model fem-corot --steps 20 --json %s/s.json",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
  const char *p = strstr(tb_test_out, "max displacement ");
  double printed = p ? atof(p + strlen("max displacement ")) : NAN;
  snprintf(cmd, sizeof cmd,
           "/usr/bin/python3 -c \"import json,sys; d=json.load(open('%s/s.json')); "
           "print(d['status'], d['steps'], d['nodes'], repr(d['max_displacement']), "
           "d['at_rest'], d['time_per_step_cpu_median_ms'] > 0)\" 2>&1",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0, "%s", out);
  char status[32] = "", rest[8] = "", pos[8] = "";
  int steps = 0, nodes = 0;
  double disp = NAN;
  TB_CHECK_MSG(
      sscanf(out, "%31s %d %d %lf %7s %7s", status, &steps, &nodes, &disp, rest, pos) == 6 &&
          !strcmp(status, "stable") && steps == 20 && nodes == 189 &&
          fabs(disp - printed) <= 1e-5 * printed && !strcmp(pos, "True"),
      "%s (printed %g)", out, printed);
  snprintf(args, sizeof args,
           "simulate --scene sphere-press --set alpha=120 --steps 400 --json %s/u.json",
           tb_test_tmpdir());
  TB_CHECK(tb_test_cli_run(args) == 1);
  snprintf(cmd, sizeof cmd,
           "/usr/bin/python3 -c \"import json; d=json.load(open('%s/u.json')); "
           "print(d['status'], len(d['reason']) > 0)\" 2>&1",
           tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_run(cmd, out, sizeof out) == 0 && !strncmp(out, "unstable True", 13), "%s",
               out);
}

const tb_test_case tb_tests_cli[] = {
    {"simulate_json", simulate_json},
    {"help_from_registries", help_from_registries},
    {"suite_names_everywhere", suite_names_everywhere},
    {"option_equals_value", option_equals_value},
    {"runs_from_anywhere", runs_from_anywhere},
    {"version_flag", version_flag},
    {"test_runner_list_and_no_match", test_runner_list_and_no_match},
    {"setup_script", setup_script},
    {"help_lists_commands", help_lists_commands},
    {"mesh_generate_and_info", mesh_generate_and_info},
    {"mesh_surface_compact", mesh_surface_compact},
    {"mesh_info_errors", mesh_info_errors},
    {"liver_stats_deterministic", liver_stats_deterministic},
    {"reproduce_meshes_suite", reproduce_meshes_suite},
    {"mesh_out_errors_no_leak", mesh_out_errors_no_leak},
    {"settings_out_of_range", settings_out_of_range},
    {"options_unknown_and_repeated", options_unknown_and_repeated},
    {"advise_rejects_bad_rows", advise_rejects_bad_rows},
    {"nul_byte_in_lines", nul_byte_in_lines},
    {0, 0},
};
