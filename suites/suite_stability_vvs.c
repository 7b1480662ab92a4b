/* `figure stability`, part 3: the stability map of msm-vvs (Bao 2006 §4,
 * suites/tb_stab_vvs.h). The paper: at dt 0.01 and m 1 the model "works
 * normally" for kd < 2 and ks < 20. A grid of ks (log-spaced 0.5..100) x
 * kd (linear 0..5) on `sphere-press`, each cell a run with the press
 * applied suddenly and let go halfway, for the paper's quasi-static update
 * (at the scene's alpha) and symplectic Euler; the boundary bisected along
 * kd 0.5 and ks 3 (the paper's defaults) and set beside the linear
 * prediction of models/msm_vvs.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stability_priv.h"
#include "tb_stab_vvs.h"
#include "core/tb_timer.h"
#include "scenes/tb_sim.h"

#define SCENE "sphere-press"
#define MODEL "msm-vvs"
#define KS_LO 0.5
#define KS_HI 100.0
#define KD_HI 5.0
#define PAPER_KS 20.0 /* the paper's region: ks < 20, kd < 2 */
#define PAPER_KD 2.0
#define DEF_KS 3.0 /* the paper's defaults */
#define DEF_KD 0.5
#define KS_CAP 1e6 /* the edge searches give up past these */
#define KD_CAP 1e4
#define MAXN 24

static const char *const integ_key[2] = {"quasistatic", "euler"};
static const char *const integ_label[2] = {"quasi-static", "symplectic Euler"};

void tb_vvs_run_init(tb_vvs_run *r) {
  r->integrator = TB_VVS_QUASISTATIC;
  r->ks = DEF_KS, r->kd = DEF_KD, r->dt = 0.01, r->duration = 3.0, r->release = 1.5;
}

int tb_vvs_run_cell(const tb_vvs_run *r, const tb_mesh *mesh, tb_vvs_cell *c, tb_error *err) {
  tb_settings md;
  tb_settings_init(&md);
  if (tb_settings_setd(&md, "node_mass", TB_STAB_NODE_MASS, err) ||
      tb_settings_setd(&md, "ks", r->ks, err) || tb_settings_setd(&md, "kd", r->kd, err) ||
      tb_settings_set(
          &md, r->integrator == TB_VVS_EULER ? "integrator=euler" : "integrator=quasistatic", err))
    return -1;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = r->dt, sd.duration = r->duration, sd.release = r->release;
  sd.energy_every = 1; /* as on the other maps: checked every step */
  sd.seed = 1;
  tb_sim s;
  if (tb_sim_create(&s, SCENE, &sd, MODEL, &md, mesh, err)) return -1;
  tb_stab_cell sc;
  tb_stab_run(&s, &sc);
  tb_sim_destroy(&s);
  c->code = sc.code, c->t = sc.t;
  snprintf(c->reason, sizeof c->reason, "%s", sc.reason);
  return 0;
}

int tb_vvs_linear_init(tb_vvs_linear *p, const tb_mesh *mesh, uint64_t seed, tb_error *err) {
  tb_settings md;
  tb_settings_init(&md);
  if (tb_settings_setd(&md, "node_mass", TB_STAB_NODE_MASS, err)) return -1;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.seed = 1;
  tb_sim s;
  if (tb_sim_create(&s, SCENE, &sd, MODEL, &md, mesh, err)) return -1;
  int *edges = NULL, ne = tb_mesh_edges(&s.mesh, &edges); /* the surface's: the springs */
  if (ne < 0) {
    tb_sim_destroy(&s);
    return tb_error_set(err, "stability", 0, "out of memory");
  }
  p->lambda = tb_stab_largest_eigen(&s, edges, ne, 1, seed);
  free(edges);
  p->mass = TB_STAB_NODE_MASS;
  tb_model_setting(MODEL, &s.settings, "alpha", &p->alpha);
  tb_model_setting(MODEL, &s.settings, "ks_v", &p->ks_v);
  tb_model_setting(MODEL, &s.settings, "kd_v", &p->kd_v);
  tb_sim_destroy(&s);
  return 0;
}

