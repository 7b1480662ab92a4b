/* The 2022 patent's performance tables (a collision simulation method of
 * soft tissue and a rigid ground, experiment 2, its tables 1 and 2): pbd-stvk
 * at the patent's settings (k 0.4, nu 0.4, 5 iterations, dt 0.005) in the
 * liver-drop scene (a liver falling onto the ground, so the ground
 * constraint is in every sweep once it lands) on livers of the patent's tet
 * counts: 596 (SOFA's liver.msh when ../shared/data is present, else ours),
 * 5395, 7325 and 12829 (TetGen livers within 2% of those counts).
 *  1. Mean solve time per step and per element, one thread, CPU time, the
 *     patent's figures beside ours, and microseconds per element-step with
 *     its 95% interval (the goal's verdict: met, not met or inconclusive);
 *     the deepest node below the ground after the projection over the run.
 *  2. One thread against all cores (wall time, CPU beside): the speed-ups
 *     with their intervals beside the patent's ("not measurable" when other
 *     processes held the cores), and whether the positions after the run
 *     are bit-identical.
 *  3. A peer: Bullet's btSoftBody (the bullet-softbody model) dropped the
 *     same way, CPU ms/step beside ours and the ratio with its interval.
 * Timing: the model's step alone, CPU and wall (the scene's health check
 * runs after each step, untimed); a warm-up, then blocks of steps, each
 * block's mean one repetition, the three runs of a liver taking turns block
 * by block; medians over the blocks, ratios paired by block. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_suites.h"
#include "tb_pbd_accuracy.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"
#include "models/tb_model.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

#define SCENE "liver-drop"
#define MODEL "pbd-stvk"
#define DT 0.005        /* the patent's time step */
#define K_STIFF 0.4     /* the patent's k */
#define NU 0.4          /* the patent's Poisson ratio */
#define ITERS 5         /* the patent's iterations */
#define GOAL_US 0.2     /* our goal: microseconds per element-step at 12829 tets, one thread */
#define DEPTH_GOAL 1e-6 /* our goal: no node deeper below the ground than this x size */
#define SOFA_LIVER TB_SHARED_DATA_FILE("sofa/liver.msh")

/* The patent's tables 1 and 2 (its machine is not named). */
#define NROWS 4
static const struct {
  const char *name;
  int tets;
  double ms, ms_elem;               /* table 1: mean solve time per step, per element */
  double ms_one, ms_multi, speedup; /* table 2: one thread, OpenMP, speed-up */
} patent[NROWS] = {
    {"liver model 1", 596, 0.50, 8.39e-4, 0.50, 0.40, 1.25},
    {"liver model 2", 5395, 5.20, 9.64e-4, 5.20, 1.85, 2.81},
    {"liver model 3", 7325, 6.80, 9.28e-4, 6.80, 2.10, 3.24},
    {"reference model", 12829, 12.96, 1.01e-3, 12.96, 3.77, 3.44},
};

/* How a run is timed: warm steps, then nblocks blocks of block steps. */
typedef struct plan {
  int warm, block, nblocks;
} plan;
static int plan_steps(const plan *p) { return p->warm + p->block * p->nblocks; }

/* Moves m so its bounding box's bottom centre is at b (as the scene's
 * [mesh] bottom does). */
static void place(tb_mesh *m, tb_vec3 b) {
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  tb_vec3 d = tb_sub(b, tb_v3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z));
  for (int i = 0; i < m->nv; i++) m->x[i] = tb_add(m->x[i], d);
}

/* The liver of row r placed where the scene puts its own: SOFA's for 596
 * tets when present, else a TetGen liver within 2% of the patent's count. */
static int make_liver(int r, const tb_mesh *scene_mesh, int sofa, uint64_t seed, tb_mesh *out,
                      char *source, size_t cap, tb_error *err) {
  if (r == 0 && sofa) {
    snprintf(source, cap, "SOFA liver.msh");
    return tb_mesh_copy(out, scene_mesh) ? tb_error_set(err, "pbd", 0, "out of memory") : 0;
  }
  if (tb_liver_of_tets(patent[r].tets, seed, out, err)) return -1;
  tb_vec3 lo, hi;
  tb_mesh_bbox(scene_mesh, &lo, &hi);
  place(out, tb_v3(0.5 * (lo.x + hi.x), 0.5 * (lo.y + hi.y), lo.z));
  snprintf(source, cap, "TetGen liver");
  return 0;
}

