/* `figure stability`: where each model blows up, and what large
 * deformations do to it.
 *
 * Part 1, stability maps: a grid of time step dt (log-spaced) x the model's
 * stiffness parameter (msm ks, fem and fem-corot E, log-spaced; sm alpha,
 * linear; pbd-stvk k, linear, and in a second map its iterations; xpbd-stvk
 * iterations; iterations log-spaced and rounded), per mesh size. Each cell
 * runs the `beam` scene (cantilever 10 x 1 x 1 held at x = 0) for a fixed
 * simulated time under a tip load applied suddenly at t = 0: the step load
 * excites every mode of the loaded end at once, so an integrator that
 * cannot follow the stiffest modes at that dt shows it within the run, and
 * nothing else disturbs the beam. The load scales with the stiffness (the
 * beam scene's 0.075 at msm ks 180 and fem E 3000), so every cell asks for
 * the same small static deflection (about 1% of L) and a failure is the
 * integrator's, not a physically huge deformation; sm's, pbd-stvk's and
 * xpbd-stvk's load is fixed. Unit node masses (node_mass = 1, as the
 * thesis's mass-spring demo and table 3.5), the thesis's other parameters.
 * Every cell is judged by the simulation driver's own detector
 * (tb_sim_step: NaN/inf, velocity bound, energy growth, and inverted
 * elements, which is on here), checked every step.
 * For msm the explicit bound of one spring, dt < 2 sqrt(m / k) (symplectic
 * Euler, m the smallest node mass, k = ks), is drawn on the map; the
 * largest stable dt per ks is bisected and set beside it and beside
 * linearised bounds of the whole mesh at rest (power iteration on M^-1 K
 * and M^-1 C: symplectic Euler on m x'' + c x' + k x = 0 is stable iff
 * h^2 k / m + 2 h c / m < 4).
 *
 * Part 2, large deformations (suites/suite_deform.c, scenes in bench/scene_deform.c): every model x
 * {stretch 100%, twist 180 deg, crush 50%} of a 4 x 1 x 1 beam, ramped, held, let go: inverted tets
 * and volume change at the peak, inverted tets and the residual displacement after recovery.
 * Inversion checking is off there (inverted tets are counted, not a stop); NaN/inf, velocity and
 * energy growth still stop a run, printed as `unstable (reason)`.
 *
 * Part 3 (suites/suite_stability_vvs.c): msm-vvs over ks x kd at dt 0.01 on
 * the pressed sphere, quasi-static and Euler, against Bao 2006's region. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "stability_priv.h"
#include "core/tb_rng.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "scenes/tb_sim.h"

/* ---- the models and their stiffness axes ---- */
const tb_stab_model tb_stab_models[] = {
    {"msm", "ks", "spring stiffness ks (N/m)", 10, 1e6, 1, 180, 0, NULL, NULL, 0},
    {"fem", "E", "Young modulus E (Pa)", 10, 1e6, 1, 3000, 0, NULL, NULL, 0},
    {"fem-corot", "E", "Young modulus E (Pa)", 10, 1e6, 1, 3000, 0, NULL, NULL, 0},
    {"sm", "alpha", "shape-matching stiffness alpha (dimensionless)", 0.05, 1, 0, 0, 0, NULL, NULL,
     0},
    /* PBD's stiffness is k, the iterations and dt (E does not enter): two maps */
    {"pbd-stvk", "k", "PBD stiffness k (dimensionless)", 0.05, 1, 0, 0, 0, NULL, NULL, 0},
    {"pbd-stvk", "iterations", "Gauss-Seidel iterations per step", 1, 100, 1, 0, 1,
     "pbd-stvk-iterations", NULL, 0},
    /* XPBD's E is the material's (the fem maps' axis); its iterations are the solver's */
    {"xpbd-stvk", "iterations", "Gauss-Seidel iterations per step", 1, 100, 1, 0, 1, NULL, NULL, 0},
    /* Bullet 3.24's peers: bullet-fem's three forces over E, as fem; btSoftBody
     * over its link stiffness kLST, load fixed as pbd-stvk's */
    {"bullet-fem", "E", "Young modulus E (Pa)", 10, 1e6, 1, 3000, 0, "bullet-fem-neohookean",
     "force=neohookean", 1},
    {"bullet-fem", "E", "Young modulus E (Pa)", 10, 1e6, 1, 3000, 0, "bullet-fem-linear",
     "force=linear", 1},
    {"bullet-fem", "E", "Young modulus E (Pa)", 10, 1e6, 1, 3000, 0, "bullet-fem-corotated",
     "force=corotated", 1},
    {"bullet-softbody", "stiffness", "link stiffness kLST (dimensionless)", 0.05, 1, 0, 0, 0, NULL,
     NULL, 1},
};
const int tb_stab_nmodels = (int)(sizeof tb_stab_models / sizeof tb_stab_models[0]);

