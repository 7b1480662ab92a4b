/* The suites of the reproduction, one entry each, in the order they run,
 * and REPORT.md's order of them (the documents'). Adding a suite is one
 * file and one entry here (docs/architecture.md). */
#include <stdio.h>
#include <string.h>

#include "tb_suites.h"
#include "report/tb_results.h"

static const tb_suite_entry suites[] = {
    {"meshes", "meshes", NULL,
     "generated meshes: counts beside the documents' (thesis §2.5, Bao 2006)", tb_suite_meshes, 0},
    {"correctness", "correctness", NULL,
     "triangle tests: wrong answers against the exact oracle, per family of pairs",
     tb_suite_correctness, 0},
    {"table-4.1", "4.1", NULL,
     "thesis table 4.1: time for 0.1-2 million tests; ns/pair on the JGT pairs", tb_suite_table41,
     0},
    {"table-4.2", "4.2", NULL,
     "thesis table 4.2: queries/s against intersecting pairs, liver against instrument",
     tb_suite_table42, 0},
    {"refit", "refit", NULL, "the deforming liver: refit, rebuild, FCL refit, Bullet update, query",
     tb_suite_refit, 0},
    {"table-3.5", "3.5", NULL,
     "thesis §3.5: steps/s of msm, fem, fem-corot, sm on the liver; recovery after a far stretch",
     tb_suite_table35, 0},
    {"figure-3.10", NULL, "3.10",
     "thesis fig. 3.10: shape-matching time per frame against particles, clusters, variant",
     tb_suite_fig310, 0},
    {"reference", "reference", NULL,
     "the reference solver's refinement study: cantilever T4/T10 against beam theory",
     tb_suite_reference, 0},
    {"calibration", "calibration", NULL,
     "model parameters fitted to the reference solution; errors with documents' vs fitted values",
     tb_suite_calibration, 0},
    {"pareto", NULL, "pareto",
     "error against the reference vs steps/s: every model x resolution x key parameter (--scene)",
     tb_suite_pareto, 1},
    {"stability", NULL, "stability",
     "stable/unstable over dt x stiffness per model (--model); large-deformation tests",
     tb_suite_stability, 1},
    {"pbd-stiffness", NULL, "pbd-stiffness",
     "PBD and XPBD: the beam's static sag under gravity over the material's, against "
     "iterations and dt",
     tb_suite_pbd_stiffness, 1},
    {"pbd", "pbd", NULL,
     "2022 patent tables 1-2: pbd-stvk solve time per step and element on 596-12829-tet livers "
     "dropped on a ground, 1 vs all threads (bit-identical?), Bullet btSoftBody beside it",
     tb_suite_pbd, 0},
    {"bao", "bao", NULL,
     "Bao 2006 table 1 and figs 6-8: msm-vvs on the sphere, base vs fully subdivided vs locally "
     "refined (time, accuracy), the conventional and the improved model pressed and released",
     tb_suite_bao, 0},
    {"metaball", "metaball", "metaball",
     "metaball patent tables 1-2 and figs 7-10: organs of spheres driven by PBD, deform and cut "
     "ms per frame, re-packing, convergence against the tet models, the speed goal",
     tb_suite_metaball, 0},
    {"scaling", NULL, "scaling",
     "ms per step against mesh size (600 to 100k+ tets) for every model of the table, fitted "
     "exponents, 30/300 Hz limits, peak RSS per tet, 1 vs all threads, collision refit + query",
     tb_suite_scaling, 1},
    {"cuts", NULL, "cuts",
     "cut torture: the metaball model's cut on five organs, designed and seeded random "
     "paths, each judged (closed pieces, no self-intersection, spheres split alike, volume)",
     tb_suite_cuts, 0},
    {"figures", NULL, "pictures",
     "the documents' pictures rendered: figs. 2.15, 3.11-3.15, 4.21, 5.5-5.7; PBD patent 7-9",
     tb_suite_figures, 0},
};
static const int nsuites = (int)(sizeof suites / sizeof suites[0]);

