/* tissuebench: the command-line front end. Every subcommand is one entry of
 * the table below; `help` lists them, `NAME --help` shows one. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "tb_cli.h"
#include "collision/tb_tritri.h"
#include "core/tb_paths.h"
#include "meshgen/tb_generators.h"
#include "models/tb_model.h"
#include "scenes/tb_sim.h"
#include "suites/tb_suites.h"
#include "core/tb_threads.h"
#include "reference/tb_oracles.h"
#include "report/tb_results.h"

static int cmd_help(int argc, char **argv);
static int cmd_test(int argc, char **argv);

#ifndef TB_VERSION
#define TB_VERSION "unknown"
#endif

/* ---- --help's lists, from the registries ---- */
static void list_suites(FILE *f) { tb_suites_print(f); }

static void list_scenes_models(FILE *f) {
  int n;
  const char *const *names = tb_sim_scene_names(&n);
  fprintf(f, "scenes (scenes/NAME.ini):\n");
  for (int i = 0; i < n; i++) fprintf(f, "  %-14s %s\n", names[i], tb_sim_scene_summary(names[i]));
  fprintf(f, "models (simulate --list shows their settings):\n");
  for (int i = 0; i < tb_model_count; i++)
    fprintf(f, "  %-14s %s\n", tb_model_classes[i]->name, tb_model_classes[i]->summary);
}

static void list_generators(FILE *f) {
  fprintf(f, "generators (mesh NAME):\n");
  tb_generator_list(f);
}

static void list_methods(FILE *f) {
  int n;
  const tb_tritri_method *m = tb_tritri_methods(&n);
  fprintf(f, "methods:\n");
  for (int i = 0; i < n; i++)
    fprintf(f, "  %-18s %s%s\n", m[i].name, m[i].source, m[i].exact ? " (exact)" : "");
}

