/* `figure pareto`: error against the reference (static Neo-Hookean FEM on
 * quadratic tets, reference/tb_reference.h) against speed, for every model
 * x at least 3 mesh resolutions x its key parameters, on the beam, the
 * held liver-stretch and the liver-hang under gravity (or --scene NAME).
 * One point: the model run on the
 * scene until it settles (measure/fidelity.c); its rms surface error over the
 * reference's largest displacement (y, log) against steps per second (x,
 * log), the Pareto front marked. Writes results/pareto/<scene>/: table.md,
 * points.csv (what `advise` reads), chart.csv and pareto.png/svg.
 * Material parity: E = 3000, nu = 0.3 for fem, fem-corot and msm
 * calibrated=1 (Van Gelder); msm with the thesis's ks, sm with the thesis's
 * alpha, beta (not physical: see the calibration suite); msm also with a
 * light damper kd 0.05 (the thesis's kd 5, meant for unit masses, makes the
 * body creep for minutes at density 1); pbd-stvk (its k and iterations: E
 * does not enter its motion, see `figure pbd-stiffness`) and xpbd-stvk (its
 * iterations), both with nu 0.3. Equal node masses of density 1 for all
 * (liver-hang, loaded by gravity: the masses of the density, so that each
 * node carries its share of the weight as in the reference); the scene's
 * dt 0.01; a model that blows up at it is rerun with 4, 16, then 64
 * substeps, and its cost per 0.01 s step counts them all. msm-vvs (a
 * surface model, Bao 2006) is not among the variants: a note says why. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_threads.h"
#include "measure/tb_fidelity.h"
#include "measure/tb_points.h"
#include "report/tb_results.h"

typedef struct variant {
  const char *model;
  const char *params; /* the model's settings, space separated ("" for the defaults) */
  int level;          /* least level that runs it: 0 smoke, 1 quick, 2 full */
  int peer;           /* 1: a Bullet peer: below --full, the coarsest mesh only */
} variant;

static const variant variants[] = {
    {"msm", "ks=180 kd=5", 0, 0},
    {"msm", "ks=180 kd=0.05", 1, 0},
    {"msm", "calibrated=1 kd=0.05", 0, 0},
    {"msm", "calibrated=1 kd=5", 2, 0},
    {"fem", "lumped", 0, 0},
    {"fem", "consistent_mass=1", 2, 0},
    {"fem", "quasistatic=1", 1, 0},
    {"fem-corot", "quasistatic=1", 0, 0},
    {"fem-corot", "lumped", 2, 0},
    {"sm", "sm_mode=quadratic clusters=50", 0, 0},
    {"sm", "sm_mode=linear clusters=50", 1, 0},
    {"sm", "sm_mode=quadratic clusters=8", 1, 0},
    {"sm", "sm_mode=quadratic cluster_mode=tets", 2, 0},
    {"pbd-stvk", "nu=0.3", 0, 0},
    {"pbd-stvk", "nu=0.3 iterations=20", 1, 0},
    {"pbd-stvk", "nu=0.3 k=1", 1, 0},
    {"pbd-stvk", "nu=0.3 k=1 iterations=20", 2, 0},
    {"xpbd-stvk", "nu=0.3", 0, 0},
    {"xpbd-stvk", "nu=0.3 iterations=20", 1, 0},
    {"xpbd-stvk", "nu=0.3 iterations=1", 2, 0},
    {"xpbd-stvk", "nu=0.3 energy=neohookean iterations=20", 2, 0},
    /* Bullet 3.24's peers, E 3000, nu 0.3 as fem. Quick mode: neohookean and
     * btSoftBody on the coarsest mesh (about 10 s more on a loaded 2-core machine); linear
     * (which lands on fem-corot's error) and corotated only with --full: corotated blows up
     * at dt 0.01, and its reruns with up to 64 substeps would dominate quick mode */
    {"bullet-fem", "force=neohookean", 1, 1},
    {"bullet-fem", "force=linear", 2, 1},
    {"bullet-fem", "force=corotated", 2, 1},
    {"bullet-softbody", "iterations=5", 1, 1},
    {"bullet-softbody", "iterations=20", 2, 1},
};
#define NVARIANTS ((int)(sizeof variants / sizeof variants[0]))