const char *tb_stab_tag(const tb_stab_model *m) { return m->tag ? m->tag : m->name; }

int tb_stab_deform_runs(const tb_stab_model *m, const char *only) {
  if (m->peer) return 0; /* the Bullet peers: maps only */
  for (const tb_stab_model *e = tb_stab_models; e < m; e++)
    if (!strcmp(e->name, m->name)) return 0; /* an earlier map of the same model */
  return !only || !strcmp(only, m->name);
}
#define NMAPS tb_stab_nmodels
#define maps tb_stab_models

#define TIP_LOAD 0.075 /* the beam scene's default tip load */
#define NODE_MASS TB_STAB_NODE_MASS
#define DT_LO 1e-4
#define DT_HI 0.1
/* A cell runs the grid's simulated time or this many steps when that is
 * longer: at dt 0.1, 0.5 s is 5 steps, too few for a growing mode to show
 * (msm at ks 10, dt 0.1 is caught after 11 steps). */
#define MIN_STEPS 50

const char *const tb_stab_status_names[ST_COUNT] = {
    "stable",     "NaN or inf", "energy growth", "inverted elements", "velocity beyond bound",
    "step failed"};

/* ---- a growing text buffer for CSV bodies ---- */

void tb_stab_text_add(tb_stab_text *b, const char *fmt, ...) {
  for (int tries = 0; tries < 2 && !b->bad; tries++) {
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(b->s ? b->s + b->len : NULL, b->s ? b->cap - b->len : 0, fmt, ap);
    va_end(ap);
    if (n < 0) {
      b->bad = 1;
      return;
    }
    if (b->s && b->len + (size_t)n < b->cap) {
      b->len += (size_t)n;
      return;
    }
    size_t cap = 2 * (b->cap + (size_t)n) + 256;
    char *p = realloc(b->s, cap);
    if (!p) {
      b->bad = 1;
      return;
    }
    b->s = p, b->cap = cap;
  }
}

/* ---- one run ---- */

int tb_stab_classify(const char *reason) {
  if (!strncmp(reason, "NaN", 3)) return ST_NAN;
  if (!strncmp(reason, "energy", 6)) return ST_ENERGY;
  if (!strncmp(reason, "inverted", 8)) return ST_INVERTED;
  if (!strncmp(reason, "velocity", 8)) return ST_VELOCITY;
  return ST_FAILED;
}

void tb_stab_run(tb_sim *s, tb_stab_cell *c) {
  long n = lround(s->def.duration / s->def.dt);
  c->code = ST_STABLE, c->t = 0, c->reason[0] = 0;
  for (long k = 0; k < n; k++) {
    tb_error e;
    tb_progress_tick("dt %g: step %ld/%ld", s->def.dt, k + 1, n);
    if (!tb_sim_step(s, &e)) continue;
    if (!s->health.ok) {
      c->code = tb_stab_classify(s->health.reason);
      snprintf(c->reason, sizeof c->reason, "%s", s->health.reason);
    } else {
      c->code = ST_FAILED;
      snprintf(c->reason, sizeof c->reason, "%.199s", e.msg);
    }
    break;
  }
  c->t = s->t;
}

static tb_settings model_def(const tb_stab_model *mm, double stiffness, tb_error *err, int *bad) {
  tb_settings md;
  tb_settings_init(&md);
  *bad = tb_settings_setd(&md, "node_mass", NODE_MASS, err) ||
         tb_settings_setd(&md, mm->key, stiffness, err) ||
         (mm->kvs && tb_settings_set(&md, mm->kvs, err)) ||
         tb_model_check_settings(mm->name, &md, err);
  return md;
}

/* One map cell: the beam scene at (dt, stiffness); -1 only when the scene
 * cannot be built (a bad setting), with err. */
static int map_cell(const tb_mesh *mesh, const tb_stab_model *mm, int cells, double dt,
                    double stiffness, double duration, tb_stab_cell *c, tb_error *err) {
  int bad;
  tb_settings md = model_def(mm, stiffness, err, &bad);
  if (bad) return -1;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  if (duration < MIN_STEPS * dt) duration = MIN_STEPS * dt;
  sd.dt = dt, sd.duration = duration, sd.release = duration, sd.nodes = cells;
  sd.amplitude = mm->ref > 0 ? TIP_LOAD * stiffness / mm->ref : TIP_LOAD;
  sd.inversion = 1;    /* inverted elements are a failure on the map */
  sd.energy_every = 1; /* the energy checked every step: the first detector to fire names it */
  sd.seed = 1;
  tb_sim s;
  if (tb_sim_create(&s, "beam", &sd, mm->name, &md, mesh, err)) return -1;
  tb_stab_run(&s, c);
  tb_sim_destroy(&s);
  return 0;
}

