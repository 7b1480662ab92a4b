/* The simulation driver: the table of scenes, scene settings, one step
 * (the scene's inputs, the model's step, the health check), metrics and
 * VTK frames. */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "sim_priv.h"
#include "tb_mesh_io.h"

/* Energy-growth detector defaults (see energy_check). */
#define ENERGY_FACTOR 100.0
#define ENERGY_EVERY 16

static const tb_sim_scene *const scenes[] = {
    &tb_scene_liver_stretch, &tb_scene_liver_press, &tb_scene_beam,      &tb_scene_drop,
    &tb_scene_beam_stretch,  &tb_scene_beam_twist,  &tb_scene_beam_crush};
#define NSCENES ((int)(sizeof scenes / sizeof scenes[0]))

static const tb_sim_scene *find(const char *name) {
  for (int i = 0; i < NSCENES; i++)
    if (!strcmp(scenes[i]->name, name)) return scenes[i];
  return NULL;
}

const char *const *tb_sim_scene_names(int *count) {
  static const char *names[NSCENES];
  for (int i = 0; i < NSCENES; i++) names[i] = scenes[i]->name;
  *count = NSCENES;
  return names;
}

const char *tb_sim_scene_summary(const char *name) {
  const tb_sim_scene *sc = find(name);
  return sc ? sc->summary : NULL;
}

int tb_sim_def_set(tb_sim_def *def, const char *kv, tb_error *err) {
  static const struct {
    const char *key;
    size_t off;
    int is_int;
  } keys[] = {
      {"dt", offsetof(tb_sim_def, dt), 0},
      {"duration", offsetof(tb_sim_def, duration), 0},
      {"amplitude", offsetof(tb_sim_def, amplitude), 0},
      {"release", offsetof(tb_sim_def, release), 0},
      {"nodes", offsetof(tb_sim_def, nodes), 1},
      {"gravity", offsetof(tb_sim_def, gravity), 0},
      {"vmax", offsetof(tb_sim_def, vmax), 0},
      {"inversion", offsetof(tb_sim_def, inversion), 1},
      {"drag", offsetof(tb_sim_def, drag), 0},
      {"energy_factor", offsetof(tb_sim_def, energy_factor), 0},
      {"energy_every", offsetof(tb_sim_def, energy_every), 1},
  };
  const char *eq = strchr(kv, '=');
  if (!eq) return 1;
  size_t klen = (size_t)(eq - kv);
  for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++) {
    if (strlen(keys[i].key) != klen || strncmp(keys[i].key, kv, klen)) continue;
    char *end;
    errno = 0;
    double x = strtod(eq + 1, &end);
    if (!eq[1] || *end || errno || !isfinite(x) || x < 0 || (keys[i].is_int && x != floor(x)) ||
        x > 1e9)
      return tb_error_set(err, "--set", 0, "%s: '%s' is not a number >= 0%s", keys[i].key, eq + 1,
                          keys[i].is_int ? " (whole)" : "");
    char *p = (char *)def + keys[i].off;
    if (keys[i].is_int) {
      int n = (int)x;
      memcpy(p, &n, sizeof n);
    } else
      memcpy(p, &x, sizeof x);
    return 0;
  }
  return 1;
}

/* Zero fields take the scene's defaults. */
static tb_sim_def with_defaults(const tb_sim_scene *sc, const tb_sim_def *in) {
  tb_sim_def d = in ? *in : sc->defaults, z = sc->defaults;
  if (!(d.dt > 0)) d.dt = z.dt;
  if (!(d.duration > 0)) d.duration = z.duration;
  if (!(d.amplitude > 0)) d.amplitude = z.amplitude;
  if (!(d.release > 0)) d.release = z.release;
  if (d.nodes <= 0) d.nodes = z.nodes;
  if (!(d.gravity > 0)) d.gravity = z.gravity;
  if (!in) d.seed = 1;
  return d;
}

int tb_sim_select(const tb_mesh *m, int (*keep)(tb_vec3 x, const void *data), const void *data,
                  int **out) {
  int n = 0;
  *out = malloc(sizeof(int) * (size_t)(m->nv > 0 ? m->nv : 1));
  if (!*out) return -1;
  for (int i = 0; i < m->nv; i++)
    if (keep(m->x[i], data)) (*out)[n++] = i;
  return n;
}

