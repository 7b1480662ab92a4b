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
 * tb_sim_step does) on one thread, CPU time (wall beside), summed over the
 * 500 steps; one run a repetition, the rows' runs taking turns (base,
 * full, local, levels=1, base, ...); medians over repetitions with their
 * 95% intervals, ratios to the base the medians of the paired ratios, the
 * goal (local <= 1.2x base) met, not met or inconclusive. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "bao_priv.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "measure/tb_draw.h"
#include "render/tb_render.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

#define PRESS "sphere-press"
#define STRETCH "sphere-stretch"
#define T_TABLE 5.0 /* the paper's simulated time */
#define W 400       /* pictures */
#define H 300
#define FIG8_W 800 /* fig 8: the refinement seen from the top */
#define FIG8_H 600
#define MAX_REPS 15 /* timed repetitions at most (--full) */
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
    {"locally refined", "levels=2 refine_force=0.1", 294, 584, 66},
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

int tb_bao_open(tb_sim *s, const char *scene, const char *settings, tb_sim_def d, tb_error *err) {
  tb_settings set;
  tb_settings_init(&set);
  char buf[128];
  snprintf(buf, sizeof buf, "%s", settings);
  for (char *save = NULL, *p = strtok_r(buf, " ", &save); p; p = strtok_r(NULL, " ", &save))
    if (tb_settings_set(&set, p, err)) return -1;
  return tb_sim_create(s, scene, &d, TB_BAO_MODEL, &set, NULL, err);
}

/* The scene's settings with duration (<= 0: the scene's) and seed. */
static tb_sim_def def_of(double duration, uint64_t seed) {
  tb_sim_def d;
  tb_sim_def_init(&d);
  if (duration > 0) d.duration = duration;
  d.seed = seed;
  return d;
}

int tb_bao_used_vertices(const tb_sim *s, char *mark) {
  tb_surface su = tb_model_surface(&s->model);
  memset(mark, 0, (size_t)su.nv);
  int n = 0;
  for (int k = 0; k < 3 * su.ntri; k++) n += !mark[su.tri[k]]++;
  return n;
}

double tb_bao_dent(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  tb_vec3 m = tb_v3(0, 0, 0);
  for (int k = 0; k < s->nprobe; k++) m = tb_add(m, tb_sub(x[s->probe[k]], s->mesh.x[s->probe[k]]));
  return s->nprobe ? tb_len(m) / s->nprobe : NAN;
}

/* A picture of the current state: the surface coloured by displacement
 * (0 to U_SCALE), wireframe when asked, into dir/name with its caption;
 * from the left front, or for fig 8 from the top at FIG8_W x FIG8_H, where
 * the refined faces under the press show. */