/* ---- msm: linearised bounds of the whole mesh at rest ---- */

double tb_stab_largest_eigen(const tb_sim *s, const int *edges, int ne, int springs,
                             uint64_t seed) {
  int n = s->mesh.nv;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)n), *y = malloc(sizeof(tb_vec3) * (size_t)n);
  char *fixed = calloc((size_t)n, 1);
  double lambda = NAN;
  if (!x || !y || !fixed) goto done;
  for (int k = 0; k < s->nanchor; k++) fixed[s->anchor[k]] = 1;
  tb_rng r = tb_rng_seed(seed);
  for (int i = 0; i < n; i++)
    x[i] =
        fixed[i] ? tb_v3(0, 0, 0) : tb_v3(tb_rng_normal(&r), tb_rng_normal(&r), tb_rng_normal(&r));
  for (int it = 0; it < 400; it++) {
    double norm = 0;
    for (int i = 0; i < n; i++) norm += tb_dot(x[i], x[i]);
    norm = sqrt(norm);
    if (!(norm > 0)) break;
    for (int i = 0; i < n; i++)
      x[i] = tb_scale(x[i], 1.0 / (norm * sqrt(s->mass[i]))), y[i] = tb_v3(0, 0, 0);
    for (int e = 0; e < ne; e++) { /* y = A M^-1/2 x */
      int i = edges[2 * e], j = edges[2 * e + 1];
      tb_vec3 d = tb_sub(x[i], x[j]), f = d;
      if (springs) {
        tb_vec3 u = tb_normalize(tb_sub(s->mesh.x[j], s->mesh.x[i]));
        f = tb_scale(u, tb_dot(u, d));
      }
      y[i] = tb_add(y[i], f), y[j] = tb_sub(y[j], f);
    }
    lambda = 0;
    for (int i = 0; i < n; i++) {
      y[i] = fixed[i] ? tb_v3(0, 0, 0) : tb_scale(y[i], 1.0 / sqrt(s->mass[i]));
      x[i] = tb_scale(x[i], sqrt(s->mass[i])); /* back to the unit vector */
      lambda += tb_dot(x[i], y[i]);
    }
    tb_vec3 *t = x;
    x = y, y = t;
  }
done:
  free(x), free(y), free(fixed);
  return lambda;
}

/* ---- part 1: the maps ---- */

/* The map's model with its further settings: "bullet-fem (force=linear)". */
static const char *who(const tb_stab_model *mm, char *buf, size_t cap) {
  snprintf(buf, cap, "%s%s%s%s", mm->name, mm->kvs ? " (" : "", mm->kvs ? mm->kvs : "",
           mm->kvs ? ")" : "");
  return buf;
}

typedef struct grid {
  int ndt, nk, nmesh;
  double dt[16], k[16];
  int cells[3];
  double duration;
  int bisect; /* msm bisection steps */
} grid;

static grid make_grid(const tb_suite_opts *o) {
  grid g;
  memset(&g, 0, sizeof g);
  double dlo = DT_LO;
  if (o->scale < 1) { /* smoke: 3 x 3, short runs */
    g.ndt = 3, g.nk = 3, g.nmesh = 1, g.cells[0] = 10, g.duration = 0.2, g.bisect = 2, dlo = 1e-3;
  } else if (o->full) {
    g.ndt = 12, g.nk = 12, g.nmesh = 3, g.duration = 0.5, g.bisect = 8;
    g.cells[0] = 10, g.cells[1] = 20, g.cells[2] = 40;
  } else {
    g.ndt = 6, g.nk = 6, g.nmesh = 1, g.cells[0] = 10, g.duration = 0.5, g.bisect = 6;
  }
  for (int i = 0; i < g.ndt; i++) g.dt[i] = dlo * pow(DT_HI / dlo, (double)i / (g.ndt - 1));
  return g;
}

/* The Bullet peers' grid: --full's as every map's; quick mode 3 dt (1e-3,
 * 1e-2, 0.1) x 3 stiffnesses over 0.1 s (at least MIN_STEPS steps), as
 * Bullet's step costs 10-100 times ours (a few seconds per map). */