static const tb_command commands[] = {
    {"help", "list the subcommands", "tissuebench help", cmd_help, NULL},
    {"reproduce", "run the reproduction suites into results/",
     "tissuebench reproduce [--quick|--full] [--seed N] [--only SUITE[,SUITE...]] [--results DIR]\n"
     "                      [--shard k/N]\n"
     "  --quick   the default: every suite at reduced scale (under 10 minutes on 2 cores)\n"
     "  --full    every suite at the documents' scale\n"
     "  --only    run only the named suites (see --list)\n"
     "  --list    list the suites\n"
     "  --scale F multiply every suite's pair and test counts by F (smoke tests)\n"
     "  --shard k/N  this machine's share (k of N) of the run, for `merge`: every N-th case\n"
     "            of the suites made of cases (pareto, stability, pbd-stiffness, scaling),\n"
     "            every N-th of the other suites whole",
     tb_cmd_reproduce, list_suites},
    {"merge", "combine the folders of `reproduce --shard k/N` (k = 1..N) into one results folder",
     "tissuebench merge SHARD_DIR... [--out DIR]\n"
     "  the N folders written by `reproduce --shard k/N --results SHARD_DIR`; checks they are the\n"
     "  N shards of one run (options, commit), then makes the suites' tables, charts and\n"
     "  REPORT.md in DIR (default results/) as an unsharded run would (scripts/slurm-array.sh)",
     tb_cmd_merge, NULL},
    {"test", "run the whole test suite (ends with \"N passed, N failed\")",
     "tissuebench test [--list] [SUBSTRING...]\n"
     "  runs the test cases whose \"suite/name\" contains any SUBSTRING (all without);\n"
     "  --list prints their names without running them; no match is an error (exit 2)",
     cmd_test, NULL},
    {"table", "make one table of the reproduction (reproduce --only NAME)",
     "tissuebench table NAME [--quick|--full] [--seed N] [--results DIR]\n"
     "  NAME: a suite's name or its table's (4.1 is table-4.1)",
     tb_cmd_table, list_suites},
    {"figure", "make one figure of the reproduction (reproduce --only NAME)",
     "tissuebench figure NAME [--quick|--full] [--seed N] [--results DIR]\n"
     "  NAME: a suite's name or its figure's (3.10 is figure-3.10)",
     tb_cmd_figure, list_suites},
    {"tritri", "classify triangle pairs with one method (0/1 per pair)",
     "tissuebench tritri --method NAME [--input FILE] [--repeat K]\n"
     "  reads pairs from FILE or stdin, one per line: 18 numbers p0 p1 p2 q0 q1 q2 (x y z each;\n"
     "  anything strtod accepts, hex floats too; '#' starts a comment); writes 0 or 1 per pair.\n"
     "  --repeat K  also classify the whole set K times; median ns/pair on stderr\n"
     "  --method list  prints the methods",
     tb_cmd_tritri, list_methods},
    {"collide", "all intersecting triangle pairs of two meshes with one BVH method",
     "tissuebench collide --bvh NAME [--tritest NAME] A B [--xform-b M] [--pairs] [--repeat K]\n"
     "  NAME: sphere, aabb, composite (ours), fcl-aabb, fcl-obbrss, bullet-gimpact,\n"
     "        bullet-gimpact-exact (Bullet's candidates, our exact test), brute\n"
     "  A, B: mesh files (triangles; a tet mesh without triangles uses all its tet faces)\n"
     "  --xform-b M  B moved by the row-major 3x4 matrix \"r00 r01 r02 t0 r10 ... r22 t2\"\n"
     "  --tritest    the triangle test for ours and brute (default exact; tritri --method list)\n"
     "  --pairs      print every intersecting pair \"i j\" (0-based, sorted) on stdout\n"
     "  a summary (pairs, volume tests, triangle tests, build and query time) goes to stderr",
     tb_cmd_collide, NULL},
    {"simulate", "run one deformation model on a scene or on a mesh file",
     "tissuebench simulate --scene NAME|FILE [--model NAME] [options]\n"
     "tissuebench simulate --model NAME --mesh FILE [--fix IDS | --fix-box x0,y0,z0,x1,y1,z1]\n"
     "                    [--gravity gx,gy,gz] [options]\n"
     "tissuebench simulate --list\n"
     "  --scene    a built-in scene (listed below: scenes/NAME.ini) or a scene file\n"
     "             (scenes/README.md)\n"
     "  --mesh     any mesh file mesh info reads (data:PATH: ../shared/data/PATH)\n"
     "  --fix      node ids, 0-based in the file's own node order (e.g. 3,39,64)\n"
     "  --static   the static equilibrium where the model has a static solve (fem, fem-corot),\n"
     "             else steps until at rest (every node slower than rest_speed x size per s)\n"
     "  --steps N, --dt X, --duration T   (default: the scene's duration / dt)\n"
     "  --set      a scene key (dt duration amplitude release nodes gravity vmax inversion drag\n"
     "             energy_factor energy_every rest_speed ground; 0 means 0) or a model key\n"
     "             (--list shows each model's keys, defaults and ranges)\n"
     "  --vtk DIR  ParaView files every K steps (--every K; default the scene's [output]\n"
     "             every, or 30 per simulated second): DIR/frames.pvd over frame_NNNNN.vtm,\n"
     "             one block per object (body, surface, instrument, ground; each also\n"
     "             NAME_NNNNN.vtu and NAME.pvd); a surface model's body is its current surface\n"
     "  --json FILE  the summary below as one JSON object (status, times per step in ms,\n"
     "             final state); written for unstable runs too\n"
     "  --out-surface FILE  the model's surface at the end (cut, or refined) by extension:\n"
     "             .obj .off .stl .vtk\n"
     "  prints the final state (max displacement and its node, volume change, energy,\n"
     "  penetration into the ground and the instrument, at rest or not), the median time per\n"
     "  step in CPU time (wall time beside it) and the threads used:\n"
     "  --threads N, or by default a step takes all cores only where they make it faster.\n"
     "  Status: \"stable\" (exit 0); \"degraded (reason)\" when the run ends with inverted tets,\n"
     "  a volume change beyond the material's tolerance ((1 - 2 nu) / 2, at least 5%) or its\n"
     "  energy above its bound (exits 3); \"unstable (reason)\" when it blows up (exits 1);\n"
     "  bad input, in the command line or a scene file (FILE:LINE), exits 2",
     tb_cmd_simulate, list_scenes_models},
    {"render", "pictures of a mesh or of a scene at chosen times (PNG, headless)",
     "tissuebench render --mesh FILE --out PICTURE.png [options]\n"
     "tissuebench render --scene NAME|FILE [--model M] [--set k=v ...] [--times t1,t2,... | "
     "--every K]\n"
     "                   --out DIR [options]\n"
     "  --view V      front, left-front (default), left-back, top: the thesis's views, fitted\n"
     "                to the body\n"
     "  --up x,y,z    the up direction of the views (default: against the scene's gravity;\n"
     "                z for a mesh file)\n"
     "  --camera SPEC \"eye=x,y,z target=x,y,z [up=x,y,z] (fov=DEG | ortho=HALF_HEIGHT)\"\n"
     "  --size WxH    image size (800x600); --ss N samples per pixel side (1..4, default 2)\n"
     "  --color C     none (default), displacement, von_mises (fem, fem-corot) or error (against\n"
     "                the reference solution of the loads at that time; beam, liver-stretch):\n"
     "                a colour map with its colour bar (quantity and unit)\n"
     "  --range LO,HI the colour map's range (default 0 to the largest value 3 surface points\n"
     "                reach in any picture of the run, the same for all its pictures)\n"
     "  --wireframe   the surface's triangle edges; --structure: the model's tet edges (sm:\n"
     "                its clusters; metaball: its spheres at half size and their links);\n"
     "                --volume: the structure alone, without the surface (the metaball\n"
     "                patent's upper row); --contacts: surface triangles crossing the instrument\n"
     "  a scene is drawn at each time (DIR/tT.png; default: its end) or every K steps\n"
     "  (DIR/frame_NNNNN.png), with its instrument, ground, time and names. OSMesa on Mesa's\n"
     "  softpipe rasterizer, text in DejaVu Sans by FreeType: the same input gives the same\n"
     "  bytes. Bad camera, size, range or times exit 2",
     tb_cmd_render, list_scenes_models},
    {"advise", "the cheapest model for a scene and an error tolerance",
     "tissuebench advise --scene NAME (--tol X | --budget-ms Y | both) [--points FILE]\n"
     "                   [--results DIR]\n"
     "  from measured points (DIR/pareto/<scene>/points.csv, DIR = results/, or FILE; made by\n"
     "  `figure pareto`), the cheapest model + resolution + parameters whose rms surface error\n"
     "  is within X (relative to the largest reference displacement, e.g. 0.05); with only\n"
     "  --budget-ms, the most accurate within Y ms per step; with both, the cheapest within X\n"
     "  and Y. Only settled runs count. Prints the choice and the evidence rows; exit 1 when\n"
     "  no point qualifies, 2 for a missing or malformed points file (FILE:LINE: reason)",
     tb_cmd_advise, NULL},
    {"mesh",
     "mesh info FILE, tetrahedralize or close a surface, subdivide it, fill it with spheres, or "
     "generate a mesh (liver, "
     "instrument, sphere, beam, spleen, gallbladder, steak)",
     "tissuebench mesh info FILE\n"
     "  counts, bounding box, closed/manifold, Euler characteristic, volume and self-\n"
     "  intersecting triangle pairs (crossing, not touching) of a mesh file\n"
     "  (.obj .off .stl .node/.ele .msh); for a .sph file, as mesh spheres --info;\n"
     "  malformed input: FILE:LINE: reason, exit 2\n"
     "tissuebench mesh tetrahedralize IN --out OUT [--quality R] [--max-volume V | --tets N]\n"
     "                                [--split-surface] [--repair]\n"
     "  a closed surface (any format read here; unused vertices dropped) to tets by TetGen:\n"
     "  radius-edge bound R (default 1.414), largest tet volume V or about N tets (the bound\n"
     "  searched); the surface is kept unless --split-surface; prints counts, volume and the\n"
     "  dihedral angles; writes .node (with .ele) .vtk .msh. A self-intersecting surface is\n"
     "  refused naming the first crossing pair; --repair smooths the vertices near crossings\n"
     "  first (and says how far they moved)\n"
     "tissuebench mesh close IN --out OUT\n"
     "  caps each hole of an open, oriented surface (an instrument) with a fan to its centroid\n"
     "tissuebench mesh subdivide IN --levels N --out OUT\n"
     "  N levels (1..6) of Zorin's modified butterfly subdivision (Bao 2006 §3.1): each level\n"
     "  splits every triangle in four, keeps the old vertices and adds one per edge; prints\n"
     "  vertices and triangles per level, writes OUT by extension. IN: a closed, oriented\n"
     "  2-manifold triangle surface (tet meshes are refused); otherwise FILE: reason, exit 2\n"
     "tissuebench mesh spheres IN --count N --out OUT.sph [--samples S] [--seed K] [--grid G]\n"
     "  N overlapping spheres inside the closed surface IN (a metaball organ model): centres at\n"
     "  inner Voronoi poles of S surface samples (default max(vertices, 20 N, 4000); CGAL's\n"
     "  Delaunay), radius the distance to the surface, largest first; prints the time, the\n"
     "  radii and the coverage (share of the volume on a G grid, default 64, inside a sphere;\n"
     "  share of vertices at r <= d <= 2r from a centre); writes SOFA's .sph format\n"
     "tissuebench mesh spheres --info X.sph [--surface IN] [--grid G]\n"
     "  count, radius range and, with IN, the coverage of a .sph file; a bad file or surface:\n"
     "  FILE:LINE: reason (FILE: reason), exit 2\n"
     "tissuebench mesh NAME [--out FILE] [--part PART] [--stats] [--set key=value ...]\n"
     "  NAME: liver, instrument, sphere, beam, and the metaball patent's spleen, gallbladder,\n"
     "  steak (exactly its vertex counts; meshgen/organs.c) (mesh list shows their settings)\n"
     "  --KEY VALUE  same as --set KEY=VALUE (dashes for underscores): mesh steak --verts 1266\n"
     "               --seed 2; mesh liver --part surface --surface-verts 8128\n"
     "  --out FILE   write by extension: .obj .off .stl .node (with .ele) .vtk .msh; .edges\n"
     "  --part PART  liver only: tets (default), surface (no TetGen; vertex count exact),\n"
     "               faces (all tet faces), edges\n"
     "  --stats      print the counts beside the documents' counts",
     tb_cmd_mesh, list_generators},
};
static const int ncommands = (int)(sizeof commands / sizeof commands[0]);

