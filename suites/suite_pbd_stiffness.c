/* `figure pbd-stiffness`: the effective stiffness of pbd-stvk and xpbd-stvk
 * (models/pbd.c) against iterations and dt (suites/tb_pbd_stiffness.h).
 *
 * The measurement: the `beam` scene's cantilever (10 x 1 x 1, held at
 * x = 0) under gravity alone, run from rest with an ambient drag about
 * critical for its first bending mode, until the sag of its tip face (the
 * scene's [output] probe) stops changing; that sag over the static sag of
 * the same material on the same mesh by the reference solver
 * (reference/tb_reference.h: St. Venant-Kirchhoff, the models' energy, on
 * the linear tets themselves, so the only difference left is the solver).
 * A ratio above 1 is softer than the material, below 1 stiffer.
 *
 * What it shows (Macklin, Müller & Chentanez 2016, "XPBD", §1 and §4):
 * PBD's projection is invariant to the energy's scale, so E cancels and the
 * sag is set by k, the iterations and dt (each step predicts a fall of
 * about dt^2 g that the sweeps pull back: more sweeps or a smaller dt make
 * it stiffer); XPBD's compliance alpha / dt^2 makes its fixed point the
 * backward-Euler step of the material, whose steady state is the static
 * solution, so its sag tends to the reference as the iterations grow.
 *
 * Writes results/pbd-stiffness/: table.md, table-sag.csv (every run),
 * chart.csv (sag ratio per model and dt against iterations), the chart,
 * data.json (each run's sag, ratio, settle time and step time). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_pbd_stiffness.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "reference/tb_reference.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

/* ---- the measurement ---- */

void tb_sag_def_init(tb_sag_def *d) {
  memset(d, 0, sizeof *d);
  d->model = "pbd-stvk";
  d->cells = 10;
  d->gravity = 0.02; /* q L^4 / (8 E I) = 0.02 * 1e4 / (8 * 3000 / 12) = 0.1 */
  d->drag = 1.5;
  d->dt = 0.01;
  d->iterations = 0;
  d->k = NAN;
  d->E = 3000, d->nu = 0.3;
  d->rayleigh = 0;
  d->max_time = 60;
  d->window = 1.0;
  d->tol = 1e-4;
}

/* The scene overrides of d: the beam at d->cells, gravity only. */
static tb_sim_def scene_def(const tb_sag_def *d) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.nodes = d->cells;
  sd.amplitude = 0; /* no tip load */
  sd.gravity = d->gravity;
  sd.drag = d->drag;
  sd.dt = d->dt;
  sd.duration = d->max_time;
  sd.release = d->max_time;
  sd.inversion = 0;
  sd.seed = 1;
  return sd;
}

static int model_settings(const tb_sag_def *d, tb_settings *md, tb_error *err) {
  tb_settings_init(md);
  if (tb_settings_setd(md, "E", d->E, err) || tb_settings_setd(md, "nu", d->nu, err)) return -1;
  /* the projection's own stiffness: constraint damping (which also softens
   * an unconverged projection) off unless asked for */
  if (tb_settings_setd(md, "rayleigh_stiffness", d->rayleigh, err)) return -1;
  if (d->iterations > 0 && tb_settings_setd(md, "iterations", d->iterations, err)) return -1;
  if (!isnan(d->k) && tb_settings_setd(md, "k", d->k, err)) return -1;
  return tb_model_check_settings(d->model, md, err);
}

/* Minus the mean z displacement of the probe nodes. */
static double tip_sag(const tb_sim *s, const tb_vec3 *x) {
  double sum = 0;
  for (int k = 0; k < s->nprobe; k++) sum += x[s->probe[k]].z - s->mesh.x[s->probe[k]].z;
  return s->nprobe > 0 ? -sum / s->nprobe : NAN;
}