static tb_settings patent_settings(void) {
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_setd(&d, "k", K_STIFF, NULL);
  tb_settings_setd(&d, "nu", NU, NULL);
  tb_settings_setd(&d, "iterations", ITERS, NULL);
  return d;
}

/* What the scene file sets, for the notes: the ground, gravity and dt, the
 * drop height, pbd-stvk's density and damping. */
typedef struct scene_info {
  tb_ground ground;
  tb_vec3 gravity;
  double dt, g, height, density, damping, drag;
} scene_info;

static int scene_info_of(const tb_mesh *mesh, scene_info *si, tb_error *err) {
  tb_settings set = patent_settings();
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = DT;
  tb_sim s;
  if (tb_sim_create(&s, SCENE, &sd, MODEL, &set, mesh, err)) return -1;
  int rc = tb_sim_loads(&s, 0, err);
  if (!rc && !s.has_ground) rc = tb_error_set(err, SCENE, 0, "the scene has no ground");
  si->ground = s.ground, si->gravity = s.gravity, si->dt = s.def.dt, si->g = tb_len(s.gravity);
  si->drag = s.def.drag;
  si->height = INFINITY;
  for (int i = 0; i < s.mesh.nv; i++)
    si->height = fmin(si->height, tb_dot(tb_sub(s.mesh.x[i], s.ground.p), s.ground.n));
  tb_model_setting(MODEL, &s.settings, "density", &si->density);
  tb_model_setting(MODEL, &s.settings, "damping", &si->damping);
  tb_sim_destroy(&s);
  return rc;
}

/* The peer's settings: btSoftBody's links at the patent's stiffness and
 * iterations, no damping, the density pbd-stvk has in the scene, and
 * Bullet's own ground contact (hardness 1 and a margin of 1e-3 of the
 * size: the model's defaults; friction the ground's kinetic one). */
static tb_settings peer_settings(const scene_info *si) {
  tb_settings d;
  tb_settings_init(&d);
  tb_settings_setd(&d, "stiffness", K_STIFF, NULL);
  tb_settings_setd(&d, "iterations", ITERS, NULL);
  tb_settings_setd(&d, "damping", 0, NULL);
  tb_settings_setd(&d, "density", si->density, NULL);
  tb_settings_set(&d, "contact=bullet", NULL);
  return d;
}

/* One simulation timed block by block on a thread count of its own, so
 * that several can take turns: a model in the scene, the model's step
 * alone timed (CPU and wall), the health check after every step untimed. */
typedef struct runner {
  const char *model;
  int threads, live, failed, nv;
  tb_sim s;
  long k;             /* steps done */
  double *wall, *cpu; /* nblocks: mean ms per step of each block */
  double deepest;     /* the deepest node below the ground after a step, over the run */
  double lowest_end;  /* the lowest node's height above the ground at the end */
  double size;        /* the rest mesh's box diagonal */
  tb_error err;
} runner;

static int runner_open(runner *u, const char *model, int threads, const tb_settings *set,
                       const tb_mesh *mesh, double *store, int nblocks) {
  memset(u, 0, sizeof *u);
  u->model = model, u->threads = threads, u->wall = store, u->cpu = store + nblocks;
  for (int b = 0; b < 2 * nblocks; b++) store[b] = NAN;
  tb_threads_set(threads);
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = DT;
  if (tb_sim_create(&u->s, SCENE, &sd, model, set, mesh, &u->err)) return u->failed = 1, -1;
  u->live = 1, u->size = u->s.size, u->nv = u->s.mesh.nv;
  if (!u->s.has_ground) {
    tb_error_set(&u->err, SCENE, 0, "the scene has no ground");
    u->failed = 1;
    return -1;
  }
  return 0;
}

static void runner_close(runner *u) {
  if (u->live) tb_sim_destroy(&u->s);
  u->live = 0;
}

/* The runner's next n steps on its own thread count; with block >= 0 their
 * mean CPU and wall ms per step go to that block. */