static int cmd_help(int argc, char **argv) {
  if (argc > 1) return tb_cli_bad_option("help", argv[1]);
  printf("usage: tissuebench COMMAND [options]   (COMMAND --help for its options)\n");
  printf("       tissuebench --version\n");
  printf(
      "every command takes --threads N: worker threads of the parallel loops (default: one\n"
      "per core; results are identical for any N)\n\n");
  for (int i = 0; i < ncommands; i++) printf("  %-10s %s\n", commands[i].name, commands[i].summary);
  return TB_EXIT_OK;
}

/* The test binary sits beside this one in the build folder. */
static int cmd_test(int argc, char **argv) {
  char self[4096];
  ssize_t n = readlink("/proc/self/exe", self, sizeof self - 16);
  if (n <= 0) {
    fprintf(stderr, "tissuebench: cannot locate the test binary\n");
    return TB_EXIT_FAIL;
  }
  self[n] = 0;
  char *slash = strrchr(self, '/');
  strcpy(slash ? slash + 1 : self, "tb_tests");
  argv[0] = self;
  (void)argc;
  execv(self, argv);
  fprintf(stderr, "tissuebench: cannot run %s: %s\n", self, strerror(errno));
  return TB_EXIT_FAIL;
}

/* The meson project version, the source's commit when git knows it, and where the files, the
 * shared data and the results are. */
