/* Fidelity metrics (measure/tb_fidelity.h): a scene's static problem posed
 * to the reference solver (reference/tb_reference.h) with the loads the
 * scene gives its models (tb_sim_loads); a model run on the scene until it
 * settles, its surface nodes compared with the reference displacement
 * sampled at their rest positions (normalised by the largest reference
 * displacement), its volume change, the reaction on a prescribed set, the
 * time to settle and what is left after release; and the Pareto front.
 *
 * Settling: every node moves slower than settle_speed (position change per
 * step / dt: also right for quasi-static models, whose velocities are 0)
 * for a window of simulated time long enough that the turning point of an
 * oscillation does not pass for rest (quasi-static models: 3 steps).
 *
 * Reaction of a model on its prescribed driven set: with an energy and a
 * settable state (fem, fem-corot: tb_fem_set_state), the derivative of the
 * energy with respect to moving the whole set (central differences);
 * otherwise the momentum the free nodes gain in the first step after the
 * set is let go: R = -sum m (v+ - v) / dt (exact for symplectic Euler at
 * rest; for shape matching it is the force its dt-dependent stiffness
 * exerts). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_fidelity.h"
#include "core/tb_timer.h"
#include "models/tb_fem.h"
#include "report/tb_results.h"

/* ---- metrics on arrays ---- */

int tb_fid_surface_nodes(const tb_mesh *m, int **out) {
  *out = NULL;
  char *on = calloc((size_t)(m->nv > 0 ? m->nv : 1), 1);
  if (!on) return -1;
  int n = 0;
  for (int k = 0; k < 3 * m->ntri; k++)
    if (m->tri[k] >= 0 && m->tri[k] < m->nv && !on[m->tri[k]]) on[m->tri[k]] = 1, n++;
  *out = malloc(sizeof(int) * (size_t)(n > 0 ? n : 1));
  if (!*out) return free(on), -1;
  n = 0;
  for (int i = 0; i < m->nv; i++)
    if (on[i]) (*out)[n++] = i;
  free(on);
  return n;
}

void tb_fid_disp_error(const tb_vec3 *X, const tb_vec3 *x, const int *idx, int n,
                       const tb_vec3 *uref, double scale, double *rms, double *max) {
  double s2 = 0, mx = 0;
  int bad = n < 1;
  for (int k = 0; k < n; k++) {
    int i = idx[k];
    double e = tb_len(tb_sub(tb_sub(x[i], X[i]), uref[k]));
    s2 += e * e;
    mx = fmax(mx, e);
    bad |= !isfinite(e);
  }
  *rms = bad ? NAN : sqrt(s2 / n) / scale;
  *max = bad ? NAN : mx / scale;
}

int tb_fid_pareto(const double *speed, const double *error, const char *valid, int n, char *on) {
  int count = 0;
  for (int k = 0; k < n; k++) {
    on[k] = valid[k] && isfinite(speed[k]) && isfinite(error[k]);
    for (int j = 0; j < n && on[k]; j++) {
      if (j == k || !valid[j] || !isfinite(speed[j]) || !isfinite(error[j])) continue;
      if (speed[j] >= speed[k] && error[j] <= error[k] &&
          (speed[j] > speed[k] || error[j] < error[k]))
        on[k] = 0;
    }
    count += on[k];
  }
  return count;
}

/* ---- the reference ---- */

static int has_static_problem(const char *scene) {
  return !strcmp(scene, "beam") || !strcmp(scene, "liver-stretch") || !strcmp(scene, "liver-hang");
}

static double volume_of(const tb_mesh *m, const tb_vec3 *x) {
  double v = 0;
  for (int t = 0; t < m->ntet; t++) {
    const int *e = m->tet + 4 * t;
    v += tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]);
  }
  return v;
}