/* Settings from the variant's params ("lumped" is fem's default, no key). */
static int variant_def(const variant *v, tb_settings *d, tb_error *err) {
  tb_settings_init(d);
  char buf[160];
  snprintf(buf, sizeof buf, "%s", v->params);
  for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
    if (strchr(tok, '=') && tb_settings_set(d, tok, err)) return -1;
  return tb_model_check_settings(v->model, d, err);
}

/* The points of one scene: every variant at every resolution. */
typedef struct scene_run {
  tb_point *pts;
  double *wall; /* each point's median wall ms per step (pts hold CPU's) */
  int n, cap;
} scene_run;

static tb_point *add_point(scene_run *r) {
  if (r->n == r->cap) {
    int cap = r->cap ? 2 * r->cap : 64;
    tb_point *p = realloc(r->pts, sizeof *p * (size_t)cap);
    if (!p) return NULL;
    r->pts = p;
    double *w = realloc(r->wall, sizeof *w * (size_t)cap);
    if (!w) return NULL;
    r->wall = w, r->cap = cap;
  }
  memset(&r->pts[r->n], 0, sizeof r->pts[0]);
  r->wall[r->n] = NAN;
  return &r->pts[r->n++];
}

/* A case (one variant at one resolution, `reproduce --shard` runs them
 * apart) keeps v[0] points, POINT_VALUES numbers each from v[1], and each
 * point's state as a text. */
#define POINT_VALUES 10
#define MAX_POINTS 4

/* Runs variant v on mesh fm: blown up at the scene's dt, again with 4, 16,
 * then 64 substeps; every run is one point of the case c. */
static int run_variant(const tb_fid_ref *ref, const tb_fid_mesh *fm, const tb_fid_plan *plan,
                       const tb_sim_def *sd, const tb_fid_opts *fo, const variant *v, tb_case *c,
                       tb_error *err) {
  tb_settings md;
  if (variant_def(v, &md, err) || tb_fid_masses(plan, &fm->mesh, v->model, &md, err)) return -1;
  int np = 0;
  for (int sub = 1; sub <= 64 && np < MAX_POINTS; sub *= 4) {
    tb_fid_opts so = *fo;
    so.substeps = sub;
    tb_fid_result fr;
    if (tb_fid_run(ref, fm, v->model, &md, sd, &so, &fr, err)) return -1;
    double *o = c->v + 1 + POINT_VALUES * np;
    double vals[POINT_VALUES] = {sub,
                                 fm->mesh.nv,
                                 fr.ms_step,
                                 fr.rms_err,
                                 fr.max_err,
                                 fr.volume_change,
                                 fr.reaction_err,
                                 fr.settle_time,
                                 fr.recovery_err,
                                 fr.ms_step_wall};
    memcpy(o, vals, sizeof vals);
    snprintf(c->t[np], sizeof c->t[np], "%s", fr.state);
    np++;
    if (fr.stable) break;
  }
  c->v[0] = np, c->nv = 1 + POINT_VALUES * np, c->nt = np;
  return 0;
}

/* A point of the table from a case's numbers o and state; *wall_ms gets
 * its median wall ms per step of the scene's dt (the point holds CPU's). */
static void case_point(tb_point *p, double *wall_ms, const variant *v, int res, double dt,
                       const double *o, const char *state) {
  int substeps = (int)o[0];
  snprintf(p->model, sizeof p->model, "%s", v->model);
  p->resolution = res, p->nodes = (int)o[1];
  snprintf(p->params, sizeof p->params, "%s dt=%g", v->params, dt / substeps);
  p->ms_step = o[2] * substeps; /* CPU, per step of the scene's dt */
  *wall_ms = o[9] * substeps;
  p->steps_per_s = p->ms_step > 0 ? 1e3 / p->ms_step : NAN;
  p->rms_err = o[3], p->max_err = o[4];
  p->volume_change = o[5], p->reaction_err = o[6];
  p->settle_time = o[7], p->recovery_err = o[8];
  snprintf(p->state, sizeof p->state, "%s", state);
}

/* The reference solution, a case every shard runs (each needs it for its
 * own cases); replayed, only its numbers (for the notes) are known. */