/* a = sc dt^2 K / m, b = sc c dt / m, stable iff a + 2 b < L */
static double scale_of(const tb_vvs_linear *p, int integ) {
  return integ == TB_VVS_EULER ? 1.0 : p->alpha;
}
static double limit_of(int integ) { return integ == TB_VVS_EULER ? 4.0 : 2.0; }

double tb_vvs_ks_limit(const tb_vvs_linear *p, int integ, double dt, double kd) {
  double sc = scale_of(p, integ), b = sc * (kd + p->kd_v) * dt / p->mass;
  double K = (limit_of(integ) - 2 * b) * p->mass / (sc * dt * dt);
  return (K - p->ks_v) / p->lambda;
}

double tb_vvs_kd_limit(const tb_vvs_linear *p, int integ, double dt, double ks) {
  double sc = scale_of(p, integ), a = sc * dt * dt * (ks * p->lambda + p->ks_v) / p->mass;
  return (limit_of(integ) - a) * p->mass / (2 * sc * dt) - p->kd_v;
}

/* r with ks (along_kd 0) or kd set to v: stable? -1 on a setup error */
static int stable_at(const tb_vvs_run *r, const tb_mesh *mesh, int along_kd, double v, int *runs,
                     tb_error *err) {
  tb_vvs_run q = *r;
  *(along_kd ? &q.kd : &q.ks) = v;
  tb_vvs_cell c;
  tb_progress_tick("msm-vvs edge: %s %g", along_kd ? "kd" : "ks", v);
  if (tb_vvs_run_cell(&q, mesh, &c, err)) return -1;
  ++*runs;
  return c.code == 0;
}

int tb_vvs_edge(const tb_vvs_run *r, const tb_mesh *mesh, int along_kd, double cap, int bisect,
                double *lo, double *hi, int *runs, tb_error *err) {
  double v = along_kd ? r->kd : r->ks;
  *runs = 0;
  int st = stable_at(r, mesh, along_kd, v, runs, err);
  if (st < 0) return -1;
  if (st) { /* up: double until unstable */
    *lo = v, *hi = INFINITY;
    while (v * 2 <= cap && isinf(*hi)) {
      v *= 2;
      if ((st = stable_at(r, mesh, along_kd, v, runs, err)) < 0) return -1;
      *(st ? lo : hi) = v;
    }
  } else { /* down: halve until stable (kd also tries 0) */
    *hi = v, *lo = 0;
    for (int k = 0; k < 12 && *lo == 0; k++) {
      v = k == 11 && along_kd ? 0 : v / 2;
      if ((st = stable_at(r, mesh, along_kd, v, runs, err)) < 0) return -1;
      if (st)
        *lo = v;
      else
        *hi = v;
      if (v == 0) break;
    }
  }
  for (int it = 0; it < bisect && isfinite(*hi) && (*lo > 0 || along_kd); it++) {
    double mid = along_kd ? 0.5 * (*lo + *hi) : sqrt(*lo * *hi);
    if ((st = stable_at(r, mesh, along_kd, mid, runs, err)) < 0) return -1;
    *(st ? lo : hi) = mid;
  }
  return 0;
}

/* ---- the map ---- */

typedef struct vgrid {
  int nks, nkd, bisect;
  double ks[MAXN], kd[MAXN];
  double duration, release;
} vgrid;

static vgrid make_grid(const tb_suite_opts *o) {
  vgrid g;
  memset(&g, 0, sizeof g);
  if (o->scale < 1) /* smoke */
    g.nks = 3, g.nkd = 3, g.duration = 1, g.release = 0.5, g.bisect = 2;
  else if (o->full) /* the scene's own run */
    g.nks = 17, g.nkd = 21, g.duration = 12, g.release = 4, g.bisect = 12;
  else
    g.nks = 9, g.nkd = 11, g.duration = 3, g.release = 1.5, g.bisect = 8;
  for (int i = 0; i < g.nks; i++) g.ks[i] = KS_LO * pow(KS_HI / KS_LO, (double)i / (g.nks - 1));
  for (int j = 0; j < g.nkd; j++) g.kd[j] = KD_HI * j / (g.nkd - 1);
  return g;
}

