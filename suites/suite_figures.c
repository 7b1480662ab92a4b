/* The documents' pictures, rendered headless (render/tb_render.h) into
 * results/figures/: thesis fig. 2.15 (the liver surface from marching
 * cubes), figs. 3.11-3.13 (each model's structure (a) and its stretched
 * shape (b), steps/s beside the thesis's FPS), figs. 3.14-3.15 (a large
 * twist and its release: shape matching recovers, mass-spring stays
 * distorted), fig. 4.21 (the liver and the grasper on the table 4.2 path,
 * intersecting triangles highlighted), figs. 5.5-5.8 (the liver before,
 * pressed, pulled, from the thesis's views) and the PBD patent's figs. 7-9
 * (the liver above the ground, at rest on it, and fallen through the floor
 * without it). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_suites.h"
#include "core/tb_timer.h"
#include "measure/tb_collision_scene.h"
#include "measure/tb_draw.h"
#include "measure/tb_fidelity.h"
#include "meshgen/tb_meshgen.h"
#include "render/tb_render.h"
#include "report/tb_results.h"
#include "scenes/tb_collider.h"
#include "scenes/tb_sim.h"

#define W 640
#define H 480

static const float BG[3] = {1, 1, 1}, RED[3] = {0.9f, 0.05f, 0.05f};
#define BODY tb_draw_body_rgb
#define TOOL tb_draw_tool_rgb

typedef struct fig {
  tb_suite *su;
  tb_renderer *r;
  const char *dir;
  int failed;
} fig;

/* Writes the picture drawn so far as dir/name and adds it with a caption. */
static void shoot(fig *f, const char *name, const char *caption) {
  char path[1200];
  tb_error err;
  snprintf(path, sizeof path, "%s/%s", f->dir, name);
  if (tb_renderer_write_png(f->r, path, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
    return;
  }
  tb_suite_figure(f->su, name, "%s", caption);
}

static void view(fig *f, const char *preset, const tb_mesh *m) {
  tb_vec3 lo, hi;
  tb_mesh_bbox(m, &lo, &hi);
  tb_camera cam;
  tb_camera_preset(preset, lo, hi, &cam);
  tb_renderer_begin(f->r, &cam, BG);
}

static void surface(fig *f, int nv, const tb_vec3 *x, int ntri, const int *tri, const float rgb[3],
                    const double *value, double hi, int wire) {
  tb_render_mesh m = {.nv = nv,
                      .ntri = ntri,
                      .x = x,
                      .tri = tri,
                      .rgb = {rgb[0], rgb[1], rgb[2]},
                      .value = value,
                      .lo = 0,
                      .hi = hi > 0 ? hi : 1,
                      .wireframe = wire};
  tb_renderer_mesh(f->r, &m);
}

/* A simulation's body (coloured by displacement when colour), ground and instrument. */
static void body(fig *f, tb_sim *s, int colour) {
  tb_surface su = tb_model_surface(&s->model);
  double *u = colour ? malloc(sizeof(double) * (size_t)su.nv) : NULL, hi = 0;
  if (u) hi = tb_draw_displacement(s, u);
  tb_draw_sim(f->r, s, u, 0, hi, "displacement (mesh length unit)", 0);
  free(u);
}

/* Builds scene with model at unit node masses (the thesis's demos) and the
 * suite's seed; sd's other fields as given (NULL: the scene's). A failure
 * is reported and marks the suite failed. */
static int make_sim(fig *f, tb_sim *s, const char *scene, const char *model, tb_sim_def *sd,
                    uint64_t seed) {
  tb_sim_def d;
  if (sd)
    d = *sd;
  else
    tb_sim_def_init(&d);
  d.seed = seed;
  tb_settings set;
  tb_settings_init(&set);
  tb_error err;
  if (!tb_settings_set(&set, "node_mass=1", &err) &&
      !tb_sim_create(s, scene, &d, model, &set, NULL, &err))
    return 0;
  fprintf(stderr, "figures: %s\n", err.msg);
  f->failed = 1;
  return -1;
}

/* Steps a simulation to time t; the median step's CPU and wall ms in
 * ms[0] and ms[1] (ms may be NULL). */
static int run_to(tb_sim *s, double t, double ms[2], tb_error *err) {
  long n = lround((t - s->t) / s->def.dt), cap = n > 0 ? n : 1;
  double *dt = malloc(sizeof(double) * 2 * (size_t)cap), *wall = dt ? dt + cap : NULL;
  int rc = dt ? 0 : -1;
  for (long k = 0; !rc && k < n; k++) {
    tb_clock c = tb_clock_start();
    rc = tb_sim_step(s, err);
    tb_clock_ms(&c, &wall[k], &dt[k]);
  }
  if (ms && n > 0 && !rc)
    ms[0] = tb_stats_of(dt, (int)n).median, ms[1] = tb_stats_of(wall, (int)n).median;
  free(dt);
  return rc;
}

/* ---- fig. 2.15 ---- */
static void liver_surface(fig *f, uint64_t seed) {
  tb_liver_def d = tb_liver_default_def();
  d.seed = seed;
  tb_mesh m;
  tb_error err;
  if (tb_liver_surface(&d, &m, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
    return;
  }
  view(f, "left-front", &m);
  surface(f, m.nv, m.x, m.ntri, m.tri, BODY, NULL, 0, 1);
  char cap[200];
  snprintf(cap, sizeof cap,
           "Fig. 2.15: the liver surface from marching cubes on the synthetic CT volume, %d "
           "vertices, %d triangles (thesis: 725, 1448).",
           m.nv, m.ntri);
  shoot(f, "fig-2.15-liver-surface.png", cap);
  tb_mesh_free(&m);
}

/* ---- figs. 3.11-3.13 ---- */
static void models(fig *f, const tb_suite_opts *o) {
  static const struct {
    const char *model, *fig, *what;
    double fps;
  } rows[] = {{"msm", "3.11", "springs on the tet edges", 335.7},
              {"fem", "3.12", "the tetrahedra", 36.5},
              {"sm", "3.13",
               "the shape-matching clusters (each node coloured by its first cluster)", 787.0}};
  for (int k = 0; k < 3; k++) {
    tb_sim s;
    tb_error err;
    if (make_sim(f, &s, "liver-stretch", rows[k].model, NULL, o->seed)) continue;
    char name[64], cap[400];
    view(f, "left-front", &s.mesh);
    if (tb_draw_structure(f->r, &s, &err)) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
    }
    snprintf(name, sizeof name, "fig-%s-a-%s-structure.png", rows[k].fig, rows[k].model);
    snprintf(cap, sizeof cap, "Fig. %sa: %s model of the liver (%d nodes): %s.", rows[k].fig,
             rows[k].model, s.mesh.nv, rows[k].what);
    shoot(f, name, cap);
    double ms[2] = {NAN, NAN}, run_wall, run_cpu; /* the median step: CPU, wall */
    tb_clock c = tb_clock_start();
    int bad = run_to(&s, s.def.release, ms, &err);
    tb_clock_ms(&c, &run_wall, &run_cpu);
    if (!bad) {
      char bench[64];
      snprintf(bench, sizeof bench, "stretch/%s", rows[k].model);
      tb_suite_bench(f->su, bench, &run_wall, &run_cpu, 1, "ms");
      tb_suite_counter(f->su, bench, "median_step_ms", ms[0]);
      tb_suite_counter(f->su, bench, "median_step_wall_ms", ms[1]);
      tb_suite_counter(f->su, bench, "thesis_fps", rows[k].fps);
    }
    if (bad) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
    } else {
      view(f, "left-front", &s.mesh);
      body(f, &s, 1);
      snprintf(name, sizeof name, "fig-%s-b-%s-stretched.png", rows[k].fig, rows[k].model);
      snprintf(cap, sizeof cap,
               "Fig. %sb: %s, the liver stretched (liver-stretch at %g s, the patch pulled %g), "
               "coloured by displacement; %.0f steps/s here in CPU time (median step %.3f ms "
               "CPU, %.3f ms wall, simulation only) beside the thesis's %.1f FPS (i3-2100, with "
               "rendering).",
               rows[k].fig, rows[k].model, s.t, s.def.amplitude, 1e3 / ms[0], ms[0], ms[1],
               rows[k].fps);
      shoot(f, name, cap);
    }
    tb_sim_destroy(&s);
  }
}

