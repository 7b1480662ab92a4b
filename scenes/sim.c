/* The simulation driver: a scene description (scenes/scene_file.c) with
 * parameter overrides becomes a mesh, a model and resolved node sets; one
 * step is the scene's inputs at t (fixed nodes, forces, prescribed
 * motions), the model's step, contact (scenes/contact.c) and the health
 * check; metrics and VTK frames of the state. */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "meshgen/tb_meshgen.h"
#include "core/tb_paths.h"
#include "sim_priv.h"

/* The built-in scenes: scenes/NAME.ini. */
static const char *const builtin[] = {
    "liver-stretch", "liver-press",    "beam",       "drop",  "beam-stretch",
    "beam-twist",    "beam-crush",     "liver-drop", "slope", "liver-hang",
    "sphere-press",  "sphere-stretch", "steak-cut"};
#define NBUILTIN ((int)(sizeof builtin / sizeof builtin[0]))

const char *const *tb_sim_scene_names(int *count) {
  *count = NBUILTIN;
  return builtin;
}

const char *tb_sim_scene_summary(const char *name) {
  static char summary[NBUILTIN][256];
  for (int i = 0; i < NBUILTIN; i++) {
    if (strcmp(builtin[i], name)) continue;
    if (!summary[i][0]) {
      char path[1024];
      tb_scene_desc d;
      tb_error err;
      tb_sim_scene_path(name, path, sizeof path);
      if (tb_scene_desc_load(&d, path, &err))
        snprintf(summary[i], sizeof summary[i], "(%.200s)", err.msg);
      else {
        snprintf(summary[i], sizeof summary[i], "%s", d.summary);
        tb_scene_desc_free(&d);
      }
    }
    return summary[i];
  }
  return NULL;
}

static int is_builtin(const char *name) {
  for (int i = 0; i < NBUILTIN; i++)
    if (!strcmp(builtin[i], name)) return 1;
  return 0;
}

void tb_sim_scene_path(const char *scene, char *out, size_t cap) {
  if (is_builtin(scene))
    snprintf(out, cap, "%s/scenes/%s.ini", tb_root(), scene);
  else
    snprintf(out, cap, "%s", scene);
}

/* ---- overrides ---- */

void tb_sim_def_init(tb_sim_def *d) {
  memset(d, 0, sizeof *d);
  d->dt = d->duration = d->amplitude = d->release = d->gravity = d->vmax = NAN;
  d->drag = d->energy_factor = d->rest_speed = NAN;
  d->nodes = d->inversion = d->energy_every = d->ground = -1;
}

/* The overrides' fields in tb_scene_param order (int fields flagged). */
static const struct {
  size_t off;
  int is_int;
} fields[TB_P_COUNT] = {
    {offsetof(tb_sim_def, dt), 0},           {offsetof(tb_sim_def, duration), 0},
    {offsetof(tb_sim_def, amplitude), 0},    {offsetof(tb_sim_def, release), 0},
    {offsetof(tb_sim_def, nodes), 1},        {offsetof(tb_sim_def, gravity), 0},
    {offsetof(tb_sim_def, vmax), 0},         {offsetof(tb_sim_def, inversion), 1},
    {offsetof(tb_sim_def, drag), 0},         {offsetof(tb_sim_def, energy_factor), 0},
    {offsetof(tb_sim_def, energy_every), 1}, {offsetof(tb_sim_def, rest_speed), 0},
    {offsetof(tb_sim_def, ground), 1}};

static double get_field(const tb_sim_def *d, int i) {
  const char *p = (const char *)d + fields[i].off;
  if (fields[i].is_int) {
    int n;
    memcpy(&n, p, sizeof n);
    return n < 0 ? NAN : n;
  }
  double x;
  memcpy(&x, p, sizeof x);
  return x;
}

static void put_field(tb_sim_def *d, int i, double x) {
  char *p = (char *)d + fields[i].off;
  if (fields[i].is_int) {
    int n = (int)x;
    memcpy(p, &n, sizeof n);
  } else
    memcpy(p, &x, sizeof x);
}

int tb_sim_def_set(tb_sim_def *def, const char *kv, tb_error *err) {
  const char *eq = strchr(kv, '=');
  if (!eq) return 1;
  char key[32];
  size_t klen = (size_t)(eq - kv);
  if (klen >= sizeof key) return 1;
  memcpy(key, kv, klen), key[klen] = 0;
  int i = tb_scene_param_index(key);
  if (i < 0) return 1;
  char *end;
  errno = 0;
  double x = strtod(eq + 1, &end);
  if (!eq[1] || *end || isnan(x) || (fields[i].is_int && isfinite(x) && x != floor(x)))
    return tb_error_set(err, "--set", 0, "%s: '%s' is not a%s number", key, eq + 1,
                        fields[i].is_int ? " whole" : "");
  if (!(x >= 0 && x <= 1e9)) /* inf, and beyond the largest double, too */
    return tb_error_set(err, "--set", 0, "%s = %s is out of range [0, 1e9]", key, eq + 1);
  put_field(def, i, x);
  return 0;
}

