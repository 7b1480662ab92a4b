/* `figure stability`, part 2: large deformations (bench/scene_deform.c).
 * Every model x {stretch 100%, twist 180 deg, crush 50%} of a 4 x 1 x 1
 * beam, ramped, held, let go: inverted tets and volume change at the peak,
 * inverted tets and the residual displacement after recovery. Inversion
 * checking is off here (inverted tets are counted, not a stop); NaN/inf,
 * velocity and energy growth still stop a run, printed as
 * `unstable (reason)`. Each model x test run is a case (`reproduce --shard`). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stability_priv.h"
#include "scenes/tb_sim.h"

#define NMAPS tb_stab_nmodels
#define maps tb_stab_models
#define NODE_MASS TB_STAB_NODE_MASS

static const struct {
  const char *scene, *label;
} tests[] = {
    {"beam-stretch", "stretch 100%"}, {"beam-twist", "twist 180 deg"}, {"beam-crush", "crush 50%"}};
#define NTESTS ((int)(sizeof tests / sizeof tests[0]))

#define DEFORM_L 4.0    /* the deform scenes' beam length */
#define DEFORM_DRAG 2.0 /* ambient drag so the motion dies out after release */
#define RECOVERED 0.05  /* residual max displacement below this x L: recovered */
#define VOLUME_LOSS 0.2 /* |volume change| at the peak named in the summary */

typedef struct deform_result {
  int run; /* 1 when this model x test ran */
  tb_stab_cell c;
  tb_sim_metrics peak, end;
  double before; /* max displacement a second before the end */
} deform_result;

/* Runs one model on one deform scene into r; -1 when the scene cannot be built. */
static int deform_run(const char *model, const char *scene, const tb_sim_def *sd, deform_result *r,
                      tb_error *err) {
  tb_settings md;
  tb_settings_init(&md);
  if (tb_settings_setd(&md, "node_mass", NODE_MASS, err)) return -1;
  tb_sim s;
  if (tb_sim_create(&s, scene, sd, model, &md, NULL, err)) return -1;
  long n = lround(s.def.duration / s.def.dt), at_release = lround(s.def.release / s.def.dt);
  memset(r, 0, sizeof *r);
  r->run = 1;
  r->c.code = ST_STABLE;
  for (long q = 0; q < n; q++) {
    tb_error e;
    tb_progress_tick("%s, %s: step %ld/%ld", model, scene, q + 1, n);
    if (tb_sim_step(&s, &e)) {
      r->c.code = s.health.ok ? ST_FAILED : tb_stab_classify(s.health.reason);
      snprintf(r->c.reason, sizeof r->c.reason, "%.199s", s.health.ok ? e.msg : s.health.reason);
      break;
    }
    if (q + 1 == at_release) r->peak = tb_sim_measure(&s);
    if (q + 1 == n - lround(1.0 / s.def.dt)) r->before = tb_sim_measure(&s).max_disp;
  }
  r->c.t = s.t;
  r->end = tb_sim_measure(&s);
  tb_sim_destroy(&s);
  return 0;
}

/* deform_run as a case of `reproduce --shard`: its outcome is what the
 * table and the summary read (a run another shard makes stays out). */
static int deform_case(tb_suite *su, const char *model, const char *scene, const tb_sim_def *sd,
                       deform_result *r, tb_error *err) {
  char key[96];
  snprintf(key, sizeof key, "deform/%s/%s", model, scene);
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c);
  memset(r, 0, sizeof *r);
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    if (deform_run(model, scene, sd, r, err)) return -1;
    double v[] = {r->c.code,       r->c.t,          r->peak.inverted, r->peak.volume_change,
                  r->end.inverted, r->end.max_disp, r->before};
    memcpy(c.v, v, sizeof v);
    c.nv = (int)(sizeof v / sizeof v[0]), c.nt = 1;
    snprintf(c.t[0], sizeof c.t[0], "%s", r->c.reason);
    tb_suite_case_done(su, &c);
    return 0;
  }
  r->run = 1;
  r->c.code = (int)c.v[0], r->c.t = c.v[1], r->peak.inverted = (int)c.v[2];
  r->peak.volume_change = c.v[3], r->end.inverted = (int)c.v[4], r->end.max_disp = c.v[5];
  r->before = c.v[6];
  snprintf(r->c.reason, sizeof r->c.reason, "%.199s", c.t[0]);
  return 0;
}