static void picture(ctx *c, tb_sim *s, int wire, const char *name, const char *caption) {
  tb_camera cam;
  int top = !strncmp(name, "fig8", 4);
  tb_error err;
  tb_renderer *big = top ? tb_renderer_new(FIG8_W, FIG8_H, 2, &err) : NULL;
  tb_renderer *rr = top ? big : c->r;
  if (!rr) {
    fprintf(stderr, "bao: %s\n", err.msg);
    c->failed = 1;
    return;
  }
  tb_camera_preset(top ? "top" : "left-front", tb_v3(-1, -1, -1), tb_v3(1, 1, 1.2), &cam);
  tb_renderer_begin(rr, &cam, (const float[3]){1, 1, 1});
  tb_surface su = tb_model_surface(&s->model);
  double *u = malloc(sizeof(double) * (size_t)su.nv);
  if (u) tb_draw_displacement(s, u);
  tb_draw_sim(rr, s, u, 0, U_SCALE, "displacement (sphere radii)", wire);
  free(u);
  char path[1200];
  snprintf(path, sizeof path, "%s/%s", c->dir, name);
  int bad = tb_renderer_write_png(rr, path, &err);
  tb_renderer_free(big);
  if (bad) {
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
  double *cpu, *wall;  /* per repetition: CPU and wall ms for the run's steps */
  double *cpu_rebuild; /* per repetition: CPU ms of the steps that rebuilt */
  double dent_press, peak;
  tb_est med;     /* CPU ms of the 500 steps: median over repetitions, 95% interval */
  tb_est to_base; /* CPU time over the base row's, paired by repetition */
  tb_est other;   /* the steps that rebuilt nothing, per step, over a base step */
  double med_wall, med_rebuild;
  tb_vec3 *x_press; /* the base vertices at the end of the press */
  tb_vec3 *x_end;   /* the base vertices at the end of the measured run */
  int identical;    /* the timed runs end where the measured run does */
  int rebuilds;     /* steps that changed the surface */
  int nb, nprobe;   /* the mesh's nodes, the probe's */
  double release;   /* the end of the press */
} row;

#define STEPS ((int)lround(T_TABLE / 0.01))

/* The measured run of row r (tb_sim_step: health checked): counts,
 * pictures, the positions the timed runs must end on. */
static void measure(ctx *c, int r, uint64_t seed, row *w) {
  tb_error err;
  tb_sim s;
  w->ok = 0;
  if (tb_bao_open(&s, PRESS, paper[r].set, def_of(T_TABLE, seed), &err)) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    return;
  }
  long n = lround(s.def.duration / s.def.dt), at = lround(s.def.release / s.def.dt);
  int nb = w->nb = s.mesh.nv;
  w->nprobe = s.nprobe, w->release = s.def.release;
  char *mark = malloc((size_t)tb_model_npoints(&s.model) + (size_t)tb_model_surface(&s.model).nv);
  w->x_end = malloc(sizeof(tb_vec3) * (size_t)nb);
  w->x_press = malloc(sizeof(tb_vec3) * (size_t)nb);
  int rc = mark && w->x_end && w->x_press ? 0 : tb_error_set(&err, "bao", 0, "out of memory");
  unsigned long version = tb_model_surface(&s.model).version;
  for (long k = 0; k < n && !rc; k++) {
    if ((rc = tb_sim_step(&s, &err))) break;
    int nv = tb_bao_used_vertices(&s, mark), nt = tb_model_surface(&s.model).ntri;
    w->rebuilds += tb_model_surface(&s.model).version != version;
    version = tb_model_surface(&s.model).version;
    if (nv > w->nv_max) w->nv_max = nv;
    if (nt > w->ntri_max) w->ntri_max = nt;
    if (k + 1 == at) {
      w->nv_press = nv, w->ntri_press = nt, w->dent_press = tb_bao_dent(&s);
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
                 r == LOCAL  ? "under local refinement (refine_force 0.1)"
                 : r == FULL ? "fully subdivided"
                             : "on the base mesh",
                 s.t, nv, nt, U_SCALE);
        picture(c, &s, 1, name, cap);
      }
    }
  }
  w->peak = s.probe_peak;
  if (!rc) memcpy(w->x_end, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nb);
  tb_sim_destroy(&s);
  free(mark);
  if (rc) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    return;
  }
  w->identical = 1, w->ok = 1;
}

/* Timed repetition q of row r: a fresh run, the model's step alone timed
 * (CPU and wall, summed over the 500 steps; the rebuilding steps' CPU time
 * apart). */