static grid peer_grid(const tb_suite_opts *o) {
  grid g = make_grid(o);
  if (o->full || o->scale < 1) return g;
  g.ndt = 3, g.nk = 3, g.duration = 0.1;
  for (int i = 0; i < g.ndt; i++) g.dt[i] = 1e-3 * pow(10, i);
  return g;
}

static void stiffness_axis(const grid *g, const tb_stab_model *mm, double *k) {
  for (int i = 0; i < g->nk; i++) {
    double u = (double)i / (g->nk - 1);
    k[i] = mm->logy ? mm->lo * pow(mm->hi / mm->lo, u) : mm->lo + (mm->hi - mm->lo) * u;
    /* whole numbers, strictly increasing (1, 1.5, 2.3 -> 1, 2, 3) */
    if (mm->integer) k[i] = i && round(k[i]) <= k[i - 1] ? k[i - 1] + 1 : round(k[i]);
  }
}

/* msm's bounds for row r of its map: the largest stable dt bisected between
 * the grid's last stable and first unstable dt (b[0], b[1]: lo, hi after
 * the halvings; 0 when none on the grid), 2 sqrt(m / k) (b[2]) and the
 * mesh's linearised bounds without and with kd (b[3], b[4]). */
#define MSM_BOUNDS 5
static int msm_row_bounds(const grid *g, const tb_mesh *mesh, int cells, int r,
                          const tb_stab_cell *row, const int *edges, int ne, uint64_t seed,
                          double *b, tb_error *err) {
  const tb_stab_model *mm = &maps[0];
  double k = g->k[r];
  int last = -1;
  while (last + 1 < g->ndt && row[last + 1].code == ST_STABLE) last++;
  double lo = last >= 0 ? g->dt[last] : 0, hi = last + 1 < g->ndt ? g->dt[last + 1] : 0;
  for (int it = 0; lo > 0 && hi > 0 && it < g->bisect; it++) {
    double mid = sqrt(lo * hi);
    tb_stab_cell c;
    if (map_cell(mesh, mm, cells, mid, k, g->duration, &c, err)) return -1;
    if (c.code == ST_STABLE)
      lo = mid;
    else
      hi = mid;
  }
  /* the mesh's linearised bounds (a sim only for its masses and anchors) */
  int bad;
  tb_settings md = model_def(mm, k, err, &bad);
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.nodes = cells, sd.seed = 1;
  tb_sim s;
  if (bad || tb_sim_create(&s, "beam", &sd, "msm", &md, mesh, err)) return -1;
  double kd = 0;
  tb_model_setting("msm", &md, "kd", &kd);
  double lk = k * tb_stab_largest_eigen(&s, edges, ne, 1, seed),
         lc = kd * tb_stab_largest_eigen(&s, edges, ne, 0, seed);
  double mmin = s.mass[0];
  for (int i = 1; i < s.mesh.nv; i++) mmin = fmin(mmin, s.mass[i]);
  tb_sim_destroy(&s);
  double hk = 2 / sqrt(lk);
  b[0] = lo, b[1] = hi, b[2] = 2 * sqrt(mmin / k), b[3] = hk;
  b[4] = lc > 0 ? (-lc + sqrt(lc * lc + 4 * lk)) / lk : hk;
  return 0;
}

/* The msm table: per ks, the largest stable dt (bisected) beside 2 sqrt(m / k)
 * and the mesh's linearised bounds (bounds: MSM_BOUNDS per row; a row
 * another shard ran has NaN there). */