static int recovered(const deform_result *r) {
  return r->end.max_disp / DEFORM_L < RECOVERED && r->end.inverted == 0;
}

/* "what: msm (twist 180 deg, crush 50%), fem (...)." for the results
 * where pick() holds, or "what: none." */
static void summary(tb_stab_text *b, const char *what, deform_result r[][NTESTS],
                    int (*pick)(const deform_result *)) {
  tb_stab_text_add(b, "%s:", what);
  int any = 0;
  for (int m = 0; m < NMAPS; m++) {
    int first = 1;
    for (int k = 0; k < NTESTS; k++) {
      if (!r[m][k].run || !pick(&r[m][k])) continue;
      tb_stab_text_add(b, "%s%s%s", first ? (any ? "; " : " ") : ", ", first ? maps[m].name : "",
                       first ? " (" : "");
      tb_stab_text_add(b, "%s", tests[k].label);
      first = 0, any = 1;
    }
    if (!first) tb_stab_text_add(b, ")");
  }
  tb_stab_text_add(b, "%s. ", any ? "" : " none");
}

static int pick_unstable(const deform_result *r) { return r->c.code != ST_STABLE; }
static int pick_inverted_peak(const deform_result *r) {
  return r->c.code == ST_STABLE && r->peak.inverted > 0;
}
static int pick_inverted_end(const deform_result *r) {
  return r->c.code == ST_STABLE && r->end.inverted > 0;
}
static int pick_volume(const deform_result *r) {
  return r->c.code == ST_STABLE && fabs(r->peak.volume_change) > VOLUME_LOSS;
}
static int pick_unrecovered(const deform_result *r) {
  return r->c.code == ST_STABLE && !recovered(r);
}

