/* The scaling suite: how every tet model of
 * models/model.c's table and the collision hierarchy grow with the mesh.
 *  1. ms per step against tets: each model of the table in the liver-stretch
 *     scene (thesis §3.5: the liver held along its back, a far patch pulled)
 *     on TetGen livers of a ladder of tet counts (tb_liver_of_tets, the pbd
 *     suite's), one thread; the model's step alone timed (as the pbd suite
 *     does), health checked after every step, untimed. A least-squares line
 *     through log(ms) against log(tets) gives each model's exponent (slope)
 *     and where it crosses 33.3 ms (30 Hz, graphics) and 3.33 ms (300 Hz,
 *     haptics): the largest mesh still interactive, read off the line.
 *  2. Peak memory, as a difference in this process: before each one-thread
 *     run, freed memory is handed back (blocks above 64 KiB come from mmap,
 *     malloc_trim) and the peak RSS reset (5 to /proc/self/clear_refs);
 *     VmHWM after the run minus VmRSS before it is the peak the run added
 *     (the scene's copy of the mesh included), per tet. (A forked child
 *     cannot be used: CHOLMOD starts OpenMP threads, and libgomp hangs in a
 *     child of a process that has used them.)
 *  3. One thread against all cores at 100 000 tets (tiny runs: the largest): ms per step,
 *     speed-up, and whether positions and velocities after the same steps
 *     are bit-identical (a hash of their bytes).
 *  4. Collision: the composite hierarchy (collision/tb_bvh.h) over all tet
 *     faces of each liver (the thesis's liver model, as the refit suite)
 *     against the instrument held inside it, the liver deformed every frame
 *     (suites/collision_scene.c): refit (delta 0) and the all-pairs query, ms against
 *     triangles, fitted the same way. */
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scaling_priv.h"
#include "tb_collision_scene.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"
#include "report/tb_results.h"
#include "scenes/tb_collider.h"
#include "scenes/tb_sim.h"

#define MAX_STEPS 400
#define THREADS_TETS 100000 /* one thread against all at this size */

/* Tet counts: --full, the default (quick) and --scale < 1 (tests). */
static const int ladder_full[] = {600, 1200, 2500, 5000, 10000, 20000, 50000, 100000, 200000};
static const int ladder_quick[] = {600, 2500, 10000, 40000, 100000};
static const int ladder_tiny[] = {600, 1200, 2500};

static uint64_t fnv(uint64_t h, const void *p, size_t n) {
  const unsigned char *c = p;
  for (size_t k = 0; k < n; k++) h = (h ^ c[k]) * 1099511628211ull;
  return h;
}

/* A /proc/self/status field in KiB (NAN when absent). */
static double status_kb(const char *key) {
  FILE *f = fopen("/proc/self/status", "r");
  char line[256];
  double v = NAN;
  size_t n = strlen(key);
  while (f && fgets(line, sizeof line, f))
    if (!strncmp(line, key, n)) v = strtod(line + n, NULL);
  if (f) fclose(f);
  return v;
}

/* model on mesh in the scene, `threads` threads: one warm-up step, then
 * `steps` timed steps (steps <= 0: until budget seconds, at least 3, at
 * most MAX_STEPS). c gets the median, the count and the state's hash. */
