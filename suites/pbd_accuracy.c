/* The PBD patent's models at rest against the converged FEM solution
 * (suites/tb_pbd_accuracy.h). The liver hangs from a patch of its top
 * under gravity (liver-hang, the pareto suite's static problem); the
 * reference is the static Neo-Hookean solution on quadratic tets of a
 * liver finer than the models' (measure/tb_fidelity.h), of the material
 * the models are given (E 3000, the patent's nu 0.4, density 1). Each row
 * runs one model until every node moves slower than 1e-3 of the
 * reference's largest displacement per second, then compares its surface
 * nodes with the reference sampled at their rest positions. pbd-stvk's
 * projection does not see E (its stiffness is k, the iterations and dt:
 * suites/suite_pbd_stiffness.c); xpbd-stvk's compliance does, and its rest
 * state tends to the material's as the iterations grow; fem-corot on the
 * same linear tets shows what the mesh alone costs. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_pbd_accuracy.h"
#include "measure/tb_fidelity.h"

#define SCENE "liver-hang"
#define NU 0.4 /* the patent's Poisson ratio, the reference's too */

typedef struct setting {
  const char *model, *what;
  double dt;
  int iterations; /* 0: the model has none */
  double k;       /* pbd-stvk's; NAN: none */
} setting;

static const setting rows[] = {
    {"pbd-stvk", "the patent's settings", 0.005, 5, 0.4},
    {"pbd-stvk", "100 iterations", 0.005, 100, 0.4},
    {"xpbd-stvk", "the patent's dt and iterations", 0.005, 5, NAN},
    {"xpbd-stvk", "50 iterations", 0.005, 50, NAN},
    {"xpbd-stvk", "converged: 100 iterations", 0.005, 100, NAN},
    {"fem-corot", "implicit FEM on the same tets", 0.005, 0, NAN},
};
#define NROWS (int)(sizeof rows / sizeof rows[0])

static int settings_of(const setting *r, tb_settings *md, tb_error *err) {
  tb_settings_init(md);
  char kv[64];
  snprintf(kv, sizeof kv, "nu=%g", NU);
  if (tb_settings_set(md, kv, err)) return -1;
  if (r->iterations > 0) {
    snprintf(kv, sizeof kv, "iterations=%d", r->iterations);
    if (tb_settings_set(md, kv, err)) return -1;
  }
  if (!isnan(r->k)) {
    snprintf(kv, sizeof kv, "k=%g", r->k);
    if (tb_settings_set(md, kv, err)) return -1;
  }
  return 0;
}