/* ---- building ---- */

#define MAX_STEPS 100000000L /* a run longer than this is refused */

/* Effective parameters: the file's, then the overrides; checked. */
static int resolve_params(tb_sim *s, const tb_sim_def *def, tb_error *err) {
  const char *path = s->desc.path[0] ? s->desc.path : s->desc.name;
  for (int i = 0; i < TB_P_COUNT; i++) {
    s->priv->param[i] = s->desc.param[i];
    double o = def ? get_field(def, i) : NAN;
    if (!isnan(o)) s->priv->param[i] = o;
  }
  double dt = s->priv->param[TB_P_DT], T = s->priv->param[TB_P_DURATION];
  if (!(dt > 0) || !isfinite(dt))
    return tb_error_set(err, path, 0, "dt must be a finite number > 0 (got %g)", dt);
  if (!(T > 0) || !isfinite(T))
    return tb_error_set(err, path, 0, "duration must be a finite number > 0 (got %g)", T);
  if (T / dt > MAX_STEPS)
    return tb_error_set(err, path, 0,
                        "duration / dt = %.3g steps: more than the %ld a run may take (raise dt "
                        "or shorten the duration)",
                        T / dt, MAX_STEPS);
  int vmax_given = s->desc.param_given[TB_P_VMAX] || (def && !isnan(def->vmax));
  if (vmax_given && !(s->priv->param[TB_P_VMAX] > 0))
    return tb_error_set(err, path, 0, "vmax must be > 0 (leave it out for 100 x size / duration)");
  if (s->priv->param[TB_P_RELEASE] > T) s->priv->param[TB_P_RELEASE] = T;
  if (!(s->priv->param[TB_P_ENERGY_FACTOR] > 0))
    return tb_error_set(err, path, 0, "energy_factor must be > 0");
  if (!(s->priv->param[TB_P_ENERGY_EVERY] >= 1))
    return tb_error_set(err, path, 0, "energy_every must be >= 1");
  if (s->priv->param[TB_P_GROUND] != 0 && s->priv->param[TB_P_GROUND] != 1)
    return tb_error_set(err, path, 0, "ground must be 0 (left out) or 1 (the file's)");
  /* the effective overrides, for callers that read s->def */
  tb_sim_def_init(&s->def);
  for (int i = 0; i < TB_P_COUNT; i++) put_field(&s->def, i, s->priv->param[i]);
  s->def.seed = def && def->seed ? def->seed : s->desc.seed;
  return 0;
}

static int merge(int *a, int na, const int *b, int nb, int **out) {
  int *r = malloc(sizeof(int) * (size_t)(na + nb > 0 ? na + nb : 1)), n = 0, i = 0, j = 0;
  if (!r) return -1;
  while (i < na || j < nb) {
    int v = j >= nb || (i < na && a[i] <= b[j]) ? a[i++] : b[j++];
    if (!n || r[n - 1] != v) r[n++] = v;
  }
  free(*out);
  *out = r;
  return n;
}

