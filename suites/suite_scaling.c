/* The scaling suite: how every tet model of
 * models/model.c's table and the collision hierarchy grow with the mesh.
 *  1. ms per step against tets: each model of the table in the liver-stretch
 *     scene (thesis §3.5: the liver held along its back, a far patch pulled)
 *     on TetGen livers of a ladder of tet counts (tb_liver_of_tets, the pbd
 *     suite's), one thread; the model's step alone timed, CPU time (wall
 *     beside; as the pbd suite does), health checked after every step,
 *     untimed. A least-squares line
 *     through log(CPU ms) against log(tets) gives each model's exponent (slope)
 *     and where it crosses 33.3 ms (30 Hz, graphics) and 3.33 ms (300 Hz,
 *     haptics): the largest mesh still interactive, read off the line.
 *  2. Peak memory, as a difference in this process: before each one-thread
 *     run, freed memory is handed back (blocks above 64 KiB come from mmap,
 *     malloc_trim) and the peak RSS reset (5 to /proc/self/clear_refs);
 *     VmHWM after the run minus VmRSS before it is the peak the run added
 *     (the scene's copy of the mesh included), per tet. (A forked child
 *     cannot be used: CHOLMOD starts OpenMP threads, and libgomp hangs in a
 *     child of a process that has used them.)
 *  3. Threads at 12 800 and 100 000 tets (the patent's liver and ten
 *     times it; tiny runs: the largest): runs on 1, 2, 4, ... threads and
 *     on every core live side by side, taking turns step by step; wall ms
 *     per step (CPU beside), each count's speed-up over one thread (the
 *     median of the steps' paired wall-time ratios, with its 95% interval;
 *     "not measurable" when other processes held the cores), whether
 *     positions and velocities after the same steps are bit-identical on
 *     every count (a hash of their bytes), and the speed-up predicted for
 *     4, 8 and 16 cores from the one measured on the most
 *     (tb_scaling_predict).
 *  4. Collision: the composite hierarchy (collision/tb_bvh.h) over all tet
 *     faces of each liver (the thesis's liver model, as the refit suite)
 *     against the instrument held inside it, the liver deformed every frame
 *     (measure/collision_scene.c): refit (delta 0) and the all-pairs query, CPU
 *     ms against triangles on one thread, fitted the same way. */
#include <malloc.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scaling_priv.h"
#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "measure/tb_collision_scene.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"
#include "report/tb_results.h"
#include "scenes/tb_collider.h"
#include "scenes/tb_sim.h"

#define MAX_STEPS 400
#define THREADS_QUICK_S 12 /* quick mode: a model's thread runs take at most this long */

/* The sizes of the thread runs: the patent's liver (table 2's largest) and
 * ten times it. */
static const int thread_sizes[] = {12800, 100000};

/* Tet counts: --full, the default (quick) and --scale < 1 (tests). */
static const int ladder_full[] = {600, 1200, 2500, 5000, 12800, 20000, 50000, 100000, 200000};
static const int ladder_quick[] = {600, 2500, 12800, 40000, 100000};
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

/* A model stepping in the scene on a thread count of its own, so that two
 * can take turns: the model's step alone timed (CPU and wall), the health
 * check after every step untimed. */
typedef struct stepper {
  const char *model;
  int threads, live, failed, n; /* n: timed steps so far */
  tb_sim s;
  double *wall, *cpu; /* MAX_STEPS each */
  tb_error err;
} stepper;

static void stepper_open(stepper *u, const tb_mesh *mesh, const char *model, int threads,
                         double *store) {
  memset(u, 0, sizeof *u);
  u->model = model, u->threads = threads, u->wall = store, u->cpu = store + MAX_STEPS;
  tb_threads_set(threads);
  if (tb_sim_create(&u->s, SCENE, NULL, model, NULL, mesh, &u->err))
    u->failed = 1;
  else
    u->live = 1;
}

static void stepper_close(stepper *u) {
  if (u->live) tb_sim_destroy(&u->s);
  u->live = 0;
}

