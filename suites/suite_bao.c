/* Bao, Wang, Liu, Cheng 2006, "A dynamic mass spring model for simulation
 * of soft tissue deformation" (J. System Simulation 18(4)), §4: msm-vvs
 * on the paper's sphere (252 vertices, radius 1).
 *  1. Its table 1: 5 s at dt 0.01 on the base mesh, the fully subdivided
 *     one and under dynamic local refinement, vertices, triangles and the
 *     time of the 500 steps beside the paper's (Pentium 4 2.8 GHz).
 *  2. "As accurate as full, as cheap as base": at the end of the press the
 *     252 base vertices of the local and of the base model against the
 *     fully subdivided one; each row's dent.
 *  3. Its figs 6-7: the conventional surface model (a hollow shell,
 *     explicit Euler) and the improved one (virtual volumetric springs,
 *     quasi-static steps) pressed and released, and stretched.
 *  4. Pictures: fig 8 (the refined sphere under the press) and figs 6-7.
 * Timing: the model's step alone (tb_model_step, the scene's loads fed as
 * tb_sim_step does), summed over the 500 steps; one run a repetition, the
 * median over repetitions reported. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_draw.h"
#include "tb_suites.h"
#include "core/tb_timer.h"
#include "render/tb_render.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

#define MODEL "msm-vvs"
#define PRESS "sphere-press"
#define STRETCH "sphere-stretch"
#define T_TABLE 5.0 /* the paper's simulated time */
#define GOAL 1.2    /* the goal: local <= 1.2 x base per step */
#define W 400       /* pictures */
#define H 300
#define U_SCALE 0.5 /* the pictures' displacement colour scale (radius 1) */

/* Table 1's rows: the paper's counts and times beside the settings. */
enum { BASE, FULL, LOCAL, PLAIN, NROWS };
static const struct {
  const char *name, *set;
  int nv, ntri;
  double ms;
} paper[NROWS] = {
    {"base mesh", "levels=2 refine_force=1e9", 252, 500, 60},
    {"fully subdivided", "levels=2 refine_force=0", 1002, 2000, 194},
    {"locally refined", "levels=2 refine_force=0.2", 294, 584, 66},
    {"no refinement (levels=1)", "levels=1", 252, 500, NAN},
};

/* Figs 6-7's variants. */
#define NVAR 4
static const struct {
  const char *name, *set;
} variant[NVAR] = {
    {"conventional (shell, Euler)", "volume_springs=0 integrator=euler"},
    {"shell, quasi-static", "volume_springs=0"},
    {"virtual springs, Euler", "integrator=euler"},
    {"improved (virtual springs, quasi-static)", ""},
};

/* The pictures are written as the runs reach them and shown in table.md
 * after the table they belong to (flush). */
#define NPICS 16
typedef struct ctx {
  tb_suite *su;
  tb_renderer *r;
  const char *dir;
  int failed, npics;
  char pic[NPICS][64], cap[NPICS][300];
} ctx;

static void flush(ctx *c) {
  for (int k = 0; k < c->npics; k++) tb_suite_figure(c->su, c->pic[k], "%s", c->cap[k]);
  c->npics = 0;
}

/* Builds scene with msm-vvs and the space-separated settings, duration
 * `duration` (<= 0: the scene's). */
static int open_sim(tb_sim *s, const char *scene, const char *settings, double duration,
                    uint64_t seed, tb_error *err) {
  tb_sim_def d;
  tb_sim_def_init(&d);
  if (duration > 0) d.duration = duration;
  d.seed = seed;
  tb_settings set;
  tb_settings_init(&set);
  char buf[128];
  snprintf(buf, sizeof buf, "%s", settings);
  for (char *p = strtok(buf, " "); p; p = strtok(NULL, " "))
    if (tb_settings_set(&set, p, err)) return -1;
  return tb_sim_create(s, scene, &d, MODEL, &set, NULL, err);
}

/* The vertices the current surface uses. */
static int used_vertices(const tb_sim *s, char *mark) {
  tb_surface su = tb_model_surface(&s->model);
  memset(mark, 0, (size_t)su.nv);
  int n = 0;
  for (int k = 0; k < 3 * su.ntri; k++) n += !mark[su.tri[k]]++;
  return n;
}