/* Row r (one ks, every kd) of integrator integ's map as a case of
 * `reproduce --shard` into row[0 .. nkd): 1 known here, 0 another shard
 * runs it, -1 a setup error. */
static int map_row(tb_suite *su, const vgrid *g, int integ, int r, const tb_mesh *mesh,
                   tb_vvs_cell *row, long *done, long total, tb_error *err) {
  char key[96];
  snprintf(key, sizeof key, "map/msm-vvs/%s/ks:%.6g", integ_key[integ], g->ks[r]);
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c);
  *done += g->nkd;
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    for (int j = 0; j < g->nkd; j++) {
      tb_progress("stability map msm-vvs", *done - g->nkd + j, total);
      tb_vvs_run q;
      tb_vvs_run_init(&q);
      q.integrator = integ, q.ks = g->ks[r], q.kd = g->kd[j];
      q.duration = g->duration, q.release = g->release;
      if (tb_vvs_run_cell(&q, mesh, &row[j], err)) return -1;
      c.v[2 * j] = row[j].code, c.v[2 * j + 1] = row[j].t;
      snprintf(c.t[j], sizeof c.t[j], "%s", row[j].reason);
    }
    c.nv = 2 * g->nkd, c.nt = g->nkd;
    tb_suite_case_done(su, &c);
    return 1;
  }
  if (c.nv != 2 * g->nkd)
    return tb_error_set(err, "stability", 0, "case %s: %d numbers", key, c.nv);
  for (int j = 0; j < g->nkd; j++) {
    row[j].code = (int)c.v[2 * j], row[j].t = c.v[2 * j + 1];
    snprintf(row[j].reason, sizeof row[j].reason, "%.199s", c.t[j]);
  }
  return 1;
}

/* One integrator's map: table, counters, CSV rows; counts[0] stable cells,
 * counts[1] cells of the paper's region, counts[2] stable ones among them. */
static int map_integ(tb_suite *su, const vgrid *g, int integ, const tb_mesh *mesh,
                     tb_stab_text *csv, int *counts, long *done, long total, tb_error *err) {
  const char *cols[MAXN + 1];
  char heads[MAXN][32];
  cols[0] = "ks";
  for (int j = 0; j < g->nkd; j++) {
    snprintf(heads[j], sizeof heads[j], "kd %.3g", g->kd[j]);
    cols[j + 1] = heads[j];
  }
  char name[48], title[240];
  snprintf(name, sizeof name, "map_msm-vvs-%s", integ_key[integ]);
  snprintf(title, sizeof title,
           "msm-vvs (%s) over ks x kd, sphere-press, dt 0.01: stable or unstable (reason, time) "
           "over %g s",
           integ_label[integ], g->duration);
  tb_table *t = tb_table_new(name, title, g->nkd + 1, cols);
  for (int r = 0; r < g->nks; r++) {
    tb_table_row(t);
    tb_table_cell(t, "%.3g", g->ks[r]);
    tb_vvs_cell row[MAXN];
    int known = map_row(su, g, integ, r, mesh, row, done, total, err);
    if (known < 0) {
      tb_suite_table(su, t);
      return -1;
    }
    for (int j = 0; j < g->nkd && known; j++) {
      tb_vvs_run q;
      tb_vvs_run_init(&q);
      q.integrator = integ, q.ks = g->ks[r], q.kd = g->kd[j];
      tb_vvs_cell c = row[j];
      int inside = q.ks < PAPER_KS && q.kd < PAPER_KD;
      counts[0] += c.code == 0, counts[1] += inside, counts[2] += inside && c.code == 0;
      char bname[128]; /* counters: stable 1/0, the detector's code, when it tripped */
      snprintf(bname, sizeof bname, "map/msm-vvs/%s/ks:%.6g/kd:%.6g", integ_key[integ], q.ks, q.kd);
      tb_suite_counter(su, bname, "stable", c.code == 0);
      tb_suite_counter(su, bname, "status_code", c.code);
      if (c.code) tb_suite_counter(su, bname, "unstable_at_s", c.t);
      if (c.code == 0)
        tb_table_cell(t, "stable");
      else
        tb_table_cell(t, "unstable (%s, t %.3g)", tb_stab_status_names[c.code], c.t);
      for (char *p = c.reason; *p; p++)
        if (*p == ',' || *p == '"') *p = ';';
      tb_stab_text_add(csv, "%.6g,%.6g,%d,%s,%.6g,%s\n", q.kd, q.ks, c.code, integ_key[integ], c.t,
                       c.reason);
    }
  }
  tb_suite_table(su, t);
  return 0;
}