/* ---- figs. 3.14-3.15 ---- */
static void recovery(fig *f, const tb_suite_opts *o) {
  static const char *const models[2] = {"sm", "msm"}, *const figs[2] = {"3.14", "3.15"};
  for (int k = 0; k < 2; k++) {
    tb_sim_def sd;
    tb_sim_def_init(&sd);
    sd.drag = 1.5;
    if (o->scale < 1) sd.duration = 3;
    tb_sim s;
    tb_error err;
    if (make_sim(f, &s, "beam-twist", models[k], &sd, o->seed)) continue;
    double when[3] = {0, s.def.release, s.def.duration};
    const char *what[3] = {"before", "twisted", "after"};
    for (int q = 0; q < 3; q++) {
      if (run_to(&s, when[q], NULL, &err)) {
        fprintf(stderr, "figures: %s\n", err.msg);
        f->failed = 1;
        break;
      }
      tb_vec3 lo, hi;
      tb_mesh_bbox(&s.mesh, &lo, &hi);
      lo = tb_madd(lo, -0.6, tb_v3(1, 1, 1)), hi = tb_madd(hi, 0.6, tb_v3(1, 1, 1));
      tb_camera cam;
      tb_camera_preset("left-front", lo, hi, &cam);
      tb_renderer_begin(f->r, &cam, BG);
      body(f, &s, 0);
      tb_draw_edges(f->r, &s.mesh, tb_model_positions(&s.model));
      char name[64], cap[300];
      tb_sim_metrics m = tb_sim_measure(&s);
      snprintf(name, sizeof name, "fig-%s-%s-%d-%s.png", figs[k], models[k], q, what[q]);
      snprintf(cap, sizeof cap,
               "Fig. %s (%s), %s: beam-twist at t = %g s (end face turned %g degrees, let go at %g "
               "s); largest displacement %.3g, %d inverted tets.",
               figs[k], models[k], what[q], s.t, s.def.amplitude, s.def.release, m.max_disp,
               m.inverted);
      shoot(f, name, cap);
    }
    tb_sim_destroy(&s);
  }
}