static void msm_bounds(tb_suite *su, const grid *g, int cells, const tb_stab_cell *map,
                       const double *bounds, tb_stab_text *csv) {
  static const char *cols[] = {"ks",
                               "largest stable dt (grid)",
                               "first unstable dt (grid)",
                               "largest stable dt (bisected)",
                               "2 sqrt(m/k)",
                               "mesh, linearised: 2/sqrt(lambda_K) (kd = 0)",
                               "mesh, linearised, with kd (lower estimate)",
                               "bisected / 2 sqrt(m/k)"};
  char title[160];
  snprintf(title, sizeof title,
           "msm, beam with %d cells along x: largest stable dt per ks against the explicit bound",
           cells);
  char name[32];
  snprintf(name, sizeof name, "msm_bound_n%d", cells);
  tb_table *t = tb_table_new(name, title, 8, cols);
  for (int r = 0; r < g->nk; r++) {
    double k = g->k[r];
    const double *b = bounds + MSM_BOUNDS * r;
    int last = -1;
    while (last + 1 < g->ndt && map[r * g->ndt + last + 1].code == ST_STABLE) last++;
    double lo = b[0], hi = b[1], single = b[2], hk = b[3], hkc = b[4];
    tb_table_row(t);
    tb_table_cell(t, "%.3g", k);
    if (last >= 0)
      tb_table_cell(t, "%.3g", g->dt[last]);
    else
      tb_table_numf(t, NAN, "< %.3g", g->dt[0]); /* none on the grid: empty in the CSV */
    if (hi > 0)
      tb_table_cell(t, "%.3g", g->dt[last + 1]);
    else
      tb_table_numf(t, NAN, "none (> %.3g)", g->dt[g->ndt - 1]);
    if (lo > 0 && hi > 0)
      tb_table_cell(t, "%.3g", lo);
    else
      tb_table_cell(t, "-");
    tb_table_cell(t, "%.3g", single);
    tb_table_cell(t, "%.3g", hk);
    tb_table_cell(t, "%.3g", hkc);
    if (lo > 0 && hi > 0)
      tb_table_cell(t, "%.2f", lo / single);
    else
      tb_table_cell(t, "-");
    tb_stab_text_add(csv, "%d,%.6g,%.6g,%.6g,%.6g,%.6g\n", cells, k, lo > 0 && hi > 0 ? lo : NAN,
                     single, hk, hkc);
    char bname[96]; /* the bounds as counters (NAN: none on the grid) */
    snprintf(bname, sizeof bname, "msm_bounds/cells:%d/ks:%.6g", cells, k);
    tb_suite_counter(su, bname, "largest_stable_dt", last >= 0 ? g->dt[last] : NAN);
    tb_suite_counter(su, bname, "first_unstable_dt", hi > 0 ? g->dt[last + 1] : NAN);
    tb_suite_counter(su, bname, "bisected_dt", lo > 0 && hi > 0 ? lo : NAN);
    tb_suite_counter(su, bname, "single_spring_dt", single);
    tb_suite_counter(su, bname, "linearised_dt", hk);
    tb_suite_counter(su, bname, "linearised_kd_dt", hkc);
  }
  tb_suite_table(su, t);
  double kd_default = 0;
  tb_model_setting("msm", NULL, "kd", &kd_default);
  tb_suite_note(su,
                "The one-spring bound 2 sqrt(m/k) (m = %g, the smallest node mass) is optimistic "
                "for a tet mesh: a node hangs on many springs, so the stiffest mode of the mesh, "
                "lambda_max(M^-1 K), is several times ks / m, and the Kelvin dampers "
                "kd (v_j - v_i) add their own limit (symplectic Euler on m x'' + c x' + k x = 0 "
                "is stable iff h^2 k / m + 2 h c / m < 4): with kd %g the damping, not the "
                "springs, limits dt at small ks. The linearised columns are power iterations on "
                "the mesh at rest with the held face fixed; the bisected dt (%d halvings on a log "
                "scale between the grid's last stable and first unstable dt, the same run and "
                "detector as the cells) should lie between the with-kd estimate (a lower bound: "
                "the worst K and C modes taken together) and the kd = 0 one.",
                NODE_MASS, kd_default, g->bisect);
}

/* Row r of a map (one stiffness, every dt) as a case of `reproduce --shard`:
 * its cells into row[0 .. ndt) and, for msm (b not NULL), its bounds into
 * b. 1: the row is known here; 0: another shard runs it; -1: a setup error. */
static int map_row(tb_suite *su, const grid *g, const tb_stab_model *mm, const tb_mesh *mesh,
                   int cells, int r, const int *edges, int ne, uint64_t seed, tb_stab_cell *row,
                   double *b, tb_error *err) {
  char key[160];
  snprintf(key, sizeof key, "map/%s/cells:%d/%s:%.6g", tb_stab_tag(mm), cells, mm->key, g->k[r]);
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c), nb = b ? MSM_BOUNDS : 0;
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    for (int j = 0; j < g->ndt; j++)
      if (map_cell(mesh, mm, cells, g->dt[j], g->k[r], g->duration, &row[j], err)) return -1;
    if (b && msm_row_bounds(g, mesh, cells, r, row, edges, ne, seed, b, err)) return -1;
    for (int j = 0; j < g->ndt; j++) {
      c.v[2 * j] = row[j].code, c.v[2 * j + 1] = row[j].t;
      snprintf(c.t[j], sizeof c.t[j], "%s", row[j].reason);
    }
    for (int q = 0; q < nb; q++) c.v[2 * g->ndt + q] = b[q];
    c.nv = 2 * g->ndt + nb, c.nt = g->ndt;
    tb_suite_case_done(su, &c);
    return 1;
  }
  if (c.nv != 2 * g->ndt + nb || c.nt > g->ndt)
    return tb_error_set(err, "stability", 0, "case %s: %d numbers, not %d", key, c.nv,
                        2 * g->ndt + nb);
  for (int j = 0; j < g->ndt; j++) {
    row[j].code = (int)c.v[2 * j], row[j].t = c.v[2 * j + 1];
    snprintf(row[j].reason, sizeof row[j].reason, "%.199s", c.t[j]);
  }
  for (int q = 0; q < nb; q++) b[q] = c.v[2 * g->ndt + q];
  return 1;
}

