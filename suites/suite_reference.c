/* The reference solution's refinement study: the cantilever of the `beam`
 * scene (10 x 1 x 1, clamped at x = 0, tip load 0.075 spread over the end
 * face's nodes, E 3000, nu 0.3) solved by the reference solver
 * (reference/tb_reference.h) on refined meshes with linear (T4) and
 * quadratic (T10) tets, Neo-Hookean and linear material, beside the
 * analytic deflections (Euler-Bernoulli P L^3 / 3EI; Timoshenko adds
 * P L / (kappa G A), kappa 5/6). T4 locks in bending; T10 converges. The
 * pareto suite's references use T10 on a mesh finer than every model's. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "reference/tb_reference.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

/* Mean z displacement of the tip face's nodes, or NAN with err; the
 * solve's wall and CPU seconds into secs[0] and secs[1]. */
static double tip_deflection(int cells, int quadratic, int material, double secs[2], int *iters,
                             tb_error *err) {
  tb_sim s;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.nodes = cells;
  tb_settings md;
  tb_settings_init(&md);
  double density;
  if (tb_settings_set(&md, "quasistatic=1", err) ||
      tb_model_setting("fem", &md, "density", &density) ||
      tb_sim_create(&s, "beam", &sd, "fem", &md, NULL, err))
    return NAN;
  double out = NAN;
  if (!tb_sim_loads(&s, s.def.dt, err)) {
    tb_ref_problem p;
    memset(&p, 0, sizeof p);
    p.mesh = &s.mesh, p.density = density, p.force = s.force;
    p.nfixed = s.nfixed, p.fixed = s.fixed, p.fixed_x = s.fixed_x;
    tb_ref_def rd = tb_ref_default_def();
    rd.quadratic = quadratic, rd.material = material;
    tb_clock c = tb_clock_start();
    tb_ref_solution *sol = tb_ref_solve(&p, &rd, err);
    tb_clock_ms(&c, &secs[0], &secs[1]);
    secs[0] *= 1e-3, secs[1] *= 1e-3;
    if (sol) {
      const tb_vec3 *x = tb_ref_positions(sol);
      double sum = 0;
      for (int k = 0; k < s.ndriven; k++) sum += x[s.driven[k]].z - s.mesh.x[s.driven[k]].z;
      out = -sum / s.ndriven;
      double res;
      int steps;
      tb_ref_stats(sol, iters, &steps, &res);
      tb_ref_free(sol);
    }
  }
  tb_sim_destroy(&s);
  return out;
}

int tb_suite_reference(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/reference", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s =
      tb_suite_begin(dir, "reference", "The reference solver's refinement study", o->seed, &err);
  if (!s) return fprintf(stderr, "reference: %s\n", err.msg), 1;
  const double P = 0.075, L = 10, E = 3000, nu = 0.3, I = 1.0 / 12, A = 1, kappa = 5.0 / 6;
  double eb = P * L * L * L / (3 * E * I), timo = eb + P * L / (kappa * E / (2 * (1 + nu)) * A);
  static const int cells_smoke[] = {10, 20}, cells_quick[] = {10, 20, 40},
                   cells_full[] = {10, 20, 40, 60};
  const int *cells = o->scale < 1 ? cells_smoke : (o->full ? cells_full : cells_quick);
  int n = o->scale < 1 ? 2 : (o->full ? 4 : 3), failed = 0;
  static const char *cols[] = {"cells along x",  "elements",     "material",
                               "tip deflection", "/ Timoshenko", "Newton iterations",
                               "solve wall (s)", "solve CPU (s)"};
  tb_table *t = tb_table_new("cantilever", "Cantilever tip deflection against refinement", 8, cols);
  static const struct {
    int quadratic, material;
    const char *elem, *mat;
  } variants[] = {{0, TB_REF_NEOHOOKE, "T4", "Neo-Hookean"},
                  {1, TB_REF_NEOHOOKE, "T10", "Neo-Hookean"},
                  {1, TB_REF_LINEAR, "T10", "linear"}};
  for (int v = 0; v < 3 && !failed; v++)
    for (int i = 0; i < n && !failed; i++) {
      tb_progress("reference", v * n + i, 3 * n);
      if (variants[v].material == TB_REF_LINEAR && i != n - 1) continue;
      double secs[2] = {0, 0};
      int iters = 0;
      double d =
          tip_deflection(cells[i], variants[v].quadratic, variants[v].material, secs, &iters, &err);
      if (isnan(d)) {
        fprintf(stderr, "reference: %s\n", err.msg);
        failed = 1;
        break;
      }
      tb_table_row(t);
      tb_table_cell(t, "%d", cells[i]);
      tb_table_cell(t, "%s", variants[v].elem);
      tb_table_cell(t, "%s", variants[v].mat);
      tb_table_cell(t, "%.6f", d);
      tb_table_cell(t, "%.4f", d / timo);
      tb_table_cell(t, "%d", iters);
      tb_table_num(t, secs[0], "%.3f");
      tb_table_num(t, secs[1], "%.3f");
      char bname[120];
      snprintf(bname, sizeof bname, "reference/%s/%s/cells:%d", variants[v].elem, variants[v].mat,
               cells[i]);
      tb_suite_bench(s, bname, &secs[0], &secs[1], 1, "s");
      tb_suite_counter(s, bname, "tip_deflection", d);
      tb_suite_counter(s, bname, "over_timoshenko", d / timo);
      tb_suite_counter(s, bname, "newton_iterations", iters);
    }
  tb_progress("reference", 3 * n, 3 * n);
  tb_suite_table(s, t);
  tb_suite_note(s,
                "Analytic: Euler-Bernoulli %.6f, Timoshenko %.6f (kappa 5/6). The beam's cells "
                "are cubes of 6 tets, the cross-section cells along y and z are cells/10. The "
                "issue's bar: T10 within 2%% of the analytic deflection (a fully clamped end face "
                "is slightly stiffer than the beam theories' support). Solve times: one solve "
                "each, wall and CPU (the process's, every thread's: the solver's factorisation "
                "may use %d threads), for scale only.",
                eb, timo, tb_threads());
  if (tb_suite_end(s, &err)) fprintf(stderr, "reference: %s\n", err.msg), failed = 1;
  return failed;
}