int tb_sag_run(const tb_sag_def *d, const tb_mesh *mesh, tb_sag_result *r, tb_error *err) {
  memset(r, 0, sizeof *r);
  r->sag = r->spread = r->settle_time = r->ms_step = r->ms_step_wall = NAN;
  if (!(d->dt > 0) || !(d->window > 0) || !(d->tol > 0) || !(d->max_time >= d->window))
    return tb_error_set(err, "pbd-stiffness", 0, "needs dt, window, tol > 0, max_time >= window");
  tb_settings md;
  if (model_settings(d, &md, err)) return -1;
  tb_sim_def sd = scene_def(d);
  tb_sim s;
  if (tb_sim_create(&s, "beam", &sd, d->model, &md, mesh, err)) return -1;
  if (s.nprobe < 1) {
    tb_sim_destroy(&s);
    return tb_error_set(err, "pbd-stiffness", 0, "the beam scene has no [output] probe (tip face)");
  }
  long nmax = lround(d->max_time / d->dt), w = lround(d->window / d->dt);
  if (w < 2) w = 2;
  double *ring = malloc(sizeof(double) * (size_t)(w + 1)); /* the last w + 1 two-step means */
  /* each step's CPU ms, then each step's wall ms */
  double *ms = malloc(sizeof(double) * 2 * (size_t)(nmax > 0 ? nmax : 1));
  double *wall = ms ? ms + (nmax > 0 ? nmax : 1) : NULL;
  if (!ring || !ms) {
    free(ring), free(ms);
    tb_sim_destroy(&s);
    return tb_error_set(err, "pbd-stiffness", 0, "out of memory");
  }
  r->stable = 1;
  double last = tip_sag(&s, tb_model_positions(&s.model)), lo = NAN, hi = NAN, mean = NAN;
  long n = 0;
  for (; n < nmax; n++) {
    tb_error why;
    tb_clock c = tb_clock_start();
    int bad = tb_sim_step(&s, &why);
    tb_clock_ms(&c, &wall[n], &ms[n]);
    if (bad) {
      r->stable = 0;
      const char *p = strstr(why.msg, "unstable ");
      snprintf(r->state, sizeof r->state, "unstable (%.170s)", p ? p + 9 : why.msg);
      n++;
      break;
    }
    tb_progress_tick("%s: t = %.2f s", d->model, s.t);
    double now = tip_sag(&s, tb_model_positions(&s.model));
    ring[n % (w + 1)] = 0.5 * (now + last);
    last = now;
    if (n < w) continue;
    lo = INFINITY, hi = -INFINITY, mean = 0;
    for (long k = 0; k <= w; k++) lo = fmin(lo, ring[k]), hi = fmax(hi, ring[k]), mean += ring[k];
    mean /= (double)(w + 1);
    if (hi - lo <= d->tol * fabs(mean)) {
      r->settled = 1;
      r->settle_time = s.t - (double)w * d->dt;
      n++;
      break;
    }
  }
  /* the last window: settled, its latest value; else its mean and spread */
  r->spread = (hi - lo) / fabs(mean);
  r->sag = r->settled ? ring[(n - 1) % (w + 1)] : mean;
  r->steps = s.steps;
  r->ms_step = tb_stats_of(ms, (int)n).median;
  r->ms_step_wall = tb_stats_of(wall, (int)n).median;
  if (r->stable && r->settled)
    snprintf(r->state, sizeof r->state, "settled");
  else if (r->stable)
    snprintf(r->state, sizeof r->state,
             "not settled (the sag varies by %.2g of it over the last "
             "%g s of %g s)",
             r->spread, d->window, d->max_time);
  if (!r->stable) r->sag = r->spread = NAN;
  free(ring), free(ms);
  tb_sim_destroy(&s);
  return 0;
}

