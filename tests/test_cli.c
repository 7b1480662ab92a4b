/* The command line, end to end through the built binary: help, --help of
 * every subcommand, exit codes, mesh info, mesh generation, reproduce. */
#include <stdio.h>
#include <string.h>

#include "tb_test.h"

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
  TB_CHECK(tb_test_cli_run("mesh sphere --set verts=250 --stats") == 1 &&
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
  snprintf(args, sizeof args, "reproduce --only meshes --results %s/res", tb_test_tmpdir());
  TB_CHECK_MSG(tb_test_cli_run(args) == 0, "%s", tb_test_out);
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

/* tools/setup.sh with fake dpkg-query and id on PATH: a missing package as
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
  snprintf(cmd, sizeof cmd, "PATH=%s/fakebin:$PATH sh %s/tools/setup.sh", dir,
           tb_test_source_root());
  TB_CHECK(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) != 0);
  TB_CHECK_MSG(strstr(tb_test_out, "apt-get install -y libcgal-dev") != NULL, "%s", tb_test_out);
  snprintf(cmd, sizeof cmd, "sed -i 's/libcgal-dev/none-such/' %s/fakebin/dpkg-query", dir);
  TB_CHECK(tb_test_run(cmd, NULL, 0) == 0);
  snprintf(cmd, sizeof cmd, "PATH=%s/fakebin:$PATH sh %s/tools/setup.sh", dir,
           tb_test_source_root());
  TB_CHECK_MSG(tb_test_run(cmd, tb_test_out, sizeof tb_test_out) == 0, "%s", tb_test_out);
}

static void version_flag(void) {
  TB_CHECK_MSG(tb_test_cli_run("--version") == 0, "%s", tb_test_out);
  char want[64];
  snprintf(want, sizeof want, "tissuebench %s", TB_VERSION);
  TB_CHECK_MSG(strncmp(tb_test_out, want, strlen(want)) == 0, "got: %s", tb_test_out);
  TB_CHECK(strchr(tb_test_out, '\n') == tb_test_out + strlen(tb_test_out) - 1); /* one line */
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

const tb_test_case tb_tests_cli[] = {
    {"version_flag", version_flag},
    {"test_runner_list_and_no_match", test_runner_list_and_no_match},
    {"setup_script", setup_script},
    {"help_lists_commands", help_lists_commands},
    {"mesh_generate_and_info", mesh_generate_and_info},
    {"mesh_surface_compact", mesh_surface_compact},
    {"mesh_info_errors", mesh_info_errors},
    {"liver_stats_deterministic", liver_stats_deterministic},
    {"reproduce_meshes_suite", reproduce_meshes_suite},
    {0, 0},
};
