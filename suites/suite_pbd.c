/* The 2022 patent's performance tables (a collision simulation method of
 * soft tissue and a rigid ground, experiment 2, its tables 1 and 2): pbd-stvk
 * at the patent's settings (k 0.4, nu 0.4, 5 iterations, dt 0.005) in the
 * liver-drop scene (a liver falling onto the ground, so the ground
 * constraint is in every sweep once it lands) on livers of the patent's tet
 * counts: 596 (SOFA's liver.msh when ../shared/data is present, else ours),
 * 5395, 7325 and 12829 (TetGen livers within 2% of those counts).
 *  1. Mean solve time per step and per element, one thread, the patent's
 *     figures beside ours, and microseconds per element-step; the deepest
 *     node below the ground after the projection over the run.
 *  2. One thread against all cores: the speed-ups beside the patent's, and
 *     whether the positions after the run are bit-identical.
 *  3. A peer: Bullet's btSoftBody (the bullet-softbody model) dropped the
 *     same way, ms/step beside ours and the ratio.
 * Timing: the model's step alone (the scene's health check runs after each
 * step, untimed); a warm-up, then blocks of steps, each block's mean one
 * repetition; medians over the blocks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_suites.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "meshgen/tb_generators.h"
#include "meshgen/tb_meshgen.h"
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
#define SOFA_LIVER TB_SHARED_DATA "/sofa/liver.msh"

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

/* What one timed run gives. */
typedef struct run_out {
  double *block_ms;  /* nblocks: mean ms per step of each block */
  tb_vec3 *x_end;    /* positions after the run (nv) */
  double deepest;    /* the deepest node below the ground after a step, over the run */
  double lowest_end; /* the lowest node's height above the ground at the end */
  double size;       /* the rest mesh's box diagonal */
} run_out;

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

/* model with settings set on mesh in the scene with `threads` threads:
 * p's steps, the model's step timed. Returns 0, or -1 with err (a failed
 * step or an unhealthy state). */
static int run_model(const char *model, const tb_settings *set, const tb_mesh *mesh, int threads,
                     const plan *p, run_out *o, tb_error *err) {
  tb_threads_set(threads);
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  sd.dt = DT;
  tb_sim s;
  if (tb_sim_create(&s, SCENE, &sd, model, set, mesh, err)) return -1;
  int rc = 0;
  if (!s.has_ground) rc = tb_error_set(err, SCENE, 0, "the scene has no ground");
  o->deepest = 0, o->size = s.size;
  int n = plan_steps(p), nv = s.mesh.nv;
  uint64_t acc = 0;
  for (int k = 0; k < n && !rc; k++) {
    if (tb_sim_loads(&s, s.t + s.def.dt, err)) {
      rc = -1;
      break;
    }
    tb_step in = {0};
    in.dt = s.def.dt, in.gravity = s.gravity, in.force = s.force;
    in.nfixed = s.nfixed, in.fixed = s.fixed, in.fixed_x = s.fixed_x, in.ground = &s.ground;
    uint64_t t0 = tb_time_ns();
    rc = tb_model_step(&s.model, &in, err);
    uint64_t t1 = tb_time_ns();
    if (rc) break;
    s.t += s.def.dt, s.steps++;
    if (k >= p->warm) {
      acc += t1 - t0;
      if ((k + 1 - p->warm) % p->block == 0) {
        o->block_ms[(k - p->warm) / p->block] = (double)acc * 1e-6 / p->block;
        acc = 0;
      }
    }
    const tb_vec3 *x = tb_model_positions(&s.model);
    double low = INFINITY;
    for (int i = 0; i < nv; i++) low = fmin(low, tb_dot(tb_sub(x[i], s.ground.p), s.ground.n));
    if (-low > o->deepest) o->deepest = -low;
    o->lowest_end = low;
    tb_health h =
        tb_model_health(&s.mesh, x, tb_model_velocities(&s.model), s.def.vmax, s.def.inversion);
    if (!h.ok) rc = tb_error_set(err, model, 0, "unstable at t = %g: %s", s.t, h.reason);
    tb_progress_tick("%s, %d threads: step %d/%d", model, threads, k + 1, n);
  }
  if (!rc) memcpy(o->x_end, tb_model_positions(&s.model), sizeof(tb_vec3) * (size_t)nv);
  tb_sim_destroy(&s);
  return rc ? -1 : 0;
}