/* The bisected boundary along kd 0.5 and ks 3 against the prediction. */
static int edges_table(tb_suite *su, const vgrid *g, const tb_mesh *mesh, const tb_vvs_linear *p,
                       tb_stab_text *csv, double meas[2][2], tb_error *err) {
  static const char *cols[] = {"integrator",
                               "varied",
                               "at",
                               "largest stable",
                               "first unstable",
                               "predicted (linear, c = kd + k'_d .. kd)",
                               "measured / predicted (low end)",
                               "the paper's limit"};
  tb_table *t =
      tb_table_new("msm-vvs_edges",
                   "msm-vvs on sphere-press, dt 0.01: the stability boundary along the paper's "
                   "defaults (bisected) against the linear prediction and the paper's region",
                   8, cols);
  for (int integ = 0; integ < 2; integ++)
    for (int along_kd = 0; along_kd < 2; along_kd++) {
      tb_vvs_run q;
      tb_vvs_run_init(&q);
      q.integrator = integ, q.duration = g->duration, q.release = g->release;
      double lo = NAN, hi = NAN;
      int runs = 0;
      char key[64]; /* a case of `reproduce --shard` */
      snprintf(key, sizeof key, "edge/msm-vvs/%s/%s", integ_key[integ], along_kd ? "kd" : "ks");
      tb_case c;
      int mode = tb_suite_case(su, key, 0, &c);
      if (mode == TB_CASE_RUN) {
        if (tb_vvs_edge(&q, mesh, along_kd, along_kd ? KD_CAP : KS_CAP, g->bisect, &lo, &hi, &runs,
                        err)) {
          tb_suite_table(su, t);
          return -1;
        }
        c.v[0] = lo, c.v[1] = hi, c.v[2] = runs, c.nv = 3;
        tb_suite_case_done(su, &c);
      } else if (mode == TB_CASE_KNOWN && c.nv == 3)
        lo = c.v[0], hi = c.v[1], runs = (int)c.v[2];
      tb_vvs_linear p0 = *p; /* the high end: k'_d across the mode */
      p0.kd_v = 0;
      double pred = along_kd ? tb_vvs_kd_limit(p, integ, q.dt, q.ks)
                             : tb_vvs_ks_limit(p, integ, q.dt, q.kd),
             pred_hi = along_kd ? tb_vvs_kd_limit(&p0, integ, q.dt, q.ks)
                                : tb_vvs_ks_limit(&p0, integ, q.dt, q.kd);
      meas[integ][along_kd] = lo;
      const char *v = along_kd ? "kd" : "ks";
      tb_table_row(t);
      tb_table_cell(t, "%s", integ_label[integ]);
      tb_table_cell(t, "%s", v);
      tb_table_cell(t, "%s %g", along_kd ? "ks" : "kd", along_kd ? q.ks : q.kd);
      tb_table_cell(t, "%.4g", lo);
      if (isfinite(hi))
        tb_table_cell(t, "%.4g", hi);
      else
        tb_table_numf(t, NAN, "none (> %g)", lo);
      tb_table_cell(t, "%.4g..%.4g", pred, pred_hi);
      tb_table_cell(t, "%.3f", lo / pred);
      tb_table_cell(t, "%s < %g", v, along_kd ? PAPER_KD : PAPER_KS);
      char bname[96];
      snprintf(bname, sizeof bname, "msm-vvs_edges/%s/%s/%s:%g", integ_key[integ], v,
               along_kd ? "ks" : "kd", along_kd ? q.ks : q.kd);
      tb_suite_counter(su, bname, "largest_stable", lo);
      tb_suite_counter(su, bname, "first_unstable", isfinite(hi) ? hi : NAN);
      tb_suite_counter(su, bname, "predicted", pred);
      tb_suite_counter(su, bname, "predicted_high", pred_hi);
      tb_suite_counter(su, bname, "paper_limit", along_kd ? PAPER_KD : PAPER_KS);
      tb_suite_counter(su, bname, "runs", runs);
      tb_stab_text_add(csv, "%s,%s,%g,%.6g,%.6g,%.6g,%.6g,%g\n", integ_key[integ], v,
                       along_kd ? q.ks : q.kd, lo, isfinite(hi) ? hi : NAN, pred, pred_hi,
                       along_kd ? PAPER_KD : PAPER_KS);
    }
  tb_suite_table(su, t);
  return 0;
}