/* Resolves [fix], [force] and [move] into node sets. */
static int resolve_sets(tb_sim *s, tb_error *err) {
  const tb_scene_desc *d = &s->desc;
  const double *P = s->priv->param;
  for (int i = 0; i < d->nfix; i++) {
    int *ids, n = tb_sim_select(s, &d->fix[i], "[fix]", &ids, err);
    if (n < 0) return -1;
    s->nanchor = merge(s->anchor, s->nanchor, ids, n, &s->anchor);
    free(ids);
    if (s->nanchor < 0) return tb_error_set(err, "scene", 0, "out of memory");
  }
  if (d->probe.n && (s->nprobe = tb_sim_select(s, &d->probe, "[output]", &s->probe, err)) < 0)
    return -1;
  s->priv->forces = calloc((size_t)(d->nforce + 1), sizeof *s->priv->forces);
  s->priv->moves = calloc((size_t)(d->nmove + 1), sizeof *s->priv->moves);
  if (!s->priv->forces || !s->priv->moves) return tb_error_set(err, "scene", 0, "out of memory");
  for (int i = 0; i < d->nforce; i++) {
    const tb_scene_force *f = &d->force[i];
    tb_sim_group *g = &s->priv->forces[s->priv->nforce++];
    g->n = tb_sim_select(s, &f->where, "[force]", &g->ids, err);
    if (g->n < 0) return -1;
    tb_vec3 v = tb_v3(tb_expr_eval(f->value[0], P), tb_expr_eval(f->value[1], P),
                      tb_expr_eval(f->value[2], P));
    g->value = f->per_node ? v : tb_v3(v.x / g->n, v.y / g->n, v.z / g->n);
    g->start = tb_expr_eval(f->start, P);
    g->stop = tb_expr_eval(f->stop, P);
    if (g->stop < 0) g->stop = INFINITY;
  }
  for (int i = 0; i < d->nmove; i++) {
    const tb_scene_move *m = &d->move[i];
    tb_sim_group *g = &s->priv->moves[s->priv->nmove++];
    g->n = tb_sim_select(s, &m->where, "[move]", &g->ids, err);
    if (g->n < 0 || tb_sim_motion_make(&m->motion, P, &g->motion, err)) return -1;
    g->release = m->has_release ? tb_expr_eval(m->release, P) : INFINITY;
  }
  for (int pass = 0; pass < 2; pass++)
    for (int i = 0; i < (pass ? s->priv->nmove : s->priv->nforce); i++) {
      tb_sim_group *g = pass ? &s->priv->moves[i] : &s->priv->forces[i];
      s->ndriven = merge(s->driven, s->ndriven, g->ids, g->n, &s->driven);
      if (s->ndriven < 0) return tb_error_set(err, "scene", 0, "out of memory");
    }
  return 0;
}

static int loads(tb_sim *s, double t, int contact, tb_error *err);

#define SETTLED 1e-9

/* [ground] settle: before t = 0 the body settles onto the ground under its
 * loads at t = 0, quasi-statically: the contacts stick (static friction
 * without bound) and every velocity is zeroed after each step, until no
 * node moves more than SETTLED x the body's size in a step (at most settle
 * seconds), so the run starts at rest with the ground carrying the body. A body released onto a
 * slope without that preload breaks static contact in its landing
 * transient (its contact nodes carry the body's weight only once the
 * elastic wave has come down) and slides where a resting block sticks.
 * The settling steps count in no measurement of the run. */
static int settle(tb_sim *s, tb_error *err) {
  if (!s->has_ground || !(s->priv->settle > 0)) return 0;
  long n = (long)ceil(s->priv->settle / s->def.dt - 1e-9);
  int nv = s->mesh.nv, *ids = malloc(sizeof(int) * (size_t)nv), rc = 0;
  tb_vec3 *zero = calloc((size_t)nv, sizeof(tb_vec3)),
          *before = malloc(sizeof(tb_vec3) * (size_t)nv);
  if (!ids || !zero || !before) rc = tb_error_set(err, "scene", 0, "out of memory (settle)");
  double size = s->size, moved = INFINITY;
  for (int i = 0; i < nv && !rc; i++) ids[i] = i;
  double mu_s = s->ground.mu_s;
  s->ground.mu_s = INFINITY;
  for (long k = 0; k < n && !rc && !(moved <= SETTLED * size); k++) {
    memcpy(before, tb_model_positions(&s->model), sizeof(tb_vec3) * (size_t)nv);
    if (loads(s, 0, 1, err)) {
      rc = -1;
      break;
    }
    if (!tb_model_owns_ground(&s->model))
      memcpy(s->priv->x_prev, tb_model_positions(&s->model), sizeof(tb_vec3) * (size_t)nv);
    tb_step in = tb_sim_step_input(s);
    if (tb_model_step(&s->model, &in, err) || tb_sim_contact(s, err)) {
      rc = -1;
      break;
    }
    tb_model_correct(&s->model, nv, ids, NULL, zero);
    const tb_vec3 *x = tb_model_positions(&s->model);
    moved = 0;
    for (int i = 0; i < nv; i++) moved = fmax(moved, tb_dist(x[i], before[i]));
    s->settle_steps = k + 1, s->settle_motion = moved;
  }
  s->ground.mu_s = mu_s;
  s->pen_ground = s->pen_ground_max = 0;
  tb_health h = tb_model_health(&s->mesh, tb_model_positions(&s->model),
                                tb_model_velocities(&s->model), s->def.vmax, s->def.inversion);
  if (!rc && !h.ok)
    rc = tb_error_set(err, s->model.cls->name, 0, "unstable while settling onto the ground: %s",
                      h.reason);
  free(ids), free(zero), free(before);
  return rc;
}