static int reference_case(tb_suite *su, const char *scene, const tb_fid_plan *plan, tb_fid_ref *ref,
                          tb_error *err) {
  memset(ref, 0, sizeof *ref);
  tb_case c;
  int mode = tb_suite_case(su, "reference", 1, &c);
  if (mode == TB_CASE_RUN) {
    tb_sim_def rd = plan->def;
    rd.nodes = plan->ref_res;
    if (tb_fid_reference(scene, &rd, plan->t_eq, NULL, ref, err)) return -1;
    double v[] = {ref->umax,    ref->volume_change, ref->has_reaction,
                  ref->seconds, ref->iterations,    ref->load_steps,
                  ref->mesh.nv, ref->mesh.ntet,     ref->cpu_seconds};
    memcpy(c.v, v, sizeof v);
    c.nv = (int)(sizeof v / sizeof v[0]);
    tb_suite_case_done(su, &c);
    return 0;
  }
  if (mode != TB_CASE_KNOWN || c.nv != 9) return tb_error_set(err, scene, 0, "no reference case");
  ref->umax = c.v[0], ref->volume_change = c.v[1], ref->has_reaction = (int)c.v[2];
  ref->seconds = c.v[3], ref->iterations = (int)c.v[4], ref->load_steps = (int)c.v[5];
  ref->mesh.nv = (int)c.v[6], ref->mesh.ntet = (int)c.v[7], ref->cpu_seconds = c.v[8];
  return 0;
}

static void pct(tb_table *t, double v) {
  if (isfinite(v))
    tb_table_cell(t, "%.3g", 100 * v);
  else
    tb_table_cell(t, "-");
}

static int write_outputs(tb_suite *su, const char *scene, const scene_run *r, const char *on,
                         tb_error *err) {
  size_t cap = (size_t)r->n * 512 + 1024, len = 0;
  char *body = malloc(cap), line[1024];
  if (!body) return tb_error_set(err, scene, 0, "out of memory");
  body[0] = 0;
  for (int k = 0; k < r->n; k++) {
    tb_point_format(&r->pts[k], line, sizeof line);
    len += (size_t)snprintf(body + len, cap - len, "%s\n", line);
  }
  int rc = tb_suite_write_data(su, "points.csv", TB_POINTS_HEADER, body, err);
  /* chart.csv: one block per model (settled points), then the front */
  const char *models[16];
  int nm = 0;
  for (int k = 0; k < r->n && nm < 16; k++) {
    int seen = 0;
    for (int j = 0; j < nm; j++) seen |= !strcmp(models[j], r->pts[k].model);
    if (!seen) models[nm++] = r->pts[k].model;
  }
  len = 0;
  char header[64] = "";
  for (int m = 0; m < nm && !rc; m++) {
    if (m == 0)
      snprintf(header, sizeof header, "%s,rms error", models[m]);
    else
      len += (size_t)snprintf(body + len, cap - len, "\n\n%s,rms error\n", models[m]);
    int any = 0;
    for (int k = 0; k < r->n; k++)
      if (!strcmp(r->pts[k].model, models[m]) && tb_point_usable(&r->pts[k]))
        len += (size_t)snprintf(body + len, cap - len, "%.6g,%.6g\n", r->pts[k].steps_per_s,
                                r->pts[k].rms_err),
            any = 1;
    if (!any) len += (size_t)snprintf(body + len, cap - len, "NaN,NaN\n");
  }
  /* the front, by speed */
  len += (size_t)snprintf(body + len, cap - len, "\n\nPareto front,rms error\n");
  int last = -1;
  for (;;) {
    int next = -1;
    for (int k = 0; k < r->n; k++)
      if (on[k] &&
          (last < 0 || r->pts[k].steps_per_s > r->pts[last].steps_per_s ||
           (r->pts[k].steps_per_s == r->pts[last].steps_per_s && k > last)) &&
          (next < 0 || r->pts[k].steps_per_s < r->pts[next].steps_per_s))
        next = k;
    if (next < 0) break;
    len += (size_t)snprintf(body + len, cap - len, "%.6g,%.6g\n", r->pts[next].steps_per_s,
                            r->pts[next].rms_err);
    last = next;
  }
  char vars[256];
  snprintf(vars, sizeof vars, "title='%s: error against the reference vs speed'; nmodels=%d", scene,
           nm);
  if (!rc) rc = tb_suite_write_data(su, "chart.csv", header, body, err);
  if (!rc) rc = tb_suite_chart_vars(su, "chart_pareto.gp", "chart.csv", "pareto", vars, err);
  if (!rc)
    tb_suite_caption(su, "pareto",
                     "%s: rms error against the reference solution against steps per second, "
                     "every model, resolution and key parameter; the Pareto front joined",
                     scene);
  free(body);
  return rc;
}