/* Everything measured on one liver. */
typedef struct row {
  int ok, nv, ntet, links, colours;
  char source[32], why[160];
  double one, all, bullet; /* median ms/step */
  double deepest, lowest_end, size, bt_deepest, bt_lowest_end;
  int identical;
} row;

static void bench_entry(tb_suite *su, const char *name, const double *ms, int n, int threads) {
  int was = tb_threads();
  tb_threads_set(threads);
  tb_suite_bench(su, name, ms, NULL, n, "ms");
  tb_threads_set(was);
}

/* Runs row r: one thread, all threads, btSoftBody. */
static void measure(tb_suite *su, int r, const tb_mesh *mesh, const scene_info *si, const plan *p,
                    int cores, row *w) {
  int nv = mesh->nv;
  double *ms = malloc(sizeof(double) * (size_t)p->nblocks);
  tb_vec3 *x1 = malloc(sizeof(tb_vec3) * (size_t)nv), *xn = malloc(sizeof(tb_vec3) * (size_t)nv);
  tb_error err;
  w->ok = 0;
  if (!ms || !x1 || !xn) {
    snprintf(w->why, sizeof w->why, "out of memory");
    goto done;
  }
  char name[128];
  run_out o = {ms, x1, 0, 0, 0};
  tb_settings set = patent_settings(), peer = peer_settings(si);
  if (run_model(MODEL, &set, mesh, 1, p, &o, &err)) {
    snprintf(w->why, sizeof w->why, "unstable (%.140s)", err.msg);
    goto done;
  }
  w->one = tb_stats_of(ms, p->nblocks).median;
  w->deepest = o.deepest, w->lowest_end = o.lowest_end, w->size = o.size;
  snprintf(name, sizeof name, MODEL "/tets:%d/threads:1", mesh->ntet);
  bench_entry(su, name, ms, p->nblocks, 1);
  tb_suite_counter(su, name, "tets", mesh->ntet);
  tb_suite_counter(su, name, "nodes", nv);
  tb_suite_counter(su, name, "us_per_element_step", 1e3 * w->one / mesh->ntet);
  tb_suite_counter(su, name, "deepest_below_ground", o.deepest);
  tb_suite_counter(su, name, "deepest_below_ground_of_size", o.deepest / o.size);
  tb_suite_counter(su, name, "patent_ms_per_step", patent[r].ms);

  o.x_end = xn;
  if (run_model(MODEL, &set, mesh, cores, p, &o, &err)) {
    snprintf(w->why, sizeof w->why, "unstable with %d threads (%.120s)", cores, err.msg);
    goto done;
  }
  w->all = tb_stats_of(ms, p->nblocks).median;
  w->identical = !memcmp(x1, xn, sizeof(tb_vec3) * (size_t)nv);
  snprintf(name, sizeof name, MODEL "/tets:%d/threads:%d", mesh->ntet, cores);
  bench_entry(su, name, ms, p->nblocks, cores);
  tb_suite_counter(su, name, "speedup", w->one / w->all);
  tb_suite_counter(su, name, "identical_to_one_thread", w->identical);
  tb_suite_counter(su, name, "patent_speedup", patent[r].speedup);

  o.x_end = xn;
  int *edges = NULL;
  w->links = tb_mesh_edges(mesh, &edges); /* btSoftBody's links: one per tet edge */
  free(edges);
  if (run_model("bullet-softbody", &peer, mesh, 1, p, &o, &err)) {
    w->bullet = NAN;
    fprintf(stderr, "pbd: btSoftBody on %d tets: %s\n", mesh->ntet, err.msg);
  } else {
    w->bullet = tb_stats_of(ms, p->nblocks).median;
    w->bt_deepest = o.deepest, w->bt_lowest_end = o.lowest_end;
    snprintf(name, sizeof name, "btSoftBody/tets:%d/threads:1", mesh->ntet);
    bench_entry(su, name, ms, p->nblocks, 1);
    tb_suite_counter(su, name, "links", w->links);
    tb_suite_counter(su, name, "ratio_to_pbd_stvk", w->bullet / w->one);
    tb_suite_counter(su, name, "deepest_below_ground", o.deepest);
  }
  w->ok = 1;
done:
  free(ms), free(x1), free(xn);
}