/* The material keys every model shares (models/tb_model.h's TB_SETTINGS_MASS and
 * TB_SETTINGS_MATERIAL): a scene's material, whichever model runs it. */
static int material_key(const char *key) {
  static const char *const keys[] = {"E", "nu", "density", "node_mass"};
  for (int i = 0; i < 4; i++)
    if (!strcmp(key, keys[i])) return 1;
  return 0;
}

int tb_sim_create_desc(tb_sim *s, tb_scene_desc *desc, const tb_sim_def *def, const char *model,
                       const tb_settings *set, const tb_mesh *mesh, tb_error *err) {
  memset(s, 0, sizeof *s);
  s->desc = *desc;
  memset(desc, 0, sizeof *desc);
  s->priv = calloc(1, sizeof *s->priv);
  if (!s->priv) {
    tb_scene_desc_free(&s->desc);
    return tb_error_set(err, s->desc.path, 0, "out of memory");
  }
  s->name = s->desc.name;
  const char *path = s->desc.path[0] ? s->desc.path : s->desc.name;
  if (resolve_params(s, def, err)) goto fail;
  int rc = mesh
               ? tb_mesh_copy(&s->mesh, mesh)
               : tb_sim_build_mesh(&s->desc.mesh, path, s->priv->param, s->def.seed, &s->mesh, err);
  if (rc) {
    if (mesh) tb_error_set(err, path, 0, "out of memory");
    goto fail;
  }
  /* the model: the file's [model] settings, then the caller's */
  const char *mname = model && *model ? model : s->desc.model;
  if (!mname[0]) {
    tb_error_set(err, path, 0, "no model: give --model or [model] name = ...");
    goto fail;
  }
  const tb_model_class *cls = tb_model_find(mname);
  if (s->mesh.ntet < 1 && cls && !cls->surface_mesh && s->mesh.ntri > 0) {
    /* a closed surface for a tet model: TetGen's default mesh of it */
    tb_mesh tets;
    tb_tetmesh_opts o = tb_tetmesh_default_opts();
    if (tb_tetmesh(&s->mesh, path, &o, &tets, err)) {
      char why[sizeof err->msg];
      snprintf(why, sizeof why, "%s", err->msg);
      tb_error_set(err, path, s->desc.mesh.line,
                   "model %s needs tets and the surface cannot be tetrahedralised: %s", mname, why);
      goto fail;
    }
    s->meshed_nv = s->mesh.nv - tb_mesh_topology(&s->mesh).unused_verts;
    s->meshed_ntri = s->mesh.ntri;
    tb_mesh_free(&s->mesh);
    s->mesh = tets;
  }
  if (s->mesh.ntet < 1 && (cls ? !cls->surface_mesh : s->mesh.ntri < 1)) {
    char takers[128] = "";
    for (int i = 0, len = 0; i < tb_model_count && len < (int)sizeof takers; i++)
      if (tb_model_classes[i]->surface_mesh)
        len += snprintf(takers + len, sizeof takers - (size_t)len, "%s%s", len ? ", " : "",
                        tb_model_classes[i]->name);
    tb_error_set(err, path, s->desc.mesh.line,
                 "the mesh has no tets (%d vertices, %d triangles): model %s needs a tet mesh "
                 "(models that take a closed surface: %s)",
                 s->mesh.nv, s->mesh.ntri, mname, takers);
    goto fail;
  }
  if (s->mesh.ntri < 1) {
    s->mesh.ntri = tb_mesh_tet_boundary(&s->mesh, &s->mesh.tri);
    if (s->mesh.ntri < 0) {
      s->mesh.ntri = 0;
      tb_error_set(err, path, 0, "out of memory");
      goto fail;
    }
  }
  size_t n = (size_t)s->mesh.nv;
  s->fixed = malloc(sizeof(int) * n);
  s->fixed_x = malloc(sizeof(tb_vec3) * n);
  s->force = calloc(n, sizeof(tb_vec3));
  s->mark = calloc(n, 1);
  s->target = calloc(n, sizeof(tb_vec3));
  s->priv->on_surface = calloc(n, 1);
  s->priv->x_prev = malloc(sizeof(tb_vec3) * n);
  s->priv->x_window = malloc(sizeof(tb_vec3) * n);
  s->priv->window_t0 = s->priv->window_speed = NAN;
  s->priv->ids_buf = malloc(sizeof(int) * n);
  s->priv->xc_buf = malloc(sizeof(tb_vec3) * n);
  s->priv->vc_buf = malloc(sizeof(tb_vec3) * n);
  s->priv->depth_buf = malloc(sizeof(double) * n);
  s->priv->keep_buf = malloc(sizeof(double) * n);
  if (!s->fixed || !s->fixed_x || !s->force || !s->mark || !s->target || !s->priv->on_surface ||
      !s->priv->x_prev || !s->priv->x_window || !s->priv->ids_buf || !s->priv->xc_buf ||
      !s->priv->vc_buf || !s->priv->depth_buf || !s->priv->keep_buf) {
    tb_error_set(err, path, 0, "out of memory");
    goto fail;
  }
  for (int k = 0; k < 3 * s->mesh.ntri; k++) s->priv->on_surface[s->mesh.tri[k]] = 1;
  tb_vec3 lo, hi;
  tb_mesh_bbox(&s->mesh, &lo, &hi);
  s->size = tb_dist(lo, hi), s->priv->lo = lo, s->priv->hi = hi;
  if (!(s->def.vmax > 0)) s->def.vmax = 100.0 * s->size / s->def.duration; /* not given */
  tb_settings all;
  tb_settings_init(&all);
  /* another model than the file's: only the file's material keys carry over
   * (where it has them); the rest are the file's model's (sphere-press's
   * alpha for msm-vvs, a step scale, is not sm's alpha, a stiffness) */
  int other = s->desc.model[0] && strcmp(mname, s->desc.model) != 0;
  for (int i = 0; i < s->desc.nmodel_set; i++) {
    char key[64];
    snprintf(key, sizeof key, "%.*s", (int)strcspn(s->desc.model_set[i], "="),
             s->desc.model_set[i]);
    if (other && (!tb_model_has_setting(mname, key) || !material_key(key))) continue;
    tb_settings one;
    tb_settings_init(&one);
    tb_error e2;
    if (tb_settings_set(&one, s->desc.model_set[i], &e2) ||
        tb_model_check_settings(mname, &one, &e2) ||
        tb_settings_set(&all, s->desc.model_set[i], &e2)) {
      tb_error_set(err, path, s->desc.model_set_line[i], "%s", e2.msg);
      goto fail;
    }
  }
  for (int i = 0; set && i < set->n; i++) {
    char kv[sizeof set->kv[0].key + sizeof set->kv[0].value + 2];
    snprintf(kv, sizeof kv, "%s=%s", set->kv[i].key, set->kv[i].value);
    if (tb_settings_set(&all, kv, err)) goto fail;
  }
  if (tb_model_create(&s->model, mname, &s->mesh, &all, err)) goto fail;
  s->settings = all;
  s->mass = tb_model_masses(&s->model);
  if (resolve_sets(s, err) || tb_sim_contact_setup(s, err) || tb_sim_cut_setup(s, err)) goto fail;
  for (int i = 0; i < s->mesh.nv; i++) s->priv->total_mass += s->mass[i];
  if (settle(s, err)) goto fail;
  s->priv->energy0 = s->energy = tb_model_energy(&s->model);
  s->health.ok = 1;
  return 0;
fail:
  tb_sim_destroy(s);
  return -1;
}