/* The map of one model on one mesh: a table, CSV rows into csv, the chart;
 * each row a case (map_row). */
static int map_one(tb_suite *su, const tb_suite_opts *o, grid *g, const tb_stab_model *mm,
                   const tb_mesh *mesh, int cells, tb_stab_text *csv, tb_stab_text *bcsv,
                   int *counts, tb_error *err) {
  stiffness_axis(g, mm, g->k);
  tb_stab_cell *map = calloc((size_t)(g->nk * g->ndt), sizeof *map);
  if (!map) return tb_error_set(err, "stability", 0, "out of memory");
  const char **cols = calloc((size_t)g->ndt + 1, sizeof *cols);
  char(*heads)[32] = calloc((size_t)g->ndt, sizeof *heads);
  if (!cols || !heads) {
    free(map), free(cols), free(heads);
    return tb_error_set(err, "stability", 0, "out of memory");
  }
  cols[0] = mm->key;
  for (int j = 0; j < g->ndt; j++) {
    snprintf(heads[j], sizeof heads[j], "dt %.3g s", g->dt[j]);
    cols[j + 1] = heads[j];
  }
  char name[48], title[320], wb[96];
  snprintf(name, sizeof name, "map_%s_n%d", tb_stab_tag(mm), cells);
  snprintf(title, sizeof title,
           "%s over %s, beam with %d cells along x (%d nodes): stable or unstable (reason, time) "
           "over %g s or %d steps",
           who(mm, wb, sizeof wb), mm->key, cells, mesh->nv, g->duration, MIN_STEPS);
  tb_table *t = tb_table_new(name, title, g->ndt + 1, cols);
  int rc = 0, msm = mm == &maps[0], *edges = NULL, ne = 0;
  double *bounds = msm ? malloc(sizeof(double) * MSM_BOUNDS * (size_t)g->nk) : NULL;
  if (msm && (!bounds || (ne = tb_mesh_edges(mesh, &edges)) < 0))
    rc = tb_error_set(err, "stability", 0, "out of memory");
  for (int q = 0; bounds && q < MSM_BOUNDS * g->nk; q++) bounds[q] = NAN;
  for (int r = 0; r < g->nk && !rc; r++) {
    tb_table_row(t);
    tb_table_cell(t, "%.3g", g->k[r]);
    int known = map_row(su, g, mm, mesh, cells, r, edges, ne, o->seed, map + r * g->ndt,
                        msm ? bounds + MSM_BOUNDS * r : NULL, err);
    if (known < 0) rc = -1;
    for (int j = 0; j < g->ndt && known > 0; j++) {
      tb_stab_cell *c = &map[r * g->ndt + j];
      counts[c->code]++;
      char bname[128]; /* counters: stable 1/0, the detector's code, when it tripped */
      snprintf(bname, sizeof bname, "map/%s/cells:%d/%s:%.6g/dt:%.6g",
               mm->kvs ? tb_stab_tag(mm) : mm->name, cells, mm->key, g->k[r], g->dt[j]);
      tb_suite_counter(su, bname, "stable", c->code == ST_STABLE);
      tb_suite_counter(su, bname, "status_code", c->code);
      if (c->code != ST_STABLE) tb_suite_counter(su, bname, "unstable_at_s", c->t);
      if (c->code == ST_STABLE)
        tb_table_cell(t, "stable");
      else
        tb_table_cell(t, "unstable (%s, t %.3g)", tb_stab_status_names[c->code], c->t);
      char detail[200];
      snprintf(detail, sizeof detail, "%s", c->reason);
      for (char *p = detail; *p; p++)
        if (*p == ',' || *p == '"') *p = ';';
      tb_stab_text_add(csv, "%.6g,%.6g,%d,%d,%.6g,%s\n", g->dt[j], g->k[r], c->code, cells, c->t,
                       detail);
    }
  }
  free(cols), free(heads), free(edges);
  tb_suite_table(su, t);
  if (!rc && msm) msm_bounds(su, g, cells, map, bounds, bcsv);
  free(map), free(bounds);
  return rc;
}

