/* A cut trial (measure/tb_cut_trial.h): the trial as a scene file in the
 * temporary folder (the organ's surface and spheres as files, a [fix] box,
 * one [cut NAME] per blade), run through the scene driver, measured with
 * measure/tb_pieces.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "tb_cut_trial.h"
#include "tb_pieces.h"
#include "core/tb_timer.h"
#include "report/tb_results.h"
#include "scenes/tb_sim.h"

static int write_scene(const tb_cut_trial *t, char *path, size_t cap, tb_error *err) {
  const char *tmp = getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp";
  snprintf(path, cap, "%s/tb-cut-trial-XXXXXX", tmp);
  int fd = mkstemp(path);
  FILE *f = fd >= 0 ? fdopen(fd, "w") : NULL;
  if (!f) {
    if (fd >= 0) close(fd);
    return tb_error_set(err, path, 0, "cannot write the trial's scene");
  }
  double end = 0;
  for (int b = 0; b < t->nblade; b++) end = fmax(end, t->blade[b].stop);
  fprintf(f, "[scene]\ndt = %.17g\nduration = %.17g\ngravity = 9.81\ninversion = 0\n",
          t->dt > 0 ? t->dt : 0.01, end + t->after);
  fprintf(f, "[mesh]\nfile = %s\n[model]\nname = metaball\nspheres_file = %s\n", t->mesh,
          t->spheres);
  fprintf(f, "[fix held]\nbox = %.17g,%.17g,%.17g, %.17g,%.17g,%.17g\n", t->hold_lo.x, t->hold_lo.y,
          t->hold_lo.z, t->hold_hi.x, t->hold_hi.y, t->hold_hi.z);
  for (int b = 0; b < t->nblade; b++) {
    const tb_cut_blade *bl = &t->blade[b];
    fprintf(f, "[cut b%d]\n", b);
    for (int i = 0; i < bl->n; i++)
      fprintf(f, "point = %.17g,%.17g,%.17g\n", bl->p[i].x, bl->p[i].y, bl->p[i].z);
    fprintf(f, "depth = %.17g,%.17g,%.17g\nstart = %.17g\nstop = %.17g\n", bl->depth.x, bl->depth.y,
            bl->depth.z, bl->start, bl->stop);
  }
  if (fclose(f)) return tb_error_set(err, path, 0, "cannot write the trial's scene");
  return 0;
}

static int measure(tb_sim *s, int self, tb_pieces *p, tb_error *err) {
  tb_surface su = tb_model_surface(&s->model);
  return tb_pieces_measure(su.nv, su.x, su.ntri, su.tri, self, p, err);
}

int tb_cut_trial_run(const tb_cut_trial *t, tb_cut_outcome *o, tb_error *err) {
  memset(o, 0, sizeof *o);
  o->self_cut = o->self_end = o->overlap_cut = o->overlap_end = -1;
  char path[1024];
  if (t->nblade < 1 || t->nblade > TB_CUT_TRIAL_BLADES)
    return tb_error_set(err, t->name, 0, "1 to %d blades, not %d", TB_CUT_TRIAL_BLADES, t->nblade);
  if (write_scene(t, path, sizeof path, err)) return -1;
  tb_sim s;
  tb_error e;
  int rc = tb_sim_create(&s, path, NULL, NULL, NULL, NULL, &e);
  remove(path);
  if (rc) {
    snprintf(o->why, sizeof o->why, "set-up: %.220s", e.msg);
    return 0;
  }
  double last_stop = 0, first_start = INFINITY;
  for (int b = 0; b < t->nblade; b++)
    last_stop = fmax(last_stop, t->blade[b].stop),
    first_start = fmin(first_start, t->blade[b].start);
  long n = lround(s.def.duration / s.def.dt), nframe = 0;
  tb_pieces before;
  if (measure(&s, 1, &before, &e) == 0) o->self_before = before.self_pairs;
  tb_pieces_free(&before);
  double *ms = malloc(sizeof(double) * (size_t)(n > 0 ? n : 1)), *vol = NULL;
  tb_pieces cut = {0};
  int measured = 0, failed = !ms;
  if (!ms) snprintf(o->why, sizeof o->why, "out of memory");
  for (long k = 0; k < n && !failed; k++) {
    double t0 = s.t, cpu;
    tb_clock c = tb_clock_start();
    failed = tb_sim_step(&s, &e);
    tb_clock_ms(&c, NULL, &cpu);
    if (failed) {
      snprintf(o->why, sizeof o->why, "t = %.3g s: %.200s", s.t, e.msg);
      break;
    }
    if (t0 + 0.5 * s.def.dt >= first_start && t0 < last_stop) ms[nframe++] = cpu;
    if (!measured && s.t >= last_stop - 1e-9 * s.def.dt) { /* the last blade has ended */
      measured = 1;
      if (measure(&s, 1, &cut, &e)) {
        snprintf(o->why, sizeof o->why, "%.200s", e.msg);
        failed = 1;
        break;
      }
      o->pieces_cut = cut.n, o->closed_cut = cut.closed, o->self_cut = cut.self_pairs;
      o->overlap_cut = cut.overlap_pairs;
      o->vertices_cut = cut.nv;
      tb_model_spheres sp =
          s.model.cls->spheres ? s.model.cls->spheres(s.model.self) : (tb_model_spheres){0};
      o->consistent_cut = tb_pieces_spheres(&cut, &sp, &o->spheres_cut, &o->crossing_cut);
      vol = malloc(sizeof(double) * (size_t)(cut.n > 0 ? cut.n : 1));
      if (!vol) snprintf(o->why, sizeof o->why, "out of memory"), failed = 1;
    } else if (measured) { /* the pieces' volumes over the second after */
      tb_surface su = tb_model_surface(&s.model);
      if (su.ntri != cut.ntri) continue; /* the surface changed again: no common pieces */
      tb_pieces_volumes(&cut, su.x, su.tri, vol);
      for (int q = 0; q < cut.n; q++) o->drift = fmax(o->drift, fabs(vol[q] / cut.volume[q] - 1));
    }
  }
  if (!failed && !measured) snprintf(o->why, sizeof o->why, "the cut never ended"), failed = 1;
  if (!failed) {
    tb_pieces end;
    if (measure(&s, 1, &end, &e))
      snprintf(o->why, sizeof o->why, "%.200s", e.msg);
    else {
      o->pieces_end = end.n, o->closed_end = end.closed, o->self_end = end.self_pairs;
      o->overlap_end = end.overlap_pairs, o->deepest_end = end.deepest;
      o->ran = 1;
      tb_pieces_free(&end);
    }
  }
  o->frame_ms = nframe ? tb_median_est(ms, (int)nframe).value : NAN;
  free(ms), free(vol);
  tb_pieces_free(&cut);
  tb_sim_destroy(&s);
  return 0;
}