int tb_sim_create(tb_sim *s, const char *scene, const tb_sim_def *def, const char *model,
                  const tb_settings *set, const tb_mesh *mesh, tb_error *err) {
  char path[1024];
  tb_sim_scene_path(scene, path, sizeof path);
  tb_scene_desc d;
  memset(s, 0, sizeof *s);
  if (tb_scene_desc_load(&d, path, err)) return -1;
  return tb_sim_create_desc(s, &d, def, model, set, mesh, err);
}

int tb_sim_mesh(const char *scene, const tb_sim_def *def, tb_mesh *out, tb_error *err) {
  char path[1024];
  tb_sim_scene_path(scene, path, sizeof path);
  tb_sim s;
  tb_sim_priv p;
  memset(&s, 0, sizeof s);
  memset(&p, 0, sizeof p);
  s.priv = &p;
  if (tb_scene_desc_load(&s.desc, path, err)) return -1;
  int rc = resolve_params(&s, def, err) ||
           tb_sim_build_mesh(&s.desc.mesh, path, p.param, s.def.seed, out, err);
  tb_scene_desc_free(&s.desc);
  return rc ? -1 : 0;
}

/* ---- one step ---- */

/* The scene's inputs at t; with contact, last step's instrument contacts
 * are prescribed too. */