/* ---- fig. 4.21 ---- */
static void collision(fig *f, const tb_suite_opts *o) {
  tb_mesh liver, tool;
  tb_error err;
  if (tb_collision_scene_make(o->seed, &liver, &tool, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
    return;
  }
  tb_collider *c = tb_collider_new("composite", &liver, &tool, NULL, NULL, NULL, &err);
  tb_pairlist pairs = {0, 0, NULL};
  tb_vec3 *tx = malloc(sizeof(tb_vec3) * (size_t)tool.nv);
  int *hit = malloc(sizeof(int) * 3 * (size_t)liver.ntri);
  /* the poses of table 4.2's rows: pair counts nearest the thesis's */
  double path[TB_COLLISION_SCENE_ROWS];
  int rows[TB_COLLISION_SCENE_ROWS];
  if (c && tb_collision_scene_row_poses(c, o->scale < 1 ? 21 : 141, tb_collision_scene_thesis_pairs,
                                        TB_COLLISION_SCENE_ROWS, path, rows, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
  }
  /* one camera for every row, fitted to the liver and the instrument's part near it in any row
   * (within half the liver's size of its box) */
  tb_vec3 lo, hi;
  tb_mesh_bbox(&liver, &lo, &hi);
  double reach = 0.5 * tb_dist(lo, hi);
  tb_vec3 *fit =
      malloc(sizeof(tb_vec3) * ((size_t)liver.nv + (size_t)tool.nv * TB_COLLISION_SCENE_ROWS));
  int nfit = liver.nv;
  if (fit) memcpy(fit, liver.x, sizeof(tb_vec3) * (size_t)liver.nv);
  for (int q = 0; fit && !f->failed && q < TB_COLLISION_SCENE_ROWS; q++) {
    tb_mat3 R;
    tb_vec3 t;
    tb_collision_scene_pose(path[q], &R, &t);
    for (int i = 0; i < tool.nv; i++) {
      tb_vec3 p = tb_add(tb_m3_mulv(R, tool.x[i]), t);
      if (p.x > lo.x - reach && p.x < hi.x + reach && p.y > lo.y - reach && p.y < hi.y + reach &&
          p.z > lo.z - reach && p.z < hi.z + reach)
        fit[nfit++] = p;
    }
  }
  tb_camera cam;
  int have_cam =
      fit && !tb_camera_preset_points("left-front", fit, nfit, tb_v3(0, 0, 1), 4.0 / 3.0, &cam);
  free(fit);
  for (int q = 0; c && tx && hit && have_cam && !f->failed && q < TB_COLLISION_SCENE_ROWS; q++) {
    tb_mat3 R;
    tb_vec3 t;
    tb_collision_scene_pose(path[q], &R, &t);
    if (tb_collider_pose(c, R, t, &err) || tb_collider_query(c, &pairs, NULL, &err)) break;
    for (int i = 0; i < tool.nv; i++) tx[i] = tb_add(tb_m3_mulv(R, tool.x[i]), t);
    int nh = 0;
    for (int k = 0; k < pairs.n; k++)
      if (!k || pairs.ij[2 * k] != pairs.ij[2 * k - 2])
        memcpy(hit + 3 * nh++, liver.tri + 3 * pairs.ij[2 * k], sizeof(int) * 3);
    tb_renderer_begin(f->r, &cam, BG);
    /* every tet face, oriented either way: both sides in the body's colour */
    tb_render_mesh b = {.nv = liver.nv,
                        .ntri = liver.ntri,
                        .x = liver.x,
                        .tri = liver.tri,
                        .rgb = {BODY[0], BODY[1], BODY[2]},
                        .any_side = 1,
                        .flat = 1};
    tb_renderer_mesh(f->r, &b);
    tb_render_mesh h = {.nv = liver.nv,
                        .ntri = nh,
                        .x = liver.x,
                        .tri = hit,
                        .rgb = {RED[0], RED[1], RED[2]},
                        .on_top = 1,
                        .any_side = 1,
                        .flat = 1};
    tb_renderer_mesh(f->r, &h);
    surface(f, tool.nv, tx, tool.ntri, tool.tri, TOOL, NULL, 0, 0);
    char name[64], cap[300];
    snprintf(name, sizeof name, "fig-4.21-row-%d.png", q + 1);
    snprintf(
        cap, sizeof cap,
        "Fig. 4.21: the liver's collision model (%d triangles) and the grasper at table 4.2's row "
        "%d (thesis: %d pairs; path position %.3f): the %d intersecting triangle pairs "
        "(composite BVH, exact test) in red (%d liver triangles).",
        liver.ntri, q + 1, tb_collision_scene_thesis_pairs[q], path[q], pairs.n, nh);
    shoot(f, name, cap);
  }
  if (!c) fprintf(stderr, "figures: %s\n", err.msg), f->failed = 1;
  tb_collider_free(c);
  tb_pairlist_free(&pairs);
  free(tx), free(hit);
  tb_mesh_free(&liver), tb_mesh_free(&tool);
}

/* ---- figs. 5.5-5.8 ---- */
static void system_views(fig *f, const tb_suite_opts *o) {
  static const struct {
    const char *scene, *fig, *what, *views[4];
    int nviews;
  } rows[] = {
      {"liver-stretch", "5.5", "the liver before", {"front", "left-front", "left-back", "top"}, 4},
      {"liver-press", "5.6", "pressed by the grasper", {"front", "left-front"}, 2},
      {"liver-stretch",
       "5.7",
       "pulled (the thesis's caption numbers this figure 5.8)",
       {"left-front", "left-back"},
       2}};
  for (int k = 0; k < 3; k++) {
    tb_sim s;
    tb_error err;
    if (make_sim(f, &s, rows[k].scene, "sm", NULL, o->seed)) continue;
    double t = k == 0 ? 0 : (k == 1 ? 0.75 * s.def.duration : s.def.release);
    if (run_to(&s, t, NULL, &err)) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
    }
    tb_sim_metrics mt = tb_sim_measure(&s);
    for (int v = 0; v < rows[k].nviews && !f->failed; v++) {
      view(f, rows[k].views[v], &s.mesh);
      body(f, &s, k == 2); /* the pull shown by the displacement's colours */
      char name[80], cap[400], how[200];
      snprintf(name, sizeof name, "fig-%s-%s.png", rows[k].fig, rows[k].views[v]);
      if (s.has_tool)
        snprintf(how, sizeof how,
                 "the grasper's penetration after the contact response at most %.3g",
                 s.pen_tool_max);
      else if (k == 2)
        snprintf(how, sizeof how,
                 "coloured by displacement: a far surface patch pulled %g by prescribed motion (no "
                 "instrument is simulated or drawn), largest displacement %.3g",
                 s.def.amplitude, mt.max_disp);
      else
        snprintf(how, sizeof how, "at rest, before the patch is pulled (no instrument)");
      snprintf(cap, sizeof cap, "Fig. %s: %s (shape matching, %s at t = %g s), %s view; %s.",
               rows[k].fig, rows[k].what, rows[k].scene, s.t, rows[k].views[v], how);
      shoot(f, name, cap);
    }
    tb_sim_destroy(&s);
  }
}

/* ---- the PBD patent's figs. 7-9 ---- */

/* The front view of the box [lo, hi] grown to take in the ground below it. */
static void view_box(fig *f, tb_vec3 lo, tb_vec3 hi) {
  tb_camera cam;
  tb_camera_preset("front", lo, hi, &cam);
  tb_renderer_begin(f->r, &cam, BG);
}

static double lowest(const tb_sim *s) {
  const tb_vec3 *x = tb_model_positions(&s->model);
  double low = INFINITY;
  for (int i = 0; i < s->mesh.nv; i++)
    low = fmin(low, tb_dot(tb_sub(x[i], s->ground.p), s->ground.n));
  return low;
}

/* liver-drop with pbd-stvk at the patent's settings: fig. 7 the liver above
 * the ground, fig. 8 at rest on it, fig. 9 without the ground (ground = 0)
 * after the same fall, below the floor it fell through (drawn, not acting). */
static void pbd_drop(fig *f, const tb_suite_opts *o) {
  static const char *const what[3] = {"above the ground", "at rest on the ground",
                                      "without the ground: fallen through the floor"};
  for (int k = 0; k < 3; k++) {
    tb_sim_def sd;
    tb_sim_def_init(&sd);
    sd.seed = o->seed;
    if (k == 2) sd.ground = 0;
    tb_sim s;
    tb_error err;
    if (tb_sim_create(&s, "liver-drop", &sd, "pbd-stvk", NULL, NULL, &err)) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
      continue;
    }
    double t = k == 0 ? 0 : (k == 1 ? s.def.duration : 0.8);
    if (run_to(&s, t, NULL, &err)) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
      tb_sim_destroy(&s);
      continue;
    }
    tb_vec3 lo, hi; /* the rest mesh and the body now, and the ground beneath */
    tb_mesh_bbox(&s.mesh, &lo, &hi);
    const tb_vec3 *x = tb_model_positions(&s.model);
    for (int i = 0; i < s.mesh.nv; i++) lo = tb_vmin(lo, x[i]), hi = tb_vmax(hi, x[i]);
    lo = tb_vmin(lo, s.ground.p), hi = tb_vmax(hi, s.ground.p);
    view_box(f, lo, hi);
    body(f, &s, 0);
    char name[64], cap[400];
    snprintf(name, sizeof name, "fig-pbd-%d.png", 7 + k);
    snprintf(cap, sizeof cap,
             "PBD patent fig. %d: the liver %s (liver-drop, pbd-stvk at k 0.4, 5 iterations, dt "
             "%g; t = %g s); its lowest node %.3g %s the ground plane%s.",
             7 + k, what[k], s.def.dt, s.t, fabs(lowest(&s)), lowest(&s) < 0 ? "below" : "above",
             k == 2 ? " (drawn; ground = 0 turns its contact off)" : "");
    shoot(f, name, cap);
    tb_sim_destroy(&s);
  }
}