const tb_suite_entry *tb_suites(int *n) {
  *n = nsuites;
  return suites;
}

static int is(const char *a, const char *name, size_t n) {
  return a && strlen(a) == n && !strncmp(a, name, n);
}

int tb_suite_find(const char *name, size_t n) {
  for (int s = 0; s < nsuites; s++)
    if (is(suites[s].name, name, n) || is(suites[s].table, name, n) ||
        is(suites[s].figure, name, n))
      return s;
  return -1;
}

void tb_suites_print(FILE *f) {
  fprintf(f, "suites (a table's or figure's name works too, e.g. 4.1 for table-4.1):\n");
  for (int s = 0; s < nsuites; s++) {
    const char *alias = suites[s].table && strcmp(suites[s].table, suites[s].name) ? suites[s].table
                        : suites[s].figure && strcmp(suites[s].figure, suites[s].name)
                            ? suites[s].figure
                            : NULL;
    char head[48];
    snprintf(head, sizeof head, "%s%s%s%s", suites[s].name, alias ? " (" : "", alias ? alias : "",
             alias ? ")" : "");
    fprintf(f, "  %-22s %s\n", head, suites[s].summary);
  }
}

/* REPORT.md's order, the documents': the thesis' chapter 2 (meshes), its
 * chapter 3 (deformation: its table and figure, then our reference, the
 * calibration against it, the error/speed trade-off, stability), its
 * chapter 4 (collision: correctness first, then its tables, then the
 * deforming liver); then the 2022 patent's performance tables; then Bao
 * 2006's sphere (its table 1, figs 6-8); then the metaball patent's organs
 * (its tables 1-2, figs 7-10); then how every model and the collision
 * hierarchy scale with the mesh. A chapter
 * is a heading then suite names; every suite above appears once
 * (tests/test_cli.c checks through --only). */
static const char *const report_order[] = {
    "#Chapter 2: meshes",
    "meshes",
    "#Chapter 3: deformation",
    "table-3.5",
    "figure-3.10",
    "reference",
    "calibration",
    "pareto",
    "stability",
    "#Chapter 4: collision detection",
    "correctness",
    "table-4.1",
    "table-4.2",
    "refit",
    "#2022 patent: position-based dynamics, a liver dropped on a rigid ground",
    "pbd",
    "pbd-stiffness",
    "#Bao 2006: a surface mass-spring model with virtual volumetric springs and local refinement",
    "bao",
    "#The metaball patent: organs of overlapping spheres, PBD, hybrid sphere - point set cutting",
    "metaball",
    "cuts",
    "#Scaling: every model and the collision hierarchy against mesh size",
    "scaling",
    "#Pictures: the documents' figures, rendered",
    "figures",
};

int tb_reproduce_report(tb_report *r, const int *status) {
  for (size_t k = 0; k < sizeof report_order / sizeof report_order[0]; k++) {
    const char *e = report_order[k];
    if (e[0] == '#') {
      tb_report_chapter(r, e + 1, NULL);
      continue;
    }
    for (int s = 0; s < nsuites; s++)
      if (!strcmp(suites[s].name, e)) tb_report_suite(r, e, suites[s].summary, status[s]);
  }
  tb_error err = {{0}};
  if (tb_report_end(r, &err)) {
    fprintf(stderr, "tissuebench reproduce: %s\n", err.msg);
    return 1;
  }
  return 0;
}

int tb_suite_listed(const char *list, const char *name) {
  size_t n = strlen(name);
  for (const char *p = list; p && *p;) {
    const char *c = strchr(p, ',');
    size_t len = c ? (size_t)(c - p) : strlen(p);
    if (len == n && !strncmp(p, name, n)) return 1;
    p = c ? c + 1 : NULL;
  }
  return 0;
}