static int loads(tb_sim *s, double t, int contact, tb_error *err) {
  memset(s->mark, 0, (size_t)s->mesh.nv);
  memset(s->force, 0, sizeof(tb_vec3) * (size_t)s->mesh.nv);
  s->gravity = tb_scale(s->desc.gravity_dir, s->def.gravity);
  for (int k = 0; k < s->nanchor; k++) {
    int i = s->anchor[k];
    s->mark[i] = 1, s->target[i] = s->mesh.x[i];
  }
  for (int g = 0; g < s->priv->nforce; g++) {
    const tb_sim_group *f = &s->priv->forces[g];
    if (t < f->start || t > f->stop) continue;
    for (int k = 0; k < f->n; k++) s->force[f->ids[k]] = tb_add(s->force[f->ids[k]], f->value);
  }
  for (int g = 0; g < s->priv->nmove; g++) {
    const tb_sim_group *m = &s->priv->moves[g];
    if (!s->hold && t > m->release + 1e-12 * s->def.dt) continue; /* let go */
    for (int k = 0; k < m->n; k++) {
      int i = m->ids[k];
      s->mark[i] = 1, s->target[i] = tb_sim_motion_apply(&m->motion, t, s->mesh.x[i]);
    }
  }
  if (contact && tb_sim_contact_prestep(s, t, err)) return -1;
  s->nfixed = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    if (s->mark[i]) s->fixed[s->nfixed] = i, s->fixed_x[s->nfixed++] = s->target[i];
  for (int k = 0; k < s->priv->nheld_new; k++) /* what cuts made in a [fix] region */
    s->fixed[s->nfixed] = s->priv->held_new[k], s->fixed_x[s->nfixed++] = s->priv->held_new_x[k];
  return 0;
}

int tb_sim_loads(tb_sim *s, double t, tb_error *err) { return loads(s, t, 0, err); }

tb_step tb_sim_step_input(const tb_sim *s) {
  tb_step in = {0};
  in.dt = s->def.dt, in.gravity = s->gravity, in.force = s->force;
  in.nfixed = s->nfixed, in.fixed = s->fixed, in.fixed_x = s->fixed_x;
  in.ground = s->has_ground ? &s->ground : NULL;
  return in;
}

void tb_sim_let_go(tb_sim *s) {
  s->hold = 0;
  for (int g = 0; g < s->priv->nmove; g++) s->priv->moves[g].release = s->t;
}

/* ---- the energy-growth detector ----
 * A stable run of a dissipative model never holds more energy than it
 * started with plus the work done on it. That work is not observable
 * through the model interface (the reactions at prescribed nodes are not
 * reported), so the reference is an a-priori scale of what the scene can
 * put in, and the bound a large factor (energy_factor, 100) times it:
 *   E_ref = max(E(0), E_char, E_driven),
 *   E_char = 1/2 M (size / T)^2 + P size + (P T)^2 / (2 M):
 *     the kinetic energy of the whole mass M moving the scene's size in the
 *     run's time T; the work of the loads (P = largest sum |f_i| + M |g|)
 *     over a displacement of the scene's size (deformation) or over free
 *     motion for time T (P's impulse P T given to M, e.g. a drop);
 *   E_driven = the largest energy reached while prescribed nodes were being
 *     moved (a pulled patch, a ramped end face) or the instrument touched
 *     the body: their work depends on the model's stiffness and cannot be
 *     known in advance, so meanwhile the energy only raises the reference
 *     and is not checked; once they are held or let go the energy can only
 *     fall, and any growth beyond the bound is a blow-up.
 * The factor leaves room for the energy swings of symplectic Euler near its
 * stability limit and for the a-priori terms being rough; an unstable mode
 * grows exponentially and crosses any such bound within a few dozen steps.
 * The energy costs up to a third of a step (msm), so it is evaluated on the
 * first energy_every steps and then every energy_every-th step; NaN/inf and
 * the velocity bound are checked every step. */

static int prescribed_moving(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  double tol = 1e-12 * s->size;
  for (int k = 0; k < s->nfixed; k++) {
    tb_vec3 d = tb_sub(s->fixed_x[k], x[s->fixed[k]]);
    if (fabs(d.x) > tol || fabs(d.y) > tol || fabs(d.z) > tol) return 1;
  }
  return s->ncontact > 0;
}

static void track_loads(tb_sim *s) {
  double p = s->priv->total_mass * tb_len(s->gravity);
  for (int i = 0; i < s->mesh.nv; i++) p += tb_len(s->force[i]);
  if (p > s->priv->load_max) s->priv->load_max = p;
}