/* ---- each model's error against the reference, as a colour map ---- */
static void errors(fig *f, const tb_suite_opts *o) {
  tb_fid_plan plan;
  tb_error err;
  if (tb_fid_plan_for("liver-stretch", o->scale < 1 ? 0 : 1, o->seed, &plan, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
    return;
  }
  tb_fid_ref ref;
  tb_sim_def rd = plan.def;
  rd.nodes = plan.ref_res;
  tb_sim_def sd = plan.def;
  sd.nodes = plan.res[plan.nres - 1];
  tb_fid_mesh fm;
  if (tb_fid_reference("liver-stretch", &rd, plan.t_eq, NULL, &ref, &err)) {
    fprintf(stderr, "figures: reference: %s\n", err.msg);
    f->failed = 1;
    return;
  }
  if (tb_fid_mesh_make(&ref, &sd, &fm, &err)) {
    fprintf(stderr, "figures: %s\n", err.msg);
    f->failed = 1;
    tb_fid_ref_free(&ref);
    return;
  }
  static const char *const models[] = {"msm", "fem", "fem-corot", "sm"};
  const tb_mesh *m = &fm.mesh;
  int *tri = NULL, ntri = tb_mesh_tet_boundary(m, &tri);
  tb_vec3 *x[4];
  double *e[4], top = 0, rms[4];
  char state[4][192];
  int subs[4] = {1, 1, 1, 1};
  for (int k = 0; k < 4; k++) {
    x[k] = malloc(sizeof(tb_vec3) * (size_t)m->nv);
    e[k] = calloc((size_t)m->nv, sizeof(double));
    tb_settings md;
    tb_settings_init(&md);
    tb_fid_opts so = plan.opts;
    so.settle_speed = plan.opts.settle_speed * ref.umax;
    so.keep_x = x[k];
    tb_fid_result fr;
    rms[k] = NAN, state[k][0] = 0;
    int bad = !x[k] || !e[k] || tb_fid_equal_masses(m, models[k], &md, &err);
    /* blown up at the scene's dt: again with 4, 16, 64 substeps (as pareto does) */
    for (so.substeps = 1; !bad && so.substeps <= 64; so.substeps *= 4)
      if ((bad = tb_fid_run(&ref, &fm, models[k], &md, &sd, &so, &fr, &err)) || fr.stable) break;
    if (bad) {
      fprintf(stderr, "figures: %s\n", err.msg);
      f->failed = 1;
      continue;
    }
    snprintf(state[k], sizeof state[k], "%s", fr.state);
    subs[k] = so.substeps;
    if (!fr.stable) continue;
    rms[k] = fr.rms_err;
    for (int q = 0; q < fm.nsurf; q++) {
      int i = fm.surf[q];
      e[k][i] = tb_dist(tb_sub(x[k][i], m->x[i]), fm.uref[q]) / ref.umax;
      top = fmax(top, e[k][i]);
    }
  }
  for (int k = 0; k < 4 && ntri > 0; k++) {
    if (isnan(rms[k])) continue;
    view(f, "left-front", m);
    tb_render_mesh rm = {.nv = m->nv,
                         .ntri = ntri,
                         .x = x[k],
                         .tri = tri,
                         .rgb = {1, 1, 1},
                         .value = e[k],
                         .lo = 0,
                         .hi = top > 0 ? top : 1};
    tb_renderer_mesh(f->r, &rm);
    tb_renderer_colorbar(f->r, 0, top > 0 ? top : 1, "error / max |u_ref|");
    char name[64], cap[1200];
    snprintf(name, sizeof name, "error-%s.png", models[k]);
    snprintf(cap, sizeof cap,
             "%s against the reference (compressible Neo-Hookean on quadratic tets, %d nodes) on "
             "liver-stretch at equilibrium (%d nodes, the patch pulled %g): each surface node's "
             "displacement error over the largest reference displacement %.3g; rms %.2f%%, %s%s. "
             "One colour scale for all models.",
             models[k], ref.mesh.nv, m->nv, plan.def.amplitude, ref.umax, 100 * rms[k], state[k],
             subs[k] > 1 ? ", with substeps" : "");
    shoot(f, name, cap);
    char bench[64];
    snprintf(bench, sizeof bench, "error/%s", models[k]);
    tb_suite_counter(f->su, bench, "rms_error", rms[k]); /* an entry of counters alone */
  }
  for (int k = 0; k < 4; k++) free(x[k]), free(e[k]);
  free(tri);
  tb_fid_mesh_free(&fm);
  tb_fid_ref_free(&ref);
}

int tb_suite_figures(const tb_suite_opts *o) {
  char dir[900];
  tb_error err;
  if (snprintf(dir, sizeof dir, "%s/figures", o->results) >= (int)sizeof dir) return 1;
  tb_suite *su = tb_suite_begin(dir, "figures", "The documents' figures, rendered", o->seed, &err);
  if (!su) return fprintf(stderr, "figures: %s\n", err.msg), 1;
  fig f = {su, tb_renderer_new(W, H, 2, &err), dir, 0};
  if (!f.r) {
    fprintf(stderr, "figures: %s\n", err.msg);
    tb_suite_end(su, &err);
    return 1;
  }
  tb_suite_note(su,
                "Rendered headless with OSMesa on Mesa's softpipe rasterizer (%dx%d, 2x2 samples a "
                "pixel): the same run gives the same bytes. Models at the thesis's parameters with "
                "unit node masses.",
                W, H);
  liver_surface(&f, o->seed);
  models(&f, o);
  recovery(&f, o);
  collision(&f, o);
  system_views(&f, o);
  pbd_drop(&f, o);
  errors(&f, o);
  tb_renderer_free(f.r);
  if (tb_suite_end(su, &err)) fprintf(stderr, "figures: %s\n", err.msg), f.failed = 1;
  return f.failed;
}
