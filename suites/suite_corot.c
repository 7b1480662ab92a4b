/* Table 3.5's "fem-corot solvers": fem-corot's solvers of the
 * implicit step (models/fem_solve.c: exact refactor, pcg, lagged, pd) on
 * the liver (liver-stretch) and the beam (beam, tip load raised to a large
 * deflection), each against the exact path and against linear fem's
 * steps/s measured in the same run: ms/step (median), the ratio, solver
 * iterations per step, factorisations, the error of the dynamic run
 * (largest node distance to the exact run over all steps / largest exact
 * displacement) and of the quasi-static solve (quasistatic=1 with the load
 * held: the equilibrium displacement's difference, relative). A variant
 * "meets 1e-6" when both errors are at most 1e-6; the speed goal is 0.2x
 * linear fem's steps/s on the liver for the fastest variant that does. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "suite_table35.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "models/tb_fem.h"
#include "scenes/tb_sim.h"

#define TOL 1e-6
#define GOAL 0.2
#define MAX_REPS 9

static const struct {
  const char *label, *set[2];
} variants[] = {
    {"exact (refactor every step)", {"solver=exact", NULL}},
    {"pcg (cg_tol 1e-7, rotated preconditioner)", {"solver=pcg", NULL}},
    {"pcg (cg_tol 1e-9)", {"solver=pcg", "cg_tol=1e-9"}},
    {"pcg (cg_tol 1e-7, not rotated)", {"solver=pcg", "cg_rotate=0"}},
    {"lagged (lag 10, refine 2)", {"solver=lagged", NULL}},
    {"pd (5 iterations)", {"solver=pd", NULL}},
    {"pd (20 iterations)", {"solver=pd", "pd_iters=20"}}, /* the last: --full only */
};
#define NVAR ((int)(sizeof variants / sizeof variants[0]))

static int nvar = NVAR; /* variants run: all but the last in quick mode */

typedef struct scene_run {
  const char *label, *scene;
  const tb_mesh *mesh;      /* NULL: the scene builds it */
  double node_mass;         /* > 0: every node this mass */
  double amplitude;         /* > 0: the scene's amplitude */
  long steps, static_steps; /* dynamic run; quasi-static steps (load held) */
} scene_run;

typedef struct outcome {
  int ok;
  double ms;    /* median CPU ms per step */
  double wall;  /* median wall ms per step */
  double mean;  /* mean CPU ms per step (refactorisations included) */
  tb_est ratio; /* linear fem's CPU time per step over this one's, paired by repetition */
  double cpu_reps[MAX_REPS], wall_reps[MAX_REPS]; /* each repetition's median ms per step */
  double iters;                                   /* solver iterations per step */
  int factors;
  double err_dyn, err_static;
  char why[200];
} outcome;

static tb_settings settings_of(const scene_run *sc, int var, int quasistatic) {
  tb_settings d;
  tb_settings_init(&d);
  if (sc->node_mass > 0) tb_settings_setd(&d, "node_mass", sc->node_mass, NULL);
  for (int k = 0; var >= 0 && k < 2 && variants[var].set[k]; k++)
    tb_settings_set(&d, variants[var].set[k], NULL);
  if (quasistatic) tb_settings_set(&d, "quasistatic=1", NULL);
  return d;
}

/* Runs model (var < 0: linear fem) on the scene for steps; per-step CPU
 * and wall ms into cpu and wall (may be NULL); positions after every step
 * into traj (nv per step) or,
 * with ref, the largest distance to ref's over all steps into *diff; the
 * last positions into last (may be NULL); solver statistics into st. */
static int run(const scene_run *sc, int var, int quasistatic, long steps, double *cpu, double *wall,
               tb_vec3 *traj, const tb_vec3 *ref, double *diff, tb_vec3 *last, tb_fem_stats *st,
               tb_error *err) {
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  if (sc->amplitude > 0) sd.amplitude = sc->amplitude;
  tb_settings set = settings_of(sc, var, quasistatic);
  tb_sim s;
  if (tb_sim_create(&s, sc->scene, &sd, var < 0 ? "fem" : "fem-corot", &set, sc->mesh, err))
    return -1;
  int nv = s.mesh.nv, rc = 0;
  if (diff) *diff = 0;
  for (long k = 0; k < steps && !rc; k++) {
    tb_clock c = tb_clock_start();
    rc = tb_sim_step(&s, err);
    tb_clock_ms(&c, wall ? wall + k : NULL, cpu ? cpu + k : NULL);
    const tb_vec3 *x = tb_model_positions(&s.model);
    if (traj) memcpy(traj + (size_t)k * nv, x, sizeof(tb_vec3) * (size_t)nv);
    if (ref && diff)
      for (int i = 0; i < nv; i++) *diff = fmax(*diff, tb_dist(x[i], ref[(size_t)k * nv + i]));
    tb_progress_tick("%s: step %ld/%ld", sc->label, k + 1, steps);
  }
  if (!rc && last) memcpy(last, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nv);
  if (!rc && st && var >= 0 && tb_fem_get_stats(&s.model, st, err)) rc = -1;
  tb_sim_destroy(&s);
  return rc;
}