int tb_fid_reference(const char *scene, const tb_sim_def *def, double t_eq, const tb_settings *mset,
                     tb_fid_ref *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  if (!has_static_problem(scene))
    return tb_error_set(err, scene, 0,
                        "no static problem to compare (beam, liver-stretch, liver-hang)");
  snprintf(out->scene, sizeof out->scene, "%s", scene);
  double density, E, nu;
  if (tb_model_check_settings("fem", mset, err)) return -1;
  tb_model_setting("fem", mset, "density", &density);
  tb_model_setting("fem", mset, "E", &E);
  tb_model_setting("fem", mset, "nu", &nu);
  tb_sim s;
  /* the sim only poses the loads: msm is the cheapest model to build (its
   * masses do not enter the loads) */
  if (tb_sim_create(&s, scene, def, "msm", NULL, NULL, err)) return -1;
  int rc = -1;
  char *driven = calloc((size_t)s.mesh.nv, 1);
  if (!driven) {
    tb_error_set(err, scene, 0, "out of memory");
    goto done;
  }
  if (tb_sim_loads(&s, t_eq, err)) goto done;
  if (tb_mesh_copy(&out->mesh, &s.mesh)) {
    tb_error_set(err, scene, 0, "out of memory");
    goto done;
  }
  out->def = s.def, out->t_eq = t_eq;
  tb_ref_problem p;
  memset(&p, 0, sizeof p);
  p.mesh = &out->mesh;
  p.density = density;
  p.gravity = s.gravity;
  p.force = s.force;
  p.nfixed = s.nfixed, p.fixed = s.fixed, p.fixed_x = s.fixed_x;
  tb_ref_def rd = tb_ref_default_def();
  rd.E = E, rd.nu = nu;
  tb_clock c = tb_clock_start();
  out->sol = tb_ref_solve(&p, &rd, err);
  double wall_ms, cpu_ms;
  tb_clock_ms(&c, &wall_ms, &cpu_ms);
  out->seconds = wall_ms * 1e-3, out->cpu_seconds = cpu_ms * 1e-3;
  if (!out->sol) goto done;
  double residual;
  tb_ref_stats(out->sol, &out->iterations, &out->load_steps, &residual);
  const tb_vec3 *x = tb_ref_positions(out->sol);
  for (int i = 0; i < out->mesh.nv; i++) out->umax = fmax(out->umax, tb_dist(x[i], out->mesh.x[i]));
  double v0 = volume_of(&out->mesh, out->mesh.x);
  out->volume_change = (volume_of(&out->mesh, x) - v0) / v0;
  /* the driven set is prescribed (liver-stretch's pulled patch): its reaction */
  int held = s.ndriven > 0;
  for (int k = 0; k < s.ndriven; k++) held &= s.mark[s.driven[k]] != 0, driven[s.driven[k]] = 1;
  if (held) {
    const tb_vec3 *r = tb_ref_reactions(out->sol);
    out->has_reaction = 1;
    for (int k = 0; k < s.nfixed; k++)
      if (driven[s.fixed[k]]) out->reaction = tb_add(out->reaction, r[k]);
  }
  if (!(out->umax > 0)) {
    tb_error_set(err, scene, 0, "the reference does not move (no load?)");
    goto done;
  }
  rc = 0;
done:
  free(driven);
  tb_sim_destroy(&s);
  if (rc) tb_fid_ref_free(out);
  return rc;
}

void tb_fid_ref_free(tb_fid_ref *r) {
  tb_ref_free(r->sol);
  tb_mesh_free(&r->mesh);
  memset(r, 0, sizeof *r);
}

int tb_fid_mesh_make(const tb_fid_ref *ref, const tb_sim_def *def, tb_fid_mesh *out,
                     tb_error *err) {
  memset(out, 0, sizeof *out);
  if (tb_sim_mesh(ref->scene, def, &out->mesh, err)) return -1;
  out->nsurf = tb_fid_surface_nodes(&out->mesh, &out->surf);
  tb_vec3 *pts = out->nsurf > 0 ? malloc(sizeof(tb_vec3) * (size_t)out->nsurf) : NULL;
  out->uref = out->nsurf > 0 ? malloc(sizeof(tb_vec3) * (size_t)out->nsurf) : NULL;
  if (out->nsurf < 1 || !pts || !out->uref) {
    free(pts);
    tb_fid_mesh_free(out);
    return tb_error_set(err, ref->scene, 0, "%s", "the mesh has no surface (or out of memory)");
  }
  for (int k = 0; k < out->nsurf; k++) pts[k] = out->mesh.x[out->surf[k]];
  int rc = tb_ref_sample(ref->sol, pts, out->nsurf, out->uref, err);
  free(pts);
  if (rc) tb_fid_mesh_free(out);
  return rc ? -1 : 0;
}

void tb_fid_mesh_free(tb_fid_mesh *m) {
  tb_mesh_free(&m->mesh);
  free(m->surf), free(m->uref);
  memset(m, 0, sizeof *m);
}

/* ---- a model run ---- */