/* |mean displacement| of the probe's nodes. */
static double probe_now(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  tb_vec3 m = tb_v3(0, 0, 0);
  for (int k = 0; k < s->nprobe; k++) m = tb_add(m, tb_sub(x[s->probe[k]], s->mesh.x[s->probe[k]]));
  return s->nprobe ? tb_len(m) / s->nprobe : NAN;
}

/* A picture of the current state: the surface coloured by displacement
 * (0 to U_SCALE), wireframe when asked, into dir/name with its caption. */
static void picture(ctx *c, tb_sim *s, int wire, const char *name, const char *caption) {
  tb_camera cam;
  tb_camera_preset("left-front", tb_v3(-1, -1, -1), tb_v3(1, 1, 1.2), &cam);
  tb_renderer_begin(c->r, &cam, (const float[3]){1, 1, 1});
  tb_surface su = tb_model_surface(&s->model);
  double *u = malloc(sizeof(double) * (size_t)su.nv);
  if (u) tb_draw_displacement(s, u);
  tb_draw_sim(c->r, s, u, U_SCALE, "displacement", wire);
  free(u);
  char path[1200];
  tb_error err;
  snprintf(path, sizeof path, "%s/%s", c->dir, name);
  if (tb_renderer_write_png(c->r, path, &err)) {
    fprintf(stderr, "bao: %s\n", err.msg);
    c->failed = 1;
    return;
  }
  if (c->npics < NPICS) {
    snprintf(c->pic[c->npics], sizeof c->pic[0], "%s", name);
    snprintf(c->cap[c->npics++], sizeof c->cap[0], "%s", caption);
  }
}

/* One row of table 1 and its accuracy. */
typedef struct row {
  int ok;
  char why[200];
  int nv_max, ntri_max, nv_press, ntri_press; /* most over the run; at the end of the press */
  double *ms;                                 /* per repetition: ms for the run's steps */
  double *ms_rebuild;                         /* per repetition: ms of the steps that rebuilt */
  double median, median_rebuild, median_other, dent_press, peak;
  tb_vec3 *x_press; /* the base vertices at the end of the press */
  int identical;    /* the timed runs end where the measured run does */
  int rebuilds;     /* steps that changed the surface */
  int nb, nprobe;   /* the mesh's nodes, the probe's */
  double release;   /* the end of the press */
} row;