static int maps_part(tb_suite *su, const tb_suite_opts *o, const char *only, tb_error *err) {
  grid g0 = make_grid(o), gp = peer_grid(o);
  long done = 0, total = 0; /* the maps run, one item a mesh */
  for (int m = 0; m < NMAPS; m++)
    total += !only || !strcmp(only, maps[m].name) ? (maps[m].peer ? gp : g0).nmesh : 0;
  for (int m = 0; m < NMAPS; m++) {
    const tb_stab_model *mm = &maps[m];
    if (only && strcmp(only, mm->name)) continue;
    grid g = mm->peer ? gp : g0;
    tb_stab_text csv = {0}, bcsv = {0};
    char wb[96];
    int counts[ST_COUNT] = {0}, rc = 0;
    tb_clock clock = tb_clock_start();
    for (int q = 0; q < g.nmesh && !rc; q++) {
      tb_progress("stability maps", done++, total);
      tb_sim_def sd;
      tb_sim_def_init(&sd);
      sd.nodes = g.cells[q];
      tb_mesh mesh;
      if (tb_sim_mesh("beam", &sd, &mesh, err)) {
        rc = -1;
        break;
      }
      rc = map_one(su, o, &g, mm, &mesh, g.cells[q], &csv, &bcsv, counts, err);
      tb_mesh_free(&mesh);
    }
    if (rc || csv.bad || bcsv.bad) {
      free(csv.s), free(bcsv.s);
      return rc ? -1 : tb_error_set(err, "stability", 0, "out of memory");
    }
    double wall_ms, cpu_ms;
    tb_clock_ms(&clock, &wall_ms, &cpu_ms);
    tb_suite_note(su,
                  "%s over %s: %d cells stable, %d NaN or inf, %d energy growth, %d inverted "
                  "elements, %d velocity beyond bound, %d failed steps (%.1f s of wall time, "
                  "%.1f s of CPU time, one thread, for the map%s).",
                  who(mm, wb, sizeof wb), mm->key, counts[ST_STABLE], counts[ST_NAN],
                  counts[ST_ENERGY], counts[ST_INVERTED], counts[ST_VELOCITY], counts[ST_FAILED],
                  wall_ms * 1e-3, cpu_ms * 1e-3, mm == &maps[0] ? " and its bisections" : "");
    char csvname[48];
    snprintf(csvname, sizeof csvname, "map_%s.csv", tb_stab_tag(mm));
    rc = tb_suite_write_data(su, csvname, "dt,stiffness,status,cells,t,reason", csv.s, err);
    if (!rc && bcsv.s)
      rc = tb_suite_write_data(su, "msm_bound.csv",
                               "cells,ks,largest stable dt (bisected),2 sqrt(m/k),"
                               "mesh linearised kd=0,mesh linearised with kd",
                               bcsv.s, err);
    free(csv.s), free(bcsv.s);
    /* the msm chart also draws the bisected bounds (a full path for gnuplot) */
    char bfile[1000] = "";
    if (mm == &maps[0] && snprintf(bfile, sizeof bfile, "%s/stability/msm_bound.csv", o->results) >=
                              (int)sizeof bfile)
      bfile[0] = 0;
    if (strchr(bfile, '\'')) bfile[0] = 0;
    for (int q = 0; q < g.nmesh && !rc; q++) {
      char base[48], vars[1600];
      snprintf(base, sizeof base, "map_%s_n%d", tb_stab_tag(mm), g.cells[q]);
      snprintf(vars, sizeof vars,
               "title='%s, %s x dt: stability over %g s (at least %d steps), beam with %d cells "
               "along x'; ylabel='%s'; logy=%d; cells=%d; psize=%g; bound=%d; mass=%g%s%s%s",
               who(mm, wb, sizeof wb), mm->key, g.duration, MIN_STEPS, g.cells[q], mm->label,
               mm->logy, g.cells[q], g.ndt > 8 ? 1.8 : 3.0, mm == &maps[0], NODE_MASS,
               bfile[0] ? "; boundfile='" : "", bfile, bfile[0] ? "'" : "");
      rc = tb_suite_chart_vars(su, "chart_map.gp", csvname, base, vars, err);
      if (!rc)
        tb_suite_caption(su, base,
                         "%s on a beam with %d cells along x: stable or why not (NaN, energy "
                         "growth, inversion, velocity) over time step and %s%s",
                         who(mm, wb, sizeof wb), g.cells[q], mm->label,
                         mm == &maps[0] ? "; the line: the bisected largest stable time step" : "");
    }
    if (rc) return -1;
  }
  tb_progress("stability maps", total, total);
  return 0;
}