static int print_version(void) {
  tb_context c;
  tb_context_collect(&c, 0);
  printf("tissuebench %s", TB_VERSION);
  if (strcmp(c.commit, "unknown") != 0)
    printf(" (commit %.12s%s)", c.commit, c.dirty > 0 ? ", dirty" : "");
  printf("\n");
  struct stat st;
  printf("files:   %s (scenes, scripts; TB_DATA_DIR overrides)\n", tb_root());
  printf("data:    %s (%s; TB_SHARED_DATA overrides)\n", tb_shared_data(),
         stat(tb_shared_data(), &st) == 0 ? "present" : "absent: suites run without it");
  printf("results: %s (--results overrides)\n", tb_results_dir());
  return TB_EXIT_OK;
}

/* `--threads N` anywhere after the command (every command takes it): the
 * worker threads of the parallel loops, 0 or absent: one per core. Results
 * are the same for any N. Returns N, or -1 on a bad value. */
static int find_threads(int argc, char **argv) {
  int n = 0, seen = 0;
  for (int i = 2; i < argc; i++) {
    if (strcmp(argv[i], "--threads")) continue;
    char *end = NULL;
    long v = i + 1 < argc ? strtol(argv[i + 1], &end, 10) : -1;
    if (i + 1 >= argc || end == argv[i + 1] || *end || v < 0 || v > 4096) {
      fprintf(stderr,
              "tissuebench: --threads needs a whole number in [0, 4096] (0: one per core)\n");
      return -1;
    }
    if (seen++) {
      fprintf(stderr, "tissuebench: --threads given twice\n");
      return -1;
    }
    n = (int)v;
    i++;
  }
  return n;
}