void tb_sim_hold_anchor(tb_sim *s) {
  for (int k = 0; k < s->nanchor; k++) {
    int i = s->anchor[k];
    s->mark[i] = 1, s->target[i] = s->mesh.x[i];
  }
}

double tb_sim_ramp(tb_sim *s, double t) {
  tb_sim_hold_anchor(s);
  if (!s->hold && t > s->def.release + 1e-12 * s->def.dt) return -1;
  double r = 0.5 * s->def.release;
  return t < r ? t / r : 1.0;
}

typedef struct beam_end {
  double x; /* the face's coordinate */
  int above;
} beam_end;
static int on_end(tb_vec3 x, const void *data) {
  const beam_end *e = data;
  return e->above ? x.x >= e->x : x.x <= e->x;
}

int tb_sim_beam_ends(tb_sim *s, tb_error *err) {
  tb_vec3 lo, hi;
  tb_mesh_bbox(&s->mesh, &lo, &hi);
  double len = hi.x - lo.x;
  beam_end root = {lo.x + 1e-9 * len, 0}, tip = {hi.x - 1e-9 * len, 1};
  s->nanchor = tb_sim_select(&s->mesh, on_end, &root, &s->anchor);
  s->ndriven = tb_sim_select(&s->mesh, on_end, &tip, &s->driven);
  if (s->nanchor < 1 || s->ndriven < 1)
    return tb_error_set(err, s->scene->name, 0, "no end faces (out of memory?)");
  return 0;
}

int tb_sim_mesh(const char *scene, const tb_sim_def *def, tb_mesh *out, tb_error *err) {
  const tb_sim_scene *sc = find(scene);
  if (!sc)
    return tb_error_set(err, scene, 0,
                        "unknown scene (liver-stretch, liver-press, beam, drop, beam-stretch, "
                        "beam-twist, beam-crush)");
  tb_sim_def d = with_defaults(sc, def);
  return sc->mesh(&d, out, err);
}

int tb_sim_create(tb_sim *s, const char *scene, const tb_sim_def *def, const char *model,
                  const tb_settings *mset, const tb_mesh *mesh, tb_error *err) {
  memset(s, 0, sizeof *s);
  const tb_sim_scene *sc = find(scene);
  if (!sc)
    return tb_error_set(err, scene, 0,
                        "unknown scene (liver-stretch, liver-press, beam, drop, beam-stretch, "
                        "beam-twist, beam-crush)");
  s->scene = sc;
  s->def = with_defaults(sc, def);
  if (s->def.release > s->def.duration) s->def.release = s->def.duration;
  int rc = mesh ? tb_mesh_copy(&s->mesh, mesh) : sc->mesh(&s->def, &s->mesh, err);
  if (rc) {
    if (mesh) tb_error_set(err, scene, 0, "out of memory");
    return -1;
  }
  if (s->mesh.ntet < 1) {
    tb_sim_destroy(s);
    return tb_error_set(err, scene, 0, "the scene's mesh has no tets");
  }
  size_t n = (size_t)s->mesh.nv;
  s->fixed = malloc(sizeof(int) * n);
  s->fixed_x = malloc(sizeof(tb_vec3) * n);
  s->force = calloc(n, sizeof(tb_vec3));
  s->mark = calloc(n, 1);
  s->target = calloc(n, sizeof(tb_vec3));
  s->mass = malloc(sizeof(double) * n);
  if (!s->fixed || !s->fixed_x || !s->force || !s->mark || !s->target || !s->mass) {
    tb_sim_destroy(s);
    return tb_error_set(err, scene, 0, "out of memory");
  }
  tb_vec3 lo, hi;
  tb_mesh_bbox(&s->mesh, &lo, &hi);
  s->size = tb_dist(lo, hi);
  if (!(s->def.vmax > 0)) s->def.vmax = 100.0 * s->size / s->def.duration;
  if (!(s->def.energy_factor > 0)) s->def.energy_factor = ENERGY_FACTOR;
  if (s->def.energy_every <= 0) s->def.energy_every = ENERGY_EVERY;
  if (tb_model_create(&s->model, model, &s->mesh, mset, err)) {
    tb_sim_destroy(s);
    return -1;
  }
  memcpy(s->mass, tb_model_masses(&s->model), sizeof(double) * n);
  if (sc->setup(s, err)) {
    tb_sim_destroy(s);
    return -1;
  }
  for (int i = 0; i < s->mesh.nv; i++) s->total_mass += s->mass[i];
  s->energy0 = s->energy = tb_model_energy(&s->model);
  s->health.ok = 1;
  return 0;
}