/* The measured run (tb_sim_step: health checked), then reps timed ones. */
static void measure(ctx *c, int r, int reps, uint64_t seed, row *w) {
  tb_error err;
  tb_sim s;
  w->ok = 0;
  if (open_sim(&s, PRESS, paper[r].set, T_TABLE, seed, &err)) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    return;
  }
  long n = lround(s.def.duration / s.def.dt), at = lround(s.def.release / s.def.dt);
  int nb = w->nb = s.mesh.nv;
  w->nprobe = s.nprobe, w->release = s.def.release;
  char *mark = malloc((size_t)tb_model_npoints(&s.model) + (size_t)tb_model_surface(&s.model).nv);
  tb_vec3 *x_end = malloc(sizeof(tb_vec3) * (size_t)nb);
  w->x_press = malloc(sizeof(tb_vec3) * (size_t)nb);
  int rc = mark && x_end && w->x_press ? 0 : tb_error_set(&err, "bao", 0, "out of memory");
  unsigned long version = tb_model_surface(&s.model).version;
  for (long k = 0; k < n && !rc; k++) {
    if ((rc = tb_sim_step(&s, &err))) break;
    int nv = used_vertices(&s, mark), nt = tb_model_surface(&s.model).ntri;
    w->rebuilds += tb_model_surface(&s.model).version != version;
    version = tb_model_surface(&s.model).version;
    if (nv > w->nv_max) w->nv_max = nv;
    if (nt > w->ntri_max) w->ntri_max = nt;
    if (k + 1 == at) {
      w->nv_press = nv, w->ntri_press = nt, w->dent_press = probe_now(&s);
      memcpy(w->x_press, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nb);
      if (r == LOCAL || r == FULL || r == BASE) {
        char name[64], cap[300];
        snprintf(name, sizeof name, "fig8-%s.png",
                 r == LOCAL  ? "local"
                 : r == FULL ? "full"
                             : "base");
        snprintf(cap, sizeof cap,
                 "Fig 8: the sphere %s at the end of the press (t = %g s), %d vertices, %d "
                 "triangles; colour: displacement 0 to %g",
                 r == LOCAL  ? "under local refinement (refine_force 0.2)"
                 : r == FULL ? "fully subdivided"
                             : "on the base mesh",
                 s.t, nv, nt, U_SCALE);
        picture(c, &s, 1, name, cap);
      }
    }
  }
  w->peak = s.probe_peak;
  if (!rc) memcpy(x_end, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nb);
  tb_sim_destroy(&s);
  w->identical = 1;
  for (int q = 0; q < reps && !rc; q++) {
    if ((rc = open_sim(&s, PRESS, paper[r].set, T_TABLE, seed, &err))) break;
    uint64_t ns = 0, ns_rebuild = 0;
    unsigned long ver = tb_model_surface(&s.model).version;
    for (long k = 0; k < n && !rc; k++) {
      if ((rc = tb_sim_loads(&s, s.t + s.def.dt, &err))) break;
      tb_step in = {0};
      in.dt = s.def.dt, in.gravity = s.gravity, in.force = s.force;
      in.nfixed = s.nfixed, in.fixed = s.fixed, in.fixed_x = s.fixed_x;
      uint64_t t0 = tb_time_ns();
      rc = tb_model_step(&s.model, &in, &err);
      uint64_t dt = tb_time_ns() - t0;
      ns += dt;
      if (tb_model_surface(&s.model).version != ver)
        ns_rebuild += dt, ver = tb_model_surface(&s.model).version;
      s.t += s.def.dt, s.steps++;
    }
    w->ms[q] = (double)ns * 1e-6, w->ms_rebuild[q] = (double)ns_rebuild * 1e-6;
    if (!rc)
      w->identical &= !memcmp(x_end, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nb);
    tb_sim_destroy(&s);
  }
  free(mark), free(x_end);
  if (rc) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    return;
  }
  w->median = tb_stats_of(w->ms, reps).median, w->ok = 1;
  w->median_rebuild = tb_stats_of(w->ms_rebuild, reps).median;
  double other[15];
  for (int q = 0; q < reps; q++) other[q] = w->ms[q] - w->ms_rebuild[q];
  w->median_other = tb_stats_of(other, reps).median;
}

/* Per step against the base, the steps that rebuilt the surface left out. */
static double other_ratio(const row *w, int r) {
  const double steps = T_TABLE / 0.01;
  return w[r].median_other / (steps - w[r].rebuilds) / (w[BASE].median / steps);
}