/* Removes every `--threads N` from argv. */
static void drop_threads(int *argc, char **argv) {
  for (int i = 2; i < *argc;) {
    if (strcmp(argv[i], "--threads")) {
      i++;
      continue;
    }
    memmove(argv + i, argv + i + 2, sizeof(char *) * (size_t)(*argc - i - 1));
    *argc -= 2;
  }
}

/* getopt_long's two spellings: "--opt=value" becomes "--opt" "value" (the first '=' splits;
 * "--set=E=3000" is "--set" "E=3000"). Returns the new argument vector (argv when nothing
 * splits), or NULL when out of memory. */
static char **split_equals(int *argc, char **argv) {
  int n = 0;
  for (int i = 2; i < *argc; i++) n += !strncmp(argv[i], "--", 2) && strchr(argv[i], '=');
  if (!n) return argv;
  static char **out; /* kept for the program's life, as argv is */
  out = malloc(sizeof(char *) * (size_t)(*argc + n + 1));
  if (!out) return NULL;
  int k = 0;
  for (int i = 0; i < *argc; i++) {
    char *eq = i >= 2 && !strncmp(argv[i], "--", 2) ? strchr(argv[i], '=') : NULL;
    if (eq) *eq = 0; /* the option's name ends where its value starts */
    out[k++] = argv[i];
    if (eq) out[k++] = eq + 1;
  }
  out[k] = NULL;
  *argc = k;
  return out;
}

int main(int argc, char **argv) {
  tb_cli_set_commands(commands, ncommands);
  tb_oracles_register();
  if (argc < 2) return cmd_help(1, argv), TB_EXIT_INPUT;
  if (!(argv = split_equals(&argc, argv))) return TB_EXIT_FAIL;
  int threads = find_threads(argc, argv);
  if (threads < 0) return TB_EXIT_INPUT;
  tb_threads_environment(threads, argv);
  drop_threads(&argc, argv);
  tb_threads_set(threads);
  const char *name = argv[1];
  if (!strcmp(name, "--version") || !strcmp(name, "version")) {
    if (argc > 2) {
      fprintf(stderr, "tissuebench %s: unknown option '%s'\nusage: tissuebench --version\n", name,
              argv[2]);
      return TB_EXIT_INPUT;
    }
    return print_version();
  }
  if (!strcmp(name, "--help") || !strcmp(name, "-h")) name = "help";
  for (int i = 0; i < ncommands; i++) {
    if (strcmp(name, commands[i].name)) continue;
    if (tb_cli_has_help(argc - 1, argv + 1)) {
      printf("%s\n\n%s\n", commands[i].summary, commands[i].usage);
      if (commands[i].lists) commands[i].lists(stdout);
      return TB_EXIT_OK;
    }
    if (tb_cli_check_repeats(name, argc - 1, argv + 1)) return TB_EXIT_INPUT;
    return commands[i].run(argc - 1, argv + 1);
  }
  fprintf(stderr, "tissuebench: unknown command '%s' (tissuebench help lists them)\n", name);
  return TB_EXIT_INPUT;
}