int tb_suite_stability(const tb_suite_opts *o) {
  const char *only = o->model; /* every map of that model */
  if (only) {
    int found = 0;
    char names[200] = "";
    for (int m = 0; m < NMAPS; m++) {
      found |= !strcmp(only, maps[m].name);
      if (tb_stab_deform_runs(&maps[m], NULL))
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", m ? ", " : "",
                 maps[m].name);
    }
    found |= !strcmp(only, TB_STAB_VVS);
    if (!found) {
      fprintf(stderr, "stability: unknown model '%s' (%s, %s)\n", only, names, TB_STAB_VVS);
      return 1;
    }
  }
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/stability", o->results) >= (int)sizeof dir) return 1;
  tb_suite *s = tb_suite_begin(
      dir, "stability", "Stability maps (dt x stiffness) and large deformations", o->seed, &err);
  if (!s) return fprintf(stderr, "stability: %s\n", err.msg), 1;
  grid g = make_grid(o);
  tb_suite_note(
      s,
      "Stability maps: the `beam` scene (cantilever 10 x 1 x 1 held at x = 0) under a "
      "tip load applied suddenly at t = 0, run for %g s (or %d steps when that is longer) per "
      "cell on a %d x %d grid "
      "(dt log-spaced %.3g..%.3g s; msm ks and fem/fem-corot E log-spaced 10..1e6, "
      "sm alpha linear 0.05..1; pbd-stvk k linear 0.05..1 and, in a second map, its "
      "iterations; xpbd-stvk iterations; iterations log-spaced 1..100, rounded). The load is "
      "0.075 x stiffness / (180 for msm ks, "
      "3000 for E): the same static deflection (about 1%% of L) in every cell, so a "
      "failure is the integrator's; sm's, pbd-stvk's and xpbd-stvk's load is 0.075 (xpbd-stvk "
      "at E 3000; pbd-stvk's stiffness is set by k, the iterations and dt, not E). Unit node "
      "masses, the thesis's other parameters (kd 5, nu 0.3, Rayleigh b 0.02, sm quadratic, 50 "
      "regions of radius 1, beta 0.63), the position-based models' defaults (nu 0.4, damping "
      "2, 5 iterations, k 0.4, StVK; pbd-stvk BDF2, xpbd-stvk Euler). Each cell is judged by "
      "the simulation driver's detector, every step: NaN or inf, velocity beyond 100 x size / "
      "duration, energy growth beyond 100 x the scene's reference energy, and "
      "inverted elements (inversion checking ON for the maps). A cell reads `stable` "
      "or `unstable (reason, t at which it was detected)`; map_<model>.csv (and "
      "map_pbd-stvk-iterations.csv) has the detector's full words.",
      g.duration, MIN_STEPS, g.nk, g.ndt, g.dt[0], g.dt[g.ndt - 1]);
  grid gp = peer_grid(o);
  tb_suite_note(
      s,
      "Bullet 3.24's peers: bullet-fem with each of Bullet's forces (neohookean, "
      "linear, corotated) over E as fem (the same scaled load, stiffness damping 0.02), and "
      "bullet-softbody over its link stiffness kLST (load 0.075, 5 position iterations), on "
      "a %d x %d grid (dt %.3g..%.3g s, %g s or %d steps per cell), with the same unit node "
      "masses and detector; not in part 2. Bullet's corotated force has no force differential, "
      "so its implicit step is explicit in the elasticity: expect it unstable wherever dt is "
      "beyond the explicit limit of the stiffest tets (shown as the detector reports it).",
      gp.nk, gp.ndt, gp.dt[0], gp.dt[gp.ndt - 1], gp.duration, MIN_STEPS);
  int deform = 0, vvs = !only || !strcmp(only, TB_STAB_VVS);
  for (int m = 0; m < NMAPS; m++) deform |= tb_stab_deform_runs(&maps[m], only);
  /* the runs are small beams and a sphere: one thread, so that a busy machine's
   * barriers do not stall them (a parallel model's barrier per colour waits a time
   * slice when the cores are shared); the answers do not depend on it */
  int threads = tb_threads_setting();
  tb_threads_set(1);
  int failed = maps_part(s, o, only, &err) || (deform && tb_stab_deform(s, o, only, &err)) ||
               (vvs && tb_stab_vvs(s, o, &err));
  tb_threads_set(threads);
  if (failed) fprintf(stderr, "stability: %s\n", err.msg);
  if (tb_suite_end(s, &err)) fprintf(stderr, "stability: %s\n", err.msg), failed = 1;
  return failed;
}