int tb_pbd_accuracy(tb_suite *su, const tb_suite_opts *o) {
  tb_fid_plan plan;
  tb_error err;
  if (tb_fid_plan_for(SCENE, o->scale < 1 ? 0 : (o->full ? 2 : 1), o->seed, &plan, &err)) {
    fprintf(stderr, "pbd: %s\n", err.msg);
    return 1;
  }
  tb_settings mat;
  tb_settings_init(&mat);
  char kv[64];
  snprintf(kv, sizeof kv, "nu=%g", NU);
  tb_fid_ref ref;
  tb_sim_def rd = plan.def;
  rd.nodes = plan.ref_res;
  if (tb_settings_set(&mat, kv, &err) ||
      tb_fid_reference(SCENE, &rd, plan.t_eq, &mat, &ref, &err)) {
    fprintf(stderr, "pbd: reference: %s\n", err.msg);
    return 1;
  }
  tb_sim_def sd = plan.def;
  sd.nodes = plan.res[o->full ? plan.nres - 1 : 0]; /* quick: the coarsest */
  tb_fid_mesh fm;
  if (tb_fid_mesh_make(&ref, &sd, &fm, &err)) {
    fprintf(stderr, "pbd: %s\n", err.msg);
    tb_fid_ref_free(&ref);
    return 1;
  }
  static const char *cols[] = {"model",
                               "settings",
                               "dt (s)",
                               "iterations",
                               "k",
                               "state",
                               "rms error (% of the largest displacement)",
                               "largest error (%)",
                               "largest displacement / reference's",
                               "CPU ms per step (median)"};
  tb_table *t =
      tb_table_new("accuracy", "At rest against the converged FEM: the liver hanging", 10, cols);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)fm.mesh.nv);
  double ratio[NROWS];
  int failed = !x;
  for (int r = 0; r < NROWS && x; r++) {
    tb_progress("pbd accuracy", r, NROWS);
    const setting *w = &rows[r];
    tb_settings md;
    tb_fid_opts so = plan.opts;
    so.settle_speed = plan.opts.settle_speed * ref.umax, so.keep_x = x;
    tb_sim_def rdef = sd;
    rdef.dt = w->dt;
    tb_fid_result fr;
    ratio[r] = NAN;
    if (settings_of(w, &md, &err) || tb_fid_masses(&plan, &fm.mesh, w->model, &md, &err) ||
        tb_fid_run(&ref, &fm, w->model, &md, &rdef, &so, &fr, &err)) {
      fprintf(stderr, "pbd: accuracy, %s: %s\n", w->model, err.msg);
      failed = 1;
      continue;
    }
    double most = 0;
    for (int i = 0; i < fm.mesh.nv; i++) most = fmax(most, tb_dist(x[i], fm.mesh.x[i]));
    if (fr.stable) ratio[r] = most / ref.umax;
    tb_table_row(t);
    tb_table_cell(t, "%s", w->model);
    tb_table_cell(t, "%s", w->what);
    tb_table_num(t, w->dt, "%g");
    tb_table_num(t, w->iterations > 0 ? w->iterations : NAN, "%.0f");
    tb_table_num(t, w->k, "%g");
    tb_table_cell(t, "%s", fr.state);
    tb_table_num(t, fr.stable ? 100 * fr.rms_err : NAN, "%.2f");
    tb_table_num(t, fr.stable ? 100 * fr.max_err : NAN, "%.2f");
    tb_table_num(t, ratio[r], "%.3f");
    tb_table_num(t, fr.ms_step, "%.3f");
    char bench[96];
    snprintf(bench, sizeof bench, "accuracy/%s/dt:%g/iterations:%d", w->model, w->dt,
             w->iterations);
    tb_suite_counter(su, bench, "rms_error", fr.stable ? fr.rms_err : NAN);
    tb_suite_counter(su, bench, "max_error", fr.stable ? fr.max_err : NAN);
    tb_suite_counter(su, bench, "displacement_ratio", ratio[r]);
    tb_suite_counter(su, bench, "cpu_ms_per_step", fr.ms_step);
    tb_suite_counter(su, bench, "settled", fr.settled);
  }
  tb_progress("pbd accuracy", NROWS, NROWS);
  tb_suite_table(su, t);
  int it, steps;
  double res;
  tb_ref_stats(ref.sol, &it, &steps, &res);
  tb_suite_note(
      su,
      "Accuracy at rest: %s (the pareto suite's static problem) on a %d-node liver, "
      "each model at the row's dt run until every node moves slower than %.3g per s (1e-3 of the "
      "reference's largest displacement), at most %g s. The reference: static "
      "compressible Neo-Hookean on quadratic tets of a %d-node liver, E 3000, nu %g "
      "(the patent's), density 1, Newton to a relative residual of %.1e (%d "
      "iterations); its largest displacement %.3g. Errors: each surface node's distance "
      "from the reference displacement at its rest position, over that largest "
      "displacement.",
      SCENE, fm.mesh.nv, plan.opts.settle_speed * ref.umax, plan.opts.max_time, ref.mesh.nv, NU,
      res, it, ref.umax);
  if (!isnan(ratio[0]) && !isnan(ratio[4]) && !isnan(ratio[5]))
    tb_suite_note(su,
                  "At the patent's settings (k 0.4, 5 iterations, dt 0.005) pbd-stvk's liver "
                  "sags %.3g of the material's: %.1f times stiffer than the tissue it models, "
                  "%.1f times stiffer than implicit FEM on the same tets (which sags %.3g of it: "
                  "what linear tets on this mesh cost), and more iterations stiffen it further "
                  "(PBD's stiffness is k, the iterations and dt, not E). xpbd-stvk with 100 "
                  "iterations sags %.3g of it, as FEM on the same tets.",
                  ratio[0], 1 / ratio[0], ratio[5] / ratio[0], ratio[5], ratio[4]);
  free(x);
  tb_fid_mesh_free(&fm);
  tb_fid_ref_free(&ref);
  return failed;
}