static int energy_check(tb_sim *s) {
  double e = tb_model_energy(&s->model);
  s->energy = e, s->energy_bound = 0;
  if (isnan(e)) return 0; /* the model has no energy (sm) */
  if (s->priv->moving) {
    s->priv->moving = 0;
    if (e > s->priv->energy_driven) s->priv->energy_driven = e;
    return 0;
  }
  double m = s->priv->total_mass > 0 ? s->priv->total_mass : 1, T = s->def.duration,
         p = s->priv->load_max;
  double ref = 0.5 * m * (s->size / T) * (s->size / T) + p * s->size + 0.5 * (p * T) * (p * T) / m;
  if (s->priv->energy0 > ref) ref = s->priv->energy0;
  if (s->priv->energy_driven > ref) ref = s->priv->energy_driven;
  s->energy_bound = s->def.energy_factor * ref;
  if (e <= s->energy_bound) return 0;
  s->health.ok = 0;
  snprintf(s->health.reason, sizeof s->health.reason, "energy growth (E = %.3g, bound %.3g)", e,
           s->energy_bound);
  return -1;
}

/* After a step: closes the rest window when TB_SIM_REST_WINDOW has passed. */
static void rest_window(tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  size_t bytes = sizeof(tb_vec3) * (size_t)s->mesh.nv;
  double len = s->t - s->priv->window_t0;
  if (len < TB_SIM_REST_WINDOW * (1 - 1e-9)) return;
  double d = 0;
  for (int i = 0; i < s->mesh.nv; i++) d = fmax(d, tb_dist(x[i], s->priv->x_window[i]));
  s->priv->window_speed = d / len, s->priv->window_t0 = s->t;
  memcpy(s->priv->x_window, x, bytes);
}

/* After a step: the largest mean displacement of the probe nodes so far. */
static void probe_track(tb_sim *s) {
  if (s->nprobe < 1) return;
  const tb_vec3 *x = tb_model_positions(&s->model);
  tb_vec3 mean = tb_v3(0, 0, 0);
  for (int k = 0; k < s->nprobe; k++)
    mean = tb_add(mean, tb_sub(x[s->probe[k]], s->mesh.x[s->probe[k]]));
  double d = tb_len(mean) / s->nprobe;
  if (d > s->probe_peak) s->probe_peak = d, s->probe_peak_t = s->t;
}

int tb_sim_step(tb_sim *s, tb_error *err) {
  double t = s->t + s->def.dt;
  if (isnan(s->priv->window_t0)) {
    memcpy(s->priv->x_window, tb_model_positions(&s->model), sizeof(tb_vec3) * (size_t)s->mesh.nv);
    s->priv->window_t0 = s->t;
  }
  if (loads(s, t, 1, err)) return -1;
  int every = s->def.energy_every;
  int check = s->steps < every || (s->steps + 1) % every == 0;
  if (check) track_loads(s);
  if (!s->priv->moving) s->priv->moving = prescribed_moving(s);
  const tb_vec3 *v = tb_model_velocities(&s->model);
  if (s->def.drag > 0)
    for (int i = 0; i < s->mesh.nv; i++)
      s->force[i] = tb_madd(s->force[i], -s->def.drag * s->mass[i], v[i]);
  if (s->has_ground && !tb_model_owns_ground(&s->model)) /* the ground's friction (contact.c) */
    memcpy(s->priv->x_prev, tb_model_positions(&s->model), sizeof(tb_vec3) * (size_t)s->mesh.nv);
  tb_step in = tb_sim_step_input(s);
  if (tb_sim_cut_before(s, t, err) || tb_model_step(&s->model, &in, err) ||
      tb_sim_cut_after(s, t, err))
    return -1;
  int np = tb_model_npoints(&s->model);
  if (np < s->mesh.nv || (np > s->mesh.nv && (s->has_ground || s->has_tool)))
    return tb_error_set(err, s->model.cls->name, 0, "the model now has %d points, the scene %d: %s",
                        np, s->mesh.nv,
                        np < s->mesh.nv ? "fewer points than the mesh's nodes"
                                        : "contact with points beyond the mesh's nodes (local "
                                          "refinement) is not supported yet");
  s->t = t;
  s->steps++;
  if ((s->has_ground || s->has_tool) && tb_sim_contact(s, err)) return -1;
  rest_window(s);
  probe_track(s);
  s->health = tb_model_health(&s->mesh, tb_model_positions(&s->model),
                              tb_model_velocities(&s->model), s->def.vmax, s->def.inversion);
  if (s->health.ok && np > s->mesh.nv) { /* the model's own points (a finer level) */
    tb_mesh extra = {0};
    extra.nv = np - s->mesh.nv;
    s->health = tb_model_health(&extra, tb_model_positions(&s->model) + s->mesh.nv,
                                tb_model_velocities(&s->model) + s->mesh.nv, s->def.vmax, 0);
  }
  if (s->health.ok && check) energy_check(s);
  if (!s->health.ok)
    return tb_error_set(err, s->model.cls->name, 0, "unstable at t = %g: %s", s->t,
                        s->health.reason);
  return 0;
}