/* Largest node speed over the last step: |x - px| / dt. */
static double step_speed(const tb_vec3 *x, const tb_vec3 *px, int n, double dt) {
  double m = 0;
  for (int i = 0; i < n; i++) m = fmax(m, tb_dist(x[i], px[i]));
  return m / dt;
}

/* Reaction on the driven set from the energy (models with a settable
 * state); returns 0, or -1 when the model has none. The state is restored. */
static int energy_reaction(tb_sim *s, const tb_vec3 *x, const tb_vec3 *v, tb_vec3 *r) {
  tb_error err;
  double e0 = tb_model_energy(&s->model);
  if (!isfinite(e0) || tb_fem_set_state(&s->model, x, v, &err)) return -1;
  int n = s->mesh.nv;
  tb_vec3 *y = malloc(sizeof(tb_vec3) * (size_t)n);
  if (!y) return -1;
  double h = 1e-6 * s->size, g[3];
  for (int a = 0; a < 3; a++) {
    double e[2];
    for (int sgn = 0; sgn < 2; sgn++) {
      memcpy(y, x, sizeof(tb_vec3) * (size_t)n);
      tb_vec3 d = tb_v3(a == 0, a == 1, a == 2);
      for (int k = 0; k < s->ndriven; k++)
        y[s->driven[k]] = tb_madd(y[s->driven[k]], sgn ? -h : h, d);
      tb_fem_set_state(&s->model, y, NULL, &err);
      e[sgn] = tb_model_energy(&s->model);
    }
    g[a] = (e[0] - e[1]) / (2 * h);
  }
  tb_fem_set_state(&s->model, x, v, &err);
  free(y);
  *r = tb_v3(g[0], g[1], g[2]);
  return 0;
}

typedef struct runner {
  tb_sim s;
  const tb_fid_opts *o;
  double dt, window; /* settle window (simulated s) */
  double speed;      /* the largest node speed of the last step */
  tb_vec3 *px;
  double *cpu, *wall; /* each step's CPU and wall ms */
  long nms, cap;
} runner;

/* One timed step; returns 0, or -1 with err. */
static int timed_step(runner *r, tb_error *err) {
  memcpy(r->px, tb_model_positions(&r->s.model), sizeof(tb_vec3) * (size_t)r->s.mesh.nv);
  tb_clock c = tb_clock_start();
  int rc = tb_sim_step(&r->s, err);
  double wall, cpu;
  tb_clock_ms(&c, &wall, &cpu);
  if (r->nms == r->cap) {
    long cap = r->cap ? 2 * r->cap : 4096;
    double *p = realloc(r->cpu, sizeof(double) * (size_t)cap);
    if (!p) return tb_error_set(err, "fidelity", 0, "out of memory");
    r->cpu = p;
    p = realloc(r->wall, sizeof(double) * (size_t)cap);
    if (!p) return tb_error_set(err, "fidelity", 0, "out of memory");
    r->wall = p, r->cap = cap;
  }
  r->cpu[r->nms] = cpu, r->wall[r->nms++] = wall;
  tb_progress_tick("model run: t = %.2f s", r->s.t);
  return rc;
}

/* Steps until every node has moved slower than settle_speed for the
 * window, from time t_from on;
 * *settled_at: the window's start, NAN when max_time passed first.
 * Returns 0, or -1 (unstable) with err. */
static int settle(runner *r, double t_from, double *settled_at, tb_error *err) {
  double quiet_since = NAN, stop = t_from + r->o->max_time;
  *settled_at = NAN;
  for (;;) {
    if (timed_step(r, err)) return -1;
    double v = r->speed = step_speed(tb_model_positions(&r->s.model), r->px, r->s.mesh.nv, r->dt);
    if (r->s.t < t_from - 1e-9 * r->dt || v >= r->o->settle_speed)
      quiet_since = NAN;
    else if (isnan(quiet_since))
      quiet_since = r->s.t - r->dt;
    if (!isnan(quiet_since) && r->s.t - quiet_since >= r->window - 1e-9 * r->dt) {
      *settled_at = quiet_since;
      return 0;
    }
    if (r->s.t >= stop) return 0;
  }
}

static void unstable(tb_fid_result *out, const char *when, const char *why) {
  out->stable = 0, out->settled = 0;
  /* the sim's message reads "model: unstable at t = ...: reason" */
  const char *p = strstr(why, "unstable ");
  snprintf(out->state, sizeof out->state, "unstable%s (%.160s)", when, p ? p + 9 : why);
}

