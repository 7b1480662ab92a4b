/* `tissuebench simulate`: one model on one scene (a built-in name or a
 * scene file), or on a mesh file with the quick form's fixes and gravity;
 * prints the median time per step and the final state's metrics, or the
 * reason the run blew up. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "tb_cli.h"
#include "meshgen/tb_meshgen.h"
#include "core/tb_parse.h"
#include "core/tb_threads.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

#define PROG "tissuebench simulate"

static void list_all(void) {
  int n;
  const char *const *names = tb_sim_scene_names(&n);
  printf("scenes (scenes/NAME.ini; or give a scene file's path):\n");
  for (int i = 0; i < n; i++) printf("  %-14s %s\n", names[i], tb_sim_scene_summary(names[i]));
  printf("scene keys (--set key=value; 0 means 0): ");
  for (int i = 0; i < TB_P_COUNT; i++)
    printf("%s%s", tb_scene_param_names[i], i + 1 < TB_P_COUNT ? " " : "\n");
  printf("models and their settings (--set key=value; default, range):\n");
  for (int i = 0; i < tb_model_count; i++) {
    printf("  %-14s %s\n", tb_model_classes[i]->name, tb_model_classes[i]->summary);
    tb_model_print_settings(stdout, tb_model_classes[i]);
  }
}

/* docs/reference.md's list: one row per model, its keys with their defaults
 * (choices: the default's name, then the choices). */
static void list_markdown(void) {
  printf("| model | settings (`--set key=value`; default) |\n|---|---|\n");
  for (int i = 0; i < tb_model_count; i++) {
    const tb_model_class *c = tb_model_classes[i];
    printf("| `%s` |", c->name);
    for (int k = 0; k < c->nsettings; k++) {
      const tb_setting *st = &c->settings[k];
      printf("%s `%s` ", k ? "," : "", st->key);
      if (st->type == TB_SETTING_FILE) {
        printf("none");
        continue;
      }
      if (st->type != TB_SETTING_CHOICE) {
        printf("%g", st->def);
        continue;
      }
      const char *p = st->choices;
      for (int j = 0; j < (int)st->def && p; j++) p = strchr(p, '|'), p = p ? p + 1 : NULL;
      printf("%.*s (", p ? (int)strcspn(p, "|") : 1, p ? p : "?");
      for (const char *q = st->choices; *q; q++) printf(*q == '|' ? "\\|" : "%c", *q);
      printf(")");
    }
    printf(" |\n");
  }
}

static int bad(const char *fmt, const char *a) {
  fprintf(stderr, PROG ": ");
  fprintf(stderr, fmt, a);
  fputc('\n', stderr);
  return TB_EXIT_INPUT;
}

/* The quick form: a description built from --mesh, --fix/--fix-box, --gravity. */
static int quick_desc(tb_scene_desc *d, const char *mesh, const char *fix, const char *fixbox,
                      const char *gravity, tb_error *err) {
  tb_scene_desc_init(d);
  snprintf(d->name, sizeof d->name, "%s", "mesh");
  snprintf(d->summary, sizeof d->summary, "%s", mesh);
  const char *why;
  if (tb_scene_resolve_path("", mesh, d->mesh.path, sizeof d->mesh.path, &why))
    return tb_error_set(err, mesh, 0, "%s", why);
  if (fix || fixbox) {
    tb_selection *s = &d->fix[d->nfix++];
    s->sel = calloc(1, sizeof *s->sel);
    if (!s->sel) return tb_error_set(err, "--fix", 0, "out of memory");
    s->n = 1;
    if (tb_selector_parse(&s->sel[0], fix ? TB_SEL_IDS : TB_SEL_BOX, fix ? fix : fixbox,
                          fix ? "--fix" : "--fix-box", 0, NULL, err))
      return -1;
  }
  if (gravity) {
    tb_vec3 g;
    const char *rest;
    if (tb_parse_vec3(gravity, &g, &rest) || *rest)
      return tb_error_set(err, "--gravity", 0, "'%s' is not gx,gy,gz", gravity);
    d->param[TB_P_GRAVITY] = tb_len(g);
    if (tb_len(g) > 0) d->gravity_dir = tb_scale(g, 1.0 / tb_len(g));
  }
  return 0;
}