int tb_sim_loads(tb_sim *s, double t, tb_error *err) {
  memset(s->mark, 0, (size_t)s->mesh.nv);
  memset(s->force, 0, sizeof(tb_vec3) * (size_t)s->mesh.nv);
  s->gravity = tb_v3(0, 0, -s->def.gravity);
  if (s->scene->inputs(s, t, err)) return -1;
  s->nfixed = 0;
  for (int i = 0; i < s->mesh.nv; i++)
    if (s->mark[i]) s->fixed[s->nfixed] = i, s->fixed_x[s->nfixed++] = s->target[i];
  return 0;
}

/* ---- the energy-growth detector ----
 * A stable run of a dissipative model never holds more energy than it
 * started with plus the work done on it. That work is not observable
 * through the model interface (the reactions at prescribed nodes are not
 * reported), so the reference is an a-priori scale of what the scene can
 * put in, and the bound a large factor (def.energy_factor, 100) times it:
 *   E_ref = max(E(0), E_char, E_driven),
 *   E_char = 1/2 M (size / T)^2 + P size + (P T)^2 / (2 M):
 *     the kinetic energy of the whole mass M moving the scene's size in the
 *     run's time T; the work of the loads (P = largest sum |f_i| + M |g|)
 *     over a displacement of the scene's size (deformation) or over free
 *     motion for time T (P's impulse P T given to M, e.g. a drop);
 *   E_driven = the largest energy reached while prescribed nodes were being
 *     moved (a pulled patch, a pushed tool, a ramped end face): their work
 *     depends on the model's stiffness and cannot be known in advance, so
 *     while they move the energy only raises the reference and is not
 *     checked; once they are held or let go (hold, release, recovery) the
 *     energy can only fall, and any growth beyond the bound is a blow-up.
 * The factor leaves room for the energy swings of symplectic Euler near its
 * stability limit (its measured energy oscillates about the true one) and
 * for the a-priori terms being rough; an unstable mode grows exponentially
 * and crosses any such bound within a few dozen steps. The energy costs up
 * to a third of a step (msm), so it is evaluated on the first energy_every
 * steps (short runs are checked every step) and then every energy_every-th
 * step; NaN/inf and the velocity bound are checked every step. */

/* Did any prescribed node's target move away from where the node is? */
static int prescribed_moving(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  double tol = 1e-12 * s->size;
  for (int k = 0; k < s->nfixed; k++) {
    tb_vec3 d = tb_sub(s->fixed_x[k], x[s->fixed[k]]);
    if (fabs(d.x) > tol || fabs(d.y) > tol || fabs(d.z) > tol) return 1;
  }
  return 0;
}

/* Largest scene load so far: sum |f_i| (scene forces, before drag) + M |g|. */
static void track_loads(tb_sim *s) {
  double p = s->total_mass * tb_len(s->gravity);
  for (int i = 0; i < s->mesh.nv; i++) p += tb_len(s->force[i]);
  if (p > s->load_max) s->load_max = p;
}

/* The energy check after a step (see above); 0 when healthy. */
static int energy_check(tb_sim *s) {
  double e = tb_model_energy(&s->model);
  s->energy = e, s->energy_bound = 0;
  if (isnan(e)) return 0; /* the model has no energy (sm) */
  if (s->moving) {
    s->moving = 0;
    if (e > s->energy_driven) s->energy_driven = e;
    return 0;
  }
  double m = s->total_mass > 0 ? s->total_mass : 1, T = s->def.duration, p = s->load_max;
  double ref = 0.5 * m * (s->size / T) * (s->size / T) + p * s->size + 0.5 * (p * T) * (p * T) / m;
  if (s->energy0 > ref) ref = s->energy0;
  if (s->energy_driven > ref) ref = s->energy_driven;
  s->energy_bound = s->def.energy_factor * ref;
  if (e <= s->energy_bound) return 0;
  s->health.ok = 0;
  snprintf(s->health.reason, sizeof s->health.reason, "energy growth (E = %.3g, bound %.3g)", e,
           s->energy_bound);
  return -1;
}