void tb_sim_destroy(tb_sim *s) {
  tb_model_destroy(&s->model);
  tb_sim_priv *p = s->priv;
  if (p) {
    tb_sim_contact_free(s);
    tb_sim_cut_free(s);
    free(p->held_new), free(p->held_new_x);
    free(p->on_surface), free(p->x_prev), free(p->x_window), free(p->ids_buf), free(p->xc_buf),
        free(p->vc_buf), free(p->depth_buf), free(p->keep_buf);
    for (int i = 0; p->forces && i < p->nforce; i++) free(p->forces[i].ids);
    for (int i = 0; p->moves && i < p->nmove; i++) {
      free(p->moves[i].ids);
      tb_sim_motion_free(&p->moves[i].motion);
    }
    free(p->forces), free(p->moves);
    free(p);
  }
  tb_mesh_free(&s->mesh);
  free(s->fixed), free(s->fixed_x), free(s->force), free(s->mark), free(s->target);
  free(s->anchor), free(s->driven), free(s->probe);
  tb_scene_desc_free(&s->desc);
  memset(s, 0, sizeof *s);
}

/* ---- metrics and output ---- */

tb_sim_metrics tb_sim_measure(const tb_sim *s) {
  tb_sim_metrics r;
  memset(&r, 0, sizeof r);
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  double sum2 = 0, v0 = 0, v1 = 0, z = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    r.max_speed = fmax(r.max_speed, tb_len(v[i]));
    double d = tb_dist(x[i], s->mesh.x[i]);
    if (d > r.max_disp) r.max_disp = d, r.max_disp_node = i;
    sum2 += d * d;
    z += x[i].z;
  }
  const unsigned char *alive = tb_model_tets_alive(&s->model); /* a cut removed the others */
  for (int t = 0; t < s->mesh.ntet; t++) {
    if (alive && !alive[t]) continue;
    const int *e = s->mesh.tet + 4 * t;
    v0 += tb_tet_volume(s->mesh.x[e[0]], s->mesh.x[e[1]], s->mesh.x[e[2]], s->mesh.x[e[3]]);
    double vol = tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]);
    v1 += vol;
    if (!(vol > 0)) r.inverted++;
  }
  if (s->mesh.ntet < 1) { /* a surface mesh: the volume it encloses */
    tb_mesh now = s->mesh;
    now.x = (tb_vec3 *)x;
    v0 = tb_mesh_volume(&s->mesh), v1 = tb_mesh_volume(&now);
  }
  r.rms_disp = sqrt(sum2 / s->mesh.nv);
  r.volume_change = (v1 - v0) / v0;
  r.energy = tb_model_energy(&s->model);
  r.com_z = z / s->mesh.nv;
  return r;
}

double tb_sim_volume_tolerance(const tb_sim *s) {
  double nu;
  if (tb_model_setting(s->model.cls->name, &s->settings, "nu", &nu) || !(nu < 0.5))
    nu = 0.3; /* a model without a Poisson ratio: tissue's usual */
  return fmax(0.05, 0.5 * (1 - 2 * nu));
}

int tb_sim_degraded(const tb_sim *s, char *why, size_t cap) {
  tb_sim_metrics m = tb_sim_measure(s);
  double tol = tb_sim_volume_tolerance(s);
  int n = 0, len = 0;
  why[0] = 0;
  if (m.inverted > 0)
    len += snprintf(why + len, cap - (size_t)len, "%d inverted tet%s", m.inverted,
                    m.inverted == 1 ? "" : "s"),
        n++;
  if (!(fabs(m.volume_change) <= tol) && (size_t)len < cap)
    len += snprintf(why + len, cap - (size_t)len, "%svolume %+.1f%% (tolerance %.0f%%)",
                    n ? ", " : "", 100 * m.volume_change, 100 * tol),
        n++;
  if (isfinite(m.energy) && s->energy_bound > 0 && m.energy > s->energy_bound && (size_t)len < cap)
    len += snprintf(why + len, cap - (size_t)len, "%senergy %.3g above its bound %.3g",
                    n ? ", " : "", m.energy, s->energy_bound),
        n++;
  return n > 0;
}

int tb_sim_at_rest(const tb_sim *s, double *speed, double *tol) {
  double m = s->priv->window_speed;
  if (isnan(m)) {
    const tb_vec3 *v = tb_model_velocities(&s->model);
    m = 0;
    for (int i = 0; i < s->mesh.nv; i++) m = fmax(m, tb_len(v[i]));
  }
  *speed = m, *tol = s->def.rest_speed * s->size;
  return m < *tol;
}