static int run_model(const tb_mesh *mesh, const char *model, int threads, int steps, double budget,
                     cell *c, tb_error *err) {
  tb_threads_set(threads);
  tb_sim s;
  if (tb_sim_create(&s, SCENE, NULL, model, NULL, mesh, err)) return -1;
  double *ms = malloc(sizeof(double) * MAX_STEPS);
  int rc = ms ? 0 : tb_error_set(err, model, 0, "out of memory"), n = 0;
  double spent = 0;
  for (int k = 0; !rc; k++) {
    if (k > 0 && (steps > 0 ? n >= steps : (n >= MAX_STEPS || (n >= 3 && spent >= budget)))) break;
    if (tb_sim_loads(&s, s.t + s.def.dt, err)) {
      rc = -1;
      break;
    }
    tb_step in = {0};
    in.dt = s.def.dt, in.gravity = s.gravity, in.force = s.force;
    in.nfixed = s.nfixed, in.fixed = s.fixed, in.fixed_x = s.fixed_x;
    in.ground = s.has_ground ? &s.ground : NULL;
    uint64_t t0 = tb_time_ns();
    rc = tb_model_step(&s.model, &in, err);
    uint64_t t1 = tb_time_ns();
    if (rc) break;
    s.t += s.def.dt, s.steps++;
    if (k > 0) ms[n++] = (double)(t1 - t0) * 1e-6, spent += (double)(t1 - t0) * 1e-9;
    int np = tb_model_npoints(&s.model);
    tb_mesh pts = {0};
    pts.nv = np;
    tb_health h = tb_model_health(np == s.mesh.nv ? &s.mesh : &pts, tb_model_positions(&s.model),
                                  tb_model_velocities(&s.model), s.def.vmax,
                                  np == s.mesh.nv ? s.def.inversion : 0);
    if (!h.ok) rc = tb_error_set(err, model, 0, "unstable at t = %g: %s", s.t, h.reason);
    tb_progress_tick("%s: step %d", model, k + 1);
  }
  if (!rc) {
    int np = tb_model_npoints(&s.model);
    c->ms = tb_stats_of(ms, n).median, c->steps = n;
    c->sum =
        fnv(1469598103934665603ull, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)np);
    c->sum = fnv(c->sum, tb_model_velocities(&s.model), sizeof(tb_vec3) * (size_t)np);
  }
  free(ms);
  tb_sim_destroy(&s);
  return rc ? -1 : 0;
}

/* run_model on one thread with the peak RSS it added (see the head): freed
 * memory is first handed back to the system (malloc_trim), the peak reset
 * to the current RSS (5 to /proc/self/clear_refs), VmHWM read after the run. */
static void run_measured(const tb_mesh *mesh, const char *model, double budget, cell *c) {
  memset(c, 0, sizeof *c);
  malloc_trim(0);
  FILE *f = fopen("/proc/self/clear_refs", "w");
  int reset = f && fputs("5", f) >= 0;
  if (f && fclose(f)) reset = 0;
  double rss0 = status_kb("VmRSS:");
  tb_error err;
  if (run_model(mesh, model, 1, 0, budget, c, &err))
    snprintf(c->why, sizeof c->why, "%.150s", err.msg);
  else
    c->ok = 1;
  c->rss = reset ? status_kb("VmHWM:") - rss0 : NAN;
}

/* Refit + query of the composite hierarchy over the liver's tet faces
 * against the instrument inside it, `frames` deformed frames. */
static int collide(const tb_mesh *tets, const tb_mesh *inst, int frames, size_row *w,
                   tb_error *err) {
  tb_mesh liver = {0};
  liver.nv = tets->nv, liver.x = tets->x;
  liver.ntri = tb_mesh_tet_faces(tets, &liver.tri);
  if (liver.ntri < 0) return tb_error_set(err, "scaling", 0, "out of memory");
  w->ntri = liver.ntri;
  tb_vec3 *x = malloc(sizeof(tb_vec3) * (size_t)liver.nv);
  double *u = malloc(sizeof(double) * (size_t)frames), *q = malloc(sizeof(double) * (size_t)frames);
  tb_pairlist pl = {0, 0, NULL};
  tb_collider *c =
      x && u && q ? tb_collider_new("composite", &liver, inst, NULL, NULL, NULL, err) : NULL;
  tb_mat3 R;
  tb_vec3 t;
  tb_collision_scene_pose(0.5, &R, &t); /* the tip inside the liver (the refit suite's pose) */
  int rc = !c || tb_collider_pose(c, R, t, err) ? -1 : 0;
  for (int f = 0; f < frames && !rc; f++) {
    tb_collision_scene_deform(tets->x, liver.nv, 0.1 * (f + 1), 0.25, x);
    uint64_t t0 = tb_time_ns();
    rc = tb_collider_deform(c, x, 0, err);
    uint64_t t1 = tb_time_ns();
    if (!rc) rc = tb_collider_query(c, &pl, NULL, err);
    uint64_t t2 = tb_time_ns();
    u[f] = (double)(t1 - t0) * 1e-6, q[f] = (double)(t2 - t1) * 1e-6;
  }
  if (!rc) {
    w->refit_ms = tb_stats_of(u, frames).median, w->query_ms = tb_stats_of(q, frames).median;
    w->pairs = pl.n;
  }
  tb_collider_free(c);
  tb_pairlist_free(&pl);
  free(liver.tri), free(x), free(u), free(q);
  return rc ? -1 : 0;
}

/* ---- the cases of `reproduce --shard`: a mesh's collision row, a model on a mesh ---- */