static void solve_table(tb_suite *su, const row *rows) {
  static const char *cols[] = {"model (patent)",
                               "mesh",
                               "tets",
                               "nodes",
                               "threads",
                               "ms/step (ours)",
                               "ms/step (patent)",
                               "ms/element (ours)",
                               "ms/element (patent)",
                               "us/element-step (ours)",
                               "us/element-step (patent)",
                               "deepest below ground (of size)",
                               "no node below ground beyond 1e-6 of size"};
  tb_table *t = tb_table_new("solve",
                             "Patent table 1: mean solve time per step and per element, pbd-stvk, "
                             "one thread (k 0.4, nu 0.4, 5 iterations, dt 0.005)",
                             13, cols);
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
      for (int c = 6; c < 13; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w->one, "%.3f");
    tb_table_num(t, patent[r].ms, "%.2f");
    tb_table_num(t, w->one / w->ntet, "%.3e");
    tb_table_num(t, patent[r].ms_elem, "%.3e");
    tb_table_num(t, 1e3 * w->one / w->ntet, "%.3f");
    tb_table_num(t, 1e3 * patent[r].ms_elem, "%.3f");
    tb_table_num(t, w->deepest / w->size, "%.2e");
    tb_table_cell(t, "%s", w->deepest <= DEPTH_GOAL * w->size ? "yes" : "NO");
  }
  tb_suite_table(su, t);
}

static void thread_table(tb_suite *su, const row *rows, int cores) {
  static const char *cols[] = {"model (patent)",
                               "tets",
                               "tet colours",
                               "threads",
                               "ms/step, 1 thread",
                               "ms/step, all threads",
                               "speed-up (ours)",
                               "patent: 1 thread (ms)",
                               "patent: OpenMP (ms)",
                               "speed-up (patent)",
                               "identical"};
  char title[160];
  snprintf(title, sizeof title,
           "Patent table 2: one thread against all %d cores; positions after the run "
           "bit-identical?",
           cores);
  tb_table *t = tb_table_new("threads", title, 11, cols);
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].name);
    if (w->ntet)
      tb_table_num(t, w->ntet, "%.0f"), tb_table_num(t, w->colours, "%.0f");
    else
      tb_table_cell(t, "-"), tb_table_cell(t, "-");
    tb_table_num(t, cores, "%.0f");
    if (w->ok) {
      tb_table_num(t, w->one, "%.3f");
      tb_table_num(t, w->all, "%.3f");
      tb_table_num(t, w->one / w->all, "%.2fx");
    } else {
      tb_table_cell(t, "-"), tb_table_cell(t, "-"), tb_table_cell(t, "-");
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
                               "btSoftBody ms/step",
                               "pbd-stvk ms/step",
                               "btSoftBody / pbd-stvk",
                               "btSoftBody deepest below ground (of size)",
                               "btSoftBody lowest node at the end (of size)"};
  tb_table *t = tb_table_new("peer",
                             "Peer: Bullet's btSoftBody (links on tet edges, kLST 0.4, 5 position "
                             "iterations) dropped on the same ground, one thread",
                             9, cols);
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    tb_table_row(t);
    tb_table_cell(t, "%s", patent[r].name);
    if (!w->ok || !isfinite(w->bullet)) {
      if (w->ntet)
        tb_table_num(t, w->ntet, "%.0f");
      else
        tb_table_cell(t, "-");
      for (int c = 2; c < 9; c++) tb_table_cell(t, "-");
      continue;
    }
    tb_table_num(t, w->ntet, "%.0f");
    tb_table_num(t, w->links, "%.0f");
    tb_table_num(t, 1, "%.0f");
    tb_table_num(t, w->bullet, "%.3f");
    tb_table_num(t, w->one, "%.3f");
    tb_table_num(t, w->bullet / w->one, "%.2fx");
    tb_table_num(t, w->bt_deepest / w->size, "%.2e");
    tb_table_num(t, w->bt_lowest_end / w->size, "%.2e");
  }
  tb_suite_table(su, t);
}

/* ms/step against tets: ours (1 thread, all threads, btSoftBody), the
 * patent's dashed. */