/* --static: the model's static solve where it has one (quasistatic steps
 * until the positions stop changing), else steps until at rest. Returns the
 * steps taken, -1 on failure. */
static long run_static(tb_sim *s, long cap, int solver, double *change, tb_error *err) {
  tb_vec3 *prev = malloc(sizeof(tb_vec3) * (size_t)s->mesh.nv);
  if (!prev) return tb_error_set(err, PROG, 0, "out of memory");
  long k = 0;
  for (; k < cap; k++) {
    memcpy(prev, tb_model_positions(&s->model), sizeof(tb_vec3) * (size_t)s->mesh.nv);
    if (tb_sim_step(s, err)) {
      free(prev);
      return -1;
    }
    const tb_vec3 *x = tb_model_positions(&s->model);
    double d = 0, speed, tol;
    for (int i = 0; i < s->mesh.nv; i++) d = fmax(d, tb_dist(x[i], prev[i]));
    *change = d;
    if (solver ? d <= 1e-12 * s->size : tb_sim_at_rest(s, &speed, &tol)) {
      k++;
      break;
    }
  }
  free(prev);
  return k;
}

static int make_dir(const char *dir, tb_error *err) {
  if (mkdir(dir, 0777) && errno != EEXIST)
    return tb_error_set(err, dir, 0, "cannot create the folder: %s", strerror(errno));
  struct stat st;
  if (stat(dir, &st) || !S_ISDIR(st.st_mode)) return tb_error_set(err, dir, 0, "not a folder");
  return 0;
}

/* 1 when path's extension names a surface format the writers know. */
static int surface_format(const char *path) {
  const char *dot = strrchr(path, '.');
  return dot && (!strcmp(dot, ".obj") || !strcmp(dot, ".off") || !strcmp(dot, ".stl") ||
                 !strcmp(dot, ".vtk"));
}