/* A liver of the ladder, made when a case that runs here first needs it. */
typedef struct scaling_mesh {
  int tets;
  uint64_t seed;
  int made; /* 1: mesh holds it; -1: it could not be made (why) */
  tb_mesh mesh;
  char why[150];
} scaling_mesh;

static const tb_mesh *mesh_of(scaling_mesh *sm, double *gen_s) {
  if (!sm->made) {
    tb_error err;
    uint64_t g0 = tb_time_ns();
    sm->made = tb_liver_of_tets(sm->tets, sm->seed, &sm->mesh, &err) ? -1 : 1;
    if (sm->made < 0) snprintf(sm->why, sizeof sm->why, "%.140s", err.msg);
    if (gen_s) *gen_s = (double)(tb_time_ns() - g0) * 1e-9;
  }
  return sm->made > 0 ? &sm->mesh : NULL;
}

/* A hash as two exact doubles, and back. */
static void put_sum(double *v, uint64_t h) {
  v[0] = (double)(h >> 32), v[1] = (double)(h & 0xffffffffu);
}
static uint64_t get_sum(const double *v) { return (uint64_t)v[0] << 32 | (uint64_t)v[1]; }

/* The mesh's row: its counts and the composite hierarchy's refit + query.
 * 1 when it failed. */
static int size_case(tb_suite *su, scaling_mesh *sm, const tb_mesh *inst, int frames, size_row *w) {
  char key[64];
  snprintf(key, sizeof key, "tets:%d/mesh", sm->tets);
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c), failed = 0;
  memset(w, 0, sizeof *w);
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    const tb_mesh *m = mesh_of(sm, &w->gen_s);
    tb_error err;
    if (!m) {
      snprintf(w->why, sizeof w->why, "no mesh (%.140s)", sm->why);
      fprintf(stderr, "scaling: %d tets: %s\n", sm->tets, w->why);
      failed = 1;
    } else {
      w->ok = 1, w->target = sm->tets, w->ntet = m->ntet, w->nv = m->nv;
      tb_threads_set(1);
      if (collide(m, inst, frames, w, &err)) {
        fprintf(stderr, "scaling: collision on %d tets: %s\n", m->ntet, err.msg);
        w->refit_ms = w->query_ms = NAN;
        failed = 1;
      }
    }
    double v[] = {w->ok,    w->target, w->ntet,     w->nv,       w->ntri,
                  w->pairs, w->gen_s,  w->refit_ms, w->query_ms, failed};
    memcpy(c.v, v, sizeof v);
    c.nv = (int)(sizeof v / sizeof v[0]), c.nt = 1;
    snprintf(c.t[0], sizeof c.t[0], "%s", w->why);
    tb_suite_case_done(su, &c);
    return failed;
  }
  w->ok = (int)c.v[0], w->target = (int)c.v[1], w->ntet = (int)c.v[2], w->nv = (int)c.v[3];
  w->ntri = (int)c.v[4], w->pairs = (int)c.v[5], w->gen_s = c.v[6], w->refit_ms = c.v[7];
  w->query_ms = c.v[8];
  snprintf(w->why, sizeof w->why, "%.159s", c.t[0]);
  return (int)c.v[9];
}

/* model on the mesh, one thread (peak RSS measured), and with cores > 0 the
 * same steps on every core (all). 1 when the thread count changed a bit. */
static int model_case(tb_suite *su, scaling_mesh *sm, const char *model, double budget, int cores,
                      cell *one, cell *all) {
  char key[96];
  snprintf(key, sizeof key, "tets:%d/%s%s", sm->tets, model, cores ? "/threads" : "");
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c);
  memset(one, 0, sizeof *one);
  if (cores) memset(all, 0, sizeof *all);
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    const tb_mesh *m = mesh_of(sm, NULL);
    tb_error err;
    if (!m)
      snprintf(one->why, sizeof one->why, "no mesh");
    else {
      tb_progress_tick("%s", model);
      run_measured(m, model, budget, one);
      if (!one->ok) fprintf(stderr, "scaling: %s on %d tets: %s\n", model, m->ntet, one->why);
    }
    if (m && cores && one->ok) { /* all cores, the same steps as the one-thread run */
      if (run_model(m, model, cores, one->steps, 0, all, &err))
        snprintf(all->why, sizeof all->why, "%.150s", err.msg);
      else
        all->ok = 1;
    }
    const cell *x[2] = {one, all};
    for (int q = 0; q < 2; q++) {
      double *v = c.v + 6 * q;
      v[0] = x[q]->ok, v[1] = x[q]->steps, v[2] = x[q]->ms, v[3] = x[q]->rss;
      put_sum(v + 4, x[q]->sum);
      snprintf(c.t[q], sizeof c.t[q], "%s", x[q]->why);
    }
    c.nv = cores ? 12 : 6, c.nt = cores ? 2 : 1;
    tb_suite_case_done(su, &c);
  } else {
    cell *x[2] = {one, all};
    for (int q = 0; q < (cores ? 2 : 1); q++) {
      const double *v = c.v + 6 * q;
      x[q]->ok = (int)v[0], x[q]->steps = (int)v[1], x[q]->ms = v[2], x[q]->rss = v[3];
      x[q]->sum = get_sum(v + 4);
      snprintf(x[q]->why, sizeof x[q]->why, "%.159s", c.t[q]);
    }
  }
  return cores && one->ok && all->ok && all->sum != one->sum; /* must not change a bit */
}

