/* The scene's scalpel ([cut], scenes/README.md): the blade's edge travels
 * the path's points at constant speed from `start` to `stop`, its depth
 * vector fixed; each step while it moves hands the model the path so far
 * (tb_model_cut's MOVE: the points passed, then the blade's position), the
 * step after `stop` ends the cut (END). The model then has more points (the
 * cut's new surface vertices): the scene's per-point force array grows
 * with them (zero forces). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "sim_priv.h"
#include "cutting/tb_fold.h"

int tb_sim_cut_setup(tb_sim *s, tb_error *err) {
  const tb_scene_desc *d = &s->desc;
  if (!d->has_cut) return 0;
  const char *path = d->path[0] ? d->path : d->name;
  if (!tb_model_can_cut(&s->model))
    return tb_error_set(err, path, d->cut_line,
                        "[cut]: the %s model cannot be cut (models that can: metaball)",
                        s->model.cls->name);
  s->priv->cut_n = d->ncut_point;
  s->priv->cut_path = malloc(sizeof(tb_vec3) * (size_t)s->priv->cut_n);
  s->priv->cut_now = malloc(sizeof(tb_vec3) * (size_t)s->priv->cut_n);
  if (!s->priv->cut_path || !s->priv->cut_now) return tb_error_set(err, path, 0, "out of memory");
  for (int i = 0; i < s->priv->cut_n; i++)
    s->priv->cut_path[i] = tb_expr_vec(d->cut_point[i], s->priv->param);
  s->priv->cut_depth = tb_expr_vec(d->cut_depth, s->priv->param);
  s->priv->cut_start = tb_expr_eval(d->cut_start, s->priv->param);
  s->priv->cut_stop = tb_expr_eval(d->cut_stop, s->priv->param);
  if (!(s->priv->cut_stop > s->priv->cut_start) || !(s->priv->cut_start >= 0))
    return tb_error_set(err, path, d->cut_line, "[cut]: need 0 <= start < stop (start %g, stop %g)",
                        s->priv->cut_start, s->priv->cut_stop);
  if (!(tb_len(s->priv->cut_depth) > 0))
    return tb_error_set(err, path, d->cut_line, "[cut]: depth must not be zero");
  for (int i = 0; i + 1 < s->priv->cut_n; i++)
    if (!(tb_dist(s->priv->cut_path[i], s->priv->cut_path[i + 1]) > 0))
      return tb_error_set(err, path, d->cut_line, "[cut]: points %d and %d are the same", i + 1,
                          i + 2);
  /* the whole path as the blade's folded plane: a depth along a segment is
   * an error of the file, found here rather than when the blade gets there */
  tb_fold f;
  tb_error e;
  if (tb_fold_init(&f, s->priv->cut_path, s->priv->cut_n, s->priv->cut_depth, &e))
    return tb_error_set(err, path, d->cut_line, "[cut]: %s",
                        strchr(e.msg, ':') ? strchr(e.msg, ':') + 2 : e.msg);
  tb_fold_free(&f);
  return 0;
}

/* The path so far at time t into s->priv->cut_now; returns its point count. */
static int path_at(tb_sim *s, double t) {
  double total = 0;
  for (int i = 0; i + 1 < s->priv->cut_n; i++)
    total += tb_dist(s->priv->cut_path[i], s->priv->cut_path[i + 1]);
  double u = (t - s->priv->cut_start) / (s->priv->cut_stop - s->priv->cut_start);
  double left = (u < 0 ? 0 : u > 1 ? 1 : u) * total;
  int n = 0;
  s->priv->cut_now[n++] = s->priv->cut_path[0];
  for (int i = 0; i + 1 < s->priv->cut_n; i++) {
    double len = tb_dist(s->priv->cut_path[i], s->priv->cut_path[i + 1]);
    if (left >= len) {
      s->priv->cut_now[n++] = s->priv->cut_path[i + 1], left -= len;
      continue;
    }
    if (left > 1e-9 * len) /* the blade inside segment i */
      s->priv->cut_now[n++] =
          tb_add(s->priv->cut_path[i],
                 tb_scale(tb_sub(s->priv->cut_path[i + 1], s->priv->cut_path[i]), left / len));
    break;
  }
  return n;
}

int tb_sim_cut_before(tb_sim *s, double t, tb_error *err) {
  if (!s->desc.has_cut || s->priv->cut_state == 2 || t < s->priv->cut_start) return 0;
  if (s->priv->cut_state == 0) {
    tb_cut_event ev = {TB_CUT_BEGIN, 0, NULL, s->priv->cut_depth};
    if (tb_model_cut(&s->model, &ev, NULL, err)) return -1;
    s->priv->cut_state = 1;
  }
  int n = path_at(s, t);
  if (n < 2 || (n == s->priv->cut_last_n &&
                !memcmp(&s->priv->cut_now[n - 1], &s->priv->cut_last, sizeof s->priv->cut_last)))
    return 0;
  s->priv->cut_last_n = n, s->priv->cut_last = s->priv->cut_now[n - 1];
  tb_cut_event ev = {TB_CUT_MOVE, n, s->priv->cut_now, s->priv->cut_depth};
  return tb_model_cut(&s->model, &ev, NULL, err);
}

int tb_sim_cut_after(tb_sim *s, double t, tb_error *err) {
  if (s->priv->cut_state != 1 || t < s->priv->cut_stop) return 0;
  tb_cut_event ev = {TB_CUT_END, 0, NULL, s->priv->cut_depth};
  if (tb_model_cut(&s->model, &ev, &s->priv->cut_stats, err)) return -1;
  s->priv->cut_state = 2;
  int np = tb_model_npoints(&s->model);
  if (np > s->mesh.nv) { /* forces for the new points: none */
    tb_vec3 *f = realloc(s->force, sizeof(tb_vec3) * (size_t)np);
    if (!f) return tb_error_set(err, s->model.cls->name, 0, "out of memory");
    memset(f + s->mesh.nv, 0, sizeof(tb_vec3) * (size_t)(np - s->mesh.nv));
    s->force = f;
  }
  return 0;
}

void tb_sim_cut_free(tb_sim *s) { free(s->priv->cut_path), free(s->priv->cut_now); }