const char *tb_cut_outcome_verdict(const tb_cut_outcome *o, double max_drift, char *buf,
                                   size_t cap) {
  if (!o->ran)
    snprintf(buf, cap, "failed: %s", o->why);
  else if (!o->closed_cut || !o->closed_end)
    snprintf(buf, cap, "a piece not a closed 2-manifold (%s)",
             o->closed_cut ? "later" : "at the cut");
  else if (o->self_cut > o->self_before || o->self_end > o->self_before)
    snprintf(buf, cap, "self-intersecting (%d pairs at the cut, %d a second later, %d before)",
             o->self_cut, o->self_end, o->self_before);
  else if (o->overlap_cut || o->overlap_end)
    snprintf(buf, cap, "pieces inside each other (%d pairs at the cut, %d a second later)",
             o->overlap_cut, o->overlap_end);
  else if (!o->consistent_cut)
    snprintf(buf, cap,
             "the spheres' components (%d) are not the pieces (%d; %d points bound across)",
             o->spheres_cut, o->pieces_cut, o->crossing_cut);
  else if (!(o->drift <= max_drift))
    snprintf(buf, cap, "a piece's volume drifted %.1f%% in the second after", 100 * o->drift);
  else
    snprintf(buf, cap, "ok");
  return buf;
}