/* One step on the stepper's thread count; timed: its CPU and wall ms kept. */
static void stepper_step(stepper *u, int timed) {
  if (!u->live || u->failed || (timed && u->n >= MAX_STEPS)) return;
  tb_threads_set(u->threads);
  tb_sim *s = &u->s;
  if (tb_sim_loads(s, s->t + s->def.dt, &u->err)) {
    u->failed = 1;
    return;
  }
  tb_step in = tb_sim_step_input(s);
  double w, c;
  tb_clock clk = tb_clock_start();
  int rc = tb_model_step(&s->model, &in, &u->err);
  tb_clock_ms(&clk, &w, &c);
  if (rc) {
    u->failed = 1;
    return;
  }
  s->t += s->def.dt, s->steps++;
  if (timed) u->wall[u->n] = w, u->cpu[u->n++] = c;
  int np = tb_model_npoints(&s->model);
  tb_mesh pts = {0};
  pts.nv = np;
  tb_health h = tb_model_health(np == s->mesh.nv ? &s->mesh : &pts, tb_model_positions(&s->model),
                                tb_model_velocities(&s->model), s->def.vmax,
                                np == s->mesh.nv ? s->def.inversion : 0);
  if (!h.ok) {
    tb_error_set(&u->err, u->model, 0, "unstable at t = %g: %s", s->t, h.reason);
    u->failed = 1;
  }
  tb_progress_tick("%s, %d thread%s: step %ld", u->model, u->threads, u->threads > 1 ? "s" : "",
                   s->steps);
}

/* A hash of the stepper's positions and velocities. */
static uint64_t stepper_sum(const stepper *u) {
  int np = tb_model_npoints(&u->s.model);
  uint64_t h =
      fnv(1469598103934665603ull, tb_model_positions(&u->s.model), sizeof(tb_vec3) * (size_t)np);
  return fnv(h, tb_model_velocities(&u->s.model), sizeof(tb_vec3) * (size_t)np);
}

/* model on mesh in the scene, one thread: one warm-up step, then timed
 * steps until budget seconds of CPU time (at least 3, at most MAX_STEPS).
 * c gets the medians, the count and the state's hash. */
static int run_model(const tb_mesh *mesh, const char *model, double budget, cell *c,
                     tb_error *err) {
  double *store = malloc(sizeof(double) * 2 * MAX_STEPS);
  if (!store) return tb_error_set(err, model, 0, "out of memory");
  stepper u;
  stepper_open(&u, mesh, model, 1, store);
  stepper_step(&u, 0);
  double spent = 0;
  while (!u.failed && u.n < MAX_STEPS && (u.n < 3 || spent < budget)) {
    stepper_step(&u, 1);
    if (!u.failed) spent += u.cpu[u.n - 1] * 1e-3;
  }
  int rc = u.failed ? -1 : 0;
  if (rc)
    *err = u.err;
  else {
    c->ms = tb_stats_of(u.cpu, u.n).median, c->wall = tb_stats_of(u.wall, u.n).median;
    c->steps = u.n, c->sum = stepper_sum(&u);
  }
  stepper_close(&u);
  free(store);
  return rc;
}

/* run_model with the peak RSS it added (see the head): freed
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
  if (run_model(mesh, model, budget, c, &err))
    snprintf(c->why, sizeof c->why, "%.150s", err.msg);
  else
    c->ok = 1;
  c->rss = reset ? status_kb("VmHWM:") - rss0 : NAN;
}

/* The thread counts run on a machine of `cores`: 1, 2, 4, ... below it,
 * then the cores; at most SCALING_MAX_COUNTS (16 and the cores beyond). */
static int thread_counts(int cores, int *count) {
  int n = 0;
  for (int c = 1; c < cores && n < SCALING_MAX_COUNTS - 1 && c <= 16; c *= 2) count[n++] = c;
  count[n++] = cores;
  return n;
}

/* model on mesh on each thread count (thread_counts), the runs live side
 * by side and taking turns step by step (one warm-up step each, then steps
 * timed), so that a busy spell of the machine falls on all alike and step
 * k of each is the same step of the scene. */