int tb_sim_step(tb_sim *s, tb_error *err) {
  double t = s->t + s->def.dt;
  if (tb_sim_loads(s, t, err)) return -1;
  int check = s->steps < s->def.energy_every || (s->steps + 1) % s->def.energy_every == 0;
  if (check) track_loads(s);
  if (!s->moving) s->moving = prescribed_moving(s);
  if (s->def.drag > 0) {
    const tb_vec3 *v = tb_model_velocities(&s->model);
    for (int i = 0; i < s->mesh.nv; i++)
      s->force[i] = tb_madd(s->force[i], -s->def.drag * s->mass[i], v[i]);
  }
  tb_step in;
  in.dt = s->def.dt;
  in.gravity = s->gravity;
  in.force = s->force;
  in.nfixed = s->nfixed;
  in.fixed = s->fixed;
  in.fixed_x = s->fixed_x;
  if (tb_model_step(&s->model, &in, err)) return -1;
  s->t = t;
  s->steps++;
  s->health = tb_model_health(&s->mesh, tb_model_positions(&s->model),
                              tb_model_velocities(&s->model), s->def.vmax, s->def.inversion);
  if (s->health.ok && check) energy_check(s);
  if (!s->health.ok)
    return tb_error_set(err, s->model.cls->name, 0, "unstable at t = %g: %s", s->t,
                        s->health.reason);
  return 0;
}

void tb_sim_destroy(tb_sim *s) {
  tb_model_destroy(&s->model);
  tb_collider_free(s->collider);
  tb_pairlist_free(&s->pairs);
  tb_mesh_free(&s->tool);
  tb_mesh_free(&s->mesh);
  free(s->fixed), free(s->fixed_x), free(s->force), free(s->mark), free(s->target), free(s->mass);
  free(s->anchor), free(s->driven), free(s->contact);
  memset(s, 0, sizeof *s);
}

tb_sim_metrics tb_sim_measure(const tb_sim *s) {
  tb_sim_metrics r;
  memset(&r, 0, sizeof r);
  const tb_vec3 *x = tb_model_positions(&s->model), *v = tb_model_velocities(&s->model);
  double sum2 = 0, v0 = 0, v1 = 0, z = 0;
  for (int i = 0; i < s->mesh.nv; i++) {
    r.max_speed = fmax(r.max_speed, tb_len(v[i]));
    double d = tb_dist(x[i], s->mesh.x[i]);
    r.max_disp = fmax(r.max_disp, d);
    sum2 += d * d;
    z += x[i].z;
  }
  for (int t = 0; t < s->mesh.ntet; t++) {
    const int *e = s->mesh.tet + 4 * t;
    v0 += tb_tet_volume(s->mesh.x[e[0]], s->mesh.x[e[1]], s->mesh.x[e[2]], s->mesh.x[e[3]]);
    double v = tb_tet_volume(x[e[0]], x[e[1]], x[e[2]], x[e[3]]);
    v1 += v;
    if (!(v > 0)) r.inverted++;
  }
  r.rms_disp = sqrt(sum2 / s->mesh.nv);
  r.volume_change = (v1 - v0) / v0;
  r.energy = tb_model_energy(&s->model);
  r.com_z = z / s->mesh.nv;
  return r;
}

int tb_sim_write_vtk(const tb_sim *s, const char *dir, int frame, tb_error *err) {
  if (mkdir(dir, 0777) && errno != EEXIST)
    return tb_error_set(err, dir, 0, "cannot create: %s", strerror(errno));
  char path[1024];
  if (snprintf(path, sizeof path, "%s/frame_%05d.vtk", dir, frame) >= (int)sizeof path)
    return tb_error_set(err, dir, 0, "path too long");
  tb_mesh m = s->mesh;
  m.x = (tb_vec3 *)tb_model_positions(&s->model);
  return tb_mesh_write(path, &m, err);
}