int tb_suite_scaling(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/scaling", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(
      dir, "scaling", "Scaling: ms per step against mesh size, memory, threads, collision", o->seed,
      &err);
  if (!su) return fprintf(stderr, "scaling: %s\n", err.msg), 1;
  uint64_t start = tb_time_ns();
  static scaling_run run;
  scaling_run *sr = &run;
  memset(sr, 0, sizeof *sr);
  const int *ladder = ladder_quick;
  int nsizes = (int)(sizeof ladder_quick / sizeof ladder_quick[0]);
  if (o->full) ladder = ladder_full, nsizes = (int)(sizeof ladder_full / sizeof ladder_full[0]);
  if (o->scale < 1)
    ladder = ladder_tiny, nsizes = (int)(sizeof ladder_tiny / sizeof ladder_tiny[0]);
  sr->nsizes = nsizes;
  sr->budget = o->full ? 1.0 : (o->scale < 1 ? 0.02 : 0.12); /* timed seconds per cell */
  sr->frames = o->full ? 20 : (o->scale < 1 ? 3 : 6);
  sr->nm = tb_model_count < SCALING_MAX_MODELS ? tb_model_count : SCALING_MAX_MODELS;
  sr->cores = tb_threads_cores(), sr->big = -1, sr->threads_row = nsizes - 1;
  for (int r = 0; r < nsizes;
       r++) /* threads: at 100 000 tets (the size), else the largest */
    if (ladder[r] == THREADS_TETS) sr->threads_row = r;
  int threads_before = tb_threads(), failed = 0, nm = sr->nm, cores = sr->cores;
  double budget = sr->budget;
  int frames = sr->frames;
  size_row *rows = sr->rows;
  cell(*cells)[SCALING_MAX_SIZES] = sr->cells, *all = sr->all;
  /* big blocks from mmap, given back when freed: a model's arrays leave no
   * resident heap behind to hide the next one's (see run_measured) */
  mallopt(M_MMAP_THRESHOLD, 64 * 1024);
  mallopt(M_TRIM_THRESHOLD, 64 * 1024);
  tb_mesh inst;
  tb_instrument_def idef = tb_instrument_default_def();
  if (tb_instrument(&idef, &inst, &err)) {
    fprintf(stderr, "scaling: %s\n", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  for (int r = 0; r < nsizes; r++) {
    tb_progress("scaling", r, nsizes);
    scaling_mesh sm;
    memset(&sm, 0, sizeof sm);
    sm.tets = ladder[r], sm.seed = o->seed;
    failed |= size_case(su, &sm, &inst, frames, &rows[r]);
    if (rows[r].ok) sr->big = r;
    for (int k = 0; k < nm; k++)
      failed |= model_case(su, &sm, tb_model_classes[k]->name, budget,
                           r == sr->threads_row ? cores : 0, &cells[k][r], &all[k]);
    if (sm.made > 0) tb_mesh_free(&sm.mesh);
  }
  tb_progress("scaling", nsizes, nsizes);
  tb_threads_set(threads_before);
  mallopt(M_MMAP_THRESHOLD, 128 * 1024); /* glibc's default values back for the later suites */
  mallopt(M_TRIM_THRESHOLD, 128 * 1024);
  tb_mesh_free(&inst);
  sr->seconds = (double)(tb_time_ns() - start) * 1e-9;
  failed |= tb_scaling_report(su, sr);
  if (tb_suite_end(su, &err)) fprintf(stderr, "scaling: %s\n", err.msg), failed = 1;
  return failed;
}