static void timed(int r, int q, uint64_t seed, row *w) {
  tb_error err;
  tb_sim s;
  if (!w->ok) return;
  if (tb_bao_open(&s, PRESS, paper[r].set, def_of(T_TABLE, seed), &err)) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    w->ok = 0;
    return;
  }
  long n = lround(s.def.duration / s.def.dt);
  double cpu = 0, wall = 0, rebuild = 0;
  unsigned long ver = tb_model_surface(&s.model).version;
  int rc = 0;
  for (long k = 0; k < n && !rc; k++) {
    if ((rc = tb_sim_loads(&s, s.t + s.def.dt, &err))) break;
    tb_step in = {0};
    in.dt = s.def.dt, in.gravity = s.gravity, in.force = s.force;
    in.nfixed = s.nfixed, in.fixed = s.fixed, in.fixed_x = s.fixed_x;
    double cw, cc;
    tb_clock clk = tb_clock_start();
    rc = tb_model_step(&s.model, &in, &err);
    tb_clock_ms(&clk, &cw, &cc);
    cpu += cc, wall += cw;
    if (tb_model_surface(&s.model).version != ver)
      rebuild += cc, ver = tb_model_surface(&s.model).version;
    s.t += s.def.dt, s.steps++;
  }
  w->cpu[q] = cpu, w->wall[q] = wall, w->cpu_rebuild[q] = rebuild;
  if (!rc)
    w->identical &=
        !memcmp(w->x_end, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)w->nb);
  tb_sim_destroy(&s);
  if (rc) {
    snprintf(w->why, sizeof w->why, "%.190s", err.msg);
    w->ok = 0;
  }
}

/* The estimates of every row from its repetitions (all CPU time). */
static void estimate(row *w, int reps) {
  for (int r = 0; r < NROWS; r++) {
    row *x = &w[r];
    if (!x->ok) continue;
    x->med = tb_median_est(x->cpu, reps);
    x->med_wall = tb_median_est(x->wall, reps).value;
    x->med_rebuild = tb_median_est(x->cpu_rebuild, reps).value;
    if (!w[BASE].ok) continue;
    x->to_base = tb_ratio_est(x->cpu, w[BASE].cpu, reps);
    double other[MAX_REPS];
    for (int q = 0; q < reps; q++)
      other[q] = (x->cpu[q] - x->cpu_rebuild[q]) / (STEPS - x->rebuilds) / (w[BASE].cpu[q] / STEPS);
    x->other = tb_median_est(other, reps);
  }
}