static int run_scene(const tb_suite_opts *o, const char *scene) {
  int level = o->scale < 1 ? 0 : (o->full ? 2 : 1), failed = 0;
  char dir[900];
  tb_error err;
  tb_fid_plan plan;
  if (tb_fid_plan_for(scene, level, o->seed, &plan, &err))
    return fprintf(stderr, "pareto: %s\n", err.msg), 1;
  if (snprintf(dir, sizeof dir, "%s/pareto/%s", o->results, scene) >= (int)sizeof dir) return 1;
  char title[160];
  snprintf(title, sizeof title, "Error against the reference vs speed: %s", scene);
  tb_suite *su = tb_suite_begin(dir, "pareto", title, o->seed, &err);
  if (!su) return fprintf(stderr, "pareto: %s\n", err.msg), 1;
  double E = 0, nu = 0; /* the reference's material: fem's defaults */
  tb_model_setting("fem", NULL, "E", &E);
  tb_model_setting("fem", NULL, "nu", &nu);
  /* items: the reference solve, then every variant at every resolution */
  int total = 1, done = 0;
  for (int v = 0; v < NVARIANTS; v++)
    total += variants[v].level > level ? 0 : (variants[v].peer && level < 2 ? 1 : plan.nres);
  tb_progress("pareto", done++, total);
  tb_fid_ref ref;
  if (reference_case(su, scene, &plan, &ref, &err)) {
    fprintf(stderr, "pareto: %s: reference: %s\n", scene, err.msg);
    tb_suite_note(su, "The reference could not be computed: %s", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  tb_fid_opts fo = plan.opts;
  fo.settle_speed = plan.opts.settle_speed * ref.umax;
  tb_suite_note(su,
                "Scene %s, %s. Reference: compressible Neo-Hookean, E %g, nu %g, on the "
                "scene's mesh at resolution %d (%d nodes, %d tets, quadratic tets), solved in "
                "%.2f s wall, %.2f s CPU (%d Newton iterations, %d load steps); largest "
                "displacement %.4g, volume change %+.4f%%%s.",
                scene, plan.load, E, nu, plan.ref_res, ref.mesh.nv, ref.mesh.ntet, ref.seconds,
                ref.cpu_seconds, ref.iterations, ref.load_steps, ref.umax, 100 * ref.volume_change,
                ref.has_reaction ? ", a reaction on the pulled patch" : "");
  tb_suite_note(su,
                "Masses: %s. The material is E %g, nu %g for fem, fem-corot, msm calibrated=1 and "
                "xpbd-stvk (nu set to 0.3; its compliance comes from E); pbd-stvk's motion does "
                "not depend on E at all: its stiffness is set by k, the iterations and dt "
                "(`figure pbd-stiffness`), so its error here says how far those happen to be from "
                "this material on this mesh, and a small error at one resolution is a "
                "coincidence, not a calibration.",
                plan.density_masses
                    ? "from the density (lumped), as gravity loads this scene: each node carries "
                      "the weight of its share of the volume, as in the reference"
                    : "every node of a mesh the same, the body's mass at density 1 over its nodes "
                      "(the static answer does not depend on masses)",
                E, nu);
  tb_suite_note(su,
                "msm-vvs (Bao 2006's surface mass-spring model with virtual volumetric springs) "
                "is left out: it simulates the boundary alone (the interior nodes copy the "
                "nearest surface node), its virtual springs tie each node to its rest place "
                "and none of its constants maps to E and nu, so its error against a volumetric "
                "reference would measure that construction, not a resolution or parameter "
                "trade-off; its own scenes are sphere-press and sphere-stretch.");
  tb_suite_note(su,
                "Bullet 3.24's peers: bullet-fem (Bullet's deformable world: backward "
                "Euler linearised once, CG with projections) with its neohookean force at E %g, "
                "nu %g, stiffness damping 0.02, and bullet-softbody (btSoftBody, a link per tet "
                "edge, kLST 1; E does not enter) with 5 position iterations; %s. Bullet's linear "
                "force is in fact corotated (small strain of R^T F), so at these small "
                "displacements it lands on fem's and fem-corot's error.",
                E, nu,
                level < 2 ? "in quick mode neohookean and 5 iterations only, on the coarsest "
                            "mesh only (their steps cost 10-100 times ours); with --full at "
                            "every resolution, plus the linear force, the corotated force (it "
                            "blows up at dt 0.01: no force differential, so its implicit step "
                            "is explicit in the elasticity) and 20 iterations"
                          : "at every resolution, plus the linear force, the corotated force "
                            "(no force differential: its implicit step is explicit in the "
                            "elasticity, so it blows up at dt 0.01 and is rerun with substeps) "
                            "and bullet-softbody with 20 iterations");
  scene_run r;
  memset(&r, 0, sizeof r);
  for (int ri = 0; ri < plan.nres && !failed; ri++) {
    tb_sim_def sd = plan.def;
    sd.nodes = plan.res[ri];
    tb_fid_mesh fm;
    int have_mesh = 0; /* made for the first case of this resolution that runs here */
    for (int v = 0; v < NVARIANTS && !failed; v++) {
      if (variants[v].level > level || (variants[v].peer && level < 2 && ri > 0)) continue;
      tb_progress("pareto", done++, total);
      char key[220];
      snprintf(key, sizeof key, "res:%d/%s/%s", plan.res[ri], variants[v].model,
               variants[v].params);
      tb_case c;
      int mode = tb_suite_case(su, key, 0, &c);
      if (mode == TB_CASE_RUN) {
        if (!have_mesh && tb_fid_mesh_make(&ref, &sd, &fm, &err)) {
          fprintf(stderr, "pareto: %s: %s\n", scene, err.msg);
          failed = 1;
          break;
        }
        have_mesh = 1;
        if (run_variant(&ref, &fm, &plan, &sd, &fo, &variants[v], &c, &err)) {
          fprintf(stderr, "pareto: %s: %s\n", variants[v].model, err.msg);
          failed = 1;
          break;
        }
        tb_suite_case_done(su, &c);
      }
      /* the case's points: (substeps, nodes, then the result's numbers) each, and its state */
      for (int q = 0; q < (int)c.v[0] && q < c.nt && !failed; q++) {
        tb_point *p = add_point(&r);
        if (!p)
          failed = 1;
        else
          case_point(p, &r.wall[r.n - 1], &variants[v], plan.res[ri], plan.def.dt,
                     c.v + 1 + POINT_VALUES * q, c.t[q]);
      }
    }
    if (have_mesh) tb_fid_mesh_free(&fm);
  }
  tb_progress("pareto", total, total);
  char *on = calloc((size_t)(r.n > 0 ? r.n : 1), 1), *valid = calloc((size_t)(r.n + 1), 1);
  double *sp = malloc(sizeof(double) * (size_t)(r.n + 1)),
         *er = malloc(sizeof(double) * (size_t)(r.n + 1));
  if (!on || !valid || !sp || !er) failed = 1;
  int nfront = 0;
  if (!failed) {
    for (int k = 0; k < r.n; k++)
      valid[k] = (char)tb_point_usable(&r.pts[k]), sp[k] = r.pts[k].steps_per_s,
      er[k] = r.pts[k].rms_err;
    nfront = tb_fid_pareto(sp, er, valid, r.n, on);
    static const char *cols[] = {"model",
                                 "resolution",
                                 "nodes",
                                 "params",
                                 "steps/s (CPU)",
                                 "ms/step CPU (median)",
                                 "ms/step wall (median)",
                                 "rms error (%)",
                                 "max error (%)",
                                 "volume change (%)",
                                 "reaction error (%)",
                                 "settle time (s)",
                                 "left after release (%)",
                                 "front",
                                 "state"};
    tb_table *t = tb_table_new(
        "points", "Every point: error against the reference, speed (CPU time, one thread)", 15,
        cols);
    for (int k = 0; k < r.n; k++) {
      const tb_point *p = &r.pts[k];
      tb_table_row(t);
      tb_table_cell(t, "%s", p->model);
      tb_table_cell(t, "%d", p->resolution);
      tb_table_cell(t, "%d", p->nodes);
      tb_table_cell(t, "%s", p->params);
      tb_table_num(t, p->steps_per_s, "%.0f");
      tb_table_num(t, p->ms_step, "%.4f");
      tb_table_num(t, r.wall[k], "%.4f");
      pct(t, p->rms_err);
      pct(t, p->max_err);
      pct(t, p->volume_change);
      pct(t, p->reaction_err);
      if (isfinite(p->settle_time))
        tb_table_cell(t, "%.2f", p->settle_time);
      else
        tb_table_cell(t, "-");
      pct(t, p->recovery_err);
      tb_table_cell(t, "%s", on[k] ? "yes" : "");
      tb_table_cell(t, "%s", p->state);
      char bname[200]; /* the step's wall and CPU time; errors (%), settle time (s) as counters */
      snprintf(bname, sizeof bname, "%s/%s/res:%d/%s", scene, p->model, p->resolution, p->params);
      tb_suite_bench(su, bname, &r.wall[k], &p->ms_step, 1, "ms");
      tb_suite_counter(su, bname, "nodes", p->nodes);
      tb_suite_counter(su, bname, "rms_error_pct", 100 * p->rms_err);
      tb_suite_counter(su, bname, "max_error_pct", 100 * p->max_err);
      tb_suite_counter(su, bname, "volume_change_pct", 100 * p->volume_change);
      tb_suite_counter(su, bname, "reaction_error_pct", 100 * p->reaction_err);
      tb_suite_counter(su, bname, "settle_time_s", p->settle_time);
      tb_suite_counter(su, bname, "left_after_release_pct", 100 * p->recovery_err);
      tb_suite_counter(su, bname, "front", on[k] ? 1 : 0);
    }
    tb_suite_table(su, t);
    tb_suite_note(su,
                  "%d points, %d on the Pareto front (no other settled point is both at least as "
                  "fast and at least as accurate). Errors: surface nodes at equilibrium against "
                  "the reference displacement sampled at their rest positions, over the "
                  "reference's largest displacement %.4g. steps/s and ms/step are per %g s step "
                  "(the median step of the run; a run with substeps costs all of them), in CPU "
                  "time on one thread, so that other processes on the machine do not enter the "
                  "ranking; the wall time per step is beside it. points.csv's steps/s and "
                  "ms/step (what `advise` reads) are these CPU figures. Each point is one run: "
                  "points whose speeds differ by a few percent may trade places on the front "
                  "from run to run. Settle: "
                  "every node slower than %.3g per s for %g s (quasi-static runs: 3 steps), "
                  "ambient drag %g; settle time from the full load; `-` where quasi-static. "
                  "Only settled rows are charted, on the front or advised: an unstable run "
                  "has no answer, an unsettled one only a passing snapshot.",
                  r.n, nfront, ref.umax, plan.def.dt, fo.settle_speed, fo.window, plan.def.drag);
    if (write_outputs(su, scene, &r, on, &err)) {
      fprintf(stderr, "pareto: %s: %s\n", scene, err.msg);
      failed = 1;
    }
  }
  free(on), free(valid), free(sp), free(er), free(r.pts), free(r.wall);
  tb_fid_ref_free(&ref);
  if (tb_suite_end(su, &err)) fprintf(stderr, "pareto: %s\n", err.msg), failed = 1;
  return failed;
}

int tb_suite_pareto(const tb_suite_opts *o) {
  static const char *defaults[] = {"beam", "liver-stretch", "liver-hang"};
  /* a comparison of models: one thread, ranked by CPU time */
  int threads = tb_threads_setting(), failed = 0;
  tb_threads_set(1);
  if (o->scene)
    failed = run_scene(o, o->scene);
  else
    for (int k = 0; k < 3; k++) failed |= run_scene(o, defaults[k]);
  tb_threads_set(threads);
  return failed;
}