int tb_stab_deform(tb_suite *su, const tb_suite_opts *o, const char *only, tb_error *err) {
  static const char *cols[] = {"model",
                               "test",
                               "state",
                               "inverted tets at peak",
                               "volume change at peak (%)",
                               "inverted tets after recovery",
                               "residual max displacement (% of L)",
                               "recovered"};
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = 0.01, sd.duration = 6.0, sd.release = 1.0, sd.nodes = o->full ? 16 : 8;
  if (o->scale < 1) sd.dt = 0.02, sd.duration = 1.0, sd.release = 0.5, sd.nodes = 4;
  sd.drag = DEFORM_DRAG;
  sd.inversion = 0;    /* inverted tets are counted here, not a stop */
  sd.energy_every = 1; /* as on the maps */
  sd.seed = 1;
  deform_result res[NMAPS][NTESTS];
  memset(res, 0, sizeof res);
  long done = 0, total = 0; /* the runs */
  for (int m = 0; m < NMAPS; m++) total += tb_stab_deform_runs(&maps[m], only) ? NTESTS : 0;
  for (int m = 0; m < NMAPS; m++) {
    if (!tb_stab_deform_runs(&maps[m], only)) continue;
    for (int k = 0; k < NTESTS; k++) {
      tb_progress("stability deformations", done++, total);
      if (deform_case(su, maps[m].name, tests[k].scene, &sd, &res[m][k], err)) return -1;
    }
  }
  tb_progress("stability deformations", total, total);
  tb_table *t = tb_table_new("deform", "Large deformations of a 4 x 1 x 1 beam", 8, cols);
  for (int m = 0; m < NMAPS; m++)
    for (int k = 0; k < NTESTS; k++) {
      const deform_result *r = &res[m][k];
      if (!r->run) continue;
      tb_table_row(t);
      tb_table_cell(t, "%s", maps[m].name);
      tb_table_cell(t, "%s", tests[k].label);
      char bname[96]; /* counters: stable 1/0, inverted tets, volume and displacement (%) */
      snprintf(bname, sizeof bname, "deform/%s/%s", maps[m].name, tests[k].label);
      tb_suite_counter(su, bname, "stable", r->c.code == ST_STABLE);
      if (r->c.code == ST_STABLE) {
        tb_suite_counter(su, bname, "peak_inverted", r->peak.inverted);
        tb_suite_counter(su, bname, "peak_volume_change_pct", 100 * r->peak.volume_change);
        tb_suite_counter(su, bname, "end_inverted", r->end.inverted);
        tb_suite_counter(su, bname, "end_max_disp_pct_of_L", 100 * r->end.max_disp / DEFORM_L);
        tb_suite_counter(su, bname, "recovered", recovered(r) ? 1 : 0);
      }
      if (r->c.code != ST_STABLE) {
        tb_table_cell(t, "unstable (%s at t = %.3g)", r->c.reason, r->c.t);
        for (int q = 0; q < 5; q++) tb_table_cell(t, "-");
        continue;
      }
      tb_table_cell(t, "stable");
      tb_table_cell(t, "%d", r->peak.inverted);
      tb_table_cell(t, "%+.1f", 100 * r->peak.volume_change);
      tb_table_cell(t, "%d", r->end.inverted);
      tb_table_cell(t, "%.2f", 100 * r->end.max_disp / DEFORM_L);
      if (recovered(r))
        tb_table_cell(t, "yes");
      else if (!(r->before > 0)) /* a run shorter than a second after release */
        tb_table_cell(t, "no");
      else if (r->end.max_disp < 0.9 * r->before)
        tb_table_cell(t, "no (still creeping back: %.2f%% of L a second earlier)",
                      100 * r->before / DEFORM_L);
      else
        tb_table_cell(t, "no (stuck)");
    }
  tb_suite_table(su, t);
  tb_mesh mesh;
  if (tb_sim_mesh(tests[0].scene, &sd, &mesh, err)) return -1;
  int ntet = mesh.ntet;
  tb_mesh_free(&mesh);
  tb_suite_note(su,
                "Large deformations: a 4 x 1 x 1 beam (%d cells along x, %d tets) held at x = 0; "
                "its end face is ramped over %g s to 2 L (stretch), 180 deg about the axis "
                "(twist) or L / 2 (crush), held to t = %g s (the peak, measured there), let go "
                "and left to recover until t = %g s; dt %g, unit node masses, the thesis's "
                "parameters, ambient drag %g (force -drag m v) for every model so the motion "
                "dies out. Inversion checking is OFF here: inverted tets are counted, not a "
                "stop; NaN/inf, the velocity bound and energy growth still stop a run, which "
                "then reads `unstable (reason)`. Recovered: residual max displacement below "
                "%g%% of L and no inverted tet; if not, `stuck` when the residual fell by "
                "less than 10%% over the last second.",
                sd.nodes, ntet, 0.5 * sd.release, sd.release, sd.duration, sd.dt, DEFORM_DRAG,
                100 * RECOVERED);
  tb_stab_text b = {0};
  summary(&b, "Blew up", res, pick_unstable);
  summary(&b, "Inverted tets at the peak", res, pick_inverted_peak);
  summary(&b, "Inverted tets left after recovery", res, pick_inverted_end);
  tb_stab_text_add(&b, "Volume changed by more than %g%% at the peak", 100 * VOLUME_LOSS);
  summary(&b, "", res, pick_volume);
  summary(&b, "Did not recover", res, pick_unrecovered);
  if (b.bad) return free(b.s), tb_error_set(err, "stability", 0, "out of memory");
  tb_suite_note(su, "%s", b.s);
  free(b.s);
  return 0;
}