static void runner_steps(runner *u, int n, int block) {
  if (!u->live || u->failed) return;
  tb_threads_set(u->threads);
  tb_sim *s = &u->s;
  double wall = 0, cpu = 0;
  for (int k = 0; k < n && !u->failed; k++) {
    if (tb_sim_loads(s, s->t + s->def.dt, &u->err)) {
      u->failed = 1;
      break;
    }
    tb_step in = tb_sim_step_input(s); /* the scene has a ground (runner_open) */
    double w, c;
    tb_clock clk = tb_clock_start();
    int rc = tb_model_step(&s->model, &in, &u->err);
    tb_clock_ms(&clk, &w, &c);
    if (rc) {
      u->failed = 1;
      break;
    }
    wall += w, cpu += c;
    s->t += s->def.dt, s->steps++, u->k++;
    const tb_vec3 *x = tb_model_positions(&s->model);
    double low = INFINITY;
    for (int i = 0; i < u->nv; i++) low = fmin(low, tb_dot(tb_sub(x[i], s->ground.p), s->ground.n));
    if (-low > u->deepest) u->deepest = -low;
    u->lowest_end = low;
    tb_health h =
        tb_model_health(&s->mesh, x, tb_model_velocities(&s->model), s->def.vmax, s->def.inversion);
    if (!h.ok) {
      tb_error_set(&u->err, u->model, 0, "unstable at t = %g: %s", s->t, h.reason);
      u->failed = 1;
    }
    tb_progress_tick("%s, %d threads: step %ld", u->model, u->threads, u->k);
  }
  if (!u->failed && block >= 0) u->wall[block] = wall / n, u->cpu[block] = cpu / n;
}

/* Everything measured on one liver: medians over blocks with their 95%
 * intervals (ms per step), the ratios paired by block. */
typedef struct row {
  int ok, nv, ntet, links, slabs, phases, blocks, bt_ok;
  char source[32], why[160];
  tb_est one, one_wall, all, all_cpu, speedup; /* one thread CPU and wall; all threads wall, CPU */
  tb_est us_elem;                              /* one thread CPU us per element-step */
  tb_est bullet, bullet_wall, peer;            /* btSoftBody CPU, wall, over pbd-stvk CPU */
  double deepest, lowest_end, size, bt_deepest, bt_lowest_end;
  int identical;
} row;

/* A benchmark entry recorded with `threads` in effect. */
static void bench_entry(tb_suite *su, const char *name, const double *wall, const double *cpu,
                        int n, int threads) {
  int was = tb_threads_setting();
  tb_threads_set(threads);
  tb_suite_bench(su, name, wall, cpu, n, "ms");
  tb_threads_set(was);
}

/* Runs row r: pbd-stvk on one thread and on all cores and btSoftBody on
 * one thread, live side by side and taking turns block by block (one
 * thread, all threads, btSoftBody, one thread, ...), so that a busy spell
 * of the machine falls on all three alike and block b of each covers the
 * same stretch of the drop. */