/* Largest |x - X| over n states of nv positions. */
static double largest_disp(const tb_vec3 *x, long n, int nv, const tb_vec3 *rest) {
  double m = 0;
  for (long k = 0; k < n; k++)
    for (int i = 0; i < nv; i++) m = fmax(m, tb_dist(x[(size_t)k * nv + i], rest[i]));
  return m;
}

/* One scene: linear fem's median CPU ms per step into fem[0] and wall into
 * fem[1] (NAN and err on failure); out gets nvar outcomes (a variant that
 * fails says why). The repetitions go round fem and every variant in turn,
 * so that a slow spell of the machine falls on all of them alike; each
 * figure is the median over repetitions of a run's median (and mean) ms per
 * step, each ratio the median of the repetitions' ratios. */
static int one_scene(const scene_run *sc, int reps, outcome *out, double fem[2], tb_error *err) {
  tb_mesh mesh;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  if (sc->amplitude > 0) sd.amplitude = sc->amplitude;
  fem[0] = fem[1] = NAN;
  if (sc->mesh)
    mesh = *sc->mesh;
  else if (tb_sim_mesh(sc->scene, &sd, &mesh, err))
    return -1;
  int nv = mesh.nv;
  long n = sc->steps, ns = sc->static_steps;
  size_t nper = (size_t)reps * (size_t)(NVAR + 1);
  double *ms = malloc(sizeof(double) * 2 * (size_t)n), *per = malloc(sizeof(double) * nper),
         *mean = malloc(sizeof(double) * nper), *perw = malloc(sizeof(double) * nper);
  double *wall = ms ? ms + n : NULL;
  tb_vec3 *traj = malloc(sizeof(tb_vec3) * (size_t)nv * (size_t)n);
  tb_vec3 *sref = malloc(sizeof(tb_vec3) * (size_t)nv),
          *last = malloc(sizeof(tb_vec3) * (size_t)nv);
  double ref_disp = 1, ref_sdisp = 1;
  int rc = -1;
  if (!ms || !per || !mean || !perw || !traj || !sref || !last) {
    tb_error_set(err, "table 3.5", 0, "out of memory");
    goto done;
  }
  for (int v = 0; v < nvar; v++) memset(out + v, 0, sizeof *out), out[v].ok = 1;
  /* per[(v + 1) reps + r]: variant v's repetition r, v = -1 linear fem */
  for (int r = 0; r < reps; r++) {
    if (run(sc, -1, 0, n, ms, wall, NULL, NULL, NULL, NULL, NULL, err)) goto done;
    per[r] = tb_stats_of(ms, (int)n).median, perw[r] = tb_stats_of(wall, (int)n).median;
    for (int v = 0; v < nvar; v++) {
      outcome *o = out + v;
      if (!o->ok) continue;
      tb_fem_stats st;
      tb_error e;
      int ref = v == 0 && r == 0; /* exact's first run stores the reference */
      double diff = 0;
      const tb_vec3 *cmp = ref || !out[0].ok ? NULL : traj; /* no reference: no error */
      if (run(sc, v, 0, n, ms, wall, ref ? traj : NULL, cmp, &diff, NULL, &st, &e)) {
        o->ok = 0;
        snprintf(o->why, sizeof o->why, "%.190s", e.msg);
        continue;
      }
      size_t k = (size_t)(v + 1) * (size_t)reps + (size_t)r;
      tb_stats sm = tb_stats_of(ms, (int)n);
      per[k] = sm.median, mean[k] = sm.mean, perw[k] = tb_stats_of(wall, (int)n).median;
      if (r > 0) continue;
      o->iters = (double)st.iterations / (double)n;
      o->factors = st.factorizations;
      if (ref) ref_disp = largest_disp(traj, n, nv, mesh.x);
      o->err_dyn = cmp || ref ? diff / ref_disp : NAN;
    }
  }
  fem[0] = tb_stats_of(per, reps).median, fem[1] = tb_stats_of(perw, reps).median;
  for (int v = 0; v < nvar; v++) {
    outcome *o = out + v;
    tb_error e;
    if (!o->ok) continue;
    if (run(sc, v, 1, ns, NULL, NULL, NULL, NULL, NULL, v == 0 ? sref : last, NULL, &e)) {
      o->ok = 0;
      snprintf(o->why, sizeof o->why, "%.190s", e.msg);
      continue;
    }
    if (v == 0) {
      ref_sdisp = largest_disp(sref, 1, nv, mesh.x);
    } else if (!out[0].ok) {
      o->err_static = NAN;
    } else {
      double d = 0;
      for (int i = 0; i < nv; i++) d = fmax(d, tb_dist(last[i], sref[i]));
      o->err_static = d / ref_sdisp;
    }
    const size_t at = (size_t)(v + 1) * (size_t)reps;
    o->ms = tb_stats_of(per + at, reps).median;
    o->wall = tb_stats_of(perw + at, reps).median;
    o->mean = tb_stats_of(mean + at, reps).median;
    o->ratio = tb_ratio_est(per, per + at, reps);
    for (int r = 0; r < reps; r++) o->cpu_reps[r] = per[at + r], o->wall_reps[r] = perw[at + r];
  }
  rc = 0;
done:
  free(ms), free(per), free(mean), free(perw), free(traj), free(sref), free(last);
  if (!sc->mesh) tb_mesh_free(&mesh);
  return rc;
}

