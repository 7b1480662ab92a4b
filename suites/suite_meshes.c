/* The meshes suite: generates every mesh the other suites use, writes them
 * to results/meshes/ (VTK and OBJ, for ParaView and for the later suites),
 * and tabulates their counts beside the documents' (thesis §2.5: liver
 * 725/1448 surface, 1206 vertices, 4230 tets, 9313 triangles, 6288 edges;
 * instrument 628/1248; Bao 2006 table 1: spheres 252/500 and 1002/2000).
 * Each mesh is generated several times: the suite checks the outputs are
 * byte-identical and reports the median generation time, CPU and wall. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_mesh_io.h"
#include "core/tb_timer.h"
#include "meshgen/tb_generators.h"
#include "report/tb_results.h"

typedef struct job {
  const char *gen;
  const char *label;    /* file base name under results/meshes/ */
  const char *settings; /* "key=value key=value" */
  int paper;            /* the documents' mesh: compare counts */
  int full_only;
} job;

static const job jobs[] = {
    {"liver", "liver", "", 1, 0},
    {"instrument", "instrument", "", 1, 0},
    {"sphere", "sphere-252", "verts=252", 1, 0},
    {"sphere", "sphere-1002", "verts=1002", 1, 0},
    {"beam", "beam-20x2x2", "nx=20 ny=2 nz=2", 0, 0},
    {"beam", "beam-40x4x4", "nx=40 ny=4 nz=4", 0, 0},
    {"liver", "liver-coarse", "surface_verts=300 tet_verts=500 tets=0", 0, 0},
    {"liver", "liver-fine", "surface_verts=1500 tet_verts=2500 tets=0", 0, 0},
    {"liver", "liver-finer", "surface_verts=3000 tet_verts=5000 tets=0", 0, 1},
    {"beam", "beam-80x8x8", "nx=80 ny=8 nz=8", 0, 1},
};

static int apply_settings(const tb_generator *g, double *p, const char *settings) {
  char buf[256], *save = NULL;
  if (strlen(settings) >= sizeof buf) return -1;
  snprintf(buf, sizeof buf, "%s", settings);
  for (char *kv = strtok_r(buf, " ", &save); kv; kv = strtok_r(NULL, " ", &save))
    if (tb_generator_set(g, p, kv)) return -1;
  return 0;
}

/* Writes the generated parts: <label>.vtk (tets or surface), <label>.obj
 * (surface), and for tet meshes <label>-faces.obj (all tet faces). */
static int write_part(const char *dir, const char *label, const char *suffix,
                      const tb_gen_result *r, tb_mesh_part part, tb_error *err) {
  char path[1024];
  if (snprintf(path, sizeof path, "%s/%s%s", dir, label, suffix) >= (int)sizeof path)
    return tb_error_set(err, dir, 0, "path too long");
  tb_mesh m;
  if (tb_gen_result_part(r, part, &m, err)) return -1;
  int rc = tb_mesh_write(path, &m, err);
  tb_mesh_free(&m);
  return rc;
}

static int write_parts(const char *dir, const char *label, const tb_gen_result *r, tb_error *err) {
  return write_part(dir, label, ".vtk", r, TB_PART_DEFAULT, err) ||
         write_part(dir, label, ".obj", r, TB_PART_SURFACE, err) ||
         (r->volume.ntet && write_part(dir, label, "-faces.obj", r, TB_PART_FACES, err));
}

static void cell_pair(tb_table *t, int ours, int paper) {
  if (!ours && !paper)
    tb_table_cell(t, "-");
  else
    tb_table_cell(t, "%d", ours);
  if (paper)
    tb_table_numf(t, paper, "%d (%+.1f%%)", paper, 100.0 * (ours - paper) / paper);
  else
    tb_table_cell(t, "-");
}