/* The charts: the map, the paper's region, the predicted boundary ks(kd). */
static int charts(tb_suite *su, const vgrid *g, const tb_vvs_linear *p, tb_error *err) {
  for (int integ = 0; integ < 2; integ++) {
    double sc = scale_of(p, integ), dt = 0.01;
    char base[48], vars[1600], alpha[32] = "";
    snprintf(base, sizeof base, "map_msm-vvs-%s", integ_key[integ]);
    if (!integ) snprintf(alpha, sizeof alpha, ", alpha %g", p->alpha); /* the scene's */
    snprintf(vars, sizeof vars,
             "title='msm-vvs (%s%s), sphere-press, dt %g: stability over %g s'; "
             "xlabel='node damping kd (N s/m)'; logx=0; ylabel='spring stiffness ks (N/m)'; "
             "logy=1; group='%s'; psize=%g; region_x=%g; region_y=%g; "
             "regiontitle='the paper: kd < %g, ks < %g'; "
             "curve='((%.10g - %.10g * (x + %.10g)) * %.10g - %.10g) / %.10g'; "
             "curvetitle='predicted edge (ks %.4g at kd %g)'",
             integ_label[integ], alpha, dt, g->duration, integ_key[integ], g->nkd > 12 ? 1.8 : 3.0,
             PAPER_KD, PAPER_KS, PAPER_KD, PAPER_KS, limit_of(integ), 2 * sc * dt / p->mass,
             p->kd_v, p->mass / (sc * dt * dt), p->ks_v, p->lambda,
             tb_vvs_ks_limit(p, integ, dt, DEF_KD), DEF_KD);
    if (tb_suite_chart_vars(su, "chart_map.gp", "map_msm-vvs.csv", base, vars, err)) return -1;
    tb_suite_caption(su, base,
                     "msm-vvs with the %s update on the pressed sphere: stable or why not over "
                     "node damping kd and spring stiffness ks at dt 0.01, the paper's region "
                     "(dashed) and the linear prediction of the boundary",
                     integ_label[integ]);
  }
  return 0;
}