double tb_sag_reference(const tb_sag_def *d, int quadratic, tb_error *err) {
  tb_settings md;
  double density = 0;
  if (model_settings(d, &md, err) || tb_model_setting(d->model, &md, "density", &density))
    return NAN;
  tb_sim_def sd = scene_def(d);
  tb_sim s;
  if (tb_sim_create(&s, "beam", &sd, d->model, &md, NULL, err)) return NAN;
  double out = NAN;
  if (!tb_sim_loads(&s, d->dt, err)) {
    tb_ref_problem p;
    memset(&p, 0, sizeof p);
    p.mesh = &s.mesh, p.density = density, p.gravity = s.gravity, p.force = s.force;
    p.nfixed = s.nfixed, p.fixed = s.fixed, p.fixed_x = s.fixed_x;
    tb_ref_def rd = tb_ref_default_def();
    rd.E = d->E, rd.nu = d->nu;
    rd.quadratic = quadratic;
    rd.material = quadratic ? TB_REF_NEOHOOKE : TB_REF_STVK;
    tb_ref_solution *sol = tb_ref_solve(&p, &rd, err);
    if (sol) {
      out = tip_sag(&s, tb_ref_positions(sol));
      tb_ref_free(sol);
    }
  }
  tb_sim_destroy(&s);
  return out;
}

/* ---- the suite ---- */

static const char *const models[] = {"pbd-stvk", "xpbd-stvk"};
#define NMODELS 2

typedef struct plan {
  int cells;
  int ndt, nit, nk;
  double dt[6];
  int it[10];
  double k[6]; /* pbd-stvk's k sweep at dt k_dt and k_it iterations */
  double k_dt;
  int k_it;
  double max_time;
} plan;

static plan make_plan(const tb_suite_opts *o) {
  static const double dt_quick[] = {0.04, 0.02, 0.01, 0.005},
                      dt_full[] = {0.04, 0.02, 0.01, 0.005, 0.0025};
  static const int it_quick[] = {1, 2, 5, 10, 20, 50, 100},
                   it_full[] = {1, 2, 3, 5, 10, 20, 50, 100};
  static const double k_all[] = {0.1, 0.2, 0.4, 0.7, 1.0};
  plan p;
  memset(&p, 0, sizeof p);
  p.cells = 10, p.max_time = 60, p.k_dt = 0.01, p.k_it = 10;
  p.nk = 5;
  memcpy(p.k, k_all, sizeof k_all);
  if (o->scale < 1) { /* smoke */
    p.cells = 4, p.max_time = 30, p.ndt = 2, p.nit = 3, p.nk = 2;
    p.dt[0] = 0.02, p.dt[1] = 0.01;
    p.it[0] = 1, p.it[1] = 5, p.it[2] = 20;
    p.k[0] = 0.2, p.k[1] = 1.0;
  } else if (o->full) {
    p.ndt = 5, p.nit = 8;
    memcpy(p.dt, dt_full, sizeof dt_full);
    memcpy(p.it, it_full, sizeof it_full);
  } else {
    p.ndt = 4, p.nit = 7;
    memcpy(p.dt, dt_quick, sizeof dt_quick);
    memcpy(p.it, it_quick, sizeof it_quick);
  }
  return p;
}

typedef struct row {
  const char *model;
  double dt, k, b; /* b: constraint damping */
  int it;
  tb_sag_result r;
} row;

static void num_or_dash(tb_table *t, double v, const char *fmt) {
  if (isfinite(v))
    tb_table_num(t, v, fmt);
  else
    tb_table_cell(t, "-");
}

/* One run into *out, its data.json entry; -1 on a setup error. A run is a
 * case of `reproduce --shard` (its outcome: the result's numbers and state;
 * a run another shard makes is left NaN here). */