int tb_fid_run(const tb_fid_ref *ref, const tb_fid_mesh *fm, const char *model,
               const tb_settings *mset, const tb_sim_def *def, const tb_fid_opts *o,
               tb_fid_result *out, tb_error *err) {
  memset(out, 0, sizeof *out);
  out->rms_err = out->max_err = out->volume_change = NAN;
  out->reaction_err = out->settle_time = out->recovery_err = NAN;
  runner r;
  memset(&r, 0, sizeof r);
  r.o = o;
  tb_sim_def sd = *def;
  if (!(sd.dt > 0)) sd.dt = ref->def.dt;
  sd.dt /= o->substeps > 1 ? o->substeps : 1;
  if (tb_sim_create(&r.s, ref->scene, &sd, model, mset, &fm->mesh, err)) return -1;
  double quasistatic = 0; /* 0 for models without the key */
  tb_model_setting(model, mset, "quasistatic", &quasistatic);
  int stretch = !strcmp(ref->scene, "liver-stretch"), rc = -1, n = r.s.mesh.nv;
  r.dt = r.s.def.dt;
  r.window =
      quasistatic != 0 ? 3 * r.dt : fmax(o->window > 0 ? o->window : o->max_time / 20, 10 * r.dt);
  double t_full = stretch ? 0.5 * r.s.def.release : 0; /* the load is complete */
  r.px = malloc(sizeof(tb_vec3) * (size_t)n);
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)n), *v = malloc(sizeof(tb_vec3) * (size_t)n);
  if (!r.px || !x || !v) {
    tb_error_set(err, model, 0, "out of memory");
    goto done;
  }
  rc = 0;
  out->stable = 1;
  tb_error why;
  double at;
  r.s.hold = stretch; /* the pull stays until the model has settled */
  if (settle(&r, t_full, &at, &why)) {
    unstable(out, "", why.msg);
    goto timing;
  }
  out->settled = !isnan(at);
  if (out->settled && quasistatic == 0) out->settle_time = fmax(0, at - t_full);
  const tb_vec3 *xs = tb_model_positions(&r.s.model);
  memcpy(x, xs, sizeof(tb_vec3) * (size_t)n);
  if (o->keep_x) memcpy(o->keep_x, xs, sizeof(tb_vec3) * (size_t)n);
  memcpy(v, tb_model_velocities(&r.s.model), sizeof(tb_vec3) * (size_t)n);
  tb_fid_disp_error(r.s.mesh.x, x, fm->surf, fm->nsurf, fm->uref, ref->umax, &out->rms_err,
                    &out->max_err);
  out->volume_change = tb_sim_measure(&r.s).volume_change;
  if (out->settled)
    snprintf(out->state, sizeof out->state, "settled");
  else
    snprintf(out->state, sizeof out->state,
             "not settled within %.3g s (below %.3g per s for %.3g s; largest node speed at the "
             "end %.3g)",
             o->max_time, o->settle_speed, r.window, r.speed);
  if (!stretch) goto timing;
  /* the reaction on the pulled patch, then let go */
  tb_vec3 react;
  int have = ref->has_reaction && energy_reaction(&r.s, x, v, &react) == 0;
  tb_sim_let_go(&r.s);
  if (timed_step(&r, &why)) {
    unstable(out, " after release", why.msg);
    goto timing;
  }
  if (ref->has_reaction && !have) {
    const tb_vec3 *v1 = tb_model_velocities(&r.s.model);
    react = tb_v3(0, 0, 0);
    for (int i = 0; i < n; i++) react = tb_madd(react, -r.s.mass[i] / r.dt, tb_sub(v1[i], v[i]));
    have = 1;
  }
  if (have) out->reaction_err = tb_dist(react, ref->reaction) / tb_len(ref->reaction);
  if (o->recovery) {
    if (settle(&r, r.s.t, &at, &why)) {
      unstable(out, " after release", why.msg);
      goto timing;
    }
    double left = 0;
    xs = tb_model_positions(&r.s.model);
    for (int k = 0; k < fm->nsurf; k++)
      left = fmax(left, tb_dist(xs[fm->surf[k]], r.s.mesh.x[fm->surf[k]]));
    out->recovery_err = left / ref->umax;
  }