static int chart(tb_suite *su, const row *rows, int cores) {
  char body[1024], paper[512], header[160];
  int len = 0, plen = 0;
  for (int r = 0; r < NROWS; r++) {
    const row *w = &rows[r];
    if (w->ok) {
      len +=
          snprintf(body + len, sizeof body - (size_t)len, "%d,%.6g,%.6g,", w->ntet, w->one, w->all);
      len += isfinite(w->bullet)
                 ? snprintf(body + len, sizeof body - (size_t)len, "%.6g\n", w->bullet)
                 : snprintf(body + len, sizeof body - (size_t)len, "NaN\n");
    }
    plen += snprintf(paper + plen, sizeof paper - (size_t)plen, "%d,%g,%g\n", patent[r].tets,
                     patent[r].ms_one, patent[r].ms_multi);
  }
  snprintf(header, sizeof header, "tets,pbd-stvk 1 thread,pbd-stvk %d threads,btSoftBody 1 thread",
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
                   "thread and on all %d cores, and Bullet's btSoftBody; dashed, the patent's "
                   "tables 1 and 2",
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
  int threads_before = tb_threads(), cores = tb_threads_cores(), failed = 0;
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
    int *order = NULL, *start = NULL;
    if (tb_tet_colours(&m, &w->colours, &order, &start, &err)) w->colours = 0;
    free(order), free(start);
    measure(su, r, &m, &si, &p, cores, w);
    if (!w->ok) fprintf(stderr, "pbd: %d tets: %s\n", m.ntet, w->why), failed = 1;
    if (w->ok && !w->identical) failed = 1; /* a bug: the count must not change the answer */
    tb_mesh_free(&m);
  }
  tb_progress("pbd", NROWS, NROWS);
  tb_mesh_free(&scene_mesh);
  tb_threads_set(threads_before);

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
      "(prediction, %d sweeps of tet and ground projections, friction, velocities); after %d "
      "warm-up steps, %d blocks of %d steps (%.2f s simulated in all; the landing comes at "
      "about %.2f s), each block's mean one repetition, the median over blocks reported. This "
      "machine: %d cores (%s), load average %.2f %.2f %.2f at the start (other work on the "
      "machine slows every figure, the all-core ones most). The patent does not name its "
      "machine; ratios to it compare machines as much as programs.",
      si.height, si.ground.mu_s, si.ground.mu_k, si.g, si.drag, si.dt, K_STIFF, NU, ITERS,
      si.density, si.damping,
      sofa ? "SOFA's liver.msh (181 nodes, 596 tets; ../shared/data)"
           : "a TetGen liver (SOFA's liver.msh is not in ../shared/data)",
      ITERS, p.warm, p.nblocks, p.block, plan_steps(&p) * DT, sqrt(2 * si.height / si.g), cores,
      c->cpu, load[0], load[1], load[2]);
  solve_table(su, rows);
  const row *big = &rows[NROWS - 1];
  if (big->ok)
    tb_suite_note(su,
                  "Per element-step at %d tets on one thread: %.3f us (goal <= %.1f us: %s; the "
                  "patent's %.2f us). Deepest node below the ground after a step, over the run: "
                  "every row's column above (goal: none deeper than %g of the mesh's box "
                  "diagonal).",
                  big->ntet, 1e3 * big->one / big->ntet, GOAL_US,
                  1e3 * big->one / big->ntet <= GOAL_US ? "met" : "NOT met",
                  1e3 * patent[NROWS - 1].ms_elem, DEPTH_GOAL);
  thread_table(su, rows, cores);
  tb_context now;
  tb_context_collect(&now, o->seed);
  tb_suite_note(su,
                "All threads: tb_threads_cores() = %d on this machine. Tets of one colour share "
                "no node and are projected in parallel; the ground, damping and friction run "
                "in node order, so the thread count must not change a single bit: `identical` "
                "compares every position after the run of 1 and of %d threads (memcmp).%s Each "
                "colour is one parallel loop ending in a barrier, and the ground's another, so "
                "a step passes about %d x (colours + 1) barriers. Thread i is pinned to CPU i "
                "(core/threads.c; left to Linux, both threads sometimes shared one CPU and a "
                "step took 3x as long); when the machine has more runnable work than cores, a "
                "thread descheduled before a barrier still holds the others up, and the "
                "all-core times grow beyond the one-thread ones. Load "
                "average at the start %.2f, at the end %.2f (%d cores).",
                cores, cores,
                cores < 2 ? " With one core both runs use one thread, so this shows nothing." : "",
                ITERS, load[0], now.have_load ? now.load[0] : NAN, cores);
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
                "collection (the model's step), on the calling thread, the same blocks as "
                "pbd-stvk.",
                K_STIFF, ITERS, si.ground.mu_k);
  failed |= chart(su, rows, cores);
  if (tb_suite_end(su, &err)) fprintf(stderr, "pbd: %s\n", err.msg), failed = 1;
  return failed;
}