static void measure(tb_suite *su, int r, const tb_mesh *mesh, const scene_info *si, const plan *p,
                    int cores, row *w) {
  int nb = p->nblocks;
  double *store = malloc(sizeof(double) * 7 * (size_t)nb), *us = store ? store + 6 * nb : NULL;
  runner u[3]; /* pbd-stvk on 1 thread, on all, btSoftBody */
  memset(u, 0, sizeof u);
  w->ok = 0, w->blocks = nb;
  if (!store) {
    snprintf(w->why, sizeof w->why, "out of memory");
    return;
  }
  tb_settings set = patent_settings(), peer = peer_settings(si);
  runner_open(&u[0], MODEL, 1, &set, mesh, store, nb);
  runner_open(&u[1], MODEL, cores, &set, mesh, store + 2 * nb, nb);
  runner_open(&u[2], "bullet-softbody", 1, &peer, mesh, store + 4 * nb, nb);
  for (int q = 0; q < 3; q++) runner_steps(&u[q], p->warm, -1);
  for (int b = 0; b < nb; b++)
    for (int q = 0; q < 3; q++) runner_steps(&u[q], p->block, b);
  char name[128];
  if (u[0].failed) {
    snprintf(w->why, sizeof w->why, "unstable (%.140s)", u[0].err.msg);
    goto done;
  }
  if (u[1].failed) {
    snprintf(w->why, sizeof w->why, "unstable with %d threads (%.120s)", cores, u[1].err.msg);
    goto done;
  }
  w->one = tb_median_est(u[0].cpu, nb), w->one_wall = tb_median_est(u[0].wall, nb);
  for (int b = 0; b < nb; b++) us[b] = 1e3 * u[0].cpu[b] / mesh->ntet;
  w->us_elem = tb_median_est(us, nb);
  w->deepest = u[0].deepest, w->lowest_end = u[0].lowest_end, w->size = u[0].size;
  snprintf(name, sizeof name, MODEL "/tets:%d/threads:1", mesh->ntet);
  bench_entry(su, name, u[0].wall, u[0].cpu, nb, 1);
  tb_suite_counter(su, name, "tets", mesh->ntet);
  tb_suite_counter(su, name, "nodes", mesh->nv);
  tb_suite_counter_est(su, name, "us_per_element_step", w->us_elem);
  tb_suite_counter(su, name, "deepest_below_ground", w->deepest);
  tb_suite_counter(su, name, "deepest_below_ground_of_size", w->deepest / w->size);
  tb_suite_counter(su, name, "patent_ms_per_step", patent[r].ms);

  w->all = tb_median_est(u[1].wall, nb), w->all_cpu = tb_median_est(u[1].cpu, nb);
  w->speedup = tb_ratio_est(u[0].wall, u[1].wall, nb);
  w->identical = !memcmp(tb_model_positions(&u[0].s.model), tb_model_positions(&u[1].s.model),
                         sizeof(tb_vec3) * (size_t)u[0].nv);
  snprintf(name, sizeof name, MODEL "/tets:%d/threads:%d", mesh->ntet, cores);
  bench_entry(su, name, u[1].wall, u[1].cpu, nb, cores);
  tb_suite_counter_est(su, name, "speedup", w->speedup);
  tb_suite_counter(su, name, "identical_to_one_thread", w->identical);
  tb_suite_counter(su, name, "patent_speedup", patent[r].speedup);

  int *edges = NULL;
  w->links = tb_mesh_edges(mesh, &edges); /* btSoftBody's links: one per tet edge */
  free(edges);
  if (u[2].failed) {
    fprintf(stderr, "pbd: btSoftBody on %d tets: %s\n", mesh->ntet, u[2].err.msg);
  } else {
    w->bt_ok = 1;
    w->bullet = tb_median_est(u[2].cpu, nb), w->bullet_wall = tb_median_est(u[2].wall, nb);
    w->peer = tb_ratio_est(u[2].cpu, u[0].cpu, nb);
    w->bt_deepest = u[2].deepest, w->bt_lowest_end = u[2].lowest_end;
    snprintf(name, sizeof name, "btSoftBody/tets:%d/threads:1", mesh->ntet);
    bench_entry(su, name, u[2].wall, u[2].cpu, nb, 1);
    tb_suite_counter(su, name, "links", w->links);
    tb_suite_counter_est(su, name, "ratio_to_pbd_stvk", w->peer);
    tb_suite_counter(su, name, "deepest_below_ground", u[2].deepest);
  }
  w->ok = 1;
done:
  for (int q = 0; q < 3; q++) runner_close(&u[q]);
  free(store);
}

/* An estimate's interval as two CSV-only columns. */
static void est_bounds(tb_table *t, tb_est e) {
  tb_table_num(t, e.lo, "%.6g");
  tb_table_num(t, e.hi, "%.6g");
}

static void solve_table(tb_suite *su, const row *rows) {
  static const char *cols[] = {"model (patent)",
                               "mesh",
                               "tets",
                               "nodes",
                               "threads",
                               "ms/step CPU (ours, median)",
                               "ms/step wall (ours, median)",
                               "ms/step (patent)",
                               "ms/element CPU (ours)",
                               "ms/element (patent)",
                               "us/element-step CPU (ours, 95% interval)",
                               "us/element-step CPU low",
                               "us/element-step CPU high",
                               "us/element-step (patent)",
                               "deepest below ground (of size)",
                               "no node below ground beyond 1e-6 of size"};
  tb_table *t = tb_table_new("solve",
                             "Patent table 1: mean solve time per step and per element, pbd-stvk, "
                             "one thread, CPU time (k 0.4, nu 0.4, 5 iterations, dt 0.005)",
                             16, cols);
  tb_table_only(t, 11, TB_CSV_ONLY), tb_table_only(t, 12, TB_CSV_ONLY);
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].name);
    tb_table_cell(t, "%s", w->source[0] ? w->source : "-");
    if (w->ntet) {
      tb_table_numf(t, w->ntet, "%d (%+.2f%%)", w->ntet,
                    100.0 * (w->ntet - patent[r].tets) / patent[r].tets);
      tb_table_num(t, w->nv, "%.0f");
    } else {
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    }
    tb_table_num(t, 1, "%.0f");
    if (!w->ok) {
      tb_table_cell(t, "%s", w->why);
      for (int c = 6; c < 16; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w->one.value, "%.3f");
    tb_table_num(t, w->one_wall.value, "%.3f");
    tb_table_num(t, patent[r].ms, "%.2f");
    tb_table_num(t, w->one.value / w->ntet, "%.3e");
    tb_table_num(t, patent[r].ms_elem, "%.3e");
    tb_table_est(t, w->us_elem, "%.3f", "");
    est_bounds(t, w->us_elem);
    tb_table_num(t, 1e3 * patent[r].ms_elem, "%.3f");
    tb_table_num(t, w->deepest / w->size, "%.2e");
    tb_table_cell(t, "%s", w->deepest <= DEPTH_GOAL * w->size ? "yes" : "NO");
  }
  tb_suite_table(su, t);
}