static int measure(tb_suite *su, const tb_sag_def *base, const tb_mesh *mesh, const char *model,
                   double dt, int it, double k, double ref, row *out, tb_error *err) {
  tb_sag_def d = *base;
  d.model = model, d.dt = dt, d.iterations = it;
  d.k = tb_model_has_setting(model, "k") ? k : NAN; /* PBD's share k; XPBD has none */
  out->model = model, out->dt = dt, out->it = it, out->k = d.k, out->b = d.rayleigh;
  char bname[128], tail[40] = "";
  if (d.rayleigh > 0) snprintf(tail, sizeof tail, "/rayleigh_stiffness:%g", d.rayleigh);
  if (isnan(d.k))
    snprintf(bname, sizeof bname, "%s/dt:%g/iterations:%d%s", model, dt, it, tail);
  else
    snprintf(bname, sizeof bname, "%s/dt:%g/iterations:%d/k:%g%s", model, dt, it, d.k, tail);
  tb_case c;
  tb_sag_result *r = &out->r;
  int mode = tb_suite_case(su, bname, 0, &c);
  if (mode == TB_CASE_SKIP) {
    memset(r, 0, sizeof *r);
    r->sag = r->spread = r->settle_time = r->ms_step = r->ms_step_wall = NAN;
    return 0;
  }
  if (mode == TB_CASE_RUN) {
    if (tb_sag_run(&d, mesh, r, err)) return -1;
    double v[] = {r->stable,      r->settled, r->sag,     r->spread,
                  r->settle_time, r->steps,   r->ms_step, r->ms_step_wall};
    memcpy(c.v, v, sizeof v);
    c.nv = 8, c.nt = 1;
    snprintf(c.t[0], sizeof c.t[0], "%s", r->state);
    tb_suite_case_done(su, &c);
  } else {
    r->stable = (int)c.v[0], r->settled = (int)c.v[1], r->sag = c.v[2], r->spread = c.v[3];
    r->settle_time = c.v[4], r->steps = (long)c.v[5], r->ms_step = c.v[6];
    r->ms_step_wall = c.nv > 7 ? c.v[7] : NAN;
    snprintf(r->state, sizeof r->state, "%.191s", c.t[0]);
  }
  tb_suite_bench(su, bname, &out->r.ms_step_wall, &out->r.ms_step, 1, "ms");
  tb_suite_counter(su, bname, "tip_sag", out->r.sag);
  tb_suite_counter(su, bname, "sag_ratio", out->r.sag / ref);
  tb_suite_counter(su, bname, "stable", out->r.stable);
  tb_suite_counter(su, bname, "settled", out->r.settled);
  tb_suite_counter(su, bname, "settle_time_s", out->r.settle_time);
  tb_suite_counter(su, bname, "spread_pct", 100 * out->r.spread);
  tb_suite_counter(su, bname, "steps", (double)out->r.steps);
  return 0;
}

/* PBD's sag in units of its law sag = c g dt^2 / (N k): c. */
static double pbd_law(const row *w, double g) {
  return w->r.sag * w->it * w->k / (g * w->dt * w->dt);
}

static tb_table *rows_table(const char *name, const char *title, const row *rows, int n, double ref,
                            double g) {
  static const char *cols[] = {"model",
                               "dt (s)",
                               "iterations",
                               "k",
                               "tip sag",
                               "sag / reference",
                               "state",
                               "settle time (s)",
                               "spread (%)",
                               "steps",
                               "ms/step CPU (median)",
                               "ms/step wall (median)",
                               "sag N k / (g dt^2)"};
  tb_table *t = tb_table_new(name, title, 13, cols);
  for (int q = 0; q < n; q++) {
    const row *w = &rows[q];
    tb_table_row(t);
    tb_table_cell(t, "%s", w->model);
    tb_table_num(t, w->dt, "%g");
    tb_table_num(t, w->it, "%.0f");
    num_or_dash(t, w->k, "%g");
    num_or_dash(t, w->r.sag, "%.5g");
    num_or_dash(t, w->r.sag / ref, "%.4g");
    tb_table_cell(t, "%s", w->r.state);
    num_or_dash(t, w->r.settle_time, "%.2f");
    num_or_dash(t, 100 * w->r.spread, "%.2g");
    tb_table_num(t, (double)w->r.steps, "%.0f");
    num_or_dash(t, w->r.ms_step, "%.4f");
    num_or_dash(t, w->r.ms_step_wall, "%.4f");
    num_or_dash(t, isnan(w->k) ? NAN : pbd_law(w, g), "%.4g");
  }
  return t;
}