static void run_threads(tb_suite *su, const tb_mesh *mesh, const char *model, int cores, int steps,
                        thread_cell *t) {
  memset(t, 0, sizeof *t);
  t->ncounts = thread_counts(cores, t->count);
  const int nc = t->ncounts;
  double *store = malloc(sizeof(double) * 2 * MAX_STEPS * (size_t)nc);
  stepper *u = calloc((size_t)nc, sizeof *u);
  if (!store || !u) {
    snprintf(t->why, sizeof t->why, "out of memory");
    free(store), free(u);
    return;
  }
  int failed = -1; /* the first count that failed */
  for (int q = 0; q < nc; q++)
    stepper_open(&u[q], mesh, model, t->count[q], store + 2 * MAX_STEPS * q);
  for (int q = 0; q < nc; q++) stepper_step(&u[q], 0);
  for (int k = 0; k < steps && failed < 0; k++)
    for (int q = 0; q < nc && failed < 0; q++) {
      stepper_step(&u[q], 1);
      if (u[q].failed) failed = q;
    }
  for (int q = 0; q < nc && failed < 0; q++)
    if (u[q].failed) failed = q;
  if (failed >= 0) {
    snprintf(t->why, sizeof t->why, "%d thread%s: %.140s", t->count[failed],
             t->count[failed] > 1 ? "s" : "", u[failed].err.msg);
  } else {
    int n = u[0].n;
    uint64_t sum0 = stepper_sum(&u[0]);
    t->ok = 1, t->steps = n, t->identical = 1;
    for (int q = 0; q < nc; q++) {
      t->wall[q] = tb_stats_of(u[q].wall, n).median, t->cpu[q] = tb_stats_of(u[q].cpu, n).median;
      t->speedup[q] = tb_ratio_est(u[0].wall, u[q].wall, n);
      t->identical &= stepper_sum(&u[q]) == sum0;
    }
  }
  for (int q = 0; q < nc; q++) stepper_close(&u[q]);
  free(store), free(u);
  tb_noise nz = tb_suite_noise(su, cores);
  t->busy = nz.busy, t->others = nz.others, t->cores = nz.cores;
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
  double *u = malloc(sizeof(double) * 3 * (size_t)frames), *q = u ? u + frames : NULL,
         *b = u ? u + 2 * frames : NULL; /* refit CPU, query CPU, both wall */
  tb_pairlist pl = {0, 0, NULL};
  tb_collider *c =
      x && u ? tb_collider_new("composite", &liver, inst, NULL, NULL, NULL, err) : NULL;
  tb_mat3 R;
  tb_vec3 t;
  tb_collision_scene_pose(0.5, &R, &t); /* the tip inside the liver (the refit suite's pose) */
  int rc = !c || tb_collider_pose(c, R, t, err) ? -1 : 0;
  for (int f = 0; f < frames && !rc; f++) {
    tb_collision_scene_deform(tets->x, liver.nv, 0.1 * (f + 1), 0.25, x);
    double w0, w1;
    tb_clock c0 = tb_clock_start();
    rc = tb_collider_deform(c, x, 0, err);
    tb_clock_ms(&c0, &w0, u + f);
    tb_clock c1 = tb_clock_start();
    if (!rc) rc = tb_collider_query(c, &pl, NULL, err);
    tb_clock_ms(&c1, &w1, q + f);
    b[f] = w0 + w1;
  }
  if (!rc) {
    w->refit_ms = tb_stats_of(u, frames).median, w->query_ms = tb_stats_of(q, frames).median;
    w->both_wall = tb_stats_of(b, frames).median;
    w->pairs = pl.n;
  }
  tb_collider_free(c);
  tb_pairlist_free(&pl);
  free(liver.tri), free(x), free(u);
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
        w->refit_ms = w->query_ms = w->both_wall = NAN;
        failed = 1;
      }
    }
    double v[] = {w->ok,    w->target,   w->ntet,     w->nv,  w->ntri,     w->pairs,
                  w->gen_s, w->refit_ms, w->query_ms, failed, w->both_wall};
    memcpy(c.v, v, sizeof v);
    c.nv = (int)(sizeof v / sizeof v[0]), c.nt = 1;
    snprintf(c.t[0], sizeof c.t[0], "%s", w->why);
    tb_suite_case_done(su, &c);
    return failed;
  }
  w->ok = (int)c.v[0], w->target = (int)c.v[1], w->ntet = (int)c.v[2], w->nv = (int)c.v[3];
  w->ntri = (int)c.v[4], w->pairs = (int)c.v[5], w->gen_s = c.v[6], w->refit_ms = c.v[7];
  w->query_ms = c.v[8], w->both_wall = c.v[10];
  snprintf(w->why, sizeof w->why, "%.159s", c.t[0]);
  return (int)c.v[9];
}

/* model on the mesh, one thread (peak RSS measured), and with cores > 0
 * one thread against all cores (thr). 1 when the thread count changed a
 * bit. */
