/* `tissuebench simulate`: one model on one scene; prints the median time
 * per step and the final state's metrics, or the reason the run blew up. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tb_cli.h"
#include "tb_results.h"
#include "tb_sim.h"
#include "tb_timer.h"

static void list_all(void) {
  int n;
  const char *const *names = tb_sim_scene_names(&n);
  printf("scenes:\n");
  for (int i = 0; i < n; i++) printf("  %-14s %s\n", names[i], tb_sim_scene_summary(names[i]));
  printf("models (--set key=value; key, type, default, range, what it is):\n");
  for (int i = 0; i < tb_model_count; i++) {
    printf("  %-14s %s\n", tb_model_classes[i]->name, tb_model_classes[i]->summary);
    tb_model_print_settings(stdout, tb_model_classes[i]);
  }
  printf(
      "scene keys: dt duration amplitude release nodes gravity vmax inversion drag energy_factor "
      "energy_every\n");
}

/* The README's list: one row per model, its keys with their defaults
 * (choices: the default's name, then the choices). */
static void list_markdown(void) {
  printf("| model | settings (`--set key=value`; default) |\n|---|---|\n");
  for (int i = 0; i < tb_model_count; i++) {
    const tb_model_class *c = tb_model_classes[i];
    printf("| `%s` |", c->name);
    for (int k = 0; k < c->nsettings; k++) {
      const tb_setting *st = &c->settings[k];
      printf("%s `%s` ", k ? "," : "", st->key);
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

int tb_cmd_simulate(int argc, char **argv) {
  const char *model = NULL, *scene = NULL, *vtk = NULL;
  long steps = 0, every = 0;
  tb_sim_def sd;
  memset(&sd, 0, sizeof sd);
  sd.seed = 1;
  tb_settings mset; /* model keys, checked against the model's table below */
  tb_settings_init(&mset);
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
    if (!v) {
      fprintf(stderr, "tissuebench simulate: unknown or incomplete option '%s'\n", a);
      return TB_EXIT_INPUT;
    }
    i++;
    if (!strcmp(a, "--model"))
      model = v;
    else if (!strcmp(a, "--scene"))
      scene = v;
    else if (!strcmp(a, "--vtk"))
      vtk = v;
    else if (!strcmp(a, "--steps") || !strcmp(a, "--every")) {
      char *end;
      long n = strtol(v, &end, 10);
      if (*end || end == v || n < 1 || n > 100000000) {
        fprintf(stderr, "tissuebench simulate: %s needs a whole number >= 1\n", a);
        return TB_EXIT_INPUT;
      }
      *(a[2] == 's' ? &steps : &every) = n;
    } else if (!strcmp(a, "--dt")) {
      if (tb_cli_parse_double("--dt", v, &sd.dt)) return TB_EXIT_INPUT;
      if (!(sd.dt > 0)) {
        fprintf(stderr, "tissuebench simulate: --dt must be > 0\n");
        return TB_EXIT_INPUT;
      }
    } else if (!strcmp(a, "--set")) {
      int rc = tb_sim_def_set(&sd, v, &err);
      if (rc == 1) rc = tb_settings_set(&mset, v, &err);
      if (rc) {
        fprintf(stderr, "tissuebench simulate: %s\n", err.msg);
        return TB_EXIT_INPUT;
      }
    } else {
      fprintf(stderr, "tissuebench simulate: unknown option '%s'\n", a);
      return TB_EXIT_INPUT;
    }
  }
  if (!model || !scene) {
    fprintf(stderr, "tissuebench simulate: --model and --scene are required (--list shows them)\n");
    return TB_EXIT_INPUT;
  }
  if (!tb_model_find(model)) {
    fprintf(stderr, "tissuebench simulate: unknown model '%s' (--list shows them)\n", model);
    return TB_EXIT_INPUT;
  }
  if (!tb_sim_scene_summary(scene)) {
    fprintf(stderr, "tissuebench simulate: unknown scene '%s' (--list shows them)\n", scene);
    return TB_EXIT_INPUT;
  }
  if (tb_model_check_settings(model, &mset, &err)) {
    fprintf(stderr, "tissuebench simulate: %s\n", err.msg);
    return TB_EXIT_INPUT;
  }
  tb_sim s;
  if (tb_sim_create(&s, scene, &sd, model, &mset, NULL, &err)) {
    fprintf(stderr, "tissuebench simulate: %s\n", err.msg);
    return TB_EXIT_FAIL;
  }
  if (!steps) steps = lround(s.def.duration / s.def.dt);
  if (steps < 1) steps = 1;
  if (!every) every = lround(1.0 / (30.0 * s.def.dt)) > 1 ? lround(1.0 / (30.0 * s.def.dt)) : 1;
  printf("scene %s: %d nodes, %d tets; model %s; dt %g, %ld steps (%g s)\n", scene, s.mesh.nv,
         s.mesh.ntet, model, s.def.dt, steps, steps * s.def.dt);
  double *ms = malloc(sizeof(double) * (size_t)steps);
  int rc = ms ? TB_EXIT_OK : TB_EXIT_FAIL, frame = 0;
  if (vtk && ms && tb_sim_write_vtk(&s, vtk, frame++, &err)) rc = TB_EXIT_FAIL;
  long done = 0;
  for (; done < steps && rc == TB_EXIT_OK; done++) {
    uint64_t t0 = tb_time_ns();
    int bad = tb_sim_step(&s, &err);
    ms[done] = (double)(tb_time_ns() - t0) * 1e-6;
    if (bad) {
      printf("status: unstable (%s)\n", err.msg);
      rc = TB_EXIT_FAIL;
      break;
    }
    if (vtk && (done + 1) % every == 0 && tb_sim_write_vtk(&s, vtk, frame++, &err)) {
      fprintf(stderr, "tissuebench simulate: %s\n", err.msg);
      rc = TB_EXIT_FAIL;
    }
  }
  if (rc == TB_EXIT_OK) {
    tb_stats st = tb_stats_of(ms, (int)done);
    tb_sim_metrics m = tb_sim_measure(&s);
    printf("time per step: median %.4f ms (min %.4f, max %.4f) = %.1f steps/s\n", st.median, st.min,
           st.max, 1e3 / st.median);
    printf("max displacement %.6g, rms displacement %.6g\n", m.max_disp, m.rms_disp);
    printf("volume change %+.4f%%, inverted tets %d\n", 100.0 * m.volume_change, m.inverted);
    if (isnan(m.energy))
      printf("energy: not defined for %s\n", model);
    else
      printf("energy %.6g\n", m.energy);
    if (vtk) printf("%d VTK frames in %s\n", frame, vtk);
    printf("status: stable\n");
  } else if (!ms)
    fprintf(stderr, "tissuebench simulate: out of memory\n");
  free(ms);
  tb_sim_destroy(&s);
  return rc;
}