int tb_stab_vvs(tb_suite *su, const tb_suite_opts *o, tb_error *err) {
  vgrid g = make_grid(o);
  tb_vvs_run q0;
  tb_vvs_run_init(&q0);
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  tb_mesh mesh;
  if (tb_sim_mesh(SCENE, &sd, &mesh, err)) return -1;
  tb_vvs_linear p;
  tb_stab_text csv = {0}, ecsv = {0};
  int counts[2][3] = {{0}}, rc = tb_vvs_linear_init(&p, &mesh, o->seed, err);
  double meas[2][2];
  long done = 0, total = 2L * g.nks * g.nkd;
  tb_clock clock = tb_clock_start();
  for (int integ = 0; integ < 2 && !rc; integ++)
    rc = map_integ(su, &g, integ, &mesh, &csv, counts[integ], &done, total, err);
  tb_progress("stability map msm-vvs", total, total);
  if (!rc) rc = edges_table(su, &g, &mesh, &p, &ecsv, meas, err);
  double wall_ms, cpu_ms;
  tb_clock_ms(&clock, &wall_ms, &cpu_ms);
  int nv = mesh.nv;
  tb_mesh_free(&mesh);
  if (!rc && (csv.bad || ecsv.bad)) rc = tb_error_set(err, "stability", 0, "out of memory");
  if (!rc)
    rc = tb_suite_write_data(su, "map_msm-vvs.csv", "kd,ks,status,integrator,t,reason", csv.s, err);
  if (!rc)
    rc = tb_suite_write_data(
        su, "msm-vvs_edges.csv",
        "integrator,varied,at,largest stable,first unstable,predicted (c = kd + k'_d),"
        "predicted (c = kd),"
        "paper limit",
        ecsv.s, err);
  free(csv.s), free(ecsv.s);
  if (rc) return -1;
  tb_suite_counter(su, "msm-vvs_linear", "lambda_per_ks", p.lambda);
  tb_suite_counter(su, "msm-vvs_linear", "alpha", p.alpha);
  double dt = q0.dt;
  tb_suite_note(
      su,
      "msm-vvs (Bao 2006 §4: at dt 0.01 and m 1 the model works for kd < %g and ks < %g): "
      "the `sphere-press` scene (the paper's sphere, %d points, base patch held, the top patch "
      "pressed with 3 in total from t = 0, let go at %g s), run for %g s per cell at dt %g, "
      "unit node masses, k'_s %g, k'_d %g, on a %d x %d grid (ks log-spaced %g..%g, kd linear "
      "0..%g), with the paper's quasi-static update (alpha %g, the scene's) and with symplectic "
      "Euler, judged by the same detector as the other maps (%.1f s of wall time, %.1f s of CPU "
      "time, for both maps and the edges). Cells of the paper's region (ks < %g and kd < %g) "
      "stable: "
      "quasi-static %d of %d, Euler %d of %d; of the whole grid: quasi-static %d, Euler %d of %d.",
      PAPER_KD, PAPER_KS, nv, g.release, g.duration, dt, p.ks_v, p.kd_v, g.nks, g.nkd, KS_LO, KS_HI,
      KD_HI, p.alpha, wall_ms * 1e-3, cpu_ms * 1e-3, PAPER_KS, PAPER_KD, counts[0][2], counts[0][1],
      counts[1][2], counts[1][1], counts[0][0], counts[1][0], g.nks * g.nkd);
  /* the prediction's bounds: k'_d along the mode (c = kd + k'_d) or across it (c = kd) */
  tb_vvs_linear p0 = p;
  p0.kd_v = 0;
  double ks_lim[2][2], kd_lim[2][2];
  for (int i = 0; i < 2; i++)
    ks_lim[i][0] = tb_vvs_ks_limit(&p, i, dt, DEF_KD),
    ks_lim[i][1] = tb_vvs_ks_limit(&p0, i, dt, DEF_KD),
    kd_lim[i][0] = tb_vvs_kd_limit(&p, i, dt, DEF_KS),
    kd_lim[i][1] = tb_vvs_kd_limit(&p0, i, dt, DEF_KS);
  tb_suite_note(
      su,
      "The boundary against the prediction of models/msm_vvs.c: a linear mode of stiffness K and "
      "damping c under the quasi-static step is stable iff alpha c dt / m < 1 and "
      "alpha dt^2 K / m + 2 alpha c dt / m < 2 (symplectic Euler: c dt / m < 2 and "
      "dt^2 K / m + 2 c dt / m < 4), here with K = lambda ks + k'_s, lambda = %.3f the largest "
      "eigenvalue of the surface springs' rest stiffness per unit ks over m (power iteration, "
      "base patch held; the file's bound 2 sum_j k_ij, 12 at valence 6, is %.2f times it), and c "
      "from kd + k'_d (k'_d acts along a point's displacement: the mode along it) to kd (across "
      "it), the prediction's low and high ends. Bisected from the paper's defaults (%d halvings, "
      "runs as the map's): quasi-static, largest stable ks at kd %g %.4g (predicted %.4g..%.4g), "
      "largest stable kd at ks %g %.4g (predicted %.4g..%.4g); symplectic Euler %.4g "
      "(%.4g..%.4g) and %.4g (%.4g..%.4g). A mode just past the limit grows slowly, and a run of "
      "%ld steps may not lift it past the detector's margins: a measured edge can lie a little "
      "beyond the prediction (the --full map's 12 s runs come closer).",
      p.lambda, 12.0 / p.lambda, g.bisect, DEF_KD, meas[0][0], ks_lim[0][0], ks_lim[0][1], DEF_KS,
      meas[0][1], kd_lim[0][0], kd_lim[0][1], meas[1][0], ks_lim[1][0], ks_lim[1][1], meas[1][1],
      kd_lim[1][0], kd_lim[1][1], lround(g.duration / dt));
  tb_suite_note(
      su,
      "Against the paper's region (ks < %g, kd < %g): the quasi-static update at alpha %g keeps "
      "%d of the region's %d grid cells stable; along its defaults it is stable up to ks %.3g "
      "(%s the paper's %g) and kd %.3g (%s the paper's %g). Its damping limit, alpha (kd + k'_d) "
      "dt / m < 1, i.e. kd < m / (alpha dt) - k'_d = %.3g, would be the paper's kd < %g at "
      "alpha %.3g. Symplectic Euler at dt %g keeps %d of the %d grid cells stable; its edges "
      "(ks %.4g, kd %.4g) are %.0f and %.0f times the paper's limits.",
      PAPER_KS, PAPER_KD, p.alpha, counts[0][2], counts[0][1], meas[0][0],
      meas[0][0] < PAPER_KS ? "inside" : "beyond", PAPER_KS, meas[0][1],
      meas[0][1] < PAPER_KD ? "inside" : "beyond", PAPER_KD, p.mass / (p.alpha * dt) - p.kd_v,
      PAPER_KD, p.mass / ((PAPER_KD + p.kd_v) * dt), dt, counts[1][0], g.nks * g.nkd, meas[1][0],
      meas[1][1], meas[1][0] / PAPER_KS, meas[1][1] / PAPER_KD);
  /* the alpha each of the paper's bounds asks for: ks < 20 at the default kd from
   * alpha dt^2 K / m + 2 alpha c dt / m = 2 (c from kd to kd + k'_d), kd < 2 from
   * alpha (kd + k'_d) dt / m = 1 */
  double K20 = p.lambda * PAPER_KS + p.ks_v;
  double a_ks_lo = 2 / (dt * dt * K20 / p.mass + 2 * (DEF_KD + p.kd_v) * dt / p.mass),
         a_ks_hi = 2 / (dt * dt * K20 / p.mass + 2 * DEF_KD * dt / p.mass),
         a_kd = p.mass / ((PAPER_KD + p.kd_v) * dt);
  tb_suite_note(su,
                "No single alpha gives both of the paper's bounds: by the prediction, ks < %g "
                "(at kd %g) is the quasi-static edge at alpha %.3g to %.3g, and kd < %g at alpha "
                "%.3g, %.2f to %.2f times that. At the scene's alpha %g the edges are ks %.3g and "
                "kd %.3g (measured above).",
                PAPER_KS, DEF_KD, a_ks_lo, a_ks_hi, PAPER_KD, a_kd, a_kd / a_ks_hi, a_kd / a_ks_lo,
                p.alpha, meas[0][0], meas[0][1]);
  tb_suite_counter(su, "msm-vvs_linear", "alpha_for_paper_ks", a_ks_lo);
  tb_suite_counter(su, "msm-vvs_linear", "alpha_for_paper_kd", a_kd);
  return charts(su, &g, &p, err);
}