/* The T4 and T10 static sags: a case every shard runs (each compares with them). */
static int references(tb_suite *su, const tb_sag_def *base, double *ref, double *ref10,
                      tb_error *err) {
  tb_case c;
  int mode = tb_suite_case(su, "reference", 1, &c);
  if (mode == TB_CASE_RUN) {
    c.v[0] = tb_sag_reference(base, 0, err);
    c.v[1] = isfinite(c.v[0]) ? tb_sag_reference(base, 1, err) : NAN;
    c.nv = 2;
    tb_suite_case_done(su, &c);
  }
  *ref = c.v[0], *ref10 = c.v[1];
  if (mode == TB_CASE_SKIP) tb_error_set(err, "pbd-stiffness", 0, "no reference case");
  return isfinite(*ref) && isfinite(*ref10) ? 0 : -1;
}

int tb_suite_pbd_stiffness(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/pbd-stiffness", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "pbd-stiffness",
                                "Effective stiffness of PBD and XPBD against iterations and dt",
                                o->seed, &err);
  if (!su) return fprintf(stderr, "pbd-stiffness: %s\n", err.msg), 1;
  plan p = make_plan(o);
  tb_sag_def base;
  tb_sag_def_init(&base);
  base.cells = p.cells, base.max_time = p.max_time;
  /* the runs are small (a few hundred tets): one thread, so that a busy
   * machine's barriers do not stall them; the answers do not depend on it */
  int threads = tb_threads_setting();
  tb_threads_set(1);
  /* then pbd-stvk's k sweep, then both models with the default constraint damping */
  static const int damp_it[] = {5, 20};
  double b_def = 0;
  tb_model_setting("pbd-stvk", NULL, "rayleigh_stiffness", &b_def);
  int failed = 0, nrows = NMODELS * p.ndt * p.nit, ndamp = 2 * NMODELS, done = 0;
  int total = nrows + p.nk + ndamp + 1;
  row *rows = calloc((size_t)(nrows + p.nk + ndamp), sizeof *rows);
  tb_mesh mesh;
  memset(&mesh, 0, sizeof mesh);
  tb_sim_def sd = scene_def(&base);
  double ref = NAN, ref10 = NAN;
  tb_progress("pbd-stiffness", done++, total);
  if (!rows) tb_error_set(&err, "pbd-stiffness", 0, "out of memory");
  if (!rows || tb_sim_mesh("beam", &sd, &mesh, &err) || references(su, &base, &ref, &ref10, &err)) {
    fprintf(stderr, "pbd-stiffness: %s\n", err.msg);
    failed = 1;
  }
  int n = 0;
  for (int m = 0; m < NMODELS && !failed; m++)
    for (int a = 0; a < p.ndt && !failed; a++)
      for (int b = 0; b < p.nit && !failed; b++) {
        tb_progress("pbd-stiffness", done++, total);
        if (measure(su, &base, &mesh, models[m], p.dt[a], p.it[b], NAN, ref, &rows[n++], &err))
          fprintf(stderr, "pbd-stiffness: %s\n", err.msg), failed = 1;
      }
  for (int c = 0; c < p.nk && !failed; c++) {
    tb_progress("pbd-stiffness", done++, total);
    if (measure(su, &base, &mesh, "pbd-stvk", p.k_dt, p.k_it, p.k[c], ref, &rows[n++], &err))
      fprintf(stderr, "pbd-stiffness: %s\n", err.msg), failed = 1;
  }
  tb_sag_def damped = base;
  damped.rayleigh = b_def;
  for (int m = 0; m < NMODELS && !failed; m++)
    for (int b = 0; b < 2 && !failed; b++) {
      tb_progress("pbd-stiffness", done++, total);
      if (measure(su, &damped, &mesh, models[m], 0.01, damp_it[b], NAN, ref, &rows[n++], &err))
        fprintf(stderr, "pbd-stiffness: %s\n", err.msg), failed = 1;
    }
  tb_progress("pbd-stiffness", total, total);
  tb_threads_set(threads);
  if (failed) {
    tb_suite_note(su, "The suite failed: %s", err.msg);
    free(rows);
    tb_mesh_free(&mesh);
    tb_suite_end(su, &err);
    return 1;
  }
  double k_def = NAN, it_v = 0; /* pbd-stvk's defaults */
  tb_model_setting("pbd-stvk", NULL, "k", &k_def);
  tb_model_setting("pbd-stvk", NULL, "iterations", &it_v);
  int it_def = (int)it_v;
  for (int q = 0; q < n; q++)
    if (isnan(rows[q].k)) rows[q].k = tb_model_has_setting(rows[q].model, "k") ? k_def : NAN;
  tb_suite_note(
      su,
      "The `beam` scene's cantilever (10 x 1 x 1, held at x = 0; %d cells along x: %d nodes, %d "
      "tets) under gravity %g along -z and no tip load, run from rest with ambient drag %g per s "
      "(about critical for the first bending mode) until the sag of its tip face (the mean z "
      "displacement of its %s nodes, averaged over two steps) varies by at most %g of itself over "
      "%g s, or %g s have passed. Material E %g, nu %g, density 1 (lumped node masses), the "
      "models' other settings at their defaults (pbd-stvk k %g and BDF2, xpbd-stvk Euler, "
      "StVK energy, no rigid-motion damping) but constraint damping (rayleigh_stiffness) off, "
      "so that the projection's own stiffness is measured (its default is in the last table). The "
      "reference: the static sag of the same material on the same mesh by the reference solver, "
      "St. Venant-Kirchhoff on the linear tets themselves, %.6g (the discrete problem both "
      "models solve; its equilibrium is the steady state of backward Euler). The continuum "
      "(compressible Neo-Hookean on quadratic tets of the same mesh) sags %.6g: the linear tets "
      "lock in bending, %.2f times too stiff, for every model on this mesh alike.",
      p.cells, mesh.nv, mesh.ntet, base.gravity, base.drag, "end face's", base.tol, base.window,
      base.max_time, base.E, base.nu, k_def, ref, ref10, ref10 / ref);
  tb_table *tr;
  {
    static const char *cols[] = {"solution", "tip sag", "sag / T4 reference"};
    tr = tb_table_new("reference", "The static sag of the material on the beam", 3, cols);
    tb_table_row(tr);
    tb_table_cell(tr, "reference, T4 (linear tets), St. Venant-Kirchhoff");
    tb_table_num(tr, ref, "%.6g");
    tb_table_num(tr, 1.0, "%.4g");
    tb_table_row(tr);
    tb_table_cell(tr, "reference, T10 (quadratic tets), Neo-Hookean");
    tb_table_num(tr, ref10, "%.6g");
    tb_table_num(tr, ref10 / ref, "%.4g");
    tb_table_row(tr);
    tb_table_cell(tr, "Euler-Bernoulli, q L^4 / (8 E I)");
    double eb = base.gravity * 1e4 / (8 * base.E / 12);
    tb_table_num(tr, eb, "%.6g");
    tb_table_num(tr, eb / ref, "%.4g");
    tb_suite_table(su, tr);
  }
  tb_suite_table(
      su, rows_table("sag", "Tip sag after settling: both models, every dt and iteration count",
                     rows, nrows, ref, base.gravity));
  char title[160];
  snprintf(title, sizeof title, "pbd-stvk: the k sweep at dt %g s, %d iterations", p.k_dt, p.k_it);
  tb_suite_table(su, rows_table("k", title, rows + nrows, p.nk, ref, base.gravity));
  /* constraint damping: each damped row beside the undamped run of the grid */
  double pbd_soft = NAN, xpbd_shift = NAN;
  {
    static const char *cols[] = {"model",   "iterations",      "rayleigh_stiffness",
                                 "tip sag", "sag / reference", "sag / sag undamped",
                                 "state"};
    char dtitle[160];
    snprintf(dtitle, sizeof dtitle,
             "Constraint damping at its default b %g (dt 0.01 s): the sag beside b = 0", b_def);
    tb_table *td = tb_table_new("damping", dtitle, 7, cols);
    for (int q = nrows + p.nk; q < n; q++) {
      const row *w = &rows[q];
      double undamped = NAN;
      for (int u = 0; u < nrows; u++)
        if (rows[u].model == w->model && rows[u].dt == w->dt && rows[u].it == w->it)
          undamped = rows[u].r.sag;
      double f = w->r.sag / undamped;
      if (w->it == it_def) *(tb_model_has_setting(w->model, "k") ? &pbd_soft : &xpbd_shift) = f;
      tb_table_row(td);
      tb_table_cell(td, "%s", w->model);
      tb_table_num(td, w->it, "%.0f");
      tb_table_num(td, w->b, "%g");
      num_or_dash(td, w->r.sag, "%.5g");
      num_or_dash(td, w->r.sag / ref, "%.4g");
      num_or_dash(td, f, "%.4g");
      tb_table_cell(td, "%s", w->r.state);
    }
    tb_suite_table(su, td);
  }
  /* chart.csv: iterations, then sag / reference per model and dt, then the reference */
  size_t cap = 4096 + (size_t)p.nit * (size_t)(NMODELS * p.ndt + 2) * 24, len = 0;
  char *body = malloc(cap), header[1024];
  int hl = snprintf(header, sizeof header, "iterations");
  for (int m = 0; m < NMODELS; m++)
    for (int a = 0; a < p.ndt; a++)
      hl += snprintf(header + hl, sizeof header - (size_t)hl, ",%s dt %g s", models[m], p.dt[a]);
  snprintf(header + hl, sizeof header - (size_t)hl, ",reference (static)");
  if (!body) failed = 1;
  for (int b = 0; b < p.nit && body; b++) {
    len += (size_t)snprintf(body + len, cap - len, "%d", p.it[b]);
    for (int m = 0; m < NMODELS; m++)
      for (int a = 0; a < p.ndt; a++) {
        const row *w = &rows[(m * p.ndt + a) * p.nit + b];
        double v = w->r.sag / ref;
        len += (size_t)snprintf(body + len, cap - len, isfinite(v) ? ",%.6g" : ",NaN", v);
      }
    len += (size_t)snprintf(body + len, cap - len, ",1\n");
  }
  if (!failed &&
      (tb_suite_write_data(su, "chart.csv", header, body, &err) ||
       tb_suite_chart_vars(su, "chart_lines.gp", "chart.csv", "stiffness",
                           "title='Cantilever under gravity: tip sag over the static sag of the "
                           "material, against iterations'; xlabel='Gauss-Seidel iterations per "
                           "step'; ylabel='tip sag / static reference sag (1: the material)'; "
                           "logx=1; logy=1",
                           &err))) {
    fprintf(stderr, "pbd-stiffness: %s\n", err.msg);
    failed = 1;
  }
  free(body);
  if (!failed)
    tb_suite_caption(su, "stiffness",
                     "The beam's static tip sag under gravity over the material's static sag "
                     "(T4 StVK reference) against iterations per step, for pbd-stvk (k %g) and "
                     "xpbd-stvk at several dt: PBD's stiffness grows with the iterations and "
                     "as dt shrinks; XPBD's sag tends to the reference",
                     k_def);
  /* the note: what the numbers say */
  double cmin = INFINITY, cmax = -INFINITY;
  int nlaw = 0, unsettled = 0, unstable = 0;
  for (int q = 0; q < n; q++) {
    const row *w = &rows[q];
    unsettled += w->r.stable && !w->r.settled, unstable += !w->r.stable;
    if (isnan(w->k) || w->b > 0 || !w->r.settled || !(w->r.sag / ref < 0.5)) continue;
    double c = pbd_law(w, base.gravity);
    cmin = fmin(cmin, c), cmax = fmax(cmax, c), nlaw++;
  }
  /* PBD at its defaults (the patent's iterations) and dt 0.01, when on the grid */
  char at_def[160] = "";
  for (int q = 0; q < p.ndt * p.nit; q++)
    if (rows[q].it == it_def && rows[q].dt == 0.01 && rows[q].r.settled)
      snprintf(at_def, sizeof at_def,
               " (at its default %d iterations and dt 0.01 it is %.3g times as "
               "stiff as the material)",
               it_def, ref / rows[q].r.sag);
  char xp[600];
  int xl = snprintf(xp, sizeof xp, "at %d iterations", p.it[p.nit - 1]);
  for (int a = 0; a < p.ndt; a++) {
    const row *w = &rows[(1 * p.ndt + a) * p.nit + p.nit - 1];
    const row *w1 = &rows[(1 * p.ndt + a) * p.nit];
    xl += snprintf(xp + xl, sizeof xp - (size_t)xl, "%s dt %g: %.4g (1 iteration: %.3g)",
                   a ? "," : "", p.dt[a], w->r.sag / ref, w1->r.sag / ref);
  }
  tb_suite_note(
      su,
      "Reading the chart: pbd-stvk's sag falls as 1 / iterations and as dt^2 (a line of slope "
      "-1 per dt, a factor 4 between dt and dt / 2); over its settled runs with a sag below half "
      "the reference (small deformation), sag = c g dt^2 / (iterations k) with c between %.4g and "
      "%.4g (%d runs; the table's last column): its stiffness is iterations x k / dt^2 and E, "
      "which its projection cannot see, plays no part%s. xpbd-stvk's sag over the reference, %s: "
      "it tends "
      "to the material as the iterations grow, faster at smaller dt (a stiff constraint, "
      "k dt^2 / m large, needs more Gauss-Seidel sweeps). Its limit stays a little above 1 and "
      "the excess shrinks with dt: each tet is one constraint C = sqrt(2 V psi), whose gradient "
      "turns during a step's sweeps while lambda starts from 0 every step, so the sweeps' fixed "
      "point is backward Euler only to first order in the motion within a step (Macklin et al. "
      "2016, eq. 11 neglects that change). Constraint damping at its default b %g (the last "
      "table) makes pbd-stvk at %d iterations sag %.4g times as much: its damping acts on the "
      "velocities after the step (each tet's strain rate), which are 0 at rest; xpbd-stvk's "
      "(Macklin et al. 2016, eq. 26, in the projection) moves its sag by a factor %.4g, as far "
      "as its sweeps are from their fixed point. %d run(s) did not settle: their sag is the mean "
      "of "
      "the last %g s and the spread column says how much it still varied (a node jittering from "
      "step to step at few iterations); %d run(s) were unstable and are left out of the chart. "
      "The runs use one thread (their answers do not depend on it); ms/step is the median "
      "step of a run in CPU time (other processes on the machine do not enter it), wall time "
      "beside it.",
      cmin, cmax, nlaw, at_def, xp, b_def, it_def, pbd_soft, xpbd_shift, unsettled, base.window,
      unstable);
  free(rows);
  tb_mesh_free(&mesh);
  if (tb_suite_end(su, &err)) fprintf(stderr, "pbd-stiffness: %s\n", err.msg), failed = 1;
  return failed;
}