int tb_table35_corot(tb_suite *su, const tb_suite_opts *o, const tb_mesh *liver) {
  uint64_t t0 = tb_time_ns();
  int quick = !o->full, reps = o->scale < 1 ? 1 : (quick ? 7 : MAX_REPS);
  /* liver: the speed table's unit masses, the stretch of table 3.5 (the
   * quasi-static run holds the patch pulled out from t = 0.5 s to the end); beam: a
   * tip load of 1.5 (Euler-Bernoulli 2, a fifth of the length) */
  scene_run scenes[2] = {
      {"liver", "liver-stretch", liver, 1.0, 0, quick ? 60 : 200, quick ? 60 : 80},
      {"beam", "beam", NULL, 0, 1.5, quick ? 60 : 200, 40},
  };
  if (o->scale < 1) scenes[0].steps = scenes[1].steps = 20;
  nvar = quick ? NVAR - 1 : NVAR;
  static const char *cols[] = {"scene",
                               "solver",
                               "ms/step CPU (median)",
                               "ms/step CPU (mean)",
                               "ms/step wall (median)",
                               "steps/s (CPU)",
                               "/ fem steps/s",
                               "/ fem, 95% low",
                               "/ fem, 95% high",
                               "iterations per step",
                               "factorisations",
                               "error, dynamic",
                               "error, static",
                               "exact to 1e-6",
                               "0.2x fem goal"};
  tb_table *t = tb_table_new("corot_solvers", "fem-corot solvers (CPU time, one thread)", 15, cols);
  tb_table_csv_name(t, 6, "ratio to linear fem steps/s");
  int failed = 0;
  double fem_ms[2][2] = {{NAN, NAN}, {NAN, NAN}};
  tb_est best_ratio = {0, 0, 0, 0};
  const char *best = NULL;
  for (int c = 0; c < 2; c++) {
    tb_progress("table 3.5 fem-corot solvers", c, 2);
    outcome out[NVAR];
    tb_error err;
    if (one_scene(scenes + c, reps, out, fem_ms[c], &err)) {
      fprintf(stderr, "table 3.5: fem-corot solvers on %s: %s\n", scenes[c].label, err.msg);
      failed = 1;
      continue;
    }
    for (int v = 0; v < nvar; v++) {
      const outcome *u = out + v;
      tb_table_row(t);
      tb_table_cell(t, "%s", scenes[c].label);
      tb_table_cell(t, "%s", variants[v].label);
      if (!u->ok) {
        for (int k = 0; k < 11; k++) tb_table_cell(t, "-");
        tb_table_cell(t, "failed (%s)", u->why);
        tb_table_cell(t, "-");
        failed = 1;
        continue;
      }
      int exact = u->err_dyn <= TOL && u->err_static <= TOL;
      char verdict[160];
      tb_table_num(t, u->ms, "%.3f");
      tb_table_num(t, u->mean, "%.3f");
      tb_table_num(t, u->wall, "%.3f");
      tb_table_num(t, 1e3 / u->ms, "%.0f");
      tb_table_num(t, u->ratio.value, "%.3fx");
      tb_table_num(t, u->ratio.lo, "%.3f");
      tb_table_num(t, u->ratio.hi, "%.3f");
      tb_table_num(t, v == 0 ? NAN : u->iters, "%.2f");
      tb_table_num(t, u->factors, "%.0f");
      tb_table_num(t, u->err_dyn, "%.2g");
      tb_table_num(t, u->err_static, "%.2g");
      tb_table_cell(t, "%s", exact ? "yes" : "no");
      tb_table_cell(
          t, "%s",
          c == 0 && exact ? tb_verdict_text(u->ratio, GOAL, 1, verdict, sizeof verdict) : "-");
      if (c == 0 && exact && v > 0 && u->ratio.value > best_ratio.value)
        best_ratio = u->ratio, best = variants[v].label;
      char name[160];
      snprintf(name, sizeof name, "corot/%s/%s", scenes[c].label, variants[v].label);
      tb_suite_bench(su, name, u->wall_reps, u->cpu_reps, reps, "ms");
      tb_suite_counter_est(su, name, "ratio_to_fem", u->ratio);
      tb_suite_counter(su, name, "mean_ms", u->mean);
      tb_suite_counter(su, name, "iterations_per_step", u->iters);
      tb_suite_counter(su, name, "factorisations", u->factors);
      tb_suite_counter(su, name, "error_dynamic", u->err_dyn);
      tb_suite_counter(su, name, "error_static", u->err_static);
    }
  }
  tb_progress("table 3.5 fem-corot solvers", 2, 2);
  tb_suite_table(su, t);
  char goal[200];
  tb_suite_note(
      su,
      "fem-corot solvers (models/fem_solve.c): the same implicit step (warped stiffness, "
      "rotations from the step's start) solved by refactoring every step (exact, the "
      "reference), by CG warm-started by extrapolating the last solutions (order 1-6, the one that "
      "best predicted the last) and preconditioned with a "
      "stale CHOLMOD factor, rotated per node, refactored when CG needs more than cg_max (8) "
      "iterations, stopping at the relative residual cg_tol (pcg), by a factor redone every lag "
      "steps plus refinements "
      "(lagged), or by projective-dynamics local/global iterations with one constant factor "
      "(pd). Steps/s come from the median CPU ms/step; the mean includes the steps that "
      "refactor; both are medians over %d runs that take turns with linear fem's. The ratio to "
      "linear fem is the median of the runs' ratios (each run against the fem run before it), "
      "with its 95%% interval; the goal is met or not when the interval is on one side of it, "
      "else inconclusive (noise). Linear fem in the same run: %.3f ms/step CPU (%.3f wall) on the "
      "liver, %.3f (%.3f) on the beam; %d thread(s). Iterations: CG iterations, refinements or "
      "pd iterations per step. Error, "
      "dynamic: the largest node distance to the exact run over %ld steps / the exact run's "
      "largest displacement; static: quasistatic=1 for %ld (liver) and %ld (beam) steps with "
      "the load held, the last state's distance to the exact one / its largest displacement. "
      "Goal: the fastest variant exact to %g reaches %.1fx linear fem's steps/s "
      "on the liver: %s.",
      reps, fem_ms[0][0], fem_ms[0][1], fem_ms[1][0], fem_ms[1][1], tb_threads(), scenes[0].steps,
      scenes[0].static_steps, scenes[1].static_steps, TOL, GOAL,
      best ? tb_verdict_text(best_ratio, GOAL, 1, goal, sizeof goal)
           : "no variant but exact is exact");
  if (best)
    tb_suite_note(su,
                  "Fastest exact variant on the liver: %s, %.3fx linear fem's steps/s (95%% "
                  "interval %.3f-%.3f).",
                  best, best_ratio.value, best_ratio.lo, best_ratio.hi);
  tb_suite_note(su, "This table took %.1f s%s.", (double)(tb_time_ns() - t0) * 1e-9,
                quick ? " (quick: pd with 20 iterations only with --full)" : "");
  return failed;
}