timing:
  out->steps = r.s.steps;
  out->ms_step = tb_stats_of(r.cpu, (int)r.nms).median;
  out->ms_step_wall = tb_stats_of(r.wall, (int)r.nms).median;
done:
  free(r.px), free(r.cpu), free(r.wall), free(x), free(v);
  tb_sim_destroy(&r.s);
  return rc;
}

/* ---- plans ---- */

int tb_fid_equal_masses(const tb_mesh *m, const char *model, tb_settings *mset, tb_error *err) {
  double v = volume_of(m, m->x), density = 0;
  if (tb_model_setting(model, mset, "density", &density))
    return tb_error_set(err, model, 0, "no density setting (or a bad value)");
  if (!(v > 0) || m->nv < 1 || !(density > 0))
    return tb_error_set(err, "masses", 0, "the mesh has no volume (or density <= 0)");
  return tb_settings_setd(mset, "node_mass", density * v / m->nv, err);
}

int tb_fid_masses(const tb_fid_plan *p, const tb_mesh *m, const char *model, tb_settings *mset,
                  tb_error *err) {
  if (p->density_masses) return tb_settings_set(mset, "node_mass=0", err);
  return tb_fid_equal_masses(m, model, mset, err);
}

int tb_fid_plan_for(const char *scene, int level, uint64_t seed, tb_fid_plan *p, tb_error *err) {
  memset(p, 0, sizeof *p);
  tb_sim_def_init(&p->def);
  if (!has_static_problem(scene))
    return tb_error_set(err, scene, 0,
                        "no static problem to compare (beam, liver-stretch, liver-hang)");
  level = level < 0 ? 0 : (level > 2 ? 2 : level);
  p->def.seed = seed ? seed : 1;
  p->def.dt = 0.01;
  p->opts.settle_speed = 1e-3; /* of the reference's largest displacement, per second */
  p->opts.recovery = 1;
  if (!strcmp(scene, "beam")) {
    static const int res[3][4] = {{4, 6, 8, 0}, {10, 20, 40, 0}, {10, 20, 40, 60}};
    static const int ref[3] = {12, 60, 80};
    static const double tmax[3] = {10, 40, 60};
    memcpy(p->res, res[level], sizeof p->res);
    p->nres = level == 2 ? 4 : 3, p->ref_res = ref[level];
    p->def.amplitude = 0.075; /* Euler-Bernoulli tip deflection 0.1 = 1% of L with E = 3000 */
    p->def.drag = 1.0;        /* about critical for the first bending mode */
    p->t_eq = 1.0;
    p->opts.max_time = tmax[level];
    p->opts.window = level ? 2.0 : 1.0;
    p->opts.recovery = 0; /* the load is never taken off */
    p->load = "tip load 0.075 along -z (Euler-Bernoulli deflection 0.1 = 1% of the length)";
  } else if (!strcmp(scene, "liver-hang")) {
    static const int res[3][4] = {{200, 250, 300, 0}, {400, 800, 1206, 0}, {400, 800, 1206, 2400}};
    static const int ref[3] = {400, 2400, 4800};
    static const double tmax[3] = {3, 10, 20};
    memcpy(p->res, res[level], sizeof p->res);
    p->nres = level == 2 ? 4 : 3, p->ref_res = ref[level];
    p->def.drag = 5.0; /* the scene's: near critical for the lowest mode */
    p->t_eq = 1.0;     /* gravity acts from the start */
    p->opts.max_time = tmax[level];
    p->opts.window = 0.5;
    p->opts.recovery = 0; /* gravity is never taken off */
    p->density_masses = 1;
    p->load = "gravity 9.81 along -z, the liver held by a patch of its top surface";
  } else {
    static const int res[3][4] = {{200, 250, 300, 0}, {400, 800, 1206, 0}, {400, 800, 1206, 2400}};
    static const int ref[3] = {400, 2400, 4800};
    static const double tmax[3] = {2, 10, 20};
    memcpy(p->res, res[level], sizeof p->res);
    p->nres = level == 2 ? 4 : 3, p->ref_res = ref[level];
    p->def.amplitude = 0.2; /* 2% of the liver's length */
    p->def.release = 1.0;   /* ramped over 0.5 s, then held until settled */
    p->def.drag = 4.0;
    p->t_eq = 1.0;
    p->opts.max_time = tmax[level];
    p->opts.window = 0.5;
    p->load = "far patch pulled 0.2 (2% of the length) along (1, 0, 0.3), held, then let go";
  }
  return 0;
}