static int model_case(tb_suite *su, scaling_mesh *sm, const char *model, double budget, int cores,
                      int min_steps, double cap_s, cell *one, thread_cell *thr) {
  char key[96];
  snprintf(key, sizeof key, "tets:%d/%s%s", sm->tets, model, cores ? "/threads" : "");
  tb_case c;
  int mode = tb_suite_case(su, key, 0, &c);
  memset(one, 0, sizeof *one);
  if (cores) memset(thr, 0, sizeof *thr);
  if (mode == TB_CASE_SKIP) return 0;
  if (mode == TB_CASE_RUN) {
    const tb_mesh *m = mesh_of(sm, NULL);
    if (!m)
      snprintf(one->why, sizeof one->why, "no mesh");
    else {
      tb_progress_tick("%s", model);
      run_measured(m, model, budget, one);
      if (!one->ok) fprintf(stderr, "scaling: %s on %d tets: %s\n", model, m->ntet, one->why);
    }
    int pairs = one->steps > min_steps ? one->steps : min_steps;
    int counts[SCALING_MAX_COUNTS];
    double secs = 1e-3 * pairs * one->wall * thread_counts(cores > 0 ? cores : 1, counts);
    /* the thread runs' time, at most about (no count slower than one thread) */
    if (m && cores && one->ok && secs <= cap_s)
      run_threads(su, m, model, cores, pairs, thr);
    else if (cores && one->ok)
      snprintf(thr->why, sizeof thr->why, "not run: %.2g s a step (%d pairs would take %.0f s)",
               one->wall * 1e-3, pairs, secs);
    else if (cores)
      snprintf(thr->why, sizeof thr->why, "-");
    double *v = c.v;
    v[0] = one->ok, v[1] = one->steps, v[2] = one->ms, v[3] = one->wall, v[4] = one->rss;
    put_sum(v + 5, one->sum);
    snprintf(c.t[0], sizeof c.t[0], "%s", one->why);
    c.nv = 7, c.nt = 1;
    if (cores) {
      double *x = c.v + 7;
      x[0] = thr->ok, x[1] = thr->steps, x[2] = thr->ncounts, x[3] = thr->identical;
      x[4] = thr->busy, x[5] = thr->others, x[6] = thr->cores;
      for (int q = 0; q < thr->ncounts; q++) {
        double *y = x + 7 + 7 * q;
        y[0] = thr->count[q], y[1] = thr->wall[q], y[2] = thr->cpu[q];
        y[3] = thr->speedup[q].value, y[4] = thr->speedup[q].lo, y[5] = thr->speedup[q].hi;
        y[6] = thr->speedup[q].n;
      }
      snprintf(c.t[1], sizeof c.t[1], "%s", thr->why);
      c.nv = 7 + 7 + 7 * SCALING_MAX_COUNTS, c.nt = 2;
    }
    tb_suite_case_done(su, &c);
  } else {
    const double *v = c.v;
    one->ok = (int)v[0], one->steps = (int)v[1], one->ms = v[2], one->wall = v[3];
    one->rss = v[4], one->sum = get_sum(v + 5);
    snprintf(one->why, sizeof one->why, "%.159s", c.t[0]);
    if (cores) {
      const double *x = c.v + 7;
      thr->ok = (int)x[0], thr->steps = (int)x[1], thr->ncounts = (int)x[2];
      thr->identical = (int)x[3], thr->busy = (int)x[4], thr->others = x[5];
      thr->cores = (int)x[6];
      if (thr->ncounts < 0 || thr->ncounts > SCALING_MAX_COUNTS) thr->ok = 0, thr->ncounts = 0;
      for (int q = 0; q < thr->ncounts; q++) {
        const double *y = x + 7 + 7 * q;
        thr->count[q] = (int)y[0], thr->wall[q] = y[1], thr->cpu[q] = y[2];
        thr->speedup[q] = (tb_est){y[3], y[4], y[5], (int)y[6]};
      }
      snprintf(thr->why, sizeof thr->why, "%.159s", c.t[1]);
    }
  }
  /* the thread count must not change a bit */
  return cores && one->ok && thr->ok && !thr->identical;
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
  sr->cores = tb_threads_cores(), sr->big = -1;
  for (int r = 0; r < nsizes; r++) /* the thread runs' sizes, else the largest */
    for (int q = 0; q < 2; q++)
      if (ladder[r] == thread_sizes[q]) sr->thread_rows[sr->nthread_rows++] = r;
  if (sr->nthread_rows == 0) sr->thread_rows[sr->nthread_rows++] = nsizes - 1;
  int threads_before = tb_threads_setting(), failed = 0, nm = sr->nm, cores = sr->cores;
  int min_steps = o->scale < 1 ? 3 : TB_EST_MIN; /* the thread runs' pairs */
  /* quick mode bounds a model's thread runs (a step of seconds would take
   * minutes); --full and the smoke runs' tiny meshes run them all */
  double cap_s = o->full || o->scale < 1 ? INFINITY : THREADS_QUICK_S;
  double budget = sr->budget;
  int frames = sr->frames;
  size_row *rows = sr->rows;
  cell(*cells)[SCALING_MAX_SIZES] = sr->cells;
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
    int tr = -1; /* this size's thread row */
    for (int q = 0; q < sr->nthread_rows; q++)
      if (sr->thread_rows[q] == r) tr = q;
    for (int k = 0; k < nm; k++)
      failed |= model_case(su, &sm, tb_model_classes[k]->name, budget, tr >= 0 ? cores : 0,
                           min_steps, cap_s, &cells[k][r], tr >= 0 ? &sr->thr[k][tr] : NULL);
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