/* "not measurable (machine busy: ...)" when the machine could not give
 * `threads` threads their cores, else NULL. */
static const char *busy_text(const tb_noise *n, int threads, char *buf, size_t cap) {
  if (threads < 2) return snprintf(buf, cap, "not measurable (one core)"), buf;
  if (!n->busy) return NULL;
  snprintf(buf, cap, "not measurable (machine busy: others kept %.1f of %d cores busy%s)",
           n->others, n->cores, n->steal > 0.05 ? ", the hypervisor stole over 5%" : "");
  return buf;
}

static void thread_table(tb_suite *su, const row *rows, int cores, const tb_noise *nz) {
  static const char *cols[] = {"model (patent)",
                               "tets",
                               "slabs",
                               "phases a sweep",
                               "threads",
                               "ms/step wall, 1 thread (median)",
                               "ms/step wall, all threads (median)",
                               "ms/step CPU, 1 thread (median)",
                               "ms/step CPU, all threads (median)",
                               "speed-up, wall (ours, 95% interval)",
                               "speed-up low",
                               "speed-up high",
                               "speed-up measurable",
                               "patent: 1 thread (ms)",
                               "patent: OpenMP (ms)",
                               "speed-up (patent)",
                               "identical"};
  char title[200], busy[200];
  snprintf(title, sizeof title,
           "Patent table 2: one thread against all %d cores (wall time, CPU beside); positions "
           "after the run bit-identical?",
           cores);
  tb_table *t = tb_table_new("threads", title, 17, cols);
  tb_table_only(t, 10, TB_CSV_ONLY), tb_table_only(t, 11, TB_CSV_ONLY);
  const char *why = busy_text(nz, cores, busy, sizeof busy);
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].name);
    if (w->ntet)
      tb_table_num(t, w->ntet, "%.0f"), tb_table_num(t, w->slabs, "%.0f"),
          tb_table_num(t, w->phases, "%.0f");
    else
      tb_table_cell(t, "-"), tb_table_cell(t, "-"), tb_table_cell(t, "-");
    tb_table_num(t, cores, "%.0f");
    if (w->ok) {
      tb_table_num(t, w->one_wall.value, "%.3f");
      tb_table_num(t, w->all.value, "%.3f");
      tb_table_num(t, w->one.value, "%.3f");
      tb_table_num(t, w->all_cpu.value, "%.3f");
      tb_table_est(t, w->speedup, "%.2f", "x");
      est_bounds(t, w->speedup);
      tb_table_cell(t, "%s", why ? why : "yes");
    } else {
      for (int c = 4; c < 12; c++) tb_table_cell(t, "-");
    }
    tb_table_num(t, patent[r].ms_one, "%.2f");
    tb_table_num(t, patent[r].ms_multi, "%.2f");
    tb_table_num(t, patent[r].speedup, "%.2fx");
    tb_table_cell(t, "%s", !w->ok ? "-" : (w->identical ? "yes" : "NO"));
  }
  tb_suite_table(su, t);
}