int tb_suite_meshes(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/meshes", o->results) >= (int)sizeof dir) {
    fprintf(stderr, "meshes: results path too long\n");
    return 1;
  }
  tb_suite *s =
      tb_suite_begin(dir, "meshes", "Generated meshes beside the documents' counts", o->seed, &err);
  if (!s) {
    fprintf(stderr, "meshes: %s\n", err.msg);
    return 1;
  }
  static const char *cols[] = {"mesh",
                               "settings",
                               "surface verts",
                               "doc",
                               "surface tris",
                               "doc",
                               "tet verts",
                               "doc",
                               "tets",
                               "doc",
                               "tet faces",
                               "doc",
                               "tet edges",
                               "doc",
                               "closed, manifold, Euler",
                               "min tet volume",
                               "deterministic",
                               "time CPU (ms, median)",
                               "time wall (ms, median)",
                               "closed",
                               "manifold",
                               "Euler characteristic"};
  tb_table *t = tb_table_new("counts", "Mesh counts (ours, and the documents' with our difference)",
                             (int)(sizeof cols / sizeof cols[0]), cols);
  for (int j = 3; j <= 13; j += 2) { /* the CSV: the documents' count alone, named */
    char name[64];
    snprintf(name, sizeof name, "%s (documents)", cols[j - 1]);
    tb_table_csv_name(t, j, name);
  }
  tb_table_only(t, 14, TB_MD_ONLY); /* closed, manifold, Euler: split for the CSV */
  for (int j = 19; j <= 21; j++) tb_table_only(t, j, TB_CSV_ONLY);
  const int reps = o->full ? 5 : 3, njobs = (int)(sizeof jobs / sizeof jobs[0]);
  int failed = 0;
  for (int j = 0; j < njobs; j++) {
    const job *jb = &jobs[j];
    if (jb->full_only && !o->full) continue;
    tb_progress("meshes", j, njobs);
    const tb_generator *g = tb_generator_find(jb->gen);
    double p[TB_GEN_MAX_PARAMS], ms[8], wall[8]; /* each generation's CPU and wall ms */
    tb_generator_defaults(g, p);
    char settings[200];
    if (!strcmp(jb->gen, "liver")) /* the liver's grey-value noise takes the run's seed */
      snprintf(settings, sizeof settings, "%s seed=%llu", jb->settings,
               (unsigned long long)o->seed);
    else
      snprintf(settings, sizeof settings, "%s", jb->settings);
    tb_gen_result first, r;
    tb_clock clock = tb_clock_start();
    if (apply_settings(g, p, settings) || tb_generator_run(g, p, &first, &err)) {
      fprintf(stderr, "meshes: %s: %s\n", jb->label, err.msg);
      failed++;
      continue;
    }
    tb_clock_ms(&clock, &wall[0], &ms[0]);
    int deterministic = 1, got = 1; /* generations timed */
    for (int k = 1; k < reps; k++) {
      clock = tb_clock_start();
      if (tb_generator_run(g, p, &r, &err)) {
        deterministic = 0;
        break;
      }
      tb_clock_ms(&clock, &wall[k], &ms[k]);
      got++;
      deterministic &=
          tb_mesh_equal(&first.surface, &r.surface) && tb_mesh_equal(&first.volume, &r.volume);
      tb_gen_result_free(&r);
    }
    char name[128];
    snprintf(name, sizeof name, "meshgen/%s", jb->label);
    tb_suite_bench(s, name, wall, ms, got, "ms");
    if (write_parts(dir, jb->label, &first, &err)) {
      fprintf(stderr, "meshes: %s: %s\n", jb->label, err.msg);
      failed++;
    }
    tb_gen_counts c = tb_gen_result_counts(&first), d;
    const char *src;
    if (!jb->paper || !g->paper || !g->paper(p, &d, &src)) memset(&d, 0, sizeof d);
    const tb_mesh *m = first.surface.nv ? &first.surface : &first.volume;
    tb_mesh_topo topo = tb_mesh_topology(m);
    tb_table_row(t);
    tb_table_cell(t, "%s", jb->label);
    tb_table_cell(t, "%s", *jb->settings ? jb->settings : "defaults");
    cell_pair(t, c.surface_verts, d.surface_verts);
    cell_pair(t, c.surface_tris, d.surface_tris);
    cell_pair(t, c.verts, d.verts);
    cell_pair(t, c.tets, d.tets);
    cell_pair(t, c.faces, d.faces);
    cell_pair(t, c.edges, d.edges);
    tb_table_cell(t, "%s, %s, %d", topo.closed ? "yes" : "NO", topo.manifold ? "yes" : "NO",
                  topo.euler);
    if (first.volume.ntet)
      tb_table_cell(t, "%.3g", tb_mesh_min_tet_volume(&first.volume));
    else
      tb_table_cell(t, "-");
    tb_table_cell(t, "%s", deterministic ? "yes" : "NO");
    tb_table_num(t, tb_stats_of(ms, got).median, "%.1f");
    tb_table_num(t, tb_stats_of(wall, got).median, "%.1f");
    tb_table_cell(t, "%s", topo.closed ? "yes" : "NO");
    tb_table_cell(t, "%s", topo.manifold ? "yes" : "NO");
    tb_table_cell(t, "%d", topo.euler);
    failed += !deterministic || !topo.closed || !topo.manifold;
    tb_gen_result_free(&first);
  }
  tb_progress("meshes", njobs, njobs);
  tb_suite_note(
      s,
      "Documents: thesis §2.5 (liver surface by Amira's marching cubes on Visible Human CT, "
      "725 vertices / 1448 triangles; QTetraMesher: 1206 vertices, 4230 tets, 9313 "
      "triangles, 6288 edges), thesis §4.5 instrument (628 / 1248), Bao 2006 table 1 "
      "(spheres 252 / 500 and 1002 / 2000). Ours: a synthetic CT-like volume, marching "
      "cubes (eqs. 2-2, 2-3), edge-collapse clean-up, TetGen with the surface kept. "
      "\"tet faces\" is the collision model (every triangle of the tet mesh).");
  tb_suite_note(s,
                "Each mesh was generated %d times; \"deterministic\" means byte-identical "
                "outputs; the times are the median generation, CPU (the process's, every "
                "thread's) and wall. The meshes are in this folder as .vtk (ParaView) and .obj.",
                reps);
  tb_suite_table(s, t);
  if (tb_suite_end(s, &err)) {
    fprintf(stderr, "meshes: %s\n", err.msg);
    return 1;
  }
  return failed ? 1 : 0;
}