static void table1(tb_suite *su, const row *w) {
  static const char *cols[] = {"mesh (paper)",
                               "settings",
                               "vertices (most)",
                               "triangles (most)",
                               "vertices at t = 4 s",
                               "triangles at t = 4 s",
                               "paper vertices",
                               "paper triangles",
                               "5 s CPU (ms, ours, median)",
                               "5 s (ms, paper)",
                               "5 s wall (ms, ours, median)",
                               "per step CPU (us, ours)",
                               "ours / base, CPU (95% interval)",
                               "ours / base low",
                               "ours / base high",
                               "paper / base",
                               "surface rebuilds",
                               "in the rebuilding steps, CPU (ms)",
                               "ours / base, the other steps, CPU (95% interval)"};
  tb_table *t = tb_table_new("table1",
                             "Bao 2006 table 1: the sphere, 5 s at dt 0.01 (500 steps), msm-vvs at "
                             "the paper's parameters; one thread, CPU time",
                             19, cols);
  tb_table_only(t, 13, TB_CSV_ONLY), tb_table_only(t, 14, TB_CSV_ONLY);
  for (int r = 0; r < NROWS; r++) {
    tb_table_row(t);
    tb_table_cell(t, "%s", paper[r].name);
    tb_table_cell(t, "%s", paper[r].set);
    if (!w[r].ok) {
      tb_table_cell(t, "%s", w[r].why);
      for (int k = 3; k < 19; k++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w[r].nv_max, "%.0f"), tb_table_num(t, w[r].ntri_max, "%.0f");
    tb_table_num(t, w[r].nv_press, "%.0f"), tb_table_num(t, w[r].ntri_press, "%.0f");
    if (r == PLAIN)
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    else
      tb_table_num(t, paper[r].nv, "%.0f"), tb_table_num(t, paper[r].ntri, "%.0f");
    tb_table_num(t, w[r].med.value, "%.2f");
    tb_table_num(t, paper[r].ms, "%.0f");
    tb_table_num(t, w[r].med_wall, "%.2f");
    tb_table_num(t, 1e3 * w[r].med.value / STEPS, "%.2f");
    tb_est nan = {NAN, NAN, NAN, 0}, tb = w[BASE].ok ? w[r].to_base : nan;
    tb_table_est(t, tb, "%.2f", "x");
    tb_table_num(t, tb.lo, "%.6g"), tb_table_num(t, tb.hi, "%.6g");
    tb_table_num(t, paper[r].ms / paper[BASE].ms, "%.2fx");
    tb_table_num(t, w[r].rebuilds, "%.0f");
    tb_table_num(t, w[r].med_rebuild, "%.2f");
    tb_table_est(t, w[BASE].ok ? w[r].other : nan, "%.2f", "x");
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
  if (tb_bao_open(&s, scene, variant[v].set, def_of(0, seed), &err)) {
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

/* "x (lo-hi)" of an estimate with the unit after x, for prose. */
static const char *est_text(tb_est e, const char *fmt, const char *unit, char *buf, size_t cap) {
  char f[64];
  snprintf(f, sizeof f, "%s%s (%s-%s)", fmt, unit, fmt, fmt);
  snprintf(buf, cap, f, e.value, e.lo, e.hi);
  return buf;
}

/* What local refinement costs against the base mesh: the ratios with their
 * intervals, the goal's verdict, and the multiple of what local refinement
 * adds that full subdivision adds only when local refinement's addition is
 * beyond noise (else what is known). */
static void cost_note(tb_suite *su, const row *w, int reps) {
  tb_est lb = w[LOCAL].to_base, fb = w[FULL].to_base;
  char v[200], a[64], b[64], c[64], d[64], e[64], adds[600];
  tb_verdict_text(lb, TB_BAO_GOAL, 0, v, sizeof v);
  double paper_added = (paper[FULL].ms - paper[BASE].ms) / (paper[LOCAL].ms - paper[BASE].ms);
  if (lb.n >= TB_EST_MIN && lb.lo > 1 && fb.lo > 1) {
    double q[MAX_REPS];
    for (int k = 0; k < reps; k++)
      q[k] = (w[FULL].cpu[k] - w[BASE].cpu[k]) / (w[LOCAL].cpu[k] - w[BASE].cpu[k]);
    tb_est added = tb_median_est(q, reps);
    snprintf(adds, sizeof adds,
             "The time full subdivision adds is %s times the time local refinement adds (the "
             "median of the repetitions' paired figures with its 95%% interval; the paper: "
             "\"20-some times\", %.1f).",
             est_text(added, "%.1f", "", a, sizeof a), paper_added);
    tb_suite_counter(su, "cost/full_added_over_local_added", "value", added.value);
    tb_suite_counter(su, "cost/full_added_over_local_added", "low", added.lo);
    tb_suite_counter(su, "cost/full_added_over_local_added", "high", added.hi);
  } else if (lb.n >= TB_EST_MIN && lb.hi < 1) {
    snprintf(adds, sizeof adds,
             "Local refinement took less time than the base mesh beyond noise, so it adds "
             "nothing to take a multiple of (the paper: full subdivision adds \"20-some times\" "
             "what local refinement adds, %.1f).",
             paper_added);
  } else {
    snprintf(adds, sizeof adds,
             "The time local refinement adds over the base mesh cannot be told from noise (%s), "
             "so no multiple of it is given (the paper: full subdivision adds \"20-some times\" "
             "what local refinement adds, %.1f).",
             lb.n < TB_EST_MIN ? "too few repetitions for a 95% interval"
                               : "the 95% interval of local / base holds 1",
             paper_added);
  }
  double e0 = 0;
  int every = tb_model_setting("msm-vvs", NULL, "refine_every", &e0) ? 0 : (int)e0;
  tb_est nan = {NAN, NAN, NAN, 0};
  tb_est bp = w[PLAIN].ok ? tb_ratio_est(w[BASE].cpu, w[PLAIN].cpu, reps) : nan;
  tb_est lp = w[PLAIN].ok ? tb_ratio_est(w[LOCAL].cpu, w[PLAIN].cpu, reps) : nan;
  double base_step = w[BASE].med.value / STEPS, rb = w[LOCAL].rebuilds;
  tb_suite_note(
      su,
      "Local refinement costs %s the base mesh per step, CPU time (about the same cost, the "
      "goal <= %.1fx: %s; the paper's %.2fx), full subdivision %s (the paper's %.2fx). %s "
      "Where it goes: %d of the local run's steps rebuilt the surface (a "
      "point's depth changed the surface: tb_lod_apply, the springs from its edges, masses and "
      "constants from the area shares), %.0f us each on the median (%.0f base steps), %.2f of "
      "its %.2f ms; its other %d steps cost %s a base step (a depth change that leaves the "
      "surface as it was rebuilds nothing). The levels=2 base row costs %s the levels=1 model "
      "(the same model with no levels: masses not shared by area, no criterion checked every %d "
      "steps), so local refinement costs %s the model without it. Each ratio x (lo-hi): the "
      "median of %d repetitions' paired ratios and its 95%% interval.",
      est_text(lb, "%.2f", "x", a, sizeof a), TB_BAO_GOAL, v, paper[LOCAL].ms / paper[BASE].ms,
      est_text(fb, "%.2f", "x", b, sizeof b), paper[FULL].ms / paper[BASE].ms, adds,
      w[LOCAL].rebuilds, rb ? 1e3 * w[LOCAL].med_rebuild / rb : 0,
      rb ? w[LOCAL].med_rebuild / rb / base_step : 0, w[LOCAL].med_rebuild, w[LOCAL].med.value,
      STEPS - w[LOCAL].rebuilds, est_text(w[LOCAL].other, "%.2f", "x", c, sizeof c),
      est_text(bp, "%.2f", "x", d, sizeof d), every, est_text(lp, "%.2f", "x", e, sizeof e), reps);
  tb_suite_counter(su, "cost/local_over_base", "value", lb.value);
  tb_suite_counter(su, "cost/local_over_base", "low", lb.lo);
  tb_suite_counter(su, "cost/local_over_base", "high", lb.hi);
  tb_suite_counter(su, "cost/local_over_base", "goal", TB_BAO_GOAL);
  tb_suite_counter(su, "cost/local_over_base", "verdict", tb_verdict(lb, TB_BAO_GOAL, 0));
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
  int reps = o->scale < 1 ? 3 : o->full ? MAX_REPS : 7;
  int threads = tb_threads_setting();
  tb_threads_set(1); /* a comparison of meshes, not of threads: one thread, CPU time */
  row w[NROWS];
  memset(w, 0, sizeof w);
  double store[NROWS][3][MAX_REPS];
  for (int r = 0; r < NROWS; r++) {
    tb_progress("bao", r, NROWS + 2 + reps);
    w[r].cpu = store[r][0], w[r].wall = store[r][1], w[r].cpu_rebuild = store[r][2];
    measure(&c, r, o->seed, &w[r]);
  }
  /* the timed runs take turns row by row (base, full, local, levels=1,
   * base, ...), so that a busy spell of the machine falls on all alike */
  for (int q = 0; q < reps; q++) {
    tb_progress("bao", NROWS + q, NROWS + 2 + reps);
    for (int r = 0; r < NROWS; r++) timed(r, q, o->seed, &w[r]);
  }
  for (int r = 0; r < NROWS; r++) {
    if (!w[r].ok) fprintf(stderr, "bao: %s: %s\n", paper[r].name, w[r].why), c.failed = 1;
    if (w[r].ok && !w[r].identical) c.failed = 1; /* the timed runs must be the measured one */
  }
  estimate(w, reps);
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
      "the 5 s and at the end of the press (t = 4 s). Time: the model's step alone on one "
      "thread, CPU time (wall beside), summed over the 500 steps; the median over %d "
      "repetitions with its 95%% interval, the four rows' runs taking turns (base, full, local, "
      "levels=1, base, ...), a ratio the median of the repetitions' paired ratios (each a fresh "
      "run; every one ends on "
      "the bit-identical positions of the measured run: %s). This machine: %s (%d cores), "
      "load average %.2f at the start; the paper's: Pentium 4 2.8 GHz.",
      reps,
      w[BASE].identical && w[FULL].identical && w[LOCAL].identical && w[PLAIN].identical ? "yes"
                                                                                         : "NO",
      cx->cpu, cx->cores, cx->have_load ? cx->load[0] : NAN);
  table1(su, w);
  for (int r = 0; r < NROWS; r++) {
    if (!w[r].ok) continue;
    char name[96];
    snprintf(name, sizeof name, TB_BAO_MODEL "/sphere-press/%s",
             r == LOCAL  ? "local"
             : r == BASE ? "base"
             : r == FULL ? "full"
                         : "levels1");
    tb_suite_bench(su, name, w[r].wall, w[r].cpu, reps, "ms");
    tb_suite_counter(su, name, "steps", STEPS);
    tb_suite_counter(su, name, "vertices_most", w[r].nv_max);
    tb_suite_counter(su, name, "triangles_most", w[r].ntri_max);
    tb_suite_counter(su, name, "vertices_at_release", w[r].nv_press);
    tb_suite_counter(su, name, "triangles_at_release", w[r].ntri_press);
    tb_suite_counter(su, name, "us_per_step", 1e3 * w[r].med.value / STEPS);
    if (w[BASE].ok) {
      tb_suite_counter_est(su, name, "ratio_to_base", w[r].to_base);
    }
    if (isfinite(paper[r].ms)) tb_suite_counter(su, name, "paper_ms", paper[r].ms);
    tb_suite_counter(su, name, "identical_runs", w[r].identical);
    tb_suite_counter(su, name, "surface_rebuilds", w[r].rebuilds);
    tb_suite_counter(su, name, "ms_in_rebuild_steps", w[r].med_rebuild);
    if (w[BASE].ok) tb_suite_counter(su, name, "ratio_to_base_other_steps", w[r].other.value);
  }
  tb_threads_set(threads);
  if (w[BASE].ok && w[FULL].ok && w[LOCAL].ok) cost_note(su, w, reps);
  flush(&c);
  tb_est none = {NAN, NAN, NAN, 0};
  c.failed |= tb_bao_accuracy(su, o, w[LOCAL].ok && w[BASE].ok ? w[LOCAL].to_base : none);
  pr res[2][NVAR];
  memset(res, 0, sizeof res);
  for (int sc = 0; sc < 2; sc++) {
    tb_progress("bao", NROWS + reps + sc, NROWS + 2 + reps);
    for (int v = 0; v < NVAR; v++) {
      press_release(&c, sc ? STRETCH : PRESS, v, o->seed, &res[sc][v]);
      if (!res[sc][v].ok)
        fprintf(stderr, "bao: %s, %s: %s\n", sc ? STRETCH : PRESS, variant[v].name, res[sc][v].why);
    }
  }
  tb_progress("bao", NROWS + 2 + reps, NROWS + 2 + reps);
  press_table(su, res, w[FULL].release, res[0][NVAR - 1].t_end);
  double wall = (double)(tb_time_ns() - t0) * 1e-9;
  tb_suite_counter(su, "suite", "wall_time_s", wall);
  tb_suite_note(su,
                "The runs of the last table go the scenes' whole 12 s (the load until 4 s). At "
                "rest: the largest node speed, averaged over the last 0.1 s, below the scene's "
                "rest_speed times the sphere's size. The pictures are rendered headless as "
                "`tissuebench render --scene sphere-press --set levels=2 --set refine_force=0.1 "
                "--times 4 --color displacement --wireframe` does (the model's current surface; "
                "a refined point's displacement from its own rest position). The suite took "
                "%.2f s in all (%d + %d timed runs of 500 steps, the pictures included).",
                wall, NROWS, NROWS * reps);
  flush(&c);
  tb_renderer_free(c.r);
  for (int r = 0; r < NROWS; r++) free(w[r].x_press), free(w[r].x_end);
  if (tb_suite_end(su, &err)) fprintf(stderr, "bao: %s\n", err.msg), c.failed = 1;
  return c.failed;
}