static void bullet_table(tb_suite *su, const row *rows) {
  static const char *cols[] = {"model (patent)",
                               "tets",
                               "links (tet edges)",
                               "threads",
                               "btSoftBody ms/step CPU (median)",
                               "pbd-stvk ms/step CPU (median)",
                               "btSoftBody / pbd-stvk (CPU, 95% interval)",
                               "btSoftBody / pbd-stvk low",
                               "btSoftBody / pbd-stvk high",
                               "btSoftBody ms/step wall (median)",
                               "btSoftBody deepest below ground (of size)",
                               "btSoftBody lowest node at the end (of size)"};
  tb_table *t = tb_table_new("peer",
                             "Peer: Bullet's btSoftBody (links on tet edges, kLST 0.4, 5 position "
                             "iterations) dropped on the same ground, one thread, CPU time",
                             12, cols);
  tb_table_only(t, 7, TB_CSV_ONLY), tb_table_only(t, 8, TB_CSV_ONLY);
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].name);
    if (!w->ok || !w->bt_ok) {
      if (w->ntet)
        tb_table_num(t, w->ntet, "%.0f");
      else
        tb_table_cell(t, "-");
      for (int c = 2; c < 12; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w->ntet, "%.0f");
    tb_table_num(t, w->links, "%.0f");
    tb_table_num(t, 1, "%.0f");
    tb_table_num(t, w->bullet.value, "%.3f");
    tb_table_num(t, w->one.value, "%.3f");
    tb_table_est(t, w->peer, "%.2f", "x");
    est_bounds(t, w->peer);
    tb_table_num(t, w->bullet_wall.value, "%.3f");
    tb_table_num(t, w->bt_deepest / w->size, "%.2e");
    tb_table_num(t, w->bt_lowest_end / w->size, "%.2e");
  }
  tb_suite_table(su, t);
}

/* ms/step against tets: ours (pbd-stvk on 1 thread, CPU and wall; on all
 * threads, wall; btSoftBody, CPU), the patent's dashed. */
static int chart(tb_suite *su, const row *rows, int cores) {
  char body[1024], paper[512], header[200];
  int len = 0, plen = 0;
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    if (w->ok)
      len +=
          snprintf(body + len, sizeof body - (size_t)len, "%d,%.6g,%.6g,%.6g,%.6g\n", w->ntet,
                   w->one.value, w->one_wall.value, w->all.value, w->bt_ok ? w->bullet.value : NAN);
    plen += snprintf(paper + plen, sizeof paper - (size_t)plen, "%d,%g,%g\n", patent[r].tets,
                     patent[r].ms_one, patent[r].ms_multi);
  }
  snprintf(header, sizeof header,
           "tets,pbd-stvk 1 thread (CPU),pbd-stvk 1 thread (wall),pbd-stvk %d threads "
           "(wall),btSoftBody 1 thread (CPU)",
           cores);
  tb_error err;
  if (tb_suite_write_data(su, "solve.csv", header, body, &err) ||
      tb_suite_write_data(su, "solve_patent.csv", "tets,patent 1 thread,patent OpenMP", paper,
                          &err) ||
      tb_suite_chart_vars(su, "chart_lines.gp", "solve.csv", "solve",
                          "title='Solve time per step against tets, liver-drop (dashed: the "
                          "patent)'; xlabel='tets'; ylabel='time per step (ms)'; points=1; "
                          "paperfile='solve_patent.csv'",
                          &err)) {
    fprintf(stderr, "pbd: %s\n", err.msg);
    return 1;
  }
  tb_suite_caption(su, "solve",
                   "Median solve time per step against the number of tets: pbd-stvk on one "
                   "thread (CPU and wall time) and on all %d cores (wall time), and Bullet's "
                   "btSoftBody (CPU time, one thread); dashed, the patent's tables 1 and 2",
                   cores);
  return 0;
}