int tb_cmd_simulate(int argc, char **argv) {
  const char *model = NULL, *scene = NULL, *vtk = NULL, *mesh = NULL, *fix = NULL, *fixbox = NULL;
  const char *gravity = NULL, *out_surface = NULL, *json = NULL;
  long steps = 0, every = 0;
  int statik = 0;
  tb_sim_def sd;
  tb_sim_def_init(&sd);
  tb_settings set;
  tb_settings_init(&set);
  tb_error err;
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i], *v = i + 1 < argc ? argv[i + 1] : NULL;
    if (!strcmp(a, "--list")) {
      list_all();
      return TB_EXIT_OK;
    }
    if (!strcmp(a, "--list-markdown")) {
      list_markdown();
      return TB_EXIT_OK;
    }
    if (!strcmp(a, "--static")) {
      statik = 1;
      continue;
    }
    if (!v) return tb_cli_bad_option("simulate", a);
    i++;
    const char **slot = !strcmp(a, "--model")         ? &model
                        : !strcmp(a, "--scene")       ? &scene
                        : !strcmp(a, "--vtk")         ? &vtk
                        : !strcmp(a, "--mesh")        ? &mesh
                        : !strcmp(a, "--fix")         ? &fix
                        : !strcmp(a, "--fix-box")     ? &fixbox
                        : !strcmp(a, "--gravity")     ? &gravity
                        : !strcmp(a, "--out-surface") ? &out_surface
                        : !strcmp(a, "--json")        ? &json
                                                      : NULL;
    if (slot) {
      if (*slot) return bad("%s given twice", a);
      *slot = v;
    } else if (!strcmp(a, "--steps") || !strcmp(a, "--every")) {
      char *end;
      long n = strtol(v, &end, 10);
      if (*end || end == v || n < 1 || n > 100000000)
        return bad("%s needs a whole number in 1..1e8", a);
      *(a[2] == 's' ? &steps : &every) = n;
    } else if (!strcmp(a, "--dt") || !strcmp(a, "--duration")) {
      char kv[96];
      snprintf(kv, sizeof kv, "%s=%s", a + 2, v);
      if (tb_sim_def_set(&sd, kv, &err)) return bad("%s", err.msg);
      if (!(a[2] == 'd' && a[3] == 't' ? sd.dt > 0 : sd.duration > 0))
        return bad("%s must be > 0", a);
    } else if (!strcmp(a, "--set")) {
      int rc = tb_sim_def_set(&sd, v, &err);
      if (rc == 1) rc = tb_settings_set(&set, v, &err);
      if (rc) return bad("%s", err.msg);
    } else
      return tb_cli_bad_option("simulate", a);
  }
  if (!scene == !mesh)
    return bad("%s",
               "give --scene NAME|FILE, or --model M --mesh FILE (--list shows scenes and models)");
  if (mesh && !model) return bad("%s", "--mesh needs --model (--list shows them)");
  if (scene && (fix || fixbox || gravity))
    return bad("%s", "--fix, --fix-box and --gravity go with --mesh (a scene file says its own)");
  if (fix && fixbox) return bad("%s", "give --fix or --fix-box, not both");
  if (model && !tb_model_find(model)) return bad("unknown model '%s' (--list shows them)", model);
  if (model && tb_model_check_settings(model, &set, &err)) return bad("%s", err.msg);
  if (vtk && make_dir(vtk, &err)) return bad("--vtk: %s", err.msg);
  if (out_surface && !surface_format(out_surface))
    return bad("--out-surface %s: the format comes from the extension: .obj, .off, .stl or .vtk",
               out_surface);
  tb_scene_desc d;
  char path[1024];
  if (scene) tb_sim_scene_path(scene, path, sizeof path);
  if (mesh ? quick_desc(&d, mesh, fix, fixbox, gravity, &err)
           : tb_scene_desc_load(&d, path, &err)) {
    tb_scene_desc_free(&d);
    return bad("%s", err.msg);
  }
  if (!model && d.model[0]) model = d.model;
  /* --static: a model with a static solve uses it */
  int solver = 0;
  double qs;
  if (statik && model && tb_model_setting(model, &set, "quasistatic", &qs) == 0) {
    if (tb_settings_set(&set, "quasistatic=1", &err))
      return tb_scene_desc_free(&d), bad("%s", err.msg);
    solver = 1;
  }
  tb_sim s;
  if (tb_sim_create_desc(&s, &d, &sd, model, &set, NULL, &err)) return bad("%s", err.msg);
  const char *mname = s.model.cls->name;
  long planned = steps ? steps : lround(s.def.duration / s.def.dt);
  int rc;
  if (planned < 1) planned = 1;
  if (!every) {
    double interval = s.desc.frame_interval > 0 ? s.desc.frame_interval : 1.0 / 30.0;
    every = lround(interval / s.def.dt) > 1 ? lround(interval / s.def.dt) : 1;
  }
  if (s.meshed_nv)
    printf(
        "mesh: the surface's %d vertices and %d triangles tetrahedralised by TetGen (quality "
        "%g, surface kept): %d nodes, %d tets (tissuebench mesh tetrahedralize chooses the "
        "density: --tets N or --max-volume V)\n",
        s.meshed_nv, s.meshed_ntri, TB_TETMESH_QUALITY, s.mesh.nv, s.mesh.ntet);
  if (statik)
    printf("scene %s: %d nodes, %d tets; model %s; %s (at most %ld steps of dt %g)\n", s.name,
           s.mesh.nv, s.mesh.ntet, mname, solver ? "static solve" : "run to rest", planned,
           s.def.dt);
  else
    printf("scene %s: %d nodes, %d tets; model %s; dt %g, %ld steps (%g s)\n", s.name, s.mesh.nv,
           s.mesh.ntet, mname, s.def.dt, planned, planned * s.def.dt);
  double *ms = malloc(sizeof(double) * 2 * (size_t)planned), *cpu = ms ? ms + planned : NULL;
  double *times = malloc(sizeof(double) * (size_t)(planned / every + 2));
  if (!ms || !times) {
    free(ms), free(times);
    tb_sim_destroy(&s);
    fprintf(stderr, PROG ": out of memory\n");
    return TB_EXIT_FAIL;
  }
  rc = TB_EXIT_OK;
  int frame = 0;
  if (vtk && tb_sim_write_frame(&s, vtk, frame, &err)) rc = TB_EXIT_FAIL;
  if (vtk) times[frame++] = s.t;
  long done = 0;
  double change = 0;
  char why[600] = "";
  tb_run_summary sum = {.status = "failed",
                        .reason = why,
                        .cpu_ms = NAN,
                        .wall_ms = NAN,
                        .cpu_min_ms = NAN,
                        .cpu_max_ms = NAN,
                        .speed = NAN,
                        .rest_tol = NAN};
  if (statik && rc == TB_EXIT_OK) {
    tb_clock c = tb_clock_start();
    done = run_static(&s, planned, solver, &change, &err);
    tb_clock_ms(&c, ms, cpu);
    ms[0] /= done > 0 ? done : 1, cpu[0] /= done > 0 ? done : 1;
    if (done < 0) {
      printf("status: unstable (%s)\n", err.msg);
      snprintf(why, sizeof why, "%s", err.msg);
      sum.status = "unstable";
      rc = TB_EXIT_FAIL;
    } else if (vtk && tb_sim_write_frame(&s, vtk, frame, &err))
      rc = TB_EXIT_FAIL;
    else if (vtk)
      times[frame++] = s.t;
  }
  for (; !statik && done < planned && rc == TB_EXIT_OK; done++) {
    tb_clock c = tb_clock_start();
    int failed = tb_sim_step(&s, &err);
    tb_clock_ms(&c, ms + done, cpu + done);
    if (failed) {
      printf("status: unstable (%s)\n", err.msg);
      snprintf(why, sizeof why, "%s", err.msg);
      sum.status = "unstable";
      rc = TB_EXIT_FAIL;
      break;
    }
    if (vtk && (done + 1) % every == 0) {
      if (tb_sim_write_frame(&s, vtk, frame, &err))
        rc = TB_EXIT_FAIL;
      else
        times[frame++] = s.t;
    }
  }
  if (rc == TB_EXIT_FAIL && vtk && s.health.ok) fprintf(stderr, PROG ": %s\n", err.msg);
  tb_error perr;
  if (vtk && frame && tb_sim_write_pvd(&s, vtk, frame, times, &perr)) {
    fprintf(stderr, PROG ": %s\n", perr.msg);
    rc = TB_EXIT_FAIL;
  }
  if (rc == TB_EXIT_OK) {
    tb_stats st = tb_stats_of(cpu, statik ? 1 : (int)done),
             sw = tb_stats_of(ms, statik ? 1 : (int)done);
    tb_sim_metrics m = tb_sim_measure(&s);
    double speed, tol;
    int rest = tb_sim_at_rest(&s, &speed, &tol);
    sum.cpu_ms = st.median, sum.wall_ms = sw.median, sum.cpu_min_ms = st.min,
    sum.cpu_max_ms = st.max;
    sum.have_metrics = 1, sum.m = m, sum.rest = rest, sum.speed = speed, sum.rest_tol = tol;
    if (statik)
      printf("time per %s: %.4f ms CPU (wall %.4f ms; mean over %ld)\n", solver ? "solve" : "step",
             st.median, sw.median, done);
    else
      printf(
          "time per step: median %.4f ms CPU (wall %.4f ms; CPU min %.4f, max %.4f) = %.1f "
          "steps/s\n",
          st.median, sw.median, st.min, st.max, 1e3 / st.median);
    printf(
        "threads: %d%s\n", tb_threads(),
        tb_threads_auto() ? " (automatic: a step takes them only where they make it faster)" : "");
    printf("max displacement %.6g at node %d, rms displacement %.6g\n", m.max_disp, m.max_disp_node,
           m.rms_disp);
    if (s.mesh.ntet > 0)
      printf("volume change %+.4f%%, inverted tets %d\n", 100.0 * m.volume_change, m.inverted);
    else
      printf("volume change %+.4f%% (enclosed by the surface; no tets)\n", 100.0 * m.volume_change);
    if (isnan(m.energy))
      printf("energy: not defined for %s\n", mname);
    else
      printf("energy %.6g\n", m.energy);
    if (s.nprobe) {
      const tb_vec3 *x = tb_model_positions(&s.model);
      tb_vec3 mean = tb_v3(0, 0, 0);
      double most = -1;
      int at = s.probe[0];
      for (int k = 0; k < s.nprobe; k++) {
        tb_vec3 u = tb_sub(x[s.probe[k]], s.mesh.x[s.probe[k]]);
        mean = tb_madd(mean, 1.0 / s.nprobe, u);
        if (tb_len(u) > most) most = tb_len(u), at = s.probe[k];
      }
      printf("probe (%d nodes): mean displacement (%.6g, %.6g, %.6g), largest %.6g at node %d\n",
             s.nprobe, mean.x, mean.y, mean.z, most, at);
      printf("probe: largest mean displacement over the run %.6g at t = %g s\n", s.probe_peak,
             s.probe_peak_t);
    }
    if (s.has_ground)
      printf("ground: largest penetration %.3g over the run (tolerance %.3g = 1e-9 x size)\n",
             s.pen_ground_max, 1e-9 * s.size);
    if (s.settle_steps)
      printf("ground: settled in %ld steps before t = 0 (last step's largest motion %.3g%s)\n",
             s.settle_steps, s.settle_motion,
             s.settle_motion <= 1e-9 * s.size ? "" : ": NOT settled, [ground] settle too short");
    if (s.has_tool)
      printf("instrument: largest penetration %.3g after the contact response, %.3g before it\n",
             s.pen_tool_max, s.pen_tool_before_max);
    if (statik && solver)
      printf("static equilibrium after %ld solve(s) (last change %.3g)%s\n", done, change,
             change <= 1e-12 * s.size ? "" : ": NOT converged");
    else
      printf("%s at t = %g s: max node speed %.3g (rest below %.3g)\n",
             rest ? "at rest" : "NOT at rest", s.t, speed, tol);
    if (vtk)
      printf(
          "%d frames in %s (frames.pvd for ParaView: per frame frame_NNNNN.vtm, one block per "
          "object; body.pvd etc. per object)\n",
          frame, vtk);
    if (out_surface) {
      if (tb_sim_write_surface(&s, out_surface, &err)) {
        fprintf(stderr, PROG ": %s\n", err.msg);
        rc = TB_EXIT_FAIL;
      } else
        printf("surface: %d points, %d triangles in %s\n", tb_model_surface(&s.model).nv,
               tb_model_surface(&s.model).ntri, out_surface);
    }
    if (rc != TB_EXIT_OK)
      ;
    else if (tb_sim_degraded(&s, why, sizeof why)) {
      printf("status: degraded (%s)\n", why);
      sum.status = "degraded";
      rc = TB_EXIT_DEGRADED;
    } else {
      printf("status: stable\n");
      sum.status = "stable";
    }
  }
  sum.steps = done;
  if (json && tb_simulate_json(json, &s, &sum, &err)) {
    fprintf(stderr, PROG ": %s\n", err.msg);
    if (rc == TB_EXIT_OK) rc = TB_EXIT_FAIL;
  }
  free(ms), free(times);
  tb_sim_destroy(&s);
  return rc;
}