static void table1(tb_suite *su, const row *w, int reps) {
  static const char *cols[] = {"mesh (paper)",
                               "settings",
                               "vertices (most)",
                               "triangles (most)",
                               "vertices at t = 4 s",
                               "triangles at t = 4 s",
                               "paper vertices",
                               "paper triangles",
                               "5 s (ms, ours)",
                               "5 s (ms, paper)",
                               "per step (us, ours)",
                               "ours / base",
                               "paper / base",
                               "surface rebuilds",
                               "in the rebuilding steps (ms)",
                               "ours / base, the other steps"};
  tb_table *t = tb_table_new("table1",
                             "Bao 2006 table 1: the sphere, 5 s at dt 0.01 (500 steps), msm-vvs at "
                             "the paper's parameters",
                             16, cols);
  for (int r = 0; r < NROWS; r++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", paper[r].name);
    tb_table_cell(t, "%s", paper[r].set);
    if (!w[r].ok) {
      tb_table_cell(t, "%s", w[r].why);
      for (int k = 3; k < 16; k++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w[r].nv_max, "%.0f"), tb_table_num(t, w[r].ntri_max, "%.0f");
    tb_table_num(t, w[r].nv_press, "%.0f"), tb_table_num(t, w[r].ntri_press, "%.0f");
    if (r == PLAIN)
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    else
      tb_table_num(t, paper[r].nv, "%.0f"), tb_table_num(t, paper[r].ntri, "%.0f");
    tb_table_num(t, w[r].median, "%.2f");
    tb_table_num(t, paper[r].ms, "%.0f");
    tb_table_num(t, 1e3 * w[r].median / (T_TABLE / 0.01), "%.2f");
    tb_table_num(t, w[BASE].ok ? w[r].median / w[BASE].median : NAN, "%.2fx");
    tb_table_num(t, paper[r].ms / paper[BASE].ms, "%.2fx");
    tb_table_num(t, w[r].rebuilds, "%.0f");
    tb_table_num(t, w[r].median_rebuild, "%.2f");
    tb_table_num(t, w[BASE].ok ? other_ratio(w, r) : NAN, "%.2fx");
  }
  (void)reps;
  tb_suite_table(su, t);
}

/* rms and largest distance between the base vertices of a and b. */
static void distance(const tb_vec3 *a, const tb_vec3 *b, int n, double *rms, double *max) {
  double s2 = 0;
  *max = 0;
  for (int i = 0; i < n; i++) {
    double d = tb_dist(a[i], b[i]);
    s2 += d * d, *max = fmax(*max, d);
  }
  *rms = sqrt(s2 / n);
}

static void accuracy(tb_suite *su, const row *w, int nb, double release) {
  static const char *cols[] = {"mesh",
                               "rms distance to full, 252 base vertices (radius 1)",
                               "largest distance to full (radius 1)",
                               "dent at t = 4 s (radius 1)",
                               "dent - full's (radius 1)",
                               "largest dent over the run (radius 1)"};
  char title[200];
  snprintf(title, sizeof title,
           "Accuracy at the end of the press (t = %g s): each model's base vertices against the "
           "fully subdivided model's",
           release);
  tb_table *t = tb_table_new("accuracy", title, 6, cols);
  static const int order[NROWS] = {LOCAL, BASE, PLAIN, FULL};
  for (int k = 0; k < NROWS; k++) {
    int r = order[k];
    tb_table_row(t);
    tb_table_cell(t, "%s", paper[r].name);
    if (!w[r].ok || !w[FULL].ok) {
      for (int c = 1; c < 6; c++) tb_table_cell(t, "-");
      continue;
    }
    double rms, max;
    distance(w[r].x_press, w[FULL].x_press, nb, &rms, &max);
    tb_table_num(t, rms, "%.2e"), tb_table_num(t, max, "%.2e");
    tb_table_num(t, w[r].dent_press, "%.4f");
    tb_table_num(t, w[r].dent_press - w[FULL].dent_press, "%+.2e");
    tb_table_num(t, w[r].peak, "%.4f");
    char name[96];
    snprintf(name, sizeof name, "accuracy/%s",
             r == LOCAL  ? "local"
             : r == BASE ? "base"
             : r == FULL ? "full"
                         : "levels1");
    tb_suite_counter(su, name, "rms_distance_to_full", rms);
    tb_suite_counter(su, name, "max_distance_to_full", max);
    tb_suite_counter(su, name, "dent_at_release", w[r].dent_press);
    tb_suite_counter(su, name, "dent_peak", w[r].peak);
  }
  tb_suite_table(su, t);
}

/* Figs 6-7: one scene, one variant, the scene's whole run. */
typedef struct pr {
  int ok, at_rest;
  char why[200];
  double dent, dent_t, left, left_rms, speed, tol, t_end;
} pr;

static void press_release(ctx *c, const char *scene, int v, uint64_t seed, pr *o) {
  tb_error err;
  tb_sim s;
  o->ok = 0;
  if (open_sim(&s, scene, variant[v].set, 0, seed, &err)) {
    snprintf(o->why, sizeof o->why, "%.190s", err.msg);
    return;
  }
  long n = lround(s.def.duration / s.def.dt), at = lround(s.def.release / s.def.dt);
  int rc = 0, pics = v == 0 || v == NVAR - 1; /* the paper's two */
  const char *who = v == 0 ? "conventional" : "improved";
  const char *verb = !strcmp(scene, PRESS) ? "pressed" : "stretched";
  char name[96], cap[300];
  for (long k = 0; k < n && !rc; k++) {
    rc = tb_sim_step(&s, &err);
    if (!rc && pics && k + 1 == at) {
      snprintf(name, sizeof name, "%s-%s-1-%s.png", scene, who, verb);
      snprintf(cap, sizeof cap,
               "Figs 6-7: the %s model %s (t = %g s); colour: displacement 0 to %g",
               variant[v].name, verb, s.t, U_SCALE);
      picture(c, &s, 0, name, cap);
    }
  }
  o->t_end = s.t, o->dent = s.probe_peak, o->dent_t = s.probe_peak_t;
  if (rc)
    snprintf(o->why, sizeof o->why, "%.190s", err.msg);
  else {
    tb_sim_metrics m = tb_sim_measure(&s);
    o->left = m.max_disp, o->left_rms = m.rms_disp;
    o->at_rest = tb_sim_at_rest(&s, &o->speed, &o->tol);
    o->ok = 1;
    if (pics) {
      snprintf(name, sizeof name, "%s-%s-2-released.png", scene, who);
      snprintf(cap, sizeof cap,
               "Figs 6-7: the %s model %g s after the release (t = %g s); colour: displacement 0 "
               "to %g",
               variant[v].name, s.t - s.def.release, s.t, U_SCALE);
      picture(c, &s, 0, name, cap);
    }
  }
  tb_sim_destroy(&s);
}

static void press_table(tb_suite *su, pr res[2][NVAR], double release, double end) {
  static const char *cols[] = {"scene",
                               "model",
                               "settings",
                               "dent: largest probe displacement (radius 1)",
                               "when (s)",
                               "left at the end: largest node distance from rest (radius 1)",
                               "rms node distance from rest at the end (radius 1)",
                               "at rest at the end",
                               "largest node speed at the end (per s)"};
  char title[240];
  snprintf(title, sizeof title,
           "Figs 6-7: pressed (sphere-press) and stretched (sphere-stretch) with 3 in total on the "
           "top patch until t = %g s, then released; the state at t = %g s",
           release, end);
  tb_table *t = tb_table_new("press_release", title, 9, cols);
  for (int sc = 0; sc < 2; sc++)
    for (int v = 0; v < NVAR; v++) {
      const pr *o = &res[sc][v];
      const char *scene = sc ? STRETCH : PRESS;
      tb_table_row(t);
      tb_table_cell(t, "%s", scene);
      tb_table_cell(t, "%s", variant[v].name);
      tb_table_cell(t, "%s", variant[v].set[0] ? variant[v].set : "(defaults)");
      tb_table_num(t, o->dent, "%.4f");
      tb_table_num(t, o->dent_t, "%.2f");
      if (!o->ok) {
        tb_table_cell(t, "%s", o->why);
        for (int k = 6; k < 9; k++) tb_table_cell(t, "-");
        continue;
      }
      tb_table_num(t, o->left, "%.2e");
      tb_table_num(t, o->left_rms, "%.2e");
      tb_table_cell(t, "%s", o->at_rest ? "yes" : "no");
      tb_table_num(t, o->speed, "%.2e");
      char name[128];
      snprintf(name, sizeof name, "press_release/%s/%s", scene,
               v == 0   ? "conventional"
               : v == 1 ? "shell_quasistatic"
               : v == 2 ? "springs_euler"
                        : "improved");
      tb_suite_counter(su, name, "dent", o->dent);
      tb_suite_counter(su, name, "dent_time_s", o->dent_t);
      tb_suite_counter(su, name, "left_max", o->left);
      tb_suite_counter(su, name, "left_rms", o->left_rms);
      tb_suite_counter(su, name, "at_rest", o->at_rest);
      tb_suite_counter(su, name, "ok", o->ok);
    }
  tb_suite_table(su, t);
}

int tb_suite_bao(const tb_suite_opts *o) {
  uint64_t t0 = tb_time_ns();
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/bao", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "bao",
                                "Bao 2006: msm-vvs on the paper's sphere, table 1 (base, fully "
                                "subdivided, locally refined) and figs 6-8",
                                o->seed, &err);
  if (!su) return fprintf(stderr, "bao: %s\n", err.msg), 1;
  ctx c = {.su = su, .r = tb_renderer_new(W, H, 2, &err), .dir = dir};
  if (!c.r) {
    fprintf(stderr, "bao: %s\n", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  int reps = o->scale < 1 ? 3 : o->full ? 15 : 7;
  row w[NROWS];
  memset(w, 0, sizeof w);
  double ms[NROWS][15], ms_rebuild[NROWS][15];
  for (int r = 0; r < NROWS; r++) {
    tb_progress("bao", r, NROWS + 2);
    w[r].ms = ms[r], w[r].ms_rebuild = ms_rebuild[r];
    measure(&c, r, reps, o->seed, &w[r]);
    if (!w[r].ok) fprintf(stderr, "bao: %s: %s\n", paper[r].name, w[r].why), c.failed = 1;
    if (w[r].ok && !w[r].identical) c.failed = 1; /* the timed runs must be the measured one */
  }
  const tb_context *cx = tb_suite_context(su);
  tb_suite_note(
      su,
      "Scene sphere-press: the paper's sphere (a geodesic surface of 252 vertices, 500 "
      "triangles, radius 1), the patch around its bottom node held, 3 in total pushing the patch "
      "around its top node down until t = 4 s, then let go; msm-vvs at the paper's parameters "
      "(m 1 per base vertex, ks 3, kd 0.5, k's 1.5, k'd 0.5, dt 0.01) with the scene's "
      "quasi-static step scale alpha 50 (the paper's table used its improved explicit Euler). "
      "The first three rows use levels=2, so that the masses (the total kept, shared by area) "
      "and the constants (damping and virtual springs per unit area, ks per spring) are made "
      "the same way in all three and only the surface differs; levels=1 is the model without "
      "refinement (uniform masses, no area shares), for reference. refine_force is the "
      "criterion of models/vvs_refine.c: a point whose stress (the sum of its springs' |k (l - "
      "R)|) per area share (its surface area over a base point's) reaches it splits its faces "
      "a level deeper, and one below coarsen_share (0.5) of it goes back; 1e9 never refines, 0 "
      "refines everything at the first step (the paper's fully subdivided sphere), 0.2 "
      "refines around the press. Vertices and triangles: the current surface's, the most over "
      "the 5 s and at the end of the press (t = 4 s). Time: the model's step alone, summed "
      "over the 500 steps; the median over %d repetitions (each a fresh run; every one ends on "
      "the bit-identical positions of the measured run: %s). This machine: %s (%d cores), "
      "load average %.2f at the start; the paper's: Pentium 4 2.8 GHz.",
      reps,
      w[BASE].identical && w[FULL].identical && w[LOCAL].identical && w[PLAIN].identical ? "yes"
                                                                                         : "NO",
      cx->cpu, cx->cores, cx->have_load ? cx->load[0] : NAN);
  table1(su, w, reps);
  for (int r = 0; r < NROWS; r++) {
    if (!w[r].ok) continue;
    char name[96];
    snprintf(name, sizeof name, MODEL "/sphere-press/%s",
             r == LOCAL  ? "local"
             : r == BASE ? "base"
             : r == FULL ? "full"
                         : "levels1");
    tb_suite_bench(su, name, w[r].ms, NULL, reps, "ms");
    tb_suite_counter(su, name, "steps", lround(T_TABLE / 0.01));
    tb_suite_counter(su, name, "vertices_most", w[r].nv_max);
    tb_suite_counter(su, name, "triangles_most", w[r].ntri_max);
    tb_suite_counter(su, name, "vertices_at_release", w[r].nv_press);
    tb_suite_counter(su, name, "triangles_at_release", w[r].ntri_press);
    tb_suite_counter(su, name, "us_per_step", 1e3 * w[r].median / (T_TABLE / 0.01));
    if (w[BASE].ok) tb_suite_counter(su, name, "ratio_to_base", w[r].median / w[BASE].median);
    if (isfinite(paper[r].ms)) tb_suite_counter(su, name, "paper_ms", paper[r].ms);
    tb_suite_counter(su, name, "identical_runs", w[r].identical);
    tb_suite_counter(su, name, "surface_rebuilds", w[r].rebuilds);
    tb_suite_counter(su, name, "ms_in_rebuild_steps", w[r].median_rebuild);
    if (w[BASE].ok) tb_suite_counter(su, name, "ratio_to_base_other_steps", other_ratio(w, r));
  }
  if (w[BASE].ok && w[FULL].ok && w[LOCAL].ok) {
    double lb = w[LOCAL].median / w[BASE].median, fb = w[FULL].median / w[BASE].median, e = 0;
    int every = tb_model_setting("msm-vvs", NULL, "refine_every", &e) ? 0 : (int)e;
    double added = (w[FULL].median - w[BASE].median) / (w[LOCAL].median - w[BASE].median);
    tb_suite_note(
        su,
        "Local refinement costs %.2fx the base mesh per step (the issue's goal <= %.1fx: %s; "
        "the paper's %.2fx), full subdivision %.2fx (the paper's %.2fx). The time full "
        "subdivision adds is %.1f times the time local refinement adds (the paper: \"20-some "
        "times\", %.1f). Where it goes: %d of the local run's steps rebuilt the surface (a "
        "point's depth changed the surface: tb_lod_apply, the springs from its edges, masses and "
        "constants from the area shares), %.0f us each on the median (%.0f base steps), %.2f of "
        "its %.2f ms; its "
        "other %d steps cost %.2fx a base step (a depth change that leaves the surface as it was "
        "rebuilds nothing). The levels=2 base row costs %.2fx the "
        "levels=1 model (the same model with no levels: masses not shared by area, no "
        "criterion checked every %d steps), so local refinement costs %.2fx the model without "
        "it.",
        lb, GOAL, lb <= GOAL ? "met" : "NOT met", paper[LOCAL].ms / paper[BASE].ms, fb,
        paper[FULL].ms / paper[BASE].ms, added,
        (paper[FULL].ms - paper[BASE].ms) / (paper[LOCAL].ms - paper[BASE].ms), w[LOCAL].rebuilds,
        w[LOCAL].rebuilds ? 1e3 * w[LOCAL].median_rebuild / w[LOCAL].rebuilds : 0,
        w[LOCAL].rebuilds
            ? w[LOCAL].median_rebuild / w[LOCAL].rebuilds / (w[BASE].median / (T_TABLE / 0.01))
            : 0,
        w[LOCAL].median_rebuild, w[LOCAL].median, (int)lround(T_TABLE / 0.01) - w[LOCAL].rebuilds,
        other_ratio(w, LOCAL), w[PLAIN].ok ? w[BASE].median / w[PLAIN].median : NAN, every,
        w[PLAIN].ok ? w[LOCAL].median / w[PLAIN].median : NAN);
  }
  flush(&c);
  accuracy(su, w, w[FULL].nb, w[FULL].release);
  tb_suite_note(su,
                "The %d base vertices exist with the same indices in every model; the distance "
                "is between the two models' positions of each at t = %g s, the end of the press. "
                "Dent: the length of the mean displacement of the pressed patch (the scene's "
                "probe, %d nodes).",
                w[FULL].nb, w[FULL].release, w[FULL].nprobe);
  pr res[2][NVAR];
  memset(res, 0, sizeof res);
  for (int sc = 0; sc < 2; sc++) {
    tb_progress("bao", NROWS + sc, NROWS + 2);
    for (int v = 0; v < NVAR; v++) {
      press_release(&c, sc ? STRETCH : PRESS, v, o->seed, &res[sc][v]);
      if (!res[sc][v].ok)
        fprintf(stderr, "bao: %s, %s: %s\n", sc ? STRETCH : PRESS, variant[v].name, res[sc][v].why);
    }
  }
  tb_progress("bao", NROWS + 2, NROWS + 2);
  press_table(su, res, w[FULL].release, res[0][NVAR - 1].t_end);
  double wall = (double)(tb_time_ns() - t0) * 1e-9;
  tb_suite_counter(su, "suite", "wall_time_s", wall);
  tb_suite_note(su,
                "The runs of the last table go the scenes' whole 12 s (the load until 4 s). At "
                "rest: the largest node speed, averaged over the last 0.1 s, below the scene's "
                "rest_speed times the sphere's size. The pictures are rendered headless as "
                "`tissuebench render --scene sphere-press --set levels=2 --set refine_force=0.2 "
                "--times 4 --color displacement --wireframe` does (the model's current surface; "
                "a refined point's displacement from its own rest position). The suite took "
                "%.2f s in all (%d + %d timed runs of 500 steps, the pictures included).",
                wall, NROWS, NROWS * reps);
  flush(&c);
  tb_renderer_free(c.r);
  for (int r = 0; r < NROWS; r++) free(w[r].x_press);
  if (tb_suite_end(su, &err)) fprintf(stderr, "bao: %s\n", err.msg), c.failed = 1;
  return c.failed;
}