int tb_suite_pbd(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/pbd", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "pbd",
                                "2022 patent: PBD with StVK constraints, a liver dropped on a "
                                "ground (tables 1 and 2)",
                                o->seed, &err);
  if (!su) return fprintf(stderr, "pbd: %s\n", err.msg), 1;
  int threads_before = tb_threads_setting(), cores = tb_threads_cores(), failed = 0;
  plan p = {10, 10, 12}; /* quick: 130 steps (0.65 s), the landing at about 0.45 s */
  if (o->full) p.warm = 20, p.block = 40; /* 500 steps: the scene's 2.5 s */
  if (o->scale < 1) p.warm = 2, p.block = 3, p.nblocks = 3;
  /* the scene's own mesh: SOFA's liver when present (its placement for all) */
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.seed = o->seed;
  tb_mesh scene_mesh;
  if (tb_sim_mesh(SCENE, &sd, &scene_mesh, &err)) {
    fprintf(stderr, "pbd: %s\n", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  int sofa = access(SOFA_LIVER, R_OK) == 0 && scene_mesh.ntet == patent[0].tets;
  scene_info si;
  if (scene_info_of(&scene_mesh, &si, &err)) {
    fprintf(stderr, "pbd: %s\n", err.msg);
    tb_mesh_free(&scene_mesh);
    tb_suite_end(su, &err);
    return 1;
  }
  row rows[NROWS];
  memset(rows, 0, sizeof rows);
  for (int r = 0; r < NROWS; r++) {
    tb_progress("pbd", r, NROWS);
    row *w = &rows[r];
    tb_mesh m;
    if (make_liver(r, &scene_mesh, sofa, o->seed, &m, w->source, sizeof w->source, &err)) {
      snprintf(w->why, sizeof w->why, "no mesh (%.140s)", err.msg);
      fprintf(stderr, "pbd: %s\n", w->why);
      failed = 1;
      continue;
    }
    w->nv = m.nv, w->ntet = m.ntet;
    tb_tet_slabs sl;
    if (!tb_tet_slabs_build(&m, TB_SWEEP_SLABS, &sl, &err)) {
      w->slabs = sl.nslabs;
      for (int ph = 0; ph < 4; ph++) w->phases += sl.phase[ph] < sl.phase[ph + 1];
      tb_tet_slabs_free(&sl);
    }
    measure(su, r, &m, &si, &p, cores, w);
    if (!w->ok) fprintf(stderr, "pbd: %d tets: %s\n", m.ntet, w->why), failed = 1;
    if (w->ok && !w->identical) failed = 1; /* a bug: the count must not change the answer */
    tb_mesh_free(&m);
  }
  tb_progress("pbd", NROWS, NROWS);
  tb_mesh_free(&scene_mesh);
  tb_threads_set(threads_before);
  tb_noise nz = tb_suite_noise(su, cores); /* over the runs on all cores */

  double load[3] = {0, 0, 0};
  const tb_context *c = tb_suite_context(su);
  if (c->have_load) memcpy(load, c->load, sizeof load);
  tb_suite_note(
      su,
      "Scene liver-drop: the liver's bottom %g above a rigid ground (mu_s %g, mu_k %g), "
      "gravity %g, the scene's ambient drag %g per s (btSoftBody below falls without it), dt %g; "
      "pbd-stvk with the patent's k %g, nu %g, %d iterations (density %g, "
      "damping %g per s). The 596-tet row uses %s; the others TetGen livers whose tet counts "
      "are within 2%% of the patent's (a marching-cubes surface of 725 (tets/4230)^0.8 "
      "vertices, TetGen's maximum tet volume searched). Timed: the model's step alone "
      "(prediction, %d sweeps of tet and ground projections, friction, velocities), CPU and "
      "wall time; after %d warm-up steps, %d blocks of %d steps (%.2f s simulated in all; the "
      "landing comes at about %.2f s), each block's mean one repetition. On each liver the "
      "three runs (pbd-stvk on one thread, pbd-stvk on all %d cores, btSoftBody on one thread) "
      "are live side by side and take turns block by block, so a busy spell of the machine "
      "falls on all three alike and block b of each covers the same stretch of the drop. "
      "Figures are medians over the blocks, with their 95%% intervals (order statistics) "
      "where a goal or a ratio rests on them; a ratio is the median of the blocks' paired "
      "ratios. One thread: CPU time (the thread's own, which other processes' time slices do "
      "not inflate); all threads: wall time, what threads are for. This machine: %d cores "
      "(%s), load average %.2f %.2f %.2f at the start. The patent does not name its machine; "
      "ratios to it compare machines as much as programs.",
      si.height, si.ground.mu_s, si.ground.mu_k, si.g, si.drag, si.dt, K_STIFF, NU, ITERS,
      si.density, si.damping,
      sofa ? "SOFA's liver.msh (181 nodes, 596 tets; ../shared/data)"
           : "a TetGen liver (SOFA's liver.msh is not in ../shared/data)",
      ITERS, p.warm, p.nblocks, p.block, plan_steps(&p) * DT, sqrt(2 * si.height / si.g), cores,
      cores, c->cpu, load[0], load[1], load[2]);
  solve_table(su, rows);
  const row *big = &rows[NROWS - 1];
  if (big->ok) {
    char v[200];
    tb_verdict_text(big->us_elem, GOAL_US, 0, v, sizeof v);
    tb_suite_note(su,
                  "Per element-step at %d tets on one thread (CPU time): %.3f us, 95%% interval "
                  "%.3f-%.3f over %d blocks (goal <= %.1f us: %s; the patent's %.2f us). Deepest "
                  "node below the ground after a step, over the run: every row's column above "
                  "(goal: none deeper than %g of the mesh's box diagonal).",
                  big->ntet, big->us_elem.value, big->us_elem.lo, big->us_elem.hi, big->us_elem.n,
                  GOAL_US, v, 1e3 * patent[NROWS - 1].ms_elem, DEPTH_GOAL);
    tb_suite_counter(su, "goal/us_per_element_step", "value", big->us_elem.value);
    tb_suite_counter(su, "goal/us_per_element_step", "low", big->us_elem.lo);
    tb_suite_counter(su, "goal/us_per_element_step", "high", big->us_elem.hi);
    tb_suite_counter(su, "goal/us_per_element_step", "goal", GOAL_US);
    tb_suite_counter(su, "goal/us_per_element_step", "verdict",
                     tb_verdict(big->us_elem, GOAL_US, 0));
  }
  thread_table(su, rows, cores, &nz);
  char what[300];
  tb_noise_describe(&nz, what, sizeof what);
  tb_suite_note(su,
                "All threads: tb_threads_cores() = %d on this machine, set explicitly (not the "
                "automatic count). The speed-up is the one-thread run's wall time per step over "
                "the all-thread run's, the median of the blocks' paired ratios with its 95%% "
                "interval; it is stated only when the machine left the cores free (over the "
                "suite so far: %s), else the table says not measurable (the numbers are still "
                "shown). The sweeps follow the slab schedule (models/tet_slabs.c): the "
                "nodes cut into slabs along the longest extent, each sweep projecting the "
                "slabs' interiors, then the even and the odd interfaces between them, then any "
                "tet spanning three slabs, each phase's tasks sharing no node, each task's tets "
                "in a fixed order; the ground, damping and friction run in node order, so the "
                "thread count must not change a single bit: `identical` compares every position "
                "after the run of 1 and of %d threads (memcmp).%s No barrier ends a phase "
                "(one per colour, 20 to 50 a sweep, before): a task waits only for the tasks "
                "of other phases that share a node with it to have run, so a thread whose "
                "share of a phase ends early goes on with the next; about 8 barriers a step "
                "remain (the ground adds one a sweep, %d a step). Each thread runs a "
                "contiguous range of a phase's tasks, cut where the tasks' counts of tets with "
                "a free node balance; a mesh too small for two slabs runs on one thread. When "
                "the machine has more runnable work than cores, a descheduled thread still "
                "holds up the tasks that wait for its own, and the all-core times grow beyond "
                "the one-thread ones.",
                cores, what, cores,
                cores < 2 ? " With one core both runs use one thread, so this shows nothing." : "",
                ITERS);
  bullet_table(su, rows);
  tb_suite_note(su,
                "btSoftBody (Bullet 3.24, double precision: the bullet-softbody model): one "
                "link per tet edge (a distance constraint, not an energy: another model, "
                "compared for speed), node masses from the density and a quarter of each tet's "
                "volume, kLST %g, %d position iterations, friction kDF %g (the ground's mu_k), no "
                "damping, ground contacts hard (kKHR 1; Bullet's default 0.1 lets a resting body "
                "sink in), margin 1e-3 of the box diagonal; the ground a static box whose top face "
                "is the plane "
                "(Bullet's soft bodies meet rigid shapes through a signed distance field that "
                "only convex shapes get). Timed: stepSimulation(dt, 0) and the SDF's garbage "
                "collection (the model's step), on the calling thread, CPU time, the same blocks "
                "as pbd-stvk and taking turns with them; `btSoftBody / pbd-stvk` is the median "
                "of the blocks' paired CPU-time ratios with its 95%% interval.",
                K_STIFF, ITERS, si.ground.mu_k);
  failed |= chart(su, rows, cores);
  failed |= tb_pbd_accuracy(su, o);
  if (tb_suite_end(su, &err)) fprintf(stderr, "pbd: %s\n", err.msg), failed = 1;
  return failed;
}
